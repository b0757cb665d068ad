"""Small meshes the mesh tests share."""

from __future__ import annotations

import numpy as np


def cube(size=1.0, centre=(0.0, 0.0, 0.0)):
    """8 welded corners and 12 outward triangles."""
    p = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    i = lambda x, y, z: x * 4 + y * 2 + z  # noqa: E731
    quads = [(i(1, 0, 0), i(1, 1, 0), i(1, 1, 1), i(1, 0, 1)),
             (i(0, 0, 0), i(0, 0, 1), i(0, 1, 1), i(0, 1, 0)),
             (i(0, 1, 0), i(0, 1, 1), i(1, 1, 1), i(1, 1, 0)),
             (i(0, 0, 0), i(1, 0, 0), i(1, 0, 1), i(0, 0, 1)),
             (i(0, 0, 1), i(1, 0, 1), i(1, 1, 1), i(0, 1, 1)),
             (i(0, 0, 0), i(0, 1, 0), i(1, 1, 0), i(1, 0, 0))]
    faces = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])
    return p * size / 2 + np.asarray(centre, float), faces

"""The tessellation levels of app.render.meshes.auto_tessellation (no GL)."""

from __future__ import annotations

import math

import numpy as np

from app.render.meshes import (
    FIXED_TESSELLATION,
    TESSELLATION_LEVELS,
    auto_tessellation,
    tessellation_level,
    torus,
    uv_sphere,
)


def test_levels_grow_with_size_and_stay_in_range():
    for name in ("sphere", "torus"):
        last = (0, 0)
        for height in (45, 90, 180, 360, 720, 1440, 2880, 5760):
            rings, segs = auto_tessellation(name, 4.9, 40.0, height, 6.0)
            assert segs in TESSELLATION_LEVELS and rings >= last[0] and segs >= last[1]
            last = (rings, segs)
        assert last[1] == TESSELLATION_LEVELS[-1]
    # a camera inside the bounding sphere gets the finest level
    assert auto_tessellation("sphere", 0.2, 40.0, 180, 6.0)[1] == TESSELLATION_LEVELS[-1]


def test_edges_span_about_the_asked_pixels_and_the_silhouette_error_is_small():
    for distance in np.geomspace(1.0, 60.0, 25):
        for height in (180, 720):
            rings, segs = auto_tessellation("sphere", float(distance), 40.0, height, 6.0)
            near = distance - 0.5
            r_px = 0.5 * height / (2 * near * math.tan(math.radians(20.0)))
            edge = 2 * math.pi * r_px / segs
            if segs not in (TESSELLATION_LEVELS[0], TESSELLATION_LEVELS[-1]):  # not clamped
                assert 6.0 <= edge < 12.0 + 1e-9  # the finest level with edges ≥ 6 px
                assert r_px * (1 - math.cos(math.pi / segs)) < 0.6  # sagitta, pixels


def test_level_picking_and_fixed_counts():
    assert tessellation_level(10.0, 6.0) == TESSELLATION_LEVELS[0]
    assert tessellation_level(24 * 6.0, 6.0) == 24 and tessellation_level(24 * 6.0 - 1, 6.0) == 12
    assert tessellation_level(1e9, 6.0) == TESSELLATION_LEVELS[-1]
    assert FIXED_TESSELLATION == {"sphere": (48, 96), "torus": (48, 96)}
    assert len(uv_sphere().indices) == len(torus().indices) == 48 * 96 * 6  # former defaults

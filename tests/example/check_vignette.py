"""The example effect's test (in your own project: tests/gl/test_vignette.py)."""

from __future__ import annotations

import numpy as np

from app.sim.camera import Camera


def test_vignette_darkens_each_pixel_by_cos4_of_its_angle(render):
    camera = Camera(position=(0.0, 2.0, 0.0), yaw=225.0, pitch=25.0, fov=90.0)
    plain, _ = render("vignette", sets=["vignette.amount=0"], camera=camera)
    lens, session = render("vignette", sets=["vignette.amount=1"], camera=camera)
    h, w = plain.shape[:2]
    cos = camera.ray_directions(w, h) @ camera.forward()  # the numpy twin of the shader's ray
    seen = plain[..., :3] > 1e-3
    ratio = lens[..., :3][seen] / plain[..., :3][seen]
    want = np.repeat(cos[..., None] ** 4, 3, axis=-1)[seen]
    assert np.allclose(ratio, want, rtol=1e-4, atol=1e-6)
    assert ratio.min() < 0.3  # the corners of a 90° view lose most of their light
    assert "vignette" in {a.owner for a in session.gpu.allocations}

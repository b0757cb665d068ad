"""The village's toon contours (spec/003 §2.13–2.14: glsl/village/contours.frag, the depth
Laplacian's outline drawn before the grass): on by default, they only darken (toward the line
colour), leave the sky alone, widen with village.contour_width, and the switch removes the
pass."""

from __future__ import annotations

import numpy as np
import pytest

from app.effects.village import Village
from app.effects.village.effect import contour_tap
from app.frame import Stage
from app.runtime import open_session, scene_params

SIZE = (160, 90)
LIGHT = ["village.resolution=65", "village.msaa=0", "fog.plane=false", "grass.blades=0",
         "village.camera=free"]
#: a house on the plaza's north side against the sky, from the south
CAMERA = dict(position=(0.0, 4.0, 6.0), yaw=0.0, pitch=2.0, fov=50.0)


@pytest.fixture(scope="module")
def village(gl_ctx):
    s = open_session("village", scene_params("village", sets=LIGHT), ctx=gl_ctx)
    target = s.gpu.target("test", "image", SIZE)
    yield s, target
    s.release()


def _render(village, target=None, **values):
    s, own = village
    target = target or own
    size = tuple(target.size)
    s.params.set("village.contours", True)
    s.params.set("village.contour_width", 1.0)
    for name, value in values.items():
        s.params.set(name.replace("__", "."), value)
    s.scene.camera.set(**CAMERA)
    frame = s.scene.frame(size, 0.0)
    s.scene.render(frame, target)
    return target.read()[..., :3], frame


def test_contours_are_on_by_default_and_only_darken(village):
    s, target = village
    assert next(p for p in Village.python_params() if p.name == "village.contours").default
    on, frame = _render(village)
    names = [p.name for p in s.scene.passes(frame, target)]
    assert "village.contours" in names
    off, frame = _render(village, village__contours=False)
    assert "village.contours" not in [p.name for p in s.scene.passes(frame, target)]
    lum_on, lum_off = on.mean(-1), off.mean(-1)
    changed = np.abs(lum_on - lum_off) > 2.0 / 255.0
    assert changed.mean() > 0.002  # the house's silhouette and corners
    assert np.mean(lum_on[changed] < lum_off[changed]) > 0.95
    assert np.isfinite(on).all()


def test_the_sky_is_never_outlined_and_the_width_widens_the_line(village):
    off, _ = _render(village, village__contours=False)
    thin, _ = _render(village)
    sky = np.zeros(SIZE[::-1], bool)
    sky[:6] = True  # the top rows look at the sky only
    assert np.abs(thin - off)[sky].max() <= 1.0 / 255.0
    assert [contour_tap(w, h) for w, h in ((1, 90), (1, 720), (4, 270), (2, 1080))] == \
        [1, 1, 2, 3]
    s, _ = village
    big = s.gpu.target("test", "big image", (320, 270))  # 4 px of 720 lines: 2 px taps
    off, _ = _render(village, big, village__contours=False)
    thin, _ = _render(village, big)
    wide, _ = _render(village, big, village__contour_width=4.0)
    s.gpu.free(big)
    n_thin = int((np.abs(thin - off).max(-1) > 2.0 / 255.0).sum())
    n_wide = int((np.abs(wide - off).max(-1) > 2.0 / 255.0).sum())
    assert n_wide > 1.3 * n_thin


def test_the_contour_pass_is_in_the_opaque_stage_before_the_grass(village):
    s, target = village
    _, frame = _render(village)
    passes = [p for p in s.scene.passes(frame, target) if p.stage == Stage.OPAQUE]
    names = [p.name for p in passes]
    assert names.index("village") < names.index("village.contours")
    if "grass" in names:
        assert names.index("village.contours") < names.index("grass")

"""The FixedHealth ring (spec/003 §2.15, criterion 36) drawn by the vr effect alone into a
target, against its twin app/sim/vr.py: Lives 8, Remaining 3 — sections k < 3 Color Full, the
rest Color Empty at 22.5° + 45°·k, gaps at multiples of 45°, alpha = Visibility × mask (read
from the ring blended over black and over white); centred at (ScreenX, ScreenY)·viewport ± 1
px and round in the corrected form, where the twin says in the document's and the
repository's; its size scales with Element Size; drawn regardless of depth; the acos mode's
mirror; Remaining beyond Lives; and when it shows (vr, always, off)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from app.effects.vr import Vr
from app.frame import FrameContext
from app.gpu.device import Gpu
from app.params import ParamSet
from app.sim import vr
from app.sim.camera import Camera
from tests.helpers import measures

SIZE = (200, 150)
RING = {"vr.lives": 8, "vr.remaining": 3.0, "vr.visibility": 0.5, "vr.element_size": 0.05,
        "vr.screen_x": 0.55, "vr.screen_y": 0.48, "vr.health_ring": "always"}
FULL, EMPTY = (1.0, 0.0, 0.0), (1.0, 0.706, 0.706)


@dataclass
class Rig:
    gpu: Gpu
    params: ParamSet
    effect: Vr

    def draw(self, size=SIZE, background=(0.0, 0.0, 0.0), depth: float = 1.0, eye=None,
             **sets) -> np.ndarray:
        """The ring (its pass, if the effect gives one) over a cleared target: (h, w, 3)."""
        for name, value in {**RING, **sets}.items():
            self.params.set(name, value)
        target = self.gpu.target("test", "ring", size)
        try:
            target.clear((*background, 1.0), depth=depth)
            frame = FrameContext(size=size, camera=Camera(), eye=eye)
            for p in self.effect.passes(frame, target):
                p.run()
            return target.read()[..., :3].copy()
        finally:
            self.gpu.free(target)
            for name in {**RING, **sets}:
                self.params.reset(name)

    def alpha(self, **sets) -> tuple[np.ndarray, np.ndarray]:
        """(alpha, colour·alpha) of the ring, from its blend over black and over white."""
        black = self.draw(background=(0.0, 0.0, 0.0), **sets)
        white = self.draw(background=(1.0, 1.0, 1.0), **sets)
        return 1.0 - (white - black).mean(-1), black


@pytest.fixture(scope="module")
def rig(gl_ctx):
    gpu = Gpu(gl_ctx)
    params = ParamSet(Vr.declare(gpu.shaders))
    effect = Vr(gpu, params)
    yield Rig(gpu, params, effect)
    effect.release()
    gpu.release()


def _twin(background, size=SIZE, **sets):
    p = {**RING, **sets}
    return vr.ring_image(size[0], size[1], p["vr.screen_x"], p["vr.screen_y"],
                         p["vr.element_size"], p["vr.lives"], p["vr.remaining"],
                         p["vr.visibility"], FULL, EMPTY, background=background,
                         form=p.get("vr.ring_aspect", "corrected"),
                         angle_mode=p.get("vr.ring_angle", "full"))


def _pixel(angle_deg: float, radius_px: float, centre, size=SIZE) -> tuple[int, int]:
    """(row, column) of the pixel at ``angle`` counter-clockwise from the right, ``radius``
    from the centre (window pixels, y up)."""
    x = centre[0] + radius_px * math.cos(math.radians(angle_deg))
    y = centre[1] + radius_px * math.sin(math.radians(angle_deg))
    return size[1] - 1 - int(math.floor(y)), int(math.floor(x))


def test_the_ring_matches_its_twin_pixel_for_pixel(rig):
    for background in ((0.0, 0.0, 0.0), (1.0, 1.0, 1.0)):
        img = rig.draw(background=background)
        want = _twin(background)
        err = np.abs(img - want).max(-1)
        assert (err < 1e-3).mean() > 0.995, (err > 1e-3).sum()
        assert err.max() < 0.5  # the few others are on the mask's ½ threshold or a gap's edge


def test_lives_8_remaining_3_colours_gaps_and_alpha(rig):
    alpha, premultiplied = rig.alpha()
    centre = (RING["vr.screen_x"] * SIZE[0], RING["vr.screen_y"] * SIZE[1])
    radius = vr.ring_half_extent_px(RING["vr.element_size"], *SIZE)[0]
    mid = radius * (vr.RING_INNER + vr.RING_OUTER) / 2  # the middle of the ring's band
    v = RING["vr.visibility"]
    for k in range(8):
        r, c = _pixel(22.5 + 45.0 * k, mid, centre)
        assert alpha[r, c] == pytest.approx(v, abs=2 / 255), k  # Visibility × mask (1)
        colour = premultiplied[r, c] / alpha[r, c]
        want = FULL if k < 3 else EMPTY
        assert np.allclose(colour, want, atol=3 / 255), (k, colour)
    for k in range(8):  # the gaps between the sections
        r, c = _pixel(45.0 * k, mid, centre)
        assert alpha[r, c] < 2 / 255, (k, alpha[r, c])
    # alpha = Visibility × mask everywhere: the twin's
    want = 1.0 - (_twin((1.0, 1.0, 1.0)) - _twin((0.0, 0.0, 0.0))).mean(-1)
    assert (np.abs(alpha - want) < 2 / 255).mean() > 0.995
    assert alpha.max() == pytest.approx(v, abs=2 / 255)


def test_visibility_scales_alpha_and_zero_hides_the_ring(rig):
    a1, _ = rig.alpha(**{"vr.visibility": 1.0})
    a5, _ = rig.alpha(**{"vr.visibility": 0.5})
    ring = a1 > 0.5
    assert ring.sum() > 500
    assert np.allclose(a5[ring], 0.5 * a1[ring], atol=2 / 255)
    assert np.abs(rig.draw(**{"vr.visibility": 0.0})).max() == 0.0


def _centre_and_extent(alpha: np.ndarray):
    cx, cy = measures.ring_centroid(alpha)
    rows, cols = np.nonzero(alpha > 1e-3)
    return (cx, cy), (cols.max() - cols.min() + 1, rows.max() - rows.min() + 1)


def test_the_ring_is_centred_at_screen_x_y_and_round(rig):
    for x, y in ((0.55, 0.48), (0.3, 0.62)):
        alpha, _ = rig.alpha(**{"vr.screen_x": x, "vr.screen_y": y})
        (cx, cy), (w, h) = _centre_and_extent(alpha)
        # the eight gaps are symmetric about the centre, and alpha does not depend on colour
        assert abs(cx - x * SIZE[0]) <= 1.0 and abs(cy - y * SIZE[1]) <= 1.0, (cx, cy)
        assert abs(w - h) <= 1, (w, h)


@pytest.mark.parametrize("form", ["document", "repository"])
def test_the_published_aspect_forms_fail_where_the_twin_says(rig, form):
    sets = {"vr.ring_aspect": form, "vr.element_size": 0.03, "vr.screen_y": 0.56}
    alpha, _ = rig.alpha(**sets)
    (cx, cy), (w, h) = _centre_and_extent(alpha)
    want_x, want_y = vr.ring_centre_px(RING["vr.screen_x"], 0.56, *SIZE, form=form)
    assert abs(cx - want_x) <= 1.0 and abs(cy - want_y) <= 1.0
    assert abs(cy - 0.56 * SIZE[1]) > 2.0  # not at Screen Y
    hx, hy = vr.ring_half_extent_px(0.03, *SIZE, form=form)
    assert abs(h / w - hy / hx) < 0.06
    if form == "document":
        assert h < 0.7 * w  # squashed: (H/W)² = 0.56


def test_the_size_scales_with_element_size(rig):
    widths = []
    for s in (0.02, 0.04):
        alpha, _ = rig.alpha(**{"vr.element_size": s})
        widths.append(_centre_and_extent(alpha)[1][0])
    want = [2 * vr.ring_half_extent_px(s, *SIZE)[0] * vr.RING_OUTER for s in (0.02, 0.04)]
    assert widths[1] / widths[0] == pytest.approx(2.0, abs=0.08)
    assert np.allclose(widths, want, atol=2.0)


def test_it_is_drawn_regardless_of_depth(rig):
    """ZTest Always: a target whose depth is at the near plane everywhere (as if a near opaque
    object covered the screen) still gets the whole ring."""
    far = rig.draw(depth=1.0)
    near = rig.draw(depth=0.0)
    assert np.abs(far).max() > 0.3
    assert np.array_equal(near, far)


def test_acos_mirrors_the_lower_half_onto_the_upper(rig):
    _, full = rig.alpha()
    _, acos = rig.alpha(**{"vr.ring_angle": "acos"})
    cy = SIZE[1] - RING["vr.screen_y"] * SIZE[1]  # the centre's row from the top
    r0 = int(round(cy))
    up, down = acos[r0 - 30:r0 - 3], acos[r0 + 3:r0 + 30][::-1]  # rows mirrored about it
    # the document's angle: the sections 225°–360° show 135°–0° (full there: red, no green)
    assert np.abs(up - down).max() < 0.05
    assert np.abs(full - acos).max() > 0.2  # the full angle is not mirrored


@pytest.mark.parametrize("remaining, full_sections", [(20.0, 8), (0.0, 0), (2.5, 3)])
def test_remaining_is_clamped_and_compared_with_each_section(rig, remaining, full_sections):
    alpha, premultiplied = rig.alpha(**{"vr.remaining": remaining})
    centre = (RING["vr.screen_x"] * SIZE[0], RING["vr.screen_y"] * SIZE[1])
    mid = vr.ring_half_extent_px(RING["vr.element_size"], *SIZE)[0] * 0.8
    greens = []
    for k in range(8):
        r, c = _pixel(22.5 + 45.0 * k, mid, centre)
        greens.append(premultiplied[r, c, 1] / alpha[r, c])
    assert sum(g < 0.05 for g in greens) == full_sections


def test_when_the_ring_shows(rig):
    assert np.abs(rig.draw(**{"vr.health_ring": "vr"})).max() == 0.0  # mono, not in VR
    assert np.abs(rig.draw(eye="left", **{"vr.health_ring": "vr"})).max() > 0.3
    rig.params.set("vr.enabled", True)
    try:
        assert np.abs(rig.draw(**{"vr.health_ring": "vr"})).max() > 0.3
        assert np.abs(rig.draw(**{"vr.health_ring": "off"})).max() == 0.0
    finally:
        rig.params.reset("vr.enabled")
    assert np.abs(rig.draw(**{"vr.health_ring": "always"})).max() > 0.3

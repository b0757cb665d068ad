"""World-space markers above the characters (spec/003 §2.15): drawn by the vr effect alone from
a frame's ``npcs`` slot — each icon's centre where the head's camera projects the point above
the head (± 1 px), its size that of a quad ``vr.marker_size`` wide at its depth, its colours its
role's icon; depth-tested against the image and writing no depth; none without characters;
shown in VR, always or never."""

from __future__ import annotations

import numpy as np
import pytest

from app.effects.vr import Vr
from app.frame import FrameContext, Npc
from app.gpu.device import Gpu
from app.params import ParamSet
from app.sim import vr
from app.sim.camera import Camera
from tests.helpers import measures

SIZE = (160, 120)
CAMERA = Camera(position=(0.0, 1.7, 6.0), yaw=0.0, pitch=-3.0, fov=60.0, near=0.1, far=200.0)
NPCS = [Npc("Lord Barus", "missions", (-1.6, 1.85, 0.0)),
        Npc("the vendor", "shop", (1.7, 1.7, -2.0)),
        Npc("a villager", "villager", (0.0, 1.65, -7.0))]


@pytest.fixture(scope="module")
def rig(gl_ctx):
    gpu = Gpu(gl_ctx)
    params = ParamSet(Vr.declare(gpu.shaders))
    effect = Vr(gpu, params)
    target = gpu.target("test", "markers", SIZE)
    yield gpu, params, effect, target
    effect.release()
    gpu.release()


def _draw(rig, background=(0.0, 0.0, 0.0), depth=1.0, npcs=NPCS, eye=None, **sets):
    gpu, params, effect, target = rig
    sets = {"vr.markers": "always", "vr.health_ring": "off", **sets}
    for k, v in sets.items():
        params.set(k, v)
    try:
        target.clear((*background, 1.0), depth=depth)
        frame = FrameContext(size=SIZE, camera=CAMERA, npcs=list(npcs), eye=eye)
        passes = effect.passes(frame, target)
        for p in passes:
            p.run()
        return target.read()[..., :3].copy(), passes
    finally:
        for k in sets:
            params.reset(k)


def _project(point):
    clip = (CAMERA.projection_matrix(SIZE[0] / SIZE[1]) @ CAMERA.view_matrix()
            @ np.append(np.asarray(point, float), 1.0))
    ndc = clip[:3] / clip[3]
    return (ndc[0] + 1) / 2 * SIZE[0], (ndc[1] + 1) / 2 * SIZE[1], clip[3]


def test_each_marker_sits_where_the_head_projects_at_its_size_in_its_roles_colours(rig):
    black, passes = _draw(rig)
    white, _ = _draw(rig, background=(1.0, 1.0, 1.0))
    assert [p.name for p in passes] == ["vr markers"]
    alpha = 1.0 - (white - black).mean(-1)
    lift, size = 0.55, 0.5
    focal = measures.focal_length_px(SIZE[1], CAMERA.fov)
    for npc in NPCS:
        x, y, depth = _project(vr.marker_centre(npc.head, lift))
        half = 0.5 * size * focal / depth
        r0, r1 = int(SIZE[1] - y - half - 3), int(SIZE[1] - y + half + 3)
        c0, c1 = int(x - half - 3), int(x + half + 3)
        window = np.zeros_like(alpha)
        window[max(r0, 0):r1, max(c0, 0):c1] = alpha[max(r0, 0):r1, max(c0, 0):c1]
        cx, cy = measures.ring_centroid(window)
        assert abs(cx - x) <= 1.0 and abs(cy - y) <= 1.0, (npc.name, (cx, cy), (x, y))
        cols = np.nonzero((window > 0.5).any(axis=0))[0]
        # the badge is a disc of radius 0.46 of the icon
        assert abs((cols.max() - cols.min() + 1) - 0.92 * 2 * half) <= 2.0, npc.name
        icon = vr.marker_icon(npc.role)
        want = icon[..., :3].sum((0, 1)) / icon[..., 3].sum()
        got = black[window > 0.5].sum(0) / alpha[window > 0.5].sum()
        assert np.allclose(got, want, atol=0.08), (npc.name, got, want)
    assert alpha[alpha > 1e-3].size < 0.2 * alpha.size  # nothing but the three icons


def test_markers_are_depth_tested_and_write_no_depth(rig):
    gpu, params, effect, target = rig
    hidden, _ = _draw(rig, depth=0.0)  # as if an opaque wall stood at the near plane
    assert np.abs(hidden).max() == 0.0
    shown, _ = _draw(rig)
    assert np.abs(shown).max() > 0.3
    assert np.all(target.read_depth() == 1.0)


def test_no_characters_no_markers_and_when_they_show(rig):
    _, passes = _draw(rig, npcs=[])
    assert passes == []
    for mode, eye, enabled, shown in (("vr", None, False, False), ("vr", "right", False, True),
                                      ("vr", None, True, True), ("off", "left", True, False),
                                      ("always", None, False, True)):
        rig[1].set("vr.enabled", enabled)
        try:
            img, passes = _draw(rig, eye=eye, **{"vr.markers": mode})
        finally:
            rig[1].reset("vr.enabled")
        assert ("vr markers" in [p.name for p in passes]) == shown, (mode, eye, enabled)
        assert (np.abs(img).max() > 0.3) == shown


def test_an_unknown_role_gets_the_villagers_icon(rig):
    stranger = [Npc("a stranger", "blacksmith", NPCS[2].head)]
    villager = [NPCS[2]]
    a, _ = _draw(rig, npcs=stranger)
    b, _ = _draw(rig, npcs=villager)
    assert np.abs(a).max() > 0.3 and np.array_equal(a, b)

"""VR mode in the village scene (spec/003 §2.15, criteria 35–36): with a fixed head camera
before Lord Barus's hall, the pair's halves differ and each is the mono render from that eye's
camera at the eye's size (the ring and the markers shown in both); the ring sits at (ScreenX,
ScreenY) of each eye's image, over opaque geometry, and is the frame's last pass; Barus's
marker is where his head projects in each eye; the hero's first-person camera (the scene's VR
camera) gives the eyes the head's orientation, IPD apart."""

from __future__ import annotations

import numpy as np
import pytest

from app.render.stereo import eye_size, eye_viewport
from app.runtime import open_session, scene_params
from app.sim import vr
from app.sim.camera import Camera
from tests.helpers import measures

SIZE = (128, 72)
HEAD = Camera(position=(0.0, 3.2, -11.0), yaw=0.0, pitch=-5.0, fov=60.0, near=0.1, far=2000.0)
RING = ("vr.lives=8", "vr.remaining=3", "vr.visibility=1", "vr.element_size=0.03",
        "vr.screen_x=0.4", "vr.screen_y=0.45")


@pytest.fixture(scope="module")
def village(gl_ctx):
    params = scene_params("village", sets=["village.camera=free", "vr.enabled=true", *RING])
    session = open_session("village", params, ctx=gl_ctx, camera=Camera(**vars(HEAD)))
    yield session
    session.release()


def _render(session, size=SIZE, **sets):
    """(image, frame) with ``sets`` applied for this render only."""
    old = {k: session.params[k] for k in sets}
    for k, v in sets.items():
        session.params.set(k, v)
    target = session.gpu.target("test", "village", size)
    try:
        frame = session.scene.frame(size, 0.0)
        session.scene.render(frame, target)
        return target.read()[..., :3].copy(), frame
    finally:
        session.gpu.free(target)
        for k, v in old.items():
            session.params.set(k, v)


@pytest.fixture(scope="module")
def pair(village):
    img, frame = _render(village)
    return img, dict(village.scene._stereo.last_eyes), frame


def _half(img, eye, size=SIZE):
    x, _, w, _ = eye_viewport(size, eye)
    return img[:, x:x + w]


def test_each_half_is_the_mono_render_from_its_eye(village, pair):
    img, eyes, _ = pair
    assert np.isfinite(img).all()
    assert np.abs(_half(img, "left") - _half(img, "right")).mean() > 1e-3
    mono_sets = {"vr.enabled": False, "vr.health_ring": "always", "vr.markers": "always"}
    try:
        for eye in ("left", "right"):
            village.scene.camera.set(position=eyes[eye].position)
            mono, _ = _render(village, size=eye_size(SIZE, 1.0, eye), **mono_sets)
            # the pair's shadow maps are drawn once from the head (the scene's choice: one
            # shadow render per stereo frame), the mono render's from the eye: the snapped
            # cascades fit 3.2 cm apart, so shadow edges may move by a texel
            diff = np.abs(_half(img, eye) - mono).max(-1)
            assert diff.mean() < 0.01 and np.mean(diff > 1e-4) < 0.05, eye
        # without the sun's shadows each half is exactly the mono render from its eye
        village.scene.camera.set(position=HEAD.position)
        flat, _ = _render(village, **{"village.shadow_sun": False})
        for eye in ("left", "right"):
            village.scene.camera.set(position=eyes[eye].position)
            mono, _ = _render(village, size=eye_size(SIZE, 1.0, eye),
                              **{**mono_sets, "village.shadow_sun": False})
            assert np.abs(_half(flat, eye) - mono).max() < 1e-4, eye
    finally:
        village.scene.camera.set(position=HEAD.position)


def test_the_ring_is_at_screen_x_y_of_each_eye_over_opaque_geometry(village, pair):
    img, _, _ = pair
    bare, _ = _render(village, **{"vr.health_ring": "off"})
    diff = np.abs(img - bare).max(-1)
    for eye in ("left", "right"):
        x0, _, w, h = eye_viewport(SIZE, eye)
        cx, cy = measures.ring_centroid(_half(diff, eye))
        assert abs(cx - 0.4 * w) <= 1.0 and abs(cy - 0.45 * h) <= 1.0, (eye, cx, cy)
        depth = village.scene._stereo.targets[eye].read_depth()
        row, col = int(h - 0.45 * h), int(0.4 * w)
        assert depth[row - 4:row + 4, col - 4:col + 4].max() < 1.0  # opaque geometry under it
    # in the mono frame (not VR) it is hidden by default
    mono, _ = _render(village, **{"vr.enabled": False})
    ringless, _ = _render(village, **{"vr.enabled": False, "vr.health_ring": "off"})
    assert np.array_equal(mono, ringless)


def test_the_ring_is_the_last_pass_of_the_frame(village):
    frame = village.scene.frame(SIZE, 0.0)
    target = village.gpu.target("test", "passes", SIZE)
    try:
        names = [p.name for p in village.scene.passes(frame, target)]
    finally:
        village.gpu.free(target)
    assert names[-1] == "vr health ring"
    assert "vr markers" in names  # the village fills the npcs slot


def test_barus_marker_is_where_his_head_projects_in_each_eye(village, pair):
    img, eyes, frame = pair
    bare, _ = _render(village, **{"vr.markers": "off"})
    barus = next(n for n in frame.npcs if n.role == "missions")
    centre = np.append(vr.marker_centre(barus.head, village.params["vr.marker_lift"]), 1.0)
    for eye in ("left", "right"):
        _, _, w, h = eye_viewport(SIZE, eye)
        cam = eyes[eye]
        clip = cam.projection_matrix(w / h) @ cam.view_matrix() @ centre
        x, y = (clip[0] / clip[3] + 1) / 2 * w, (clip[1] / clip[3] + 1) / 2 * h
        diff = np.abs(_half(img, eye) - _half(bare, eye)).max(-1)
        diff[int(h - 0.45 * h) - 12:, :] = 0.0  # the ring's own difference is not the marker's
        rows, cols = np.nonzero(diff > 0.05)
        near = (np.abs(cols + 0.5 - x) < 6) & (np.abs(h - rows - 0.5 - y) < 6)
        assert near.sum() >= 4, (eye, x, y)
        cx, cy = measures.ring_centroid(np.where(diff > 0.05, diff, 0.0) * (
            (np.abs(np.arange(w)[None, :] + 0.5 - x) < 6)
            & (np.abs(h - np.arange(h)[:, None] - 0.5 - y) < 6)))
        assert abs(cx - x) <= 1.0 and abs(cy - y) <= 1.5, (eye, (cx, cy), (x, y))


def test_markers_are_hidden_behind_the_village_and_seen_in_the_open(village):
    """From behind Lord Barus's hall his marker (and the vendor's) is hidden by the house; the
    villager's, in the open, shows: the markers are depth-tested against the village."""
    behind = Camera(position=(1.0, 3.0, -40.0), yaw=195.0, pitch=0.0, fov=70.0)
    village.scene.camera.set(position=behind.position, yaw=behind.yaw, pitch=behind.pitch,
                             fov=behind.fov)
    big = {"vr.marker_size": 1.5}  # 2 px at the villager's 37 m in a 64 × 72 eye: not sub-pixel
    try:
        img, frame = _render(village, **big)
        eyes = dict(village.scene._stereo.last_eyes)
        bare, _ = _render(village, **big, **{"vr.markers": "off"})
    finally:
        village.scene.camera.set(position=HEAD.position, yaw=HEAD.yaw, pitch=HEAD.pitch,
                                 fov=HEAD.fov)
    seen = {}
    for eye in ("left", "right"):
        _, _, w, h = eye_viewport(SIZE, eye)
        diff = np.abs(_half(img, eye) - _half(bare, eye)).max(-1)
        for npc in frame.npcs:
            cam = eyes[eye]
            c = np.append(vr.marker_centre(npc.head, village.params["vr.marker_lift"]), 1.0)
            clip = cam.projection_matrix(w / h) @ cam.view_matrix() @ c
            x, y = (clip[0] / clip[3] + 1) / 2 * w, h - (clip[1] / clip[3] + 1) / 2 * h
            assert 0 <= x < w and 0 <= y < h, npc.name  # each is in view...
            r0, c0 = int(y), int(x)
            seen[(eye, npc.role)] = diff[max(r0 - 3, 0):r0 + 4, max(c0 - 3, 0):c0 + 4].max()
    for eye in ("left", "right"):
        assert seen[(eye, "missions")] == 0.0 and seen[(eye, "shop")] == 0.0  # ...or hidden
        assert seen[(eye, "villager")] > 0.03


def test_in_vr_the_third_person_camera_becomes_the_heros_eyes(village):
    try:
        img, frame = _render(village, size=(64, 36), **{"village.camera": "third"})
        head = Camera(**{k: getattr(frame.camera, k) for k in vars(HEAD)})  # before restoring
        assert village.scene.camera_mode() == "free"  # restored
        village.params.set("village.camera", "third")
        assert village.scene.camera_mode() == "first"  # spec/003 §2.15: lowered to the head
    finally:
        village.params.set("village.camera", "free")
        village.scene.camera.set(position=HEAD.position, yaw=HEAD.yaw, pitch=HEAD.pitch,
                                 fov=HEAD.fov)
    eyes = village.scene._stereo.last_eyes
    hx, hz, _ = village.scene.village().hero()
    assert np.hypot(head.position[0] - hx, head.position[2] - hz) < 1e-6  # at the hero's head
    r, _, _ = head.basis()
    assert np.allclose(np.subtract(eyes["right"].position, eyes["left"].position),
                       village.params["vr.ipd"] * r)
    assert eyes["left"].yaw == head.yaw and eyes["left"].pitch == head.pitch
    assert np.isfinite(img).all()

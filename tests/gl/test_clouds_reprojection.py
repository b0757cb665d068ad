"""Temporal reprojection of the cloud layer: one pixel of each 4×4 block per frame, the rest
reprojected; with a still camera it converges to the full march, a turning camera stays close,
and the first frame (no history) is the full march itself."""

from __future__ import annotations

import numpy as np
import pytest

from app.colour import to_srgb8
from app.runtime import open_session, render_frames, scene_params

SIZE = (64, 36)


@pytest.fixture
def clouds(gl_ctx, tmp_path, monkeypatch):
    monkeypatch.setenv("NATURA_CACHE", str(tmp_path / "cache"))
    sessions = []

    def _open(*sets):
        base = ["time.hour=10", "clouds.preset=stratocumulus", "clouds.wind_speed=0",
                "bake_shape.size=32", "bake_detail.size=16", "bake_weather.size=64"]
        s = open_session("clouds", scene_params("clouds", sets=base + list(sets)), ctx=gl_ctx)
        sessions.append(s)
        return s

    yield _open
    for s in sessions:
        s.release()


def srgb(img):
    return to_srgb8(img[..., :3], 1.0, "aces").astype(float)


def test_first_frame_is_the_full_march(clouds):
    s = clouds("clouds.reprojection=off")
    full = next(render_frames(s, SIZE))
    # the bakes ran during this very frame (cold cache): the clouds must still be there
    layer = np.frombuffer(s.scene.effect("clouds")._layer.color.read(),
                          dtype="f4").reshape(SIZE[1], SIZE[0], 4)
    assert layer[..., 3].min() < 0.5
    reproj = next(render_frames(clouds("clouds.reprojection=on"), SIZE))
    assert np.abs(srgb(full) - srgb(reproj)).max() <= 1.0


def test_still_camera_converges_to_the_full_march(clouds):
    full = srgb(next(render_frames(clouds("clouds.reprojection=off"), SIZE)))
    s = clouds("clouds.reprojection=on")
    frames = list(render_frames(s, SIZE, frames=18))
    eff = s.scene.effect("clouds")
    assert eff._reprojection.full_marches == 1  # only the first frame marched every pixel
    last = srgb(frames[-1])
    err = np.abs(last - full).max(axis=-1)
    assert err.mean() < 2.0 and np.percentile(err, 99) < 24.0, (err.mean(), np.percentile(err, 99))


def test_turning_camera_stays_close_to_the_full_march(clouds):
    s = clouds("clouds.reprojection=on")
    ref = clouds("clouds.reprojection=off")
    gen = render_frames(s, SIZE, frames=24)
    for i in range(20):
        next(gen)
        s.scene.camera.rotate(0.3, 0.0)  # a slow pan: 0.3° per frame
    img = srgb(next(gen))
    ref.scene.camera.set(yaw=s.scene.camera.yaw, pitch=s.scene.camera.pitch)
    want = srgb(next(render_frames(ref, SIZE)))
    gen.close()
    err = np.abs(img - want).max(axis=-1)
    assert np.isfinite(img).all()
    assert err.mean() < 4.0, err.mean()


@pytest.mark.parametrize("mode", ["on", "off"])
def test_scene_depth_compare_mode_is_restored(clouds, mode):
    s = clouds(f"clouds.reprojection={mode}")
    target = s.gpu.target("test", "t", SIZE)
    target.depth.compare_func = "<="
    frame = s.scene.frame(SIZE)
    for _ in range(2):  # the second frame reprojects when on
        s.scene.render(frame, target)
    assert target.depth.compare_func == "<="
    s.gpu.free(target)

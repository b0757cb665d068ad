"""The reflection probe (spec/000 §1.7): the sky's environment cubemap re-renders only when the
sky changed, and its compute and fragment paths agree with each other and with the screen.
"""

from __future__ import annotations

import numpy as np

from app.effects.sky.effect import Sky
from app.runtime import open_session, render_frames, scene_params
from app.sim.camera import Camera
from app.sim.sky import cubemap_face_direction


def test_probe_scene_rerenders_cubemap_only_when_sky_changes(gl_ctx):
    params = scene_params("probe", sets=["sky.cubemap_size=16"])
    session = open_session("probe", params, ctx=gl_ctx)
    sky = session.scene.effect("sky")
    frames = render_frames(session, (32, 18), frames=8)
    next(frames)
    assert sky.environment_renders == 1
    next(frames)
    next(frames)  # paused time: nothing changed
    assert sky.environment_renders == 1
    params.set("time.hour", 15.0)
    next(frames)
    assert sky.environment_renders == 2
    params.set("sky.sun_size", 0.1)
    next(frames)
    assert sky.environment_renders == 3
    params.set("output.exposure", 2.0)  # not a sky parameter
    next(frames)
    assert sky.environment_renders == 3
    params.set("time.playing", True)  # time moves: the probe follows every frame
    next(frames)
    next(frames)
    assert sky.environment_renders == 5
    frames.close()
    session.release()


def test_cubemap_compute_and_fragment_paths_agree_and_match_the_screen(gl_ctx):
    n = 32
    session = open_session("probe", scene_params("probe", sets=[f"sky.cubemap_size={n}",
                                                                 "time.hour=17.5"]), ctx=gl_ctx)
    next(render_frames(session, (16, 16)))
    sky: Sky = session.scene.effect("sky")
    cube_a = sky.environment()
    cube_b = session.gpu.texture_cube("test", "fallback", n)
    sky._render_cubemap(cube_b, use_compute=False)
    faces_a = [np.frombuffer(cube_a.read(f), dtype=np.float16).reshape(n, n, 4).astype(np.float32)
               for f in range(6)]
    faces_b = [np.frombuffer(cube_b.read(f), dtype=np.float16).reshape(n, n, 4).astype(np.float32)
               for f in range(6)]
    for a, b in zip(faces_a, faces_b):
        assert np.allclose(a, b, rtol=2e-3, atol=2e-3)
    # face +X seen by a camera looking east with a 90° square view: same directions, mirrored
    # columns
    cam = Camera(position=(0, 2, 0), yaw=90.0, pitch=0.0, fov=90.0)
    screen = next(render_frames(open_session("sky", session.params, ctx=gl_ctx, camera=cam),
                                (n, n)))
    assert np.allclose(faces_a[0][:, ::-1, :3], screen[..., :3], rtol=3e-3, atol=3e-3)
    # and the twin of the face directions agrees with the camera twin
    st = (np.arange(n) + 0.5) / n * 2 - 1
    s, t = np.meshgrid(st, st)
    assert np.allclose(cubemap_face_direction(0, s, t)[:, ::-1], cam.ray_directions(n, n),
                       atol=1e-6)
    session.release()

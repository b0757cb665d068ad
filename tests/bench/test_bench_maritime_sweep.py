"""`natura bench maritime`'s sweep (app/bench/maritime.py): the amortised clouds graded from
the chase camera's eye, which stays where it is while the view pans. (The chase camera reads a
turn of the view as an orbit about the boat: before, each row's pan lowered the eye, and after
three rows it was under the waves, where the clouds are not seen and every error read 0.)"""

from __future__ import annotations

import numpy as np
import pytest

from app.runtime import open_session, scene_params

pytestmark = pytest.mark.slow  # a maritime session and seven sweeps: ~10 s on llvmpipe

SETS = ["ocean.fft_size=64", "sky.cubemap_size=16", "boat.fittings=false",
        "clouds_b.volume_resolution=16", "clouds_b.detail_resolution=8"]


def test_the_sweep_pans_from_the_chase_cameras_eye_above_the_sea(gl_ctx, tmp_path, monkeypatch):
    from app.bench import maritime

    monkeypatch.setenv("NATURA_CACHE", str(tmp_path / "cache"))
    # the sweep's wake figure (a maritime session of its own, 40 s sailed: ~2.7 s) is not read
    # here: tests/bench/test_bench_maritime_wake.py grades it
    monkeypatch.setattr(maritime, "wake_angle", lambda ctx, shader_root=None: {})
    session = open_session("maritime", scene_params("maritime", sets=SETS), ctx=gl_ctx)
    try:
        session.scene.frame((48, 27), 0.0)
        eye = np.array(session.scene.camera.position, dtype=float)
        report = maritime.sweep(session, (48, 27), warmup=0, repeat=1)["amortised"]
        assert session.params["maritime.camera"] == "chase"  # restored
        session.scene.frame((48, 27), 0.0)
        after = np.array(session.scene.camera.position, dtype=float)
    finally:
        session.release()
    assert eye[1] > 1.0
    np.testing.assert_allclose(after, eye, atol=1e-6)  # the sweep left the chase camera's orbit
    rows = report["rows"][1:]
    assert len(rows) == 6
    # the clouds are in view at the end of every pan: the amortised image differs from its
    # reference somewhere (under the sea the two were equal, error 0 exactly)
    assert all(r["pan"]["mean"] > 0.0 for r in rows), [r["pan"] for r in rows]

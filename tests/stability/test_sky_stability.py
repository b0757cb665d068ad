"""The day–night sky over 24 hours: no NaN/Inf on screen or in the environment cubemap."""

from __future__ import annotations

import numpy as np

# ---- stability -----------------------------------------------------------------------------------

def test_no_nan_or_inf_over_24_hours(render):
    _, session = render("probe", (32, 18))
    from app.runtime import render_frames

    for h in np.arange(0.0, 24.0, 0.25):
        session.params.set("time.hour", float(h))
        img = next(render_frames(session, (32, 18)))
        assert np.isfinite(img).all(), h
        cube = session.scene.effect("sky").environment()
        data = np.concatenate([np.frombuffer(cube.read(f), dtype=np.float16) for f in range(6)])
        assert np.isfinite(data).all(), h

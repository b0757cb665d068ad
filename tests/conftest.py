"""Shared fixtures: one standalone EGL context for the whole run (llvmpipe on CI), created only
when a test asks for it; and the layer markers, one per folder (tests/unit, tests/gl, …)."""

from __future__ import annotations

from pathlib import Path

import pytest

from app.gpu.context import create_headless_context
from app.gpu.device import Gpu
from app.runtime import open_session, render_frames, scene_params
from app.sim.camera import Camera

#: fixtures a domain's GL tests and its stability sweeps share (tests/helpers/fixtures.py)
pytest_plugins = ["tests.helpers.fixtures"]

TESTS = Path(__file__).resolve().parent
#: the folders under tests/ and the marker each gives its tests (registered in pyproject.toml)
LAYERS = ("unit", "gl", "stability", "bench", "cli", "window")


def pytest_collection_modifyitems(config, items):
    """Every test gets the marker of its folder: ``pytest -m unit`` selects tests/unit."""
    for item in items:
        try:
            folder = Path(item.path).resolve().relative_to(TESTS).parts[0]
        except ValueError:
            continue
        if folder in LAYERS:
            item.add_marker(getattr(pytest.mark, folder))


@pytest.fixture(scope="session")
def gl_ctx():
    ctx = create_headless_context()
    yield ctx
    ctx.release()


@pytest.fixture
def gpu(gl_ctx):
    g = Gpu(gl_ctx)
    yield g
    g.release()


@pytest.fixture
def render(gl_ctx):
    """render(scene, size, sets=..., camera=...) → (image (h, w, 4) float32, session)."""
    sessions = []

    def _render(scene="sky", size=(160, 90), sets=(), camera: Camera | None = None,
                frames: int = 1, fps=30.0):
        params = scene_params(scene, sets=sets)
        session = open_session(scene, params, ctx=gl_ctx, camera=camera)
        sessions.append(session)
        images = list(render_frames(session, size, frames, fps))
        return (images[0] if frames == 1 else images), session

    yield _render
    for s in sessions:
        s.release()

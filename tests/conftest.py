"""Shared fixtures: one standalone EGL context for the whole run (llvmpipe on CI), created only
when a test asks for it; and the layer markers, one per folder (tests/unit, tests/gl, …)."""

from __future__ import annotations

import gc
import os
import sys
from pathlib import Path

import pytest

from app.bakes import CACHE_ENV
from app.gpu.context import create_headless_context
from app.gpu.device import Gpu
from app.runtime import open_session, render_frames, scene_params
from app.sim.camera import Camera

#: fixtures a domain's GL tests and its stability sweeps share (tests/helpers/fixtures.py)
pytest_plugins = ["tests.helpers.fixtures", "tests.helpers.tiers", "tests.helpers.cores"]

TESTS = Path(__file__).resolve().parent
#: a natura process a test starts that dies of a signal (a driver crash) prints where it was
os.environ.setdefault("PYTHONFAULTHANDLER", "1")
#: pytest keeps each test module's assertion-rewritten bytecode in tests/**/__pycache__ (ignored
#: by git), as setup.sh compiles app/, even where $PYTHONDONTWRITEBYTECODE is set: without it
#: every worker rewrites all ~300 modules on each run (collecting the suite took 9.9 s of CPU
#: a process, 2.5 s with the bytecode kept). Only this process: the ones the tests start are
#: set up by ``session_cache`` below.
sys.dont_write_bytecode = False
#: the folders under tests/ and the marker each gives its tests (registered in pyproject.toml)
LAYERS = ("unit", "gl", "stability", "bench", "cli", "window")


@pytest.hookimpl(tryfirst=True)  # before xdist's, which turns the groups into node ids
def pytest_collection_modifyitems(config, items):
    """Every test gets the marker of its folder: ``pytest -m unit`` selects tests/unit. Under
    pytest-xdist (``-n``, with ``--dist loadgroup``) the tests of a module that share a
    module-scoped fixture (a bench run, a scene with its programs) run on one worker, so the
    fixture is made once, not once per worker. (The window tests spread over the workers: each
    worker's Xvfb displays are numbered apart, tests/helpers/window_driver.py.)"""
    from tests.helpers.tiers import uses_module_fixture  # the plugin, loaded by now

    xdist = config.pluginmanager.hasplugin("xdist")
    for item in items:
        try:
            folder = Path(item.path).resolve().relative_to(TESTS).parts[0]
        except ValueError:
            continue
        if folder in LAYERS:
            item.add_marker(getattr(pytest.mark, folder))
        if not xdist:
            continue
        if uses_module_fixture(item):
            item.add_marker(pytest.mark.xdist_group(f"module {item.path.name}"))


def pytest_collection_finish(session):
    """What collection made (the test modules, their items, the imported app) lives to the end
    of the run: frozen out of the garbage collector's generations, so its later full collections
    (and the leak tests' explicit ones) no longer walk it. ``gc.get_objects`` does not list
    frozen objects; no GL object exists yet at this point."""
    gc.freeze()


@pytest.fixture(scope="session", autouse=True)
def session_cache(tmp_path_factory):
    """One ``$NATURA_CACHE`` (noise bakes, moon and star textures) for the whole run and the
    ``natura`` processes it starts: each bake is made once per run, not once per module, and
    the user's own cache is neither read nor written. Under pytest-xdist the workers share it
    (cache files are written atomically). Tests of the cache itself point $NATURA_CACHE
    elsewhere with monkeypatch."""
    base = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        base = base.parent  # the run's folder, above the worker's own
    cache = base / "natura-cache"
    cache.mkdir(parents=True, exist_ok=True)
    # the processes the tests start compile Natura's modules once per run, into the run's cache,
    # even where the environment asks Python not to write bytecode (each process would
    # otherwise compile every module it imports again: ~0.1-0.35 s of CPU a process)
    saved = {k: os.environ.get(k) for k in (CACHE_ENV, "PYTHONPYCACHEPREFIX",
                                            "PYTHONDONTWRITEBYTECODE")}
    os.environ[CACHE_ENV] = str(cache)
    os.environ["PYTHONPYCACHEPREFIX"] = str(cache / "pycache")
    os.environ.pop("PYTHONDONTWRITEBYTECODE", None)
    yield cache
    for key, value in saved.items():
        if value is None:
            os.environ.pop(key, None)
        else:
            os.environ[key] = value


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


@pytest.fixture(scope="module")
def module_gpu(gl_ctx):
    """One :class:`Gpu` for a module's tests (for module-scoped fixtures that build on it)."""
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

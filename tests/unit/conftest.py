"""tests/unit runs without a GL context: numpy twins, parameters, key maps, bake specs, cache
logic. A test here that asks for the GL fixtures, or creates a context any other way, fails
loudly with where it belongs."""

from __future__ import annotations

import moderngl
import pytest

import app.gpu.context
import app.gpu.device

MESSAGE = "unit tests run without GL: move this test to tests/gl"
#: the root conftest's fixtures that make or hold a context
GL_FIXTURES = ("gl_ctx", "gpu", "render")


def _no_context(*args, **kwargs):
    raise RuntimeError(MESSAGE)


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_setup(item):
    """Before any fixture is set up: the session's shared context is never made (or lent) for a
    unit test."""
    wanted = [name for name in GL_FIXTURES if name in getattr(item, "fixturenames", ())]
    if wanted:
        raise RuntimeError(f"{MESSAGE} (it asks for {', '.join(wanted)})")


@pytest.fixture(autouse=True)
def no_gl_context(monkeypatch):
    """Every way the app and moderngl make a context raises instead."""
    monkeypatch.setattr(moderngl, "create_context", _no_context)
    monkeypatch.setattr(moderngl, "create_standalone_context", _no_context)
    monkeypatch.setattr(app.gpu.context, "create_headless_context", _no_context)
    monkeypatch.setattr(app.gpu.device, "create_headless_context", _no_context)

"""Making a headless context (app.gpu.context) without one: the versions asked for, newest
first, and the version a capped driver gave remembered so the next context does not ask for
the newer ones again — while the environment is the same."""

from __future__ import annotations

import moderngl

from app.gpu import context


def _fake_driver(monkeypatch, newest: int) -> list[int]:
    asked: list[int] = []

    def create_context(standalone, require, **kw):
        asked.append(require)
        if require > newest:
            raise RuntimeError(f"no {require} context")
        return f"context {require}"

    monkeypatch.setattr(moderngl, "create_context", create_context)
    monkeypatch.setattr(context, "_MADE_AT", {})
    return asked


def test_a_capped_driver_is_asked_for_the_newer_versions_once(monkeypatch):
    asked = _fake_driver(monkeypatch, 410)
    assert context._try(context.VERSIONS, 330, backend="egl") == ("context 410", None)
    assert asked == [450, 430, 410]
    asked.clear()
    assert context._try(context.VERSIONS, 330, backend="egl") == ("context 410", None)
    assert asked == [410]
    asked.clear()
    monkeypatch.setenv("MESA_GL_VERSION_OVERRIDE", "4.5")  # another environment: from the top
    assert context._try(context.VERSIONS, 330, backend="egl")[0] == "context 410"
    assert asked == [450, 430, 410]


def test_a_driver_without_the_version_required_fails_as_before(monkeypatch):
    asked = _fake_driver(monkeypatch, 330)
    ctx, error = context._try(context.VERSIONS, 410, backend="egl")
    assert ctx is None and str(error) == "no 410 context" and asked == [450, 430, 410]
    assert context._try(context.VERSIONS, 330, backend="egl")[0] == "context 330"
    asked.clear()
    ctx, error = context._try(context.VERSIONS, 410, backend="egl")  # still every version
    assert ctx is None and asked == [450, 430, 410]

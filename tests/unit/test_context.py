"""Making a headless context (app.gpu.context) without one: the versions asked for, newest
first, down to the one required."""

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
    return asked


def test_a_capped_driver_gives_the_newest_version_it_has(monkeypatch):
    asked = _fake_driver(monkeypatch, 410)
    assert context._try(context.VERSIONS, 330, backend="egl") == ("context 410", None)
    assert asked == [450, 430, 410]


def test_a_driver_without_the_version_required_fails(monkeypatch):
    asked = _fake_driver(monkeypatch, 330)
    ctx, error = context._try(context.VERSIONS, 410, backend="egl")
    assert ctx is None and str(error) == "no 410 context" and asked == [450, 430, 410]
    assert context._try(context.VERSIONS, 330, backend="egl")[0] == "context 330"

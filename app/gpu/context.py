"""OpenGL contexts and what they can do.

Headless work uses a standalone context: EGL first (Mesa's llvmpipe on machines without a GPU,
the vendor's driver on a GPU), then — where EGL is missing — the platform's own standalone
context through moderngl's default backend: CGL on macOS, WGL on Windows, GLX on Linux (which
needs an X display). The desktop window gets its context from moderngl-window
(``app.ui.window``). :func:`describe_context` says in one line which context a command got.
"""

from __future__ import annotations

import os
import sys
from dataclasses import dataclass
from typing import Callable

import moderngl

from ..errors import GpuUnavailableError

#: the versions asked for, newest first: 4.5 and 4.3 (compute shaders), 4.1 (macOS's last),
#: 3.3 (the least Natura runs on)
VERSIONS = (450, 430, 410, 330)
#: where a context's backend is recorded (``ctx.extra`` is a dict Natura owns)
BACKEND_KEY = "natura.backend"

_announce: Callable[[str], None] | None = None


@dataclass(frozen=True)
class Caps:
    """What the current context offers."""

    version_code: int
    renderer: str
    vendor: str
    max_samples: int = 0
    extensions: frozenset[str] = frozenset()

    @property
    def compute(self) -> bool:
        """Compute shaders and image load/store (GL ≥ 4.3). macOS stops at 4.1."""
        return self.version_code >= 430

    @property
    def software(self) -> bool:
        """A CPU rasteriser: timer queries are unreliable there (docs/architecture.md,
        Measuring)."""
        r = self.renderer.lower()
        return any(s in r for s in ("llvmpipe", "softpipe", "swrast", "software"))

    @property
    def gpu_timers(self) -> bool:
        """Whether GPU timer queries are worth reading (a hardware GPU; GL 3.3 has them)."""
        return not self.software

    @property
    def pipeline_statistics(self) -> bool:
        return "GL_ARB_pipeline_statistics_query" in self.extensions

    def describe(self) -> str:
        return f"{self.renderer} (GL {self.version_code // 100}.{self.version_code % 100 // 10})"


def caps_of(ctx: moderngl.Context) -> Caps:
    info = ctx.info
    return Caps(ctx.version_code, str(info.get("GL_RENDERER", "?")),
                str(info.get("GL_VENDOR", "?")), int(ctx.max_samples), frozenset(ctx.extensions))


def platform_backend() -> str:
    """The name of moderngl's default standalone backend on this platform."""
    if sys.platform == "darwin":
        return "CGL"
    if sys.platform.startswith("win"):
        return "WGL"
    return "GLX"


def backend_of(ctx: moderngl.Context) -> str:
    """How ``ctx`` was made: ``EGL``, ``GLX``/``CGL``/``WGL`` or ``window`` (a window's)."""
    extra = ctx.extra if isinstance(ctx.extra, dict) else {}
    return str(extra.get(BACKEND_KEY, "window"))


def _mark(ctx: moderngl.Context, backend: str) -> moderngl.Context:
    extra = ctx.extra if isinstance(ctx.extra, dict) else {}
    extra[BACKEND_KEY] = backend
    ctx.extra = extra
    return ctx


def _try(versions, require: int, **kw) -> tuple[moderngl.Context | None, Exception | None]:
    last: Exception | None = None
    for version in (v for v in versions if v >= require):
        try:
            return moderngl.create_context(standalone=True, require=version, **kw), None
        except Exception as exc:  # moderngl and glcontext raise plain Exception subclasses
            last = exc
    return None, last


def create_headless_context(require: int = 330) -> moderngl.Context:
    """A standalone context, the newest core version available: through EGL, else through the
    platform's default backend (CGL, WGL, or GLX with a display)."""
    ctx, egl_error = _try(VERSIONS, require, backend="egl")
    if ctx is not None:
        return _announced(_mark(ctx, "EGL"))
    backend = platform_backend()
    if backend == "GLX" and not os.environ.get("DISPLAY"):
        native_error: Exception | None = RuntimeError("no X display ($DISPLAY is not set)")
    else:
        ctx, native_error = _try(VERSIONS, require)
        if ctx is not None:
            return _announced(_mark(ctx, backend))
    raise GpuUnavailableError(
        f"no OpenGL {require // 100}.{require % 100 // 10} context: EGL: {_short(egl_error)}; "
        f"{backend}: {_short(native_error)} (Debian: apt-get install libegl1 libgl1-mesa-dri)")


def _short(exc: Exception | None) -> str:
    text = " ".join(str(exc).split()) if exc is not None else "not tried"
    return text[:70] or type(exc).__name__


def describe_context(ctx: moderngl.Context) -> str:
    """One line: the version string, how the context was made, the renderer and vendor."""
    info = ctx.info
    version = str(info.get("GL_VERSION", f"{ctx.version_code}"))
    return (f"OpenGL {version} through {backend_of(ctx)}: {info.get('GL_RENDERER', '?')} "
            f"({info.get('GL_VENDOR', '?')})")


def announce_contexts(callback: Callable[[str], None] | None) -> None:
    """Have the next headless context described to ``callback`` once (None: stop). The
    command line uses it so that render, bench, compare and report say which context they
    got."""
    global _announce
    _announce = callback


def _announced(ctx: moderngl.Context) -> moderngl.Context:
    global _announce
    callback, _announce = _announce, None
    if callback is not None:
        callback(describe_context(ctx))
    return ctx

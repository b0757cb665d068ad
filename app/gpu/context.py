"""OpenGL contexts and what they can do.

Headless work uses a standalone EGL context (Mesa's llvmpipe on machines without a GPU);
the desktop window gets its context from moderngl-window (``app.ui.window``).
"""

from __future__ import annotations

from dataclasses import dataclass

import moderngl

from ..errors import GpuUnavailableError


@dataclass(frozen=True)
class Caps:
    """What the current context offers."""

    version_code: int
    renderer: str
    vendor: str

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

    def describe(self) -> str:
        return f"{self.renderer} (GL {self.version_code // 100}.{self.version_code % 100 // 10})"


def caps_of(ctx: moderngl.Context) -> Caps:
    info = ctx.info
    return Caps(ctx.version_code, str(info.get("GL_RENDERER", "?")),
                str(info.get("GL_VENDOR", "?")))


def create_headless_context(require: int = 330) -> moderngl.Context:
    """A standalone EGL context, the newest core version available (4.5, 4.3, then 3.3)."""
    last = None
    for version in (450, 430, 330):
        if version < require:
            continue
        try:
            return moderngl.create_context(standalone=True, backend="egl", require=version)  # type: ignore[arg-type]
        except Exception as exc:  # moderngl raises plain Exception subclasses here
            last = exc
    raise GpuUnavailableError(
        f"no OpenGL {require // 100}.{require % 100 // 10} context through EGL ({last}): "
        "install Mesa's EGL and DRI drivers (Debian: libegl1 libgl1-mesa-dri)"
    )

"""What a program is made of, and the one full-screen draw every pass shares.

A :class:`ProgramSpec` names a program of the shader library (``app.gpu.shaders``) by its path
under the shader root, with optional explicit stage files and defines. Effects list their specs
(``natura shaders check`` compiles every one, and their ``// @param`` annotations become
parameters); anything that draws gets the compiled program with ``gpu.program(owner, spec)``.

A full-screen pass is ``common/fullscreen.vert`` (one triangle that covers the viewport) plus a
fragment shader: :func:`fullscreen` builds its spec, :func:`draw_fullscreen` draws it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import moderngl

if TYPE_CHECKING:
    from .shaders import Program

#: The vertex shader of every full-screen pass.
FULLSCREEN_VERT = "common/fullscreen.vert"


@dataclass(frozen=True)
class ProgramSpec:
    """A program by library name, with optional explicit stage files and defines."""

    name: str
    vert: str | None = None
    frag: str | None = None
    comp: str | None = None
    defines: tuple[tuple[str, Any], ...] = ()
    requires_compute: bool = False

    def stages(self) -> dict[str, str | None]:
        return {"vert": self.vert, "frag": self.frag, "comp": self.comp}


def fullscreen(frag_name: str, **kw: Any) -> ProgramSpec:
    """A full-screen pass: the shared triangle vertex shader plus ``<frag_name>.frag``."""
    return ProgramSpec(frag_name, vert=FULLSCREEN_VERT, frag=f"{frag_name}.frag", **kw)


def draw_fullscreen(prog: Program, blend: tuple[int, int, int, int] | None = None) -> None:
    """Draw the full-screen triangle with ``prog`` into the bound framebuffer. ``blend``
    (source and destination factors for colour, then for alpha) blends the pass over what the
    framebuffer holds, and blending is off again afterwards; other GL state (depth test,
    viewport) is the caller's."""
    if blend is None:
        prog.vao().render(moderngl.TRIANGLES, vertices=3)
        return
    ctx = prog.library.ctx
    ctx.enable(moderngl.BLEND)
    ctx.blend_func = blend  # type: ignore[assignment]  # 2 or 4 factors
    try:
        prog.vao().render(moderngl.TRIANGLES, vertices=3)
    finally:
        ctx.blend_func = moderngl.DEFAULT_BLENDING  # type: ignore[assignment]
        ctx.disable(moderngl.BLEND)

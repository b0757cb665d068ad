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


def draw_fullscreen(prog: Program) -> None:
    """Draw the full-screen triangle with ``prog`` into the bound framebuffer (GL state —
    depth test, blending, viewport — is the caller's)."""
    prog.vao().render(moderngl.TRIANGLES, vertices=3)

"""The three ways the grass effect draws its blades (spec/003 §2.9; app/effects/grass/effect.py
chooses one with ``grass.method``). Each holds its GPU buffers under the effect's owner, built
from the shared placement (app/sim/grass.py) and rebuilt only when its key changes, and draws
with the uniforms the effect has already set on its program (light, shadows, fog, wind,
camera).

* :class:`GeometryBlades` — the thesis's geometry-shader pyramids: one root triangle per blade
  (jittered roots, or the thesis's regular grid mesh), one program per section count S (its
  ``max_vertices`` declared for that S).
* :class:`CrossedBillboards` — the thesis's final grass: one instance per unit of n crossed
  planes, the tuft atlas, alpha to coverage on a multisampled target, else the alpha cutoff.
* :class:`InstancedBlades` — beyond the thesis: one instanced Bézier-blade strip per blade,
  culled on the CPU per tile of blades (frustum and distance), drawn with two levels of detail
  through ``glMultiDrawArraysIndirect`` (each visible run of tiles one command, its first
  blade the command's base instance), or all blades in one draw when culling is off.
"""

from __future__ import annotations

from typing import Any

import moderngl
import numpy as np

from ...gpu.programs import ProgramSpec
from ...sim import grass as gs

#: GL_SAMPLE_ALPHA_TO_COVERAGE and GL_SAMPLE_ALPHA_TO_ONE (moderngl has no names for them)
GL_SAMPLE_ALPHA_TO_COVERAGE = 0x809E
GL_SAMPLE_ALPHA_TO_ONE = 0x809F
#: bytes of one glMultiDrawArraysIndirect command as moderngl strides them (count,
#: instanceCount, first, baseInstance and a pad: moderngl uses the 20-byte elements stride)
INDIRECT_STRIDE = 20
#: bytes of one blade's per-instance row (root xyz, id): 4 floats
ROOT_STRIDE = 16


def gs_program(sections: int) -> ProgramSpec:
    """The geometry-shader program for S sections (its max_vertices 3·(6(S − 1) + 3))."""
    return ProgramSpec("grass/blades_gs", defines=(("GS_SECTIONS", int(sections)),
                                                   ("GS_MAX_VERTICES",
                                                    gs.gs_max_vertices(sections))))


GS_PROGRAMS = tuple(gs_program(s) for s in range(gs.GS_SECTIONS[0], gs.GS_SECTIONS[1] + 1))
BILLBOARD = ProgramSpec("grass/billboard")
INSTANCED = ProgramSpec("grass/instanced")


class _Method:
    def __init__(self, gpu, owner: str, keyed):
        self.gpu = gpu
        self.owner = owner
        self.keyed = keyed
        self._make: Any = None  # what builds the value a keyed get is about to ask for
        #: what the last draw drew: blades, triangles (expected), draw calls
        self.last: dict[str, Any] = {}

    def _held(self, keyed, key, make):
        """``keyed``'s value for ``key`` (plain values), built by ``make()`` when it changed."""
        self._make = make
        return keyed.get(key)

    def _buffer(self, name: str, data: np.ndarray):
        if data.nbytes == 0:
            data = np.zeros(4, np.float32)  # a GL buffer cannot be empty
        return self.gpu.buffer(self.owner, name, np.ascontiguousarray(data).tobytes())

    def _free(self, buffer) -> None:
        if buffer is not None:
            self.gpu.free(buffer)


class GeometryBlades(_Method):
    """spec/003 §2.9 a: the root triangles of every blade in one vertex buffer."""

    def __init__(self, gpu, owner, keyed):
        super().__init__(gpu, owner, keyed)
        self._tris = keyed(self._build, lambda v: self._free(v[0]))

    def _build(self, key):
        triangles = self._make()
        data = np.asarray(triangles, np.float32).reshape(-1, 3)
        return (self._buffer("geometry grass roots", data), len(triangles))

    def draw(self, prog, key, triangles_of, sections: int) -> None:
        vbo, count = self._held(self._tris, key, triangles_of)
        self.last = {"blades": count, "triangles": count * gs.gs_triangles_per_blade(sections),
                     "draws": 1 if count else 0}
        if count:
            prog.vao([(vbo, "3f", "in_position")]).render(moderngl.TRIANGLES, vertices=3 * count)


def _plane_mesh() -> np.ndarray:
    """Four planes of two triangles each (24 rows: corner x, corner y, plane index)."""
    quad = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
    return np.asarray([(x, y, k) for k in range(4) for x, y in quad], np.float32)


class CrossedBillboards(_Method):
    """spec/003 §2.9 b: the units' instance rows and the shared four-plane mesh."""

    def __init__(self, gpu, owner, keyed):
        super().__init__(gpu, owner, keyed)
        self._units = keyed(self._build, lambda v: self._free(v[0]))
        self._mesh = None

    def _build(self, key):
        units = self._make()
        return (self._buffer("billboard units", units.instance_data()), len(units))

    def mesh(self):
        if self._mesh is None:
            self._mesh = self._buffer("billboard planes", _plane_mesh())
        return self._mesh

    def _content(self, vbo) -> list:
        return [(self.mesh(), "2f 1f", "in_corner", "in_plane"),
                (vbo, "3f 4f 3f/i", "in_centre", "in_unit", "in_tint")]

    def draw(self, prog, key, units_of, planes: int, target) -> None:
        vbo, count = self._held(self._units, key, units_of)
        self._render(prog, prog.vao(self._content(vbo)), count, planes, target)

    def draw_once(self, prog, units: gs.Units, planes: int, target) -> None:
        """``units`` from a buffer and a vertex array made for this draw and freed after it
        (not kept in the program's cache of vertex arrays)."""
        vbo = self._buffer("billboard units (once)", units.instance_data())
        vao = self.gpu.ctx.vertex_array(prog.program, self._content(vbo), skip_errors=True)
        try:
            self._render(prog, vao, len(units), planes, target)
        finally:
            vao.release()
            self.gpu.free(vbo)

    def _render(self, prog, vao, count: int, planes: int, target) -> None:
        ctx = self.gpu.ctx
        a2c = int(getattr(target, "samples", 0) or 0) > 0
        prog.set("uAlphaToCoverage", a2c)
        self.last = {"units": count, "blades": count * gs.BLADES_PER_TUFT,
                     "triangles": count * planes * 2, "draws": 1 if count else 0,
                     "alpha_to_coverage": a2c}
        if not count:
            return
        if a2c:
            ctx.enable_direct(GL_SAMPLE_ALPHA_TO_COVERAGE)
            ctx.enable_direct(GL_SAMPLE_ALPHA_TO_ONE)
        try:
            vao.render(moderngl.TRIANGLES, vertices=6 * planes, instances=count)
        finally:
            if a2c:
                ctx.disable_direct(GL_SAMPLE_ALPHA_TO_ONE)
                ctx.disable_direct(GL_SAMPLE_ALPHA_TO_COVERAGE)

    def release(self) -> None:
        if self._mesh is not None:
            self.gpu.free(self._mesh)
            self._mesh = None


class InstancedBlades(_Method):
    """Beyond the thesis (Wohllaib 2021): the blades sorted by tile, two strip meshes (full and
    LOD segments), culled per tile on the CPU each frame."""

    def __init__(self, gpu, owner, keyed):
        super().__init__(gpu, owner, keyed)
        self._blades = keyed(self._build, lambda v: self._free(v[0]))
        self._strips = keyed(self._build_strip, self._free)
        self._lod_strips = keyed(self._build_strip, self._free)
        self._indirect: list = []
        #: one indirect draw per LOD needs GL 4.3 (glMultiDrawArraysIndirect with a base
        #: instance); before it (macOS stops at 4.1) each run of visible tiles is one instanced
        #: draw with the per-instance roots bound from the run's first blade: the same blades,
        #: more draw calls
        self.indirect_ok = gpu.ctx.version_code >= 430

    def _build(self, key):
        roots, reach = self._make()
        tiles = gs.make_tiles(roots, reach)
        rows = np.zeros((len(roots), 4), np.float32)
        if len(roots):
            rows[:, :3] = np.asarray(roots)[tiles.order]
            rows[:, 3] = tiles.order  # the blade's id: its place in the placement
        return (self._buffer("instanced blades", rows), tiles, len(roots))

    def _build_strip(self, segments):
        return self._buffer(f"blade strip {segments}", gs.blade_strip(segments))

    def _commands(self, slot: int, runs: list[tuple[int, int]], vertices: int):
        need = max(1, len(runs)) * INDIRECT_STRIDE
        while len(self._indirect) <= slot:
            self._indirect.append(None)
        buf = self._indirect[slot]
        if buf is None or buf.size < need:
            if buf is not None:
                self.gpu.free(buf)
            buf = self.gpu.buffer(self.owner, f"indirect {slot}", bytes(max(need, 4096)))
            self._indirect[slot] = buf
        cmd = np.zeros((len(runs), 5), np.uint32)
        for i, (first, count) in enumerate(runs):
            cmd[i] = (vertices, count, 0, first, 0)
        buf.write(cmd.tobytes())
        return buf

    def draw(self, prog, key, roots_of, segments: int, lod_segments: int, culling: bool,
             view_proj, camera_pos, lod_distance: float, draw_distance: float) -> None:
        vbo, tiles, count = self._held(self._blades, key, roots_of)
        self.last = {"blades": 0, "triangles": 0, "draws": 0, "placed": count,
                     "culled_tiles": 0, "tiles": len(tiles.start)}
        if not count:
            return
        strips = {0: (self._strips.get(segments), segments),
                  1: (self._lod_strips.get(lod_segments), lod_segments)}
        inst = (vbo, "4f/i", "in_root")
        prog.set("uFade", bool(culling))
        if not culling:
            strip, seg = strips[0]
            prog.vao([(strip, "2f", "in_blade"), inst]).render(
                moderngl.TRIANGLE_STRIP, vertices=2 * seg + 1, instances=count)
            self.last.update(blades=count, triangles=count * gs.blade_triangles(seg), draws=1)
            return
        lods = gs.tile_lods(tiles, view_proj, camera_pos, lod_distance, draw_distance)
        self.last["culled_tiles"] = int(np.sum(lods < 0))
        for lod in (0, 1):
            runs = gs.draw_runs(tiles, lods, lod)
            if not runs:
                continue
            strip, seg = strips[lod]
            if self.indirect_ok:
                buf = self._commands(lod, runs, 2 * seg + 1)
                prog.vao([(strip, "2f", "in_blade"), inst]).render_indirect(
                    buf, moderngl.TRIANGLE_STRIP, count=len(runs))
            else:
                vao = prog.vao([(strip, "2f", "in_blade")])  # the roots bound per run
                where = prog.program["in_root"].location
                for first, n in runs:
                    vao.bind(where, "f", vbo, "4f", offset=first * ROOT_STRIDE,
                             stride=ROOT_STRIDE, divisor=1)
                    vao.render(moderngl.TRIANGLE_STRIP, vertices=2 * seg + 1, instances=n)
            drawn = sum(c for _, c in runs)
            self.last["blades"] += drawn
            self.last["triangles"] += drawn * gs.blade_triangles(seg)
            self.last["draws"] += len(runs)

    def release(self) -> None:
        for buf in self._indirect:
            if buf is not None:
                self.gpu.free(buf)
        self._indirect = []

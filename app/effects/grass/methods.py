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
* :class:`InstancedBlades` — beyond the thesis: one instanced Bézier-blade strip per blade.

Culling and level of detail, the same for all three (:class:`Cull`, on by default): each
method's blades (root triangles, units or roots) are sorted by tile of 8 m once, when built;
each frame the tiles are culled on the CPU (outside the frustum, or farther than the draw
distance), those beyond the LOD distance are drawn with the coarser mesh — fewer pyramid
sections, fewer crossed planes, fewer strip segments — and the visible tiles are drawn front
to back, so the depth test rejects the fragments of blades that nearer ones hide before they
are shaded (the alpha-tested tufts overlap many times toward the horizon). The visible runs
of tiles are drawn through ``glMultiDrawArraysIndirect`` (GL 4.3: each run one command; an
instanced method's first blade is the command's base instance), before GL 4.3 one draw per
run. With culling off every blade is drawn at full detail in one draw (the thesis's way).
"""

from __future__ import annotations

from dataclasses import dataclass
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
#: the billboards in two passes (single-sample targets): the alpha test writing depth only,
#: then the shading with the depth test "equal" and no discard (tested before it shades)
BILLBOARD_DEPTH = ProgramSpec("grass/billboard", defines=(("GRASS_DEPTH_ONLY", 1),))
BILLBOARD_EQUAL = ProgramSpec("grass/billboard", defines=(("GRASS_SHADE_EQUAL", 1),))
INSTANCED = ProgramSpec("grass/instanced")
#: the programs that shade (and so receive the sun's shadow): each is also built for the
#: shadow filter in use (receiver_variants)
SHADED = (*GS_PROGRAMS, BILLBOARD, BILLBOARD_EQUAL, INSTANCED)


@dataclass(frozen=True)
class Cull:
    """What the culling needs (``grass.culling``, ``grass.lod_distance``,
    ``grass.draw_distance``) and the camera's view-projection and position."""

    enabled: bool
    view_proj: Any
    camera_pos: Any
    lod_distance: float
    draw_distance: float

    def runs(self, tiles: gs.Tiles, total: int) -> tuple[dict[int, list[tuple[int, int]]], int]:
        """(first, count) runs of visible blades per LOD (0 full, 1 coarse) and the culled
        tiles; culling off: every blade at LOD 0 in one run."""
        if not self.enabled:
            return {0: [(0, total)] if total else [], 1: []}, 0
        lods = gs.tile_lods(tiles, self.view_proj, self.camera_pos, self.lod_distance,
                            self.draw_distance)
        near = gs.tile_distances(tiles, self.camera_pos) if len(tiles.start) else None
        return ({lod: gs.draw_runs(tiles, lods, lod, near) for lod in (0, 1)},
                int(np.sum(lods < 0)))


#: no culling: every blade, full detail (the bench's side-view coverage, tests)
NO_CULL = Cull(False, np.eye(4), (0.0, 0.0, 0.0), 0.0, 0.0)


class _Method:
    def __init__(self, gpu, owner: str, keyed):
        self.gpu = gpu
        self.owner = owner
        self.keyed = keyed
        self._make: Any = None  # what builds the value a keyed get is about to ask for
        #: what the last draw drew: blades, triangles (expected), draw calls
        self.last: dict[str, Any] = {}
        self._indirect: list = []
        #: a multi-draw per LOD needs GL 4.3 (glMultiDrawArraysIndirect, with a base instance
        #: for the instanced methods); before it (macOS stops at 4.1) each run of visible
        #: tiles is a draw of its own: the same blades, more draw calls
        self.indirect_ok = gpu.ctx.version_code >= 430

    def _commands(self, slot: int, rows: list[tuple[int, int, int, int]]):
        """An indirect buffer (one per slot, grown as needed) holding ``rows`` of (count,
        instances, first vertex, base instance)."""
        need = max(1, len(rows)) * INDIRECT_STRIDE
        while len(self._indirect) <= slot:
            self._indirect.append(None)
        buf = self._indirect[slot]
        if buf is None or buf.size < need:
            if buf is not None:
                self.gpu.free(buf)
            buf = self.gpu.buffer(self.owner, f"indirect {slot}", bytes(max(need, 4096)))
            self._indirect[slot] = buf
        cmd = np.zeros((len(rows), 5), np.uint32)
        for i, row in enumerate(rows):
            cmd[i, :4] = row
        buf.write(cmd.tobytes())
        return buf

    def _tally(self, placed: int, tiles: gs.Tiles, culled: int) -> None:
        self.last = {"blades": 0, "triangles": 0, "draws": 0, "placed": placed,
                     "culled_tiles": culled, "tiles": len(tiles.start)}

    def _count(self, runs: list[tuple[int, int]], per_blade: int, draws: int) -> None:
        drawn = sum(c for _, c in runs)
        self.last["blades"] += drawn
        self.last["triangles"] += drawn * per_blade
        self.last["draws"] += draws

    def release(self) -> None:
        for buf in self._indirect:
            if buf is not None:
                self.gpu.free(buf)
        self._indirect = []

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
    """spec/003 §2.9 a: the root triangles of every blade in one vertex buffer, sorted by
    tile."""

    def __init__(self, gpu, owner, keyed):
        super().__init__(gpu, owner, keyed)
        self._tris = keyed(self._build, lambda v: self._free(v[0]))

    def _build(self, key):
        triangles, reach = self._make()
        tris = np.asarray(triangles, np.float32).reshape(-1, 3, 3)
        tiles = gs.make_tiles(tris.mean(axis=1), reach)
        data = tris[tiles.order].reshape(-1, 3)
        return (self._buffer("geometry grass roots", data), len(tris), tiles)

    def draw(self, progs: dict[int, Any], key, triangles_of, sections: dict[int, int],
             cull: Cull = NO_CULL, bind=None) -> None:
        """``progs`` and ``sections``: the program (uniforms set) and section count of each
        LOD, 0 near and 1 beyond the LOD distance; ``bind(prog)`` binds a program's textures
        again just before it draws."""
        vbo, count, tiles = self._held(self._tris, key, triangles_of)
        runs, culled = cull.runs(tiles, count)
        self._tally(count, tiles, culled)
        for lod in (0, 1):
            if not runs[lod]:
                continue
            prog = progs[lod]
            if bind is not None:
                bind(prog)
            vao = prog.vao([(vbo, "3f", "in_position")])
            if len(runs[lod]) == 1:
                first, n = runs[lod][0]
                vao.render(moderngl.TRIANGLES, vertices=3 * n, first=3 * first)
            elif self.indirect_ok:
                buf = self._commands(lod, [(3 * n, 1, 3 * first, 0) for first, n in runs[lod]])
                vao.render_indirect(buf, moderngl.TRIANGLES, count=len(runs[lod]))
            else:
                for first, n in runs[lod]:
                    vao.render(moderngl.TRIANGLES, vertices=3 * n, first=3 * first)
            self._count(runs[lod], gs.gs_triangles_per_blade(sections[lod]),
                        1 if self.indirect_ok else len(runs[lod]))


def _plane_mesh() -> np.ndarray:
    """Four planes of two triangles each (24 rows: corner x, corner y, plane index)."""
    quad = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
    return np.asarray([(x, y, k) for k in range(4) for x, y in quad], np.float32)


#: bytes of one unit's per-instance row (centre xyz, seed, sin seed, texture, 0, tint rgb)
UNIT_STRIDE = 40
#: the units' per-instance attributes: (name, components, byte offset in the row)
UNIT_ATTRIBUTES = (("in_centre", 3, 0), ("in_unit", 4, 12), ("in_tint", 3, 28))


class CrossedBillboards(_Method):
    """spec/003 §2.9 b: the units' instance rows, sorted by tile, and the shared four-plane
    mesh."""

    def __init__(self, gpu, owner, keyed):
        super().__init__(gpu, owner, keyed)
        self._units = keyed(self._build, lambda v: self._free(v[0]))
        self._mesh = None
        self._bind = None

    def _build(self, key):
        units, reach = self._make()
        rows = units.instance_data()
        tiles = gs.make_tiles(units.roots, reach)
        return (self._buffer("billboard units", rows[tiles.order]), len(units), tiles)

    def mesh(self):
        if self._mesh is None:
            self._mesh = self._buffer("billboard planes", _plane_mesh())
        return self._mesh

    def _content(self, vbo) -> list:
        return [(self.mesh(), "2f 1f", "in_corner", "in_plane"),
                (vbo, "3f 4f 3f/i", "in_centre", "in_unit", "in_tint")]

    def draw(self, progs: list, key, units_of, planes: dict[int, int], target, angles=None,
             cull: Cull = NO_CULL, bind=None) -> None:
        """``progs``: one program (uniforms set), or two — the depth-only alpha test and the
        shading with the depth test "equal" — drawn pass after pass (single-sample targets);
        ``planes``: the crossed planes of each LOD (0 near, 1 beyond the LOD distance);
        ``angles(n)`` sets the programs' plane angles for n planes before that LOD's draw;
        ``bind(prog)`` binds a program's textures again just before it draws."""
        self._bind = bind
        vbo, count, tiles = self._held(self._units, key, units_of)
        runs, culled = cull.runs(tiles, count)
        self._tally(count * gs.BLADES_PER_TUFT, tiles, culled)
        a2c = self._a2c(target)
        self.last.update(units=0, alpha_to_coverage=a2c, passes=len(progs))
        for prog in progs:
            prog.set("uAlphaToCoverage", a2c)
        if not count:
            return
        ctx = self.gpu.ctx
        fbo = getattr(target, "fbo", None)
        with self._coverage(target):
            for lod in (0, 1):
                if not runs[lod]:
                    continue
                n = planes[lod]
                if angles is not None:
                    angles(n)
                if len(progs) == 1:
                    draws = self._draw_runs(progs[0], vbo, runs[lod], 6 * n, lod)
                else:
                    fbo.color_mask = (False, False, False, False)
                    try:
                        draws = self._draw_runs(progs[0], vbo, runs[lod], 6 * n, lod)
                    finally:
                        fbo.color_mask = (True, True, True, True)
                    ctx.depth_func = "=="
                    fbo.depth_mask = False
                    try:
                        draws += self._draw_runs(progs[1], vbo, runs[lod], 6 * n, lod)
                    finally:
                        fbo.depth_mask = True
                        ctx.depth_func = "<"
                drawn = sum(c for _, c in runs[lod])
                self.last["units"] += drawn
                self.last["blades"] += drawn * gs.BLADES_PER_TUFT
                self.last["triangles"] += drawn * 2 * n
                self.last["draws"] += draws

    def _draw_runs(self, prog, vbo, runs: list[tuple[int, int]], vertices: int, slot: int) -> int:
        """The units of ``runs``, ``vertices`` per unit; the draw calls it took."""
        if self._bind is not None:
            self._bind(prog)
        if len(runs) == 1 and runs[0][0] == 0:
            prog.vao(self._content(vbo)).render(moderngl.TRIANGLES, vertices=vertices,
                                                instances=runs[0][1])
            return 1
        if self.indirect_ok:
            buf = self._commands(slot, [(vertices, c, 0, first) for first, c in runs])
            prog.vao(self._content(vbo)).render_indirect(buf, moderngl.TRIANGLES,
                                                         count=len(runs))
            return 1
        vao = prog.vao([(self.mesh(), "2f 1f", "in_corner", "in_plane")])
        for first, c in runs:  # the units' rows bound from the run's first unit
            for name, comps, offset in UNIT_ATTRIBUTES:
                if name not in prog.program:  # e.g. the depth pass reads no tint
                    continue
                vao.bind(prog.program[name].location, "f", vbo, f"{comps}f",
                         offset=first * UNIT_STRIDE + offset, stride=UNIT_STRIDE, divisor=1)
            vao.render(moderngl.TRIANGLES, vertices=vertices, instances=c)
        return len(runs)

    def draw_once(self, prog, units: gs.Units, planes: int, target) -> None:
        """``units`` from a buffer and a vertex array made for this draw and freed after it
        (not kept in the program's cache of vertex arrays), every unit drawn."""
        vbo = self._buffer("billboard units (once)", units.instance_data())
        vao = self.gpu.ctx.vertex_array(prog.program, self._content(vbo), skip_errors=True)
        a2c = self._a2c(target)
        prog.set("uAlphaToCoverage", a2c)
        self.last = {"units": len(units), "blades": len(units) * gs.BLADES_PER_TUFT,
                     "triangles": len(units) * planes * 2, "draws": 1 if len(units) else 0,
                     "alpha_to_coverage": a2c}
        try:
            if len(units):
                with self._coverage(target):
                    vao.render(moderngl.TRIANGLES, vertices=6 * planes, instances=len(units))
        finally:
            vao.release()
            self.gpu.free(vbo)

    @staticmethod
    def _a2c(target) -> bool:
        return int(getattr(target, "samples", 0) or 0) > 0

    def _coverage(self, target):
        """Alpha to coverage (and alpha to one) while drawing into a multisampled target."""
        from contextlib import contextmanager

        ctx = self.gpu.ctx
        a2c = self._a2c(target)

        @contextmanager
        def on():
            if a2c:
                ctx.enable_direct(GL_SAMPLE_ALPHA_TO_COVERAGE)
                ctx.enable_direct(GL_SAMPLE_ALPHA_TO_ONE)
            try:
                yield
            finally:
                if a2c:
                    ctx.disable_direct(GL_SAMPLE_ALPHA_TO_ONE)
                    ctx.disable_direct(GL_SAMPLE_ALPHA_TO_COVERAGE)

        return on()

    def release(self) -> None:
        super().release()
        if self._mesh is not None:
            self.gpu.free(self._mesh)
            self._mesh = None


class InstancedBlades(_Method):
    """Beyond the thesis (Wohllaib 2021): the blades sorted by tile, two strip meshes (full and
    LOD segments)."""

    def __init__(self, gpu, owner, keyed):
        super().__init__(gpu, owner, keyed)
        self._blades = keyed(self._build, lambda v: self._free(v[0]))
        self._strips = keyed(self._build_strip, self._free)
        self._lod_strips = keyed(self._build_strip, self._free)

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

    def draw(self, prog, key, roots_of, segments: int, lod_segments: int,
             cull: Cull = NO_CULL) -> None:
        vbo, tiles, count = self._held(self._blades, key, roots_of)
        runs, culled = cull.runs(tiles, count)
        self._tally(count, tiles, culled)
        if not count:
            return
        strips = {0: (self._strips.get(segments), segments),
                  1: (self._lod_strips.get(lod_segments), lod_segments)}
        inst = (vbo, "4f/i", "in_root")
        prog.set("uFade", bool(cull.enabled))
        for lod in (0, 1):
            if not runs[lod]:
                continue
            strip, seg = strips[lod]
            if len(runs[lod]) == 1 and runs[lod][0][0] == 0:
                prog.vao([(strip, "2f", "in_blade"), inst]).render(
                    moderngl.TRIANGLE_STRIP, vertices=2 * seg + 1, instances=runs[lod][0][1])
                draws = 1
            elif self.indirect_ok:
                buf = self._commands(lod, [(2 * seg + 1, n, 0, first) for first, n in runs[lod]])
                prog.vao([(strip, "2f", "in_blade"), inst]).render_indirect(
                    buf, moderngl.TRIANGLE_STRIP, count=len(runs[lod]))
                draws = 1
            else:
                vao = prog.vao([(strip, "2f", "in_blade")])  # the roots bound per run
                where = prog.program["in_root"].location
                for first, n in runs[lod]:
                    vao.bind(where, "f", vbo, "4f", offset=first * ROOT_STRIDE,
                             stride=ROOT_STRIDE, divisor=1)
                    vao.render(moderngl.TRIANGLE_STRIP, vertices=2 * seg + 1, instances=n)
                draws = len(runs[lod])
            self._count(runs[lod], gs.blade_triangles(seg), draws)

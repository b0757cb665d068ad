"""Transparency in the surfaces lab (spec/003 §2.4): the lab's alpha quads drawn in Unity's
render-queue order, each with a mode — opaque, cutout (``clip(alpha − Cutoff)``), the naive
``alpha == 0`` test, alpha-to-coverage, blended with or without depth writes — and the blended
ones composited by one of three methods (``surfaces.transparency``):

* ``sorted`` — Unity's way: queue ascending, back to front by object centre within the
  transparent queues, ``Blend SrcAlpha OneMinusSrcAlpha``. Both of the thesis's failures are
  a parameter away: ``surfaces.blue_queue=Geometry`` draws the α = 0.5 blue pane (ZWrite on)
  before the cut-out fence behind it, which then fails the depth test (Fig. 44c); the two
  intersecting panes sorted by their common centre hide each other's far half (Fig. 45), and
  ``surfaces.zwrite_blended=false`` is the partial workaround (Fig. 46);
* ``wboit`` — weighted blended order-independent transparency (McGuire and Bavoil 2013): the
  blended quads accumulate into an RGBA16F + R16F pair sharing the image's depth (test on,
  write off), composited once over the image (``glsl/surfaces/oit_composite.frag``);
* ``peeled`` — depth peeling, the exact reference: layer after layer (nearest first, until a
  pass draws nothing or ``surfaces.peel_layers``), under-composited front to back
  (``glsl/surfaces/peel_composite.frag``).

With ``wboit`` and ``peeled`` the quads that write depth (opaque, cutout, alpha-to-coverage) are
drawn first in queue order; every blended quad then goes to the order-independent method,
whatever its queue. The numpy twin is ``app/sim/transparency.py``.

API: the surfaces effect calls ``Transparency(gpu, owner, params).draw(target, view_proj,
camera_pos, light, quads)`` in the transparent stage, after its opaque scene. ``target``:
``.fbo``, ``.colour`` (or ``.color``), ``.depth``, ``.size`` and ``.samples`` (0 or 4; read from
the colour texture when absent). ``light``: ``direction`` (toward the light), ``radiance``,
``ambient``. ``quads``: ``(Quad, vbo, ibo, alpha_texture)`` with the vertex layout
``"3f 3f 2f 4f"`` (in_position, in_normal, in_uv, in_tangent; world space), or
:meth:`Transparency.scene_quads` builds them from ``app.sim.surfaces_scene.mesh``. GL state left
behind: depth test, blending and alpha-to-coverage off, the target bound with depth writes on.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import moderngl
import numpy as np

from ...gpu.cache import memoised
from ...gpu.programs import ProgramSpec, draw_fullscreen, fullscreen
from ...params import Param
from ...sim import maths
from ...sim import surfaces_scene as ss
from ...sim import transparency as tw

ALPHA = ProgramSpec("surfaces/alpha")
ALPHA_MS = ProgramSpec("surfaces/alpha", defines=(("OPAQUE_MS", 1),))
OIT_COMPOSITE = fullscreen("surfaces/oit_composite")
OIT_COMPOSITE_MS = fullscreen("surfaces/oit_composite", defines=(("SAMPLES", 4),))
PEEL_COMPOSITE = fullscreen("surfaces/peel_composite")
PROGRAMS = (ALPHA, ALPHA_MS, OIT_COMPOSITE, OIT_COMPOSITE_MS, PEEL_COMPOSITE)

MODES = ("opaque", "cutout", "alpha-test-naive", "alpha-to-coverage", "blend",
         "blend-zwrite-off")
#: mode → alpha.frag's uMode
MODE_CODE = {"opaque": 0, "cutout": 1, "alpha-test-naive": 2, "alpha-to-coverage": 3,
             "blend": 4, "blend-zwrite-off": 4}
BLENDED = ("blend", "blend-zwrite-off")
METHODS = ("sorted", "wboit", "peeled")
#: the queue choices of the panel (parse_queue accepts any "Name±N" or 0…5000 in code)
QUEUE_CHOICES = ("Background", "Geometry", "Geometry-10", "AlphaTest", "Transparent",
                 "Transparent+5", "Overlay")
WEIGHT_CODE = {w: i for i, w in enumerate(tw.WEIGHTS)}
#: each mode's queue when none is given (Unity's defaults for such a shader)
MODE_QUEUE = {"opaque": "Geometry", "cutout": "AlphaTest", "alpha-test-naive": "AlphaTest",
              "alpha-to-coverage": "AlphaTest", "blend": "Transparent",
              "blend-zwrite-off": "Transparent"}
VERTEX_FORMAT = ("3f 3f 2f 16x", "in_position", "in_normal", "in_uv")
ATTRIBUTES = ("position", "normal", "uv", "tangent")
GL_SAMPLE_ALPHA_TO_COVERAGE = 0x809E
OVER = (moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ZERO, moderngl.ONE)
ACCUMULATE = (moderngl.ONE, moderngl.ONE, moderngl.ONE_MINUS_DST_ALPHA, moderngl.ONE)
UNDER = (moderngl.ONE_MINUS_DST_ALPHA, moderngl.ONE, moderngl.ONE_MINUS_DST_ALPHA, moderngl.ONE)
PREMULTIPLIED_OVER = (moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ZERO, moderngl.ONE)

#: the lab's views of transparency: name → (eye, look-at point, vertical fov in degrees)
VIEWS = {
    "crossing": ((1.2, 0.9, 4.0), (1.4, 0.7, 2.1), 45.0),
    "blue_fence": ((0.6, 0.9, 4.6), (-2.6, 0.6, -0.6), 30.0),
    "smoke": ((0.0, 1.5, 0.6), (0.0, 1.5, -3.0), 40.0),
}


def look_at(eye, centre, fov: float, aspect: float, near: float = 0.05, far: float = 50.0
            ) -> np.ndarray:
    """Projection × view of a camera at ``eye`` looking at ``centre`` (y up)."""
    return maths.perspective(fov, aspect, near, far) @ maths.look_at(eye, centre, (0.0, 1.0, 0.0))


def transparency_params() -> list[Param]:
    """The Python parameters of transparency (group ``surfaces``)."""
    s = "spec/003 §2.4"
    mode = "how the {} is drawn: " + ", ".join(MODES)
    return [
        Param("surfaces.transparency", "sorted", doc="how blended quads are composited: sorted "
              "(Unity: back to front by object centre), wboit (weighted blended OIT, McGuire "
              "and Bavoil 2013), peeled (depth peeling, the exact reference)", kind="choice",
              choices=METHODS, section=s),
        Param("surfaces.cutoff", 0.5, 0.0, 1.0, "alpha cutoff: clip(alpha − Cutoff) discards "
              "fragments whose alpha is below it", step=0.01, section=s),
        Param("surfaces.a2c", False, doc="cut-out quads use alpha-to-coverage (AlphaToMask On) "
              "on a multisampled image instead of the hard clip", kind="bool", section=s),
        Param("surfaces.zwrite_blended", True, doc="blended quads write depth (ZWrite On, the "
              "thesis's Fig. 45); off is its partial workaround (Fig. 46)", kind="bool",
              section=s),
        Param("surfaces.blue_queue", "Transparent", doc="the blue α = 0.5 pane's render queue: "
              "Geometry draws it before the cut-out fence behind it, which it then hides "
              "(Fig. 44c)", kind="choice", choices=QUEUE_CHOICES, section=s),
        Param("surfaces.fence_queue", "AlphaTest", doc="the cut-out fence's render queue",
              kind="choice", choices=QUEUE_CHOICES, section=s),
        Param("surfaces.fence_mode", "cutout", doc=mode.format("fence"), kind="choice",
              choices=MODES, section=s),
        Param("surfaces.leaves_mode", "cutout", doc=mode.format("leaves quad (soft-edged "
              "alpha: alpha-test-naive shows its stray fragments)"), kind="choice",
              choices=MODES, section=s),
        Param("surfaces.smoke_mode", "blend", doc=mode.format("smoke"), kind="choice",
              choices=MODES, section=s),
        Param("surfaces.blue_mode", "blend", doc=mode.format("blue pane"), kind="choice",
              choices=MODES, section=s),
        Param("surfaces.cross_mode", "blend", doc=mode.format("two intersecting panes"),
              kind="choice", choices=MODES, section=s),
        Param("surfaces.wboit_weight", "eq7", doc="the WBOIT depth weight w(z, α): McGuire "
              "and Bavoil's eq7, eq8, eq9 (view depth) or eq10 (window depth)",
              kind="choice", choices=tw.WEIGHTS, section=s),
        Param("surfaces.peel_layers", 16, 1, 64, "depth peeling: at most this many layers "
              "(it stops earlier when a pass draws nothing)", kind="int", section=s),
    ]


def default_mode(quad: ss.Quad) -> str:
    if quad.alpha in ("fence", "leaves", "gradient"):
        return "cutout"
    if quad.alpha == "smoke" or quad.opacity < 1.0:
        return "blend"
    return "opaque"


@dataclass(frozen=True)
class Item:
    """One quad's place in the frame: its name, mode, queue and centre distance."""

    name: str
    mode: str
    queue: int
    distance: float
    index: int  # into the quads given to draw


def _samples(target) -> int:
    s = getattr(target, "samples", None)
    if s is None:
        s = getattr(_colour(target), "samples", 0)
    return int(s or 0)


def _colour(target):
    return getattr(target, "colour", None) or getattr(target, "color")


class Transparency:
    """The lab's alpha quads (module docstring); GL resources under ``owner``, parameters read
    from ``params`` at each draw."""

    programs = PROGRAMS

    def __init__(self, gpu, owner: str, params) -> None:
        self.gpu = gpu
        self.owner = owner
        self.params = params
        #: per-quad (mode, queue) overrides of the parameters: name → (mode | None, queue | None)
        self.overrides: dict[str, tuple[str | None, str | int | None]] = {}
        self._oit: tuple | None = None
        self._peel: tuple | None = None
        self._quads: list | None = None
        self._textures: dict[str, Any] = {}
        #: figures of the last draw: layers peeled, quads per method
        self.last: dict[str, Any] = {}

    @staticmethod
    def python_params() -> list[Param]:
        return transparency_params()

    def setting(self, quad: ss.Quad) -> tuple[str, int]:
        """(mode, queue) of ``quad``: an override, else its parameters, else its default."""
        p = self.params
        key = {"cross_a": "cross", "cross_b": "cross"}.get(quad.name, quad.name)
        mode = default_mode(quad)
        if f"surfaces.{key}_mode" in p:
            mode = p[f"surfaces.{key}_mode"]
        queue: str | int = MODE_QUEUE[mode]
        if f"surfaces.{key}_queue" in p:
            queue = p[f"surfaces.{key}_queue"]
        o_mode, o_queue = self.overrides.get(quad.name, (None, None))
        if o_mode is not None:
            if o_mode not in MODES:
                raise ValueError(f"transparency mode {o_mode!r} of {quad.name}: allowed "
                                 + ", ".join(MODES))
            mode = o_mode
            if o_queue is None and f"surfaces.{key}_queue" not in p:
                queue = MODE_QUEUE[mode]
        if o_queue is not None:
            queue = o_queue
        return mode, tw.parse_queue(queue)

    def plan(self, quads: Sequence[ss.Quad], camera_pos) -> list[Item]:
        """Every quad in Unity's draw order (app.sim.transparency.draw_order)."""
        settings = [self.setting(q) for q in quads]
        centres = [q.centre for q in quads]
        order = tw.draw_order([s[1] for s in settings], centres, camera_pos)
        cam = np.asarray(camera_pos, float)
        return [Item(quads[i].name, settings[i][0], settings[i][1],
                     float(np.linalg.norm(np.asarray(quads[i].centre) - cam)), i)
                for i in order]

    def notes(self, quads: Sequence[ss.Quad], camera_pos) -> list[str]:
        """Panel lines: the draw order with each quad's queue and mode, and the last draw's
        method (layers peeled)."""
        order = ", ".join(f"{it.name} {tw.format_queue(it.queue)} {it.mode}"
                          for it in self.plan(quads, camera_pos))
        out = [f"draw order: {order}"]
        if self.last:
            extra = f", {self.last['layers']} layers" if self.last["method"] == "peeled" else ""
            out.append(f"{self.last['method']}: {self.last['deferred']} quads composited"
                       f"{extra}")
        return out

    def scene_quads(self, scene: ss.SurfacesScene | None = None) -> list[tuple]:
        """(Quad, vbo, ibo, alpha texture) of the scene's quads (default_scene), built once
        under the owner (:meth:`build_quads`)."""
        if self._quads is None:
            self._quads = self.build_quads((scene or ss.default_scene()).quads)
        return self._quads

    def build_quads(self, quads: Sequence[ss.Quad]) -> list[tuple]:
        """(Quad, vbo, ibo, alpha texture) of ``quads`` from app.sim.surfaces_scene.mesh and
        alpha_texture, under the owner (the caller frees them, or :meth:`release` when they
        are the scene's)."""
        textures = self._textures
        out = []
        for q in quads:
            m = ss.mesh(q)
            vbo = self.gpu.buffer(self.owner, f"{q.name} quad", m.vertex_data(ATTRIBUTES))
            ibo = self.gpu.buffer(self.owner, f"{q.name} quad indices", m.index_data())
            if q.alpha not in textures:
                textures[q.alpha] = self.alpha_texture(q.alpha)
            out.append((q, vbo, ibo, textures[q.alpha]))
        return out

    def alpha_texture(self, kind: str, size: int = 256):
        data = np.ascontiguousarray(memoised(ss.alpha_texture, kind, size), np.float32)
        tex = self.gpu.texture(self.owner, f"alpha {kind}", (size, size), 4, data=data.tobytes(),
                               dtype="f4")
        tex.build_mipmaps()
        tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
        return tex

    def _oit_targets(self, target):
        size, samples = tuple(target.size), _samples(target)
        key = (size, samples, id(target.depth))
        if self._oit is None or self._oit[0] != key:
            self._free(self._oit)
            gpu = self.gpu
            accum = gpu.texture(self.owner, "wboit accumulation", size, 4, dtype="f2",
                                samples=samples)
            weight = gpu.texture(self.owner, "wboit weights", size, 1, dtype="f2",
                                 samples=samples)
            fbo = gpu.framebuffer(self.owner, "wboit framebuffer", [accum, weight], target.depth)
            self._oit = (key, fbo, accum, weight)
        return self._oit

    def _peel_targets(self, size):
        size = tuple(size)
        if self._peel is None or self._peel[0] != size:
            self._free(self._peel)
            g = self.gpu
            layer = g.texture(self.owner, "peel layer", size, 4, dtype="f4",
                              filter=(moderngl.NEAREST, moderngl.NEAREST))
            acc = g.texture(self.owner, "peel accumulation", size, 4, dtype="f4",
                            filter=(moderngl.NEAREST, moderngl.NEAREST))
            depths = [g.depth_texture(self.owner, f"peel depth {k}", size) for k in (0, 1)]
            for d in depths:
                d.compare_func = ""
                d.filter = (moderngl.NEAREST, moderngl.NEAREST)
            fbos = [g.framebuffer(self.owner, f"peel {k}", [layer], depths[k]) for k in (0, 1)]
            acc_fbo = g.framebuffer(self.owner, "peel accumulation", [acc])
            self._peel = (size, layer, acc, depths, fbos, acc_fbo)
        return self._peel

    def _free(self, held) -> None:
        if held is None:
            return
        for obj in held[1:]:
            for o in (obj if isinstance(obj, list) else [obj]):
                self.gpu.free(o)

    def release(self) -> None:
        self._free(self._oit)
        self._free(self._peel)
        self._oit = self._peel = None
        if self._quads is not None:
            for _q, vbo, ibo, _tex in self._quads:
                self.gpu.free(vbo)
                self.gpu.free(ibo)
        for tex in self._textures.values():
            self.gpu.free(tex)
        self._quads = None
        self._textures = {}

    def _uniforms(self, prog, view_proj, camera_pos, light) -> None:
        d = np.asarray(light.get("direction", (0.0, 1.0, 0.0)), float)
        n = float(np.linalg.norm(d))
        d = d / n if n > 1e-12 and np.isfinite(n) else np.array([0.0, 1.0, 0.0])
        prog.set_many({"uViewProj": np.asarray(view_proj, float),
                       "uCameraPos": tuple(float(c) for c in camera_pos),
                       "uLightDir": tuple(d),
                       "uRadiance": tuple(light.get("radiance", (1.0, 1.0, 1.0))),
                       "uAmbient": tuple(light.get("ambient", (0.1, 0.1, 0.1))),
                       "uCutoff": float(self.params["surfaces.cutoff"]),
                       "uWeight": WEIGHT_CODE[self.params["surfaces.wboit_weight"]]})

    def _quad(self, prog, entry, mode_code: int, extra: dict | None = None) -> None:
        quad, vbo, ibo, tex = entry
        prog.bind_textures({"uAlphaMap": tex, **(extra or {})})
        prog.set_many({"uMode": mode_code, "uAlbedo": tuple(quad.albedo),
                       "uOpacity": float(quad.opacity)})
        prog.vao([(vbo, *VERTEX_FORMAT)], ibo).render(moderngl.TRIANGLES)

    def draw(self, target, view_proj, camera_pos, light: dict, quads: Sequence[tuple]) -> None:
        """Draw ``quads`` ((Quad, vbo, ibo, alpha texture)) over ``target`` (module docstring)."""
        ctx = self.gpu.ctx
        method = self.params["surfaces.transparency"]
        samples = _samples(target)
        items = self.plan([e[0] for e in quads], camera_pos)
        deferred = [it for it in items if method != "sorted" and it.mode in BLENDED]
        direct = [it for it in items if it not in deferred]
        prog = self.gpu.program(self.owner, ALPHA)
        self._uniforms(prog, view_proj, camera_pos, light)
        a2c = bool(self.params["surfaces.a2c"])
        fbo = target.fbo
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.disable(moderngl.CULL_FACE)
        ctx.depth_func = "<"
        try:
            for it in direct:
                coverage = (it.mode == "alpha-to-coverage" or (a2c and it.mode == "cutout"))
                code = MODE_CODE[it.mode]
                if coverage:
                    code = 3 if samples > 0 else 1  # single-sample: the hard clip instead
                blended = it.mode in BLENDED
                fbo.depth_mask = not blended or (it.mode == "blend"
                                                 and bool(self.params["surfaces.zwrite_blended"]))
                fbo.use()
                if blended:
                    ctx.enable(moderngl.BLEND)
                    ctx.blend_func = OVER
                if code == 3:
                    ctx.enable_direct(GL_SAMPLE_ALPHA_TO_COVERAGE)
                try:
                    self._quad(prog, quads[it.index], code)
                finally:
                    if code == 3:
                        ctx.disable_direct(GL_SAMPLE_ALPHA_TO_COVERAGE)
                    if blended:
                        ctx.disable(moderngl.BLEND)
                        ctx.blend_func = moderngl.DEFAULT_BLENDING
                    fbo.depth_mask = True
            fbo.use()
            chosen = [quads[it.index] for it in deferred]
            self.last = {"method": method, "direct": len(direct), "deferred": len(chosen),
                         "layers": 0}
            if chosen and method == "wboit":
                self._wboit(target, view_proj, camera_pos, light, chosen)
            elif chosen and method == "peeled":
                self.last["layers"] = self.draw_peeled(
                    target, view_proj, camera_pos, light, chosen,
                    int(self.params["surfaces.peel_layers"]))
        finally:
            ctx.disable(moderngl.BLEND)
            ctx.blend_func = moderngl.DEFAULT_BLENDING
            ctx.disable(moderngl.DEPTH_TEST)
            fbo.depth_mask = True
            fbo.use()

    def _wboit(self, target, view_proj, camera_pos, light, quads) -> None:
        ctx = self.gpu.ctx
        samples = _samples(target)
        _key, fbo, accum, weight = self._oit_targets(target)
        prog = self.gpu.program(self.owner, ALPHA)
        self._uniforms(prog, view_proj, camera_pos, light)
        fbo.depth_mask = False
        fbo.use()
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)  # colour only: depth_mask is off
        ctx.enable(moderngl.DEPTH_TEST | moderngl.BLEND)
        ctx.blend_func = ACCUMULATE
        try:
            for entry in quads:
                self._quad(prog, entry, 5)
        finally:
            ctx.blend_func = moderngl.DEFAULT_BLENDING
            ctx.disable(moderngl.BLEND | moderngl.DEPTH_TEST)
            fbo.depth_mask = True
        comp = self.gpu.program(self.owner, OIT_COMPOSITE_MS if samples else OIT_COMPOSITE)
        comp.bind_textures({"uAccum": accum, "uWeightSum": weight})
        target.fbo.use()
        draw_fullscreen(comp, blend=OVER)

    def draw_peeled(self, target, view_proj, camera_pos, light, quads, max_layers: int) -> int:
        """Depth peeling of ``quads`` (all blended) over ``target``, at most ``max_layers``
        layers, stopping at the first pass that draws nothing; returns the layers peeled."""
        ctx = self.gpu.ctx
        samples = _samples(target)
        _size, layer, acc, depths, fbos, acc_fbo = self._peel_targets(target.size)
        prog = self.gpu.program(self.owner, ALPHA_MS if samples else ALPHA)
        self._uniforms(prog, view_proj, camera_pos, light)
        opaque = target.depth
        old_compare = getattr(opaque, "compare_func", "")
        if not samples:
            opaque.compare_func = ""
        acc_fbo.use()
        acc_fbo.clear(0.0, 0.0, 0.0, 0.0)
        copy = self.gpu.program(self.owner, PEEL_COMPOSITE)
        peeled = 0
        query = ctx.query(samples=True)
        try:
            for k in range(max(1, int(max_layers))):
                fbo = fbos[k % 2]
                fbo.use()
                fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
                ctx.enable(moderngl.DEPTH_TEST)
                ctx.depth_func = "<"
                prog.set("uFirstLayer", k == 0)
                with query:
                    for entry in quads:
                        self._quad(prog, entry, 6, {"uPrevDepth": depths[(k + 1) % 2],
                                                    "uOpaqueDepth": opaque})
                ctx.disable(moderngl.DEPTH_TEST)
                if query.samples == 0:
                    break
                peeled += 1
                copy.bind_textures({"uLayer": layer})
                acc_fbo.use()
                draw_fullscreen(copy, blend=UNDER)
            copy.bind_textures({"uLayer": acc})
            target.fbo.use()
            draw_fullscreen(copy, blend=PREMULTIPLIED_OVER)
        finally:
            if not samples:
                opaque.compare_func = old_compare
            ctx.disable(moderngl.DEPTH_TEST)
        return peeled

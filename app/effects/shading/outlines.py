"""The shading lab's contours and bloom (spec/003 §2.13 outlines, spec/003 §2.14
post-processing): every outline method of the thesis behind one switch, ``shading.contour``,
plus the screen-space edge detector and bloom the thesis left as future work.

Methods (``shading.contour``):

* ``none`` — nothing;
* ``hull`` — the inverted hull (``glsl/shading/outline_hull.*``): the objects' back faces,
  extruded by a geometry shader along the per-vertex normals by ``shading.contour_width``
  pixels, drawn after the objects in the outline colour. On the low-poly table and barrel it
  opens at hard edges (the thesis's failure);
* ``hull_smooth`` — the same shell extruded along the smoothed normals (the
  ``smooth_normals`` of ``app.sim.lab_meshes.LabMesh``, a second vertex buffer built here):
  closed;
* ``rim_threshold``, ``rim_soft``, ``rim_50x2`` — the rim silhouettes
  (``glsl/shading/rim_outline.glsl``: n·v thresholded, the soft staircase of
  spec/003 eq. 8.4, saturate(50x²)) in the band n·v < ``shading.contour_rim``, evaluated per
  pixel from the G-buffer and mixed over the image (the surface shader may call the same
  functions instead);
* ``edges_sobel``, ``edges_roberts`` — a screen-space edge detector on the G-buffer's depth and
  normals (``glsl/shading/edges.frag``), its depth threshold scaled by the view angle.

Every method but the hull renders the G-buffer (``glsl/shading/gbuffer.*``: view-space normal
and linear depth into an RGBA32F target of the image's size, with its own depth buffer) and
composites one full-screen pass over the image. ``shading.bloom`` adds a post pass
(``glsl/shading/bloom.frag``: bright pass, separable Gaussian at half resolution, added back).

API (``Shading.draw`` calls it after drawing its objects into ``target``, depth kept):
``Outlines(gpu, owner, params)`` once, then ``draw(target, view, proj, objects)`` (the contour
of ``shading.contour``) and ``bloom(target)`` (when ``shading.bloom``). ``objects`` are the
effect's own ``(vbo, ibo, LabMesh, model)``: the vertex buffer in the format ``"3f 3f 2f 4f"``
(only position and normal are read), the uint32 index buffer, the mesh (its smooth normals are
uploaded here once, keyed by the vertex buffer; :meth:`Outlines.forget` drops them), and the
model matrix. The effect lists :data:`PROGRAMS` in its programs (every parameter is
:func:`outline_params`, Python-side). GL state left behind: depth test and face culling off,
blending off, the target bound.
"""

from __future__ import annotations

from typing import Any, Sequence

import moderngl
import numpy as np

from ...gpu.programs import ProgramSpec, draw_fullscreen, fullscreen
from ...params import Param

HULL = ProgramSpec("shading/outline_hull")
GBUFFER = ProgramSpec("shading/gbuffer")
EDGES = fullscreen("shading/edges")
BLOOM = fullscreen("shading/bloom")
PROGRAMS = (HULL, GBUFFER, EDGES, BLOOM)

CONTOURS = ("none", "hull", "hull_smooth", "rim_threshold", "rim_soft", "rim_50x2",
            "edges_sobel", "edges_roberts")
#: contour → the edges.frag mode
EDGE_MODES = {"edges_sobel": 0, "edges_roberts": 1, "rim_threshold": 2, "rim_soft": 3,
              "rim_50x2": 4}
#: the G-buffer's depth where nothing was drawn (metres; far beyond the lab)
BACKGROUND_DEPTH = 1.0e5
VERTEX_FORMAT = ("3f 3f 24x", "in_position", "in_normal")  # of the "3f 3f 2f 4f" buffer
COMPOSITE_BLEND = (moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA, moderngl.ZERO, moderngl.ONE)
ADD_BLEND = (moderngl.ONE, moderngl.ONE, moderngl.ZERO, moderngl.ONE)


def outline_params() -> list[Param]:
    """The Python parameters of the contours and bloom (group ``shading``)."""
    c, b = "spec/003 §2.13", "spec/003 §2.14"
    return [
        Param("shading.contour", "none", doc="the outline method: the inverted hull (per-vertex "
              "or smoothed normals), the three rim silhouettes, a Sobel or Roberts edge "
              "detector on depth and normals", kind="choice", choices=CONTOURS, section=c),
        Param("shading.contour_width", 3.0, 0.0, 32.0, "outline width: the hull's extrusion "
              "and the edge detector's kernel reach (the rim methods use contour_rim)",
              step=0.5, unit="px", section=c),
        Param("shading.contour_color", (0.02, 0.02, 0.03), 0.0, 1.0, "the outline colour "
              "(linear)", kind="color", section=c),
        Param("shading.contour_rim", 0.5, 0.01, 1.0, "the rim silhouettes' band: the outline "
              "lies where n·v is below this", step=0.01, section=c),
        Param("shading.edge_depth_threshold", 1.5, 0.05, 50.0, "edge detector: the depth "
              "slope per pixel, relative to the depth and the pixel's size, above which an "
              "edge is drawn (divided by n·v; at 1 or more a flat plane never fires)",
              step=0.05, section=c),
        Param("shading.edge_normal_threshold", 0.4, 0.01, 2.0, "edge detector: the change of "
              "the unit normal across the kernel above which an edge is drawn (0.4 ≈ a 23° "
              "crease)", step=0.01, section=c),
        Param("shading.bloom", False, doc="bloom: a post pass that spreads light above the "
              "threshold", kind="bool", section=b),
        Param("shading.bloom_threshold", 1.0, 0.0, 100.0, "bloom: the luminance above which "
              "light blooms (linear radiance)", step=0.05, section=b),
        Param("shading.bloom_radius", 16.0, 0.0, 128.0, "bloom: the Gaussian's radius (σ is "
              "half of it), blurred at half resolution", step=1.0, unit="px", section=b),
        Param("shading.bloom_intensity", 0.6, 0.0, 10.0, "bloom: the gain of the blurred "
              "light added back", step=0.05, section=b),
    ]


def pixel_world(proj: np.ndarray, height: int) -> float:
    """The world size of one pixel at unit view depth, 2 / (P[1][1] · H)."""
    return float(2.0 / (float(proj[1, 1]) * max(int(height), 1)))


class Outlines:
    """The contours and bloom of the shading lab (module docstring): GL resources under
    ``owner``, parameters read from ``params`` at each call."""

    def __init__(self, gpu, owner: str, params) -> None:
        self.gpu = gpu
        self.owner = owner
        self.params = params
        #: divide the edge detector's depth threshold by n·v (off shows the grazing failure)
        self.view_angle_scaling = True
        self._smooth: dict[int, tuple[Any, Any]] = {}  # id(vbo) → (vbo, smooth-normal buffer)
        self._gbuffer: Any = None
        self._bloom: tuple | None = None

    def _smooth_buffer(self, vbo, mesh):
        held = self._smooth.get(id(vbo))
        if held is None or held[0] is not vbo:
            data = np.ascontiguousarray(mesh.smooth_normals, np.float32).tobytes()
            held = (vbo, self.gpu.buffer(self.owner, f"{mesh.name} smooth normals", data))
            self._smooth[id(vbo)] = held
        return held[1]

    def forget(self, vbo) -> None:
        """Drop the smooth normals uploaded for ``vbo`` (its mesh was dropped)."""
        held = self._smooth.pop(id(vbo), None)
        if held is not None:
            self.gpu.free(held[1])

    def _gbuffer_target(self, size):
        if self._gbuffer is None or self._gbuffer.size != tuple(size):
            if self._gbuffer is not None:
                self.gpu.free(self._gbuffer)
            self._gbuffer = self.gpu.target(self.owner, "outline gbuffer", size, dtype="f4")
        return self._gbuffer

    def _bloom_targets(self, size):
        half = (max(1, size[0] // 2), max(1, size[1] // 2))
        if self._bloom is None or self._bloom[0] != half:
            if self._bloom is not None:
                for obj in self._bloom[1:]:
                    self.gpu.free(obj)
            made = []
            for k in ("a", "b"):
                tex = self.gpu.texture(self.owner, f"bloom {k}", half, 4, dtype="f2")
                made += [tex, self.gpu.framebuffer(self.owner, f"bloom {k}", [tex])]
            self._bloom = (half, *made)
        return self._bloom

    def draw(self, target, view: np.ndarray, proj: np.ndarray,
             objects: Sequence[tuple]) -> None:
        """The contour ``shading.contour`` of ``objects`` ((vbo, ibo, LabMesh, model) each)
        over ``target``, whose depth holds the objects already drawn."""
        contour = self.params["shading.contour"]
        if contour == "none" or not objects:
            return
        if contour in ("hull", "hull_smooth"):
            self.draw_hull(target, view, proj, objects, smooth=contour == "hull_smooth")
        else:
            self.draw_edges(target, view, proj, objects, EDGE_MODES[contour])

    def draw_hull(self, target, view, proj, objects, smooth: bool = False) -> None:
        """The inverted hull: back faces extruded by the geometry shader, front faces culled,
        depth-tested against the objects in ``target``."""
        ctx = self.gpu.ctx
        prog = self.gpu.program(self.owner, HULL)
        prog.set_many({"uViewProj": np.asarray(proj) @ np.asarray(view),
                       "uWidthPx": float(self.params["shading.contour_width"]),
                       "uPixelWorld": pixel_world(proj, target.size[1]),
                       "uSmoothNormals": bool(smooth),
                       "uOutlineColor": tuple(self.params["shading.contour_color"])})
        target.use()
        ctx.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        ctx.cull_face = "front"
        try:
            for vbo, ibo, mesh, model in objects:
                prog.set("uModel", np.asarray(model))
                smooth_vbo = self._smooth_buffer(vbo, mesh)
                prog.vao([(vbo, *VERTEX_FORMAT), (smooth_vbo, "3f", "in_smooth_normal")],
                         ibo).render(moderngl.TRIANGLES)
        finally:
            ctx.cull_face = "back"
            ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)

    def draw_gbuffer(self, size, view, proj, objects):
        """The outline G-buffer of ``objects``: an RGBA32F target of ``size`` (view-space
        normal, linear depth; BACKGROUND_DEPTH where nothing is)."""
        ctx = self.gpu.ctx
        g = self._gbuffer_target(size)
        prog = self.gpu.program(self.owner, GBUFFER)
        prog.set_many({"uView": np.asarray(view), "uProj": np.asarray(proj)})
        g.use()
        g.clear((0.0, 0.0, 0.0, BACKGROUND_DEPTH))
        ctx.enable(moderngl.DEPTH_TEST)
        try:
            for vbo, ibo, _mesh, model in objects:
                prog.set("uModel", np.asarray(model))
                prog.vao([(vbo, *VERTEX_FORMAT)], ibo).render(moderngl.TRIANGLES)
        finally:
            ctx.disable(moderngl.DEPTH_TEST)
        return g

    def draw_edges(self, target, view, proj, objects, mode: int) -> None:
        """The screen-space composite (edges.frag mode ``mode``: 0 Sobel, 1 Roberts, 2–4 the
        rim silhouettes) of the objects' G-buffer over ``target``."""
        g = self.draw_gbuffer(target.size, view, proj, objects)
        p = self.params
        prog = self.gpu.program(self.owner, EDGES)
        prog.bind_textures({"uGBuffer": g.color})
        prog.set_many({"uMode": int(mode), "uWidthPx": float(p["shading.contour_width"]),
                       "uDepthThreshold": float(p["shading.edge_depth_threshold"]),
                       "uNormalThreshold": float(p["shading.edge_normal_threshold"]),
                       "uScaleByViewAngle": bool(self.view_angle_scaling),
                       "uTanHalfFov": (1.0 / float(proj[0, 0]), 1.0 / float(proj[1, 1])),
                       "uPixelWorld": pixel_world(proj, target.size[1]),
                       "uBackgroundDepth": BACKGROUND_DEPTH,
                       "uRim": float(p["shading.contour_rim"]),
                       "uOutlineColor": tuple(p["shading.contour_color"])})
        target.use()
        if mode < 2 and float(p["shading.contour_width"]) <= 0.0:
            return
        draw_fullscreen(prog, blend=COMPOSITE_BLEND)

    def bloom(self, target, force: bool = False) -> None:
        """Bloom over ``target`` when ``shading.bloom`` (or ``force``): bright pass and blur at
        half resolution, the result × intensity added to the image."""
        p = self.params
        if not (force or p["shading.bloom"]):
            return
        half, tex_a, fbo_a, tex_b, fbo_b = self._bloom_targets(target.size)
        prog = self.gpu.program(self.owner, BLOOM)
        prog.set_many({"uThreshold": float(p["shading.bloom_threshold"]),
                       "uRadiusPx": float(p["shading.bloom_radius"]),
                       "uIntensity": float(p["shading.bloom_intensity"])})
        steps = [(0, target.color, fbo_a, (0.0, 0.0)), (1, tex_a, fbo_b, (1.0 / half[0], 0.0)),
                 (1, tex_b, fbo_a, (0.0, 1.0 / half[1]))]
        for pass_, source, fbo, direction in steps:
            fbo.use()
            prog.bind_textures({"uSource": source})
            prog.set_many({"uPass": pass_, "uDirection": direction})
            draw_fullscreen(prog)
        target.use()
        prog.bind_textures({"uSource": tex_a})
        prog.set("uPass", 2)
        draw_fullscreen(prog, blend=ADD_BLEND)

    def release(self) -> None:
        """Forget every resource (the owner's allocations are freed by the Gpu)."""
        for vbo in list(self._smooth):
            held = self._smooth.pop(vbo)
            self.gpu.free(held[1])
        for obj in ([self._gbuffer] if self._gbuffer is not None else []) + (
                list(self._bloom[1:]) if self._bloom is not None else []):
            self.gpu.free(obj)
        self._gbuffer = None
        self._bloom = None

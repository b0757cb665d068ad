"""The shading lab's outline figures (spec/003 §2.13): each ``shading.contour`` method's outline
mask against the analytic silhouette of the lab's sphere and of its low-poly table — IoU and
the number of gaps along the silhouette — beside the contour pass's cost, timed in one
interleaved run.

The objects are drawn white (ambient 1, no sun) with the lab's surface program on black and the
outline colour is pure red, so the outline mask is the set of pixels near red; the reference
bands come from ``app.sim.outline_metrics``: outside the silhouette for the hulls, on both sides
(half the width each) for the edge detectors, where the analytic rim weight exceeds ½ for the
rim silhouettes on the sphere (the table has no analytic n·v: a band inside its edge).
"""

from __future__ import annotations

import numpy as np

from ..effects.shading.outlines import Outlines, outline_params
from ..gpu.programs import ProgramSpec
from ..gpu.timing import time_interleaved
from ..params import ParamSet
from ..sim import lab_meshes
from ..sim import lighting as lt
from ..sim import outline_metrics as om
from ..sim.camera import Camera

OWNER = "bench-outlines"
SURFACE = ProgramSpec("shading/surface")
RED = np.array([1.0, 0.0, 0.0])
FORMAT = ("3f 3f 2f 4f", "in_position", "in_normal", "in_uv", "in_tangent")
ATTRIBUTES = ("position", "normal", "uv", "tangent")
METHODS = ("hull", "hull_smooth", "rim_threshold", "rim_soft", "rim_50x2", "edges_sobel",
           "edges_roberts")
WIDTH = 4.0  # px
RIM = 0.6
#: where a closed outline of each family covers every pixel next to the silhouette
GAP_SIDE = {"hull": "outside", "rim": "inside", "edges": "both"}


def _cameras():
    sphere = Camera(position=(0.0, 0.5, 3.0), yaw=0.0, pitch=0.0, fov=40.0)
    eye = np.array([1.7, 1.9, 2.3])
    table = Camera(position=tuple(eye), fov=45.0).look_at_direction(
        np.array([0.0, 0.42, 0.0]) - eye)
    return {"sphere": sphere, "table": table}


def draw_white(gpu, owner: str, objects, view, proj, camera, ramp) -> None:
    """Draw ``objects`` ((vbo, ibo, mesh, model) each) white into the bound target: the lab's
    surface program lit by an ambient of 1 alone, depth-tested; ``ramp`` a 1×1 texture."""
    import moderngl

    prog = gpu.program(owner, SURFACE)
    lights = lt.Lights(sun_radiance=(0.0, 0.0, 0.0), ambient=(1.0, 1.0, 1.0))
    prog.set_many({**lt.Shading(lighting_model=0, specularity=0.0).uniforms(),
                   **lights.uniforms(), "uViewProj": proj @ view,
                   "uCameraPos": camera.position, "uAlbedo": (1.0, 1.0, 1.0),
                   "uUseMasks": False, "uUseMaps": False, "uUseAlbedoMap": False,
                   "uTime": 0.0})
    for k, rows in lights.arrays().items():
        prog.set_array(k, rows)
    prog.bind_textures({"uRamp": ramp, "uMasks": ramp})
    gpu.ctx.enable(moderngl.DEPTH_TEST)
    for vbo, ibo, _mesh, model in objects:
        prog.set("uModel", model)
        prog.vao([(vbo, *FORMAT)], ibo).render(moderngl.TRIANGLES)
    gpu.ctx.disable(moderngl.DEPTH_TEST)


class _Lab:
    """The objects, the surface program and an Outlines of its own (red, width 4 px)."""

    def __init__(self, gpu, size):
        self.gpu = gpu
        self.size = size
        self.params = ParamSet(outline_params())
        self.params.set_many({"shading.contour_color": tuple(RED),
                              "shading.contour_width": WIDTH, "shading.contour_rim": RIM})
        self.outlines = Outlines(gpu, OWNER, self.params)
        one = np.array([0.0, 1.0, 0.0, 0.0], "f4").tobytes()
        self.tex = gpu.texture(OWNER, "one", (1, 1), 4, data=one)
        self.objects = {}
        for name in ("sphere", "table"):
            mesh = lab_meshes.TEST_OBJECTS[name]()
            vbo = gpu.buffer(OWNER, name, mesh.vertex_data(ATTRIBUTES))
            ibo = gpu.buffer(OWNER, name + " indices", mesh.index_data())
            self.objects[name] = (vbo, ibo, mesh, np.identity(4))
        self.target = gpu.target(OWNER, "image", size)

    def objects_pass(self, name, camera):
        view, proj = camera.view_matrix(), camera.projection_matrix(self.size[0] / self.size[1])
        self.target.use()
        self.target.clear((0.0, 0.0, 0.0, 1.0))
        draw_white(self.gpu, OWNER, [self.objects[name]], view, proj, camera, self.tex)
        return view, proj

    def contour(self, name, camera, method):
        self.params.set("shading.contour", method)
        view, proj = self.objects_pass(name, camera)
        self.outlines.draw(self.target, view, proj, [self.objects[name]])

    def release(self):
        self.outlines.release()
        self.gpu.release_owner(OWNER)


def _reference(method, inside, nv):
    if method.startswith("hull"):
        return om.silhouette_band(inside, WIDTH, "outside")
    if method.startswith("edges"):
        return om.silhouette_band(inside, WIDTH / 2, "both")
    if nv is None:  # no analytic n·v (the table): the band inside the silhouette
        return om.silhouette_band(inside, WIDTH, "inside")
    mode = {"rim_threshold": "threshold", "rim_soft": "soft", "rim_50x2": "50x2"}[method]
    return inside & (om.rim_outline_weight(mode, np.nan_to_num(nv, nan=1.0), RIM) > 0.5)


def outline_sweep(gpu, size=(128, 128), warmup: int = 1, rounds: int = 5) -> dict:
    """IoU, gaps and the contour pass's time (ms, interleaved; the objects alone timed beside
    them) per method on the sphere and the table."""
    lab = _Lab(gpu, tuple(size))
    cams = _cameras()
    try:
        rows = []
        for name, camera in cams.items():
            view, proj = camera.view_matrix(), camera.projection_matrix(size[0] / size[1])
            if name == "sphere":
                inside = om.sphere_coverage(view, proj, size, (0.0, 0.5, 0.0), 0.5)
                nv = om.sphere_nv(view, proj, size, (0.0, 0.5, 0.0), 0.5)
            else:
                inside = om.boxes_coverage(view, proj, size, om.table_boxes())
                nv = None
            for method in METHODS:
                lab.contour(name, camera, method)
                img = lab.target.read()
                mask = np.abs(img[..., :3] - RED).max(-1) < 0.5
                side = GAP_SIDE[method.split("_")[0]]
                rows.append({"object": name, "method": method,
                             "iou": om.outline_iou(mask, _reference(method, inside, nv)),
                             "gaps": om.gap_count(mask, om.silhouette_band(
                                 inside, 1.5 if side != "both" else 1.0, side)),
                             "finite": bool(np.isfinite(img).all())})
            variants = {"objects only": lambda n=name, c=camera: lab.objects_pass(n, c)}
            for method in METHODS:
                variants[method] = lambda n=name, c=camera, m=method: lab.contour(n, c, m)
            timed = time_interleaved(gpu.ctx, variants, warmup, rounds)
            base = timed.quartiles("objects only")[1]
            for r in rows:
                if r["object"] == name:
                    total = timed.quartiles(r["method"])[1]
                    r["ms"] = total
                    r["contour_ms"] = max(total - base, 0.0)
        return {"size": list(size), "width_px": WIDTH, "rim": RIM, "rows": rows}
    finally:
        lab.release()


def summary_lines(report: dict) -> list[str]:
    lines = [f"outlines at {report['size'][0]}x{report['size'][1]}, width {report['width_px']:g} "
             "px (IoU against the analytic silhouette band, gaps along it, contour ms):"]
    for r in report["rows"]:
        lines.append(f"  {r['object']:6s} {r['method']:14s} IoU {r['iou']:.3f}  gaps "
                     f"{r['gaps']:3d}  {r['contour_ms']:.2f} ms")
    return lines

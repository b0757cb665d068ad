"""The village's fog figures (spec/003 §2.11): what computing the fog per vertex costs in accuracy
and saves in time, and what the analytic height fog costs and how exact it is.

1. **Per vertex against per pixel.** The thesis computes the fog factor per vertex "to avoid
   the exponentials" per pixel and lets the rasteriser interpolate it across each triangle
   (fog.glsl's FogVertexFactor in the w of the world position). The exponentials are not
   linear, so on large triangles the interpolated factor is wrong. A ground of 256 m at the
   plateau's height (1.6 m), seen from the village's default camera, is tessellated at cells of
   0.5 … 256 m (two triangles at 256 m, the whole ground) and drawn with the fog of the
   village's defaults (``app.sim.fog.FogGenerator``: exp2 t = 0.0162/m; exp at the same t;
   linear 0 → 40.6 m) through ``glsl/fog/bench_surface.*`` into a float target with fog colour
   0 and object colour 1, so each pixel *is* its factor f. The per-pixel factor (the same
   formula at each fragment's own depth, checked against the numpy twin from the fragment's
   depth) is the reference; the error of the per-vertex one is |f_vertex − f_pixel|·255: the
   8-bit levels a full-contrast lerp(fogColour, colour, f) is off, mean and max over the
   ground's pixels, against the cell size and the mode. Both paths are timed in interleaved
   rounds (``app.gpu.timing.time_interleaved``; medians and quartiles).
2. **The height fog.** Quílez's analytic transmittance (fog.glsl's FogHeightTransmittance, the
   scene's defaults: a = 0.15·0.324/m at the sea level, b = 0.35/m) per pixel on the same
   ground from the same camera, against the midpoint integral of the density along each
   pixel's ray (``fog_height_reference``, 2048 steps) at the pixels' world positions
   (reconstructed from their depth): max and mean |ΔT|; the numpy twin against the same
   reference on random rays, grazing ones included; and its ms beside the distance fog's two
   paths on the 1 m ground, in the same rounds.

On llvmpipe absolute times mean little; the ratios within one run hold.

``run(gpu, quick)`` → dict; ``chart(report, path, force)``; ``summary(report)`` → lines.
"""

from __future__ import annotations

from typing import Callable

import moderngl
import numpy as np

from ..gpu.device import Gpu
from ..gpu.programs import ProgramSpec
from ..gpu.timing import time_interleaved
from ..sim import fog as fs
from ..sim.camera import Camera
from . import pyplot, write_chart

SURFACE = ProgramSpec("fog/bench_surface")
OWNER = "bench-fog"
#: the village's default camera (app/scenes/village.py)
CAMERA = {"position": (0.0, 4.8, 25.0), "yaw": 0.0, "pitch": -12.0, "fov": 60.0, "near": 0.1,
          "far": 2000.0}
GROUND_Y = 1.6  # the island's plateau [m]
EXTENT = 256.0  # the ground: x ∈ [−128, 128], z ∈ [25 − 256, 25] [m]
QUICK = {"size": (160, 90), "cells": (1.0, 8.0, 64.0, 256.0), "rounds": 4, "budget_s": 3.0,
         "rays": 400}
FULL = {"size": (320, 180), "cells": (0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0, 256.0),
        "rounds": 11, "budget_s": 40.0, "rays": 4000}
MODES = ("linear", "exp", "exp2")


def ground_mesh(cell: float) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (n, 3) float32, indices uint32): the ground tessellated at ``cell`` metres."""
    n = max(1, int(round(EXTENT / cell)))
    xs = np.linspace(-EXTENT / 2, EXTENT / 2, n + 1)
    zs = np.linspace(25.0, 25.0 - EXTENT, n + 1)
    gx, gz = np.meshgrid(xs, zs, indexing="xy")
    verts = np.stack([gx.ravel(), np.full(gx.size, GROUND_Y), gz.ravel()], -1).astype("f4")
    r, c = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    a = r * (n + 1) + c
    b = a + n + 1
    idx = np.stack([a, b, a + 1, a + 1, b, b + 1], -1).reshape(-1).astype("u4")
    return verts, idx


def village_fog() -> fs.FogGenerator:
    return fs.FogGenerator()  # the scene's defaults: Fig. 124 and fog.scale = 2


def mode_settings(mode: str, **kw) -> fs.FogSettings:
    g = fs.FogGenerator(mode=mode)
    s = g.settings(colour=(0.0, 0.0, 0.0), **kw)
    assert s is not None
    return s


class _Rig:
    def __init__(self, gpu: Gpu, size):
        self.gpu, self.size = gpu, tuple(size)
        self.camera = Camera(**CAMERA)
        self.colour = gpu.texture(OWNER, "colour", self.size, 4, dtype="f4")
        self.depth = gpu.depth_texture(OWNER, "depth", self.size)
        self.fbo = gpu.framebuffer(OWNER, "fbo", [self.colour], self.depth)
        self.prog = gpu.program(OWNER, SURFACE)
        self.meshes: dict[float, tuple] = {}

    def mesh(self, cell: float):
        if cell not in self.meshes:
            verts, idx = ground_mesh(cell)
            self.meshes[cell] = (self.gpu.buffer(OWNER, f"ground {cell}", verts.tobytes()),
                                 self.gpu.buffer(OWNER, f"ground {cell} idx", idx.tobytes()),
                                 len(idx) // 3)
        return self.meshes[cell]

    def draw(self, cell: float, cfg: fs.FogSettings) -> None:
        cam = self.camera
        vbo, ibo, _ = self.mesh(cell)
        self.prog.set_many({"uViewProj": cam.projection_matrix(self.size[0] / self.size[1])
                            @ cam.view_matrix(), "uObjectColor": (1.0, 1.0, 1.0),
                            **fs.fog_uniforms(cfg, cam.position, cam.near, cam.far)})
        self.fbo.use()
        self.fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        ctx = self.gpu.ctx
        ctx.enable(moderngl.DEPTH_TEST)
        self.prog.vao([(vbo, "3f", "in_position")], index_buffer=ibo).render(moderngl.TRIANGLES)
        ctx.disable(moderngl.DEPTH_TEST)

    def read(self) -> np.ndarray:
        w, h = self.size
        raw = np.frombuffer(self.fbo.read(components=4, dtype="f4"), np.float32)
        return raw.reshape(h, w, 4)[::-1].astype(np.float64)

    def world(self, w: np.ndarray) -> np.ndarray:
        """World positions of pixels at view depth ``w`` (the probe's alpha)."""
        cam = self.camera
        dirs = cam.ray_directions(*self.size)
        return np.asarray(cam.position) + dirs * (w / (dirs @ cam.forward()))[..., None]


def _errors(vertex: np.ndarray, pixel: np.ndarray, seen: np.ndarray) -> dict:
    e = np.abs(vertex - pixel)[seen] * 255.0
    return {"mean_levels": float(e.mean()), "max_levels": float(e.max()),
            "p99_levels": float(np.percentile(e, 99))}


def run(gpu, quick: bool = False) -> dict:
    """The figures of the module docstring."""
    cfg = QUICK if quick else FULL
    caller = gpu
    gpu = Gpu(caller.ctx, caller.shaders.root)  # its own record: release frees only ours
    rig = _Rig(gpu, cfg["size"])
    try:
        return _run(rig, cfg, quick)
    finally:
        gpu.release()


def _run(rig: _Rig, cfg: dict, quick: bool) -> dict:
    cells = tuple(cfg["cells"])
    rows = []
    twin_error = 0.0
    for mode in MODES:
        settings = {pp: mode_settings(mode, per_pixel=pp) for pp in (False, True)}
        for cell in cells:
            rig.draw(cell, settings[True])
            pixel = rig.read()
            rig.draw(cell, settings[False])
            vertex = rig.read()
            seen = pixel[..., 3] > 0
            d = fs.fog_distance(pixel[..., 3][seen], rig.camera.near, rig.camera.far)
            twin = fs.fog_factor(d, settings[True])
            twin_error = max(twin_error, float(np.abs(pixel[..., 0][seen] - twin).max()))
            rows.append({"mode": mode, "cell_m": cell, "triangles": rig.mesh(cell)[2],
                         "coverage": float(seen.mean()),
                         **_errors(vertex[..., 0], pixel[..., 0], seen)})
    # the height fog on the same ground, per pixel, against the numeric integral
    g = village_fog()
    height = g.settings(colour=(0.0, 0.0, 0.0), height=True)
    assert height is not None
    a, b, y0 = height.height_density, height.height_falloff, height.height_base
    rig.draw(cells[0], height)
    img = rig.read()
    seen = img[..., 3] > 0
    pts = rig.world(img[..., 3])[seen]
    pts[:, 1] = GROUND_Y
    cam = np.asarray(rig.camera.position)
    ref = fs.fog_height_reference(pts, cam, a, b, y0, steps=2048)
    gpu_err = np.abs(img[..., 0][seen] - ref)
    rng = np.random.default_rng(3)
    n = cfg["rays"]
    o = np.stack([rng.uniform(-60, 60, n), rng.uniform(0.0, 40.0, n),
                  rng.uniform(-60, 60, n)], -1)
    dirs = rng.normal(size=(n, 3))
    dirs[: n // 4, 1] = rng.choice([0.0, 1e-6, -1e-4, 1e-3], n // 4)  # grazing rays
    dirs /= np.linalg.norm(dirs, axis=-1, keepdims=True)
    ends = o + dirs * rng.uniform(0.0, 500.0, (n, 1))
    twin_ray_err = np.abs(fs.fog_height_transmittance(ends, o, a, b, y0)
                          - fs.fog_height_reference(ends, o, a, b, y0, steps=8192))
    # the times: both paths at each cell (exp2, the village's mode) and the height fog
    exp2 = {pp: mode_settings("exp2", per_pixel=pp) for pp in (False, True)}
    variants: dict[str, Callable[[], None]] = {}
    for cell in cells:
        variants[f"vertex {cell:g}"] = (lambda c=cell: rig.draw(c, exp2[False]))
        variants[f"pixel {cell:g}"] = (lambda c=cell: rig.draw(c, exp2[True]))
    variants["height 1"] = lambda: rig.draw(1.0, height)
    rig.mesh(1.0)
    timed = time_interleaved(rig.gpu.ctx, variants, warmup=1, rounds=cfg["rounds"],
                             budget_s=cfg["budget_s"], min_rounds=3)
    times = timed.summary(reference="vertex 1" if "vertex 1" in variants else None)
    return {
        "quick": quick, "size": list(rig.size), "camera": CAMERA, "ground_y": GROUND_Y,
        "extent_m": EXTENT, "cells_m": list(cells), "rounds": timed.rounds,
        "settings": {m: {k: v for k, v in mode_settings(m).__dict__.items()
                         if k in ("mode", "density", "start", "end")} for m in MODES},
        "rows": rows, "per_pixel_vs_twin_max": twin_error,
        "times": times,
        "height": {"a": a, "b": b, "y0": y0, "pixels": int(seen.sum()),
                   "gpu_vs_reference_max": float(gpu_err.max()),
                   "gpu_vs_reference_mean": float(gpu_err.mean()),
                   "twin_vs_reference_max": float(twin_ray_err.max()), "rays": n,
                   "ms": times["height 1"]["median_ms"]},
    }


def chart(report: dict, path, force: bool = False) -> None:
    """Left: the per-vertex error against the cell size, each mode (max solid, mean dashed);
    right: the ms of both paths (exp2) and of the height fog on the 1 m ground."""
    plt = pyplot()
    from matplotlib.ticker import ScalarFormatter

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 4.8))
    cells = report["cells_m"]
    for k, mode in enumerate(MODES):
        rows = [r for r in report["rows"] if r["mode"] == mode]
        x = [r["cell_m"] for r in rows]
        s = report["settings"][mode]
        label = (f"linear {s['start']:.0f}→{s['end']:.1f} m" if mode == "linear"
                 else f"{mode} t = {s['density']:.4f}/m")
        ax.plot(x, [max(r["max_levels"], 1e-3) for r in rows], "o-", color=f"C{k}",
                label=f"{label}: max")
        ax.plot(x, [max(r["mean_levels"], 1e-3) for r in rows], "s--", color=f"C{k}",
                label="mean")
    ax.axhline(1.0, color="grey", lw=0.8, ls=":")
    ax.text(cells[0], 1.08, "1 level", fontsize=7, color="grey")
    ax.set_xscale("log", base=2)
    ax.set(yscale="log", xlabel="ground cell [m] (256 m: the whole ground in 2 triangles)",
           ylabel="|f_vertex − f_pixel| · 255  [8-bit levels]")
    ax.set_title("per-vertex fog factor (the thesis's) vs per pixel, village camera", fontsize=9)
    ax.legend(fontsize=6, ncol=3)
    t = report["times"]
    for k, path_name in enumerate(("vertex", "pixel")):
        med = [t[f"{path_name} {c:g}"]["median_ms"] for c in cells]
        lo = [t[f"{path_name} {c:g}"]["p25_ms"] for c in cells]
        hi = [t[f"{path_name} {c:g}"]["p75_ms"] for c in cells]
        bx.errorbar(cells, med, yerr=[np.subtract(med, lo), np.subtract(hi, med)], fmt="o-",
                    color=f"C{k + 3}", capsize=2, label=f"exp2 per {path_name}")
    h = report["height"]
    bx.plot([1.0], [h["ms"]], "k*", ms=10,
            label=f"height fog (1 m cells): max |ΔT| {h['gpu_vs_reference_max']:.1e} vs the "
                  "numeric integral")
    bx.set_xscale("log", base=2)
    bx.set_yscale("log")
    for axis in (ax.xaxis, bx.xaxis):
        axis.set_major_formatter(ScalarFormatter())
    bx.set(xlabel="ground cell [m]", ylabel="ms per draw (median, quartiles)")
    bx.set_title(f"cost, {report['size'][0]}×{report['size'][1]}, {report['rounds']} "
                 "interleaved rounds", fontsize=9)
    bx.legend(fontsize=7)
    write_chart(fig, path, force, title="village fog — per vertex vs per pixel "
                                        "(spec/003 eq. 7.28, spec/003 eq. 7.29), "
                                        "height fog (Quílez 2010)")


def summary(report: dict) -> list[str]:
    lines = []
    for mode in MODES:
        rows = [r for r in report["rows"] if r["mode"] == mode]
        lines.append(f"{mode}: per-vertex error (8-bit levels, mean / max) "
                     + ", ".join(f"{r['cell_m']:g} m {r['mean_levels']:.3g}/"
                                 f"{r['max_levels']:.3g}" for r in rows))
    t = report["times"]
    cells = report["cells_m"]
    lines.append("exp2 ms per draw (vertex / pixel): "
                 + ", ".join(f"{c:g} m {t[f'vertex {c:g}']['median_ms']:.2f}/"
                             f"{t[f'pixel {c:g}']['median_ms']:.2f}" for c in cells))
    h = report["height"]
    lines.append(f"height fog: GPU vs numeric integral max |ΔT| {h['gpu_vs_reference_max']:.1e} "
                 f"(mean {h['gpu_vs_reference_mean']:.1e}, {h['pixels']} px); twin vs integral "
                 f"max {h['twin_vs_reference_max']:.1e} on {h['rays']} rays; {h['ms']:.2f} ms; "
                 f"per-pixel factor vs twin max {report['per_pixel_vs_twin_max']:.1e}")
    return lines

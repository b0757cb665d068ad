"""The surfaces lab's reflection figures (spec/003 §2.5, §2.6), a section of its bench:

(a) each probe lookup (cube, box, approximation, perfect) against the exact ray cast of the
    reflected ray (``app.sim.surfaces_scene.ray_cast``) over the mirror floor and the mirror
    sphere seen from the lab's camera: the probe is captured with each texel's world position
    as its colour (``glsl/surfaces/probe_scene.frag``), so the colour a lookup returns is the
    point it shows; the errors are that point's distance to the exact hit (m) and the angle
    between the two as seen from the mirror (°), beside the ms of the lookup pass over the
    points (one pass = one fragment per point; ``glsl/surfaces/probe_reflection_eval.frag``);
(b) the thesis's metallic/dielectric (diffuse lerped with the mip-blurred probe by
    weight = 0.25·s + 0.75·m, tinted lerp(1, albedo, m)) against the split-sum prefiltered GGX
    reference on the dielectric sphere, over smoothness × metallic: the mean |Δ| radiance
    over the sphere's visible points (the probe shows the room's albedos on a checker under a
    glowing ceiling), and the reference's mean for scale;

and the probe's capture (six faces + mips) and GGX prefilter ms. The mirror sphere is left out
of the capture and of the reference ray cast (a probe cannot show the mirror it lights).
"""

from __future__ import annotations

import numpy as np

from ..effects.surfaces.reflections import PROBE_EVAL, PositionScene, ReflectionProbe
from ..gpu.timing import time_call
from ..sim import reflections as rf
from ..sim import surfaces_scene as ss
from . import pyplot, write_chart

OWNER = "bench-reflections"
EYE = np.array([-1.2, 1.7, 3.4])  # sees the mirror sphere past the glass one
CORRECTIONS = ("cube", "box", "approximation", "perfect")
SMOOTHNESS = (0.0, 0.25, 0.5, 0.75, 1.0)
METALLIC = (0.0, 0.5, 1.0)


def _visible_floor(scene, ref, n: int, rng) -> np.ndarray:
    lo, hi = np.asarray(scene.room.lo), np.asarray(scene.room.hi)
    p = np.stack([rng.uniform(lo[0] + 0.05, hi[0] - 0.05, n), np.zeros(n),
                  rng.uniform(lo[2] + 0.05, hi[2] - 0.05, n)], 1)
    t, index = _from_eye(ref, p)
    return p[(index == -1) & (t > 0.999)]


def _visible_sphere(sphere, ref, n: int, rng) -> np.ndarray:
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    p = np.asarray(sphere.centre) + sphere.radius * 1.0001 * d
    facing = np.einsum("ij,ij->i", d, EYE - p) > 0
    p = p[facing]
    t, _ = _from_eye(ref, p)
    return p[t > 0.999]


def _from_eye(ref, p):
    """The ray cast from the eye toward ``p``, t as a fraction of the way (unit directions:
    ``ray_cast``'s sphere test assumes them)."""
    d = p - EYE
    length = np.linalg.norm(d, axis=1)
    t, index = ss.ray_cast(ref, np.broadcast_to(EYE, p.shape), d / length[:, None])
    return t / length, index


class _Points:
    """The eval program over fixed points: uploaded once, each run draws and reads back."""

    def __init__(self, gpu, points: np.ndarray):
        import moderngl

        pts = np.asarray(points, np.float32)
        self.n = len(pts)
        if self.n == 0:
            raise ValueError("no visible points on the surface: allowed a camera that sees it")
        w = min(self.n, 256)
        h = (self.n + w - 1) // w
        padded = np.zeros((w * h, 4), np.float32)
        padded[: self.n, :3] = pts
        self.gpu = gpu
        self.size = (w, h)
        self.src = gpu.texture(OWNER, "points", (w, h), 4, padded.tobytes(),
                               filter=(moderngl.NEAREST, moderngl.NEAREST))
        self.target = gpu.target(OWNER, "points out", (w, h), depth=False)
        self.prog = gpu.program(OWNER, PROBE_EVAL, vert="common/fullscreen.vert",
                                frag=f"{PROBE_EVAL}.frag")

    def setup(self, probe: ReflectionProbe, uniforms: dict) -> None:
        probe.bind(self.prog, {"uPoints": self.src})
        self.prog.set_many(uniforms)

    def draw(self) -> None:
        import moderngl

        self.target.use()
        self.gpu.ctx.viewport = (0, 0, *self.size)
        self.prog.vao().render(moderngl.TRIANGLES, vertices=3)

    def read(self) -> np.ndarray:
        raw = np.frombuffer(self.target.fbo.read(components=4, dtype="f4"), np.float32)
        return raw.reshape(-1, 4)[: self.n].astype(np.float64)

    def release(self) -> None:
        self.gpu.free(self.src)
        self.gpu.free(self.target)


def _angle(a, b) -> np.ndarray:
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    b = b / np.linalg.norm(b, axis=1, keepdims=True)
    return np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", a, b), -1.0, 1.0)))


def run(gpu, size=(128, 128), quick: bool = False) -> dict:
    """Both sweeps (module docstring); ``size`` (w, h) bounds the points per surface (w·h)."""
    full = ss.default_scene()
    mirror = full.get("mirror")
    ref = ss.SurfacesScene(room=full.room, spheres=[s for s in full.spheres if s is not mirror],
                           boxes=full.boxes, cylinders=full.cylinders)
    rng = np.random.default_rng(7)
    n = int(size[0]) * int(size[1])
    n = min(n, 4096) if quick else n
    repeat = 3 if quick else 10
    probe_size = 64 if quick else 128
    params = {"surfaces.probe_size": probe_size,
              "surfaces.prefilter_samples": 32 if quick else 64}
    probe = ReflectionProbe(gpu, OWNER, params)
    position = PositionScene(gpu, OWNER, full, skip=("mirror",))
    radiance = PositionScene(gpu, OWNER, full, skip=("mirror",), radiance=True)
    report: dict = {"probe_size": probe_size, "points_per_surface": n, "eye": EYE.tolist()}
    made = []
    try:
        box = (full.room.lo, full.room.hi)
        keys = iter(range(10 ** 6))

        def capture():
            probe.update(next(keys), position.draw, full.probe_position, *box)

        t = time_call(gpu.ctx, "capture", capture, warmup=1, repeat=repeat)
        report["capture_ms"] = t.median_ms
        report["prefilter_ms"] = probe.prefilter_ms
        report["capture_only_ms"] = probe.capture_ms
        surfaces = {"floor": (_visible_floor(full, ref, 2 * n, rng), None),
                    "sphere": (_visible_sphere(mirror, ref, 3 * n, rng), mirror)}
        rows = []
        for name, (pts, sphere) in surfaces.items():
            pts = pts[:n]
            nrm = (pts - np.asarray(sphere.centre)) / sphere.radius if sphere else \
                np.broadcast_to([0.0, 1.0, 0.0], pts.shape)
            nrm = nrm / np.linalg.norm(nrm, axis=1, keepdims=True)
            d = pts - EYE
            d /= np.linalg.norm(d, axis=1, keepdims=True)
            r = d - 2.0 * np.einsum("ij,ij->i", d, nrm)[:, None] * nrm
            start = pts + 1e-4 * r
            tt, _ = ss.ray_cast(ref, start, r)
            exact = start + tt[:, None] * r
            ev = _Points(gpu, pts)
            made.append(ev)
            for mode in CORRECTIONS:
                u = {"uEvalMode": 2, "uReflection": rf.MODE_CODE[mode], "uEye": tuple(EYE),
                     "uNormal": (0.0, 1.0, 0.0), "uSphereNormal": int(sphere is not None),
                     "uSphereCentre": tuple(sphere.centre) if sphere else (0.0, 0.0, 0.0),
                     "uSmoothness": 1.0}
                ev.setup(probe, u)
                timing = time_call(gpu.ctx, mode, ev.draw, warmup=1, repeat=repeat)
                seen = ev.read()[:, :3]
                dist = np.linalg.norm(seen - exact, axis=1)
                ang = _angle(seen - pts, exact - pts)
                rows.append({"surface": name, "mode": mode, "points": len(pts),
                             "median_ms": timing.median_ms,
                             "hit_error_m_median": float(np.median(dist)),
                             "hit_error_m_p90": float(np.percentile(dist, 90)),
                             "angle_deg_median": float(np.median(ang)),
                             "angle_deg_p90": float(np.percentile(ang, 90))})
        report["directions"] = rows
        # (b) the thesis against the split-sum GGX reference on the dielectric sphere
        probe.update("radiance", radiance.draw, full.probe_position, *box)
        target = full.get("dielectric")
        pts = _visible_sphere(target, ref, 3 * min(n, 4096), rng)[: min(n, 4096)]
        ev = _Points(gpu, pts)
        made.append(ev)
        grid = []
        smooth = SMOOTHNESS[::2] if quick else SMOOTHNESS
        metal = METALLIC[::2] if quick else METALLIC
        for m in metal:
            for s in smooth:
                out = {}
                for ggx in (0, 1):
                    ev.setup(probe, {"uEvalMode": 5, "uReflection": rf.MODE_CODE["box"],
                                     "uEye": tuple(EYE), "uSphereCentre": tuple(target.centre),
                                     "uAlbedo": tuple(target.albedo), "uSmoothness": s,
                                     "uMetallic": m, "uGgx": ggx})
                    ev.draw()
                    out[ggx] = ev.read()[:, :3]
                diff = np.abs(out[0] - out[1]).mean()
                grid.append({"smoothness": s, "metallic": m,
                             "weight": float(rf.reflection_weight(s, m)),
                             "mean_abs_error": float(diff),
                             "thesis_mean": float(out[0].mean()),
                             "ggx_mean": float(out[1].mean())})
        report["materials"] = {"object": target.name, "points": len(pts), "rows": grid}
        report["table_1"] = {f"s{s:g}_m{m:g}": float(rf.reflection_weight(s, m))
                             for s in (0, 1) for m in (0, 1)}
    finally:
        for ev in made:
            ev.release()
        probe.release()
        gpu.release_owner(OWNER)
    return report


def chart(report: dict, path, force: bool = False) -> None:
    """(a) angular error against ms per correction, floor and sphere; (b) thesis vs GGX."""
    plt = pyplot()

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    colours = {"cube": "tab:red", "box": "tab:blue", "approximation": "tab:orange",
               "perfect": "tab:green"}
    for ax, surface in zip(axes[:2], ("floor", "sphere")):
        for r in (r for r in report["directions"] if r["surface"] == surface):
            ax.errorbar([r["median_ms"]], [max(r["angle_deg_median"], 1e-3)],
                        yerr=[[0], [max(r["angle_deg_p90"] - r["angle_deg_median"], 0)]],
                        fmt="o", color=colours[r["mode"]], label=f"{r['mode']} "
                        f"({r['hit_error_m_median']:.3f} m)")
        ax.set(yscale="log", xlabel="ms, lookup pass over the points",
               ylabel="angular error vs ray cast [°] (median, bar to p90)")
        ax.set_title(f"mirror {surface}: probe lookup vs exact reflection", fontsize=9)
        ax.legend(fontsize=7)
    ax = axes[2]
    rows = report["materials"]["rows"]
    for k, m in enumerate(sorted({r["metallic"] for r in rows})):
        rs = [r for r in rows if r["metallic"] == m]
        c = f"C{k}"
        ax.plot([r["smoothness"] for r in rs], [r["mean_abs_error"] for r in rs], "o-",
                color=c, label=f"metallic {m:g}: |thesis − GGX|")
        ax.plot([r["smoothness"] for r in rs], [r["ggx_mean"] for r in rs], ":", color=c,
                label=f"metallic {m:g}: GGX mean radiance")
    ax.set(xlabel="smoothness", ylabel="mean radiance")
    ax.set_title("thesis weights (spec/003 eq. 5.18) vs split-sum GGX on the dielectric sphere",
                 fontsize=9)
    ax.legend(fontsize=7)
    write_chart(fig, path, force,
                title=f"surfaces reflections — probe {report['probe_size']}², capture "
                      f"{report['capture_ms']:.1f} ms")


def summary(report: dict) -> list[str]:
    t1 = report["table_1"]
    lines = [f"Table 1 (spec/003 eq. 5.18): (s0,m0) {t1['s0_m0']:.2f}, (s0,m1) "
             f"{t1['s0_m1']:.2f}, (s1,m0) {t1['s1_m0']:.2f}, (s1,m1) {t1['s1_m1']:.2f}",
             f"probe {report['probe_size']}²: capture + mips + prefilter "
             f"{report['capture_ms']:.1f} ms (capture {report['capture_only_ms']:.1f} ms, "
             f"GGX prefilter {report['prefilter_ms']:.1f} ms)"]
    for r in report["directions"]:
        lines.append(f"  {r['surface']:6s} {r['mode']:13s} {r['median_ms']:7.3f} ms  hit "
                     f"{r['hit_error_m_median']:.4f}/{r['hit_error_m_p90']:.4f} m  angle "
                     f"{r['angle_deg_median']:.3f}/{r['angle_deg_p90']:.3f}° (median/p90, "
                     f"{r['points']} points)")
    lines.append(f"thesis vs GGX on the {report['materials']['object']} sphere "
                 "(mean |Δ| radiance; GGX mean):")
    for r in report["materials"]["rows"]:
        lines.append(f"  s {r['smoothness']:.2f} m {r['metallic']:.2f} (weight "
                     f"{r['weight']:.2f}): {r['mean_abs_error']:.4f} (GGX {r['ggx_mean']:.4f})")
    return lines

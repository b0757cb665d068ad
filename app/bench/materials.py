"""Speed against accuracy for the procedural materials: noise octaves, baked noise, ring edges.

Three sweeps, each timed in one run on one renderer (ratios hold where absolute times do not):

1. **Noise cost per octave** — the cross-section filling the target, RecDepth 1…8, for the
   thesis's value noise and Perlin's gradient noise; a least-squares line gives ms per octave.
2. **Baked 3D texture against per-pixel noise** — the wood's distortion noise baked over the
   object box at N³ (N = 8…128) and read with trilinear filtering, against evaluating it per
   pixel. Error is measured against the per-pixel render of the same view: the noise itself
   (mean and 99th percentile of |Δ|) and the final colour (display units).
3. **Ring edges** — hard rings (the thesis) against the box-filtered rings, each compared with an
   8×8 supersampled render of the hard rings, with rings finer than the pixels.
4. **Tessellation** — the sphere and torus tessellated from their projected size
   (``materials.tessellation = auto``) against the fixed 48 × 96 segments, on the scene's view
   at 320×180 and 1280×720: the time ratio auto / fixed in one interleaved run per size
   (``app.gpu.timing.time_interleaved``; median and quartiles of the per-round ratios), the
   triangles of each, and the image change: the share of pixels whose display value moves by
   more than 0.05 and the mean |Δ| (display units, largest channel).
"""

from __future__ import annotations

import numpy as np

from ..colour import linear_to_srgb
from ..effects.materials.effect import (
    MATERIAL,
    MATERIAL_BAKED,
    MATERIAL_BAKED_RADIUS,
    MATERIAL_RADIUS,
    Materials,
)
from ..gpu.timing import time_call, time_interleaved
from . import pyplot, ratio_text, write_chart

TOP_VIEW = np.array([[2.0, 0, 0, 0], [0, 0, -2.0, 0], [0, 0, 0, 0], [0, 0, 0, 1.0]])
BAKE_SIZES = (8, 16, 32, 64, 128)
TESSELLATION_SIZES = ((320, 180), (1280, 720))
#: a pixel "changes" when its display value moves by more than this
CHANGE_THRESHOLD = 0.05


def _render(session, eff: Materials, target, frame, spec=MATERIAL, view_proj=None, baked=None):
    def run():
        target.use()
        target.clear((*session.scene.background, 1.0))
        eff.draw(frame, target, spec, view_proj=view_proj, baked=baked)

    return run


def _display(img):
    return linear_to_srgb(img[..., :3].astype(np.float64))


def tessellation(session, sizes=TESSELLATION_SIZES, warmup: int = 2, rounds: int = 15) -> dict:
    """Auto against fixed tessellation on the scene's view (see the module's item 4)."""
    params = session.params
    eff: Materials = session.scene.effect("materials")
    gpu = session.gpu
    rows = []
    with params.kept(["materials.tessellation"]):
        for size in sizes:
            size = tuple(int(v) for v in size)
            with gpu.scratch_target("bench", "tessellation", size) as target:
                frame = session.scene.frame(size)
                variants, images, triangles = {}, {}, {}
                for mode in ("fixed", "auto"):
                    draw = _render(session, eff, target, frame)

                    def run(mode=mode, draw=draw):
                        params.set("materials.tessellation", mode)
                        draw()

                    variants[mode] = run
                    run()
                    images[mode] = _display(target.read())
                    triangles[mode] = eff.triangles()
                timed = time_interleaved(gpu.ctx, variants, warmup, rounds)
            d = np.abs(images["auto"] - images["fixed"]).max(axis=-1)
            rows.append({"size": list(size), "rounds": timed.rounds,
                         "ratio": timed.ratio("auto", "fixed"),
                         "fixed_ms": timed.quartiles("fixed")[1],
                         "auto_ms": timed.quartiles("auto")[1],
                         "triangles_fixed": triangles["fixed"],
                         "triangles_auto": triangles["auto"],
                         "changed_share": float((d > CHANGE_THRESHOLD).mean()),
                         "mean_abs_diff": float(d.mean())})
    return {"threshold": CHANGE_THRESHOLD, "edge_pixels": params["materials.edge_pixels"],
            "rows": rows}


def sweep(session, size, warmup: int = 2, repeat: int = 7, bake_sizes=BAKE_SIZES,
          sizes=None) -> dict:
    params = session.params
    eff: Materials = session.scene.effect("materials")
    gpu = session.gpu
    out: dict = {}
    with params.kept() as saved:
        params.set("materials.material", "wood")
        # 1. noise cost per octave (square target, the slice fills it)
        n = min(size)
        square = gpu.target("bench", "square", (n, n))
        params.set("materials.objects", "slice")
        frame = session.scene.frame((n, n))
        octaves = {}
        for kind in ("value", "gradient"):
            params.set("materials.noise", kind)
            ms = []
            for d in range(1, 9):
                params.set("wood.rec_depth", d)
                t = time_call(gpu.ctx, f"{kind} d{d}",
                              _render(session, eff, square, frame, view_proj=TOP_VIEW),
                              warmup, repeat)
                ms.append(t.median_ms)
            slope, intercept = np.polyfit(np.arange(1, 9), ms, 1)
            octaves[kind] = {"ms_by_depth": ms, "ms_per_octave": float(slope),
                             "ms_base": float(intercept)}
        out["octave_cost"] = {"size": [n, n], **octaves}

        # 2. baked volume against per-pixel noise, on the scene's own view of the meshes
        params.set("materials.noise", "value")
        params.set("wood.rec_depth", saved.get("wood.rec_depth", 3))
        params.set("materials.objects", "all")
        view = gpu.target("bench", "view", size)
        frame = session.scene.frame(size)
        exact_run = _render(session, eff, view, frame)
        t_exact = time_call(gpu.ctx, "per-pixel", exact_run, warmup, repeat)
        exact_run()
        exact = view.read()
        _render(session, eff, view, frame, MATERIAL_RADIUS)()
        exact_noise = view.read()
        covered = exact_noise[..., 0] > 0.0
        rows = [{"method": "per-pixel", "size": None, "median_ms": t_exact.median_ms,
                 "noise_mean": 0.0, "noise_p99": 0.0, "colour_mean": 0.0, "colour_p99": 0.0,
                 "bake_s": 0.0}]
        for bs in bake_sizes:
            bake = eff.bake_noise(bs)
            run = _render(session, eff, view, frame, MATERIAL_BAKED, baked=bake.texture)
            t = time_call(gpu.ctx, f"baked {bs}", run, warmup, repeat)
            run()
            img = view.read()
            _render(session, eff, view, frame, MATERIAL_BAKED_RADIUS, baked=bake.texture)()
            noise = view.read()
            dn = np.abs(noise[..., 1:4] - exact_noise[..., 1:4])[covered]
            dc = np.abs(_display(img) - _display(exact))[covered].max(axis=-1)
            rows.append({"method": "baked", "size": bs, "median_ms": t.median_ms,
                         "noise_mean": float(dn.mean()),
                         "noise_p99": float(np.percentile(dn, 99)),
                         "colour_mean": float(dc.mean()),
                         "colour_p99": float(np.percentile(dc, 99)),
                         "bake_s": bake.seconds, "bake_path": bake.path,
                         "bake_mb": bs**3 * 16 / 2**20})
            gpu.free(bake.texture)
        out["baked_vs_per_pixel"] = {"size": list(size), "rows": rows}

        # 3. hard against filtered ring edges, rings finer than pixels
        params.set_many({"materials.objects": "slice",
                         "wood.vol_tex_scale": (1.0, 1.0, 1.0, 70.0)})
        small, ss = 64, 8
        big = gpu.target("bench", "supersampled", (small * ss, small * ss))
        tiny = gpu.target("bench", "small", (small, small))
        frame_big = session.scene.frame((small * ss, small * ss))
        frame_small = session.scene.frame((small, small))
        params.set("materials.filter_rings", False)
        _render(session, eff, big, frame_big, view_proj=TOP_VIEW)()
        ref = _display(big.read()).reshape(small, ss, small, ss, 3).mean(axis=(1, 3))
        rings = {}
        for filtered in (False, True):
            params.set("materials.filter_rings", filtered)
            run = _render(session, eff, tiny, frame_small, view_proj=TOP_VIEW)
            t = time_call(gpu.ctx, "rings", run, warmup, repeat)
            run()
            err = np.abs(_display(tiny.read()) - ref).max(axis=-1)
            rings["filtered" if filtered else "hard"] = {
                "median_ms": t.median_ms, "mean_error": float(err.mean()),
                "p99_error": float(np.percentile(err, 99))}
        out["ring_edges"] = {"size": [small, small], "supersampling": ss, "vol_tex_scale_w": 70.0,
                             **rings}
        for tgt in (square, view, big, tiny):
            gpu.free(tgt)
        # 4. tessellation from the projected size against the fixed one
        for name in ("wood.vol_tex_scale", "materials.filter_rings", "materials.objects"):
            params.set(name, saved[name])
        out["tessellation"] = tessellation(session, sizes or TESSELLATION_SIZES, warmup,
                                           max(9, 2 * repeat))
    return out


def chart(report: dict, path, force: bool = False) -> None:
    """Time against error: baked sizes and per-pixel noise; octave cost; ring filtering."""
    plt = pyplot()

    sweep_ = report["sweep"]
    fig, axes = plt.subplots(1, 4, figsize=(20, 4.6))
    ax = axes[0]
    rows = sweep_["baked_vs_per_pixel"]["rows"]
    floor = 1e-5
    for key, style in (("noise_mean", "o-"), ("colour_mean", "s--")):
        xs = [r["median_ms"] for r in rows]
        ys = [max(r[key], floor) for r in rows]
        ax.plot(xs, ys, style[0], label=key.replace("_", " "))
        for r, x, y in zip(rows, xs, ys):
            ax.annotate("per pixel" if r["size"] is None else f"{r['size']}³", (x, y), fontsize=8,
                        textcoords="offset points", xytext=(4, 4))
    ax.set(yscale="log", xlabel="ms per frame",
           ylabel=f"error vs per-pixel noise (floor {floor:g})",
           title="wood noise: baked 3D texture vs per pixel")
    ax.legend(fontsize=8)
    ax = axes[1]
    oc = sweep_["octave_cost"]
    for kind, style in (("value", "o-"), ("gradient", "s-")):
        ax.plot(range(1, 9), oc[kind]["ms_by_depth"], style,
                label=f"{kind}: {oc[kind]['ms_per_octave']:.3f} ms/octave")
    ax.set(xlabel="octaves (RecDepth)", ylabel="ms per frame",
           title=f"noise cost, {oc['size'][0]}×{oc['size'][1]} cross-section")
    ax.legend(fontsize=8)
    ax = axes[2]
    re_ = sweep_["ring_edges"]
    for name, marker in (("hard", "o"), ("filtered", "s")):
        ax.plot([re_[name]["median_ms"]], [re_[name]["mean_error"]], marker, markersize=9,
                label=f"{name}: mean {re_[name]['mean_error']:.3f}, "
                      f"p99 {re_[name]['p99_error']:.3f}")
    ax.set(xlabel="ms per frame", ylabel="error vs 8×8 supersampling",
           title="ring edges: hard (thesis) vs box-filtered")
    ax.legend(fontsize=8)
    ax = axes[3]
    tess = sweep_.get("tessellation")
    if tess:
        rows = tess["rows"]
        x = np.arange(len(rows))
        med = [r["ratio"]["median"] for r in rows]
        err = [[r["ratio"]["median"] - r["ratio"]["p25"] for r in rows],
               [r["ratio"]["p75"] - r["ratio"]["median"] for r in rows]]
        ax.bar(x, med, 0.5, yerr=err, capsize=4, label="time auto / fixed (median, p25–p75)")
        for i, r in enumerate(rows):
            ax.annotate(f"{r['triangles_auto']} / {r['triangles_fixed']} tris\n"
                        f"{100 * r['changed_share']:.2f} % > {tess['threshold']:g}\n"
                        f"mean |Δ| {r['mean_abs_diff']:.4f}", (i, med[i]), fontsize=7,
                        ha="center", textcoords="offset points", xytext=(0, 12))
        ax.axhline(1.0, color="k", lw=0.8, ls=":")
        ax.set_xticks(x, [f"{r['size'][0]}×{r['size'][1]}" for r in rows])
        ax.set_ylim(0, max(1.3, max(med) * 1.5))
        ax.set(ylabel="time ratio, one interleaved run",
               title=f"tessellation: auto (edges ≈ {tess['edge_pixels']:g} px) vs fixed 48×96")
        ax.legend(fontsize=8, loc="lower right")
    write_chart(fig, path, force, title=f"natura bench materials — {report['renderer']}")


def summary(report: dict) -> str:
    s = report["sweep"]
    lines = []
    for kind in ("value", "gradient"):
        o = s["octave_cost"][kind]
        lines.append(f"{kind:9s} noise: {o['ms_per_octave']:.3f} ms per octave "
                     f"(base {o['ms_base']:.3f} ms)")
    for r in s["baked_vs_per_pixel"]["rows"]:
        label = "per pixel" if r["size"] is None else f"baked {r['size']}³"
        lines.append(f"{label:12s} {r['median_ms']:8.3f} ms   "
                     f"noise err mean {r['noise_mean']:.5f} p99 {r['noise_p99']:.5f}"
                     f"   colour err mean {r['colour_mean']:.4f} p99 {r['colour_p99']:.4f}")
    for name in ("hard", "filtered"):
        r = s["ring_edges"][name]
        lines.append(f"rings {name:8s} {r['median_ms']:8.3f} ms   "
                     f"error vs 8×8 supersampling mean {r['mean_error']:.4f}"
                     f" p99 {r['p99_error']:.4f}")
    tess = s.get("tessellation")
    if tess:
        lines.append(f"tessellation auto (edges ≈ {tess['edge_pixels']:g} px) / fixed 48×96, "
                     "one interleaved run per size:")
        for r in tess["rows"]:
            q = r["ratio"]
            lines.append(f"  {r['size'][0]}x{r['size'][1]}: time {ratio_text(q)}, triangles "
                         f"{r['triangles_auto']} / {r['triangles_fixed']}, pixels changing "
                         f"> {tess['threshold']:g}: {100 * r['changed_share']:.2f} %, "
                         f"mean |Δ| {r['mean_abs_diff']:.5f}")
    return "\n".join(lines)

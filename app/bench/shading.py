"""Speed against accuracy for the shading lab (spec/003 §2.3 parallax, §2.1/§2.12 lighting and
toon).

1. **Parallax** — the brick wall alone (``shading.object = wall``), the camera placed so the
   wall fills the view at a view elevation of 10°, 30° and 60° above its plane (the eye
   direction in tangent space is :func:`app.sim.parallax.view_at` of the angle and
   :data:`AZIMUTH`, the one :func:`~app.sim.parallax.parallax_error` measures at; the field of
   view is narrowed at grazing angles so every pixel sees the wall, so the angle varies little
   across the image: its range is reported). Per angle, one interleaved set
   (``app.gpu.timing.time_interleaved``) times the shading pass from a cleared target for off
   (mode 0), bare, steep and occlusion at n ∈ :data:`LAYERS` and the reference (mode 4, 1024
   layers and bisection); ``clear`` alone is timed in the same rounds. Bare reads no layer
   count: it is timed and measured once per angle (``layers`` None). Error against the
   reference is the numpy twin's (:func:`app.sim.parallax.parallax_error` on the same 256²
   brick height map and albedo, :func:`app.sim.surface_maps.bricks`): the UV offset error in
   texels (mean, p99) and the albedo's colour error (largest channel, mean and p99). Beside it
   the rendered image's error against the mode-4 render of the same view (display units,
   largest channel, over the wall's pixels). The thesis's claims are measured too: its 10–20
   layers advice (marked on the chart) and the "critical angle" — the albedo difference between
   n = 12 and n = 32 per angle (the thesis: almost invisible at 45°–90°, visible near 0°),
   with the share of points over 2/255.
2. **Lighting/toon cost** — every lighting model × toon mode × Gouraud on ``shading.object =
   all`` at the scene's own view, in one interleaved run, each with its per-round ratio to
   the default (Blinn–Phong, no toon, per fragment).
3. **Outlines** — ``None`` here: the outline IoU figures (IoU and gap count per contour method
   on the sphere and the table against their cost) are added by the outline module
   (app/effects/shading/outlines.py, app/sim/outline_metrics.py) when it is present.

Sizes: the sweep renders at most :data:`SWEEP_SIZE` pixels (the bench's ``--size`` scaled
down, aspect kept), or at each of ``sizes`` (``--sizes``); the chart and the summary show the
first. On llvmpipe absolute times mean little; ratios within one interleaved set hold.
"""

from __future__ import annotations

import math

import numpy as np

from ..colour import linear_to_srgb
from ..gpu.timing import time_interleaved
from ..sim import lab_meshes, surface_maps
from ..sim.camera import Camera
from ..sim.parallax import error_grid, parallax_error, parallax_uv, view_at
from . import pyplot, surfaces_speed, write_chart
from .shading_outlines import outline_sweep
from .shading_outlines import summary_lines as outline_summary

ANGLES = (10.0, 30.0, 60.0)
LAYERS = (4, 8, 12, 16, 32, 64)
METHODS = ("bare", "steep", "occlusion")
MODES = {"off": 0, "bare": 1, "steep": 2, "occlusion": 3, "reference": 4}
#: the azimuth of the eye from +u toward +v in tangent space (parallax_error's default)
AZIMUTH = 30.0
#: the thesis's advice: "generally adequate to keep n between 10 and 20" (spec/003 §2.3)
ADVICE = (10, 20)
#: the thesis's critical-angle comparison: n = 12 against n = 32
CRITICAL_PAIR = (12, 32)
#: a visible difference (one display step of 8 bits, twice)
VISIBLE = 2.0 / 255.0
#: the largest render the sweep uses (pixels of 320 × 180)
SWEEP_SIZE = (320, 180)
#: seconds of timed rounds per interleaved set after which no round starts (at least 3 run)
SET_BUDGET_S = 6.0
#: the speed section's timed rounds stop past this many seconds (at least two run)
SPEED_BUDGET_S = 20.0
LIGHTING_MODELS = ("Lambert", "Phong", "Blinn-Phong")
TOON_MODES = ("none", "flat", "stepped", "ramp")
#: the wall's front face (app.sim.lab_meshes.brick_wall): z = thickness/2, x in ±width/2,
#: y in [0, height], u along +x and v along +y (tangent frame = world axes)
_WALL = lab_meshes.WALL
WALL_Z = _WALL["thickness"] / 2
WALL_CENTRE = np.array([0.0, _WALL["height"] / 2, WALL_Z])
#: the view's corners lie at most this share of the view angle, and at most FIELD_MAX_DEG, from
#: its centre: the angle then varies little across the image (nearly orthographic)
FIELD_SHARE = 0.3
FIELD_MAX_DEG = 5.0
#: keep the view this far (m) inside the wall's edges
WALL_MARGIN = 0.03


def render_size(size) -> tuple[int, int]:
    """``size`` if it has no more pixels than :data:`SWEEP_SIZE`, else scaled down to that many
    (aspect kept)."""
    w, h = int(size[0]), int(size[1])
    most = SWEEP_SIZE[0] * SWEEP_SIZE[1]
    if w * h <= most:
        return w, h
    s = math.sqrt(most / (w * h))
    return max(16, round(w * s)), max(16, round(h * s))


def _wall_hits(camera: Camera, aspect: float, grid=(33, 19)) -> tuple[bool, np.ndarray]:
    """Whether every ray of a coarse grid over the view meets the wall's front inside its
    margin, and the view elevations (degrees above the wall's plane) of those rays."""
    d = camera.ray_directions(int(grid[0]), int(grid[1]))
    d = d.reshape(-1, 3)
    eye = np.asarray(camera.position)
    dz = d[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (WALL_Z - eye[2]) / dz
    p = eye + t[:, None] * d
    hw = _WALL["width"] / 2 - WALL_MARGIN
    ok = ((dz < 0) & (t > 0) & (np.abs(p[:, 0]) <= hw) & (p[:, 1] >= WALL_MARGIN)
          & (p[:, 1] <= _WALL["height"] - WALL_MARGIN))
    elevation = np.degrees(np.arcsin(np.clip(-dz, -1.0, 1.0)))
    return bool(ok.all()), elevation


def wall_camera(angle_deg: float, aspect: float, azimuth_deg: float = AZIMUTH) -> Camera:
    """A camera looking at the wall's centre from ``angle_deg`` above its plane (the tangent-
    space eye direction :func:`view_at`), as far away as it can be with the wall filling the
    view. The field of view keeps the view's corners within :data:`FIELD_SHARE` of the angle
    (and :data:`FIELD_MAX_DEG`) from the view's centre: every ray meets the wall's plane, at
    nearly the same angle."""
    w = view_at(angle_deg, azimuth_deg)  # tangent (u, v, n) = world (x, y, z) on the front
    half_diag = math.radians(min(FIELD_SHARE * angle_deg, FIELD_MAX_DEG))
    fov = 2.0 * math.degrees(math.atan(math.tan(half_diag) / math.hypot(1.0, aspect)))
    fov = float(min(45.0, max(1.0, fov)))
    cam = Camera(position=tuple(WALL_CENTRE + w), fov=fov)
    cam.look_at_direction(-w)
    lo, hi = 0.02, 20.0
    for _ in range(40):  # the largest distance at which the wall still fills the view
        mid = math.sqrt(lo * hi)
        cam.set(position=tuple(WALL_CENTRE + mid * w))
        if _wall_hits(cam, aspect)[0]:
            lo = mid
        else:
            hi = mid
    cam.set(position=tuple(WALL_CENTRE + lo * w))
    cam.near = min(0.1, 0.25 * lo)
    return cam


def _display(img: np.ndarray) -> np.ndarray:
    return linear_to_srgb(np.clip(img[..., :3].astype(np.float64), 0.0, None))


def _image_error(img: np.ndarray, ref: np.ndarray, mask: np.ndarray) -> tuple[float, float]:
    d = np.abs(_display(img) - _display(ref)).max(axis=-1)[mask]
    if d.size == 0:
        return float("nan"), float("nan")
    return float(d.mean()), float(np.percentile(d, 99))


def critical_angle(height, albedo, angles=ANGLES, pair=CRITICAL_PAIR, scale: float = 0.05,
                   grid: int = 64) -> list[dict]:
    """The thesis's critical-angle claim: per angle and method (steep, occlusion), the albedo
    difference (largest channel) between n = pair[0] and n = pair[1] over
    :func:`error_grid`, its mean, p99 and the share of points over :data:`VISIBLE`."""
    uv = error_grid(grid)
    rows = []
    for angle in angles:
        v = view_at(angle, AZIMUTH)
        for method in ("steep", "occlusion"):
            a = parallax_uv(height, uv, v, method, pair[0], scale)
            b = parallax_uv(height, uv, v, method, pair[1], scale)
            d = np.abs(surface_maps.sample_bilinear(albedo, a)
                       - surface_maps.sample_bilinear(albedo, b)).max(axis=-1)
            rows.append({"angle": float(angle), "method": method, "layers": list(pair),
                         "mean_colour": float(d.mean()),
                         "p99_colour": float(np.percentile(d, 99)),
                         "share_visible": float((d > VISIBLE).mean())})
    return rows


def _pass(session, target, frame, sets: dict):
    params = session.params
    eff = session.scene.effect("shading")

    def run():
        params.set_many(sets)
        target.clear()
        eff.draw(frame, target)

    return run


def parallax_sweep(session, size, warmup: int, repeat: int, angles=ANGLES,
                   layers=LAYERS) -> dict:
    """Item 1 of the module's docstring at one render size."""
    params = session.params
    gpu = session.gpu
    scene = session.scene
    scale = float(params["shading.parallax_scale"])
    bricks = surface_maps.bricks(256)
    height, albedo = bricks.height.astype(np.float64), bricks.albedo.astype(np.float64)
    size = tuple(int(v) for v in size)
    aspect = size[0] / size[1]
    saved_camera = scene.camera
    params.set_many({"shading.object": "wall", "shading.turntable": 0.0, "shading.maps": True})
    target = gpu.target("bench", "shading parallax", size)
    rows: list[dict] = []
    views: list[dict] = []
    try:
        for angle in angles:
            cam = wall_camera(angle, aspect)
            scene.camera = cam
            frame = scene.frame(size)
            frame.camera = cam
            _, elevation = _wall_hits(cam, aspect)
            variants = {"clear": target.clear}
            entries: dict[str, dict] = {}
            for mode in ("off", "reference", "bare"):
                entries[mode] = {"method": mode, "layers": None,
                                 "sets": {"shading.parallax_mode": MODES[mode]}}
            for method in ("steep", "occlusion"):
                for n in layers:
                    entries[f"{method} {n}"] = {"method": method, "layers": int(n), "sets": {
                        "shading.parallax_mode": MODES[method],
                        "shading.parallax_layers": int(n)}}
            images = {}
            for key, e in entries.items():
                run = _pass(session, target, frame, e["sets"])
                variants[key] = run
                run()
                images[key] = target.read()
            mask = target.read_depth() < 1.0
            # the run for its image above is each variant's first untimed run
            timed = time_interleaved(gpu.ctx, variants, max(0, warmup - 1), repeat,
                                     budget_s=SET_BUDGET_S, min_rounds=min(3, max(1, repeat)))
            ref_img = images["reference"]
            for key, e in entries.items():
                p25, med, p75 = timed.quartiles(key)
                row: dict = {"angle": float(angle), "method": e["method"], "layers": e["layers"],
                             "median_ms": med, "p25_ms": p25, "p75_ms": p75,
                             "ratio_to_reference": timed.ratio(key, "reference")["median"],
                             "ratio_to_off": timed.ratio(key, "off")["median"]}
                if e["method"] == "reference":
                    err = {"mean_px": 0.0, "p99_px": 0.0, "mean_colour": 0.0, "p99_colour": 0.0}
                else:
                    err = parallax_error(e["method"], e["layers"] or 12, angle, height,
                                         scale=scale, azimuth_deg=AZIMUTH, albedo=albedo)
                row.update(err)
                row["image_mean"], row["image_p99"] = _image_error(images[key], ref_img, mask)
                rows.append(row)
            views.append({"angle": float(angle), "fov": cam.fov,
                          "distance": float(np.linalg.norm(np.asarray(cam.position)
                                                           - WALL_CENTRE)),
                          "elevation_min": float(elevation.min()),
                          "elevation_max": float(elevation.max()),
                          "covered_share": float(mask.mean()), "rounds": timed.rounds,
                          "clear_ms": timed.quartiles("clear")[1]})
    finally:
        scene.camera = saved_camera
        gpu.free(target)
    return {"size": list(size), "scale": scale, "azimuth": AZIMUTH, "map": "bricks 256²",
            "views": views, "rows": rows}


def lighting_sweep(session, size, warmup: int, repeat: int) -> dict:
    """Item 2 of the module's docstring: one interleaved run of every lighting model × toon
    mode × Gouraud on all the objects."""
    params = session.params
    gpu = session.gpu
    size = tuple(int(v) for v in size)
    params.set_many({"shading.object": "all", "shading.turntable": 0.0})
    with gpu.scratch_target("bench", "shading lighting", size) as target:
        variants, keys = {}, {}
        frame = session.scene.frame(size)
        for lm, lm_name in enumerate(LIGHTING_MODELS):
            for toon, toon_name in enumerate(TOON_MODES):
                for gouraud in (False, True):
                    key = f"{lm_name}/{toon_name}/{'vertex' if gouraud else 'fragment'}"
                    keys[key] = (lm_name, toon_name, gouraud)
                    variants[key] = _pass(session, target, frame, {
                        "shading.lighting_model": lm, "shading.toon": toon,
                        "shading.gouraud": gouraud})
        timed = time_interleaved(gpu.ctx, variants, warmup, repeat, budget_s=SET_BUDGET_S,
                                 min_rounds=min(3, max(1, repeat)))
    base = "Blinn-Phong/none/fragment"
    rows = []
    for key, (lm_name, toon_name, gouraud) in keys.items():
        p25, med, p75 = timed.quartiles(key)
        r = timed.ratio(key, base)
        rows.append({"lighting_model": lm_name, "toon": toon_name, "gouraud": gouraud,
                     "median_ms": med, "p25_ms": p25, "p75_ms": p75,
                     "ratio_to_default": r["median"], "ratio_p25": r["p25"],
                     "ratio_p75": r["p75"]})
    return {"size": list(size), "rounds": timed.rounds, "baseline": base, "rows": rows}


def sweep(session, size, warmup: int = 1, repeat: int = 3, sizes=None, angles=ANGLES,
          layers=LAYERS, lighting: bool = True, outlines: bool = True) -> dict:
    """The shading lab's sweeps (the module's docstring): ``parallax`` (one entry per render
    size), ``critical_angle``, ``lighting`` and ``outlines``."""
    params = session.params
    render_sizes = [render_size(s) for s in (sizes or [size])]
    out: dict = {"render_sizes": [list(s) for s in render_sizes], "angles": list(angles),
                 "layers": list(layers), "advice": list(ADVICE)}
    with params.kept() as saved:
        out["parallax"] = [parallax_sweep(session, s, warmup, repeat, angles, layers)
                           for s in render_sizes]
        params.set_many(saved)
        bricks = surface_maps.bricks(256)
        out["critical_angle"] = critical_angle(bricks.height.astype(np.float64),
                                               bricks.albedo.astype(np.float64), angles,
                                               scale=float(params["shading.parallax_scale"]))
        out["lighting"] = (lighting_sweep(session, render_sizes[0], warmup, repeat)
                           if lighting else None)
        # IoU and gaps per contour method on the sphere and the table, against their cost
        out["outlines"] = (outline_sweep(session.gpu, warmup=warmup, rounds=max(3, repeat))
                           if outlines else None)
        # the default frame against the full shadow taps (app/bench/surfaces_speed.py)
        out["speed"] = surfaces_speed.run(session, size, surfaces_speed.SHADING,
                                          surfaces_speed.SHADING_PASSES, warmup=warmup,
                                          rounds=max(3, repeat), budget_s=SPEED_BUDGET_S)
    return out


def _rows(report: dict, angle: float, method: str) -> list[dict]:
    rows = report["sweep"]["parallax"][0]["rows"]
    return sorted((r for r in rows if r["angle"] == angle and r["method"] == method),
                  key=lambda r: r["layers"] or 0)


def chart(report: dict, path, force: bool = False) -> None:
    """Per angle: error against ms (top) and against n with the thesis's 10–20 band (bottom);
    the last column: the lighting/toon cost and the critical-angle difference."""
    plt = pyplot()

    s = report["sweep"]
    par = s["parallax"][0]
    angles = [v["angle"] for v in par["views"]]
    floor = 1e-4
    outlines = s.get("outlines")
    nrows = 3 if outlines else 2
    fig, axes = plt.subplots(nrows, len(angles) + 1, figsize=(5.2 * (len(angles) + 1),
                                                              4.5 * nrows), squeeze=False)
    colours = {"bare": "tab:red", "steep": "tab:blue", "occlusion": "tab:green"}
    lo, hi = ADVICE
    for col, angle in enumerate(angles):
        top, bottom = axes[0, col], axes[1, col]
        for method in METHODS:
            rs = _rows(report, angle, method)
            if not rs:
                continue
            xs = [r["median_ms"] for r in rs]
            ys = [max(r["mean_px"], floor) for r in rs]
            c = colours[method]
            if method == "bare":
                top.plot(xs, ys, "*", color=c, markersize=12, label="bare (no layers)")
                bottom.axhline(ys[0], color=c, ls="--", label="bare (no layers)")
                continue
            top.plot(xs, ys, "o-", color=c, label=method)
            band = [i for i, r in enumerate(rs) if lo <= r["layers"] <= hi]
            top.plot([xs[i] for i in band], [ys[i] for i in band], "o", color=c,
                     markersize=11, markerfacecolor="none", markeredgewidth=2)
            for r, x, y in zip(rs, xs, ys):
                top.annotate(f"{r['layers']}", (x, y), fontsize=7, textcoords="offset points",
                             xytext=(4, 3))
            ns = [r["layers"] for r in rs]
            bottom.plot(ns, ys, "o-", color=c, label=f"{method} mean")
            bottom.plot(ns, [max(r["p99_px"], floor) for r in rs], "s:", color=c,
                        label=f"{method} p99")
        (off,) = _rows(report, angle, "off")
        (ref,) = _rows(report, angle, "reference")
        top.plot([off["median_ms"]], [max(off["mean_px"], floor)], "kx", markersize=9,
                 label=f"off ({off['median_ms']:.2f} ms)")
        top.set(yscale="log", xlabel="ms, shading pass (interleaved)",
                ylabel=f"mean UV error vs reference [texels] (floor {floor:g})")
        view = par["views"][col]
        top.set_title(f"{angle:g}° view (field {view['elevation_min']:.1f}–"
                      f"{view['elevation_max']:.1f}°); ringed: n in {lo}–{hi}\n"
                      f"reference (error 0): {ref['median_ms']:.2f} ms", fontsize=9)
        top.legend(fontsize=7)
        bottom.axvspan(lo, hi, color="gold", alpha=0.3, label=f"thesis: n {lo}–{hi}")
        bottom.set_xscale("log", base=2)
        bottom.set(yscale="log", xlabel="layers n", ylabel="UV error vs reference [texels]")
        bottom.set_title(f"{angle:g}°: error against n", fontsize=9)
        bottom.legend(fontsize=7)
    ax = axes[0, -1]
    light = s.get("lighting")
    if light:
        rows = light["rows"]
        x = np.arange(len(rows))
        ax.bar(x, [r["ratio_to_default"] for r in rows],
               color=["tab:orange" if r["gouraud"] else "tab:purple" for r in rows])
        ax.set_xticks(x, [f"{r['lighting_model'][:5]} {r['toon']}" for r in rows],
                      rotation=90, fontsize=6)
        ax.axhline(1.0, color="k", lw=0.8, ls=":")
        ax.set_ylabel("time / Blinn-Phong per fragment (median per round)")
        ax.set_title("lighting × toon; orange: Gouraud", fontsize=9)
    ax = axes[1, -1]
    crit = s.get("critical_angle") or []
    for method, c in (("steep", "tab:blue"), ("occlusion", "tab:green")):
        rs = [r for r in crit if r["method"] == method]
        ax.plot([r["angle"] for r in rs], [max(r["mean_colour"], floor) for r in rs], "o-",
                color=c, label=f"{method} mean")
        ax.plot([r["angle"] for r in rs], [max(r["p99_colour"], floor) for r in rs], "s:",
                color=c, label=f"{method} p99")
    ax.axhline(VISIBLE, color="k", ls="--", lw=0.8, label="2/255")
    ax.set(yscale="log", xlabel="view angle above the wall [°]",
           ylabel=f"albedo |Δ|, n = {CRITICAL_PAIR[0]} vs {CRITICAL_PAIR[1]}")
    ax.set_title("the critical angle (spec/003 §2.3)", fontsize=9)
    ax.legend(fontsize=7)
    if outlines:
        for k, obj in enumerate(("sphere", "table")):
            ax = axes[2, k]
            rs = [r for r in outlines["rows"] if r["object"] == obj]
            for r in rs:
                ax.scatter(r["contour_ms"], r["iou"], s=30)
                ax.annotate(f"{r['method']} ({r['gaps']} gaps)", (r["contour_ms"], r["iou"]),
                            fontsize=7, xytext=(3, 3), textcoords="offset points")
            ax.set(xlabel="contour pass [ms]", ylabel="IoU against the analytic silhouette band")
            ax.set_ylim(0.0, 1.05)
            ax.set_title(f"outlines on the {obj} (spec/003 §2.13)", fontsize=9)
        for k in range(2, len(angles) + 1):
            axes[2, k].axis("off")
    size = par["size"]
    write_chart(fig, path, force,
                title=f"natura bench shading — parallax on the brick wall at {size[0]}×{size[1]}, "
                      f"{report.get('renderer', '')}")


def summary(report: dict) -> str:
    s = report["sweep"]
    lines = []
    for par in s["parallax"]:
        size = par["size"]
        lines.append(f"parallax on the brick wall at {size[0]}x{size[1]} (scale "
                     f"{par['scale']:g}): ms of the shading pass, UV error vs the reference "
                     "[texels] mean/p99, albedo error mean, render error mean")
        for view in par["views"]:
            a = view["angle"]
            lines.append(f"  {a:g}° (field {view['elevation_min']:.1f}–"
                         f"{view['elevation_max']:.1f}°, {view['rounds']} rounds, wall "
                         f"{100 * view['covered_share']:.0f} % of the view)")
            for r in sorted((r for r in par["rows"] if r["angle"] == a),
                            key=lambda r: (list(MODES).index(r["method"]), r["layers"] or 0)):
                label = r["method"] + (f" {r['layers']}" if r["layers"] else "")
                lines.append(f"    {label:13s} {r['median_ms']:8.3f} ms  "
                             f"uv {r['mean_px']:7.3f}/{r['p99_px']:7.3f}  "
                             f"albedo {r['mean_colour']:.4f}  render {r['image_mean']:.4f}")
    for r in s.get("critical_angle") or []:
        lines.append(f"critical angle {r['angle']:4g}° {r['method']:9s} n {r['layers'][0]} vs "
                     f"{r['layers'][1]}: albedo |Δ| mean {r['mean_colour']:.4f} p99 "
                     f"{r['p99_colour']:.4f}, {100 * r['share_visible']:.1f} % over 2/255")
    light = s.get("lighting")
    if light:
        lines.append(f"lighting × toon × Gouraud on all objects at {light['size'][0]}x"
                     f"{light['size'][1]} ({light['rounds']} rounds; ratio to "
                     f"{light['baseline']}):")
        for r in light["rows"]:
            lines.append(f"  {r['lighting_model']:11s} {r['toon']:8s} "
                         f"{'vertex  ' if r['gouraud'] else 'fragment'} {r['median_ms']:8.3f} ms"
                         f"  ×{r['ratio_to_default']:.2f}")
    if s.get("outlines"):
        lines.extend(outline_summary(s["outlines"]))
    if s.get("speed"):
        lines.extend(surfaces_speed.summary(s["speed"], "the lab's frame, shadow taps"))
    return "\n".join(lines)

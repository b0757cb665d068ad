"""Speed and accuracy of the four atmosphere methods: ms per frame and error against a reference.
docs/commands.md (``natura bench planet``) and docs/theory/002-atmosphere.md describe the report.

* **The thesis's table** (spec/002 §5, :func:`thesis_table`): methods 1–4 × sizes × a ground and
  a space view, ms per frame (median, ``ctx.finish()`` around each frame, static sun so the
  shadow map is not redrawn) and ratios to method 1 in the same cell.
* **Accuracy** (:func:`accuracy`): each method's in-scattered radiance ("in-scattering on
  black") and transmittance ("out-scattering on white") against
  :func:`app.sim.atmosphere.reference` on a small ground view, as its quality knob changes
  (method 3's shadow-map size against the same method with an 8192² map: the reference has no
  shadows; Hillaire's error includes multiple scattering on purpose).
* **Changes** (:func:`changes`): each change to the fixed per-pixel work against its earlier
  path (``planet.shadow_compare``, ``planet.ground_noise``, ``planet.ground_pass``,
  ``planet.march_scale``), timed in one interleaved run (``app.gpu.timing.time_interleaved``:
  per-round ratios, median [p25–p75], robust to the machine's load) beside the image
  difference it makes.
* **Multiple scattering** (:func:`multiple_scattering`, numpy only, ``FILE-multiple.png``):
  Hillaire's sky against the multi-order reference of :mod:`app.sim.multiple_scattering`, with
  the reference's own figures and Hillaire's LUT variants side by side.
* The table and the accuracy sweep grade the thesis's per-pixel march (:data:`PER_PIXEL`); the
  reduced march is graded against it in "changes".
"""

from __future__ import annotations

import numpy as np

from ..gpu.timing import time_call, time_interleaved
from ..sim import atmosphere as atm
from ..teach.sweeps import HILLAIRE_SIZES  # noqa: F401 - defined there, read by the picker
from ..teach.sweeps import scale_hillaire as _scale_hillaire
from . import at_most, pyplot, write_chart

DEFAULT_SIZES = ((800, 600), (1280, 720), (1920, 1080))
#: the charts: the thesis's table and the accuracy sweep, then multiple scattering
CHART_SUFFIXES = (".png", "-multiple.png")
#: Hillaire's multiple-scattering LUT variants the multiple-scattering section grades:
#: name → keyword arguments of :func:`app.sim.multiple_scattering.hillaire_ms_lut`
MS_VARIANTS: dict[str, dict] = {
    "paper (32², 64 directions)": {"size": 32, "directions": 8},
    "64², 256 directions": {"size": 64, "directions": 16},
    "32², true first-event phase": {"size": 32, "directions": 8, "first_phase": "full"},
}
VIEWS = {
    "ground": {"position": (0.0, 2.0, 60.0), "yaw": 0.0, "pitch": 4.0, "fov": 60.0},
    "space": {"position": (0.0, 300000.0, 60.0), "yaw": 0.0, "pitch": -30.0, "fov": 60.0},
}
TABLE_METHODS = ("brute_force", "lut", "shadowed", "hillaire")
#: the thesis's per-pixel march, which the table and the accuracy sweep measure
PER_PIXEL = {"planet.march_scale": "full"}
#: a low sun behind the mountains, seen past them: light shafts toward the camera
SHAFT_VIEW = {"position": (0.0, 2.0, 60.0), "yaw": 0.0, "pitch": 4.0, "fov": 60.0}
SHAFT_SUN = {"planet.sun_elevation": 10.0, "planet.sun_azimuth": 0.0}


def _set_view(session, view: str) -> None:
    v = VIEWS[view]
    session.scene.camera.set(position=v["position"], yaw=v["yaw"], pitch=v["pitch"], fov=v["fov"])


def _frame_ms(session, size, warmup, repeat, scattering_only: bool = False,
              both: bool = False):
    """Median ms of a whole frame, or of the scattering pass alone (the part the methods change);
    with ``both``, (frame ms, scattering ms), each timed as it would be alone, after one build.
    The first of the ``warmup`` untimed runs is a whole frame, which builds what the knob just
    changed (at least that one runs: the LUTs, the shadow map and the G-buffer at this size)."""
    gpu = session.gpu
    eff = session.scene.effect("planet")
    with gpu.scratch_target("bench", "planet frame", size) as target:
        frame = session.scene.frame(size)
        session.scene.render(frame, target)  # builds LUTs, shadow map, G-buffer at this size
        runs = {"frame": lambda: session.scene.render(frame, target),
                "scattering": lambda: eff.render_composite(frame, target)}
        parts = ("frame", "scattering") if both else \
            ("scattering",) if scattering_only else ("frame",)
        ms = [time_call(gpu.ctx, part, runs[part], _warmup_after_build(warmup),
                        repeat).median_ms for part in parts]
        return tuple(ms) if both else ms[0]


def thesis_table(session, sizes=DEFAULT_SIZES, warmup: int = 2, repeat: int = 5,
                 methods=TABLE_METHODS) -> dict:
    p = session.params
    rows = []
    for view in VIEWS:
        _set_view(session, view)
        for size in sizes:
            cell, scatter = {}, {}
            for method in methods:
                p.set("planet.method", method)
                # one build for both (the same method, view and size)
                cell[method], scatter[method] = _frame_ms(session, tuple(size), warmup, repeat,
                                                          both=True)
            base, base_s = cell["brute_force"], scatter["brute_force"]
            for method in methods:
                rows.append({"view": view, "size": list(size), "method": method, "ms": cell[method],
                             "fps": 1000.0 / cell[method],
                             "ratio_fps_to_method_1": base / cell[method],
                             "scattering_ms": scatter[method],
                             "scattering_ratio_to_method_1": base_s / scatter[method]})
    return {"rows": rows, "n_steps": p["planet.n_steps"]}


def _render_debug(session, size) -> tuple[np.ndarray, np.ndarray]:
    """(in-scatter image, transmittance image) of the current view (the callers' ground view),
    each (h, w, 3) linear, row 0 at the top."""
    p = session.params
    gpu = session.gpu
    target = gpu.target("bench", "planet debug", size)
    out = []
    try:
        for dv in ("in_scatter", "out_scatter"):
            p.set("planet.debug_view", dv)
            frame = session.scene.frame(size)
            session.scene.render(frame, target)
            out.append(target.read()[..., :3].astype(np.float64))
    finally:
        gpu.free(target)
        p.set("planet.debug_view", "final")
    return out[0], out[1]


def reference_for_view(session, size, steps: int = 2048) -> dict:
    """The numpy reference for every pixel of ``size`` (keep it small: ~1 s per 100 rays at
    4096 steps), using the G-buffer for mesh distances."""
    eff = session.scene.effect("planet")
    model = eff.model()
    _render_debug(session, size)  # fills the G-buffer at this size
    colour, position, _, _ = eff._gbuffer_for(size)
    w, h = size
    pos = np.frombuffer(position.read(), dtype=np.float32).reshape(h, w, 4)[::-1].astype(np.float64)
    cam = session.scene.camera
    dirs = cam.ray_directions(w, h)
    covered = pos[..., 3] > 0.5
    dist = np.linalg.norm(pos[..., :3], axis=-1)
    dirs = np.where(covered[..., None], pos[..., :3] / np.maximum(dist, 1e-9)[..., None], dirs)
    max_dist = np.where(covered, dist, np.inf).reshape(-1)
    cam_planet = atm.local_to_planet(cam.position, model)
    ref = atm.reference(cam_planet, dirs.reshape(-1, 3), eff.sun_dir, model, max_dist=max_dist,
                        steps=steps)
    return {"in_scatter": ref.in_scatter.reshape(h, w, 3),
            "transmittance": ref.transmittance.reshape(h, w, 3)}


def _errors(got_in, got_t, ref) -> dict:
    d_in = np.abs(got_in - ref["in_scatter"]).max(axis=-1)
    d_t = np.abs(got_t - ref["transmittance"]).max(axis=-1)
    return {"in_mean": float(d_in.mean()), "in_p99": float(np.percentile(d_in, 99)),
            "t_mean": float(d_t.mean()), "t_p99": float(np.percentile(d_t, 99))}


#: the knobs of method 1 that make its figure (spec/002 §2.3): reset to their defaults for
#: the ``method_1_defaults`` field of the accuracy report
METHOD_1_KNOBS = ("planet.n_steps", "planet.inner_steps", "planet.pc_rule",
                  "planet.universe_radius", "planet.universe_centre")


def method_1_at_defaults(session, size, ref) -> dict:
    """Method 1 (brute force) with its knobs at their defaults against the reference ``ref`` of
    the ground view (:func:`reference_for_view`): the absolute errors of :func:`_errors` and the
    in-scattering's relative mean error ``in_rel_mean`` = mean |Δ| / mean reference (per pixel,
    the largest channel). Leaves the method and those knobs as it found them."""
    p = session.params
    with p.kept(("planet.method",) + METHOD_1_KNOBS):
        p.set_many({k: p.spec(k).default for k in METHOD_1_KNOBS})
        p.set("planet.method", "brute_force")
        rule = session.scene.effect("planet").pc_rule()
        got_in, got_t = _render_debug(session, size)
    errs = _errors(got_in, got_t, ref)
    ref_mean = float(ref["in_scatter"].max(axis=-1).mean())
    return {**errs, "in_rel_mean": errs["in_mean"] / max(ref_mean, 1e-30),
            **{k.split(".", 1)[1]: p.spec(k).default for k in METHOD_1_KNOBS},
            "pc_rule_used": rule}


def accuracy(session, size=(64, 36), time_size=(320, 180), warmup: int = 1, repeat: int = 3,
             steps_list=(5, 10, 20, 30, 60, 120), lut_sizes=(16, 32, 64, 128, 256),
             shadow_sizes=(256, 512, 1024, 2048), hillaire_scales=(0.5, 1.0), ref_steps: int = 2048,
             hillaire: bool = True, ozone: bool = True) -> dict:
    p = session.params
    _set_view(session, "ground")
    p.set_many({"planet.sun_disk": False, "planet.star_intensity": 0.0})
    ref = reference_for_view(session, size, ref_steps)
    method_1 = method_1_at_defaults(session, size, ref)
    rows = []

    def measure(method, knob, value, extra_ref=None):
        p.set("planet.method", method)
        got_in, got_t = _render_debug(session, size)
        errs = _errors(got_in, got_t, extra_ref or ref)
        ms = _frame_ms(session, time_size, warmup, repeat)
        rows.append({"method": method, "knob": knob, "value": value, "ms": ms, **errs})

    with p.kept(("planet.n_steps", "planet.inner_steps", "planet.lut_height", "planet.lut_angle",
                 "planet.shadow_map_size", "planet.pc_rule", "atmosphere.ozone")) as saved:
        for n in steps_list:
            p.set_many({"planet.n_steps": n, "planet.inner_steps": n})
            measure("brute_force", "n_steps", n)
            measure("lut", "n_steps", n)
            measure("shadowed", "n_steps", n)
        p.set("planet.pc_rule", "thesis")  # the thesis's τ(PC) rule, for comparison
        for n in steps_list:
            p.set("planet.n_steps", n)
            measure("lut", "n_steps, thesis τ(PC) rule", n)
        p.set_many({k: saved[k] for k in ("planet.pc_rule", "planet.n_steps",
                                          "planet.inner_steps")})
        for size_ in lut_sizes:
            p.set_many({"planet.lut_height": size_, "planet.lut_angle": size_})
            measure("lut", "lut_size", size_)
        p.set_many({k: saved[k] for k in ("planet.lut_height", "planet.lut_angle")})
        # the shadow-map knob against the same method with a very large map
        p.set_many({"planet.method": "shadowed", "planet.shadow_map_size": 8192})
        best_in, best_t = _render_debug(session, size)
        best = {"in_scatter": best_in, "transmittance": best_t}
        for s in shadow_sizes:
            p.set("planet.shadow_map_size", s)
            measure("shadowed", "shadow_map_size (vs 8192²)", s, best)
        p.set("planet.shadow_map_size", saved["planet.shadow_map_size"])
        if hillaire:
            for scale in hillaire_scales:
                _scale_hillaire(p, scale)
                measure("hillaire", "lut scale", scale)
            _scale_hillaire(p, 1.0)
            # single scattering only: the reference's physics
            p.set("hillaire.multiple_scattering", False)
            measure("hillaire", "single scattering only", 1.0)
            p.set("hillaire.multiple_scattering", True)
        if ozone:
            # every method at its defaults with the standard ozone layer, against the reference
            # with the same layer (beyond the thesis: spec/002 §10)
            p.set("atmosphere.ozone", 1.0)
            ref_ozone = reference_for_view(session, size, ref_steps)
            for method in ("brute_force", "lut", "shadowed") + (("hillaire",) if hillaire else ()):
                measure(method, "ozone layer on", 1.0, ref_ozone)
            p.set("atmosphere.ozone", saved["atmosphere.ozone"])
    return {"size": list(size), "time_size": list(time_size), "reference_steps": ref_steps,
            "rows": rows, "method_1_defaults": method_1}


def _final_image(session, size, view: str) -> np.ndarray:
    """The final linear image (h, w, 3) of ``view`` at ``size``."""
    _set_view(session, view)
    return _final_image_at(session, size)


def _diff(before: np.ndarray, after: np.ndarray) -> dict:
    d = np.abs(after - before)
    rel = d / np.maximum(np.abs(before), 1e-6)
    return {"mean_abs": float(d.mean()), "max_abs": float(d.max()), "max_rel": float(rel.max())}


def _variants(session, size, settings: dict, scattering_only: bool = False) -> tuple:
    """({name: run}, cleanup): each run sets its parameters and renders one frame (or the
    scattering pass alone) of the current view at ``size``. Each variant renders one whole
    frame here, untimed: the first of its warm-up runs (:func:`_warmup_after_build`)."""
    gpu = session.gpu
    eff = session.scene.effect("planet")
    p = session.params
    target = gpu.target("bench", "planet changes", size)
    runs = {}
    for name, sets in settings.items():
        p.set_many(sets)
        frame = session.scene.frame(size)
        session.scene.render(frame, target)  # programs, bakes and the G-buffer at this size

        def run(sets=sets, frame=frame):
            p.set_many(sets)
            if scattering_only:
                eff.render_composite(frame, target)
            else:
                session.scene.render(frame, target)
        runs[name] = run
    return runs, (lambda: gpu.free(target))


def _warmup_after_build(warmup: int) -> int:
    """The warm-up runs left to do after the untimed frame that built a variant (it is the
    first of ``warmup``)."""
    return max(0, warmup - 1)


def _ratio(timed, a: str, b: str) -> dict:
    """Per-round ratio time(a) / time(b): median, p25, p75."""
    return timed.ratio(a, b)


def changes(session, size=(320, 180), warmup: int = 1, rounds: int = 7) -> dict:
    """Before/after of each change to the fixed per-pixel work, interleaved, with its error."""
    p = session.params
    keys = ("planet.method", "planet.shadow_compare", "planet.ground_noise", "planet.ground_pass",
            "planet.n_steps", "planet.inner_steps")
    out: dict = {"size": list(size), "rounds": rounds, "n_steps": 30}
    with p.kept(keys):
        p.set_many({"planet.n_steps": 30, "planet.inner_steps": 30})
        # 1. hardware depth compares (method 3: the filter on every Phong surface and ground
        #    pixel, and one comparison per integral sample)
        shadow = {c: {"planet.method": "shadowed", "planet.shadow_compare": c}
                  for c in ("manual", "hardware")}
        err = {}
        for view in VIEWS:
            imgs = {}
            for c, sets in shadow.items():
                p.set_many(sets)
                imgs[c] = _final_image(session, size, view)
            err[view] = _diff(imgs["manual"], imgs["hardware"])
        _set_view(session, "ground")
        runs, done = _variants(session, size, shadow)
        try:
            timed = time_interleaved(session.gpu.ctx, runs, _warmup_after_build(warmup), rounds)
        finally:
            done()
        out["shadow_compare"] = {"method": "shadowed", "view": "ground",
                                 "frame_ratio_hardware_to_manual":
                                     _ratio(timed, "hardware", "manual"),
                                 "timings": timed.summary(), "error": err}
        # 2. the baked ground noise (in the scattering pass, as it was made), then the ground pass
        #    (the ground and the background into the G-buffer, baked noise), and the LUT method's
        #    speed-up over brute force at each step
        p.set("planet.shadow_compare", "hardware")
        steps = {"live": {"planet.ground_noise": "live", "planet.ground_pass": "scattering"},
                 "baked": {"planet.ground_noise": "baked", "planet.ground_pass": "scattering"},
                 "gbuffer": {"planet.ground_noise": "baked", "planet.ground_pass": "gbuffer"}}
        noise = {f"{m}:{n}": {"planet.method": m, **sets}
                 for m in ("brute_force", "lut") for n, sets in steps.items()}
        err, err_pass = {}, {}
        for view in VIEWS:
            for m in ("brute_force", "lut"):
                imgs = {}
                for n, sets in steps.items():
                    p.set_many({"planet.method": m, **sets})
                    imgs[n] = _final_image(session, size, view)
                err[f"{view}:{m}"] = _diff(imgs["live"], imgs["baked"])
                err_pass[f"{view}:{m}"] = _diff(imgs["baked"], imgs["gbuffer"])
        _set_view(session, "ground")
        pass_result = {}
        result = {}
        for part, only in (("frame", False), ("scattering", True)):
            runs, done = _variants(session, size, noise, scattering_only=only)
            try:
                timed = time_interleaved(session.gpu.ctx, runs, _warmup_after_build(warmup), rounds)
            finally:
                done()
            result[part] = {
                "timings": timed.summary(),
                "baked_to_live": {m: _ratio(timed, f"{m}:baked", f"{m}:live")
                                  for m in ("brute_force", "lut")},
                "lut_speedup_over_brute_force": {
                    n: _ratio(timed, f"brute_force:{n}", f"lut:{n}") for n in steps},
            }
            pass_result[part] = {"gbuffer_to_scattering": {
                m: _ratio(timed, f"{m}:gbuffer", f"{m}:baked") for m in ("brute_force", "lut")}}
        out["ground_noise"] = {"view": "ground", **result, "error": err,
                               "bake_size": p["planet.ground_noise_size"]}
        out["ground_pass"] = {"view": "ground", **pass_result, "error": err_pass}
    return out


def sweep(session, size, warmup: int = 2, repeat: int = 5, sizes=None) -> dict:
    """What ``natura bench planet`` runs after the per-pass timings."""
    table_sizes = sizes or DEFAULT_SIZES
    small = at_most(size, (320, 180))
    p = session.params
    with p.kept(PER_PIXEL):
        p.set_many(PER_PIXEL)
        table = thesis_table(session, table_sizes, warmup, repeat)
        acc = accuracy(session, size=at_most(size, (64, 36)), time_size=small,
                       warmup=max(1, warmup - 1), repeat=max(2, repeat // 2))
        done = changes(session, small, warmup=max(1, warmup - 1), rounds=max(5, repeat))
    done["march_scale"] = march_scale_change(session, at_most(size, (640, 360)),
                                             warmup=max(1, warmup - 1), rounds=max(5, repeat))
    # a bench scaled down (--size at most 320x180, as the examples run it) scales the
    # reference's grid down too: half a side (its error then about 5 %, stated in the JSON
    # by the resolution check beside the figures)
    from ..sim import multiple_scattering as msr

    coarse = size[0] * size[1] <= 320 * 180
    return {"table": {**table, "march_scale": "full"}, "accuracy": acc, "changes": done,
            "multiple_scattering": multiple_scattering(
                grid=msr.Grid().scaled(0.5) if coarse else None)}


def multiple_scattering(grid=None, orders: int = 10, variants=None, lut_steps: int = 60) -> dict:
    """Hillaire against the multi-order reference (numpy, no GL; the module notes): for each
    LUT variant of :data:`MS_VARIANTS`, :func:`app.sim.multiple_scattering.compare`; beside them
    the reference's resolution check (the same sky with the grid halved: largest relative
    change) and its single-scattering check against :func:`app.sim.atmosphere.reference`.
    The atmosphere is the scene's default (``ozone`` 0)."""
    import time

    from ..sim import multiple_scattering as msr

    params = atm.AtmosphereParams()
    grid = grid or msr.Grid()
    t0 = time.perf_counter()
    ref = msr.Reference(params, grid, orders)
    build_s = time.perf_counter() - t0
    out: dict = {"grid": dict(grid.__dict__), "orders": orders, "reference_build_s": build_s,
                 "variants": {}}
    for name, kw in (variants or MS_VARIANTS).items():
        lut = msr.hillaire_ms_lut(params, steps=lut_steps, model=ref.m, **kw)
        out["variants"][name] = msr.compare(params, grid, orders, reference=ref, lut=lut)
    half = msr.Reference(params, grid.scaled(0.5), orders)
    el = np.asarray(msr.ELEVATIONS)
    change = 0.0
    single = 0.0
    for se in msr.SUN_ELEVATIONS:
        sun = atm.direction(se, 0.0)
        for az in (0.0, 180.0):
            a = ref.orders_along(msr.H_CAM, el, np.full(el.shape, az), se)
            b = half.orders_along(msr.H_CAM, el, np.full(el.shape, az), se)
            change = max(change, float(np.max(np.abs(sum(b.values()) / sum(a.values()) - 1))))
            dirs = np.stack([atm.direction(e, az) for e in el])
            cam = atm.local_to_planet(np.array([0.0, msr.H_CAM, 0.0]), params)
            exact = atm.reference(cam, dirs, sun, params, steps=4096).in_scatter
            single = max(single, float(np.max(np.abs(a[1] / exact - 1))))
    out["resolution_change_half_grid"] = change
    out["single_vs_atmosphere_reference"] = single
    return out


def march_scale_change(session, size=(640, 360), warmup: int = 1, rounds: int = 7) -> dict:
    """``planet.march_scale`` half and quarter against full (method 3): per view (the ground
    view, and a light-shaft view with a low sun behind the mountains), the 8-bit difference
    of the tone-mapped images (mean, p99, max), the share of pixels that marched their own
    ray, and, interleaved, the scattering pass's and the frame's time ratio to full."""
    p = session.params
    eff = session.scene.effect("planet")
    keys = ("planet.method", "planet.march_scale", "planet.sun_elevation",
            "planet.sun_azimuth")
    saved = {k: p[k] for k in keys}
    scales = ("full", "half", "quarter")
    out: dict = {"size": list(size), "rounds": rounds, "method": "shadowed", "views": {}}
    try:
        p.set("planet.method", "shadowed")
        for view, sun in (("ground", {}), ("shafts", SHAFT_SUN)):
            p.set_many({**{k: saved[k] for k in keys[2:]}, **sun})
            v = SHAFT_VIEW if view == "shafts" else VIEWS["ground"]
            session.scene.camera.set(**v)
            imgs, alone = {}, {}
            for sc in scales:
                p.set("planet.march_scale", sc)
                imgs[sc] = _final_image_at(session, size)
                mask = eff.marched_alone()
                alone[sc] = float(mask.mean()) if mask is not None else 1.0
            exposure = float(session.scene.exposure())
            show = {sc: 1.0 - np.exp(-exposure * img) for sc, img in imgs.items()}
            entry: dict = {"own_ray_share": alone, "error_8bit": {}}
            for sc in scales[1:]:
                d = np.abs(show[sc] - show["full"]).max(axis=-1) * 255.0
                entry["error_8bit"][sc] = {"mean": float(d.mean()),
                                           "p99": float(np.percentile(d, 99)),
                                           "max": float(d.max())}
            for part, only in (("frame", False), ("scattering", True)):
                runs, done = _variants(session, size, {sc: {"planet.march_scale": sc}
                                                       for sc in scales}, scattering_only=only)
                try:
                    timed = time_interleaved(session.gpu.ctx, runs,
                                             _warmup_after_build(warmup), rounds)
                finally:
                    done()
                entry[f"{part}_ratio_to_full"] = {sc: _ratio(timed, sc, "full")
                                                  for sc in scales[1:]}
                entry[f"{part}_ms"] = {sc: timed.quartiles(sc)[1] for sc in scales}
            out["views"][view] = entry
    finally:
        p.set_many(saved)
        _set_view(session, "ground")
    return out


def _final_image_at(session, size) -> np.ndarray:
    """The final linear image (h, w, 3) of the current camera at ``size``."""
    gpu = session.gpu
    with gpu.scratch_target("bench", "planet change", size) as target:
        session.scene.render(session.scene.frame(size), target)
        return target.read()[..., :3].astype(np.float64)


def chart(report: dict, path, force: bool = False) -> None:
    plt = pyplot()

    s = report["sweep"]
    fig, axes = plt.subplots(1, 2, figsize=(14, 5))
    ax = axes[0]
    markers = {"brute_force": "o", "lut": "s", "shadowed": "^", "hillaire": "D"}
    for method in markers:
        for knob in sorted({r["knob"] for r in s["accuracy"]["rows"] if r["method"] == method}):
            rows = [r for r in s["accuracy"]["rows"] if r["method"] == method and r["knob"] == knob]
            ax.plot([r["ms"] for r in rows], [max(r["in_mean"], 1e-6) for r in rows],
                    markers[method] + "-", label=f"{method}: {knob}")
            for r in rows:
                ax.annotate(str(r["value"]), (r["ms"], max(r["in_mean"], 1e-6)), fontsize=7,
                            textcoords="offset points", xytext=(3, 3))
    ax.set_yscale("log")
    ax.set_xlabel(f"ms per frame at "
                  f"{s['accuracy']['time_size'][0]}×{s['accuracy']['time_size'][1]}")
    ax.set(ylabel="mean |in-scatter − reference| (linear radiance)", title="time against error")
    ax.legend(fontsize=7)
    ax = axes[1]
    rows = s["table"]["rows"]
    labels = sorted({(r["view"], tuple(r["size"])) for r in rows}, key=lambda k: (k[0], k[1][0]))
    width = 0.2
    for i, method in enumerate(TABLE_METHODS):
        ys = [next((r["ms"] for r in rows
                    if r["method"] == method and (r["view"], tuple(r["size"])) == lab), np.nan)
              for lab in labels]
        ax.bar(np.arange(len(labels)) + (i - 1.5) * width, ys, width, label=method)
    ax.set_xticks(range(len(labels)), [f"{v}\n{w}×{h}" for v, (w, h) in labels], fontsize=8)
    ax.set(ylabel="ms per frame", title="the thesis's table layout (spec/002 §5)")
    ax.legend(fontsize=8)
    write_chart(fig, path, force, title=f"natura bench planet — {report['renderer']}")
    ms = s.get("multiple_scattering")
    if ms:
        from pathlib import Path

        p = Path(path)
        multiple_chart(ms, p.with_name(p.stem + CHART_SUFFIXES[1]), force)


def multiple_chart(ms: dict, path, force: bool = False) -> None:
    """Hillaire's relative error against the multi-order reference (green channel) per view
    elevation, one panel per sun elevation, each LUT variant toward (solid) and away (dashed)."""
    plt = pyplot()

    suns = list(next(iter(ms["variants"].values()))["suns"])
    fig, axes = plt.subplots(1, len(suns), figsize=(5 * len(suns), 4.5), sharey=True)
    for ax, se in zip(np.atleast_1d(axes), suns):
        for i, (name, c) in enumerate(ms["variants"].items()):
            el = c["elevations"]
            for side, style in (("toward", "-"), ("away", "--")):
                err = 100.0 * np.asarray(c["suns"][se][side]["error"])[:, 1]
                ax.plot(el, err, style, color=f"C{i}", marker="o", ms=3,
                        label=f"{name}, {side}")
        first = next(iter(ms["variants"].values()))
        for side, style in (("toward", "-"), ("away", "--")):
            ax.plot(first["elevations"],
                    100.0 * np.asarray(first["suns"][se][side]["oracle_error"]["sphere"])[:, 1],
                    style, color="k", lw=0.8,
                    label=f"bound: best isotropic Ψ (reference averaged), {side}")
        ax.axhspan(-5, 5, color="0.9", zorder=0)
        ax.axhline(0, color="k", lw=0.5)
        ax.set(xscale="log", xlabel="view elevation (°)", title=f"sun {float(se):g}° up")
    np.atleast_1d(axes)[0].set_ylabel("Hillaire / reference − 1 (%, green)")
    np.atleast_1d(axes)[0].legend(fontsize=6)
    write_chart(fig, path, force, title=f"Hillaire 2020 against orders 1–{ms['orders']} "
                f"(Bruneton 2017 formulation); reference grid halved changes it ≤ "
                f"{100 * ms['resolution_change_half_grid']:.2f} %")


def multiple_summary(ms: dict | None) -> list[str]:
    if not ms:
        return []
    lines = [f"multiple scattering: Hillaire against the multi-order reference (orders 1–"
             f"{ms['orders']}, grid {ms['grid']}; halving the grid changes the sky ≤ "
             f"{100 * ms['resolution_change_half_grid']:.2f} %, its single scattering is within "
             f"{100 * ms['single_vs_atmosphere_reference']:.3f} % of the float64 reference)"]
    for name, c in ms["variants"].items():
        worst = ", ".join(f"sun {float(se):g}°: {100 * d['worst']:+.1f} %"
                          for se, d in c["suns"].items())
        lines.append(f"  {name:28s} worst error above 1° elevation — {worst}")
    c = next(iter(ms["variants"].values()))
    ge5 = max(max(d["toward"]["orders_ge5_share"], d["away"]["orders_ge5_share"])
              for d in c["suns"].values())
    tail = max(max(d["toward"]["tail_share"], d["away"]["tail_share"])
               for d in c["suns"].values())
    for over, what in (("sphere", "any isotropic Ψ(h, μ_s), Hillaire's form"),
                       ("azimuth", "an azimuth-averaged Ψ(h, μ_s, μ)")):
        worst = ", ".join(f"sun {float(se):g}°: {100 * d[f'worst_oracle_{over}']:+.1f} %"
                          for se, d in c["suns"].items())
        lines.append(f"  bound: the reference's own source as {what} — {worst}")
    lines.append(f"  reference: orders ≥ 5 are ≤ {100 * ge5:.2f} % of the sky, orders beyond "
                 f"{ms['orders']} ≤ {100 * tail:.3f} % (geometric tail)")
    return lines


def summary(report: dict) -> str:
    s = report["sweep"]
    lines = ["view    size        method        frame ms   fps   ×method 1 (fps)   "
             "scattering pass ms   ×method 1"]
    for r in s["table"]["rows"]:
        lines.append(f"{r['view']:7s} {r['size'][0]}x{r['size'][1]:<6d} {r['method']:12s} "
                     f"{r['ms']:8.2f} "
                     f"{r['fps']:7.1f}   {r['ratio_fps_to_method_1']:5.2f}             "
                     f"{r['scattering_ms']:8.2f}"
                     f"           {r['scattering_ratio_to_method_1']:5.2f}")
    lines.append("method       knob                         value      ms   "
                 "in-scatter err mean / p99   "
                 "transmittance err mean / p99")
    for r in s["accuracy"]["rows"]:
        lines.append(f"{r['method']:12s} {r['knob']:28s} {str(r['value']):>6s} {r['ms']:8.2f}   "
                     f"{r['in_mean']:.2e} / {r['in_p99']:.2e}       "
                     f"{r['t_mean']:.2e} / {r['t_p99']:.2e}")
    lines += changes_summary(s.get("changes"), s.get("accuracy"))
    lines += multiple_summary(s.get("multiple_scattering"))
    m1 = s["accuracy"].get("method_1_defaults")
    if m1:
        lines.append(f"method 1 at its defaults (N = {m1['n_steps']}, τ(PC) rule "
                     f"{m1['pc_rule_used']}, universe sphere {m1['universe_radius']:.4g} m about "
                     f"the {m1['universe_centre']}) against the reference:")
        lines.append(f"    in-scatter err mean {m1['in_mean']:.2e} "
                     f"({100.0 * m1['in_rel_mean']:.1f} % of the reference's mean), "
                     f"p99 {m1['in_p99']:.2e}; transmittance err mean {m1['t_mean']:.2e}")
    return "\n".join(lines)


def _fmt(r: dict) -> str:
    return f"{r['median']:.2f}× [{r['p25']:.2f}–{r['p75']:.2f}]"


def changes_summary(c: dict | None, accuracy: dict | None = None) -> list[str]:
    """The "changes" section's lines: each change's time ratio (median [p25–p75]) beside its
    image difference, and the LUT/brute-force speed-up before and after — with, given the
    ``accuracy`` report, each method's error against the reference at the same N beside it."""
    if not c:
        return []
    w, h = c["size"]
    lines = [f"changes (interleaved, {c['rounds']} rounds, {w}x{h}, N = {c['n_steps']}; "
             "time ratio median [p25–p75], image difference):"]
    sc = c["shadow_compare"]
    e = sc["error"]
    lines.append(f"  hardware depth compares / manual (method 3 frame, ground): "
                 f"{_fmt(sc['frame_ratio_hardware_to_manual'])}; max rel. diff ground "
                 f"{e['ground']['max_rel']:.1e}, space {e['space']['max_rel']:.1e}")
    g = c["ground_noise"]
    for m in ("brute_force", "lut"):
        eg, es = g["error"][f"ground:{m}"], g["error"][f"space:{m}"]
        lines.append(f"  baked ground noise / live, {m:11s}: frame "
                     f"{_fmt(g['frame']['baked_to_live'][m])}, scattering pass "
                     f"{_fmt(g['scattering']['baked_to_live'][m])}; |Δ| mean/max ground "
                     f"{eg['mean_abs']:.1e}/{eg['max_abs']:.1e}, space "
                     f"{es['mean_abs']:.1e}/{es['max_abs']:.1e}")
    gp = c.get("ground_pass")
    if gp:
        for m in ("brute_force", "lut"):
            eg, es = gp["error"][f"ground:{m}"], gp["error"][f"space:{m}"]
            lines.append(f"  ground pass in the G-buffer / in the scattering pass, {m:11s}: frame "
                         f"{_fmt(gp['frame']['gbuffer_to_scattering'][m])}, scattering pass "
                         f"{_fmt(gp['scattering']['gbuffer_to_scattering'][m])}; |Δ| max ground "
                         f"{eg['max_abs']:.1e}, space {es['max_abs']:.1e}")
    for part in ("frame", "scattering"):
        su = g[part]["lut_speedup_over_brute_force"]
        after = f", ground pass in the G-buffer {_fmt(su['gbuffer'])}" if "gbuffer" in su else ""
        lines.append(f"  LUT speed-up over brute force, ground view, {part:10s}: live noise "
                     f"{_fmt(su['live'])}, baked {_fmt(su['baked'])}{after} "
                     "(the thesis: 3.3–7×)")
    ms = c.get("march_scale")
    if ms:
        for view, e in ms["views"].items():
            for sc in ("half", "quarter"):
                err = e["error_8bit"][sc]
                lines.append(
                    f"  march_scale {sc:7s}/ full, {view:6s} view ({ms['size'][0]}x"
                    f"{ms['size'][1]}, method 3): scattering pass "
                    f"{_fmt(e['scattering_ratio_to_full'][sc])}, frame "
                    f"{_fmt(e['frame_ratio_to_full'][sc])}; 8-bit |Δ| mean {err['mean']:.3f}, "
                    f"p99 {err['p99']:.2f}, max {err['max']:.2f}; own rays "
                    f"{100.0 * e['own_ray_share'][sc]:.1f} %")
    rows = {r["method"]: r for r in (accuracy or {}).get("rows", [])
            if r["knob"] == "n_steps" and r["value"] == c["n_steps"]}
    if "brute_force" in rows and "lut" in rows:
        lines.append(f"  their error against the reference at N = {c['n_steps']} (in-scatter / "
                     "transmittance, mean): " + ", ".join(
                         f"{m} {rows[m]['in_mean']:.2e} / {rows[m]['t_mean']:.2e}"
                         for m in ("brute_force", "lut")))
    return lines

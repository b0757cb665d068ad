"""Speed against accuracy for the ocean: FFT size and cascades, ms per frame and spectrum error.

Two comparisons and four sweeps, run by ``natura bench ocean`` after the per-pass timings, all at
the bench view size with the scene's camera and the session's sea state (wind, spectrum, patch
sizes); each function below says what it measures:

0. forward against deferred surface shading (:func:`shading_comparison`);
0b. the simulation of what the view resolves against the thesis's (:func:`simulation_comparison`);
1. **FFT size × cascades** (:func:`fft_sweep`, ``ocean.simulation = full``) — ms per frame and
   of the simulation alone, against the error of the mean-square slope and Hs carried by the
   cascades' actual h₀ — mss = Σ_k k²(|h₀(k)|² + |h₀(−k)|²) = 2·Σk²|h₀|²,
   Hs = 4·sqrt(2·Σ|h₀|²), summed over cascades — against ``spectrum_moments`` of the same
   spectrum (same short-wave fade) up to k_ref = π·512/L_min, the Nyquist of the finest
   configuration: the *mss deficit* 1 − mss/mss_ref and the *Hs error* |Hs − Hs_ref|/Hs_ref.
   The actual h₀ is one random draw, so the same figures are also given for its expectation
   (E|h₀|² = ½Ψ(−k)Δk²): ``*_expected`` is the deficit of the band limits alone, without the
   sampling noise;
2. **Gerstner 8–64 waves vs the FFT** (:func:`gerstner_sweep`) at equal Hs and peak period;
3. **GPU FFT against a direct sum of the same waves** (:func:`direct_sweep`);
4. **Oceanography** (``app.sim.ocean_validation``).

All timings are wall time around ``ctx.finish()`` (``app.gpu.timing.time_call``): the figures
are specific to the renderer that produced them (on llvmpipe the CPU does everything and the
ocean surface pass, not the simulation, dominates a frame); compare ratios within one report.
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..errors import NaturaError, ParamError, UsageError
from ..gpu.timing import time_call, time_interleaved
from ..sim import ocean as oc
from ..sim.ocean_validation import (
    cascade_moments,
    fft_peak_period,
    fft_shape_distance,
    gerstner_peak_period,
    gerstner_shape_distance,
    oceanography,
    ratio_errors,
    shape_bins,
    spectrum_peak_period,
)
from ..sim.ocean_validation import summary as oceanography_summary
from . import pyplot, write_chart

FFT_SIZES = (64, 128, 256, 512)
CASCADES = (1, 2, 3, 4)
GERSTNER_COUNTS = (8, 16, 32, 64)
FFT_COMPARE = (256, 3)
DIRECT_SIZES = (16, 32, 64)
DIRECT_EXTRA = 128
DIRECT_BUDGET_S = 20.0
DT = 1.0 / 30.0
DIRECT_TIME = 3.0  # simulation time [s] of the direct-sum comparison

SHADINGS = ("forward", "deferred")

TITLES = {"shading": "Surface pass, forward vs deferred",
          "simulation": "Simulation, what the view resolves vs the thesis's",
          "fft": "FFT size × cascades",
          "gerstner": "Gerstner waves vs FFT", "direct_sum": "GPU FFT vs direct sum"}


# ---- sea-state helpers -----------------------------------------------------------------------

def reference(session) -> dict:
    """Moments of the session's spectrum up to the Nyquist of the finest configuration."""
    eff = session.scene.effect("ocean")
    sp = eff.sea.spectrum_params()
    sizes = [float(s) for s in session.params["ocean.patch_sizes"]]
    k_ref = math.pi * max(FFT_SIZES) / min(sizes)
    m = oc.spectrum_moments(sp, k_max=k_ref)
    return {"k_ref": k_ref, "m0": m["m0"], "hs": m["hs"], "mss": m["mss"], "k_peak": m["k_peak"],
            "tp_s": spectrum_peak_period(sp, m["k_peak"])}


def gpu_significant_height(gpu):
    """For :func:`app.sim.ocean_validation.oceanography`: Hs = 4·std(η) of a seeded sea simulated
    on the GPU (the effect's ``GpuOceanSim``, N = 256, read back at t = 3 s)."""
    from ..effects.ocean.fft import GpuOceanSim

    def measure(p, size, seed) -> float:
        ref = oc.FFTOcean(p, n=256, patch_sizes=(size,), choppiness=1.0, seed=seed)
        sim = GpuOceanSim(gpu, "validation")
        try:
            sim.set_spectrum(ref.cascades, 256)
            sim.update(3.0, 1.0, 0.0)
            return 4.0 * float(np.std(sim.read_fields(0)["height"]))
        finally:
            sim.release()

    return measure


# ---- timing ----------------------------------------------------------------------------------

def _frame_ms(session, size, warmup: int, repeat: int) -> float:
    """Median ms of ``scene.frame(size, dt=1/30)`` + ``scene.render``; ``warmup`` untimed frames
    first, at least one (it builds what a configuration change made stale)."""
    gpu = session.gpu
    with gpu.scratch_target("bench", "ocean frame", tuple(size)) as target:
        def one():
            session.scene.render(session.scene.frame(tuple(size), DT), target)

        one()
        return time_call(gpu.ctx, "frame", one, max(0, warmup - 1), repeat).median_ms


def _sim_ms(session, warmup: int, repeat: int) -> float:
    eff, t = session.scene.effect("ocean"), session.scene.time
    sea, thresholds = eff.sea, eff.foam.thresholds()
    return time_call(session.gpu.ctx, "ocean.simulate",
                     lambda: sea.simulate(sea.sim, t, DT, thresholds), warmup, repeat).median_ms


def _cascades_of(eff, n: int, count: int):
    ref = eff.sea.reference  # what the effect uploaded to its GpuOceanSim
    if ref is None or ref.n != n or len(ref.cascades) != count:
        p = eff.params
        ref = oc.FFTOcean(eff.sea.spectrum_params(), n=n, patch_sizes=eff.sea.patch_sizes(),
                          seed=p["ocean.seed"])
    return ref.cascades


def _fft_sizes_from(sizes) -> tuple[int, ...]:
    """``natura bench ocean --sizes 64x64,128x128``: square pairs name FFT sizes."""
    out = sorted({int(w) for w, h in sizes if int(w) == int(h) and int(w) in FFT_SIZES})
    if not out:
        raise UsageError(f"natura bench ocean --sizes: {','.join(f'{w}x{h}' for w, h in sizes)} "
                         f"names no FFT size: give NxN pairs with N in "
                         f"{', '.join(map(str, FFT_SIZES))}")
    return tuple(out)


def _quartiles(timed, names) -> dict:
    """Median and quartiles [ms] of each of ``names`` in an interleaved timing."""
    rows = {name: timed.quartiles(name) for name in names}
    return {name: {"median_ms": q[1], "p25_ms": q[0], "p75_ms": q[2]} for name, q in rows.items()}


# ---- comparison: forward against deferred shading ----------------------------------------------

def shading_comparison(session, size, warmup: int = 2, rounds: int = 5) -> dict:
    """The ocean's surface pass with ``ocean.shading`` = forward and = deferred, from a cleared
    target each time, timed in the same interleaved rounds; and the two images' difference."""
    p = session.params
    eff = session.scene.effect("ocean")
    gpu = session.gpu
    saved = p["ocean.shading"]
    target = gpu.target("bench", "ocean shading", tuple(size))
    images = {}
    try:
        frame = session.scene.frame(tuple(size), 0.0)
        session.scene.render(frame, target)  # lazy resources, the sky, the FFT's fields

        def variant(mode: str):
            def run():
                p.set("ocean.shading", mode)
                target.clear()
                eff.surface.render(frame, target)

            return run

        variants = {mode: variant(mode) for mode in SHADINGS}
        for mode, run in variants.items():
            run()
            images[mode] = target.read()[..., :3].astype(np.float64)
            if mode == "deferred":
                band = eff.surface.far_band
        timed = time_interleaved(gpu.ctx, variants, warmup, rounds)
    finally:
        p.set("ocean.shading", saved)
        gpu.free(target)
    diff = np.abs(images["deferred"] - images["forward"])
    out = {"view_size": list(size), "model": p["ocean.model"], "rounds": timed.rounds,
           "warmup": warmup, "ratio": timed.ratio("deferred", "forward"),
           "mean_abs_diff": float(diff.mean()), "max_abs_diff": float(diff.max()),
           "max_radiance": float(images["forward"].max()),
           "far_band_ndc": list(band) if band is not None else None}
    return {**out, **_quartiles(timed, SHADINGS)}


# ---- comparison: the simulation for what the view resolves against the thesis's --------------

SIM_POINTS = 4096  # random rest points the two seas are compared at
SIM_FRAMES = 12  # frames of 1/30 s the error is measured over (a slow cascade's period or more)


def _sea_at_points(sim, patch_sizes, x, z) -> tuple[np.ndarray, np.ndarray]:
    """(height, slope (x, z)) of ``sim``'s displayed textures at rest points (x, z): each cascade
    read back, looked up bilinearly (as the surface samples level 0), summed."""
    disp, slope = [], []
    for i in range(sim.cascade_count):
        f = sim.read_fields(i)
        disp.append(np.stack([f["height"]], axis=-1).astype(np.float64))
        slope.append(np.stack([f["slope_x"], f["slope_z"]], axis=-1).astype(np.float64))
    h = oc.sample_cascade_groups(oc.group_cascade_grids(disp, patch_sizes), x, z)
    s = oc.sample_cascade_groups(oc.group_cascade_grids(slope, patch_sizes), x, z)
    return h[..., 0], s


def simulation_comparison(session, size, warmup: int = 2, rounds: int = 5,
                          frames: int = SIM_FRAMES) -> dict:
    """``ocean.simulation`` = view against full (the thesis: every cascade at ``ocean.fft_size``,
    every frame) for the scene's view at ``size``: the view's grids and slow-cascade periods
    (as the effect chose them), the ms of one frame's simulation of each — two copies of the
    simulation, each on a clock of its own that moves 1/30 s a call, timed in the same
    interleaved rounds — and the error of the view's sea against the full one: both simulated
    over ``frames`` frames in step, read back and looked up at the same random rest points
    (rms and max |Δη| over Hs/4 and Hs, rms |Δslope| over the sea's rms slope), beside the
    error predicted for the worst instant (mid-interval): the dropped modes' energy plus
    :func:`app.sim.ocean.interpolation_error`."""
    from ..effects.ocean.fft import GpuOceanSim

    p = session.params
    eff = session.scene.effect("ocean")
    gpu = session.gpu
    p.set_many({"ocean.model": "fft", "ocean.simulation": "view"})
    target = gpu.target("bench", "ocean simulation", tuple(size))
    sims: dict[str, GpuOceanSim] = {}
    try:
        for _ in range(3):  # the view's grids and periods settle at frames of 1/30 s
            session.scene.render(session.scene.frame(tuple(size), DT), target)
        full_cascades = eff.sea.reference.cascades
        view_cascades = list(eff.sea._sim_cascades)
        sizes, periods = list(eff.sea.sim.sizes), list(eff.sea.sim.periods)
        thresholds = eff.foam.thresholds()
        for name, cascades, refresh in (("full", full_cascades, [0.0] * len(sizes)),
                                        ("view", view_cascades, periods)):
            sim = GpuOceanSim(gpu, "bench", use_compute=eff.sea.sim.use_compute)
            sim.set_spectrum(cascades)
            sim.set_refresh(refresh)
            sims[name] = sim
        t0 = float(session.scene.time)
        clock = {name: 0 for name in sims}

        def variant(name: str):
            def run():
                clock[name] += 1
                eff.sea.simulate(sims[name], t0 + clock[name] * DT, DT, thresholds)

            return run

        timed = time_interleaved(gpu.ctx, {n: variant(n) for n in sims}, warmup, rounds)
        rng = np.random.default_rng(37)
        span = max(eff.sea.patch_sizes())
        x, z = rng.uniform(-span, span, SIM_POINTS), rng.uniform(-span, span, SIM_POINTS)
        patch = eff.sea.patch_sizes()
        t1 = t0 + (max(clock.values()) + 10) * DT  # a jump ahead: the slow cascades start over
        d_h2, d_s2, d_max, h2, s2 = 0.0, 0.0, 0.0, 0.0, 0.0
        for j in range(max(1, frames)):
            for sim in sims.values():
                eff.sea.simulate(sim, t1 + j * DT, DT, thresholds)
            hf, sf = _sea_at_points(sims["full"], patch, x, z)
            hv, sv = _sea_at_points(sims["view"], patch, x, z)
            d_h2 += float(np.mean((hv - hf) ** 2))
            d_s2 += float(np.mean(np.sum((sv - sf) ** 2, axis=-1)))
            d_max = max(d_max, float(np.max(np.abs(hv - hf))))
            h2 += float(np.mean(hf ** 2))
            s2 += float(np.mean(np.sum(sf ** 2, axis=-1)))
    finally:
        for sim in sims.values():
            sim.release()
        gpu.free(target)
    # predicted at mid-interval: the dropped modes' energy, plus the blend's shortfall
    m_full = [c.moments() for c in full_cascades]
    m_view = [c.moments() for c in view_cascades]
    pred_h2 = sum(a[0] - b[0] for a, b in zip(m_full, m_view))
    pred_s2 = sum(a[1] - b[1] for a, b in zip(m_full, m_view))
    for c, period in zip(view_cascades, periods):
        if period > 0.0:
            e_h, e_s = oc.interpolation_error(c, period)
            pred_h2 += e_h * e_h
            pred_s2 += e_s * e_s
    var_full = sum(a[0] for a in m_full)
    mss_full = sum(a[1] for a in m_full)
    hs = 4.0 * math.sqrt(var_full)
    n = max(1, frames)
    out = {"view_size": list(size), "fft_size": int(p["ocean.fft_size"]), "grids": sizes,
           "periods_s": periods, "footprint_m": float(eff.sea.footprint),
           "rounds": timed.rounds, "warmup": warmup, "frames": n, "points": SIM_POINTS,
           "ratio": timed.ratio("view", "full"), "hs_m": hs,
           "rms_height_error": math.sqrt(d_h2 / n) / math.sqrt(h2 / n),
           "max_height_error": d_max / hs,
           "rms_slope_error": math.sqrt(d_s2 / n) / math.sqrt(s2 / n),
           "predicted_rms_height_error": math.sqrt(max(pred_h2, 0.0) / var_full),
           "predicted_rms_slope_error": math.sqrt(max(pred_s2, 0.0) / mss_full)}
    return {**out, **_quartiles(timed, sims)}


def simulation_summary(c: dict) -> list[str]:
    """Lines of the view/full simulation comparison."""
    w, h = c["view_size"]
    r = c["ratio"]
    slow = ", ".join(f"{i}: {1e3 * t:.0f} ms" for i, t in enumerate(c["periods_s"]) if t > 0)
    lines = [f"{TITLES['simulation']} at {w}x{h} ({c['rounds']} interleaved rounds): view grids "
             f"{'/'.join(map(str, c['grids']))} of {c['fft_size']} (smallest footprint "
             f"{100.0 * c['footprint_m']:.1f} cm), snapshot periods "
             f"{slow or 'none (every cascade every frame)'}"]
    for mode in ("full", "view"):
        t = c[mode]
        lines.append(f"  {mode:5s} {t['median_ms']:8.1f} ms  [{t['p25_ms']:.1f}–{t['p75_ms']:.1f}]")
    lines.append(f"  view/full ×{r['median']:.3f} [{r['p25']:.3f}–{r['p75']:.3f}] per round; "
                 f"view's sea against the full one over {c['frames']} frames at {c['points']} "
                 f"points: rms Δη {_pct(c['rms_height_error'])} of rms η (predicted at worst "
                 f"{_pct(c['predicted_rms_height_error'])}), max |Δη| "
                 f"{_pct(c['max_height_error'])} of Hs {c['hs_m']:.2f} m, rms Δslope "
                 f"{_pct(c['rms_slope_error'])} of rms slope (predicted at worst "
                 f"{_pct(c['predicted_rms_slope_error'])})")
    return lines


# ---- sweep 1 ---------------------------------------------------------------------------------

def fft_sweep(session, size, fft_sizes=FFT_SIZES, cascades=CASCADES, warmup: int = 2,
              repeat: int = 5, ref: dict | None = None) -> dict:
    """Each N × cascades: ms per frame (:func:`_frame_ms`: the simulation and every pass, with
    the sky) and of ``GpuOceanSim.update`` alone, and the errors of the module docstring; the
    combinations ``cascade_bands`` refuses are reported as skipped with its message."""
    p = session.params
    eff = session.scene.effect("ocean")
    ref = ref or reference(session)
    sp = eff.sea.spectrum_params()
    p.set("ocean.model", "fft")
    p.set("ocean.simulation", "full")  # every cascade on the N of the row, every frame
    all_sizes = [float(s) for s in p["ocean.patch_sizes"]]
    bins = shape_bins(sp, ref)
    rows = []
    for n in fft_sizes:
        for c in cascades:
            row = {"fft_size": int(n), "cascades": int(c), "patch_sizes": all_sizes[:c]}
            try:
                row["bands"] = [list(b) for b in oc.cascade_bands(int(n), all_sizes[:c])]
                p.set_many({"ocean.fft_size": str(n), "ocean.cascades": int(c)})
                row["ms_frame"] = _frame_ms(session, size, warmup, repeat)
                row["ms_sim"] = _sim_ms(session, warmup, repeat)
            except ParamError as exc:
                row["skipped"] = str(exc)
                rows.append(row)
                continue
            casc = _cascades_of(eff, int(n), int(c))
            m = cascade_moments(casc, sp)
            row.update({"hs": m["hs"], "mss": m["mss"], **ratio_errors(m["mss"], m["hs"], ref),
                        "shape_distance": fft_shape_distance(casc, sp, bins)})
            e = ratio_errors(m["mss_expected"], m["hs_expected"], ref)
            row.update({"mss_expected": m["mss_expected"], "hs_expected": m["hs_expected"],
                        "mss_deficit_expected": e["mss_deficit"],
                        "hs_error_expected": e["hs_error"]})
            rows.append(row)
    return {"fft_sizes": [int(n) for n in fft_sizes], "cascades": [int(c) for c in cascades],
            "rows": rows}


# ---- sweep 2 ---------------------------------------------------------------------------------

def gerstner_sweep(session, size, counts=GERSTNER_COUNTS, fft=FFT_COMPARE, warmup: int = 2,
                   repeat: int = 5, ref: dict | None = None) -> dict:
    """Gerstner sets of ``counts`` waves and the FFT at ``fft`` = (N, cascades): ms per frame,
    Hs, peak period (its definitions: the report's ``tp_definition``), mss deficit, distinct
    wave directions (1° bins) and the length over which the FFT repeats (its tile sizes)."""
    p = session.params
    eff = session.scene.effect("ocean")
    ref = ref or reference(session)
    sp = eff.sea.spectrum_params()
    p.set("ocean.simulation", "full")  # the FFT at the N compared, every frame
    rows = []
    bins = shape_bins(sp, ref)
    p.set("ocean.model", "gerstner")
    for count in counts:
        row = {"model": "gerstner", "waves": int(count)}
        try:
            p.set("ocean.gerstner_waves", int(count))
            waves = eff.sea.gerstner_waves()
            row["ms_frame"] = _frame_ms(session, size, warmup, repeat)
        except ParamError as exc:
            row["skipped"] = str(exc)
            rows.append(row)
            continue
        m = oc.gerstner_moments(waves)
        tp = gerstner_peak_period(waves, sp.depth)
        angles = {round(math.degrees(math.atan2(w.direction[1], w.direction[0]))) % 360
                  for w in waves}
        row.update({"hs": m["hs"], "mss": m["mss"], **ratio_errors(m["mss"], m["hs"], ref),
                    "tp_s": tp,
                    "tp_error": (abs(tp - ref["tp_s"]) / ref["tp_s"]) if ref["tp_s"] else None,
                    "distinct_directions": len(angles),
                    "shape_distance": gerstner_shape_distance(waves, sp, bins),
                    "shortest_wavelength_m": min(w.wavelength for w in waves),
                    "longest_wavelength_m": max(w.wavelength for w in waves)})
        rows.append(row)
    n, c = fft
    all_sizes = [float(s) for s in p["ocean.patch_sizes"]]
    row = {"model": "fft", "fft_size": int(n), "cascades": int(c),
           "repeat_lengths_m": all_sizes[:c]}
    try:
        oc.cascade_bands(int(n), all_sizes[:c])
        p.set_many({"ocean.model": "fft", "ocean.fft_size": str(n), "ocean.cascades": int(c)})
        row["ms_frame"] = _frame_ms(session, size, warmup, repeat)
    except ParamError as exc:
        row["skipped"] = str(exc)
    else:
        casc = _cascades_of(eff, int(n), int(c))
        m = cascade_moments(casc, sp)
        tp = fft_peak_period(casc, sp)
        row.update({"hs": m["hs"], "mss": m["mss"], **ratio_errors(m["mss"], m["hs"], ref),
                    "tp_s": tp,
                    "tp_error": ((abs(tp - ref["tp_s"]) / ref["tp_s"]) if (ref["tp_s"] and tp)
                                 else None),
                    "modes": int(sum(int(np.count_nonzero(cc.h0)) for cc in casc)),
                    "shape_distance": fft_shape_distance(casc, sp, bins)})
    rows.append(row)
    return {"counts": [int(k) for k in counts], "fft": [int(n), int(c)], "rows": rows,
            "tp_definition": {"gerstner": "2π/ω of the wave with the largest A²/2",
                              "fft": "peak of S(ω) of the actual h0, rings 2π/L0 wide",
                              "spectrum": "SpectrumParams.peak_omega() (E(k) peak for phillips)"}}


# ---- sweep 3 ---------------------------------------------------------------------------------

def direct_sweep(session, sizes=DIRECT_SIZES, extra: int | None = DIRECT_EXTRA,
                 budget_s: float = DIRECT_BUDGET_S, warmup: int = 2, repeat: int = 5) -> dict:
    """One cascade (L = the first patch size): GpuOceanSim.update (FFT) against direct_sum, same
    waves, same run, at ``sizes`` and at ``extra`` when its estimated cost stays under
    ``budget_s``: ms of each, the speed-up and max|η_direct − η_FFT|/max|η_FFT|."""
    from ..effects.ocean.fft import GpuOceanSim

    p = session.params
    eff = session.scene.effect("ocean")
    sp = eff.sea.spectrum_params()
    patch = float(p["ocean.patch_sizes"][0])
    lam = float(p["ocean.choppiness"])
    direct_repeat = max(1, min(repeat, 3))  # the first (accuracy) run is its warm-up
    rows, skipped = [], []

    def measure(n: int) -> dict:
        ocean = oc.FFTOcean(sp, n=n, patch_sizes=(patch,), seed=p["ocean.seed"])
        sim = GpuOceanSim(session.gpu, "bench-ocean")
        try:
            sim.set_spectrum(ocean.cascades, n)
            sim.update(DIRECT_TIME, lam, 0.0)
            fft_eta = sim.read_fields(0)["height"].astype(np.float64)
            t0 = time.perf_counter()
            sim.direct_sum(DIRECT_TIME, lam)
            first_s = time.perf_counter() - t0  # includes building the mode table
            direct_eta = sim.read_fields(0)["height"].astype(np.float64)
            scale = float(np.abs(fft_eta).max())
            diff = float(np.abs(direct_eta - fft_eta).max())
            ms_fft = time_call(session.gpu.ctx, "fft", lambda: sim.update(DIRECT_TIME, lam, 0.0),
                               warmup, repeat).median_ms
            direct = time_call(session.gpu.ctx, "direct", lambda: sim.direct_sum(DIRECT_TIME, lam),
                               0, direct_repeat)
            ms_direct = direct.median_ms
            return {"fft_size": n, "patch_size": patch, "modes": sim.mode_counts()[0],
                    "path": sim.path,
                    "ms_fft": ms_fft, "ms_direct": ms_direct, "speedup": ms_direct / ms_fft,
                    "max_abs_diff": diff, "max_abs_eta": scale,
                    "rel_diff": diff / scale if scale > 0 else diff,
                    "min_ms_direct": min(direct.wall_ms), "first_direct_s": first_s,
                    "direct_repeat": direct_repeat}
        finally:
            sim.release()

    for n in sizes:
        rows.append(measure(int(n)))
    if extra and rows and extra > rows[-1]["fft_size"]:
        last = rows[-1]
        ext_modes = int(np.count_nonzero(oc.FFTOcean(sp, n=extra, patch_sizes=(patch,),
                                                     seed=p["ocean.seed"]).cascades[0].h0))
        scale = (extra / last["fft_size"]) ** 2 * ext_modes / max(last["modes"], 1)
        # O(N²·modes); from the fastest run (the least disturbed by other load), 1 + repeat runs
        estimate = last["min_ms_direct"] * 1e-3 * scale * (1 + direct_repeat)
        if estimate < budget_s:
            rows.append({**measure(int(extra)), "estimated_s": estimate})
        else:
            skipped.append({"fft_size": extra,
                            "reason": f"estimated {estimate:.0f} s of direct sums "
                                      f"(budget {budget_s:g} s)"})
    return {"patch_size": patch, "time_s": DIRECT_TIME, "choppiness": lam, "rows": rows,
            "skipped": skipped}


# ---- the whole sweep -------------------------------------------------------------------------

def sweep(session, size, warmup: int = 2, repeat: int = 5, sizes=None, fft_sizes=None,
          cascades=CASCADES, gerstner_counts=GERSTNER_COUNTS, fft_compare=FFT_COMPARE,
          direct_sizes=DIRECT_SIZES, direct_extra: int | None = DIRECT_EXTRA) -> dict:
    """What ``natura bench ocean`` runs after the per-pass timings."""
    if fft_sizes is None:
        fft_sizes = _fft_sizes_from(sizes) if sizes else FFT_SIZES
    if sizes:  # --sizes: the direct-sum comparison goes no further than the FFT sizes asked for
        direct_sizes = tuple(n for n in direct_sizes if n <= max(fft_sizes)) or direct_sizes[:1]
        if direct_extra is not None and direct_extra > max(fft_sizes):
            direct_extra = None
    saved = session.params.values()
    eff = session.scene.effect("ocean")
    t0 = time.perf_counter()
    try:
        ref = reference(session)
        sp = eff.sea.spectrum_params()
        out = {
            "renderer": session.gpu.caps.renderer,
            "view_size": list(size),
            "camera": {"position": [float(x) for x in session.scene.camera.position]},
            "wind": session.params["ocean.wind"],
            "wind_direction": session.params["ocean.wind_direction"],
            "spectrum": sp.kind, "fetch_km": session.params["ocean.fetch"], "depth": sp.depth,
            "short_wave_fade": sp.short_wave_fade,
            "patch_sizes": [float(s) for s in session.params["ocean.patch_sizes"]],
            "warmup": warmup, "repeat": repeat,
            "reference": ref,
            "shading": shading_comparison(session, size, warmup, max(repeat, 3)),
            "simulation": simulation_comparison(session, size, warmup, max(repeat, 3)),
            "fft": fft_sweep(session, size, fft_sizes, cascades, warmup, repeat, ref),
            "gerstner": gerstner_sweep(session, size, gerstner_counts, fft_compare, warmup, repeat,
                                       ref),
            "direct_sum": direct_sweep(session, direct_sizes, direct_extra, DIRECT_BUDGET_S, warmup,
                                       repeat),
            "oceanography": oceanography(gpu_hs=gpu_significant_height(session.gpu)),
        }
    finally:
        for k, v in saved.items():
            try:
                session.params.set(k, v)
            except NaturaError:
                pass
    out["seconds"] = time.perf_counter() - t0
    return out


# ---- chart and summary -----------------------------------------------------------------------

FLOOR = 1e-4
SYMLOG_LINEAR = 1e-2


def _time_against(ax, s: dict, rows: list, gerstner: list, key: str) -> None:
    """ms per frame against ``key``: a line per FFT size (labels: cascades), one for the
    Gerstner sets (labels: waves)."""
    for n in s["fft"]["fft_sizes"]:
        line = [r for r in rows if r["fft_size"] == n]
        if line:
            ax.plot([r["ms_frame"] for r in line], [r[key] for r in line], "o-",
                    label=f"FFT N = {n}")
            for r in line:
                ax.annotate(str(r["cascades"]), (r["ms_frame"], r[key]), fontsize=8,
                            textcoords="offset points", xytext=(3, 3))
    if gerstner:
        ax.plot([r["ms_frame"] for r in gerstner], [r[key] for r in gerstner], "s--", color="k",
                label="Gerstner (waves)")
        for r in gerstner:
            ax.annotate(f"{r['waves']}w", (r["ms_frame"], r[key]), fontsize=8,
                        textcoords="offset points", xytext=(3, -9))
    ax.set_xlabel(f"ms per frame at {s['view_size'][0]}×{s['view_size'][1]} (labels: cascades)")


def chart(report: dict, path, force: bool = False) -> None:
    plt = pyplot()

    s = report["sweep"]
    fig, axes = plt.subplots(2, 2, figsize=(14, 10))
    axes = axes.ravel()
    ax = axes[0]
    rows = [r for r in s["fft"]["rows"] if "skipped" not in r]
    g = [r for r in s["gerstner"]["rows"] if r["model"] == "gerstner" and "skipped" not in r]
    _time_against(ax, s, rows, g, "mss_deficit")
    f = [r for r in s["gerstner"]["rows"] if r["model"] == "fft" and "skipped" not in r]
    for r in f:
        ax.plot([r["ms_frame"]], [r["mss_deficit"]], "*", ms=13, color="tab:red",
                label=f"FFT {r['fft_size']}, {r['cascades']} cascades (Gerstner comparison)")
    # symlog: a random draw of h0 can hold slightly more slope than the reference (deficit < 0)
    ax.set_yscale("symlog", linthresh=SYMLOG_LINEAR)
    ax.axhline(0.0, color="0.6", lw=0.5)
    ax.set(ylabel=f"mss deficit 1 − mss/mss_ref (symlog, linear below {SYMLOG_LINEAR:g})",
           title="(a) time against slope error")
    ax.legend(fontsize=7)

    ax = axes[1]
    d = s["direct_sum"]["rows"]
    ns = [r["fft_size"] for r in d]
    ax.plot(ns, [r["ms_fft"] for r in d], "o-", label="GPU FFT (GpuOceanSim.update)")
    ax.plot(ns, [r["ms_direct"] for r in d], "s-", label="direct sum (direct_sum)")
    for r in d:
        ax.annotate(f"×{r['speedup']:.0f}", (r["fft_size"], r["ms_direct"]), fontsize=8,
                    textcoords="offset points", xytext=(4, -10))
    ax.set_xscale("log", base=2)
    ax.set(yscale="log", xlabel="N (one cascade)", ylabel="ms",
           title="(b) FFT against direct sum (labels: speed-up)")
    ax.legend(fontsize=8)

    ax = axes[2]
    for n in s["fft"]["fft_sizes"]:
        line = [r for r in rows if r["fft_size"] == n]
        if line:
            ax.plot([r["cascades"] for r in line], [max(r["hs_error"], FLOOR) for r in line],
                    "o-", label=f"N = {n} (actual h0)")
            ax.plot([r["cascades"] for r in line],
                    [max(r["hs_error_expected"], FLOOR) for r in line], ":",
                    color=ax.lines[-1].get_color())
    for r in g:
        ax.axhline(max(r["hs_error"], FLOOR), color="k", lw=0.5, ls="--")
    ax.set_yscale("log")
    ax.set_xticks(list(s["fft"]["cascades"]))
    ax.set(xlabel="cascades (dotted: expectation of h0; dashed: Gerstner sets)",
           ylabel=f"Hs error |Hs − Hs_ref|/Hs_ref (floored at {FLOOR:g})", title="(c) Hs error")
    ax.legend(fontsize=7)
    ax = axes[3]
    _time_against(ax, s, rows, g, "shape_distance")
    ax.set_ylim(0.0, 1.0)
    ax.set(ylabel="spectrum shape distance (½ L1 over log k × direction bins)",
           title="(d) time against how well the waves fill the directional spectrum")
    ax.legend(fontsize=7)
    write_chart(fig, path, force,
                title=f"natura bench ocean — {report.get('renderer', s.get('renderer'))}, "
                      f"{s['spectrum']}, U = {s['wind']:g} m/s")


def _pct(x) -> str:
    return "   n/a" if x is None else f"{100.0 * x:6.2f}%"


def shading_summary(c: dict) -> list[str]:
    """Lines of the forward/deferred comparison."""
    w, h = c["view_size"]
    r = c["ratio"]
    lines = [f"{TITLES['shading']} at {w}x{h} ({c['model']}, {c['rounds']} interleaved rounds):"]
    for mode in SHADINGS:
        t = c[mode]
        lines.append(f"  {mode:9s} {t['median_ms']:8.1f} ms  [{t['p25_ms']:.1f}–{t['p75_ms']:.1f}]")
    lines.append(f"  deferred/forward ×{r['median']:.3f} [{r['p25']:.3f}–{r['p75']:.3f}] "
                 "per round; "
                 f"image mean |Δ| {c['mean_abs_diff']:.2e}, max |Δ| {c['max_abs_diff']:.2e} "
                 f"(max radiance {c['max_radiance']:.3g})")
    return lines


def summary(report: dict) -> str:
    s = report["sweep"]
    ref = s["reference"]
    lines = shading_summary(s["shading"]) if "shading" in s else []
    if "simulation" in s:
        lines += simulation_summary(s["simulation"])
    lines += [f"reference: {s['spectrum']}, U = {s['wind']:g} m/s, Hs = {ref['hs']:.3f} m, "
              f"mss = {ref['mss']:.4g}, "
              f"Tp = {ref['tp_s'] or float('nan'):.2f} s, k ≤ {ref['k_ref']:.0f} rad/m",
              f"{TITLES['fft']} at {s['view_size'][0]}x{s['view_size'][1]}:",
              "  N    casc   frame ms   sim ms   mss deficit (expected)    Hs error (expected)   "
              "shape"]
    for r in s["fft"]["rows"]:
        if "skipped" in r:
            lines.append(f"  {r['fft_size']:<4d} {r['cascades']:4d}   skipped: {r['skipped']}")
            continue
        lines.append(f"  {r['fft_size']:<4d} {r['cascades']:4d} {r['ms_frame']:10.1f} "
                     f"{r['ms_sim']:8.1f}   "
                     f"{_pct(r['mss_deficit'])} ({_pct(r['mss_deficit_expected'])})       "
                     f"{_pct(r['hs_error'])} ({_pct(r['hs_error_expected'])})   "
                     f"{r['shape_distance']:.3f}")
    lines.append(f"{TITLES['gerstner']} (equal Hs and peak period):")
    lines.append("  model            frame ms   Hs m     Hs err    Tp s    Tp err   "
                 "mss deficit  shape  directions")
    for r in s["gerstner"]["rows"]:
        label = (f"gerstner {r['waves']}" if r["model"] == "gerstner"
                 else f"fft {r['fft_size']}×{r['cascades']}")
        if "skipped" in r:
            lines.append(f"  {label:16s} skipped: {r['skipped']}")
            continue
        dirs = r.get("distinct_directions", "grid")
        lines.append(f"  {label:16s} {r['ms_frame']:8.1f} {r['hs']:7.3f} {_pct(r['hs_error'])} "
                     f"{r['tp_s'] or float('nan'):7.2f} {_pct(r['tp_error'])}  "
                     f"{_pct(r['mss_deficit'])}  "
                     f"{r['shape_distance']:.3f}  {dirs}")
    lines.append("  shape: half the L1 distance between the sea's variance over (log k, direction) "
                 "bins and the spectrum's (0 = same shape, 1 = disjoint)")
    lines.append(f"{TITLES['direct_sum']} (one cascade, L = {s['direct_sum']['patch_size']:g} m):")
    lines.append("  N     modes    FFT ms   direct ms   speed-up   max|Δη|/max|η|")
    for r in s["direct_sum"]["rows"]:
        lines.append(f"  {r['fft_size']:<4d} {r['modes']:7d} {r['ms_fft']:9.2f} "
                     f"{r['ms_direct']:11.2f}   "
                     f"×{r['speedup']:<8.1f} {r['rel_diff']:.2e}")
    for sk in s["direct_sum"]["skipped"]:
        lines.append(f"  {sk['fft_size']:<4d} skipped: {sk['reason']}")
    if "oceanography" in s:
        lines.append(oceanography_summary(s["oceanography"]))
    lines.append(f"sweeps took {s.get('seconds', float('nan')):.0f} s; "
                 f"figures are specific to {s['renderer']}")
    return "\n".join(lines)

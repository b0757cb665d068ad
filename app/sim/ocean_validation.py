"""The ocean against oceanography (beyond the thesis), as figures a report can quote.

``oceanography()`` measures, on the numpy reference (and on the GPU simulation when a
measurement of it is given, through its read-back fields):

* **significant wave height** of a fully developed Pierson–Moskowitz sea, 4·std(η), against
  Hs = 0.21·U²/g for U = 5…20 m/s (one realisation on a grid 10 peak wavelengths wide, which
  holds > 99 % of the variance);
* **phase speed** of a single Fourier mode against sqrt(g/k) and, in 2 m of water,
  sqrt(g/k·tanh(k·d));
* **wind alignment**: energy with |cos θ| > 0.7 over energy with |cos θ| < 0.3, and the drift of
  the height field between two frames 2 s apart along the wind, against the peak phase speed;
* **mean-square slope** against Cox & Munk's 0.003 + 5.12·10⁻³·U: a grid without sub-grid
  detail falls below it (the ocean's glitter adds the remainder, ``ocean.subgrid_slopes``).

Beside it, the metrics ``natura bench ocean`` charts for a sea against its own spectrum: the
moments the cascades carry (``cascade_moments``), the peak period of an FFT sea, a Gerstner set
and a spectrum, and how well a wave set fills the directional spectrum (``shape_distance``).
"""

from __future__ import annotations

import math

import numpy as np

from . import ocean as oc

WINDS = (5.0, 10.0, 15.0, 20.0)
PM_HS_COEFF = 0.21


def pm_setup(wind: float, n: int = 256, direction: float = 0.0):
    """A fully developed PM sea on an N×N grid 10 peak wavelengths wide."""
    kp = oc.pierson_moskowitz_peak(wind) ** 2 / oc.G
    size = 10 * 2 * math.pi / kp
    return (oc.SpectrumParams(kind="pierson_moskowitz", wind_speed=wind,
                              wind_direction=direction), size)


def fields(p, size, n=256, t=3.0, lam=1.0, seed=0):
    """One seeded sea on an N×N grid of side ``size`` at time t:
    (OceanFields, h(k, t), k_x, k_z)."""
    kx, kz = oc.wavenumber_grid(n, size)
    h0 = oc.initial_amplitudes(n, size, p, seed=seed)
    om = oc.dispersion_omega(np.hypot(kx, kz), p.depth)
    h = oc.evolve_amplitudes(h0, om, t)
    return oc.synthesize(h, kx, kz, lam), h, kx, kz


def phase_speed_error(depth: float, n: int = 64, size: float = 100.0, m: int = 3,
                      dt: float = 0.8) -> float:
    """Relative error of one mode's measured phase speed against the dispersion relation."""
    kx, kz = oc.wavenumber_grid(n, size)
    om = oc.dispersion_omega(np.hypot(kx, kz), depth)
    h0 = np.zeros((n, n), complex)
    h0[0, n - m] = 0.5  # h₀(k) travels toward −k̂: this mode goes +x
    k = 2 * math.pi * m / size
    coef = [np.fft.fft2(oc.synthesize(oc.evolve_amplitudes(h0, om, t), kx, kz).height)[0, m]
            for t in (0.0, dt)]
    c = -np.angle(coef[1] / coef[0]) / (k * dt)
    ref = math.sqrt(oc.G / k * (1.0 if math.isinf(depth) else math.tanh(k * depth)))
    return abs(c / ref - 1.0)


def oceanography(gpu_hs=None, seed: int = 0) -> dict:
    """The report. ``gpu_hs(spectrum params, patch size, seed) → Hs`` measures the same seeded
    sea on the GPU (``app.bench.ocean.gpu_significant_height``); without it the GPU rows are
    left out (this module is numpy only)."""
    out: dict = {"hs": [], "mss": [], "phase_speed_error": {
        "deep": phase_speed_error(math.inf), "2 m": phase_speed_error(2.0)}}
    for wind in WINDS:
        p, size = pm_setup(wind)
        f, *_ = fields(p, size, seed=seed + int(wind))
        target = PM_HS_COEFF * wind * wind / oc.G
        row = {"wind": wind, "hs_target": target, "hs_numpy": 4 * float(f.height.std())}
        if gpu_hs is not None:
            row["hs_gpu"] = gpu_hs(p, size, seed + int(wind))
        out["hs"].append(row)
        cm = 0.003 + 5.12e-3 * wind
        out["mss"].append({"wind": wind, "cox_munk": cm,
                           "resolved": float(np.mean(f.slope_x**2 + f.slope_z**2)),
                           "ratio": float(np.mean(f.slope_x**2 + f.slope_z**2)) / cm})
    # wind alignment (JONSWAP, wind 10 m/s toward 0.5 rad)
    wd = 0.5
    p = oc.SpectrumParams(kind="jonswap", wind_speed=10.0, wind_direction=wd)
    kx, kz = oc.wavenumber_grid(256, 840.0)
    e = np.abs(oc.initial_amplitudes(256, 840.0, p, seed=seed + 1)) ** 2
    k = np.hypot(kx, kz)
    cos_t = np.where(k > 0, (kx * math.cos(wd) + kz * math.sin(wd)) / np.where(k > 0, k, 1), 0)
    out["alignment_ratio"] = float(e[np.abs(cos_t) > 0.7].sum()
                                   / e[(np.abs(cos_t) < 0.3) & (k > 0)].sum())
    p, size = pm_setup(10.0, direction=wd)
    f0, *_ = fields(p, size, t=0.0, seed=seed)
    f1, *_ = fields(p, size, t=2.0, seed=seed)
    corr = np.fft.ifft2(np.conj(np.fft.fft2(f0.height)) * np.fft.fft2(f1.height)).real
    iz, ix = np.unravel_index(np.argmax(corr), corr.shape)
    shift = ((np.array([ix, iz]) + 128) % 256 - 128) * size / 256
    cp = oc.G / oc.pierson_moskowitz_peak(10.0)
    out["drift_along_wind_m"] = float(shift @ [math.cos(wd), math.sin(wd)])
    out["drift_expected_m"] = cp * 2.0
    return out


def summary(report: dict) -> str:
    lines = ["oceanography:",
             "  wind  Hs 0.21U²/g  numpy (ratio)   gpu (ratio)   mss/Cox–Munk"]
    for hs, ms in zip(report["hs"], report["mss"]):
        gpu = (f"{hs['hs_gpu']:.3f} ({hs['hs_gpu'] / hs['hs_target']:.3f})" if "hs_gpu" in hs
               else "—")
        lines.append(f"  {hs['wind']:4.0f}  {hs['hs_target']:10.3f}  {hs['hs_numpy']:.3f} "
                     f"({hs['hs_numpy'] / hs['hs_target']:.3f})   {gpu:14s}  {ms['ratio']:.3f}")
    pe = report["phase_speed_error"]
    lines.append(f"  phase speed error: deep {pe['deep']:.1e}, 2 m {pe['2 m']:.1e}")
    lines.append(f"  energy along / across the wind: {report['alignment_ratio']:.1f}; drift in 2 s "
                 f"{report['drift_along_wind_m']:.1f} m along the wind (peak phase speed: "
                 f"{report['drift_expected_m']:.1f} m)")
    return "\n".join(lines)


def spectrum_peak_period(sp: oc.SpectrumParams, k_peak: float) -> float | None:
    """Tp = 2π/ω_p of the spectrum: S(ω)'s peak for JONSWAP and Pierson–Moskowitz, ω(k_peak)
    of the omnidirectional E(k) for Phillips (which has no frequency form)."""
    if sp.wind_speed <= 0:
        return None
    if sp.kind == "phillips":
        w = float(oc.dispersion_omega(k_peak, sp.depth, sp.g))
    else:
        w = sp.peak_omega()
    return 2.0 * math.pi / w


def ratio_errors(mss: float, hs: float, ref: dict) -> dict:
    return {"mss_deficit": (1.0 - mss / ref["mss"]) if ref["mss"] > 0 else None,
            "hs_error": (abs(hs - ref["hs"]) / ref["hs"]) if ref["hs"] > 0 else None}


def cascade_moments(cascades, sp: oc.SpectrumParams) -> dict:
    """mss and Hs of the cascades' actual h₀, and of its expectation ½Ψ(−k)Δk²."""
    m0 = mss = m0_e = mss_e = 0.0
    for c in cascades:
        m, s = c.moments()
        m0 += m
        mss += s
        expected = c.expected_variance(sp)  # Σ(E|h₀(k)|² + E|h₀(−k)|²) = ΣΨ(−k)Δk²
        m0_e += float(expected.sum())
        mss_e += float(((c.kx**2 + c.kz**2) * expected).sum())
    return {"m0": m0, "hs": 4.0 * math.sqrt(m0), "mss": mss,
            "hs_expected": 4.0 * math.sqrt(m0_e), "mss_expected": mss_e}


def fft_peak_period(cascades, sp: oc.SpectrumParams) -> float | None:
    """Tp of the FFT sea: the peak of S(ω) = ring energy / ring Δω of its actual h₀, rings
    2π/L₀ wide (L₀ the coarsest tile)."""
    ks, es = [], []
    for c in cascades:
        h2 = np.abs(np.asarray(c.h0)) ** 2
        nz = h2 > 0
        ks.append(np.hypot(c.kx, c.kz)[nz])
        es.append(2.0 * h2[nz])
    k = np.concatenate(ks)
    e = np.concatenate(es)
    if e.sum() <= 0:
        return None
    dk = 2.0 * math.pi / cascades[0].patch_size
    ring = np.floor(k / dk + 0.5).astype(np.int64)  # ring j covers [(j − ½)Δk, (j + ½)Δk)
    energy = np.bincount(ring, weights=e)
    j = np.arange(len(energy))
    lo = np.maximum(j - 0.5, 0.0) * dk
    hi = (j + 0.5) * dk
    dw = oc.dispersion_omega(hi, sp.depth, sp.g) - oc.dispersion_omega(lo, sp.depth, sp.g)
    s = np.where(dw > 0, energy / np.where(dw > 0, dw, 1.0), 0.0)
    jp = int(np.argmax(s))
    return 2.0 * math.pi / float(oc.dispersion_omega(jp * dk, sp.depth, sp.g))


def gerstner_peak_period(waves, depth: float) -> float:
    """Tp = 2π/ω of the wave with the most energy A²/2."""
    energy = [(w.steepness * w.wavelength / (2.0 * math.pi)) ** 2 for w in waves]
    w = waves[int(np.argmax(energy))]
    return 2.0 * math.pi / float(oc.dispersion_omega(2.0 * math.pi / w.wavelength, depth))


SHAPE_BINS_PER_DECADE = 8
SHAPE_DIRECTIONS = 16


def shape_bins(sp: oc.SpectrumParams, ref: dict):
    """log-k edges (k_p/4 … k_ref, 8 per decade) and the reference's variance share per
    (log k, direction) bin, directions measured from the wind (16 sectors)."""
    k_lo = max(ref["k_peak"] / 4.0, 1e-4) if math.isfinite(ref["k_peak"]) else 1e-3
    decades = math.log10(ref["k_ref"] / k_lo)
    edges = np.geomspace(k_lo, ref["k_ref"],
                         max(2, int(math.ceil(decades * SHAPE_BINS_PER_DECADE))) + 1)
    k, th, psi, dk, dth = oc.polar_spectrum(sp, k_lo, ref["k_ref"], nk=800, nth=144)
    e = psi * (k * dk)[:, None] * dth
    kk = np.repeat(k[:, None], len(th), axis=1)
    tt = np.repeat(th[None, :], len(k), axis=0)  # already relative to the wind
    return edges, direction_histogram(kk.ravel(), tt.ravel(), e.ravel(), edges)


def direction_histogram(k, theta_from_wind, energy, edges):
    ik = np.searchsorted(edges, k) - 1
    it = np.floor((np.angle(np.exp(1j * theta_from_wind)) + math.pi) / (2 * math.pi)
                  * SHAPE_DIRECTIONS)
    it = np.clip(it.astype(np.int64), 0, SHAPE_DIRECTIONS - 1)
    ok = (ik >= 0) & (ik < len(edges) - 1)
    hist = np.zeros((len(edges) - 1, SHAPE_DIRECTIONS))
    np.add.at(hist, (ik[ok], it[ok]), energy[ok])
    total = hist.sum()
    return hist / total if total > 0 else hist


def shape_distance(k, theta_travel, energy, sp: oc.SpectrumParams, bins) -> float:
    """Half the L1 distance (0 = same shape, 1 = disjoint) between a sea's variance over
    (log k, direction) bins and the spectrum's: how well a wave set fills the directional
    spectrum, whatever its Hs and mss."""
    edges, ref_hist = bins
    hist = direction_histogram(np.asarray(k, float),
                               np.asarray(theta_travel, float) - sp.wind_direction,
                               np.asarray(energy, float), edges)
    return 0.5 * float(np.abs(hist - ref_hist).sum())


def fft_shape_distance(cascades, sp, bins) -> float:
    """For the expectation of h₀ (½Ψ(−k)Δk² per mode, so the figure measures the grid and the
    bands, not the luck of one draw): mode k carries a wave travelling toward −k."""
    ks, ts, es = [], [], []
    for c in cascades:
        expected = c.expected_variance(sp)
        held = expected > 0
        ks.append(np.hypot(c.kx, c.kz)[held])
        ts.append(np.arctan2(-c.kz[held], -c.kx[held]))
        es.append(expected[held])
    return shape_distance(np.concatenate(ks), np.concatenate(ts), np.concatenate(es), sp, bins)


def gerstner_shape_distance(waves, sp, bins) -> float:
    k = [2.0 * math.pi / w.wavelength for w in waves]
    t = [math.atan2(w.direction[1], w.direction[0]) for w in waves]
    e = [0.5 * (w.steepness / kk) ** 2 for w, kk in zip(waves, k)]
    return shape_distance(k, t, e, sp, bins)

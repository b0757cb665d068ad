"""The ocean against oceanography (issue 6, item 5), as figures a report can quote.

``oceanography()`` measures, on the numpy reference (and on the GPU simulation when a ``gpu``
is given, through its read-back fields):

* **significant wave height** of a fully developed Pierson–Moskowitz sea, 4·std(η), against
  Hs = 0.21·U²/g for U = 5…20 m/s (one realisation on a grid 10 peak wavelengths wide, which
  holds > 99 % of the variance);
* **phase speed** of a single Fourier mode against sqrt(g/k) and, in 2 m of water,
  sqrt(g/k·tanh(k·d));
* **wind alignment**: energy with |cos θ| > 0.7 over energy with |cos θ| < 0.3, and the drift of
  the height field between two frames 2 s apart along the wind, against the peak phase speed;
* **mean-square slope** against Cox & Munk's 0.003 + 5.12·10⁻³·U: a grid without sub-grid
  detail falls below it (the ocean's glitter adds the remainder, ``ocean.subgrid_slopes``).
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
    return oc.SpectrumParams(kind="pierson_moskowitz", wind_speed=wind, wind_direction=direction), size


def fields(p, size, n=256, t=3.0, lam=1.0, seed=0):
    """One seeded sea on an N×N grid of side ``size`` at time t: (OceanFields, h(k, t), k_x, k_z)."""
    kx, kz = oc.wavenumber_grid(n, size)
    h0 = oc.initial_amplitudes(n, size, p, seed=seed)
    om = oc.dispersion_omega(np.hypot(kx, kz), p.depth)
    h = oc.evolve_amplitudes(h0, om, t)
    return oc.synthesize(h, kx, kz, lam), h, kx, kz


def phase_speed_error(depth: float, n: int = 64, size: float = 100.0, m: int = 3, dt: float = 0.8) -> float:
    """Relative error of one mode's measured phase speed against the dispersion relation."""
    kx, kz = oc.wavenumber_grid(n, size)
    om = oc.dispersion_omega(np.hypot(kx, kz), depth)
    h0 = np.zeros((n, n), complex)
    h0[0, n - m] = 0.5  # h₀(k) travels toward −k̂: this mode goes +x
    k = 2 * math.pi * m / size
    coef = [np.fft.fft2(oc.synthesize(oc.evolve_amplitudes(h0, om, t), kx, kz).height)[0, m] for t in (0.0, dt)]
    c = -np.angle(coef[1] / coef[0]) / (k * dt)
    ref = math.sqrt(oc.G / k * (1.0 if math.isinf(depth) else math.tanh(k * depth)))
    return abs(c / ref - 1.0)


def oceanography(gpu=None, seed: int = 0) -> dict:
    out: dict = {"hs": [], "mss": [], "phase_speed_error": {
        "deep": phase_speed_error(math.inf), "2 m": phase_speed_error(2.0)}}
    for wind in WINDS:
        p, size = pm_setup(wind)
        f, *_ = fields(p, size, seed=seed + int(wind))
        target = PM_HS_COEFF * wind * wind / oc.G
        row = {"wind": wind, "hs_target": target, "hs_numpy": 4 * float(f.height.std())}
        if gpu is not None:
            row["hs_gpu"] = _gpu_hs(gpu, p, size, seed + int(wind))
        out["hs"].append(row)
        cm = 0.003 + 5.12e-3 * wind
        out["mss"].append({"wind": wind, "cox_munk": cm, "resolved": float(np.mean(f.slope_x**2 + f.slope_z**2)),
                           "ratio": float(np.mean(f.slope_x**2 + f.slope_z**2)) / cm})
    # wind alignment (JONSWAP, wind 10 m/s toward 0.5 rad)
    wd = 0.5
    p = oc.SpectrumParams(kind="jonswap", wind_speed=10.0, wind_direction=wd)
    kx, kz = oc.wavenumber_grid(256, 840.0)
    e = np.abs(oc.initial_amplitudes(256, 840.0, p, seed=seed + 1)) ** 2
    k = np.hypot(kx, kz)
    cos_t = np.where(k > 0, (kx * math.cos(wd) + kz * math.sin(wd)) / np.where(k > 0, k, 1), 0)
    out["alignment_ratio"] = float(e[np.abs(cos_t) > 0.7].sum() / e[(np.abs(cos_t) < 0.3) & (k > 0)].sum())
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


def _gpu_hs(gpu, p, size, seed) -> float:
    from ..effects.ocean.fft import GpuOceanSim

    ref = oc.FFTOcean(p, n=256, patch_sizes=(size,), choppiness=1.0, seed=seed)
    sim = GpuOceanSim(gpu, "validation")
    try:
        sim.set_spectrum(ref.cascades, 256)
        sim.update(3.0, 1.0, 0.0)
        return 4.0 * float(np.std(sim.read_fields(0)["height"]))
    finally:
        sim.release()


def summary(report: dict) -> str:
    lines = ["oceanography (issue 6, item 5):",
             "  wind  Hs 0.21U²/g  numpy (ratio)   gpu (ratio)   mss/Cox–Munk"]
    for hs, ms in zip(report["hs"], report["mss"]):
        gpu = f"{hs['hs_gpu']:.3f} ({hs['hs_gpu'] / hs['hs_target']:.3f})" if "hs_gpu" in hs else "—"
        lines.append(f"  {hs['wind']:4.0f}  {hs['hs_target']:10.3f}  {hs['hs_numpy']:.3f} "
                     f"({hs['hs_numpy'] / hs['hs_target']:.3f})   {gpu:14s}  {ms['ratio']:.3f}")
    pe = report["phase_speed_error"]
    lines.append(f"  phase speed error: deep {pe['deep']:.1e}, 2 m {pe['2 m']:.1e}")
    lines.append(f"  energy along / across the wind: {report['alignment_ratio']:.1f}; drift in 2 s "
                 f"{report['drift_along_wind_m']:.1f} m along the wind (peak phase speed: "
                 f"{report['drift_expected_m']:.1f} m)")
    return "\n".join(lines)

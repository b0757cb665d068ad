"""Ocean waves on the CPU — the numpy reference of spec/000 §1.1–1.3 (thesis chapter 2 and
§3 buoyancy queries; FFT ocean after Tessendorf 2001 and Horvath 2015, as in gasgiant's
FFT-Ocean which the thesis adopted).

Frame: right-handed, y up; the sea surface is the (x, z) plane.  Grids are indexed ``[iz, ix]``
with sample j at ``j·L/N`` (periodic, period L).  Units: metres, seconds, radians; wavenumbers in
rad/m, angular frequencies in rad/s; ``g`` = 9.81 m/s².

What each function implements
-----------------------------
Each function's docstring gives its equation; what they share, and where the thesis is wrong:

* the sine wave (spec/000 §1.1(a)) and ``gerstner`` (spec/000 §1.1(c)): the normal is
  **B × T** (spec/000 eq. 2.4 prints T × B, which points down in a right-handed y-up frame —
  erratum); the horizontal Jacobian det ∂(X,Z)/∂(x,z) (= 1 − s·sin f for one wave: loops where
  < 0). ``check_gerstner_steepness`` enforces 0 ≤ s ≤ 1 per wave (the thesis's bound; for
  several waves loops are only excluded when Σ s ≤ 1 — the Jacobian shows it).
* ``dispersion_omega`` — ω² = g·k·tanh(k·d) (the thesis prints *tan*: erratum).
* Frequency spectra S(ω) [m²·s/rad]: ``pierson_moskowitz`` (U at 19.5 m: Hs = 0.209·U²/g),
  ``jonswap`` (Hasselmann et al. 1973 with fetch), ``tma_correction`` (Kitaigorodskii depth
  factor in Thompson & Vincent's piecewise form, as Horvath 2015 and gasgiant's FFT-Ocean use
  it; applied to JONSWAP and PM alike).
* Directional spreading D(θ, ω), ∫D dθ = 1 over (−π, π]: ``spreading_hasselmann`` — the
  documented choice: Longuet-Higgins cos^{2s}(θ/2) with Hasselmann et al. 1980's s(ω/ω_p)
  (s ≈ 7–10 at the peak, falling above it: long waves follow the wind, short ones spread, as the
  thesis says).  ``spreading_cos2s`` is the same with a fixed s.
* ``phillips`` — Tessendorf's Phillips spectrum scaled physically (L_w = U²/g: its k⁻³ tail
  then equals Pierson–Moskowitz's).
* ``directional_spectrum`` — any of the three as a wavenumber spectrum Ψ(k_x, k_z) [m⁴]:
  Ψ = S(ω(k))·D(θ, ω)·(dω/dk)/k (the Jacobian factor of spec/000 eq. 2.10, with the
  finite-depth dispersion), times TMA when ``depth`` is finite, times the short-wave fade
  exp(−(k·ℓ)²) (Tessendorf's small-wave suppression; ℓ = ``short_wave_fade``, 0 = off).
* ``initial_amplitudes`` — spec/000 eq. 2.10, with two deliberate differences: (1) the factor
  is ½, not 2 — with the Hermitian pair below, var η = Σ(|h₀(k)|² + |h₀(−k)|²) must equal
  ∫Ψ d²k; with the printed 2 Hs would come out twice too large (the Hs test checks this); (2) Ψ
  is sampled at −k because with η = Σ h·e^{ik·x} the term h₀(k)·e^{iωt} travels towards −k̂ — so
  the energy travels down-wind.
* ``evolve_amplitudes`` — spec/000 eq. 2.11 with the conjugate the thesis dropped (Tessendorf
  2001 eq. 26): the field is real.
* ``synthesize`` — the choppy displacement of spec/000 §1.1(d) (displaced point x + λ·D:
  crests sharpen) and the Jacobian J that drives foam (``foam_step``); ``surface_normals`` clamps
  its slope formula's denominators to ≥ 1e-3 (they reach 0 where the surface folds, J ≤ 0; the
  normal is then steep but finite and still has n.y > 0).
* ``cascade_bands`` / ``FFTOcean`` — 1–4 cascades (defaults N = 256, L = 250 / 17 / 5 m, the
  upstream's).  Band split: cascade i keeps |k| ∈ [k_i, k_{i+1}) with k_0 = 0,
  k_i = min(``boundary_factor``·2π/L_i, π·N/L_{i−1}) (default factor 6: the finest waves a
  cascade leaves to the next one are six of that cascade's fundamentals, so its tiling needs six
  wavelengths to repeat; the min hands over at the coarser cascade's Nyquist when N is small)
  and the last upper edge the last cascade's Nyquist π·N/L.  Every edge must lie inside the
  range the cascade can represent (ParamError otherwise), so bands never overlap and never
  leave a gap.  Defaults: [0, 2.218), [2.218, 7.540), [7.540, 160.8] rad/m.
* ``invert_horizontal_displacement`` (spec/000 §1.3 / fig. 3.2, gasgiant's GetWaterHeight) and
  ``floating_points_pose`` (fig. 3.1 read as edge vectors on the displaced surface: a spec
  inference) answer the buoyancy's queries; ``FFTOcean.water_height`` gives height,
  displacement and normal at world points.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from ..errors import ParamError
from .vec import length, norm

G = 9.81  # m/s²
SPECTRA = ("phillips", "pierson_moskowitz", "jonswap")


# ---- Sine wave (spec/000 §1.1(a)) -----------------------------------------------------------


def sine_wave_height(x, t: float, amplitude: float, wavenumber: float, omega: float):
    """spec/000 eq. 2.1: y = A·sin(kx + ωt) [m] at x [m], time t [s]."""
    return amplitude * np.sin(wavenumber * np.asarray(x, dtype=float) + omega * t)


def sine_wave_normal(x, t: float, amplitude: float, wavenumber: float, omega: float):
    """spec/000 eq. 2.2: unit normal (−kA·cos(kx+ωt), 1, 0)/‖·‖ = B × T normalised, with
    T = ∂P/∂x = (1, kA·cos(kx+ωt), 0) and B = ẑ (spec/000 §1.1(a)); shape (..., 3)."""
    x = np.asarray(x, dtype=float)
    sx = amplitude * wavenumber * np.cos(wavenumber * x + omega * t)
    n = np.stack([-sx, np.ones_like(sx), np.zeros_like(sx)], axis=-1)
    return n / np.linalg.norm(n, axis=-1, keepdims=True)



def _tanh_kd(k, depth):
    if math.isinf(depth):
        return np.ones_like(k)
    if depth <= 0:
        raise ParamError(f"ocean.depth: {depth} m is outside the allowed range (0, inf]")
    return np.tanh(k * depth)


def dispersion_omega(k, depth: float = math.inf, g: float = G):
    """ω(k) = sqrt(g·k·tanh(k·d)) [rad/s] (tanh, not the thesis's tan); d = inf → sqrt(g·k)."""
    k = np.abs(np.asarray(k, dtype=float))
    return np.sqrt(g * k * _tanh_kd(k, depth))


def dispersion_domega_dk(k, depth: float = math.inf, g: float = G):
    """Group speed dω/dk [m/s] = g·(tanh(kd) + kd·sech²(kd))/(2ω); at k = 0: sqrt(g·d) or inf."""
    k = np.abs(np.asarray(k, dtype=float))
    th = _tanh_kd(k, depth)
    kd_sech2 = np.zeros_like(k) if math.isinf(depth) else k * depth * (1.0 - th * th)
    w = np.sqrt(g * k * th)
    with np.errstate(divide="ignore", invalid="ignore"):
        cg = g * (th + kd_sech2) / (2.0 * w)
    k0 = math.inf if math.isinf(depth) else math.sqrt(g * depth)
    return np.where(k > 0, cg, k0)


def phase_speed(k, depth: float = math.inf, g: float = G):
    """Phase speed c = ω/k [m/s]: sqrt(g/k) in deep water, sqrt(g/k·tanh(kd)) in general."""
    k = np.abs(np.asarray(k, dtype=float))
    with np.errstate(divide="ignore", invalid="ignore"):
        c = dispersion_omega(k, depth, g) / k
    k0 = math.inf if math.isinf(depth) else math.sqrt(g * depth)
    return np.where(k > 0, c, k0)


# ---- Gerstner waves (spec/000 §1.1(c)) ------------------------------------------------------


@dataclass(frozen=True)
class GerstnerWave:
    """One Gerstner wave: ``direction`` (D_x, D_z) (normalised on use), ``wavelength`` λ [m] > 0,
    ``steepness`` s = k·A in [0, 1], ``phase`` [rad]."""

    direction: tuple[float, float]
    wavelength: float
    steepness: float
    phase: float = 0.0


@dataclass
class GerstnerSurface:
    position: np.ndarray  # (..., 3) displaced point, spec/000 eq. 2.5
    tangent: np.ndarray  # (..., 3) ∂P/∂x, spec/000 eq. 2.7
    binormal: np.ndarray  # (..., 3) ∂P/∂z, spec/000 eq. 2.8
    normal: np.ndarray  # (..., 3) unit B × T (upward)
    jacobian: np.ndarray  # (...,) det ∂(X, Z)/∂(x, z); < 0 → loops


def check_gerstner_steepness(waves: Sequence[GerstnerWave]) -> None:
    """Raise a one-line ParamError for the first wave outside 0 ≤ s ≤ 1 or with λ ≤ 0, D = 0."""
    for i, w in enumerate(waves):
        if not (0.0 <= w.steepness <= 1.0):
            raise ParamError(
                f"ocean.gerstner wave {i}: steepness {w.steepness:g} is outside the allowed "
                "range [0, 1] (s > 1 makes loops at the crests)"
            )
        if not w.wavelength > 0:
            raise ParamError(
                f"ocean.gerstner wave {i}: wavelength {w.wavelength:g} m is outside the allowed "
                "range (0, inf)"
            )
        if math.hypot(*w.direction) == 0:
            raise ParamError(f"ocean.gerstner wave {i}: direction must be a non-zero 2-vector")


def gerstner(x, z, t: float, waves: Sequence[GerstnerWave], *, depth: float = math.inf,
             g: float = G, check: bool = True) -> GerstnerSurface:
    """Sum of Gerstner waves at rest positions (x, z) [m], time t [s]: spec/000 eq. 2.5,
    spec/000 eq. 2.7, spec/000 eq. 2.8, and the normal B × T (spec/000 eq. 2.4, order fixed).

    ω comes from ``dispersion_omega`` (deep water: c = sqrt(g/k), as the thesis).  ``check=False``
    skips the steepness bound — only for tests and stability sweeps that need loops (s > 1).
    """
    if check:
        check_gerstner_steepness(waves)
    x = np.asarray(x, dtype=float)
    z = np.asarray(z, dtype=float)
    d = np.array([w.direction for w in waves], dtype=float).reshape(-1, 2)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    k = 2.0 * np.pi / np.array([w.wavelength for w in waves], dtype=float)
    s = np.array([w.steepness for w in waves], dtype=float)
    ph = np.array([w.phase for w in waves], dtype=float)
    a = s / k
    om = dispersion_omega(k, depth, g)
    dx, dz = d[:, 0], d[:, 1]
    f = k * (dx * x[..., None] + dz * z[..., None]) - om * t + ph
    sf, cf = np.sin(f), np.cos(f)
    px = x + np.sum(dx * a * cf, axis=-1)
    py = np.sum(a * sf, axis=-1)
    pz = z + np.sum(dz * a * cf, axis=-1)
    txx = 1.0 - np.sum(dx * dx * s * sf, axis=-1)
    txy = np.sum(dx * s * cf, axis=-1)
    xz = -np.sum(dx * dz * s * sf, axis=-1)
    bzy = np.sum(dz * s * cf, axis=-1)
    bzz = 1.0 - np.sum(dz * dz * s * sf, axis=-1)
    tangent = np.stack([txx, txy, xz], axis=-1)
    binormal = np.stack([xz, bzy, bzz], axis=-1)
    n = np.cross(binormal, tangent)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    jac = txx * bzz - xz * xz
    return GerstnerSurface(np.stack([px, py, pz], axis=-1), tangent, binormal, n, jac)



def pierson_moskowitz_peak(wind_speed: float, g: float = G) -> float:
    """ω_p = 0.877·g/U [rad/s] (= (0.74·4/5)^¼·g/U, U at 19.5 m)."""
    return (0.74 * 0.8) ** 0.25 * g / wind_speed


def pierson_moskowitz(omega, wind_speed: float, g: float = G):
    """S(ω) = α·g²·ω⁻⁵·exp(−5/4·(ω_p/ω)⁴), α = 8.1e-3 [m²·s/rad]; U ≤ 0 → 0."""
    omega = np.asarray(omega, dtype=float)
    if wind_speed <= 0:
        return np.zeros_like(omega)
    wp = pierson_moskowitz_peak(wind_speed, g)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        s = 8.1e-3 * g * g / omega**5 * np.exp(-1.25 * (wp / omega) ** 4)
    return np.where(omega > 0, s, 0.0)


def jonswap_peak(wind_speed: float, fetch: float, g: float = G) -> float:
    """ω_p = 22·(g²/(U·F))^(1/3) [rad/s], fetch F [m]."""
    return 22.0 * (g * g / (wind_speed * fetch)) ** (1.0 / 3.0)


def jonswap(omega, wind_speed: float, fetch: float, gamma: float = 3.3, g: float = G):
    """JONSWAP S(ω) = α·g²·ω⁻⁵·exp(−5/4·(ω_p/ω)⁴)·γ^r, r = exp(−(ω−ω_p)²/(2σ²ω_p²)),
    σ = 0.07 (ω ≤ ω_p) / 0.09, α = 0.076·(U²/(F·g))^0.22 [m²·s/rad]; U ≤ 0 → 0."""
    omega = np.asarray(omega, dtype=float)
    if fetch <= 0:
        raise ParamError(f"ocean.fetch: {fetch} m is outside the allowed range (0, inf)")
    if gamma < 1:
        raise ParamError(f"ocean.gamma: {gamma} is outside the allowed range [1, inf)")
    if wind_speed <= 0:
        return np.zeros_like(omega)
    wp = jonswap_peak(wind_speed, fetch, g)
    alpha = 0.076 * (wind_speed**2 / (fetch * g)) ** 0.22
    sigma = np.where(omega <= wp, 0.07, 0.09)
    r = np.exp(-((omega - wp) ** 2) / (2.0 * sigma**2 * wp**2))
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        s = alpha * g * g / omega**5 * np.exp(-1.25 * (wp / omega) ** 4) * gamma**r
    return np.where(omega > 0, s, 0.0)


def tma_correction(omega, depth: float, g: float = G):
    """Kitaigorodskii depth factor Φ(ω_h), ω_h = ω·sqrt(d/g): ½ω_h² (ω_h ≤ 1),
    1 − ½(2 − ω_h)² (ω_h < 2), 1 beyond; 1 for d = inf."""
    omega = np.asarray(omega, dtype=float)
    if math.isinf(depth):
        return np.ones_like(omega)
    wh = omega * math.sqrt(depth / g)
    return np.where(wh <= 1.0, 0.5 * wh * wh, np.where(wh < 2.0, 1.0 - 0.5 * (2.0 - wh) ** 2, 1.0))


def _lgamma_difference(s: np.ndarray) -> np.ndarray:
    """ln Γ(s+1) − ln Γ(s+½) per element of ``s``, ``math.lgamma`` once per distinct value.

    Why: numpy has no lgamma, and one Python call per grid cell was most of the cost of a
    spectrum; s depends on ω alone (a polar grid of 1200 × 360 cells holds 1200 values, an FFT
    grid's |k| repeat eightfold), and each value's difference is the same float operations as
    per cell, so the result is bit-identical. Runs of equal neighbours (a polar grid's rows)
    are collapsed before the sort that finds the distinct values."""
    flat = s.reshape(-1)
    if flat.size == 0:
        return np.zeros(s.shape)
    start = np.flatnonzero(np.concatenate(([True], flat[1:] != flat[:-1])))
    values, where = np.unique(flat[start], return_inverse=True)
    diff = np.array([math.lgamma(v + 1.0) - math.lgamma(v + 0.5) for v in values.tolist()],
                    dtype=float)
    runs = np.diff(np.append(start, flat.size))
    return np.repeat(diff[where.reshape(-1)], runs).reshape(s.shape)


def spreading_cos2s(theta, s):
    """Longuet-Higgins D(θ) = Q(s)·cos^{2s}(θ/2), Q = Γ(s+1)/(2·sqrt(π)·Γ(s+½)); θ from the wind."""
    theta = np.asarray(theta, dtype=float)
    s = np.broadcast_to(np.asarray(s, dtype=float), theta.shape)
    q = np.exp(_lgamma_difference(s)) / (2.0 * math.sqrt(math.pi))
    c = np.abs(np.cos(0.5 * theta))
    return q * c ** (2.0 * s)


def hasselmann_s(omega, omega_peak: float, wind_speed: float, g: float = G):
    """Hasselmann et al. 1980: s = 6.97·(ω/ω_p)^4.06 (ω ≤ ω_p),
    9.77·(ω/ω_p)^(−2.33 − 1.45·(U·ω_p/g − 1.17)) above."""
    r = np.asarray(omega, dtype=float) / omega_peak
    mu = -2.33 - 1.45 * (wind_speed * omega_peak / g - 1.17)
    with np.errstate(divide="ignore"):
        return np.where(r <= 1.0, 6.97 * r**4.06, 9.77 * r**mu)


def spreading_hasselmann(theta, omega, omega_peak: float, wind_speed: float, g: float = G):
    """D(θ, ω) = cos^{2s}(θ/2) spreading with Hasselmann's s(ω) (s clipped to [0, 100])."""
    s = np.clip(hasselmann_s(omega, omega_peak, wind_speed, g), 0.0, 100.0)
    return spreading_cos2s(theta, s)


def phillips(kx, kz, wind_speed: float, wind_direction: float, *, alpha: float = 8.1e-3,
             against_wind: float = 0.0, g: float = G):
    """Tessendorf's Phillips spectrum Ψ(k) [m⁴] = ½α·k⁻⁴·e^{−1/(k·L_w)²}·cos²θ·w/(π/2·(1+w_b)),
    L_w = U²/g, θ from the wind; w = 1 down-wind, ``against_wind`` (w_b) up-wind."""
    kx = np.asarray(kx, dtype=float)
    kz = np.asarray(kz, dtype=float)
    if wind_speed <= 0:
        return np.zeros(np.broadcast(kx, kz).shape)
    k = np.hypot(kx, kz)
    lw = wind_speed**2 / g
    cos_t = np.where(k > 0, (kx * math.cos(wind_direction) + kz * math.sin(wind_direction))
                     / np.where(k > 0, k, 1.0), 0.0)
    w = np.where(cos_t >= 0, 1.0, against_wind)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        psi = 0.5 * alpha / k**4 * np.exp(-1.0 / (k * lw) ** 2) * cos_t**2 * w
    return np.where(k > 0, psi / (0.5 * math.pi * (1.0 + against_wind)), 0.0)


@dataclass(frozen=True)
class SpectrumParams:
    """Sea state: ``kind`` one of SPECTRA; wind speed U [m/s] (19.5 m), wind direction [rad]
    from +x towards +z, fetch [m] (JONSWAP), γ (JONSWAP), depth [m] (inf = deep), short-wave
    fade ℓ [m] (0 = off)."""

    kind: str = "jonswap"
    wind_speed: float = 10.0
    wind_direction: float = 0.0
    fetch: float = 100_000.0
    gamma: float = 3.3
    depth: float = math.inf
    short_wave_fade: float = 0.0
    phillips_against_wind: float = 0.0
    g: float = G

    def validate(self) -> None:
        if self.kind not in SPECTRA:
            raise ParamError(f"ocean.spectrum: {self.kind!r} is not one of {', '.join(SPECTRA)}")
        if not 0.0 <= self.wind_speed <= 60.0:
            raise ParamError(
                f"ocean.wind: {self.wind_speed} m/s is outside the allowed range [0, 60]")
        if not self.depth > 0:
            raise ParamError(f"ocean.depth: {self.depth} m is outside the allowed range (0, inf]")
        if self.short_wave_fade < 0:
            raise ParamError(
                f"ocean.short_wave_fade: {self.short_wave_fade} m is outside [0, inf)")

    def peak_omega(self) -> float:
        if self.kind == "jonswap":
            return jonswap_peak(self.wind_speed, self.fetch, self.g)
        return pierson_moskowitz_peak(self.wind_speed, self.g)


def directional_spectrum(kx, kz, p: SpectrumParams):
    """Wavenumber spectrum Ψ(k_x, k_z) [m⁴] of waves *travelling* along k, ∫Ψ d²k = var η."""
    p.validate()
    kx = np.asarray(kx, dtype=float)
    kz = np.asarray(kz, dtype=float)
    k = np.hypot(kx, kz)
    if p.wind_speed <= 0:
        return np.zeros_like(k)
    if p.kind == "phillips":
        psi = phillips(kx, kz, p.wind_speed, p.wind_direction,
                       against_wind=p.phillips_against_wind, g=p.g)
    else:
        w = dispersion_omega(k, p.depth, p.g)
        if p.kind == "pierson_moskowitz":
            s = pierson_moskowitz(w, p.wind_speed, p.g)
        else:
            s = jonswap(w, p.wind_speed, p.fetch, p.gamma, p.g)
        s = s * tma_correction(w, p.depth, p.g)
        theta = np.arctan2(kz, kx) - p.wind_direction
        theta = np.angle(np.exp(1j * theta))
        d = spreading_hasselmann(theta, w, p.peak_omega(), p.wind_speed, p.g)
        with np.errstate(divide="ignore", invalid="ignore"):
            psi = np.where(k > 0, s * d * dispersion_domega_dk(k, p.depth, p.g) / k, 0.0)
    if p.short_wave_fade > 0:
        psi = psi * np.exp(-((k * p.short_wave_fade) ** 2))
    return psi



def wavenumber_grid(n: int, patch_size: float):
    """(k_x, k_z) [rad/m], each (N, N) in numpy FFT order, indexed [iz, ix]; Δk = 2π/L."""
    k1 = 2.0 * np.pi * np.fft.fftfreq(n, d=patch_size / n)
    kz, kx = np.meshgrid(k1, k1, indexing="ij")
    return kx, kz


def _negate_index(a):
    """a(−k) on an FFT-ordered grid: index j → (N − j) mod N on the last two axes."""
    return np.roll(np.flip(a, axis=(-2, -1)), 1, axis=(-2, -1))


def band_mask(kx, kz, band: tuple[float, float]):
    """The modes a cascade holds: |k| in [band), k ≠ 0, and neither the Nyquist row nor column."""
    n = kx.shape[-1]
    k = np.hypot(kx, kz)
    keep = (k >= band[0]) & (k < band[1]) & (k > 0)
    keep[n // 2, :] = False
    keep[:, n // 2] = False
    return keep


def initial_amplitudes(n: int, patch_size: float, params: SpectrumParams, *, seed: int = 0,
                       band: tuple[float, float] = (0.0, math.inf)):
    """spec/000 eq. 2.10 (corrected): h₀(k) = (ξ₁+iξ₂)/√2·sqrt(½·Ψ(−k)·Δk²), |k| ∈ [band);
    complex (N, N).

    k = 0 and the Nyquist row and column are zero.  Seeded with numpy's default_rng(seed)."""
    if n < 4 or n & (n - 1):
        raise ParamError(f"ocean.fft_size: {n} is not a power of two ≥ 4")
    if not patch_size > 0:
        raise ParamError(f"ocean.patch_size: {patch_size} m is outside the allowed range (0, inf)")
    kx, kz = wavenumber_grid(n, patch_size)
    dk = 2.0 * np.pi / patch_size
    psi = directional_spectrum(-kx, -kz, params)
    keep = band_mask(kx, kz, band)
    rng = np.random.default_rng(seed)
    xi = rng.standard_normal((2, n, n))
    amp = np.sqrt(0.5 * psi * dk * dk) * keep
    return (xi[0] + 1j * xi[1]) / math.sqrt(2.0) * amp


def evolve_amplitudes(h0, omega, t: float):
    """spec/000 eq. 2.11 with the conjugate: h(k,t) = h₀(k)·e^{iωt} + conj(h₀(−k))·e^{−iωt}."""
    e = np.exp(1j * omega * t)
    return h0 * e + np.conj(_negate_index(h0)) * np.conj(e)


@dataclass
class OceanFields:
    """Real (N, N) fields of one cascade at one time; displacements already times λ."""

    height: np.ndarray  # η [m]
    disp_x: np.ndarray  # λ·D_x [m]
    disp_z: np.ndarray  # λ·D_z [m]
    slope_x: np.ndarray  # ∂η/∂x
    slope_z: np.ndarray  # ∂η/∂z
    ddx_dx: np.ndarray  # λ·∂D_x/∂x
    ddz_dz: np.ndarray  # λ·∂D_z/∂z
    ddx_dz: np.ndarray  # λ·∂D_x/∂z (= λ·∂D_z/∂x)
    jacobian: np.ndarray  # (1 + λD_x,x)(1 + λD_z,z) − (λD_x,z)²
    max_imag_ratio: float  # max|Im|/max|Re| of the inverse FFTs (0 for a Hermitian h)


def synthesize(h, kx, kz, choppiness: float = 1.0) -> OceanFields:
    """Inverse FFTs of h(k,t) (η = N²·ifft2(h)): height, λ·choppy displacement, spectral slopes
    (i·k·h), displacement derivatives and Jacobian."""
    n = h.shape[-1]
    k = np.hypot(kx, kz)
    inv_k = np.where(k > 0, 1.0 / np.where(k > 0, k, 1.0), 0.0)
    lam = choppiness
    spectra = np.stack([
        h,
        1j * kx * inv_k * h * lam,
        1j * kz * inv_k * h * lam,
        1j * kx * h,
        1j * kz * h,
        -kx * kx * inv_k * h * lam,
        -kz * kz * inv_k * h * lam,
        -kx * kz * inv_k * h * lam,
    ])
    out = np.fft.ifft2(spectra, axes=(-2, -1)) * (n * n)
    re, im = out.real, out.imag
    max_re = float(np.max(np.abs(re)))
    ratio = float(np.max(np.abs(im)) / max_re) if max_re > 0 else 0.0
    jac = (1.0 + re[5]) * (1.0 + re[6]) - re[7] ** 2
    return OceanFields(re[0], re[1], re[2], re[3], re[4], re[5], re[6], re[7], jac, ratio)


def surface_normals(slope_x, slope_z, ddx_dx, ddz_dz):
    """Thesis's formula: s = (η_,x/(1+λD_x,x), η_,z/(1+λD_z,z)), n = (−s_x, 1, −s_z)/‖·‖.
    Denominators clamped to ≥ 1e-3 (folds).  Shape (..., 3)."""
    sx = slope_x / np.maximum(1.0 + ddx_dx, 1e-3)
    sz = slope_z / np.maximum(1.0 + ddz_dz, 1e-3)
    n = np.stack([-sx, np.ones_like(sx), -sz], axis=-1)
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


def foam_step(foam, jacobian, dt: float, *, threshold: float = 0.5, decay_time: float = 2.0,
              width: float | None = None):
    """Foam in [0, 1]: decays as e^{−dt/τ} and is raised to clip((threshold − J)/width)
    where the Jacobian says the surface is compressed (J < threshold); width = threshold by
    default (the upstream's ramp from J = threshold to J = 0)."""
    w = threshold if width is None else width
    source = np.clip((threshold - jacobian) / w, 0.0, 1.0)
    return np.maximum(np.asarray(foam) * math.exp(-dt / decay_time), source)


def whitecap_coverage(wind_speed: float) -> float:
    """Monahan & O'Muircheartaigh 1980: fraction of the sea covered by whitecaps,
    W = 3.84·10⁻⁶·U₁₀^3.41, with U₁₀ ≈ U₁₉.₅/1.075 (log wind profile); clipped to [0, 0.5]."""
    u10 = max(wind_speed, 0.0) / 1.075
    return min(3.84e-6 * u10 ** 3.41, 0.5)


def whitecap_thresholds(jacobians: Sequence[np.ndarray], coverage: float,
                        shares: Sequence[float] | None = None):
    """Foam threshold and ramp width per cascade, calibrated on samples of each cascade's
    Jacobian so that half-strength foam (J < T − w/2) covers its share of ``coverage``:
    w = std(J), T = quantile(J, share·coverage) + w/2 (shares equal unless given; they are
    normalised). A flat cascade (std ≈ 0) gets no foam."""
    n = max(len(jacobians), 1)
    shares = np.ones(n) if shares is None else np.asarray(shares, dtype=float)[:n]
    shares = shares / shares.sum()
    out = []
    for jac, share in zip(jacobians, shares):
        jac = np.asarray(jac, dtype=float).ravel()
        w = float(jac.std()) if jac.size else 0.0
        if w <= 1e-9 or coverage <= 0:
            out.append((1e-3, 1.0))  # below any J a real sea reaches: no foam
            continue
        t = float(np.quantile(jac, min(coverage * share, 0.5))) + 0.5 * w
        out.append((max(t, 1e-3), w))
    return out


def sample_periodic_bilinear(grid, patch_size: float, x, z):
    """Bilinear lookup of a periodic grid (N, N) or (N, N, C) indexed [iz, ix], sample j at j·L/N,
    at world points (x, z) [m] of any shape (:func:`sample_periodic_cascades` of one grid)."""
    grid = np.asarray(grid)
    if grid.ndim == 2:
        return sample_periodic_cascades(grid[None, ..., None], (patch_size,), x, z)[..., 0]
    return sample_periodic_cascades(grid[None], (patch_size,), x, z)


def sample_periodic_cascades(grids, patch_sizes, x, z, channels: int | None = None):
    """Σ over the cascades of the bilinear lookup of periodic grid ``grids[c]`` (patch
    ``patch_sizes[c]``) at world points (x, z), summed in cascade order: ``grids`` (C, N, N, K),
    one gather for all cascades (the boat's dozen queries a physics step pay numpy's per-call
    cost once, not C times); ``channels``: only the first that many of the K (the height
    queries leave the Jacobian out). Grids of several sizes: :func:`group_cascade_grids`."""
    grids = np.asarray(grids)
    table = group_cascade_grids(grids if grids.ndim > 3 else grids[..., None], patch_sizes)
    out = sample_cascade_groups(table, x, z, channels)
    return out if grids.ndim > 3 else out.reshape(np.shape(x))


@dataclass(frozen=True)
class CascadeGrids:
    """Cascade grids of any sizes N_c as one table, for the many lookups of
    :func:`sample_cascade_groups`: every texel in ``flat`` (Σ N_c², K), cascade c's from
    ``base[c]``, its side ``n[c]`` and ``scale[c]`` = N_c / L_c; the cascades in summation
    order (grouped by size, each group in cascade order; ``spans``: each group's cascades)."""

    flat: np.ndarray
    n: np.ndarray
    scale: np.ndarray
    base: np.ndarray
    spans: tuple[tuple[int, int], ...]


def group_cascade_grids(grids, patch_sizes) -> CascadeGrids:
    """Cascade grids of possibly different N — one (C, N, N, K) array, or a sequence of
    (N_i, N_i, K) grids — as one :class:`CascadeGrids`, made once for the many lookups of
    :func:`sample_cascade_groups`. The sum runs over the grids of one N in cascade order, then
    over the sizes in the order they first appear."""
    groups: dict[int, list] = {}
    for grid, size in zip(grids, patch_sizes):
        grid = np.asarray(grid)
        groups.setdefault(grid.shape[0], []).append((grid, float(size)))
    ordered = [m for group in groups.values() for m in group]
    ends = np.cumsum([len(group) for group in groups.values()])
    n = np.array([g.shape[0] for g, _ in ordered], dtype=np.int64)
    one = isinstance(grids, np.ndarray)  # one N: its texels as they lie, not a copy
    return CascadeGrids(
        flat=grids.reshape(-1, grids.shape[-1]) if one else
        np.concatenate([g.reshape(-1, g.shape[-1]) for g, _ in ordered]),
        n=n, scale=np.array([int(k) / s for k, s in zip(n, (s for _, s in ordered))]),
        base=np.concatenate([[0], np.cumsum(n * n)[:-1]]).astype(np.int64),
        spans=tuple((int(e - len(g)), int(e)) for e, g in zip(ends, groups.values())))


def sample_cascade_groups(groups: CascadeGrids, x, z, channels: int | None = None):
    """Σ over every cascade of :func:`group_cascade_grids` of the bilinear lookup at world
    points (x, z) (shape (..., K)): one gather for every cascade, whatever its size.

    The corners are gathered, then laid out channel-major (4, K, C, points) for the arithmetic:
    the same operations on the same numbers as per point, but over long rows instead of rows of
    K (numpy's per-row cost made the point-major form twice as slow)."""
    x = np.asarray(x, dtype=float)
    z = np.asarray(z, dtype=float)
    shape = (len(groups.n),) + (1,) * x.ndim
    scale = groups.scale.reshape(shape)
    side = groups.n.reshape(shape)
    u = x * scale  # (C, ...)
    v = z * scale
    i0 = np.floor(u)
    j0 = np.floor(v)
    fu = u - i0
    fv = v - j0
    cols = np.empty((2,) + u.shape, dtype=np.int64)  # i0, i1 (mod N)
    rows = np.empty((2,) + u.shape, dtype=np.int64)  # j0, j1 (mod N)
    if not np.any(groups.n & (groups.n - 1)):  # powers of two: the mask is the modulo
        mask = side - 1
        np.bitwise_and(i0.astype(np.int64), mask, out=cols[0])
        np.bitwise_and(j0.astype(np.int64), mask, out=rows[0])
        np.bitwise_and(cols[0] + 1, mask, out=cols[1])
        np.bitwise_and(rows[0] + 1, mask, out=rows[1])
    else:
        np.remainder(i0.astype(np.int64), side, out=cols[0])
        np.remainder(j0.astype(np.int64), side, out=rows[0])
        np.remainder(cols[0] + 1, side, out=cols[1])
        np.remainder(rows[0] + 1, side, out=rows[1])
    rows *= side
    rows += groups.base.reshape(shape)
    # (r0 + i0, r0 + i1, r1 + i0, r1 + i1): the corners a, b, c, d
    index = (rows[:, None] + cols[None]).reshape(-1)
    flat = groups.flat
    k = flat.shape[1] if channels is None else min(int(channels), flat.shape[1])
    corners = flat.take(index, axis=0).reshape(4, -1, flat.shape[1])[..., :k]
    corners = np.ascontiguousarray(corners.transpose(0, 2, 1), dtype=np.float64)
    a, b, c, d = corners.reshape((4, k) + u.shape)
    # (1 − f_v)·((1 − f_u)·a + f_u·b) + f_v·((1 − f_u)·c + f_u·d), in place (the same
    # products and sums, without their temporaries)
    gu = 1 - fu
    each = gu * a
    part = fu * b
    each += part
    each *= 1 - fv
    lower = gu * c
    np.multiply(fu, d, out=part)
    lower += part
    lower *= fv
    each += lower  # (K, C, ...)
    out = None
    for first, end in groups.spans:  # a group's sum, then the groups' (the order of the sums)
        group = each[:, first]
        for i in range(first + 1, end):
            group = group + each[:, i]
        out = group if out is None else out + group
    return np.ascontiguousarray(out.transpose(tuple(range(1, out.ndim)) + (0,)))  # (..., K)



def cascade_bands(n: int, patch_sizes: Sequence[float], boundary_factor: float = 6.0):
    """Non-overlapping |k| bands [lo, hi) [rad/m], one per cascade (see the module docstring)."""
    sizes = [float(s) for s in patch_sizes]
    if not 1 <= len(sizes) <= 4:
        raise ParamError(f"ocean.cascades: {len(sizes)} is outside the allowed range [1, 4]")
    if any(b >= a for a, b in zip(sizes, sizes[1:])) or sizes[-1] <= 0:
        shown = ",".join(f"{x:g}" for x in sizes)
        raise ParamError(f"ocean.patch_sizes={shown} (the cascades used) are not strictly "
                         "decreasing to a positive size")
    # A boundary never lies beyond the coarser cascade's Nyquist (small N: the coarse cascade hands
    # over earlier, so its band stays inside what it can represent).
    edges = [0.0] + [min(boundary_factor * 2.0 * math.pi / s, math.pi * n / prev)
                     for prev, s in zip(sizes, sizes[1:])]
    edges.append(math.pi * n / sizes[-1])
    for i, s in enumerate(sizes):
        lo, hi = edges[i], edges[i + 1]
        nyq = math.pi * n / s
        fundamental = 2.0 * math.pi / s
        if not (lo < hi <= nyq * (1 + 1e-12)) or (i > 0 and lo < fundamental):
            raise ParamError(
                f"ocean.patch_sizes: cascade {i} (L {s:g} m) cannot hold the band "
                f"[{lo:.3g}, {hi:.3g}) rad/m, it resolves [{fundamental:.3g}, {nyq:.3g}]"
            )
    return [(edges[i], edges[i + 1]) for i in range(len(sizes))]


@dataclass
class WaterQuery:
    height: np.ndarray  # (...,) water surface height [m] above the world points
    displacement: np.ndarray  # (..., 3) displacement of the surface point found
    normal: np.ndarray  # (..., 3) unit normal there
    rest_x: np.ndarray  # (...,) rest position x₀ whose displaced point lands on the query
    rest_z: np.ndarray
    residuals: list = field(default_factory=list)  # |x_q − (x₀ + D_xz(x₀))| per step


def invert_horizontal_displacement(displacement_fn: Callable, xq, zq, iterations: int = 3,
                                   residuals: bool = True):
    """spec/000 §1.3: find x₀ with x₀ + D_xz(x₀) = x_q by x₀ ← x_q − D_xz(x₀) (x₀ = x_q first).

    ``displacement_fn(x, z)`` → (..., 3) displacement (D_x, η, D_z).  Returns (x₀, z₀, D(x₀),
    residuals) with ``iterations + 1`` residual arrays (before any correction, after each);
    ``residuals=False`` leaves the list empty (a height query that only wants D(x₀) skips
    their arithmetic; the same x₀ and D)."""
    xq = np.asarray(xq, dtype=float)
    zq = np.asarray(zq, dtype=float)
    x0, z0 = xq, zq
    d = displacement_fn(x0, z0)
    out = [np.hypot(x0 + d[..., 0] - xq, z0 + d[..., 2] - zq)] if residuals else []
    for _ in range(iterations):
        x0 = xq - d[..., 0]
        z0 = zq - d[..., 2]
        d = displacement_fn(x0, z0)
        if residuals:
            out.append(np.hypot(x0 + d[..., 0] - xq, z0 + d[..., 2] - zq))
    return x0, z0, d, out


def cascade_arrays(params: SpectrumParams, n: int, patch_sizes: Sequence[float], seed: int = 0,
                   boundary_factor: float = 6.0) -> tuple:
    """Each cascade's (L, band, k_x, k_z, ω, h₀) of :class:`FFTOcean` (cascade i seeded with
    seed + 7919·i); a pure function of its arguments, so one build may serve every ocean of the
    same sea (``app.gpu.cache.memoised``)."""
    out = []
    for i, (size, band) in enumerate(zip(patch_sizes, cascade_bands(n, patch_sizes,
                                                                   boundary_factor))):
        kx, kz = wavenumber_grid(n, size)
        om = dispersion_omega(np.hypot(kx, kz), params.depth, params.g)
        h0 = initial_amplitudes(n, size, params, seed=seed + 7919 * i, band=band)
        out.append((float(size), band, kx, kz, om, h0))
    return tuple(out)


@dataclass
class Cascade:
    patch_size: float
    band: tuple[float, float]
    kx: np.ndarray
    kz: np.ndarray
    omega: np.ndarray
    h0: np.ndarray
    fields: OceanFields | None = None

    def moments(self) -> tuple[float, float]:
        """(variance m0 [m²], mean-square slope) of this draw of h₀: the Hermitian pair doubles
        each mode, m0 = 2Σ|h₀|², mss = 2Σk²|h₀|²."""
        h2 = np.abs(self.h0) ** 2
        return 2.0 * float(h2.sum()), 2.0 * float(((self.kx**2 + self.kz**2) * h2).sum())

    def expected_variance(self, params: "SpectrumParams") -> np.ndarray:
        """Variance per mode expected of h₀ (both Hermitian halves): Ψ(−k)·Δk² where held,
        else 0."""
        dk = 2.0 * math.pi / self.patch_size
        return (directional_spectrum(-self.kx, -self.kz, params)
                * band_mask(self.kx, self.kz, self.band) * dk * dk)


class FFTOcean:
    """Numpy reference of the cascaded Tessendorf ocean.

    ``FFTOcean(params, n=256, patch_sizes=(250, 17, 5), choppiness=1.0, seed=0)``;
    ``update(t)`` synthesises every cascade at time t [s]; ``displacement(x, z)`` → (..., 3)
    summed (λD_x, η, λD_z) at rest points; ``normal(x, z)`` → thesis-formula normals from the
    summed derivatives; ``water_height(x, z, iterations=3)`` → WaterQuery at world points.
    """

    def __init__(self, params: SpectrumParams | None = None, *, n: int = 256,
                 patch_sizes: Sequence[float] = (250.0, 17.0, 5.0), choppiness: float = 1.0,
                 seed: int = 0, boundary_factor: float = 6.0,
                 build: Callable[..., tuple] | None = None):
        """``build(params, n, patch_sizes, seed, boundary_factor)`` makes the cascades' arrays
        (default :func:`cascade_arrays`; the ocean effect passes a memoised one)."""
        self.params = params or SpectrumParams()
        self.params.validate()
        if not 0.0 <= choppiness <= 4.0:
            raise ParamError(f"ocean.choppiness: {choppiness} is outside the allowed range [0, 4]")
        self.n = n
        self.choppiness = choppiness
        arrays = (build or cascade_arrays)(self.params, n, tuple(patch_sizes), seed,
                                           boundary_factor)
        self.cascades: list[Cascade] = [Cascade(*a) for a in arrays]
        self.time = None

    def update(self, t: float) -> None:
        for c in self.cascades:
            c.fields = synthesize(evolve_amplitudes(c.h0, c.omega, t), c.kx, c.kz,
                                  self.choppiness)
        self.time = t

    def _sum(self, names, x, z):
        if self.time is None:
            raise RuntimeError("FFTOcean.update(t) must be called before sampling")
        total = 0.0
        for c in self.cascades:
            grid = np.stack([getattr(c.fields, nm) for nm in names], axis=-1)
            total = total + sample_periodic_bilinear(grid, c.patch_size, x, z)
        return total

    def displacement(self, x, z):
        """Summed (λD_x, η, λD_z) [m] at rest points (x, z), shape (..., 3)."""
        return self._sum(("disp_x", "height", "disp_z"), x, z)

    def normal(self, x, z):
        """Unit normals at rest points from the summed slopes (thesis formula), (..., 3)."""
        d = self._sum(("slope_x", "slope_z", "ddx_dx", "ddz_dz"), x, z)
        return surface_normals(d[..., 0], d[..., 1], d[..., 2], d[..., 3])

    def water_height(self, x, z, iterations: int = 3) -> WaterQuery:
        """Height, displacement and normal of the water above world points (x, z)."""
        x0, z0, d, res = invert_horizontal_displacement(self.displacement, x, z, iterations)
        return WaterQuery(d[..., 1], d, self.normal(x0, z0), x0, z0, res)


def floating_points_pose(query: Callable, points_x, points_z, probe_distance: float = 1.0,
                         height: Callable | None = None):
    """spec/000 §1.3, fig. 3.1: averaged unit normal and displacement over floating points.

    ``query(x, z)`` → WaterQuery at world points; ``height(x, z)`` → its heights alone, where
    the surface has them (the two offset points need no normal and no displacement: on the
    FFT ocean a third of the work of a whole query; the same heights).  For each point, the
    surface points P(p), P(p + x̂·δ), P(p + ẑ·δ) give Nᵢ = (P_z − P) × (P_x − P) (upward);
    returns (normal (3,), displacement (3,))."""
    px = np.asarray(points_x, dtype=float)
    pz = np.asarray(points_z, dtype=float)
    d = float(probe_distance)
    q0 = query(px, pz)
    if height is None:
        def height(x, z):
            return query(x, z).height
    h0 = q0.height
    dx = np.asarray(height(px + d, pz), dtype=float) - h0
    dz = np.asarray(height(px, pz + d), dtype=float) - h0
    # Nᵢ = (0, dz, δ) × (δ, dx, 0), numpy.cross's products and differences in its order, by
    # component (no stacked edge vectors)
    ni = np.empty(np.broadcast(dx, dz).shape + (3,))
    ni[..., 0] = dz * 0.0 - d * dx
    ni[..., 1] = d * d - 0.0 * 0.0
    ni[..., 2] = 0.0 * dx - dz * d
    ni /= norm(ni, keepdims=True)
    nm = ni.reshape(-1, 3).mean(axis=0)
    return nm / length(nm), q0.displacement.reshape(-1, 3).mean(axis=0)



def polar_spectrum(p: SpectrumParams, k_lo: float, k_hi: float, nk: int = 1200, nth: int = 360):
    """Ψ on a polar grid: (k (nk,), θ (nth,), Ψ (nk, nth), Δk (nk,), Δθ), k log-spaced."""
    edges = np.geomspace(k_lo, k_hi, nk + 1)
    k = np.sqrt(edges[:-1] * edges[1:])
    dk = np.diff(edges)
    th = (np.arange(nth) + 0.5) / nth * 2.0 * np.pi - np.pi
    kk, tt = np.meshgrid(k, th + p.wind_direction, indexing="ij")
    psi = directional_spectrum(kk * np.cos(tt), kk * np.sin(tt), p)
    return k, th, psi, dk, 2.0 * np.pi / nth


def spectrum_moments(p: SpectrumParams, k_max: float = 1.0e3, k_min: float = 1.0e-4) -> dict:
    """Numerical moments of Ψ over k_min ≤ |k| ≤ k_max: variance m0 [m²], Hs = 4·sqrt(m0) [m],
    mean-square slope mss = ∫k²Ψ d²k, and the peak wavenumber of the omnidirectional E(k)."""
    k, _, psi, dk, dth = polar_spectrum(p, k_min, k_max)
    e_k = psi.sum(axis=1) * k * dth  # omnidirectional E(k) [m³]
    m0 = float(np.sum(e_k * dk))
    mss = float(np.sum(e_k * k * k * dk))
    kp = float(k[int(np.argmax(e_k))]) if m0 > 0 else float("nan")
    return {"m0": m0, "hs": 4.0 * math.sqrt(m0), "mss": mss, "k_peak": kp}


def gerstner_waves_from_spectrum(p: SpectrumParams, count: int, *, seed: int = 0,
                                 steepness_scale: float = 1.0,
                                 energy_range: tuple[float, float] = (0.005, 0.995)):
    """``count`` Gerstner waves with the spectrum's variance (so the same Hs) and peak period.

    Half the waves (rounded up) split the energy-carrying range — log-spaced wavenumber bins
    between the given quantiles of the variance — and the rest continue, log-spaced, up to the
    (1 − 1/count) quantile of the *slope* variance k²·E(k), where the short waves that make
    the glitter live.  Each wave gets its bin's share of the whole variance (the tails are
    folded into the end bins, so Σ A²/2 = m0 exactly), a wavenumber jittered inside its bin (no
    exact harmonics), a direction drawn from the spectrum's own directional distribution at
    that wavenumber, and a random phase.  Steepness s = k·A times ``steepness_scale`` (which
    scales the amplitudes: Hs scales with it).  Seeded; returns a list of GerstnerWave."""
    if not 1 <= count <= 64:
        raise ParamError(f"ocean.gerstner_waves: {count} is outside the allowed range [1, 64]")
    p.validate()
    rng = np.random.default_rng(seed)
    if p.wind_speed <= 0:
        return [GerstnerWave((math.cos(p.wind_direction), math.sin(p.wind_direction)), 10.0, 0.0)
                for _ in range(count)]
    k, th, psi, dk, dth = polar_spectrum(p, 1e-4, 1e3)
    e_k = psi.sum(axis=1) * k * dth * dk
    m0 = float(e_k.sum())
    cdf = np.cumsum(e_k) / m0
    k_lo = float(np.interp(energy_range[0], cdf, k))
    k_hi = float(np.interp(energy_range[1], cdf, k))
    n_energy = (count + 1) // 2
    edges = np.geomspace(k_lo, k_hi, n_energy + 1)
    if count > n_energy:
        slope = e_k * k * k
        cdf_s = np.cumsum(slope) / slope.sum()
        k_slope = float(np.interp(1.0 - 1.0 / count, cdf_s, k))
        if k_slope > k_hi * 1.01:
            edges = np.concatenate([edges, np.geomspace(k_hi, k_slope, count - n_energy + 1)[1:]])
        else:
            edges = np.geomspace(k_lo, k_hi, count + 1)
    # each bin's energy (tails folded into the end bins), then normalised to m0
    idx = np.clip(np.searchsorted(edges, k) - 1, 0, count - 1)
    bin_e = np.bincount(idx, weights=e_k, minlength=count)
    bin_e *= m0 / bin_e.sum()
    waves = []
    for i in range(count):
        kw = float(np.exp(rng.uniform(np.log(edges[i]), np.log(edges[i + 1]))))
        row = psi[min(int(np.searchsorted(k, kw)), len(k) - 1)]
        wsum = row.sum()
        if wsum > 0:
            cdf_t = np.cumsum(row) / wsum
            theta = float(np.interp(rng.uniform(), cdf_t, th)) + p.wind_direction
        else:
            theta = p.wind_direction
        amp = math.sqrt(2.0 * bin_e[i]) * steepness_scale
        waves.append(GerstnerWave((math.cos(theta), math.sin(theta)), 2.0 * math.pi / kw, kw * amp,
                                  float(rng.uniform(0.0, 2.0 * math.pi))))
    return waves


def gerstner_moments(waves: Sequence[GerstnerWave]) -> dict:
    """Variance m0 = ΣA²/2, Hs = 4·sqrt(m0), mss = Σ(kA)²/2 = Σs²/2 of a Gerstner wave set."""
    a = np.array([w.steepness * w.wavelength / (2.0 * math.pi) for w in waves])
    s = np.array([w.steepness for w in waves])
    m0 = float(np.sum(a * a) / 2.0)
    return {"m0": m0, "hs": 4.0 * math.sqrt(m0), "mss": float(np.sum(s * s) / 2.0)}


# ---- What the view resolves: each cascade's grid from the screen footprint of its wavelengths, and
# how often a slow cascade needs a new snapshot


def crop_cascade(c: Cascade, n: int) -> Cascade:
    """Cascade ``c`` on an n × n grid (n a power of two ≤ its own N): the modes with
    |m_x|, |m_z| < n/2 keep their h₀, k and ω exactly (copied, not recomputed), the finer ones
    are dropped, and the n grid's Nyquist row and column are zero as
    :func:`initial_amplitudes` leaves them.  Sampled at the n grid's points, its fields equal the
    full grid's fields of the same truncated spectrum: a smaller N removes only the shortest
    waves, never redraws the sea.  The band's top becomes min(band top, π·n/L)."""
    size = c.h0.shape[-1]
    n = int(n)
    if n >= size:
        return c
    if n < 4 or n & (n - 1):
        raise ParamError(f"ocean.fft_size: {n} is not a power of two ≥ 4")
    half = n // 2
    idx = np.r_[0:half, size - half:size]  # numpy FFT order of the n grid, m = 0…n/2−1, −n/2…−1
    pick = np.ix_(idx, idx)
    h0 = c.h0[pick].copy()
    h0[half, :] = 0.0
    h0[:, half] = 0.0
    band = (c.band[0], min(c.band[1], math.pi * n / c.patch_size))
    return Cascade(c.patch_size, band, c.kx[pick].copy(), c.kz[pick].copy(),
                   c.omega[pick].copy(), h0)


def nearest_water_footprint(camera, aspect: float, rows: int, clearance: float) -> float:
    """The smallest pixel footprint [m] on the water the camera can see, along the view (the
    axis a mip-mapped lookup filters by): h·p/d_y², with h the camera's height above the highest
    crest (``clearance``: its height above the mean level minus the crests' reach), p =
    2·tan(fov/2)/rows a pixel row's height on the image plane at unit distance, and d = f + y·u
    the ray through image-plane height y (f, u the camera's forward and up vectors).  The hit
    of that ray on a plane h below is at d·h/(−d_y), whose derivative in y has length
    h·|u·f_y − f·u_y|/d_y² = h/d_y² (no roll: the world's up lies in the (f, u) plane), so the
    row spacing is smallest where −d_y is largest: at the bottom edge of the frustum, y =
    −tan(fov/2), on every column alike.  0 when the camera is at or below the crests (the
    surface may be at any distance); inf when no ray looks down."""
    if not clearance > 0.0:
        return 0.0
    _, u, f = camera.basis()
    th = math.tan(math.radians(camera.fov) * 0.5)
    d_y = float(f[1]) - th * float(u[1])
    if d_y >= 0.0:
        return math.inf
    pixel = 2.0 * th / max(int(rows), 1)
    return clearance * pixel / (d_y * d_y)


def view_cascade_size(patch_size: float, band_top: float, footprint: float, n_max: int,
                      samples: float = 4.0, current: int | None = None, n_min: int = 16) -> int:
    """The grid N a cascade of tile ``patch_size`` [m] needs for a view: texels as large as the
    larger of the view's smallest footprint (finer texels cover less than a pixel anywhere on
    screen: the mip chain would average them away) and the band's shortest wave 2π/``band_top``
    over ``samples`` (a finer grid resolves no more of the band's waves); N = the smallest power
    of two whose texels are no larger than that, within [n_min, n_max].  With ``current``, a
    smaller N is taken only once the need L/texel is 20 % under current/2 (no back and forth
    at the threshold); a larger one at once."""
    texel = max(float(footprint), 2.0 * math.pi / (float(band_top) * samples))
    need = patch_size / texel if texel > 0.0 else math.inf
    n = n_max if not math.isfinite(need) else 1 << max(0, math.ceil(math.log2(max(need, 1.0))))
    n = int(min(max(n, n_min), n_max))
    if current is not None and n < current and need > 0.5 * current / 1.25:
        return int(min(current, n_max))
    return n


def interpolation_error(c: Cascade, period: float) -> tuple[float, float]:
    """Expected rms error (height [m], slope) of cascade ``c`` drawn as the linear interpolation
    between its snapshots ``period`` seconds apart, at mid-interval where it is largest.

    Each mode evolves as e^{iωt} (spec/000 eq. 2.11): between snapshots at t_a and t_a + T, the
    interpolated phasor at the middle is cos(ωT/2)·e^{iω(t_a + T/2)}, short by 1 − cos(ωT/2) =
    2·sin²(ωT/4) of its length; over the random phases of h₀ the squared errors add:
    e_η² = Σ_k 2|h₀(k)|²·(2 sin²(ω_k T/4))² (the Hermitian pair counted once each, as in
    :meth:`Cascade.moments`), e_s² the same weighted by k²."""
    h2 = 2.0 * np.abs(c.h0) ** 2
    f2 = (2.0 * np.sin(c.omega * (0.25 * float(period))) ** 2) ** 2
    k2 = c.kx ** 2 + c.kz ** 2
    return math.sqrt(float((h2 * f2).sum())), math.sqrt(float((k2 * h2 * f2).sum()))


def refresh_period(c: Cascade, slope_tolerance: float, longest: float = 1.0) -> float:
    """The longest snapshot period T ≤ ``longest`` [s] up to which the interpolation slope error
    (:func:`interpolation_error`) stays within ``slope_tolerance`` (absolute rms slope): the
    first period of a geometric scan from 1 ms (×1.25) whose error exceeds it, refined by
    bisection against the last that did not (the error is not monotonic once ωT passes 2π for
    the fastest modes, so the scan stops at the first excess); 0 when 1 ms already exceeds it."""
    if not slope_tolerance > 0.0:
        return 0.0
    held = np.abs(c.h0) > 0.0
    h2 = 2.0 * np.abs(c.h0[held]) ** 2
    k2h2 = (c.kx[held] ** 2 + c.kz[held] ** 2) * h2
    omega = c.omega[held]

    def slope_error(periods: np.ndarray) -> np.ndarray:
        f = 2.0 * np.sin(np.outer(periods, omega) * 0.25) ** 2
        return np.sqrt((f * f) @ k2h2)

    scan = np.minimum(1e-3 * 1.25 ** np.arange(int(math.log(longest / 1e-3) / math.log(1.25)) + 2),
                      longest)
    over = np.nonzero(slope_error(scan) > slope_tolerance)[0]
    if over.size == 0:
        return float(longest)
    if over[0] == 0:
        return 0.0
    lo, hi = float(scan[over[0] - 1]), float(scan[over[0]])
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        if slope_error(np.array([mid]))[0] <= slope_tolerance:
            lo = mid
        else:
            hi = mid
    return lo

"""Numpy twins of method 4's LUT maths (glsl/atmosphere/hillaire/), in double precision.

Used by the method-4 tests and available to benches: the transmittance-LUT parametrisation
(Bruneton's (x_μ, x_r), as Hillaire 2020 §4), an accurate optical depth, the transmittance of
any texel, and the Ψ_ms integral of one multiple-scattering texel (Hillaire 2020 §5.5) with
exact sun transmittance. Same model as glsl/atmosphere/model.glsl: ρ_x(h) = P0 exp(−h/H_x), and
the ozone layer when ``ozone_absorption`` (uOzoneAbsorption) is not zero: the tent ρ_O of
:func:`app.sim.atmosphere.ozone_density`, absorbing only (it adds σ_a ρ_O to the extinction).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .atmosphere import ozone_density


@dataclass(frozen=True)
class Model:
    bottom: float = 6_360_000.0
    top: float = 6_420_000.0
    beta_rayleigh: tuple = (5.8e-6, 13.5e-6, 33.1e-6)
    beta_mie_scatter: tuple = (2.0e-5, 2.0e-5, 2.0e-5)
    beta_mie_ext: tuple = (2.2e-5, 2.2e-5, 2.2e-5)
    h_rayleigh: float = 7994.0
    h_mie: float = 1200.0
    p0: float = 1.0
    #: ozone's σ_a at the tent's peak, RGB 1/m (0: no ozone, the thesis)
    ozone_absorption: tuple = (0.0, 0.0, 0.0)

    @classmethod
    def from_uniforms(cls, u) -> Model:
        return cls(float(u["uBottomRadius"]), float(u["uTopRadius"]), tuple(u["uBetaRayleigh"]),
                   tuple(u["uBetaMieScatter"]), tuple(u["uBetaMieExt"]), float(u["uHRayleigh"]),
                   float(u["uHMie"]), float(u["uP0"]),
                   tuple(float(v) for v in u.get("uOzoneAbsorption", (0.0, 0.0, 0.0))))

    @property
    def height(self) -> float:
        return self.top - self.bottom

    def density(self, h):
        h = np.maximum(np.asarray(h, dtype=float), 0.0)
        return self.p0 * np.exp(-h / self.h_rayleigh), self.p0 * np.exp(-h / self.h_mie)

    def transmittance(self, depth_r, depth_m, depth_o=0.0) -> np.ndarray:
        d_r = np.asarray(depth_r, dtype=float)[..., None]
        d_m = np.asarray(depth_m, dtype=float)[..., None]
        d_o = np.asarray(depth_o, dtype=float)[..., None]
        return np.exp(-(np.asarray(self.beta_rayleigh) * d_r + np.asarray(self.beta_mie_ext) * d_m
                        + np.asarray(self.ozone_absorption) * d_o))

    def ozone_extinction(self, h) -> np.ndarray:
        """σ_a ρ_O(h), RGB (..., 3): the ozone layer's share of the extinction."""
        rho = ozone_density(np.asarray(h, dtype=float))
        return np.asarray(self.ozone_absorption) * rho[..., None]


def distance_to_top(m: Model, h, mu):
    r = m.bottom + np.asarray(h, dtype=float)
    mu = np.asarray(mu, dtype=float)
    disc = (m.top - r) * (m.top + r) + (r * mu) ** 2
    return -r * mu + np.sqrt(np.maximum(disc, 0.0))


def height_along(m: Model, h, mu, t):
    r = m.bottom + np.asarray(h, dtype=float)
    return np.sqrt(r * r + 2.0 * r * np.asarray(mu) * t + t * t) - m.bottom


def hits_ground(m: Model, h, mu):
    h = np.maximum(np.asarray(h, dtype=float), 0.0)
    r = m.bottom + h
    return np.asarray(mu) < -np.sqrt(h * (2 * m.bottom + h)) / r


def transmittance_params(m: Model, x_mu, x_r):
    """(h, μ) of unit LUT coordinates (x_μ, x_r) — twin of HillaireTransmittanceParams."""
    H = math.sqrt(m.top ** 2 - m.bottom ** 2)
    rho = H * np.asarray(x_r, dtype=float)
    r = np.sqrt(rho * rho + m.bottom ** 2)
    d_min = m.top - r
    d_max = rho + H
    d = d_min + np.asarray(x_mu, dtype=float) * (d_max - d_min)
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = np.where(d <= 0.0, 1.0, (H * H - rho * rho - d * d) / (2.0 * r * d))
    return r - m.bottom, np.clip(mu, -1.0, 1.0)


def optical_depth_to_top(m: Model, h, mu, n: int = 4000, ozone: bool = False):
    """(∫ρ_R dt, ∫ρ_M dt) to the top: midpoint in s with t = d s³ (converged at n = 4000);
    with ``ozone`` a third value, ∫ρ_O dt."""
    h = np.asarray(h, dtype=float)
    mu = np.asarray(mu, dtype=float)
    d = distance_to_top(m, h, mu)[..., None]
    s = (np.arange(n) + 0.5) / n
    t = d * s ** 3
    dt = 3.0 * d * s ** 2 / n
    alt = height_along(m, h[..., None], mu[..., None], t)
    rho_r, rho_m = m.density(alt)
    out = (rho_r * dt).sum(-1), (rho_m * dt).sum(-1)
    if ozone:
        return out + ((ozone_density(alt) * dt).sum(-1),)
    return out


def transmittance_lut(m: Model, width: int, height: int, n: int = 4000) -> np.ndarray:
    """(height, width, 3) reference of the transmittance LUT (texel centres)."""
    xm, xr = np.meshgrid(np.arange(width) / (width - 1), np.arange(height) / (height - 1))
    h, mu = transmittance_params(m, xm, xr)
    return m.transmittance(*optical_depth_to_top(m, h, mu, n, ozone=True))


def sun_transmittance(m: Model, h, mu_s, n: int = 400):
    """Exact transmittance of sunlight at altitude h, zero in the planet's shadow."""
    h = np.asarray(h, dtype=float)
    mu_s = np.asarray(mu_s, dtype=float)
    T = m.transmittance(*optical_depth_to_top(m, h, mu_s, n, ozone=True))
    return np.where(hits_ground(m, h, mu_s)[..., None], 0.0, T)


def _segment(m: Model, h, mu):
    """(t0, t1) of the ray inside the atmosphere, clipped at the ground; None if empty."""
    r = m.bottom + h
    disc = (m.top - r) * (m.top + r) + (r * mu) ** 2
    if disc < 0:
        return None
    s = math.sqrt(disc)
    t1 = -r * mu + s
    t0 = max(-r * mu - s, 0.0) if r > m.top else 0.0
    if bool(hits_ground(m, h, mu)):
        t1 = min(t1, -r * mu - math.sqrt(max((r * mu) ** 2 - (r * r - m.bottom ** 2), 0.0)))
    return (t0, t1) if t1 > t0 else None


def integrate_ray(m: Model, h0: float, mu: float, mu_s: float, nu: float, steps: int = 4000,
                  ms_lut=None, max_dist: float = math.inf):
    """Brute-force twin of HillaireIntegrateSegment: uniform midpoint steps, exact sun
    transmittance. Returns dict(rayleigh, mie, multiple, transfer, transmittance); ``ms_lut``
    (h, μ_s) → Ψ rgb gives the multiple-scattering source (None: no multiple term).

    ``rayleigh`` + ``mie`` is the in-scattering of Hillaire 2020 eq. 6 without its phase and
    ground term, ``transfer`` the inner integral of Hillaire 2020 eq. 8, ``multiple`` the
    σ_s Ψ_ms source of Hillaire 2020 eq. 11."""
    seg = _segment(m, h0, mu)
    zero = np.zeros(3)
    if seg is None or min(seg[1], max_dist) <= seg[0]:
        return {"rayleigh": zero, "mie": zero, "multiple": zero, "transfer": zero,
                "transmittance": np.ones(3)}
    t0, t1 = seg[0], min(seg[1], max_dist)
    dt = (t1 - t0) / steps
    t = t0 + (np.arange(steps) + 0.5) * dt
    r0 = m.bottom + h0
    h = height_along(m, h0, mu, t)
    rho_r, rho_m = m.density(h)
    scat_r = np.asarray(m.beta_rayleigh) * rho_r[:, None]
    scat_m = np.asarray(m.beta_mie_scatter) * rho_m[:, None]
    ext = scat_r + np.asarray(m.beta_mie_ext) * rho_m[:, None] + m.ozone_extinction(h)
    tau = np.cumsum(ext * dt, axis=0) - 0.5 * ext * dt
    view_t = np.exp(-tau)
    mu_s_t = np.clip((r0 * mu_s + t * nu) / (m.bottom + h), -1, 1)
    sun_t = sun_transmittance(m, h, mu_s_t, 200)
    out = {
        "rayleigh": (view_t * sun_t * scat_r).sum(0) * dt,
        "mie": (view_t * sun_t * scat_m).sum(0) * dt,
        "transfer": (view_t * (scat_r + scat_m)).sum(0) * dt,
        "transmittance": np.exp(-(ext * dt).sum(0)),
        "multiple": zero,
    }
    if ms_lut is not None:
        out["multiple"] = (view_t * (scat_r + scat_m) * ms_lut(h, mu_s_t)).sum(0) * dt
    return out


def multiple_scattering_texel(m: Model, h: float, mu_s: float, directions: int = 8,
                              steps: int = 400,
                              infinite: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """(Ψ_ms rgb, f_ms rgb) at altitude h and sun cosine μ_s — the same N × N direction grid as
    multiscattering_lut.frag, exact sun transmittance, no ground albedo: L_2nd
    (Hillaire 2020 eq. 5), f_ms (Hillaire 2020 eq. 8), F_ms = 1/(1 − f_ms) when ``infinite``
    (Hillaire 2020 eq. 9, else F_ms = 1) and Ψ_ms = L_2nd F_ms (Hillaire 2020 eq. 10)."""
    n = directions
    L2 = np.zeros(3)
    f = np.zeros(3)
    sin_s = math.sqrt(max(0.0, 1 - mu_s * mu_s))
    for j in range(n):
        mu = 1 - 2 * (j + 0.5) / n
        sin_t = math.sqrt(max(0.0, 1 - mu * mu))
        for i in range(n):
            phi = 2 * math.pi * (i + 0.5) / n
            nu = mu * mu_s + sin_t * sin_s * math.cos(phi)
            res = integrate_ray(m, h, mu, mu_s, nu, steps)
            L2 += (res["rayleigh"] + res["mie"]) / (4 * math.pi)
            f += res["transfer"]
    L2 /= n * n
    f /= n * n
    return (L2 / (1 - np.minimum(f, 0.999)) if infinite else L2), f


def multiple_scattering_lookup(table: np.ndarray, m: Model, h: float, mu_s: float) -> np.ndarray:
    """Ψ_ms rgb at altitude h and sun cosine μ_s read from a multiple-scattering LUT ``table``
    (rows × columns × ≥ 3, row = altitude, column = μ_s) as HillaireMultipleScatteringAt reads
    it: unit coordinates (μ_s/2 + ½, h/H) on texel centres, bilinear, clamped at the edges."""
    rows, cols = table.shape[:2]
    x = float(np.clip(0.5 * mu_s + 0.5, 0.0, 1.0)) * (cols - 1)
    y = float(np.clip(h / m.height, 0.0, 1.0)) * (rows - 1)
    x0, y0 = min(int(x), cols - 2) if cols > 1 else 0, min(int(y), rows - 2) if rows > 1 else 0
    fx, fy = x - x0, y - y0
    x1, y1 = min(x0 + 1, cols - 1), min(y0 + 1, rows - 1)
    t = np.asarray(table[..., :3], dtype=np.float64)
    top = (1 - fx) * t[y0, x0] + fx * t[y0, x1]
    bottom = (1 - fx) * t[y1, x0] + fx * t[y1, x1]
    return (1 - fy) * top + fy * bottom

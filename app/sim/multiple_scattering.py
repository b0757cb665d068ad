"""A multi-order scattering reference for the planet's atmosphere, and Hillaire's method graded
against it. Numpy float64, no GL.

The reference (Bruneton & Neyret 2008, Bruneton 2017: scattering order by order)
-------------------------------------------------------------------------------
Same atmosphere as :mod:`app.sim.atmosphere` and :mod:`app.sim.hillaire`: a spherical planet
(R, R + top), Rayleigh and Mie densities P0 exp(−h/H), their coefficients, Mie's absorption,
the optional ozone tent (absorbing only), a white sun at infinity, a black ground (the thesis
has no ground reflection; Hillaire's ``ground_albedo`` is 0 by default). The phase functions are
the full ones: Rayleigh's 3/(16π)(1 + ν²) and the planet's Cornette–Shanks Mie with its g.

For a distant sun and a spherically symmetric atmosphere the radiance field depends on four
numbers: altitude h, sun zenith cosine μ_s, view zenith cosine μ and the view azimuth φ around
the local vertical measured from the sun's (the field is even in φ). Order by order:

* J_1(x, ω) = T_sun(x) [σ_R(x) P_R(ω·s) + σ_M(x) P_M(ω·s)]  (exact, no table);
* L_n(x, ω) = ∫ T(x, x + tω) J_n(x + tω, ω) dt along the ray to the top or the
  (black) ground;
* J(n+1; x, ω) = σ_R(x) ∫ P_R(ω·ω') L_n(x, ω') dω' + σ_M(x) ∫ P_M(ω·ω') L_n(x, ω') dω'.

Discretisation (:class:`Grid`): J_n and L_n live on nodes of (h, μ_s, μ, φ). Altitudes
h = top · u² (u uniform: dense near the ground, where the Mie layer's 1.2 km scale height is);
sun cosines μ_s = v |v| with v uniform in [−0.5, 1] (dense at the horizon, where the sun's
transmittance changes fastest; μ_s ≥ −0.25 covers every point that sees the sun, and below it
the table is clamped); view directions at the centres of a midpoint grid, uniform in μ (cells
meet at μ = 0, the ground's horizon) and in φ ∈ [0, π] (each node stands for its cell and the
mirror cell at −φ). The sphere integral of J(n+1) uses a phase *matrix*: for each target
node, the phase integrated over each source cell (sub-sampled 6 × 6 per cell and per mirror),
its rows then scaled to sum to 1 (energy conserved exactly), so the forward-peaked Mie phase
(g = 0.76, a lobe ~15° wide) is integrated, not point-sampled. L_n is marched from every node
with ``steps`` samples on t = d (1 − cos πs)/2 (dense at both ends: the ground where rays
start, and where they hit it), reading J_n 4-linearly at (h_t, μ_s,t, μ_t, φ_t) — ν = ω·s is
constant along a ray, which gives φ_t. Sun transmittance comes from a fine (x_μ, x_r) table of
exact optical depths (:func:`app.sim.atmosphere._density_integrals`), bilinear.

The sky seen by a camera is then a final gather along its exact ray with many samples:
single scattering from the exact J_1, plus T times the sum over n ≥ 2 of J_n read from the
tables. Its errors are measured, not assumed: the single-scattering part against
:func:`app.sim.atmosphere.reference`; the orders' convergence (the share of orders ≥ 5); the
table's resolution by halving the grid (``natura bench planet``).

Hillaire's method (Hillaire 2020), its numpy twin here
------------------------------------------------------
:func:`hillaire_ms_lut` computes Ψ_ms(h, μ_s) on the GPU's texel grid (``ms_size``², N × N
directions, isotropic phase for both events, F_ms = 1/(1 − f_ms), black ground) as
``multiscattering_lut.frag`` does, with converged integrals (``steps`` samples, exact sun
transmittance); :func:`sky` adds σ_s Ψ_ms read bilinearly (as ``HillaireMultipleScatteringAt``)
along the same camera ray and the same exact single scattering — so the difference between the
two is the multiple-scattering model alone (no sky-view LUT interpolation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import atmosphere as atm
from .optics import phase_mie_cornette_shanks, phase_rayleigh

#: the v of the lowest sun-cosine node: μ_s = v |v| = −0.25 (sun 14.5° below the horizon)
_V_MIN = -0.5


@dataclass(frozen=True)
class Grid:
    """Resolution of the reference's tables and marches (see the module notes)."""

    n_h: int = 12        # altitude nodes (h = top · u², u uniform)
    n_mu_s: int = 16     # sun-cosine nodes (μ_s = v|v|, v uniform in [−0.5, 1])
    n_mu: int = 24       # view-cosine cells (uniform in μ, midpoints)
    n_phi: int = 12      # azimuth cells over [0, π] (midpoints; mirrored to [−π, 0])
    steps: int = 32      # samples per table ray
    sub: int = 6         # sub-samples per cell side of the phase matrix

    def scaled(self, f: float) -> "Grid":
        """Every resolution times ``f`` (halve: 0.5, double: 2), at least 2 per axis."""
        def s(n):
            return max(2, int(round(n * f)))
        return Grid(s(self.n_h), s(self.n_mu_s), 2 * max(1, int(round(self.n_mu * f / 2))),
                    s(self.n_phi), s(self.steps), self.sub)


class _Model:
    def __init__(self, p: atm.AtmosphereParams):
        self.p = p
        self.R = p.bottom_radius
        self.top = p.top_radius
        self.H = p.top_height
        self.s_r = p.p0 * np.asarray(p.beta_rayleigh_scatter)
        self.s_m = p.p0 * np.asarray(p.beta_mie_scatter, dtype=float)
        self.e_r = p.p0 * np.asarray(p.beta_rayleigh_ext)
        self.e_m = p.p0 * np.asarray(p.beta_mie_ext)
        self.e_o = np.asarray(p.beta_ozone)
        self._build_transmittance()

    def rho(self, h):
        h = np.maximum(np.asarray(h, dtype=float), 0.0)
        return np.exp(-h / self.p.h_rayleigh), np.exp(-h / self.p.h_mie)

    def scattering(self, h):
        """(σ_R, σ_M) RGB at altitude h: shapes h.shape + (3,)."""
        rr, rm = self.rho(h)
        return rr[..., None] * self.s_r, rm[..., None] * self.s_m

    def extinction(self, h):
        rr, rm = self.rho(h)
        ext = rr[..., None] * self.e_r + rm[..., None] * self.e_m
        if self.p.ozone > 0.0:
            ext = ext + atm.ozone_density(h)[..., None] * self.e_o
        return ext

    def _build_transmittance(self, n_mu: int = 512, n_r: int = 128) -> None:
        R, T = self.R, self.top
        Hh = math.sqrt(T * T - R * R)
        xm, xr = np.meshgrid(np.linspace(0, 1, n_mu), np.linspace(0, 1, n_r))
        rho = Hh * xr
        r = np.sqrt(rho * rho + R * R)
        d_min, d_max = T - r, rho + Hh
        d = d_min + xm * (d_max - d_min)
        with np.errstate(divide="ignore", invalid="ignore"):
            mu = np.where(d <= 0.0, 1.0, (Hh * Hh - rho * rho - d * d) / (2.0 * r * d))
        mu = np.clip(mu, -1.0, 1.0)
        h = r - R
        D = self.p.p0 * atm._density_integrals(h, mu, self.p, 16, ground=False)
        tau = D[..., 0:1] * np.asarray(self.p.beta_rayleigh_ext) \
            + D[..., 1:2] * np.asarray(self.p.beta_mie_ext)
        if self.p.ozone > 0.0:
            tau = tau + atm.ozone_optical_depth(h, mu, self.p, ground=False)[..., None] * self.e_o
        self._t_texels = np.ascontiguousarray(np.exp(-tau).reshape(n_r * n_mu, 3).T)  # (3, texels)
        self._t_shape = (n_r, n_mu)

    def sun_transmittance(self, h, mu_s):
        """T to the sun (RGB, shape + (3,)), 0 where the sun ray hits the planet."""
        return np.ascontiguousarray(np.moveaxis(self.sun_transmittance_at(h)(mu_s), 0, -1))

    def sun_transmittance_at(self, h):
        """:meth:`sun_transmittance` at the altitudes ``h`` as a function of μ_s (broadcast),
        channels first, (3,) + shape: what the altitude alone sets is made once for all μ_s."""
        R, T, (n_r, n_mu) = self.R, self.top, self._t_shape
        h = np.clip(np.asarray(h, dtype=float), 0.0, self.H)
        r, Hh = R + h, math.sqrt(T * T - R * R)
        rho = np.sqrt(np.maximum(r * r - R * R, 0.0))
        d_min, inside = T - r, (T - r) * (T + r)
        span = np.maximum(rho + Hh - d_min, 1e-9)
        y0, fy = _cell(rho / Hh * (n_r - 1), n_r)

        def at(mu_s):
            mu = np.clip(np.asarray(mu_s, dtype=float), -1.0, 1.0)
            d = -r * mu + np.sqrt(np.maximum(inside + (r * mu) ** 2, 0.0))
            x0, fx = _cell(np.clip((d - d_min) / span, 0.0, 1.0) * (n_mu - 1), n_mu)
            out = _bilinear(self._t_texels, y0 * n_mu + x0, fy, fx, n_mu)
            dark = atm.sun_ray_hits_ground(h, mu, self.p)
            return np.where(dark, 0.0, out)
        return at

    def segment_length(self, h, mu):
        """Distance from altitude h along μ to the top, or to the ground if the ray hits it."""
        r = self.R + np.asarray(h, dtype=float)
        mu = np.asarray(mu, dtype=float)
        disc_t = (self.top - r) * (self.top + r) + (r * mu) ** 2
        t_top = -r * mu + np.sqrt(np.maximum(disc_t, 0.0))
        disc_g = (r * mu) ** 2 - (r * r - self.R ** 2)
        ground = (mu < 0.0) & (disc_g >= 0.0)
        t_g = -r * mu - np.sqrt(np.maximum(disc_g, 0.0))
        return np.where(ground, np.maximum(t_g, 0.0), np.maximum(t_top, 0.0))


def _cell(f, n: int):
    """The fractional index ``f`` on ``n`` nodes, clamped: (its low node, the next one's weight)."""
    f = np.clip(f, 0.0, n - 1.0)
    i0 = np.minimum(f.astype(np.intp), n - 2)
    return i0, f - i0


def _bilinear(texels, i, fy, fx, nx: int):
    """The channels-first ``texels`` (C, rows × nx) blended around each low corner's flat index
    ``i`` with the next row's and column's weights (fy, fx): (C,) + i.shape."""
    t00, t01 = texels.take(i, axis=1), texels.take(i + 1, axis=1)
    t10, t11 = texels.take(i + nx, axis=1), texels.take(i + nx + 1, axis=1)
    return (1 - fy) * ((1 - fx) * t00 + fx * t01) + fy * ((1 - fx) * t10 + fx * t11)


def _march(m: _Model, h0, mu, steps: int):
    """Samples of rays from altitude h0 along μ (broadcast): (t, dt, h_t, μ_t, transmittance
    from the start to each sample), the last axis the samples, on t = d (1 − cos πs)/2."""
    h0 = np.asarray(h0, dtype=float)[..., None]
    mu = np.asarray(mu, dtype=float)[..., None]
    d = m.segment_length(h0, mu)
    s = (np.arange(steps) + 0.5) / steps
    t = d * 0.5 * (1.0 - np.cos(np.pi * s))
    dt = d * 0.5 * np.pi * np.sin(np.pi * s) / steps
    r0 = m.R + h0
    r = np.sqrt(np.maximum(r0 * r0 + 2.0 * r0 * mu * t + t * t, 0.0))
    h = np.maximum(r - m.R, 0.0)
    mu_t = np.clip((r0 * mu + t) / r, -1.0, 1.0)
    ext = m.extinction(h)
    step = ext * dt[..., None]
    tau = np.cumsum(step, axis=-2) - 0.5 * step
    return t, dt, h, mu_t, np.exp(-tau), r


def _j1(m: _Model, h, mu_s, nu):
    """Order-1 source J_1 (per unit sun radiance): T_sun (σ_R P_R(ν) + σ_M P_M(ν))."""
    sr, sm = m.scattering(h)
    return m.sun_transmittance(h, mu_s) * (sr * phase_rayleigh(nu)[..., None]
                                           + sm * phase_mie_cornette_shanks(nu, m.p.g)[..., None])


class Reference:
    """J_n tables for orders 2 … ``orders`` on :class:`Grid` ``grid`` (see the module notes).

    ``self.j[n]`` is J_n on the nodes (n_h, n_mu_s, n_mu, n_phi, 3), per unit sun radiance;
    ``self.l1_nodes`` the order-1 radiance at the nodes (marched, for the single-scattering
    check of the tables themselves)."""

    def __init__(self, params: atm.AtmosphereParams, grid: Grid = Grid(), orders: int = 10):
        self.params = params
        self.grid = grid
        self.m = m = _Model(params)
        g = grid
        u = np.linspace(0.0, 1.0, g.n_h)
        self.h_nodes = m.H * u * u
        v = np.linspace(_V_MIN, 1.0, g.n_mu_s)
        self.mu_s_nodes = v * np.abs(v)
        self.mu_edges = np.linspace(-1.0, 1.0, g.n_mu + 1)
        self.mu_nodes = 0.5 * (self.mu_edges[1:] + self.mu_edges[:-1])
        self.phi_nodes = (np.arange(g.n_phi) + 0.5) * np.pi / g.n_phi
        self._phase_matrices()
        _, S, MU, PHI = np.meshgrid(self.h_nodes, self.mu_s_nodes, self.mu_nodes, self.phi_nodes,
                                    indexing="ij")
        self._nu = MU * S + np.sqrt(1 - MU * MU) * np.sqrt(np.maximum(1 - S * S, 0.0)) * np.cos(PHI)
        self.j: dict[int, np.ndarray] = {}
        # order 1 at the nodes: exact J_1 along each ray
        self.l1_nodes = l_prev = self._march_nodes(None)
        for n in range(2, orders + 1):
            self.j[n] = self._gather(l_prev)
            if n < orders:
                l_prev = self._march_nodes(self.j[n])

    def _phase_matrices(self) -> None:
        g = self.grid
        k = g.sub
        mu_t = self.mu_nodes[:, None]
        phi_t = self.phi_nodes[None, :]
        tgt = _dirs(mu_t, phi_t).reshape(-1, 3)                     # (D, 3)
        dmu = np.diff(self.mu_edges)
        dphi = np.pi / g.n_phi
        a = (np.arange(k) + 0.5) / k
        mus = self.mu_edges[:-1, None] + dmu[:, None] * a[None, :]       # (n_mu, k)
        phis = (np.arange(g.n_phi)[:, None] + a[None, :]) * dphi        # (n_phi, k)
        MU = np.broadcast_to(mus[:, None, :, None], (g.n_mu, g.n_phi, k, k))
        PH = np.broadcast_to(phis[None, :, None, :], (g.n_mu, g.n_phi, k, k))
        src = np.concatenate([_dirs(MU, PH).reshape(g.n_mu * g.n_phi, k * k, 3),
                              _dirs(MU, -PH).reshape(g.n_mu * g.n_phi, k * k, 3)], axis=1)
        w = (dmu[:, None] * np.full(g.n_phi, dphi)[None, :]).reshape(-1, 1) / (k * k)
        pr, pm = np.empty((2, len(tgt), len(src)))
        for a0 in range(0, len(tgt), 64):                                # chunks of targets
            cos = np.einsum("dc,sjc->dsj", tgt[a0:a0 + 64], src)          # (64, D, 2k²)
            pr[a0:a0 + 64] = phase_rayleigh(cos).sum(-1) * w.T
            pm[a0:a0 + 64] = phase_mie_cornette_shanks(cos, self.params.g).sum(-1) * w.T
        self.p_r = pr / pr.sum(1, keepdims=True)
        self.p_m = pm / pm.sum(1, keepdims=True)

    def _gather(self, l_nodes: np.ndarray) -> np.ndarray:
        """J(n+1) at the nodes from L_n at the nodes."""
        g = self.grid
        D = g.n_mu * g.n_phi
        L = l_nodes.reshape(g.n_h, g.n_mu_s, D, 3)
        jr = np.einsum("ab,hsbc->hsac", self.p_r, L)
        jm = np.einsum("ab,hsbc->hsac", self.p_m, L)
        sr, sm = self.m.scattering(self.h_nodes)
        out = jr * sr[:, None, None, :] + jm * sm[:, None, None, :]
        return out.reshape(g.n_h, g.n_mu_s, g.n_mu, g.n_phi, 3)

    def _march_nodes(self, j_table: np.ndarray | None) -> np.ndarray:
        g, m = self.grid, self.m
        out = np.zeros((g.n_h, g.n_mu_s, g.n_mu, g.n_phi, 3))
        t, dt, h, mu_t, trans, r = _march(m, self.h_nodes[:, None], self.mu_nodes[None, :],
                                          g.steps)                      # (n_h, n_mu, steps)
        chunk = max(1, 4096 * 64 // (g.n_mu * g.n_phi * g.steps))       # μ_s nodes per block
        for i, k0 in ((i, k0) for i in range(g.n_h) for k0 in range(0, g.n_mu_s, chunk)):
            ks = slice(k0, k0 + chunk)
            r0 = m.R + self.h_nodes[i]
            nu = self._nu[i, ks][..., None]  # then (μ_s block, n_mu, n_phi, steps)
            tt = t[i][None, :, None, :]
            rr = r[i][None, :, None, :]
            mu_s_t = np.clip((r0 * self.mu_s_nodes[ks, None, None, None] + tt * nu) / rr, -1, 1)
            hh = np.broadcast_to(h[i][None, :, None, :], mu_s_t.shape)
            if j_table is None:
                src = _j1(m, hh, mu_s_t, np.broadcast_to(nu, mu_s_t.shape))
            else:
                mt = np.broadcast_to(mu_t[i][None, :, None, :], mu_s_t.shape)
                src = self.lookup(j_table, hh, mu_s_t, mt, _azimuth(mt, mu_s_t, nu))
            w = (trans[i] * dt[i][..., None])[None, :, None, :, :]
            out[i, ks] = (src * w).sum(-2)
        return out

    def lookup(self, table, h, mu_s, mu, phi):
        """4-linear read of a node table at (h, μ_s, μ, φ) (broadcast), clamped."""
        g = self.grid
        fh = np.sqrt(np.clip(h, 0.0, self.m.H) / self.m.H) * (g.n_h - 1)
        v = np.sign(mu_s) * np.sqrt(np.abs(mu_s))
        fs = (np.clip(v, _V_MIN, 1.0) - _V_MIN) / (1.0 - _V_MIN) * (g.n_mu_s - 1)
        fm = (np.clip(mu, -1.0, 1.0) + 1.0) / 2.0 * g.n_mu - 0.5
        fp = np.clip(phi, 0.0, np.pi) / np.pi * g.n_phi - 0.5
        strides = (g.n_mu_s * g.n_mu * g.n_phi, g.n_mu * g.n_phi, g.n_phi, 1)
        base, weights = 0, []  # the low corner's flat index; per axis (1 − w, w)
        for f, n, stride in zip((fh, fs, fm, fp), (g.n_h, g.n_mu_s, g.n_mu, g.n_phi), strides):
            i0, w = _cell(f, n)
            base = base + i0 * stride
            weights.append((1.0 - w, w))
        flat = np.ascontiguousarray(table.reshape(-1, 3).T)  # channels first: rows of samples
        out: np.ndarray = np.zeros(())
        for c in range(16):  # the corners: a fixed offset from the low one (take: no 2D index)
            bits = [(c >> k) & 1 for k in range(4)]
            w = weights[0][bits[0]]
            for k in range(1, 4):
                w = w * weights[k][bits[k]]
            out = out + flat.take(base + sum(b * s for b, s in zip(bits, strides)), axis=1) * w
        return np.ascontiguousarray(np.moveaxis(out, 0, -1))

    def averaged(self, over: str) -> dict[int, np.ndarray]:
        """The J_n tables averaged over the sphere of directions (``over="sphere"``: the best
        any isotropic source σ_s Ψ(h, μ_s) — Hillaire's form — can do) or over the azimuth
        (``"azimuth"``: the best a source Ψ(h, μ_s, μ) can do), broadcast back to the grid.
        Oracle bounds for the bench, built from the reference itself, not methods."""
        g = self.grid
        w = np.diff(self.mu_edges)[:, None] * np.ones(g.n_phi)[None, :]
        if over == "sphere":
            w = w / w.sum()
            return {n: np.broadcast_to((j * w[..., None]).sum((2, 3), keepdims=True), j.shape)
                    for n, j in self.j.items()}
        if over == "azimuth":
            return {n: np.broadcast_to(j.mean(3, keepdims=True), j.shape)
                    for n, j in self.j.items()}
        raise ValueError(f"over={over!r}: allowed sphere, azimuth")

    def orders_along(self, h_cam: float, elevation_deg, azimuth_deg, sun_elevation_deg: float,
                     steps: int = 1500, tables: dict | None = None) -> dict[int, np.ndarray]:
        """Radiance per order n (1: exact single scattering) toward each (elevation, azimuth
        from the sun) direction seen from altitude ``h_cam``, times the sun's radiance:
        {n: (N, 3)}; ``tables`` replaces the J_n tables (:meth:`averaged`)."""
        mu, mu_s, nu = _view(elevation_deg, azimuth_deg, sun_elevation_deg)
        t, dt, h, mu_t, trans, r = _march(self.m, np.full(mu.shape, h_cam), mu, steps)
        r0 = self.m.R + h_cam
        mu_s_t = np.clip((r0 * mu_s[:, None] + t * nu[:, None]) / r, -1, 1)
        w = trans * dt[..., None]
        E = self.params.sun_intensity
        out = {1: E * (_j1(self.m, h, mu_s_t, np.broadcast_to(nu[:, None], h.shape)) * w).sum(1)}
        phi = _azimuth(mu_t, mu_s_t, nu[:, None])
        for n, table in (self.j if tables is None else tables).items():
            out[n] = E * (self.lookup(np.ascontiguousarray(table), h, mu_s_t, mu_t, phi)
                          * w).sum(1)
        return out


def _dirs(mu, phi):
    s = np.sqrt(np.maximum(1.0 - mu * mu, 0.0))
    return np.stack(np.broadcast_arrays(s * np.cos(phi), s * np.sin(phi), mu), axis=-1)


def _azimuth(mu, mu_s, nu):
    """φ ∈ [0, π] of a direction at zenith cosine μ whose cosine with the sun (zenith cosine
    μ_s) is ν: ν = μ μ_s + sin θ sin θ_s cos φ."""
    den = np.sqrt(np.maximum(1 - mu * mu, 0.0) * np.maximum(1 - mu_s * mu_s, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.where(den > 1e-12, (nu - mu * mu_s) / np.maximum(den, 1e-300), 1.0)
    return np.arccos(np.clip(c, -1.0, 1.0))


def _view(elevation_deg, azimuth_deg, sun_elevation_deg):
    el = np.radians(np.atleast_1d(np.asarray(elevation_deg, dtype=float)))
    az = np.radians(np.atleast_1d(np.asarray(azimuth_deg, dtype=float)))
    el, az = np.broadcast_arrays(el, az)
    se = math.radians(sun_elevation_deg)
    mu = np.sin(el)
    nu = mu * math.sin(se) + np.cos(el) * math.cos(se) * np.cos(az)
    return mu, np.full(mu.shape, math.sin(se)), nu


# ==== Hillaire 2020's Ψ_ms, its numpy twin (converged integrals) =============================

def hillaire_ms_lut(params: atm.AtmosphereParams, size: int = 32, directions: int = 8,
                    steps: int = 200, infinite: bool = True, model: _Model | None = None,
                    first_phase: str = "isotropic"):
    """Ψ_ms (size, size, 3), row = altitude, column = μ_s, on the GPU's texel grid (unit
    coordinates i/(size−1)): Hillaire 2020's equations 5 (L_2nd, isotropic phase), 8 (f_ms),
    9 (F_ms = 1/(1 − f_ms), or 1 without ``infinite``) and 10 (Ψ_ms = L_2nd F_ms), on
    ``directions``² directions uniform in cos θ and φ, black ground.

    ``first_phase``: "isotropic" is Hillaire's choice (p_u for both scattering events); "full"
    gives the first event (sunlight scattered at x + tω toward x, cos θ = ω·s) the true Rayleigh
    and Mie phases; the second, at x, stays isotropic, so Ψ_ms is still a function of (h, μ_s)."""
    m = model or _Model(params)
    hs = np.linspace(0.0, 1.0, size) * m.H
    mus_s = np.linspace(0.0, 1.0, size) * 2.0 - 1.0
    n = directions
    mu_d, half = 1.0 - 2.0 * (np.arange(n) + 0.5) / n, (n + 1) // 2
    # φ and 2π − φ give one scattering angle ν: marched once, counted twice (φ = π once)
    cos_phi = np.cos(2.0 * np.pi * (np.arange(half) + 0.5) / n)   # φ uniform in [0, 2π)
    sin_d = np.sqrt(1 - mu_d ** 2)
    twice = np.where(np.arange(half) == n - 1 - np.arange(half), 1.0, 2.0)
    chunk = max(1, 16384 // (n * half * steps))  # sun cosines at a time: ~16k samples

    def channels(a):  # (n, steps, 3) → (3, 1, n, 1, steps): a row of samples per channel
        return np.ascontiguousarray(np.moveaxis(a, -1, 0))[:, None, :, None, :]
    out = np.zeros((size, size, 3))
    for i, h0 in enumerate(hs):
        t, dt, h, mu_t, trans, r = _march(m, np.full(n, h0), mu_d, steps)   # (n, steps)
        sr, sm = m.scattering(h)
        sig = sr + sm
        f = (trans * sig * dt[..., None]).sum(1).mean(0)                      # (3,)
        F = 1.0 / (1.0 - np.minimum(f, 0.999)) if infinite else np.ones(3)
        sun = m.sun_transmittance_at(h[:, None, :])                          # (n, 1, steps)
        w = channels(trans * dt[..., None])
        ws = w * channels(sig) * (1.0 / (4.0 * np.pi))                   # the phase p_u
        cr, cm = (channels(sr), channels(sm)) if first_phase == "full" else (None, None)
        for j in range(0, size, chunk):
            ms = mus_s[j:j + chunk, None, None]                              # (J, 1, 1)
            nu = mu_d[:, None] * ms + sin_d[:, None] * np.sqrt(np.maximum(0.0, 1 - ms * ms)) \
                * cos_phi                                                     # (J, n, half)
            mu_s_t = np.clip(((m.R + h0) * ms[..., None] + t[:, None, :] * nu[..., None])
                             / r[:, None, :], -1, 1)                          # (J, n, half, steps)
            ts = sun(mu_s_t)                                            # (3, J, n, half, steps)
            if first_phase == "full":
                ts *= w * (cr * phase_rayleigh(nu)[..., None]
                           + cm * phase_mie_cornette_shanks(nu, m.p.g)[..., None])
            else:
                ts *= ws
            L2 = (ts.sum(-1) * twice).sum((2, 3)) / (n * n)                   # (3, J)
            out[i, j:j + chunk] = L2.T * F
    return out


def ms_lookup(table, H: float, h, mu_s):
    """Bilinear Ψ_ms read as HillaireMultipleScatteringAt (vectorised twin of
    :func:`app.sim.hillaire.multiple_scattering_lookup`)."""
    rows, cols = table.shape[:2]
    y0, fy = _cell(np.clip(np.asarray(h) / H, 0.0, 1.0) * (rows - 1), rows)
    x0, fx = _cell(np.clip(0.5 * np.asarray(mu_s) + 0.5, 0.0, 1.0) * (cols - 1), cols)
    texels = np.asarray(table[..., :3], dtype=float).reshape(rows * cols, 3).T
    return np.ascontiguousarray(np.moveaxis(_bilinear(texels, y0 * cols + x0, fy, fx, cols), 0, -1))


def hillaire_multiple(params, table, h_cam: float, elevation_deg, azimuth_deg,
                      sun_elevation_deg: float, steps: int = 1500, model: _Model | None = None):
    """E_sun ∫ T σ_s Ψ_ms dt along the camera rays (Hillaire 2020 eq. 11's multiple term)."""
    m = model or _Model(params)
    mu, mu_s, nu = _view(elevation_deg, azimuth_deg, sun_elevation_deg)
    t, dt, h, mu_t, trans, r = _march(m, np.full(mu.shape, h_cam), mu, steps)
    r0 = m.R + h_cam
    mu_s_t = np.clip((r0 * mu_s[:, None] + t * nu[:, None]) / r, -1, 1)
    sr, sm = m.scattering(h)
    src = (sr + sm) * ms_lookup(table, m.H, h, mu_s_t)
    return params.sun_intensity * (src * trans * dt[..., None]).sum(1)


#: the chart's view elevations (degrees) and sun elevations
ELEVATIONS = (1.0, 2.0, 3.0, 5.0, 7.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0, 75.0, 90.0)
SUN_ELEVATIONS = (3.0, 10.0, 45.0)
H_CAM = 2.0


def compare(params: atm.AtmosphereParams | None = None, grid: Grid = Grid(), orders: int = 10,
            ms_size: int = 32, ms_directions: int = 8, elevations=ELEVATIONS,
            sun_elevations=SUN_ELEVATIONS, reference: Reference | None = None,
            lut=None, oracles=("sphere", "azimuth"), lut_steps: int = 60) -> dict:
    """Hillaire's sky (exact single + σ_s Ψ_ms) against the reference (exact single + orders
    2…``orders``) from 2 m up, toward (azimuth 0) and away from (180) the sun, per sun elevation.
    Errors are relative, per RGB channel; ``worst`` the largest |error| over directions and
    channels (signed). ``oracles``: the same with the reference's own sources averaged over the
    sphere or the azimuth (:meth:`Reference.averaged`), the bounds of what an isotropic 2D or
    an azimuth-averaged 3D Ψ could reach. Returns plain JSON-able numbers."""
    params = params or atm.AtmosphereParams()
    ref = reference or Reference(params, grid, orders)
    table = hillaire_ms_lut(params, ms_size, ms_directions, lut_steps, model=ref.m) \
        if lut is None else lut
    out: dict = {"grid": grid.__dict__, "orders": orders, "ms_size": ms_size,
                 "ms_directions": ms_directions, "elevations": list(elevations), "suns": {}}
    el = np.asarray(elevations, dtype=float)
    averaged = {over: ref.averaged(over) for over in oracles}
    for se in sun_elevations:
        per: dict = {}
        for name, az in (("toward", 0.0), ("away", 180.0)):
            o = ref.orders_along(H_CAM, el, np.full(el.shape, az), se)
            total: np.ndarray = np.sum(list(o.values()), axis=0)
            high = np.sum([v for n, v in o.items() if n >= 5], axis=0)
            last, before = o[orders], o[orders - 1]
            # the orders beyond the last, as the geometric tail of the last two
            tail = last * last / np.maximum(before - last, 1e-300)
            hil = o[1] + hillaire_multiple(params, table, H_CAM, el, np.full(el.shape, az), se,
                                           model=ref.m)
            err = hil / total - 1.0
            bounds = {}
            for over in oracles:
                ob = ref.orders_along(H_CAM, el, np.full(el.shape, az), se,
                                      tables=averaged[over])
                bounds[over] = (np.sum(list(ob.values()), axis=0) / total - 1.0).tolist()
            per[name] = {"reference": total.tolist(), "single": o[1].tolist(),
                         "hillaire": hil.tolist(), "error": err.tolist(),
                         "orders_ge5_share": float(np.max(high / total)),
                         "tail_share": float(np.max(tail / total)),
                         "per_order_share": {str(n): float(np.max(v / total))
                                             for n, v in o.items()},
                         "ms_share": (1.0 - o[1] / total).tolist(),
                         "oracle_error": bounds}
        errs = np.concatenate([np.asarray(per[k]["error"]) for k in per])
        k = int(np.argmax(np.abs(errs)))
        per["worst"] = float(errs.flat[k])
        for over in oracles:
            e = np.concatenate([np.asarray(per[k]["oracle_error"][over])
                                for k in ("toward", "away")])
            per[f"worst_oracle_{over}"] = float(e.flat[int(np.argmax(np.abs(e)))])
        out["suns"][str(se)] = per
    return out

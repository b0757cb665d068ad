"""Numpy twins of cloud model A's shader functions (``glsl/clouds/cloud_model.glsl``; the
cloud thesis, spec/001 §1.2–1.4 with the errata of §1.10 fixed): the tests compare the GPU with
these, function by function."""

from __future__ import annotations

import numpy as np

from .optics import henyey_greenstein


def density_length(base_height: float, max_height: float) -> float:
    """L_ref, metres per unit of accumulated density: the thesis's light step
    0.5 · thickness / 6."""
    return 0.5 * (max_height - base_height) / 6.0


def sat(v):
    """spec/001 eq. 4.2"""
    return np.clip(v, 0.0, 1.0)


def remap(v, ia, fa, in_, fn):
    """spec/001 eq. 4.1"""
    return in_ + (np.asarray(v, dtype=np.float64) - ia) * (fn - in_) / (fa - ia)


def height_fraction(h, base, top):
    """spec/001 eq. 4.4"""
    return sat((np.asarray(h, dtype=np.float64) - base) / max(top - base, 1e-3))


def round_bottom(pa):
    """spec/001 eq. 4.6"""
    return sat(remap(pa, 0.0, 0.07, 0.0, 1.0))


def round_top(pa, mca):
    """spec/001 eq. 4.7, 0 where mc_a = 0."""
    pa, mca = np.broadcast_arrays(np.asarray(pa, dtype=np.float64),
                                  np.asarray(mca, dtype=np.float64))
    with np.errstate(divide="ignore", invalid="ignore"):
        out = sat(remap(pa, 0.2 * mca, mca, 1.0, 0.0))
    return np.where(mca > 0.0, out, 0.0)


def density_bottom(pa):
    """spec/001 eq. 4.9"""
    return np.asarray(pa, dtype=np.float64) * sat(remap(pa, 0.0, 0.15, 0.0, 1.0))


def density_top(pa):
    """spec/001 eq. 4.10"""
    return sat(remap(pa, 0.9, 1.0, 1.0, 0.0))


def height_density(pa, global_density, mcd):
    """spec/001 eq. 4.11"""
    return global_density * density_bottom(pa) * density_top(pa) * mcd * 2.0


def cloud_density(weather, shape, detail, pa, coverage, global_density, with_detail=True):
    """The total density of spec/001 §1.3 and §1.4 (each line tagged with its equation) on
    arrays: weather (..., 4), shape (..., 4), detail (..., 3), pa (...)."""
    w, s, d = (np.asarray(a, dtype=np.float64) for a in (weather, shape, detail))
    pa = np.asarray(pa, dtype=np.float64)
    nub = w[..., 0] + (w[..., 1] - w[..., 0]) * coverage  # spec/001 eq. 4.5
    altura = round_bottom(pa) * round_top(pa, w[..., 2])  # spec/001 eq. 4.8
    dns = height_density(pa, global_density, w[..., 3])  # spec/001 eq. 4.11
    worley = 0.625 * s[..., 1] + 0.25 * s[..., 2] + 0.125 * s[..., 3]
    base = remap(s[..., 0], worley - 1.0, 1.0, 0.0, 1.0)  # spec/001 eq. 4.12
    c = coverage * nub
    with np.errstate(divide="ignore", invalid="ignore"):
        # spec/001 eq. 4.13
        forma = np.where(c > 0.0, sat(remap(base * altura, 1.0 - c, 1.0, 0.0, 1.0)), 0.0)
    if not with_detail:
        return forma * dns
    db = 0.625 * d[..., 0] + 0.25 * d[..., 1] + 0.125 * d[..., 2]  # spec/001 eq. 4.14
    # spec/001 eq. 4.15, sign fixed
    det = 0.35 * np.exp(-coverage * 0.75) * (db + ((1.0 - db) - db) * sat(pa * 5.0))
    # spec/001 eq. 4.16
    return np.where(forma > 0.0, sat(remap(forma, det, 1.0, 0.0, 1.0)), 0.0) * dns


def beer(b, ds):
    """spec/001 eq. 4.18"""
    return np.exp(-np.asarray(b, dtype=np.float64) * ds)


def silver_lobe(cos_theta, intensity, exponent):
    """spec/001 eq. 4.20 with Sat(cos θ)."""
    return intensity * sat(np.asarray(cos_theta, dtype=np.float64)) ** exponent


def in_out_scatter(cos_theta, in_s=0.2, out_s=0.1, ivo=0.5, cs_i=3.0, cs_e=2.0):
    """spec/001 eq. 4.21; the defaults are the lighting preset of spec/001 §2."""
    fwd = np.maximum(henyey_greenstein(cos_theta, in_s), silver_lobe(cos_theta, cs_i, cs_e))
    return fwd + (henyey_greenstein(cos_theta, -out_s) - fwd) * ivo


def powder(b, ds):
    """spec/001 eq. 4.22"""
    return 2.0 * beer(b, ds) * (1.0 - beer(b, 2.0 * np.asarray(ds, dtype=np.float64)))



"""Fractal sums of noise — numpy twin of ``glsl/common/noise_fbm.glsl``.

Sources: fBm as spec/001 eq. 3.1 and spec/001 eq. 3.2 (spec/001 §1.1, after Quilez);
turbulence (Perlin 1985, the sum of |noise|); Perlin–Worley as in Schneider, "The real-time
volumetric cloudscapes of Horizon: Zero Dawn", SIGGRAPH 2015 (the remap
of the cloud thesis's shape texture, red channel, spec/001 §1.1; spec/000 §1.6).

Octave sums, with a_0 = 1, a_i = G·a_{i−1} (gain G) and f_0 = 1, f_i = L·f_{i−1}
(lacunarity L); G = L^(−H) when the Hurst exponent H is given instead (spec/001 eq. 3.1 with
L = 2):

    fbm(p)        = Σ_{i<n} a_i · noise(f_i p) / Σ_{i<n} a_i      (spec/001 eq. 3.2, normalised)
    turbulence(p) = Σ_{i<n} a_i · |noise(f_i p)| / Σ_{i<n} a_i
    worley_fbm(p) = Σ_{i<n} a_i · (1 − clamp(F1(f_i p), 0, 1)) / Σ_{i<n} a_i   ∈ [0, 1]

The division by Σ a_i (our choice; spec/001 eq. 3.1 is the bare sum) keeps each sum in its base
noise's range, so one octave is exactly the base noise (spec/001 §6, criterion B5) and the
Perlin–Worley remap below sees inputs of known range.

Perlin–Worley (exact formula used here and in GLSL ``PerlinWorleyRemap``):

    P  = clamp(0.5 + 0.5 · perlin_fbm(p), 0, 1)         Perlin fBm mapped to [0, 1]
    W  = worley_fbm(p)                                   inverted-Worley fBm, [0, 1]
    PW = clamp(remap(P, W − 1, 1, 0, 1), 0, 1) = clamp((P + 1 − W) / (2 − W), 0, 1)

with remap(v, l0, h0, l1, h1) = l1 + (v − l0)(h1 − l1)/(h0 − l0). Where W = 1 (at Worley
feature points of every octave) PW = P; where W = 0 PW = (P + 1)/2: the Worley cells lift
the Perlin field into billows. 2 − W ≥ 1, so the division is always safe.

Tileable variants (for bakes): the lattice or cell index of octave i wraps with period
base_period · L^i, which needs an integer lacunarity L; the sum then tiles with
``base_period`` in p on every axis.

Seeds: Perlin sums take ``seed`` as a permutation seed (``app.sim.noise.gradient.permutation``:
None/0 = Perlin's table); Worley sums take it as the uint32 hash seed (None = 0). Perlin–Worley
uses the same ``seed`` for both. All octaves share the seed.

Known artefact of spec/001 eq. 3.1 with integer lacunarity: Perlin noise is 0 at lattice points
and the lattices of all octaves contain the integer points, so Perlin fBm is 0 at every
integer p.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from . import cellular, gradient


def gain_for(lacunarity: float = 2.0, gain: float | None = None, H: float | None = None) -> float:
    """The octave gain G: ``gain`` if given, else L^(−H) if ``H`` is given, else 1/2
    (G = 2^(−H) of spec/001 eq. 3.2)."""
    if gain is not None and H is not None:
        raise ValueError("give the fBm gain or its Hurst exponent H, not both")
    if H is not None:
        return float(lacunarity) ** (-float(H))
    return 0.5 if gain is None else float(gain)


#: The GLSL side clamps octaves to [1, FBM_MAX_OCTAVES] (noise_fbm.glsl); the twin refuses others.
MAX_OCTAVES = 16


def _check_octaves(octaves: int) -> int:
    octaves = int(octaves)
    if not 1 <= octaves <= MAX_OCTAVES:
        raise ValueError(f"fBm octaves={octaves}: allowed 1..{MAX_OCTAVES}")
    return octaves


def _int_lacunarity(lacunarity) -> int:
    lac = round(float(lacunarity))
    if lac < 1 or lac != float(lacunarity):
        raise ValueError(f"tileable fBm needs an integer lacunarity ≥ 1, got {lacunarity}")
    return lac


def octave_sum(noise: Callable[..., np.ndarray], coords, octaves: int = 5, lacunarity: float = 2.0,
               gain: float | None = None, H: float | None = None) -> np.ndarray:
    """Σ a_i noise(f_i·coords, i) / Σ a_i — the generic form of every sum in this module
    (spec/001 eq. 3.2, normalised).

    ``noise(scaled_coords, i)`` gets the coordinates already multiplied by f_i and the octave
    index (for per-octave periods)."""
    octaves = _check_octaves(octaves)
    g = gain_for(lacunarity, gain, H)
    coords = [np.asarray(c, dtype=np.float64) for c in coords]
    total, amp, freq, norm = 0.0, 1.0, 1.0, 0.0
    for i in range(octaves):
        total = total + amp * noise([c * freq for c in coords], i)
        norm += amp
        amp *= g
        freq *= float(lacunarity)
    return total / norm


def perlin_fbm3(x, y, z, octaves: int = 5, lacunarity: float = 2.0, gain: float | None = None,
                H: float | None = None, seed: int | None = None) -> np.ndarray:
    """Normalised fBm of ``perlin3``; twin of GLSL ``PerlinFbm3``."""
    return octave_sum(lambda c, i: gradient.perlin3(*c, seed=seed), (x, y, z),
                      octaves, lacunarity, gain, H)


def perlin_fbm2(x, y, octaves: int = 5, lacunarity: float = 2.0, gain: float | None = None,
                H: float | None = None, seed: int | None = None) -> np.ndarray:
    """Normalised fBm of ``perlin2``; twin of GLSL ``PerlinFbm2``."""
    return octave_sum(lambda c, i: gradient.perlin2(*c, seed=seed), (x, y),
                      octaves, lacunarity, gain, H)


def perlin_turbulence3(x, y, z, octaves: int = 5, lacunarity: float = 2.0,
                       gain: float | None = None, H: float | None = None,
                       seed: int | None = None) -> np.ndarray:
    """Σ a_i |perlin3(f_i p)| / Σ a_i ≥ 0; twin of GLSL ``PerlinTurbulence3``."""
    return octave_sum(lambda c, i: np.abs(gradient.perlin3(*c, seed=seed)), (x, y, z),
                      octaves, lacunarity, gain, H)


def perlin_turbulence2(x, y, octaves: int = 5, lacunarity: float = 2.0, gain: float | None = None,
                       H: float | None = None, seed: int | None = None) -> np.ndarray:
    """Σ a_i |perlin2(f_i p)| / Σ a_i ≥ 0; twin of GLSL ``PerlinTurbulence2``."""
    return octave_sum(lambda c, i: np.abs(gradient.perlin2(*c, seed=seed)), (x, y),
                      octaves, lacunarity, gain, H)


def _periodic_sum(basis, coords, period, octaves, lacunarity, gain, H) -> np.ndarray:
    """``octave_sum`` of ``basis(c, periods)``, octave i tiling with period·L^i cells."""
    lac = _int_lacunarity(lacunarity)
    base = np.broadcast_to(np.asarray(period, dtype=np.int64), (len(coords),))
    return octave_sum(lambda c, i: basis(c, base * lac**i), coords, octaves, lac, gain, H)


def perlin_fbm3_periodic(x, y, z, period, octaves: int = 5, lacunarity: int = 2,
                         gain: float | None = None, H: float | None = None,
                         seed: int | None = None) -> np.ndarray:
    """``perlin_fbm3`` tiling with ``period`` (int or 3 ints); twin of ``PerlinFbm3Periodic``."""
    return _periodic_sum(lambda c, per: gradient.perlin3_periodic(*c, per, seed=seed), (x, y, z),
                         period, octaves, lacunarity, gain, H)


def perlin_fbm2_periodic(x, y, period, octaves: int = 5, lacunarity: int = 2,
                         gain: float | None = None, H: float | None = None,
                         seed: int | None = None) -> np.ndarray:
    """``perlin_fbm2`` tiling with ``period`` (int or 2 ints); twin of ``PerlinFbm2Periodic``."""
    return _periodic_sum(lambda c, per: gradient.perlin2_periodic(*c, per, seed=seed), (x, y),
                         period, octaves, lacunarity, gain, H)


def perlin_turbulence3_periodic(x, y, z, period, octaves: int = 5, lacunarity: int = 2,
                                gain: float | None = None, H: float | None = None,
                                seed: int | None = None) -> np.ndarray:
    """Tileable ``perlin_turbulence3``; twin of ``PerlinTurbulence3Periodic``."""
    return _periodic_sum(lambda c, per: np.abs(gradient.perlin3_periodic(*c, per, seed=seed)),
                         (x, y, z), period, octaves, lacunarity, gain, H)


def perlin_turbulence2_periodic(x, y, period, octaves: int = 5, lacunarity: int = 2,
                                gain: float | None = None, H: float | None = None,
                                seed: int | None = None) -> np.ndarray:
    """Tileable ``perlin_turbulence2``; twin of ``PerlinTurbulence2Periodic``."""
    return _periodic_sum(lambda c, per: np.abs(gradient.perlin2_periodic(*c, per, seed=seed)),
                         (x, y), period, octaves, lacunarity, gain, H)


def worley_fbm3(x, y, z, octaves: int = 3, lacunarity: float = 2.0, gain: float | None = None,
                H: float | None = None, seed: int | None = 0) -> np.ndarray:
    """Normalised fBm of the inverted F1, in [0, 1]; twin of GLSL ``WorleyFbm3``."""
    return octave_sum(lambda c, i: cellular.worley_inverted_f1(cellular.worley3(*c, seed=seed)[0]),
                      (x, y, z), octaves, lacunarity, gain, H)


def worley_fbm2(x, y, octaves: int = 3, lacunarity: float = 2.0, gain: float | None = None,
                H: float | None = None, seed: int | None = 0) -> np.ndarray:
    """2D ``worley_fbm3``; twin of GLSL ``WorleyFbm2``."""
    return octave_sum(lambda c, i: cellular.worley_inverted_f1(cellular.worley2(*c, seed=seed)[0]),
                      (x, y), octaves, lacunarity, gain, H)


def worley_fbm3_periodic(x, y, z, period, octaves: int = 3, lacunarity: int = 2,
                         gain: float | None = None, H: float | None = None,
                         seed: int | None = 0) -> np.ndarray:
    """Tileable ``worley_fbm3``: octave i has period·L^i cells; twin of ``WorleyFbm3Periodic``."""
    return _periodic_sum(
        lambda c, p: cellular.worley_inverted_f1(cellular.worley3_periodic(*c, p, seed=seed)[0]),
        (x, y, z), period, octaves, lacunarity, gain, H)


def worley_fbm2_periodic(x, y, period, octaves: int = 3, lacunarity: int = 2,
                         gain: float | None = None, H: float | None = None,
                         seed: int | None = 0) -> np.ndarray:
    """Tileable ``worley_fbm2``; twin of ``WorleyFbm2Periodic``."""
    return _periodic_sum(
        lambda c, p: cellular.worley_inverted_f1(cellular.worley2_periodic(*c, p, seed=seed)[0]),
        (x, y), period, octaves, lacunarity, gain, H)


def perlin_worley_remap(perlin_fbm, worley_fbm) -> np.ndarray:
    """PW = clamp((P + 1 − W)/(2 − W), 0, 1) with P = clamp(0.5 + 0.5·perlin_fbm, 0, 1) and
    W = worley_fbm (module doc); twin of GLSL ``PerlinWorleyRemap``."""
    p = np.clip(0.5 + 0.5 * np.asarray(perlin_fbm, dtype=np.float64), 0.0, 1.0)
    w = np.asarray(worley_fbm, dtype=np.float64)
    return np.clip((p + 1.0 - w) / (2.0 - w), 0.0, 1.0)


def perlin_worley3(x, y, z, octaves: int = 3, lacunarity: float = 2.0, gain: float | None = None,
                   H: float | None = None, seed: int | None = None) -> np.ndarray:
    """Perlin–Worley from a Perlin fBm and an inverted-Worley fBm with the same octave
    parameters; twin of GLSL ``PerlinWorley3``."""
    return perlin_worley_remap(perlin_fbm3(x, y, z, octaves, lacunarity, gain, H, seed),
                               worley_fbm3(x, y, z, octaves, lacunarity, gain, H, seed))


def perlin_worley2(x, y, octaves: int = 3, lacunarity: float = 2.0, gain: float | None = None,
                   H: float | None = None, seed: int | None = None) -> np.ndarray:
    """2D ``perlin_worley3``; twin of GLSL ``PerlinWorley2``."""
    return perlin_worley_remap(perlin_fbm2(x, y, octaves, lacunarity, gain, H, seed),
                               worley_fbm2(x, y, octaves, lacunarity, gain, H, seed))


def perlin_worley3_periodic(x, y, z, period, octaves: int = 3, lacunarity: int = 2,
                            gain: float | None = None, H: float | None = None,
                            seed: int | None = None) -> np.ndarray:
    """Tileable ``perlin_worley3``; twin of GLSL ``PerlinWorley3Periodic``."""
    return perlin_worley_remap(
        perlin_fbm3_periodic(x, y, z, period, octaves, lacunarity, gain, H, seed),
        worley_fbm3_periodic(x, y, z, period, octaves, lacunarity, gain, H, seed))


def perlin_worley2_periodic(x, y, period, octaves: int = 3, lacunarity: int = 2,
                            gain: float | None = None, H: float | None = None,
                            seed: int | None = None) -> np.ndarray:
    """Tileable ``perlin_worley2``; twin of GLSL ``PerlinWorley2Periodic``."""
    return perlin_worley_remap(
        perlin_fbm2_periodic(x, y, period, octaves, lacunarity, gain, H, seed),
        worley_fbm2_periodic(x, y, period, octaves, lacunarity, gain, H, seed))

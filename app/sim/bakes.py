"""Numpy twins of the bake shaders (``glsl/bakes/*.glsl``), built from the noise twins in
``app.sim.noise`` — for small sizes (16³ takes well under a second; 128³ would take minutes).

A spec is one of ``app.bakes.params``' ShapeBake, DetailBake or WeatherBake, read here only by
attribute (this module stays below ``app.bakes``). Each ``*_reference(spec)`` returns the raw
float64 channels the GPU writes into its RGBA32F volume, before :func:`app.bakes.core.finish`
normalises and quantises them; the coordinates are formed in float32 exactly as the shaders
form them (texel centre (g + 0.5) / size, times the period), then evaluated in float64 by the
twins.
"""

from __future__ import annotations

import numpy as np

from .noise import fractal, gradient

_U32 = 0xFFFFFFFF


def texel_centres(n: int) -> np.ndarray:
    """(g + 0.5) / n in float32, as ``bake3d_*.glsl`` computes uvw."""
    return ((np.arange(n, dtype=np.float32) + np.float32(0.5)) / np.float32(n)).astype(np.float32)


def _grid3(n: int):
    s = texel_centres(n)
    z, y, x = np.meshgrid(s, s, s, indexing="ij")  # array order (depth, height, width)
    return x, y, z


def _scaled(coords, factor) -> list[np.ndarray]:
    f = np.float32(factor)
    return [(c * f).astype(np.float32).astype(np.float64) for c in coords]


def _worley_channel(coords, cells: int, octaves: int, gain: float, seed: int) -> np.ndarray:
    p = _scaled(coords, cells)
    return fractal.worley_fbm3_periodic(*p, cells, octaves=octaves, lacunarity=2, gain=gain,
                                        seed=seed & _U32)


def shape_reference(spec) -> np.ndarray:
    """(size, size, size, 4) float64: R Perlin–Worley, G/B/A inverted-Worley fBm."""
    coords = _grid3(spec.size)
    p = _scaled(coords, spec.base_cells)
    perlin = fractal.perlin_fbm3_periodic(*p, spec.base_cells, octaves=spec.perlin_octaves,
                                          lacunarity=2, gain=spec.gain, seed=spec.seed)
    worley = fractal.worley_fbm3_periodic(*p, spec.base_cells, octaves=spec.base_worley_octaves,
                                          lacunarity=2, gain=spec.gain,
                                          seed=(spec.seed * 8) & _U32)
    channels = [fractal.perlin_worley_remap(perlin, worley)]
    for i, cells in enumerate((spec.cells_g, spec.cells_b, spec.cells_a), start=1):
        channels.append(_worley_channel(coords, cells, spec.worley_octaves, spec.gain,
                                        spec.seed * 8 + i))
    return np.stack(channels, axis=-1)


def detail_reference(spec) -> np.ndarray:
    """(size, size, size, 4) float64: R/G/B inverted-Worley fBm, A = 1."""
    coords = _grid3(spec.size)
    channels = [_worley_channel(coords, cells, spec.octaves, spec.gain, spec.seed * 8 + 4 + i)
                for i, cells in enumerate((spec.cells_r, spec.cells_g, spec.cells_b))]
    channels.append(np.ones_like(channels[0]))
    return np.stack(channels, axis=-1)


#: K of the max-height field (WEATHER_HEIGHT_LATTICE_OFFSET in weather_map.glsl).
HEIGHT_LATTICE_OFFSET = (128, 64)


def weather_noise(px, py, cells: int, lattice_offset=(0, 0), seed: int | None = None) -> np.ndarray:
    """noise_K of weather_map.glsl: ``perlin2_periodic`` with the wrapped lattice index shifted
    by ``lattice_offset`` (mod 256) before hashing; (0, 0) is ``perlin2_periodic`` itself."""
    perm = gradient.permutation(seed)
    X0, X1, x = gradient._lattice(px, cells)
    Y0, Y1, y = gradient._lattice(py, cells)
    kx, ky = lattice_offset
    X0, X1, Y0, Y1 = (X0 + kx) & 255, (X1 + kx) & 255, (Y0 + ky) & 255, (Y1 + ky) & 255
    u, v = gradient.fade(x), gradient.fade(y)
    A, B = perm[X0], perm[X1]
    g = gradient._grad2
    lerp = gradient._lerp
    return lerp(v, lerp(u, g(perm[(A + Y0) & 255], x, y), g(perm[(B + Y0) & 255], x - 1, y)),
                lerp(u, g(perm[(A + Y1) & 255], x, y - 1), g(perm[(B + Y1) & 255], x - 1, y - 1)))


def weather_fbm(spec, qx: np.ndarray, qy: np.ndarray, lattice_offset=(0, 0)) -> np.ndarray:
    """F_K(q) of weather_map.glsl: the layered tiling Perlin fBm at float32 points q (maps);
    spec/001 eq. 3.2, normalised by the sum of the amplitudes."""
    cells = spec.layer_cells()
    total, norm, amp = 0.0, 0.0, 1.0
    for i in range(spec.layers):
        c = np.float32(cells[i])
        px = (qx * c).astype(np.float32).astype(np.float64)
        py = (qy * c).astype(np.float32).astype(np.float64)
        total = total + amp * weather_noise(px, py, cells[i], lattice_offset, spec.seed)
        norm += amp
        amp *= float(np.float32(spec.persistence))
    return total / norm


def weather_reference(spec) -> np.ndarray:
    """(size, size, 4) float64: low coverage, high coverage, max height, density (row 0 is
    v = 0, as in the texture)."""
    s = texel_centres(spec.size)
    v, u = np.meshgrid(s, s, indexing="ij")
    ox, oy = (np.float32(o) for o in spec.wrapped_offset())
    qx = (u + ox).astype(np.float32)
    qy = (v + oy).astype(np.float32)
    k = float(np.float32(spec.contrast))
    low = np.clip(0.5 + 0.5 * k * weather_fbm(spec, qx, qy), 0.0, 1.0)
    height = np.clip(0.5 + 0.5 * k * weather_fbm(spec, qx, qy, HEIGHT_LATTICE_OFFSET), 0.0, 1.0)
    high = 1.0 - (1.0 - low) ** 2
    density = np.full_like(low, float(np.float32(spec.density)))
    return np.stack([low, high, height, density], axis=-1)


def reference(spec) -> np.ndarray:
    """The raw float channels of any bake spec (by its ``kind``)."""
    twins = {"shape": shape_reference, "detail": detail_reference, "weather": weather_reference}
    kind = getattr(spec, "kind", None)
    if kind not in twins:
        raise TypeError(f"no reference for {type(spec).__name__}")
    return twins[kind](spec)

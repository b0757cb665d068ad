"""Geometry of the `planet` scene (spec/002 §5: mountains, a city, the Earth, the universe).

The Earth itself is an analytic sphere hit per pixel (no tessellation error from 2 m above the
sea to space); the mountains and the city block are meshes in a local tangent frame at the
scene origin (y up, the planet centre at (0, −R, 0)), bent down by the planet's curvature so they
sit on the sphere. Vertices carry position, normal, tangent and a texture coordinate in metres
(for the albedo and normal-map textures, which tile).
"""

from __future__ import annotations

import numpy as np

from ...sim.noise.fractal import perlin_fbm2


def curvature_drop(x, z, radius: float) -> np.ndarray:
    """How far the sphere falls below the tangent plane at horizontal distance √(x² + z²)."""
    d2 = np.asarray(x) ** 2 + np.asarray(z) ** 2
    return d2 / (radius + np.sqrt(np.maximum(radius * radius - d2, 0.0)))


def _pack(pos, nor, tan, uv, idx):
    verts = np.hstack([pos, nor, tan, uv]).astype("f4")
    return verts, idx.astype("u4")


def mountains(radius: float, size: float = 20000.0, grid: int = 192, centre=(0.0, -17000.0),
              peak: float = 2400.0, seed: int = 5):
    """A ridged fBm heightfield (size × size metres) whose base follows the sphere."""
    n = grid + 1
    xs = np.linspace(-size / 2, size / 2, n) + centre[0]
    zs = np.linspace(-size / 2, size / 2, n) + centre[1]
    x, z = np.meshgrid(xs, zs)
    u = (x - centre[0]) / size * 3.3 + 0.37  # off the lattice: fBm vanishes at integer points
    v = (z - centre[1]) / size * 3.3 + 0.61
    ridge = 1.0 - np.abs(perlin_fbm2(u, v, octaves=6, lacunarity=2.07, seed=seed))
    ridge = ridge**2
    fall = np.clip(1.0 - (np.hypot(x - centre[0], z - centre[1]) / (size * 0.5)) ** 2, 0.0, 1.0)
    h = peak * ridge * fall - 30.0
    y = h - curvature_drop(x, z, radius)
    pos = np.stack([x, y, z], -1).reshape(-1, 3)
    dx = np.gradient(y, xs, axis=1)
    dz = np.gradient(y, zs, axis=0)
    nor = np.stack([-dx, np.ones_like(dx), -dz], -1)
    nor /= np.linalg.norm(nor, axis=-1, keepdims=True)
    tan = np.stack([np.ones_like(dx), dx, np.zeros_like(dx)], -1)
    tan /= np.linalg.norm(tan, axis=-1, keepdims=True)
    uv = np.stack([x, z], -1).reshape(-1, 2)
    r, c = np.meshgrid(np.arange(grid), np.arange(grid), indexing="ij")
    a = r * n + c
    idx = np.stack([a, a + n, a + 1, a + 1, a + n, a + n + 1], -1).reshape(-1)
    return _pack(pos, nor.reshape(-1, 3), tan.reshape(-1, 3), uv, idx)


def boxes(radius: float, count: int = 24, centre=(0.0, -400.0), spread: float = 180.0,
          seed: int = 11):
    """A small city block: boxes of random footprint and height on the sphere."""
    rng = np.random.default_rng(seed)
    pos, nor, tan, uv, idx = [], [], [], [], []
    cols = int(np.ceil(np.sqrt(count)))
    for k in range(count):
        gx, gz = k % cols, k // cols
        cx = centre[0] + (gx - cols / 2) * spread / cols * 2.0
        cz = centre[1] + (gz - cols / 2) * spread / cols * 2.0
        w, d = rng.uniform(12, 28, 2)
        h = rng.uniform(10, 90)
        base = -float(curvature_drop(cx, cz, radius))
        lo = np.array([cx - w / 2, base - 1.0, cz - d / 2])
        hi = np.array([cx + w / 2, base + h, cz + d / 2])
        for axis in range(3):
            for sign in (-1.0, 1.0):
                if axis == 1 and sign < 0:
                    continue  # no floor
                n_ = np.zeros(3)
                n_[axis] = sign
                a1, a2 = (axis + 1) % 3, (axis + 2) % 3
                t_ = np.zeros(3)
                t_[a1] = 1.0
                start = len(pos)
                for s1, s2 in ((0, 0), (1, 0), (1, 1), (0, 1)):
                    p = np.where(n_ > 0, hi, np.where(n_ < 0, lo, 0.0))
                    p[a1] = (lo, hi)[s1][a1]
                    p[a2] = (lo, hi)[s2][a2]
                    pos.append(p)
                    nor.append(n_)
                    tan.append(t_)
                    uv.append((p[a1], p[a2]))
                quad = [start, start + 1, start + 2, start, start + 2, start + 3]
                if np.dot(np.cross(pos[start + 1] - pos[start], pos[start + 2] - pos[start]),
                          n_) < 0:
                    quad = [start, start + 2, start + 1, start, start + 3, start + 2]
                idx += quad
    return _pack(np.array(pos), np.array(nor), np.array(tan), np.array(uv), np.array(idx))


def albedo_texture(size: int = 256, seed: int = 2) -> np.ndarray:
    """A tileable rock/grass albedo (RGBA8)."""
    y, x = np.mgrid[0:size, 0:size] / size
    from ...sim.noise.fractal import perlin_fbm2_periodic

    n = perlin_fbm2_periodic(x * 8, y * 8, (8, 8), octaves=5, seed=seed)
    t = np.clip(0.5 + 0.7 * n, 0, 1)[..., None]
    rock = np.array([0.42, 0.38, 0.33])
    grass = np.array([0.22, 0.3, 0.14])
    rgb = rock * t + grass * (1 - t)
    out = np.concatenate([rgb, np.ones((size, size, 1))], -1)
    return np.round(np.clip(out, 0, 1) * 255).astype(np.uint8)


def normal_texture(size: int = 256, seed: int = 3, strength: float = 2.5) -> np.ndarray:
    """A tileable tangent-space normal map (RGBA8, (0.5, 0.5, 1) = flat) from periodic fBm."""
    y, x = np.mgrid[0:size, 0:size] / size
    from ...sim.noise.fractal import perlin_fbm2_periodic

    h = perlin_fbm2_periodic(x * 16, y * 16, (16, 16), octaves=4, seed=seed)
    gx = (np.roll(h, -1, axis=1) - np.roll(h, 1, axis=1)) * size / 2 * strength / size * 8
    gy = (np.roll(h, -1, axis=0) - np.roll(h, 1, axis=0)) * size / 2 * strength / size * 8
    n = np.stack([-gx, -gy, np.ones_like(gx)], -1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    out = np.concatenate([n * 0.5 + 0.5, np.ones((size, size, 1))], -1)
    return np.round(out * 255).astype(np.uint8)

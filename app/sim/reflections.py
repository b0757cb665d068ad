"""Reflection probes and metallic/dielectric of the surfaces lab (spec/003 §2.5, §2.6): the
numpy twin of ``glsl/surfaces/reflection.glsl`` (one function each), the Unity NHxRoughness
texture it samples, and the split-sum GGX reference's LUT (Karis 2013). No GL here.

Readings of the thesis (spec/003 §2.5, from the seed text):

* box projection — with r unit, cos(r, x̂) = r_x, so d_x = dx_f / r_x is the distance along r
  to the face plane r heads for on x; d = min(d_x, d_y, d_z) (spec/003 eq. 5.4 extended to 3D, as
  criterion 21 asks), and the lookup is r' = d·r + (P − C) (spec/003 eq. 5.1);
* the quadratic stretch — in the thesis's 2D figure the face of the box that r hits first is a
  segment; x runs 0 → 1 across it, and f(x, h) = 4hx(1 − x) (spec/003 eq. 5.9) lengthens d
  by h at the face's middle and by 0 at its ends (the corners), so the box hit is pushed out
  toward a sphere through the corners; h = d_cmax − d_cmin with d_cmax the sphere's radius
  ("radius = d_cmax") and d_cmin the probe's distance to that face. In 3D a face has two
  in-face axes: we average f over them (h at the centre, h/2 at an edge's middle, 0 at the
  corners — for a cube within 0.05 half-sizes of the true gap to the circumscribed sphere along the
  edges);
* the perfect sphere — the segment from P0 = P to P1 = P + L·r with L = 2r_s + |P − C|, long
  enough to leave a sphere containing P, is solved for t ∈ [0, 1] (spec/003 eq. 5.10 to
  spec/003 eq. 5.17) and the lookup is P(t) − C.

Unity's NHxRoughness texture (``unity_NHxRoughness``, UnityStandardBRDF.cginc's BRDF3_Direct
reads it at (RdotL⁴, perceptual roughness) and × LUT_RANGE = 16; the texture itself is made in
Unity's engine code, not public). We rebuild it as the normalised Blinn-Phong lobe that its
"Modified Normalized Blinn-Phong" comment names, with Unity's own roughness → power mapping
(RoughnessToSpecPower): texel (u, v) with c = u^(1/4), m = v², n = max(2 / max(m², 1e-4) − 2,
1e-4) holds min((n + 2) / (2π) · cᴺ / 16, 1). Low roughness gives a lobe narrower than a texel
column, so the LUT reads 0 almost everywhere there, as the thesis observes (Fig. 61). The
thesis samples it with (n·h)⁴ instead of Unity's (r·l)⁴.
"""

from __future__ import annotations

import numpy as np

#: ``surfaces.reflection`` choices → reflection.glsl's mode codes
MODES = ("none", "cube", "box", "approximation", "perfect")
MODE_CODE = {m: i for i, m in enumerate(MODES)}
#: Unity's UNITY_SPECCUBE_LOD_STEPS and LUT_RANGE
LOD_STEPS = 6.0
LUT_RANGE = 16.0


def _mode(mode) -> int:
    if isinstance(mode, str):
        if mode not in MODE_CODE:
            raise ValueError(f"reflection mode {mode!r}: allowed {', '.join(MODES)}")
        return MODE_CODE[mode]
    if int(mode) not in range(len(MODES)):
        raise ValueError(f"reflection mode {mode!r}: allowed 0–4 or {', '.join(MODES)}")
    return int(mode)


def box_distances(p, direction, box_min, box_max) -> np.ndarray:
    """(..., 3) distances along ``direction`` (unit) to the face plane it heads for on each
    axis — spec/003 eq. 5.2 (x), spec/003 eq. 5.3 (y) and z alike; inf for a component ~0."""
    p, d = np.broadcast_arrays(np.asarray(p, float), np.asarray(direction, float))
    face = np.where(d >= 0.0, np.asarray(box_max, float), np.asarray(box_min, float))
    ok = np.abs(d) >= 1e-8
    with np.errstate(divide="ignore", invalid="ignore"):
        out = (face - p) / np.where(ok, d, 1.0)
    return np.where(ok, out, 1e30)


def box_distance(p, direction, box_min, box_max) -> np.ndarray:
    """d = min(d_x, d_y, d_z), at least 0 (spec/003 eq. 5.4, in 3D)."""
    return np.maximum(box_distances(p, direction, box_min, box_max).min(-1), 0.0)


def quadratic_stretch(x, h):
    """f(x, h) = 4hx(1 − x) with x clamped to [0, 1] (spec/003 eq. 5.9)."""
    x = np.clip(x, 0.0, 1.0)
    return 4.0 * np.asarray(h, float) * x * (1.0 - x)


def sphere_segment_t(p0, p1, centre, radius) -> np.ndarray:
    """t where P(t) = (p1 − p0)t + p0 leaves the sphere |X − C| = r (spec/003 eq. 5.17, with
    a, b, c of spec/003 eq. 5.14, spec/003 eq. 5.15, spec/003 eq. 5.16); −1 on a miss."""
    seg = np.asarray(p1, float) - np.asarray(p0, float)  # spec/003 eq. 5.11
    oc = np.asarray(p0, float) - np.asarray(centre, float)
    a = np.einsum("...i,...i", seg, seg)
    b = 2.0 * np.einsum("...i,...i", seg, oc)
    c = np.einsum("...i,...i", oc, oc) - float(radius) ** 2  # spec/003 eq. 5.16
    disc = b * b - 4.0 * a * c
    ok = (disc >= 0.0) & (a > 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (-b + np.sqrt(np.maximum(disc, 0.0))) / (2.0 * np.where(a > 0, a, 1.0))
    return np.where(ok, t, -1.0)


def perfect_segment(p, direction, probe_pos, sphere_radius):
    """(p1, t) of the perfect sphere's segment from ``p`` along ``direction``."""
    p = np.asarray(p, float)
    d = np.asarray(direction, float)
    length = 2.0 * sphere_radius + np.linalg.norm(p - np.asarray(probe_pos, float), axis=-1)
    p1 = p + length[..., None] * d
    return p1, sphere_segment_t(p, p1, probe_pos, sphere_radius)


def compute_reflex_direction(mode, world_pos, direction, probe_pos, box_min, box_max,
                             sphere_radius: float) -> np.ndarray:
    """The direction to sample the probe with (reflection.glsl's ComputeReflexDirection):
    ``mode`` none/cube → ``direction``; box → d·r + (P − C) (spec/003 eq. 5.1); approximation
    → (d + f)·r + (P − C); perfect → P(t) − C. Not normalised (a cubemap needs no unit
    vector)."""
    m = _mode(mode)
    p, d = np.broadcast_arrays(np.asarray(world_pos, float), np.asarray(direction, float))
    c = np.asarray(probe_pos, float)
    if m <= 1:
        return d.copy()
    if m == 4:
        p1, t = perfect_segment(p, d, c, sphere_radius)
        out = p + t[..., None] * (p1 - p) - c
        return np.where((t >= 0)[..., None], out, d)
    lo, hi = np.asarray(box_min, float), np.asarray(box_max, float)
    ds = box_distances(p, d, lo, hi)
    dist = np.maximum(ds.min(-1), 0.0)
    if m == 3:
        hit = p + dist[..., None] * d
        x = np.clip((hit - lo) / np.maximum(hi - lo, 1e-6), 0.0, 1.0)
        face = np.where(d >= 0.0, hi, lo)
        axis = np.argmin(ds, axis=-1)  # first minimum: x before y before z, as the GLSL
        stretch = np.zeros(dist.shape)
        for k in range(3):
            j1, j2 = [j for j in range(3) if j != k]
            h = np.maximum(sphere_radius - np.abs(face[..., k] - c[k]), 0.0)
            f = 0.5 * (quadratic_stretch(x[..., j1], h) + quadratic_stretch(x[..., j2], h))
            stretch = np.where(axis == k, f, stretch)
        dist = dist + stretch
    return dist[..., None] * d + (p - c)


def reflection_weight(smoothness, metallic):
    """weight = 0.25·Smoothness + 0.75·Metallic (spec/003 eq. 5.18, Table 1)."""
    return 0.25 * np.asarray(smoothness, float) + 0.75 * np.asarray(metallic, float)


def specular_color_by_metallic(light_colour, albedo, metallic):
    """lerp(lightColor, albedo, metallic) (GetSpecularColorByMetallic, spec/003 §2.6)."""
    m = np.asarray(metallic, float)[..., None]
    return np.asarray(light_colour, float) * (1.0 - m) + np.asarray(albedo, float) * m


def spec_power(perceptual_roughness):
    """Unity's RoughnessToSpecPower: m = r², n = max(2 / max(m², 1e-4) − 2, 1e-4)."""
    m = np.asarray(perceptual_roughness, float) ** 2
    return np.maximum(2.0 / np.maximum(m * m, 1e-4) - 2.0, 1e-4)


def nhx_roughness(u, v):
    """The NHxRoughness texture's value at (u = cos⁴, v = perceptual roughness) (module
    docstring): min((n + 2)/(2π)·cosᴺ / 16, 1)."""
    c = np.clip(np.asarray(u, float), 0.0, 1.0) ** 0.25
    n = spec_power(v)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore", under="ignore"):
        val = (n + 2.0) / (2.0 * np.pi) * np.power(c, n) / LUT_RANGE
    return np.clip(np.nan_to_num(val), 0.0, 1.0)


def nhx_roughness_lut(size: int = 64) -> np.ndarray:
    """The (size, size) float32 texture: row j at v = (j + ½)/size (roughness), column i at
    u = (i + ½)/size (cos⁴), the layout of a texture written row 0 first."""
    if not 2 <= int(size) <= 4096:
        raise ValueError(f"NHxRoughness LUT size {size}: allowed 2–4096")
    t = (np.arange(size) + 0.5) / size
    return nhx_roughness(t[None, :], t[:, None]).astype(np.float32)


def sample_2d(lut: np.ndarray, u, v) -> np.ndarray:
    """Bilinear lookup of a (h, w) or (h, w, c) texture at (u, v) ∈ [0, 1]² like GL's LINEAR
    with clamp-to-edge (texel centres at (i + ½)/w)."""
    h, w = lut.shape[:2]
    x = np.clip(np.asarray(u, float) * w - 0.5, 0.0, w - 1.0)
    y = np.clip(np.asarray(v, float) * h - 0.5, 0.0, h - 1.0)
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    x1, y1 = np.minimum(x0 + 1, w - 1), np.minimum(y0 + 1, h - 1)
    fx, fy = x - x0, y - y0
    if lut.ndim == 3:
        fx, fy = fx[..., None], fy[..., None]
    top = lut[y0, x0] * (1 - fx) + lut[y0, x1] * fx
    bottom = lut[y1, x0] * (1 - fx) + lut[y1, x1] * fx
    return top * (1 - fy) + bottom * fy


def specular_intensity_from_lut(lut: np.ndarray, nh, roughness):
    """GetSpecularIntensityFromLUT: the LUT at ((n·h)⁴, roughness) × 16 (spec/003 §2.6)."""
    c = np.clip(np.asarray(nh, float), 0.0, 1.0)
    return sample_2d(lut, c ** 4, np.clip(roughness, 0.0, 1.0)) * LUT_RANGE


def probe_mip_level(smoothness, mip_count: float):
    """Unity's perceptualRoughnessToMipmapLevel: r = 1 − smoothness, r(1.7 − 0.7r)·6, at most
    mip_count − 1 (the level SampleProbe reads)."""
    r = np.clip(1.0 - np.asarray(smoothness, float), 0.0, 1.0)
    return np.minimum(r * (1.7 - 0.7 * r) * LOD_STEPS, max(mip_count - 1.0, 0.0))


def split_sum(prefiltered_rgb, ab, f0):
    """PrefilteredSpecular's combination (Karis 2013 eq. 2): prefiltered × (F0·A + B)."""
    ab = np.asarray(ab, float)
    return np.asarray(prefiltered_rgb, float) * (np.asarray(f0, float) * ab[..., :1]
                                                 + ab[..., 1:2])


# -- GGX (the prefilter and BRDF-LUT passes' twins) ---------------------------------------------
def hammersley(n: int) -> np.ndarray:
    """(n, 2) Hammersley points (i/n, radical inverse base 2), as reflection.glsl."""
    i = np.arange(n, dtype=np.uint32)
    b: np.ndarray = i.copy()
    b = (b << 16) | (b >> 16)
    b = ((b & 0x55555555) << 1) | ((b & 0xAAAAAAAA) >> 1)
    b = ((b & 0x33333333) << 2) | ((b & 0xCCCCCCCC) >> 2)
    b = ((b & 0x0F0F0F0F) << 4) | ((b & 0xF0F0F0F0) >> 4)
    b = ((b & 0x00FF00FF) << 8) | ((b & 0xFF00FF00) >> 8)
    return np.stack([i / float(n), b.astype(np.float64) * 2.3283064365386963e-10], 1)


def ggx_half_vectors(xi: np.ndarray, alpha: float) -> np.ndarray:
    """Half vectors around +z drawn from GGX of α (ImportanceSampleGGX with n = +z)."""
    phi = 2.0 * np.pi * xi[:, 0]
    cos_t = np.sqrt((1.0 - xi[:, 1]) / (1.0 + (alpha * alpha - 1.0) * xi[:, 1]))
    sin_t = np.sqrt(np.maximum(1.0 - cos_t ** 2, 0.0))
    return np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], 1)


def brdf_ab(nv, roughness, samples: int = 256) -> np.ndarray:
    """(..., 2) split-sum (A, B) at (n·v, perceptual roughness): ∫ f·cos = F0·A + B for GGX
    with Smith–Schlick visibility k = α/2, α = roughness² (Karis 2013), by the same Hammersley
    importance sampling as glsl/surfaces/brdf_lut.frag."""
    nv, r = np.broadcast_arrays(np.asarray(nv, float), np.asarray(roughness, float))
    xi = hammersley(samples)
    out = np.zeros(nv.shape + (2,))
    for idx in np.ndindex(nv.shape):
        alpha = max(float(r[idx]), 1e-3) ** 2
        c = max(float(nv[idx]), 1e-3)
        # the GLSL's tangent frame around n = +z is (−y, x): h = (h_y, −h_x, h_z)
        h = ggx_half_vectors(xi, alpha)[:, [1, 0, 2]] * [1.0, -1.0, 1.0]
        v = np.array([np.sqrt(1 - c * c), 0.0, c])
        vh = h @ v
        nl = (2.0 * vh[:, None] * h - v)[:, 2]
        nlc, vhc, nh = np.maximum(nl, 0.0), np.maximum(vh, 0.0), np.maximum(h[:, 2], 0.0)
        k = alpha / 2
        g = (c / (c * (1 - k) + k)) * (nlc / (nlc * (1 - k) + k))
        g_vis = np.where(nl > 0, g * vhc / np.maximum(nh * c, 1e-6), 0.0)
        fc = (1.0 - vhc) ** 5
        out[idx] = [((1 - fc) * g_vis).sum() / samples, (fc * g_vis).sum() / samples]
    return out


def brdf_lut(size: int = 32, samples: int = 256) -> np.ndarray:
    """(size, size, 2) split-sum (A, B) with row j at roughness (j + ½)/size and column i at
    n·v = (i + ½)/size: the twin of glsl/surfaces/brdf_lut.frag's texture."""
    t = (np.arange(size) + 0.5) / size
    return brdf_ab(t[None, :], t[:, None], samples).astype(np.float32)


def cube_face_views() -> list[np.ndarray]:
    """The six world → view matrices (4×4) of a cube capture at the origin, in GL face order
    +X, −X, +Y, −Y, +Z, −Z with the standard orientation (forward, up): (+x, −y), (−x, −y),
    (+y, +z), (−y, −z), (+z, −y), (−z, −y) — the image of each is stored as rendered (GL row 0
    at the bottom is the face's t = 0 row), so it matches glsl/common/cubemap.glsl."""
    pairs = [((1, 0, 0), (0, -1, 0)), ((-1, 0, 0), (0, -1, 0)), ((0, 1, 0), (0, 0, 1)),
             ((0, -1, 0), (0, 0, -1)), ((0, 0, 1), (0, -1, 0)), ((0, 0, -1), (0, -1, 0))]
    views = []
    for fwd, top in pairs:
        f, up = np.asarray(fwd, float), np.asarray(top, float)
        r = np.cross(f, up)
        u = np.cross(r, f)
        v = np.identity(4)
        v[0, :3], v[1, :3], v[2, :3] = r, u, -f
        views.append(v)
    return views


def cube_view(face: int, position) -> np.ndarray:
    """Face ``face``'s view matrix for a probe at ``position``."""
    v = cube_face_views()[face].copy()
    v[:3, 3] = -v[:3, :3] @ np.asarray(position, float)
    return v


def cube_projection(near: float = 0.02, far: float = 100.0) -> np.ndarray:
    """The 90°, square perspective projection of each face."""
    proj = np.zeros((4, 4))
    proj[0, 0] = proj[1, 1] = 1.0
    proj[2, 2], proj[2, 3] = (far + near) / (near - far), 2 * far * near / (near - far)
    proj[3, 2] = -1.0
    return proj


def farthest_corner(position, box_min, box_max) -> float:
    """The distance from ``position`` to the box's farthest corner (the default radius of the
    probe's sphere: it holds the whole room, so the perfect sphere's t is in [0, 1] from any
    point inside)."""
    p = np.asarray(position, float)
    lo, hi = np.asarray(box_min, float), np.asarray(box_max, float)
    far = np.where(np.abs(hi - p) > np.abs(lo - p), hi, lo)
    return float(np.linalg.norm(far - p))

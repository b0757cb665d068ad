"""Preetham, Shirley & Smits 1999, "A practical analytic model for daylight" — numpy twin of
``glsl/preetham/preetham.glsl`` (spec/001 §1.8: the cloud thesis's sky is three.js ``Sky.js``,
"obtained from" Preetham et al.; this is the paper's own analytic model, appendix A.2).

Every function here has a GLSL namesake (``Preetham…``) and the tests compare them per pixel.

Model, for a view direction at zenith angle θ and angle γ from the sun (sun zenith angle θs):

* Perez et al. distribution (Preetham 1999 eq. 3):
  F(θ, γ) = (1 + A·e^{B / cos θ}) · (1 + C·e^{D·γ} + E·cos²γ)
* each of Y, x, y is its zenith value times the normalised distribution (Preetham 1999 eq. 4):
  Y = Y_z · F(θ, γ) / F(0, θs)
* distribution coefficients, linear in turbidity T (appendix A.2, table "distribution
  coefficients for luminance Y and chromaticities x, y");
* zenith luminance (appendix A.2), kcd/m²:
  Y_z = (4.0453·T − 4.9710)·tan χ − 0.2155·T + 2.4192,  χ = (4/9 − T/120)·(π − 2θs)
* zenith chromaticity (appendix A.2): x_z = [T² T 1] · M_x · [θs³ θs² θs 1]ᵀ, likewise y_z;
* xyY → XYZ (X = x/y·Y, Z = (1 − x − y)/y·Y) → linear sRGB (IEC 61966-2-1, D65).

Domain guards (documented, the same in GLSL):

* turbidity is limited to [2, 10]: there every B < 0 and Y_z > 0 (Y_z ≥ 2.4192 − 0.2155·10 =
  0.264 kcd/m² at θs = 90°), and both Perez denominators F(0, θs) stay positive;
* view directions below the horizon use cos θ = max(cos θ, 1e-3): with B < 0 the factor
  e^{B/cos θ} tends to 0, so the lower hemisphere shows the horizon colour (the paper's model
  has no ground) — unless a sea plane is drawn there (beyond the paper: :func:`sea_radiance`,
  the shared maths of app/sim/sea_plane.py reflecting this sky, lit by :func:`sky_ambient`
  and the main light);
* the sun below the horizon: the model is evaluated at θs = min(θs, 90°) and the radiance is
  multiplied by a twilight factor, smoothstep over sun elevation −6°…0° (civil twilight), so
  there is no NaN and no pop; the model itself is only defined for the sun above the horizon.

Exposure: the model gives luminance in kcd/m²; the shader writes ``exposure · RGB`` with RGB the
linear sRGB of XYZ in kcd/m² (Y = 1 kcd/m² → 1.0 before exposure). The default exposure 0.05
puts a clear noon zenith (≈ 6–9 kcd/m² at T 2–3) near 0.3–0.45, the range of the day–night sky.
"""

from __future__ import annotations

import math

import numpy as np

from .maths import direction as sun_direction  # noqa: F401 - the sun of the preetham effect
from .sea_plane import SeaPlane, sea_horizon_direction, sea_reflection_direction

#: Perez coefficients (A, B, C, D, E) = slope · T + offset, rows Y, x, y (appendix A.2).
PEREZ_SLOPE = np.array([
    [0.1787, -0.3554, -0.0227, 0.1206, -0.0670],
    [-0.0193, -0.0665, -0.0004, -0.0641, -0.0033],
    [-0.0167, -0.0950, -0.0079, -0.0441, -0.0109],
])
PEREZ_OFFSET = np.array([
    [-1.4630, 0.4275, 5.3251, -2.5771, 0.3703],
    [-0.2592, 0.0008, 0.2125, -0.8989, 0.0452],
    [-0.2608, 0.0092, 0.2102, -1.6537, 0.0529],
])
#: zenith chromaticity matrices: rows T², T, 1; columns θs³, θs², θs, 1 (appendix A.2)
ZENITH_X = np.array([
    [0.00166, -0.00375, 0.00209, 0.0],
    [-0.02903, 0.06377, -0.03202, 0.00394],
    [0.11693, -0.21196, 0.06052, 0.25886],
])
ZENITH_Y = np.array([
    [0.00275, -0.00610, 0.00317, 0.0],
    [-0.04214, 0.08970, -0.04153, 0.00516],
    [0.15346, -0.26756, 0.06670, 0.26688],
])
#: XYZ → linear sRGB (D65)
XYZ_TO_SRGB = np.array([
    [3.2404542, -1.5371385, -0.4985314],
    [-0.9692660, 1.8760108, 0.0415560],
    [0.0556434, -0.2040259, 1.0572252],
])

#: wavelengths (μm) the sun's colour is evaluated at for linear R, G, B
SUN_WAVELENGTHS_UM = np.array([0.680, 0.550, 0.440])
MIN_COS_THETA = 1e-3
TWILIGHT_DEGREES = 6.0


def perez_coefficients(turbidity: float) -> np.ndarray:
    """(3, 5): rows Y, x, y; columns A..E."""
    return PEREZ_SLOPE * float(turbidity) + PEREZ_OFFSET


def perez(cos_theta, gamma, coeffs) -> np.ndarray:
    """F(θ, γ) (Preetham 1999 eq. 3) with cos θ clamped to ≥ 1e-3; ``coeffs`` = (A, B, C, D, E)."""
    a, b, c, d, e = coeffs
    ct = np.maximum(np.asarray(cos_theta, dtype=np.float64), MIN_COS_THETA)
    g = np.asarray(gamma, dtype=np.float64)
    return (1.0 + a * np.exp(b / ct)) * (1.0 + c * np.exp(d * g) + e * np.cos(g) ** 2)


def zenith_luminance(turbidity: float, theta_s) -> np.ndarray:
    """Y_z in kcd/m² (appendix A.2)."""
    t = float(turbidity)
    chi = (4.0 / 9.0 - t / 120.0) * (math.pi - 2.0 * np.asarray(theta_s, dtype=np.float64))
    return (4.0453 * t - 4.9710) * np.tan(chi) - 0.2155 * t + 2.4192


def zenith_chromaticity(turbidity: float, theta_s) -> np.ndarray:
    """(x_z, y_z) (appendix A.2); last axis of the result."""
    t = float(turbidity)
    ts = np.asarray(theta_s, dtype=np.float64)
    tv = np.array([t * t, t, 1.0])
    th = np.stack([ts**3, ts**2, ts, np.ones_like(ts)], axis=-1)
    return np.stack([th @ (tv @ ZENITH_X), th @ (tv @ ZENITH_Y)], axis=-1)


def model_sun_zenith(sun_dir) -> float:
    """θs used by the model: the sun's zenith angle clamped to ≤ 90° (sun below the horizon)."""
    return math.acos(min(1.0, max(0.0, float(np.asarray(sun_dir)[1]))))


def twilight(sun_dir) -> float:
    """1 with the sun above the horizon, smoothstep to 0 at 6° below it."""
    elev = math.degrees(math.asin(min(1.0, max(-1.0, float(np.asarray(sun_dir)[1])))))
    t = min(1.0, max(0.0, (elev + TWILIGHT_DEGREES) / TWILIGHT_DEGREES))
    return t * t * (3.0 - 2.0 * t)


def sky_xyY(directions, sun_dir, turbidity: float) -> np.ndarray:
    """(…, 3) = (x, y, Y[kcd/m²]) toward unit ``directions`` (…, 3) for a unit ``sun_dir``:
    each of Y, x, y is Y_z · F(θ, γ) / F(0, θs) (Preetham 1999 eq. 4)."""
    d = np.asarray(directions, dtype=np.float64)
    s = np.asarray(sun_dir, dtype=np.float64)
    theta_s = model_sun_zenith(s)
    s_model = np.array([s[0], 0.0, s[2]])
    hl = np.linalg.norm(s_model)
    s_model = s_model / hl * math.sin(theta_s) if hl > 0 else np.zeros(3)
    s_model[1] = math.cos(theta_s)
    cos_gamma = np.clip(d @ s_model, -1.0, 1.0)
    gamma = np.arccos(cos_gamma)
    cos_theta = d[..., 1]
    k = perez_coefficients(turbidity)
    xz, yz = zenith_chromaticity(turbidity, theta_s)
    Yz = zenith_luminance(turbidity, theta_s)
    Y, x, y = (zenith * perez(cos_theta, gamma, row) / perez(1.0, theta_s, row)
               for row, zenith in zip(k, (Yz, xz, yz)))  # rows of k: Y, x, y
    return np.stack([x, y, Y], axis=-1)


def xyY_to_XYZ(xyY) -> np.ndarray:
    xyY = np.asarray(xyY, dtype=np.float64)
    x, y, Y = xyY[..., 0], xyY[..., 1], xyY[..., 2]
    return np.stack([x / y * Y, Y, (1.0 - x - y) / y * Y], axis=-1)


def XYZ_to_linear_srgb(xyz) -> np.ndarray:
    return np.asarray(xyz, dtype=np.float64) @ XYZ_TO_SRGB.T


def sky_rgb(directions, sun_dir, turbidity: float) -> np.ndarray:
    """Linear sRGB in kcd/m² (no exposure, no twilight), clamped ≥ 0 (sRGB cannot show every
    chromaticity: tiny negative components near the horizon are cut)."""
    return np.maximum(XYZ_to_linear_srgb(xyY_to_XYZ(sky_xyY(directions, sun_dir, turbidity))),
                      0.0)


def air_mass(theta_s) -> np.ndarray:
    """Relative optical mass m(θs) = 1 / (cos θs + 0.15·(93.885 − θs[°])^−1.253) (appendix A.1,
    after Kasten), finite at θs = 90° (m ≈ 36.5)."""
    ts = np.asarray(theta_s, dtype=np.float64)
    return 1.0 / (np.cos(ts) + 0.15 * (93.885 - np.degrees(ts)) ** -1.253)


def sun_transmittance(theta_s, turbidity: float) -> np.ndarray:
    """Sun colour after the atmosphere at λ = (680, 550, 440) nm for linear R, G, B (appendix
    A.1: Rayleigh τ_R = exp(−0.008735·λ^−4.08·m), aerosols τ_a = exp(−β·λ^−α·m), β = 0.04608·T −
    0.04586, α = 1.3, λ in μm; ozone, gas and water terms left out). Yellow-white at noon,
    dim red at the horizon. Last axis: RGB."""
    m = air_mass(theta_s)[..., None]
    lam = SUN_WAVELENGTHS_UM
    beta = 0.04608 * float(turbidity) - 0.04586
    return np.exp(-0.008735 * lam**-4.08 * m) * np.exp(-beta * lam**-1.3 * m)


def sun_disk(directions, sun_dir, radius_deg: float) -> np.ndarray:
    """Disk coverage: 1 inside the angular radius, a smooth edge 10 % of the radius wide."""
    d = np.asarray(directions, dtype=np.float64)
    c = d @ np.asarray(sun_dir, dtype=np.float64)
    c_in = math.cos(math.radians(radius_deg * 0.9))
    c_out = math.cos(math.radians(radius_deg * 1.1))
    t = np.clip((c - c_out) / (c_in - c_out), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def sky_no_disk(directions, sun_dir, turbidity: float = 2.5,
                exposure: float = 0.05) -> np.ndarray:
    """Twin of ``PreethamSkyNoDisk``: exposure · twilight · sky, linear RGB."""
    return sky_rgb(directions, sun_dir, turbidity) * exposure * twilight(sun_dir)


def sky_ambient_rgb(sun_dir, turbidity: float, elevations: int = 12,
                    azimuths: int = 24) -> np.ndarray:
    """(1/π)∫ L cosθ dω of :func:`sky_rgb` (no disk) over the upper hemisphere, kcd/m² (RGB):
    the cosine-weighted mean radiance, ``elevations`` × ``azimuths`` directions at the
    midpoints, weights sin(2·elevation) normalised (as ``Keyframes.ambient_at`` in
    app/sim/daynight.py). A diffuse horizontal surface under this sky has the irradiance
    π × this."""
    el = (np.arange(elevations) + 0.5) / elevations * (math.pi / 2)
    az = (np.arange(azimuths) + 0.5) / azimuths * (2.0 * math.pi)
    e, a = np.meshgrid(el, az, indexing="ij")
    d = np.stack([np.cos(e) * np.sin(a), np.sin(e), -np.cos(e) * np.cos(a)], axis=-1)
    w = np.sin(2.0 * e)
    rgb = sky_rgb(d, sun_dir, turbidity)
    return (w[..., None] * rgb).sum(axis=(0, 1)) / w.sum()


def sky_ambient(sun_dir, turbidity: float = 2.5, exposure: float = 0.05) -> np.ndarray:
    """The sky's ambient in the picture's units (``uSkyAmbient``): exposure · twilight ·
    :func:`sky_ambient_rgb`."""
    return sky_ambient_rgb(sun_dir, turbidity) * exposure * twilight(sun_dir)


def sea_radiance(directions, sun_dir, turbidity: float, exposure: float,
                 sea: SeaPlane) -> np.ndarray:
    """Twin of ``PreethamSea``: the shared sea plane (app/sim/sea_plane.py) reflecting
    :func:`sky_no_disk`, hazed toward the horizon colour. ``directions`` below the horizon."""
    d = np.asarray(directions, dtype=np.float64)
    reflected = sky_no_disk(sea_reflection_direction(d, sea.mss), sun_dir, turbidity, exposure)
    horizon = sky_no_disk(sea_horizon_direction(d), sun_dir, turbidity, exposure)
    return sea.radiance(d, reflected, horizon)


def sky_radiance(directions, sun_dir, turbidity: float = 2.5, exposure: float = 0.05,
                 disk: bool = True, disk_radius_deg: float = 0.27,
                 disk_intensity: float = 200.0, sea: SeaPlane | None = None) -> np.ndarray:
    """Twin of ``PreethamSkyRadiance``: exposure · (sky + disk) · twilight, linear RGB; below
    the horizon :func:`sea_radiance` when ``sea`` is given (``preetham.ground = sea``)."""
    d = np.asarray(directions, dtype=np.float64)
    rgb = sky_rgb(d, sun_dir, turbidity)
    if disk:
        above = (d[..., 1] >= 0.0).astype(np.float64)
        rgb = rgb + (sun_disk(d, sun_dir, disk_radius_deg) * above * disk_intensity)[..., None] \
            * sun_transmittance(model_sun_zenith(sun_dir), turbidity)
    out = rgb * exposure * twilight(sun_dir)
    if sea is not None:
        below = d[..., 1] < 0.0
        if below.any():
            out[below] = sea_radiance(d[below], sun_dir, turbidity, exposure, sea)
    return out

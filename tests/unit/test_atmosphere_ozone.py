"""The ozone layer of the planet's atmosphere (beyond the thesis): the numpy
twins of app/sim/atmosphere.py and app/sim/hillaire.py against independent float64 integrations
of the tent profile, and the size of its effect on the single-scattering sky (the reference).

The independent reference here is a plain midpoint sum along the ray's length s (not the
perigee substitution and Gauss–Legendre pieces the twin uses), 400 000 steps: its own error is
below 1e-7 relative (second order; the tent's kinks cost one step's worth each, < 1 m of ~1e5).
"""

from __future__ import annotations

import numpy as np
import pytest

from app.errors import ParamError
from app.params import ParamSet
from app.sim import atmosphere as atm
from app.sim import hillaire as twin

OFF = atm.AtmosphereParams()
ON = OFF.replace(ozone=1.0)
LUMA = np.array([0.2126, 0.7152, 0.0722])


def midpoint_ozone_column(h: float, mu: float, params=OFF, steps: int = 400_000) -> float:
    """∫ ρ_O ds from height h along cos Φ = mu to the top: midpoint sum in s, float64, written
    from the tent's definition (0 at 10 km, 1 at 25 km, 0 at 40 km) and the ray's geometry."""
    R, top = params.bottom_radius, params.bottom_radius + params.top_height
    r = R + h
    length = -r * mu + np.sqrt(r * r * mu * mu + top * top - r * r)
    s = (np.arange(steps) + 0.5) * (length / steps)
    alt = np.sqrt(s * s + 2.0 * r * mu * s + r * r) - R
    tent = np.interp(alt, [0.0, 10_000.0, 25_000.0, 40_000.0, 1.0e9], [0.0, 0.0, 1.0, 0.0, 0.0])
    return float(tent.sum() * length / steps)


RAYS = [(0.0, 1.0), (0.0, 0.0), (0.0, 0.05), (2.0, -1.0e-4), (5_000.0, -0.02),
        (30_000.0, 0.3), (30_000.0, -0.05), (45_000.0, -0.1), (45_000.0, 0.5)]


def test_the_vertical_column_is_the_tents_area():
    assert atm.ozone_optical_depth(0.0, 1.0, OFF) == pytest.approx(15_000.0, rel=1e-12)
    assert atm.OZONE_COLUMN_M == 15_000.0
    assert atm.ozone_density(np.array([0.0, 10e3, 17.5e3, 25e3, 32.5e3, 40e3, 50e3])) \
        == pytest.approx([0.0, 0.0, 0.5, 1.0, 0.5, 0.0, 0.0])


@pytest.mark.parametrize("h, mu", RAYS)
def test_exact_ozone_depth_matches_an_independent_midpoint_integral(h, mu):
    """Vertical, grazing (the horizontal ray from the ground crosses ~174 km of the layer),
    downward from altitude through the perigee, and from inside and above the layer."""
    got = float(atm.ozone_optical_depth(h, mu, OFF))
    want = midpoint_ozone_column(h, mu)
    assert got == pytest.approx(want, rel=1e-7, abs=1e-3)


def test_ground_rays_carry_no_sunlight_and_the_brute_force_twin_converges():
    assert np.isinf(atm.ozone_optical_depth(1000.0, -0.5, OFF))
    h = np.array([0.0, 0.0, 30_000.0])
    mu = np.array([1.0, 0.05, -0.05])
    exact = atm.ozone_optical_depth(h, mu, OFF)
    coarse = atm.ozone_optical_depth_midpoint(h, mu, OFF, 30)
    fine = atm.ozone_optical_depth_midpoint(h, mu, OFF, 20_000)
    assert np.allclose(fine, exact, rtol=1e-5)
    assert np.all(np.abs(coarse / exact - 1.0) < 0.05)   # the thesis's N = 30 inner loop


def test_the_lut_holds_the_ozone_column_to_a_thousandth_of_an_optical_depth():
    lut = atm.OpticalDepthLut(OFF)
    rng = np.random.default_rng(3)
    h = rng.uniform(0.0, OFF.top_height, 4000)
    mu = rng.uniform(-1.0, 1.0, 4000)
    sky = ~atm.sun_ray_hits_ground(h, mu, OFF)
    got = lut.optical_depth_to_sun(h[sky], mu[sky])[:, 2]
    exact = atm.ozone_optical_depth(h[sky], mu[sky], OFF)
    tau_error = np.abs(got - exact) * max(atm.OZONE_ABSORPTION)
    assert tau_error.max() < 1e-3, tau_error.max()


def test_the_hillaire_twin_absorbs_what_the_exact_column_says():
    """app/sim/hillaire.py: the transmittance with ozone over that without is exp(−σ_a D_O)."""
    off = twin.Model()
    on = twin.Model(ozone_absorption=atm.OZONE_ABSORPTION)
    h = np.array([0.0, 0.0, 12_000.0, 35_000.0])
    mu = np.array([1.0, 0.1, 0.02, -0.1])
    ratio = twin.sun_transmittance(on, h, mu, 4000) / twin.sun_transmittance(off, h, mu, 4000)
    want = np.exp(-np.asarray(atm.OZONE_ABSORPTION) * atm.ozone_optical_depth(h, mu, OFF)[:, None])
    assert np.allclose(ratio, want, rtol=2e-4)


def test_the_parameter_is_off_by_default_and_validated():
    names = {p.name: p for p in atm.params_list()}
    assert names["atmosphere.ozone"].default == 0.0        # the thesis has no ozone
    assert OFF.uniforms()["uOzoneAbsorption"] == (0.0, 0.0, 0.0)
    assert ON.uniforms()["uOzoneAbsorption"] == pytest.approx(atm.OZONE_ABSORPTION)
    ps = ParamSet(atm.params_list())
    ps.set("atmosphere.ozone", 1.0)
    assert atm.from_params(ps).ozone == 1.0
    with pytest.raises(ParamError, match="atmosphere.ozone"):
        OFF.replace(ozone=-1.0)


def test_ozone_off_is_the_thesis_bit_for_bit():
    cam = atm.local_to_planet((0.0, 2.0, 0.0))
    dirs = atm.direction(np.array([5.0, 30.0, 80.0]), np.array([0.0, 90.0, 200.0]))
    sun = atm.direction(10.0, 180.0)
    a = atm.single_scattering(cam, dirs, sun, OFF, steps=30)
    b = atm.single_scattering(cam, dirs, sun, OFF.replace(ozone=0.0), steps=30)
    assert np.array_equal(a.radiance, b.radiance)
    c = atm.single_scattering(cam, dirs, sun, ON, steps=30)
    assert np.all(c.in_scatter[:, 1] < a.in_scatter[:, 1])      # green absorbed


# ---- the figure: a 10° sun and the twilight zenith, single scattering (the reference) ----------

def sky_directions(n=120, seed=0):
    rng = np.random.default_rng(seed)
    el = np.degrees(np.arcsin(rng.uniform(0.02, 1.0, n)))      # uniform in solid angle
    return atm.direction(el, rng.uniform(0.0, 360.0, n))


def test_a_ten_degree_sun_loses_about_a_tenth_of_the_skys_luminance():
    """The issue's figure, measured on the double-precision reference (120 directions over the
    sky, uniform in solid angle): luminance −11.0 %, green −13.5 %, red −4.9 %, blue −0.6 %."""
    cam = atm.local_to_planet((0.0, 2.0, 0.0))
    dirs = sky_directions()
    sun = atm.direction(10.0, 180.0)
    off = atm.reference(cam, dirs, sun, OFF, steps=256).in_scatter.mean(0)
    on = atm.reference(cam, dirs, sun, ON, steps=256).in_scatter.mean(0)
    change = on / off - 1.0
    luma = (on @ LUMA) / (off @ LUMA) - 1.0
    assert -0.13 < luma < -0.09, luma
    assert -0.16 < change[1] < -0.11, change
    assert change[1] < change[0] < change[2] <= 0.0, change


def test_the_twilight_zenith_turns_from_grey_to_blue_violet():
    """Sun 4° below the horizon: without ozone the single-scattered zenith is greyish-yellow
    (r : g : b ≈ 0.35 : 0.36 : 0.29); with it green falls to about 40 % and the zenith is blue-
    violet (b > r > g), as the sky's 'blue hour' (Hulburt 1953's explanation of the twilight
    zenith's colour)."""
    cam = atm.local_to_planet((0.0, 2.0, 0.0))
    zenith = np.array([[0.0, 1.0, 0.0]])
    sun = atm.direction(-4.0, 180.0)
    off = atm.reference(cam, zenith, sun, OFF, steps=1024).in_scatter[0]
    on = atm.reference(cam, zenith, sun, ON, steps=1024).in_scatter[0]
    assert off[1] > off[2]                       # without ozone: more green than blue
    assert on[2] > on[0] > on[1]                 # with it: blue, then red, green least
    assert (on[2] / on[1]) / (off[2] / off[1]) > 2.0

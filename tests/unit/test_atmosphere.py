"""The atmosphere's CPU model and numpy twins (spec/002-atmosphere.md §9 criteria 1–8, issue 4).

Numbers, not goldens: phase-function integrals and ratios, analytic vertical optical depths,
the sea-level transmittance the thesis's constants imply, segment geometry, the LUT against
exact and Riemann references (its GLSL twin: tests/gl/test_atmosphere.py), convergence of the
midpoint sums, and sky colours of the reference integral (noon blue, sunset red).
"""

from __future__ import annotations

import numpy as np
import pytest

from app.errors import ParamError
from app.params import ParamSet
from app.sim import atmosphere as atm


@pytest.fixture(scope="module")
def ground_cam(atmosphere_model) -> np.ndarray:
    """Camera 2 m above the sea at the scene origin (criterion 12), planet-centred."""
    return atm.local_to_planet([0.0, 2.0, 0.0], atmosphere_model)


def one_line(exc: pytest.ExceptionInfo) -> str:
    text = str(exc.value)
    assert "\n" not in text, text
    return text


def sphere_integral(f, n: int = 200_000) -> float:
    """2π ∫_{-1}^{1} f(μ) dμ by a fine midpoint rule (error ~1e-9 for peaks up to g = 0.9)."""
    mu = -1.0 + (np.arange(n) + 0.5) * (2.0 / n)
    return float(2.0 * np.pi * np.sum(f(mu)) * (2.0 / n))


def horizon_cos(h, atmosphere_model):
    r = atmosphere_model.bottom_radius + np.asarray(h, dtype=np.float64)
    return -np.sqrt(h * (2.0 * atmosphere_model.bottom_radius + h)) / r


# ---- criterion 1: phase functions (§1.2) ----------------------------------------------------

def test_rayleigh_phase_is_normalised():
    assert abs(sphere_integral(atm.phase_rayleigh) - 1.0) < 1e-3


@pytest.mark.parametrize("g", [0.0, 0.3, 0.5, 0.7, 0.76, 0.85, 0.9])
def test_cornette_shanks_is_normalised(g):
    assert abs(sphere_integral(lambda mu: atm.phase_mie(mu, g)) - 1.0) < 1e-3


def test_cornette_shanks_reduces_to_rayleigh_at_g0():
    mu = np.linspace(-1.0, 1.0, 1001)
    assert np.max(np.abs(atm.phase_mie(mu, 0.0) - atm.phase_rayleigh(mu))) < 1e-7


def test_forward_backward_ratio_at_g076():
    ratio = atm.phase_mie(1.0, 0.76) / atm.phase_mie(-1.0, 0.76)
    assert ratio == pytest.approx(394.37, rel=1e-3)
    assert ratio == pytest.approx(((1 + 0.76) / (1 - 0.76)) ** 3, rel=1e-12)


def test_thesis_code_phase_constant_is_the_same_function():
    """§2.3's ``3/8π (1−G²)(1+μ²) / ((2+G²)(1+G²−2Gμ)^1.5)`` equals §1.2's form: no
    erratum."""
    mu = np.linspace(-1.0, 1.0, 201)
    g = 0.76
    code = (3.0 / (8.0 * np.pi) * (1 - g * g) * (1 + mu * mu)
            / ((2 + g * g) * (1 + g * g - 2 * g * mu) ** 1.5))
    assert np.allclose(atm.phase_mie(mu, g), code, rtol=1e-13)


@pytest.mark.parametrize("g", [1.0, -1.0, 1.5])
def test_phase_rejects_g_at_or_beyond_one(g):
    with pytest.raises(ParamError) as exc:
        atm.phase_mie(0.5, g)
    assert "atmosphere.g" in one_line(exc) and "|g| < 1" in str(exc.value)


# ---- criteria 2–3: configuration and coefficients (§1.3, §7) --------------------------------

@pytest.mark.parametrize("g", [1.0, -1.0, 1.0000001, 2.0])
def test_config_rejects_g_at_or_beyond_one(g):
    with pytest.raises(ParamError) as exc:
        atm.AtmosphereParams(g=g)
    text = one_line(exc)
    assert text.startswith("atmosphere.g=") and "|g| < 1" in text and "[0.7, 0.999]" in text


@pytest.mark.parametrize("field, value", [
    ("h_mie", 0.0), ("h_rayleigh", -1.0), ("top_height", 0.0), ("p0", -0.1),
    ("beta_rayleigh", (1e-6, -1e-6, 1e-6)), ("g", float("nan")), ("sun_intensity", float("inf")),
])
def test_config_rejects_unphysical_values_in_one_line(field, value):
    with pytest.raises(ParamError) as exc:
        atm.AtmosphereParams(**{field: value})
    assert one_line(exc).startswith(f"atmosphere.{field}=")


def test_defaults_inside_the_thesis_ranges(atmosphere_model):
    assert 0.70 <= atmosphere_model.g <= 0.999 and atmosphere_model.g == 0.76
    assert 0.7 <= atmosphere_model.p0 <= 1.3
    assert 30.0 <= atmosphere_model.sun_intensity <= 100.0
    assert (atmosphere_model.h_rayleigh, atmosphere_model.h_mie) == (7994.0, 1200.0)
    assert (atmosphere_model.bottom_radius == 6_360_000.0
            and atmosphere_model.top_radius == 6_420_000.0)


def test_extinction_coefficients(atmosphere_model):
    assert np.allclose(atmosphere_model.beta_rayleigh_ext, [5.8e-6, 13.5e-6, 33.1e-6], rtol=1e-12)
    assert np.array_equal(atmosphere_model.beta_rayleigh_ext,
                          atmosphere_model.beta_rayleigh_scatter)
    assert np.allclose(atmosphere_model.beta_mie_absorption, 2.0e-6, rtol=1e-12)
    assert np.allclose(atmosphere_model.beta_mie_ext, 2.2e-5, rtol=1e-12)


def test_params_list_defaults_and_ranges(atmosphere_model):
    ps = ParamSet(atm.params_list())
    assert {p.group for p in ps} == {"atmosphere"}
    assert all(p.section.startswith("spec/002 §") and p.doc for p in ps)
    ranges = {p.name: (p.lo, p.hi) for p in ps}
    assert ranges["atmosphere.g"] == (0.70, 0.999)
    assert ranges["atmosphere.p0"] == (0.7, 1.3)
    assert ranges["atmosphere.sun_intensity"] == (30.0, 100.0)
    built = atm.from_params(ps)
    assert np.allclose(built.beta_rayleigh, atmosphere_model.beta_rayleigh, rtol=1e-12)
    assert np.allclose(built.beta_mie_ext, atmosphere_model.beta_mie_ext, rtol=1e-12)
    assert built.lut_key() == atmosphere_model.lut_key()
    assert (built.g, built.p0, built.sun_intensity) == (atmosphere_model.g, atmosphere_model.p0,
                                                        atmosphere_model.sun_intensity)


def test_params_set_rejects_g_one_and_converts_units():
    ps = ParamSet(atm.params_list())
    with pytest.raises(ParamError) as exc:
        ps.set("atmosphere.g", 1.0)
    assert "atmosphere.g" in one_line(exc) and "[0.7, 0.999]" in str(exc.value)
    ps.set("atmosphere.top_height", 100)
    ps.set("atmosphere.beta_mie", 40)
    ps.set("atmosphere.beta_rayleigh", "1, 2, 3")
    ps.set("atmosphere.p0", 1.2)
    m = atm.from_params(ps)
    assert m.top_height == pytest.approx(100_000.0)
    assert np.allclose(m.beta_mie_ext, 1.1 * 40e-6)
    assert np.allclose(m.beta_rayleigh, [1e-6, 2e-6, 3e-6])
    assert m.p0 == 1.2
    assert m.uniforms()["uTopRadius"] == pytest.approx(6_460_000.0)


# ---- optical depth: exact, Riemann and the vertical analytic case (§1.3) -------------------

def test_exact_optical_depth_vertical_is_analytic(atmosphere_model):
    h = np.linspace(0.0, atmosphere_model.top_height, 61)
    d_r, d_m = atm.optical_depth(h, 1.0, atmosphere_model)
    for d, H in ((d_r, atmosphere_model.h_rayleigh), (d_m, atmosphere_model.h_mie)):
        analytic = H * (np.exp(-h / H) - np.exp(-atmosphere_model.top_height / H))
        assert np.allclose(d, analytic, rtol=1e-10, atol=1e-12)


def test_exact_optical_depth_matches_a_fine_riemann_sum(atmosphere_model):
    h = np.array([0.0, 0.0, 1500.0, 8000.0, 30000.0, 500.0])
    mu = np.array([0.0, 0.3, -0.02, -0.05, -0.1, 0.01])
    exact = np.stack(atm.optical_depth(h, mu, atmosphere_model), -1)
    riemann = np.stack(atm.optical_depth_midpoint(h, mu, atmosphere_model, steps=20000), -1)
    assert np.allclose(exact, riemann, rtol=1e-5)


def test_rays_into_the_ground_have_no_sunlight(atmosphere_model, atmosphere_lut):
    h, mu = np.array([0.0, 1000.0, 50000.0]), np.array([-0.01, -0.5, -0.2])
    assert np.all(atm.sun_ray_hits_ground(h, mu, atmosphere_model))
    assert np.all(np.isinf(np.stack(atm.optical_depth(h, mu, atmosphere_model))))
    assert np.all(np.isinf(np.stack(atm.optical_depth_midpoint(h, mu, atmosphere_model, 10))))
    assert np.all(np.stack(atmosphere_lut.lookup(h, mu)) == atm.OPTICAL_DEPTH_GROUND_M)
    tau = atmosphere_model.p0 * (atmosphere_model.beta_rayleigh_ext * atm.OPTICAL_DEPTH_GROUND_M)
    assert np.all(np.exp(-tau) == 0.0)
    # horizontal at sea level: grazes
    assert not atm.sun_ray_hits_ground(0.0, 0.0, atmosphere_model)


# ---- criterion 4: the optical-depth LUT ("Chapman function", §1.8) -------------------------

def test_lut_layout(atmosphere_lut, atmosphere_model):
    assert atmosphere_lut.table.dtype == np.float32 and atmosphere_lut.table.shape == (256, 256, 3)
    assert atmosphere_lut.size == (256, 256)
    assert atm.OpticalDepthLut(atmosphere_model, n_height=16, n_angle=32).table.shape == (16, 32, 3)
    assert atmosphere_lut.key == atmosphere_model.lut_key() + (256, 256)
    # P0 and g are applied after the lookup
    assert atmosphere_model.replace(p0=1.3, g=0.9).lut_key() == atmosphere_model.lut_key()


def test_lut_uv_texel_centres_and_inverse(atmosphere_model):
    size = (64, 32)
    corners = atm.lut_uv([0.0, atmosphere_model.top_height], [0.0, 1.0], atmosphere_model, size)
    assert np.allclose(corners[0], [0.5 / 64, 0.5 / 32], atol=1e-12)            # sea level, horizon
    assert np.allclose(corners[1], [1 - 0.5 / 64, 1 - 0.5 / 32], atol=1e-12)    # top, zenith
    rng = np.random.default_rng(3)
    x_phi, x_h = rng.uniform(0, 1, 500), rng.uniform(0, 1, 500)
    h, mu = atm.lut_inverse(x_phi, x_h, atmosphere_model)
    back = atm.lut_coordinates(h, mu, atmosphere_model)
    assert np.allclose(back, (x_phi, x_h), atol=1e-9)
    # the horizon of every height is the first column
    hh = np.linspace(0.0, atmosphere_model.top_height, 7)
    x_phi = atm.lut_coordinates(hh, horizon_cos(hh, atmosphere_model), atmosphere_model)[0]
    assert np.allclose(x_phi, 0.0, atol=1e-6)


def test_lut_vertical_matches_analytic(atmosphere_lut, atmosphere_model):
    """Tabulated rows (texel heights) and off-grid heights, cos Φ = 1, within 0.5 %."""
    h = np.concatenate([atmosphere_lut.heights[:, -1],
                        np.linspace(0.0, atmosphere_model.top_height - 2000.0, 397)])
    d_r, d_m = atmosphere_lut.lookup(h, 1.0)
    for d, H in ((d_r, atmosphere_model.h_rayleigh), (d_m, atmosphere_model.h_mie)):
        analytic = H * (np.exp(-h / H) - np.exp(-atmosphere_model.top_height / H))
        assert np.allclose(d, analytic, rtol=5e-3, atol=1e-6)


def test_lut_nonnegative_and_monotonic(atmosphere_lut, atmosphere_model):
    h = np.linspace(0.0, atmosphere_model.top_height, 121)
    mu = np.linspace(-1.0, 1.0, 401)
    H, M = np.meshgrid(h, mu, indexing="ij")
    sky = ~atm.sun_ray_hits_ground(H, M, atmosphere_model)
    assert np.all(atmosphere_lut.table >= 0.0)
    for d in (np.stack(atmosphere_lut.lookup(H, M), -1),
              np.stack(atm.optical_depth(H, M, atmosphere_model), -1)):
        d = np.where(sky[..., None], d, np.nan)
        assert np.nanmin(d) >= 0.0
        with np.errstate(invalid="ignore"):
            assert not np.any(np.diff(d, axis=0) > 0.0), "increases with height"
            assert not np.any(np.diff(d, axis=1) > 0.0), "increases with cos Φ"
    assert np.all(np.diff(atmosphere_lut.densities, axis=1) < 0.0)   # each row, along cos Φ


def test_lut_bilinear_lookup_matches_riemann_reference(atmosphere_lut, atmosphere_model):
    """Random off-grid (h, cos Φ) against a 1000-step midpoint sum: within 1 % outside the
    grazing band (plus 1 mm of sea-level air, i.e. τ < 4e-8, where D → 0 at the very top)."""
    rng = np.random.default_rng(7)
    h = rng.uniform(0.0, atmosphere_model.top_height, 3000)
    mu = rng.uniform(-1.0, 1.0, 3000)
    keep = mu > horizon_cos(h, atmosphere_model) + 0.01
    h, mu = h[keep], mu[keep]
    got = np.stack(atmosphere_lut.lookup(h, mu), -1)
    want = np.stack(atm.optical_depth_midpoint(h, mu, atmosphere_model, steps=1000), -1)
    assert np.allclose(got, want, rtol=0.01, atol=1e-3)
    below_top = h < atmosphere_model.top_height - 2000.0
    assert np.max(np.abs(got[below_top] / want[below_top] - 1.0)) < 0.01


def test_lut_grazing_band_error_in_optical_depth(atmosphere_lut, atmosphere_model):
    """Inside the band the interpolation error stays small in τ (what the transmittance sees)."""
    rng = np.random.default_rng(11)
    h = rng.uniform(0.0, atmosphere_model.top_height, 2000)
    mu = horizon_cos(h, atmosphere_model) + rng.uniform(1e-6, 0.01, 2000)
    got = np.stack(atmosphere_lut.lookup(h, mu), -1)
    exact = np.stack(atm.optical_depth(h, mu, atmosphere_model), -1)
    tau_err = np.abs(got - exact) * [atmosphere_model.beta_rayleigh_ext[2],
                                     atmosphere_model.beta_mie_ext[2]]
    assert tau_err.max() < 2e-3


# ---- criterion 5: sea-level vertical transmittance -----------------------------------------

@pytest.mark.parametrize("top_km", [60, 80, 100])
def test_sea_level_vertical_transmittance(top_km):
    m = atm.AtmosphereParams(top_height=top_km * 1000.0)
    table = atm.OpticalDepthLut(m, 64, 64)
    for d_r, d_m in (atm.optical_depth(0.0, 1.0, m), table.lookup(0.0, 1.0)):
        t = np.exp(-m.p0 * (m.beta_rayleigh_ext * d_r + m.beta_mie_ext * d_m))  # e^(−τ), not ×τ
        assert np.allclose(t, [0.930, 0.874, 0.748], atol=0.005)


# ---- criterion 6: the view segment clipped to the atmosphere (§2.4) ------------------------

def test_segment_camera_inside_looking_up(atmosphere_model, ground_cam):
    seg = atm.atmosphere_segment(ground_cam, [[0.0, 1.0, 0.0], atm.direction(20.0, 45.0)], None,
                                 atmosphere_model)
    assert np.all(seg.hit) and np.all(seg.t0 == 0.0)
    exits = ground_cam + seg.t1[:, None] * np.array([[0.0, 1.0, 0.0], atm.direction(20.0, 45.0)])
    assert np.allclose(np.linalg.norm(exits, axis=-1), atmosphere_model.top_radius, atol=1.0)
    assert seg.t1[0] == pytest.approx(atmosphere_model.top_height - 2.0, abs=1e-6)


def test_segment_camera_inside_target_below_top(atmosphere_model, ground_cam):
    d = atm.direction([5.0, -1.0], [0.0, 90.0])
    seg = atm.atmosphere_segment(ground_cam, d, [5000.0, 100.0], atmosphere_model)
    assert np.all(seg.hit)
    assert np.allclose(seg.t0, 0.0) and np.allclose(seg.t1, [5000.0, 100.0])
    # the −1° ray meets the sea 114.7 m away: a target beyond that is hidden by the ground
    assert atm.atmosphere_segment(ground_cam, d[1:], 150.0, atmosphere_model).t1[0] == \
        pytest.approx(114.66, abs=0.01)


def test_segment_camera_outside_missing(atmosphere_model):
    cam = np.array([0.0, atmosphere_model.top_radius + 300_000.0, 0.0])
    seg = atm.atmosphere_segment(cam, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], None, atmosphere_model)
    assert not np.any(seg.hit) and np.all(seg.t0 == 0.0) and np.all(seg.t1 == 0.0)
    near, far = atm.ray_sphere(cam, [[1.0, 0.0, 0.0]], atmosphere_model.top_radius)
    assert np.isnan(near[0]) and np.isnan(far[0])


def test_segment_camera_outside_crossing(atmosphere_model):
    d = np.array([[1.0, 0.0, 0.0]])
    # perigee 30 km up: the limb
    limb_cam = np.array([-2.0e7, atmosphere_model.bottom_radius + 30_000.0, 0.0])
    seg = atm.atmosphere_segment(limb_cam, d, None, atmosphere_model)
    assert seg.hit[0] and seg.t0[0] > 0.0 and seg.t1[0] > seg.t0[0]
    for t in (seg.t0[0], seg.t1[0]):
        assert np.linalg.norm(limb_cam + t * d[0]) == pytest.approx(atmosphere_model.top_radius,
                                                                    abs=1.0)
    # without the ground, a ray through the centre crosses the whole sphere
    cam = np.array([-2.0e7, 0.0, 0.0])
    seg = atm.atmosphere_segment(cam, d, None, atmosphere_model, clip_ground=False)
    assert seg.t0[0] == pytest.approx(2.0e7 - atmosphere_model.top_radius, abs=1e-6)
    assert seg.t1[0] == pytest.approx(2.0e7 + atmosphere_model.top_radius, abs=1e-6)


def test_segment_camera_outside_target_on_ground(atmosphere_model):
    cam = np.array([0.0, atmosphere_model.top_radius + 100_000.0, 0.0])
    d = atm.direction(-80.0, 30.0)[None]
    ground = atm.ground_distance(cam, d, atmosphere_model)
    assert np.isfinite(ground[0])
    seg = atm.atmosphere_segment(cam, d, ground, atmosphere_model)
    entry = atm.ray_sphere(cam, d, atmosphere_model.top_radius)[0]
    assert (seg.hit[0] and seg.t0[0] == pytest.approx(entry[0])
            and seg.t1[0] == pytest.approx(ground[0]))
    assert np.linalg.norm(cam + seg.t1[0] * d[0]) == pytest.approx(atmosphere_model.bottom_radius,
                                                                   abs=1e-3)
    # a sky ray (no target) that hits the planet stops at the ground too
    assert atm.atmosphere_segment(cam, d, None, atmosphere_model).t1[0] == pytest.approx(ground[0])


# ---- criterion 7: pupil and the final mapping (§1.6) ---------------------------------------

def test_pupil_values():
    assert np.allclose(atm.pupil([1.0, 0.5, 0.0, -1.0]), [0.75, 0.875, 1.0, 1.0], atol=1e-15)


def test_final_colour_range():
    x = np.concatenate([[0.0], np.geomspace(1e-8, 30.0, 500)])
    for p in (0.75, 0.875, 1.0):
        c = atm.final_colour(x, p)
        assert c[0] == 0.0 and np.all(c >= 0.0) and np.all(c < 1.0) and np.all(np.diff(c) > 0.0)


# ---- criterion 8 and the single-scattering integral (§1.5, §1.7, §2.3) ---------------------

def test_midpoint_sum_converges(atmosphere_model, ground_cam):
    cases = [(atm.direction(30.0, 0.0), atm.direction(90.0, 0.0)),       # noon, 30° up
             (atm.direction(5.0, 150.0), atm.direction(2.0, 180.0))]      # sunset, low ray
    for view, sun in cases:
        err = atm.convergence(ground_cam, view[None], sun, atmosphere_model, ns=(10, 20, 30),
                              n_ref=1024)
        assert err[10] > err[20] > err[30]


@pytest.fixture(scope="module")
def sky_rays():
    """(name, view elevation, view azimuth, sun elevation, sun azimuth): typical sky rays."""
    return [("noon30", 30.0, 0.0, 90.0, 180.0), ("noon60", 60.0, 90.0, 90.0, 180.0),
            ("noon10", 10.0, 200.0, 90.0, 180.0), ("noon_horizon", 1.0, 150.0, 90.0, 180.0),
            ("sunset10", 10.0, 180.0, 2.0, 180.0), ("sunset_horizon", 1.0, 150.0, 2.0, 180.0),
            ("morning", 20.0, 0.0, 10.0, 90.0)]


@pytest.fixture(scope="module")
def reference_sky(atmosphere_model, ground_cam, sky_rays):
    views = np.array([atm.direction(e, a) for _, e, a, _, _ in sky_rays])
    suns = [atm.direction(se, sa) for _, _, _, se, sa in sky_rays]
    out = {}
    for sun in {tuple(s) for s in suns}:
        idx = [i for i, s in enumerate(suns) if tuple(s) == sun]
        ref = atm.reference(ground_cam, views[idx], np.array(sun), atmosphere_model, steps=2048)
        for j, i in enumerate(idx):
            out[sky_rays[i][0]] = (views[i], np.array(sun), ref.in_scatter[j], ref.transmittance[j])
    return out


def test_reference_agrees_with_the_thirty_step_sums(atmosphere_model, atmosphere_lut, ground_cam,
                                                    reference_sky):
    for name, (view, sun, ref, _) in reference_sky.items():
        brute = atm.single_scattering(ground_cam, view[None], sun, atmosphere_model,
                                      steps=30).in_scatter[0]
        with_lut = atm.single_scattering(ground_cam, view[None], sun, atmosphere_model, steps=30,
                                         lut=atmosphere_lut).in_scatter[0]
        assert np.max(np.abs(brute / ref - 1.0)) < 0.06, name
        assert np.max(np.abs(with_lut / ref - 1.0)) < 0.06, name
        assert np.max(np.abs(with_lut / brute - 1.0)) < 0.02, name   # method 2 ≈ method 1


def test_reference_is_converged(atmosphere_model, ground_cam, reference_sky):
    view, sun, ref, trans = reference_sky["sunset_horizon"]
    finer = atm.reference(ground_cam, view[None], sun, atmosphere_model, steps=4096)
    assert np.allclose(finer.in_scatter[0], ref, rtol=1e-3)
    assert np.allclose(finer.transmittance[0], trans, rtol=1e-5)


def test_noon_sky_is_blue(reference_sky):
    for name in ("noon30", "noon60", "noon10"):
        r, g, b = reference_sky[name][2]
        assert b > g > r > 0.0, name
        assert b / r >= 1.5, name


def test_sunset_horizon_is_redder_than_noon(reference_sky):
    noon, sunset = reference_sky["noon_horizon"][2], reference_sky["sunset_horizon"][2]
    assert sunset[0] / sunset[2] > noon[0] / noon[2]
    assert sunset[0] > sunset[2]


def test_thesis_accumulation_is_selectable_and_less_accurate(atmosphere_model, ground_cam,
                                                             reference_sky):
    """pc_rule="thesis" reproduces the printed ``dPC += ρ ds`` before use (τ(PC) over-estimated
    by half a step); the default midpoint rule is the documented accuracy fix."""
    view, sun, ref, _ = reference_sky["sunset_horizon"]
    mid = atm.single_scattering(ground_cam, view[None], sun, atmosphere_model).in_scatter[0]
    thesis = atm.single_scattering(ground_cam, view[None], sun, atmosphere_model,
                                   pc_rule="thesis").in_scatter[0]
    assert np.all(thesis < mid)
    assert np.max(np.abs(thesis / ref - 1)) > 3 * np.max(np.abs(mid / ref - 1))
    with pytest.raises(ParamError):
        atm.single_scattering(ground_cam, view[None], sun, atmosphere_model, pc_rule="nope")


def test_p0_scales_both_loops_consistently(atmosphere_model, ground_cam):
    """Erratum: P0 multiplies the sun-ray depth too, so P0 = k is exactly every β times k."""
    views = atm.direction([5.0, 30.0, 80.0], [0.0, 120.0, 240.0])
    sun = atm.direction(8.0, 100.0)
    k = 1.3
    m = atmosphere_model
    a = atm.single_scattering(ground_cam, views, sun, m.replace(p0=k), steps=12)
    scaled = m.replace(beta_rayleigh=tuple(k * m.beta_rayleigh_scatter),
                       beta_mie_scatter=tuple(k * np.array(m.beta_mie_scatter)))
    b = atm.single_scattering(ground_cam, views, sun, scaled, steps=12)
    assert np.allclose(a.in_scatter, b.in_scatter, rtol=1e-12)
    assert np.allclose(a.transmittance, b.transmittance, rtol=1e-12)


def test_out_scattering_on_white(atmosphere_model, ground_cam):
    """Criterion 14's twin: a white target along the horizon — R > G > B, darker with distance."""
    view = atm.direction(0.0, 0.0)[None]
    sun = atm.direction(45.0, 90.0)
    previous = np.ones(3)
    for dist in (10_000.0, 30_000.0, 50_000.0):
        s = atm.single_scattering(ground_cam, view, sun, atmosphere_model, max_dist=dist,
                                  surface_colour=(1, 1, 1))
        t = s.transmittance[0]
        assert t[0] > t[1] > t[2] and np.all(t < previous)
        assert np.allclose(s.radiance[0], t + s.in_scatter[0])
        previous = t


def test_visibility_scales_in_scattering(atmosphere_model, ground_cam):
    views = atm.direction([10.0, 40.0], [0.0, 90.0])
    sun = atm.direction(30.0, 0.0)
    full = atm.single_scattering(ground_cam, views, sun, atmosphere_model, steps=16)
    half = atm.single_scattering(ground_cam, views, sun, atmosphere_model, steps=16,
                                 visibility=lambda p: np.full(len(p), 0.5))
    dark = atm.single_scattering(ground_cam, views, sun, atmosphere_model, steps=16,
                                 visibility=lambda p: np.zeros(len(p)))
    assert np.allclose(half.in_scatter, 0.5 * full.in_scatter) and np.all(dark.in_scatter == 0.0)
    assert np.allclose(dark.transmittance, full.transmittance)   # V only gates the sun's light


def test_space_view_misses_and_limb(atmosphere_model):
    """Camera far outside: rays that miss the atmosphere add nothing; the limb is blue."""
    cam = np.array([0.0, 0.0, 3.0e7])
    limb = np.array([0.0, atmosphere_model.bottom_radius + 15_000.0, 0.0]) - cam
    views = np.array([[0.0, 1.0, 0.0], limb / np.linalg.norm(limb)])
    s = atm.single_scattering(cam, views, np.array([0.0, 0.0, 1.0]), atmosphere_model)
    assert np.all(s.in_scatter[0] == 0.0) and np.all(s.transmittance[0] == 1.0)
    assert s.in_scatter[1, 2] > s.in_scatter[1, 0] > 0.0

"""Method 4 (Hillaire 2020 LUT atmosphere) against numpy twins (app/sim/hillaire.py) and a
brute-force GPU march of the same integral (glsl/tests/hillaire_probe.frag); its stability
sweep (issue 4) is tests/stability/test_hillaire_stability.py.

Small static LUTs (64 × 16 transmittance, 16² multiple scattering; the paper's 192 × 108 sky
view and 32³ volume) and 32 × 18 probes keep the file at a few seconds on llvmpipe.

Note on the brute force: llvmpipe stops any loop after 65 535 iterations in total per shader
invocation (nested loops count their product), so it runs 400 view × 120 sun steps.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from app.effects.planet.hillaire import PROGRAMS, params
from app.sim import hillaire as twin
from app.sim import optics
from tests.helpers.hillaire import SIZE, TOP, Rig


def sky(hillaire_rig: Rig, **kw) -> np.ndarray:
    return hillaire_rig.update(**kw).probe(0)[..., :3]


# ---- declarations -------------------------------------------------------------------------------

def test_params_and_programs(hillaire_rig):
    ps = {p.name: p for p in params()}
    assert all(p.group == "hillaire" for p in ps.values())
    # the paper's sizes are the defaults
    assert (ps["hillaire.transmittance_width"].default == 256
            and ps["hillaire.transmittance_height"].default == 64)
    assert ps["hillaire.ms_size"].default == 32 and ps["hillaire.ms_directions"].default == 64
    assert (ps["hillaire.skyview_width"].default,
            ps["hillaire.skyview_height"].default) == (192, 108)
    assert ps["hillaire.ap_size"].default == 32 and ps["hillaire.ap_slices"].default == 32
    for spec in PROGRAMS:
        if spec.requires_compute and not hillaire_rig.gpu.caps.compute:
            continue
        hillaire_rig.gpu.shaders.program(spec.name, dict(spec.defines), **spec.stages())


# ---- transmittance LUT --------------------------------------------------------------------------

def test_transmittance_lut_matches_numpy_optical_depth(hillaire_rig):
    hillaire_rig.update()
    lut = hillaire_rig.luts.read("transmittance")[..., :3].astype(float)
    ref = twin.transmittance_lut(twin.Model(), 64, 16)
    rel = np.abs(lut - ref) / ref
    assert rel.max() <= 1e-3, rel.max()
    # texel (x_μ = 0, x_r = 0): the vertical ray from sea level, spec/002 §9 criterion 5
    assert lut[0, 0] == pytest.approx((0.930, 0.874, 0.748), abs=0.005)
    # x_r = 1, x_μ = 0 is the zenith ray from the top of the atmosphere: nothing to cross
    assert np.allclose(lut[-1, 0], 1.0, atol=1e-6)


# ---- multiple-scattering LUT --------------------------------------------------------------------

def test_multiscattering_lut_finite_positive_and_matches_numpy(hillaire_rig):
    hillaire_rig.update()
    ms = hillaire_rig.luts.read("multiscattering")
    assert np.isfinite(ms).all() and (ms >= 0).all()
    assert (ms[..., 3] < 1).all() and ms[..., 3].max() > 0.05  # f_ms: a fraction, not nothing
    n = 16
    m = twin.Model()
    for ix, iy in ((15, 0), (10, 3)):  # (μ_s, h) = (1, 0 m), (1/3, 12 km)
        mu_s = 2 * ix / (n - 1) - 1
        h = iy / (n - 1) * m.height
        psi, f = twin.multiple_scattering_texel(m, h, mu_s)
        got = ms[iy, ix]
        assert got[:3] == pytest.approx(psi, rel=0.03), (ix, iy, got, psi)
        assert got[3] == pytest.approx(f.mean(), rel=0.03)
    # blue light scatters more: Ψ_ms is bluest at noon at the ground
    assert ms[0, 15, 2] > ms[0, 15, 1] > ms[0, 15, 0]


def test_multiple_scattering_adds_light(hillaire_rig):
    """single < single + second order < single + all orders (F_ms = 1/(1 − f_ms))."""
    try:
        hillaire_rig.set("multiple_scattering", False)
        single = sky(hillaire_rig, sun_el=30.0, pitch=20.0)
        hillaire_rig.set("multiple_scattering", True)
        hillaire_rig.set("ms_infinite", False)
        second = sky(hillaire_rig, sun_el=30.0, pitch=20.0)
        hillaire_rig.set("ms_infinite", True)
        every = sky(hillaire_rig, sun_el=30.0, pitch=20.0)
    finally:
        hillaire_rig.set("multiple_scattering", True)
        hillaire_rig.set("ms_infinite", True)
    assert (second > single).all() and (every > second).all()
    gain = every.mean() / single.mean()
    assert 1.02 < gain < 2.0, gain
    # after sunset the sky keeps only multiply scattered light from the lit air far away
    hillaire_rig.set("multiple_scattering", False)
    try:
        dusk_single = sky(hillaire_rig, altitude=2.0, sun_el=-4.0, pitch=40.0)
    finally:
        hillaire_rig.set("multiple_scattering", True)
    dusk = sky(hillaire_rig, altitude=2.0, sun_el=-4.0, pitch=40.0)
    assert dusk.mean() > dusk_single.mean()


# ---- sky view -----------------------------------------------------------------------------------

def test_noon_sky_is_blue(hillaire_rig):
    img = sky(hillaire_rig, sun_el=90.0, pitch=45.0)
    r, g, b = img.reshape(-1, 3).mean(0)
    assert b > g > r and b / r >= 1.5


def test_sunset_horizon_reddens(hillaire_rig):
    def horizon_band(sun_el):
        img = sky(hillaire_rig, sun_el=sun_el, pitch=3.0, yaw=0.0, sun_az=0.0, fov=20.0)
        d = hillaire_rig.directions()
        elev = np.degrees(np.arcsin(d[..., 1]))
        sun = np.asarray(hillaire_rig.u["uSunDir"])
        away = np.degrees(np.arccos(np.clip(d @ sun, -1, 1))) > 5.0
        band = (elev > 0.0) & (elev < 3.0) & away
        assert band.sum() > 10
        return img[band].mean(0)

    noon = horizon_band(60.0)
    sunset = horizon_band(2.0)
    assert sunset[0] / sunset[2] > noon[0] / noon[2]
    assert sunset[0] > sunset[2]


CASES = [  # altitude m, sun elevation °, view pitch °
    (2.0, 90.0, 30.0),
    (2.0, 5.0, 5.0),
    (10_000.0, 30.0, -20.0),
    (59_000.0, 10.0, -5.0),
    (300_000.0, 20.0, -60.0),  # from space: the per-pixel march
]


@pytest.mark.parametrize("altitude, sun_el, pitch", CASES)
def test_sky_radiance_matches_brute_force_march(hillaire_rig, altitude, sun_el, pitch):
    hillaire_rig.update(altitude=altitude, sun_el=sun_el, pitch=pitch)
    lut = hillaire_rig.probe(0)[..., :3]
    ref = hillaire_rig.probe(4)[..., :3]
    peak = ref.max()
    assert peak > 0.05
    err = np.abs(lut - ref)
    assert err.max() / peak < 0.03, err.max() / peak
    lit = ref > 0.05 * peak
    assert (err[lit] / ref[lit]).mean() < 0.015


def test_single_scattering_matches_numpy_integral(hillaire_rig):
    """With multiple scattering off, method 4 is the thesis's single-scattering integral."""
    hillaire_rig.set("multiple_scattering", False)
    try:
        hillaire_rig.update(altitude=2.0, sun_el=20.0, pitch=10.0, yaw=30.0)
        img = hillaire_rig.probe(0)[..., :3]
    finally:
        hillaire_rig.set("multiple_scattering", True)
    d = hillaire_rig.directions()
    up = np.array([0.0, 1.0, 0.0])
    sun = np.asarray(hillaire_rig.u["uSunDir"])
    m = twin.Model()
    for iy, ix in ((2, 3), (8, 16), (10, 28)):
        v = d[iy, ix]
        nu = float(v @ sun)
        res = twin.integrate_ray(m, 2.0, float(v @ up), float(sun @ up), nu, steps=3000)
        ref = 30.0 * (optics.phase_rayleigh(nu) * res["rayleigh"]
                      + optics.phase_mie_cornette_shanks(nu, 0.76) * res["mie"])
        assert img[iy, ix] == pytest.approx(ref, rel=0.01), (iy, ix)


# ---- aerial perspective -------------------------------------------------------------------------

def test_aerial_perspective_monotone_and_accurate(hillaire_rig):
    hillaire_rig.update(altitude=500.0, sun_el=25.0, pitch=40.0)  # every ray of the frame climbs
    distances = [50.0, 1000.0, 8000.0, 30000.0, 90000.0, 120000.0, 200000.0]
    aps = [hillaire_rig.probe(1, d) for d in distances]
    for near, far in itertools.pairwise(aps):  # up to float noise where the rays have left the air
        assert (far[..., :3] >= near[..., :3] * (1 - 1e-3)).all()
        assert (far[..., 3] <= near[..., 3] + 1e-3).all()
    assert aps[-1][..., 3].max() < aps[0][..., 3].min()
    for d, ap in zip(distances, aps):
        ref = hillaire_rig.probe(5, d)
        peak = ref[..., :3].max()
        assert np.abs(ap[..., :3] - ref[..., :3]).max() <= 0.02 * peak + 1e-6, d
        assert np.abs(ap[..., 3] - ref[..., 3]).max() <= 0.01, d
    # per-channel transmittance: the LUT ratio against the brute force's optical depth
    ref = hillaire_rig.probe(5, 30000.0)
    rgb = hillaire_rig.probe(2, 30000.0)[..., :3]
    assert np.abs(rgb.mean(-1) - ref[..., 3]).max() < 0.01
    assert (rgb[..., 0] > rgb[..., 1]).all() and (rgb[..., 1] > rgb[..., 2]).all()


def test_aerial_perspective_compute_and_fragment_paths_agree(gl_ctx):
    frag = Rig(gl_ctx)
    frag.luts.use_compute = False
    frag.luts.fragment_rows = 32 * 5  # 5 slices per pass: 7 passes, the last one partial
    try:
        frag.update(altitude=1000.0, sun_el=10.0, pitch=0.0)
        a = [frag.luts.read("ap0"), frag.luts.read("ap1")]
        if not frag.gpu.caps.compute:
            pytest.skip("no compute shaders in this context")
        frag.luts.use_compute = True
        frag.update(altitude=1000.0, sun_el=10.0, pitch=0.0)
        b = [frag.luts.read("ap0"), frag.luts.read("ap1")]
    finally:
        frag.release()
    for x, y in zip(a, b):
        assert np.allclose(x, y, rtol=1e-5, atol=1e-9)


def test_sun_transmittance(hillaire_rig):
    hillaire_rig.update(altitude=2.0, sun_el=90.0, pitch=-30.0)
    zenith = hillaire_rig.probe(3, 0.0)[..., :3]
    assert np.allclose(zenith, (0.930, 0.874, 0.748), atol=0.006)
    hillaire_rig.update(altitude=2.0, sun_el=-3.0, pitch=-30.0)
    assert np.abs(hillaire_rig.probe(3, 0.0)[..., :3]).max() == 0.0  # in the planet's shadow
    # a point 20 km up, seen from the ground, still sees the sun 3° below our horizon
    hillaire_rig.update(altitude=2.0, sun_el=-3.0, pitch=89.0, fov=1.0)
    assert hillaire_rig.probe(3, 20000.0)[..., :3].min() > 0.0


# ---- LUT life -----------------------------------------------------------------------------------

def test_static_luts_rebuild_only_when_the_model_changes(gl_ctx):
    r = Rig(gl_ctx)
    try:
        b = r.luts.builds
        r.update()
        r.update(sun_el=10.0, pitch=0.0, uMieG=0.9, uSunIntensity=100.0)
        assert b["transmittance"] == b["multiscattering"] == 1
        assert b["skyview"] == b["aerial_perspective"] == 2
        r.update(uP0=1.2)
        assert b["transmittance"] == b["multiscattering"] == 2
        r.set("ms_steps", 12)
        r.update(uP0=1.2)
        assert b["transmittance"] == 3
        r.update(altitude=10 * TOP)  # far in space: only the static LUTs are read
        assert b["skyview"] == 4 and r.luts._space_weight == 1.0
    finally:
        r.release()


def test_frame_luts_rebuild_only_when_their_inputs_change(gl_ctx):
    """The sky view follows the camera's altitude and the sun's elevation (its azimuth is
    relative to the sun), the volume the camera and the sun's direction; neither rebuilds for
    a still camera under a still sun, nor for G or the sun's intensity (applied per pixel). A
    LUT kept from an earlier frame reads as one rebuilt for this frame."""
    r = Rig(gl_ctx)
    try:
        b = r.luts.builds
        r.update(altitude=2.0, sun_el=20.0, pitch=10.0)
        first = dict(b)
        r.update(altitude=2.0, sun_el=20.0, pitch=10.0, uMieG=0.9, uSunIntensity=30.0)
        assert b == first                                     # nothing moved
        r.update(altitude=2.0, sun_el=20.0, pitch=10.0, yaw=40.0)   # the camera turns
        assert b["skyview"] == first["skyview"]
        assert b["aerial_perspective"] == first["aerial_perspective"] + 1
        r.update(altitude=2.0, sun_el=20.0, pitch=10.0, yaw=40.0, sun_az=60.0)  # sun's azimuth
        assert b["skyview"] == first["skyview"]
        assert b["aerial_perspective"] == first["aerial_perspective"] + 2
        r.update(altitude=2.0, sun_el=25.0, pitch=10.0, yaw=40.0, sun_az=60.0)  # its elevation
        assert b["skyview"] == first["skyview"] + 1
        assert b["aerial_perspective"] == first["aerial_perspective"] + 3
        r.update(altitude=500.0, sun_el=25.0, pitch=10.0, yaw=40.0, sun_az=60.0)  # it climbs
        assert b["skyview"] == first["skyview"] + 2
        assert b["transmittance"] == b["multiscattering"] == 1   # the model never changed
        kept = [r.luts.read(name) for name in ("skyview0", "skyview1", "ap0", "ap1")]
        r.luts.rebuild_frame_luts()
        assert b["skyview"] == first["skyview"] + 3
        for name, old in zip(("skyview0", "skyview1", "ap0", "ap1"), kept):
            assert np.array_equal(r.luts.read(name), old), name
    finally:
        r.release()


def test_horizon_band_has_no_dark_row(hillaire_rig):
    """No dark row just above the horizon (spec/002 §3.2.3 artifact), sun low."""
    hillaire_rig.update(altitude=2.0, sun_el=3.0, pitch=0.0, fov=10.0)
    img = hillaire_rig.probe(0)[..., :3]
    lum = img @ np.array([0.2126, 0.7152, 0.0722])
    elev = np.degrees(np.arcsin(hillaire_rig.directions()[..., 1]))
    rows = [lum[i].mean() for i in range(SIZE[1]) if elev[i, 16] > 0.0]
    for i in range(1, len(rows) - 1):
        assert rows[i] >= 0.25 * min(rows[i - 1], rows[i + 1])
    assert math.isfinite(sum(rows))

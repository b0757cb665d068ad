"""Fresnel and Snell refraction (spec/003 §2.7, criterion 20): the numpy twins in
app/sim/optics.py. The GPU twins are compared in tests/gl/test_surfaces_refraction.py."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from app.sim import optics as op
from app.sim.maths import normalize

INDICES = st.floats(1.0, 3.0)
COSINES = st.floats(0.0, 1.0)


def test_criterion_20_schlick_for_air_to_water():
    assert op.fresnel_schlick(1.0, 1.0, 1.31) == pytest.approx(0.0180, abs=5e-4)
    assert op.fresnel_schlick(0.0, 1.0, 1.31) == pytest.approx(1.0, abs=1e-12)
    assert op.fresnel_schlick(0.5, 1.0, 1.31) == pytest.approx(0.0487, abs=1e-3)


@pytest.mark.parametrize("n2, c", [(1.31, 0.0180), (1.52, 0.0426), (2.42, 0.1724)])
def test_criterion_20_normal_incidence_c_equals_exact_fresnel(n2, c):
    assert op.fresnel_schlick(1.0, 1.0, n2) == pytest.approx(c, abs=1e-4)
    assert op.fresnel_exact(1.0, 1.0, n2) == pytest.approx(c, abs=1e-4)
    assert op.fresnel_exact(1.0, 1.0, n2) == pytest.approx(op.fresnel_schlick(1.0, 1.0, n2),
                                                            abs=1e-12)


@settings(max_examples=200, deadline=None)
@given(COSINES, INDICES, INDICES)
def test_exact_fresnel_is_a_fraction_and_conserves_energy(cos_i, n1, n2):
    r = float(op.fresnel_exact(cos_i, n1, n2))
    assert 0.0 <= r <= 1.0 and math.isfinite(r)
    if cos_i > 1e-6:
        assert r + float(op.fresnel_transmittance(cos_i, n1, n2)) == pytest.approx(1.0, abs=1e-9)


@settings(max_examples=100, deadline=None)
@given(st.floats(1.05, 3.0), st.floats(0.0, 1.0))
def test_beyond_the_critical_angle_reflectance_is_one(n1, frac):
    # inside the denser medium toward air: sin θc = 1/n1
    cos_c = math.sqrt(1.0 - 1.0 / (n1 * n1))
    cos_i = cos_c * frac * (1.0 - 1e-6)
    assert op.fresnel_exact(cos_i, n1, 1.0) == 1.0
    assert op.fresnel_schlick(cos_i, n1, 1.0) == 1.0
    # just inside the window both stay below 1 and rise toward it
    assert op.fresnel_exact(min(cos_c * 1.01 + 1e-3, 1.0), n1, 1.0) < 1.0


def test_grazing_and_equal_media_give_no_nan():
    for n1, n2 in [(1.0, 1.31), (1.31, 1.0), (1.5, 1.5), (1.0, 1.0)]:
        for f in (op.fresnel_exact, op.fresnel_schlick):
            r = float(f(0.0, n1, n2))
            assert math.isfinite(r)
    assert op.fresnel_exact(0.0, 1.0, 1.31) == pytest.approx(1.0)
    assert op.fresnel_exact(np.linspace(0.0, 1.0, 11), 1.4, 1.4) == pytest.approx(0.0, abs=1e-12)
    assert op.fresnel_exact(-0.5, 1.0, 1.5) == op.fresnel_exact(0.0, 1.0, 1.5)  # clamped


def test_schlick_keeps_the_sea_planes_twin():
    from app.sim import sea_plane
    assert sea_plane.schlick_fresnel is op.schlick_fresnel
    assert op.schlick_fresnel(0.0204, 1.0) == pytest.approx(0.0204)


def test_bad_indices_are_refused():
    with pytest.raises(ValueError, match="n1"):
        op.fresnel_exact(0.5, 0.0, 1.5)
    with pytest.raises(ValueError, match="eta"):
        op.refract_direction([0, 0, -1], [0, 0, 1], -1.0)
    with pytest.raises(ValueError, match="interfaces"):
        op.refract_sphere(3, [0, 0, 1], [0, 0, -1], [0, 0, 0], 1.0, 0.7)


def _dir(theta, phi):
    return np.array([math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi),
                     -math.cos(theta)])


@settings(max_examples=200, deadline=None)
@given(st.floats(0.0, 1.55), st.floats(0.0, 6.28), INDICES, INDICES)
def test_refraction_obeys_snell(theta, phi, n1, n2):
    v = _dir(theta, phi)
    n = np.array([0.0, 0.0, 1.0])
    r, tir = op.refract_direction(v, n, n1 / n2)
    assert np.all(np.isfinite(r)) and np.linalg.norm(r) == pytest.approx(1.0)
    sin1 = math.sin(theta)
    if n1 * sin1 / n2 > 1.0 + 1e-9:
        assert tir
        assert r == pytest.approx(v - 2.0 * np.dot(v, n) * n, abs=1e-12)
    elif n1 * sin1 / n2 < 1.0 - 1e-9:
        assert not tir
        sin2 = math.hypot(r[0], r[1])
        assert n1 * sin1 == pytest.approx(n2 * sin2, abs=1e-9)
        assert r[2] < 0.0                                   # it goes through
        # the plane of incidence is kept: r, v, n coplanar
        assert np.dot(np.cross(v, n), r) == pytest.approx(0.0, abs=1e-9)


@settings(max_examples=50, deadline=None)
@given(st.floats(0.0, 1.5), st.floats(0.0, 6.28), INDICES)
def test_equal_indices_are_the_identity(theta, phi, n):
    v = _dir(theta, phi)
    r, tir = op.refract_direction(v, [0.0, 0.0, 1.0], n / n)
    assert not tir and r == pytest.approx(v, abs=1e-12)
    p = np.array([math.sin(theta), 0.0, math.cos(theta)])   # a point on the unit sphere
    v = normalize(-p + np.array([0.1, 0.2, 0.0]))            # entering the sphere
    d, tir = op.refract_through_sphere(p, v, [0, 0, 0], 1.0, 1.0)
    assert not bool(tir) and d == pytest.approx(v, abs=1e-12)


def test_sphere_exit_is_parallel_through_the_centre_and_deviates_off_it():
    v = np.array([0.0, 0.0, -1.0])
    d, tir = op.refract_through_sphere([0, 0, 1.0], v, [0, 0, 0], 1.0, 1 / 1.5)
    assert not tir and d == pytest.approx(v, abs=1e-12)
    # off-axis ray: two interfaces bend it further than one, toward the axis
    p = np.array([0.5, 0.0, math.sqrt(0.75)])
    one, _ = op.refract_sphere(1, p, v, [0, 0, 0], 1.0, 1 / 1.5)
    two, _ = op.refract_sphere(2, p, v, [0, 0, 0], 1.0, 1 / 1.5)
    assert one[0] < 0.0 and two[0] < one[0]
    # a sphere of lower index than outside totally reflects at entry for grazing rays
    p = np.array([0.99, 0.0, math.sqrt(1 - 0.99 ** 2)])
    d, tir = op.refract_through_sphere(p, v, [0, 0, 0], 1.0, 1.5)
    assert tir and np.all(np.isfinite(d))


def test_distortion_lod_and_mix():
    n = op.distort_normal([0, 0, 1.0], [1.0, 0, 0], [0, 1.0, 0], [0.5, -0.5], 0.0)
    assert n == pytest.approx([0, 0, 1.0])
    n = op.distort_normal([0, 0, 1.0], [1.0, 0, 0], [0, 1.0, 0], [1.0, 0.0], 1.0)
    assert n == pytest.approx(normalize([1.0, 0, 1.0]))
    assert op.distortion_strength(0.4, 0.5) == pytest.approx(0.2)
    assert op.refraction_lod(1.0, 8) == 0.0 and op.refraction_lod(0.0, 8) == 7.0
    assert op.refraction_lod(0.569, 8) == pytest.approx(0.431 * 7)
    assert op.refraction_lod(0.3, 0.5) == 0.0
    m = op.refract_reflect_mix([[0.0, 0.0, 0.0]], [[1.0, 2.0, 4.0]], [0.25])
    assert m[0] == pytest.approx([0.25, 0.5, 1.0])


def test_the_bench_section_reports_fig_67_as_numbers(tmp_path):
    from app.bench import surfaces_fresnel as bench

    report = bench.run(quick=True)
    assert report["criterion_20"]["F1"] == pytest.approx(0.0180, abs=5e-4)
    for r in report["outside"]:
        assert r["c"] == pytest.approx(r["exact_normal"], abs=1e-12)
        assert 0.01 < r["max_abs_error"] < 0.1 and 75.0 < r["max_error_at_deg"] < 90.0
    for r in report["inside"]:
        # the naive Schlick misses total internal reflection: nearly all of R at θc
        assert r["naive_errors"]["max_abs_error"] > 0.5 > r["schlick_errors"]["max_abs_error"]
        assert abs(r["naive_errors"]["max_error_at_deg"] - r["critical_deg"]) < 1.0
    assert len(bench.summary(report)) == 1 + 2 * len(bench.INDICES)
    bench.chart(report, tmp_path / "fresnel.png")
    assert (tmp_path / "fresnel.png").stat().st_size > 0


def test_the_distortion_map_tiles_and_peaks_at_one():
    from app.sim import distortion

    xy = distortion.distortion_map(64, seed=3)
    assert xy.shape == (64, 64, 2) and np.abs(xy).max() == pytest.approx(1.0)
    # tileable: the step across the seam is like the steps inside
    inner = np.abs(np.diff(xy, axis=1)).max()
    assert np.abs(xy[:, 0] - xy[:, -1]).max() <= inner * 1.01
    tex = distortion.encode(xy)
    assert np.abs(tex / 255.0 * 2.0 - 1.0 - xy).max() <= 1.0 / 255.0 + 1e-6
    with pytest.raises(ValueError, match="size"):
        distortion.distortion_map(2)

"""app/sim/maths.py, the one home of the shared maths: the matrices against pyrr (an
independent implementation), the ramps, wraps, normalisers and the compass convention against
their definitions. The GLSL twins are checked in tests/gl/test_maths_twin.py."""

from __future__ import annotations

import math

import numpy as np
import pytest
from pyrr import matrix44

from app.sim import maths


def test_look_at_and_perspective_match_pyrr():
    rng = np.random.default_rng(0)
    for _ in range(20):
        eye, target = rng.normal(size=3) * 5.0, rng.normal(size=3)
        ref = matrix44.create_look_at(eye, target, [0.0, 1.0, 0.0], dtype=np.float64).T
        np.testing.assert_allclose(maths.look_at(eye, target, [0.0, 1.0, 0.0]), ref, atol=1e-12)
        fov, aspect = rng.uniform(10.0, 120.0), rng.uniform(0.5, 2.0)
        ref = matrix44.create_perspective_projection(fov, aspect, 0.1, 50.0,
                                                     dtype=np.float64).T
        np.testing.assert_allclose(maths.perspective(fov, aspect, 0.1, 50.0), ref, rtol=1e-12)


def test_look_at_with_up_along_the_view_falls_back_to_x():
    m = maths.look_at([0.0, 0.0, 0.0], [0.0, 5.0, 0.0], [0.0, 1.0, 0.0])
    assert np.all(np.isfinite(m))
    np.testing.assert_allclose(m[:3, :3] @ m[:3, :3].T, np.identity(3), atol=1e-12)


def test_rotation_y_turns_x_toward_minus_z():
    r = maths.rotation_y(maths.HALF_PI)
    np.testing.assert_allclose(r @ [1.0, 0.0, 0.0], [0.0, 0.0, -1.0], atol=1e-15)
    np.testing.assert_allclose(r @ r.T, np.identity(3), atol=1e-15)


def test_smoothstep_ends_middle_and_reversed_ramp():
    x = np.array([-1.0, 0.0, 0.5, 1.0, 2.0])
    np.testing.assert_array_equal(maths.smoothstep(0.0, 1.0, x), [0.0, 0.0, 0.5, 1.0, 1.0])
    np.testing.assert_array_equal(maths.smoothstep_down(1.0, 0.0, x), [1.0, 1.0, 0.5, 0.0, 0.0])
    np.testing.assert_array_equal(maths.smoothstep(0.0, 1.0, [np.nan]), [np.nan])
    np.testing.assert_array_equal(maths.saturate([-2.0, 0.25, 3.0]), [0.0, 0.25, 1.0])


def test_normalisers_and_their_fallbacks():
    v = np.array([[3.0, 0.0, 4.0], [0.0, 0.0, 0.0], [np.inf, 0.0, 0.0], [np.nan, 1.0, 0.0]])
    out, ok = maths.unit_vectors(v, np.array([0.0, 1.0, 0.0]))
    np.testing.assert_array_equal(ok, [True, False, False, False])
    np.testing.assert_array_equal(out, [[0.6, 0.0, 0.8]] + [[0.0, 1.0, 0.0]] * 3)
    np.testing.assert_array_equal(maths.safe_normalize(v[1]), [0.0, 0.0, 0.0])
    np.testing.assert_array_equal(maths.normalize([3.0, 0.0, 4.0], axis=None), [0.6, 0.0, 0.8])
    np.testing.assert_array_equal(maths.normalize(v[:1]), [[0.6, 0.0, 0.8]])


@pytest.mark.parametrize("angle, wrapped", [(190.0, -170.0), (-180.0, 180.0), (180.0, 180.0),
                                            (540.0, 180.0), (-45.0, -45.0), (720.0, 0.0)])
def test_wrap_degrees_into_half_open_range(angle, wrapped):
    assert maths.wrap_degrees(angle) == wrapped


def test_wrap_two_pi():
    a = np.array([0.0, 1.0, maths.TWO_PI, 7.0, 100.0])
    w = maths.wrap_two_pi(a)
    assert np.all((w >= 0.0) & (w < maths.TWO_PI))
    np.testing.assert_allclose(np.sin(w), np.sin(a), atol=1e-13)


@pytest.mark.parametrize("degrees, xz", [(0.0, (0.0, -1.0)), (90.0, (1.0, 0.0)),
                                         (180.0, (0.0, 1.0)), (270.0, (-1.0, 0.0))])
def test_compass_convention_toward_north_is_minus_z(degrees, xz):
    np.testing.assert_allclose(maths.compass_xz(degrees), xz, atol=1e-15)
    assert math.isclose(maths.compass_degrees(*xz), degrees, abs_tol=1e-12)


def test_compass_round_trip():
    for d in np.linspace(0.0, 359.0, 50):
        assert math.isclose(maths.compass_degrees(*maths.compass_xz(d)), d, abs_tol=1e-9)

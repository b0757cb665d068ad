"""Parallax mapping's numpy twin (app/sim/parallax.py): spec/003 §2.3 and §6 criterion 15 — at
grazing angles occlusion < steep < bare against the reference; n = 12 and n = 32 agree within
2/255 in colour at 60° on a brick texture (and not at 10°, the thesis's "critical angle"); mode 0
leaves uv alone; nothing turns NaN at grazing views or on flat maps."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from app import DEFAULT_SHADER_ROOT
from app.params import parse_glsl_annotations
from app.sim import parallax as px
from app.sim import surface_maps as sm


@pytest.fixture(scope="module")
def brick():
    return sm.bricks(128)


@pytest.mark.parametrize("angle", [10.0, 20.0])
def test_error_ordering_at_grazing_angles(brick, angle):
    err = {m: px.parallax_error(m, 12, angle, brick.height, grid=48)["mean_px"]
           for m in ("bare", "steep", "occlusion", "reference")}
    assert err["reference"] == 0.0
    assert err["occlusion"] < err["steep"] < err["bare"], err


def test_more_layers_help_and_the_error_falls_with_elevation(brick):
    for method in ("steep", "occlusion"):
        by_n = [px.parallax_error(method, n, 30.0, brick.height, grid=32)["mean_px"]
                for n in (4, 12, 64)]
        assert by_n[0] > by_n[1] > by_n[2], (method, by_n)
        by_angle = [px.parallax_error(method, 12, a, brick.height, grid=32)["mean_px"]
                    for a in (10.0, 30.0, 60.0)]
        assert by_angle[0] > by_angle[1] > by_angle[2], (method, by_angle)


def test_steep_12_and_32_agree_in_colour_at_60_degrees_not_at_10(brick):
    uv = px.error_grid(64)

    def colour(angle, n):
        v = px.view_at(angle, 30.0)
        return sm.sample_bilinear(brick.albedo, px.parallax_uv(brick.height, uv, v, "steep", n))

    at60 = np.abs(colour(60.0, 12) - colour(60.0, 32)).mean()
    at10 = np.abs(colour(10.0, 12) - colour(10.0, 32)).mean()
    assert at60 < 2.0 / 255.0, at60 * 255
    assert at10 > 2.0 * at60  # the critical angle: layering shows near grazing


def test_mode_zero_returns_uv_unchanged(brick):
    uv = np.random.default_rng(0).uniform(-3, 3, (100, 2))
    got = px.parallax_uv(brick.height, uv, np.array([0.3, 0.2, 0.5]), "off")
    assert np.array_equal(got, uv)
    # a zero scale, or a view along the normal, moves nothing either
    for mode in ("bare", "steep", "occlusion", "reference"):
        assert np.allclose(px.parallax_uv(brick.height, uv, np.array([0.3, 0.2, 0.5]), mode,
                                          12, 0.0), uv)
        assert np.allclose(px.parallax_uv(brick.height, uv, np.array([0.0, 0.0, 1.0]), mode), uv)


@pytest.mark.parametrize("mode", ["bare", "steep", "occlusion", "reference"])
@pytest.mark.parametrize("view", [(1.0, 0.0, 0.0), (0.6, 0.8, 1e-9), (0.3, -0.1, -0.5),
                                  (0.0, 0.0, 0.0), (1.0, 1.0, 1e-30)])
def test_no_nan_at_grazing_views_or_on_flat_maps(brick, mode, view):
    uv = px.error_grid(12)
    for height in (brick.height, np.zeros((16, 16)), np.ones((16, 16)), np.full((8, 8), 0.5)):
        got = px.parallax_uv(height, uv, np.array(view), mode, 12, 0.05)
        assert np.isfinite(got).all()
        offset = np.linalg.norm(got - uv, axis=-1)
        assert offset.max() <= 0.05 / px.MIN_VZ * np.sqrt(2) + 1e-9


def test_flat_maps_give_the_plane_at_their_depth():
    uv = px.error_grid(8)
    v = px.view_at(40.0, 10.0)
    for h0 in (0.0, 0.25, 1.0):
        height = np.full((16, 16), h0)
        want = uv - (1.0 - h0) * 0.05 * v[:2] / v[2]
        ref = px.parallax_uv(height, uv, v, "reference")
        occ = px.parallax_uv(height, uv, v, "occlusion", 7)
        assert np.abs(ref - want).max() < 1e-6 and np.abs(occ - want).max() < 1e-9
        # bare (offset-limited) has no division by v.z
        bare = px.parallax_uv(height, uv, v, "bare")
        assert np.allclose(bare, uv - (1.0 - h0) * 0.05 * v[:2])


@given(angle=st.floats(1.0, 89.0), azimuth=st.floats(0.0, 360.0), n=st.integers(1, 40))
@settings(max_examples=40, deadline=None)
def test_steep_lands_at_or_below_the_surface_and_occlusion_between_layers(angle, azimuth, n):
    height = sm.stones(32).height
    uv = px.error_grid(6)
    v = px.parallax_view(px.view_at(angle, azimuth))
    steep = px.parallax_steep(height, uv, v, 0.05, n)
    occl = px.parallax_occlusion(height, uv, v, 0.05, n)
    delta = 0.05 * v[:2] / (v[2] * n)
    # steep's uv is a whole number of steps along −v_xy; occlusion lies within the last step
    steps = (uv - steep) @ delta / (delta @ delta)
    assert np.allclose(steps, np.round(steps), atol=1e-6)
    back = (occl - steep) @ delta / (delta @ delta)
    assert (back >= -1e-9).all() and (back <= 1.0 + 1e-9).all()
    depth_layer = 1.0 - np.round(steps) / n
    assert (px.parallax_height(height, steep) >= depth_layer - 1e-9).all()


def test_error_in_texels_wraps():
    assert np.isclose(px.wrapped_texels(np.array([0.99, 0.5]), np.array([0.01, 0.5]),
                                        (100, 100)), 2.0)


def test_parallax_uniforms_are_parameters_with_the_thesis_values():
    text = (DEFAULT_SHADER_ROOT / "common" / "parallax.glsl").read_text(encoding="utf-8")
    params = {p.name: p for p in parse_glsl_annotations(text, "shading")}
    assert params["shading.parallax_mode"].lo == 0 and params["shading.parallax_mode"].hi == 4
    assert params["shading.parallax_layers"].default == 12
    assert 10 <= params["shading.parallax_layers"].default <= 20
    assert params["shading.parallax_scale"].default == 0.05

"""Bump mapping's numpy twin (app/sim/bump.py) and the generated maps (app/sim/surface_maps.py):
spec/003 §2.2 and §6 criterion 14 — the exact unpack is unit length, the approximation's error
is what spec/003 eq. 3.4 implies, DXT5nm reads (a, g), Bumpiness 0 is the vertex normal, the
tangent frame is orthonormal and its handedness flips the bitangent; the maps tile."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from app import DEFAULT_SHADER_ROOT
from app.params import parse_glsl_annotations
from app.sim import bump
from app.sim import surface_maps as sm

SETTINGS = settings(max_examples=100, deadline=None)
unit3 = st.tuples(*[st.floats(-1.0, 1.0)] * 3).filter(lambda v: 0.1 < np.linalg.norm(v))


def disk_xy(n=2000, s_max=1.0, seed=0):
    rng = np.random.default_rng(seed)
    r = np.sqrt(rng.uniform(0.0, s_max, n))
    a = rng.uniform(0.0, 2 * np.pi, n)
    return np.stack([r * np.cos(a), r * np.sin(a)], -1)


def test_exact_unpack_is_unit_length():
    n = bump.normal_from_xy(disk_xy(), bump.EXACT)
    assert np.allclose(np.linalg.norm(n, axis=-1), 1.0, atol=1e-12)
    assert (n[:, 2] >= 0).all()


def test_approximate_unpack_differs_by_what_eq_3_4_implies():
    xy = disk_xy(s_max=0.5)
    s = np.sum(xy * xy, -1)
    exact = bump.normal_from_xy(xy, bump.EXACT)
    approx = bump.normal_from_xy(xy, bump.APPROX)
    assert np.allclose(approx[:, :2], exact[:, :2])
    assert np.allclose(approx[:, 2] - exact[:, 2], bump.approx_z_error(s), atol=1e-12)
    # the approximation overestimates z, never by more than 0.07 where x² + y² ≤ ½ (criterion 14)
    assert (approx[:, 2] >= exact[:, 2] - 1e-12).all()
    err = np.abs(approx[:, 2] - exact[:, 2])
    assert err.max() < 0.07
    assert abs(bump.approx_z_error(0.5) - (0.75 - np.sqrt(0.5))) < 1e-12
    # its length is sqrt(1 + s²/4): 1 at the pole, 1.03 at s = ½
    assert np.allclose(np.linalg.norm(approx, axis=-1), np.sqrt(1 + s * s / 4))
    assert abs(err.max() - bump.approx_z_error(s.max())) < 1e-12
    # and after normalising the direction error stays a few degrees
    cos = np.sum(exact * approx / np.linalg.norm(approx, axis=-1, keepdims=True), -1)
    assert np.degrees(np.arccos(np.clip(cos, -1, 1))).max() < 2.5


def test_dxt5nm_round_trip_reads_alpha_and_green():
    field = sm.bricks(32)
    n = field.normals(4.0)
    for dxt5nm in (False, True):
        tex = sm.decode_normal_texture(sm.encode_normal(n, dxt5nm=dxt5nm))
        got = bump.unpack_normal(tex, bump.EXACT, dxt5nm)
        assert np.abs(got - n).max() < 0.02  # 8-bit quantisation, through z
    tex = sm.encode_normal(n, dxt5nm=True)
    assert (tex[..., 0] == 255).all() and (tex[..., 2] == 0).all()
    assert np.abs(tex[..., 3] / 255.0 - (0.5 * n[..., 0] + 0.5)).max() <= 0.5 / 255 + 1e-6
    # reading a DXT5nm texture as RGB gets x wrong: the layouts are not interchangeable
    wrong = bump.unpack_normal(sm.decode_normal_texture(tex), bump.EXACT, False)
    assert np.abs(wrong[..., 0] - n[..., 0]).max() > 0.5


def test_unpack_of_an_over_long_xy_stays_finite():
    tex = np.array([[1.0, 1.0, 0.5, 1.0], [0.0, 0.0, 0.5, 0.0]])
    for mode in (bump.EXACT, bump.APPROX):
        for b in (0.0, 1.0, 2.0):
            got = bump.unpack_normal(tex, mode, False, b)
            assert np.isfinite(got).all() and (got[:, 2] >= 0).all()


@given(n=unit3, t=unit3, w=st.sampled_from([-1.0, 1.0]))
@SETTINGS
def test_tangent_frame_is_orthonormal_and_handedness_flips_the_bitangent(n, t, w):
    frame = bump.tangent_frame(np.array(n), np.array([*t, w]))
    assert np.allclose(frame.swapaxes(-1, -2) @ frame, np.eye(3), atol=1e-9)
    T, B, N = frame[:, 0], frame[:, 1], frame[:, 2]
    assert np.allclose(N, np.array(n) / np.linalg.norm(n))
    assert np.isclose(np.linalg.det(frame), w)  # w = +1: right-handed, n = t × b
    flipped = bump.tangent_frame(np.array(n), np.array([*t, -w]))
    assert np.allclose(flipped[:, 1], -B) and np.allclose(flipped[:, 0], T)


def test_degenerate_tangent_and_normal_give_a_frame():
    for n, t in [((0, 0, 1), (0, 0, 2, 1)), ((0, 1, 0), (0, 0, 0, 0)), ((0, 0, 0), (1, 0, 0, 1))]:
        frame = bump.tangent_frame(np.array(n, float), np.array(t, float))
        assert np.isfinite(frame).all()
        assert np.allclose(frame.T @ frame, np.eye(3), atol=1e-9)


@given(n=unit3, t=unit3, u=st.floats(0, 1), v=st.floats(0, 1),
       mode=st.sampled_from([0, 1]), dxt=st.booleans())
@SETTINGS
def test_bumpiness_zero_returns_the_vertex_normal(n, t, u, v, mode, dxt):
    tex = sm.decode_normal_texture(sm.encode_normal(sm.stones(16).normals(6.0), dxt5nm=dxt))
    got = bump.bumped_normal(tex, np.array([u, v]), np.array(n), np.array([*t, 1.0]),
                             mode, dxt, 0.0)
    assert np.allclose(got, np.array(n) / np.linalg.norm(n), atol=1e-12)


def test_flat_map_and_world_transform():
    tex = sm.decode_normal_texture(sm.encode_normal(sm.normal_map(np.zeros((8, 8)))))
    n = np.array([0.0, 1.0, 0.0])
    t = np.array([1.0, 0.0, 0.0, 1.0])
    uv = np.random.default_rng(1).uniform(-2, 3, (50, 2))
    got = bump.bumped_normal(tex, uv, n, t, bump.EXACT, False, 2.0)
    assert np.abs(got - n).max() < 0.01  # 128/255 is not exactly ½
    # a local normal tilted toward +x tilts toward the tangent, +y toward the bitangent
    frame = bump.tangent_frame(n, t)
    assert bump.tangent_to_world(np.array([0.6, 0.0, 0.8]), frame)[0] > 0.5
    assert np.allclose(bump.tangent_to_world(np.array([0.0, 0.6, 0.8]), frame),
                       0.6 * frame[:, 1] + 0.8 * n)
    # bumpiness scales the slope: x/z doubles (through the exact z) from 1 to 2 on small slopes
    xy = np.array([[0.1, 0.05]])
    n1 = bump.normal_from_xy(xy * 1.0)
    n2 = bump.normal_from_xy(xy * 2.0)
    assert abs((n2[0, 0] / n2[0, 2]) / (n1[0, 0] / n1[0, 2]) - 2.0) < 0.05


@pytest.mark.parametrize("name", sorted(sm.GENERATORS))
def test_generated_maps_tile_and_are_sane(name):
    field = sm.GENERATORS[name](64)
    h = field.height
    assert h.shape == (64, 64) and h.dtype == np.float32
    assert h.min() == 0.0 and h.max() == 1.0 and 0.2 < h.mean() < 0.8
    assert field.albedo.shape == (64, 64, 3)
    # tileable: the jump across the wrap is no larger than the jumps inside the map
    inside = max(np.abs(np.diff(h, axis=0)).max(), np.abs(np.diff(h, axis=1)).max())
    assert np.abs(h[0] - h[-1]).max() <= inside + 1e-6
    assert np.abs(h[:, 0] - h[:, -1]).max() <= inside + 1e-6
    n = field.normals(4.0)
    assert np.allclose(np.linalg.norm(n, axis=-1), 1.0, atol=1e-5) and (n[..., 2] > 0).all()
    # the same map drawn twice as large is the same pattern (the generator is resolution-free)
    big = sm.GENERATORS[name](128).height
    assert np.corrcoef(big[::2, ::2].ravel(), h.ravel())[0, 1] > 0.85  # half a texel apart
    rgba = field.height_texture()
    assert rgba.dtype == np.uint8
    assert np.array_equal(rgba[..., 3], np.round(h * 255).astype(np.uint8))


def test_normal_map_uses_wrapped_central_differences():
    h = np.zeros((16, 16))
    h[:, 5] = 1.0  # a ridge along v at column 5
    n = sm.normal_map(h, 2.0)
    # left of the ridge the surface rises toward +u: the normal leans to −u
    assert n[3, 4, 0] < 0 and n[3, 6, 0] > 0 and abs(n[3, 5, 0]) < 1e-7
    assert np.allclose(n[3, 4], np.array([-1.0, 0.0, 1.0]) / np.sqrt(2.0), atol=1e-6)
    flat = sm.normal_map(np.full((8, 8), 0.3), 10.0)
    assert np.array_equal(flat, np.broadcast_to(np.array([0, 0, 1], np.float32), flat.shape))
    ring = np.zeros((8, 8))
    ring[:, 0] = 1.0  # at the wrap: column 7 sees column 0
    assert sm.normal_map(ring, 2.0)[0, 7, 0] < 0


def test_bilinear_sampling_matches_texel_centres_and_wraps():
    rng = np.random.default_rng(3)
    tex = rng.random((8, 16, 3))
    centres = np.array([[(2 + 0.5) / 16, (5 + 0.5) / 8]])
    assert np.allclose(sm.sample_bilinear(tex, centres), tex[5, 2])
    assert np.allclose(sm.sample_bilinear(tex, centres + 3.0), tex[5, 2])
    edge = np.array([[0.0, (5 + 0.5) / 8]])  # halfway between column 15 and column 0
    assert np.allclose(sm.sample_bilinear(tex, edge), 0.5 * (tex[5, 15] + tex[5, 0]))


def test_bump_uniforms_are_parameters_with_the_thesis_ranges():
    text = (DEFAULT_SHADER_ROOT / "common" / "bump.glsl").read_text(encoding="utf-8")
    params = {p.name: p for p in parse_glsl_annotations(text, "shading")}
    assert params["shading.bumpiness"].lo == 0 and params["shading.bumpiness"].hi == 2
    assert params["shading.bumpiness"].default == 1
    assert params["shading.normal_unpack"].default == 0
    assert params["shading.normal_dxt5nm"].kind == "bool"

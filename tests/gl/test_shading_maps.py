"""Bump and parallax mapping (glsl/common/bump.glsl, glsl/common/parallax.glsl) against their
numpy twins (app/sim/bump.py, app/sim/parallax.py) per pixel, through the probe
glsl/tests/shading_maps_probe.frag: each unpack mode with and without DXT5nm, each parallax
mode, on a grid of texture coordinates drawn as one full-screen quad (spec/003 §2.2, §2.3)."""

from __future__ import annotations

import moderngl
import numpy as np
import pytest

from app.sim import bump
from app.sim import parallax as px
from app.sim import surface_maps as sm
from tests.helpers.glsl_eval import evaluate_points

PROBE = "tests/shading_maps_probe"
SIZE = 32  # the maps' size in texels
GRID = 24  # points per side (576 pixels)


def uv_grid(seed=0) -> np.ndarray:
    """GRID² points: the first half random (outside [0, 1] too: wrap), the second half at texel
    centres (where filtering is exact, whatever the filter's precision)."""
    rng = np.random.default_rng(seed)
    half = GRID * GRID // 2
    uv = rng.uniform(-1.0, 2.0, (GRID * GRID, 2))
    uv[half:] = (rng.integers(-SIZE, 2 * SIZE, (GRID * GRID - half, 2)) + 0.5) / SIZE
    return np.concatenate([uv, np.zeros((len(uv), 1))], -1)


def texture(gpu, name, rgba: np.ndarray, dtype="f1"):
    h, w = rgba.shape[:2]
    data = np.ascontiguousarray(rgba).tobytes()
    return gpu.texture("probe", name, (w, h), 4, data, dtype=dtype,
                       filter=(moderngl.LINEAR, moderngl.LINEAR), repeat=True)


@pytest.fixture(scope="module")
def field():
    return sm.bricks(SIZE, rows=4, columns=2)


@pytest.mark.parametrize("unpack", [bump.EXACT, bump.APPROX])
@pytest.mark.parametrize("dxt5nm", [False, True])
@pytest.mark.parametrize("bumpiness", [0.0, 1.0, 2.0])
def test_bumped_normals_match_the_twin(gpu, field, unpack, dxt5nm, bumpiness):
    tex8 = field.normal_texture(3.0, dxt5nm=dxt5nm)
    nmap = texture(gpu, "normals", tex8)
    rng = np.random.default_rng(unpack * 7 + dxt5nm * 3 + int(bumpiness))
    n = rng.normal(size=3)
    n /= np.linalg.norm(n)
    t = np.array([*rng.normal(size=3), -1.0 if dxt5nm else 1.0])
    pts = uv_grid(1)
    uniforms = {"uProbeMode": 0, "uVertexNormal": tuple(n), "uTangent": tuple(t),
                "uNormalUnpack": unpack, "uNormalDXT5nm": dxt5nm, "uBumpiness": bumpiness}
    got = evaluate_points(gpu, pts, PROBE, uniforms, textures=[("uNormalMap", nmap)])
    got = got[:, :3].astype(np.float64)
    want = bump.bumped_normal(sm.decode_normal_texture(tex8), pts[:, :2], n, t, unpack, dxt5nm,
                              bumpiness)
    assert np.isfinite(got).all()
    err = np.linalg.norm(got - want, axis=-1)
    half = len(err) // 2
    assert err[half:].max() < 2e-5, err[half:].max()  # texel centres: the shader's arithmetic
    # between them llvmpipe's filter weights are fixed point (8 bits): about half a degree per
    # unit of Bumpiness (which scales the slopes the weights blend)
    # unit of Bumpiness (which scales the slopes the weights blend); spec/003 eq. 3.3's square
    # root magnifies them without bound as x² + y² → 1, so those points are left out there
    k = max(bumpiness, 1.0)
    xy = bump.unpack_normal_xy(sm.sample_bilinear(sm.decode_normal_texture(tex8), pts[:, :2]),
                               dxt5nm) * bumpiness
    steep = (unpack == bump.EXACT) & (np.sum(xy * xy, -1) > 0.9)
    between = err[:half][~steep[:half]]
    assert np.percentile(between, 99) < 1e-2 * k and between.max() < 2e-2 * k, between.max()
    if bumpiness == 0.0:
        assert np.abs(got - n).max() < 1e-5  # criterion 14: the flat-normal output


def test_tangent_space_view_matches_the_twin(gpu):
    rng = np.random.default_rng(4)
    d = rng.normal(size=(300, 3))
    n = np.array([0.2, 0.9, -0.3])
    t = np.array([1.0, 0.1, 0.4, -1.0])
    got = evaluate_points(gpu, d, PROBE, {"uProbeMode": 2, "uVertexNormal": tuple(n),
                                          "uTangent": tuple(t)})[:, :3]
    want = px.tangent_space_view(d, bump.tangent_frame(n, t))
    assert np.abs(got - want).max() < 1e-5


@pytest.mark.parametrize("mode", [px.OFF, px.BARE, px.STEEP, px.OCCLUSION, px.REFERENCE])
@pytest.mark.parametrize("angle", [10.0, 60.0])
def test_parallax_uv_matches_the_twin(gpu, field, mode, angle):
    rgba = np.repeat(field.height[..., None], 4, axis=-1).astype(np.float32)
    hmap = texture(gpu, "height", rgba, dtype="f4")  # float texels: the same heights on both
    view = px.view_at(angle, 35.0)
    pts = uv_grid(2)
    uniforms = {"uProbeMode": 1, "uViewTS": tuple(view), "uParallaxMode": mode,
                "uParallaxLayers": 12, "uParallaxScale": 0.05}
    got = evaluate_points(gpu, pts, PROBE, uniforms,
                          textures=[("uHeightMap", hmap)])[:, :2].astype(np.float64)
    want = px.parallax_uv(field.height.astype(np.float64), pts[:, :2], view, mode, 12, 0.05)
    assert np.isfinite(got).all()
    texels = px.wrapped_texels(got, want, (SIZE, SIZE))
    if mode == px.OFF:
        assert np.abs(got - pts[:, :2]).max() < 1e-6
        return
    # a layer search may stop one layer apart where a height and a layer nearly tie: allow a
    # few such pixels, and agreement to a hundredth of a texel everywhere else
    close = texels < 0.01
    assert close.mean() > 0.97, (close.mean(), texels.max())
    one_step = 0.05 * np.linalg.norm(view[:2]) / (view[2] * 12) * SIZE
    assert texels.max() < max(1.05 * one_step, 0.05)


def test_parallax_stays_finite_when_grazing_and_flat(gpu):
    flat = texture(gpu, "flat", np.zeros((8, 8, 4), np.float32), dtype="f4")
    pts = uv_grid(3)
    for mode in (px.BARE, px.STEEP, px.OCCLUSION, px.REFERENCE):
        for view in ((1.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.5, 0.5, -0.2)):
            got = evaluate_points(gpu, pts, PROBE,
                                  {"uProbeMode": 1, "uViewTS": view, "uParallaxMode": mode,
                                   "uParallaxLayers": 16, "uParallaxScale": 0.05},
                                  textures=[("uHeightMap", flat)])[:, :2]
            assert np.isfinite(got).all()
            want = px.parallax_uv(np.zeros((8, 8)), pts[:, :2], np.array(view), mode, 16, 0.05)
            assert np.abs(got - want).max() < 1e-4

"""The reflection probe's numpy twin (app/sim/reflections.py; spec/003 §2.5, §2.6): Table 1,
box projection, the approximation, the perfect sphere, the NHxRoughness LUT, Unity's mip
mapping and the split-sum LUT."""

from __future__ import annotations

import numpy as np
import pytest

from app.effects.surfaces.reflections import ReflectionProbe
from app.sim import reflections as rf
from app.sim import surfaces_scene as ss

ROOM = ss.Room()
LO, HI = np.asarray(ROOM.lo, float), np.asarray(ROOM.hi, float)
PROBE = np.array([0.0, 1.5, 0.0])


def _points_and_dirs(n=2000, seed=1):
    rng = np.random.default_rng(seed)
    p = rng.uniform(LO + 0.05, HI - 0.05, (n, 3))
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return p, d


def test_reflection_weight_is_table_1_exactly():
    # criterion 19: (smoothness, metallic) → weight
    table = {(0, 0): 0.00, (0, 1): 0.75, (1, 0): 0.25, (1, 1): 1.00}
    for (s, m), w in table.items():
        assert rf.reflection_weight(s, m) == w
    assert rf.reflection_weight(0.5, 0.5) == pytest.approx(0.5)


def test_box_projection_takes_the_nearest_face_and_lands_on_the_box():
    p, d = _points_and_dirs()
    ds = rf.box_distances(p, d, LO, HI)
    dist = rf.box_distance(p, d, LO, HI)
    assert np.array_equal(dist, ds.min(-1))  # d = min(d_x, d_y, d_z), criterion 21
    assert np.all(ds > 0)
    hit = p + dist[:, None] * d
    on_face = np.isclose(hit, LO, atol=1e-9) | np.isclose(hit, HI, atol=1e-9)
    assert np.all(on_face.any(-1))
    assert np.all((hit >= LO - 1e-9) & (hit <= HI + 1e-9))
    # the returned lookup is the vector from the probe to that hit point (eq. 5.1)
    look = rf.compute_reflex_direction("box", p, d, PROBE, LO, HI, 6.0)
    assert np.allclose(look, hit - PROBE)
    # and it is the exact ray cast of the empty room
    t, index = ss.ray_cast(ss.SurfacesScene(room=ROOM), p, d)
    assert np.all(index == -1)
    assert np.allclose(dist, t, atol=1e-9)


def test_box_distance_guards_axis_parallel_rays_and_points_outside():
    d = np.array([[1.0, 0.0, 0.0]])
    ds = rf.box_distances(np.zeros((1, 3)) + [0, 1, 0], d, LO, HI)
    assert ds[0, 0] == pytest.approx(4.0) and ds[0, 1] >= 1e29 and ds[0, 2] >= 1e29
    outside = np.array([[5.0, 1.0, 0.0]])  # beyond +x, heading further out
    assert rf.box_distance(outside, d, LO, HI)[0] == 0.0


def test_cube_and_none_return_the_reflected_direction():
    p, d = _points_and_dirs(50)
    for mode in ("none", "cube", 0, 1):
        assert np.array_equal(rf.compute_reflex_direction(mode, p, d, PROBE, LO, HI, 6.0), d)
    with pytest.raises(ValueError, match="allowed"):
        rf.compute_reflex_direction("mirror", p, d, PROBE, LO, HI, 6.0)


def test_perfect_sphere_returns_t_in_0_1_on_the_sphere():
    p, d = _points_and_dirs()
    radius = rf.farthest_corner(PROBE, LO, HI)
    p1, t = rf.perfect_segment(p, d, PROBE, radius)
    assert np.all((t >= 0) & (t <= 1))  # criterion 21
    point = p + t[:, None] * (p1 - p)
    assert np.allclose(np.linalg.norm(point - PROBE, axis=1), radius, atol=1e-4)
    look = rf.compute_reflex_direction("perfect", p, d, PROBE, LO, HI, radius)
    assert np.allclose(look, point - PROBE)
    # the probe's own position reflects along r itself (a point at the centre sees r)
    at_centre = rf.compute_reflex_direction("perfect", PROBE[None], d[:5], PROBE, LO, HI, 2.0)
    assert np.allclose(at_centre / np.linalg.norm(at_centre, axis=1, keepdims=True), d[:5])


def test_perfect_sphere_misses_fall_back_to_the_plain_direction():
    far = np.array([[20.0, 0.0, 0.0]])
    d = np.array([[0.0, 1.0, 0.0]])
    assert rf.sphere_segment_t(far, far + d, PROBE, 1.0)[0] == -1.0
    assert np.array_equal(rf.compute_reflex_direction("perfect", far, d, PROBE, LO, HI, 1.0), d)


def test_quadratic_stretch_is_eq_5_9_and_pushes_face_centres_out_to_the_sphere():
    assert rf.quadratic_stretch(0.0, 2.0) == 0.0 and rf.quadratic_stretch(1.0, 2.0) == 0.0
    assert rf.quadratic_stretch(0.5, 2.0) == pytest.approx(2.0)
    assert rf.quadratic_stretch(0.25, 1.0) == pytest.approx(0.75)
    # a cube probe box centred on the probe: the ray through a face centre lands on the sphere,
    # one toward a corner lands on the corner (also on the sphere), so both see the sphere
    lo, hi, c = -np.ones(3), np.ones(3), np.zeros(3)
    radius = np.sqrt(3.0)
    d = np.array([[1.0, 0.0, 0.0], [1.0, 1.0, 1.0] / np.sqrt(3.0)])
    look = rf.compute_reflex_direction("approximation", np.zeros((2, 3)), d, c, lo, hi, radius)
    assert np.allclose(np.linalg.norm(look, axis=1), radius)
    # elsewhere it lies between the box and the sphere
    p, dd = _points_and_dirs(500, seed=4)
    p = p * 0.0
    box = rf.compute_reflex_direction("box", p, dd, c, lo, hi, radius)
    approx = rf.compute_reflex_direction("approximation", p, dd, c, lo, hi, radius)
    nb, na = np.linalg.norm(box, axis=1), np.linalg.norm(approx, axis=1)
    assert np.all(na >= nb - 1e-12) and np.all(na <= radius + 0.06)


def test_specular_colour_by_metallic_is_the_lerp():
    light, albedo = np.array([1.0, 1.0, 1.0]), np.array([0.9, 0.6, 0.2])
    assert np.allclose(rf.specular_color_by_metallic(light, albedo, 0.0), light)
    assert np.allclose(rf.specular_color_by_metallic(light, albedo, 1.0), albedo)
    assert np.allclose(rf.specular_color_by_metallic(light, albedo, 0.5), (light + albedo) / 2)


def test_nhx_lut_is_a_normalised_blinn_phong_lobe_and_dark_when_smooth():
    lut = rf.nhx_roughness_lut(64)
    assert lut.shape == (64, 64) and lut.dtype == np.float32
    assert lut.min() >= 0.0 and lut.max() <= 1.0
    # intensity grows toward n·h = 1 on every row
    assert np.all(np.diff(lut, axis=1) >= -1e-7)
    # value × 16 = (n + 2)/(2π)·cosⁿ where it is not clamped (a rough row)
    n = float(rf.spec_power(0.8))
    cos = 0.9
    want = (n + 2) / (2 * np.pi) * cos ** n
    assert rf.nhx_roughness(cos ** 4, 0.8) * 16 == pytest.approx(want, rel=1e-9)
    # low roughness: zero almost everywhere (the thesis's Fig. 61)
    smooth = rf.specular_intensity_from_lut(lut, np.linspace(0, 0.98, 50), 0.02)
    assert np.all(smooth < 1e-3)
    rough = rf.specular_intensity_from_lut(lut, np.linspace(0, 0.98, 50), 0.7)
    assert rough.max() > 0.1
    with pytest.raises(ValueError, match="allowed"):
        rf.nhx_roughness_lut(1)


def test_probe_mip_level_is_unitys_mapping():
    assert rf.probe_mip_level(1.0, 8) == 0.0
    assert rf.probe_mip_level(0.0, 8) == pytest.approx(6.0)  # r = 1: 1·(1.7 − 0.7)·6
    assert rf.probe_mip_level(0.5, 8) == pytest.approx(0.5 * (1.7 - 0.35) * 6)
    assert rf.probe_mip_level(0.0, 4) == 3.0  # clamped to the last level
    levels = rf.probe_mip_level(np.linspace(1, 0, 20), 8)
    assert np.all(np.diff(levels) > 0)


def test_split_sum_lut_is_bounded_and_a_mirror_at_normal_incidence():
    lut = rf.brdf_lut(8, 128)
    total = lut.sum(-1)
    assert np.all(lut >= 0) and np.all(total <= 1.0 + 1e-6)
    # smooth, seen head-on: A ≈ 1, B ≈ 0 (all energy, F = F0)
    a, b = lut[0, -1]
    assert a > 0.9 and b < 0.05
    # rougher loses energy (single scattering)
    assert total[-1, -1] < total[0, -1]
    assert np.allclose(rf.split_sum(np.ones(3), [0.5, 0.1], 0.04), 0.04 * 0.5 + 0.1)


def test_cube_views_match_the_cubemap_face_convention():
    # the view's −z axis is the face direction, its x the +s and its y the −t direction of
    # glsl/common/cubemap.glsl's CubemapFaceDirection
    want = {0: ((1, 0, 0), (0, 0, -1), (0, -1, 0)), 1: ((-1, 0, 0), (0, 0, 1), (0, -1, 0)),
            2: ((0, 1, 0), (1, 0, 0), (0, 0, 1)), 3: ((0, -1, 0), (1, 0, 0), (0, 0, -1)),
            4: ((0, 0, 1), (1, 0, 0), (0, -1, 0)), 5: ((0, 0, -1), (-1, 0, 0), (0, -1, 0))}
    for face, v in enumerate(rf.cube_face_views()):
        f, s, up = want[face]
        assert np.allclose(-v[2, :3], f) and np.allclose(v[0, :3], s)
        assert np.allclose(v[1, :3], up)
        assert np.linalg.det(v[:3, :3]) == pytest.approx(1.0)  # a rotation: no flipped winding


def test_params_are_in_the_surfaces_group_with_sections():
    params = {p.name: p for p in ReflectionProbe.python_params()}
    assert params["surfaces.reflection"].choices == rf.MODES
    assert params["surfaces.probe_size"].default == 128
    assert (params["surfaces.probe_size"].lo, params["surfaces.probe_size"].hi) == (64, 512)
    assert params["surfaces.specular_model"].choices == ("thesis", "ggx")
    assert all(p.section.startswith("spec/003 §2.") for p in params.values())
    assert rf.farthest_corner(PROBE, LO, HI) == pytest.approx(np.sqrt(16 + 2.25 + 16))

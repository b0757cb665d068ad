"""The lighting and toon models of the shading lab (spec/003 §2.1, spec/003 §2.12),
app/sim/lighting.py, the numpy twin of glsl/common/lighting.glsl: spec/003 §6 criteria 3–9 as
they apply to the functions (the GPU renders are tests/gl/test_shading_lighting.py), the forward
light sum, and no NaN where the vectors degenerate."""

from __future__ import annotations

import re

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from app import DEFAULT_SHADER_ROOT
from app.sim import lighting as lt

GLSL = DEFAULT_SHADER_ROOT / "common" / "lighting.glsl"
FUNCTION = re.compile(r"^(?:float|vec3)\s+(\w+)\s*\(", re.M)
unit = st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)).filter(
    lambda t: 0.01 < sum(c * c for c in t))


def _n(t) -> np.ndarray:
    a = np.asarray(t, dtype=np.float64)
    return a / np.linalg.norm(a, axis=-1, keepdims=True)


def _sphere(res: int = 201):
    """Normals of the visible hemisphere of a sphere seen along −z (v = +z), on a pixel grid."""
    x, y = np.meshgrid(np.linspace(-1, 1, res), np.linspace(-1, 1, res))
    inside = x * x + y * y < 1.0
    z = np.sqrt(np.clip(1 - x * x - y * y, 0, None))
    n = np.stack([x, y, z], -1)[inside]
    return n, np.broadcast_to([0.0, 0.0, 1.0], n.shape)


def _snake(name: str) -> str:
    name = name.replace("NdotL", "Ndotl")  # RemappedNdotL: remapped_ndotl
    return re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()


def test_every_glsl_function_has_its_twin():
    names = set(FUNCTION.findall(GLSL.read_text(encoding="utf-8")))
    assert len(names) >= 20
    assert not [n for n in names if not hasattr(lt, _snake(n))]


def test_defaults_match_the_annotations():
    from app.params import parse_glsl_annotations

    text = GLSL.read_text(encoding="utf-8") + (DEFAULT_SHADER_ROOT / "shading" /
                                               "surface.vert").read_text(encoding="utf-8")
    params = {p.uniform: p for p in parse_glsl_annotations(text, "shading")}
    u = lt.Shading().uniforms()
    assert set(params) == set(u)
    for name, p in params.items():
        want = p.default
        if isinstance(want, str):
            want = tuple(float(c) for c in want.split(","))
        assert np.allclose(np.asarray(u[name], dtype=float), np.asarray(want, dtype=float)), name


# ---- criterion 3: Lambert -------------------------------------------------------------------

@settings(max_examples=200, deadline=None)
@given(unit, unit)
def test_lambert_is_non_negative_and_the_clamped_cosine(n, l):  # noqa: E741
    n, l = _n(n), _n(l)  # noqa: E741
    k = lt.lambert_term(n, l)
    assert k >= 0.0 and np.isclose(k, max(0.0, float(n @ l)))


def test_criterion_3_lambert_sphere_lit_along_the_view():
    n, v = _sphere()
    s = lt.Shading(lighting_model=0)
    c = lt.shade_light(n, v, v, (1, 1, 1), np.ones(len(n)), (1, 1, 1), 1.0, s)
    centre = np.argmin(np.hypot(n[:, 0], n[:, 1]))
    assert c[centre, 0] >= 250 / 255
    assert np.allclose(c[:, 0], np.maximum(n[:, 2], 0.0))
    back = lt.shade_light(n, v, -v, (1, 1, 1), np.ones(len(n)), (1, 1, 1), 1.0, s)
    assert np.all(back == 0.0)  # n·l ≤ 0 and no ambient: black


# ---- criterion 4: Blinn–Phong and Phong -----------------------------------------------------

@settings(max_examples=200, deadline=None)
@given(unit, unit, unit, st.floats(1, 1000))
def test_blinn_phong_peaks_where_h_is_n(n, l, v, m):  # noqa: E741
    n, l, v = _n(n), _n(l), _n(v)  # noqa: E741
    h = lt.half_vector(l, v)
    k = lt.blinn_phong_term(n, h, m)
    assert 0.0 <= k <= 1.0 + 1e-12
    if np.linalg.norm(l + v) > 1e-3:
        assert np.isclose(lt.blinn_phong_term(h, h, m), 1.0)


def test_criterion_4_highlight_area_shrinks_with_the_exponent():
    n, v = _sphere(301)
    l = _n([0.4, 0.5, 0.77])  # noqa: E741
    ln = np.broadcast_to(l, n.shape)
    h = lt.half_vector(l, v[0])
    areas = {m: int((lt.blinn_phong_term(n, h, m) > 0.5).sum()) for m in (120, 400)}
    assert areas[120] > areas[400] > 0
    brightest = n[np.argmax(lt.blinn_phong_term(n, h, 400))]
    assert np.degrees(np.arccos(np.clip(brightest @ h, -1, 1))) < 0.5
    areas = {e: int((lt.phong_term(n, v, ln, e) > 0.5).sum()) for e in (60, 200)}
    assert areas[60] > areas[200] > 0


def test_specular_only_where_the_light_reaches():
    n, v = _sphere()
    l = np.broadcast_to(_n([0.0, -0.3, -1.0]), n.shape)  # noqa: E741 - from behind
    for model in (1, 2):
        k = lt.specular_term(n, v, l, lt.Shading(lighting_model=model))
        assert np.all(k[(n * l).sum(-1) <= 0] == 0.0)
    assert np.all(lt.specular_term(n, v, v, lt.Shading(lighting_model=0)) == 0.0)


# ---- criterion 5: rim -----------------------------------------------------------------------

def test_criterion_5_rim():
    v = np.array([0.0, 0.0, 1.0])
    assert lt.rim_term(v, v, 2) <= 2 / 255
    assert lt.rim_term(np.array([1.0, 0.0, 0.0]), v, 2) == 1.0  # grazing
    assert lt.rim_term(np.array([0.0, 0.0, -1.0]), v, 2) == 1.0  # clamped: max(0, n·v)
    n, vv = _sphere()
    edge = np.hypot(n[:, 0], n[:, 1]) > 0.999
    assert lt.rim_term(n[edge], vv[edge], 2).min() > 0.9
    means = [lt.rim_term(n, vv, m).mean() for m in (1, 2, 4, 8)]
    assert all(a > b for a, b in zip(means, means[1:], strict=False))


# ---- criterion 6: Stepped -------------------------------------------------------------------

@settings(max_examples=300, deadline=None)
@given(unit, unit, st.booleans(), st.floats(0, 5))
def test_stepped_takes_only_the_four_levels_times_the_light(n, l, repo, radiance):  # noqa: E741
    n, l = _n(n), _n(l)  # noqa: E741
    s = lt.Shading(toon=2, stepped_repository=repo, specularity=0.0)
    c = lt.shade_light(n, n, l, (radiance,) * 3, 1.0, (1, 1, 1), 1.0, s)
    assert np.any(np.isclose(c[0], np.asarray(lt.STEPPED_LEVELS) * radiance))
    assert c[0] >= 0.2 * radiance - 1e-12


def test_criterion_6_band_edges_at_the_documents_thresholds():
    ndotl = np.linspace(-1, 1, 20001)
    y = lt.stepped_document(lt.remapped_ndotl(ndotl))
    assert set(np.unique(y)) == set(lt.STEPPED_LEVELS)
    edges = ndotl[1:][np.diff(y) != 0]
    assert np.allclose(edges, [-0.1, 0.1, 0.3], atol=2e-4)
    assert y[0] == 0.2  # n·l = −1: the ambient floor


def test_the_two_stepped_variants_differ_where_appendix_a_says():
    ndotl = np.linspace(-1, 1, 20001)
    doc = lt.stepped_document(lt.remapped_ndotl(ndotl))
    repo = lt.stepped_repository(np.clip(ndotl, 0, 1))
    differ = ndotl[doc != repo]
    a = (ndotl > -0.1 + 1e-9) & (ndotl <= 0.0)
    b = (ndotl > 0.1 + 1e-9) & (ndotl <= 0.15)
    assert np.all(doc[a] == 0.5) and np.all(repo[a] == 0.2)
    assert np.all(doc[b] == 0.7) and np.all(repo[b] == 0.5)
    inside = ((differ > -0.1 - 2e-4) & (differ <= 2e-4)) | ((differ > 0.1 - 2e-4)
                                                              & (differ <= 0.15 + 2e-4))
    same_threshold = np.abs(differ - 0.3) < 2e-4  # x = 0.65 is n·l = 0.3: rounding only
    assert np.all(inside | same_threshold) and same_threshold.sum() <= 2
    # the repository thresholds saturate(n·l)·atten: a weaker light steps down earlier
    assert lt.stepped_repository(0.5 * 0.5) == 0.7 and lt.stepped_document(0.75) == 1.0


# ---- criterion 7: Flat ----------------------------------------------------------------------

def test_criterion_7_flat_two_levels_cut_at_the_terminator():
    ndotl = np.linspace(-1, 1, 20001)
    hard = lt.flat_diffuse(ndotl, 1.0)
    assert set(np.round(np.unique(hard), 9)) == {0.25, 1.0}
    cut = ndotl[1:][np.diff(hard) != 0]
    assert len(cut) == 1 and abs(cut[0]) < 2e-4
    counts = [int(((lt.flat_diffuse(ndotl, s) > 0.26) & (lt.flat_diffuse(ndotl, s) < 0.99)).sum())
              for s in (1.0, 0.75, 0.5, 0.25)]
    assert all(a < b for a, b in zip(counts, counts[1:], strict=False))
    k = np.linspace(0, 1, 10001)
    assert set(np.unique(lt.flat_edge(k, 1.0))) == {0.0, 1.0}  # hard-edged specular


# ---- criterion 8: Ramp ----------------------------------------------------------------------

RAMP = np.array([[0.1, 0.1, 0.3], [0.5, 0.4, 0.3], [1.0, 0.95, 0.8]])


def test_criterion_8_ramp_samples_at_half_ndotl_plus_half():
    n, v = _sphere()
    l = np.broadcast_to(_n([0.6, 0.3, 0.74]), n.shape)  # noqa: E741
    albedo = np.array([0.9, 0.6, 0.3])
    s = lt.Shading(toon=3, specularity=0.0)
    c = lt.shade_light(n, v, l, (1, 1, 1), np.ones(len(n)), albedo, 1.0, s, RAMP)
    x = 0.5 * (n * l).sum(-1) + 0.5
    idx = np.clip(np.floor(x * 3), 0, 2).astype(int)
    assert np.allclose(c, RAMP[idx] * albedo)
    found = np.unique(np.round(c / albedo, 9), axis=0)
    assert all(any(np.allclose(f, r) for r in RAMP) for f in found)
    linear = lt.ramp_sample(RAMP, np.array([0.0, 0.5, 1.0]), nearest=False)
    assert np.allclose(linear, RAMP)  # texel centres at 1/6, 1/2, 5/6; clamped to the ends


# ---- criterion 9: masks, emission, flicker --------------------------------------------------

def test_criterion_9_specular_mask_equals_specularity_zero():
    n, v = _sphere()
    l = np.broadcast_to(_n([0.3, 0.4, 0.87]), n.shape)  # noqa: E741
    for toon in (0, 1, 2):
        masked = lt.shade_light(n, v, l, (1, 1, 1), np.ones(len(n)), (0.5, 0.5, 0.5), 0.0,
                                lt.Shading(toon=toon, specularity=1.0))
        zero = lt.shade_light(n, v, l, (1, 1, 1), np.ones(len(n)), (0.5, 0.5, 0.5), 1.0,
                              lt.Shading(toon=toon, specularity=0.0))
        lit = lt.shade_light(n, v, l, (1, 1, 1), np.ones(len(n)), (0.5, 0.5, 0.5), 1.0,
                             lt.Shading(toon=toon, specularity=1.0))
        assert np.array_equal(masked, zero) and lit.max() > zero.max()


def test_criterion_9_emission_without_light_and_its_flicker():
    n, v = _sphere(51)
    dark = lt.Lights(sun_radiance=(0, 0, 0))
    s = lt.Shading(emission_color=(1.0, 0.75, 0.35))
    c = lt.shade_forward_base(n, v, (0.5, 0.5, 0.5), 1.0, 1.0, s, dark)
    assert np.allclose(c, [1.0, 0.75, 0.35])
    assert np.all(lt.shade_forward_base(n, v, (0.5, 0.5, 0.5), 1.0, 0.0, s, dark) == 0.0)
    flick = lt.Shading(flicker=1.0)
    means = {t: lt.shade_forward_base(n, v, (0.5,) * 3, 1.0, 1.0, flick, dark, t).mean()
             for t in (0.0, 0.37)}
    assert abs(means[0.0] - means[0.37]) > 1e-3
    t = np.linspace(0, 100, 200001)
    f = lt.flicker_wave(t)
    assert f.min() >= 0.0 and f.max() <= 1.0 and f.max() - f.min() > 0.8


# ---- the forward sum and the lights ---------------------------------------------------------

def test_forward_base_plus_add_and_each_light_adds():
    n, v = _sphere(61)
    p = n * 0.5
    s = lt.Shading(lighting_model=2, specularity=0.5)
    sun = lt.Lights(sun_dir=(0.3, 0.8, 0.5), sun_radiance=(1, 1, 1), ambient=(0.05, 0.05, 0.05))
    more = lt.Lights(**{**sun.__dict__, "point_pos": [(1.0, 0.0, 1.0), (-1.0, 0.5, 1.0)],
                        "point_radiance": [(2, 1, 0.5), (0.5, 0.5, 2)],
                        "point_range": [3.0, 3.0],
                        "spot_on": True, "spot_pos": (0, 0, 2), "spot_dir": (0, 0, -1),
                        "spot_cos": (0.99, 0.97), "spot_radiance": (1, 1, 1)})
    base = lt.shade_forward_base(n, v, (0.6,) * 3, 1.0, 0.0, s, more)
    add = lt.shade_forward_add(p, n, v, (0.6,) * 3, 1.0, s, more)
    total = lt.shade_surface(p, n, v, (0.6,) * 3, 1.0, 0.0, s, more)
    assert np.allclose(total, base + add)
    assert np.allclose(base, lt.shade_surface(p, n, v, (0.6,) * 3, 1.0, 0.0, s, sun))
    assert np.all(add >= 0) and add.sum() > 0


def test_point_attenuation_and_spot_cone():
    assert lt.point_attenuation(0.0, 2.0) == 1.0
    assert lt.point_attenuation(2.0, 2.0) == 0.0 and lt.point_attenuation(5.0, 2.0) == 0.0
    d = np.linspace(0, 2, 101)
    assert np.all(np.diff(lt.point_attenuation(d, 2.0)) <= 0)
    assert np.all(lt.point_attenuation(d, 0.0) == 1.0)
    c = np.linspace(-1, 1, 2001)
    cone = lt.spot_cone(c, (0.95, 0.9))
    assert np.all(cone[c <= 0.9] == 0.0) and np.all(cone[c >= 0.95] == 1.0)
    assert np.all(np.diff(cone) >= 0)
    hard = lt.spot_cone(c, (0.9, 0.9))
    assert set(np.unique(hard)) <= {0.0, 1.0} or np.isfinite(hard).all()


# ---- stability: degenerate vectors ----------------------------------------------------------

def test_no_nan_with_the_light_exactly_behind_at_grazing_or_at_the_surface():
    v = np.array([[0.0, 0.0, 1.0]])
    normals = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
    for toon in range(4):
        for model in range(3):
            s = lt.Shading(toon=toon, lighting_model=model, specularity=1.0, smoothness=1.0,
                           rim=True)
            for n in normals:
                for l in (-v[0], v[0], np.array([1.0, 0.0, 0.0]), n):  # noqa: E741
                    c = lt.shade_light(n[None], v, l[None], (1, 1, 1), np.ones(1), (1, 1, 1),
                                       1.0, s, RAMP)
                    assert np.all(np.isfinite(c))
            lights = lt.Lights(sun_dir=(0, 0, 0), point_pos=[(0.0, 0.0, 0.5)],
                               point_radiance=[(1, 1, 1)], point_range=[0.0], spot_on=True,
                               spot_pos=(0, 0, 0.5), spot_dir=(0, 0, 0), spot_cos=(0.9, 0.9))
            c = lt.shade_surface(np.array([[0, 0, 0.5]]), normals[:1], v, (1, 1, 1), 1.0, 1.0, s,
                                 lights, 0.0, RAMP)
            assert np.all(np.isfinite(c))
    assert np.array_equal(lt.half_vector(-v, v), np.zeros((1, 3)))

"""The numpy twin of the surfaces lab's transparency (app/sim/transparency.py, spec/003 §2.4):
render queues and their parsing, Unity's draw order, the alpha cutoff (criterion 16 on the
gradient texture), and the compositing operators — sorted over, front-to-back under (depth
peeling) and weighted blended OIT (McGuire and Bavoil 2013) — against each other."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from app.sim import surfaces_scene as ss
from app.sim import transparency as tw


@pytest.mark.parametrize("text, number", [
    ("Background", 1000), ("Geometry", 2000), ("AlphaTest", 2450), ("Transparent", 3000),
    ("Overlay", 4000), ("Transparent+5", 3005), ("Geometry-10", 1990), (" transparent + 1 ", 3001),
    ("2450", 2450), (0, 0), (5000, 5000)])
def test_queues_parse_as_unity_writes_them(text, number):
    assert tw.parse_queue(text) == number


@pytest.mark.parametrize("bad", ["Transparnt", "Transparent+", "Geometry*2", "", "5001", -1,
                                 "Overlay+1001", True, 2.5, None])
def test_bad_queues_are_one_line_errors(bad):
    with pytest.raises(ValueError) as e:
        tw.parse_queue(bad)
    msg = str(e.value)
    assert "\n" not in msg and "allowed" in msg and "render queue" in msg


@given(st.integers(0, 5000))
def test_format_and_parse_round_trip(n):
    assert tw.parse_queue(tw.format_queue(n)) == n


def test_format_names_the_queue_below():
    assert tw.format_queue(2450) == "AlphaTest"
    assert tw.format_queue(3005) == "Transparent+5"
    assert tw.format_queue(500) == "500"


def test_draw_order_opaque_front_to_back_transparent_back_to_front():
    queues = [3000, 2000, 3000, 2000, 2450, 1000]
    centres = [(0, 0, -1), (0, 0, -5), (0, 0, -9), (0, 0, -2), (0, 0, -3), (0, 0, -4)]
    order = tw.draw_order(queues, centres, (0, 0, 0))
    assert order == [5, 3, 1, 4, 2, 0]


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 5000), st.floats(-20, 20), st.floats(-20, 20)),
                min_size=1, max_size=12))
@example([(0, 0.0, 3.621652306268528e-193), (0, 0.0, 0.0)])  # its square underflows
def test_draw_order_properties(objs):
    queues = [o[0] for o in objs]
    centres = [(o[1], 0.0, o[2]) for o in objs]
    order = tw.draw_order(queues, centres, (0.0, 0.0, 0.0))
    assert sorted(order) == list(range(len(objs)))
    dist = [np.hypot(o[1], o[2]) for o in objs]
    for a, b in zip(order, order[1:]):
        assert queues[a] <= queues[b]
        if queues[a] == queues[b]:
            if queues[a] <= 2500:
                assert dist[a] <= dist[b]
            else:
                assert dist[a] >= dist[b]


def test_cutoff_sweep_on_the_gradient_texture():
    """Criterion 16: the discarded fraction is non-decreasing over Cutoff ∈ {0, 0.1, 0.5, 1},
    0 at 0, and at 1 every alpha below 1 is discarded."""
    a = ss.alpha_texture("gradient", 128)[..., 3]
    fractions = [tw.discarded_fraction(a, c) for c in (0.0, 0.1, 0.5, 1.0)]
    assert fractions[0] == 0.0
    assert all(x <= y for x, y in zip(fractions, fractions[1:]))
    assert fractions[1] > 0.05 and fractions[2] == pytest.approx(0.5, abs=0.01)
    assert not tw.cutout_kept(a[a < 1.0], 1.0).any()


def test_naive_alpha_test_keeps_stray_fragments_of_soft_leaves():
    a = ss.alpha_texture("leaves", 128)[..., 3]
    stray = tw.naive_kept(a) & ~tw.cutout_kept(a, 0.5)
    assert stray.mean() > 0.005  # alpha ≈ 0 but not 0: kept by the naive test


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.floats(0, 1), st.floats(0, 1), st.floats(0.1, 30)),
                min_size=0, max_size=6))
@example([(0.0, 0.001953125, 19.0)])  # Σ α·w below the resolve's floor (found by CI)
def test_peeling_equals_exact_sort_and_wboit_coverage_is_exact(layers):
    c = np.array([[x[0], 1 - x[0], 0.5] for x in layers]).reshape(-1, 3)
    a = np.array([x[1] for x in layers])
    z = np.array([x[2] for x in layers])
    bg = np.array([0.2, 0.3, 0.4])
    exact = tw.sorted_exact(c, a, z, bg)
    assert np.allclose(tw.peeled(c, a, z, bg), exact, atol=1e-9)
    # WBOIT: identical colours composite exactly (only the colour mix is approximate) while
    # Σ α·w(z, α) clears the 1e-5 floor of the resolve; below it the layers' colour is dimmed,
    # by at most their coverage times that colour (the background's share stays exact)
    grey = np.full_like(c, 0.7)
    err = np.abs(tw.wboit(grey, a, z, bg) - tw.sorted_exact(grey, a, z, bg)).max()
    coverage = 1.0 - float(np.prod(1.0 - a))
    if len(a) and (a * tw.wboit_weight(z, a)).sum() < 1e-5:
        assert err <= 0.7 * coverage + 1e-9
    else:
        assert err < 1e-9
    out = tw.wboit(c, a, z, bg)
    assert np.isfinite(out).all()


def test_wboit_is_exact_for_one_layer_and_order_independent():
    c, a, z, bg = [[0.9, 0.2, 0.1]], [0.5], [3.0], np.array([0.1, 0.1, 0.1])
    assert np.allclose(tw.wboit(c, a, z, bg), tw.sorted_exact(c, a, z, bg))
    cs = np.array([[0.9, 0.2, 0.1], [0.1, 0.8, 0.2], [0.2, 0.2, 0.9]])
    al, zs = np.array([0.5, 0.4, 0.7]), np.array([2.0, 3.0, 4.0])
    perm = [2, 0, 1]
    assert np.allclose(tw.wboit(cs, al, zs, bg), tw.wboit(cs[perm], al[perm], zs[perm], bg))


def test_intersecting_panes_wboit_beats_centre_sorting():
    """Two α = 0.5 panes crossing: where B lies behind A, sorting by their common centre draws
    B over A (ZWrite off) or drops B (ZWrite on); WBOIT's depth weight favours A."""
    A, B, bg = np.array([0.9, 0.25, 0.2]), np.array([0.2, 0.8, 0.3]), np.array([0.3, 0.3, 0.35])
    exact = tw.sorted_exact([A, B], [0.5, 0.5], [2.0, 2.3], bg)
    zwrite_off = tw.over([A, B], [0.5, 0.5], bg)  # B drawn last, over A
    zwrite_on = tw.over([A], [0.5], bg)  # B fails the depth test A wrote
    for eq in ("eq7", "eq8"):
        err = np.abs(tw.wboit([A, B], [0.5, 0.5], [2.0, 2.3], bg, eq) - exact).max()
        assert err < np.abs(zwrite_off - exact).max()
        assert err < np.abs(zwrite_on - exact).max()


def test_weights_are_clamped_decreasing_and_need_window_depth_for_eq10():
    z = np.linspace(0.01, 500, 200)
    for eq in ("eq7", "eq8", "eq9"):
        w = tw.wboit_weight(z, 1.0, eq)
        assert (w >= 1e-2 - 1e-12).all() and (w <= 3e3 + 1e-9).all()
        assert (np.diff(w) <= 1e-9).all()
    assert tw.wboit_weight(1.0, 0.5, "eq10", window_depth=0.0) == pytest.approx(1500.0)
    with pytest.raises(ValueError, match="allowed"):
        tw.wboit_weight(1.0, 0.5, "eq10")
    with pytest.raises(ValueError, match="allowed"):
        tw.wboit_weight(1.0, 0.5, "eq11")


def test_peeling_fewer_layers_loses_the_far_ones():
    c = np.array([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]])
    a, z, bg = np.array([0.5, 0.5, 0.5]), np.array([1.0, 2.0, 3.0]), np.zeros(3)
    assert tw.peel_layers(z, 2).tolist() == [True, True, False]
    one = tw.peeled(c, a, z, bg, layers=1)
    assert np.allclose(one, [0.5, 0, 0])
    assert np.allclose(tw.peeled(c, a, z, bg, layers=3), tw.sorted_exact(c, a, z, bg))


def test_two_sided_lighting_faces_the_viewer():
    n = np.array([0.0, 0.0, 1.0])
    lit = tw.quad_radiance((1, 1, 1), (1, 1, 1), n, (0, 0, 1), (0, 0, 1), (1, 1, 1), (0, 0, 0))
    back = tw.quad_radiance((1, 1, 1), (1, 1, 1), -n, (0, 0, 1), (0, 0, 1), (1, 1, 1),
                            (0, 0, 0))
    assert np.allclose(lit, 1.0) and np.allclose(back, 1.0)


# -- the A-buffer reference (issue 39) ---------------------------------------------------------
def test_the_a_buffer_sorts_each_pixel_and_ignores_absent_layers():
    """Per pixel, the A-buffer composite equals the per-pixel exact sort (sorted_exact) of the
    layers present there, whatever order the layers are given in; an absent layer (alpha 0)
    changes nothing, whatever its depth."""
    rng = np.random.default_rng(39)
    k, h, w = 4, 5, 6
    colour = rng.random((k, h, w, 3))
    alpha = rng.random((k, h, w)) * (rng.random((k, h, w)) > 0.3)
    depth = rng.random((k, h, w))
    bg = rng.random((h, w, 3))
    out = tw.a_buffer(colour * alpha[..., None], alpha, depth, bg)
    for y in range(h):
        for x in range(w):
            want = tw.sorted_exact(colour[:, y, x], alpha[:, y, x], depth[:, y, x], bg[y, x])
            np.testing.assert_allclose(out[y, x], want, atol=1e-12)
    perm = rng.permutation(k)
    again = tw.a_buffer((colour * alpha[..., None])[perm], alpha[perm], depth[perm], bg)
    np.testing.assert_allclose(again, out, atol=1e-12)
    # an absent layer (alpha 0, so α·c = 0) in front of everything does nothing
    extra = tw.a_buffer(np.concatenate([colour * alpha[..., None], np.zeros((1, h, w, 3))]),
                        np.concatenate([alpha, np.zeros((1, h, w))]),
                        np.concatenate([depth, -np.ones((1, h, w))]), bg)
    np.testing.assert_allclose(extra, out, atol=1e-12)


def test_the_a_buffer_differs_from_wboit_only_where_layers_overlap():
    """One layer over the background: the A-buffer, over, under and WBOIT agree; two layers:
    WBOIT's weighted mean is not the ordered composite."""
    c = np.array([[0.9, 0.2, 0.1], [0.1, 0.3, 0.9]])
    a = np.array([0.5, 0.6])
    z = np.array([1.0, 3.0])
    bg = np.array([0.3, 0.3, 0.35])
    one = tw.a_buffer((c * a[:, None])[:1, None], a[:1, None], z[:1, None], bg)[0]
    np.testing.assert_allclose(one, tw.wboit(c[:1], a[:1], z[:1], bg), atol=1e-12)
    two = tw.a_buffer((c * a[:, None])[:, None], a[:, None], z[:, None], bg)[0]
    np.testing.assert_allclose(two, tw.sorted_exact(c, a, z, bg), atol=1e-12)
    assert np.abs(two - tw.wboit(c, a, z, bg)).max() > 0.01


def test_layer_counts_count_alpha_above_the_threshold():
    a = np.array([[[0.0, 0.5, 1e-4, 0.2]], [[0.0, 0.0, 0.3, 0.9]], [[0.0, 0.002, 0.0, 0.1]]])
    np.testing.assert_array_equal(tw.layer_counts(a), [[0, 2, 1, 3]])
    np.testing.assert_array_equal(tw.layer_counts(a, 0.25), [[0, 1, 1, 1]])
    assert tw.layer_counts(np.zeros((0, 2, 3))).shape == (2, 3)

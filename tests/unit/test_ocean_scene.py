"""The `ocean` scene's numpy side (issue 6): the polar mesh and the whitecap foam calibration."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from app.effects.ocean.mesh import CHUNK, GROUP, polar_grid, stretch_height, whole_groups
from app.sim import ocean as oc

# -- mesh ----------------------------------------------------------------------------------------

def test_polar_grid_covers_the_disc_facing_up_without_degenerate_cells():
    verts, idx = polar_grid(128, 0.25, 3000.0)
    r, th = verts[:, 0].astype(float), verts[:, 1].astype(float)
    p = np.stack([r * np.cos(th), np.zeros_like(r), r * np.sin(th)], axis=1)
    tri = idx.reshape(-1, 3)
    a, b, c = p[tri[:, 0]], p[tri[:, 1]], p[tri[:, 2]]
    ny = np.cross(b - a, c - a)[:, 1]
    assert np.all(ny > 0), "every triangle faces up (front faces are the top of the sea)"
    area = 0.5 * ny.sum()
    polygon = 0.5 * 128 * 3000.0**2 * math.sin(2 * math.pi / 128)  # the outer ring is a 128-gon
    assert abs(area / polygon - 1.0) < 1e-6
    assert r.max() == pytest.approx(3000.0)
    # cells stay about square: radial step / tangential step within [0.5, 2] beyond the first ring
    radii = np.unique(r)
    ratio = np.diff(radii)[1:-1] / (radii[1:-2] * 2 * math.pi / 128)
    assert ratio.min() > 0.5 and ratio.max() < 2.0


def test_polar_grid_is_ordered_group_by_group_and_column_by_column():
    """Wedge j's triangles (its fan triangle, then two per ring outward) lie in its group of
    GROUP wedges, chunk by chunk of CHUNK triangles outward, wedge after wedge; the vertices run
    column by column: the per-wedge construction, integer for integer."""
    chunked = False
    for segments, inner, extent in ((16, 0.5, 400.0), (7, 1.0, 1.5), (5, 2.0, 1.0),
                                    (21, 0.25, 3000.0)):
        verts, idx = polar_grid(segments, inner, extent)
        nr = (len(verts) - 1) // segments
        col = verts[1:].reshape(segments, nr, 3)
        assert np.all(col[:, :, 1] == (np.arange(segments) * (2 * math.pi / segments))[:, None]
                      .astype("f4"))
        assert np.all(col == col[:1, :, :] * [1, 0, 1] + col[:, :, :] * [0, 1, 0])
        wedges = []
        for j in range(segments):
            a, b = 1 + j * nr, 1 + (j + 1) % segments * nr
            tris = [[0, b, a]]
            for i in range(nr - 1):
                tris += [[a + i, b + i, b + i + 1], [a + i, b + i + 1, a + i + 1]]
            wedges.append(tris)
        want = []
        for g in range(0, segments, GROUP):
            for c in range(0, len(wedges[0]), CHUNK):
                for tris in wedges[g:g + GROUP]:
                    want += [v for t in tris[c:c + CHUNK] for v in t]
        assert idx.dtype == np.uint32 and idx.tolist() == want
        chunked = chunked or (segments > GROUP and len(wedges[0]) > CHUNK)
    assert chunked  # a case with several groups and several chunks a wedge


@given(st.integers(1, 64), st.data())
def test_whole_groups_cover_the_visible_wedges_and_little_more(segments, data):
    first = data.draw(st.integers(0, segments - 1))
    count = data.draw(st.integers(1, segments))
    run = whole_groups(first, count, segments)
    want = {(first + k) % segments for k in range(count)}
    if run is None:  # every wedge: the groups around the visible ones reach all the way round
        assert count + 2 * (GROUP - 1) >= segments or segments <= GROUP
        return
    start, n = run
    assert start % GROUP == 0 and 0 < n < segments
    drawn = {(start + k) % segments for k in range(n)}
    assert want <= drawn and len(drawn) == n
    assert n < count + 2 * GROUP  # at most a part group each side
    end = start + n if start + n <= segments else start + n - segments
    assert end % GROUP == 0 or end == segments  # whole groups: ranges of the index buffer


def test_whitecap_thresholds_are_calibrated_quantiles():
    rng = np.random.default_rng(0)
    jac = [1.0 + 0.2 * rng.standard_normal(200_000), 1.0 + 0.05 * rng.standard_normal(200_000),
           np.ones(10)]
    (t0, w0), (t1, w1), (t2, _) = oc.whitecap_thresholds(jac, 0.03, shares=[2, 1, 1])
    assert w0 == pytest.approx(0.2, rel=0.01) and w1 == pytest.approx(0.05, rel=0.01)
    assert np.mean(jac[0] < t0 - w0 / 2) == pytest.approx(0.015, rel=0.05)
    assert np.mean(jac[1] < t1 - w1 / 2) == pytest.approx(0.0075, rel=0.05)
    assert t2 <= 1e-3, "a flat cascade makes no foam"
    assert oc.whitecap_coverage(0.0) == 0.0 and oc.whitecap_coverage(12.0) == pytest.approx(
        3.84e-6 * (12 / 1.075) ** 3.41)


def test_stretched_grid_keeps_far_cells_at_the_asked_screen_aspect():
    """Beyond aspect·h a cell's radial step grows as r/(aspect·h), so seen from height h (its
    depression angle shrinks by h·Δr/r²) it is 1/aspect as tall as its arc is wide; the square
    grid is untouched where the stretch has not begun, and aspect 0 is the square grid."""
    segments, aspect, h = 256, 8.0, 4.0
    square = polar_grid(segments, 0.25, 3000.0)
    assert all(np.array_equal(a, b) for a, b in zip(square, polar_grid(segments, 0.25, 3000.0,
                                                                       0.0, h)))
    verts, idx = polar_grid(segments, 0.25, 3000.0, aspect, h)
    radii = np.unique(verts[:, 0].astype(float))
    knee = aspect * h
    arc = radii * 2 * math.pi / segments
    far = (radii > knee)[:-2]  # (the last ring is cut at the extent)
    screen = np.diff(radii)[:-1][far] * h / radii[:-2][far] / arc[:-2][far]
    assert np.allclose(screen, 1.0 / aspect, rtol=1e-4)
    near = radii[radii <= knee]
    assert np.array_equal(near, np.unique(square[0][:, 0].astype(float))[:len(near)])
    beyond = int((radii > knee).sum())
    assert beyond <= 1.15 * segments / (2 * math.pi)  # about segments/2π, whatever the extent
    wider = np.unique(polar_grid(segments, 0.25, 30000.0, aspect, h)[0][:, 0].astype(float))
    assert int((wider > knee).sum()) <= beyond + 2  # ten times the extent: hardly more rings
    assert len(idx) < 0.75 * len(square[1])
    assert verts[:, 0].max() == pytest.approx(3000.0)
    tri = idx.reshape(-1, 3)  # still facing up, with no degenerate cell
    r, th = verts[:, 0].astype(float), verts[:, 1].astype(float)
    p = np.stack([r * np.cos(th), np.zeros_like(r), r * np.sin(th)], axis=1)
    assert np.all(np.cross(p[tri[:, 1]] - p[tri[:, 0]], p[tri[:, 2]] - p[tri[:, 0]])[:, 1] > 0)


def test_stretch_height_keeps_its_power_of_two_while_the_camera_bobs():
    h = stretch_height(0.0, 6.0)
    assert h == 4.0
    for bob in (5.0, 7.5, 11.9, 2.7):
        assert stretch_height(h, bob) == 4.0
    assert stretch_height(h, 12.5) == 8.0 and stretch_height(h, 2.6) == 2.0
    assert stretch_height(0.0, -3.0) == 2.0  # under water: the depth below the surface
    assert stretch_height(0.0, 0.0) == 0.5

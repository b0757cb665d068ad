"""The outline measures of app/sim/outline_metrics.py (spec/003 §2.13): the analytic sphere and
box silhouettes against closed forms, the silhouette bands' areas, IoU and gap counts on
synthetic masks, the rim weights' twin (app/sim/staircase.py), the table's boxes against the
lab's mesh."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from app.sim import lab_meshes, staircase
from app.sim import outline_metrics as om
from app.sim.camera import Camera

SIZE = (96, 96)
CAMERA = Camera(position=(0.0, 0.0, 4.0), yaw=0.0, pitch=0.0, fov=40.0)
VIEW = CAMERA.view_matrix()
PROJ = CAMERA.projection_matrix(1.0)


def _disc_radius_px(radius: float, distance: float) -> float:
    """A centred sphere's silhouette: a circle of angular radius asin(r / d)."""
    return math.tan(math.asin(radius / distance)) / math.tan(math.radians(20.0)) * SIZE[1] / 2


def test_the_sphere_silhouette_is_the_analytic_disc():
    inside = om.sphere_coverage(VIEW, PROJ, SIZE, (0.0, 0.0, 0.0), 1.0)
    r = _disc_radius_px(1.0, 4.0)
    assert inside.sum() == pytest.approx(math.pi * r * r, rel=0.02)
    assert inside[48, 48] and not inside[0, 0]
    nv = om.sphere_nv(VIEW, PROJ, SIZE, (0.0, 0.0, 0.0), 1.0)
    assert np.isnan(nv[~inside]).all()
    assert nv[47:49, 47:49].min() > 0.999  # the centre faces the camera
    assert np.nanmin(nv) < 0.3  # the rim is grazing


def test_a_face_on_cube_covers_its_square():
    inside = om.boxes_coverage(VIEW, PROJ, SIZE, [((-0.5, -0.5, -0.5), (0.5, 0.5, 0.5))])
    side = 2 * 0.5 / 3.5 / math.tan(math.radians(20.0)) * SIZE[1] / 2  # its front face, at z 3.5
    assert inside.sum() == pytest.approx(side * side, rel=0.05)
    moved = np.identity(4)
    moved[0, 3] = 5.0  # placed out of view by the model matrix
    assert not om.boxes_coverage(VIEW, PROJ, SIZE, [((-0.5, -0.5, -0.5), (0.5, 0.5, 0.5))],
                                 model=moved).any()


def test_bands_have_the_width_asked():
    inside = om.sphere_coverage(VIEW, PROJ, SIZE, (0.0, 0.0, 0.0), 1.0)
    r = _disc_radius_px(1.0, 4.0)
    for w in (2.0, 4.0):
        out = om.silhouette_band(inside, w, "outside")
        assert out.sum() == pytest.approx(math.pi * ((r + w) ** 2 - r * r), rel=0.1)
        assert not (out & inside).any()
        inner = om.silhouette_band(inside, w, "inside")
        assert inner.sum() == pytest.approx(math.pi * (r * r - (r - w) ** 2), rel=0.1)
        both = om.silhouette_band(inside, w, "both")
        assert (both == (out | inner)).all()
    with pytest.raises(ValueError):
        om.silhouette_band(inside, 1.0, "sideways")
    assert np.isinf(om.boundary_distance(np.zeros((4, 4), bool))).all()


def test_iou_and_gaps_on_synthetic_masks():
    inside = om.sphere_coverage(VIEW, PROJ, SIZE, (0.0, 0.0, 0.0), 1.0)
    band = om.silhouette_band(inside, 3.0, "outside")
    assert om.outline_iou(band, band) == 1.0
    assert om.outline_iou(band, inside) == 0.0
    assert om.outline_iou(np.zeros_like(band), np.zeros_like(band)) == 1.0
    thin = om.silhouette_band(inside, 1.5, "outside")
    assert om.gap_count(band, thin) == 0
    torn = band.copy()
    torn[:, 46:50] = False  # two cuts, top and bottom of the ring
    assert om.gap_count(torn, thin) == 2
    assert om.gap_count(torn, thin, min_size=100) == 0
    assert 0.8 < om.outline_iou(torn, band) < 1.0


def test_rim_weights_are_the_staircase_twins():
    nv = np.linspace(0.0, 1.0, 401)
    r = 0.5
    x = np.clip(1.0 - nv / r, 0.0, 1.0)
    thr = om.rim_outline_weight("threshold", nv, r)
    assert set(np.unique(thr)) <= {0.0, 1.0}
    assert (thr == (nv < r)).all()
    assert np.allclose(om.rim_outline_weight("50x2", nv, r), np.clip(50 * x * x, 0.0, 1.0))
    soft = om.rim_outline_weight("soft", nv, r)
    assert np.allclose(soft, staircase.soft_staired_value(x * (1 + om.RIM_STAIR_STEP),
                                                          om.RIM_STAIR_STEP,
                                                          om.RIM_STAIR_STEP / 2))
    assert soft.min() == 0.0 and soft.max() == 1.0
    assert (np.diff(soft[::-1]) >= -1e-12).all()  # non-decreasing toward the silhouette
    assert np.isfinite(om.rim_outline_weight("soft", nv, 0.0)).all()  # r clamped
    with pytest.raises(ValueError):
        om.rim_outline_weight("bands", nv, r)


def test_the_table_boxes_bound_the_lab_table():
    mesh = lab_meshes.table()
    lo, hi = mesh.bounds()
    boxes = np.array(om.table_boxes())
    assert np.allclose(boxes[:, 0].min(axis=0), lo, atol=1e-6)
    assert np.allclose(boxes[:, 1].max(axis=0), hi, atol=1e-6)
    assert len(boxes) == 5


@given(arrays(np.bool_, st.tuples(st.integers(1, 24), st.integers(1, 24))),
       st.sampled_from([0.5, 1.0, 1.5, 2.0, 3.0, 4.5]))
def test_the_windowed_distance_is_the_brute_force_below_its_limit(inside, limit):
    """boundary_distance(limit=…) (what silhouette_band uses): the same values as the search
    over every edge midpoint wherever that is below the limit, inf elsewhere."""
    every = om.boundary_distance(inside)
    near = om.boundary_distance(inside, limit=limit)
    below = every < limit
    assert np.array_equal(near[below], every[below])
    assert np.isinf(near[~below]).all()

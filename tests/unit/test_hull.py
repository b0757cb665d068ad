"""The boat's hull (app/sim/hull.py): closed and manifold, outward normals, exact volumes and
waterplanes against independent integrals, the draft that floats a mass, subdivision."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.errors import ParamError
from app.sim import hull as H
from app.sim.rigid_body import quat_from_axis_angle, quat_to_matrix
from tests.helpers import measures


@pytest.fixture(scope="module")
def mesh():
    return H.make_hull()


def _simpson(y, x):
    n = len(x) - 1
    assert n % 2 == 0
    h = (x[-1] - x[0]) / n
    return h / 3.0 * (y[0] + y[-1] + 4.0 * y[1:-1:2].sum() + 2.0 * y[2:-1:2].sum())


def _section_area(mesh, z):
    """Area of the hull's cross-section at z, from the cut segments by Green's theorem: each
    segment oriented so that the outward normal of its triangle lies to its right."""
    p = mesh.corners()
    n = mesh.area_vectors()
    d = p[..., 2] - z
    a, b = p[:, [0, 1, 2]], p[:, [1, 2, 0]]
    da, db = d[:, [0, 1, 2]], d[:, [1, 2, 0]]
    cut = (da > 0) != (db > 0)
    sel = np.nonzero(cut.sum(1) == 2)[0]
    t = np.where(cut, da / np.where(cut, da - db, 1.0), 0.0)
    pts = (a + t[..., None] * (b - a))[sel]
    e = np.argsort(~cut[sel], axis=1, kind="stable")[:, :2]
    seg = np.take_along_axis(pts, e[:, :, None], 1)[..., :2]  # (S, 2, xy)
    tx, ty = seg[:, 1, 0] - seg[:, 0, 0], seg[:, 1, 1] - seg[:, 0, 1]
    flip = ty * n[sel, 0] - tx * n[sel, 1] < 0  # outward must be to the right: (ty, −tx)
    seg[flip] = seg[flip][:, ::-1]
    return 0.5 * float(np.sum(seg[:, 0, 0] * seg[:, 1, 1] - seg[:, 1, 0] * seg[:, 0, 1]))


def test_the_hull_is_closed_manifold_and_wound_outward(mesh):
    assert mesh.vertices.dtype == np.float64 and mesh.triangles.dtype == np.int32
    assert mesh.deck.dtype == bool and mesh.deck.shape == (len(mesh.triangles),)
    assert 300 <= len(mesh.triangles) <= 2000
    assert np.all(measures.edges_shared(mesh) == 2)
    # consistent winding: every directed edge appears once, its reverse once
    t = mesh.triangles
    directed = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    assert len(np.unique(directed, axis=0)) == len(directed)
    assert mesh.volume() > 0
    assert np.allclose(mesh.area_vectors().sum(0), 0.0, atol=1e-9)
    # deck triangles face up, the bottom faces down
    av = mesh.area_vectors()
    assert np.all(av[mesh.deck, 1] > 0)
    bottom = mesh.corners()[..., 1].max(1) < 0.05
    assert bottom.any() and np.all(av[bottom, 1] < 0)
    assert mesh.vertices[:, 1].min() == pytest.approx(0.0, abs=1e-12)
    assert np.ptp(mesh.vertices[:, 2]) == pytest.approx(8.0)
    assert 2.0 * mesh.vertices[:, 0].max() == pytest.approx(2.6, rel=1e-6)


def test_volume_matches_the_integral_of_section_areas(mesh):
    z = np.linspace(-4.0 + 1e-9, 4.0 - 1e-9, 801)
    areas = np.array([_section_area(mesh, c) for c in z])
    assert np.all(areas >= -1e-12)
    independent = _simpson(areas, z)
    assert mesh.volume() == pytest.approx(independent, rel=5e-3)
    # the centroid's z: the first moment of the same slices
    zc = _simpson(areas * z, z) / independent
    assert mesh.centroid()[2] == pytest.approx(zc, abs=0.01)
    assert abs(mesh.centroid()[0]) < 1e-9  # the mesh is symmetric


def test_a_real_hull_shape_not_a_box(mesh):
    d = H.draft_for_mass(mesh, 3000.0)
    z = np.array([-3.0, -2.0, -0.4, 2.0, 3.0])
    half = H.waterline_half_beam(mesh, d, z)
    assert half[2] > half[1] > 0 and half[2] > half[3] > half[4] > 0
    assert half[0] > half[4]  # the stern fuller than the bow
    block = mesh.volume() / (8.0 * 2.6 * 1.4)
    assert 0.3 < block < 0.75
    # V sections forward, a flat floor aft: breadth low down over breadth higher up
    low = H.waterline_half_beam(mesh, 0.1 * 1.4, np.array([-0.5, 2.0]))
    high = H.waterline_half_beam(mesh, 0.5 * 1.4, np.array([-0.5, 2.0]))
    assert low[0] / high[0] > 2.0 * low[1] / high[1]


def test_waterplane_area_matches_the_integral_of_the_waterline_beam(mesh):
    for mass in (1500.0, 3000.0, 5000.0):
        d = H.draft_for_mass(mesh, mass)
        z = np.linspace(-4.0, 4.0, 4001)
        beam = 2.0 * H.waterline_half_beam(mesh, d, z)
        integral = float(np.sum(0.5 * (beam[1:] + beam[:-1]) * np.diff(z)))
        sub = mesh.submerged(d)
        assert sub.waterplane_area == pytest.approx(integral, rel=5e-3)
        assert sub.volume * H.RHO_SEA == pytest.approx(mass, rel=1e-6)
        assert 0.0 < d < 1.4


def test_volume_is_invariant_under_rigid_motion(mesh):
    q = quat_from_axis_angle((0.3, 1.0, -0.7), 1.1)
    r = quat_to_matrix(q)
    moved = H.HullMesh(mesh.vertices @ r.T + np.array([5.0, -2.0, 3.0]), mesh.triangles,
                       mesh.deck)
    assert moved.volume() == pytest.approx(mesh.volume(), rel=1e-12)
    assert np.allclose(moved.centroid(), r @ mesh.centroid() + [5.0, -2.0, 3.0], atol=1e-9)


def test_submerged_part_is_exact_at_the_limits_and_symmetric_in_heel(mesh):
    assert mesh.submerged(-0.1).volume == 0.0
    assert mesh.submerged(3.0).volume == pytest.approx(mesh.volume(), rel=1e-12)
    assert mesh.submerged(3.0).waterplane_area == pytest.approx(0.0, abs=1e-9)
    a, b = mesh.submerged(0.5, heel=0.3), mesh.submerged(0.5, heel=-0.3)
    assert a.volume == pytest.approx(b.volume, rel=1e-12)
    assert a.centre[0] == pytest.approx(-b.centre[0], abs=1e-9) and a.centre[0] > 0.05
    # bow-down trim moves the centre of buoyancy forward
    assert mesh.submerged(0.5, trim=0.05).centre[2] > mesh.submerged(0.5).centre[2]
    # the same volume by cutting the rotated mesh with the level plane
    r = H.heel_trim_rotation(0.3, 0.1)
    corners = (mesh.vertices @ r.T)[mesh.triangles]
    via_world = H.submerged_below_plane(mesh, r @ [0.0, 0.5, 0.0], (0, 1, 0), corners=corners)
    assert via_world.volume == pytest.approx(mesh.submerged(0.5, 0.3, 0.1).volume, rel=1e-12)


def test_submerged_volume_of_a_box_is_analytic():
    v = np.array([[x, y, z] for x in (0, 2) for y in (0, 1) for z in (0, 3)], float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))], np.int32)
    box = H.HullMesh(v, tris, np.zeros(len(tris), bool))
    assert box.volume() == pytest.approx(6.0)
    s = box.submerged(0.25)
    assert s.volume == pytest.approx(1.5) and s.waterplane_area == pytest.approx(6.0)
    assert np.allclose(s.centre, [1.0, 0.125, 1.5])
    # heeled 10° starboard down about the z-axis through the corner: a triangular prism
    s = box.submerged(0.0, heel=math.radians(10.0))
    assert s.volume == pytest.approx(0.5 * 2.0 * 2.0 * math.tan(math.radians(10.0)) * 3.0)
    inertia = H.solid_inertia(box, 6.0)
    assert np.allclose(inertia, np.diag([(1 + 9) / 12 * 6, (4 + 9) / 12 * 6, (4 + 1) / 12 * 6]))


def test_draft_for_mass_floats_the_mass_and_refuses_what_sinks(mesh):
    d = H.draft_for_mass(mesh, 2500.0)
    assert mesh.submerged(d).volume * H.RHO_SEA == pytest.approx(2500.0, rel=1e-7)
    assert H.draft_for_mass(mesh, 4000.0) > d
    with pytest.raises(ParamError, match="boat.mass"):
        H.draft_for_mass(mesh, 1e6)


def test_subdivide_keeps_the_polyhedron(mesh):
    fine = H.subdivide(mesh, 4)
    assert len(fine.triangles) == 16 * len(mesh.triangles)
    assert np.all(measures.edges_shared(fine) == 2)
    assert fine.volume() == pytest.approx(mesh.volume(), rel=1e-12)
    assert fine.deck.sum() == 16 * mesh.deck.sum()
    d = H.draft_for_mass(mesh, 3000.0)
    assert fine.submerged(d, 0.2).volume == pytest.approx(mesh.submerged(d, 0.2).volume,
                                                         rel=1e-10)
    assert len(fine.vertices) < 16 * len(mesh.vertices)  # shared vertices merged


def test_solid_inertia_is_symmetric_positive_and_shifts_by_parallel_axes(mesh):
    i0 = H.solid_inertia(mesh, 3000.0)
    assert np.allclose(i0, i0.T) and np.all(np.linalg.eigvalsh(i0) > 0)
    about = mesh.centroid() + [0.0, -0.3, 0.2]
    i1 = H.solid_inertia(mesh, 3000.0, about=about)
    d = about - mesh.centroid()
    assert np.allclose(i1 - i0, 3000.0 * (d @ d * np.eye(3) - np.outer(d, d)))
    assert i0[0, 0] > i0[2, 2]  # pitch inertia above roll for a long hull


@pytest.mark.parametrize("name,value", [("length", 0.0), ("beam", -1.0), ("depth", math.nan),
                                        ("transom", 1.5), ("section_bow", 0.5)])
def test_bad_hull_parameters_name_the_culprit(name, value):
    with pytest.raises(ParamError, match=f"boat.hull.{name}") as err:
        H.make_hull(H.HullParams(**{name: value}))
    assert "allowed" in str(err.value) and "\n" not in str(err.value)


def test_hull_resolution_and_scaling():
    small = H.make_hull(H.HullParams().scaled(0.125), stations=9, around=4)
    assert np.all(measures.edges_shared(small) == 2)
    big = H.make_hull(H.HullParams().scaled(2.0))
    assert big.volume() == pytest.approx(8.0 * H.make_hull().volume(), rel=1e-9)
    with pytest.raises(ParamError):
        H.make_hull(stations=2)

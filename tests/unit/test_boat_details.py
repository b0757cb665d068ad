"""The boat's visual parts (app/effects/boat/details.py): the hull drawn is the buoyancy's hull,
unchanged; the deck fittings stand on its deck; the waterline the shader wets and foams the
hull at is where the water meets the sides (spec/000 §1.3)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.effects.boat import details
from app.effects.boat.effect import WATERLINE_STATIONS, Boat
from app.sim.boat import BoatSim
from app.sim.hull import make_hull


def test_the_drawn_hull_is_the_physics_hull():
    sim = BoatSim()
    before = sim.mesh.vertices.copy(), sim.mesh.triangles.copy()
    rows = details.hull_rows(sim.mesh)
    assert len(rows) == 3 * len(sim.mesh.triangles)
    assert np.allclose(rows[:, 0:3], sim.mesh.vertices[sim.mesh.triangles].reshape(-1, 3),
                       atol=1e-6)
    assert np.array_equal(sim.mesh.vertices, before[0])
    assert np.array_equal(sim.mesh.triangles, before[1])
    assert sim.mesh.volume() == pytest.approx(make_hull().volume())
    topsides = rows[rows[:, 10] == details.MATERIAL_HULL]
    assert (topsides[:, 9] >= -1e-5).all() and topsides[:, 9].max() > 1.0  # depth below sheer


def test_deck_fittings_stand_on_the_deck():
    hull = make_hull()
    deck = details.Deck(hull)
    parts = details.deck_fittings(hull)
    assert len(parts) > 300 and len(parts) % 3 == 0
    assert np.isfinite(parts).all()
    p = parts[:, 0:3].astype(np.float64)
    assert np.allclose(np.linalg.norm(parts[:, 3:6], axis=1), 1.0, atol=1e-4)
    # nothing hangs outside the hull's deck edge or below the deck by more than a sinking
    assert (np.abs(p[:, 0]) <= deck.breadth(p[:, 2]) + 1e-3).all()
    assert (p[:, 1] >= deck.height(p[:, 2]) - 0.35).all()
    assert (p[:, 2] >= deck.stern - 1e-6).all() and (p[:, 2] <= deck.stem).all()
    materials = set(np.unique(parts[:, 10]).astype(int))
    assert materials <= set(range(5)) and details.MATERIAL_GLASS in materials
    cabin = p[(p[:, 2] > -1.0) & (p[:, 2] < 1.8)]  # the coachroof between the cockpit and the bow
    assert cabin[:, 1].max() > deck.height(0.0) + 0.4  # a coachroof stands above the deck


class _Water:
    """A flat sea at height h, or tilted by slope along x."""

    def __init__(self, h: float, slope: float = 0.0):
        self.h, self.slope, self.query_time = h, slope, 0.0

    def height(self, x, z):
        return self.h + self.slope * np.asarray(x, float) + 0.0 * np.asarray(z, float)


def _boat(sim: BoatSim) -> Boat:
    boat = Boat.__new__(Boat)
    boat.sim, boat._deck = sim, None
    return boat


def test_the_waterline_is_where_the_water_meets_the_sides():
    sim = BoatSim()
    sim.body.position = (3.0, 1.5 - sim.draft, -7.0)  # floating level on a sea at 1.5 m
    sim.body.rotation = np.identity(3)
    wl = _boat(sim)._waterline(_Water(1.5))
    assert wl.shape == (2, WATERLINE_STATIONS)
    assert np.allclose(wl, sim.draft, atol=1e-9)
    # heeled to starboard by 10° on the same sea: the water climbs the starboard side
    a = math.radians(10.0)
    sim.body.rotation = np.array([[math.cos(a), math.sin(a), 0.0],
                                  [-math.sin(a), math.cos(a), 0.0], [0.0, 0.0, 1.0]])
    wl = _boat(sim)._waterline(_Water(1.5))
    mid = slice(0, WATERLINE_STATIONS - 2)  # the stem is on the centreline
    assert (wl[1, mid] > sim.draft + 0.05).all() and (wl[0, mid] < sim.draft - 0.05).all()
    assert np.isfinite(wl).all()

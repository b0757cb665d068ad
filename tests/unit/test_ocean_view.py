"""The FFT ocean simulated for what the view resolves (``ocean.simulation = view``, issue 37):
each cascade's grid from the screen footprint of its wavelengths and slow cascades interpolated
between snapshots computed ahead of time — app/sim/ocean.py (``crop_cascade``,
``nearest_water_footprint``, ``view_cascade_size``, ``interpolation_error``,
``refresh_period``) and app/effects/ocean/schedule.py (the snapshot plan), in numpy alone.

Each figure is checked against an independent computation: the cropped grid against the full
grid's synthesis with the dropped modes zeroed, the footprint against rays cast through the
pixel rows, the interpolation error against the fields synthesised at three times.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.effects.ocean.schedule import SnapshotSchedule
from app.errors import ParamError
from app.sim import ocean as oc
from app.sim.camera import Camera


@pytest.fixture(scope="module")
def sea() -> oc.FFTOcean:
    return oc.FFTOcean(oc.SpectrumParams(kind="jonswap", wind_speed=12.0), n=64,
                       patch_sizes=(250.0, 17.0, 5.0), choppiness=1.0, seed=3)


# -- crop_cascade --------------------------------------------------------------------------------

@pytest.mark.parametrize("n", [16, 32])
def test_a_cropped_cascade_is_the_full_grid_without_its_finest_modes(sea, n):
    """Sampled at its own points, the n grid's fields equal the 64 grid's fields of the same
    spectrum with every mode |m| ≥ n/2 zeroed: a smaller N drops waves, never redraws the sea."""
    c = sea.cascades[1]
    small = oc.crop_cascade(c, n)
    assert small.h0.shape == (n, n) and small.patch_size == c.patch_size
    assert small.band[1] == pytest.approx(min(c.band[1], math.pi * n / c.patch_size))
    size = c.h0.shape[0]
    m = np.fft.fftfreq(size, 1.0 / size)
    keep = (np.abs(m)[:, None] < n // 2) & (np.abs(m)[None, :] < n // 2)
    t = 4.2
    full = oc.synthesize(oc.evolve_amplitudes(np.where(keep, c.h0, 0.0), c.omega, t), c.kx, c.kz)
    got = oc.synthesize(oc.evolve_amplitudes(small.h0, small.omega, t), small.kx, small.kz)
    step = size // n
    for key in ("height", "disp_x", "slope_z", "jacobian"):
        ref = getattr(full, key)[::step, ::step]
        assert np.max(np.abs(getattr(got, key) - ref)) < 1e-9 * max(1.0, np.max(np.abs(ref)))
    assert oc.crop_cascade(c, size) is c and oc.crop_cascade(c, 128) is c


def test_a_crop_to_a_bad_size_is_one_line(sea):
    with pytest.raises(ParamError, match="power of two") as err:
        oc.crop_cascade(sea.cascades[0], 24)
    assert "\n" not in str(err.value)


# -- nearest_water_footprint ---------------------------------------------------------------------

def _footprints_by_ray(camera: Camera, rows: int, clearance: float) -> np.ndarray:
    """Distance between the water hits of neighbouring pixel rows on the centre column (a plane
    ``clearance`` below the camera), rays cast through the pixel centres."""
    cols = 2 * rows  # any even width: the column pair around the centre is averaged
    d = camera.ray_directions(cols, rows)[:, cols // 2 - 1: cols // 2 + 1].mean(axis=1)
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    down = d[:, 1] < 0.0
    hits = d[down] * (clearance / -d[down, 1:2])
    return np.linalg.norm(np.diff(hits, axis=0), axis=-1)


@pytest.mark.parametrize("pitch, fov", [(-10.0, 60.0), (-25.0, 40.0), (-70.0, 60.0),
                                        (5.0, 60.0)])
def test_the_nearest_footprint_is_the_smallest_row_spacing_on_the_water(pitch, fov):
    cam = Camera(position=(0.0, 12.0, 0.0), yaw=30.0, pitch=pitch, fov=fov)
    rows, clearance = 360, 10.0
    got = oc.nearest_water_footprint(cam, 16 / 9, rows, clearance)
    ref = float(np.min(_footprints_by_ray(cam, rows, clearance)))
    assert got == pytest.approx(ref, rel=0.02)


def test_footprint_edge_cases():
    cam = Camera(position=(0.0, 3.0, 0.0), pitch=10.0, fov=10.0)  # no ray looks down
    assert oc.nearest_water_footprint(cam, 1.0, 100, 2.0) == math.inf
    assert oc.nearest_water_footprint(cam, 1.0, 100, 0.0) == 0.0  # among the crests
    assert oc.nearest_water_footprint(cam, 1.0, 100, -1.0) == 0.0


# -- view_cascade_size ---------------------------------------------------------------------------

def test_a_cascade_grid_follows_the_footprint():
    size = 17.0
    top = math.pi * 256 / size
    # a fine footprint asks for the finest grid, a coarse one for the coarsest
    assert oc.view_cascade_size(size, top, 1e-4, 256) == 256
    assert oc.view_cascade_size(size, top, 50.0, 256) == 16
    assert oc.view_cascade_size(size, top, 0.0, 256) == 256  # the camera among the crests
    # texels no larger than the footprint: N = the next power of two of L / footprint
    for footprint in (0.05, 0.1, 0.3, 0.9):
        n = oc.view_cascade_size(size, 1e3, footprint, 512)
        assert size / n <= footprint < 2.0 * size / n or n == 16
    # ... and no finer than a quarter of the band's shortest wave (samples = 4) needs
    n = oc.view_cascade_size(size, 2.0 * math.pi / 0.8, 1e-3, 512)
    assert size / n <= 0.2 < 2.0 * size / n
    # monotonic in the footprint
    grids = [oc.view_cascade_size(size, top, f, 256) for f in np.geomspace(1e-3, 10.0, 40)]
    assert grids == sorted(grids, reverse=True)


def test_a_smaller_grid_waits_until_the_need_has_clearly_fallen():
    size, top = 17.0, 1e3
    assert oc.view_cascade_size(size, top, 17.0 / 100, 256) == 128  # need 100 texels
    # at 60 texels of need, 64 would do, but 128 stays (60 > 128/2/1.25 = 51.2)
    assert oc.view_cascade_size(size, top, 17.0 / 60, 256, current=128) == 128
    assert oc.view_cascade_size(size, top, 17.0 / 50, 256, current=128) == 64
    assert oc.view_cascade_size(size, top, 17.0 / 200, 256, current=128) == 256  # up at once


# -- interpolation between snapshots ----------------------------------------------------------

@pytest.mark.parametrize("i, period", [(0, 0.5), (0, 1.0), (1, 0.1), (1, 0.3)])
def test_interpolation_error_matches_the_synthesised_fields(sea, i, period):
    """The rms error of the linear blend of two snapshots at mid-interval against the fields
    synthesised there (an expectation over h₀'s random phases: one draw of 64² modes is within
    a few per cent of it)."""
    c = sea.cascades[i]
    t_a = 3.0

    def fields(t):
        return oc.synthesize(oc.evolve_amplitudes(c.h0, c.omega, t), c.kx, c.kz)

    a, b, mid = fields(t_a), fields(t_a + period), fields(t_a + 0.5 * period)
    e_h = math.sqrt(np.mean((0.5 * (a.height + b.height) - mid.height) ** 2))
    e_s = math.sqrt(np.mean((0.5 * (a.slope_x + b.slope_x) - mid.slope_x) ** 2
                            + (0.5 * (a.slope_z + b.slope_z) - mid.slope_z) ** 2))
    want_h, want_s = oc.interpolation_error(c, period)
    assert e_h == pytest.approx(want_h, rel=0.15)
    assert e_s == pytest.approx(want_s, rel=0.15)
    assert want_s > 0.0


def test_refresh_period_holds_the_tolerance(sea):
    slope = math.sqrt(sum(c.moments()[1] for c in sea.cascades))
    tol = 0.03 * slope
    periods = [oc.refresh_period(c, tol) for c in sea.cascades]
    # the long waves may wait longest; the shortest cascade changes fastest
    assert periods[0] >= periods[1] >= periods[2]
    for c, period in zip(sea.cascades, periods):
        if 0.0 < period < 1.0:
            assert oc.interpolation_error(c, period)[1] <= tol * (1 + 1e-9)
            assert oc.interpolation_error(c, period * 1.01)[1] > tol  # the longest that holds
    assert oc.refresh_period(sea.cascades[0], 0.0) == 0.0
    assert oc.refresh_period(sea.cascades[0], 1e9) == 1.0  # capped at ``longest``


# -- the snapshot schedule ---------------------------------------------------------------------

def _run(schedule: SnapshotSchedule, times):
    return [(t, schedule.plan(t, dt)) for t, dt in times]


def test_the_next_snapshot_is_complete_before_it_is_needed():
    """Frames of 1/30 s against a period of 0.2 s and 17 steps: the first frame computes A and
    B; each later frame does a share of C's steps, all of them done before t reaches t_b; at
    t ≥ t_b, C is finalised into A's set (swap) and the weight restarts from 0."""
    dt = 1.0 / 30.0
    s = SnapshotSchedule(period=0.2, steps=17)
    frames = _run(s, [(1.0 + k * dt, dt) for k in range(40)])
    assert frames[0][1].reset and not frames[0][1].actions
    t_a, done, swaps = 1.0, 0, 0
    for t, plan in frames[1:]:
        assert not plan.reset
        for action in plan.actions:
            if action.kind == "step":
                assert action.index == done and action.time == pytest.approx(t_a + 0.4)
                done += 1
            else:
                assert done == 17 and action.time == pytest.approx(t_a + 0.4)
                t_a, done, swaps = t_a + 0.2, 0, swaps + 1
        assert plan.weight == pytest.approx((t - t_a) / 0.2)
        assert 0.0 <= plan.weight <= 1.0
        assert plan.steps <= math.ceil(17 / (0.2 / dt - 1)) + 1  # spread, not bunched
        if t + dt >= t_a + 0.2 - 1e-9:  # the last frame before t_b: C is complete
            assert done == 17
    assert swaps == 6


def test_the_schedule_starts_over_when_the_clock_jumps_or_the_sea_changes():
    s = SnapshotSchedule(period=0.5, steps=5)
    assert s.plan(10.0, 0.1).reset
    assert not s.plan(10.1, 0.1).reset
    assert s.plan(9.0, -1.1).reset  # back in time
    assert not s.plan(9.2, 0.2).reset
    assert s.plan(20.0, 10.8).reset  # past the snapshot in progress
    assert s.plan(20.1, 0.1, key="new sea").reset
    assert not s.plan(20.2, 0.1, key="new sea").reset


def test_a_standing_clock_keeps_the_last_interval():
    s = SnapshotSchedule(period=0.4, steps=9)
    s.plan(0.0, 0.1)
    first = s.plan(0.1, 0.1)
    stand = s.plan(0.1, 0.0)  # paused: nothing left to spread it over but the last interval
    assert stand.weight == first.weight == pytest.approx(0.25)
    assert first.steps + stand.steps <= 9


@pytest.mark.parametrize("period, steps", [(0.0, 3), (math.inf, 3), (-1.0, 3), (0.5, 0)])
def test_bad_schedules_are_refused(period, steps):
    with pytest.raises(ValueError):
        SnapshotSchedule(period=period, steps=steps)


# -- the wake map's screen rectangle (app/effects/ocean/deferred.py) --------------------------

def test_the_screen_rectangle_of_a_box_holds_its_pixels_and_nothing_behind_the_camera():
    from app.effects.ocean.deferred import screen_rect

    cam = Camera(position=(0.0, 5.0, 0.0), yaw=0.0, pitch=-10.0, fov=60.0)
    size = (320, 180)
    vp = cam.view_projection_relative(size[0] / size[1])
    # a box 40 m ahead (−z is north, yaw 0): every pixel of its corners is inside the rectangle
    bounds, heights = (-3.0, -45.0, 3.0, -35.0), (-6.0, -4.0)
    x, y, w, h = screen_rect(vp, bounds, heights, size)
    assert w > 0 and h > 0 and x >= 0 and y >= 0 and x + w <= size[0] and y + h <= size[1]
    rng = np.random.default_rng(1)
    pts = np.column_stack([rng.uniform(-3, 3, 200), rng.uniform(-6, -4, 200),
                           rng.uniform(-45, -35, 200), np.ones(200)])
    clip = pts @ vp.T
    px = (clip[:, 0] / clip[:, 3] + 1.0) * 0.5 * size[0]
    py = (clip[:, 1] / clip[:, 3] + 1.0) * 0.5 * size[1]
    assert (px >= x).all() and (px <= x + w).all() and (py >= y).all() and (py <= y + h).all()
    assert w < 0.5 * size[0]  # and not the whole screen
    # behind the camera: nothing; around it: clipped at the near side, not flipped
    assert screen_rect(vp, (-3.0, 35.0, 3.0, 45.0), heights, size) == (0, 0, 0, 0)
    x, y, w, h = screen_rect(vp, (-3.0, -45.0, 3.0, 45.0), heights, size)
    assert w > 0 and h > 0 and y == 0  # reaches the bottom edge (the water under the camera)
    assert screen_rect(vp, (3.0, 0.0, -3.0, 1.0), heights, size) == (0, 0, 0, 0)  # empty box

"""The numpy side of the amortised march (app/sim/amortise.py): the refresh order, the
void-and-cluster blue noise, the schedule ``auto`` picks from the frame budget, the depth
agreement and the rules that throw a history away."""

from __future__ import annotations

import numpy as np
import pytest

from app.sim.amortise import (
    BUDGET_SHARE,
    LayerState,
    Schedule,
    bayer_matrix,
    block_position,
    blue_noise,
    choose_schedule,
    depth_agree,
    jitter_phase,
    reset_reason,
)


def test_bayer_order_visits_every_pixel_of_a_block_once_per_cycle():
    for block in (1, 2, 4, 8):
        seen = [block_position(i, block) for i in range(block * block)]
        assert sorted(seen) == sorted((x, y) for x in range(block) for y in range(block))
        assert block_position(block * block + 3, block) == block_position(3, block)
    # consecutive steps are well spread: the first four of a 4×4 block are one per 2×2 quarter
    quarters = {(x // 2, y // 2) for x, y in (block_position(i, 4) for i in range(4))}
    assert len(quarters) == 4
    with pytest.raises(ValueError):
        bayer_matrix(3)


def test_blue_noise_is_a_permutation_with_little_low_frequency_energy():
    n = 32
    noise = blue_noise(n)
    ranks = np.sort(((noise * n * n) - 0.5).round().astype(int).ravel())
    assert np.array_equal(ranks, np.arange(n * n))  # each threshold once: uniform in (0, 1)

    def low_share(a):
        spec = np.abs(np.fft.fft2(a - a.mean())) ** 2
        f = np.fft.fftfreq(n)
        r = np.hypot(f[:, None], f[None, :])
        return spec[(r > 0) & (r < 0.15)].sum() / spec.sum()

    white = np.random.default_rng(1).permutation(n * n).reshape(n, n).astype(float)
    assert low_share(noise) < 0.3 * low_share(white), (low_share(noise), low_share(white))
    # neighbours differ (no clumps): the mean |difference| of horizontal neighbours is well
    # above white noise's 1/3
    assert np.abs(noise - np.roll(noise, 1, axis=1)).mean() > 0.4
    # deterministic: the same map every time (a memoised build, no download)
    assert np.array_equal(noise, blue_noise(n))


def test_jitter_phase_starts_at_zero_and_spreads():
    phases = [jitter_phase(i) for i in range(8)]
    assert phases[0] == 0.0
    gaps = np.diff(np.sort(phases + [1.0]))
    assert gaps.min() > 0.05  # the golden ratio keeps successive phases apart


@pytest.mark.parametrize("cost", [10.0, 300.0, 1050.0, 3300.0, 1.0e6])
def test_auto_schedule_fits_the_budget_when_it_can(cost):
    size, budget = (640, 360), 33.0
    mpx = size[0] * size[1] / 1e6
    s = choose_schedule("auto", "auto", size, cost, budget)
    fits = cost * mpx * s.fraction <= BUDGET_SHARE * budget
    assert fits or s == Schedule(4, 4)  # the coarsest when nothing fits
    # no finer candidate of the order would have fitted before it
    assert s.scale in (2, 4) and s.refresh in (1, 2, 4)
    if cost <= 10.0:
        assert s == Schedule(2, 1)  # a fast GPU: half resolution, every ray each frame


def test_fixed_choices_are_kept():
    assert choose_schedule("full", "all", (64, 64), 1e6, 33.0) == Schedule(1, 1)
    assert choose_schedule("quarter", "1/16", (64, 64), 0.0, 33.0) == Schedule(4, 4)
    assert choose_schedule("half", "auto", (640, 360), 1050.0, 33.0).scale == 2
    s = Schedule(4, 2)
    assert (s.block, s.cycle, s.fraction) == (8, 64, 1 / 64)
    assert s.label() == "quarter, refresh 1/4"


def test_depth_agreement():
    assert depth_agree(1000.0, 1040.0) and not depth_agree(1000.0, 1100.0)
    assert depth_agree(0.2, 1.1) and not depth_agree(2.0, 4.0)  # the 1 m floor, then 5 %


def _state(**kw) -> LayerState:
    base = dict(key=(1,), light_dir=np.array([0.0, 1.0, 0.0]), light_radiance=np.ones(3),
                wind=np.array([5.0, 0.0, 0.0]), field_offset=np.zeros(3), near=0.0, far=1e5)
    base.update(kw)
    return LayerState(**base)


def _turned(deg: float) -> np.ndarray:
    a = np.radians(deg)
    return np.array([np.sin(a), np.cos(a), 0.0])


def test_reset_reasons():
    s = _state()
    assert reset_reason(s, None, None) == "no history"
    assert reset_reason(s, s, s) is None
    # a slow sun (a second of the day at 1×) keeps the history; time of day jumping does not
    assert reset_reason(_state(light_dir=_turned(0.01)), s, s) is None
    assert reset_reason(_state(light_dir=_turned(1.0)), s, s) == "the light turned fast"
    drift = _state(light_dir=_turned(2.5))
    assert reset_reason(drift, _state(light_dir=_turned(2.4)), s) == "the light turned"
    assert reset_reason(_state(light_radiance=np.full(3, 1.2)), s, s) == \
        "the light's radiance changed"
    assert reset_reason(_state(wind=np.array([7.0, 0.0, 0.0])), s, s) == "the wind changed"
    assert reset_reason(_state(wind=np.array([5.5, 0.0, 0.0])), s, s) is None
    assert reset_reason(_state(field_offset=np.array([80.0, 0.0, 0.0])), s, s) == \
        "the field jumped"
    assert reset_reason(_state(key=(2,)), s, s) == "parameters changed"
    assert reset_reason(s, s, s, cam_turn_deg=30.0) == "the camera jumped"
    assert reset_reason(s, s, s, cam_move_m=1000.0) == "the camera jumped"
    assert reset_reason(s, s, s, cam_turn_deg=1.0, cam_move_m=10.0) is None  # a 30°/s pan

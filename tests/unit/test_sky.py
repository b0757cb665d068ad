"""The day–night sky against spec/000 §6 criteria 26–31 on numpy: the twins (app/sim/sky.py,
app/sim/daynight.py) against the digest's numbers, the keyframes, time and the ecliptic.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.effects.sky.effect import DEFAULT_KEYFRAMES
from app.errors import ParamError
from app.sim import sky as skyfx
from app.sim.daynight import GRADIENT_TEXELS, DayNight, Keyframes, sun_direction, wrap_hour

ECLIPTIC = (0.0, 0.6, -1.0)


# ---- criterion 26: the sun disk ---------------------------------------------------------------

def test_twin_matches_digest_table():
    table = {0.0: 400.7, 2.0: 57.4, 5.0: 4.26, 10.0: 0.58}
    for deg, value in table.items():
        got = float(skyfx.sun_term(math.cos(math.radians(deg))))
        assert got == pytest.approx(value, rel=0.02), (deg, got)


# ---- criterion 27: horizon glow -----------------------------------------------------------------

def test_halo_strongest_at_horizon():
    sins = np.linspace(-0.2, 1.0, 61)
    f = skyfx.scattering_intensity_factor(sins)
    assert np.all(f[sins <= 0.0] == 1.0)
    assert np.allclose(f[sins >= 0.6], 0.15)
    assert np.all(np.diff(f) <= 1e-12)  # never rises as the sun climbs


# ---- criterion 29: keyframes every three hours ---------------------------------------------------

def test_keyframes_exact_at_keyframe_hours_and_linear_between():
    kf = Keyframes.load(DEFAULT_KEYFRAMES)
    assert [k.hour for k in kf.frames] == [0, 3, 6, 9, 12, 15, 18, 21]
    u = np.linspace(0, 1, GRADIENT_TEXELS)
    for k in kf.frames:
        assert np.allclose(kf.gradient_at(u, k.hour), k.evaluate(u), atol=1e-6)
    mid = kf.gradient_at(u, 10.5)
    assert np.allclose(mid, 0.5 * (kf.frames[3].evaluate(u) + kf.frames[4].evaluate(u)), atol=1e-6)
    # across midnight: 22.5 h is halfway between 21 h and 0 h
    assert np.allclose(kf.gradient_at(u, 22.5),
                       0.5 * (kf.frames[7].evaluate(u) + kf.frames[0].evaluate(u)), atol=1e-6)


def test_time_stays_in_range():
    for h, expected in [(24.0, 0.0), (25.0, 1.0), (-1.0, 23.0), (48.25, 0.25), (23.999, 23.999)]:
        assert wrap_hour(h) == pytest.approx(expected)
        assert 0.0 <= wrap_hour(h) < 24.0
    dn = DayNight(Keyframes.load(DEFAULT_KEYFRAMES), hour=23.5, speed=3.0, playing=True)
    for _ in range(100):
        dn.advance(0.37)
        assert 0.0 <= dn.hour < 24.0


def test_keyframe_file_errors_are_one_line(tmp_path):
    bad = tmp_path / "k.toml"
    bad.write_text('[[keyframe]]\nhour = 30\ngradient = [[0, "#ffffff"]]\n')
    with pytest.raises(ParamError, match=r"hour 30 .*allowed a number in \[0, 24\)"):
        Keyframes.load(bad)
    bad.write_text('[[keyframe]]\nhour = 3\ngradient = [[0, "blue"]]\n')
    with pytest.raises(ParamError, match="colour 'blue'"):
        Keyframes.load(bad)


# ---- criterion 30: sun and moon about the ecliptic axis ------------------------------------------

def test_sun_highest_at_noon_below_horizon_at_midnight_moon_opposite():
    hours = np.arange(0, 24, 0.25)
    elev = np.array([sun_direction(h, ECLIPTIC)[1] for h in hours])
    assert hours[np.argmax(elev)] == 12.0
    assert elev[hours == 0.0][0] < 0 and elev.max() > 0.5
    east = sun_direction(6.5, ECLIPTIC)
    assert east[0] > 0.9 and east[1] > 0  # rises in the east (+x)
    dn = DayNight(Keyframes.load(DEFAULT_KEYFRAMES), hour=0.0)
    st = dn.state()
    assert np.allclose(st.moon_dir, -st.sun_dir)
    assert st.main_light.name == "moon"
    dn.hour = 12.0
    assert dn.state().main_light.name == "sun"


def test_vertical_axis_and_zero_axis():
    d = sun_direction(7.0, (0.0, 1.0, 0.0))
    assert np.all(np.isfinite(d)) and abs(np.linalg.norm(d) - 1) < 1e-9
    with pytest.raises(ParamError, match="sky.ecliptic"):
        sun_direction(7.0, (0.0, 0.0, 0.0))

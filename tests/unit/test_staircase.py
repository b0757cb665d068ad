"""The staircase functions of the toon look (spec/003 §2.10, §2.13), app/sim/staircase.py, the
numpy twin of glsl/common/staircase.glsl: spec/003 §6 criteria 11 and 12, and the twin's
one-to-one correspondence with the GLSL functions."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from app import DEFAULT_SHADER_ROOT
from app.sim import staircase as sc

GLSL = DEFAULT_SHADER_ROOT / "common" / "staircase.glsl"
FUNCTION = re.compile(r"^(?:float|vec3)\s+(\w+)\s*\(", re.M)


def _snake(name: str) -> str:
    return re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()


def test_every_glsl_function_has_its_twin():
    names = set(FUNCTION.findall(GLSL.read_text(encoding="utf-8")))
    assert len(names) >= 10
    missing = [n for n in names if not hasattr(sc, _snake(n))]
    assert not missing


def test_each_equation_is_tagged_once_in_the_glsl_and_in_the_twin():
    text = GLSL.read_text(encoding="utf-8")
    body = text[text.index("=\n", text.index("Numpy twin")):]  # past the header
    twin = Path(sc.__file__).read_text(encoding="utf-8")
    for eq in ("7.18", "7.19", "7.20", "8.2", "8.3", "8.4"):
        tag = f"// spec/003 eq. {eq}:"
        assert body.count(tag) == 1, tag
        assert twin.count(f'"""spec/003 eq. {eq}:') == 1, eq


def test_step_y():
    assert sc.staircase_step_y(0.15) == 0.15 / 0.85
    assert sc.staircase_step_y(0.25) == 0.25 / 0.75
    assert np.isfinite(sc.staircase_step_y(1.0)) and np.isfinite(sc.staircase_step_y(0.0))


def test_criterion_12_levels_for_step_015():
    x = np.linspace(0.0, 1.0, 100001)
    levels = np.unique(np.round(sc.staired_value(x, 0.15), 9))
    want = np.unique(np.round(np.minimum([k * 0.15 / 0.85 for k in range(7)], 1.0), 9))
    assert np.allclose(levels, want, atol=1e-9)
    assert levels[-1] == 1.0 and len(levels) == 7


def test_criterion_12_integer_steps_give_k_over_n_minus_1():
    for n in (2, 3, 4, 5, 8, 10):
        x = (np.arange(n * 200) + 0.5) / (n * 200)  # x in [0, 1), away from the jumps
        levels = np.unique(np.round(sc.staired_value(x, 1.0 / n), 9))
        assert np.allclose(levels, np.arange(n) / (n - 1), atol=1e-9), n


@settings(max_examples=200, deadline=None)
@given(st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0.02, 0.5))
def test_staircase_is_monotone_bounded_and_below_its_floor_level(a, b, step):
    lo, hi = min(a, b), max(a, b)
    ylo, yhi = sc.staired_value(lo, step), sc.staired_value(hi, step)
    assert 0.0 <= ylo <= yhi + 1e-12 <= 1.0 + 1e-12
    f = sc.staircase_floor(hi, step)
    assert f <= hi + 1e-12 and hi - f < step + 1e-12


def test_soft_staircase_with_zero_softness_is_the_hard_staircase():
    x = np.linspace(0.0, 1.0, 5001)
    for step in (0.1, 0.25, 0.3):
        hard = np.clip(x - (x - step * np.floor(x / step)), 0.0, 1.0)
        assert np.array_equal(sc.soft_staired_value(x, step, 0.0), hard)


@settings(max_examples=60, deadline=None)
@given(st.floats(0.05, 0.5), st.floats(0.05, 1.0))
def test_criterion_11_soft_staircase_never_jumps_more_than_its_slope_allows(step, frac):
    soft = step * frac  # 0 < step_soft ≤ step
    x = np.linspace(0.0, 1.0, 20001)
    y = sc.soft_staired_value(x, step, soft)
    dx = x[1] - x[0]
    assert np.abs(np.diff(y)).max() <= step * dx / soft + 1e-9


def test_soft_staircase_ramp_is_centred_on_each_jump():
    step, soft = 0.25, 0.1
    assert np.isclose(sc.soft_staired_value(0.5, step, soft), 0.5 - step / 2)
    assert np.isclose(sc.soft_staired_value(0.5 + soft / 2, step, soft), 0.5, atol=1e-12)
    assert np.isclose(sc.soft_staired_value(0.5 - soft / 2 - 1e-9, step, soft), 0.25,
                      atol=1e-6)
    assert sc.soft_staired_value(0.375, step, soft) == 0.25  # mid-step: the hard level


def test_weights_of_spec_003_eq_8_2_and_8_3():
    assert sc.soft_stair_weight_min(0.0, 0.1) == 0.5
    assert sc.soft_stair_weight_min(0.05, 0.1) == 0.0
    assert sc.soft_stair_weight_max(0.25, 0.25, 0.1) == 0.5
    assert np.isclose(sc.soft_stair_weight_max(0.2, 0.25, 0.1), 0.0)


def test_criterion_11_threshold_is_binary_and_the_third_variant_is_50x2():
    x = np.linspace(0.0, 1.0, 1001)
    assert set(np.unique(sc.threshold_step(x, 0.4))) == {0.0, 1.0}
    assert np.allclose(sc.soft_silhouette(x), np.clip(50 * x * x, 0, 1))
    assert sc.soft_silhouette(0.1) == 0.5

"""The water section of `natura bench village` (app/bench/village_water.py, spec/003 §2.10)
in its quick run: every variant timed (Simple and Complex, the depth fog off and its three
methods, the Complex water with the fifth power), the Fresnel ramp's errors against
0.018 + 0.982·(1 − u)^5 (criterion 20) in numpy and on the GPU, the report JSON-serialisable,
its chart written and its summary printed."""

from __future__ import annotations

import json
import math

import pytest

from app.bench import village_water as vw
from tests.helpers.readme import village_report

report = village_report("water")


def test_every_variant_is_timed(report):
    cost = report["cost"]
    names = {f"{kind} fog {fog}" for kind, fog in vw.VARIANTS} | {"complex pow5 fog thickness"}
    assert names | {"restore"} == set(cost)
    for name in names:
        c = cost[name]
        assert c["rounds"] >= 5
        assert math.isfinite(c["net_ms"]) and c["net_ms"] > 0.0, name
        assert c["net_p25_ms"] <= c["net_ms"] <= c["net_p75_ms"]
        assert c["ratio_to_simple_fog_off"] > 0.0
    assert cost[vw.BASE]["ratio_to_simple_fog_off"] == pytest.approx(1.0)
    json.dumps(report)  # the report is JSON


def test_the_fresnel_ramp_against_the_fifth_power(report):
    r = report["ramp"]
    widths = r["widths"]
    assert [x["width"] for x in widths] == list(vw.RAMP_WIDTHS)
    errors = [x["max_error"] for x in widths]
    assert all(a > b for a, b in zip(errors, errors[1:]))  # finer ramps are closer
    assert errors[0] > 1.0 / 255.0  # 8 texels miss criterion 20: the check can fail
    assert widths[-1]["max_error"] < 0.05 / 255.0  # the effect's ramp: far within it
    assert widths[-1]["max_error_8bit"] < 1.0 / 255.0  # the thesis's 8-bit painting, just
    # on the GPU the water's reflectance with the ramp is the fifth power's, and the fifth
    # power is the formula at each pixel's n·v
    assert r["gpu_pixels"] > 1000
    assert r["gpu_ramp_vs_pow5_max"] < 1.0 / 255.0
    assert r["gpu_pow5_vs_formula_max"] < 1e-4
    assert r["ramp_ms"] > 0.0 and r["pow5_ms"] > 0.0 and r["ramp_over_pow5"] > 0.0


def test_chart_and_summary(report, tmp_path):
    path = tmp_path / "water.png"
    vw.chart(report, path)
    assert path.stat().st_size > 20000
    lines = vw.summary(report)
    assert len(lines) == 5
    assert lines[1].startswith("  simple: fog off") and "thickness" in lines[2]
    assert "ratio ramp/pow5" in lines[-1]


def test_the_ramp_figures_without_a_gl_context():
    """The ramp section's numpy half on its own: a coarse ramp misses criterion 20 (one 8-bit
    level), the effect's 256-texel ramp is far within it, finer is closer."""
    coarse, fine = vw.ramp_errors(widths=(8, 256), samples=4001)
    assert coarse["max_error"] > 1.0 / 255.0 > fine["max_error_8bit"]
    assert fine["max_error"] < 0.05 / 255.0 < coarse["max_error"]

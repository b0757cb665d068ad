"""The toon look measured (spec/003 §6 criterion 37, app/bench/village_look.py): on the lit
houses, props and people of one village view, the toon look has fewer distinct luma levels than
Lambert / Blinn–Phong and no lower mean saturation, in the image the village shows (Unity 5's
clamped LDR output); the report and its chart."""

from __future__ import annotations

import json

from app.bench import village_look
from tests.helpers.readme import village_report

report = village_report("look")


def test_criterion_37_fewer_levels_and_no_less_saturation(report):
    toon, plain = report["looks"]["toon"], report["looks"]["lambert_blinn_phong"]
    assert report["tonemap"] == "clamp"
    assert report["masked_pixels"] > 1000  # houses, props and people in view, sunlit
    assert report["masked_pixels"] <= report["object_pixels"]
    assert toon["levels"] < 0.75 * plain["levels"]
    assert toon["levels_all"] < plain["levels_all"]
    assert report["fewer_levels"] and report["saturation_not_lower"]
    assert toon["saturation"] >= plain["saturation"]
    # under ACES the brighter toon bands lose saturation in its shoulder: reported, not hidden
    assert set(report["by_tonemap"]) == {"clamp", "aces"}
    assert report["looks"]["toon"]["village_pass_ms"] > 0.0
    json.dumps(report)


def test_the_levels_count_bands_not_edges():
    import numpy as np

    banded = np.repeat([40, 120, 200], 1000)
    ramp = np.linspace(0, 255, 3000).round()
    edges = np.concatenate([banded, np.arange(0, 256, 2)])  # a few stray edge pixels
    assert village_look.levels(banded) == 3
    assert village_look.levels(ramp) > 200  # a gradient needs as many as it spans
    assert village_look.levels(edges) == 3


def test_the_chart_and_the_summary(report, tmp_path):
    out = tmp_path / "look.png"
    village_look.chart(report, out)
    assert out.stat().st_size > 1000
    lines = village_look.summary(report)
    assert any("luma levels" in line for line in lines)

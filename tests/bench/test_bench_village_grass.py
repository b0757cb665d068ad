"""The grass section of ``natura bench village`` (app/bench/village_grass.py), quick: the three
methods at 10k and 30k blades — times, blades per second, the triangles each drew against its
budget — and the crossed billboards' side-view coverage for n = 1…4 planes; the chart and the
summary."""

from __future__ import annotations

import math

import pytest

from app.bench import village_grass as vg
from app.sim import grass as gs
from tests.helpers.readme import village_report

report = village_report("grass")


def test_every_method_at_every_count_with_sane_times(report):
    assert report["quick"] is True and report["counts"] == [10_000, 30_000]
    rows = report["speed"]
    assert {(x["method"], x["blades"]) for x in rows} == {
        (m, n) for m in gs.METHODS for n in report["counts"]}
    for x in rows:
        assert math.isfinite(x["median_ms"]) and x["median_ms"] > 0
        assert x["p25_ms"] <= x["median_ms"] <= x["p75_ms"]
        assert x["blades_per_s"] == pytest.approx(x["blades"] / (x["net_ms"] * 1e-3))
        assert x["rounds"] >= 3


def test_triangles_follow_each_methods_budget(report):
    s = report["settings"]
    # every method is culled per tile (grass.culling, on by default): at most every blade at
    # full detail
    for x in report["speed"]:
        n = x["blades"]
        assert 0 < x["drawn_blades"] <= n
        if x["method"] == "geometry":
            assert x["triangles"] <= n * gs.gs_triangles_per_blade(s["gs_sections"])
        elif x["method"] == "billboard":
            assert x["triangles"] <= gs.units_for(n) * s["bb_planes"] * 2
        else:
            assert x["triangles"] <= n * gs.blade_triangles(s["segments"])


def test_the_thesis_ranking_the_pyramids_draw_most(report):
    """The thesis: the geometry-shader grass is "muy costoso", the billboards "bastante
    ligero" — in work drawn, at 30k blades the pyramids make the most triangles of the three.
    (Which is fastest is the bench's figure, in its chart and summary: a test never judges
    times, which follow the machine's load.)"""
    rows = {x["method"]: x for x in report["speed"] if x["blades"] == 30_000}
    assert rows["geometry"]["triangles"] > rows["instanced"]["triangles"]
    assert rows["geometry"]["triangles"] > 5 * rows["billboard"]["triangles"]


def test_coverage_rises_to_three_planes_and_levels_off(report):
    c = report["coverage"]["layouts"]["document"]
    r = c["rendered"]
    assert r[0] > 0.02 and r[2] > r[0] and r[1] >= r[0] * 0.99
    assert abs(c["change_3_to_4"]) < 0.10
    assert c["angles"]["3"] == [0.0, 60.0, 120.0]
    assert report["coverage"]["layouts"]["repository"]["angles"]["3"] == [-60.0, 0.0, 60.0]


def test_chart_and_summary(report, tmp_path):
    path = tmp_path / "grass.png"
    vg.chart(report, path)
    assert path.stat().st_size > 20_000
    lines = vg.summary(report)
    assert len(lines) == 4
    assert "30,000 blades" in lines[1] and "M blades/s" in lines[1]
    assert "n = 3 → 4" in lines[2]


def test_the_readme_example_runs_the_quick_sections():
    """These tests read the README's own `natura bench village` run: it is in the README as
    written, and its --repeat asks for the quick sections (QUICK_COUNTS, the quick size)."""
    import shlex

    from app.bench.village import QUICK_REPEAT
    from tests.helpers.readme import VILLAGE_EXAMPLE, command_lines

    assert VILLAGE_EXAMPLE in command_lines()
    words = shlex.split(VILLAGE_EXAMPLE)
    assert int(words[words.index("--repeat") + 1]) <= QUICK_REPEAT
    assert set(vg.QUICK_COUNTS) <= set(vg.COUNTS)

"""The village bench's fog section (app/bench/village_fog.py) run once, quick: the per-vertex
factor's error grows with the triangles (below one 8-bit level at 1 m cells, tens of levels
when the whole ground is two triangles), the per-pixel factor equals its twin, the analytic
height fog equals the numeric integral of its density on the GPU and in numpy, every time is
finite, and the chart and the summary are written."""

from __future__ import annotations

import math

import pytest

from app.bench import village_fog as vf
from tests.helpers.readme import village_section


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    """The section as the README's `natura bench village` example wrote it (run once per test
    run, tests/helpers/readme.py): what a user's JSON holds."""
    return village_section(tmp_path_factory, "fog")


def rows(report, mode):
    return {r["cell_m"]: r for r in report["rows"] if r["mode"] == mode}


def test_per_vertex_error_grows_with_the_cells(report):
    assert report["quick"] is True and report["cells_m"] == list(vf.QUICK["cells"])
    for mode in vf.MODES:
        r = rows(report, mode)
        small, large = min(r), max(r)
        assert r[small]["max_levels"] < 1.0, (mode, r[small])
        assert r[large]["max_levels"] > 50.0, (mode, r[large])
        means = [r[c]["mean_levels"] for c in sorted(r)]
        assert means[0] < means[1] < means[2], (mode, means)
        assert all(0.2 < x["coverage"] < 0.9 for x in r.values())  # ground and sky in view
    # the exponentials are the thesis's concern: at 8 m cells exp2 is already off by a level
    assert rows(report, "exp2")[8.0]["max_levels"] > 0.5
    assert report["per_pixel_vs_twin_max"] < 1e-4


def test_height_fog_against_the_numeric_integral(report):
    h = report["height"]
    assert h["pixels"] > 1000
    assert h["gpu_vs_reference_max"] < 1e-4
    assert h["twin_vs_reference_max"] < 1e-5
    assert h["a"] == pytest.approx(0.15 * 0.324) and h["b"] == pytest.approx(0.35)


def test_times_are_interleaved_medians(report):
    t = report["times"]
    assert report["rounds"] >= 3
    for c in report["cells_m"]:
        for path in ("vertex", "pixel"):
            e = t[f"{path} {c:g}"]
            assert math.isfinite(e["median_ms"]) and e["median_ms"] > 0 and e["n"] >= 3
    assert t["pixel 1"]["ratio_to_vertex 1"]["n"] >= 3
    assert report["height"]["ms"] > 0


def test_chart_and_summary(report, tmp_path):
    path = tmp_path / "fog.png"
    vf.chart(report, path)
    assert path.stat().st_size > 20000
    lines = vf.summary(report)
    assert len(lines) == 5 and lines[0].startswith("linear:") and "height fog" in lines[-1]

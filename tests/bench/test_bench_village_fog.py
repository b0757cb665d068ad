"""The village bench's fog section (app/bench/village_fog.py) run once, quick: the per-vertex
factor's error grows with the triangles (below one 8-bit level at 1 m cells, tens of levels
when the whole ground is two triangles), the per-pixel factor equals its twin, the analytic
height fog equals the numeric integral of its density on the GPU and in numpy, every time is
finite, and the chart and the summary are written."""

from __future__ import annotations

import math

import pytest

from app.bench import village_fog as vf
from tests.helpers.readme import village_report

report = village_report("fog")


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


def test_the_numpy_twin_is_the_integral_on_random_rays():
    """What the section's twin figure measures, without a GL context: the analytic height
    transmittance (Quílez 2010) against the midpoint integral of the density on random rays,
    grazing and steep, at the scene's fog (a, b from the section's defaults)."""
    import numpy as np

    from app.sim import fog as fs

    rng = np.random.default_rng(5)
    start = np.stack([rng.uniform(-60, 60, 64), rng.uniform(0.0, 40.0, 64),
                      rng.uniform(-60, 60, 64)], -1)
    dirs = rng.normal(size=(64, 3))
    dirs[:8, 1] = 1e-4  # grazing: the analytic form's 0/0 limit
    dirs /= np.linalg.norm(dirs, axis=-1, keepdims=True)
    end = start + dirs * rng.uniform(0.0, 500.0, (64, 1))
    a, b = 0.15 * 0.324, 0.35
    twin = fs.fog_height_transmittance(end, start, a, b, 0.0)
    assert np.abs(twin - fs.fog_height_reference(end, start, a, b, 0.0, steps=8192)).max() < 1e-5

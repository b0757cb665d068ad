"""`natura bench materials`: the materials speed/accuracy sweep and its chart."""

from __future__ import annotations

import json

import pytest

from app.bench import materials as mbench
from app.runtime import open_session, scene_params
from tests.helpers.readme import bench_lane, command_lines


def test_materials_sweep_orders_methods_sensibly(gl_ctx, tmp_path):
    session = open_session("materials", scene_params("materials"), ctx=gl_ctx)
    try:
        sweep = mbench.sweep(session, (96, 54), warmup=1, repeat=3, bake_sizes=(8, 32))
    finally:
        session.release()
    oc = sweep["octave_cost"]
    for kind in ("value", "gradient"):  # timings are reported, not asserted (they vary with load)
        assert len(oc[kind]["ms_by_depth"]) == 8 and min(oc[kind]["ms_by_depth"]) > 0
    rows = sweep["baked_vs_per_pixel"]["rows"]
    assert rows[0]["method"] == "per-pixel" and rows[0]["noise_mean"] == 0.0
    baked = {r["size"]: r for r in rows[1:]}
    # a finer bake is closer to per-pixel noise
    assert baked[32]["noise_mean"] < baked[8]["noise_mean"]
    assert baked[32]["noise_p99"] < baked[8]["noise_p99"]
    rings = sweep["ring_edges"]
    assert rings["filtered"]["mean_error"] < 0.5 * rings["hard"]["mean_error"]
    small, large = sweep["tessellation"]["rows"]  # 320×180 and 1280×720, auto against fixed
    assert small["triangles_auto"] < 0.25 * small["triangles_fixed"]
    assert small["triangles_auto"] < large["triangles_auto"] <= large["triangles_fixed"]
    assert small["ratio"]["n"] >= 9 and 0.0 <= small["changed_share"] <= 0.015
    report = {"renderer": "test", "sweep": sweep}
    chart = tmp_path / "chart.png"
    mbench.chart(report, chart)
    assert chart.stat().st_size > 10000
    assert "ms per octave" in mbench.summary(report)
    assert "tessellation auto" in mbench.summary(report)


#: the README's example (tests/helpers/readme.py runs it once per test run, for the walk-through
#: and for this test)
EXAMPLE = "natura bench materials --size 160x90 --repeat 3"


@pytest.mark.slow  # runs (or waits for) the README example: the whole bench
def test_cli_bench_writes_json_and_chart(tmp_path_factory):
    folder, ran = bench_lane(tmp_path_factory, EXAMPLE)
    (name,) = [n for n in ran.written if n.endswith(".json")]
    out = folder / name
    report = json.loads(out.read_text())
    assert {"materials", "frame", "reference.fullscreen",
            "reference.clear"} <= set(report["passes"])
    assert all(t["median_ms"] > 0 for t in report["passes"].values())
    assert len(report["sweep"]["baked_vs_per_pixel"]["rows"]) == 1 + len(mbench.BAKE_SIZES)
    assert out.with_suffix(".png").stat().st_size > 10000


def test_the_example_is_the_readmes_own():
    """The command these tests read the output of is an example the README shows, as written:
    a README edit that changes it must change this module too."""
    assert EXAMPLE in command_lines()

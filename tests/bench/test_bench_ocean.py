"""`natura bench ocean`: the three speed/accuracy sweeps at tiny settings (issue 6, item 6).

Timings are reported, never asserted (they vary with load); the accuracy figures are."""

from __future__ import annotations

import json

import pytest

from app.bench import ocean as obench
from app.errors import UsageError
from app.runtime import open_session, scene_params
from tests.helpers.readme import bench_lane, command_lines

SIZE = (64, 36)


@pytest.fixture(scope="module")
def tiny_report(gl_ctx):
    session = open_session("ocean", scene_params("ocean"), ctx=gl_ctx)
    try:
        sweep = obench.sweep(session, SIZE, warmup=0, repeat=1, fft_sizes=(64,), cascades=(1, 2),
                             gerstner_counts=(8,), fft_compare=(64, 2), direct_sizes=(16,),
                             direct_extra=None)
        restored = session.params["ocean.model"], session.params["ocean.cascades"]
    finally:
        session.release()
    return {"renderer": "test", "sweep": sweep, "restored": restored}


def test_json_structure(tiny_report):
    s = tiny_report["sweep"]
    assert tiny_report["restored"] == ("fft", 3)  # the session's parameters are put back
    assert {"renderer", "view_size", "wind", "spectrum", "patch_sizes", "reference", "shading",
            "fft", "gerstner", "direct_sum"} <= set(s)
    assert s["view_size"] == list(SIZE) and s["spectrum"] == "jonswap"
    json.dumps(s)  # everything serialises
    rows = s["fft"]["rows"]
    assert [(r["fft_size"], r["cascades"]) for r in rows] == [(64, 1), (64, 2)]
    for r in rows:
        assert r["ms_frame"] > 0 and r["ms_sim"] > 0
        assert {"mss_deficit", "hs_error", "mss_deficit_expected", "hs_error_expected",
                "bands"} <= set(r)
    g = s["gerstner"]["rows"]
    assert [r["model"] for r in g] == ["gerstner", "fft"] and g[0]["waves"] == 8
    assert all(r["ms_frame"] > 0 and r["tp_s"] > 0 for r in g)
    d = s["direct_sum"]["rows"]
    assert [r["fft_size"] for r in d] == [16] and d[0]["ms_fft"] > 0 and d[0]["ms_direct"] > 0
    assert d[0]["speedup"] == pytest.approx(d[0]["ms_direct"] / d[0]["ms_fft"])


def test_the_view_simulation_is_timed_against_the_full_one(tiny_report):
    """Issue 37: ``ocean.simulation`` view against full (the thesis), timed in the same rounds,
    with the view's sea measured against the full one at random points; the measured rms
    slope error stays near the prediction for the worst instant (the blend's shortfall at
    mid-interval plus the dropped modes)."""
    c = tiny_report["sweep"]["simulation"]
    assert c["view_size"] == list(SIZE) and c["rounds"] >= 3
    assert len(c["grids"]) == len(c["periods_s"]) == 3
    assert all(16 <= n <= c["fft_size"] for n in c["grids"])
    for mode in ("full", "view"):
        assert 0 < c[mode]["p25_ms"] <= c[mode]["median_ms"] <= c[mode]["p75_ms"]
    assert c["ratio"]["n"] == c["rounds"]
    assert 0 < c["rms_slope_error"] <= 1.25 * c["predicted_rms_slope_error"] + 1e-3
    assert 0 < c["rms_height_error"] <= 1.25 * c["predicted_rms_height_error"] + 1e-3
    assert c["max_height_error"] < 0.1
    assert "Simulation, what the view resolves" in obench.summary(tiny_report)


def test_the_simulation_comparison_measures_nothing_when_nothing_is_cut(gl_ctx):
    """Every grid at ocean.fft_size (a fine view texel) and no slow cascade: the two seas are
    the same computation, and the measured error is zero."""
    sets = ["ocean.fft_size=64", "ocean.view_texel=0.25", "ocean.refresh_tolerance=0"]
    session = open_session("ocean", scene_params("ocean", sets=sets), ctx=gl_ctx)
    try:
        c = obench.simulation_comparison(session, SIZE, warmup=0, rounds=1, frames=2)
    finally:
        session.release()
    assert c["grids"] == [64, 64, 64] and c["periods_s"] == [0.0, 0.0, 0.0]
    assert c["rms_height_error"] == 0.0 and c["rms_slope_error"] == 0.0
    assert c["predicted_rms_slope_error"] == 0.0


def test_forward_and_deferred_are_timed_together_and_draw_the_same_sea(tiny_report):
    c = tiny_report["sweep"]["shading"]
    assert c["view_size"] == list(SIZE) and c["rounds"] >= 3
    for mode in obench.SHADINGS:
        assert 0 < c[mode]["p25_ms"] <= c[mode]["median_ms"] <= c[mode]["p75_ms"]
    r = c["ratio"]
    assert r["n"] == c["rounds"] and 0 < r["p25"] <= r["median"] <= r["p75"]
    assert c["mean_abs_diff"] <= 1e-3 and c["max_abs_diff"] <= 0.3 * max(c["max_radiance"], 1.0)
    text = "\n".join(obench.shading_summary(c))
    assert "deferred/forward ×" in text and "mean |Δ|" in text


def test_cascades_reduce_the_slope_deficit(tiny_report):
    rows = {r["cascades"]: r for r in tiny_report["sweep"]["fft"]["rows"]}
    assert 0 < rows[2]["mss_deficit"] < rows[1]["mss_deficit"] < 1
    assert rows[2]["mss_deficit_expected"] < rows[1]["mss_deficit_expected"]


def test_gerstner_has_the_spectrum_hs(tiny_report):
    g = tiny_report["sweep"]["gerstner"]["rows"][0]
    assert g["hs_error"] < 0.01
    assert g["hs"] == pytest.approx(tiny_report["sweep"]["reference"]["hs"], rel=0.01)


def test_direct_sum_matches_fft(tiny_report):
    r = tiny_report["sweep"]["direct_sum"]["rows"][0]
    assert r["modes"] > 0 and r["max_abs_eta"] > 0
    assert r["rel_diff"] < 1e-3


def test_refused_cascades_are_skipped(gl_ctx):
    session = open_session("ocean", scene_params("ocean"), ctx=gl_ctx)
    try:
        # N = 64 cannot reach 1 m from 250 m
        session.params.set("ocean.patch_sizes", (250.0, 1.0, 0.5, 0.2))
        out = obench.fft_sweep(session, SIZE, fft_sizes=(64,), cascades=(2,), warmup=0, repeat=1)
    finally:
        session.release()
    (row,) = out["rows"]
    assert "cannot hold the band" in row["skipped"] and "ms_frame" not in row


def test_sizes_option_names_fft_sizes():
    assert obench._fft_sizes_from([(128, 128), (64, 64), (640, 360)]) == (64, 128)
    with pytest.raises(UsageError, match="NxN pairs"):
        obench._fft_sizes_from([(640, 360)])


def test_chart_and_summary(tiny_report, tmp_path):
    path = tmp_path / "o.png"
    obench.chart(tiny_report, path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 10000
    text = obench.summary(tiny_report)
    for title in obench.TITLES.values():
        assert title in text


#: the README's example (tests/helpers/readme.py runs it once per test run, for the walk-through
#: and for this test): the sweep at 96×54, its FFT sizes narrowed to 64 by --sizes
EXAMPLE = "natura bench ocean --sizes 64x64 --size 96x54 --repeat 2"


@pytest.mark.slow  # runs (or waits for) the README example: the whole bench
def test_cli_bench_ocean(tmp_path_factory):
    folder, ran = bench_lane(tmp_path_factory, EXAMPLE)
    (name,) = [n for n in ran.written if n.endswith(".json")]
    out = folder / name
    report = json.loads(out.read_text())
    assert {"ocean.surface", "frame"} <= set(report["passes"])
    s = report["sweep"]
    assert s["fft"]["fft_sizes"] == [64]
    assert len(s["fft"]["rows"]) == len(obench.CASCADES)
    assert {"forward", "deferred", "ratio", "mean_abs_diff"} <= set(s["shading"])
    assert obench.TITLES["shading"] in ran.stdout
    assert [r["waves"] for r in s["gerstner"]["rows"][:-1]] == list(obench.GERSTNER_COUNTS)
    assert [r["fft_size"] for r in s["direct_sum"]["rows"]][:3] == list(obench.DIRECT_SIZES)
    assert out.with_suffix(".png").stat().st_size > 10000


def test_fft_fills_the_directional_spectrum_better_than_few_gerstner_waves(tiny_report):
    g, f = tiny_report["sweep"]["gerstner"]["rows"]
    assert 0.0 <= f["shape_distance"] < 0.3 < g["shape_distance"] <= 1.0
    assert "oceanography" in tiny_report["sweep"]
    assert "Cox–Munk" in obench.summary(tiny_report)


def test_the_example_is_the_readmes_own():
    """The command these tests read the output of is an example the README shows, as written:
    a README edit that changes it must change this module too."""
    assert EXAMPLE in command_lines()

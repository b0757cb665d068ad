"""The village's VR bench section (app/bench/village_vr.py), quick: a mono frame against the
stereo pair at render scales 0.5, 0.75 and 1 on the village scene, interleaved — the figures
are finite and consistent (the ratio is stereo over mono of the same rounds, the eyes' pixels
are S² of the frame's, a smaller eye texture costs no more than the full one), the summary
names every variant and the chart is a PNG: the section as the README's `natura bench village`
example wrote it (run once per test run, tests/helpers/readme.py). The caller's scene is left
intact: a run of the section, on a tiny frame, between two renders of a village session."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from PIL import Image

from app.bench import village_vr
from app.runtime import open_session, render_frames, scene_params
from tests.helpers.readme import village_report

#: the section's run between the caller's two renders: what it does to the caller's scene does
#: not depend on the size, the scales or the rounds (two scales: the eye targets are remade)
TINY = {"size": (32, 18), "scales": (0.5, 1.0), "rounds": 1, "budget_s": 0.0, "min_rounds": 1}


report = village_report("vr")


def test_the_figures_are_finite_and_consistent(report):
    json.dumps(report)  # JSON-serialisable
    assert report["scene"] == "village" and report["size"] == [160, 90] and report["quick"]
    assert report["rounds"] >= 3
    mono = report["mono"]["median_ms"]
    assert math.isfinite(mono) and mono > 0
    rows = report["stereo"]
    assert [r["scale"] for r in rows] == [0.5, 0.75, 1.0]
    for r in rows:
        assert 0 < r["p25_ms"] <= r["median_ms"] <= r["p75_ms"]
        assert r["pixels_ratio"] == pytest.approx(r["scale"] ** 2, rel=0.05)
        assert r["eye_size"] == [round(80 * r["scale"]), round(90 * r["scale"])]
        q = r["ratio_to_mono"]
        assert q["p25"] <= q["median"] <= q["p75"] and q["n"] == report["rounds"]
        # the per-round ratio's median lies between the ratios of the two medians' quartiles
        assert r["p25_ms"] / report["mono"]["p75_ms"] * 0.5 < q["median"]
        assert q["median"] < r["p75_ms"] / report["mono"]["p25_ms"] * 2.0
    # both eyes render every stage: the pair at scale 1 is not cheaper than one mono frame
    assert rows[-1]["ratio_to_mono"]["median"] > 0.9
    maps = report["shadow_maps_per_frame"]
    assert sorted(maps) == ["mono", "stereo_0.5", "stereo_0.75", "stereo_1"]
    if maps["mono"] is not None:  # one per eye in the pair, at most one in mono
        assert 0 <= maps["mono"] <= 1 and all(maps[k] <= 2 for k in maps)


@pytest.mark.slow  # a village session and the section's own village scene: a few seconds
def test_the_callers_scene_is_left_intact(gl_ctx):
    session = open_session("village", scene_params("village"), ctx=gl_ctx)
    try:
        before = next(render_frames(session, (32, 18)))
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(village_vr, "QUICK", TINY)
            tiny = village_vr.run(session.gpu, quick=True)
        after = next(render_frames(session, (32, 18)))
    finally:
        session.release()
    assert tiny["size"] == [32, 18] and [r["scale"] for r in tiny["stereo"]] == [0.5, 1.0]
    assert np.isfinite(after).all()
    assert np.abs(after - before).max() < 1e-4


def test_summary_and_chart(report, tmp_path):
    lines = village_vr.summary(report)
    assert len(lines) in (4, 5) and "mono" in lines[0]
    assert all(f"scale {s:g}" in " ".join(lines) for s in (0.5, 0.75, 1.0))
    path = tmp_path / "vr.png"
    village_vr.chart(report, path)
    with Image.open(path) as im:
        assert im.format == "PNG" and im.size[0] > 300
    with pytest.raises(Exception, match="refusing to overwrite"):
        village_vr.chart(report, path)
    village_vr.chart(report, path, force=True)

"""`tools/gpu_report.sh --small`, as CI and a maintainer run it before a GPU is lent: the driver
report, every scene's frame with per-pass timings, the budget check and the theses' tables, in
one Markdown page and one JSON file; and the paths it names are the context's (a software
renderer: fragment FFT, deferred ocean). How long it takes is not asserted: it depends on the
machine's load."""

from __future__ import annotations

import json
import os
import subprocess

from app import PROJECT_ROOT
from app.scenes import SCENES

SCRIPT = PROJECT_ROOT / "tools" / "gpu_report.sh"


def test_the_small_report_runs_and_says_which_paths_ran(tmp_path):
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    r = subprocess.run(["sh", str(SCRIPT), "--small", "--out", str(tmp_path / "rep")], env=env,
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    assert r.stdout.startswith("natura doctor — ")  # the driver report comes first
    report = json.loads((tmp_path / "rep" / "gpu-report.json").read_text())
    page = (tmp_path / "rep" / "gpu-report.md").read_text()
    assert set(report["scenes"]) == set(SCENES)
    for scene, f in report["scenes"].items():
        assert f["median_ms"] > 0 and f["p25_ms"] <= f["median_ms"] <= f["p75_ms"], scene
        assert f["passes"], scene
        assert f"| {scene} |" in page
    assert report["software_renderer"] and not report["gpu_timers"]
    paths = {what: ways[0][0] for what, ways in report["paths"].items()}
    assert paths["ocean FFT"].startswith("fragment passes")
    assert paths["ocean surface"].startswith("deferred")
    assert set(report["budget"]) == {"maritime", "village"}
    tables = report["tables"]
    assert {r["method"] for r in tables["planet"]["rows"]} == {"brute_force", "lut", "shadowed",
                                                                "hillaire"}
    assert {r["preset"] for r in tables["clouds"]["rows"]} == {"cumulus", "stratocumulus",
                                                                "stratus"}
    assert {r["method"] for r in tables["grass"]} == {"geometry", "billboard", "instanced"}
    assert all(r.get("ms_frame", 0) > 0 for r in tables["ocean_fft"]["rows"])
    for heading in ("## Frames", "## The 16.7 ms budget", "Table 6.1", "## Grass methods",
                    "## FFT ocean"):
        assert heading in page


def test_a_bad_option_is_one_line(tmp_path):
    r = subprocess.run(["sh", str(SCRIPT), "--big"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "'--big'" in r.stderr

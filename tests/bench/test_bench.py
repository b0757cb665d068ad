"""`natura bench <scene>`: per-pass timings written as JSON, never overwritten without --force."""

from __future__ import annotations

import json

import pytest

from tests.helpers.cli import SIZE, SMALL, run, usage_error

# ---- bench -------------------------------------------------------------------------------------

def test_bench_writes_json(tmp_path):
    r = run("bench", "sky", "--size", SMALL, "--repeat", "3", "--warmup", "1", "--out", "b.json",
            cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    report = json.loads((tmp_path / "b.json").read_text())
    assert report["scene"] == "sky" and report["size"] == list(SIZE) and report["repeat"] == 3
    passes = report["passes"]
    for name in ("sky", "reference.fullscreen"):
        assert passes[name]["median_ms"] > 0
        assert passes[name]["n"] == 3
    assert passes["reference.fullscreen"]["ratio_to_fullscreen"] == pytest.approx(1.0)
    assert "sky" in r.stdout and "b.json" in r.stdout

    before = (tmp_path / "b.json").read_bytes()
    line = usage_error(run("bench", "sky", "--size", SMALL, "--out", "b.json", cwd=tmp_path))
    assert "b.json" in line and "--force" in line
    assert (tmp_path / "b.json").read_bytes() == before

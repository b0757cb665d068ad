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


def test_bench_prints_quartiles_and_ratio_spread(tmp_path):
    r = run("bench", "sky", "--size", SMALL, "--repeat", "3", "--warmup", "1", "--out", "b.json",
            cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    report = json.loads((tmp_path / "b.json").read_text())
    assert report["timing"]["method"] == "interleaved"
    sky = report["passes"]["sky"]
    line = next(ln for ln in r.stdout.splitlines() if ln.startswith("sky "))
    assert f"{sky['median_ms']:.3f} [{sky['p25_ms']:.3f}–{sky['p75_ms']:.3f}]" in line
    assert f"×{sky['ratio_to_fullscreen']:.2f} [" in line


def test_bench_budget_on_a_scene_without_sweeps_prints_the_passes_over_it(tmp_path):
    r = run("bench", "sky", "--budget", "1", "--size", SMALL, "--repeat", "3", "--warmup", "1",
            "--out", "b.json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    report = json.loads((tmp_path / "b.json").read_text())
    lines = r.stdout.splitlines()
    head = next(i for i, ln in enumerate(lines) if ln.startswith("budget 1 ms at 64x36"))
    over = [n for n, p in report["passes"].items()
            if not n.startswith("reference.") and p["median_ms"] > 1.0]
    if over:
        assert lines[head + 1].startswith("over budget: ")
        for name in over:
            assert name in lines[head + 1]
    else:
        assert lines[head + 1] == "no pass is over 1 ms"
    assert not any("--set" in ln for ln in lines)  # sky has no sweeps


@pytest.mark.parametrize("value", ["0", "-1", "nan", "inf", "1e400", "100001", "x", ""])
def test_bench_budget_bad_values_are_one_line_before_any_work(tmp_path, value):
    line = usage_error(run("bench", "sky", "--budget", value, "--size", SMALL, "--out", "b.json",
                           cwd=tmp_path))
    assert "--budget" in line and "allowed a number of ms in (0, 100000]" in line
    assert not (tmp_path / "b.json").exists()


def test_bench_budget_with_no_sweep_says_the_view_needs_the_sweeps(tmp_path):
    r = run("bench", "materials", "--budget", "5", "--no-sweep", "--size", SMALL, "--repeat", "1",
            "--warmup", "0", "--out", "b.json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    said = [ln for ln in r.stdout.splitlines() if "--no-sweep" in ln]
    assert len(said) == 1 and "sweeps" in said[0]

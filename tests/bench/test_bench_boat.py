"""`natura bench boat`: the boat physics (app/bench/boat.py) and the speed polar
(app/bench/polar.py) in one JSON report with two charts, run by the real console script, numpy
only — a GL context created in that process would fail it — and refusing what a scene bench
takes but it does not."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import pytest

from app.bench import NUMPY_BENCHES
from app.cli import NUMPY_BENCH_NAMES
from app.scenes import SCENES
from tests.helpers.cli import run, usage_error
from tests.helpers.readme import bench_lane, command_lines, lane_fixture

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


#: the README's example (tests/helpers/readme.py runs it once per test run, as the walk-through
#: does, with GL context creation made to raise: the numpy bench must not need one)
EXAMPLE = "natura bench boat --quick"


@pytest.fixture(scope="module")
@lane_fixture
def quick(tmp_path_factory):
    """The README's ``natura bench boat --quick``: (folder, its report's name, its stdout)."""
    folder, ran = bench_lane(tmp_path_factory, EXAMPLE)
    (report,) = [name for name in ran.written if name.endswith(".json")]
    assert "Traceback" not in ran.stdout
    return folder, Path(report), ran.stdout


def _numbers(value, where="report"):
    """Every number in a JSON value, with where it is."""
    if isinstance(value, bool):
        return
    if isinstance(value, (int, float)):
        yield where, value
    elif isinstance(value, dict):
        for k, v in value.items():
            yield from _numbers(v, f"{where}.{k}")
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _numbers(v, f"{where}[{i}]")


def test_the_report_has_both_sections_with_finite_figures(quick):
    folder, name, _ = quick
    report = json.loads((folder / name).read_text())
    assert report["bench"] == "boat" and report["quick"] is True
    assert set(report["seconds"]) == {"physics", "polar"}
    bad = [(where, v) for where, v in _numbers(report) if not math.isfinite(v)]
    assert not bad, bad[:5]
    physics, polar = report["physics"], report["polar"]
    rows = physics["archimedes"]["rows"]
    assert len(rows) >= 2
    for r in rows:  # the settled draft against Archimedes' exact one
        assert r["hydrostatic"] == pytest.approx(r["exact"], rel=0.01), r
    assert abs(physics["periods"]["heave_error"]) < 0.05, physics["periods"]
    assert physics["periods"]["heave"] == pytest.approx(physics["periods"]["heave_expected"],
                                                        rel=0.05)
    assert physics["sea"]["storm"]["finite"]
    assert len(physics["energy"]["rows"]) >= 3 and len(physics["speed"]["rows"]) >= 6
    assert len(polar["no_go"]) == len(polar["wind_speeds"]) == 3
    for vt, no_go in zip(polar["wind_speeds"], polar["no_go"]):
        assert 30.0 < no_go < 55.0, (vt, no_go)
    assert report["charts"] == {"physics": f"{name.stem}.png", "polar": f"{name.stem}-polar.png"}


def test_both_charts_are_written_and_both_summaries_printed(quick):
    folder, name, stdout = quick
    charts = [name.with_name(f"{name.stem}{suffix}") for suffix in (".png", "-polar.png")]
    for chart in charts:
        data = (folder / chart).read_bytes()
        assert data.startswith(PNG_MAGIC) and len(data) > 10_000, chart
    assert "draft exact" in stdout and "heave period" in stdout
    assert "no-go" in stdout and "VMG up" in stdout
    for chart in charts:
        assert f"chart → {chart.as_posix()}" in stdout, stdout[-400:]
    assert stdout.rstrip().endswith(f"→ {name.as_posix()}")


def test_a_second_run_without_force_refuses_and_touches_nothing(quick, tmp_path):
    source, name, _ = quick
    folder = tmp_path  # a copy: the example's own folder stays as it wrote it
    names = ("boat.json", "boat.png", "boat-polar.png")
    for suffix, new in zip((".json", ".png", "-polar.png"), names):
        shutil.copy2(source / name.with_name(name.stem + suffix), folder / new)
    before = {n: ((folder / n).read_bytes(), (folder / n).stat().st_mtime_ns) for n in names}
    line = usage_error(run("bench", "boat", "--quick", "--out", "boat.json", cwd=folder))
    assert "boat.json" in line and "--force" in line
    # the report is free, a chart beside it is not: refused too, before any work
    (folder / "other.png").write_bytes(b"kept")
    line = usage_error(run("bench", "boat", "--quick", "--out", "other.json", cwd=folder))
    assert "other.png" in line and "--force" in line
    assert not (folder / "other.json").exists() and (folder / "other.png").read_bytes() == b"kept"
    after = {n: ((folder / n).read_bytes(), (folder / n).stat().st_mtime_ns) for n in names}
    assert after == before
    assert not [p for p in folder.iterdir() if p.name.startswith(".")], "temporary files left"


@pytest.mark.parametrize("option", [["--size", "64x64"], ["--sizes", "64x64"],
                                    ["--budget", "16"], ["--repeat", "3"],
                                    ["--set", "sky.sun_size=0.1"]])
def test_scene_options_with_boat_are_refused_in_one_line(tmp_path, option):
    line = usage_error(run("bench", "boat", *option, "--out", "b.json", cwd=tmp_path))
    assert option[0] in line and "boat" in line and "--quick" in line
    assert list(tmp_path.iterdir()) == []


def test_unknown_names_list_boat_and_quick_is_for_numpy_benches(tmp_path):
    line = usage_error(run("bench", "atlantis", cwd=tmp_path))
    assert "atlantis" in line and "sky" in line and "boat" in line
    line = usage_error(run("bench", "sky", "--quick", cwd=tmp_path))
    assert "--quick" in line and "boat" in line
    assert list(tmp_path.iterdir()) == []
    help_text = run("bench", "--help", cwd=tmp_path)
    assert help_text.returncode == 0 and "boat" in help_text.stdout
    assert "--quick" in help_text.stdout


def test_the_numpy_benches_are_named_alike_and_are_no_scene():
    assert set(NUMPY_BENCH_NAMES) == set(NUMPY_BENCHES) == {"boat"}
    assert not set(NUMPY_BENCHES) & set(SCENES)
    for bench in NUMPY_BENCHES.values():
        suffixes = bench.chart_suffixes()
        assert len(set(suffixes)) == len(suffixes) and all(s.endswith(".png") for s in suffixes)
        for key, *_ in bench.sections:
            module = bench.module(key)
            assert all(callable(getattr(module, f, None)) for f in ("run", "chart", "summary"))


def test_the_example_is_the_readmes_own():
    """The command these tests read the output of is an example the README shows, as written:
    a README edit that changes it must change this module too."""
    assert EXAMPLE in command_lines()

"""The test tiers (tests/helpers/tiers.py): ``pytest -m fast`` covers every module within its
budget, ``slow`` comes from measured durations, and a test that is not marked slow but takes
longer than the guard is listed after the summary without changing the exit code (unless
``--slow-guard`` asks for that) — tried on a small test folder of its own, run by pytest in a
process of its own, as a developer's run would be (with and without pytest-xdist)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from app import PROJECT_ROOT
from tests.helpers import tiers

TESTS = PROJECT_ROOT / "tests"

SAMPLE = """
import time
import pytest

@pytest.fixture(scope="module")
def shared():
    time.sleep(0.2)
    return 1

def test_quick():
    assert True

def test_sleepy():
    time.sleep(0.6)

def test_uses_shared_a(shared):
    assert shared == 1

def test_uses_shared_b(shared):
    assert shared == 1
"""


def _pytest(folder: Path, *args: str, guard: float = 0.4) -> subprocess.CompletedProcess:
    env = dict(os.environ, NATURA_TEST_DURATIONS=str(folder / "durations.json"),
               NATURA_SLOW_GUARD_S=str(guard), PYTHONPATH=str(PROJECT_ROOT))
    env.pop("PYTEST_XDIST_WORKER", None)
    env.pop("PYTEST_ADDOPTS", None)
    return subprocess.run([sys.executable, "-m", "pytest", "-p", "tests.helpers.tiers",
                           "-p", "no:cacheprovider", "-q", "--rootdir", str(folder),
                           "-c", str(folder / "pytest.ini"), *args],
                          cwd=folder, env=env, capture_output=True, text=True, timeout=120)


@pytest.fixture
def sample(tmp_path):
    (tmp_path / "pytest.ini").write_text("[pytest]\nmarkers =\n    slow: slow\n    fast: fast\n")
    (tmp_path / "test_sample.py").write_text(SAMPLE)
    return tmp_path


def _late_lines(stdout: str) -> list[str]:
    return [line for line in stdout.splitlines() if "is not marked slow" in line]


@pytest.mark.parametrize("workers", [[], pytest.param(["-n", "2"], marks=pytest.mark.slow)],
                         ids=["one process", "xdist"])
def test_an_unmarked_slow_test_is_listed_after_the_summary_and_the_run_still_passes(sample,
                                                                                    workers):
    r = _pytest(sample, *workers)
    assert r.returncode == 0, r.stdout + r.stderr
    lines = r.stdout.splitlines()
    summary = max(i for i, line in enumerate(lines) if "4 passed" in line)
    section = max(i for i, line in enumerate(lines) if "slow tests" in line)
    assert section > summary, r.stdout  # after the summary line
    late = _late_lines(r.stdout)
    assert len(late) == 1 and "test_sample.py::test_sleepy took 0.6 s" in late[0], r.stdout
    assert "--record-durations" in late[0]


def test_a_failing_test_keeps_its_exit_code_beside_the_report(sample):
    (sample / "test_sample.py").write_text(SAMPLE + "\ndef test_wrong():\n    assert 1 == 2\n")
    r = _pytest(sample)
    assert r.returncode == 1 and "1 failed, 4 passed" in r.stdout, r.stdout
    assert len(_late_lines(r.stdout)) == 1


def test_the_guard_blocks_only_when_asked_and_passes_what_is_marked_slow(sample):
    r = _pytest(sample, "--slow-guard")
    assert r.returncode == 1, r.stdout
    assert len(_late_lines(r.stdout)) == 1
    text = SAMPLE.replace("def test_sleepy", "@pytest.mark.slow\ndef test_sleepy")
    (sample / "test_sample.py").write_text(text)
    r = _pytest(sample, "--slow-guard")
    assert r.returncode == 0 and not _late_lines(r.stdout), r.stdout


def test_the_ci_script_and_the_default_options_never_ask_for_the_guard():
    import tomllib

    assert "--slow-guard" not in (PROJECT_ROOT / ".ci" / "run").read_text(encoding="utf-8")
    config = tomllib.loads((PROJECT_ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert "--slow-guard" not in config["tool"]["pytest"]["ini_options"]["addopts"]


def test_recorded_durations_mark_slow_and_fast(sample):
    r = _pytest(sample, "--record-durations")
    assert r.returncode == 0, r.stdout
    recorded = json.loads((sample / "durations.json").read_text())["modules"]
    assert list(recorded) == ["test_sample.py"]
    module = recorded["test_sample.py"]  # one number a test, the shared fixture once
    assert set(module["tests"]) == {"test_quick", "test_sleepy"}
    assert module["tests"]["test_sleepy"] >= 0.6
    assert set(module["shared"]) == {"test_uses_shared_a", "test_uses_shared_b"}
    assert module["fixture"] >= 0.2 and max(module["shared"].values()) < 0.2
    costs = tiers.load(sample / "durations.json")
    nodes = list(costs)
    assert len(nodes) == 4
    fast, predicted = tiers.fast_tier(costs, nodes)
    assert fast == {"test_sample.py::test_quick"} and predicted < 0.05
    r = _pytest(sample, "-m", "fast", "--collect-only")
    assert "test_quick" in r.stdout and "test_sleepy" not in r.stdout, r.stdout


def test_a_module_recorded_again_replaces_its_entry_and_keeps_the_others(tmp_path):
    """A renamed or deleted test leaves no stale entry: recording a module replaces all of it;
    the modules this run did not measure keep theirs (saved and loaded, rounded to 1 ms)."""
    path = tmp_path / "durations.json"
    tiers.save({"a.py::old_name": tiers.Cost(0.0, 1.23456, 0.0),
                "b.py::kept": tiers.Cost(0.5, 0.25, 0.0, True)}, "note", path)
    assert tiers.load(path) == {"a.py::old_name": tiers.Cost(0.0, 1.235, 0.0),
                                "b.py::kept": tiers.Cost(0.5, 0.25, 0.0, True)}
    (tmp_path / "pytest.ini").write_text("[pytest]\nmarkers =\n    slow: slow\n    fast: fast\n")
    (tmp_path / "a.py").write_text("def test_new_name():\n    pass\n")
    (tmp_path / "b.py").write_text("def test_kept():\n    pass\n")
    r = _pytest(tmp_path, "a.py", "--record-durations")
    assert r.returncode == 0, r.stdout
    costs = tiers.load(path)
    assert set(costs) == {"a.py::test_new_name", "b.py::kept"}
    assert costs["b.py::kept"] == tiers.Cost(0.5, 0.25, 0.0, True)


def test_slow_marks_what_shares_a_costly_module_fixture():
    costs = {"m.py::a": tiers.Cost(2.0, 0.01, 0.0, True),
             "m.py::b": tiers.Cost(0.0, 0.01, 0.0, True),
             "m.py::c": tiers.Cost(0.0, 0.02, 0.0, False),
             "n.py::d": tiers.Cost(0.1, 1.6, 0.0)}
    assert tiers.slow_tests(costs, list(costs)) == {"m.py::a", "m.py::b", "n.py::d"}
    fast, predicted = tiers.fast_tier(costs, list(costs) + ["n.py::new"])
    # c alone is cheaper than b with the fixture it would pay; d is n's only measured test
    assert fast == {"m.py::c", "n.py::d", "n.py::new"}
    assert predicted == pytest.approx(0.02 + 1.6 + 0.1)


def test_the_recorded_durations_cover_every_test_module():
    costs = tiers.load()
    recorded = {tiers.module_of(node) for node in costs}
    modules = {p.relative_to(PROJECT_ROOT).as_posix() for p in TESTS.rglob("test_*.py")}
    assert modules - recorded == set(), "record the durations again: pytest --record-durations"


def test_the_fast_tier_fits_its_budget():
    costs = tiers.load()
    fast, predicted = tiers.fast_tier(costs, list(costs))
    modules = {tiers.module_of(node) for node in costs}
    assert {tiers.module_of(node) for node in fast} == modules
    assert predicted <= tiers.FAST_BUDGET_S, (
        f"the fast tier would take {predicted:.0f} s of test time: lower tiers.FAST_EACH_S or "
        f"make the costliest module's cheapest test cheaper")


def test_a_fixture_reading_a_readme_lane_makes_its_tests_slow_whatever_they_measured():
    """Whichever test asks first pays a README example's whole run: a recorded 0 s must not make
    the others unmarked (the guard would fail the next run) or fast."""
    from types import SimpleNamespace

    from tests.helpers.readme import lane_fixture

    @lane_fixture
    def lane(tmp_path_factory):
        return None

    def plain():
        return None

    def item(*funcs):
        defs = {f.__name__: [SimpleNamespace(func=f)] for f in funcs}
        return SimpleNamespace(_fixtureinfo=SimpleNamespace(name2fixturedefs=defs))

    assert tiers.reads_readme_lane(item(plain, lane))
    assert not tiers.reads_readme_lane(item(plain))
    assert not tiers.reads_readme_lane(SimpleNamespace())


def test_workers_get_the_costliest_units_first_each_in_its_own_order():
    """Under pytest-xdist the work units (a module sharing a fixture, else a test) are ordered
    by recorded cost, longest first; a unit's tests keep their order, ties and unknown tests
    (UNKNOWN_S each) keep theirs."""

    class Item:
        def __init__(self, nodeid, group=None):
            self.nodeid = nodeid
            self.group = group

        def get_closest_marker(self, name):
            if name != "xdist_group" or self.group is None:
                return None
            return pytest.mark.xdist_group(self.group).mark

    costs = {"a.py::one": tiers.Cost(0.0, 0.3, 0.0), "b.py::x": tiers.Cost(3.0, 0.1, 0.0, True),
             "b.py::y": tiers.Cost(0.0, 0.1, 0.0, True), "c.py::big": tiers.Cost(0.0, 2.0, 0.0),
             "d.py::tie1": tiers.Cost(0.0, 0.3, 0.0)}
    items = [Item("a.py::one"), Item("b.py::x", "module b.py"), Item("c.py::big"),
             Item("b.py::y", "module b.py"), Item("d.py::tie1"), Item("e.py::new")]
    order = [i.nodeid for i in tiers.longest_first(items, costs)]
    assert order == ["b.py::x", "b.py::y", "c.py::big", "e.py::new", "a.py::one", "d.py::tie1"]
    assert tiers.UNKNOWN_S == 0.5

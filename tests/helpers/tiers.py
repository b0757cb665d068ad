"""Test tiers from measured durations (issue 26).

``tests/durations.json`` holds what each test cost in the last recorded run, one rounded number
a test, by module: a module's ``tests`` (setup + call + teardown seconds), its ``shared`` ones
(those sharing a module-scoped fixture: call + teardown) and that fixture's seconds once
(``fixture``: the setup of the test that paid it). ``pytest --record-durations`` writes it
(see tests/conftest.py): each module the run measured replaces its entry, so record whole
modules. From it, at collection:

* ``slow``: a test whose measured setup + call + teardown exceeds ``SLOW_S``. An unmarked test
  (neither ``slow`` by measurement nor by decorator) that takes more than ``GUARD_S`` is listed
  in a "slow tests" section after the summary: a test grew, or a new test is slow — mark it,
  make it cheaper, or record the durations again. The list is a report: a test's duration
  depends on the machine's load, so it never changes the exit code, unless you ask for that in
  your own inner loop with ``--slow-guard`` (never in CI or the README's test command).
* ``fast``: the ``pytest -m fast`` tier — in every test module the cheapest test (what it costs
  when it runs alone: a test that shares a module fixture pays that fixture's setup), then every
  test whose added cost is at most ``FAST_EACH_S``. A test not yet measured is ``fast`` (a new
  test runs in the inner loop until its cost is known). The tier's predicted total is reported
  by ``predicted_fast_seconds``; ``tests/unit/test_tiers.py`` keeps it within the budget.
"""

from __future__ import annotations

import json
import os
import tempfile
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path

import pytest

#: ``$NATURA_TEST_DURATIONS`` points elsewhere (the tiers' own tests)
DURATIONS = Path(os.environ.get("NATURA_TEST_DURATIONS")
                 or Path(__file__).resolve().parents[1] / "durations.json")
#: measured seconds above which a test is marked ``slow``
SLOW_S = 1.5
#: an unmarked test taking longer than this is reported (and fails the run with --slow-guard)
GUARD_S = 5.0
#: ``$NATURA_SLOW_GUARD_S`` sets another guard (the tiers' own tests)


def guard_seconds() -> float:
    return float(os.environ.get("NATURA_SLOW_GUARD_S") or GUARD_S)


#: after a module's cheapest test, further tests join the fast tier when they add at most this
FAST_EACH_S = 0.02
#: the fast tier's budget, CPU seconds summed over tests (two workers: ≈ 60 s wall with start-up)
FAST_BUDGET_S = 80.0


@dataclass(frozen=True)
class Cost:
    setup: float
    call: float
    teardown: float
    shares_module_fixture: bool = False

    @property
    def total(self) -> float:
        return self.setup + self.call + self.teardown


def load(path: Path = DURATIONS) -> dict[str, Cost]:
    """Each test's cost; a test sharing a module fixture carries the fixture as its setup."""
    if not path.is_file():
        return {}
    raw = json.loads(path.read_text(encoding="utf-8"))
    costs = {}
    for module, entry in raw.get("modules", {}).items():
        fixture = entry.get("fixture", 0.0)
        for name, seconds in entry.get("tests", {}).items():
            costs[f"{module}::{name}"] = Cost(0.0, seconds, 0.0)
        for name, seconds in entry.get("shared", {}).items():
            costs[f"{module}::{name}"] = Cost(fixture, seconds, 0.0, True)
    return costs


def save(costs: dict[str, Cost], note: str, path: Path = DURATIONS) -> None:
    """Write by module, one rounded number a test (see the module's note), atomically (a
    temporary file beside it, then a rename; removed on any error)."""
    modules: dict[str, dict] = {}
    for node, c in sorted(costs.items()):
        module, name = node.split("::", 1)
        entry = modules.setdefault(module, {})
        if c.shares_module_fixture:
            entry["fixture"] = round(max(entry.get("fixture", 0.0), c.setup), 3)
            entry.setdefault("shared", {})[name] = round(c.call + c.teardown, 3)
        else:
            entry.setdefault("tests", {})[name] = round(c.total, 3)
    text = json.dumps({"note": note, "modules": modules}, indent=1, ensure_ascii=False) + "\n"
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".durations-", suffix=".json")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def plain_nodeid(node: str) -> str:
    """The test's id without the ``@group`` pytest-xdist's loadgroup appends on its workers
    (``…::test_x@module test_file.py``): the same test has one id in every run."""
    head, sep, group = node.rpartition("@")
    return head if sep and group.startswith("module ") else node


def module_of(node: str) -> str:
    return node.split("::", 1)[0]


def fixture_cost(costs: dict[str, Cost], nodes: list[str]) -> float:
    """What a module's shared (module-scoped) fixtures cost: the setup of the test that paid it
    in the recorded run — the largest setup among the module's tests that share one."""
    return max((costs[n].setup for n in nodes if n in costs and costs[n].shares_module_fixture),
               default=0.0)


def fast_tier(costs: dict[str, Cost], nodes: list[str]) -> tuple[set[str], float]:
    """(the fast tier among ``nodes``, its predicted seconds)."""
    by_module: dict[str, list[str]] = defaultdict(list)
    for node in nodes:
        by_module[module_of(node)].append(node)
    chosen: set[str] = set()
    total = 0.0
    for module_nodes in by_module.values():
        shared = fixture_cost(costs, module_nodes)

        def alone(node: str) -> float:
            c = costs[node]
            return c.call + c.teardown + (max(c.setup, shared) if c.shares_module_fixture
                                          else c.setup)

        known = [n for n in module_nodes if n in costs]
        unknown = [n for n in module_nodes if n not in costs]
        chosen.update(unknown)
        if not known:
            continue
        first = min(known, key=alone)
        chosen.add(first)
        total += alone(first)
        paid = costs[first].shares_module_fixture
        for node in known:
            if node == first:
                continue
            c = costs[node]
            if c.shares_module_fixture:
                extra = c.call + c.teardown + (0.0 if paid else max(c.setup, shared))
            else:
                extra = c.total
            if extra <= FAST_EACH_S:
                chosen.add(node)
                total += extra
                paid = paid or c.shares_module_fixture
    return chosen, total


def slow_tests(costs: dict[str, Cost], nodes: list[str]) -> set[str]:
    """The tests among ``nodes`` measured slower than ``SLOW_S``: alone, or because they share
    a module fixture that costs more than that (whichever of them runs first pays it)."""
    by_module: dict[str, list[str]] = defaultdict(list)
    for node in nodes:
        by_module[module_of(node)].append(node)
    slow = set()
    for module_nodes in by_module.values():
        shared = fixture_cost(costs, module_nodes)
        for node in module_nodes:
            c = costs.get(node)
            if c is not None and (c.total > SLOW_S
                                  or (c.shares_module_fixture and shared > SLOW_S)):
                slow.add(node)
    return slow


def uses_module_fixture(item) -> bool:
    info = getattr(item, "_fixtureinfo", None)
    if info is None:
        return False
    return any(defs and defs[-1].scope == "module" for defs in info.name2fixturedefs.values())


def pytest_collection_modifyitems(config, items):
    costs = load()
    mark(items, costs)
    if hasattr(config, "workerinput"):  # a pytest-xdist worker: the order is the schedule's
        items[:] = longest_first(items, costs)


#: what a test missing from tests/durations.json is taken to cost when scheduling
UNKNOWN_S = 0.5


def longest_first(items, costs: dict[str, Cost]) -> list:
    """``items`` with the work units of ``--dist loadgroup`` (a module sharing a fixture, else
    a single test) in decreasing recorded cost, each unit's tests in their own order. The
    scheduler hands the units out in this order as workers free up, so the long ones (the
    README walk-through, the gallery, the parity run) start first and no worker is left with
    one at the end while the other idles (longest processing time first)."""
    units: dict[str, list] = {}
    for item in items:
        group = item.get_closest_marker("xdist_group")
        key = f"group {group.args[0] if group.args else group.kwargs.get('name')}" \
            if group is not None else item.nodeid
        units.setdefault(key, []).append(item)

    def cost(unit: list) -> float:  # a shared fixture once: the largest setup
        known = [costs[n] for n in (plain_nodeid(i.nodeid) for i in unit) if n in costs]
        return (sum(c.call + c.teardown for c in known) + max((c.setup for c in known),
                                                             default=0.0)
                + UNKNOWN_S * (len(unit) - len(known)))

    ordered = sorted(units.values(), key=cost, reverse=True)  # stable: ties keep their order
    return [item for unit in ordered for item in unit]


def reads_readme_lane(item) -> bool:
    """Whether a fixture of ``item`` runs (or waits for) a README example's lane
    (tests/helpers/readme.py, ``lane_fixture``): whichever test asks first pays the whole
    example, so what one run recorded says nothing about the next."""
    info = getattr(item, "_fixtureinfo", None)
    if info is None:
        return False
    return any(getattr(d.func, "readme_lane", False)
               for defs in info.name2fixturedefs.values() for d in defs)


def mark(items, costs: dict[str, Cost] | None = None) -> None:
    """At collection: ``fast`` and ``slow`` markers from the measured durations, and which tests
    share a module fixture (recorded with their durations). A test marked slow by hand, or
    reading a README lane, is slow whatever it measured, and never fast."""
    costs = load() if costs is None else costs
    nodes = [plain_nodeid(item.nodeid) for item in items]
    always_slow = {node for item, node in zip(items, nodes)
                   if item.get_closest_marker("slow") is not None or reads_readme_lane(item)}
    fast, _ = fast_tier(costs, [n for n in nodes if n not in always_slow])
    slow = slow_tests(costs, nodes) | always_slow
    for item, node in zip(items, nodes):
        if node in fast:
            item.add_marker(pytest.mark.fast)
        if node in slow and item.get_closest_marker("slow") is None:
            item.add_marker(pytest.mark.slow)
        if uses_module_fixture(item):
            item.user_properties.append(("shares_module_fixture", True))


# -- the plugin (tests/conftest.py loads it): recording and the slow-test report --------------

def pytest_addoption(parser):
    parser.addoption("--record-durations", action="store_true",
                     help="write what each test cost into tests/durations.json, which the "
                          "fast and slow tiers come from (each module measured replaces its "
                          "entry: record whole modules)")
    parser.addoption("--slow-guard", action="store_true",
                     help=f"fail the run when a test not marked slow takes more than "
                          f"{guard_seconds():g} s (opt-in, for your own inner loop: a test's "
                          f"duration depends on the machine's load; without it they are only "
                          f"listed after the summary)")


#: what each test of this run cost, on the controller: nodeid -> [setup, call, teardown seconds,
#: shares a module fixture, marked slow]; and the unmarked tests over the guard
_COSTS: dict[str, list] = {}
_LATE: list[tuple[float, str]] = []


def pytest_runtest_logreport(report):
    """On the controller (under xdist the workers' reports arrive here): what each test cost,
    and whether it is marked slow."""
    row = _COSTS.setdefault(plain_nodeid(report.nodeid), [0.0, 0.0, 0.0, False, False])
    row[("setup", "call", "teardown").index(report.when)] = report.duration
    row[3] = row[3] or dict(report.user_properties).get("shares_module_fixture", False)
    row[4] = row[4] or "slow" in report.keywords


def pytest_sessionfinish(session, exitstatus):
    config = session.config
    if os.environ.get("PYTEST_XDIST_WORKER"):
        return
    costs = _COSTS
    if config.getoption("--record-durations") and costs:
        measured = {module_of(node) for node in costs}  # these modules' entries are replaced
        root = Path(str(config.rootpath))
        merged = {n: c for n, c in load().items()
                  if module_of(n) not in measured and (root / module_of(n)).is_file()}
        merged.update({node: Cost(s, c, t, bool(shared))
                       for node, (s, c, t, shared, _) in costs.items()})
        save(merged, "pytest --record-durations (tests/helpers/tiers.py): by module, seconds "
                     "a test (setup + call + teardown; a shared one's without its module "
                     "fixture, whose setup is counted once)")
    late = sorted(((sum(row[:3]), node) for node, row in costs.items()
                   if sum(row[:3]) > guard_seconds() and not row[4]), reverse=True)
    _LATE[:] = late
    if late and config.getoption("--slow-guard") and session.exitstatus == 0:
        session.exitstatus = 1


def pytest_unconfigure(config):
    """The slow tests, in a section of their own after the run's summary line."""
    terminalreporter = config.pluginmanager.get_plugin("terminalreporter")
    if not _LATE or terminalreporter is None:
        return
    blocking = config.getoption("--slow-guard")
    terminalreporter.write_sep("=", "slow tests", red=blocking, yellow=not blocking)
    for seconds, node in _LATE:
        terminalreporter.line(f"{node} took {seconds:.1f} s and is not marked slow "
                              f"(over {guard_seconds():g} s): make it cheaper, mark it "
                              f"@pytest.mark.slow, or record the durations again "
                              f"(pytest --record-durations)")
    if not blocking:
        terminalreporter.line("(a report: durations depend on the machine's load, so they do "
                              "not change the exit code; --slow-guard makes them fail the run)")

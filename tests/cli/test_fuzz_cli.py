"""Fuzzing the command line (issue 11): hundreds of bad invocations over every subcommand, each
of which must end with exit 2 and one stderr line of at most 200 characters, prefixed once with
``natura:``, saying what is allowed — no traceback, no hang, no file written, modified or left
behind. The cases and the checks: tests/cli/fuzz_cases.py.

Seeded: ``NATURA_FUZZ_SEED`` (default :data:`fuzz_cases.DEFAULT_SEED`, printed in every failure).
Bounded: the bad invocations fail at validation, so most run in one interpreter
(tests/cli/fuzz_driver.py, a fresh argv per case through ``app.cli.main``); a sample also runs
as the real ``natura`` console script. ``NATURA_FUZZ_REPORT=FILE`` writes the counts as JSON.
"""

from __future__ import annotations

import json
import os
import random
import resource
import subprocess
import sys
from collections import Counter
from pathlib import Path

import pytest

from app import PROJECT_ROOT
from app.gpu.shaders import SHADER_ENV
from tests.cli import fuzz_cases as fc
from tests.helpers.cli import NATURA

#: cases also run as the console script: ten of the fixed ones, the rest drawn from the seed (every
#: case runs in process; these check what only a real process shows: the exit status, stderr)
SAMPLE = 20
DRIVER_BUDGET = 420.0  # seconds for all in-process cases together


def _env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items()
           if k not in (SHADER_ENV, "DISPLAY", "WAYLAND_DISPLAY")}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(PROJECT_ROOT), env.get("PYTHONPATH")]))
    return env


@pytest.fixture
def fuzz(tmp_path):
    seed = fc.seed_from_env()
    fx = fc.make_fixtures(tmp_path / "fx")
    cases = fc.generate(seed, fx)
    yield seed, fx, cases, tmp_path
    for p in (tmp_path / "fx" / "unreadable.toml", tmp_path / "fx" / "locked"):
        p.chmod(0o700)  # let pytest remove them


def _report(kind: str, seed: int, cases, results) -> str:
    counts: Counter[str] = Counter()
    for r in results:
        counts.update(set(r["problems"]))
    figures = {"seed": seed, "tried": len(results), "generated": len(cases),
               "failing": sum(1 for r in results if r["problems"]), **counts}
    path = os.environ.get("NATURA_FUZZ_REPORT")
    if path:
        with open(f"{path}.{kind}.json", "w", encoding="utf-8") as f:
            json.dump({"figures": figures, "failures": [
                {"argv": fc.shorten(cases[r["i"]]), **r} for r in results if r["problems"]]},
                f, indent=1, ensure_ascii=False)
    lines = [f"{kind}: NATURA_FUZZ_SEED={seed}: {json.dumps(figures)}"]
    for r in [r for r in results if r["problems"]][:25]:
        lines.append(f"  {fc.shorten(cases[r['i']])}\n    → rc={r['rc']} {r['problems']}: "
                     f"{r['stderr'][:300]!r}")
    return "\n".join(lines)


def test_bad_invocations_in_process(fuzz):
    seed, fx, cases, tmp = fuzz
    assert len(cases) >= 300, len(cases)
    specs = []
    for i, argv in enumerate(cases):
        cwd = tmp / "w" / str(i)
        fc.make_workdir(cwd)
        specs.append({"argv": argv, "cwd": str(cwd)})
    spec_file, out = tmp / "cases.json", tmp / "results.jsonl"
    results: dict[int, dict] = {}
    start = 0
    while start < len(cases):
        spec_file.write_text(json.dumps({"fixtures": fx["root"], "cases": specs,
                                         "start": start}))
        try:
            subprocess.run([sys.executable, "-m", "tests.cli.fuzz_driver", str(spec_file),
                            str(out)], env=_env(), cwd=tmp, capture_output=True,
                           timeout=DRIVER_BUDGET)
        except subprocess.TimeoutExpired:
            pass
        started = None
        for line in out.read_text().splitlines():
            r = json.loads(line)
            if r.get("started"):
                started = r["i"]
            else:
                results[r["i"]] = r
        if started is not None and started not in results:  # the driver died in this case
            results[started] = {"i": started, "rc": None if started == len(cases) else -1,
                                "problems": ["crash"], "stderr": "the interpreter died",
                                "stdout": ""}
        nxt = max(results, default=-1) + 1
        if nxt <= start:  # no progress at all: report what is missing
            break
        start = nxt
    missing = [i for i in range(len(cases)) if i not in results]
    assert not missing, f"seed {seed}: {len(missing)} cases never ran, from {missing[:5]}"
    ordered = [results[i] for i in range(len(cases))]
    message = _report("in-process", seed, cases, ordered)
    print(message.splitlines()[0])
    assert not any(r["problems"] for r in ordered), message


def _limit_memory():
    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))


def test_bad_invocations_as_the_console_script(fuzz):
    seed, fx, cases, tmp = fuzz
    rng = random.Random(seed + 1)
    fixed = len(fc._fixed_cases(fx))
    picks = sorted(rng.sample(range(len(cases)), SAMPLE - 10)
                   + list(range(0, fixed, max(1, fixed // 10)))[:10])
    assert len(set(picks)) >= SAMPLE - 3
    results = []
    for i in sorted(set(picks)):
        cwd = tmp / "s" / str(i)
        fc.make_workdir(cwd)
        before = {**{f"fx/{k}": v for k, v in fc.snapshot(Path(fx["root"])).items()},
                  **fc.snapshot(cwd)}
        try:
            r = subprocess.run([*NATURA, *cases[i]], cwd=cwd, env=_env(), capture_output=True,
                               text=True, errors="replace", timeout=fc.CASE_TIMEOUT,
                               preexec_fn=_limit_memory)
            rc, stdout, stderr = r.returncode, r.stdout, r.stderr
        except subprocess.TimeoutExpired:
            rc, stdout, stderr = None, "", ""
        after = {**{f"fx/{k}": v for k, v in fc.snapshot(Path(fx["root"])).items()},
                 **fc.snapshot(cwd)}
        results.append({"i": i, "rc": rc, "stderr": stderr[:400], "stdout": stdout[:200],
                        "problems": fc.judge(rc, stdout, stderr, before, after)})
    message = _report("console-script", seed, cases, results)
    print(message.splitlines()[0])
    assert not any(r["problems"] for r in results), message


def test_the_cases_are_reproducible_and_reach_every_subcommand(tmp_path):
    """The fuzzing's premise, without running a case: one seed gives the same cases, another
    seed others, and every subcommand of the parser gets bad invocations."""
    import argparse

    from app.cli import build_parser

    fx = fc.make_fixtures(tmp_path / "fx")
    try:
        seed = fc.seed_from_env()
        first, again = fc.generate(seed, fx), fc.generate(seed, fx)
        assert first == again and fc.generate(seed + 1, fx) != first
        (sub,) = [a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)]
        reached = {case[0] for case in first if case}
        assert set(sub.choices) <= reached, set(sub.choices) - reached
    finally:
        for p in (tmp_path / "fx" / "unreadable.toml", tmp_path / "fx" / "locked"):
            if p.exists():
                p.chmod(0o700)

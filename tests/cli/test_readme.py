"""The README and docs/commands.md as a new user follows them: every command-line example runs
as written — the benches each in a folder of their own, the rest in order in one folder, as many
folders at a time as there are cores — no two examples write the same file, and every Python
snippet runs both as a script and pasted line by line into the interactive interpreter.
tests/cli/test_readme_page.py checks the README itself: short, its links, pictures and facts."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from app import PROJECT_ROOT
from app.params import parse_glsl_annotations
from tests.helpers import readme as R

README = R.README_PATH.read_text(encoding="utf-8")
COMMANDS = R.COMMANDS_PATH.read_text(encoding="utf-8")


def test_the_command_line_section_has_examples():
    lines = R.command_lines()
    assert len(lines) >= 15 and all(line.split()[0] == "natura" for line in lines), lines
    assert len(set(lines)) == len(lines), "an example is shown twice: it would run twice"
    assert R.readme_command_lines(), "the README shows no example of its own"


def test_every_command_line_example_runs_in_order_as_written(tmp_path_factory, record_property):
    """No display here: ``natura`` and ``natura window`` render headless, as the README says.
    The examples that share a folder run in order, so one that overwrote another's file would
    fail there (nothing is overwritten without --force); across folders, no two examples may
    write the same file. Each lane runs once per test run (tests/helpers/readme.py): a
    dedicated test that checks a bench example's output reads this same run."""
    from concurrent.futures import ThreadPoolExecutor

    commands = R.command_lines()
    lanes = R.lanes(commands)
    assert sorted(c for lane in lanes for c in lane) == sorted(commands)
    with ThreadPoolExecutor(max_workers=min(len(lanes), os.cpu_count() or 2)) as pool:
        results = list(pool.map(lambda i: R.lane_result(tmp_path_factory, i)[1],
                                range(len(lanes))))
    written: dict[str, str] = {}
    for lane in results:
        for ran in lane:
            record_property(f"seconds: {ran.command}", round(ran.seconds, 2))  # in --junitxml
            assert ran.failure is None, ran.failure
            for name in ran.written:
                assert name not in written, (
                    f"`{ran.command}` and `{written[name]}` both write {name}")
                written[name] = ran.command
    ran_commands = [ran.command for lane in results for ran in lane]
    assert sorted(ran_commands) == sorted(commands)
    # the examples' own outputs, each from the example that names it
    names = {Path(name).parts[0] for name in written}
    for name in ("sunset.png", "night.exr", "clouds.png", "my-glsl"):
        assert name in names, f"no example wrote {name}"


def _python_snippets() -> list[str]:
    snippets = R.blocks("python", path=R.COMMANDS_PATH)
    assert snippets, "docs/commands.md has no Python snippet"
    return snippets


@pytest.mark.parametrize("how", ["script", "pasted"])
def test_python_snippets_run_and_print_their_answer(tmp_path, how):
    for code in _python_snippets():
        if how == "script":
            argv, stdin = [sys.executable, "-c", code], None
        else:  # the interactive interpreter reads it as a user pasting it would type it
            argv, stdin = [sys.executable, "-i", "-q"], code
        r = subprocess.run(argv, input=stdin, cwd=tmp_path, env=R.env(), capture_output=True,
                           text=True, timeout=300)
        assert r.returncode == 0 and "Traceback" not in r.stderr and "Error" not in r.stderr, (
            f"{how}: {r.stderr.strip()[-800:]}")
        numbers = re.findall(r"-?\d+\.\d+", r.stdout)
        assert len(numbers) >= 6, f"{how}: the snippet printed no answer: {r.stdout!r}"
        assert "FrameContext(" not in r.stdout, f"{how}: the REPL echoes a whole frame"


def test_the_annotation_example_makes_the_parameter_the_readme_names():
    (glsl,) = [b for b in R.blocks("glsl", path=R.COMMANDS_PATH) if "@param" in b]
    params = parse_glsl_annotations(glsl, "sky", "glsl/sky/sky.frag")
    assert [p.name for p in params] == ["sky.night_tint"]
    p = params[0]
    assert (p.default, p.lo, p.hi, p.step) == (0.5, 0.0, 1.0, 0.01)
    assert "sky.night_tint" in COMMANDS and "--set sky.night_tint=0.8" in COMMANDS


def test_the_setup_commands_are_the_ones_ci_runs():
    ci = (PROJECT_ROOT / ".ci" / "run").read_text(encoding="utf-8")
    setup = R.blocks("sh", R.SETUP_SECTION)
    first, second = setup[0].strip(), setup[1].strip()
    assert first == "./setup.sh && .venv/bin/natura" and first in ci
    assert second == ".venv/bin/python -m pytest" and second in ci
    assert Path(PROJECT_ROOT / "setup.sh").stat().st_mode & 0o111

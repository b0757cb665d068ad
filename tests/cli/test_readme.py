"""The README as a new user follows it: every command-line example runs as written — the benches
each in a folder of their own, the rest in order in one folder, as many folders at a time as
there are cores — no two examples write the same file, and every Python snippet runs both as
a script and pasted line by line into the interactive interpreter."""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
import time
from pathlib import Path

import pytest

from app import PROJECT_ROOT
from app.params import parse_glsl_annotations
from tests.helpers.cli import NATURA

README = (PROJECT_ROOT / "README.md").read_text(encoding="utf-8")


def _blocks(language: str, section: str | None = None) -> list[str]:
    text = README
    if section is not None:
        start = text.index(f"\n## {section}\n")
        end = text.find("\n## ", start + 1)
        text = text[start:end if end > 0 else None]
    return re.findall(rf"^```{language}\n(.*?)^```$", text, flags=re.S | re.M)


def _env() -> dict:
    env = {k: v for k, v in os.environ.items()
           if k not in ("DISPLAY", "WAYLAND_DISPLAY", "NATURA_SHADERS")}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(PROJECT_ROOT),
                                                      os.environ.get("PYTHONPATH")]))
    return env


def _command_lines() -> list[str]:
    lines = []
    for block in _blocks("sh", "Command line"):
        for line in block.splitlines():
            command = line.split("#", 1)[0].strip()
            if command:
                lines.append(command)
    return lines


def test_the_command_line_section_has_examples():
    lines = _command_lines()
    assert len(lines) >= 15 and all(line.split()[0] == "natura" for line in lines), lines


def _lanes(commands: list[str]) -> list[list[str]]:
    """The examples split into lanes that may run at the same time, each in a folder of its own:
    every ``natura bench`` example alone (a bench reads no file an example writes, and its
    sweeps are the long part), everything else in one lane, in the README's order."""
    main = [c for c in commands if shlex.split(c)[1:2] != ["bench"]]
    return [main] + [[c] for c in commands if c not in main]


def _files(folder: Path) -> set[str]:
    return {p.relative_to(folder).as_posix() for p in folder.rglob("*") if not p.is_dir()}


def _run_lane(commands: list[str], folder: Path
              ) -> list[tuple[str, str | None, set[str], float]]:
    """Run ``commands`` in order in ``folder``: (command, failure or None, files it wrote,
    seconds it took)."""
    folder.mkdir()
    out = []
    for command in commands:
        before = _files(folder)
        start = time.perf_counter()
        r = subprocess.run([*NATURA, *shlex.split(command)[1:]], cwd=folder, env=_env(),
                           capture_output=True, text=True, timeout=900)
        failure = None
        if r.returncode != 0:
            failure = f"`{command}` exited {r.returncode}: {r.stderr.strip()[-600:]}"
        elif "Traceback" in r.stderr:
            failure = f"`{command}` printed a traceback: {r.stderr.strip()[-600:]}"
        out.append((command, failure, _files(folder) - before, time.perf_counter() - start))
        if failure:
            break
    return out


def test_every_command_line_example_runs_in_order_as_written(tmp_path, record_property):
    """No display here: ``natura`` and ``natura window`` render headless, as the README says.
    The examples that share a folder run in order, so one that overwrote another's file would
    fail there (nothing is overwritten without --force); across folders, no two examples may
    write the same file."""
    from concurrent.futures import ThreadPoolExecutor

    commands = _command_lines()
    lanes = _lanes(commands)
    assert sorted(c for lane in lanes for c in lane) == sorted(commands)
    with ThreadPoolExecutor(max_workers=min(len(lanes), os.cpu_count() or 2)) as pool:
        results = list(pool.map(_run_lane, lanes,
                                [tmp_path / f"lane-{i}" for i in range(len(lanes))]))
    written: dict[str, str] = {}
    for lane in results:
        for command, failure, new, seconds in lane:
            record_property(f"seconds: {command}", round(seconds, 2))  # in --junitxml
            assert failure is None, failure
            for name in new:
                assert name not in written, (
                    f"`{command}` and `{written[name]}` both write {name}")
                written[name] = command
    ran = [command for lane in results for command, *_ in lane]
    assert sorted(ran) == sorted(commands)
    # the examples' own outputs, each from the example that names it
    names = {Path(name).parts[0] for name in written}
    for name in ("sunset.png", "night.exr", "clouds.png", "my-glsl"):
        assert name in names, f"no example wrote {name}"


def _python_snippets() -> list[str]:
    snippets = _blocks("python")
    assert snippets, "the README has no Python snippet"
    return snippets


@pytest.mark.parametrize("how", ["script", "pasted"])
def test_python_snippets_run_and_print_their_answer(tmp_path, how):
    for code in _python_snippets():
        if how == "script":
            argv, stdin = [sys.executable, "-c", code], None
        else:  # the interactive interpreter reads it as a user pasting it would type it
            argv, stdin = [sys.executable, "-i", "-q"], code
        r = subprocess.run(argv, input=stdin, cwd=tmp_path, env=_env(), capture_output=True,
                           text=True, timeout=300)
        assert r.returncode == 0 and "Traceback" not in r.stderr and "Error" not in r.stderr, (
            f"{how}: {r.stderr.strip()[-800:]}")
        numbers = re.findall(r"-?\d+\.\d+", r.stdout)
        assert len(numbers) >= 6, f"{how}: the snippet printed no answer: {r.stdout!r}"
        assert "FrameContext(" not in r.stdout, f"{how}: the REPL echoes a whole frame"


def test_the_annotation_example_makes_the_parameter_the_readme_names():
    (glsl,) = [b for b in _blocks("glsl") if "@param" in b]
    params = parse_glsl_annotations(glsl, "sky", "glsl/sky/sky.frag")
    assert [p.name for p in params] == ["sky.night_tint"]
    p = params[0]
    assert (p.default, p.lo, p.hi, p.step) == (0.5, 0.0, 1.0, 0.01)
    assert "sky.night_tint" in README and "--set sky.night_tint=0.8" in README


def test_the_setup_commands_are_the_ones_ci_runs():
    ci = (PROJECT_ROOT / ".ci" / "run").read_text(encoding="utf-8")
    setup = _blocks("sh", "Set up and run")
    first, second = setup[0].strip(), setup[1].strip()
    assert first == "./setup.sh && .venv/bin/natura" and first in ci
    assert second == ".venv/bin/python -m pytest" and second in ci
    assert Path(PROJECT_ROOT / "setup.sh").stat().st_mode & 0o111

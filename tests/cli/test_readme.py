"""The README as a new user follows it: every command-line example runs, in order, as written, in
one folder (so two examples that write the same file are caught), and every Python snippet runs
both as a script and pasted line by line into the interactive interpreter."""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
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


def test_every_command_line_example_runs_in_order_as_written(tmp_path):
    """No display here: ``natura`` and ``natura window`` render headless, as the README says."""
    written: dict[str, str] = {}
    for command in _command_lines():
        before = {p.name for p in tmp_path.rglob("*")}
        r = subprocess.run([*NATURA, *shlex.split(command)[1:]], cwd=tmp_path, env=_env(),
                           capture_output=True, text=True, timeout=900)
        assert r.returncode == 0, f"`{command}` exited {r.returncode}: {r.stderr.strip()[-600:]}"
        assert "Traceback" not in r.stderr, command
        new = {p.name for p in tmp_path.rglob("*")} - before
        for name in new:
            written[name] = command
    # the examples' own outputs, each from the example that names it
    for name in ("sunset.png", "night.exr", "clouds.png", "my-glsl"):
        assert name in written, f"no example wrote {name}"


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

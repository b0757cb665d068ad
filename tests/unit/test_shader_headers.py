"""Each main shader opens with a short header: the thesis (or paper) and section it implements,
its equations, and the failure cases it guards against.

A program's main file is each stage file its ProgramSpec names; a thin stage file (a compute or
fragment wrapper) may instead begin with ``#include`` of the file of its own folder that holds
the header.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from app import DEFAULT_SHADER_ROOT
from app.bakes import PROGRAMS as BAKE_PROGRAMS
from app.scenes import SCENES

CITES = re.compile(r"spec/\d{3}|\b(?:19|20)\d{2}\b")
FAILURES = re.compile(r"[Ff]ailure|[Ff]ails?\b|[Gg]uard")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def main_files() -> list[Path]:
    """The stage files of every program of every scene's effects and of the bakes."""
    effects = {effect for scene in SCENES.values() for effect in scene.effects}
    specs = {spec for effect in effects for spec in effect.programs}
    specs |= {spec for pair in BAKE_PROGRAMS.values() for spec in (pair.compute, pair.fragment)}
    files = set()
    for spec in specs:
        stages = [s for s in spec.stages().values() if s]
        if not stages:  # named by the program: name.vert + name.frag, or name.comp
            compute = DEFAULT_SHADER_ROOT / f"{spec.name}.comp"
            stages = [f"{spec.name}.comp"] if compute.is_file() else [f"{spec.name}.vert",
                                                                       f"{spec.name}.frag"]
        for stage in stages:
            path = DEFAULT_SHADER_ROOT / stage
            if path.is_file() and path.parent.name != "common":
                files.add(path)
    return sorted(files)


def header(path: Path) -> str:
    """The comment block the file opens with (before its first line of code)."""
    out = []
    for line in path.read_text(encoding="utf-8").splitlines():
        s = line.strip()
        if s.startswith("//"):
            out.append(s)
        elif s and not s.startswith("#version") and not s.startswith("#extension"):
            break
    return "\n".join(out)


def first_local_include(path: Path) -> Path | None:
    for line in path.read_text(encoding="utf-8").splitlines():
        m = INCLUDE.match(line)
        if m and (path.parent / m.group(1)).is_file():
            return path.parent / m.group(1)
    return None


@pytest.mark.parametrize("path", main_files(),
                         ids=lambda p: str(p.relative_to(DEFAULT_SHADER_ROOT)))
def test_main_shader_opens_with_its_thesis_and_failure_cases(path):
    text = header(path)
    if not (CITES.search(text) and FAILURES.search(text)):
        inc = first_local_include(path)
        if inc is not None:
            text = header(inc)
    assert CITES.search(text), f"{path}: the header names no thesis (spec/NNN §…) or paper (YEAR)"
    assert FAILURES.search(text), f"{path}: the header lists no failure cases ('Failure cases …')"


MAX_COLUMNS = 100


def test_every_shader_line_fits_in_100_columns():
    """Every line of every file under glsl/ is at most 100 characters wide (as the Python is):
    one message lists every offending file with its lines and widths."""
    shaders = [p for p in DEFAULT_SHADER_ROOT.rglob("*")
               if p.is_file() and p.suffix in (".glsl", ".frag", ".vert", ".comp", ".geom")]
    assert shaders
    wide = []
    for path in sorted(shaders):
        lines = path.read_text(encoding="utf-8").split("\n")
        over = [f"{i} ({len(line)})" for i, line in enumerate(lines, 1)
                if len(line) > MAX_COLUMNS]
        if over:
            wide.append(f"{path.relative_to(DEFAULT_SHADER_ROOT)}: lines {', '.join(over)}")
    assert not wide, (f"{len(wide)} shader files have lines over {MAX_COLUMNS} columns:\n"
                      + "\n".join(wide))

"""The strict check: every stage of a program, preprocessed exactly as the library compiles it
(includes expanded, the spec's defines and the stage's define injected after ``#version``),
judged by the Khronos reference compiler, ``glslangValidator``, for its own ``#version``.

Drivers differ in what they let through — Mesa accepts a line continuation in a 3.30 shader,
NVIDIA an implicit conversion another compiler rejects, Apple almost nothing beyond the letter
of the version — so a program that compiles here proves little. glslang reads the version line
and applies that version's rules; its messages (``ERROR: <source id>:<line>: …``, the form
AMD's driver also uses) go through the library's ``#line`` table back to ``glsl/<file>:<line>``.

The stages are compiled and linked together in one run (``-l``), so an interface mismatch
between stages is caught as well; only when that run fails is each stage compiled on its own,
to say which file and line are to blame.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import tempfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable

from .programs import ProgramSpec
from .shaders import STAGE_DEFINES, PreprocessError, ShaderError, ShaderLibrary

VALIDATOR = "glslangValidator"
#: a stage that takes longer than this is reported, not waited for
TIMEOUT_S = 60
_VERSION_LINE = re.compile(r"Glslang Version:\s*(\S+)")


def validator_path() -> str | None:
    """Where ``glslangValidator`` is, or None (Debian: glslang-tools)."""
    return shutil.which(VALIDATOR)


def validator_version(path: str | None = None) -> str | None:
    path = path or validator_path()
    if path is None:
        return None
    try:
        out = subprocess.run([path, "--version"], capture_output=True, text=True,
                             timeout=TIMEOUT_S).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    m = _VERSION_LINE.search(out)
    return m.group(1) if m else out.strip().splitlines()[0] if out.strip() else "?"


@dataclass
class StrictResult:
    """One program's verdict: ``stages`` checked, ``errors`` as ``file:line: message``."""

    spec: ProgramSpec
    stages: int = 0
    errors: list[ShaderError] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not self.errors


def _messages(output: str) -> str:
    """glslang's ERROR/WARNING lines (the summary 'N compilation errors' line dropped)."""
    keep = []
    for line in output.splitlines():
        if not line.startswith("ERROR:"):
            continue
        if "compilation errors" in line or "compilation terminated" in line:
            continue
        keep.append(line)
    return "\n".join(keep)


def check_program(library: ShaderLibrary, spec: ProgramSpec,
                  validator: str | None = None) -> StrictResult:
    """glslang's verdict on every stage of ``spec`` and on their link."""
    validator = validator or validator_path()
    if validator is None:
        raise FileNotFoundError(f"{VALIDATOR} is not installed (Debian: glslang-tools)")
    result = StrictResult(spec)
    files = library.stage_files(spec.name, **spec.stages())
    with tempfile.TemporaryDirectory(prefix="natura-strict-") as tmp:
        stages = []  # (stage file, its preprocessed copy, the source's files)
        for ext, path in files.items():
            try:
                src = library.preprocess(path, {**dict(spec.defines), STAGE_DEFINES[ext]: 1})
            except PreprocessError as exc:
                result.errors.append(exc.error)
                continue
            copy = Path(tmp) / f"stage.{ext}"
            copy.write_text(src.text, encoding="utf-8")
            stages.append((path, copy, src.files))
        result.stages = len(stages)
        if result.errors or not stages:
            return result
        # one run compiles and links every stage; only a failure is looked at stage by stage
        linked = _run([validator, *(["-l"] if len(stages) > 1 else []),
                       *(str(copy) for _, copy, _ in stages)])
        if linked is None:
            return result
        for path, copy, sources in stages:
            out = _run([validator, str(copy)]) if len(stages) > 1 else linked
            if out is not None:
                result.errors.extend(library.map_errors(_messages(out), sources, path)
                                     or [ShaderError(library.display(path), 1,
                                                     out.strip()[:200] or "rejected")])
        if not result.errors:  # each stage compiles alone: the link failed
            first = stages[0][0]
            result.errors.append(ShaderError(library.display(first), 1,
                                             "link: " + " ".join(_messages(linked).split())[:300]
                                             or "link failed"))
    return result


def _run(argv: list[str]) -> str | None:
    """None when glslang accepts the input; its output when it does not."""
    try:
        done = subprocess.run(argv, capture_output=True, text=True, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return f"ERROR: 0:1: {VALIDATOR} took over {TIMEOUT_S} s"
    if done.returncode == 0:
        return None
    return done.stdout + done.stderr


def check_programs(library: ShaderLibrary, specs: Iterable[ProgramSpec],
                   validator: str | None = None, workers: int = 4) -> list[StrictResult]:
    """:func:`check_program` over ``specs`` (a few at a time: each is a few processes)."""
    validator = validator or validator_path()
    specs = list(specs)
    with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:
        return list(pool.map(lambda s: check_program(library, s, validator), specs))

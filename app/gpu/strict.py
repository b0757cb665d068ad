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

Where the caller gives a folder (``accepted_dir``; the command line gives
``<bake cache>/strict``), a program glslang accepted is remembered there (:class:`Accepted`;
docs/architecture.md, "Caches", has what it keys on and its win). Only acceptances are kept (a
rejection is always rerun, for its messages and lines); a cache that cannot be read or written
is no cache.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import re
import shutil
import subprocess
import tempfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable

from ..errors import NaturaError
from .programs import ProgramSpec
from .shaders import STAGE_DEFINES, PreprocessError, ShaderError, ShaderLibrary

VALIDATOR = "glslangValidator"
#: a stage that takes longer than this is reported, not waited for
TIMEOUT_S = 60
_VERSION_LINE = re.compile(r"Glslang Version:\s*(\S+)")


def validator_path() -> str | None:
    """Where ``glslangValidator`` is, or None (Debian: glslang-tools)."""
    return shutil.which(VALIDATOR)


class ValidatorMissingError(NaturaError):
    """The strict check was asked for, but the reference compiler is not installed: the
    environment lacks something (exit 3), and the check never passes by not running."""

    exit_code = 3


def require_validator(what: str = "shaders check --strict") -> str:
    """Where ``glslangValidator`` is, or :class:`ValidatorMissingError` saying how to get it."""
    path = validator_path()
    if path is None:
        raise ValidatorMissingError(
            f"{what} cannot run: {VALIDATOR} is not on PATH: allowed once it is installed "
            "(Debian: apt-get install glslang-tools; macOS: brew install glslang)")
    return path


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
                  validator: str | None = None, accepted_dir: Path | None = None
                  ) -> StrictResult:
    """glslang's verdict on every stage of ``spec`` and on their link (remembered in
    ``accepted_dir`` when it accepts them, and not asked again there)."""
    validator = validator or validator_path()
    if validator is None:
        raise FileNotFoundError(f"{VALIDATOR} is not installed (Debian: glslang-tools)")
    result = StrictResult(spec)
    files = library.stage_files(spec.name, **spec.stages())
    stages = []  # (stage file, its extension, its preprocessed bytes, the source's files)
    for ext, path in files.items():
        try:
            src = library.preprocess(path, {**dict(spec.defines), STAGE_DEFINES[ext]: 1})
        except PreprocessError as exc:
            result.errors.append(exc.error)
            continue
        stages.append((path, ext, src.text.encode("utf-8"), src.files))
    result.stages = len(stages)
    if result.errors or not stages:
        return result
    # one run compiles and links every stage; only a failure is looked at stage by stage
    flags = ["-l"] if len(stages) > 1 else []
    accepted = Accepted(accepted_dir, validator, flags,
                        [(f"stage.{ext}", data) for _, ext, data, _ in stages])
    if accepted.known():  # judged before: no folder, no files, no process
        return result
    with tempfile.TemporaryDirectory(prefix="natura-strict-") as tmp:
        copies = []  # (stage file, its preprocessed copy, the source's files)
        for path, ext, data, sources in stages:
            copy = Path(tmp) / f"stage.{ext}"
            copy.write_bytes(data)
            copies.append((path, copy, sources))
        linked = _run([validator, *flags, *(str(copy) for _, copy, _ in copies)])
        if linked is None:
            accepted.remember()
            return result
        for path, copy, sources in copies:
            out = _run([validator, str(copy)]) if len(copies) > 1 else linked
            if out is not None:
                result.errors.extend(library.map_errors(_messages(out), sources, path)
                                     or [ShaderError(library.display(path), 1,
                                                     out.strip()[:200] or "rejected")])
        if not result.errors:  # each stage compiles alone: the link failed
            first = copies[0][0]
            result.errors.append(ShaderError(library.display(first), 1,
                                             "link: " + " ".join(_messages(linked).split())[:300]
                                             or "link failed"))
    return result


class Accepted:
    """Whether ``validator`` run with ``flags`` on these (file name, bytes) stages is known in
    ``directory`` to accept them (see the module docstring; None: nothing is known);
    :meth:`remember` records that it did."""

    def __init__(self, directory: Path | None, validator: str, flags: list[str],
                 stages: list[tuple[str, bytes]]):
        self.path: Path | None = None
        if directory is None:
            return
        try:
            st = os.stat(validator)
        except OSError:
            return
        h = hashlib.sha256(repr((os.path.realpath(validator), st.st_size, st.st_mtime_ns,
                                 flags)).encode())
        for name, data in stages:
            h.update(b"\0%d:%s\0" % (len(data), name.encode()))
            h.update(data)
        self.path = directory / h.hexdigest()

    def known(self) -> bool:
        return self.path is not None and self.path.is_file()

    def remember(self) -> None:
        if self.path is None:
            return
        with contextlib.suppress(OSError):  # an empty file: created whole or not at all
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self.path.touch()


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
                   validator: str | None = None, workers: int = 4,
                   accepted_dir: Path | None = None) -> list[StrictResult]:
    """:func:`check_program` over ``specs`` (a few at a time: each is a few processes)."""
    validator = validator or validator_path()
    specs = list(specs)
    with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:
        return list(pool.map(lambda s: check_program(library, s, validator, accepted_dir),
                             specs))

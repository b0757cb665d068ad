"""Live shader reload under random edits: a seeded fuzz of a copy of ``glsl/``.

A real session (``app.runtime.open_session``) renders a small scene from a copy of the shader
folder while random edits hit the files its programs include: deleted, garbage or swapped lines,
a uniform's type changed, a ``// @param`` comment broken, an include removed or renamed, a file
replaced by a folder or a named pipe, Latin-1, NUL or random bytes, a truncated file, a
duplicated function, a varying whose interpolation no longer links, include cycles, a 1 MB line,
``#version`` removed, and no-op edits that must reload. After each edit the code path the window
runs every frame (``gpu.shaders.poll()``, then the scene's ``frame()`` and ``render()``) must not
raise; a broken program keeps its last good program; every listed error reads
``<file>:<line>: ...`` with a line ≥ 1 and a file of the copy (or the path that was removed).
The files are then restored, at once or after a few more edits, and after a poll every program
compiles with no errors and renders the image it rendered before the first edit.

The edits do not touch the files' modification times: two edits of the same size within one
tick of the file system's clock must still be seen (the library's stamp holds a content hash).

Every kind of edit comes once first (a no-op on the clean copy, then the others in a seeded
order), then kinds at random by weight: 60 edits a scene see each kind at least once, which 120
random ones did not always do (a kind that finds nothing to edit in a scene's files is named).

``NATURA_FUZZ_SEED`` picks the seed (printed in every failure message); ``NATURA_FUZZ_EDITS``
the number of edits per scene.
"""

from __future__ import annotations

import os
import random
import re
import shutil
import stat
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

from app import DEFAULT_SHADER_ROOT
from app.runtime import open_session

SEED = int(os.environ.get("NATURA_FUZZ_SEED", "1"))
EDITS = int(os.environ.get("NATURA_FUZZ_EDITS", "60"))
SIZE = (64, 36)
#: scenes whose programs compile in milliseconds on llvmpipe (about 10 ms a frame at 64×36)
SCENES = ("sky", "materials", "probe")
#: a poll is one window frame every 0.25 s; two polls let a file stay missing past one poll
POLLS = 2
ERROR_LINE = re.compile(r"^(?P<file>.+?):(?P<line>-?\d+): \S")
GARBAGE = [
    "@#$%", "float float;", "}", "{", "vec3(", "return;", "#endif", "#if 1", "#define X (",
    "uniform sampler2D", "discard", ")))", "void main() {}", "#line 3 9", "#line 0", "#pragma",
    "int x = 1.0.0;", "#error fuzz", "#include", '#include ""', "é ü — ☃", "float f() {",
    "/*", "*/", "#else", "precision highp float;", "layout(location = 99) out vec4 q;",
]
UNIFORM = re.compile(r"^(\s*uniform\s+)(float|int|bool|vec2|vec3|vec4|mat4)(\s+\w+)")
VARYING = re.compile(r"^(\s*)(in|out)(\s+(?:vec[234]|float)\s+v\w+\s*;)")
PARAM = re.compile(r"//\s*@param\b.*$")
FUNCTION = re.compile(r"^\w+\s+\w+\s*\([^;]*\)\s*\{?\s*$")


@dataclass
class Stats:
    edits: int = 0
    failing: int = 0  # edits after which some error was listed
    kept: int = 0  # failing edits where every program kept a good program and rendered finite
    errors: int = 0
    proper: int = 0  # error strings with a proper file:line
    restores: int = 0
    recovered: int = 0
    noops: int = 0
    noops_reloaded: int = 0
    raised: int = 0  # exceptions into the caller (poll, frame, render)
    hangs: int = 0  # a poll or render that blocked (a named pipe opened for reading)
    problems: list[str] = field(default_factory=list)
    kinds: dict[str, int] = field(default_factory=dict)
    not_applicable: set[str] = field(default_factory=set)  # kinds with nothing to edit
    log: list[str] = field(default_factory=list)  # each edit and its first errors

    def problem(self, text: str) -> None:
        if len(self.problems) < 40:
            self.problems.append(text)

    def line(self, scene: str) -> str:
        return (f"{scene}: seed {SEED}: {self.edits} edits, {self.failing} with errors, "
                f"last good kept {self.kept}/{self.failing}, proper file:line "
                f"{self.proper}/{self.errors}, recovered {self.recovered}/{self.restores}, "
                f"no-op edits reloaded {self.noops_reloaded}/{self.noops}, "
                f"exceptions {self.raised}, hangs {self.hangs}")


class PipeWatchdog:
    """Unblocks a reader stuck opening one of our named pipes (the code before the fix opened
    them): after ``after`` seconds it opens each pipe for writing and closes it, so the reader
    gets end-of-file; it counts how often it had to."""

    def __init__(self, after: float = 3.0):
        self.after = after
        self.pipes: set[Path] = set()
        self.fired = 0
        self._deadline: float | None = None
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def arm(self) -> None:
        self._deadline = time.monotonic() + self.after

    def disarm(self) -> None:
        self._deadline = None

    def _run(self) -> None:
        while not self._stop.wait(0.2):
            if self._deadline is None or time.monotonic() < self._deadline:
                continue
            for pipe in list(self.pipes):
                try:
                    fd = os.open(pipe, os.O_WRONLY | os.O_NONBLOCK)
                except OSError:
                    continue
                os.close(fd)
                self.fired += 1
            self._deadline = time.monotonic() + self.after

    def stop(self) -> None:
        self._stop.set()
        self._thread.join()


class Fuzzer:
    def __init__(self, root: Path, rng: random.Random, files: list[Path], stages: set[Path]):
        self.root = root
        self.rng = rng
        self.files = files  # every file the scene's programs include, in a fixed order
        self.stages = stages
        self.backup: dict[Path, bytes | None] = {}  # original bytes (None: did not exist)
        self.removed: set[Path] = set()  # paths an edit removed (errors may name them)
        self.pipes: set[Path] = set()

    # -- bookkeeping ---------------------------------------------------------------------
    def remember(self, path: Path) -> None:
        if path not in self.backup:
            self.backup[path] = path.read_bytes() if _regular(path) else None

    def pending(self) -> bool:
        return bool(self.backup)

    def restore(self) -> None:
        for path, data in self.backup.items():
            _clear(path)
            if data is not None:
                _write(path, data, self.rng.random() < 0.5)
        self.backup.clear()
        self.removed.clear()

    def text_file(self) -> Path | None:
        choices = [p for p in self.files if _regular(p)]
        return self.rng.choice(choices) if choices else None

    def write(self, path: Path, data: bytes) -> None:
        self.remember(path)
        _write(path, data, self.rng.random() < 0.5)

    def lines(self, path: Path) -> list[str]:
        return path.read_bytes().decode("utf-8", "replace").split("\n")

    def write_lines(self, path: Path, lines: list[str]) -> None:
        self.write(path, "\n".join(lines).encode("utf-8"))

    # -- edits: each returns a description, or None when it does not apply ----------------
    def edit(self, kind: str) -> str | None:
        return getattr(self, f"e_{kind}")()

    def e_noop(self) -> str | None:
        path = self.text_file()
        if path is None:
            return None
        lines = self.lines(path)
        at = self.rng.randrange(1, len(lines) + 1)
        lines.insert(at, f"// fuzz: a comment ({self.rng.randrange(10**6)})")
        self.write_lines(path, lines)
        return f"comment added to {path.name}:{at + 1}"

    def e_delete_line(self) -> str | None:
        path = self.text_file()
        if path is None:
            return None
        lines = self.lines(path)
        at = self.rng.randrange(len(lines))
        del lines[at]
        self.write_lines(path, lines)
        return f"deleted {path.name}:{at + 1}"

    def e_garbage(self) -> str | None:
        path = self.text_file()
        if path is None:
            return None
        lines = self.lines(path)
        at = self.rng.randrange(len(lines) + 1)
        junk = " ".join(self.rng.choice(GARBAGE) for _ in range(self.rng.randint(1, 3)))
        lines.insert(at, junk)
        self.write_lines(path, lines)
        return f"garbage {junk!r} at {path.name}:{at + 1}"

    def e_swap(self) -> str | None:
        path = self.text_file()
        if path is None:
            return None
        lines = self.lines(path)
        if len(lines) < 3:
            return None
        a, b = self.rng.sample(range(len(lines)), 2)
        if lines[a] == lines[b]:
            return None
        lines[a], lines[b] = lines[b], lines[a]
        self.write_lines(path, lines)  # same size: only a content check can see it
        return f"swapped {path.name}:{a + 1} and :{b + 1}"

    def _matching(self, pattern: re.Pattern) -> list[tuple[Path, int]]:
        return [(p, i) for p in self.files if _regular(p)
                for i, line in enumerate(self.lines(p)) if pattern.search(line)]

    def e_uniform_type(self) -> str | None:
        hits = self._matching(UNIFORM)
        if not hits:
            return None
        path, at = self.rng.choice(hits)
        lines = self.lines(path)
        old = UNIFORM.match(lines[at])
        assert old is not None
        # float -> int mostly: GLSL converts int to float implicitly, so that edit usually
        # compiles and the program then sets a float parameter on an int uniform
        likely = {"float": ["int", "int", "int", "vec3"], "int": ["float", "bool"],
                  "bool": ["int", "float"], "vec3": ["float", "vec4"]}.get(old[2], [])
        new = self.rng.choice(likely + [t for t in ("float", "int", "bool", "vec2", "vec3",
                                                    "vec4") if t != old[2]])
        lines[at] = UNIFORM.sub(rf"\g<1>{new}\g<3>", lines[at], count=1)
        self.write_lines(path, lines)
        return f"uniform {old[3].strip()} {old[2]} -> {new} at {path.name}:{at + 1}"

    def e_param(self) -> str | None:
        hits = self._matching(PARAM)
        if not hits:
            return None
        path, at = self.rng.choice(hits)
        lines = self.lines(path)
        broken = self.rng.choice(["// @param", "// @param abc [0, 1]", "// @param 1 [0, 1",
                                  "// @param 2 [0, 1] step=abc", "// @param (1, 2) [0, 1]",
                                  "// @param 5 [0, 1] out of range", "// @param true [x, y]",
                                  "// @param 1e999 [0, 1]", "// @param 1 [1, 0] reversed"])
        lines[at] = PARAM.sub(broken, lines[at])
        self.write_lines(path, lines)
        return f"@param broken to {broken!r} at {path.name}:{at + 1}"

    def e_remove(self) -> str | None:
        path = self.text_file()
        if path is None:
            return None
        self.remember(path)
        if self.rng.random() < 0.5:
            path.unlink()
            how = "deleted"
        else:
            aside = path.with_name(path.name + ".fuzz-renamed")
            self.remember(aside)
            os.replace(path, aside)
            how = "renamed away"
        self.removed.add(path)
        return f"{path.name} {how}"

    def _replace(self, make) -> Path | None:
        path = self.text_file()
        if path is None:
            return None
        self.remember(path)
        path.unlink()
        make(path)
        return path

    def e_folder(self) -> str | None:
        path = self._replace(lambda p: p.mkdir())
        return f"{path.name} replaced by a folder" if path else None

    def e_fifo(self) -> str | None:
        path = self._replace(os.mkfifo)
        if path is None:
            return None
        self.pipes.add(path)
        return f"{path.name} replaced by a named pipe"

    def e_latin1(self) -> str | None:
        path = self.text_file()
        if path is None:
            return None
        data = path.read_bytes().split(b"\n")
        at = self.rng.randrange(len(data) + 1)
        data.insert(at, "// caf\u00e9 na\u00efve".encode("latin-1"))
        self.write(path, b"\n".join(data))
        return f"Latin-1 line at {path.name}:{at + 1}"

    def e_binary(self) -> str | None:
        path = self.text_file()
        if path is None:
            return None
        blob = bytes(self.rng.randrange(256) for _ in range(self.rng.randint(1, 64)))
        data = path.read_bytes()
        at = self.rng.randrange(len(data) + 1)
        self.write(path, data[:at] + blob + data[at:])
        return f"{len(blob)} random bytes into {path.name} at byte {at}"

    def e_nul(self) -> str | None:
        path = self.text_file()
        if path is None:
            return None
        data = path.read_bytes()
        at = self.rng.randrange(len(data) + 1)
        self.write(path, data[:at] + b"\0" + data[at:])
        return f"NUL byte into {path.name} at byte {at}"

    def e_truncate(self) -> str | None:
        path = self.text_file()
        if path is None:
            return None
        data = path.read_bytes()
        keep = 0 if self.rng.random() < 0.4 else self.rng.randrange(len(data) + 1)
        self.write(path, data[:keep])
        return f"{path.name} truncated to {keep} bytes"

    def e_duplicate_function(self) -> str | None:
        hits = self._matching(FUNCTION)
        if not hits:
            return None
        path, at = self.rng.choice(hits)
        lines = self.lines(path)
        depth, end = 0, None
        for j in range(at, len(lines)):
            depth += lines[j].count("{") - lines[j].count("}")
            if depth <= 0 and "}" in lines[j]:
                end = j
                break
        if end is None:
            return None
        lines[end + 1:end + 1] = lines[at:end + 1]
        self.write_lines(path, lines)
        return f"function at {path.name}:{at + 1} duplicated"

    def e_varying(self) -> str | None:
        hits = [(p, i) for p, i in self._matching(VARYING) if p in self.stages]
        if not hits:
            return None
        path, at = self.rng.choice(hits)
        lines = self.lines(path)
        qualifier = self.rng.choice(["flat ", "noperspective "])
        lines[at] = VARYING.sub(rf"\g<1>{qualifier}\g<2>\g<3>", lines[at], count=1)
        self.write_lines(path, lines)
        return f"varying made {qualifier.strip()} at {path.name}:{at + 1} (link error)"

    def e_include_self(self) -> str | None:
        path = self.text_file()
        if path is None:
            return None
        other = self.rng.choice([p for p in self.files if p.parent == path.parent] or [path])
        lines = self.lines(path)
        at = self.rng.randrange(1, len(lines) + 1)
        lines.insert(at, f'#include "{other.name}"')
        self.write_lines(path, lines)
        return f"#include of {other.name} (a cycle or itself) at {path.name}:{at + 1}"

    def e_include_folder(self) -> str | None:
        path = self.text_file()
        if path is None:
            return None
        folder = path.parent / "fuzz-folder.glsl"
        self.remember(folder)
        folder.mkdir(exist_ok=True)
        lines = self.lines(path)
        at = self.rng.randrange(1, len(lines) + 1)
        lines.insert(at, '#include "fuzz-folder.glsl"')
        self.write_lines(path, lines)
        return f"#include of a folder at {path.name}:{at + 1}"

    def e_huge_line(self) -> str | None:
        path = self.text_file()
        if path is None:
            return None
        lines = self.lines(path)
        at = self.rng.randrange(1, len(lines) + 1)
        lines.insert(at, self.rng.choice(["// ", "float q = 1.0 "]) + "x" * 1_000_000)
        self.write_lines(path, lines)
        return f"1 MB line at {path.name}:{at + 1}"

    def e_huge_file(self) -> str | None:
        path = self.text_file()
        if path is None:
            return None
        self.write(path, path.read_bytes() + b"\n//" + b"y" * (20 << 20) + b"\n")
        return f"{path.name} grown past 20 MB"

    def e_no_version(self) -> str | None:
        hits = [(p, i) for p, i in self._matching(re.compile(r"^\s*#\s*version"))]
        if not hits:
            return None
        path, at = self.rng.choice(hits)
        lines = self.lines(path)
        del lines[at]
        self.write_lines(path, lines)
        return f"#version removed from {path.name}"


#: edit kinds and their weights
KINDS = {
    "noop": 4, "delete_line": 4, "garbage": 4, "swap": 3, "uniform_type": 3, "param": 3,
    "remove": 3, "folder": 2, "fifo": 2, "latin1": 2, "binary": 2, "nul": 1, "truncate": 2,
    "duplicate_function": 2, "varying": 2, "include_self": 1, "include_folder": 1,
    "huge_line": 1, "huge_file": 1, "no_version": 1,
}


def _regular(path: Path) -> bool:
    try:
        return stat.S_ISREG(os.lstat(path).st_mode)
    except OSError:
        return False


def _clear(path: Path) -> None:
    if os.path.lexists(path):
        if path.is_dir() and not path.is_symlink():
            shutil.rmtree(path)
        else:
            path.unlink()


def _write(path: Path, data: bytes, by_rename: bool) -> None:
    """Write in place, or the way many editors save: a temporary file renamed over the path."""
    if by_rename or not _regular(path):
        tmp = path.with_name(f".{path.name}.fuzz-tmp")
        tmp.write_bytes(data)
        if os.path.lexists(path) and not _regular(path):
            _clear(path)
        os.replace(tmp, path)
    else:
        with open(path, "wb") as f:
            f.write(data)


def _check_errors(errors: list[str], root: Path, removed: set[Path], stats: Stats,
                  where: str) -> None:
    for text in errors:
        stats.errors += 1
        m = ERROR_LINE.match(text)
        if m is None:
            stats.problem(f"{where}: no file:line in {text[:200]!r}")
            continue
        path = Path(m["file"])
        path = (path if path.is_absolute() else Path.cwd() / path).resolve()
        inside = path.is_relative_to(root.resolve())
        exists = os.path.lexists(path) or path in {p.resolve() for p in removed}
        if text.endswith(": compile failed"):  # the driver's own words were lost
            stats.problem(f"{where}: no message in {text[:200]!r}")
        elif int(m["line"]) >= 1 and inside and exists and (
                not _regular(path) or int(m["line"]) <= path.read_bytes().count(b"\n") + 1):
            stats.proper += 1
        else:
            stats.problem(f"{where}: bad location in {text[:200]!r}")


def fuzz_scene(gl_ctx, tmp_path: Path, scene: str, seed: int, edits: int) -> Stats:
    rng = random.Random(f"{seed}:{scene}")
    root = tmp_path / scene / "glsl"
    shutil.copytree(DEFAULT_SHADER_ROOT, root)  # what `natura shaders copy` does
    session = open_session(scene, shader_root=root, ctx=gl_ctx)
    gpu, lib = session.gpu, session.gpu.shaders
    target = gpu.target("fuzz", "fuzz target", SIZE)
    stats = Stats()
    watchdog = PipeWatchdog()

    def frame(where: str) -> np.ndarray | None:
        for _ in range(POLLS):
            watchdog.arm()
            try:
                lib.poll()
            except Exception as exc:  # counted: nothing may reach the window loop
                stats.raised += 1
                stats.problem(f"{where}: poll raised {type(exc).__name__}: {exc}"[:300])
            finally:
                watchdog.disarm()
        watchdog.arm()
        try:
            f = session.scene.frame(SIZE, dt=0.0)
            session.scene.render(f, target)
            return target.read()
        except Exception as exc:
            stats.raised += 1
            stats.problem(f"{where}: frame/render raised {type(exc).__name__}: {exc}"[:300])
            return None
        finally:
            watchdog.disarm()

    try:
        reference = frame("first frame")
        assert reference is not None and np.isfinite(reference).all()
        assert lib.errors() == [], lib.errors()
        programs = lib.programs()
        files = sorted({p for prog in programs for p in prog.files})
        stages = {p.resolve() for prog in programs for p in prog.stage_paths.values()}
        fz = Fuzzer(root, rng, files, stages)
        watchdog.pipes = fz.pipes
        kinds, weights = list(KINDS), list(KINDS.values())
        # each kind once first: the no-op on the clean copy, the others in a seeded order (one
        # with nothing to edit is tried again after the rest, three times in all)
        first = sorted(set(kinds) - {"noop"})
        rng.shuffle(first)
        first.insert(0, "noop")
        tries: dict[str, int] = {}
        was_finite = True  # the image before the edit
        while stats.edits < edits:
            queued = bool(first)
            if queued:
                kind = first.pop(0)
            else:
                kind = "noop" if rng.random() < 0.05 else rng.choices(kinds, weights)[0]
            if kind == "noop" and fz.pending():
                kind = "delete_line"
            clean = not fz.pending()
            before = {id(p): p.generation for p in programs}
            what = fz.edit(kind)
            if what is None:
                tries[kind] = tries.get(kind, 0) + 1
                if queued and tries[kind] < 3:
                    first.append(kind)
                elif queued:
                    stats.not_applicable.add(kind)
                continue
            stats.edits += 1
            stats.kinds[kind] = stats.kinds.get(kind, 0) + 1
            where = f"seed {seed} {scene} edit {stats.edits} ({what})"
            image = frame(where)
            errors = [str(e) for e in lib.errors()]
            stats.log.append(f"{stats.edits} {what}\n" + "".join(
                f"    {e[:300]}\n" for e in errors[:3]))
            fired = watchdog.fired
            if kind == "noop" and clean:
                stats.noops += 1
                reloaded = any(p.generation > before[id(p)] for p in programs)
                if not errors and reloaded and image is not None:
                    stats.noops_reloaded += 1
                else:
                    stats.problem(f"{where}: a no-op edit did not reload cleanly: {errors[:3]}")
            finite = image is not None and bool(np.isfinite(image).all())
            if errors:
                stats.failing += 1
                # finite pixels, unless the program kept was already making NaN (an edit that
                # compiled, e.g. a float uniform made an int that rounds to a zero divisor)
                good = (all(p.program is not None for p in programs) and image is not None
                        and (finite or not was_finite))
                stats.kept += good
                if not good:
                    lost = [p.name for p in programs if p.program is None]
                    stats.problem(f"{where}: the last good program was not kept (programs "
                                  f"lost: {lost}, finite image: {finite})")
                _check_errors(errors, root, fz.removed, stats, where)
            was_finite = finite
            if fz.pending() and (rng.random() < 0.5 or len(fz.backup) > 3):
                fz.restore()
                stats.restores += 1
                image = frame(f"{where}, restored")
                was_finite = image is not None and bool(np.isfinite(image).all())
                errors = [str(e) for e in lib.errors()]
                same = (image is not None
                        and np.allclose(image, reference, rtol=1 / 255, atol=1 / 255))
                if not errors and same:
                    stats.recovered += 1
                else:
                    stats.problem(f"{where}: not recovered after restore (image same: {same}, "
                                  f"errors: {errors[:3]})")
            stats.hangs = watchdog.fired
            if watchdog.fired > fired:
                stats.problem(f"{where}: blocked reading a named pipe")
        if fz.pending():
            fz.restore()
            stats.restores += 1
            image = frame(f"seed {seed} {scene}: final restore")
            if (not lib.errors() and image is not None
                    and np.allclose(image, reference, rtol=1 / 255, atol=1 / 255)):
                stats.recovered += 1
            else:
                stats.problem(f"seed {seed} {scene}: not recovered after the final restore: "
                              f"{[str(e) for e in lib.errors()][:3]}")
    finally:
        watchdog.stop()
        gpu.free(target)
        session.release()
    return stats


@pytest.mark.parametrize("scene", SCENES)
def test_live_reload_survives_random_edits(gl_ctx, tmp_path, scene):
    stats = fuzz_scene(gl_ctx, tmp_path, scene, SEED, EDITS)
    summary = stats.line(scene)
    print(summary, "\n  kinds:", dict(sorted(stats.kinds.items())),
          "\n  nothing to edit:", sorted(stats.not_applicable))
    report = os.environ.get("NATURA_FUZZ_REPORT")
    if report:
        with open(report, "a", encoding="utf-8") as f:
            f.write(summary + "\n" + "".join(f"  {p}\n" for p in stats.problems))
        with open(report + ".log", "a", encoding="utf-8") as f:
            f.write(f"# {summary}\n" + "".join(stats.log))
    detail = summary + "\n" + "\n".join(stats.problems[:20])
    assert stats.edits >= min(EDITS, 60), detail
    if EDITS >= 2 * len(KINDS):  # every kind ran, or found nothing to edit in this scene
        assert set(stats.kinds) | stats.not_applicable == set(KINDS), (
            f"{detail}\nkinds that never ran: "
            f"{sorted(set(KINDS) - set(stats.kinds) - stats.not_applicable)}")
    assert stats.raised == 0 and stats.hangs == 0, detail
    assert stats.failing > 0 and stats.kept == stats.failing, detail
    assert stats.proper == stats.errors, detail
    assert stats.restores > 0 and stats.recovered == stats.restores, detail
    assert stats.noops_reloaded == stats.noops, detail
    assert not stats.problems, detail

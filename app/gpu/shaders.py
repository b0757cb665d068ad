"""The shader library: GLSL programs by name, with includes, defines, mapped errors and live
reload (docs/architecture.md, "Shaders", and docs/commands.md say what a user sees).

* A program is named by its path under the shader root without extension
  (``materials/material`` for ``glsl/materials/material.vert`` + ``.frag``); each stage can
  also be given explicitly (a full-screen pass reuses ``common/fullscreen.vert``).
* An include must stay inside the shader root or Natura's own ``glsl/``: an absolute path, a
  ``..`` or a link that leads out is refused at the ``#include`` line and never read (students
  share folders: another user's file or ``/etc`` must not end up in a compiler message). A
  program's own stage files are named by the program: a link there is followed wherever it
  points (a test mounts an example's folder into a root that way).
* Every file gets an integer source id in ``#line`` directives (Mesa rejects file names there),
  and its lines are numbered from ``id * LINE_STRIDE``: Mesa reports some errors with source id
  0 whatever ``#line`` said, but with the right line, so the file is recovered from the line.
  Mesa (``0:12(5):``), NVIDIA (``0(12) :``) and AMD (``ERROR: 0:12:``) messages are mapped back
  to ``glsl/<file>:<line>: message``; user ``#line`` directives are dropped.
* :meth:`ShaderLibrary.poll` never raises: every failure becomes a :class:`ShaderError` on its
  program (``internal: ...`` for the unexpected), the last good program keeps running, and the
  user's file is never touched. A file that vanished is given one poll (editors that save by
  moving the original away).
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import os
import re
import stat
import threading
from collections import OrderedDict
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Iterable

from .. import DEFAULT_SHADER_ROOT
from ..errors import ShaderCompileError, UsageError, quote

if TYPE_CHECKING:  # numpy and moderngl are imported where used: `import app.cli` stays light
    import moderngl

STAGES = {
    "vert": "vertex_shader",
    "frag": "fragment_shader",
    "geom": "geometry_shader",
    "tesc": "tess_control_shader",
    "tese": "tess_evaluation_shader",
    "comp": "compute_shader",
}
#: a define every stage gets after #version, so a shared include can hold code that only one
#: stage may compile (``#ifdef NATURA_FRAGMENT_STAGE`` around a use of gl_FragCoord)
STAGE_DEFINES = {"vert": "NATURA_VERTEX_STAGE", "frag": "NATURA_FRAGMENT_STAGE",
                 "geom": "NATURA_GEOMETRY_STAGE", "tesc": "NATURA_TESS_CONTROL_STAGE",
                 "tese": "NATURA_TESS_EVALUATION_STAGE", "comp": "NATURA_COMPUTE_STAGE"}
SHADER_ENV = "NATURA_SHADERS"
#: GL types of sampler uniforms (samplers use texture units; image uniforms do not).
SAMPLER_TYPES = frozenset(
    list(range(0x8B5D, 0x8B65))  # sampler1D … sampler2DRectShadow
    + list(range(0x8DC0, 0x8DC6))  # array, buffer and cube shadow samplers
    + list(range(0x8DC9, 0x8DD0)) + list(range(0x8DD1, 0x8DD9))  # isampler*, usampler*
    + list(range(0x900C, 0x9010))  # cube-map arrays
    + list(range(0x9108, 0x910E))  # multisample
)
#: Line numbers of the file with source id ``k`` start at ``k * LINE_STRIDE`` (see module doc).
LINE_STRIDE = 100_000

#: the largest GLSL file read (a bigger one is an error, not a long stall)
MAX_SOURCE_BYTES = 4 << 20
#: the longest compiler message kept (a 1 MB line may come back quoted)
MAX_MESSAGE_CHARS = 500

#: why a link that leads back to itself cannot be read (a file's problem at its line 1)
LOOP_REASON = ("is a symlink loop (a link that leads back to itself): allowed a GLSL text file "
               "(replace the link with the file)")

_INCLUDE = re.compile(r'^\s*#\s*include\s+[<"]([^">]+)[">]')
_VERSION = re.compile(r"^\s*#\s*version\b")
_LINE_DIRECTIVE = re.compile(r"^\s*#\s*line\b")
_MAIN = re.compile(r"^\s*void\s+main\s*\(")
#: identifiers a driver message quotes: Mesa `name', others 'name' or "name"
_QUOTED = re.compile(r"[`'\"\u2018]([A-Za-z_][A-Za-z0-9_]*)['\"\u2019]")
_STAGE_WORDS = [
    ("fragment", "fragment_shader"), ("vertex", "vertex_shader"),
    ("geometry", "geometry_shader"), ("tessellation control", "tess_control_shader"),
    ("tessellation evaluation", "tess_evaluation_shader"), ("compute", "compute_shader"),
]
#: words a link message quotes that are not the user's identifiers
_GLSL_WORDS = frozenset({"main", "float", "int", "uint", "bool", "double", "void", "in", "out",
                         "uniform", "flat", "smooth", "noperspective", "centroid", "sample"})
_DECLARING = r"\b(?:in|out|inout|uniform|varying|attribute|buffer|flat|smooth|noperspective|" \
             r"centroid|layout|const)\b[^;]*\b{name}\b"
# (source id, line, message) for each vendor's message format.
_MESSAGE_FORMATS = [
    re.compile(r"^\s*(?P<id>\d+):(?P<line>\d+)\(\d+\):\s*(?P<msg>.*)$"),  # Mesa
    re.compile(r"^\s*(?P<id>\d+)\((?P<line>\d+)\)\s*:\s*(?P<msg>.*)$"),  # NVIDIA
    re.compile(r"^\s*(?:ERROR|WARNING):\s*(?P<id>\d+):(?P<line>\d+):\s*(?P<msg>.*)$"),  # AMD
]


def resolve_shader_root(arg: str | os.PathLike | None = None) -> Path:
    """``--shaders DIR`` beats ``$NATURA_SHADERS`` beats the project's ``glsl/``. The folder
    must be laid out like ``glsl/`` (a ``common/`` folder of shared code beside the effects'
    folders), so an empty or wrong folder is named here rather than as a missing parameter."""
    chosen = arg if arg else os.environ.get(SHADER_ENV)
    if not chosen:
        return DEFAULT_SHADER_ROOT
    origin = "--shaders" if arg else f"${SHADER_ENV}"
    allowed = "allowed a folder laid out like glsl/ (see natura shaders copy)"
    try:
        root = Path(chosen).expanduser()
    except RuntimeError:  # ~user of an unknown user
        raise UsageError(f"{origin} {quote(str(chosen))}: no such user's home folder: "
                         f"{allowed}") from None
    try:
        if not root.is_dir():
            raise UsageError(f"{origin} {quote(str(root))} is not a directory: {allowed}")
        if not (root / "common").is_dir():
            raise UsageError(f"{origin} {quote(str(root))} has no common/ folder of shared "
                             f"GLSL: {allowed}")
        return root.resolve()
    except OSError as exc:  # a name too long, a loop of links, an unreadable parent
        raise UsageError(f"{origin} {quote(str(root))}: {exc.strerror or exc}: "
                         f"{allowed}") from None


@dataclass(frozen=True)
class ShaderError:
    """A compiler or linker message mapped back to a file and line."""

    file: str
    line: int
    message: str

    def __str__(self) -> str:
        return (f"{self.file}:{self.line}: {self.message}" if self.line
                else f"{self.file}: {self.message}")


@dataclass
class Source:
    """One preprocessed stage: text for the compiler, the id → file table, and the stamp of
    every file it read or looked for (``None``: not there)."""

    text: str
    files: list[Path]
    stamps: dict[Path, Any] = field(default_factory=dict)


class PreprocessError(Exception):
    def __init__(self, error: ShaderError, files: list[Path],
                 stamps: dict[Path, Any] | None = None):
        super().__init__(str(error))
        self.error = error
        self.files = files
        self.stamps = stamps or {}


class SourceError(Exception):
    """A GLSL file that cannot be used as text: ``line`` (≥ 1) and ``reason``."""

    def __init__(self, line: int, reason: str, stamp: Any = None):
        super().__init__(f"line {line}: {reason}")
        self.line = line
        self.reason = reason
        self.stamp = stamp


def _kind(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISFIFO(mode):
        return "a named pipe"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def _stat_part(st: os.stat_result) -> tuple:
    return (stat.S_IFMT(st.st_mode), st.st_mtime_ns, st.st_size, st.st_ino)


def _read_bytes(path: Path) -> tuple[bytes, Any]:
    """The bytes of a regular file and its stamp; :class:`SourceError` for anything else.
    Never blocks: a named pipe is refused from its type before it is opened, and the file is
    opened non-blocking (a pipe swapped in between is refused from ``fstat``)."""
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise SourceError(1, "file not found (deleted or renamed?)") from None
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise SourceError(1, LOOP_REASON) from None
        raise SourceError(1, f"cannot read: {exc.strerror or exc}") from None
    except ValueError as exc:
        raise SourceError(1, f"cannot read: {getattr(exc, 'strerror', None) or exc}") from None
    if not stat.S_ISREG(st.st_mode):
        raise SourceError(1, f"is {_kind(st.st_mode)}, not a file: allowed a GLSL text file",
                          (_stat_part(st), None))
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0)
                     | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        raise SourceError(1, f"cannot read: {exc.strerror or exc}", (_stat_part(st), None)) \
            from None
    try:
        st = os.fstat(fd)
        stamp0 = _stat_part(st)
        if not stat.S_ISREG(st.st_mode):
            raise SourceError(1, f"is {_kind(st.st_mode)}, not a file: allowed a GLSL text file",
                              (stamp0, None))
        if st.st_size > MAX_SOURCE_BYTES:
            raise SourceError(1, f"is {st.st_size} bytes: allowed at most "
                                 f"{MAX_SOURCE_BYTES >> 20} MiB of GLSL", (stamp0, None))
        chunks, total = [], 0
        while total <= MAX_SOURCE_BYTES:
            chunk = os.read(fd, min(1 << 20, MAX_SOURCE_BYTES + 1 - total))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
    except OSError as exc:
        raise SourceError(1, f"cannot read: {exc.strerror or exc}", (_stat_part(st), None)) \
            from None
    finally:
        os.close(fd)
    data = b"".join(chunks)
    stamp = (stamp0, hashlib.blake2b(data, digest_size=16).digest())
    if len(data) > MAX_SOURCE_BYTES:
        raise SourceError(1, f"is over {MAX_SOURCE_BYTES >> 20} MiB: allowed at most "
                             f"{MAX_SOURCE_BYTES >> 20} MiB of GLSL", stamp)
    return data, stamp


def _decode(data: bytes, stamp: Any = None) -> str:
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        column = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        raise SourceError(line, f"not UTF-8 text: byte 0x{data[exc.start]:02x} at column "
                                f"{column} ({exc.reason}): allowed UTF-8 (save the file as "
                                "UTF-8)", stamp) from None
    text = text.removeprefix("\ufeff")
    nul = text.find("\0")
    if nul >= 0:
        line = text.count("\n", 0, nul) + 1
        column = nul - (text.rfind("\n", 0, nul) + 1) + 1
        raise SourceError(line, f"NUL byte at column {column}: allowed text only", stamp)
    return text


def read_source(path: Path) -> str:
    """The text of a GLSL file (UTF-8, a regular file of at most :data:`MAX_SOURCE_BYTES`),
    or :class:`SourceError` with the line to blame. Never blocks on a named pipe."""
    data, stamp = _read_bytes(Path(path))
    return _decode(data, stamp)


def source_lines(text: str) -> list[str]:
    """Lines as the compiler counts them (only ``\\n`` ends a line, unlike ``splitlines``)."""
    lines = [line.removesuffix("\r") for line in text.split("\n")]
    if lines and lines[-1] == "":
        lines.pop()
    return lines


def _stamp(path: Path) -> Any:
    """What poll compares: (type, mtime, size, inode) and a hash of the content of a regular
    file (``None`` when nothing is there)."""
    try:
        _, stamp = _read_bytes(path)
        return stamp
    except SourceError as exc:
        return exc.stamp


class ShaderLibrary:
    """Loads, compiles and live-reloads GLSL programs from one shader root."""

    def __init__(self, ctx: moderngl.Context, root: Path | None = None):
        self.ctx = ctx
        self.root = Path(root or DEFAULT_SHADER_ROOT).resolve()
        self._programs: dict[tuple, Program] = {}

    def display(self, path: Path, follow: bool = True) -> str:
        """How a file is named in messages: ``glsl/sky/sky.frag`` for the project's shaders.
        ``follow=False`` names a link itself, not where it leads."""
        path = Path(path)
        resolved = _resolved(path) if follow else Path(os.path.abspath(path))
        try:
            rel = resolved.relative_to(self.root)
        except ValueError:
            return str(path)
        if self.root == DEFAULT_SHADER_ROOT.resolve():
            return "glsl" if rel == Path(".") else f"glsl/{rel.as_posix()}"
        try:
            return str(resolved.relative_to(Path.cwd()))
        except (ValueError, OSError):
            return str(resolved)

    def stage_files(self, name: str, **explicit: str | None) -> dict[str, Path]:
        """Stage → file for program ``name``. Explicit ``vert=``/``frag=``/``comp=``… name the
        stages exactly; otherwise ``name.vert`` + ``name.frag`` (+ geometry/tessellation files of
        that name) make a graphics program, or ``name.comp`` alone a compute program."""
        given = {ext: self.root / path for ext, path in explicit.items() if path}
        if given:
            out = given
        elif (self.root / f"{name}.vert").is_file():
            out = {ext: self.root / f"{name}.{ext}" for ext in STAGES
                   if ext != "comp" and (self.root / f"{name}.{ext}").is_file()}
        elif (self.root / f"{name}.comp").is_file():
            out = {"comp": self.root / f"{name}.comp"}
        else:
            raise UsageError(f"no shader program {name!r} under {self.root}: "
                             f"expected {name}.vert/.frag or .comp")
        if "comp" in out and len(out) > 1:
            raise UsageError(f"program {name!r} mixes a compute stage with others")
        if "comp" not in out and not {"vert", "frag"} <= set(out):
            missing = sorted({"vert", "frag"} - set(out))
            raise UsageError(f"program {name!r} lacks a {' and '.join(missing)} stage")
        return out

    def preprocess(self, path: Path, defines: dict[str, Any] | None = None) -> Source:
        """Expand includes and inject defines; raise :class:`PreprocessError` on a bad include
        or a file that cannot be read as text (with the file and line to blame).

        A successful expansion is remembered (:data:`_EXPANSIONS`, shared by every library of
        the process) under the shader root and the file, and given again while everything it
        depended on is as it was: the stamp (content hash included) of every file it read, the
        absence (or non-file) of every place an include was looked for before the one that was
        used, and where each link among those places pointed. The defines are not part of it:
        they only add lines after ``#version`` (includes are resolved whatever they say), so
        they are put in on every call. Why: every program compile re-read and re-expanded every
        include (~19 s of the test suite, most of it resolving the three places of each
        ``#include``), and a scene's parameters, the compile and the strict check each expand
        the same stage again; checking the stamps is a read and a hash per file. A failed
        expansion is never remembered: errors take the full path every time."""
        top = _resolved(Path(path))  # a loop stays as named: reading it says what it is
        key = (self.root, top)
        with _EXPANSIONS_LOCK:
            held = _EXPANSIONS.get(key)
        if held is None or not held.still_valid():
            files: list[Path] = []
            out: list[str] = []
            stamps: dict[Path, Any] = {}
            trace = _Trace()
            self._expand(top, files, out, {}, True, stamps, trace)
            # out[0] is the #version line (the defines go after it), then the #line of the rest
            held = _Expansion(out[0], "\n".join(out[1:]) + "\n", tuple(files), stamps,
                              {**trace.probes, **stamps}, tuple(trace.links.items()))
        with _EXPANSIONS_LOCK:
            _EXPANSIONS[key] = held
            _EXPANSIONS.move_to_end(key)
            while len(_EXPANSIONS) > _EXPANSIONS_KEPT:
                _EXPANSIONS.popitem(last=False)
        lines = "".join(f"#define {k} {_glsl_literal(v)}\n" for k, v in (defines or {}).items())
        return Source(f"{held.version}\n{lines}{held.rest}", list(held.files), dict(held.stamps))

    def areas(self) -> tuple[Path, ...]:
        """Where an include may lead: the shader root and Natura's own ``glsl/``."""
        return tuple(dict.fromkeys((self.root, DEFAULT_SHADER_ROOT.resolve())))

    def _inside(self, path: Path) -> bool:
        return any(path.is_relative_to(area) for area in self.areas())

    def _places(self, name: str, including: Path,
                trace: "_Trace | None" = None) -> tuple[list["_Place"], str | None]:
        """Where ``#include "name"`` in ``including`` is looked for, in order (relative to the
        including file, then ``common/``, then the root), and why the name itself is refused
        (``None``: it is not). A place outside the shader root is no place: it is never looked
        at. A place inside whose file is a link that loops or points out carries its problem."""
        if os.path.isabs(name):
            return [], "is an absolute path"
        out: dict[Path, _Place] = {}
        for base in (including.parent, self.root / "common", self.root):
            raw = base / name
            place = Path(os.path.normpath(raw))  # as named: what is never looked at if out
            if not self._inside(place) or place in out:
                continue
            try:  # then as the file system has it (a link in the name, then "..")
                resolved: Path | None = raw.resolve()
            except (OSError, RuntimeError, ValueError):  # a loop (Python < 3.13 raises)
                resolved = None
            if trace is not None and resolved != raw:
                trace.links[raw] = resolved
            there = _lexists(raw)
            if resolved is None or _is_loop(resolved):
                out[place] = _Place(place, None, "a symlink loop" if there else None)
            elif not self._inside(resolved):
                out[place] = _Place(place, None,
                                    "a link out of the shader folder" if there else None)
            else:
                out[place] = _Place(place, resolved, None)
        if not out:
            return [], "leads out of the shader folder"
        return list(out.values()), None

    def _find_include(self, name: str, including: Path) -> Path | None:
        places, refused = self._places(name, including)
        if refused is not None:
            return None
        return next((p.resolved for p in places if p.problem is None
                     and p.resolved is not None and _is_regular(p.resolved)), None)

    def _expand(self, path: Path, files: list[Path], out: list[str], defines, top: bool,
                stamps: dict[Path, Any], trace: "_Trace | None" = None) -> None:
        sid = len(files)
        files.append(path)

        def fail(line: int, message: str) -> PreprocessError:
            return PreprocessError(ShaderError(self.display(path), max(1, line), message),
                                   files, stamps)

        try:
            data, stamps[path] = _read_bytes(path)
            lines = source_lines(_decode(data, stamps[path]))
        except SourceError as exc:
            stamps[path] = exc.stamp
            raise fail(exc.line, exc.reason) from None
        start = 0
        if top:
            for i, line in enumerate(lines):
                if _VERSION.match(line):
                    out.append(line)
                    for key, value in defines.items():
                        out.append(f"#define {key} {_glsl_literal(value)}")
                    start = i + 1
                    break
                if line.strip() and not line.strip().startswith("//"):
                    raise fail(i + 1, "the first directive must be #version")
            else:
                raise fail(1, "missing #version")
        if not top and not any(line.strip() for line in lines):
            raise _EmptyInclude()  # blamed at the #include line, naming this file
        base = sid * LINE_STRIDE
        out.append(f"#line {base + start + 1} {sid}")
        for i in range(start, len(lines)):
            line = lines[i]
            m = _INCLUDE.match(line)
            if not m:
                if not top and _VERSION.match(line):
                    out.append("// (#version of an included file dropped)")
                elif _LINE_DIRECTIVE.match(line):
                    out.append("// (#line dropped: the library numbers the lines)")
                else:
                    out.append(line)
                continue
            name = m.group(1)
            places, refused = self._places(name, path, trace)
            if refused is not None:  # never looked at, let alone read
                raise fail(i + 1, f'include "{name}" {refused}: allowed a path to a file inside '
                                  f"{self.display(self.root)}/, relative to this file or to "
                                  "common/")
            usable = [p.resolved for p in places if p.problem is None and p.resolved is not None]
            target = next((p for p in usable if _is_regular(p)), None)
            if trace is not None and target is not None:
                for p in places:
                    if p.resolved == target:
                        break
                    if p.resolved is not None:  # a file appearing there wins
                        trace.probes.setdefault(p.resolved, _stamp(p.resolved))
            if target is None:
                for p in places:  # watched: the include appearing (or fixed) recompiles
                    if p.resolved is not None:
                        stamps.setdefault(p.resolved, _stamp(p.resolved))
                    elif _lexists(p.place.parent):  # a bad link: its folder, never its target
                        stamps.setdefault(p.place.parent, _stamp(p.place.parent))
                bad = next((p for p in places if p.problem is not None), None)
                if bad is not None and bad.problem is not None:
                    shown = self.display(bad.place, follow=False)
                    raise fail(i + 1, f'include "{name}" is {bad.problem} ({shown}): allowed a '
                                      f"GLSL text file inside {self.display(self.root)}/"
                                      + (" (copy the file in)" if "out" in bad.problem else ""))
                odd = next((p for p in usable if _lexists(p)), None)
                if odd is not None:
                    try:
                        what = _kind(os.stat(odd).st_mode)
                    except OSError:
                        what = "not readable"
                    raise fail(i + 1, f'include "{name}" is {what} '
                                      f"({self.display(odd)}): allowed a GLSL text file")
                looked = ", ".join(self.display(p.place, follow=False) for p in places)
                raise fail(i + 1, f'cannot find include "{name}" (no {looked}): allowed a GLSL '
                                  "file at one of them")
            if target in files:
                out.append(f"// include {name} already included")
                continue
            try:
                self._expand(target, files, out, defines, False, stamps, trace)
            except _EmptyInclude:
                raise fail(i + 1, f'include "{name}" ({self.display(target)}) is empty: '
                                  "allowed a GLSL file holding the code included from it "
                                  "(restore it)") from None
            out.append(f"#line {base + i + 2} {sid}")

    def map_errors(self, message: str, files: list[Path],
                   stage_file: Path | None = None) -> list[ShaderError]:
        """Turn a driver log into ``file:line`` errors through the id → file table. A line
        without a location is put at ``stage_file``'s ``void main`` line (or its first)."""
        errors = []
        for raw in message.splitlines():
            line = raw.strip()
            if (not line or line.startswith("GLSL ") or set(line) <= {"="}
                    or line in STAGES.values() or line == "Program"):
                continue
            for fmt in _MESSAGE_FORMATS:
                m = fmt.match(line)
                if m:
                    sid, lineno = int(m["id"]), int(m["line"])
                    if lineno >= LINE_STRIDE:  # the line number names the file (see module doc)
                        sid, lineno = divmod(lineno, LINE_STRIDE)
                    where = files[sid] if sid < len(files) else (stage_file or Path("?"))
                    lineno, note = _within(where, lineno, m["msg"])
                    errors.append(ShaderError(self.display(where), lineno,
                                              _short(m["msg"].strip()) + note))
                    break
            else:
                if stage_file is None:
                    errors.append(ShaderError("link", 1, _short(line)))
                else:
                    errors.append(ShaderError(self.display(stage_file), _main_line(stage_file),
                                              _short(line)))
        return errors

    def blame_link(self, message: str, tables: dict[str, list[Path]],
                   fallback: Path) -> ShaderError:
        """A link message (no location) at the declaration of the identifier it quotes: in the
        stages it names first, the most recently saved file declaring it (the one just edited).
        Without such a declaration: ``fallback``'s ``void main`` line, and the message says so."""
        text = _short(message.strip())
        order = [stage for word, stage in sorted(
            ((w, s) for w, s in _STAGE_WORDS if w in text), key=lambda ws: text.find(ws[0]))]
        order += [s for s in tables if s not in order]
        for name in dict.fromkeys(_QUOTED.findall(text)):
            if name in _GLSL_WORDS or re.fullmatch(r"[biud]?vec[234]|d?mat[234](x[234])?", name):
                continue
            found = []  # (stage preference, -mtime, file, line)
            pattern = re.compile(_DECLARING.format(name=re.escape(name)))
            for rank, stage in enumerate(order):
                for path in tables.get(stage, []):
                    line = _declaration_line(path, pattern)
                    if line:
                        found.append((-_mtime(path), rank, path, line))
            if found:
                found.sort(key=lambda f: (f[0], f[1]))
                _, _, path, line = found[0]
                others = [f"{self.display(p)}:{n}" for _, _, p, n in found[1:]
                          if (p, n) != (path, line)]
                also = f" (`{name}' is also declared at {', '.join(dict.fromkeys(others))})" \
                    if others else ""
                return ShaderError(self.display(path), line, f"link {text}{also}")
        main = _main_line(fallback)
        return ShaderError(self.display(fallback), main,
                           f"link {text} (no file declares what it names: shown at the "
                           f"{'void main line' if main > 1 else 'first line'} of the fragment "
                           "stage)")

    def program(self, name: str, defines: dict[str, Any] | None = None,
                **stages: str | None) -> "Program":
        """The program ``name`` (compiled on first use, then shared). Raises
        :class:`ShaderCompileError` if the first compile fails."""
        key = (name, tuple(sorted((defines or {}).items())),
               tuple(sorted((k, v) for k, v in stages.items() if v)))
        prog = self._programs.get(key)
        if prog is None:
            prog = Program(self, name, dict(defines or {}), self.stage_files(name, **stages))
            prog.compile()
            if prog.program is None:
                raise ShaderCompileError(prog.errors)
            self._programs[key] = prog
        return prog

    def programs(self) -> list["Program"]:
        return list(self._programs.values())

    def include_children(self, path: Path) -> list[Path]:
        """The files ``path`` includes directly, in order, as the preprocessor resolves them
        (relative to it, then ``common/``); an include that cannot be found is left out."""
        try:
            lines = source_lines(read_source(Path(path)))
        except Exception:  # noqa: BLE001 - an unreadable file has no children to show
            return []
        out: list[Path] = []
        for line in lines:
            m = _INCLUDE.match(line)
            if m:
                found = self._find_include(m.group(1), _resolved(Path(path)))
                if found is not None and found not in out:
                    out.append(found)
        return out

    def set_root(self, root: Path) -> None:
        """Move every program to the same files under another root (a copy of this one, made
        by ``natura shaders copy``) and recompile them from there: the window's editor does
        this when a first save must not go into Natura's own shaders. A program that fails
        keeps its last good version, as a live edit does."""
        new_root = Path(root).resolve()
        for prog in self._programs.values():
            moved = {}
            for ext, path in prog.stage_paths.items():
                try:
                    moved[ext] = new_root / _resolved(Path(path)).relative_to(self.root)
                except ValueError:  # a stage outside the root stays where it is
                    moved[ext] = path
            prog.stage_paths = moved
        self.root = new_root
        for prog in self._programs.values():
            prog.compile()

    def poll(self) -> list["Program"]:
        """Recompile programs whose include set changed. Returns the programs that were
        recompiled (successfully or not); errors stay on each program. Never raises: an
        unexpected failure becomes an ``internal:`` error on the program it happened in."""
        changed = []
        seen: dict[Path, Any] = {}  # one stamp per file and poll, however many include it
        for prog in list(self._programs.values()):
            try:
                if not prog.changed_on_disk(seen):
                    continue
                changed.append(prog)
                prog.compile()
            except Exception as exc:  # noqa: BLE001 - the window loop must survive anything
                prog.internal_error(exc, "poll")
        return changed

    def errors(self) -> list[ShaderError]:
        """Every program's errors (each listed once)."""
        return list(dict.fromkeys(e for p in self._programs.values() for e in p.errors))

    def release(self) -> None:
        for prog in self._programs.values():
            prog.release()
        self._programs.clear()


@dataclass
class _Trace:
    """What an expansion depended on beyond the files it read: ``probes``, the stamp of each
    place an include was looked for before the one used (``None``: nothing there), and
    ``links``, each place under a name that resolved elsewhere (a symlink, ``..``) → where it
    pointed (``None``: it could not be resolved)."""

    probes: dict[Path, Any] = field(default_factory=dict)
    links: dict[Path, Path | None] = field(default_factory=dict)


@dataclass(frozen=True)
class _Expansion:
    """A remembered :meth:`ShaderLibrary.preprocess` result (without defines: the
    ``#version`` line, and the text after it) and what it depended on."""

    version: str
    rest: str
    files: tuple[Path, ...]
    stamps: dict[Path, Any]  # the Source's own (the files read)
    checks: dict[Path, Any]  # those and the probes
    links: tuple[tuple[Path, Path | None], ...]

    def still_valid(self) -> bool:
        for place, resolved in self.links:
            try:
                if place.resolve() != resolved:
                    return False
            except (OSError, RuntimeError, ValueError):
                if resolved is not None:
                    return False
        return all(_stamp(p) == stamp for p, stamp in self.checks.items())


#: remembered expansions (see :meth:`ShaderLibrary.preprocess`), least recently used out first;
#: every stage file of every effect is ~150 entries of ~16 KB of text
_EXPANSIONS: "OrderedDict[tuple, _Expansion]" = OrderedDict()
_EXPANSIONS_KEPT = 512
_EXPANSIONS_LOCK = threading.Lock()  # the strict check preprocesses from a thread pool


@dataclass(frozen=True)
class _Place:
    """A place an include is looked for: ``place`` as named (normalised), ``resolved`` where
    it leads (``None`` when it cannot be used: a loop, or a link out of the shader folder —
    ``problem`` says which when something is there)."""

    place: Path
    resolved: Path | None
    problem: str | None


class _EmptyInclude(Exception):
    """An included file with nothing in it (reported at the including file's #include)."""


def _resolved(path: Path) -> Path:
    """``path`` with its links followed, or made absolute as named when they loop."""
    try:
        return path.resolve()
    except (OSError, RuntimeError, ValueError):  # a symlink loop (Python < 3.13 raises)
        return Path(os.path.abspath(path))


def _lexists(path: Path) -> bool:
    try:
        return os.path.lexists(path)
    except (OSError, ValueError):
        return False


def _is_loop(path: Path) -> bool:
    try:
        os.stat(path)
    except OSError as exc:
        return exc.errno == errno.ELOOP
    except ValueError:
        return False
    return False


def _is_regular(path: Path) -> bool:
    try:
        return stat.S_ISREG(os.stat(path).st_mode)
    except (OSError, ValueError):
        return False


def _mtime(path: Path) -> int:
    try:
        return os.stat(path).st_mtime_ns
    except (OSError, ValueError):
        return 0


def _short(message: str) -> str:
    if len(message) <= MAX_MESSAGE_CHARS:
        return message
    return message[:MAX_MESSAGE_CHARS] + f"… ({len(message)} characters)"


def _lines_of(path: Path) -> list[str]:
    try:
        return source_lines(read_source(path))
    except SourceError:
        return []


def _within(path: Path, line: int, message: str) -> tuple[int, str]:
    """A reported line made a line of ``path``: an unterminated comment (which swallows the
    rest of the stage, so the driver reports its end) is put at its ``/*``; any other line past
    the end of the file at the file's last line, saying so."""
    if line < 1:
        return 1, ""
    lines = _lines_of(path)
    if line <= max(1, len(lines)) or not lines:
        return line, ""
    if "nterminated comment" in message:
        opened = _unclosed_comment(lines)
        if opened:
            return opened, " (the comment opened here)"
    return len(lines), f" (reported at line {line}, past the end of the file)"


def _unclosed_comment(lines: list[str]) -> int:
    """The line of a ``/*`` that no ``*/`` closes (0 if none)."""
    opened = 0
    for i, line in enumerate(lines, 1):
        pos = 0
        while pos < len(line):
            if opened:
                end = line.find("*/", pos)
                if end < 0:
                    break
                opened, pos = 0, end + 2
                continue
            start, comment = line.find("/*", pos), line.find("//", pos)
            if start < 0 or 0 <= comment < start:
                break
            opened, pos = i, start + 2
    return opened


def _main_line(path: Path) -> int:
    """The line of ``void main`` in ``path`` (1 when there is none)."""
    for i, line in enumerate(_lines_of(path), 1):
        if _MAIN.match(line):
            return i
    return 1


def _declaration_line(path: Path, pattern: re.Pattern) -> int:
    for i, line in enumerate(_lines_of(path), 1):
        if pattern.search(line.split("//", 1)[0]):
            return i
    return 0


def _glsl_literal(value: Any) -> str:
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, float):
        text = repr(value)
        return text if ("." in text or "e" in text) else text + ".0"
    return str(value)


_FLOAT_TYPES = {0x1406: "float", 0x8B50: "vec2", 0x8B51: "vec3", 0x8B52: "vec4"}
_INT_TYPES = {0x1404: "int", 0x8B53: "ivec2", 0x8B54: "ivec3", 0x8B55: "ivec4"}
_UINT_TYPES = {0x1405: "uint", 0x8DC6: "uvec2", 0x8DC7: "uvec3", 0x8DC8: "uvec4"}
_BOOL_TYPES = {0x8B56: "bool", 0x8B57: "bvec2", 0x8B58: "bvec3", 0x8B59: "bvec4"}
_DOUBLE_TYPES = {0x140A: "double", 0x8FFC: "dvec2", 0x8FFD: "dvec3", 0x8FFE: "dvec4"}
_MATRIX_TYPES = {0x8B5A: "mat2", 0x8B5B: "mat3", 0x8B5C: "mat4"}


def _type_name(member: Any) -> str:
    gl_type = getattr(member, "gl_type", None)
    for table in (_FLOAT_TYPES, _INT_TYPES, _UINT_TYPES, _BOOL_TYPES, _DOUBLE_TYPES,
                  _MATRIX_TYPES):
        if gl_type in table:
            return table[gl_type]
    if gl_type in SAMPLER_TYPES:
        return "sampler"
    return f"GL type 0x{gl_type:04x}" if isinstance(gl_type, int) else type(member).__name__


def _moderngl():
    import moderngl

    return moderngl


def _components(value: Any) -> list[float] | None:
    """A value as a flat list of numbers (``None`` if it is not numbers)."""
    import numpy as np

    try:
        if isinstance(value, (bool, np.bool_)):
            return [1.0 if value else 0.0]
        if isinstance(value, (int, float, np.number)):
            return [float(value)]
        arr = np.asarray(value, dtype=np.float64)
        if arr.dtype.kind not in "fiub":
            return None
        return [float(v) for v in arr.ravel()]
    except (TypeError, ValueError):
        return None


def _convert(member: Any, value: Any) -> Any:
    """``value`` in the form ``member``'s GLSL type takes, or ``None`` if it cannot be:
    float → int rounds, bool → 0/1, a scalar fills every component of a vector; vectors must
    have the uniform's size; samplers, matrices of another size and arrays are refused."""
    gl_type = getattr(member, "gl_type", None)
    if getattr(member, "array_length", 1) != 1 or gl_type in SAMPLER_TYPES:
        return None
    flat = _components(value)
    if flat is None:
        return None
    size = int(getattr(member, "dimension", 1))
    if gl_type in _MATRIX_TYPES:
        if len(flat) != size:
            return None
        return tuple(flat)
    if len(flat) == 1 and size > 1:
        flat = flat * size
    if len(flat) != size:
        return None
    if gl_type in _FLOAT_TYPES or gl_type in _DOUBLE_TYPES:
        out: list[Any] = flat
    else:
        import numpy as np

        if not all(np.isfinite(flat)):
            return None
        if gl_type in _BOOL_TYPES:
            out = [int(v != 0.0) for v in flat]
        elif gl_type in _UINT_TYPES:
            out = [max(0, int(round(v))) for v in flat]
        elif gl_type in _INT_TYPES:
            out = [int(round(v)) for v in flat]
        else:
            return None
    return out[0] if size == 1 else tuple(out)


@dataclass
class Program:
    """A compiled program that survives bad edits: ``program`` is always the last good one."""

    library: ShaderLibrary
    name: str
    defines: dict[str, Any]
    stage_paths: dict[str, Path]
    program: Any = None  # moderngl.Program | moderngl.ComputeShader
    errors: list[ShaderError] = field(default_factory=list)
    generation: int = 0  # increases with each successful compile
    #: the last compile failed: ``program`` is the last good one (``errors`` say why). Errors
    #: on a program that did not fail are about its use: a broken ``@param`` annotation, a
    #: uniform whose GLSL type no longer takes the value set
    failed: bool = False
    stamps: dict[Path, Any] = field(default_factory=dict)
    _vaos: dict = field(default_factory=dict)
    _samplers: tuple[int, list[str]] | None = None
    on_reload: list[Callable[["Program"], None]] = field(default_factory=list)
    #: files seen missing at the last poll(s): path → polls (one is a save in progress)
    _gone: dict[Path, int] = field(default_factory=dict)
    #: uniforms already reported as not settable since the last successful compile
    _bad_uniforms: set[str] = field(default_factory=set)
    #: files that exist among ``stamps`` (includes and stage files, not watched absences)
    _files: list[Path] = field(default_factory=list)

    @property
    def is_compute(self) -> bool:
        return "comp" in self.stage_paths

    @property
    def files(self) -> list[Path]:
        """The files of the program's include set (stage files first, in include order)."""
        return list(self._files)

    def changed_on_disk(self, seen: dict[Path, Any] | None = None) -> bool:
        """Whether a file of the include set (or a watched missing include) changed. A file
        that vanished counts only at the second poll that finds it missing (a save by moving
        the original away is given one poll to finish)."""
        seen = {} if seen is None else seen
        changed = False
        for path, stamp in self.stamps.items():
            if path not in seen:
                seen[path] = _stamp(path)
            now = seen[path]
            if now == stamp:
                self._gone.pop(path, None)
                continue
            if now is None and stamp is not None:
                self._gone[path] = self._gone.get(path, 0) + 1
                if self._gone[path] < 2:
                    continue  # mid-save (renamed away); look again on the next poll
            changed = True
        return changed

    def report(self, error: ShaderError) -> None:
        """List an error on this program (once)."""
        if error not in self.errors:
            self.errors.append(error)

    def internal_error(self, exc: BaseException, during: str) -> None:
        """An unexpected exception, listed on the program instead of raised."""
        stage = next(iter(self.stage_paths.values()), None)
        where = self.library.display(stage) if stage is not None else self.name
        self.report(ShaderError(where, 1, _short(f"internal: {during} failed: "
                                                 f"{type(exc).__name__}: {exc}")))

    def compile(self) -> bool:
        """Recompile from the files; ``program`` changes only when this succeeds. Never raises
        for anything the files hold."""
        try:
            return self._compile()
        except Exception as exc:  # noqa: BLE001 - listed, never raised into the caller
            self.errors = []
            self.failed = True
            self.internal_error(exc, "compile")
            if not self.stamps:
                self.stamps = {p: _stamp(p) for p in self.stage_paths.values()}
            return False

    def _compile(self) -> bool:
        lib = self.library
        sources: dict[str, str] = {}
        all_files: list[Path] = []
        stamps: dict[Path, Any] = {}
        errors: list[ShaderError] = []
        tables: dict[str, list[Path]] = {}
        for ext, path in self.stage_paths.items():
            try:
                src = lib.preprocess(path, {**self.defines, STAGE_DEFINES[ext]: 1})
            except PreprocessError as exc:
                errors.append(exc.error)
                all_files.extend(exc.files)
                stamps.update(exc.stamps)
                continue
            sources[STAGES[ext]] = src.text
            tables[STAGES[ext]] = src.files
            all_files.extend(src.files)
            stamps.update(src.stamps)
        watched = {p: stamps.get(p) for p in dict.fromkeys(all_files)}
        watched.update(stamps)  # and where missing includes may appear
        if errors:
            # keep watching the previous include set too: restoring any of it recompiles
            for old in self.stamps:
                if old not in watched:
                    watched[old] = _stamp(old)
        self.stamps = watched
        self._gone.clear()
        self._files = list(dict.fromkeys(
            [p for p in all_files if os.path.lexists(p)]
            + ([p for p in self._files if p not in all_files] if errors else [])))
        if not errors:
            try:
                new: Any
                if self.is_compute:
                    new = lib.ctx.compute_shader(sources["compute_shader"])
                else:
                    new = lib.ctx.program(**sources)  # type: ignore[arg-type]
            except _moderngl().Error as exc:
                errors = self._map(str(exc), tables)
            else:
                if self.program is not None:
                    self.program.release()
                self.program = new
                self.generation += 1
                for vao in self._vaos.values():
                    vao.release()
                self._vaos.clear()
                self.errors = []
                self.failed = False
                self._bad_uniforms.clear()
                for callback in list(self.on_reload):
                    try:
                        callback(self)
                    except Exception as exc:  # noqa: BLE001 - listed on the program
                        self.internal_error(exc, f"reload callback "
                                                 f"{getattr(callback, '__qualname__', callback)}")
                return True
        first = next(iter(self.stage_paths.values()))
        self.errors = errors or [ShaderError(lib.display(first), 1, "compile failed")]
        self.failed = True
        return False

    def _map(self, message: str, tables: dict[str, list[Path]]) -> list[ShaderError]:
        """Split a moderngl log by stage and map each part with that stage's id table; the
        linker's part (no locations) goes through :meth:`ShaderLibrary.blame_link`."""
        errors: list[ShaderError] = []
        current = None
        chunk: list[str] = []
        parts: list[tuple[str | None, list[str]]] = []
        for line in message.splitlines():
            if line.strip() in tables or line.strip() == "Program":
                parts.append((current, chunk))
                current, chunk = line.strip(), []
            else:
                chunk.append(line)
        parts.append((current, chunk))
        main_stage = ("fragment_shader" if "fragment_shader" in tables
                      else next(iter(tables), ""))
        fallback = (tables[main_stage][0] if main_stage in tables
                    else next(iter(self.stage_paths.values())))
        for stage, lines in parts:
            if stage == "Program":
                errors.extend(self.library.blame_link(line, tables, fallback) for line in lines
                              if set(line.strip()) - {"="})
                continue
            files = tables.get(stage or "", [])
            stage_file = files[0] if files else fallback
            errors.extend(self.library.map_errors("\n".join(lines), files, stage_file))
        return errors

    def __contains__(self, uniform: str) -> bool:
        return self.program is not None and self.program.get(uniform, None) is not None

    def set(self, uniform: str, value: Any) -> None:
        """Set a uniform if the compiler kept it (removed uniforms are tolerated). A value that
        does not fit the uniform's GLSL type is converted when it can be (see :func:`_convert`)
        and otherwise skipped with an error listed at the uniform's declaration: a GLSL edit
        that changes a uniform's type never raises here."""
        import numpy as np

        prog = self.program
        # (a dict lookup: ``in`` on a moderngl program walks its members one by one)
        member = None if prog is None else prog.get(uniform, None)
        if member is None:
            return
        with contextlib.suppress(Exception):  # converted below, or listed
            if isinstance(value, np.ndarray) and value.ndim == 2:
                # numpy row-major → GL column-major
                data = np.ascontiguousarray(value.T, dtype="f4").tobytes()
                size = getattr(member, "element_size", len(data)) * getattr(member,
                                                                            "array_length", 1)
                if len(data) != size:
                    raise ValueError(f"{len(data)} bytes for a {size}-byte uniform")
                member.write(data)
            elif isinstance(value, bool):
                member.value = int(value)
            elif isinstance(value, np.ndarray):
                member.value = tuple(float(v) for v in value.ravel())
            else:
                member.value = value
            return
        with contextlib.suppress(Exception):  # listed below
            converted = _convert(member, value)
            if converted is not None:
                member.value = converted
                return
        self._bad_uniform(uniform, value, member)

    def _bad_uniform(self, uniform: str, value: Any, member: Any) -> None:
        if uniform in self._bad_uniforms:
            return
        self._bad_uniforms.add(uniform)
        flat = _components(value)
        got = (f"{len(flat)} number(s)" if flat is not None else type(value).__name__)
        where, line = self.declaration(uniform)
        self.report(ShaderError(where, line,
                                f"uniform {uniform} is a {_type_name(member)} in the GLSL, but "
                                f"the program sets it from {got}: skipped (it keeps its last "
                                "value; allowed a matching type, or change the GLSL back)"))

    def declaration(self, uniform: str) -> tuple[str, int]:
        """Where ``uniform`` is declared: (display name, line), the first stage file's line 1
        when no file of the include set declares it."""
        pattern = re.compile(rf"^\s*(?:layout\s*\([^)]*\)\s*)?uniform\b[^;]*\b"
                             rf"{re.escape(uniform)}\b")
        for path in self.files:
            line = _declaration_line(path, pattern)
            if line:
                return self.library.display(path), line
        first = next(iter(self.stage_paths.values()))
        return self.library.display(first), 1

    def set_many(self, values: dict[str, Any]) -> None:
        for k, v in values.items():
            self.set(k, v)

    def set_array(self, uniform: str, rows: Any) -> None:
        """Write a uniform array (``vec4 uRows[16]``) from rows of numbers: missing rows are
        zeros, extra rows are dropped, and an array the compiler removed is tolerated (as is
        one whose type changed: skipped and listed)."""
        import numpy as np

        prog = self.program
        member = None if prog is None else prog.get(uniform, None)
        if member is None:
            return
        try:
            gl_type = getattr(member, "gl_type", None)
            if gl_type in SAMPLER_TYPES or any(gl_type in t for t in (
                    _INT_TYPES, _UINT_TYPES, _BOOL_TYPES, _DOUBLE_TYPES)):
                raise ValueError("not a float array")  # float bytes would be garbage there
            arr = np.zeros((member.array_length, member.dimension), dtype="f4")
            data = np.asarray(rows, dtype="f4").reshape(-1, member.dimension)
            data = data[: member.array_length]
            arr[: len(data)] = data
            member.write(arr.tobytes())
        except Exception:  # noqa: BLE001 - listed, never raised into a render
            self._bad_uniform(uniform, rows, member)

    def samplers(self) -> list[str]:
        """The sampler uniforms the linked program kept, in location order."""
        prog = self.program
        if prog is None:
            return []
        if self._samplers is None or self._samplers[0] != self.generation:
            found = []
            for name in prog:
                member = prog[name]
                if (isinstance(member, _moderngl().Uniform)
                        and getattr(member, "gl_type", None) in SAMPLER_TYPES):
                    found.append((member.location, name))
            self._samplers = (self.generation, [name for _, name in sorted(found)])
        return self._samplers[1]

    def bind_textures(self, textures: dict[str, Any]) -> None:
        """Bind textures by sampler name, with texture units assigned here: the given
        textures take units 0, 1, … in the order given, and every other sampler of the program
        gets a unit of its own after them (two samplers of different types on one unit fail
        the draw, and an unset sampler reads unit 0). Names the compiler removed are skipped."""
        present = self.samplers()
        given = {name: tex for name, tex in textures.items() if tex is not None and name in present}
        unit = 0
        for name, texture in given.items():
            texture.use(unit)
            self.program[name].value = unit
            unit += 1
        for name in present:
            if name not in given:
                self.program[name].value = unit
                unit += 1

    def uniforms(self) -> list[str]:
        prog = self.program
        return [name for name in prog] if prog is not None else []

    def vao(self, content: Iterable = (), index_buffer=None):
        """A vertex array for this program, rebuilt after each reload."""
        content = [tuple(c) for c in content]
        key = (tuple((id(c[0]), *c[1:]) for c in content), id(index_buffer))
        if key not in self._vaos:
            # skip_errors: attributes the compiler removed (e.g. normals in an unlit variant) are
            # fine
            vao = self.library.ctx.vertex_array(self.program, content,
                                                index_buffer=index_buffer, skip_errors=True)
            # the key holds the buffers' ids: keep the buffers alive as long as their vertex
            # array is cached, so a freed mesh's id cannot be reused by a new buffer and draw
            # with this stale array
            vao.extra = ([c[0] for c in content], index_buffer)
            self._vaos[key] = vao
        return self._vaos[key]

    def forget_buffer(self, buffer) -> None:
        """Release the vertex arrays cached for ``buffer`` (as a vertex or index buffer): a
        deleted buffer still attached to an array keeps its storage in the driver until the
        array is deleted too (``Gpu.free`` calls this for every program)."""
        dead = [key for key, vao in self._vaos.items()
                if isinstance(vao.extra, tuple) and len(vao.extra) == 2
                and (buffer is vao.extra[1] or any(buffer is b for b in vao.extra[0]))]
        for key in dead:
            self._vaos.pop(key).release()

    def release(self) -> None:
        for vao in self._vaos.values():
            vao.release()
        self._vaos.clear()
        if self.program is not None:
            self.program.release()
            self.program = None

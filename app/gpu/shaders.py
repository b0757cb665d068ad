"""The shader library: GLSL programs by name, with includes, defines, mapped errors and live
reload.

* A program is named by its path under the shader root without extension, e.g.
  ``materials/material`` for ``glsl/materials/material.vert`` +
  ``glsl/materials/material.frag``; each stage can also be given explicitly (a full-screen pass
  reuses ``common/fullscreen.vert``).
* ``#include "file"`` resolves relative to the including file, then ``glsl/common``, then the
  root; each file is included once per stage (later includes of it are dropped).
* Defines are injected right after ``#version``.
* Every file gets an integer source id in ``#line`` directives (Mesa rejects file names there),
  and its lines are numbered from ``id * LINE_STRIDE`` (Mesa reports some errors — e.g. an
  undeclared identifier — with source id 0 whatever ``#line`` said, but with the right line, so
  the file is recovered from the line number); compiler messages in Mesa (``0:12(5):``),
  NVIDIA (``0(12) :``) and AMD (``ERROR: 0:12:``) formats are mapped back to
  ``glsl/<file>:<line>: message``.
* :meth:`ShaderLibrary.poll` checks the modification stamps of each program's whole include set
  (on the main thread; editors that save by rename change the inode and are caught). A failed
  reload keeps the last good program and records the error; the user's file is never touched.
"""

from __future__ import annotations

import os
import re
import struct
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable

import moderngl
import numpy as np

from .. import DEFAULT_SHADER_ROOT
from ..errors import ShaderCompileError, UsageError

STAGES = {
    "vert": "vertex_shader",
    "frag": "fragment_shader",
    "geom": "geometry_shader",
    "tesc": "tess_control_shader",
    "tese": "tess_evaluation_shader",
    "comp": "compute_shader",
}
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

_INCLUDE = re.compile(r'^\s*#\s*include\s+[<"]([^">]+)[">]')
_VERSION = re.compile(r"^\s*#\s*version\b")
# (source id, line, message) for each vendor's message format.
_MESSAGE_FORMATS = [
    re.compile(r"^\s*(?P<id>\d+):(?P<line>\d+)\(\d+\):\s*(?P<msg>.*)$"),  # Mesa
    re.compile(r"^\s*(?P<id>\d+)\((?P<line>\d+)\)\s*:\s*(?P<msg>.*)$"),  # NVIDIA
    re.compile(r"^\s*(?:ERROR|WARNING):\s*(?P<id>\d+):(?P<line>\d+):\s*(?P<msg>.*)$"),  # AMD
]


def resolve_shader_root(arg: str | os.PathLike | None = None) -> Path:
    """``--shaders DIR`` beats ``$NATURA_SHADERS`` beats the project's ``glsl/``."""
    chosen = arg if arg else os.environ.get(SHADER_ENV)
    if not chosen:
        return DEFAULT_SHADER_ROOT
    root = Path(chosen).expanduser()
    origin = "--shaders" if arg else f"${SHADER_ENV}"
    if not root.is_dir():
        raise UsageError(f"{origin} {str(root)!r} is not a directory: "
                         "allowed a folder laid out like glsl/")
    return root.resolve()


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
    """One preprocessed stage: text for the compiler, and the id → file table."""

    text: str
    files: list[Path]


class PreprocessError(Exception):
    def __init__(self, error: ShaderError, files: list[Path]):
        super().__init__(str(error))
        self.error = error
        self.files = files


class ShaderLibrary:
    """Loads, compiles and live-reloads GLSL programs from one shader root."""

    def __init__(self, ctx: moderngl.Context, root: Path | None = None):
        self.ctx = ctx
        self.root = Path(root or DEFAULT_SHADER_ROOT).resolve()
        self._programs: dict[tuple, Program] = {}

    # -- names -----------------------------------------------------------------------------
    def display(self, path: Path) -> str:
        """How a file is named in messages: ``glsl/sky/sky.frag`` for the project's shaders."""
        path = Path(path)
        try:
            rel = path.resolve().relative_to(self.root)
        except ValueError:
            return str(path)
        if self.root == DEFAULT_SHADER_ROOT.resolve():
            return f"glsl/{rel.as_posix()}"
        try:
            return str(path.resolve().relative_to(Path.cwd()))
        except ValueError:
            return str(path)

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

    # -- preprocessing ---------------------------------------------------------------------
    def preprocess(self, path: Path, defines: dict[str, Any] | None = None) -> Source:
        """Expand includes and inject defines; raise :class:`PreprocessError` on a bad include."""
        files: list[Path] = []
        out: list[str] = []
        self._expand(Path(path).resolve(), files, out, defines or {}, top=True)
        return Source("\n".join(out) + "\n", files)

    def _find_include(self, name: str, including: Path) -> Path | None:
        for base in (including.parent, self.root / "common", self.root):
            cand = (base / name).resolve()
            if cand.is_file():
                return cand
        return None

    def _expand(self, path: Path, files: list[Path], out: list[str], defines, top: bool) -> None:
        sid = len(files)
        files.append(path)
        try:
            lines = path.read_text(encoding="utf-8").splitlines()
        except FileNotFoundError:
            raise PreprocessError(ShaderError(self.display(path), 0, "file not found"),
                                  files) from None
        except UnicodeDecodeError as exc:
            raise PreprocessError(ShaderError(self.display(path), 0,
                                              f"not UTF-8 text ({exc.reason})"), files) from None
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
                    raise PreprocessError(
                        ShaderError(self.display(path), i + 1,
                                    "the first directive must be #version"), files
                    )
            else:
                raise PreprocessError(ShaderError(self.display(path), 1, "missing #version"), files)
        base = sid * LINE_STRIDE
        out.append(f"#line {base + start + 1} {sid}")
        for i in range(start, len(lines)):
            line = lines[i]
            m = _INCLUDE.match(line)
            if not m:
                if not top and _VERSION.match(line):
                    out.append("// (#version of an included file dropped)")
                else:
                    out.append(line)
                continue
            target = self._find_include(m.group(1), path)
            if target is None:
                looked = ", ".join(self.display(b) for b in (path.parent, self.root / "common"))
                raise PreprocessError(
                    ShaderError(self.display(path), i + 1,
                                f'cannot find include "{m.group(1)}" (looked in {looked})'),
                    files,
                )
            if target in files:
                out.append(f"// include {m.group(1)} already included")
                continue
            self._expand(target, files, out, defines, top=False)
            out.append(f"#line {base + i + 2} {sid}")

    # -- errors ----------------------------------------------------------------------------
    def map_errors(self, message: str, files: list[Path],
                   stage_file: Path | None = None) -> list[ShaderError]:
        """Turn a driver log into ``file:line`` errors through the id → file table."""
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
                    errors.append(ShaderError(self.display(where), lineno, m["msg"].strip()))
                    break
            else:
                errors.append(ShaderError(self.display(stage_file) if stage_file else "link", 0,
                                          line))
        return errors

    # -- programs --------------------------------------------------------------------------
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

    def poll(self) -> list["Program"]:
        """Recompile programs whose include set changed. Returns the programs that were
        recompiled (successfully or not); errors stay on each program."""
        changed = []
        for prog in self._programs.values():
            if prog.changed_on_disk():
                prog.compile()
                changed.append(prog)
        return changed

    def errors(self) -> list[ShaderError]:
        return [e for p in self._programs.values() for e in p.errors]

    def release(self) -> None:
        for prog in self._programs.values():
            prog.release()
        self._programs.clear()


def _glsl_literal(value: Any) -> str:
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, float):
        text = repr(value)
        return text if ("." in text or "e" in text) else text + ".0"
    return str(value)


def _stamp(path: Path):
    try:
        st = os.stat(path)
    except FileNotFoundError:
        return None
    return (st.st_mtime_ns, st.st_size, st.st_ino)


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
    stamps: dict[Path, Any] = field(default_factory=dict)
    _vaos: dict = field(default_factory=dict)
    _samplers: tuple[int, list[str]] | None = None
    on_reload: list[Callable[["Program"], None]] = field(default_factory=list)

    @property
    def is_compute(self) -> bool:
        return "comp" in self.stage_paths

    @property
    def files(self) -> list[Path]:
        return list(self.stamps)

    def changed_on_disk(self) -> bool:
        for path, stamp in self.stamps.items():
            now = _stamp(path)
            if now is None:
                return False  # mid-save (renamed away); look again on the next poll
            if now != stamp:
                return True
        return False

    def compile(self) -> bool:
        lib = self.library
        sources: dict[str, str] = {}
        all_files: list[Path] = []
        errors: list[ShaderError] = []
        tables: dict[str, list[Path]] = {}
        for ext, path in self.stage_paths.items():
            try:
                src = lib.preprocess(path, self.defines)
            except PreprocessError as exc:
                errors.append(exc.error)
                all_files.extend(exc.files)
                continue
            sources[STAGES[ext]] = src.text
            tables[STAGES[ext]] = src.files
            all_files.extend(src.files)
        self.stamps = {p: _stamp(p) for p in dict.fromkeys(all_files)}
        if not errors:
            try:
                new: Any
                if self.is_compute:
                    new = lib.ctx.compute_shader(sources["compute_shader"])
                else:
                    new = lib.ctx.program(**sources)  # type: ignore[arg-type]
            except moderngl.Error as exc:
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
                for callback in self.on_reload:
                    callback(self)
                return True
        self.errors = errors or [ShaderError(self.name, 0, "compile failed")]
        return False

    def _map(self, message: str, tables: dict[str, list[Path]]) -> list[ShaderError]:
        """Split a moderngl log by stage and map each part with that stage's id table."""
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
        for stage, lines in parts:
            files = tables.get(stage or "", [])
            stage_file = files[0] if files else next(iter(self.stage_paths.values()))
            errors.extend(self.library.map_errors("\n".join(lines), files, stage_file))
        return errors

    # -- use -------------------------------------------------------------------------------
    def __contains__(self, uniform: str) -> bool:
        return self.program is not None and uniform in self.program

    def set(self, uniform: str, value: Any) -> None:
        """Set a uniform if the compiler kept it (removed uniforms are tolerated)."""
        prog = self.program
        if prog is None or uniform not in prog:
            return
        member = prog[uniform]
        try:
            if isinstance(value, np.ndarray) and value.ndim == 2:
                # numpy row-major → GL column-major
                member.write(np.ascontiguousarray(value.T, dtype="f4").tobytes())
            elif isinstance(value, bool):
                member.value = int(value)
            elif isinstance(value, np.ndarray):
                member.value = tuple(float(v) for v in value.ravel())
            else:
                member.value = value
        except (struct.error, TypeError, ValueError) as exc:
            # e.g. a student changed a uniform's type in the GLSL: name it instead of a struct error
            raise ValueError(f"uniform {uniform} of program {self.name}: cannot set {value!r} "
                             f"(GLSL type has {member.dimension} component(s)): {exc}") from None

    def set_many(self, values: dict[str, Any]) -> None:
        for k, v in values.items():
            self.set(k, v)

    def set_array(self, uniform: str, rows: Any) -> None:
        """Write a uniform array (``vec4 uRows[16]``) from rows of numbers: missing rows are
        zeros, extra rows are dropped, and an array the compiler removed is tolerated."""
        prog = self.program
        if prog is None or uniform not in prog:
            return
        member = prog[uniform]
        arr = np.zeros((member.array_length, member.dimension), dtype="f4")
        data = np.asarray(rows, dtype="f4").reshape(-1, member.dimension)[: member.array_length]
        arr[: len(data)] = data
        member.write(arr.tobytes())

    def samplers(self) -> list[str]:
        """The sampler uniforms the linked program kept, in location order."""
        prog = self.program
        if prog is None:
            return []
        if self._samplers is None or self._samplers[0] != self.generation:
            found = []
            for name in prog:
                member = prog[name]
                if (isinstance(member, moderngl.Uniform)
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
        key = (tuple(id(c[0]) for c in content), id(index_buffer))
        if key not in self._vaos:
            # skip_errors: attributes the compiler removed (e.g. normals in an unlit variant) are
            # fine
            self._vaos[key] = self.library.ctx.vertex_array(self.program, list(content),
                                                            index_buffer=index_buffer,
                                                            skip_errors=True)
        return self._vaos[key]

    def release(self) -> None:
        for vao in self._vaos.values():
            vao.release()
        self._vaos.clear()
        if self.program is not None:
            self.program.release()
            self.program = None

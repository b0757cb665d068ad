"""Graded exercises: ``natura exercise list | start NAME DIR | check DIR``.

An exercise is one TOML file, ``resources/exercises/<name>.toml``, in the format of
docs/exercises.md. ``start`` copies the shader library into ``DIR/glsl``, puts a stub in place
of the function's body (it compiles and returns a neutral value) and renders
``DIR/expected.png`` with Natura's own shaders; ``check`` renders the view with the student's
shaders and with Natura's own on one context, and compares them (mean and 99th percentile of
the displayed image's per-pixel error, and the probe's worst error: a render can hide what a
probe shows).
"""

from __future__ import annotations

import os
import re
import shutil
import tempfile
import textwrap
import tomllib
from contextlib import closing
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import moderngl
import numpy as np

from .. import DEFAULT_SHADER_ROOT, PROJECT_ROOT, RESOURCES
from ..colour import srgb_to_linear, to_srgb8
from ..errors import NaturaError, UsageError, quote
from ..gpu import context as gl_context
from ..gpu.device import Gpu
from ..imageio import (
    _LIVE,
    check_new_folder,
    expand,
    temp_name_in,
    write_bytes_atomic,
    write_text_atomic,
)
from ..runtime import open_session, parse_size, placed_camera, render_frames, scene_params
from ..scenes import SCENES
from ..scenes.views import get_view
from . import theory
from .compare import LUMINANCE, choose_gain, encode_png, heat_map
from .editor import copy_shaders

EXERCISES = RESOURCES / "exercises"
#: the file in DIR that says which exercise DIR holds (a copy of the exercise's TOML)
MARKER = "exercise.toml"
#: the largest view an exercise may ask for (checks must stay quick on a software renderer)
MAX_SIDE = 512
#: the largest probe grid
MAX_POINTS = 4096
_NAME = re.compile(r"^[a-z0-9][a-z0-9-]{0,39}$")
_TOP_KEYS = {"title", "tag", "file", "function", "task", "expected", "stub", "view",
             "tolerance", "probe", "wrong"}
_NEUTRAL = {"float": "0.0", "int": "0", "uint": "0u", "bool": "false"}


@dataclass
class Wrong:
    body: str
    hint: str


@dataclass
class Probe:
    expr: str
    axes: tuple[tuple[float, float, int], ...]
    version: str = "330 core"
    uniforms: dict[str, Any] = field(default_factory=dict)

    def points(self) -> np.ndarray:
        grids = np.meshgrid(*[np.linspace(lo, hi, n) for lo, hi, n in self.axes], indexing="ij")
        return np.stack([g.ravel() for g in grids], axis=-1).astype(np.float32)


@dataclass
class Exercise:
    name: str
    path: Path
    text: str
    title: str
    tag: str
    file: str
    function: str
    task: str
    expected: str
    scene: str
    size: tuple[int, int]
    view: str | None = None
    camera: str | None = None
    sets: list[str] = field(default_factory=list)
    mean_tolerance: float = 0.01
    p99_tolerance: float = 0.05
    probe_tolerance: float = 1e-4
    stub: str | None = None
    probe: Probe | None = None
    wrong: list[Wrong] = field(default_factory=list)

    @property
    def thesis(self) -> str:
        return self.tag[5:8]

    def theory(self) -> str:
        """``docs/theory/NNN-….md#anchor`` of the exercise's tag."""
        page, anchor = theory_anchor(self.tag, f"exercise {self.name}: tag")
        return f"{page.relative_to(PROJECT_ROOT).as_posix()}#{anchor}"

    def view_args(self) -> str:
        parts = [self.scene]
        if self.view:
            parts.append(f"--view {self.view}")
        if self.camera:
            parts.append(f"--camera {self.camera}")
        parts += [f"--set {s}" for s in self.sets]
        return " ".join(parts)


def theory_anchor(tag: str, what: str) -> tuple[Path, str]:
    """(page, anchor) of a tag in docs/theory; a one-line error when it resolves to none."""
    m = theory.TAG.fullmatch(tag) if isinstance(tag, str) else None
    if m is None:
        raise UsageError(f"{what} {quote(str(tag), 40)} is not a tag: allowed 'spec/NNN eq. X' "
                         "or 'spec/NNN §X' (e.g. 'spec/003 eq. 5.27')")
    anchor = theory.anchor_of(m.group(2), m.group(3))
    pages = sorted(theory.THEORY.glob(f"{m.group(1)}-*.md"))
    if not pages or f'<a id="{anchor}"></a>' not in pages[0].read_text(encoding="utf-8"):
        raise UsageError(f"{what} {quote(tag, 40)} has no anchor {anchor!r} in "
                         f"docs/theory/{m.group(1)}-*.md: allowed a tag the theory pages "
                         "explain")
    return pages[0], anchor


def _get(data: dict, key: str, kind: type | tuple, where: str, default: Any = ...) -> Any:
    if key not in data:
        if default is ...:
            raise UsageError(f"{where}: {key} is missing: allowed see docs/exercises.md")
        return default
    value = data[key]
    if kind is float and isinstance(value, int) and not isinstance(value, bool):
        value = float(value)
    if not isinstance(value, kind) or isinstance(value, bool) and kind is not bool:
        name = kind.__name__ if isinstance(kind, type) else "/".join(k.__name__ for k in kind)
        raise UsageError(f"{where}: {key} = {quote(repr(value), 40)}: allowed a {name}")
    return value


def load(path: Path, name: str | None = None) -> Exercise:
    """Read and check one exercise file (every problem one line naming the file and key);
    ``name``: the exercise's name when the file's stem is not (a folder's copy)."""
    name = name or path.stem
    where = f"exercise {quote(str(path), 60)}"
    if not _NAME.match(name):
        raise UsageError(f"{where}: the name {quote(name, 40)} is not allowed: allowed lower-case "
                         "letters, digits and '-' (at most 40)")
    try:
        text = path.read_text(encoding="utf-8")
        data = tomllib.loads(text)
    except (OSError, UnicodeDecodeError) as exc:
        raise UsageError(f"{where} cannot be read ({type(exc).__name__}): allowed a UTF-8 TOML "
                         "file") from None
    except tomllib.TOMLDecodeError as exc:
        raise UsageError(f"{where} is not valid TOML ({exc}): allowed see docs/exercises.md") \
            from None
    unknown = sorted(set(data) - _TOP_KEYS)
    if unknown:
        raise UsageError(f"{where}: unknown key {unknown[0]!r}: allowed "
                         f"{', '.join(sorted(_TOP_KEYS))}")
    tag = _get(data, "tag", str, where)
    theory_anchor(tag, f"{where}: tag")
    file = _get(data, "file", str, where)
    glsl = DEFAULT_SHADER_ROOT / file
    if Path(file).is_absolute() or ".." in Path(file).parts or not glsl.is_file():
        raise UsageError(f"{where}: file {quote(file, 60)} is not a file under glsl/: allowed a "
                         "path relative to glsl/ (e.g. common/fresnel.glsl)")
    function = _get(data, "function", str, where)
    if not function_spans(glsl.read_text(encoding="utf-8"), function):
        raise UsageError(f"{where}: glsl/{file} defines no function {quote(function, 40)}: "
                         "allowed a function defined in that file")
    view = _get(data, "view", dict, where)
    vwhere = f"{where}: [view]"
    scene = _get(view, "scene", str, vwhere)
    size = parse_size(_get(view, "size", str, vwhere, "96x54"), f"{vwhere} size")
    if max(size) > MAX_SIDE:
        raise UsageError(f"{vwhere} size {size[0]}x{size[1]} is too large: allowed at most "
                         f"{MAX_SIDE} a side (a check must stay quick)")
    sets = _get(view, "set", list, vwhere, [])
    if not all(isinstance(s, str) for s in sets):
        raise UsageError(f"{vwhere} set: allowed a list of 'NAME=VALUE' strings")
    tol = _get(data, "tolerance", dict, where, {})
    twhere = f"{where}: [tolerance]"
    ex = Exercise(
        name=name, path=path, text=text, title=_get(data, "title", str, where), tag=tag,
        file=file, function=function, task=_get(data, "task", str, where),
        expected=_get(data, "expected", str, where), scene=scene, size=size,
        view=_get(view, "view", str, vwhere, None), camera=_get(view, "camera", str, vwhere, None),
        sets=list(sets), mean_tolerance=_get(tol, "mean", float, twhere, 0.01),
        p99_tolerance=_get(tol, "p99", float, twhere, 0.05),
        probe_tolerance=_get(tol, "probe", float, twhere, 1e-4),
        stub=_get(data, "stub", str, where, None))
    if "probe" in data:
        pr = _get(data, "probe", dict, where)
        pwhere = f"{where}: [probe]"
        axes = []
        for axis in "xyz":
            a = _get(pr, axis, list, pwhere, [0.0, 0.0, 1])
            if (len(a) != 3 or not all(isinstance(v, (int, float)) for v in a)
                    or not isinstance(a[2], int) or a[2] < 1):
                raise UsageError(f"{pwhere} {axis} = {quote(repr(a), 40)}: allowed [low, high, "
                                 "count] (count a positive integer)")
            axes.append((float(a[0]), float(a[1]), int(a[2])))
        if np.prod([a[2] for a in axes]) > MAX_POINTS:
            raise UsageError(f"{pwhere}: more than {MAX_POINTS} points: allowed fewer")
        uniforms = _get(pr, "uniforms", dict, pwhere, {})
        for key, value in uniforms.items():
            if not (isinstance(value, (int, float)) and not isinstance(value, bool)
                    or isinstance(value, list) and all(isinstance(v, (int, float))
                                                       for v in value)):
                raise UsageError(f"{pwhere} uniforms: {key} = {quote(repr(value), 40)}: "
                                 "allowed a number or a list of numbers")
        ex.probe = Probe(_get(pr, "expr", str, pwhere), tuple(axes),
                         _get(pr, "version", str, pwhere, "330 core"), dict(uniforms))
    for i, w in enumerate(_get(data, "wrong", list, where, []), 1):
        wwhere = f"{where}: [[wrong]] {i}"
        if not isinstance(w, dict):
            raise UsageError(f"{wwhere}: allowed a table with body and hint")
        ex.wrong.append(Wrong(_get(w, "body", str, wwhere), _get(w, "hint", str, wwhere)))
    return ex


def names() -> list[str]:
    return sorted(p.stem for p in EXERCISES.glob("*.toml"))


def all_exercises() -> list[Exercise]:
    return [load(p) for p in sorted(EXERCISES.glob("*.toml"))]


def find(name: str) -> Exercise:
    """An exercise by name, or a teacher's own TOML file by path."""
    if name.endswith(".toml"):
        path = expand(name, "exercise file")
        if not path.is_file():
            raise UsageError(f"exercise file {quote(name, 60)} does not exist: allowed a TOML "
                             "file laid out as docs/exercises.md says")
        return load(path)
    path = EXERCISES / f"{name}.toml"
    if not _NAME.match(name) or not path.is_file():
        raise UsageError(f"unknown exercise {quote(name, 40)}: allowed "
                         f"{', '.join(names()[:3])}, … (natura exercise list lists them), or "
                         "an exercise's .toml file")
    return load(path)


def _code_mask(text: str) -> str:
    """``text`` with comments blanked (same length), so braces in comments do not count."""
    return re.sub(r"//[^\n]*|/\*.*?\*/", lambda m: re.sub(r"[^\n]", " ", m.group(0)), text,
                  flags=re.S)


def function_spans(text: str, name: str) -> list[tuple[str, int, int]]:
    """(return type, start, end) of the body of every definition of ``name`` (every overload):
    ``text[start:end]`` is what lies between its braces."""
    code = _code_mask(text)
    out = []
    for m in re.finditer(rf"^[ \t]*(\w+)[ \t]+{re.escape(name)}[ \t]*\(", code, re.M):
        depth, i = 1, m.end()
        while i < len(code) and depth:
            depth += {"(": 1, ")": -1}.get(code[i], 0)
            i += 1
        j = i
        while j < len(code) and code[j] in " \t\r\n":
            j += 1
        if j >= len(code) or code[j] != "{":  # a prototype, or a call at a line's start
            continue
        depth, k = 1, j + 1
        while k < len(code) and depth:
            depth += {"{": 1, "}": -1}.get(code[k], 0)
            k += 1
        if depth == 0:
            out.append((m.group(1), j + 1, k - 1))
    return out


def _neutral(ret: str) -> str:
    if ret == "void":
        return ""
    m = re.fullmatch(r"([iub]?)vec([234])", ret)
    if m:
        zero = {"": "0.0", "i": "0", "u": "0u", "b": "false"}[m.group(1)]
        return f"return {ret}({zero});"
    return f"return {_NEUTRAL.get(ret, f'{ret}({FLOAT_ZERO})')};"


#: a float zero as GLSL writes it
FLOAT_ZERO = "0.0"


def replace_bodies(text: str, name: str, body: Callable[[str], str]) -> str:
    """``text`` with the body of every definition of ``name`` replaced by ``body(return type)``
    (the last first, so the spans of the earlier ones hold)."""
    for ret, start, end in reversed(function_spans(text, name)):
        text = text[:start] + body(ret) + text[end:]
    return text


def stub_body(ex: Exercise, dest: Path) -> Callable[[str], str]:
    def body(ret: str) -> str:
        lines = [f"Exercise {ex.name}: {ex.title}.",
                 f"Theory: {ex.theory()} ({ex.tag}).", *_wrap(ex.task),
                 f"See it: natura window {ex.view_args()} --shaders {dest / 'glsl'}",
                 f"Grade it: natura exercise check {dest}"]
        stub = ex.stub if ex.stub is not None else _neutral(ret)
        return ("\n" + "".join(f"    // {line}\n" for line in lines)
                + (f"    {stub}\n" if stub else ""))
    return body


def _wrap(text: str, width: int = 88) -> list[str]:
    return textwrap.wrap(" ".join(text.split()), width) or [""]


def write_body(root: Path, ex: Exercise, body: str) -> None:
    """Put ``body`` in place of the function's body in the copy under ``root`` (every
    overload)."""
    path = root / ex.file
    text = path.read_text(encoding="utf-8")
    path.write_text(replace_bodies(text, ex.function, lambda ret: body), encoding="utf-8")


def render_view(ex: Exercise, root: Path, ctx) -> np.ndarray:
    """The exercise's view rendered with the shaders of ``root``, as displayed: (h, w, 3) in
    [0, 1] (tone-mapped sRGB). A compile error raises ShaderCompileError (file:line lines)."""
    if ex.scene not in SCENES:
        raise UsageError(f"exercise {ex.name}: unknown scene {quote(ex.scene, 40)}: allowed "
                         f"{', '.join(SCENES)}")
    view = None
    if ex.view is not None:
        view = get_view(ex.scene, ex.view)
    params = scene_params(ex.scene, root, ex.sets, None, view)
    camera = placed_camera(ex.scene, params, view, ex.camera)
    with open_session(ex.scene, params, root, ctx=ctx, camera=camera, sizes=[ex.size]) as session:
        with closing(render_frames(session, ex.size, 1,
                                   warmup=view.frames - 1 if view is not None else 0)) as frames:
            image = next(frames)
        srgb = to_srgb8(image[..., :3], session.scene.exposure(), params["output.tonemap"])
    return srgb.astype(np.float64) / 255.0


_PROBE_SOURCE = """#version {version}
#include "{file}"

uniform sampler2D uExercisePoints;
out vec4 fragColor;

void main() {{
    vec3 p = texelFetch(uExercisePoints, ivec2(gl_FragCoord.xy), 0).xyz;
    fragColor = vec4({expr});
}}
"""


def run_probe(ex: Exercise, root: Path, ctx, scratch: Path) -> np.ndarray:
    """The probe's expression at its points with the shaders of ``root``: (n, 4)."""

    assert ex.probe is not None
    pts = ex.probe.points()
    n = len(pts)
    w = min(n, 256)
    h = (n + w - 1) // w
    padded = np.zeros((h * w, 4), np.float32)
    padded[:n, :3] = pts
    frag = scratch / f"probe-{ex.name}.frag"
    if not frag.exists():
        frag.write_text(_PROBE_SOURCE.format(version=ex.probe.version, file=ex.file,
                                             expr=ex.probe.expr), encoding="utf-8")
    gpu = Gpu(ctx, root)
    try:
        src = gpu.texture("exercise", "points", (w, h), 4, padded.tobytes(),
                          filter=(moderngl.NEAREST, moderngl.NEAREST))
        target = gpu.target("exercise", "probe", (w, h), depth=False)
        prog = gpu.program("exercise", f"exercise-probe-{ex.name}", {},
                           vert="common/fullscreen.vert", frag=str(frag))
        src.use(0)
        prog.set("uExercisePoints", 0)
        prog.set_many({k: tuple(v) if isinstance(v, list) else v
                       for k, v in ex.probe.uniforms.items()})
        target.use()
        prog.vao().render(moderngl.TRIANGLES, vertices=3)
        raw = np.frombuffer(target.fbo.read(components=4, dtype="f4"), dtype=np.float32)
        return raw.reshape(h * w, 4)[:n].astype(np.float64)
    finally:
        gpu.release()


def image_errors(mine: np.ndarray, ref: np.ndarray) -> tuple[float, float]:
    """(mean, 99th percentile) of the per-pixel error: the largest channel difference of the
    displayed images, 0..1."""
    err = np.abs(mine - ref).max(axis=-1)
    return float(err.mean()), float(np.percentile(err, 99))


def probe_error(mine: np.ndarray, ref: np.ndarray) -> tuple[float, int]:
    """(worst error, its point): absolute, relative where the reference exceeds 1."""
    mine = np.nan_to_num(mine, nan=1e30, posinf=1e30, neginf=-1e30)
    err = (np.abs(mine - ref) / np.maximum(np.abs(ref), 1.0)).max(axis=-1)
    i = int(err.argmax())
    return float(err[i]), i


def difference_image(ref: np.ndarray, mine: np.ndarray) -> np.ndarray:
    """expected | yours | the signed difference (red: yours brighter, blue: darker)."""
    diff = (srgb_to_linear(mine) - srgb_to_linear(ref)) @ LUMINANCE
    gain, _ = choose_gain(diff)
    gap = np.full((ref.shape[0], 2, 3), 255, np.uint8)
    return np.concatenate([_as8(ref), gap, _as8(mine), gap, heat_map(diff, gain)], axis=1)


def cmd_list() -> int:
    for ex in all_exercises():
        print(f"{ex.name:22s} {ex.title}  ({ex.tag})\n{'':22s} glsl/{ex.file}: {ex.function}"
              f" · view: {ex.view_args()} · theory: {ex.theory()}")
    return 0


def cmd_start(name: str, dest_arg: str) -> int:
    """Copy the shaders to DEST/glsl with the function blanked, and render DEST/expected.png;
    all in a temporary sibling renamed at the end (nothing is left behind on an error)."""
    ex = find(name)
    if not dest_arg.strip():
        raise UsageError(f"exercise start DIR {quote(dest_arg)} is empty: allowed a new folder "
                         "name")
    dest = expand(dest_arg, "exercise start DIR")
    if os.path.lexists(dest):
        raise UsageError(f"{quote(str(dest))} already exists: allowed a new folder name "
                         "(nothing is overwritten)")
    parent = check_new_folder(dest, quote(str(dest)), "allowed a new folder name in an "
                              "existing, writable folder")
    shown = dest if dest.is_absolute() else Path(dest_arg)
    ctx = gl_context.create_headless_context()
    expected = render_view(ex, DEFAULT_SHADER_ROOT, ctx)  # before anything is written
    tmp = temp_name_in(parent)
    _LIVE.add(tmp)  # removed on an error, Ctrl-C or SIGTERM
    try:
        tmp.mkdir()  # the umask's mode, as a plain mkdir
        copy_shaders(str(tmp / "glsl"), DEFAULT_SHADER_ROOT)
        path = tmp / "glsl" / ex.file
        text = path.read_text(encoding="utf-8")
        path.write_text(replace_bodies(text, ex.function, stub_body(ex, shown)),
                        encoding="utf-8")
        write_text_atomic(tmp / MARKER, f"# exercise: {ex.name}\n{ex.text}")
        write_bytes_atomic(tmp / "expected.png", encode_png(_as8(expected)))
        if os.path.lexists(dest):  # taken meanwhile
            raise UsageError(f"{quote(str(dest))} already exists: allowed a new folder name "
                             "(nothing is overwritten)")
        os.rename(tmp, dest)
        _LIVE.discard(tmp)
    except OSError as exc:
        raise UsageError(f"cannot write the exercise to {quote(str(dest))} "
                         f"({exc.strerror or type(exc).__name__}): allowed a new folder in an "
                         "existing, writable folder, with free space") from None
    finally:
        if tmp in _LIVE:
            shutil.rmtree(tmp, ignore_errors=True)
            _LIVE.discard(tmp)
    line = _first_line(dest / "glsl" / ex.file, ex.function)
    print(f"exercise {ex.name}: {ex.title}\n"
          f"  write the body of {ex.function} in {shown / 'glsl' / ex.file}:{line}\n"
          f"  theory: {ex.theory()} ({ex.tag})\n"
          f"  task: {' '.join(ex.task.split())}\n"
          f"  expected picture: {shown / 'expected.png'} — {' '.join(ex.expected.split())}\n"
          f"  see it live: natura window {ex.view_args()} --shaders {shown / 'glsl'}\n"
          f"  grade it: natura exercise check {shown}")
    return 0


def _as8(display: np.ndarray) -> np.ndarray:
    return np.round(np.clip(display, 0.0, 1.0) * 255.0).astype(np.uint8)


def _first_line(path: Path, function: str) -> int:
    text = path.read_text(encoding="utf-8")
    spans = function_spans(text, function)
    return text.count("\n", 0, spans[0][1]) + 1 if spans else 1


def _exercise_of(folder: Path, shown: str) -> Exercise:
    """The exercise of a folder made by ``start``: Natura's own file of that name when there is
    one (a teacher's correction applies), else the copy kept in the folder."""
    marker = folder / MARKER
    if not marker.is_file() or not (folder / "glsl").is_dir():
        raise UsageError(f"{quote(shown)} holds no exercise (no {MARKER} and glsl/): allowed a "
                         "folder made by natura exercise start NAME DIR")
    text = marker.read_text(encoding="utf-8", errors="replace")
    m = re.match(r"# exercise: ([a-z0-9][a-z0-9-]{0,39})\n", text)
    if m is None:
        raise UsageError(f"{quote(str(marker))} does not name its exercise (first line "
                         "'# exercise: NAME'): allowed a folder made by natura exercise start")
    own = EXERCISES / f"{m.group(1)}.toml"
    return load(own) if own.is_file() else load(marker, m.group(1))


def cmd_check(dir_arg: str) -> int:
    if not dir_arg.strip():
        raise UsageError(f"exercise check DIR {quote(dir_arg)} is empty: allowed a folder made "
                         "by natura exercise start")
    folder = expand(dir_arg, "exercise check DIR")
    if not folder.is_dir():
        raise UsageError(f"{quote(dir_arg)} is not a folder: allowed a folder made by natura "
                         "exercise start NAME DIR")
    ex = _exercise_of(folder, dir_arg)
    root = folder / "glsl"
    ctx = gl_context.create_headless_context()
    mine = render_view(ex, root, ctx)  # a compile error stops here, as file:line lines
    ref = render_view(ex, DEFAULT_SHADER_ROOT, ctx)
    mean, p99 = image_errors(mine, ref)
    ok = mean <= ex.mean_tolerance and p99 <= ex.p99_tolerance
    lines = [f"  view {ex.view_args()} ({ex.size[0]}x{ex.size[1]}): mean error {mean:.4f} "
             f"({'≤' if mean <= ex.mean_tolerance else '>'} {ex.mean_tolerance:g}), 99th "
             f"percentile {p99:.4f} ({'≤' if p99 <= ex.p99_tolerance else '>'} "
             f"{ex.p99_tolerance:g})"]
    with tempfile.TemporaryDirectory(prefix="natura-exercise-") as scratch_name:
        scratch = Path(scratch_name)
        probe_mine = probe_ref = None
        if ex.probe is not None:
            probe_mine = run_probe(ex, root, ctx, scratch)
            probe_ref = run_probe(ex, DEFAULT_SHADER_ROOT, ctx, scratch)
            err, i = probe_error(probe_mine, probe_ref)
            ok = ok and err <= ex.probe_tolerance
            p = ex.probe.points()[i]
            at = ", ".join(f"{v:g}" for v in p)
            lines.append(f"  probe of {ex.function} at {len(ex.probe.points())} points: worst "
                         f"error {err:.3g} ({'≤' if err <= ex.probe_tolerance else '>'} "
                         f"{ex.probe_tolerance:g}) at p = ({at}): yours "
                         f"{_vec(probe_mine[i])}, expected {_vec(probe_ref[i])}")
        out = folder / "difference.png"
        write_bytes_atomic(out, encode_png(difference_image(ref, mine)), force=True)
        lines.append(f"  difference image: {out} (expected | yours | red: yours brighter, "
                     "blue: darker)")
        hint = None if ok else _known_mistake(ex, ctx, scratch, mine, probe_mine)
    print(f"exercise {ex.name}: {'PASS' if ok else 'FAIL'} — {ex.title}")
    for line in lines:
        print(line)
    if not ok:
        if hint is not None:
            print(f"  likely mistake: {' '.join(hint.split())}")
        print(f"  theory: {ex.theory()} ({ex.tag}); the task: {' '.join(ex.task.split())}")
    return 0 if ok else 1


def _vec(v: np.ndarray) -> str:
    return "(" + ", ".join(f"{x:.5g}" for x in v) + ")"


def _known_mistake(ex: Exercise, ctx, scratch: Path, mine: np.ndarray,
                   probe_mine: np.ndarray | None) -> str | None:
    """The hint of the first known wrong answer the student's function behaves like: same probe
    values (where there is a probe), else the same picture, within the tolerances."""
    for i, wrong in enumerate(ex.wrong):
        root = scratch / f"wrong-{i}"
        shutil.copytree(DEFAULT_SHADER_ROOT, root)
        write_body(root, ex, wrong.body)
        try:
            if ex.probe is not None and probe_mine is not None:
                err, _ = probe_error(probe_mine, run_probe(ex, root, ctx, scratch))
                if err <= max(ex.probe_tolerance, 1e-4):
                    return wrong.hint
            else:
                mean, p99 = image_errors(mine, render_view(ex, root, ctx))
                if mean <= ex.mean_tolerance and p99 <= ex.p99_tolerance:
                    return wrong.hint
        except NaturaError:  # a wrong answer of the file that no longer compiles: skipped
            continue
    return None

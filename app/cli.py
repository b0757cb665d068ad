"""``natura`` — the command line: one ``_add_*`` function per subcommand (``natura --help``
lists them; docs/commands.md explains each), then one ``cmd_*`` function per subcommand.

Exit codes: 0 success, 1 shader errors, 2 bad arguments or an output that cannot be written
(one line naming the culprit and what is allowed), 3 no OpenGL, 70 an internal error (a bug:
one line, please report), 130 Ctrl-C, 143 SIGTERM (temporary files removed).
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import re
import shlex
import signal
import sys
import warnings
from pathlib import Path

from . import __version__
from .errors import (
    LINE_LIMIT,
    NaturaError,
    NaturaWarning,
    ShaderCompileError,
    UsageError,
    one_line,
    quote,
    quote_path,
)
from .gpu.shaders import SHADER_ENV, resolve_shader_root

#: bounds of the counts and rates (checked before anything is allocated or rendered)
MAX_FRAMES = 100_000
MAX_REPEAT = 10_000
MAX_WARMUP = 1_000
MAX_SIZES = 32
MAX_BUDGET_MS = 100_000.0
FPS_RANGE = (0.001, 1000.0)
#: ``natura bench SCENE``'s default untimed runs and timed rounds
BENCH_WARMUP, BENCH_REPEAT = 3, 15
#: a short run (``--repeat`` at most this) warms up once by default: one untimed run compiles
#: the programs and fills the bakes and caches a timed run reads, and further warm-ups would
#: be as many runs as the few timed ones asked for
SHORT_REPEAT = 3
#: the benches that are not scenes (app.bench.NUMPY_BENCHES, named here so that --help does not
#: import the bench package) and what each measures
NUMPY_BENCH_NAMES = {"boat": "the floating boat's physics and the sailing speed polar"}
INTERNAL_ERROR = 70


class _Parser(argparse.ArgumentParser):
    """argparse, but errors are one line (and exit 2), prefixed once with ``natura:`` (by
    main), naming the subcommand and saying what is allowed."""

    def error(self, message):
        sub = self.prog.removeprefix("natura").strip()
        # argparse names a bad token unquoted: cut any long one (a 100 kB argument)
        text = re.sub(r"\S{61,}", lambda m: m.group(0)[:30] + "…" + m.group(0)[-29:],
                      one_line(message, 10**9))
        if "allowed" not in text:
            if "invalid choice" in text and "choose from" in text:
                # unquoted, so that every choice fits the line's kept end
                text = re.sub(r"\(choose from (.*)\)$",
                              lambda m: f"(allowed {m.group(1).replace(chr(39), '')})", text)
            else:
                text += f" (allowed: see {self.prog} --help)"
        raise UsageError(f"{sub}: {text}" if sub else text)


def _int_in(option: str, lo: int, hi: int):
    """An argparse type: an integer in [lo, hi], or one line naming the option."""
    def convert(text: str) -> int:
        t = text.strip()
        if not re.fullmatch(r"[+-]?\d{1,15}", t):
            raise UsageError(f"{option} {quote(text)} is not an integer: allowed {lo}..{hi}")
        value = int(t)
        if not lo <= value <= hi:
            raise UsageError(f"{option} {value} is out of range: allowed {lo}..{hi}")
        return value

    return convert


def _float_in(option: str, lo: float, hi: float, allowed: str = "", open_low: bool = False,
              out: str = "is out of range"):
    """An argparse type: a finite number in [lo, hi] ((lo, hi] with ``open_low``); the errors
    end in ``allowed`` (default: the interval)."""
    allowed = allowed or f"allowed [{lo:g}, {hi:g}]"

    def convert(text: str) -> float:
        try:
            value = float(text.strip())
        except ValueError:
            raise UsageError(f"{option} {quote(text)} is not a number: {allowed}") from None
        if not (math.isfinite(value) and (lo < value if open_low else lo <= value)
                and value <= hi):
            raise UsageError(f"{option} {quote(text)} {out}: {allowed}")
        return value

    return convert


def _positive_ms(option: str, hi: float):
    """An argparse type: a positive finite number of milliseconds, at most ``hi``."""
    return _float_in(option, 0.0, hi, f"allowed a number of ms in (0, {hi:g}]", open_low=True)


def _number(option: str):
    """An argparse type: any finite number (ranges are checked where the value is used)."""
    return _float_in(option, -math.inf, math.inf, "allowed a finite number", out="is not finite")


def _add_common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--shaders", metavar="DIR",
                   help=f"shader folder to load GLSL from (default: ${SHADER_ENV} or glsl/)")


def _add_base_options(p: argparse.ArgumentParser, camera_help: str, set_help: str) -> None:
    """--time, --camera, --set and --preset: the base every scene command starts from."""
    p.add_argument("--time", type=_float_in("--time", 0.0, 24.0), default=None, metavar="HOURS",
                   help="hour of day, 0 to 24")
    p.add_argument("--camera", default=None, metavar="X,Y,Z[,YAW[,PITCH[,FOV]]]",
                   help=camera_help)
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=VALUE",
                   help=set_help)
    p.add_argument("--preset", default=None, metavar="FILE.toml",
                   help="apply a TOML preset before --set")


def _add_scene_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--size", default=None, metavar="WxH",
                   help="image size (default 1280x720; 1..16384 a side, within what the "
                        "renderer can allocate: natura doctor says)")
    _add_base_options(p, "camera position in metres, then yaw (0 = north, 90 = east), pitch "
                      "and vertical fov in degrees",
                      "set a parameter (repeatable); see `natura params SCENE`")
    p.add_argument("--yaw", type=_number("--yaw"), default=None,
                   help="camera yaw in degrees (0 = north, 90 = east)")
    p.add_argument("--pitch", type=_float_in("--pitch", -90.0, 90.0), default=None,
                   help="camera pitch in degrees (positive looks up)")
    p.add_argument("--fov", type=_float_in("--fov", 1.0, 170.0), default=None,
                   help="vertical field of view in degrees")
    p.add_argument("--view", default=None, metavar="NAME",
                   help="start from one of the scene's views (natura scenes lists them): its "
                        "camera, hour and parameters, before --preset and --set")
    p.add_argument("--mesh", default=None, metavar="FILE",
                   help="your own mesh on the shading lab's turntable (.obj, .stl, .gltf, .glb)")
    p.add_argument("--vr", action="store_true",
                   help="VR mode: a side-by-side stereo pair, one eye per half (the village)")
    _add_common(p)


def _add_quality_options(p: argparse.ArgumentParser) -> None:
    """``--quality auto`` and its budgets (render and window; app/teach/quality.py)."""
    p.add_argument("--quality", choices=("fixed", "auto"), default="fixed",
                   help="auto: per effect and knob, the cheapest setting whose measured error "
                   "(the benches' sweeps) meets --error-budget and/or --ms-budget; prints each "
                   "pick and why (your --set values win)")
    p.add_argument("--error-budget", default=None, metavar="E|Nx",
                   help="largest error, in each knob family's own metric (printed with it), or "
                   "Nx: N times the current setting's error")
    p.add_argument("--ms-budget", type=_positive_ms("--ms-budget", MAX_BUDGET_MS), default=None,
                   metavar="MS", help="largest ms per frame, each sweep's time scaled by pixel "
                   "count to --size")
    p.add_argument("--sweeps", default=None, metavar="FILE.json",
                   help="the natura bench report to pick from (default: your newest "
                   "bench-results/SCENE-NNNN.json with sweeps, else the shipped docs/ run)")


def _apply_quality(args, params, scene_name: str | None = None,
                   size: tuple[int, int] | None = None):
    """``--quality auto``: pick per knob family from the measured sweeps, print each pick and
    why (stderr), and set the picks on ``params`` (the user's --set values win). Budgets
    without ``--quality auto`` are refused. Returns the picks (also ``args.quality_picks``, for
    the window's chart), or None."""
    given = [(option, getattr(args, attr, None)) for option, attr in (
        ("--error-budget", "error_budget"), ("--ms-budget", "ms_budget"), ("--sweeps", "sweeps"))]
    given = [(option, value) for option, value in given if value is not None]
    if getattr(args, "quality", "fixed") != "auto":
        if given:
            raise UsageError(f"{given[0][0]} needs --quality auto: allowed --quality auto with "
                             "--error-budget E and/or --ms-budget MS")
        return None
    from .teach.quality import parse_error_budget, pick

    _nonempty("--error-budget", args.error_budget, "a number ≥ 0 or Nx")
    budget = parse_error_budget(args.error_budget) if args.error_budget is not None else None
    if budget is None and args.ms_budget is None:
        raise UsageError("--quality auto needs a budget: allowed --error-budget E and/or "
                         "--ms-budget MS")
    _nonempty("--sweeps", args.sweeps, "a natura bench report (FILE.json)")
    scene_name = scene_name or args.scene
    explicit = [s.partition("=")[0].strip() for s in args.sets]
    picks = pick(scene_name, budget, args.ms_budget, args.sweeps, params=params, size=size,
                 interactive=args.command == "window", explicit=explicit)
    lines = picks.lines(params)
    picks.apply(params)
    for line in lines:
        print(line, file=sys.stderr)
    args.quality_picks = picks
    return picks


def _add_window(sub: argparse._SubParsersAction) -> None:
    """``natura window [SCENE]``: the desktop window."""
    w = sub.add_parser("window", help="open the desktop window")
    w.add_argument("scene", nargs="?", default=None)
    _add_scene_options(w)
    _add_quality_options(w)
    w.add_argument("--frames", type=_int_in("--frames", 1, MAX_FRAMES), default=None,
                   help="close after N frames (scripts, tests)")


def _add_render(sub: argparse._SubParsersAction) -> None:
    """``natura render SCENE``: headless PNG or EXR."""
    r = sub.add_parser("render", help="render headless to PNG (tone-mapped sRGB) or EXR (linear)")
    r.add_argument("scene")
    _add_scene_options(r)
    _add_quality_options(r)
    r.add_argument("--out", default=None, metavar="FILE.png|FILE.exr",
                   help="output file (default: the next free SCENE-NNNN.png here)")
    r.add_argument("--frames", type=_int_in("--frames", 1, MAX_FRAMES), default=1,
                   help=f"number of frames, 1..{MAX_FRAMES} (numbered files -0001... when > 1)")
    r.add_argument("--fps", type=_float_in("--fps", *FPS_RANGE), default=30.0,
                   help="frames per second of simulated time (0.001..1000)")
    r.add_argument("--force", action="store_true", help="overwrite existing output files")


def _add_explain(sub: argparse._SubParsersAction) -> None:
    """``natura explain TAG``: a theory section and every file:line that carries its tag."""
    ex = sub.add_parser("explain", help="an equation or section of the theory pages, and "
                        "every file:line that carries its tag",
                        description="Print the text of a tag's section of docs/theory (math as "
                        "Unicode), then every file:line in app/, glsl/ and tests/ that carries "
                        "the tag: GLSL, numpy twins, the rest of the Python, tests.")
    ex.add_argument("tag", nargs="+", metavar="TAG",
                    help='"spec/NNN eq. X" or "spec/NNN §X", e.g. "spec/003 eq. 7.18" or '
                    '"spec/003 §2.9 a" (quoted or not)')


def _add_params(sub: argparse._SubParsersAction) -> None:
    """``natura params SCENE``: a scene's parameters."""
    pp = sub.add_parser("params", help="list a scene's parameters")
    pp.add_argument("scene")
    _add_common(pp)


def _add_shaders(sub: argparse._SubParsersAction) -> None:
    """``natura shaders check|copy``: compile or copy the GLSL library."""
    s = sub.add_parser("shaders", help="check or copy the GLSL library")
    s_sub = s.add_subparsers(dest="shaders_command", parser_class=_Parser)
    sc = s_sub.add_parser("check", help="compile every program; print file:line errors")
    _add_common(sc)
    sc.add_argument("programs", nargs="*", metavar="PROGRAM",
                    help="only these programs (e.g. sky/sky; default: every one)")
    sc.add_argument("--strict", action="store_true",
                    help="also judge every preprocessed stage with the Khronos reference "
                         "compiler (glslangValidator) for its #version")
    cp = s_sub.add_parser("copy", help="copy the shader folder to DIR for editing")
    cp.add_argument("dest", metavar="DIR")


def _add_bench_rounds(b: argparse.ArgumentParser) -> None:
    """The bench's untimed and timed rounds (--warmup, --repeat)."""
    b.add_argument("--warmup", type=_int_in("--warmup", 0, MAX_WARMUP), default=None,
                   help=f"untimed runs first, 0..{MAX_WARMUP} (default {BENCH_WARMUP}; 1 "
                   f"with --repeat {SHORT_REPEAT} or fewer)")
    b.add_argument("--repeat", type=_int_in("--repeat", 1, MAX_REPEAT), default=None,
                   help=f"timed rounds (every pass once per round, shuffled; the median and "
                   f"quartiles are reported), 1..{MAX_REPEAT} (default {BENCH_REPEAT}, fewer — "
                   "at least 5 — once the rounds have taken 6 s)")


def _add_bench_scene_table(b: argparse.ArgumentParser) -> None:
    """A scene's table, sweeps and budget (--sizes, --no-sweep, --budget), then --force and
    --window (in this order: the help lists them so)."""
    b.add_argument("--sizes", default=None, metavar="WxH,WxH,...",
                   help="image sizes of the scene's table "
                   "(planet: the thesis's 800x600,1280x720,1920x1080)")
    b.add_argument("--no-sweep", action="store_true",
                   help="time the passes only, skip the scene's sweeps")
    b.add_argument("--budget", type=_positive_ms("--budget", MAX_BUDGET_MS), default=None,
                   metavar="MS",
                   help="frame budget in ms: the passes over it, and the parameter changes "
                   "from the scene's sweeps that bring the frame under it at the least error")
    b.add_argument("--force", action="store_true",
                   help="overwrite an existing report and its chart")
    b.add_argument("--window", action="store_true",
                   help="frames per second in a real window (needs a display; xvfb-run without "
                   "one) at --size (default 640x360): --repeat timed frames (default 100) "
                   "after --warmup untimed ones (default 10), with dynamic resolution as "
                   "output.scale sets it; the median frame time, fps and the scale reached, "
                   "into bench-results/SCENE-window-NNNN.json")


def _add_bench(sub: argparse._SubParsersAction) -> None:
    """``natura bench NAME``: time a scene's passes, or run a numpy bench."""
    b = sub.add_parser("bench", help="time each pass of a scene, or run the boat bench; "
                       "write JSON",
                       description="Time each pass of a scene (and its sweeps), or run a numpy "
                       "bench that is not a scene: " + ", ".join(
                           f"{name} ({about})" for name, about in NUMPY_BENCH_NAMES.items())
                       + ". A numpy bench takes --out, --quick and --force only.")
    b.add_argument("scene", metavar="NAME",
                   help="a scene (see natura scenes) or a numpy bench: "
                   + ", ".join(NUMPY_BENCH_NAMES))
    _add_scene_options(b)
    _add_bench_rounds(b)
    b.add_argument("--out", default=None, metavar="FILE.json",
                   help="default: bench-results/NAME-NNNN.json (a numpy bench's charts beside "
                   "it: FILE.png, FILE-polar.png)")
    b.add_argument("--quick", action="store_true",
                   help="numpy benches (boat): a reduced run, the same figures on fewer masses, "
                   "steps and poses")
    _add_bench_scene_table(b)


def _add_compare_sides(c: argparse.ArgumentParser) -> None:
    """Sides A and B, and how the image lays them out (--a, --b, --layout, --wipe)."""
    c.add_argument("--a", dest="a_sets", action="extend", nargs="+", default=[],
                   metavar="NAME=VALUE",
                   help="side A's parameters over the base (repeatable; several after one --a)")
    c.add_argument("--b", dest="b_sets", action="extend", nargs="+", default=[],
                   metavar="NAME=VALUE", help="side B's parameters over the base")
    c.add_argument("--layout", choices=("side", "wipe"), default="side",
                   help="side: A | B | difference; wipe: A left and B right of a line, beside "
                   "the difference")
    c.add_argument("--wipe", type=_float_in("--wipe", 0.0, 1.0), default=None, metavar="0..1",
                   help="where the wipe's line is, as a share of the width (default 0.5)")


def _add_compare(sub: argparse._SubParsersAction) -> None:
    """``natura compare SCENE``: two parameter sets side by side."""
    c = sub.add_parser("compare", help="two parameter sets of a scene side by side: both "
                       "images, their ms, the difference and each one's error; PNG + JSON",
                       description="Render a scene with two parameter sets A and B (each over "
                       "the same base: defaults, --preset, --set, --time, --camera), time both "
                       "in interleaved rounds, and write one PNG: A | B | the signed, magnified "
                       "difference B − A (or a wipe between A and B beside it) with a caption "
                       "(both ms, their ratio, each one's error against the scene's reference "
                       "where it has one, the gain, the renderer), and every figure as JSON "
                       "beside it. The caption is printed too.")
    c.add_argument("scene")
    _add_scene_options(c)
    for action in c._actions:
        if action.dest == "size":
            action.help = f"image size of each side (default {COMPARE_SIZE})"
    _add_compare_sides(c)
    c.add_argument("--rounds", type=_int_in("--rounds", 1, MAX_COMPARE_ROUNDS), default=5,
                   help=f"timed rounds, each frame of A and of B once, 1..{MAX_COMPARE_ROUNDS} "
                   "(default 5; the median and quartiles are reported)")
    c.add_argument("--no-reference", action="store_true",
                   help="skip the reference renders (no error figures; faster)")
    c.add_argument("--out", default=None, metavar="FILE.png",
                   help="output image (default: the next free compare-SCENE-NNNN.png here); "
                   "the JSON is FILE.json beside it")
    c.add_argument("--force", action="store_true", help="overwrite existing PNG and JSON")


def _add_report(sub: argparse._SubParsersAction) -> None:
    """``natura report SCENE``: the HTML handout of a scene's methods."""
    rp = sub.add_parser("report", help="write an HTML handout: a scene's methods side by side "
                        "with their times, errors, charts and thesis sections",
                        description="Render every method of a scene (see --methods) in "
                        "interleaved timed rounds and write DIR/"
                        "index.html: the images with their ms, error against the scene's "
                        "reference and the command that reproduces each, the differences "
                        "against the first method, the time-against-error charts, and the "
                        "parameters grouped by thesis section with the digest's paragraph. "
                        "Images are inline: the page alone is the handout, offline.")
    rp.add_argument("scene")
    rp.add_argument("--out", default=None, metavar="DIR",
                    help="the handout's folder: new or empty (default: the next free "
                    "SCENE-report-NNNN here); it gets index.html and report.json")
    from .teach.methods import AXES  # names only: no numpy, no GL

    rp.add_argument("--methods", default=None, metavar="A,B,...",
                    help="a subset of the scene's methods, the first the base of the "
                    "differences (default: all; the sky and the probe have one) — "
                    + "; ".join(f"{a.scene}: {','.join(v for v, _ in a.choices)} "
                                f"({a.param})" for a in AXES.values()))
    rp.add_argument("--size", default=None, metavar="WxH", help="each image's size "
                    "(default 320x180)")
    rp.add_argument("--rounds", type=_int_in("--rounds", 1, MAX_COMPARE_ROUNDS), default=5,
                    help=f"timed rounds of each method with the first, 1..{MAX_COMPARE_ROUNDS} "
                    "(default 5)")
    _add_base_options(rp, "camera position in metres, then yaw, pitch and fov in degrees",
                      "set a parameter for every method (repeatable)")
    rp.add_argument("--force", action="store_true",
                    help="write into a non-empty DIR (its index.html and report.json are "
                    "replaced, nothing else)")
    _add_common(rp)
    rp.set_defaults(yaw=None, pitch=None, fov=None, vr=False, mesh=None)


def _add_exercise(sub: argparse._SubParsersAction) -> None:
    """``natura exercise list|start|check``: the graded shader exercises."""
    ex = sub.add_parser("exercise", help="graded shader exercises: list, start NAME DIR, "
                        "check DIR (docs/exercises.md)")
    ex_sub = ex.add_subparsers(dest="exercise_command", parser_class=_Parser)
    ex_sub.add_parser("list", help="the exercises, their functions, views and theory pages")
    es = ex_sub.add_parser("start", help="copy the shaders to DIR/glsl with one function "
                           "blanked, and render DIR/expected.png")
    es.add_argument("name", metavar="NAME", help="an exercise (natura exercise list) or a "
                    "teacher's .toml file")
    es.add_argument("dest", metavar="DIR", help="a new folder")
    ec = ex_sub.add_parser("check", help="render DIR's version against Natura's: PASS or FAIL "
                           "(exit 0 or 1), the errors, DIR/difference.png")
    ec.add_argument("dest", metavar="DIR", help="a folder made by natura exercise start")


def build_parser() -> argparse.ArgumentParser:
    """The whole command line: one ``_add_*`` function per subcommand, in help order."""
    parser = _Parser(prog="natura",
                     description="Natural effects from five graphics theses, live and measured.")
    parser.add_argument("--version", action="version", version=f"natura {__version__}")
    sub = parser.add_subparsers(dest="command", parser_class=_Parser)
    _add_window(sub)
    _add_render(sub)
    sub.add_parser("scenes", help="list the scenes")
    _add_explain(sub)
    _add_params(sub)
    _add_shaders(sub)
    sub.add_parser("doctor", help="the driver report: context, the paths the scenes take on "
                   "it, the shader compilers' verdict, what the window and the tests lack")
    _add_bench(sub)
    _add_compare(sub)
    _add_report(sub)
    _add_exercise(sub)
    return parser


def cmd_exercise(args) -> int:
    from .teach import exercise

    if args.exercise_command == "list":
        return exercise.cmd_list()
    if args.exercise_command == "start":
        return exercise.cmd_start(args.name, args.dest)
    if args.exercise_command == "check":
        return exercise.cmd_check(args.dest)
    raise UsageError("exercise: a subcommand is needed: allowed list, start, check")


def _nonempty(option: str, value: str | None, allowed: str) -> None:
    """An option given as '' is refused (it would otherwise silently mean its default)."""
    if value is not None and not value.strip():
        raise UsageError(f"{option} {quote(value)} is empty: allowed {allowed}")


def _check_shader_arg(value: str | None) -> None:
    """``--shaders DIR`` checked here first, so every odd path is one short line."""
    if value is None:
        return
    _nonempty("--shaders", value, "a folder laid out like glsl/")
    from .imageio import expand

    root = expand(value, "--shaders")
    try:
        ok = root.is_dir()
    except (OSError, ValueError):
        ok = False
    if not ok:
        what = "does not exist" if not os.path.lexists(root) else "is not a folder"
        raise UsageError(f"--shaders {quote(value)} {what}: allowed a folder laid out like glsl/ "
                         "(see natura shaders copy)")


def _session_inputs(args, scene_name: str, opening: bool = False, size=(1280, 720)):
    """Validate everything the user gave (scene, parameters, camera, size: ``size`` without
    ``--size``) before any GL work. ``opening`` (the window and render): with no ``--view``, the
    scene's own opening view (``Scene.default_view``) is applied; ``--view none`` applies none."""
    from .runtime import parse_size, placed_camera, scene_params
    from .scenes import SCENES

    if scene_name not in SCENES:
        raise UsageError(f"unknown scene {quote(scene_name, 40)}: allowed {', '.join(SCENES)}")
    _nonempty("--size", args.size, "WxH, e.g. 1280x720")
    _nonempty("--camera", args.camera, "X,Y,Z[,YAW[,PITCH[,FOV]]]")
    _nonempty("--preset", args.preset, "a TOML preset file")
    _check_shader_arg(args.shaders)
    size = parse_size(args.size) if args.size is not None else size
    view = None
    name = getattr(args, "view", None)
    if name is None and opening:
        name = SCENES[scene_name].default_view
    if name is not None and name != "none":
        from .scenes.views import get_view

        _nonempty("--view", name, "a view name (natura scenes lists them)")
        view = get_view(scene_name, name)
    params = scene_params(scene_name, args.shaders, args.sets, args.preset, view)
    if args.time is not None:
        if "time.hour" not in params:
            raise UsageError(f"--time: scene {scene_name!r} has no time of day: allowed with the "
                             "scenes that have a day–night sky (see natura scenes)")
        params.set("time.hour", args.time % 24.0)
    if getattr(args, "vr", False):
        if "vr.enabled" not in params:
            vr_scenes = [n for n, c in SCENES.items() if any(e.name == "vr" for e in c.effects)]
            raise UsageError(f"--vr: scene {scene_name!r} has no VR mode: allowed "
                             f"{', '.join(vr_scenes) or 'none'}")
        params.set("vr.enabled", True)
    camera = placed_camera(scene_name, params, view, args.camera)
    camera.set(yaw=args.yaw, pitch=args.pitch, fov=args.fov)
    _apply_quality(args, params, scene_name, size)
    args.resolved_view = view
    return params, camera, size


def _user_mesh(args, scene_name: str):
    """``--mesh FILE`` loaded and checked before any GL work (one-line errors), or None."""
    path = getattr(args, "mesh", None)
    if path is None:
        return None
    from .scenes import get_scene

    _nonempty("--mesh", path, "a mesh file (.obj, .stl, .gltf, .glb)")
    takers = [e for e in get_scene(scene_name).effects if hasattr(e, "set_user_mesh")]
    if not takers:
        raise UsageError(f"--mesh: scene {scene_name!r} shows no mesh of yours: allowed with the "
                         "shading and surfaces scenes (natura render shading --mesh FILE)")
    from .sim.mesh_files import load_mesh

    return load_mesh(path)


def attach_mesh(scene, mesh) -> None:
    """Hand a loaded ``--mesh`` to the effect of ``scene`` that shows one."""
    if mesh is None:
        return
    for effect in scene.instances:
        if hasattr(effect, "set_user_mesh"):
            effect.set_user_mesh(mesh)


def frame_path(base: Path, i: int, frames: int) -> Path:
    """The name of frame ``i`` (1-based) of ``frames``: ``base`` itself for one frame, else
    ``stem-0001.suffix`` ... (wider when there are more than 9999 frames)."""
    if frames == 1:
        return base
    return base.with_name(f"{base.stem}-{i:0{max(4, len(str(frames)))}d}{base.suffix}")


def cmd_render(args) -> int:
    from .imageio import OutputError, check_output_path, next_free_path, write_image
    from .runtime import end_progress, open_session, render_frames

    _nonempty("--out", args.out, "a file name ending in .png or .exr")
    params, camera, size = _session_inputs(args, args.scene, opening=True)
    mesh = _user_mesh(args, args.scene)
    if args.out is not None:
        base = check_output_path(args.out, force=True)  # suffix and folder; per-file check below
    else:
        base = check_output_path(next_free_path(Path("."), args.scene, ".png"))
    for i in range(1, args.frames + 1):  # every name before any work (bounded: MAX_FRAMES)
        # the frames share base's folder, which the check above probed once
        check_output_path(frame_path(base, i, args.frames), force=args.force, probe_folder=False)
    session = open_session(args.scene, params, args.shaders, camera=camera, sizes=[size])
    attach_mesh(session.scene, mesh)
    written = []
    view = getattr(args, "resolved_view", None)
    frames = render_frames(session, size, args.frames, args.fps, progress=args.frames > 1,
                           warmup=view.frames - 1 if view is not None else 0)
    try:
        for i, image in enumerate(frames, 1):
            out = frame_path(base, i, args.frames)
            try:
                write_image(out, image, session.scene.exposure(), params["output.tonemap"],
                            force=args.force)
            except OutputError as exc:
                if not written or exc.path is None:
                    raise
                # the frames before it are whole images: kept, and their names go to stdout
                kept = f"frames 1–{i - 1} are" if i > 2 else "frame 1 is"
                raise OutputError(f"cannot write frame {i} {quote_path(exc.path, 50)} "
                                  f"({exc.why}): {exc.allowed}; {kept} kept (named on "
                                  "stdout)") from None
            written.append(out)
    finally:
        frames.close()  # frees its target now, while the session is alive
        end_progress()
        session.release()
        for out in written:  # after the progress line has ended; also when interrupted
            print(out)
    return 0


def _picks_a_scene(args) -> bool:
    """Whether the window opens on the scene picker: no scene named, and nothing given that
    belongs to a scene (parameters, a view, a preset, a time, a camera, a mesh)."""
    return args.scene is None and all(
        getattr(args, name, None) in (None, [], False)
        for name in ("sets", "view", "preset", "time", "camera", "mesh", "vr"))


def cmd_window(args) -> int:
    from .scenes import DEFAULT_SCENE

    scene_name = args.scene if args.scene is not None else DEFAULT_SCENE
    params, camera, size = _session_inputs(args, scene_name, opening=True)
    mesh = _user_mesh(args, scene_name)
    from .ui.window import display_problem, run_window

    problem = display_problem()
    if problem is None and _picks_a_scene(args):
        from .ui.picker import pick_scene

        chosen = pick_scene(DEFAULT_SCENE, size)
        if chosen is None:
            return 0
        scene_name = chosen
        params, camera, size = _session_inputs(args, scene_name, opening=True)
    if problem is not None:
        from .imageio import check_output_path, next_free_path, write_image
        from .runtime import open_session, render_frames

        # the picture's name and folder are checked before the message and the render
        out = check_output_path(next_free_path(Path("."), f"natura-{scene_name}", ".png"))
        print(f"natura: no display ({problem}): "
              f"rendering {scene_name!r} headless instead", file=sys.stderr)
        session = open_session(scene_name, params, args.shaders, camera=camera, sizes=[size])
        attach_mesh(session.scene, mesh)
        frames = render_frames(session, size)
        try:
            image = next(frames)
            write_image(out, image, session.scene.exposure(), params["output.tonemap"])
        finally:
            frames.close()
            session.release()
        print(out)
        return 0
    return run_window(scene_name, params, camera, size,
                      shader_root=resolve_shader_root(args.shaders), frames=args.frames,
                      setup=(lambda scene: attach_mesh(scene, mesh)) if mesh is not None
                      else None, quality=getattr(args, "quality_picks", None))


def cmd_explain(args) -> int:
    from .teach.theory import explain

    print(explain(" ".join(args.tag)))
    return 0


def cmd_scenes(args) -> int:
    from .scenes import DEFAULT_SCENE, SCENES
    from .scenes.views import views_of

    for name, cls in SCENES.items():
        mark = " (default)" if name == DEFAULT_SCENE else ""
        effects = ", ".join(e.name for e in cls.effects)
        print(f"{name:10s} {cls.title}{mark}\n{'':10s} effects: {effects}\n"
              f"{'':10s} {cls.description}")
        for view in views_of(name):
            print(f"{'':10s} --view {view.name}: {view.title} — {view.lesson}")
    return 0


def cmd_params(args) -> int:
    from .runtime import scene_params
    from .scenes import SCENES

    if args.scene not in SCENES:
        raise UsageError(f"unknown scene {quote(args.scene, 40)}: allowed {', '.join(SCENES)}")
    _check_shader_arg(args.shaders)
    params = scene_params(args.scene, args.shaders)
    for group, items in params.groups().items():
        print(f"[{group}]")
        for p in items:
            value = params[p.name]
            rng = p.allowed() + "".join(f"; and {j.text}" for j in p.joint)
            unit = f" {p.unit}" if p.unit else ""
            where = f"  ({p.section})" if p.section else ""
            print(f"  {p.name} = {p.written(value)}{unit}    {rng}\n      {p.doc}{where}")
    return 0


def cmd_shaders(args) -> int:
    if args.shaders_command == "copy":
        from .teach.editor import copy_shaders  # a temporary sibling renamed at the end

        dest = copy_shaders(args.dest)
        where = shlex.quote(str(dest))
        print(f"{dest}\nedit there, then: natura --shaders {where} window sky (--shaders goes "
              f"before or after any command that reads shaders; or export {SHADER_ENV}={where})")
        return 0
    if args.shaders_command != "check":
        raise UsageError("shaders: a subcommand is needed: allowed check, copy")
    from .gpu.context import caps_of, create_headless_context
    from .gpu.shaders import ShaderLibrary

    _check_shader_arg(args.shaders)
    root = resolve_shader_root(args.shaders)
    if args.strict:  # before any work: a check that cannot run must not pass (exit 3)
        from .gpu.strict import require_validator

        require_validator()
    ctx = create_headless_context()
    caps = caps_of(ctx)
    library = ShaderLibrary(ctx, root)
    specs = program_specs()
    owners = _spec_effects()
    if args.programs:
        names = dict.fromkeys(s.name for s in specs)
        unknown = [p for p in args.programs if p not in names]
        if unknown:
            raise UsageError(f"shaders check: no program {quote(unknown[0])}: allowed "
                             f"{', '.join(list(names)[:6])}, … (natura shaders check lists "
                             "them all)")
        specs = [s for s in specs if s.name in args.programs]
    failures = params_broken = 0
    for spec in specs:
        if spec.requires_compute and not caps.compute:
            print(f"skip {spec.name}: needs compute shaders (GL 4.3), "
                  f"this context has {caps.describe()}")
            continue
        try:
            prog = library.program(spec.name, dict(spec.defines), **spec.stages())
        except NaturaError as exc:
            failures += 1
            for line in str(exc).splitlines():
                print(line)
            continue
        broken = _param_problems(library, prog, owners.get(spec), spec)
        if broken:  # it compiles, but render refuses it: the same rule, as file:line lines
            params_broken += 1
            for error in broken:
                print(error)
        else:
            print(f"ok   {spec.name}{_defines_label(spec)}")
    print(f"{len(specs) - failures} of {len(specs)} programs compiled "
          f"({caps.describe()}, shaders from {root})"
          + (f"; {params_broken} with a broken @param comment (render refuses it)"
             if params_broken else ""))
    failures += params_broken
    if args.strict:
        failures += _strict_check(library, specs)
    return 1 if failures else 0


def program_specs() -> list:
    """Every program the app builds, each variant once: the effects' programs (their
    variants included), the bench's reference pass and the window's display pass."""
    from .bench import TRIVIAL
    from .ui.display import DISPLAY

    return list(dict.fromkeys([*_spec_effects(), TRIVIAL, DISPLAY]))


def _spec_effects() -> dict:
    """Each effect program's effect class (the group its ``@param`` uniforms belong to)."""
    from .scenes import SCENES

    owners: dict = {}
    for scene in SCENES.values():
        for effect in scene.effects:
            for spec in effect.programs:
                owners.setdefault(spec, effect)
    return owners


def _param_problems(library, prog, effect, spec) -> list:
    """The ``@param`` annotations of a compiled program's files that render refuses (the same
    parser), as ``file:line: message`` errors; files that are not text are the compile's."""
    from .gpu.shaders import ShaderError, SourceError, read_source
    from .params import parse_glsl_annotations

    group = effect.name if effect is not None else spec.name.split("/")[0]
    out = []
    for path in prog.files:
        try:
            text = read_source(path)
        except SourceError:
            continue
        found: list[tuple[int, str]] = []
        where = library.display(path)
        parse_glsl_annotations(text, group, where, getattr(effect, "spec", ""), found)
        out.extend(ShaderError(where, line, message) for line, message in found)
    return out


def _defines_label(spec) -> str:
    return (" [" + ", ".join(f"{k}={v}" for k, v in spec.defines) + "]") if spec.defines else ""


def strict_verdict(library, specs):
    """For natura doctor: (programs passing, programs, stages, validator) from glslangValidator
    over every preprocessed stage, or None when it is not installed."""
    from .gpu import strict

    validator = strict.validator_path()
    if validator is None:
        return None
    results = strict.check_programs(library, specs, validator, accepted_dir=_accepted_dir())
    return (sum(r.ok for r in results), len(results), sum(r.stages for r in results),
            f"{strict.VALIDATOR} {strict.validator_version(validator)}")


def cmd_doctor(args) -> int:
    from .teach import doctor
    from .ui.window import display_problem

    return doctor.run(program_specs(), display_problem(), strict_check=strict_verdict)


def _accepted_dir():
    """Where the strict check remembers the programs glslang accepted: beside the bakes."""
    from .bakes.cache import default_cache_dir

    return default_cache_dir() / "strict"


def _strict_check(library, specs) -> int:
    """glslangValidator over every preprocessed stage (app.gpu.strict); the failures."""
    from .gpu import strict

    validator = strict.require_validator()  # checked before the compile: removed since?
    results = strict.check_programs(library, specs, validator, accepted_dir=_accepted_dir())
    stages = sum(r.stages for r in results)
    bad = [r for r in results if not r.ok]
    for r in bad:
        print(f"strict FAIL {r.spec.name}{_defines_label(r.spec)}")
        for error in r.errors:
            print(f"  {error}")
    print(f"strict: {len(results) - len(bad)} of {len(results)} programs ({stages} stages) pass "
          f"{strict.VALIDATOR} {strict.validator_version(validator)}")
    return len(bad)


def _bench_outputs(args, charts: tuple[str, ...] = ()) -> tuple[Path, list[Path]]:
    """The report's path and its charts' (``charts`` are suffixes put after the report's stem:
    ``.png`` beside a scene's sweeps, ``.png`` and ``-polar.png`` beside the boat bench's), all
    checked before anything runs: nothing is overwritten without --force."""
    from .imageio import check_output_path, next_free_path

    if args.out is not None:
        _nonempty("--out", args.out, "a file name ending in .json")
        path = check_output_path(args.out, force=args.force, suffixes=(".json",))
    else:
        folder = Path("bench-results")
        if os.path.lexists(folder) and not folder.is_dir():
            raise UsageError("bench-results exists and is not a folder: allowed --out FILE.json, "
                             "or move that file away")
        if not folder.is_dir():
            from .imageio import _can_create_in

            if not _can_create_in(Path(".")):
                raise UsageError(f"the folder {quote(os.getcwd())} is not writable (for "
                                 "bench-results/): allowed --out FILE.json in a writable folder")
            path = folder / f"{args.scene}-0001.json"
        else:
            also = tuple(dict.fromkeys((".png", *charts)))
            path = check_output_path(next_free_path(folder, args.scene, ".json", also=also),
                                     suffixes=(".json",))
    chart_paths = [path.with_name(path.stem + suffix) for suffix in charts]
    if path.parent.is_dir():
        for chart in chart_paths:
            check_output_path(chart, force=args.force)
    return path, chart_paths


def _make_results_folder(args, path: Path) -> None:
    """bench-results/, made only once the bench has run (not when --out names the file)."""
    if args.out is None and not path.parent.is_dir():
        try:
            path.parent.mkdir(exist_ok=True)
        except OSError as exc:
            raise UsageError(f"cannot create {quote(str(path.parent))} ({exc.strerror}): "
                             "allowed --out FILE.json in a writable folder") from None


#: ``natura bench`` options that only a scene takes: (option, its attribute, its value when
#: not given)
_SCENE_BENCH_OPTIONS = (
    ("--size", "size", None), ("--sizes", "sizes", None), ("--budget", "budget", None),
    ("--warmup", "warmup", None), ("--repeat", "repeat", None), ("--no-sweep", "no_sweep", False),
    ("--time", "time", None), ("--camera", "camera", None), ("--yaw", "yaw", None),
    ("--pitch", "pitch", None), ("--fov", "fov", None), ("--set", "sets", []),
    ("--preset", "preset", None), ("--shaders", "shaders", None), ("--mesh", "mesh", None),
    ("--window", "window", False),
)


def cmd_numpy_bench(args) -> int:
    """``natura bench boat``: numpy only (no GL context), every section's report in one JSON,
    a chart per section beside it, every summary printed."""
    import json
    import time

    from .bench import NUMPY_BENCHES
    from .imageio import write_text_atomic

    bench = NUMPY_BENCHES[args.scene]
    for option, attr, unset in _SCENE_BENCH_OPTIONS:
        if getattr(args, attr) != unset:
            raise UsageError(f"bench {bench.name}: {option} is for scene benches ({bench.name} "
                             "is a numpy bench: no image, no GL): allowed with "
                             f"{bench.name} --out FILE.json, --quick, --force")
    path, chart_paths = _bench_outputs(args, bench.chart_suffixes())
    how = "quick run" if args.quick else "full run; --quick for a reduced one"
    start = time.perf_counter()

    def progress(title: str) -> None:
        print(f"running the {bench.name} bench: {title} ({how})", file=sys.stderr, flush=True)

    report = bench.run(quick=args.quick, progress=progress)
    report["charts"] = {key: chart.name for (key, *_), chart in zip(bench.sections, chart_paths)}
    _make_results_folder(args, path)
    path = write_text_atomic(path, json.dumps(report, indent=2) + "\n", force=args.force)
    for (key, _, _, title), chart in zip(bench.sections, chart_paths):
        module = bench.module(key)
        print(f"{title} ({report['seconds'][key]:.1f} s):")
        print(module.summary(report[key]), flush=True)
        module.chart(report[key], chart, force=args.force)
        print(f"chart → {chart}")
    print(f"numpy {bench.name} bench, {'quick' if args.quick else 'full'} run, "
          f"{time.perf_counter() - start:.1f} s → {path}")
    return 0


def cmd_window_bench(args) -> int:
    """``natura bench SCENE --window``: fps in a real window (app/ui/window_bench.py)."""
    import json

    from .imageio import write_text_atomic
    from .ui.window import display_problem
    from .ui.window_bench import WINDOW_FRAMES, WINDOW_WARMUP, bench_window, summary

    for option, attr in (("--sizes", "sizes"), ("--budget", "budget"), ("--quick", "quick")):
        if getattr(args, attr):
            raise UsageError(f"bench --window: {option} is for the timed passes, not the window: "
                             "allowed with --window --size, --repeat N frames, --warmup N, "
                             "--set, --camera, --time, --out")
    params, camera, size = _session_inputs(args, args.scene, size=(640, 360))
    mesh = _user_mesh(args, args.scene)
    problem = display_problem()
    if problem is not None:
        raise UsageError(f"bench --window needs a display ({problem}): allowed under X, or "
                         f"xvfb-run -a natura bench {args.scene} --window")
    path, _ = _bench_outputs(argparse.Namespace(**{**vars(args),
                                                   "scene": f"{args.scene}-window"}))
    report = bench_window(
        args.scene, params, camera, size,
        frames=WINDOW_FRAMES if args.repeat is None else args.repeat,
        warmup=WINDOW_WARMUP if args.warmup is None else args.warmup,
        shader_root=resolve_shader_root(args.shaders),
        setup=(lambda scene: attach_mesh(scene, mesh)) if mesh is not None else None,
        progress=lambda text: print(f"natura: bench --window {args.scene}: {text}",
                                    file=sys.stderr, flush=True))
    _make_results_folder(args, path)
    path = write_text_atomic(path, json.dumps(report, indent=2) + "\n", force=args.force)
    for line in summary(report):
        print(line)
    print(f"{report['renderer']} → {path}")
    return 0


def cmd_bench(args) -> int:
    from .bench import (
        NUMPY_BENCHES,
        ROUNDS_BUDGET_S,
        accounting_lines,
        bench_scene,
        scene_sweeps,
        write_report,
    )
    from .runtime import open_session, parse_size
    from .scenes import SCENES

    if args.scene in NUMPY_BENCHES:
        return cmd_numpy_bench(args)
    if args.scene not in SCENES:
        raise UsageError(f"unknown scene or bench {quote(args.scene, 40)}: allowed "
                         f"{', '.join([*SCENES, *NUMPY_BENCHES])}")
    if args.window:
        return cmd_window_bench(args)
    if args.quick:
        raise UsageError(f"bench {args.scene}: --quick is for the numpy benches "
                         f"({', '.join(NUMPY_BENCHES)}): allowed with a scene --repeat N and "
                         "--warmup N for a shorter run, --no-sweep to skip its sweeps")
    repeat = BENCH_REPEAT if args.repeat is None else args.repeat
    if args.warmup is not None:
        warmup = args.warmup
    else:
        warmup = 1 if args.repeat is not None and args.repeat <= SHORT_REPEAT else BENCH_WARMUP
    params, camera, size = _session_inputs(args, args.scene, size=(640, 360))
    mesh = _user_mesh(args, args.scene)
    table_sizes = None
    if args.sizes is not None:
        items = args.sizes.split(",")
        if not args.sizes.strip() or len(items) > MAX_SIZES:
            raise UsageError(f"--sizes {quote(args.sizes)} has {len(items)} sizes: allowed "
                             f"1..{MAX_SIZES} comma-separated WxH")
        table_sizes = [parse_size(t, "--sizes item") for t in items]
    sweeps = None if args.no_sweep else scene_sweeps(args.scene)
    # a sweep module with several charts lists their suffixes (CHART_SUFFIXES, ".png" first):
    # all are checked before anything runs, and its chart() writes them all
    suffixes = tuple(getattr(sweeps, "CHART_SUFFIXES", (".png",))) if sweeps is not None else ()
    path, _ = _bench_outputs(args, suffixes)
    session = open_session(args.scene, params, args.shaders, camera=camera,
                           sizes=[size, *(table_sizes or ())])
    attach_mesh(session.scene, mesh)
    try:
        # a slow scene stops adding timed rounds after ROUNDS_BUDGET_S (at least 5 rounds)
        # unless --repeat asked for a number
        budget = ROUNDS_BUDGET_S if args.repeat is None else None
        report = bench_scene(session, size, warmup, repeat, budget_s=budget)
        if sweeps is not None:
            print(f"running the {args.scene} speed/accuracy sweeps "
                  "(this takes a while on a software renderer)", file=sys.stderr)
            kwargs = {"sizes": table_sizes} if table_sizes else {}
            report["sweep"] = sweeps.sweep(session, size, warmup=min(warmup, 2),
                                           repeat=max(3, repeat // 2), **kwargs)
    finally:
        session.release()
    _make_results_folder(args, path)
    path = write_report(report, str(path), force=args.force)
    print(f"{'pass':24s} {'median [p25–p75] ms':>30s}   ×full-screen pass [p25–p75]")
    for name, t in report["passes"].items():
        spread = f"{t['median_ms']:.3f} [{t['p25_ms']:.3f}–{t['p75_ms']:.3f}]"
        print(f"{name:24s} {spread:>30s}   ×{t['ratio_to_fullscreen']:.2f} "
              f"[{t['ratio_to_fullscreen_p25']:.2f}–{t['ratio_to_fullscreen_p75']:.2f}]")
    for line in accounting_lines(report):
        print(line)
    stats = report.get("pipeline_statistics", {})
    if not stats.get("supported"):
        print(f"no pipeline statistics: {stats.get('reason')}")
    if sweeps is not None and "sweep" in report:
        chart_path = Path(path).with_suffix(".png")
        sweeps.chart(report, chart_path, force=args.force)
        print(sweeps.summary(report))
        for suffix in suffixes:
            print(f"chart → {path.with_name(path.stem + suffix)}")
    if args.budget is not None:
        from .bench.budget import budget_view

        for line in budget_view(report, args.budget):
            print(line)
        if args.no_sweep and scene_sweeps(args.scene) is not None:
            print(f"budget: the parameter changes come from the {args.scene} sweeps, "
                  "which --no-sweep skips: run without it")
    print(f"{report['renderer']}, {size[0]}x{size[1]} → {path}")
    return 0


#: ``natura compare``'s default size of each side, and its bound on --rounds
COMPARE_SIZE = "640x360"
MAX_COMPARE_ROUNDS = 1000


def cmd_compare(args) -> int:
    """``natura compare SCENE --a ... --b ...``: every input and both output names checked
    before anything is rendered (app/teach/compare.py does the work)."""
    from .imageio import check_output_path, next_free_path
    from .runtime import parse_size
    from .teach.compare import compare, side_params, write

    _nonempty("--out", args.out, "a file name ending in .png")
    params, camera, size = _session_inputs(args, args.scene, size=parse_size(COMPARE_SIZE))
    mesh = _user_mesh(args, args.scene)
    if not args.a_sets and not args.b_sets:
        raise UsageError("compare: nothing differs between A and B: allowed --a NAME=VALUE ... "
                         "and/or --b NAME=VALUE ... (the names: natura params "
                         f"{args.scene})")
    side_params(params, args.a_sets, "--a")  # each set checked here: one line naming it
    side_params(params, args.b_sets, "--b")
    if args.wipe is not None and args.layout != "wipe":
        raise UsageError(f"--wipe {args.wipe:g}: the wipe's position is for --layout wipe: "
                         "allowed --layout wipe --wipe 0..1")
    if args.out is not None:
        png = check_output_path(args.out, force=args.force, suffixes=(".png",))
    else:
        png = check_output_path(next_free_path(Path("."), f"compare-{args.scene}", ".png",
                                               also=(".json",)), suffixes=(".png",))
    json_path = check_output_path(png.with_suffix(".json"), force=args.force,
                                  suffixes=(".json",), probe_folder=False)
    cmp = compare(args.scene, args.a_sets, args.b_sets, size=size, params=params,
                  camera=camera, rounds=args.rounds, shader_root=args.shaders,
                  reference=not args.no_reference,
                  setup=(lambda scene: attach_mesh(scene, mesh)) if mesh is not None else None,
                  progress=lambda text: print(text, file=sys.stderr, flush=True))
    png, json_path = write(cmp, png, json_path, layout=args.layout,
                           wipe=0.5 if args.wipe is None else args.wipe, force=args.force)
    print("\n".join(cmp.caption))
    print(png)
    print(json_path)
    return 0


def cmd_report(args) -> int:
    """``natura report SCENE``: every input checked (scene, sets, methods, camera, the folder)
    before anything renders; app.teach.report does the work."""
    from .runtime import scene_params
    from .teach.methods import axis_of, select
    from .teach.report import DEFAULT_SIZE, check_out_dir, collect, default_out, write_handout

    _nonempty("--out", args.out, "a folder name")
    _nonempty("--methods", args.methods, "comma-separated methods of the scene")
    params, _, size = _session_inputs(args, args.scene, size=DEFAULT_SIZE)
    chosen = select(args.scene, args.methods)
    axis = axis_of(args.scene)
    for s in args.sets:
        if axis is not None and params.resolve(s.split("=", 1)[0].strip()) == axis.param:
            raise UsageError(f"--set {quote(s, 40)}: the report varies {axis.param} itself: "
                             f"allowed --methods {','.join(m.label for m in axis.methods)}")
    for m in chosen:
        scene_params(args.scene, args.shaders, [*args.sets, *m.sets], args.preset)
    out_arg = args.out if args.out is not None else str(default_out(args.scene))
    out = check_out_dir(out_arg, args.force)
    handout = collect(args.scene, chosen, size=size, rounds=args.rounds, base_sets=args.sets,
                      preset=args.preset, camera=args.camera, hour=args.time,
                      shader_root=args.shaders, out_name=out_arg)
    page = write_handout(handout, out, force=args.force)
    for shot in handout.shots:
        error = "no reference" if shot.error is None else f"error {100 * shot.error:.3g} %"
        print(f"{shot.method.label:12s} {shot.ms:8.3f} ms [{shot.ms_quartiles[0]:.3f}–"
              f"{shot.ms_quartiles[1]:.3f}]  {error}")
    print(f"{len(handout.shots)} method(s), {len(handout.charts)} chart(s), "
          f"{sum(len(g.rows) for g in handout.groups)} parameters, {handout.renderer}")
    print(page)
    return 0


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised in the main thread so that every ``finally`` runs (temporary files are
    removed) — like Ctrl-C, with exit code 143."""


def _on_sigterm(signum, frame):
    signal.signal(signal.SIGTERM, signal.SIG_IGN)  # the clean-up that follows runs to its end
    raise Terminated()


def _install_sigterm() -> None:
    import threading

    if threading.current_thread() is threading.main_thread():
        with contextlib.suppress(ValueError, OSError):
            signal.signal(signal.SIGTERM, _on_sigterm)


class StdoutError(NaturaError):
    """Standard output could not take what natura printed (``> /dev/full``, a full disk)."""


class _GuardedStdout:
    """``sys.stdout`` during a command: a failed write or flush becomes one
    :class:`StdoutError` line naming standard output (an OSError from a print names no file)."""

    def __init__(self, stream):
        self._stream = stream

    def _failed(self, exc: OSError) -> StdoutError:
        # drop what it could not write: Python's flush at exit would fail again
        with contextlib.suppress(OSError, ValueError, AttributeError):
            null = os.open(os.devnull, os.O_WRONLY)
            os.dup2(null, self._stream.fileno())
            os.close(null)
        return StdoutError(f"cannot write to standard output ({exc.strerror or 'error'}, "
                           f"errno {exc.errno}): allowed an output with room for it (a "
                           "terminal, a pipe, a file on a disk with free space)")

    def _guarded(self, call, *args):
        try:
            return call(*args)
        except BrokenPipeError:
            raise
        except OSError as exc:
            raise self._failed(exc) from None

    def write(self, text: str) -> int:
        return self._guarded(self._stream.write, text)

    def flush(self) -> None:
        self._guarded(self._stream.flush)

    def __getattr__(self, name: str):
        return getattr(self._stream, name)


def _say(text: str) -> None:
    with contextlib.suppress(OSError, ValueError):
        print(f"natura: {text}", file=sys.stderr)


#: the commands that render headless (the window too, when there is no display)
HEADLESS_COMMANDS = ("render", "bench", "compare", "report", "window")


def _tolerate_encoding() -> None:
    """Output that cannot carry Unicode (``PYTHONIOENCODING=ascii``, a C locale) still gets
    every line: characters it cannot encode are written as backslash escapes."""
    for stream in (sys.stdout, sys.stderr):
        # AttributeError, ValueError, OSError: not a text stream of ours, or closed
        with contextlib.suppress(AttributeError, ValueError, OSError):
            stream.reconfigure(errors="backslashreplace")  # type: ignore[union-attr]


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning as one ``natura:`` line (Python's own shows a line of Natura's source): a
    :class:`NaturaWarning` is said as it is, any other as ``warning: …``."""
    text = str(message)
    if not issubclass(category, NaturaWarning):
        text = f"warning: {text} ({category.__name__})"
    _say(one_line(text, LINE_LIMIT - len("natura: ")))


def main(argv: list[str] | None = None) -> int:
    stdout = sys.stdout
    if stdout is not None and not isinstance(stdout, _GuardedStdout):
        sys.stdout = _GuardedStdout(stdout)  # type: ignore[assignment]
    show = warnings.showwarning
    warnings.showwarning = _show_warning
    try:
        return _main(argv)
    finally:
        sys.stdout = stdout
        warnings.showwarning = show


def _shaders_after_command(parser: argparse.ArgumentParser, argv: list[str]) -> list[str]:
    """``natura --shaders DIR COMMAND …`` (what ``shaders copy`` suggests) is ``natura COMMAND
    --shaders DIR …``: leading ``--shaders`` options move after the (sub)command's name, so the
    option is accepted before the command as after it. A command that reads no shaders is
    refused in one line."""
    moved: list[str] = []
    i = 0
    while i < len(argv):
        if argv[i] == "--shaders" and i + 1 < len(argv):
            moved += argv[i:i + 2]
            i += 2
        elif argv[i].startswith("--shaders="):
            moved.append(argv[i])
            i += 1
        else:
            break
    if not moved:
        return argv
    rest = argv[i:]
    p: argparse.ArgumentParser = parser
    names: list[str] = []
    while True:
        subs = [a for a in p._actions if isinstance(a, argparse._SubParsersAction)]
        if not subs:
            break
        choices = subs[0].choices
        at = len(names)
        if at < len(rest) and rest[at] in choices:
            names.append(rest[at])
            p = choices[rest[at]]
        elif p is parser:  # no command named: the window's options (natura --shaders d sky)
            rest, names, p = ["window", *rest], ["window"], choices["window"]
        else:
            break
    if "--shaders" not in p._option_string_actions:
        takers = [n for n, sp in _commands_taking(parser, "--shaders")]
        raise UsageError(f"--shaders before `{' '.join(names)}`: it reads no shaders: allowed "
                         f"with {', '.join(takers)}")
    return [*names, *moved, *rest[len(names):]]


def _commands_taking(parser: argparse.ArgumentParser, option: str, prefix: str = ""):
    """(command words, parser) of every (sub)command that takes ``option``."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sp in action.choices.items():
                words = f"{prefix} {name}".strip()
                if option in sp._option_string_actions:
                    yield words, sp
                yield from _commands_taking(sp, option, words)


def _main(argv: list[str] | None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    _install_sigterm()
    _tolerate_encoding()
    parser = build_parser()
    try:
        try:
            if argv and argv[0] == "--version" and len(argv) > 1:
                raise UsageError(f"--version takes nothing after it, not {quote(argv[1], 40)}: "
                                 "allowed natura --version alone")
            argv = _shaders_after_command(parser, argv)
            if not argv or argv[0].startswith("-") and argv[0] not in ("-h", "--help",
                                                                       "--version"):
                argv = ["window", *argv]
            args = parser.parse_args(argv)
            command = args.command or "window"
            if command in HEADLESS_COMMANDS:  # say which context they got, in one line
                from .gpu.context import announce_contexts

                announce_contexts(lambda line: _say(f"context: {line}"))
            handler = {
                "window": cmd_window, "render": cmd_render, "scenes": cmd_scenes,
                "params": cmd_params, "shaders": cmd_shaders, "bench": cmd_bench,
                "report": cmd_report, "explain": cmd_explain,
                "compare": cmd_compare, "doctor": cmd_doctor,
                "exercise": cmd_exercise,
            }[command]
            code = handler(args)
            sys.stdout.flush()  # what could not be written fails here, in one line
            return code
        finally:
            context = sys.modules.get(f"{__package__}.gpu.context")
            if context is not None:
                context.announce_contexts(None)
            imageio = sys.modules.get(f"{__package__}.imageio")
            if imageio is not None:  # nothing was written unless the writer was imported
                imageio.remove_live_temps()
    except ShaderCompileError as exc:  # file:line errors, one per line
        _say(str(exc))
        return exc.exit_code
    except NaturaError as exc:
        _say(one_line(str(exc), LINE_LIMIT - len("natura: ")))
        return exc.exit_code
    except KeyboardInterrupt as exc:
        term = isinstance(exc, Terminated)
        _say(f"{'terminated (SIGTERM)' if term else 'interrupted (Ctrl-C)'}: stopped, "
             "temporary files removed")
        return 143 if term else 130
    except BrokenPipeError:  # e.g. `natura params sky | head`
        sys.stderr.close()
        return 0
    except OSError as exc:  # the safety net: a path problem nothing above expected
        name = exc.filename if exc.filename is not None else "a file"
        _say(one_line(f"{quote(str(name))}: {exc.strerror or type(exc).__name__} "
                      f"(errno {exc.errno}): allowed a path natura can read or write"))
        return 2
    except Exception as exc:  # noqa: BLE001 — a bug: one line, never a traceback
        _say(one_line(f"internal error: {type(exc).__name__}: {quote(str(exc), 80)[1:-1]} "
                      "(please report)"))
        return INTERNAL_ERROR


if __name__ == "__main__":
    os.environ.setdefault("PYTHONUNBUFFERED", "1")
    sys.exit(main())

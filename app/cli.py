"""``natura`` — the command line.

    natura                      open the window on the default scene (headless PNG without a
                                display)
    natura window [SCENE]       the same, for any scene
    natura render SCENE ...     render headless to PNG or EXR
    natura scenes               list the scenes and their effects
    natura params SCENE         list a scene's parameters (name, default, range, unit, doc, section)
    natura shaders check        compile every program, print file:line errors (exit 1 on any)
    natura shaders copy DIR     copy the shader folder for editing (then --shaders DIR)
    natura bench SCENE          time each pass, write JSON

Exit codes: 0 success, 1 shader errors, 2 bad arguments (one line naming the culprit and what
is allowed), 3 no OpenGL.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
from pathlib import Path

from . import __version__
from .errors import NaturaError, UsageError
from .gpu.shaders import SHADER_ENV, resolve_shader_root


class _Parser(argparse.ArgumentParser):
    """argparse, but errors are one line (and exit 2)."""

    def error(self, message):
        raise UsageError(f"{self.prog}: {message}")


def _add_common(p: argparse.ArgumentParser) -> None:
    p.add_argument("--shaders", metavar="DIR",
                   help=f"shader folder to load GLSL from (default: ${SHADER_ENV} or glsl/)")


def _add_scene_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--size", default=None, metavar="WxH", help="image size (default 1280x720)")
    p.add_argument("--time", type=float, default=None, metavar="HOURS", help="hour of day, 0 to 24")
    p.add_argument("--camera", default=None, metavar="X,Y,Z[,YAW[,PITCH[,FOV]]]",
                   help="camera position in metres, then yaw (0 = north, 90 = east), pitch and "
                   "vertical fov in degrees")
    p.add_argument("--yaw", type=float, default=None,
                   help="camera yaw in degrees (0 = north, 90 = east)")
    p.add_argument("--pitch", type=float, default=None,
                   help="camera pitch in degrees (positive looks up)")
    p.add_argument("--fov", type=float, default=None, help="vertical field of view in degrees")
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=VALUE",
                   help="set a parameter (repeatable); see `natura params SCENE`")
    p.add_argument("--preset", default=None, metavar="FILE.toml",
                   help="apply a TOML preset before --set")
    _add_common(p)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="natura",
                     description="Natural effects from five graphics theses, live and measured.")
    parser.add_argument("--version", action="version", version=f"natura {__version__}")
    sub = parser.add_subparsers(dest="command", parser_class=_Parser)

    w = sub.add_parser("window", help="open the desktop window")
    w.add_argument("scene", nargs="?", default=None)
    _add_scene_options(w)
    w.add_argument("--frames", type=int, default=None, help="close after N frames (scripts, tests)")

    r = sub.add_parser("render", help="render headless to PNG (tone-mapped sRGB) or EXR (linear)")
    r.add_argument("scene")
    _add_scene_options(r)
    r.add_argument("--out", default=None, metavar="FILE.png|FILE.exr",
                   help="output file (default: the next free SCENE-NNNN.png here)")
    r.add_argument("--frames", type=int, default=1,
                   help="number of frames (numbered files when > 1)")
    r.add_argument("--fps", type=float, default=30.0, help="frames per second of simulated time")
    r.add_argument("--force", action="store_true", help="overwrite existing output files")

    sub.add_parser("scenes", help="list the scenes")

    pp = sub.add_parser("params", help="list a scene's parameters")
    pp.add_argument("scene")
    _add_common(pp)

    s = sub.add_parser("shaders", help="check or copy the GLSL library")
    s_sub = s.add_subparsers(dest="shaders_command", parser_class=_Parser)
    sc = s_sub.add_parser("check", help="compile every program; print file:line errors")
    _add_common(sc)
    cp = s_sub.add_parser("copy", help="copy the shader folder to DIR for editing")
    cp.add_argument("dest", metavar="DIR")

    b = sub.add_parser("bench", help="time each pass of a scene; write JSON")
    b.add_argument("scene")
    _add_scene_options(b)
    b.add_argument("--warmup", type=int, default=3)
    b.add_argument("--repeat", type=int, default=15)
    b.add_argument("--out", default=None, metavar="FILE.json",
                   help="default: bench-results/SCENE-NNNN.json")
    b.add_argument("--sizes", default=None, metavar="WxH,WxH,...",
                   help="image sizes of the scene's table "
                   "(planet: the thesis's 800x600,1280x720,1920x1080)")
    b.add_argument("--no-sweep", action="store_true",
                   help="time the passes only, skip the scene's sweeps")
    b.add_argument("--force", action="store_true")
    return parser


# ---- commands --------------------------------------------------------------------------------

def _session_inputs(args, scene_name: str):
    """Validate everything the user gave (scene, parameters, camera, size) before any GL work."""
    from .runtime import parse_size, scene_params
    from .scenes import get_scene
    from .sim.camera import parse_camera

    cls = get_scene(scene_name)
    params = scene_params(scene_name, args.shaders, args.sets, args.preset)
    if args.time is not None:
        if "time.hour" not in params:
            raise UsageError(f"--time: scene {scene_name!r} has no time of day: allowed with the "
                             "scenes that have a day–night sky (see natura scenes)")
        if not 0.0 <= args.time <= 24.0:
            raise UsageError(f"--time {args.time:g} is out of range: allowed hours in [0, 24]")
        params.set("time.hour", args.time % 24.0)
    camera = cls.new_camera()
    if args.camera:
        parse_camera(args.camera, camera)
    camera.set(yaw=args.yaw, pitch=args.pitch, fov=args.fov)
    size = parse_size(args.size) if args.size else (1280, 720)
    return params, camera, size


def cmd_render(args) -> int:
    from .imageio import check_output_path, next_free_path, write_image
    from .runtime import open_session, render_frames

    params, camera, size = _session_inputs(args, args.scene)
    if args.frames < 1:
        raise UsageError(f"--frames {args.frames} is out of range: allowed 1 or more")
    if not (args.fps > 0):
        raise UsageError(f"--fps {args.fps:g} is out of range: allowed a positive number")
    if args.out:
        base = check_output_path(args.out, force=True)  # suffix and folder; per-file check below
    else:
        base = next_free_path(Path("."), args.scene, ".png")
    if args.frames == 1:
        outs = [base]
    else:
        outs = [base.with_name(f"{base.stem}-{i:04d}{base.suffix}") for i in range(args.frames)]
    for out in outs:
        check_output_path(out, force=args.force)
    session = open_session(args.scene, params, args.shaders, camera=camera)
    try:
        for out, image in zip(outs, render_frames(session, size, args.frames, args.fps,
                                                  progress=args.frames > 1)):
            write_image(out, image, session.scene.exposure(), params["output.tonemap"],
                        force=args.force)
            print(out)
    finally:
        session.release()
    return 0


def cmd_window(args) -> int:
    from .scenes import DEFAULT_SCENE

    if getattr(args, "frames", None) is not None and args.frames < 1:
        raise UsageError(f"--frames {args.frames} is out of range: allowed 1 or more")
    scene_name = args.scene or DEFAULT_SCENE
    params, camera, size = _session_inputs(args, scene_name)
    from .ui.window import display_available, run_window

    if not display_available():
        from .imageio import next_free_path, write_image
        from .runtime import open_session, render_frames

        print(f"natura: no display (DISPLAY and WAYLAND_DISPLAY are unset): "
              f"rendering {scene_name!r} headless instead", file=sys.stderr)
        out = next_free_path(Path("."), f"natura-{scene_name}", ".png")
        session = open_session(scene_name, params, args.shaders, camera=camera)
        try:
            image = next(render_frames(session, size))
            write_image(out, image, session.scene.exposure(), params["output.tonemap"])
        finally:
            session.release()
        print(out)
        return 0
    return run_window(scene_name, params, camera, size,
                      shader_root=resolve_shader_root(args.shaders), frames=args.frames)


def cmd_scenes(args) -> int:
    from .scenes import DEFAULT_SCENE, SCENES

    for name, cls in SCENES.items():
        mark = " (default)" if name == DEFAULT_SCENE else ""
        effects = ", ".join(e.name for e in cls.effects)
        print(f"{name:10s} {cls.title}{mark}\n{'':10s} effects: {effects}\n"
              f"{'':10s} {cls.description}")
    return 0


def cmd_params(args) -> int:
    from .runtime import scene_params

    params = scene_params(args.scene, args.shaders)
    for group, items in params.groups().items():
        print(f"[{group}]")
        for p in items:
            value = params[p.name]
            rng = p.allowed()
            unit = f" {p.unit}" if p.unit else ""
            where = f"  ({p.section})" if p.section else ""
            print(f"  {p.name} = {value!r}{unit}    {rng}\n      {p.doc}{where}")
    return 0


def cmd_shaders(args) -> int:
    if args.shaders_command == "copy":
        dest = Path(args.dest)
        if dest.exists():
            raise UsageError(f"{str(dest)!r} already exists: "
                             "allowed a new folder name (nothing is overwritten)")
        shutil.copytree(resolve_shader_root(None), dest)
        print(f"{dest}\nedit there, then: natura --shaders {dest} ... "
              f"(or export {SHADER_ENV}={dest})")
        return 0
    if args.shaders_command != "check":
        raise UsageError("natura shaders: allowed subcommands: check, copy")
    from .gpu.context import caps_of, create_headless_context
    from .gpu.shaders import ShaderLibrary
    from .scenes import SCENES

    root = resolve_shader_root(args.shaders)
    ctx = create_headless_context()
    caps = caps_of(ctx)
    library = ShaderLibrary(ctx, root)
    specs = {}
    for scene in SCENES.values():
        for effect in scene.effects:
            for spec in effect.programs:
                specs[spec] = effect.name
    from .bench import TRIVIAL
    from .ui.display import DISPLAY

    specs[TRIVIAL] = "bench"
    specs[DISPLAY] = "window"
    failures = 0
    for spec in specs:
        if spec.requires_compute and not caps.compute:
            print(f"skip {spec.name}: needs compute shaders (GL 4.3), "
                  f"this context has {caps.describe()}")
            continue
        try:
            library.program(spec.name, dict(spec.defines), **spec.stages())
            print(f"ok   {spec.name}")
        except NaturaError as exc:
            failures += 1
            for line in str(exc).splitlines():
                print(line)
    print(f"{len(specs) - failures} of {len(specs)} programs compiled "
          f"({caps.describe()}, shaders from {root})")
    return 1 if failures else 0


def cmd_bench(args) -> int:
    from .bench import bench_scene, scene_sweeps, write_report
    from .runtime import open_session, parse_size

    params, camera, size = _session_inputs(args, args.scene)
    if args.size is None:
        size = (640, 360)
    table_sizes = ([parse_size(t) for t in args.sizes.split(",") if t.strip()] if args.sizes
                   else None)
    if args.out:
        from .imageio import check_output_path

        check_output_path(args.out, force=args.force, suffixes=(".json",))
    session = open_session(args.scene, params, args.shaders, camera=camera)
    try:
        report = bench_scene(session, size, args.warmup, args.repeat)
        sweeps = None if args.no_sweep else scene_sweeps(args.scene)
        if sweeps is not None:
            print(f"running the {args.scene} speed/accuracy sweeps "
                  "(this takes a while on a software renderer)", file=sys.stderr)
            kwargs = {"sizes": table_sizes} if table_sizes else {}
            report["sweep"] = sweeps.sweep(session, size, warmup=min(args.warmup, 2),
                                           repeat=max(3, args.repeat // 2), **kwargs)
    finally:
        session.release()
    path = write_report(report, args.out, force=args.force)
    for name, t in report["passes"].items():
        print(f"{name:24s} {t['median_ms']:9.3f} ms  ×{t['ratio_to_fullscreen']:.2f} "
              "of a full-screen pass")
    if "sweep" in report:
        chart_path = Path(path).with_suffix(".png")
        sweeps.chart(report, chart_path)
        print(sweeps.summary(report))
        print(f"chart → {chart_path}")
    print(f"{report['renderer']}, {size[0]}x{size[1]} → {path}")
    return 0


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser()
    try:
        if not argv or argv[0].startswith("-") and argv[0] not in ("-h", "--help", "--version"):
            argv = ["window", *argv]
        args = parser.parse_args(argv)
        command = args.command or "window"
        handler = {
            "window": cmd_window, "render": cmd_render, "scenes": cmd_scenes, "params": cmd_params,
            "shaders": cmd_shaders, "bench": cmd_bench,
        }[command]
        return handler(args)
    except NaturaError as exc:
        print(f"natura: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:  # e.g. `natura params sky | head`
        sys.stderr.close()
        return 0


if __name__ == "__main__":
    os.environ.setdefault("PYTHONUNBUFFERED", "1")
    sys.exit(main())

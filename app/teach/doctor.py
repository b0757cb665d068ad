"""``natura doctor``: the driver report a teacher pastes into a course forum, on one screen.

docs/commands.md ("Platforms and drivers") shows one: the context and what it offers, the path
each scene takes on it (``Effect.context_paths``), both compilers' verdicts, and what the window
and the tests lack.

The command line gives it the programs to compile and the window's display problem (both live
in higher layers); everything else it finds itself.
"""

from __future__ import annotations

import importlib.metadata
import platform
import shutil
import sys
import textwrap
import time
from typing import Callable, Iterable, TextIO

from .. import __version__ as NATURA_VERSION
from ..errors import NaturaError
from ..gpu import context as gl_context
from ..gpu.context import caps_of, describe_context
from ..gpu.shaders import ShaderLibrary
from ..runtime import scene_params
from ..scenes import SCENES

WIDTH = 100
LABEL = 9  # the labels' column
#: what the tests need beyond Python packages, and the Debian package of each
TEST_TOOLS = (("Xvfb", "xvfb", "window tests"), ("xdotool", "xdotool", "window key tests"),
              ("chromium", "chromium", "handout test"),
              ("glslangValidator", "glslang-tools", "shaders check --strict"))
PACKAGES = ("moderngl", "glcontext", "moderngl-window", "pyglet", "imgui-bundle", "numpy")


def _version(package: str) -> str:
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return "missing"


def _writer(out: TextIO) -> Callable[[str, str], None]:
    def say(label: str, text: str) -> None:
        lines = textwrap.wrap(text, WIDTH - LABEL - 1, break_on_hyphens=False) or [""]
        for i, line in enumerate(lines):
            print(f"{label if i == 0 else '':<{LABEL}} {line}", file=out)
    return say


def paths_by_scene(caps, params_of: Callable | None = None) -> dict[str, list[tuple[str, str]]]:
    """What → [(path, scenes)] over every scene's effects at the scenes' default parameters
    (``params_of(scene)`` gives them where the caller has them declared already: the GPU
    report opens its sessions with the same ones; else ``app.runtime.scene_params``)."""
    found: dict[str, dict[str, list[str]]] = {}
    for name, scene in SCENES.items():
        params = (params_of or scene_params)(name)
        for effect in scene.effects:
            for what, how in effect.context_paths(caps, params).items():
                found.setdefault(what, {}).setdefault(how, []).append(name)
    return {what: [(how, ", ".join(dict.fromkeys(scenes))) for how, scenes in ways.items()]
            for what, ways in found.items()}


def run(specs: Iterable, display_problem: str | None, out: TextIO | None = None,
        strict_check: Callable | None = None) -> int:
    """Print the report; 0 when a context was made and every program compiled, 1 when a
    program failed, 3 when no context could be made (what could be said without one is said).
    ``strict_check(library, specs)`` → (programs passing, programs, stages, validator) runs the
    reference compiler when given and installed."""
    out = out or sys.stdout
    say = _writer(out)
    print(f"natura doctor — Natura {NATURA_VERSION}, Python {platform.python_version()} on "
          f"{platform.system()} {platform.machine()}", file=out)
    say("packages", " · ".join(f"{p} {_version(p)}" for p in PACKAGES))
    code = _gl_part(say, list(specs), strict_check)
    if display_problem is None:
        say("window", "a window can open here (pyglet, OpenGL 3.3 core or newer; macOS 4.1)")
    else:
        say("window", f"cannot open: {display_problem}; `natura` renders headless to a PNG "
                      "instead")
    tools = []
    for exe, debian, why in TEST_TOOLS:
        where = shutil.which(exe)
        tools.append(f"{exe} yes" if where else f"{exe} missing ({why}; Debian: {debian})")
    say("tests", " · ".join(tools))
    return code


def _gl_part(say: Callable[[str, str], None], specs: list,
             strict_check: Callable | None) -> int:
    try:
        ctx = gl_context.create_headless_context()
    except NaturaError as exc:
        say("context", f"none: {exc}")
        return 3
    try:
        caps = caps_of(ctx)
        say("context", describe_context(ctx))
        timers = ("GPU timer queries beside wall time" if caps.gpu_timers else
                  "wall time only (a software renderer's timer queries mean little)")
        say("offers", " · ".join([
            "a software renderer" if caps.software else "a hardware GPU",
            f"compute shaders {'yes' if caps.compute else 'no (GL < 4.3: fragment twins)'}",
            f"MSAA up to {caps.max_samples}× (the village and the surfaces lab, msaa=auto: 4× on a "
            "GPU, none on a software renderer unless a quad needs alpha-to-coverage)",
            timers,
            f"pipeline statistics {'yes' if caps.pipeline_statistics else 'no'}"]))
        for i, (what, ways) in enumerate(sorted(paths_by_scene(caps).items())):
            say("paths" if i == 0 else "", f"{what}: " + "; ".join(
                f"{how} [{scenes}]" if len(ways) > 1 else how for how, scenes in ways))
        library = ShaderLibrary(ctx)
        t0 = time.perf_counter()
        failed = []
        skipped = 0
        for spec in specs:
            if spec.requires_compute and not caps.compute:
                skipped += 1
                continue
            try:
                library.program(spec.name, dict(spec.defines), **spec.stages())
            except NaturaError as exc:
                failed.append(f"{spec.name}: {str(exc).splitlines()[0]}")
        built = len(specs) - skipped
        say("shaders", f"{built - len(failed)} of {built} programs compile on this driver "
                       f"({time.perf_counter() - t0:.1f} s" +
                       (f"; {skipped} compute programs not asked for on GL < 4.3)" if skipped
                        else ")"))
        for line in failed[:5]:
            say("", f"FAIL {line}")
        if strict_check is not None:
            verdict = strict_check(library, specs)
            if verdict is None:
                say("strict", "glslangValidator is not installed: the reference compiler's "
                              "check did not run (Debian: glslang-tools)")
            else:
                passing, total, stages, validator = verdict
                say("strict", f"{passing} of {total} programs ({stages} stages) pass "
                              f"{validator} for their #version")
                if passing < total:
                    failed.append("strict")
        library.release()
        return 1 if failed else 0
    finally:
        ctx.release()

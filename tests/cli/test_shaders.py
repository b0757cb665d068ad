"""`natura shaders`: every project program compiles through the CLI, a broken copy fails the
check with file:line, and `shaders copy` never overwrites.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from app import DEFAULT_SHADER_ROOT, PROJECT_ROOT
from app.gpu.shaders import SHADER_ENV
from tests.helpers.window_driver import NO_XVFB, XVFB_SKIP

# ---- the project's own shaders, through the CLI ------------------------------------------------

def natura(*args: str, cwd: Path, env: dict | None = None) -> subprocess.CompletedProcess:
    env = dict(os.environ if env is None else env)
    env.pop(SHADER_ENV, None)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(PROJECT_ROOT), env.get("PYTHONPATH")]))
    cmd = [sys.executable, "-c", "from app.cli import main; raise SystemExit(main())", *args]
    return subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=120)


def test_every_project_program_compiles(tmp_path):
    r = natura("shaders", "check", cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    for name in ("sky/sky", "sky/sky_face", "probe/mirror_ball", "common/constant"):
        assert any(line.split()[:2] in (["ok", name], ["skip", f"{name}:"])
                   for line in r.stdout.splitlines()), r.stdout
    assert "ok" in r.stdout
    # no file:line errors
    assert not any(":" in line.split()[0] for line in r.stdout.splitlines() if line.strip())


def test_a_broken_copy_fails_the_check_with_file_and_line(tmp_path):
    copy = tmp_path / "my-shaders"
    r = natura("shaders", "copy", str(copy), cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    radiance = copy / "sky" / "sky_radiance.glsl"
    original = (DEFAULT_SHADER_ROOT / "sky" / "sky_radiance.glsl").read_text()
    assert radiance.read_text() == original
    bad_line = len(original.splitlines()) + 1
    with radiance.open("a") as f:
        f.write("float nataraBroken() { return not_declared_anywhere; }\n")

    r = natura("shaders", "check", "--shaders", str(copy), cwd=tmp_path)
    assert r.returncode == 1, r.stdout + r.stderr
    errors = [line for line in r.stdout.splitlines() if f"sky_radiance.glsl:{bad_line}:" in line]
    assert errors, r.stdout
    assert all(line.startswith("my-shaders/sky/sky_radiance.glsl:") for line in errors)
    assert any("not_declared_anywhere" in line for line in errors)
    # programs that don't include the file still compile
    assert "ok   probe/mirror_ball" in r.stdout

    # the default shaders are untouched and still pass
    assert (DEFAULT_SHADER_ROOT / "sky" / "sky_radiance.glsl").read_text() == original


def test_shaders_copy_never_overwrites(tmp_path):
    dest = tmp_path / "exists"
    dest.mkdir()
    (dest / "keep.txt").write_text("mine")
    r = natura("shaders", "copy", str(dest), cwd=tmp_path)
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1 and "already exists" in r.stderr
    assert sorted(p.name for p in dest.iterdir()) == ["keep.txt"]



def _suggested(stdout: str) -> list[str]:
    """The command line ``natura shaders copy`` suggests (after "then: ", up to " (")."""
    import shlex

    line = next(line for line in stdout.splitlines() if "then: " in line)
    words = shlex.split(line.split("then: ", 1)[1].split(" (", 1)[0])
    assert words[0] == "natura", line
    return words[1:]


@pytest.mark.skipif(NO_XVFB, reason=XVFB_SKIP)
def test_the_command_shaders_copy_suggests_runs_on_the_copy(tmp_path):
    """The trial's `natura --shaders g window sky` (what the copy suggests) failed with
    `unrecognized arguments: sky`: run as suggested, it opens the window on the copy."""
    from tests.helpers.window_driver import under_xvfb

    r = natura("shaders", "copy", "g", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    words = _suggested(r.stdout)
    assert words == ["--shaders", "g", "window", "sky"], words
    env_free = [sys.executable, "-c", "from app.cli import main; raise SystemExit(main())"]
    proc = under_xvfb([*env_free, *words, "--frames", "3", "--size", "160x90"], cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "unrecognized" not in proc.stderr


@pytest.mark.parametrize("where", ["before", "after"])
def test_shaders_before_or_after_the_command_reads_the_copy(tmp_path, where):
    """`--shaders g` before the command is the same option as after it: a broken line in the
    copy fails `render` and `shaders check` with the copy's file:line either way."""
    r = natura("shaders", "copy", "g", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    radiance = tmp_path / "g" / "sky" / "sky_radiance.glsl"
    bad_line = len(radiance.read_text().splitlines()) + 1
    with radiance.open("a") as f:
        f.write("float broken() { return not_declared_anywhere; }\n")
    option = ["--shaders", "g"]
    for command in (["render", "sky", "--size", "16x16", "--out", "a.png"],
                    ["shaders", "check", "sky/sky"]):
        args = [*option, *command] if where == "before" else [*command, *option]
        r = natura(*args, cwd=tmp_path)
        assert r.returncode == 1, (args, r.stdout, r.stderr)
        assert f"g/sky/sky_radiance.glsl:{bad_line}:" in r.stdout + r.stderr, (args, r.stderr)
    assert not (tmp_path / "a.png").exists()


def test_shaders_before_a_command_that_reads_none_is_one_line(tmp_path):
    r = natura("--shaders", "g", "scenes", cwd=tmp_path)
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.strip().splitlines() == [
        "natura: --shaders before `scenes`: it reads no shaders: allowed with window, render, "
        "params, shaders check, bench, compare, report"]


# ---- the strict check: the Khronos reference compiler ----------------------------------------

GLSLANG_SKIP = "glslangValidator not installed (Debian: apt-get install glslang-tools)"


@pytest.mark.skipif(shutil.which("glslangValidator") is None, reason=GLSLANG_SKIP)
def test_every_preprocessed_stage_passes_the_reference_compiler(tmp_path):
    r = natura("shaders", "check", "--strict", cwd=tmp_path)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr
    last = r.stdout.strip().splitlines()[-1]
    m = re.fullmatch(r"strict: (\d+) of (\d+) programs \((\d+) stages\) pass glslangValidator .+",
                     last)
    assert m and m[1] == m[2] and int(m[3]) > int(m[2]) > 100, last
    assert "strict FAIL" not in r.stdout


@pytest.mark.skipif(shutil.which("glslangValidator") is None, reason=GLSLANG_SKIP)
def test_what_only_a_lenient_driver_accepts_is_blamed_at_its_line(tmp_path):
    """Mesa compiles a line continuation in a GLSL 3.30 shader (it came in 4.20) and an int
    initialised from a float literal is an error everywhere: the driver's check passes the
    first, the strict one names both by file and line."""
    copy = tmp_path / "my-shaders"  # `natura shaders copy` itself: the tests above
    shutil.copytree(DEFAULT_SHADER_ROOT, copy)
    radiance = copy / "sky" / "sky_radiance.glsl"
    lines = radiance.read_text().splitlines()
    at = len(lines) + 1
    lines += ["#define NATURA_TWO_LINES(x) \\", "    (x + 1.0)"]
    radiance.write_text("\n".join(lines) + "\n")
    r = natura("shaders", "check", "--strict", "sky/sky", "sky/sky_face", "--shaders", str(copy),
               cwd=tmp_path)
    assert r.returncode == 1, r.stdout[-2000:]
    # the driver's own check comes first in the same run, and the lenient driver lets it through
    driver = r.stdout.split("\nstrict")[0].splitlines()
    assert "ok   sky/sky" in driver and "ok   sky/sky_face" in driver, r.stdout[-2000:]
    assert any(line.startswith("2 of 2 programs compiled") for line in driver), r.stdout[-2000:]
    blamed = [line.strip() for line in r.stdout.splitlines() if "line continuation" in line]
    assert blamed and all(line.startswith(f"my-shaders/sky/sky_radiance.glsl:{at}:")
                          for line in blamed), blamed
    assert "strict FAIL sky/sky" in r.stdout and "strict FAIL sky/sky_face" in r.stdout
    assert r.stdout.strip().splitlines()[-1].startswith("strict: 0 of 2 programs")
    radiance.write_text("\n".join(lines[:-2]) + "\n")
    face = copy / "sky" / "sky.frag"
    face.write_text(face.read_text().replace("void main() {", "void main() {\n    int n = 2.0;"))
    r = natura("shaders", "check", "--strict", "sky/sky", "--shaders", str(copy), cwd=tmp_path)
    assert any(line.strip().startswith("my-shaders/sky/sky.frag:") and "cannot convert" in line
               for line in r.stdout.splitlines()), r.stdout[-2000:]


def test_an_unknown_program_is_named(tmp_path):
    r = natura("shaders", "check", "sky/skyy", cwd=tmp_path)
    assert r.returncode == 2 and "'sky/skyy'" in r.stderr and "allowed" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


@pytest.mark.skipif(shutil.which("glslangValidator") is None, reason=GLSLANG_SKIP)
def test_an_accepted_program_is_not_judged_again_and_a_changed_byte_is(tmp_path, monkeypatch):
    """The strict check remembers acceptances only: the same bytes by the same validator are
    not run again; an edited stage, another folder or a rejection is."""
    from app.effects.sky.effect import SKY
    from app.gpu import strict
    from app.gpu.shaders import ShaderLibrary

    runs = []
    real_run = strict._run
    monkeypatch.setattr(strict, "_run", lambda argv: runs.append(argv) or real_run(argv))
    copy = tmp_path / "my-shaders"
    shutil.copytree(DEFAULT_SHADER_ROOT, copy)
    library = ShaderLibrary(None, copy)
    seen = tmp_path / "accepted"
    assert strict.check_program(library, SKY, accepted_dir=seen).ok and len(runs) == 1
    assert len(list(seen.iterdir())) == 1
    assert strict.check_program(library, SKY, accepted_dir=seen).ok and len(runs) == 1
    assert strict.check_program(library, SKY).ok and len(runs) == 2  # no folder: judged
    face = copy / "sky" / "sky.frag"
    face.write_text(face.read_text().replace("void main() {", "void main() {\n    int n = 2.0;"))
    for _ in range(2):  # a rejection is judged every time, for its lines
        before = len(runs)
        assert not strict.check_program(library, SKY, accepted_dir=seen).ok
        assert len(runs) > before
    assert len(list(seen.iterdir())) == 1


# ---- issue 36's fuzz residue: what a copied folder can hold --------------------------------------

def _copy(tmp_path: Path) -> Path:
    """``natura shaders copy d`` (the same files: a copytree is what it does)."""
    shutil.copytree(DEFAULT_SHADER_ROOT, tmp_path / "d")
    return tmp_path / "d"


def _render(tmp_path: Path) -> str:
    """``natura render sky --shaders d`` refused: one line (exit 2), nothing written."""
    from tests.helpers.cli import run, usage_error

    before = sorted(p.name for p in tmp_path.iterdir())
    line = usage_error(run("render", "sky", "--shaders", "d", "--size", "32x32", "--out",
                           "b.png", cwd=tmp_path))
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # nothing left behind
    assert len(line) <= 200, line
    return line


def _params(tmp_path: Path) -> str:
    from tests.helpers.cli import run, usage_error

    return usage_error(run("params", "sky", "--shaders", "d", cwd=tmp_path))


def _check(tmp_path: Path, *programs: str) -> list[str]:
    """``natura shaders check --shaders d PROGRAMS``: exit 1, no traceback; its lines."""
    r = natura("shaders", "check", "--shaders", "d", *(programs or ("sky/sky",)), cwd=tmp_path)
    assert r.returncode == 1, r.stdout + r.stderr
    assert "Traceback" not in r.stdout + r.stderr and r.stderr == "", r.stderr
    return r.stdout.splitlines()


def test_a_symlink_loop_is_named_as_one(tmp_path):
    """`ln -s sky.frag d/sky/sky.frag`: an internal error (exit 70) in render, an internal error
    blamed on common/fullscreen.vert in check, before."""
    d = _copy(tmp_path)
    (d / "sky" / "sky.frag").unlink()
    (d / "sky" / "sky.frag").symlink_to("sky.frag")
    for line in (_render(tmp_path), _params(tmp_path)):
        assert line.startswith("natura: d/sky/sky.frag:1: is a symlink loop"), line
        assert "allowed a GLSL text file" in line and "internal" not in line
    lines = _check(tmp_path, "sky/sky", "sky/sky_face")
    assert [line for line in lines if ":" in line.split()[0]] == [
        "d/sky/sky.frag:1: is a symlink loop (a link that leads back to itself): allowed a GLSL "
        "text file (replace the link with the file)"], lines
    assert "ok   sky/sky_face" in lines  # the programs that do not use it still compile


@pytest.mark.parametrize("include, why", [
    ("/etc/passwd", "is an absolute path"),
    ("../../../../../../etc/hostname", "leads out of the shader folder"),
    ("host.glsl", "is a link out of the shader folder (d/sky/host.glsl)"),  # → /etc/hostname
], ids=["absolute", "dot-dot", "link-out"])
def test_an_include_out_of_the_shader_folder_is_refused_unread(tmp_path, include, why):
    """Before, each was read and compiled (``/etc/passwd:1: error: syntax error ...``)."""
    d = _copy(tmp_path)
    (d / "sky" / "host.glsl").symlink_to("/etc/hostname")
    frag = d / "sky" / "sky.frag"
    lines = frag.read_text().splitlines()
    assert lines[3] == '#include "sky_radiance.glsl"'
    frag.write_text("\n".join([*lines[:4], f'#include "{include}"', *lines[4:]]) + "\n")
    said = f'd/sky/sky.frag:5: include "{include}" {why}'
    for line in (_render(tmp_path), _params(tmp_path)):
        assert line.startswith(f"natura: {said}"), line
        assert "allowed" in line and "inside d/" in line
    lines = _check(tmp_path)
    assert [line for line in lines if line.startswith("d/")] == [
        next(line for line in lines if line.startswith(said))], lines
    target = Path("/etc/passwd" if "passwd" in include else "/etc/hostname")
    first = target.read_text().splitlines()[0].strip() if target.is_file() else ""
    if len(first) >= 6:  # what it holds is never read, so never shown
        assert first not in "\n".join(lines), lines


@pytest.mark.parametrize("how, said", [
    ("deleted", 'cannot find include "sky_radiance.glsl" (no d/sky/sky_radiance.glsl, '
                "d/common/sky_radiance.glsl, d/sky_radiance.glsl): allowed a GLSL file at one "
                "of them"),
    ("emptied", 'include "sky_radiance.glsl" (d/sky/sky_radiance.glsl) is empty: allowed a '
                "GLSL file holding the code included from it (restore it)"),
    ("a folder", 'include "sky_radiance.glsl" is a folder (d/sky/sky_radiance.glsl): allowed '
                 "a GLSL text file"),
], ids=["deleted", "emptied", "folder"])
def test_a_missing_empty_or_folder_include_is_named_by_render_params_and_check(tmp_path, how,
                                                                              said):
    """Before, render said ``unknown parameter 'sky.sun_color'`` and ``natura params sky``
    exited 0 listing 12 of the 23 parameters: the include's own @params were missing."""
    d = _copy(tmp_path)
    radiance = d / "sky" / "sky_radiance.glsl"
    if how == "deleted":
        radiance.unlink()
    elif how == "emptied":
        radiance.write_text("")
    else:
        radiance.unlink()
        radiance.mkdir()
    for line in (_render(tmp_path), _params(tmp_path)):
        assert line == f"natura: d/sky/sky.frag:4: {said}"
    lines = _check(tmp_path)
    assert f"d/sky/sky.frag:4: {said}" in lines, lines


@pytest.mark.parametrize("where", ["on the uniform", "on a line of its own"])
def test_check_refuses_the_param_comment_render_refuses(tmp_path, where):
    """``// @param abc [1, 0]``: render refuses it on a uniform's line, and check said ``ok``.
    On a line of its own it is a comment to both (it declares nothing: tests/unit/test_params)."""
    from tests.helpers.cli import run

    d = _copy(tmp_path)
    radiance = d / "sky" / "sky_radiance.glsl"
    lines = radiance.read_text().splitlines()
    at = next(i for i, line in enumerate(lines) if line.startswith("uniform float uSunSize;"))
    lines.insert(at, "uniform float uAbc; // @param abc [1, 0]" if where == "on the uniform"
                 else "// @param abc [1, 0]")
    radiance.write_text("\n".join(lines) + "\n")
    if where == "on a line of its own":
        r = run("render", "sky", "--shaders", "d", "--size", "32x32", "--out", "b.png",
                cwd=tmp_path)
        assert r.returncode == 0 and (tmp_path / "b.png").is_file(), r.stderr
        r = natura("shaders", "check", "--shaders", "d", "sky/sky", cwd=tmp_path)
        assert r.returncode == 0 and "ok   sky/sky" in r.stdout, r.stdout + r.stderr
        return
    said = (f"d/sky/sky_radiance.glsl:{at + 1}: @param needs a default first: allowed a "
            "number, true/false or (a, b, c)")
    assert _render(tmp_path) == f"natura: {said}"
    lines = _check(tmp_path, "sky/sky", "sky/sky_face")
    assert lines.count(said) == 2 and not any(line.startswith("ok") for line in lines), lines
    assert lines[-1].startswith("2 of 2 programs compiled") and lines[-1].endswith(
        "; 2 with a broken @param comment (render refuses it)"), lines


def test_the_strict_check_without_its_validator_fails_saying_so(tmp_path):
    """glslangValidator not on PATH: exit 0 and a line among the results, before."""
    bare = tmp_path / "bin"  # a PATH with no glslangValidator (natura is run by its full path)
    bare.mkdir()
    r = natura("shaders", "check", "--strict", "sky/sky", cwd=tmp_path,
               env={**os.environ, "PATH": str(bare)})
    assert r.returncode == 3, r.stdout + r.stderr
    assert r.stdout == "" and "Traceback" not in r.stderr
    [line] = r.stderr.splitlines()
    assert line == ("natura: shaders check --strict cannot run: glslangValidator is not on "
                    "PATH: allowed once it is installed (Debian: apt-get install glslang-tools; "
                    "macOS: brew install glslang)")
    assert len(line) <= 200
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bin"]

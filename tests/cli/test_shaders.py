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

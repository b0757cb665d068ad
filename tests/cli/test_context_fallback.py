"""Headless without EGL: with libEGL unloadable, `natura render`, `bench`, `compare` and
`report` take the platform's standalone context (GLX here, on a display) and say so in one
line; without EGL and without a display they fail in one line naming both.

EGL is made unavailable the way a system without it looks to the program: the loader finds a
file named libEGL.so.1 first on LD_LIBRARY_PATH, and it is not a library.
"""

from __future__ import annotations

import os
import shutil
import subprocess

import numpy as np
import pytest
from PIL import Image

from app import PROJECT_ROOT
from tests.helpers.cli import CONTEXT_LINE, NATURA, messages, run
from tests.helpers.window_driver import XVFB_SKIP, xvfb_server_num


@pytest.fixture(scope="module")
def no_egl(tmp_path_factory):
    lib = tmp_path_factory.mktemp("no-egl")
    (lib / "libEGL.so.1").write_text("not a library: EGL is missing on this system\n")
    env = dict(os.environ)
    env["LD_LIBRARY_PATH"] = os.pathsep.join(filter(None, [str(lib),
                                                           env.get("LD_LIBRARY_PATH")]))
    return env


def _context_of(stderr: str) -> str:
    (line,) = [ln for ln in stderr.splitlines() if ln.startswith(CONTEXT_LINE)]
    return line


def test_without_egl_and_without_a_display_one_line_names_both(tmp_path, no_egl):
    env = {k: v for k, v in no_egl.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    r = run("render", "sky", "--size", "32x18", "--out", "x.png", cwd=tmp_path, env=env)
    assert r.returncode == 3, r.stderr
    (line,) = messages(r.stderr)
    assert "EGL" in line and "GLX" in line and "DISPLAY" in line, line
    assert not (tmp_path / "x.png").exists()


@pytest.mark.skipif(shutil.which("xvfb-run") is None, reason=XVFB_SKIP)
def test_render_bench_compare_report_fall_back_to_glx(tmp_path, no_egl):
    """One Xvfb, the four commands in turn, EGL unloadable: each names a GLX context; the
    render is the same picture as through EGL (the same driver behind both)."""
    script = tmp_path / "run.sh"
    natura = " ".join(f"'{a}'" for a in NATURA)
    script.write_text("\n".join([
        "set -e",
        f"{natura} render sky --size 64x36 --time 9 --out glx.png 2> render.err",
        f"{natura} bench sky --size 32x18 --repeat 1 --warmup 0 --out b.json 2> bench.err",
        f"{natura} compare sky --a sky.sun_size=0.05 --b sky.sun_size=0.1 --size 32x18 "
        "--rounds 1 --out c.png 2> compare.err",
        f"{natura} report sky --size 32x18 --rounds 1 --out handout 2> report.err",
    ]) + "\n")
    env = {k: v for k, v in no_egl.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(PROJECT_ROOT),
                                                      env.get("PYTHONPATH")]))
    proc = subprocess.run(["xvfb-run", "-a", "-n", str(xvfb_server_num()), "bash", str(script)],
                          cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:] + "".join(
        p.read_text()[-800:] for p in tmp_path.glob("*.err"))
    for command in ("render", "bench", "compare", "report"):
        line = _context_of((tmp_path / f"{command}.err").read_text())
        assert "through GLX" in line and "OpenGL" in line, (command, line)
    egl = run("render", "sky", "--size", "64x36", "--time", "9", "--out", "egl.png",
              cwd=tmp_path)
    assert egl.returncode == 0 and "through EGL" in _context_of(egl.stderr), egl.stderr
    a = np.asarray(Image.open(tmp_path / "glx.png"), dtype=np.int16)
    b = np.asarray(Image.open(tmp_path / "egl.png"), dtype=np.int16)
    assert a.shape == b.shape and np.abs(a - b).max() <= 1

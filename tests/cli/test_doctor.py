"""`natura doctor`, as a teacher runs it before pasting it into a course forum: one screen,
the context, the paths the scenes take on it, the compilers' verdicts, what is missing."""

from __future__ import annotations

import os
import re

from tests.helpers.cli import run
from tests.helpers.parity import GL41_ENV

#: a terminal's screen: the report must fit in it
SCREEN_LINES = 30
LABELS = ("packages", "context", "offers", "paths", "shaders", "window", "tests")


def _sections(stdout: str) -> dict[str, str]:
    out: dict[str, str] = {}
    label = ""
    for line in stdout.splitlines()[1:]:
        head = line[:9].strip()
        if head:
            label = head
        out[label] = (out.get(label, "") + " " + line[10:].strip()).strip()
    return out


def test_the_report_fits_one_screen_and_says_everything(tmp_path):
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    r = run("doctor", cwd=tmp_path, env=env)
    assert r.returncode == 0, r.stdout + r.stderr
    lines = r.stdout.splitlines()
    assert lines[0].startswith("natura doctor — Natura ")
    assert len(lines) <= SCREEN_LINES and max(map(len, lines)) <= 100, r.stdout
    s = _sections(r.stdout)
    assert set(LABELS) <= set(s), s.keys()
    assert re.match(r"OpenGL 4\.5 .* through EGL: llvmpipe", s["context"]), s["context"]
    assert "a software renderer" in s["offers"] and "compute shaders yes" in s["offers"]
    assert "wall time only" in s["offers"]  # no GPU timers on llvmpipe
    # the paths picked for a software renderer, from the context
    assert "ocean FFT: fragment passes (ocean.fft_path=auto)" in s["paths"]
    assert "ocean surface: deferred (ocean.shading=auto)" in s["paths"]
    assert "sky cubemap: a compute shader" in s["paths"]
    m = re.search(r"(\d+) of (\d+) programs compile on this driver", s["shaders"])
    assert m and m[1] == m[2] and int(m[2]) > 100, s["shaders"]
    assert "cannot open" in s["window"]
    for tool in ("Xvfb", "xdotool", "chromium", "glslangValidator"):
        assert tool in s["tests"]


def test_on_a_41_context_it_names_the_fragment_twins(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"}
    r = run("doctor", cwd=tmp_path, env={**env, **GL41_ENV})
    assert r.returncode == 0, r.stdout + r.stderr
    s = _sections(r.stdout)
    assert "OpenGL 4.1" in s["context"]
    assert "compute shaders no" in s["offers"] and "pipeline statistics no" in s["offers"]
    assert "sky cubemap: six fragment passes" in s["paths"]
    assert "noise bakes (3D textures): one fragment pass per slice" in s["paths"]
    assert "one instanced draw per run of visible tiles" in s["paths"]
    assert "compute programs not asked for on GL < 4.3" in s["shaders"]


def test_without_any_context_it_still_says_what_it_can(tmp_path):
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "libEGL.so.1").write_text("not a library\n")
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env["LD_LIBRARY_PATH"] = str(lib)
    r = run("doctor", cwd=tmp_path, env=env)
    assert r.returncode == 3, r.stdout + r.stderr
    s = _sections(r.stdout)
    assert s["context"].startswith("none: no OpenGL 3.3 context: EGL:"), s["context"]
    assert "tests" in s and "window" in s and "shaders" not in s

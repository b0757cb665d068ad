"""What the fuzz suite cannot see from one bad argument (issue 11): file modes from the umask,
Ctrl-C and SIGTERM in the middle of a render, a full disk and a failing encoder, a partial
shader copy, a bench that refuses before running, long but valid names, stale temporary files,
and the ended progress line.
"""

from __future__ import annotations

import errno
import os
import signal
import subprocess
import time
from pathlib import Path

import pytest
from PIL import Image

from app import PROJECT_ROOT, cli
from app.imageio import STALE_AFTER
from tests.cli.fuzz_cases import is_root
from tests.helpers.cli import NATURA, SMALL, messages, run, usage_error


def temps(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.rglob(".natura-*"))


# ---- an interrupt at the worst moment ------------------------------------------------------------

@pytest.mark.parametrize("writer", ["png", "probe"])
def test_an_interrupt_right_after_a_temporary_file_is_created_leaves_nothing(
        tmp_path, monkeypatch, writer):
    """A Ctrl-C that Python's handler caught before the signals were blocked is raised at the
    next bytecode — possibly the one right after the temporary file (or the writable-folder
    probe) was created. The file must already be registered, so the CLI's clean-up (the same
    call as in app.cli.main) removes it (CI once found a .natura-*.tmp left behind)."""
    import numpy as np

    from app import imageio

    real_open = os.open

    def open_then_interrupt(path, flags, mode=0o777, *args, **kw):
        fd = real_open(path, flags, mode, *args, **kw)
        if Path(path).name.startswith(".natura-"):
            os.close(fd)
            raise KeyboardInterrupt
        return fd

    monkeypatch.setattr(imageio.os, "open", open_then_interrupt)
    with pytest.raises(KeyboardInterrupt):
        if writer == "png":
            imageio.write_png(tmp_path / "x.png", np.zeros((4, 4, 3), np.float32))
        else:
            imageio._can_create_in(tmp_path)
    assert temps(tmp_path)  # the interrupt came after the file existed
    imageio.remove_live_temps()
    assert temps(tmp_path) == [] and not (tmp_path / "x.png").exists()


# ---- permissions -------------------------------------------------------------------------------

@pytest.mark.parametrize("umask", [0o022, 0o002, 0o077])
def test_written_files_have_the_umask_mode(tmp_path, umask):
    env = dict(os.environ)
    outs = []
    for args, out in ((["render", "sky", "--size", SMALL, "--out", "a.png"], "a.png"),
                      (["render", "sky", "--size", SMALL, "--out", "a.exr"], "a.exr"),
                      (["bench", "sky", "--size", SMALL, "--repeat", "1", "--warmup", "0",
                        "--out", "b.json"], "b.json")):
        r = subprocess.run([*NATURA, *args], cwd=tmp_path, env=env, capture_output=True,
                           text=True, timeout=120, preexec_fn=lambda: os.umask(umask))
        assert r.returncode == 0, r.stderr
        outs.append(out)
    for out in outs:
        mode = (tmp_path / out).stat().st_mode & 0o777
        assert mode == 0o666 & ~umask, (out, oct(mode), oct(umask))
    assert temps(tmp_path) == []


# ---- signals -----------------------------------------------------------------------------------

def _default_signals() -> None:
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, signal.SIG_DFL)


@pytest.mark.parametrize("sig, code", [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_a_signal_during_a_render_leaves_no_temporary_file(tmp_path, sig, code):
    env = {k: v for k, v in os.environ.items() if k != "NATURA_SHADERS"}
    proc = subprocess.Popen([*NATURA, "render", "sky", "--frames", "2000", "--size", "64x36",
                             "--out", "x.png"], cwd=tmp_path, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE,  # bytes: text mode would turn \r into \n
                            # as from a terminal: a test run started in the background (nohup,
                            # `cmd &` in a script) inherits SIGINT ignored, and so would natura
                            preexec_fn=_default_signals)
    try:
        deadline = time.monotonic() + 60
        while not (tmp_path / "x-0002.png").exists():
            assert proc.poll() is None, proc.communicate()
            assert time.monotonic() < deadline, "no frame written in 60 s"
            time.sleep(0.01)
        proc.send_signal(sig)
        out_bytes, err_bytes = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    out, err = out_bytes.decode(), err_bytes.decode()
    assert proc.returncode == code, err
    assert "Traceback" not in err
    lines = messages(err)
    # the progress line (ended), then one line saying what happened
    assert len(lines) == 2 and lines[0].lstrip("\r").startswith("rendering ["), err
    assert lines[1].startswith("natura: ") and "temporary files removed" in lines[1], err
    assert temps(tmp_path) == []
    written = sorted(p.name for p in tmp_path.iterdir())
    assert 2 <= len(written) < 2000
    for name in written:  # every file there is a whole picture
        with Image.open(tmp_path / name) as im:
            im.load()
    listed = out.split()  # stdout names them (but one committed as the signal came)
    assert listed == written[:len(listed)] and len(written) - len(listed) <= 1, (listed, written)


# ---- write failures (in-process: the writer is patched) --------------------------------------

def _main(capsys, *argv: str) -> tuple[int, list[str]]:
    rc = cli.main(list(argv))
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return rc, messages(err)


def test_a_full_disk_is_one_line_and_leaves_nothing(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)

    def full(self, fp, *a, **k):
        with open(fp, "wb") as f:
            f.write(b"partial")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(Image.Image, "save", full)
    rc, lines = _main(capsys, "render", "sky", "--size", SMALL, "--out", "full.png")
    assert rc == 2 and len(lines) == 1, lines
    assert "full.png" in lines[0] and "No space left" in lines[0] and "allowed" in lines[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_an_encoder_error_is_one_line_and_leaves_nothing(tmp_path, monkeypatch, capsys):
    import OpenEXR

    class Broken:
        def __init__(self, *a, **k):
            pass

        def __enter__(self):
            return self

        def __exit__(self, *a):
            return False

        def write(self, name):
            Path(name).write_bytes(b"half an exr")
            raise RuntimeError("Cannot write image file")

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(OpenEXR, "File", Broken)
    rc, lines = _main(capsys, "render", "sky", "--size", SMALL, "--out", "x.exr")
    assert rc == 2 and len(lines) == 1 and "x.exr" in lines[0], lines
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_an_unexpected_exception_is_one_line_with_exit_70(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(cli, "cmd_scenes", lambda args: 1 / 0)
    rc, lines = _main(capsys, "scenes")
    assert rc == 70 and len(lines) == 1, lines
    assert lines[0].startswith("natura: internal error: ZeroDivisionError")
    assert "please report" in lines[0]


def test_shaders_copy_that_fails_midway_leaves_nothing_and_a_retry_works(
        tmp_path, monkeypatch, capsys):
    import shutil

    real = shutil.copytree

    def half(src, dst, *a, **k):
        os.makedirs(dst)
        Path(dst, "partial.glsl").write_text("half")
        raise OSError(errno.ENOSPC, "No space left on device", str(dst))

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(shutil, "copytree", half)
    rc, lines = _main(capsys, "shaders", "copy", "mine")
    assert rc == 2 and len(lines) == 1 and "mine" in lines[0] and "allowed" in lines[0], lines
    assert list(tmp_path.iterdir()) == []
    monkeypatch.setattr(shutil, "copytree", real)
    rc, lines = _main(capsys, "shaders", "copy", "mine")
    assert rc == 0, lines
    assert (tmp_path / "mine" / "sky").is_dir() and temps(tmp_path) == []


# ---- refusing before any work ------------------------------------------------------------------

def test_bench_refuses_before_running_when_its_chart_exists(tmp_path):
    chart = tmp_path / "r.png"
    chart.write_bytes(b"my chart")
    line = usage_error(run("bench", "materials", "--size", SMALL, "--out", "r.json",
                           cwd=tmp_path))
    assert "r.png" in line and "--force" in line
    assert chart.read_bytes() == b"my chart"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.png"]


def test_no_display_in_an_unwritable_folder_is_refused_before_rendering(tmp_path):
    if is_root():
        folder = Path("/proc")  # root may write anywhere on disk, but not here
    else:
        folder = tmp_path / "locked"
        folder.mkdir()
        folder.chmod(0o500)
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    try:
        line = usage_error(run("--size", SMALL, cwd=folder, env=env))
        assert "not writable" in line and "no display" not in line
    finally:
        if folder != Path("/proc"):
            folder.chmod(0o700)


# ---- names -------------------------------------------------------------------------------------

def test_a_long_but_valid_name_is_written(tmp_path):
    name = "n" * 251 + ".png"  # 255 bytes: the longest name; the temporary name is short
    r = run("render", "sky", "--size", SMALL, "--out", name, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]
    line = usage_error(run("render", "sky", "--size", SMALL, "--out", "n" + name, cwd=tmp_path))
    assert "256 bytes" in line and "at most 255" in line


def test_stale_temporary_files_are_removed_fresh_ones_kept(tmp_path):
    stale, fresh = tmp_path / ".natura-dead0001.tmp", tmp_path / ".natura-live0001.tmp"
    for p in (stale, fresh):
        p.write_bytes(b"left by a killed run")
    old = time.time() - STALE_AFTER - 60
    os.utime(stale, (old, old))
    r = run("render", "sky", "--size", SMALL, "--out", "a.png", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert not stale.exists() and fresh.exists()


def test_sequences_are_numbered_from_one_and_the_progress_line_is_ended(tmp_path):
    r = run("render", "sky", "--size", SMALL, "--frames", "2", "--out", "s.png", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["s-0001.png", "s-0002.png"]
    assert r.stderr.endswith("2/2 frames\n"), repr(r.stderr)
    # the default headless name of a window without a display
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    r = run("window", "sky", "--size", SMALL, cwd=tmp_path, env=env)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "natura-sky-0001.png"


@pytest.mark.parametrize("where", ["flag", "env"])
def test_a_shader_folder_of_an_unknown_user_or_without_common_is_named(tmp_path, where):
    (tmp_path / "empty").mkdir()
    for folder, expect in (("~nosuchuser/glsl", "user"),
                           (str(tmp_path / "empty"), "has no common/ folder")):
        if where == "flag":
            r = run("params", "sky", "--shaders", folder, cwd=tmp_path)
        else:  # run() clears $NATURA_SHADERS, as a user without it has
            env = {**os.environ, "NATURA_SHADERS": folder, "PYTHONPATH": str(PROJECT_ROOT)}
            r = subprocess.run([*NATURA, "params", "sky"], cwd=tmp_path, env=env,
                               capture_output=True, text=True, timeout=120)
        line = usage_error(r)
        assert expect in line and ("--shaders" if where == "flag" else "$NATURA_SHADERS") in line

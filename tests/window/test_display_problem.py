"""app.ui.window.display_problem: None when a window can be opened, else why not — the CLI's
"no display" message must not say DISPLAY is unset when it points at a server that is gone."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.helpers.window_driver import NO_XVFB, XVFB_SKIP, under_xvfb

pytestmark = pytest.mark.window

PROBE = ("from app.ui.window import display_problem; "
         "print(repr(display_problem())); print(display_problem() is None)")


def _probe(env_changes: dict) -> list[str]:
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env.update(env_changes)
    proc = subprocess.run([sys.executable, "-c", PROBE], env=env, capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.splitlines()


def _dead_display() -> str:
    """A display number no X server holds (no socket, no lock file)."""
    for n in range(190, 300):
        if not (Path(f"/tmp/.X11-unix/X{n}").exists() or Path(f"/tmp/.X{n}-lock").exists()):
            return f":{n}"
    pytest.fail("every display number from :190 to :299 is taken")


def test_no_display_variables():
    assert _probe({}) == ["'DISPLAY and WAYLAND_DISPLAY are unset'", "False"]


def test_wayland_alone_is_not_enough_for_pyglet():
    problem, available = _probe({"WAYLAND_DISPLAY": "wayland-0"})
    assert "DISPLAY is unset" in problem and "X11" in problem and available == "False"


def test_a_display_that_does_not_answer():
    dead = _dead_display()
    assert _probe({"DISPLAY": dead}) == [repr(f"the X display {dead!r} does not answer"),
                                         "False"]


@pytest.mark.skipif(NO_XVFB, reason=XVFB_SKIP)
def test_a_live_display_has_no_problem():
    proc = under_xvfb([sys.executable, "-c", PROBE], cwd=".")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.splitlines() == ["None", "True"]


@pytest.mark.skipif(NO_XVFB, reason=XVFB_SKIP)
def test_commands_share_one_xvfb_and_leave_nothing_running(tmp_path):
    """tests/helpers/window_driver.py's ``under_xvfb``: a test process's commands run on one
    Xvfb (the same display each time, and it answers), and what a command left running (a
    ``natura window`` a driver started) ends with it, so no window is left for the next."""
    leaver = ("import os, subprocess, sys; print(os.environ['DISPLAY']); "
              "print(subprocess.Popen([sys.executable, '-c', 'import time; time.sleep(600)'],"
              " start_new_session=False).pid)")
    first = under_xvfb([sys.executable, "-c", leaver], cwd=tmp_path)
    second = under_xvfb([sys.executable, "-c", PROBE + "; import os; print(os.environ['DISPLAY'])"],
                        cwd=tmp_path)
    assert first.returncode == 0 and second.returncode == 0, first.stderr + second.stderr
    display, pid = first.stdout.split()
    assert second.stdout.splitlines() == ["None", "True", display]

    def gone() -> bool:  # no such process, or a zombie nobody reaped yet
        try:
            return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] == "Z"
        except OSError:
            return True

    for _ in range(100):
        if gone():
            break
        time.sleep(0.05)
    assert gone(), f"process {pid} left running"

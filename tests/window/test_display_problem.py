"""app.ui.window.display_problem: None when a window can be opened, else why not — the CLI's
"no display" message must not say DISPLAY is unset when it points at a server that is gone."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.helpers.window_driver import XVFB_SKIP, under_xvfb

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


@pytest.mark.skipif(shutil.which("xvfb-run") is None, reason=XVFB_SKIP)
def test_a_live_display_has_no_problem():
    proc = under_xvfb([sys.executable, "-c", PROBE], cwd=".")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.splitlines() == ["None", "True"]

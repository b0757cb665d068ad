"""Running ``natura`` as a user runs it (tests/cli and tests/bench): the console script of the
interpreter running the tests, the project on PYTHONPATH, $NATURA_SHADERS unset. Where the test
leaves the environment as it is, the process is forked from a server that has the modules
imported already (tests/helpers/forkserver.py).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from app import PROJECT_ROOT
from app.gpu.shaders import SHADER_ENV
from tests.helpers import forkserver

SIZE = (64, 36)
SMALL = f"{SIZE[0]}x{SIZE[1]}"


def natura_command() -> list[str]:
    """The ``natura`` console script of the interpreter running the tests (not whichever one is
    first on PATH), else the same entry point through ``-c``."""
    script = Path(sys.executable).with_name("natura")
    if script.is_file() and os.access(script, os.X_OK):
        return [str(script)]
    return [sys.executable, "-c", "from app.cli import main; raise SystemExit(main())"]


NATURA = natura_command()


def command_env(env: dict | None = None) -> dict[str, str]:
    """The environment ``run`` gives a command: ``env`` (else this process's), the project on
    PYTHONPATH, $NATURA_SHADERS unset."""
    env = dict(os.environ if env is None else env)
    env.pop(SHADER_ENV, None)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(PROJECT_ROOT), env.get("PYTHONPATH")]))
    return env


def run(*args: str, cwd: Path, env: dict | None = None) -> subprocess.CompletedProcess:
    own_env = env is None
    env = command_env(env)
    if own_env and len(NATURA) == 1:  # the console script: a child of the warm server
        r = forkserver.run([*NATURA, *args], cwd, env, timeout=120)
        if r is not None:
            return r
    return subprocess.run([*NATURA, *args], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=120)


#: how the commands that render headless (render, bench, compare, report, and the window
#: without a display) start: one line naming the OpenGL context they got
CONTEXT_LINE = "natura: context: "


def messages(stderr: str) -> list[str]:
    """The non-blank lines of ``stderr`` without the context line (said at most once)."""
    lines = [line for line in stderr.split("\n") if line.strip()]
    rest = [line for line in lines if not line.startswith(CONTEXT_LINE)]
    assert len(lines) - len(rest) <= 1, stderr
    return rest


def usage_error(r: subprocess.CompletedProcess) -> str:
    """Assert exit 2 with exactly one line on stderr and nothing on stdout; return that line."""
    assert r.returncode == 2, (r.returncode, r.stdout, r.stderr)
    lines = messages(r.stderr)
    assert len(lines) == 1, r.stderr
    assert "Traceback" not in r.stderr
    assert r.stdout == ""
    return lines[0]

"""Running ``natura`` as a user runs it (tests/cli and tests/bench): the console script of the
interpreter running the tests, the project on PYTHONPATH, $NATURA_SHADERS unset.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from app import PROJECT_ROOT
from app.gpu.shaders import SHADER_ENV

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


def run(*args: str, cwd: Path, env: dict | None = None) -> subprocess.CompletedProcess:
    env = dict(os.environ if env is None else env)
    env.pop(SHADER_ENV, None)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(PROJECT_ROOT), env.get("PYTHONPATH")]))
    return subprocess.run([*NATURA, *args], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=120)


def usage_error(r: subprocess.CompletedProcess) -> str:
    """Assert exit 2 with exactly one line on stderr and nothing on stdout; return that line."""
    assert r.returncode == 2, (r.returncode, r.stdout, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert "Traceback" not in r.stderr
    assert r.stdout == ""
    return lines[0]

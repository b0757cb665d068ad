"""The warm start of the tests' ``natura`` commands (tests/helpers/forkserver.py) gives what a
real process gives: the same exit status, output, errors and files, under the caller's umask;
a command past its time limit is killed; a changed environment gets a real process."""

from __future__ import annotations

import os
import subprocess

import pytest

from app import PROJECT_ROOT
from tests.helpers import forkserver
from tests.helpers.cli import NATURA, SMALL, command_env

pytestmark = pytest.mark.skipif(
    len(NATURA) != 1, reason="natura is not installed as a console script beside this Python "
    "(pip install -e .): run() starts real processes then, and there is nothing to fork")


@pytest.fixture(scope="module")
def server():
    s = forkserver.Server(command_env(), str(PROJECT_ROOT))
    yield s
    s.close()


#: a picture written, a usage error, an unknown scene, plain output, and a file that exists
COMMANDS = [
    ("render", "sky", "--size", SMALL, "--out", "sky.png"),
    ("render", "sky", "--size", "64x", "--out", "bad.png"),
    ("render", "atlantis"),
    ("params", "sky"),
    ("render", "sky", "--size", SMALL, "--out", "taken.png"),
]


@pytest.mark.parametrize("args", COMMANDS, ids=lambda a: "-".join(a[:2]) + f"-{len(a)}")
def test_a_forked_command_gives_what_a_real_process_gives(server, tmp_path, args):
    results, files = [], []
    for way in ("real", "forked"):
        folder = tmp_path / way
        folder.mkdir()
        (folder / "taken.png").write_bytes(b"mine")
        argv = [*NATURA, *args]
        if way == "real":
            r = subprocess.run(argv, cwd=folder, env=command_env(), capture_output=True, text=True,
                               timeout=120)
        else:
            r = server.run(argv, str(folder), command_env(), timeout=120)
        results.append((r.returncode, r.stdout, r.stderr))
        files.append({p.name: p.read_bytes() for p in sorted(folder.iterdir())})
    assert results[0] == results[1]
    assert files[0] == files[1]
    assert files[1]["taken.png"] == b"mine"  # never overwritten, either way


def test_the_child_writes_with_the_callers_umask(server, tmp_path):
    old = os.umask(0o077)
    try:
        r = server.run([*NATURA, "render", "sky", "--size", SMALL, "--out", "u.png"],
                       str(tmp_path), command_env(), timeout=120)
    finally:
        os.umask(old)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "u.png").stat().st_mode & 0o777 == 0o600


def test_a_command_past_its_limit_is_killed_and_the_server_goes_on(server, tmp_path):
    argv = [*NATURA, "render", "sky", "--frames", "100000", "--size", SMALL, "--out", "l.png"]
    with pytest.raises(subprocess.TimeoutExpired):
        server.run(argv, str(tmp_path), command_env(), timeout=1)
    assert not (tmp_path / "l.png").exists()
    r = server.run([*NATURA, "scenes"], str(tmp_path), command_env(), timeout=120)
    assert r.returncode == 0 and "maritime" in r.stdout


def test_a_changed_environment_or_the_switch_gets_a_real_process(tmp_path, monkeypatch):
    monkeypatch.setattr(forkserver, "_server", None)  # this test's own, started with env
    env = command_env()
    assert forkserver.run([*NATURA, "scenes"], tmp_path, env, timeout=120) is not None
    started = forkserver._server
    assert started is not None
    assert forkserver.run([*NATURA, "scenes"], tmp_path, {**env, "NATURA_X": "1"},
                          timeout=120) is None
    per_test = {**env, "PYTEST_CURRENT_TEST": "another test"}
    assert forkserver.run([*NATURA, "scenes"], tmp_path, per_test, timeout=120) is not None
    monkeypatch.setenv(forkserver.SWITCH, "0")
    assert forkserver.run([*NATURA, "scenes"], tmp_path, env, timeout=120) is None
    started.close()

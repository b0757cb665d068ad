"""The README's first command, ``./setup.sh && .venv/bin/natura``, on a machine that lacks
system packages: as root it installs them with apt-get; as another user it stops with one line
naming them. Faked commands on PATH stand in for dpkg, apt-get, id and Python, so the test runs
the real script without touching this machine."""

from __future__ import annotations

import os
import shutil
import stat
import subprocess
from pathlib import Path

import pytest

from app import PROJECT_ROOT

SCRIPT = PROJECT_ROOT / "setup.sh"


def _tool(folder: Path, name: str, body: str) -> None:
    path = folder / name
    path.write_text("#!/bin/sh\n" + body + "\n")
    path.chmod(path.stat().st_mode | stat.S_IXUSR)


def _machine(tmp_path: Path, installed: set[str], uid: int, system: str = "Linux",
             apt: bool = True) -> tuple[Path, dict]:
    """A copy of the script in ``tmp_path/repo`` and PATH with fake system tools first
    (``uname -s`` answers ``system``; without ``apt``, apt-get is not on PATH)."""
    repo = tmp_path / "repo"
    repo.mkdir()
    shutil.copy(SCRIPT, repo / "setup.sh")
    bin_ = tmp_path / "bin"
    bin_.mkdir()
    log = tmp_path / "log"
    cases = "\n".join(f'  {p}) echo "install ok installed"; exit 0 ;;' for p in installed)
    _tool(bin_, "dpkg-query", f'for last; do :; done\ncase "$last" in\n{cases}\nesac\nexit 1')
    _tool(bin_, "id", f"echo {uid}")
    _tool(bin_, "uname", f"echo {system}")
    if apt:
        _tool(bin_, "apt-get", f'echo "apt-get $*" >> {log}')
    # Python: answers the version check, makes a venv whose pip records what it installs
    _tool(bin_, "fakepython",
          f'echo "python $*" >> {log}\n'
          'if [ "$1 $2" = "-m venv" ]; then mkdir -p "$3/bin"\n'
          f'  printf \'#!/bin/sh\\necho "pip $*" >> {log}\\n\' > "$3/bin/pip"\n'
          '  chmod +x "$3/bin/pip"; fi\nexit 0')
    path = os.environ["PATH"]
    if not apt:  # the real apt-get must not be found either: every other command, linked
        system = tmp_path / "system-bin"
        system.mkdir()
        for folder in path.split(os.pathsep):
            if not os.path.isdir(folder):
                continue
            for entry in os.scandir(folder):
                target = system / entry.name
                if entry.name != "apt-get" and not os.path.lexists(target):
                    target.symlink_to(entry.path)
        path = str(system)
    env = {**os.environ, "PATH": f"{bin_}{os.pathsep}{path}", "PYTHON": "fakepython"}
    return repo, env


def _run(repo: Path, env: dict, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["sh", str(repo / "setup.sh"), *args], env=env, capture_output=True,
                          text=True, timeout=60)


ALL = {"python3-venv", "libegl1", "libgl1-mesa-dri", "xvfb", "xdotool", "chromium",
       "glslang-tools"}


def test_as_a_user_it_names_the_missing_packages_in_one_line(tmp_path):
    repo, env = _machine(tmp_path, ALL - {"libegl1", "xvfb"}, uid=1000)
    r = _run(repo, env)
    assert r.returncode == 1
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert "libegl1" in lines[0] and "sudo apt-get install libegl1 xvfb" in lines[0]
    assert not (repo / ".venv").exists()  # stopped before doing anything
    assert not (tmp_path / "log").exists() or "apt-get" not in (tmp_path / "log").read_text()


def test_as_root_it_installs_them_then_the_venv(tmp_path):
    repo, env = _machine(tmp_path, ALL - {"python3-venv", "libgl1-mesa-dri", "xdotool"}, uid=0)
    r = _run(repo, env)
    assert r.returncode == 0, r.stderr
    log = (tmp_path / "log").read_text().splitlines()
    installs = [line for line in log if line.startswith("apt-get") and " install " in line]
    assert installs and all(p in installs[0]
                            for p in ("python3-venv", "libgl1-mesa-dri", "xdotool"))
    assert "libegl1" not in installs[0]  # already there
    assert any(line.startswith("python -m venv .venv") for line in log)
    assert any(line.startswith("pip install") and ".[test]" in line for line in log)
    # the order a fresh machine needs: system packages, the venv, pip, then the sources
    # compiled (an editable install compiles none of them)
    order = [next(i for i, line in enumerate(log) if line.startswith(w))
             for w in ("apt-get update", "python -m venv", "pip install",
                       "python -m compileall -q app")]
    assert order == sorted(order)


def test_nothing_missing_installs_nothing(tmp_path):
    repo, env = _machine(tmp_path, ALL, uid=0)
    r = _run(repo, env)
    assert r.returncode == 0, r.stderr
    assert "apt-get" not in (tmp_path / "log").read_text()


@pytest.mark.parametrize("installed,code", [(ALL, 0), (ALL - {"xvfb"}, 0),
                                            (ALL - {"libegl1"}, 1)])
def test_check_only_reports(tmp_path, installed, code):
    repo, env = _machine(tmp_path, installed, uid=0)
    r = _run(repo, env, "--check")
    assert r.returncode == code
    assert len(r.stderr.strip().splitlines()) == 1
    assert not (repo / ".venv").exists()


def test_a_bad_option_is_one_line(tmp_path):
    repo, env = _machine(tmp_path, ALL, uid=1000)
    r = _run(repo, env, "--bogus")
    assert r.returncode == 1
    assert r.stderr.strip() == "setup: unknown option '--bogus': allowed --check or nothing"


@pytest.mark.parametrize("system", ["Darwin", "MINGW64_NT-10.0"])
def test_on_macos_and_windows_it_installs_nothing_and_says_so(tmp_path, system):
    repo, env = _machine(tmp_path, {"python3-venv"}, uid=501, system=system, apt=False)
    r = _run(repo, env)
    assert r.returncode == 0, r.stderr
    first = r.stderr.strip().splitlines()[0]
    name = "macOS" if system == "Darwin" else "Windows"
    assert first.startswith(f"setup: {name}: nothing to install from the system"), first
    assert "libegl1" not in first  # EGL is Linux's: CGL and WGL need nothing
    log = (tmp_path / "log").read_text()
    assert "apt-get" not in log and "python -m venv .venv" in log and "pip install" in log


def test_on_a_linux_without_apt_it_names_what_to_install_and_goes_on(tmp_path):
    repo, env = _machine(tmp_path, ALL - {"libegl1", "xvfb"}, uid=0, apt=False)
    r = _run(repo, env)
    assert r.returncode == 0, r.stderr
    first = r.stderr.strip().splitlines()[0]
    assert first.startswith("setup: no apt-get on this system, nothing installed"), first
    assert "libegl1" in first and "dnf install mesa-libEGL" in first and "xvfb" in first
    assert "pip install" in (tmp_path / "log").read_text()


def test_without_apt_and_without_venv_it_stops_in_one_line(tmp_path):
    repo, env = _machine(tmp_path, ALL - {"python3-venv"}, uid=0, apt=False)
    r = _run(repo, env)
    assert r.returncode == 1
    (line,) = r.stderr.strip().splitlines()
    assert "venv" in line and "python.org" in line
    assert not (repo / ".venv").exists()

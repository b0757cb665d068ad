"""Under pytest-xdist each worker's llvmpipe gets its share of the cores (tests/helpers/cores.py):
tried with pytest in a process of its own on a small test folder, as a developer's run would be."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from app import PROJECT_ROOT
from tests.helpers.cores import LLVMPIPE_THREADS, cores, setting, share

SAMPLE = """
import os

def test_a():
    print("threads:", os.environ.get("LP_NUM_THREADS", "unset"))
    assert False  # shows the printed line in the report

def test_b():
    print("threads:", os.environ.get("LP_NUM_THREADS", "unset"))
    assert False
"""


def _threads(folder: Path, *args: str, **env_extra: str) -> list[str]:
    env = {k: v for k, v in os.environ.items()
           if k not in (LLVMPIPE_THREADS, "PYTEST_XDIST_WORKER", "PYTEST_ADDOPTS")}
    env.update(env_extra, PYTHONPATH=str(PROJECT_ROOT))
    (folder / "pytest.ini").write_text("[pytest]\n")
    (folder / "test_sample.py").write_text(SAMPLE)
    r = subprocess.run([sys.executable, "-m", "pytest", "-p", "tests.helpers.cores",
                        "-p", "no:cacheprovider", "-q", "--rootdir", str(folder),
                        "-c", str(folder / "pytest.ini"), *args],
                       cwd=folder, env=env, capture_output=True, text=True, timeout=120)
    assert r.returncode == 1, r.stdout + r.stderr
    found = [line.split(":", 1)[1].strip() for line in r.stdout.splitlines()
             if line.startswith("threads:")]
    assert len(found) == 2, r.stdout
    return found


def test_the_share_is_the_cores_over_the_workers_at_least_one():
    assert [share(2, 2), share(16, 4), share(3, 2), share(2, 8), share(None, 2)] == [1, 4, 1, 1, 1]


def test_a_share_of_one_core_rasterizes_on_the_drawing_thread():
    assert [setting(2, 2), setting(16, 4), setting(3, 2), setting(None, 2)] == [0, 4, 0, 0]


@pytest.mark.slow
def test_xdist_workers_render_with_their_share_of_the_cores(tmp_path):
    assert _threads(tmp_path, "-n", "2") == [str(setting(cores(), 2))] * 2


@pytest.mark.slow
def test_a_value_the_user_set_is_kept(tmp_path):
    assert _threads(tmp_path, "-n", "2", LP_NUM_THREADS="3") == ["3", "3"]


def test_one_process_leaves_llvmpipe_every_core(tmp_path):
    assert _threads(tmp_path) == ["unset", "unset"]

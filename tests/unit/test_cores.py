"""Under pytest-xdist each worker's llvmpipe gets its share of the cores (tests/helpers/cores.py):
tried with pytest in a process of its own on a small test folder, as a developer's run would be.
And each test process keeps the bytecode of the test modules it collects, and freezes what the
collection made out of the garbage collector's walks (tests/conftest.py)."""

from __future__ import annotations

import gc
import os
import platform
import subprocess
import sys
from pathlib import Path

import pytest

from app import PROJECT_ROOT
from tests.helpers.cores import (
    BLAS_THREADS,
    LLVMPIPE_THREADS,
    MEMORY_SETTINGS,
    cores,
    setting,
    share,
)

#: what every run hands its processes, after the threads
MEMORY = " ".join(MEMORY_SETTINGS.values())

SAMPLE = """
import os

def _say():
    import numpy  # noqa: F401 - what a worker's BLAS reads is set before numpy starts it
    names = ("LP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS",
             "MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_", "NUMPY_MADVISE_HUGEPAGE")
    print("threads:", " ".join(os.environ.get(n, "unset") for n in names))

def test_a():
    _say()
    assert False  # shows the printed line in the report

def test_b():
    _say()
    assert False
"""


def _threads(folder: Path, *args: str, **env_extra: str) -> list[str]:
    env = {k: v for k, v in os.environ.items()
           if k not in (LLVMPIPE_THREADS, *BLAS_THREADS, *MEMORY_SETTINGS, "PYTEST_XDIST_WORKER",
                        "PYTEST_ADDOPTS")}
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
def test_xdist_workers_render_and_multiply_with_their_share_of_the_cores(tmp_path):
    n = share(cores(), 2)
    assert _threads(tmp_path, "-n", "2") == [f"{setting(cores(), 2)} {n} {n} {MEMORY}"] * 2


@pytest.mark.slow
def test_a_value_the_user_set_is_kept(tmp_path):
    n = share(cores(), 2)
    mmap = MEMORY_SETTINGS["MALLOC_MMAP_THRESHOLD_"]
    kept = _threads(tmp_path, "-n", "2", LP_NUM_THREADS="3", OMP_NUM_THREADS="5",
                    MALLOC_TRIM_THRESHOLD_="7", NUMPY_MADVISE_HUGEPAGE="1")
    assert kept == [f"3 {n} 5 {mmap} 7 1"] * 2


def test_one_process_leaves_llvmpipe_and_blas_every_core_and_sets_malloc(tmp_path):
    assert _threads(tmp_path) == [f"unset unset unset {MEMORY}"] * 2


FAULTS = """
import resource
import numpy as np

faults = []
for mib in (8, 24, 16, 24, 8, 24):
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    a = np.ones(mib << 20, np.uint8)
    faults.append(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)
    del a
print(*faults)
"""


@pytest.mark.skipif(platform.libc_ver()[0] != "glibc", reason="not glibc: the settings are glibc's")
def test_with_the_malloc_settings_arrays_reuse_the_pages_freed_before():
    """Arrays of 8-24 MiB made and dropped in turn: by default glibc maps fresh pages for the
    third (its threshold has only risen to 24 MiB); with the settings, only the first two
    arrays touch new pages."""
    def faults(**extra):
        env = {k: v for k, v in os.environ.items() if k not in MEMORY_SETTINGS}
        r = subprocess.run([sys.executable, "-c", FAULTS], env={**env, **extra},
                           capture_output=True, text=True, timeout=60, check=True)
        return [int(x) for x in r.stdout.split()]

    default, tuned = faults(), faults(**MEMORY_SETTINGS)
    assert sum(default[2:]) > default[0] // 2, default
    assert sum(tuned[2:]) < tuned[0] // 10, tuned


def test_this_process_kept_the_bytecode_of_the_test_module_it_collected():
    """Whatever $PYTHONDONTWRITEBYTECODE says, the module was rewritten into a cached file."""
    here = Path(__file__)
    if not os.access(here.parent, os.W_OK):
        pytest.skip(f"{here.parent} is read-only: pytest cannot keep bytecode there")
    assert sys.dont_write_bytecode is False
    cache = here.parent / "__pycache__"
    kept = list(cache.glob(f"{here.stem}.*-pytest-{pytest.__version__}.pyc"))
    assert kept, f"no rewritten bytecode of {here.name} in {cache}"


def test_what_collection_made_is_frozen_out_of_the_garbage_collectors_walks():
    """tests/conftest.py freezes the collected modules and items: a full collection then walks
    only what the tests made since (the suite's workers spent 14.4 s collecting, 4.9 s after)."""
    assert gc.get_freeze_count() > 10_000

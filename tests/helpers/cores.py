"""Each pytest-xdist worker gets its share of the cores for software rendering.

Mesa's llvmpipe (the GL of CI and of machines without a GPU) starts one rasterizer thread per
core in every process that renders. Two workers on two cores then run four rasterizer threads
that wait on each other: the full suite took 351 s that way and 272 s with one thread per
worker (2,373 tests, one run each, same machine and hour; user CPU 625 s against 475 s). So
under xdist ``LP_NUM_THREADS`` is set from cores // workers unless the user set it; the workers
and the ``natura`` processes the tests start inherit it, and a GPU driver ignores it. A share of
one core is ``0``: llvmpipe then rasterizes on the thread that draws, with no thread to hand
each frame to and wait for (2,891 tests: 415 s with one rasterizer thread a worker, 381 s with
none; user CPU 707 s against 657 s). A run in one process (``-n 0``) leaves llvmpipe every core.
"""

from __future__ import annotations

import os

#: read by llvmpipe when it creates a context: how many rasterizer threads it starts
LLVMPIPE_THREADS = "LP_NUM_THREADS"


def share(cores: int | None, workers: int) -> int:
    return max(1, (cores or 1) // max(1, workers))


def setting(cores: int | None, workers: int) -> int:
    """``LP_NUM_THREADS`` for a worker: its share of the cores, 0 (the drawing thread alone)
    for a share of one."""
    n = share(cores, workers)
    return 0 if n == 1 else n


def cores() -> int | None:
    """The cores this process may run on (its affinity where the OS says, else all)."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()


def pytest_configure(config):
    # in the controller before it starts the workers (they inherit the environment); in a
    # worker from the count the controller sends, for a worker started some other way
    workers = getattr(config, "workerinput", {}).get("workercount")
    if workers is None:
        workers = getattr(config.option, "numprocesses", None)
    if not isinstance(workers, int) or workers < 2:
        return
    os.environ.setdefault(LLVMPIPE_THREADS, str(setting(cores(), workers)))

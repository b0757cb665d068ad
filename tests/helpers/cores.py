"""Each pytest-xdist worker gets its share of the cores for software rendering.

Mesa's llvmpipe (the GL of CI and of machines without a GPU) starts one rasterizer thread per
core in every process that renders. Two workers on two cores then run four rasterizer threads
that wait on each other: the full suite took 351 s that way and 272 s with one thread per
worker (2,373 tests, one run each, same machine and hour; user CPU 625 s against 475 s). So
under xdist ``LP_NUM_THREADS`` is set to cores // workers (at least 1) unless the user set it;
the workers and the ``natura`` processes the tests start inherit it, and a GPU driver ignores
it. A run in one process (``-n 0``) leaves llvmpipe every core.
"""

from __future__ import annotations

import os

#: read by llvmpipe when it creates a context: how many rasterizer threads it starts
LLVMPIPE_THREADS = "LP_NUM_THREADS"


def share(cores: int | None, workers: int) -> int:
    return max(1, (cores or 1) // max(1, workers))


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
    os.environ.setdefault(LLVMPIPE_THREADS, str(share(cores(), workers)))

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

numpy's BLAS gets the same share (``OPENBLAS_NUM_THREADS``, and ``OMP_NUM_THREADS`` for a BLAS
built on OpenMP). OpenBLAS starts a thread per core when numpy is imported and its threads spin
for a while after each call: in the ~400 ``natura`` processes the tests start and in the workers
they only took CPU from the rest of a run that already uses every core. ``natura params sky``:
0.28 s of CPU with a thread a core, 0.12 s with one; ``tests/unit`` and ``tests/stability``
under ``-n 2``, back to back: 98.0 s against 89.6 s, user CPU 163 s against 145 s (whole-suite
runs drift by ±25 s with the host's hour, more than this change). The frames ``natura
bench maritime`` times did not change (37.9–45.4 ms either way, three rounds interleaved), so
the app leaves its BLAS as it is.

glibc's malloc gets two settings in every run, one process or many (``MEMORY_SETTINGS``, read
when a process starts, so the workers and the ``natura`` processes have them): arrays up to
32 MiB come from the heap instead of a fresh ``mmap`` each, and freed heap stays with the process
for the next array. The suite's processes make and drop such arrays all the time (frames read
back, bakes, meshes), and on this machine a page touched for the first time costs ~5-50 µs of
kernel time. Full suite, back to back in one hour: 15.1 M page faults against 18.1 M, system CPU
93 s against 105 s, 386 s against 397 s. The leak tests still see a leak: the live-change test
reads the resident memory after ``malloc_trim`` (tests/helpers/leaks.py), which hands the kept
heap back whatever these say, and the session-release loop grew alike over 40 cycles with and
without them (sky 1.95 and 1.91 MB, ocean 4.06 and 3.94 MB; its bound is 8 MB).

numpy gets one (``NUMPY_MADVISE_HUGEPAGE=0``, read when numpy is imported: the workers and the
``natura`` processes, not the process that runs ``-n 0``): it then stops asking the kernel for
2 MiB pages for every array of 4 MiB or more. Where the kernel grants them on request (THP
``madvise``, as here), each first touch clears 2 MiB at once, and on this virtual machine that
cost more than the small pages it saves. Measured here, alternated: the largest STL allowed
(tests/unit/test_mesh_files.py, the test alone, ``-n 0``) 15.3 s with 10.6-11.0 s of system CPU,
and 6.6-7.4 s with 2.8-3.0 s without huge pages; ``tests/unit`` and ``tests/stability`` under
``-n 2``: system CPU 26.1 and 24.6 s, 14.8 s without. Whole-suite runs drift more than that
(303-385 s in one morning, with the setting or without).
A third setting was tried and left out: ``MALLOC_MMAP_MAX_=0`` (every array from the heap) also
halved those two folders' system CPU, but doubled it where a test allocates hundreds of MiB at
once (tests/cli/test_fuzz_residue.py 4.6 → 8.5 s, tests/bench/test_gpu_report.py 1.2 → 5.0 s).
"""

from __future__ import annotations

import os

#: read by llvmpipe when it creates a context: how many rasterizer threads it starts
LLVMPIPE_THREADS = "LP_NUM_THREADS"
#: read by numpy's BLAS when numpy is imported: OpenBLAS, and a BLAS built on OpenMP
BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")
#: read by glibc's malloc when a process starts: the largest request served from the heap, and
#: how much free heap a process keeps before handing it back; read by numpy when it is imported:
#: whether its large arrays ask for huge pages
MEMORY_SETTINGS = {"MALLOC_MMAP_THRESHOLD_": str(32 << 20), "MALLOC_TRIM_THRESHOLD_": str(1 << 30),
                   "NUMPY_MADVISE_HUGEPAGE": "0"}


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
    # every run: the processes it starts inherit the environment
    for name, value in MEMORY_SETTINGS.items():
        os.environ.setdefault(name, value)
    # in the controller before it starts the workers (they inherit the environment); in a
    # worker from the count the controller sends, for a worker started some other way
    workers = getattr(config, "workerinput", {}).get("workercount")
    if workers is None:
        workers = getattr(config.option, "numprocesses", None)
    if not isinstance(workers, int) or workers < 2:
        return
    os.environ.setdefault(LLVMPIPE_THREADS, str(setting(cores(), workers)))
    for name in BLAS_THREADS:
        os.environ.setdefault(name, str(share(cores(), workers)))

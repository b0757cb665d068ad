"""Sessions release everything: a script or a test suite that opens and releases many sessions
must not grow without bound (each kept EGL context cost 8–35 MB).

The bound is a rate: 40 open/release cycles may grow RSS by less than 0.2 MB a session (8 MB),
the rate 100 cycles < 20 MB allowed before, so a leak of a fixed size per session fails at the
same size whatever the count (a kept context is 40–175× over it). Measured on llvmpipe: sky
grows ~0.04 MB a cycle, ocean ~0.06 MB, linearly from the first cycle after the warm-up, with
RSS noise under 1.5 MB — about a third of the bound, at 40 cycles as at 100. What a process
keeps on purpose across sessions (``app.gpu.cache.MEMO``: pure builds, keyed by
content; the parameter declarations; the shader library's remembered expansions) is made in the
warm-up cycles, the same every cycle after (ocean: one entry of 4 kB), so it is not counted as
growth — and a leak through it still is. What released sessions leave in reference cycles is
collected at every ``RELEASES_PER_COLLECT``-th release (``app.gpu.device``): at most that many
sessions' worth (~0.1 MB) waits, a constant (measured: sky 1.86 MB over 40 cycles, 4.29 MB over
100, as with a collection at every release: 1.79 and 4.23)."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

from app import PROJECT_ROOT

CYCLES = 40
PER_SESSION_MB = 0.2
BOUND_MB = PER_SESSION_MB * CYCLES
#: what makes a cycle cheap without changing what it opens and releases: every program, texture,
#: target and context is still made each cycle, only smaller (the ocean's FFT grids and the sky's
#: reflection cubemap are most of a default ocean cycle's time on llvmpipe, ~0.5 s)
SETS = {"sky": [], "ocean": ["ocean.fft_size=64", "sky.cubemap_size=16"]}

# Runs in a fresh interpreter so the figure is this loop's alone (not the test session's heap).
_LOOP = textwrap.dedent("""
    import json, os, sys
    from app.runtime import open_session, render_frames, scene_params

    def rss_mb():
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 1e6

    scene, cycles, sets = sys.argv[1], int(sys.argv[2]), json.loads(sys.argv[3])
    def cycle():
        s = open_session(scene, scene_params(scene, sets=sets))
        next(render_frames(s, (64, 36)))
        s.release()
        return s
    for _ in range(3):  # warm: imports, first compiles, numpy caches
        cycle()
    start = rss_mb()
    for _ in range(cycles):
        s = cycle()
    print(json.dumps({"growth_mb": rss_mb() - start,
                      "context_released": type(s.gpu.ctx.mglo).__name__ == "InvalidObject"}))
""")


@pytest.mark.parametrize("scene", ["sky", "ocean"])
def test_sessions_grow_rss_by_less_than_0_2_mb_each(scene):
    r = subprocess.run([sys.executable, "-c", _LOOP, scene, str(CYCLES), json.dumps(SETS[scene])],
                       cwd=PROJECT_ROOT, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr[-2000:]
    out = json.loads(r.stdout.strip().splitlines()[-1])
    assert out["context_released"]
    assert out["growth_mb"] < BOUND_MB, (
        f"{CYCLES} open/release cycles of {scene!r} grew RSS by {out['growth_mb']:.1f} MB "
        f"(allowed < {BOUND_MB:g} MB: {PER_SESSION_MB:g} MB a session)")


def test_release_frees_the_context_it_made_and_not_a_given_one(gl_ctx):
    from app.gpu.device import Gpu

    own = Gpu()
    own.release()
    own.release()  # twice is harmless
    assert not own.owns_context
    assert type(own.ctx.mglo).__name__ == "InvalidObject"  # moderngl's mark of a released one

    given = Gpu(gl_ctx)
    given.texture("test", "t", (4, 4), 4)
    given.release()
    assert not given.allocations
    gl_ctx.texture((1, 1), 4).release()  # the caller's context still works


def test_what_released_sessions_leave_in_cycles_is_collected_within_a_few_releases():
    """The full collection runs at every RELEASES_PER_COLLECT-th release (not each: it walks
    the whole heap), so a released session's cycles wait at most that many releases — with
    Python's own collector off, so it is the release that collects them."""
    import gc
    import weakref

    from app.gpu import device
    from app.gpu.device import RELEASES_PER_COLLECT, Gpu

    class Effect:  # an effect and its session's Gpu in a cycle, as the scenes' are
        def __init__(self, gpu):
            self.gpu, gpu.owner = gpu, self

    was_enabled = gc.isenabled()
    gc.disable()
    try:
        gc.collect()
        while device._releases % RELEASES_PER_COLLECT:  # from where earlier releases left it
            device._return_freed_memory()
        left = []
        for _ in range(RELEASES_PER_COLLECT):
            gpu = Gpu()
            left.append(weakref.ref(Effect(gpu)))
            gpu.release()
            del gpu
        assert all(ref() is None for ref in left[:-1]) and left[-1]() is not None
        for _ in range(RELEASES_PER_COLLECT):
            Gpu().release()
        assert left[-1]() is None
    finally:
        if was_enabled:
            gc.enable()

"""Timing GPU work: ``ctx.finish()`` around a pass, warm-up, then the median of N; several
variants in the same shuffled rounds (:func:`time_interleaved`); one frame split into named
parts that add up to it (:class:`FrameClock`); pipeline-statistics counts.

GPU timer queries are used only on a hardware GPU (on llvmpipe they are unreliable) and are
reported beside wall time, never instead of it.
"""

from __future__ import annotations

import ctypes
import random
import statistics
import time
from dataclasses import dataclass, field
from typing import Any, Callable

import moderngl

from ..errors import NaturaError
from .rawgl import gl_function


@dataclass
class Timing:
    name: str
    wall_ms: list[float] = field(default_factory=list)
    gpu_ms: list[float] = field(default_factory=list)

    @property
    def median_ms(self) -> float:
        return statistics.median(self.wall_ms) if self.wall_ms else float("nan")

    def summary(self) -> dict:
        w = sorted(self.wall_ms)
        out = {
            "median_ms": self.median_ms,
            "min_ms": w[0] if w else None,
            "p90_ms": w[min(len(w) - 1, int(0.9 * len(w)))] if w else None,
            "n": len(w),
        }
        if self.gpu_ms:
            out["gpu_median_ms"] = statistics.median(self.gpu_ms)
        return out


def time_call(ctx: moderngl.Context, name: str, fn: Callable[[], None], warmup: int = 3,
              repeat: int = 15, gpu_queries: bool = False) -> Timing:
    """Run ``fn`` ``warmup`` times, then ``repeat`` times with ``ctx.finish()`` on both sides
    (:func:`time_interleaved` with one variant)."""
    return time_interleaved(ctx, {name: fn}, warmup, repeat,
                            gpu_queries=gpu_queries).timings[name]


@dataclass
class Interleaved:
    """Times of several variants measured in the same rounds (each variant once per round, in
    a shuffled order), so machine load moves them together and their ratios hold."""

    timings: dict[str, Timing]
    rounds: int

    def quartiles(self, name: str) -> tuple[float, float, float]:
        """(p25, median, p75) of ``name``'s wall times in ms."""
        return quartiles_of(self.timings[name].wall_ms)

    def ratio(self, name: str, reference: str) -> dict:
        """Per-round ratios ``name / reference``: their median and quartiles."""
        a, b = self.timings[name].wall_ms, self.timings[reference].wall_ms
        rs = [x / y for x, y in zip(a, b) if y > 0]
        p25, med, p75 = quartiles_of(rs)
        return {"median": med, "p25": p25, "p75": p75, "n": len(rs)}

    def summary(self, reference: str | None = None) -> dict:
        out = {}
        for name, t in self.timings.items():
            p25, med, p75 = self.quartiles(name)
            entry: dict[str, Any] = {"median_ms": med, "p25_ms": p25, "p75_ms": p75,
                                     "n": len(t.wall_ms)}
            if reference is not None and name != reference:
                entry["ratio_to_" + reference] = self.ratio(name, reference)
            out[name] = entry
        return out


def quartiles_of(values: list[float]) -> tuple[float, float, float]:
    """(p25, median, p75) of ``values``, inclusive method (NaN for none)."""
    if not values:
        nan = float("nan")
        return nan, nan, nan
    if len(values) == 1:
        return values[0], values[0], values[0]
    q = statistics.quantiles(values, n=4, method="inclusive")
    return q[0], q[1], q[2]


def time_interleaved(ctx: moderngl.Context, variants: dict[str, Callable[[], None]],
                     warmup: int = 2, rounds: int = 15, seed: int = 0,
                     gpu_queries: bool = False, budget_s: float | None = None,
                     min_rounds: int = 5) -> Interleaved:
    """Warm each variant up, then ``rounds`` rounds in which every variant runs once (shuffled
    order per round, ``ctx.finish()`` on both sides of each run). With ``gpu_queries`` a GPU
    timer query is wrapped around each run too (hardware GPUs only; beside wall time). With
    ``budget_s``, no round starts once the rounds have taken that long and at least
    ``min_rounds`` are done (a slow scene then reports fewer rounds, never fewer than that)."""
    rng = random.Random(seed)
    names = list(variants)
    for name in names:
        for _ in range(max(0, warmup)):
            variants[name]()
    ctx.finish()
    query = ctx.query(time=True) if gpu_queries else None
    timings = {name: Timing(name) for name in names}
    start = time.perf_counter()
    done = 0
    for _ in range(max(1, rounds)):
        if (budget_s is not None and done >= max(1, min_rounds)
                and time.perf_counter() - start > budget_s):
            break
        done += 1
        order = names[:]
        rng.shuffle(order)
        for name in order:
            ctx.finish()
            t0 = time.perf_counter()
            if query is not None:
                with query:
                    variants[name]()
            else:
                variants[name]()
            ctx.finish()
            timings[name].wall_ms.append((time.perf_counter() - t0) * 1e3)
            if query is not None:
                timings[name].gpu_ms.append(query.elapsed / 1e6)
    return Interleaved(timings, done)


#: the part of a frame that is the scene's own work between its passes: clearing the target,
#: resolving a multisampled twin, composing eyes, and the Python between two passes
BETWEEN_PASSES = "scene: clears, resolves, between passes"


class FrameClock:
    """One frame's wall time split into named parts that add up to it.

    A renderer that queues its work (llvmpipe binds draws into scenes it rasterises at the next
    flush; a GPU runs behind the CPU) bills a pass's cost to whoever synchronises next — a
    readback, a ``copy_framebuffer``, the next pass. Here every part ends with ``ctx.finish()``
    inside its own time, so its cost is its own: :meth:`part` first finishes what came before
    (billed to :data:`BETWEEN_PASSES`: the scene's clears and resolves), then runs the part and
    finishes it. The time from :meth:`begin` to :meth:`end` is exactly the sum of the parts; the
    finishes themselves cost the frame a little overlap, which a whole frame timed without them
    shows (``natura bench``'s remainder). ``issue`` holds, per part, the time until its work was
    queued (uniforms, draw calls and, on a software renderer, the vertex stage), before the
    finish waited for the rest.
    """

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self.parts: dict[str, float] = {}
        self.issue: dict[str, float] = {}
        self._mark = 0.0
        self._depth = 0

    def begin(self) -> None:
        self.parts, self.issue = {}, {}
        self._depth = 0
        self.ctx.finish()
        self._mark = time.perf_counter()

    def _add(self, table: dict[str, float], name: str, seconds: float) -> None:
        table[name] = table.get(name, 0.0) + seconds * 1e3

    def part(self, name: str, fn: Callable[[], Any]) -> Any:
        """Run ``fn`` as the part ``name`` (summed when it runs more than once in the frame,
        e.g. once per eye); a part run inside another part is that part's."""
        if self._depth:
            return fn()
        self.ctx.finish()
        start = time.perf_counter()
        self._add(self.parts, BETWEEN_PASSES, start - self._mark)
        self._depth += 1
        try:
            out = fn()
            queued = time.perf_counter()
            self.ctx.finish()
        finally:
            self._depth -= 1
        self._mark = time.perf_counter()
        self._add(self.parts, name, self._mark - start)
        self._add(self.issue, name, queued - start)
        return out

    def end(self) -> dict[str, float]:
        """Finish the frame (what followed the last part is the scene's); the parts in ms."""
        self.ctx.finish()
        self._add(self.parts, BETWEEN_PASSES, time.perf_counter() - self._mark)
        return dict(self.parts)


PIPELINE_EXTENSION = "GL_ARB_pipeline_statistics_query"
#: query targets of GL_ARB_pipeline_statistics_query (and GL_SAMPLES_PASSED, GL 1.5)
PIPELINE_COUNTERS = {
    "vertices_submitted": 0x82EE,
    "primitives_submitted": 0x82EF,
    "vertex_shader_invocations": 0x82F0,
    "clipping_input_primitives": 0x82F6,
    "clipping_output_primitives": 0x82F7,
    "fragment_shader_invocations": 0x82F4,
    "compute_shader_invocations": 0x82F5,
    "samples_passed": 0x8914,
}
_GL_QUERY_RESULT = 0x8866


class PipelineStatistics:
    """Counts of one run of a callable: vertices and primitives submitted, shader invocations
    per stage and samples passed, from GL_ARB_pipeline_statistics_query. moderngl does not
    expose these queries, so the GL entry points come from the context's own loader
    (``app.gpu.rawgl``: EGL, GLX, WGL or CGL alike). ``available`` is False, with ``reason``
    saying why, where the context lacks the extension or the entry points cannot be found;
    then :meth:`count` returns None.
    """

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self.available = False
        self.reason: str | None = None
        self._fns: dict[str, Any] = {}
        if PIPELINE_EXTENSION not in ctx.extensions:
            self.reason = f"{PIPELINE_EXTENSION} is not supported by this context"
            return
        try:
            self._load()
        except NaturaError as exc:
            self.reason = f"no GL entry points for the queries ({exc})"
            return
        self.available = True

    def _load(self) -> None:

        uint, sizei, p_uint = ctypes.c_uint, ctypes.c_int, ctypes.POINTER(ctypes.c_uint)
        protos: dict[str, tuple[Any, ...]] = {
            "glGenQueries": (sizei, p_uint),
            "glDeleteQueries": (sizei, p_uint),
            "glBeginQuery": (uint, uint),
            "glEndQuery": (uint,),
            "glGetQueryObjectui64v": (uint, uint, ctypes.POINTER(ctypes.c_uint64)),
        }
        for fn, args in protos.items():
            self._fns[fn] = gl_function(self.ctx, fn, *args)

    def count(self, fn: Callable[[], None]) -> dict[str, int] | None:
        """Run ``fn`` once with every counter's query active around it; the counts."""
        if not self.available:
            return None
        n = len(PIPELINE_COUNTERS)
        ids = (ctypes.c_uint * n)()
        f = self._fns
        self.ctx.finish()
        _ = self.ctx.error  # clears an error flag left by earlier work: not the queries'
        f["glGenQueries"](n, ids)
        try:
            for i, target in enumerate(PIPELINE_COUNTERS.values()):
                f["glBeginQuery"](target, ids[i])
            try:
                fn()
            finally:
                for target in PIPELINE_COUNTERS.values():
                    f["glEndQuery"](target)
            out = {}
            for i, key in enumerate(PIPELINE_COUNTERS):
                value = ctypes.c_uint64(0)
                f["glGetQueryObjectui64v"](ids[i], _GL_QUERY_RESULT, ctypes.byref(value))
                out[key] = int(value.value)
        finally:
            f["glDeleteQueries"](n, ids)
        error = self.ctx.error
        if error != "GL_NO_ERROR":
            self.available = False
            self.reason = f"the queries raised {error}"
            return None
        return out

"""Timing GPU work: ``ctx.finish()`` around a pass, warm-up, then the median of N.

GPU timer queries are used only on a hardware GPU (on llvmpipe they are unreliable) and are
reported beside wall time, never instead of it.
"""

from __future__ import annotations

import statistics
import time
from dataclasses import dataclass, field
from typing import Callable

import moderngl


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
    """Run ``fn`` ``warmup`` times, then ``repeat`` times with ``ctx.finish()`` on both sides."""
    timing = Timing(name)
    for _ in range(max(0, warmup)):
        fn()
    ctx.finish()
    query = ctx.query(time=True) if gpu_queries else None
    for _ in range(max(1, repeat)):
        ctx.finish()
        t0 = time.perf_counter()
        if query is not None:
            with query:
                fn()
        else:
            fn()
        ctx.finish()
        timing.wall_ms.append((time.perf_counter() - t0) * 1e3)
        if query is not None:
            timing.gpu_ms.append(query.elapsed / 1e6)
    return timing

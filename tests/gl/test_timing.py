"""Interleaved timing: every variant runs once per round, ratios come from the same rounds."""

from __future__ import annotations

import time

from app.gpu.timing import time_interleaved


def test_interleaved_rounds_run_each_variant_once_per_round_and_ratio_by_round(gl_ctx):
    calls: list[str] = []

    def variant(name, seconds):
        def run():
            calls.append(name)
            time.sleep(seconds)
        return run

    result = time_interleaved(gl_ctx, {"slow": variant("slow", 0.004),
                                       "fast": variant("fast", 0.001)}, warmup=1, rounds=6)
    measured = calls[2:]  # after one warm-up each
    assert len(measured) == 12
    for r in range(6):  # each round holds both, in some order
        assert sorted(measured[2 * r:2 * r + 2]) == ["fast", "slow"]
    ratio = result.ratio("slow", "fast")
    assert ratio["n"] == 6 and ratio["p25"] <= ratio["median"] <= ratio["p75"]
    assert 1.5 < ratio["median"] < 8.0, ratio
    summary = result.summary(reference="fast")
    assert summary["slow"]["ratio_to_fast"]["median"] == ratio["median"]
    assert summary["fast"]["p25_ms"] <= summary["fast"]["median_ms"] <= summary["fast"]["p75_ms"]

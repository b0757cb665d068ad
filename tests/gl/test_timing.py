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


def test_pipeline_statistics_count_a_full_screen_triangle(gl_ctx):
    import moderngl
    import numpy as np
    import pytest

    from app.gpu.timing import PIPELINE_EXTENSION, PipelineStatistics

    stats = PipelineStatistics(gl_ctx)
    if not stats.available:
        assert stats.reason and stats.count(lambda: None) is None
        pytest.skip(stats.reason)
    assert PIPELINE_EXTENSION in gl_ctx.extensions
    fbo = gl_ctx.simple_framebuffer((48, 16))
    prog = gl_ctx.program(
        vertex_shader="#version 330\nin vec2 p; void main() { gl_Position = vec4(p, 0, 1); }",
        fragment_shader="#version 330\nout vec4 c; void main() { c = vec4(1); }")
    vbo = gl_ctx.buffer(np.array([-1, -1, 3, -1, -1, 3], dtype="f4"))
    vao = gl_ctx.vertex_array(prog, [(vbo, "2f", "p")])
    try:
        fbo.use()
        counts = stats.count(lambda: vao.render(moderngl.TRIANGLES))
        assert counts is not None
        assert counts["vertices_submitted"] == 3 and counts["primitives_submitted"] == 1
        assert counts["samples_passed"] == 48 * 16
        assert 48 * 16 <= counts["fragment_shader_invocations"] <= 2 * 48 * 16
        assert stats.count(lambda: None)["fragment_shader_invocations"] == 0
    finally:
        for obj in (vao, vbo, prog, fbo):
            obj.release()


def test_interleaved_gpu_queries_sit_beside_wall_time(gl_ctx):
    result = time_interleaved(gl_ctx, {"a": lambda: None, "b": lambda: None}, warmup=0,
                              rounds=3, gpu_queries=True)
    for t in result.timings.values():
        assert len(t.wall_ms) == 3 and len(t.gpu_ms) == 3


def test_frame_clock_parts_add_up_and_each_pass_pays_its_own_work(gl_ctx):
    """FrameClock: the parts sum to the frame's time (begin to end), and a pass's queued work is
    finished inside its own part, not billed to the part that synchronises next."""
    import time as _time

    from app.gpu.timing import BETWEEN_PASSES, FrameClock

    clock = FrameClock(gl_ctx)
    before = _time.perf_counter()
    clock.begin()
    clock.part("slow", lambda: _time.sleep(0.03))
    clock.part("quick", lambda: None)
    clock.part("slow", lambda: _time.sleep(0.01))  # a second run of a part adds to it
    parts = clock.end()
    after = _time.perf_counter()
    assert set(parts) == {"slow", "quick", BETWEEN_PASSES}
    assert parts["slow"] >= 40.0  # both sleeps, inside the part
    # the parts tile the frame: their sum lies within the time around begin() … end()
    assert 40.0 <= sum(parts.values()) <= (after - before) * 1e3
    assert clock.issue["slow"] <= parts["slow"] and clock.issue["quick"] <= parts["quick"]

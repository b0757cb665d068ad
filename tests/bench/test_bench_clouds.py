"""`natura bench clouds`: the accuracy table of the cloud marchers and its equal-error chart."""

from __future__ import annotations

import numpy as np

from app.runtime import open_session, scene_params


def test_clouds_sweep_reports_table_and_equal_error(gl_ctx, tmp_path, monkeypatch):
    from app.bench import clouds as cbench

    monkeypatch.setenv("NATURA_CACHE", str(tmp_path / "cache"))
    sets = ["time.hour=10", "bake_shape.size=32", "bake_detail.size=16", "bake_weather.size=64"]
    session = open_session("clouds", scene_params("clouds", sets=sets), ctx=gl_ctx)
    try:
        acc = cbench.accuracy(session, size=(48, 27), warmup=0, repeat=1)
        tab = cbench.table(session, sizes=((32, 32),), warmup=0, repeat=1)
        change = cbench.default_change(session, sizes=((48, 27),), warmup=0, rounds=3)
    finally:
        session.release()
    rows = {r["config"]: r for r in acc["rows"]}
    uniform = [rows[f"uniform {n} steps (thesis marcher)"]["mean"] for n in (16, 64, 256)]
    assert uniform[0] > uniform[1] > uniform[2]  # more steps, closer to the 512-step reference
    assert rows["energy-conserving"]["mean"] < rows["uniform 64 steps (thesis marcher)"]["mean"]
    assert len(tab["rows"]) == 3 and {r["preset"] for r in tab["rows"]} == set(cbench.PRESETS)
    # the default march is adaptive, and the bench checks it against its stated budget
    budget = acc["budget"]
    assert budget["adaptive_default"] and budget["default"] == "default adaptive 64 steps"
    assert budget["mean_bound"] == cbench.BUDGET_FACTOR * rows["default uniform 64 steps"]["mean"]
    assert budget["within"], budget
    # the thesis's marcher (Table 6.1) stays the uniform one, one setting away from the default
    assert cbench.THESIS["clouds.adaptive_steps"] is False
    (row,) = change["rows"]
    assert row["ratio"]["n"] == 3 and row["ratio"]["median"] > 0
    assert row["after"]["mean"] == rows["default adaptive 64 steps"]["mean"]
    assert row["before"]["mean"] == rows["default uniform 64 steps"]["mean"]
    report = {"renderer": "test", "sweep": {"accuracy": acc, "table": tab,
                                            "default_change": change}}
    cbench.chart(report, tmp_path / "c.png")
    text = cbench.summary(report)
    assert (tmp_path / "c.png").stat().st_size > 10000 and "equal error" in text
    assert "error budget" in text and "within the budget" in text


def test_amortised_march_chart_grades_each_schedule_against_the_converged_march(gl_ctx, tmp_path,
                                                                                monkeypatch):
    """app/bench/amortise.py: one row per march resolution × refresh fraction, besides the
    thesis's march; after one refresh cycle of a still camera every schedule is within the
    converged-still bound; the pan is graded, and a 30°/s pan throws no history away."""
    from app.bench import amortise

    monkeypatch.setenv("NATURA_CACHE", str(tmp_path / "cache"))
    sets = ["time.hour=10", "bake_shape.size=32", "bake_detail.size=16", "bake_weather.size=64"]
    session = open_session("clouds", scene_params("clouds", sets=sets), ctx=gl_ctx)
    try:
        report = amortise.sweep(session, "clouds", (48, 27), warmup=0, repeat=1)
        assert session.params["clouds.march_scale"] == "auto"  # restored
    finally:
        session.release()
    rows = report["rows"]
    assert rows[0]["pan"] is None and rows[0]["fraction"] == 1.0
    assert [(r["scale"], r["refresh"]) for r in rows[1:]] == list(amortise.SCHEDULES)
    for r in rows[1:]:
        assert r["still"]["mean"] <= amortise.STILL_BOUND["mean"], r
        assert r["still"]["p99"] <= amortise.STILL_BOUND["p99"], r
        assert r["resets_in_pan"] == 0 and np.isfinite(r["pan"]["mean"]) and r["ms"] > 0
    assert rows[-1]["fraction"] < rows[1]["fraction"]
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    amortise.plot(ax, report)
    fig.savefig(tmp_path / "a.png")
    plt.close(fig)
    assert (tmp_path / "a.png").stat().st_size > 10000
    text = "\n".join(amortise.summary(report))
    assert "quarter, refresh 1/16" in text and "pan 30°/s" in text

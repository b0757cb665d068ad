"""`natura bench planet`: the accuracy report carries method 1's error at its own defaults against
the independent reference (``method_1_defaults``), and its summary says it."""

from __future__ import annotations

from app.runtime import open_session, scene_params


def test_planet_accuracy_reports_method_1_at_its_defaults(gl_ctx):
    from app.bench import planet as pbench

    # non-default method-1 knobs and method: method 1 is still measured at its defaults
    sets = ["planet.method=lut", "planet.universe_centre=camera", "planet.pc_rule=midpoint"]
    session = open_session("planet", scene_params("planet", sets=sets), ctx=gl_ctx)
    try:
        p = session.params
        pbench._set_view(session, "ground")
        ref = pbench.reference_for_view(session, (32, 18), steps=512)
        alone = pbench.method_1_at_defaults(session, (32, 18), ref)
        assert (p["planet.method"], p["planet.universe_centre"], p["planet.pc_rule"]) == (
            "lut", "camera", "midpoint")     # left as it found them
        for name in ("planet.universe_centre", "planet.pc_rule"):
            p.set(name, p.spec(name).default)
        acc = pbench.accuracy(session, size=(32, 18), time_size=(32, 18), warmup=0, repeat=1,
                              steps_list=(30,), lut_sizes=(), shadow_sizes=(), ref_steps=512,
                              hillaire=False)
    finally:
        session.release()
    m1 = acc["method_1_defaults"]
    assert m1["universe_centre"] == "earth" and m1["pc_rule_used"] == "thesis"
    assert m1["n_steps"] == 30 and m1["universe_radius"] > 6.36e6
    assert 0.0 < m1["in_rel_mean"] < 0.30 and m1["t_mean"] < 0.05, m1
    assert abs(alone["in_mean"] - m1["in_mean"]) < 1e-6
    rows = {(r["method"], r["knob"], r["value"]): r for r in acc["rows"]}
    # the n_steps row at 30 is method 1 at its defaults too: the same error
    assert abs(rows[("brute_force", "n_steps", 30)]["in_mean"] - m1["in_mean"]) < 1e-6
    # each method with the ozone layer, against the reference with the same layer: the same
    # accuracy as without it (measured 0.00518 and 0.00522 for the LUT method)
    for method in ("brute_force", "lut", "shadowed"):
        oz = rows[(method, "ozone layer on", 1.0)]["in_mean"]
        assert oz < 1.5 * rows[(method, "n_steps", 30)]["in_mean"], (method, oz)
    report = {"renderer": "test", "sweep": {"accuracy": acc, "table": {"rows": []}}}
    text = pbench.summary(report)
    assert "method 1 at its defaults" in text and f"{100.0 * m1['in_rel_mean']:.1f} %" in text

"""Quality by budget (app/teach/quality.py, ``--quality auto``): the knob families read from
the shipped sweeps (docs/bench-*.json, no GL), the rules of the pick as properties — a tighter
error budget never chooses a cheaper setting, the chosen setting's measured error is within the
budget, an impossible budget chooses nothing and says why — and the command line's refusals
(exit 2, one line). The render with --quality auto: tests/cli/test_cli_quality.py."""

from __future__ import annotations

import copy
import json
import math

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from app import PROJECT_ROOT
from app.cli import main
from app.errors import UsageError
from app.runtime import scene_params
from app.teach import quality as q

SHIPPED = ("planet", "clouds", "ocean", "materials")


def _doc(scene: str):
    return PROJECT_ROOT / "docs" / f"bench-{scene}.json"


@pytest.fixture(scope="module")
def shipped() -> dict[str, list[q.Family]]:
    return {scene: q.families(scene, _doc(scene)) for scene in SHIPPED}


def _family(pairs, size=(100, 100)) -> q.Family:
    points = [q.Point(f"p{i}", {"x.k": i}, ms, err, size) for i, (ms, err) in enumerate(pairs)]
    return q.Family("test", "fx", "k", "units", points, "test")


# ---- families from the shipped sweeps --------------------------------------------------------

def test_every_shipped_scene_has_families_of_valid_settings(shipped):
    for scene, fams in shipped.items():
        assert fams, scene
        for fam in fams:
            params = scene_params(scene)
            assert fam.scene == scene and fam.metric and fam.points, fam.title
            assert len({p.label for p in fam.points}) == len(fam.points), fam.title
            for p in fam.points:
                assert p.ms > 0 and math.isfinite(p.ms), (fam.title, p)
                assert p.error >= 0 and math.isfinite(p.error), (fam.title, p)
                for name, value in p.sets.items():
                    params.set(name, value)  # raises on an unknown name or a bad value
            for name in fam.requires:
                assert name in params, (fam.title, name)


def test_planet_has_a_family_per_method_knob(shipped):
    knobs = {f.knob for f in shipped["planet"]}
    for expected in ("N_STEPS (method 1, brute force)", "N_STEPS (method 2, optical-depth LUT)",
                     "N_STEPS (method 3, LUT + shadows)",
                     "optical-depth LUT size (method 2, optical-depth LUT)",
                     "shadow-map size (method 3, LUT + shadows)",
                     "LUT sizes (× the defaults) (method 4, Hillaire)"):
        assert expected in knobs, knobs
    ocean = {f.knob for f in shipped["ocean"]}
    assert ocean == {"FFT size × cascades", "Gerstner wave count"}


# ---- the rules, as properties ----------------------------------------------------------------

pairs = st.lists(st.tuples(st.floats(0.01, 1000.0), st.floats(0.0, 10.0)), min_size=1,
                 max_size=12)
budgets = st.floats(0.0, 12.0)


@settings(max_examples=150, deadline=None)
@given(pairs, budgets, budgets)
def test_a_tighter_error_budget_never_chooses_a_cheaper_setting(points, e1, e2):
    e1, e2 = sorted((e1, e2))
    fam = _family(points)
    c1, c2 = q.choose(fam, e1), q.choose(fam, e2)
    if c1.point is not None:
        assert c2.point is not None
        assert c1.point.ms >= c2.point.ms
    for c, e in ((c1, e1), (c2, e2)):
        if c.point is not None:
            assert c.point.error <= e
            # the cheapest of those within the budget
            assert all(p.ms >= c.point.ms for p in fam.points if p.error <= e)


@settings(max_examples=100, deadline=None)
@given(st.data())
def test_the_rules_hold_on_the_shipped_families(shipped, data):
    fams = [f for fs in shipped.values() for f in fs]
    fam = data.draw(st.sampled_from(fams), label="family")
    errors = sorted(p.error for p in fam.points)
    e1, e2 = sorted(data.draw(st.lists(st.sampled_from(errors) | st.floats(0, 2 * errors[-1]),
                                       min_size=2, max_size=2), label="budgets"))
    c1, c2 = q.choose(fam, e1, size=(64, 36)), q.choose(fam, e2, size=(64, 36))
    if c1.point is not None:
        assert c1.point.error <= e1
        assert c1.ms(c1.point) >= c2.ms(c2.point)
    else:
        assert c1.status == "none" and "no measured setting has error ≤" in c1.reason


@settings(max_examples=150, deadline=None)
@given(pairs, st.floats(0.0, 9.9))
def test_an_impossible_error_budget_chooses_nothing_and_says_why(points, below):
    fam = _family(points)
    best = min(p.error for p in fam.points)
    budget = best * below / 10
    assume(budget < best)  # a point with no error meets every budget ≥ 0
    c = q.choose(fam, budget)
    assert c.point is None and c.status == "none"
    assert "no measured setting has error ≤" in c.reason and "the most accurate" in c.reason
    assert "nothing chosen" in c.line()


@settings(max_examples=150, deadline=None)
@given(pairs, st.floats(0.001, 1200.0), st.floats(0.001, 1200.0))
def test_a_looser_ms_budget_never_chooses_a_less_accurate_setting(points, m1, m2):
    m1, m2 = sorted((m1, m2))
    fam = _family(points)
    c1, c2 = q.choose(fam, ms_budget=m1), q.choose(fam, ms_budget=m2)
    if c1.point is not None:
        assert c1.point.ms <= m1 and c2.point is not None
        assert c2.point.error <= c1.point.error
    else:
        assert "no measured setting fits" in c1.reason


@settings(max_examples=150, deadline=None)
@given(pairs, budgets, st.floats(0.001, 1200.0))
def test_both_budgets_cheapest_within_both_else_most_accurate_that_fits(points, e, m):
    fam = _family(points)
    c = q.choose(fam, e, m)
    both = [p for p in fam.points if p.error <= e and p.ms <= m]
    fits = [p for p in fam.points if p.ms <= m]
    if both:
        assert c.status == "chosen" and c.point.error <= e and c.point.ms <= m
        assert c.point.ms == min(p.ms for p in both)
    elif fits:
        assert c.status == "over" and c.point.ms <= m and c.point.error > e
        assert c.point.error == min(p.error for p in fits)
        assert "kept the most accurate that fits" in c.reason
    else:
        assert c.point is None and "no measured setting fits" in c.reason


def test_ms_scale_by_pixel_count_except_fixed_costs():
    p = q.Point("x", {}, 10.0, 0.1, (100, 100), fixed_ms=4.0)
    assert p.ms_at((100, 100)) == 10.0 and p.ms_at(None) == 10.0
    assert p.ms_at((200, 100)) == pytest.approx(4.0 + 6.0 * 2)


# ---- pick: what applies, --set, relative budgets, sources ------------------------------------

def test_families_of_another_method_are_skipped_with_the_reason():
    picks = q.pick("planet", 0.02, sweeps=_doc("planet"), size=(64, 36))
    by = {c.family.knob: c for c in picks}
    skipped = by["N_STEPS (method 1, brute force)"]
    assert skipped.status == "skipped" and skipped.point is None
    assert "planet.method=brute_force; yours is shadowed" in skipped.line()
    chosen = by["N_STEPS (method 3, LUT + shadows)"]
    assert chosen.status == "chosen" and chosen.point.error <= 0.02
    assert "cheapest within the error budget" in chosen.line()
    params = scene_params("planet", sets=["planet.method=lut"])
    by = {c.family.knob: c for c in q.pick("planet", 0.02, sweeps=_doc("planet"), params=params)}
    assert by["N_STEPS (method 2, optical-depth LUT)"].status == "chosen"
    assert by["N_STEPS (method 3, LUT + shadows)"].status == "skipped"
    # the τ(PC) rule as it takes effect: by_method is the midpoint rule for method 2
    assert by["N_STEPS, thesis τ(PC) rule (method 2, optical-depth LUT)"].status == "skipped"
    params.set("planet.pc_rule", "thesis")
    by = {c.family.knob: c for c in q.pick("planet", 0.02, sweeps=_doc("planet"), params=params)}
    assert by["N_STEPS, thesis τ(PC) rule (method 2, optical-depth LUT)"].status != "skipped"
    assert by["N_STEPS (method 2, optical-depth LUT)"].status == "skipped"


def test_the_users_set_wins_and_the_line_says_so():
    params = scene_params("planet", sets=["planet.n_steps=60"])
    picks = q.pick("planet", 0.02, sweeps=_doc("planet"), params=params,
                   explicit=["planet.n_steps"])
    c = next(c for c in picks if c.family.knob == "N_STEPS (method 3, LUT + shadows)")
    assert c.status == "yours" and c.point is None and c.would is not None
    assert "your --set planet.n_steps wins (the picker would choose N_STEPS=" in c.line()
    assert "planet.n_steps" not in picks.changes(params)
    before = params["planet.n_steps"]
    picks.apply(params)
    assert params["planet.n_steps"] == before


def test_a_relative_budget_is_times_the_current_error():
    picks = q.pick("ocean", "2x", sweeps=_doc("ocean"))
    c = next(c for c in picks if c.family.knob == "FFT size × cascades")
    assert c.current is not None and c.current.label == "FFT 256² × 3 cascades"
    assert c.error_budget == pytest.approx(2 * c.current.error)
    assert c.point is not None and c.point.error <= c.error_budget


def test_clouds_reprojection_counts_as_it_takes_effect():
    """``window`` reprojects in the window only: the reprojected sweep applies there."""
    knob = "view steps (adaptive, energy-conserving, reprojected)"
    params = scene_params("clouds", sets=["clouds.reprojection=window"])  # default: on
    render = {c.family.knob: c for c in q.pick("clouds", 0.01, sweeps=_doc("clouds"),
                                               params=params)}
    window = {c.family.knob: c for c in q.pick("clouds", 0.01, sweeps=_doc("clouds"),
                                               params=params, interactive=True)}
    assert render[knob].status == "skipped" and "clouds.reprojection=on" in render[knob].reason
    assert window[knob].status == "chosen" and window[knob].point.error <= 0.01


def test_a_scene_without_sweeps_says_so_in_one_line(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    picks = q.pick("sky", 0.1)
    lines = picks.lines(scene_params("sky"))
    assert len(lines) == 1 and "no measured sweeps for sky" in lines[0]
    assert "keeping the settings" in lines[0] and not picks.sets


def test_the_newest_own_run_with_sweeps_is_read_first(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    report = json.loads(_doc("materials").read_text())
    (tmp_path / "bench-results").mkdir()
    mine = copy.deepcopy(report)
    mine["sweep"]["ring_edges"]["filtered"]["median_ms"] = 99.0
    (tmp_path / "bench-results" / "materials-0002.json").write_text(json.dumps(mine))
    bare = {k: v for k, v in report.items() if k != "sweep"}  # a --no-sweep run
    (tmp_path / "bench-results" / "materials-0003.json").write_text(json.dumps(bare))
    found = q.load_sweeps("materials")
    assert found.source.startswith("bench-results/materials-0002.json")
    fam = q.families("materials")[0]
    assert max(p.ms for p in fam.points) == 99.0


def test_other_benches_families_from_their_report_layout():
    shading = {"scene": "shading", "sweep": {"parallax": [{"size": [320, 180], "rows": [
        {"angle": a, "method": m, "layers": n, "median_ms": n * 0.1 + a / 100,
         "mean_px": 8.0 / n * (90 - a) / 30}
        for a in (10.0, 30.0, 60.0) for m in ("steep", "occlusion") for n in (4, 8, 16, 32)]
        + [{"angle": 10.0, "method": "bare", "layers": None, "median_ms": 1.0, "mean_px": 3.0}]}]}}
    fams = q.families("shading", shading)
    assert [f.knob for f in fams] == ["parallax layers (steep)", "parallax layers (occlusion)"]
    assert fams[0].requires == {"shading.parallax_mode": 2}
    assert fams[0].points[0].error == pytest.approx(8.0 / 4 * 80 / 30)  # the worst view (10°)
    surfaces = {"scene": "surfaces", "sweep": {
        "shadows": {"rows": [{"size": s, "bias": "thesis 0.3+0.01", "filter": "hard",
                              "cascades": c, "mismatch": 1.0 / s, "ms": s / 100}
                             for s in (256, 1024) for c in (0, 4)]},
        "transparency": {"size": [256, 256], "rows": [
            {"view": v, "method": m, "ms": ms, "rms": e}
            for v in ("panes", "smoke") for m, ms, e in (("peeled_1", 1.0, 0.2),
                                                         ("peeled_2", 1.5, 0.05),
                                                         ("peeled_reference", 9.0, 0.0),
                                                         ("wboit", 0.8, 0.1))]}}}
    fams = {f.knob: f for f in q.families("surfaces", surfaces)}
    assert set(fams) == {"shadow-map size (hard filter, one map)",
                         "shadow-map size (hard filter, 4 cascades)", "depth-peeling layers"}
    peel = fams["depth-peeling layers"]
    assert [p.sets["surfaces.peel_layers"] for p in peel.points] == [1, 2, 64]
    params = scene_params("surfaces", sets=["surfaces.shadow_filter=hard",
                                            "surfaces.transparency=peeled"])
    by = {c.family.knob: c for c in q.pick("surfaces", 0.002, sweeps=surfaces, params=params,
                                           size=(512, 512))}
    assert by["shadow-map size (hard filter, one map)"].status == "skipped"  # 4 cascades here
    shadow = by["shadow-map size (hard filter, 4 cascades)"].point
    assert shadow.sets == {"surfaces.shadow_map_size": 1024}
    assert shadow.ms_at((512, 512)) == shadow.ms  # a map's cost does not follow the pixels
    assert by["depth-peeling layers"].point.label == "64 layers"


# ---- charts ----------------------------------------------------------------------------------

def test_chart_and_plot_arrays_show_the_chosen_point(tmp_path, shipped):
    from PIL import Image

    picks = q.pick("planet", 0.02, 40.0, sweeps=_doc("planet"), size=(320, 180))
    c = next(c for c in picks if c.point is not None)
    a = q.plot_arrays(c.family, c)
    assert a["labels"][a["chosen"]] == c.point.label and a["error_budget"] == 0.02
    assert a["ms"].shape == a["error"].shape == (len(c.family.points),)
    assert a["ms"][a["chosen"]] <= 40.0
    path = tmp_path / "chart.png"
    q.chart_png(c.family, c, path)
    with Image.open(path) as im:
        assert im.size[0] > 200 and im.size[1] > 150
    with pytest.raises(UsageError, match="refusing to overwrite"):
        q.chart_png(c.family, c, path)


# ---- the command line: bad budgets are one line, exit 2 ---------------------------------------

@pytest.mark.parametrize("args, words", [
    (["--quality", "auto", "--error-budget", "-0.5"], "--error-budget '-0.5' is out of range"),
    (["--quality", "auto", "--error-budget", "nan"], "--error-budget 'nan' is not finite"),
    (["--quality", "auto", "--error-budget", "lots"], "--error-budget 'lots' is not a number"),
    (["--error-budget", "0.01"], "--error-budget needs --quality auto"),
    (["--quality", "fixed", "--ms-budget", "5"], "--ms-budget needs --quality auto"),
    (["--quality", "auto"], "--quality auto needs a budget"),
    (["--quality", "auto", "--ms-budget", "nan"], "--ms-budget 'nan' is out of range"),
    (["--quality", "auto", "--error-budget", "1", "--sweeps", "docs/bench-ocean.json"],
     "is a bench of 'ocean'"),
])
def test_bad_budgets_exit_2_with_one_line(args, words, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(PROJECT_ROOT)  # --sweeps docs/... is relative
    out = tmp_path / "never.png"
    code = main(["render", "planet", "--size", "64x36", "--out", str(out), *args])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and words in err[0], err
    assert "allowed" in err[0] and not out.exists()

"""`natura bench SCENE --budget MS` (app/bench/budget.py): the options each scene's sweeps give,
read from the reports in docs/ (no GL), and the passes over a budget."""

from __future__ import annotations

import copy
import json

import pytest

from app import PROJECT_ROOT
from app.bench import budget as bb

SCENES = ("clouds", "planet", "ocean", "materials")


def _report(scene: str) -> dict:
    return json.loads((PROJECT_ROOT / "docs" / f"bench-{scene}.json").read_text())


@pytest.mark.parametrize("scene", SCENES)
def test_every_scene_with_sweeps_gives_options_with_time_and_error(scene):
    found = bb.scene_options(_report(scene))
    assert found is not None and found.options, scene
    for o in found.options:
        assert o.ms > 0 and o.error >= 0 and o.size[0] > 0 and o.sets
        assert all("." in name for name in o.sets)


def test_fitting_options_are_ready_set_strings_lowest_error_first():
    report = copy.deepcopy(_report("clouds"))
    # as if the bench had run with adaptive steps off: the options that turn them on say so
    report["parameters"]["clouds.adaptive_steps"] = False
    lines = bb.budget_view(report, 20.0)
    w, h = report["size"]  # the shipped run's size
    assert lines[0].startswith(f"budget 20 ms at {w}x{h}") and "over the budget" in lines[0]
    assert lines[1].startswith("over budget:") and "clouds.march" in lines[1]
    options = [ln for ln in lines if ln.startswith("  --set")]
    assert 1 <= len(options) <= bb.TOP
    errors = [float(ln.rsplit("error ", 1)[1].split()[0]) for ln in options]
    assert errors == sorted(errors)
    for ln in options:
        assert float(ln.split("≈", 1)[1].split()[0]) <= 20.0
    # values equal to the bench's parameters are left out; booleans as --set takes them
    assert "clouds.adaptive_steps=true" in options[0]
    assert "clouds.jitter" not in options[0]


def test_set_strings_parse_as_parameters():
    """Each option's ``--set`` strings go through what ``scene_params(scene, sets=...)`` does
    with them (``set_from_string``, which raises on an unknown name or a bad value), on one
    parameter set per scene put back to its defaults after each option (declaring a scene's
    parameters reads its GLSL annotations, about 0.1 s for the planet each time)."""
    from app.runtime import scene_params

    for scene in SCENES:
        report = _report(scene)
        found = bb.scene_options(report)
        assert found is not None
        params = scene_params(scene)
        defaults = params.values()
        for o in found.options:
            text = bb.set_string(o.sets, report["parameters"])
            sets = [t for t in text.split() if t != "--set"]
            if text.startswith("("):
                continue
            for assignment in sets:
                params.set_from_string(assignment)
            for name, value in defaults.items():
                params.set(name, value)


def test_times_scale_by_pixel_count_and_say_so():
    report = _report("materials")  # the ring sweep is timed at 64x64, the bench at 640x360
    lines = bb.budget_view(report, 100_000.0)
    assert any("scaled by pixel count from the sweep's 64x64 to 640x360" in ln for ln in lines)
    o = next(o for o in bb.scene_options(report).options if o.size == (64, 64))
    assert o.ms_at((640, 360)) == pytest.approx(o.ms * 640 * 360 / 64**2)


def test_nothing_fits_names_the_fastest():
    lines = bb.budget_view(_report("ocean"), 1.0)
    assert lines[-1].startswith("no measured option fits 1 ms; the fastest: --set ")


def test_a_report_without_sweeps_prints_only_the_passes_over_budget():
    report = _report("clouds")
    report.pop("sweep")
    lines = bb.budget_view(report, 1.0)
    assert len(lines) == 2 and lines[1].startswith("over budget: ")
    assert "reference" not in lines[1]
    assert bb.budget_view(report, 99_999.0)[1] == "no pass is over 99999 ms"


def test_a_sweep_of_another_layout_is_one_note_not_a_crash():
    report = copy.deepcopy(_report("planet"))
    report["sweep"]["accuracy"] = {"rows": "not rows"}
    lines = bb.budget_view(report, 10.0)
    assert any("layout" in ln for ln in lines)


def test_shadow_map_error_is_bounded_by_the_reference_error_at_the_current_steps():
    report = _report("planet")
    found = bb.scene_options(report)
    shadow = [o for o in found.options if "planet.shadow_map_size" in o.sets]
    assert shadow
    n = report["parameters"]["planet.n_steps"]
    base = next(r for r in report["sweep"]["accuracy"]["rows"] if r["method"] == "shadowed"
                and r["knob"] == "n_steps" and r["value"] == n)
    assert all(o.error >= base["in_mean"] for o in shadow)


def test_options_are_costed_as_the_frame_times_their_ratio_to_the_current_settings():
    """A sweep that times a 64×64 slice says how much an option costs relative to the current
    settings, not what the frame costs: the view applies that ratio to the measured frame."""
    from app.bench.budget import budget_view

    report = {"scene": "materials", "size": [640, 360],
              "passes": {"frame": {"median_ms": 8.0}},
              "parameters": {"materials.filter_rings": False},
              "sweep": {"ring_edges": {"size": [64, 64],
                                       "hard": {"median_ms": 1.0, "mean_error": 0.06},
                                       "filtered": {"median_ms": 1.5, "mean_error": 0.006}}}}
    lines = budget_view(report, 11.0)
    assert any("time ratio to the current settings'" in line for line in lines)
    # 8 ms × 1.5 = 12 ms > 11: filtered edges do not fit; the current settings do
    assert not any("filter_rings=true" in line for line in lines), lines
    assert lines[-1].startswith("  (the bench's own settings)  ≈8.000 ms"), lines
    lines = budget_view(report, 13.0)
    assert lines[-2].startswith("  --set materials.filter_rings=true  ≈12.000 ms"), lines

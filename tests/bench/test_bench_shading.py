"""`natura bench shading`: the parallax sweep (error against the reference and the shading
pass's time per method, n and view angle), the critical-angle figures, the lighting/toon cost
table, the JSON, the chart and the printed summary."""

from __future__ import annotations

import json
import math

import pytest

from app.bench import shading as sbench
from tests.helpers.readme import bench_lane, command_lines


def _finite(*values) -> bool:
    return all(isinstance(v, (int, float)) and math.isfinite(v) for v in values)


#: the README's example (tests/helpers/readme.py runs it once per test run, for the walk-through
#: and for this test)
EXAMPLE = "natura bench shading --size 160x90 --repeat 3"


@pytest.mark.slow  # runs (or waits for) the README example: the whole bench
def test_cli_bench_shading_writes_json_chart_and_summary(tmp_path_factory):
    folder, r = bench_lane(tmp_path_factory, EXAMPLE)
    (name,) = [n for n in r.written if n.endswith(".json")]
    out = folder / name
    report = json.loads(out.read_text())
    assert {"shading", "frame", "reference.fullscreen"} <= set(report["passes"])
    assert out.with_suffix(".png").stat().st_size > 20000
    assert "parallax on the brick wall at 160x90" in r.stdout
    assert "lighting × toon × Gouraud" in r.stdout and "critical angle" in r.stdout

    sweep = report["sweep"]
    # the lab's frame against the full shadow taps (PCSS): timed in the same rounds; the fast
    # taps change the picture by a few levels where the penumbra is, if at all
    speed = {r["variant"]: r for r in sweep["speed"]["rows"]}
    assert list(speed) == ["reference", "taps fast", "default"]
    assert speed["reference"]["chosen"] == {"taps": "full"}
    assert speed["taps fast"]["chosen"] == {"taps": "fast"}
    assert all(_finite(r["ms"], r["p99_levels"]) and r["ms"] > 0 for r in speed.values())
    assert speed["taps fast"]["p99_levels"] <= 8
    assert "the lab's frame, shadow taps at 160x90" in r.stdout
    # the outline figures (spec/003 §2.13): every method on the sphere and the table; the
    # per-vertex hull tears open on the low-poly table, the smoothed-normal hull does not
    outlines = {(r["object"], r["method"]): r for r in sweep["outlines"]["rows"]}
    assert len(outlines) == 14 and all(r["finite"] for r in outlines.values())
    assert all(0.0 <= r["iou"] <= 1.0 and r["contour_ms"] >= 0.0 for r in outlines.values())
    assert outlines[("table", "hull")]["gaps"] > outlines[("table", "hull_smooth")]["gaps"]
    assert outlines[("sphere", "hull")]["iou"] > 0.7
    assert "outlines at 128x128" in r.stdout
    (par,) = sweep["parallax"]
    assert par["size"] == [160, 90]
    for view in par["views"]:  # the wall fills the view, at nearly the nominal angle
        assert view["covered_share"] > 0.97
        assert view["elevation_min"] < view["angle"] < view["elevation_max"]
        assert view["elevation_max"] - view["elevation_min"] < 12.0
    rows = par["rows"]
    # off, reference and bare once per angle; steep and occlusion at every n
    assert len(rows) == len(sbench.ANGLES) * (3 + 2 * len(sbench.LAYERS))
    for row in rows:
        assert _finite(row["median_ms"], row["mean_px"], row["p99_px"], row["mean_colour"],
                       row["p99_colour"], row["image_mean"], row["image_p99"]), row
        assert row["median_ms"] > 0 and row["mean_px"] >= 0

    def get(angle, method, n=None):
        (row,) = [x for x in rows if x["angle"] == angle and x["method"] == method
                  and x["layers"] == n]
        return row

    # at the grazing angle: occlusion < steep < bare for the same n (n = 4 excepted: four
    # layers are coarser than bare's single offset there)
    bare = get(10.0, "bare")
    for n in sbench.LAYERS[1:]:
        assert get(10.0, "occlusion", n)["mean_px"] < get(10.0, "steep", n)["mean_px"] \
            < bare["mean_px"], n
    for angle in sbench.ANGLES:  # more layers, less error; the render follows the twin
        for method in ("steep", "occlusion"):
            assert get(angle, method, 64)["mean_px"] < get(angle, method, 4)["mean_px"]
            assert get(angle, method, 64)["image_mean"] < get(angle, method, 4)["image_mean"]
        assert get(angle, "reference")["mean_px"] == 0.0
    # the thesis's critical angle: at 60° occlusion's n = 12 and n = 32 agree within 2/255,
    # at 10° neither method's do
    crit = {(c["angle"], c["method"]): c for c in sweep["critical_angle"]}
    assert crit[(60.0, "occlusion")]["p99_colour"] < 2 / 255
    for method in ("steep", "occlusion"):
        assert crit[(10.0, method)]["mean_colour"] > crit[(60.0, method)]["mean_colour"]
        assert crit[(10.0, method)]["share_visible"] > 0.2

    light = sweep["lighting"]
    assert len(light["rows"]) == 3 * 4 * 2
    assert all(_finite(x["median_ms"], x["ratio_to_default"]) and x["median_ms"] > 0
               for x in light["rows"])


def test_the_example_is_the_readmes_own():
    """The command these tests read the output of is an example the README shows, as written:
    a README edit that changes it must change this module too."""
    assert EXAMPLE in command_lines()

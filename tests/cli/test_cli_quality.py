"""``natura render SCENE --quality auto`` (app/teach/quality.py) as a user runs it: the picks
from the shipped planet sweeps (docs/bench-planet.json) printed one line per knob family with
why, applied to the render, and the --set values the user gave left as given. The picker's
rules and the refusals of bad budgets: tests/unit/test_quality.py. Images are tiny (64×36)."""

from __future__ import annotations

import numpy as np
from PIL import Image

from tests.helpers.cli import SMALL, messages, run


def test_render_planet_with_an_error_budget_prints_and_applies_its_picks(tmp_path):
    r = run("render", "planet", "--size", SMALL, "--quality", "auto", "--error-budget", "0.02",
            "--set", "planet.shadow_map_size=1024", "--out", "auto.png", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "auto.png" and (tmp_path / "auto.png").stat().st_size > 0
    lines = messages(r.stderr)
    assert lines[0] == "quality auto for planet at 64x36: error ≤ 0.02 (each family's own metric)"
    assert lines[1].startswith("  sweeps: docs/bench-planet.json (shipped)")
    steps = next(ln for ln in lines if ln.startswith("planet · N_STEPS (method 3, LUT + shadows)"))
    assert "N_STEPS=20:" in steps and "≤ 0.02 (cheapest within the error budget; now N_STEPS=30" \
        in steps, steps
    skipped = next(ln for ln in lines if ln.startswith("planet · N_STEPS (method 1"))
    assert "skipped — measured with planet.method=brute_force; yours is shadowed" in skipped
    shadow = next(ln for ln in lines if ln.startswith("planet · shadow-map size"))
    assert "your --set planet.shadow_map_size wins" in shadow
    assert lines[-1] == "as --set: planet.n_steps=20"
    # the picks are what was rendered: the same image as the same values given by hand
    by_hand = run("render", "planet", "--size", SMALL, "--set", "planet.n_steps=20",
                  "--set", "planet.shadow_map_size=1024", "--out", "hand.png", cwd=tmp_path)
    assert by_hand.returncode == 0, by_hand.stderr
    assert "quality" not in by_hand.stderr
    with Image.open(tmp_path / "auto.png") as a, Image.open(tmp_path / "hand.png") as b:
        assert np.array_equal(np.asarray(a), np.asarray(b))

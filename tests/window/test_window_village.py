"""The village's keys (spec/003 §1, §2.9–2.11, §2.15) typed as real X key events with xdotool
into its window under Xvfb: W walks the hero, C steps through the three cameras, each switch key
steps its parameter from the scene's start and changes the image, V shows the two eyes side by
side."""

from __future__ import annotations

import math
import shutil

import pytest

from tests.helpers.window_driver import XDOTOOL_SKIP, XVFB_SKIP, drive

pytestmark = [
    pytest.mark.window,
    pytest.mark.skipif(shutil.which("xvfb-run") is None, reason=XVFB_SKIP),
    pytest.mark.skipif(shutil.which("xdotool") is None, reason=XDOTOOL_SKIP),
]


def test_the_village_keys_typed_in_the_window(tmp_path):
    r, _ = drive("village-keys", tmp_path)
    assert r["render_error"] == ""
    walk = r["walk"]
    assert walk["camera"] == "third" and walk["frames"] >= 10
    moved = math.dist(walk["from"], walk["to"])
    assert moved > 0.5  # W walked the hero (northward, the way it faces)
    assert walk["to"][1] < walk["from"][1]
    steps = {  # the scene's start, then each tap
        "village.camera": ["third", "first", "free", "third"],
        "grass.method": ["billboard", "instanced"],
        "fog.mode": ["exp2", "off"],
        "fog.height": [False, True],
        "village.toon": [2, 3],
        "toon_water.type": ["complex", "simple"],
        "village.lamps_auto": [True, False],
    }
    for name, expected in steps.items():
        assert [v for v, _ in r[name]] == expected, name
        assert len({s for _, s in r[name]}) > 1, name  # the image changes as the key steps
    assert r["vr"]["enabled"] is True and r["vr"]["halves_differ"] > 1e-3
    assert r["vr_off"] is False
    assert any(h.startswith("Village inspector") for h in r["inspector"]["headers"])
    assert r["closing"] is True

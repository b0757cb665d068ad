"""The village's keys (spec/003 §1, §2.9–2.11, §2.15) typed as real X key events with xdotool
into its window under Xvfb: W walks the hero, C steps through the three cameras, each switch key
steps its parameter from the scene's start and changes the image, V shows the two eyes side by
side."""

from __future__ import annotations

import math
import shutil

import pytest

from tests.helpers.window_driver import NO_XVFB, XDOTOOL_SKIP, XVFB_SKIP, drive

pytestmark = [
    pytest.mark.window,
    pytest.mark.skipif(NO_XVFB, reason=XVFB_SKIP),
    pytest.mark.skipif(shutil.which("xdotool") is None, reason=XDOTOOL_SKIP),
]


STEPS = {  # the scene's start, then each tap
    "village.camera": ["third", "first", "free", "third"],
    "grass.method": ["billboard", "instanced"],
    "fog.mode": ["exp2", "off"],
    "fog.height": [False, True],
    "village.toon": [2, 3],
    "toon_water.type": ["complex", "simple"],
    "village.lamps_auto": [True, False],
}


def test_the_typed_keys_are_the_villages_and_step_as_its_keymap_says():
    """The window test's premise, without a window: it types every key the village binds to a
    parameter (V, the VR pair, has its own check), and what it expects each tap to give is what
    the key map's cycle or toggle gives from the settings the driver starts with."""
    from app.runtime import scene_params
    from app.scenes.village import VILLAGE
    from app.ui.keymap import cycle_value
    from tests.helpers.window_driver import VILLAGE_LAB_KEYS, VILLAGE_SMALL

    params = scene_params("village", sets=VILLAGE_SMALL)
    lab = {k: a for k, a in VILLAGE.bindings.items()
           if a.startswith(("cycle:", "toggle:")) and k != "V"}
    assert {key.upper(): a for key, name, _ in VILLAGE_LAB_KEYS
            for a in (f"cycle:{name}", f"toggle:{name}") if a in lab.values()} == lab
    for key, name, times in VILLAGE_LAB_KEYS:
        spec, value = params.spec(name), params[name]
        got = [value]
        for _ in range(times):
            value = cycle_value(spec, value)
            got.append(value)
        assert got == STEPS[name], name


def test_the_village_keys_typed_in_the_window(tmp_path):
    r, _ = drive("village-keys", tmp_path)
    assert r["render_error"] == ""
    walk = r["walk"]
    assert walk["camera"] == "third" and walk["frames"] >= 10
    moved = math.dist(walk["from"], walk["to"])
    assert moved > 0.5  # W walked the hero (northward, the way it faces)
    assert walk["to"][1] < walk["from"][1]
    for name, expected in STEPS.items():
        assert [v for v, _ in r[name]] == expected, name
        assert len({s for _, s in r[name]}) > 1, name  # the image changes as the key steps
    assert r["vr"]["enabled"] is True and r["vr"]["halves_differ"] > 1e-3
    assert r["vr_off"] is False
    assert any(h.startswith("Village inspector") for h in r["inspector"]["headers"])
    assert r["closing"] is True

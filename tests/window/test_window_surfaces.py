"""The surfaces lab's keys (spec/003 §2.4–2.8) typed as real X key events with xdotool into its
window under Xvfb: each key steps its parameter through its choices and the image changes."""

from __future__ import annotations

import shutil

import pytest

from tests.helpers.window_driver import NO_XVFB, XDOTOOL_SKIP, XVFB_SKIP, drive

pytestmark = [
    pytest.mark.window,
    pytest.mark.skipif(NO_XVFB, reason=XVFB_SKIP),
    pytest.mark.skipif(shutil.which("xdotool") is None, reason=XDOTOOL_SKIP),
]


STEPS = {  # what each tap gives, from where the driver starts
    "transparency": ["wboit", "peeled", "sorted"],
    "reflection": ["approximation", "perfect", "none", "cube", "box"],
    "specular_model": ["ggx", "thesis"],
    "fresnel": ["schlick", "exact"],
    "shadow_filter": ["pcss", "vsm", "hard", "four_tap", "pcf"],  # from the lab's pcf
    "shadow_cascades": ["0", "2", "4"],
    "failure": ["queue_order", "intersecting"],
    "msaa": ["4", "auto"],  # the driver starts it at 0; auto is 0 on llvmpipe (no A2C quad)
    "debug": ["cascades", "shadow"],
}


def test_the_typed_keys_are_the_labs_and_step_as_its_keymap_says():
    """The window test's premise, without a window: it types every key the lab binds to a
    parameter, and what it expects each tap to give is what the key map's cycle gives from the
    settings the driver starts with."""
    from app.runtime import scene_params
    from app.scenes.surfaces import SURFACES
    from app.ui.keymap import cycle_value
    from tests.helpers.window_driver import SURFACES_LAB_KEYS, SURFACES_SMALL

    params = scene_params("surfaces", sets=SURFACES_SMALL)
    lab = {k: a for k, a in SURFACES.bindings.items() if a.startswith("cycle:surfaces.")}
    assert {key.upper(): f"cycle:surfaces.{name}" for key, name, _ in SURFACES_LAB_KEYS} == lab
    for key, name, times in SURFACES_LAB_KEYS:
        spec, value, got = params.spec(f"surfaces.{name}"), params[f"surfaces.{name}"], []
        for _ in range(times):
            value = cycle_value(spec, value)
            got.append(str(value))
        assert got == STEPS[name], name


def test_the_lab_keys_typed_in_the_window(tmp_path):
    r, _ = drive("surfaces-keys", tmp_path)
    assert r["render_error"] == ""
    for name, expected in STEPS.items():
        assert [v for v, _ in r[name]] == expected, name
        sums = [s for _, s in r[name]]
        assert len(set(sums)) > 1, name  # the image changes as the key steps
    inspector = r["inspector"]
    assert any(h.startswith("Surfaces inspector") for h in inspector["headers"])
    assert {"Lights…", "Transparency…", "Reflections…", "Refraction…", "Shadows…"} <= {
        b.split("##")[0] for b in inspector["buttons"]}
    assert inspector["images"] >= 4  # the shadow atlas, the lamp's faces, the two LUTs
    assert r["closing"] is True

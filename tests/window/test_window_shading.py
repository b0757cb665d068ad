"""The shading lab's keys (spec/003 §2.1–2.3, §2.12) typed as real X key events with xdotool
into its window under Xvfb: each key sets its parameter and the image changes with it."""

from __future__ import annotations

import shutil

import pytest

from tests.helpers.window_driver import NO_XVFB, XDOTOOL_SKIP, XVFB_SKIP, drive

pytestmark = [
    pytest.mark.window,
    pytest.mark.skipif(NO_XVFB, reason=XVFB_SKIP),
    pytest.mark.skipif(shutil.which("xdotool") is None, reason=XDOTOOL_SKIP),
]


def test_the_typed_keys_step_as_the_labs_keymap_says():
    """The window test's premise, without a window: the keys it types are bound as it expects,
    and what it expects each tap to give is what the key map's cycle gives from the lab's start
    (turntable stopped, as the driver starts it)."""
    from app.runtime import scene_params
    from app.scenes.shading import SHADING
    from app.ui.keymap import cycle_value

    b = SHADING.bindings
    assert [b[f"NUMBER_{i}"] for i in (1, 2, 3)] == [
        f"set:shading.lighting_model={m}" for m in (0, 1, 2)]
    assert (b["G"], b["B"], b["L"]) == ("toggle:shading.gouraud", "toggle:shading.rim",
                                        "toggle:shading.bloom")
    params = scene_params("shading", sets=["shading.turntable=0"])
    for key, name, expected in (("T", "toon", [1, 2, 3, 0]),
                                ("V", "parallax_mode", [2, 3, 4, 0, 1]),
                                ("O", "object", ["sphere", "table", "barrel"]),
                                ("K", "contour", ["hull", "hull_smooth", "rim_threshold"])):
        assert b[key] == f"cycle:shading.{name}"
        spec, value, got = params.spec(f"shading.{name}"), params[f"shading.{name}"], []
        for _ in expected:
            value = cycle_value(spec, value)
            got.append(value)
        assert got == expected, name
    assert params["shading.gouraud"] is False and params["shading.rim"] is False
    assert params["shading.bloom"] is False


def test_the_lab_keys_typed_in_the_window(tmp_path):
    r, _ = drive("shading-keys", tmp_path)
    assert r["render_error"] == ""
    assert [m for m, _ in r["model"]] == [0, 1, 2]
    sums = [s for _, s in r["model"]]
    assert sums[0] != sums[1] != sums[2]  # Lambert, Phong, Blinn–Phong differ
    assert [t for t, _ in r["toon"]] == [1, 2, 3, 0]  # T steps through and wraps
    toon_sums = [s for _, s in r["toon"]]
    assert len(set(toon_sums)) == 4
    assert r["gouraud"] is True and r["rim"] is True
    assert r["parallax"] == [2, 3, 4, 0, 1]  # from the thesis's default, bare
    assert r["objects"] == ["sphere", "table", "barrel"]
    # K: the contours in order, each changing the image; L: bloom on
    assert [c for c, _ in r["contours"]] == ["hull", "hull_smooth", "rim_threshold"]
    assert len({s for _, s in r["contours"]}) == 3
    assert r["bloom"] is True
    # the material inspector (spec/003 Fig. 130): its popups and the generated maps
    inspector = r["inspector"]
    assert any(h.startswith("Material inspector") for h in inspector["headers"])
    assert {"Lighting…", "Toon…", "Parallax…"} <= {b.split("##")[0] for b in inspector["buttons"]}
    assert inspector["images"] >= 5  # ramp, masks, normal, height, albedo
    assert r["closing"] is True

"""The ``shading`` scene: the toon-village thesis's lighting and toon lab (spec/003 §2.1–2.3,
§2.12) — the test objects on a turntable under a sun, street lamps and a spot light, every
lighting model, toon mode, bump and parallax method a live switch. ``--mesh FILE`` puts a
user's own OBJ, STL or glTF on the turntable."""

from __future__ import annotations

from ..effects.shading import Shading
from ..effects.shading.effect import BACKGROUND
from .base import Scene
from .keymaps import FLY, KeyMap

SHADING = KeyMap("shading", {
    **FLY.bindings, "NUMBER_1": "set:shading.lighting_model=0",
    "NUMBER_2": "set:shading.lighting_model=1", "NUMBER_3": "set:shading.lighting_model=2",
    "T": "cycle:shading.toon", "G": "toggle:shading.gouraud", "B": "toggle:shading.rim",
    "V": "cycle:shading.parallax_mode", "O": "cycle:shading.object",
    "K": "cycle:shading.contour", "L": "toggle:shading.bloom",
}, FLY.help[:-2] + (
    ("1 / 2 / 3", "Lambert / Phong / Blinn–Phong"), ("T", "toon: none, flat, stepped, ramp"),
    ("G", "Gouraud (per vertex) on / off"), ("B", "rim light on / off"),
    ("V", "parallax: off, bare, steep, occlusion, reference"), ("O", "next object"),
    ("K", "contour: none, hulls, rim silhouettes, edge detectors"), ("L", "bloom on / off"),
) + FLY.help[-2:])


class ShadingScene(Scene):
    name = "shading"
    order = 80
    title = "Lighting and toon lab"
    description = ("Lambert, Phong, Blinn–Phong and rim, Gouraud or per fragment; the thesis's "
                   "CelShader and ComplexCelShader (flat, stepped, ramp, masks, emission); bump "
                   "and parallax mapping on the thesis's test objects (spec/003 §2.1–2.3, §2.12)")
    effects = (Shading,)
    #: the arc of five objects fills the width at 16:9, the ground and their shadows below
    default_camera = {"position": (0.0, 1.25, 4.4), "yaw": 0.0, "pitch": -6.0, "fov": 50.0}
    #: the ground fades into it far from the objects
    background = BACKGROUND
    keymap = SHADING

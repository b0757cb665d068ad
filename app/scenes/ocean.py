"""The ``ocean`` scene: the open sea with its three wave models, switchable with 1 / 2 / 3."""

from __future__ import annotations

from ..effects.clouds import Clouds
from ..effects.clouds_b import CloudsB
from ..effects.ocean import Ocean
from ..effects.sky import Sky
from .base import Scene
from .keymaps import FLY, KeyMap

OCEAN = KeyMap("ocean", {**FLY.bindings, "NUMBER_1": "set:ocean.model=sine",
                         "NUMBER_2": "set:ocean.model=gerstner", "NUMBER_3": "set:ocean.model=fft"},
               FLY.help[:-2] + (("1 / 2 / 3", "waves: sine / Gerstner / FFT"),) + FLY.help[-2:])


class OceanScene(Scene):
    name = "ocean"
    order = 70
    title = "Open sea"
    description = ("sine, Gerstner and FFT waves (Phillips, Pierson–Moskowitz, JONSWAP/TMA, "
                   "cascades, foam) under the day–night sky, with its reflection probe, an "
                   "underwater view and the maritime thesis's clouds (spec/000 §1.1, §1.2, §1.3)")
    effects = (Sky, Clouds, CloudsB, Ocean)
    selectors = {
        "scene.clouds": ("off", {"off": "", "a": "clouds", "b": "clouds_b"},
                         "clouds over the sea: off, a = the cloud thesis (spec/001), "
                         "b = the maritime thesis (spec/000 §1.6)"),
    }
    default_camera = {"position": (0.0, 4.0, 0.0), "yaw": 262.0, "pitch": -2.0, "fov": 60.0,
                      "far": 200000.0}
    keymap = OCEAN

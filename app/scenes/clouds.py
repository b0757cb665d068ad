"""The ``clouds`` scene: the two cloud models over the day–night or the Preetham sky."""

from __future__ import annotations

from ..effects.clouds import Clouds
from ..effects.clouds_b import CloudsB
from ..effects.preetham import Preetham
from ..effects.sky import Sky
from .base import Scene


class CloudsScene(Scene):
    name = "clouds"
    order = 60
    title = "Volumetric clouds"
    description = ("model A: the cloud thesis's weather map, density gradients, ray and cone light "
                   "march, Beer, powder and two-lobe HG with the silver lobe (spec/001); model B: "
                   "the maritime thesis's clouds (spec/000 §1.6); over the day–night or the "
                   "Preetham sky")
    effects = (Sky, Preetham, Clouds, CloudsB)
    selectors = {
        "scene.sky": ("day_night", {"day_night": "sky", "preetham": "preetham"},
                      "background: the maritime thesis's day–night sky or Preetham's analytic "
                      "sky (spec/001 §1.8)"),
        "scene.model": ("a", {"a": "clouds", "b": "clouds_b"},
                        "cloud model: a = the cloud thesis (spec/001), b = the maritime thesis "
                        "(spec/000 §1.6)"),
    }
    default_camera = {"position": (0.0, 300.0, 0.0), "yaw": 30.0, "pitch": 25.0, "fov": 70.0,
                      "far": 200000.0}

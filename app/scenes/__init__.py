"""The scene registry: ``natura scenes`` lists it."""

from __future__ import annotations

from ..effects.clouds import Clouds
from ..effects.clouds_maritime import CloudsMaritime
from ..effects.materials import Materials
from ..effects.noiselab import NoiseLab
from ..effects.ocean import Ocean
from ..effects.planet import Planet
from ..ui.keymap import ATMOSPHERE_THESIS, OCEAN
from ..effects.preetham import Preetham
from ..effects.probe import MirrorBall
from ..effects.sky import Sky
from ..errors import UsageError
from .base import Scene

DEFAULT_SCENE = "sky"


class SkyScene(Scene):
    name = "sky"
    title = "Day–night sky at sea level"
    description = "procedural sky, sun, halo, moon and stars over 24 h (spec/000 §1.7)"
    effects = (Sky,)
    camera = {"position": (0.0, 2.0, 0.0), "yaw": 225.0, "pitch": 25.0, "fov": 90.0}


class ProbeScene(Scene):
    name = "probe"
    title = "Sky with a reflection probe"
    description = "the sky's environment cubemap on a mirror ball, re-rendered only when the sky changes (spec/000 §1.7)"
    effects = (Sky, MirrorBall)
    camera = {"position": (0.0, 2.0, 0.0), "yaw": 0.0, "pitch": 5.0, "fov": 60.0}


class MaterialsScene(Scene):
    name = "materials"
    title = "Procedural materials"
    description = "the thesis's volumetric wood on a cube, a sphere and a torus; marble and granite (spec/004)"
    effects = (Materials,)
    camera = {"position": (0.0, 0.5, 3.1), "yaw": 0.0, "pitch": -8.0, "fov": 40.0}
    background = (0.02, 0.02, 0.025)


class PlanetScene(Scene):
    name = "planet"
    title = "Atmospheric scattering, ground to space"
    description = ("single scattering in the thesis's three approximations (brute force, optical-depth LUT, "
                   "LUT + shadow-map light shafts) and Hillaire 2020 multiple scattering (spec/002)")
    effects = (Planet,)
    camera = {"position": (0.0, 2.0, 60.0), "yaw": 0.0, "pitch": 4.0, "fov": 60.0, "far": 5.0e7}
    keymap = ATMOSPHERE_THESIS


class NoiseScene(Scene):
    name = "noise"
    title = "Noise lab"
    description = ("every noise function of glsl/common and the cloud bakes (shape, detail, weather map), "
                   "tiled to show they are seamless (spec/001 §1.1, spec/000 §1.6, spec/004)")
    effects = (NoiseLab,)


class CloudsScene(Scene):
    name = "clouds"
    title = "Volumetric clouds"
    description = ("model A: the cloud thesis's weather map, density gradients, ray and cone light march, Beer, "
                   "powder and two-lobe HG with the silver lobe (spec/001); model B: the maritime thesis's "
                   "clouds (spec/000 §1.6); over the day–night or the Preetham sky")
    effects = (Sky, Preetham, Clouds, CloudsMaritime)
    selectors = {
        "scene.sky": ("day_night", {"day_night": "sky", "preetham": "preetham"},
                      "background: the maritime thesis's day–night sky or Preetham's analytic sky (spec/001 §1.8)"),
        "scene.model": ("a", {"a": "clouds", "b": "clouds_b"},
                        "cloud model: a = the cloud thesis (spec/001), b = the maritime thesis (spec/000 §1.6)"),
    }
    camera = {"position": (0.0, 300.0, 0.0), "yaw": 30.0, "pitch": 25.0, "fov": 70.0, "far": 200000.0}


class OceanScene(Scene):
    name = "ocean"
    title = "Open sea"
    description = ("sine, Gerstner and FFT waves (Phillips, Pierson–Moskowitz, JONSWAP/TMA, cascades, foam) under "
                   "the day–night sky, with its reflection probe, an underwater view and the maritime thesis's "
                   "clouds (spec/000 §1.1–1.3)")
    effects = (Sky, Clouds, CloudsMaritime, Ocean)
    selectors = {
        "scene.clouds": ("off", {"off": "", "a": "clouds", "b": "clouds_b"},
                         "clouds over the sea: off, a = the cloud thesis (spec/001), b = the maritime thesis "
                         "(spec/000 §1.6)"),
    }
    camera = {"position": (0.0, 4.0, 0.0), "yaw": 262.0, "pitch": -2.0, "fov": 60.0, "far": 200000.0}
    keymap = OCEAN


SCENES: dict[str, type[Scene]] = {cls.name: cls for cls in (SkyScene, ProbeScene, MaterialsScene, PlanetScene,
                                                            NoiseScene, CloudsScene, OceanScene)}


def get_scene(name: str) -> type[Scene]:
    try:
        return SCENES[name]
    except KeyError:
        raise UsageError(f"unknown scene {name!r}: allowed {', '.join(SCENES)}") from None



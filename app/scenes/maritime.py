"""The ``maritime`` scene: the maritime thesis's whole demo (spec/000 §0, §1.3–1.5, §2) — the
captain of a sailing boat on the FFT ocean under the day–night sky and the maritime clouds, one
wind for sea, clouds, sails and flag, and the thesis's HUD (the window draws it from
:meth:`MaritimeScene.hud`).

It builds only what it uses: the wind, the day–night sky (with its reflection probe, which also
lights the boat), the maritime clouds (model B), the ocean and the boat — no cloud-thesis bakes,
no Preetham sky.

Cameras (``maritime.camera``): ``chase`` follows the boat (smoothed, so it does not shake with
the swell; looking around orbits it about the boat), by default from its port quarter
(``maritime.chase_angle``: dead astern shows only the transom) and aimed a little above the
deck (``maritime.chase_aim``), so the sky and the low sun of the default hour are in the frame;
``free`` is the fly camera, which can dive under the water and rise above the clouds. C switches
between them.

Weather (``maritime.weather``, the thesis's forced weather states, §2): calm, fair, overcast and
storm each set the wind, the sea and the cloud cover at once (:data:`WEATHER`); fair is what the
defaults are. Changing one of those parameters by hand afterwards (or with ``--set`` at the
start) keeps the others and the state reads ``custom``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..effects.boat import Boat
from ..effects.clouds_b import CloudsB
from ..effects.ocean import Ocean
from ..effects.sky import Sky
from ..effects.wind import Wind
from ..frame import FrameContext
from ..params import Param, ParamSet
from ..sim.maths import compass_degrees, wrap_degrees
from .base import Scene
from .keymaps import FLY, KeyMap

#: forced weather states: the parameters each sets (spec/000 §2, the weather panel)
# (the weather map's coverage thins fair-weather layers into banks and gaps — the preset's
# clouds_b.weather_coverage — and less so the thick layers of the overcast and the storm)
_LIGHT = {"clouds_b.light_absortion_sun": 0.03, "clouds_b.base_brightness": 0.8,
          "clouds_b.darkness_threshold": 0.2, "clouds_b.weather_coverage": 1.0}
WEATHER: dict[str, dict[str, object]] = {
    "calm": {"wind.speed": 3.0, "clouds_b.density_threshold": -7.0,
             "clouds_b.density_multiplier": 0.6, "ocean.choppiness": 0.8, **_LIGHT},
    "fair": {"wind.speed": 8.0, "clouds_b.density_threshold": -5.5,
             "clouds_b.density_multiplier": 1.0, "ocean.choppiness": 1.0, **_LIGHT},
    # thick layers: more of the sun's light absorbed on its way in, a darker floor (grey)
    "overcast": {"wind.speed": 12.0, "clouds_b.density_threshold": -3.5,
                 "clouds_b.density_multiplier": 1.2, "ocean.choppiness": 1.0,
                 "clouds_b.light_absortion_sun": 0.08, "clouds_b.base_brightness": 0.45,
                 "clouds_b.darkness_threshold": 0.12, "clouds_b.weather_coverage": 0.5},
    "storm": {"wind.speed": 22.0, "clouds_b.density_threshold": -2.5,
              "clouds_b.density_multiplier": 2.0, "ocean.choppiness": 1.4,
              "clouds_b.light_absortion_sun": 0.15, "clouds_b.base_brightness": 0.25,
              "clouds_b.darkness_threshold": 0.06, "clouds_b.weather_coverage": 0.15},
}


DEFAULT_WEATHER = "fair"

MARITIME = KeyMap("maritime", {
    **{k: v for k, v in FLY.bindings.items() if k not in ("SPACE", "UP", "DOWN", "ESCAPE")},
    "LEFT": "hold:boat.helm=-0.8", "RIGHT": "hold:boat.helm=0.8",
    "UP": "hold:boat.throttle=0.5", "DOWN": "hold:boat.throttle=-0.5",
    "Z": "hold:boat.sails=-0.4", "X": "hold:boat.sails=0.4",
    "H": "set:boat.helm=0", "C": "cycle:maritime.camera", "T": "toggle_time",
    "SPACE": "toggle_ui", "ESCAPE": "pause_menu",
    "NUMBER_1": "set:maritime.weather=calm", "NUMBER_2": "set:maritime.weather=fair",
    "NUMBER_3": "set:maritime.weather=overcast", "NUMBER_4": "set:maritime.weather=storm",
}, (
    ("Left / Right", "helm to port / starboard (H: centre)"),
    ("Up / Down", "throttle + / −"), ("Z / X", "sheet the sails in / let them out"),
    ("C", "chase camera / free camera"), ("W A S D, Q / E", "fly (free camera)"),
    ("Space", "UI mode / free navigation (mouse look)"),
    ("1 2 3 4", "weather: calm, fair, overcast, storm"), ("T", "pause / resume time"),
    ("[ / ]", "time -/+ 15 min"), ("R", "reset camera"), ("P or F12", "screenshot"),
    ("F1", "hide / show panel"), ("Esc", "pause menu (Esc again: quit)"),
))


@dataclass
class HudState:
    """What the HUD shows, as plain numbers (tested without a window)."""

    heading: float          # compass heading of the bow [°]
    speed: float            # through the water, along the bow [m/s]
    wind_speed: float       # true wind [m/s]
    wind_direction: float   # direction the wind blows toward [°]
    wind_relative: float    # the dial: wind direction − heading, in (−180, 180] [°]
    apparent_angle: float   # apparent wind off the bow (where it comes from) [°]
    helm: float
    sails: float
    throttle: float
    hour: float
    playing: bool
    weather: str
    camera: str


class MaritimeScene(Scene):
    name = "maritime"
    order = 75
    title = "Sailing (maritime demo)"
    description = ("the maritime thesis's demo: a sailing boat that floats (probes or Kerner's "
                   "hydrostatics), steers and sails on the FFT ocean, one wind for sea, clouds, "
                   "sails and flag, the cloth shader, a wake and the HUD (spec/000 §1.3–1.5, §2)")
    effects = (Wind, Sky, CloudsB, Ocean, Boat)
    default_camera = {"position": (0.0, 6.0, 18.0), "yaw": 270.0, "pitch": -10.0, "fov": 60.0,
                      "far": 200000.0}
    keymap = MARITIME

    @classmethod
    def declare_params(cls, library) -> ParamSet:
        params = super().declare_params(library)
        params.add(Param("maritime.camera", "chase", doc="chase: behind the boat; free: the fly "
                         "camera (under the water, above the clouds)", kind="choice",
                         choices=("chase", "free")))
        params.add(Param("maritime.weather", DEFAULT_WEATHER, doc="forced weather state: wind, "
                         "sea and cloud cover at once (custom: as the parameters are)",
                         kind="choice",
                         choices=(*WEATHER, "custom"), section="spec/000 §2"))
        params.add(Param("maritime.chase_distance", 14.0, 4.0, 200.0, "chase camera: distance "
                         "behind the boat", step=0.5, unit="m"))
        params.add(Param("maritime.chase_height", 5.0, 0.5, 100.0, "chase camera: height above "
                         "the water", step=0.5, unit="m"))
        params.add(Param("maritime.chase_angle", 22.0, -180.0, 180.0, "chase camera: angle "
                         "about the boat from dead astern (+ toward the port quarter: the view "
                         "turns to starboard of the bow)", step=1.0, unit="°"))
        params.add(Param("maritime.chase_aim", 3.0, -5.0, 30.0, "chase camera: height above "
                         "the water of the point it looks at, over the boat", step=0.1,
                         unit="m"))
        return params

    def __init__(self, gpu, params, camera=None):
        super().__init__(gpu, params, camera)
        # the default state's values are the parameters' defaults (and the preset's): it is
        # not applied at the start, so a --set of the wind or the clouds is kept (and the state
        # then reads custom); a state chosen with --set is applied on the first frame
        w = params["maritime.weather"]
        self._weather_applied: str | None = w if w == DEFAULT_WEATHER else None
        self._chase: np.ndarray | None = None  # smoothed (x, y, z, heading)
        #: the chase camera's orbit about the boat [°] (yaw, pitch), from looking around
        self._orbit = np.zeros(2)
        self._placed: tuple[float, float] | None = None  # (yaw, pitch) the chase last set

    def apply_weather(self) -> None:
        """Set the parameters of the chosen weather state once, when it changes; once one of
        them is changed by hand (the wind slider, ``--set``), the state reads ``custom``."""
        p = self.params
        w = p["maritime.weather"]
        if w != self._weather_applied:
            self._weather_applied = w
            for name, value in WEATHER.get(w, {}).items():
                if name in p:
                    p.set(name, value)
            return
        state = WEATHER.get(w)
        if state and any(name in p and p[name] != value for name, value in state.items()):
            p.set("maritime.weather", "custom")
            self._weather_applied = "custom"

    def frame(self, size, dt: float = 0.0) -> FrameContext:
        self.apply_weather()
        frame = super().frame(size, dt)
        if self.params["maritime.camera"] == "chase":
            self._follow(dt)
        else:
            self._chase = None
            self._placed = None
        return frame

    def boat(self) -> Boat:
        effect = self.effect("boat")
        assert isinstance(effect, Boat)
        return effect

    def _follow(self, dt: float) -> None:
        """The chase camera: behind the boat along its heading, above the water, looking at the
        deck; position and heading low-pass filtered (time constant 0.6 s)."""
        sim = self.boat().sim
        if sim is None:
            return
        pos = sim.body.position
        target = np.array([pos[0], 0.0, pos[2], sim.heading])
        if self._chase is None or dt <= 0.0:
            self._chase = target
        else:
            a = 1.0 - math.exp(-dt / 0.6)
            d = target - self._chase
            d[3] = math.atan2(math.sin(d[3]), math.cos(d[3]))
            self._chase = self._chase + a * d
        # looking around (mouse look, the turn keys) since the last frame orbits the camera
        # about the boat instead of being overwritten
        if self._placed is not None:
            self._orbit[0] += math.remainder(self.camera.yaw - self._placed[0], 360.0)
            self._orbit[1] = min(60.0, max(-20.0, self._orbit[1]
                                           + self.camera.pitch - self._placed[1]))
        x, _, z, psi = self._chase
        psi = psi + math.radians(self._orbit[0] + self.params["maritime.chase_angle"])
        back = self.params["maritime.chase_distance"]
        height = self.params["maritime.chase_height"] + back * math.sin(
            math.radians(self._orbit[1]))
        bow = np.array([math.sin(psi), 0.0, -math.cos(psi)])
        eye = np.array([x, max(height, 0.5), z]) - back * bow
        look = np.array([x, self.params["maritime.chase_aim"], z]) - eye
        yaw = compass_degrees(look[0], look[2])  # compass, as the camera
        pitch = math.degrees(math.atan2(look[1], math.hypot(look[0], look[2])))
        self.camera.set(position=tuple(eye), yaw=yaw, pitch=pitch)
        self._placed = (self.camera.yaw, self.camera.pitch)

    def hud(self) -> HudState:
        """The HUD's figures (spec/000 §2): the wind dial is the wind's direction minus the
        heading (criterion 36)."""
        p = self.params
        sim = self.boat().sim
        heading = math.degrees(sim.heading) % 360.0 if sim is not None else p["boat.heading"]
        speed = sim.speed() if sim is not None else 0.0
        st = self.boat().sail_state
        return HudState(heading=heading, speed=speed, wind_speed=p["wind.speed"],
                        wind_direction=p["wind.direction"],
                        wind_relative=wrap_degrees(p["wind.direction"] - heading),
                        apparent_angle=math.degrees(st.awa) if st is not None else 0.0,
                        helm=p["boat.helm"], sails=p["boat.sails"], throttle=p["boat.throttle"],
                        hour=p["time.hour"], playing=p["time.playing"],
                        weather=p["maritime.weather"], camera=p["maritime.camera"])

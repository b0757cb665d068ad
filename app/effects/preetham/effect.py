"""The Preetham analytic sky (spec/001 §1.8; Preetham, Shirley & Smits 1999) as a background.

GPU side: ``glsl/preetham/preetham.glsl`` (the model and its ``@param`` uniforms: turbidity,
exposure, sun disk) and ``sky.frag`` (one full-screen pass). CPU side: the numpy twin
``app.sim.preetham`` (every GLSL function has a namesake there; the tests compare them per
pixel).

How a scene composes it — it is a drop-in alternative to the day–night
:class:`~app.effects.sky.Sky`:

* **stage**: the background (it overwrites every pixel of the target); listed after a
  day–night ``Sky`` if the scene has both (then Preetham only replaces the picture, see below)
  and before anything that reads the lights (clouds, water, fog);
* **update()** reads ``frame.sun``: when an earlier effect (a day–night ``Sky``) already set it,
  that sun is used and the frame is left as it is; otherwise the sun comes from this effect's
  ``preetham.sun_elevation`` / ``preetham.sun_azimuth`` and ``update()`` fills ``frame.sun`` and
  ``frame.main_light`` (colour = the sun's transmittance through the atmosphere, paper appendix
  A.1 — yellow-white at noon, dim red at sunset; intensity = ``preetham.sun_intensity`` times
  the day–night sky's horizon fade, so the light goes out smoothly 2° below the horizon) — the
  same interface as ``Sky``;
* **draw()** draws the sky into the target (linear radiance, alpha 1) with the depth test
  off; it reads nothing from the target. A later cloud pass composites over this picture.

Exposure: the model's luminance is in kcd/m²; the picture is ``preetham.exposure`` times the
linear sRGB of it (see app/sim/preetham.py). The default 0.05 puts a clear noon zenith near the
day–night sky's brightness.

Below the horizon (``preetham.ground``): ``horizon`` (the default) is the paper's model clamped
at the horizon — a flat band of the horizon colour; ``sea`` (beyond the paper and the thesis;
the clouds scene's preset turns it on) is the calm sea plane the day–night sky draws too, the
maths shared in ``glsl/common/sea_plane.glsl`` (twin ``app.sim.sea_plane``): it reflects this
sky without the sun disk, hazes toward its horizon colour over ``preetham.sea_haze`` seen from
the camera's height, has the body colour ``preetham.sea_color`` and the glitter of Cox & Munk's
slope variance for ``preetham.sea_wind``. Its light is the frame's ``main_light`` after
``update()`` (this effect's own sun, or the day–night sky's light) — the same light, in the same
units, that the clouds are lit with; its ambient is this sky's cosine-weighted mean radiance
(``app.sim.preetham.sky_ambient``), computed on the CPU only when the sun or the turbidity
change.
"""

from __future__ import annotations

import moderngl
import numpy as np

from ...frame import Stage
from ...gpu.programs import draw_fullscreen, fullscreen
from ...params import Param
from ...sim import preetham as model
from ...sim.daynight import Light, light_fade
from ...sim.sea_plane import GROUNDS, SeaPlane, cox_munk_mss, ground_params
from ..base import Effect

PREETHAM_SKY = fullscreen("preetham/sky")


class Preetham(Effect):
    name = "preetham"
    title = "Preetham analytic sky"
    spec = "spec/001"
    programs = (PREETHAM_SKY,)
    stages = (Stage.BACKGROUND,)
    produces = frozenset({"sun", "main_light"})  # only when no day–night sky filled them first
    consumes = {"sun": "optional"}

    @classmethod
    def python_params(cls) -> list[Param]:
        s = "spec/001 §1.8"
        return [
            Param("preetham.sun_elevation", 45.0, -90.0, 90.0,
                  "sun elevation when no day–night sky runs before this effect (Sky.js "
                  "'inclination')", step=0.1, unit="°", section=s),
            Param("preetham.sun_azimuth", 180.0, 0.0, 360.0,
                  "sun azimuth, 0 = north (−z), 90 = east (+x), when no day–night sky sets the sun",
                  step=0.5, unit="°", section=s),
            Param("preetham.sun_intensity", 1.0, 0.0, 20.0,
                  "main-light intensity of the sun when this effect sets the lights", step=0.05,
                  section=s),
            *ground_params("preetham", s, "the paper's model clamped at the horizon colour",
                           "this sky"),
        ]

    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        self.sun_direction = model.sun_direction(45.0, 180.0)
        self.owns_sun = True
        #: the light the sea is lit with: the frame's main light after update()
        self.main_light: Light | None = None
        #: the sky's ambient (kcd/m², before exposure and twilight), per (sun, turbidity)
        self._ambient = self.keyed(lambda key: model.sky_ambient_rgb(np.array(key[0]), key[1]))

    def own_sun_direction(self) -> np.ndarray:
        return model.sun_direction(self.params["preetham.sun_elevation"],
                                   self.params["preetham.sun_azimuth"])

    def update(self, frame, dt: float) -> None:
        if frame.sun is not None:  # a day–night sky ran first: follow its sun
            self.owns_sun = False
            self.sun_direction = np.asarray(frame.sun.direction, dtype=np.float64)
            self.main_light = frame.main_light if frame.main_light is not None else frame.sun
            return
        self.owns_sun = True
        sun = self.own_sun_direction()
        self.sun_direction = sun
        colour = tuple(float(c) for c in model.sun_transmittance(
            model.model_sun_zenith(sun), self.params["preetham.turbidity"]))
        light = Light("sun", sun, colour,
                      self.params["preetham.sun_intensity"] * light_fade(sun[1]))
        frame.sun = light
        frame.main_light = light
        self.main_light = light

    def sky_ambient(self) -> np.ndarray:
        """``uSkyAmbient``: the cosine-weighted mean radiance of the sky (no disk) in the
        picture's units; the hemisphere is integrated again only when the sun or the turbidity
        changed."""
        key = (tuple(float(v) for v in self.sun_direction),
               float(self.params["preetham.turbidity"]))
        return (self._ambient.get(key) * self.params["preetham.exposure"]
                * model.twilight(self.sun_direction))

    def sea(self, eye_height: float) -> SeaPlane | None:
        """The sea plane's light and settings (``None`` with ``preetham.ground = horizon``)."""
        p = self.params
        if p["preetham.ground"] != "sea":
            return None
        light = self.main_light
        if light is None:
            direction, radiance = self.sun_direction, np.zeros(3)
        else:
            direction, radiance = np.asarray(light.direction, float), light.radiance
        return SeaPlane(sky_ambient=tuple(float(v) for v in self.sky_ambient()),
                        light_dir=tuple(float(v) for v in direction),
                        light_radiance=tuple(float(v) for v in radiance),
                        body_color=tuple(float(v) for v in p["preetham.sea_color"]),
                        mss=cox_munk_mss(p["preetham.sea_wind"]),
                        eye_height=max(float(eye_height), 0.5),
                        haze_distance=float(p["preetham.sea_haze"]))

    def draw(self, frame, target) -> None:
        prog = self.program(PREETHAM_SKY)
        self.apply_params(prog)
        prog.set_many(frame.camera_uniforms())
        prog.set("uSunDir", tuple(float(v) for v in self.sun_direction))
        sea = self.sea(float(frame.camera.position[1]))
        prog.set("uGround", GROUNDS.index(self.params["preetham.ground"]))
        if sea is not None:
            prog.set_many({"uSkyAmbient": sea.sky_ambient, "uMainLightDir": sea.light_dir,
                           "uMainLightRadiance": sea.light_radiance, "uSeaMss": sea.mss,
                           "uEyeHeight": sea.eye_height})
        target.use()
        self.gpu.ctx.disable(moderngl.DEPTH_TEST)
        draw_fullscreen(prog)

    def radiance_numpy(self, directions, eye_height: float = 2.0) -> np.ndarray:
        """The twin of what :meth:`draw` draws toward ``directions`` (…, 3), for a camera
        ``eye_height`` metres above the sea."""
        p = self.params
        return model.sky_radiance(directions, self.sun_direction, p["preetham.turbidity"],
                                  p["preetham.exposure"],
                                  p["preetham.sun_disk"], p["preetham.sun_disk_radius"],
                                  p["preetham.sun_disk_intensity"], sea=self.sea(eye_height))

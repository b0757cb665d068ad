"""Cloud Model B: the maritime thesis's volumetric clouds (spec/000 §1.6; annex listings
spec/000 §A.3, §A.4, §A.5, §A.6, §A.7, §A.8).

A box of cloud ray-marched at a fixed step over the scene, with the thesis's inspector
parameters (``clouds_b.*``, from the ``@param`` uniforms of
``glsl/clouds_b/clouds_b_model.glsl``):
container bounds and edge fade, cloud scale, density threshold and multipliers, volume and
detail noise weights, the two-lobe phase (forward/back scattering, base brightness, phase
factor), darkness threshold, light absorption toward the sun and through the cloud, light
steps and the fixed step size. The thesis's light-direction double inversion is fixed (see the
shader header); ``clouds_b.thesis_light_inversion`` brings it back for comparison.

Textures come from :mod:`app.bakes` at the thesis's sizes: the "volume" noise (a
:class:`~app.bakes.ShapeBake`, 132³), the detail noise (a :class:`~app.bakes.DetailBake`, 64³)
and GradientSimulator's coverage map (a :class:`~app.bakes.WeatherBake`, 512², R channel) —
baked once and cached on disk; ``clouds_b.volume_resolution`` and friends change the sizes.

How a scene composes it:

* **stage**: volumes — after the background (``Sky`` or ``Preetham``), the opaque geometry and
  water seen from above, before fog and the overlay. It blends over whatever the image holds;
* **update()** moves ``_CloudOffset`` with the wind: ``clouds_b.wind_speed`` along
  ``clouds_b.wind_direction`` plus the frame's ``wind`` slot (read as (x, z) in m/s; filled
  only by effects listed before this one in the scene), so the base shape drifts at the wind's
  speed in metres per second and the detail noise at twice that (the thesis's offset factors
  0.1 and 0.2), and the coverage map drifts with the base shape (beyond the thesis, which
  leaves the map still); speed 0 gives identical frames;
* **passes** read the ``main_light`` slot (else ``sun``; the fallback: its own
  ``clouds_b.sun_elevation``/``sun_azimuth``/``sun_color``) for _SunDir and _SunColor, the
  camera from the frame, and the depth of the ``image`` slot (none = everything far). Pass 1
  marches into a cloud layer of its own (rgb = in-scattered light, a = transmittance); pass 2
  blends it into the image: target = target·a + rgb (the thesis's background·transmittance +
  lightEnergy·SunColor). The target's alpha and depth are kept.
* beyond the thesis, both off by default: ``clouds_b.weather_coverage`` lets the coverage map
  thin the clouds where it is low (cloud banks and clear gaps kilometres wide instead of one
  repeating tile), and ``clouds_b.haze_distance`` fades distant clouds into the horizon's haze
  (aerial perspective, the colour from the ``environment`` slot's probe when there is one).

The numpy twins of the shader functions are in :mod:`app.sim.clouds_b`.
"""

from __future__ import annotations

import math

import moderngl
import numpy as np

from ... import bakes
from ...bakes.textures import BakedTextures
from ...frame import Stage
from ...gpu.programs import draw_fullscreen, fullscreen
from ...params import Param, ParamSet
from ...render.layers import LAYER_COMPOSITE, composite_layer
from ...sim import clouds_b as twin
from ..base import Effect, Pass

CLOUDS_B = fullscreen("clouds_b/clouds_b")


class CloudsB(Effect):
    name = "clouds_b"
    title = "Volumetric clouds, model B (maritime thesis)"
    spec = "spec/000"
    programs = (CLOUDS_B, LAYER_COMPOSITE)
    stages = (Stage.VOLUMES,)
    consumes = {"main_light": "optional", "sun": "optional", "wind": "optional",
                "image": "optional", "environment": "optional"}

    @classmethod
    def context_paths(cls, caps, params) -> dict[str, str]:
        how = "compute shaders" if caps.compute else "one fragment pass per slice"
        return {"noise bakes (3D textures)": how}

    @classmethod
    def python_params(cls) -> list[Param]:
        s = "spec/000 §1.6"
        return [
            Param("clouds_b.volume_resolution", 132, 8, 256, "Volume Resolution: texels per side "
                  "of the volume (shape) noise", kind="int", unit="texels", section=s),
            Param("clouds_b.detail_resolution", 64, 8, 256, "Detail Resolution: texels per side of "
                  "the detail noise", kind="int", unit="texels", section=s),
            Param("clouds_b.gradient_resolution", 512, 8, 4096, "Resolution of GradientSimulator's "
                  "coverage map", kind="int", unit="texels", section=s),
            Param("clouds_b.cloud_offset", (0.0, 0.0, 0.0), -1.0e6, 1.0e6, "_CloudOffset at time 0 "
                  "(noise units; the wind adds to it)", kind="vec3", step=0.01, section=s),
            Param("clouds_b.wind_speed", 5.0, 0.0, 200.0, "wind speed: the base shape drifts this "
                  "fast", step=0.5, unit="m/s", section=s),
            Param("clouds_b.wind_direction", 90.0, 0.0, 360.0, "direction the wind blows toward: 0 "
                  "= north (−z), 90 = east (+x)", step=1.0, unit="°", section=s),
            Param("clouds_b.sun_elevation", 35.0, -90.0, 90.0, "sun elevation when no effect "
                  "before sets a light", step=0.1, unit="°", section=s),
            Param("clouds_b.sun_azimuth", 135.0, 0.0, 360.0, "sun azimuth when no effect before "
                  "sets a light (0 = north, 90 = east)", step=0.5, unit="°", section=s),
            Param("clouds_b.sun_color", (1.0, 1.0, 1.0), 0.0, 100.0, "_SunColor when no effect "
                  "before sets a light", kind="vec3", step=0.01, section=s),
        ]

    @classmethod
    def lesson(cls, params: ParamSet) -> str | None:
        return ("Model B, the maritime thesis's clouds (spec/000 §1.6, after Schneider 2015): "
                "a box marched at a fixed step, the volume noise above a density threshold "
                "eroded by detail noise under a coverage map, lit by a short light march (Beer's "
                "law) with a two-lobe Henyey–Greenstein phase and the powder term.")

    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        self.bakes = BakedTextures(gpu, self.name)
        self._layer = None
        self.cloud_offset = np.zeros(3)
        self.coverage_shift = np.zeros(2)  # metres the coverage map has drifted (x, z)

    # -- CPU -------------------------------------------------------------------------------
    def wind_velocity(self, frame=None) -> np.ndarray:
        """Wind (x, z) in m/s: the parameters plus ``frame.wind``."""
        a = math.radians(self.params["clouds_b.wind_direction"])
        v = self.params["clouds_b.wind_speed"] * np.array([math.sin(a), -math.cos(a)])
        if frame is not None and getattr(frame, "wind", None) is not None and len(frame.wind) == 2:
            v = v + np.asarray(frame.wind, dtype=np.float64)
        return v

    def offset_at(self, time_s: float, frame=None) -> np.ndarray:
        """_CloudOffset at ``time_s``: base offset − wind·t·CloudScale·0.01, so the base shape
        (sampled at samplePos + offset·0.1, samplePos = (halfSize + p)·CloudScale·0.001) moves
        with the wind in metres per second."""
        return twin.wind_offset(self.params["clouds_b.cloud_offset"], self.wind_velocity(frame),
                                time_s, self.params["clouds_b.cloud_scale"])

    def update(self, frame, dt: float) -> None:
        self.cloud_offset = self.offset_at(frame.time, frame)
        self.coverage_shift = self.wind_velocity(frame) * frame.time

    def light(self, frame) -> tuple[np.ndarray, np.ndarray]:
        """(direction toward the light, radiance) for _SunDir and _SunColor."""
        light = frame.main_light if frame.main_light is not None else frame.sun
        if light is not None:
            d = np.asarray(light.direction, dtype=np.float64)
            return d / np.linalg.norm(d), np.asarray(light.radiance, dtype=np.float64)
        e = math.radians(self.params["clouds_b.sun_elevation"])
        a = math.radians(self.params["clouds_b.sun_azimuth"])
        d = np.array([math.sin(a) * math.cos(e), math.sin(e), -math.cos(a) * math.cos(e)])
        return d, np.asarray(self.params["clouds_b.sun_color"], dtype=np.float64)

    # -- textures --------------------------------------------------------------------------
    def bake_specs(self) -> dict[str, object]:
        p = self.params
        shape, detail = bakes.maritime()
        return {"shape": shape.replace(size=p["clouds_b.volume_resolution"]),
                "detail": detail.replace(size=p["clouds_b.detail_resolution"]),
                "weather": bakes.WeatherBake(size=p["clouds_b.gradient_resolution"])}

    def texture(self, kind: str):
        return self.bakes.get(self.bake_specs()[kind])

    def layer(self, size):
        """The cloud layer target (rgb in-scattered light, a transmittance) of the last render."""
        if self._layer is None or self._layer.size != tuple(size):
            if self._layer is not None:
                self.gpu.free(self._layer)
            self._layer = self.gpu.target(self.name, "cloud layer", size, dtype="f4",
                                          depth=False)
        return self._layer

    # -- passes ----------------------------------------------------------------------------
    def march(self, frame, target) -> None:
        """Pass 1: the view march into the cloud layer."""
        prog = self.program(CLOUDS_B)
        self.apply_params(prog)
        layer = self.layer(target.size)
        # all bakes first, then the bindings: a bake run now uses texture units of its own
        shape, detail, weather = (self.texture(kind) for kind in ("shape", "detail", "weather"))
        # the stored depth, not a shadow comparison
        with frame.image_for(target).depth_values() as depth:
            self._march(frame, prog, layer, shape, detail, weather, depth)

    def _march(self, frame, prog, layer, shape, detail, weather, depth) -> None:
        ctx = self.gpu.ctx
        textures = {"uVolumeNoise": shape, "uDetailNoise": detail, "uGradientNoise": weather,
                    "uSceneDepth": depth}
        # aerial perspective's horizon colour: the sky probe (without its sun disk), when the
        # scene has one and the haze is on (clouds_b.haze_distance > 0)
        env = None
        if frame.environment is not None and self.params["clouds_b.haze_distance"] > 0.0:
            env = frame.environment.cubemap(sun=False)
            textures["uHazeEnvironment"] = env
        prog.bind_textures(textures)
        light_dir, light_color = self.light(frame)
        cam = frame.camera
        prog.set_many(frame.camera_uniforms())
        prog.set_many({
            "uHasDepth": depth is not None, "uCameraNear": float(cam.near),
            "uCameraFar": float(cam.far),
            "uLightDir": tuple(float(v) for v in light_dir),
            "uLightColor": tuple(float(v) for v in light_color),
            "uCloudOffset": tuple(float(v) for v in self.cloud_offset),
            "uCoverageShift": tuple(float(v) for v in self.coverage_shift),
            "uHasHazeEnvironment": env is not None,
            "uHazeLods": float(max(0, int(math.log2(env.size[0])))) if env is not None else 0.0,
        })
        layer.use()
        ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        draw_fullscreen(prog)

    def composite(self, frame, target) -> None:
        """Pass 2: target = target·transmittance + in-scattered light (alpha kept)."""
        composite_layer(self, self.layer(target.size).color, target)

    def passes(self, frame, target) -> list[Pass]:
        return [Pass("clouds_b.march", lambda: self.march(frame, target), Stage.VOLUMES),
                Pass("clouds_b.composite", lambda: self.composite(frame, target),
                     Stage.VOLUMES)]

    def read_layer(self) -> np.ndarray:
        """(h, w, 4) float32 of the last cloud layer: rgb in-scattered light, a transmittance."""
        if self._layer is None:
            raise RuntimeError("clouds_b: nothing rendered yet")
        return self._layer.read()

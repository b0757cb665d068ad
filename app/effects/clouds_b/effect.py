"""Cloud Model B: the maritime thesis's volumetric clouds (spec/000 §1.6; annex listings
spec/000 §A.3, §A.4, §A.5, §A.6, §A.7, §A.8).

A box of cloud ray-marched at a fixed step over the scene, with the thesis's inspector
parameters (``clouds_b.*``, the ``@param`` uniforms of ``glsl/clouds_b/clouds_b_model.glsl``).
The thesis's light-direction double inversion is fixed (see the shader header);
``clouds_b.thesis_light_inversion`` brings it back for comparison. Textures come from
:mod:`app.bakes` at the thesis's sizes (volume noise 132³, detail noise 64³, GradientSimulator's
coverage map 512²), baked once and cached on disk.

* **stage**: volumes; it blends over whatever the image holds;
* **update()** moves ``_CloudOffset`` with ``clouds_b.wind_speed`` along
  ``clouds_b.wind_direction`` plus the frame's ``wind`` slot ((x, z) in m/s): the base shape
  and the coverage map drift at the wind's speed, the detail noise at twice that (the thesis's
  offset factors 0.1 and 0.2; the thesis leaves the map still); speed 0 gives identical frames;
* **passes** read the ``main_light`` slot (else ``sun``; the fallback: its own
  ``clouds_b.sun_elevation``/``sun_azimuth``/``sun_color``), the camera and the ``image``
  slot's depth (none = everything far): the layer marched and blended over the image
  (:class:`app.render.layers.MarchedLayer`; ``clouds_b.reprojection=off`` is the thesis's march
  of every pixel every frame);
* beyond the thesis, both off by default: ``clouds_b.weather_coverage`` and
  ``clouds_b.haze_distance`` (distant clouds fade into the ``environment`` slot's horizon).

The numpy twins of the shader functions are in :mod:`app.sim.clouds_b`.
"""

from __future__ import annotations

import math

import moderngl
import numpy as np

from ... import bakes
from ...frame import Stage
from ...gpu.programs import draw_fullscreen, fullscreen
from ...params import Param, ParamSet
from ...render.amortise import PROGRAMS, amortise_params
from ...render.layers import LAYER_COMPOSITE, MarchedLayer
from ...sim import clouds_b as twin
from ...sim.amortise import LayerState
from ...sim.maths import compass_xz, direction
from ..base import Effect, Pass

CLOUDS_B = fullscreen("clouds_b/clouds_b")


class CloudsB(MarchedLayer, Effect):
    name = "clouds_b"
    title = "Volumetric clouds, model B (maritime thesis)"
    spec = "spec/000"
    programs = (CLOUDS_B, LAYER_COMPOSITE, *PROGRAMS)
    stages = (Stage.VOLUMES,)
    consumes = {"main_light": "optional", "sun": "optional", "wind": "optional",
                "image": "optional", "environment": "optional"}
    #: the software figure is the maritime scene's default view measured at 640×360 on two cores
    #: of llvmpipe (769 ms); the GPU's is an estimate
    FULL_MARCH_MS_PER_MPX = (3300.0, 20.0)

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
            *amortise_params("clouds_b"),
        ]

    @classmethod
    def lesson(cls, params: ParamSet) -> str | None:
        return ("Model B, the maritime thesis's clouds (spec/000 §1.6, after Schneider 2015): "
                "a box marched at a fixed step, the volume noise above a density threshold "
                "eroded by detail noise under a coverage map, lit by a short light march (Beer's "
                "law) with a two-lobe Henyey–Greenstein phase and the powder term.")

    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        #: the bench's reference: the thesis's march jittered at this phase (None: not jittered)
        self.jitter_phase: float | None = None
        self.cloud_offset = np.zeros(3)
        self.coverage_shift = np.zeros(2)  # metres the coverage map has drifted (x, z)
        self._specs: tuple[tuple, dict] | None = None  # (their sizes, bake_specs()) last made

    def wind_velocity(self, frame=None) -> np.ndarray:
        """Wind (x, z) in m/s: the parameters plus ``frame.wind``."""
        p = self.params
        v = p["clouds_b.wind_speed"] * compass_xz(p["clouds_b.wind_direction"])
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
        d = direction(self.params["clouds_b.sun_elevation"], self.params["clouds_b.sun_azimuth"])
        return d, np.asarray(self.params["clouds_b.sun_color"], dtype=np.float64)

    def bake_specs(self) -> dict[str, object]:
        p = self.params
        shape, detail = bakes.maritime()
        return {"shape": shape.replace(size=p["clouds_b.volume_resolution"]),
                "detail": detail.replace(size=p["clouds_b.detail_resolution"]),
                "weather": bakes.WeatherBake(size=p["clouds_b.gradient_resolution"])}

    def texture(self, kind: str):
        # the specs are made again only when their three sizes change (not three times a frame)
        p = self.params
        key = (p["clouds_b.volume_resolution"], p["clouds_b.detail_resolution"],
               p["clouds_b.gradient_resolution"])
        if self._specs is None or self._specs[0] != key:
            self._specs = (key, self.bake_specs())
        return self.bakes.get(self._specs[1][kind])

    def container_distances(self, frame) -> tuple[float, float]:
        """(nearest, farthest) distance from the camera to the cloud box."""
        lo = np.asarray(self.params["clouds_b.bounds_min"], dtype=np.float64)
        hi = np.asarray(self.params["clouds_b.bounds_max"], dtype=np.float64)
        cam = np.asarray(frame.camera.position, dtype=np.float64)
        near = float(np.linalg.norm(np.maximum(np.maximum(lo - cam, cam - hi), 0.0)))
        far = float(np.linalg.norm(np.maximum(np.abs(lo - cam), np.abs(hi - cam))))
        return near, far

    def layer_state(self, frame) -> LayerState:
        """What the amortised layer's history depends on this frame: the base shape and the
        coverage map move with the wind (the detail noise at twice its speed)."""
        light_dir, light_color = self.light(frame)
        wind = self.wind_velocity(frame)
        near, far = self.container_distances(frame)
        env = frame.environment is not None and self.params["clouds_b.haze_distance"] > 0.0
        return LayerState(key=(self.params.version(self.name), env), light_dir=light_dir,
                          light_radiance=np.asarray(light_color, float),
                          wind=np.array([wind[0], 0.0, wind[1]]),
                          field_offset=np.array([self.coverage_shift[0], 0.0,
                                                 self.coverage_shift[1]]),
                          near=near, far=far)

    def march(self, frame, target) -> None:
        """Pass 1: the cloud layer (amortised, or the thesis's march of every pixel)."""
        prog = self.program(CLOUDS_B)
        self.apply_params(prog)
        # all bakes first, then the bindings: a bake run now uses texture units of its own
        shape, detail, weather = (self.texture(kind) for kind in ("shape", "detail", "weather"))
        self.render_layer(frame, target, lambda grid, depth: self._march(
            frame, prog, grid, shape, detail, weather, depth), self.jitter_phase or 0.0)

    def _march(self, frame, prog, grid, shape, detail, weather, depth) -> None:
        ctx = self.gpu.ctx
        textures = {"uVolumeNoise": shape, "uDetailNoise": detail, "uGradientNoise": weather,
                    "uSceneDepth": depth, **grid.textures}
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
            "uJitterReference": self.jitter_phase is not None,
            **grid.uniforms,
        })
        grid.use()
        ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        draw_fullscreen(prog)

    def passes(self, frame, target) -> list[Pass]:
        return [Pass("clouds_b.march", lambda: self.march(frame, target), Stage.VOLUMES),
                Pass("clouds_b.composite", lambda: self.composite(target),
                     Stage.VOLUMES)]

"""Volumetric clouds, model A: the cloud thesis (spec/001, after Häggström 2018 / Schneider 2015).

GPU side: ``glsl/clouds/cloud_model.glsl`` (density and lighting models), ``cloud_march.frag``
(view march, light march, the speed options; its header has the per-pixel algorithm) and
``glsl/common/layer_composite.frag`` (app/render/layers.py). Most tunables are ``// @param``
uniforms of ``cloud_march.frag``; the ones that need the CPU are declared here.

Per frame:

* the shape, detail and weather textures come from :mod:`app.bakes` (cached on disk), created
  on the first render from the ``bake_*`` parameters, progress through ``gpu.progress``;
* the light: the frame's ``main_light`` slot when a sky fills it and ``clouds.sun_from_sky``
  is on, else (the fallback) ``clouds.sun_direction`` / ``sun_color`` / ``sun_intensity``;
* wind: the density field is translated rigidly by ``wind_speed · time · (wind_dir_x,
  wind_dir_y)`` metres along world (x, z), each texture's offset wrapped by its own tile on
  the CPU in float64 (so float32 never loses the fraction); speed 0 gives identical frames;
* the volumes stage marches the layer (premultiplied radiance, transmittance) and blends it
  over the image (:class:`app.render.layers.MarchedLayer`; ``clouds.reprojection=off`` is the
  thesis's march of every pixel every frame).

Presets (``clouds.preset``, docs/theory/001-clouds.md): the effect applies the file when the
choice changes. On the first frame, parameters that already differ from their defaults (given
with ``--set`` or a preset file) are kept, so ``--set clouds.preset=stratus --set
clouds.coverage=0.9`` keeps 0.9; ``custom`` applies nothing; groups the scene does not have
(``[time]`` without a sky) are skipped.

The numpy twins of the shader helpers, which the tests compare them with, are in
app/sim/clouds.py.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import moderngl
import numpy as np

from ... import RESOURCES, bakes
from ...errors import ParamError
from ...frame import Stage
from ...gpu.programs import draw_fullscreen, fullscreen
from ...params import Joint, Param, ParamSet, non_zero, show
from ...render.amortise import PROGRAMS, amortise_params
from ...render.layers import LAYER_COMPOSITE, MarchedLayer
from ...sim.amortise import LayerState
from ...sim.clouds import density_length
from ..base import Effect, Pass

CLOUD_MARCH = fullscreen("clouds/cloud_march")

PRESET_DIR = RESOURCES / "presets"
PRESETS = ("custom", "cumulus", "stratocumulus", "stratus", "lighting")
CONTAINERS = ("box", "spheres")
SPEC = "spec/001"


def preset_path(name: str) -> Path:
    """``resources/presets/clouds-<name>.toml``."""
    return PRESET_DIR / f"clouds-{name}.toml"


class Clouds(MarchedLayer, Effect):
    name = "clouds"
    title = "Volumetric clouds (model A)"
    spec = SPEC
    programs = (CLOUD_MARCH, LAYER_COMPOSITE, *PROGRAMS)
    extra_groups = ("bake_shape", "bake_detail", "bake_weather")
    stages = (Stage.VOLUMES,)
    consumes = {"main_light": "optional", "image": "optional"}
    joints = (Joint(("clouds.base_height", "clouds.max_height"),
                    "clouds.max_height ≥ base_height + 1 m (the layer has a thickness)",
                    lambda base, top: top - base >= 1.0),
              non_zero("clouds.sun_direction"))
    #: the software figure is the default cumulus view measured at 640×360 on two cores of
    #: llvmpipe (243 ms); the GPU's is an estimate
    FULL_MARCH_MS_PER_MPX = (1050.0, 10.0)

    @classmethod
    def python_params(cls) -> list[Param]:
        s = SPEC
        return [
            Param("clouds.preset", "cumulus", doc="apply resources/presets/clouds-<name>.toml when "
                  "chosen (custom: nothing; the weather map's contrast is part of each preset)",
                  kind="choice", choices=PRESETS, section=f"{s} §2"),
            *amortise_params("clouds"),
            Param("clouds.container", "box", doc="Cubo o esfera: an axis-aligned box or the shell "
                  "between two spheres", kind="choice", choices=CONTAINERS, section=f"{s} §1.5"),
            Param("clouds.sun_from_sky", True, doc="take the light from the frame (a sky's main "
                  "light) when there is one; off: clouds.sun_direction/colour/intensity",
                  kind="bool", section=f"{s} §1.8"),
            Param("clouds.sky_ambient", 0.25, 0.0, 4.0, "beyond the thesis: isotropic ambient "
                  "radiance from the sky, as a fraction of its ambient (the cosine-weighted mean "
                  "radiance of the day–night sky, given with its light), added to clouds.ambient × "
                  "the light's radiance (0: the light's only; no such sky: none)", step=0.01,
                  section=f"{s} §1.8"),
            Param("clouds.sun_direction", (0.0, 0.5, -1.0), -1.0, 1.0, "direction toward the light "
                  "when not from the sky (normalised; the zero vector is refused)", kind="vec3",
                  step=0.01, section=f"{s} §1.8"),
            Param("clouds.sun_color", (1.0, 0.96, 0.9), 0.0, 1.0,
                  "light colour when not from the sky", kind="color", section=f"{s} §1.8"),
            Param("clouds.sun_intensity", 1.0, 0.0, 100.0, "light intensity when not from the sky",
                  step=0.05, section=f"{s} §1.8"),
            Param("clouds.wind_speed", 10.0, 0.0, 500.0,
                  "Velocidad: wind speed (0: identical frames)", step=0.5, unit="m/s",
                  section=f"{s} §2"),
            Param("clouds.wind_dir_x", 1.0, -1.0, 1.0,
                  "Dirección eje X: wind direction along world x", step=0.01, section=f"{s} §2"),
            Param("clouds.wind_dir_y", 0.0, -1.0, 1.0,
                  "Dirección eje Y: wind direction along world z", step=0.01, section=f"{s} §2"),
        ] + bakes.bake_params()

    @classmethod
    def lesson(cls, params: ParamSet) -> str | None:
        return ("Model A, the cloud thesis (spec/001 §1.4, §1.5): a density field of "
                "Perlin–Worley shape noise eroded by Worley detail under a weather map, "
                "ray-marched through the container with a light march toward the sun at each "
                "sample (spec/001 §1.6, §1.7); the thesis reached only 1–2 FPS at 1920×1080 "
                "(spec/001 §4).")

    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        #: the jitter phase of the thesis's march (the bench's reference averages over it)
        self.jitter_phase = 0.0
        self._applied_preset: str | None = None
        self.light_dir = np.array([0.0, 1.0, 0.0])
        self.light_radiance = np.ones(3)
        self.ambient_radiance = np.full(3, 0.3)

    def apply_preset(self, name: str, keep_changed: bool = False) -> list[str]:
        """Set the values of ``clouds-<name>.toml``; return the names set. ``keep_changed``:
        leave parameters whose value differs from their default alone."""
        if name == "custom":
            return []
        path = preset_path(name)
        try:
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise ParamError(f"clouds.preset={name!r}: {path} is missing: allowed "
                             f"{', '.join(PRESETS)}") from None
        done = []
        for group, table in data.items():
            if not isinstance(table, dict):
                raise ParamError(f"preset {str(path)!r}: {group!r} must be a table like [{group}]")
            for key, value in table.items():
                full = f"{group}.{key}"
                if full not in self.params or full == "clouds.preset":
                    continue
                spec = self.params.spec(full)
                if keep_changed and self.params[full] != spec.default:
                    continue
                self.params.set(full, value)
                done.append(full)
        return done

    def update(self, frame, dt: float) -> None:
        chosen = self.params["clouds.preset"]
        if chosen != self._applied_preset:
            self.apply_preset(chosen, keep_changed=self._applied_preset is None)
            self._applied_preset = chosen
        p = self.params
        light = getattr(frame, "main_light", None)
        sky_ambient = None
        if p["clouds.sun_from_sky"] and light is not None:
            direction = np.asarray(light.direction, dtype=np.float64)
            radiance = np.asarray(light.radiance, dtype=np.float64)
            sky_ambient = getattr(light, "ambient", None)
        else:
            direction = np.asarray(p["clouds.sun_direction"], dtype=np.float64)
            radiance = (np.asarray(p["clouds.sun_color"], dtype=np.float64)
                        * p["clouds.sun_intensity"])
        norm = float(np.linalg.norm(direction))
        if not math.isfinite(norm) or norm < 1e-9:
            raise ParamError(f"clouds.sun_direction={show(direction)} is the zero vector: "
                             "allowed any non-zero direction")
        self.light_dir = direction / norm
        self.light_radiance = radiance
        # multiple scattering of the light stands in as clouds.ambient × its radiance; the sky
        # dome's own light is added when the sky gives it with the light
        self.ambient_radiance = p["clouds.ambient"] * radiance
        if sky_ambient is not None:
            self.ambient_radiance = (self.ambient_radiance
                                     + p["clouds.sky_ambient"] * np.asarray(sky_ambient, float))

    def wind_offset_m(self, time: float) -> np.ndarray:
        """How far the clouds have moved at ``time``, metres along world (x, z)."""
        p = self.params
        return p["clouds.wind_speed"] * float(time) * np.array([p["clouds.wind_dir_x"],
                                                                  p["clouds.wind_dir_y"]])

    def uniforms(self, frame) -> dict:
        """Everything the march needs besides the ``@param`` uniforms."""
        p = self.params
        base, top = p["clouds.base_height"], p["clouds.max_height"]
        if top - base < 1.0:
            raise ParamError(f"clouds.max_height={top:g} is not above clouds.base_height={base:g} "
                             "by at least 1 m: allowed max_height ≥ base_height + 1")
        wind = self.wind_offset_m(frame.time)
        cam = frame.camera
        return {
            "uLightDir": tuple(float(v) for v in self.light_dir),
            "uLightRadiance": tuple(float(v) for v in self.light_radiance),
            "uAmbientRadiance": tuple(float(v) for v in self.ambient_radiance),
            "uDensityLength": density_length(base, top),
            "uWeatherOffset": tuple(np.mod(wind / p["clouds.weather_scale"], 1.0)),
            "uShapeOffset": tuple(np.mod(wind / p["clouds.shape_scale"], 1.0)),
            "uDetailOffset": tuple(np.mod(wind / p["clouds.detail_scale"], 1.0)),
            "uContainer": CONTAINERS.index(p["clouds.container"]),
            "uCamNear": float(cam.near), "uCamFar": float(cam.far),
        }

    def texture_for(self, kind: str):
        return self.bakes.from_params(kind, self.params)

    def container_distances(self, frame) -> tuple[float, float]:
        """(nearest, farthest) distance from the camera at which a cloud can be: the container
        (box or shell), the far end bounded by clouds.max_distance."""
        p = self.params
        cam = np.asarray(frame.camera.position, dtype=np.float64)
        base, top = p["clouds.base_height"], p["clouds.max_height"]
        if p["clouds.container"] == "box":
            half = p["clouds.box_half_size"]
            lo, hi = np.array([-half, base, -half]), np.array([half, top, half])
            near = float(np.linalg.norm(np.maximum(np.maximum(lo - cam, cam - hi), 0.0)))
        else:
            radius = p["clouds.planet_radius"]
            r = float(np.linalg.norm(cam - np.array([0.0, -radius, 0.0])))
            near = max(radius + base - r, r - radius - top, 0.0)
        return near, float(p["clouds.max_distance"])

    def layer_state(self, frame) -> LayerState:
        """What the amortised layer's history depends on this frame."""
        p = self.params
        wind = p["clouds.wind_speed"] * np.array([p["clouds.wind_dir_x"], 0.0,
                                                  p["clouds.wind_dir_y"]])
        offset = self.wind_offset_m(frame.time)
        near, far = self.container_distances(frame)
        key = tuple(self.params.version(g) for g in (self.name, *self.extra_groups))
        return LayerState(key=key, light_dir=np.asarray(self.light_dir, float),
                          light_radiance=np.concatenate([self.light_radiance,
                                                         self.ambient_radiance]),
                          wind=wind, field_offset=np.array([offset[0], 0.0, offset[1]]),
                          near=near, far=far)

    def march(self, frame, grid, depth) -> None:
        """The view march into ``grid`` (``app.render.amortise.MarchGrid``: every pixel, or one
        pixel of each block of an amortised frame), clipped at ``depth`` (the scene image's,
        readable as values: ``render_layer`` sees to it)."""
        ctx = self.gpu.ctx
        prog = self.program(CLOUD_MARCH)
        # all bakes first, then the bindings: a bake run now uses texture units of its own
        weather, shape, detail = (self.texture_for(kind) for kind in ("weather", "shape", "detail"))
        prog.bind_textures({"uWeather": weather, "uShape": shape, "uDetail": detail,
                            "uSceneDepth": depth, **grid.textures})
        self.apply_params(prog)
        prog.set_many(frame.camera_uniforms())
        prog.set_many(self.uniforms(frame))
        prog.set_many({"uHasSceneDepth": depth is not None, **grid.uniforms})
        grid.use()
        ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        draw_fullscreen(prog)

    def passes(self, frame, target) -> list[Pass]:
        def march() -> None:
            self.render_layer(frame, target, lambda grid, depth: self.march(frame, grid, depth),
                              self.jitter_phase)

        return [Pass("clouds.march", march, Stage.VOLUMES),
                Pass("clouds.composite", lambda: self.composite(target), Stage.VOLUMES)]

"""The harness of the `planet` scene's tests: spec/002-atmosphere.md §9 criteria 10–27 (GPU),
issue 4 item 7.

Pixel statistics of small float renders (llvmpipe-friendly), compared where it makes sense with
the numpy model of ``app/sim/atmosphere.py``: per-ray twins of the GPU's midpoint sums
(``single_scattering`` with the same N, rule and table) and the double-precision ``reference``.
Shadows are checked against an analytic ray–box footprint of ``planet_geometry.boxes`` and against
a numpy twin of ``glsl/planet/shadow.glsl`` that reads the rendered shadow map back.

One scene (one GPU, one shader library) serves a whole test module (the ``planet`` fixture):
parameters are reset to the scene's defaults before every render, so programs compile once per
module. The tests: tests/gl/test_planet_*.py and tests/stability/test_planet_stability.py.

Conventions: images are (h, w, 3) linear radiance, row 0 at the top; "display" values are the
scene's tone map ``1 − exp(−exposure · x)`` (exponential, spec/002 §1.6) with the frame's
exposure (the pupil included), so "n/255" tolerances are in the 8-bit output's units.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from app.effects.planet.effect import Planet
from app.effects.planet.geometry import boxes
from app.gpu.device import Gpu
from app.runtime import Session, render_frames, scene_params
from app.scenes.planet import PlanetScene
from app.sim import atmosphere as atm
from app.sim.camera import Camera

SIZE = (160, 90)
SMALL = (96, 54)
THESIS_METHODS = ("brute_force", "lut", "shadowed")       # methods 1–3
LUMA = np.array([0.2126, 0.7152, 0.0722])
MODEL = atm.AtmosphereParams()                             # the scene's defaults (spec/002 §9)
R = MODEL.bottom_radius
TOP = MODEL.top_height
#: what "plain surfaces" means: no atmosphere at all (β = 0), no stars, no sun disk
NO_AIR = {"atmosphere.beta_rayleigh": "0,0,0", "atmosphere.beta_mie": 0.0}
DARK_SPACE = {"planet.star_intensity": 0.0, "planet.sun_disk": False}


# =============================================================================================
# Harness
# =============================================================================================

class Shot(NamedTuple):
    rgb: np.ndarray          # (h, w, 3) linear radiance, float64
    exposure: float          # output.exposure × the frame's pupil
    gcolour: np.ndarray      # G-buffer colour (h, w, 3): Color_original(O) of mesh pixels
    gpos: np.ndarray         # G-buffer camera-relative position (h, w, 4); w = 1 on meshes
    camera: Camera

    @property
    def display(self) -> np.ndarray:
        return display(self.rgb, self.exposure)

    @property
    def mesh(self) -> np.ndarray:
        return self.gpos[..., 3] > 0.5


class PlanetHarness:
    """One planet scene on one GPU; ``shoot`` resets every parameter to the scene's defaults,
    applies ``sets`` and renders (cached by camera, size and settings)."""

    def __init__(self, ctx):
        self.gpu = Gpu(ctx)
        self.params = scene_params("planet")
        self.defaults = dict(self.params.values())
        self.scene = PlanetScene(self.gpu, self.params, Camera())
        self.session = Session(self.gpu, self.scene, self.params)
        self._cache: dict = {}

    @property
    def effect(self) -> Planet:
        return self.scene.effect("planet")

    def apply(self, sets: dict | None) -> None:
        for name, value in self.defaults.items():
            self.params.set(name, value)
        for name, value in (sets or {}).items():
            if isinstance(value, str):
                self.params.set_from_string(f"{name}={value}")
            else:
                self.params.set(name, value)

    def shoot(self, camera: Camera, size=SIZE, sets: dict | None = None, scene=None,
              fresh=False) -> Shot:
        """``fresh``: render even if cached (the effect's state — its shadow map — is then this
        shot's, for tests that read it back)."""
        scene = scene or self.scene
        key = (id(scene), tuple(camera.position), camera.yaw, camera.pitch, camera.fov, tuple(size),
               tuple(sorted((k, str(v)) for k, v in (sets or {}).items())))
        if scene is self.scene and key in self._cache and not fresh:
            return self._cache[key]
        self.apply(sets)
        scene.camera = camera
        session = Session(self.gpu, scene, self.params)
        image = next(render_frames(session, tuple(size)))
        effect = scene.effect("planet")
        colour, position = effect.gbuffer[0], effect.gbuffer[1]
        w, h = size
        gcol = (np.frombuffer(colour.read(), dtype=np.float32)
                .reshape(h, w, 4)[::-1, :, :3].astype(np.float64))
        gpos = (np.frombuffer(position.read(), dtype=np.float32)
                .reshape(h, w, 4)[::-1].astype(np.float64))
        shot = Shot(image[..., :3].astype(np.float64), float(scene.exposure()), gcol, gpos, camera)
        if scene is self.scene:
            self._cache[key] = shot
        return shot

    def fresh_scene(self) -> PlanetScene:
        """A new planet effect (own counters, textures) on the same GPU: no recompiles."""
        return PlanetScene(self.gpu, self.params, Camera())


def camera(pos=(0.0, 2.0, 60.0), yaw=0.0, pitch=0.0, fov=60.0) -> Camera:
    return Camera(position=pos, yaw=yaw, pitch=pitch, fov=fov, far=5.0e7)


def display(rgb, exposure) -> np.ndarray:
    return 1.0 - np.exp(-np.maximum(rgb, 0.0) * exposure)


def luminance(rgb) -> np.ndarray:
    return np.asarray(rgb) @ LUMA


def rays(cam: Camera, size) -> np.ndarray:
    return cam.ray_directions(*size)


def planet_centred(cam: Camera) -> np.ndarray:
    return atm.local_to_planet(cam.position, MODEL)


def ground_distance(cam: Camera, size) -> np.ndarray:
    """Per pixel: distance to the sea-level sphere (inf where the ray misses it)."""
    d = rays(cam, size)
    return atm.ground_distance(planet_centred(cam), d.reshape(-1, 3), MODEL).reshape(d.shape[:2])


def elevation_deg(cam: Camera, size) -> np.ndarray:
    """Per pixel: elevation of the ray above the camera's local horizontal plane."""
    up = planet_centred(cam) / np.linalg.norm(planet_centred(cam))
    return np.degrees(np.arcsin(np.clip(rays(cam, size) @ up, -1.0, 1.0)))


def angle_to(cam: Camera, size, direction) -> np.ndarray:
    return np.degrees(np.arccos(np.clip(rays(cam, size) @ np.asarray(direction), -1.0, 1.0)))


def sun_sets(elevation, azimuth=180.0, **more) -> dict:
    return {"planet.sun_elevation": float(elevation), "planet.sun_azimuth": float(azimuth), **more}


# ---- boxes: analytic geometry of the city (planet_geometry.boxes, same radius) -----------------

def box_bounds() -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi) of the city's boxes in the local frame: 20 vertices (5 faces) per box."""
    verts, _ = boxes(R)
    p = verts[:, :3].astype(np.float64).reshape(-1, 20, 3)
    return p.min(1), p.max(1)


def ray_boxes(origins, dirs, lo, hi) -> np.ndarray:
    """Distance to the first box along each ray (inf where none): slab test, (N,) from (N, 3)."""
    dirs = np.asarray(dirs, dtype=np.float64)
    o = np.broadcast_to(np.asarray(origins, dtype=np.float64), dirs.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / dirs
        t1 = (lo[None] - o[:, None]) * inv[:, None]
        t2 = (hi[None] - o[:, None]) * inv[:, None]
    t_near = np.nanmax(np.minimum(t1, t2), -1)
    t_far = np.nanmin(np.maximum(t1, t2), -1)
    hit = t_far >= np.maximum(t_near, 0.0)
    return np.where(hit, np.maximum(t_near, 0.0), np.inf).min(1)


def dilate(mask: np.ndarray, r: int) -> np.ndarray:
    out = mask.copy()
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            out |= np.roll(np.roll(mask, dy, 0), dx, 1)
    return out


def ground_view(cam: Camera, size, sun_dir, lo, hi):
    """(ground, shadow, points): pixels that see the sea-level ground (not a box), those of them
    whose ground point has a box between it and the sun, and the ground points (local frame)."""
    d = rays(cam, size).reshape(-1, 3)
    pos = np.asarray(cam.position)
    gd = atm.ground_distance(planet_centred(cam), d, MODEL)
    ground = np.isfinite(gd) & (gd < ray_boxes(pos, d, lo, hi))
    pts = pos + np.where(np.isfinite(gd), gd, 0.0)[:, None] * d
    shadow = np.isfinite(ray_boxes(pts, np.broadcast_to(sun_dir, pts.shape), lo, hi))
    shape = (size[1], size[0])
    return ground.reshape(shape), (shadow & ground).reshape(shape), pts.reshape(shape + (3,))


SPACE_VIEW = dict(pos=(0.0, 200_000.0, 60.0), yaw=0.0, pitch=-12.0, fov=60.0)   # > 3 × 60 km


def horizon_rows(cam, size, shot):
    """Row luminance (display) and the rows whose centre is 0–3° above the horizon."""
    elev = elevation_deg(cam, size)[:, size[0] // 2]
    ground = np.isfinite(ground_distance(cam, size))[:, size[0] // 2]
    rows = luminance(shot.display).mean(1)
    band = np.flatnonzero(~ground & (elev <= 3.0))
    return rows, band


def dark_band_rows(rows, band, factor, gap=2):
    """Rows of ``band`` darker than ``factor`` × the rows ``gap`` above and below."""
    return [r for r in band if r - gap >= 0 and r + gap < len(rows)
            and rows[r] < factor * rows[r - gap] and rows[r] < factor * rows[r + gap]]

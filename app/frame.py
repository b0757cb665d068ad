"""What every pass sees in a frame, and the typed slots through which effects meet.

Effects never name each other. A *producer* fills a slot of the :class:`FrameContext` in its
``update`` (or, for GPU resources, hands over an object that makes them on request), and a
*consumer* reads the slot. Each effect declares the slots it ``produces`` and ``consumes``
(``"required"`` or ``"optional"``); a scene whose effects require a slot that none of them
produces is refused when it is built, with one line naming both. An optional slot that no active
effect fills has a documented fallback at its consumer.

The slots (:data:`SLOTS` is the machine-readable list):

``hour``, ``sun``, ``moon``, ``main_light``
    The time of day and the lights (:class:`~app.sim.daynight.Light`: direction *toward* the
    light, colour, intensity). ``main_light`` is what lit surfaces use: the sun by day, the moon
    by night. Filled by a sky (day–night or analytic).
``environment``
    An :class:`Environment`: the scene's reflection probe, a cubemap of linear radiance with or
    without the sun disk, re-rendered by its producer only when it changed.
``wind``
    (x, z) wind velocity in m/s over the scene (None until an effect fills it: the scene's
    ``wind`` effect, or the ocean from its own parameters when none did).
``water``
    A :class:`WaterSurface`: height, displacement and normal of the water at world points, and
    the simulation time those answers describe.
``wakes``
    Trails floating objects leave on the water (:class:`app.sim.wake.WakeTrail`: samples in
    world space, so a wake has inertia); the water draws them as foam.
``dry_mask``
    A :class:`DryMask`: window depths of the volumes the water must not enter (a hull and its
    deck), drawn in the opaque stage; the water discards its fragments inside them.
``image``
    The :class:`SceneImage` the frame is drawn into: colour (linear radiance of every stage drawn
    so far) and depth (window depth of the opaque geometry drawn so far), for effects that
    composite over it or read it (clouds clip at the depth, water refracts the colour).
``shadows``
    Shadow maps by light name (:class:`ShadowMap`), filled in the shadow stage.
``exposure``
    A factor on ``output.exposure`` (the atmosphere thesis's "pupil").
``terrain``
    A :class:`Terrain`: the height field a scene stands on (the village's island) — heights,
    normals, where grass grows, its bounds and sea level — for what grows or stands on it.
``fog``
    An ``app.sim.fog.FogSettings``: the scene's global fog (mode, density, start and end,
    colour, the height-fog switch), which every lit surface applies once after its lighting
    (``glsl/common/fog.glsl``); None: no fog.
``npcs``
    The characters a scene's player can talk to (:class:`Npc`: name, role, where their head
    is), for world-space markers above them.

Stages (:class:`Stage`) order the passes of a frame: each pass says in which stage it runs, and
the scene runs them stage by stage (effects in the scene's order within a stage).
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass, field
from enum import IntEnum
from typing import TYPE_CHECKING, Any, Callable, Iterator, Protocol, runtime_checkable

import numpy as np

from .errors import NaturaError
from .sim.camera import Camera
from .sim.daynight import Light
from .sim.fog import FogSettings
from .sim.wake import WakeTrail

if TYPE_CHECKING:
    from .gpu.targets import RenderTarget


class Stage(IntEnum):
    """When a pass runs within a frame, in this order.

    * ``SHADOW`` — depth from each shadowed light into ``frame.shadows``;
    * ``ENVIRONMENT`` — reflection probes, re-rendered only when what they show changed;
    * ``BACKGROUND`` — what is behind everything (sky): overwrites every pixel;
    * ``OPAQUE`` — solid geometry, depth-tested and depth-writing;
    * ``WATER`` — water surfaces seen from above: they read the opaque image (refraction) and
      are covered by the volumes in front of them;
    * ``SKY`` — what is behind everything, drawn after the opaque and water stages only where
      they left the far plane (depth-tested there): the image ``BACKGROUND`` would give, without
      shading the pixels something covers. A scene with a pass here must have no pass in the
      opaque or water stages that reads the image (the sky is not in it yet);
    * ``TRANSPARENT`` — blended surfaces, back to front;
    * ``VOLUMES`` — ray-marched media composited over the image (clouds), clipped at its depth;
    * ``FOG`` — participating media in front of everything: distance and height fog, aerial
      perspective, and the water when the camera is in it or at it (seen from below, the
      surface is part of the medium the camera is in, so it draws after the volumes and
      Snell's window shows them): an effect may pick its stage per frame;
    * ``POST`` — image-space effects on the finished radiance (outlines, bloom);
    * ``OVERLAY`` — HUD and debug views, drawn last.
    """

    SHADOW = 10
    ENVIRONMENT = 20
    BACKGROUND = 30
    OPAQUE = 40
    WATER = 50
    SKY = 55
    TRANSPARENT = 60
    VOLUMES = 70
    FOG = 80
    POST = 90
    OVERLAY = 100


@runtime_checkable
class Environment(Protocol):
    """A reflection probe: the scene's surroundings as a cubemap (linear radiance, mipmapped)."""

    def cubemap(self, sun: bool = True) -> Any:
        """The cubemap, with the sun disk or without it (for surfaces that add the sun as an
        analytic highlight); made on the first request, re-rendered only when it changed."""
        ...


@runtime_checkable
class WaterSurface(Protocol):
    """The water as floating objects and cameras query it (all lengths in metres, world axes,
    arrays broadcast over the points)."""

    #: simulation time [s] the answers describe; None before the first one (flat water)
    query_time: float | None

    def height(self, x: Any, z: Any) -> np.ndarray:
        """Water height above the world points (x, z)."""
        ...

    def displacement(self, x: Any, z: Any) -> np.ndarray:
        """(D_x, η, D_z) of the surface point whose rest position is (x, z)."""
        ...

    def normal(self, x: Any, z: Any) -> np.ndarray:
        """Unit normal of the displaced surface above the world points (x, z), (..., 3)."""
        ...

    def water(self, x: Any, z: Any, iterations: int | None = None) -> Any:
        """Height, displacement and normal at once (an ``app.sim.ocean.WaterQuery``)."""
        ...


@runtime_checkable
class Terrain(Protocol):
    """A height field over the xz plane (metres, world axes; arrays broadcast over points)."""

    #: (x_min, z_min, x_max, z_max) of the field
    bounds: tuple[float, float, float, float]
    #: height of the water at rest around it
    sea_level: float
    #: changes whenever the field or its masks change (consumers rebuild what they derived)
    revision: int

    def height(self, x: Any, z: Any) -> np.ndarray:
        """Ground height at (x, z) (outside the bounds: the field's border value)."""
        ...

    def normal(self, x: Any, z: Any) -> np.ndarray:
        """Unit ground normal at (x, z), (..., 3)."""
        ...

    def grass_density(self, x: Any, z: Any) -> np.ndarray:
        """Where grass grows, in [0, 1]: 0 on sand, paths, rock, under water and under the
        buildings, 1 on open meadow."""
        ...


@dataclass(frozen=True)
class Npc:
    """A character the player can talk to (spec/003 §1: Lord Barus, the vendor)."""

    name: str
    role: str  # what talking to them does ("missions", "shop", ...)
    head: tuple[float, float, float]  # world position of the top of the head [m]


@dataclass
class SceneImage:
    """The target a frame is drawn into, as compositing effects read it."""

    target: RenderTarget

    @property
    def colour(self) -> Any:
        return self.target.color

    @property
    def depth(self) -> Any:
        """The depth texture (None for a target without depth)."""
        return getattr(self.target, "depth", None)

    @contextlib.contextmanager
    def depth_values(self) -> Iterator[Any]:
        """The depth texture sampled as values (its compare mode off) for the duration, then
        restored; yields it (None without depth)."""
        depth = self.depth
        if depth is None:
            yield None
            return
        old = depth.compare_func
        depth.compare_func = ""
        try:
            yield depth
        finally:
            depth.compare_func = old


@dataclass
class ShadowMap:
    """One light's shadow map, as receivers sample it."""

    light: str  # the light's name ("sun", "lamp 2", ...)
    kind: str  # "directional" | "spot" | "point"
    texture: Any  # depth texture (a cubemap for a point light)
    view_proj: np.ndarray  # world → the light's clip space (directional and spot)
    bias: float = 0.0
    #: sets every ``glsl/common/shadow.glsl`` uniform of this light on a program and returns
    #: its textures by sampler name (None: a map shadow.glsl does not read, e.g. the planet's);
    #: ``app.render.shadow_maps.bind_published`` binds a frame's whole slot at once
    bind: Callable[[Any], dict[str, Any]] | None = None


@dataclass
class DryMask:
    """Where water must not be drawn: window depths (textures at the frame's size, one float
    channel) of the nearest front faces and the farthest back faces of the dry volumes; a water
    fragment whose depth lies between them is inside a boat."""

    front: Any
    back: Any


#: slot name → what it holds (the attributes of FrameContext effects may produce and consume)
SLOTS: dict[str, str] = {
    "hour": "time of day in hours",
    "sun": "the sun (Light)",
    "moon": "the moon (Light)",
    "main_light": "the light surfaces are lit by (Light)",
    "environment": "reflection probe (Environment)",
    "wind": "(x, z) wind velocity in m/s",
    "water": "water heights, displacements and normals (WaterSurface)",
    "wakes": "trails left on the water (WakeTrail list)",
    "dry_mask": "volumes the water must not enter (DryMask)",
    "image": "colour and depth drawn so far (SceneImage)",
    "shadows": "shadow maps by light name (ShadowMap)",
    "exposure": "factor on output.exposure",
    "terrain": "the ground's height field, normals and grass mask (Terrain)",
    "fog": "the global fog every lit surface applies (app.sim.fog.FogSettings)",
    "npcs": "characters to mark in the world (Npc list)",
}


#: slots the scene fills itself (not an effect)
SCENE_SLOTS = frozenset({"image"})


class SlotMissing(NaturaError):
    """A consumer needed a slot that no active effect filled."""


@dataclass
class FrameContext:
    size: tuple[int, int]
    camera: Camera
    time: float = 0.0  # seconds since the scene started
    dt: float = 0.0
    index: int = 0
    hour: float = 12.0
    sun: Light | None = None
    moon: Light | None = None
    main_light: Light | None = None
    environment: Environment | None = None
    wind: np.ndarray | None = None  # (x, z) m/s; None until an effect fills it
    water: WaterSurface | None = None
    wakes: list[WakeTrail] = field(default_factory=list)
    dry_mask: DryMask | None = None
    image: SceneImage | None = None
    shadows: dict[str, ShadowMap] = field(default_factory=dict)
    exposure: float = 1.0  # multiplies output.exposure (e.g. the atmosphere thesis's "pupil")
    terrain: Terrain | None = None
    fog: FogSettings | None = None
    npcs: list[Npc] = field(default_factory=list)
    #: in a stereo (VR) frame, which eye this frame is drawn for: "left", "right"; None mono
    eye: str | None = None
    interactive: bool = False  # rendered in the window (frames follow each other)

    @property
    def aspect(self) -> float:
        return self.size[0] / self.size[1]

    def image_for(self, target: RenderTarget) -> SceneImage:
        """The ``image`` slot when it is ``target`` (the scene sets it before the passes run);
        for a pass run on its own, ``target`` wrapped as one."""
        if self.image is not None and self.image.target is target:
            return self.image
        return SceneImage(target)

    def require(self, slot: str, by: str) -> Any:
        """The value of ``slot``, or a :class:`SlotMissing` error naming the consumer ``by``."""
        value = getattr(self, slot)
        if value is None:
            raise SlotMissing(f"effect {by!r} needs the frame slot {slot!r} ({SLOTS[slot]}), "
                              "which no active effect of the scene fills: allowed a scene with an "
                              "effect that produces it")
        return value

    def camera_uniforms(self) -> dict[str, Any]:
        return self.camera.uniforms(self.aspect)

    def light_uniforms(self) -> dict[str, Any]:
        out: dict[str, Any] = {}
        if self.main_light is not None:
            out["uMainLightDir"] = tuple(self.main_light.direction)
            out["uMainLightRadiance"] = tuple(self.main_light.radiance)
        if self.sun is not None:
            out["uSunDir"] = tuple(self.sun.direction)
        if self.moon is not None:
            out["uMoonDir"] = tuple(self.moon.direction)
        return out

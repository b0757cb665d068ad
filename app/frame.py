"""What every pass sees in a frame, and the typed slots through which effects meet.

Effects never name each other. A *producer* fills a slot of the :class:`FrameContext` in its
``update`` (or, for GPU resources, hands over an object that makes them on request), and a
*consumer* reads the slot. Each effect declares the slots it ``produces`` and ``consumes``
(``"required"`` or ``"optional"``); a scene whose effects require a slot that none of them
produces is refused when it is built, with one line naming both. An optional slot that no active
effect fills has a documented fallback at its consumer.

The slots are :data:`SLOTS`; docs/architecture.md ("Frame slots") says who fills and reads
each, and the fallback of an optional one.

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
    """When a pass runs within a frame, in this order (docs/architecture.md, "A frame", says
    what draws in each). A scene with a ``SKY`` pass must have no opaque or water pass that
    reads the image (the sky is not in it yet); an effect may pick its stage per frame (the
    water draws in ``FOG`` when the camera is in it, so that Snell's window shows the volumes).
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
    """The target a frame is drawn into, as compositing effects read it. ``opaque``: whether a
    pass of the frame draws surfaces into its depth before the volumes (false: the depth holds
    the clear's far plane everywhere; a pass run on its own assumes it may)."""

    target: RenderTarget
    opaque: bool = True

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
    #: the defines a receiver may be compiled with to match what ``bind`` sets (its filter
    #: and taps as constants: ``app.render.shadow_maps.receiver_defines``)
    defines: tuple[tuple[str, int], ...] = ()


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

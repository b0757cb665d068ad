"""The ``surfaces`` scene: the toon-village thesis's surface and shadow lab (spec/003 §2.4–2.8)
— a room with test spheres, cylinders, an occluder, a crate and alpha-textured quads under a
sun, a lamp and a spot light; transparency and queues, the reflection probe and its
corrections, metallic and dielectric, refraction and Fresnel, and the shared shadow module's
maps, biases and filters, each a live switch, each failure one key away."""

from __future__ import annotations

from ..effects.surfaces import Surfaces
from .base import Scene
from .keymaps import FLY, KeyMap

SURFACES = KeyMap("surfaces", {
    **FLY.bindings, "T": "cycle:surfaces.transparency", "G": "cycle:surfaces.reflection",
    "K": "cycle:surfaces.specular_model", "F": "cycle:surfaces.fresnel",
    "H": "cycle:surfaces.shadow_filter", "J": "cycle:surfaces.shadow_cascades",
    "X": "cycle:surfaces.failure", "N": "cycle:surfaces.msaa", "V": "cycle:surfaces.debug",
}, FLY.help[:-2] + (
    ("T", "transparency: sorted blending, weighted blended OIT, depth-peeled reference"),
    ("G", "reflection: none, cube, box projection, approximation, perfect sphere"),
    ("K", "specular: the thesis's weights / split-sum GGX"), ("F", "Fresnel: exact / Schlick"),
    ("H", "shadow filter: hard, 4-tap, PCF, PCSS, VSM"), ("J", "cascades: 0, 2, 4"),
    ("X", "show the next failure of the thesis (queues, intersecting panes, acne, Peter Panning)"),
    ("N", "MSAA 4× on / off (alpha-to-coverage needs it)"),
    ("V", "debug view: cascades, sun shadow, reflection direction"),
) + FLY.help[-2:])


class SurfacesScene(Scene):
    name = "surfaces"
    order = 85
    title = "Surfaces and shadows lab"
    description = ("cutout, alpha-to-coverage, queues, sorted blending and weighted blended OIT; "
                   "reflection probes with box and sphere correction; metallic and dielectric; "
                   "refraction with exact Fresnel and Schlick; directional (cascaded), point and "
                   "spot shadow maps with biases, soft, PCSS, VSM and dithered shadows "
                   "(spec/003 §2.4–2.8)")
    effects = (Surfaces,)
    #: above the near panes: every sphere, the fence, the leaves and the panes in view
    default_camera = {"position": (0.0, 2.4, 4.3), "yaw": 0.0, "pitch": -25.0, "fov": 62.0}
    background = (0.05, 0.06, 0.08)
    keymap = SURFACES

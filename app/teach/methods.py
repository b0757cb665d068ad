"""The methods of each scene a handout (``natura report``) or a comparison shows side by side.

Each scene that has competing methods for one effect names the parameter that switches them
and, for every value, a short title in the thesis's words. The first method is the one the
others are compared against (the difference images are "method − first"): where the scene has
an exact or baseline method, it comes first (the brute-force atmosphere, depth peeling,
the FFT ocean); otherwise the thesis's own choice or the scene's default does.

A scene without competing methods (the sky, the probe) has no entry: its handout shows the
default image alone. Nothing here touches numpy or the GPU, so the command line can use it to
check ``--methods`` before any work.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import UsageError, quote


@dataclass(frozen=True)
class Method:
    """One side of a comparison: ``sets`` (``NAME=VALUE`` strings) over the scene's base."""

    label: str                 # the parameter's value, e.g. "lut"
    title: str                 # what it is, e.g. "2 · optical-depth LUT"
    sets: tuple[str, ...]      # e.g. ("planet.method=lut",)


@dataclass(frozen=True)
class Axis:
    """The parameter of one scene whose values are its methods, in the order shown."""

    scene: str
    param: str
    choices: tuple[tuple[str, str], ...]   # (value, title), the first is the comparison base
    lesson: str                            # one sentence: what the comparison teaches

    @property
    def methods(self) -> list[Method]:
        return [Method(value, title, (f"{self.param}={value}",))
                for value, title in self.choices]


#: the ocean's wave models (the ocean and maritime scenes)
_WAVE_MODELS = (("fft", "FFT (Tessendorf cascades)"), ("gerstner", "Gerstner waves"),
                ("sine", "sine waves"))

AXES: dict[str, Axis] = {a.scene: a for a in (
    Axis("planet", "planet.method", (
        ("brute_force", "1 · brute force"),
        ("lut", "2 · optical-depth LUT"),
        ("shadowed", "3 · LUT + shadow map (light shafts)"),
        ("hillaire", "4 · Hillaire 2020, multiple scattering"),
    ), "the thesis's three single-scattering approximations, each faster than the last, "
       "against Hillaire's LUT-based multiple scattering"),
    Axis("ocean", "ocean.model", _WAVE_MODELS, "three wave models of the same sea: the "
         "spectrum's FFT, a set of Gerstner waves drawn from it, and plain sine waves"),
    Axis("maritime", "ocean.model", _WAVE_MODELS, "the sea under the boat in each wave model"),
    Axis("clouds", "scene.model", (
        ("a", "A · the cloud thesis (spec/001)"),
        ("b", "B · the maritime thesis (spec/000 §1.6)"),
    ), "two volumetric cloud models of the same sky"),
    Axis("materials", "materials.noise", (
        ("value", "value noise (the thesis's)"),
        ("gradient", "gradient noise (Perlin 2002)"),
    ), "the wood's noise: lattice value noise against gradient noise"),
    Axis("noise", "noise.view", (
        ("value", "value noise"),
        ("perlin", "Perlin gradient noise"),
    ), "two lattice noises on the same cells: values at the corners against gradients"),
    Axis("shading", "shading.toon", (
        ("0", "0 · no toon (Blinn–Phong)"),
        ("1", "1 · Flat"),
        ("2", "2 · Stepped"),
        ("3", "3 · Ramp"),
    ), "the CelShader's toon modes over the same lighting"),
    Axis("surfaces", "surfaces.transparency", (
        ("peeled", "depth peeling (the exact reference)"),
        ("sorted", "sorted blending (Unity's queue)"),
        ("wboit", "weighted blended OIT"),
    ), "order-independent transparency: sorted blending and WBOIT against depth peeling"),
    Axis("village", "grass.method", (
        ("billboard", "crossed billboards (the thesis's final choice)"),
        ("geometry", "geometry-shader pyramids"),
        ("instanced", "instanced Bézier blades"),
    ), "three ways to draw the same meadow of grass"),
)}


def axis_of(scene_name: str) -> Axis | None:
    """The scene's method parameter, or None (a scene with one method: its default image)."""
    return AXES.get(scene_name)


def select(scene_name: str, names: str | None = None) -> list[Method]:
    """The methods to show: all of the scene's, or those ``names`` lists (comma-separated
    values of its method parameter, in the order given; the first is the comparison base).
    One line naming the culprit for an unknown or repeated value."""
    axis = axis_of(scene_name)
    if names is None:  # a scene without competing methods: one side, its defaults
        return axis.methods if axis else [Method("default", "the scene's defaults", ())]
    if axis is None:
        with_methods = ", ".join(AXES)
        raise UsageError(f"--methods: scene {scene_name!r} has one method (its handout shows "
                         f"the default image): allowed with {with_methods}")
    by_value = {m.label: m for m in axis.methods}
    allowed = f"allowed comma-separated values of {axis.param}: {', '.join(by_value)}"
    items = [t.strip() for t in names.split(",")]
    if not names.strip() or any(not t for t in items):
        raise UsageError(f"--methods {quote(names)} has an empty item: {allowed}")
    chosen: list[Method] = []
    for item in items:
        if item not in by_value:
            raise UsageError(f"--methods: {quote(item, 40)} is not a method of {scene_name}: "
                             f"{allowed}")
        if by_value[item] in chosen:
            raise UsageError(f"--methods: {quote(item, 40)} is given twice: {allowed}, "
                             "each once")
        chosen.append(by_value[item])
    return chosen

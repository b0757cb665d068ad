"""Procedural solid materials on meshes: the procedural-wood thesis (spec/004) and, beyond it,
marble and granite, with a switch between the thesis's value noise and Perlin's gradient noise.

The thesis's property table (spec/004 §2) is the ``wood`` parameter group, with its names and
defaults; each Vector property keeps its four components and its effective scale is xyz·w.
The ring, noise and colour code is in ``glsl/materials/``; numpy twins of the wood chain are in
``app/sim/materials.py`` (tests compare them with the GPU).

The sphere and the torus are tessellated from their projected size
(``materials.tessellation = auto``: ``app.render.meshes.auto_tessellation``, edges of about
``materials.edge_pixels`` pixels, from a few power-of-two levels, each built once and kept
while the view stays in its level); ``fixed`` is the former 48 × 96 segments of both.
"""

from __future__ import annotations

import math

import moderngl
import numpy as np

from ...colour import srgb_to_linear
from ...gpu.programs import ProgramSpec
from ...params import Param
from ...render.meshes import (
    FIXED_TESSELLATION,
    Mesh,
    auto_tessellation,
    cube,
    slice_quad,
    torus,
    uv_sphere,
)
from ...render.noise import value_noise_texture
from ..base import Effect

MATERIALS = ("wood", "marble", "granite")
NOISES = ("value", "gradient")
OBJECTS = ("all", "cube", "sphere", "torus", "slice")
TESSELLATIONS = ("auto", "fixed")

MATERIAL = ProgramSpec("materials/material")
MATERIAL_OBJECT_POS = ProgramSpec("materials/material", defines=(("OUTPUT_OBJECT_POSITION", 1),))
MATERIAL_RADIUS = ProgramSpec("materials/material", defines=(("OUTPUT_RING_RADIUS", 1),))
MATERIAL_BAKED = ProgramSpec("materials/material", defines=(("BAKED_NOISE", 1),))
MATERIAL_BAKED_RADIUS = ProgramSpec("materials/material",
                                    defines=(("BAKED_NOISE", 1), ("OUTPUT_RING_RADIUS", 1)))
WOOD_BAKE_COMPUTE = ProgramSpec("materials/wood_noise_bake", requires_compute=True)
WOOD_BAKE_FRAGMENT = ProgramSpec("materials/wood_noise_bake", vert="common/fullscreen.vert",
                                 frag="materials/wood_noise_bake.frag")

#: object name → (mesh factory, translation, rotation axis-angle in degrees)
LAYOUT = {
    "cube": (cube, (-1.45, 0.0, 0.0), ((1.0, 1.0, 0.0), 35.0)),
    # tilted 40° toward the camera: the rings show as a bullseye on the ball and as long grain
    # above it, instead of the equator (r = 0.5, a ring edge at the default period 0.1) facing
    # the camera as a band of blotches
    "sphere": (uv_sphere, (0.0, 0.0, 0.0), ((1.0, 0.0, 0.0), 40.0)),
    "torus": (torus, (1.45, 0.0, 0.0), ((1.0, 0.0, 0.0), 55.0)),
    # the slice's mesh is built at materials.slice_y
    "slice": (slice_quad, (0.0, 0.0, 0.0), ((1.0, 0.0, 0.0), 0.0)),
}


def rotation(axis, degrees: float) -> np.ndarray:
    a = np.asarray(axis, dtype=np.float64)
    a = a / np.linalg.norm(a)
    t = math.radians(degrees)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    r = np.identity(4)
    r[:3, :3] = np.identity(3) + math.sin(t) * k + (1 - math.cos(t)) * (k @ k)
    return r


def model_matrix(translation, axis, degrees: float, spin_degrees: float = 0.0) -> np.ndarray:
    m = rotation(axis, degrees) @ rotation((0.0, 1.0, 0.0), spin_degrees)
    m[:3, 3] = translation
    return m


class Materials(Effect):
    name = "materials"
    former_names = ("material",)
    title = "Procedural materials"
    spec = "spec/004"
    programs = (MATERIAL, MATERIAL_OBJECT_POS, MATERIAL_RADIUS, MATERIAL_BAKED,
                MATERIAL_BAKED_RADIUS, WOOD_BAKE_COMPUTE, WOOD_BAKE_FRAGMENT)
    extra_groups = ("wood", "marble", "granite")

    @classmethod
    def context_paths(cls, caps, params) -> dict[str, str]:
        return {"baked wood noise": "a compute shader" if caps.compute
                else "one fragment pass per slice"}

    @classmethod
    def python_params(cls) -> list[Param]:
        w = "spec/004 §2"
        return [
            Param("materials.material", "wood", doc="which material: the thesis's wood, or "
                  "marble / granite", kind="choice", choices=MATERIALS, section="spec/004 §1.4"),
            Param("materials.noise", "value", doc="value = the thesis's lattice value noise; "
                  "gradient = Perlin 2002", kind="choice", choices=NOISES, section="spec/004 §1.5"),
            Param("materials.objects", "all", doc="which meshes to draw (slice = the y = 0 "
                  "cross-section, fig. 7)", kind="choice", choices=OBJECTS),
            Param("materials.tessellation", "auto", doc="segments of the sphere and torus: "
                  "auto = from their projected size (edges of about materials.edge_pixels, a few "
                  "levels), fixed = 48 × 96 at any size (the former meshes)", kind="choice",
                  choices=TESSELLATIONS),
            Param("materials.edge_pixels", 6.0, 1.0, 64.0, "auto tessellation: on-screen length "
                  "of an edge of the sphere and torus (smaller = finer meshes)", step=0.5,
                  unit="px"),
            Param("materials.filter_rings", False, doc="box-filter the ring edges over the pixel "
                  "footprint (anti-aliasing)", kind="bool"),
            Param("materials.lighting", False,
                  doc="Blinn–Phong lighting (the thesis renders unlit)", kind="bool"),
            Param("materials.light_dir", (0.5, 0.8, 0.45), -1.0, 1.0, "direction toward the light",
                  kind="vec3"),
            Param("materials.light_color", (1.0, 1.0, 1.0), 0.0, 4.0, "light colour", kind="vec3"),
            Param("materials.ambient", 0.3, 0.0, 1.0, "ambient light"),
            Param("materials.specular", 0.15, 0.0, 1.0, "specular strength"),
            Param("materials.shininess", 32.0, 1.0, 512.0, "Blinn–Phong exponent"),
            Param("materials.spin", 0.0, 0.0, 360.0, "turntable speed", unit="deg/s"),
            Param("materials.slice_y", 0.0, -0.5, 0.5, "height of the cross-section (objects = "
                  "slice)", unit="object units", section="spec/004 §1.4"),
            # the thesis's property table (spec/004 §2), names and defaults as documented
            Param("wood.vol_tex_scale", (1.0, 1.0, 1.0, 10.0), 0.0, 1000.0,
                  "_VolTexScale: scale before the ring texture (effective xyz·w; ring period 1/w)",
                  kind="vec4", section=w),
            Param("wood.noise_grid_size", (0.2, 1.0, 1.0, 10.0), 0.0, 1000.0,
                  "_NoiseGridSize: lattice cells per object unit (xyz·w)", kind="vec4", section=w),
            Param("wood.distor_factor", (1.0, 1.0, 1.0, 0.5), 0.0, 100.0,
                  "_DistorFactor: scale of the distortion vector (xyz·w)", kind="vec4", section=w),
            Param("wood.texture_2d_image_size", (1.0, 1.0, 1.0, 256.0), 0.0, 4096.0,
                  "_Texture2DImageSize: wrap of the noise input (xyz·w)", kind="vec4", section=w),
            Param("wood.inner_color", (0.75, 0.5, 0.25), 0.0, 1.0,
                  "_InnerColor: innermost, lighter ring colour", kind="color", section=w,
                  srgb=True),
            Param("wood.outer_color", (0.5, 0.25, 0.0), 0.0, 1.0,
                  "_OuterColor: outermost, darker ring colour", kind="color", section=w, srgb=True),
            Param("wood.rec_depth", 3, 1, 8, "_RecDepth: octaves of the noise", kind="int",
                  section=w),
            Param("wood.noise_seed", 1, 0, 2**31 - 1,
                  "seed of the 256×256 random noise source (_Noise)", kind="int", section=w),
            # marble and granite: beyond the thesis
            Param("marble.scale", 2.5, 0.01, 100.0, "frequency of the turbulence in object space"),
            Param("marble.vein_frequency", 2.0, 0.0, 50.0, "veins per object unit along x"),
            Param("marble.turbulence", 2.2, 0.0, 20.0, "how far turbulence pushes the veins"),
            Param("marble.sharpness", 0.35, 0.05, 8.0,
                  "exponent of the vein profile (small = thin dark veins)"),
            Param("marble.octaves", 5, 1, 10, "octaves of turbulence", kind="int"),
            Param("marble.base_color", (0.93, 0.92, 0.88), 0.0, 1.0, "marble colour", kind="color",
                  srgb=True),
            Param("marble.vein_color", (0.28, 0.3, 0.34), 0.0, 1.0, "vein colour", kind="color",
                  srgb=True),
            Param("granite.scale", 18.0, 0.01, 400.0, "frequency of the grains in object space"),
            Param("granite.octaves", 4, 1, 10, "octaves of fBm", kind="int"),
            Param("granite.threshold", 0.22, 0.0, 1.0,
                  "fBm level beyond which a grain is dark or light"),
            Param("granite.dark_color", (0.12, 0.11, 0.11), 0.0, 1.0, "dark grains", kind="color",
                  srgb=True),
            Param("granite.matrix_color", (0.62, 0.56, 0.54), 0.0, 1.0, "matrix", kind="color",
                  srgb=True),
            Param("granite.light_color", (0.9, 0.88, 0.86), 0.0, 1.0, "light grains", kind="color",
                  srgb=True),
        ]

    #: what each noise teaches (materials.noise)
    lesson_param = "materials.noise"
    LESSONS = {
        "value": "Value noise (spec/004 §1.5), the thesis's: random values at the lattice's "
                 "corners blended with the cubic fade 3t² − 2t³ and summed over octaves — C¹, "
                 "and not Perlin's gradient noise although the thesis calls it so (spec/004 "
                 "§1.2).",
        "gradient": "Gradient noise (Perlin 2002, beyond the thesis; compare spec/004 §1.5): "
                    "random gradients at the corners, dotted with the offsets and blended with "
                    "the quintic fade; zero at every lattice point, so the lattice shows less "
                    "than with the thesis's value noise.",
    }

    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        self._meshes: dict[object, Mesh] = {}
        self.last_meshes: dict[str, Mesh] = {}
        self._value_tex = self.keyed(lambda seed: value_noise_texture(gpu, self.name, seed),
                                     release=gpu.free)
        self._gradient = None

    def tessellation(self, name: str, frame=None) -> tuple[int, int] | None:
        """(rings, segments) of the sphere or torus for ``frame``'s camera and size (the fixed
        counts with ``materials.tessellation = fixed`` or without a frame); None for the flat
        meshes."""
        if name not in FIXED_TESSELLATION:
            return None
        if self.params["materials.tessellation"] == "fixed" or frame is None:
            return FIXED_TESSELLATION[name]
        centre = np.asarray(LAYOUT[name][1], dtype=np.float64)
        distance = float(np.linalg.norm(centre - np.asarray(frame.camera.position, float)))
        return auto_tessellation(name, distance, frame.camera.fov, frame.size[1],
                                 self.params["materials.edge_pixels"])

    def meshes(self, frame=None) -> list[tuple[str, Mesh]]:
        """The meshes to draw, each built once per key: the slice per height, the sphere and
        torus per tessellation level (a handful at most, so every level built is kept: a
        program's vertex arrays are cached by buffer, which a freed mesh must not leave
        behind)."""
        which = self.params["materials.objects"]
        names = ["cube", "sphere", "torus"] if which == "all" else [which]
        out = []
        for n in names:
            counts = self.tessellation(n, frame)
            key = ((n, self.params["materials.slice_y"]) if n == "slice"
                   else (n, *counts) if counts else n)
            if key not in self._meshes:
                if n == "slice":
                    data = slice_quad(self.params["materials.slice_y"])
                elif counts:
                    data = LAYOUT[n][0](rings=counts[0], segments=counts[1])
                else:
                    data = LAYOUT[n][0]()
                self._meshes[key] = Mesh(self.gpu, self.name, data)
            out.append((n, self._meshes[key]))
        self.last_meshes = {n: m for n, m in out}
        return out

    def triangles(self) -> int:
        """Triangles of the meshes drawn last."""
        return sum(len(m.data.indices) // 3 for m in self.last_meshes.values())

    def panel_notes(self) -> list[str]:
        counts = [f"{n} {len(m.data.indices) // 3} triangles" for n, m in self.last_meshes.items()
                  if n in FIXED_TESSELLATION]
        return [", ".join(counts)] if counts else []

    def _noise_textures(self) -> dict:
        """The noise sources the chosen material and noise read, by sampler name."""
        seed = self.params["wood.noise_seed"]
        out = {}
        if self.params["materials.noise"] == "value" or self.params["materials.material"] == "wood":
            out["uValueNoiseTex"] = self._value_tex.get(seed)
        if self.params["materials.noise"] == "gradient":
            from ...render.noise import GradientNoiseTextures

            if self._gradient is None:
                self._gradient = GradientNoiseTextures(self.gpu, self.name)
            out.update(self._gradient.textures(seed))
        return out

    def uniforms(self) -> dict:
        p = self.params
        size = p["wood.texture_2d_image_size"]
        out = {
            "uMaterial": MATERIALS.index(p["materials.material"]),
            "uNoiseKind": NOISES.index(p["materials.noise"]),
            "uRecDepth": p["wood.rec_depth"],
            "uFilterRings": p["materials.filter_rings"],
            "uLighting": p["materials.lighting"],
            "uLightDir": p["materials.light_dir"],
            "uLightColor": p["materials.light_color"],
            "uAmbient": p["materials.ambient"],
            "uSpecular": p["materials.specular"],
            "uShininess": p["materials.shininess"],
            "uVolTexScale": p["wood.vol_tex_scale"],
            "uNoiseGridSize": p["wood.noise_grid_size"],
            "uDistorFactor": p["wood.distor_factor"],
            "uValueNoiseWrap": tuple(float(v) * size[3] for v in size[:3]),
        }
        for group in ("marble", "granite"):
            for prm in p.groups().get(group, []):
                value = p[prm.name]
                if prm.srgb:
                    value = tuple(float(v) for v in srgb_to_linear(np.asarray(value)))
                out["u" + group.capitalize()
                    + "".join(s.capitalize() for s in prm.short.split("_"))] = value
        # the thesis lerps the ring colours as display values (Unity's gamma colour space);
        # the shader converts the result to linear radiance
        out["uInnerColor"] = p["wood.inner_color"]
        out["uOuterColor"] = p["wood.outer_color"]
        return out

    def bake_noise(self, size: int, use_compute: bool | None = None):
        """Bake the wood's distortion noise over the object box into a size³ texture."""
        from ...gpu.bake import bake_volume

        def setup(prog):
            prog.bind_textures(self._noise_textures())
            prog.set_many(self.uniforms())

        result = bake_volume(self.gpu, self.name, f"wood noise {size}³", (size, size, size),
                             WOOD_BAKE_COMPUTE, WOOD_BAKE_FRAGMENT, setup, use_compute)
        result.texture.repeat_x = result.texture.repeat_y = result.texture.repeat_z = False
        return result

    def draw(self, frame, target, spec: ProgramSpec = MATERIAL, view_proj: np.ndarray | None = None,
             baked=None) -> None:
        """Draw the meshes; ``view_proj`` replaces the camera's (tests look at the slice from
        above); ``baked`` is a noise volume from :meth:`bake_noise` for the BAKED_NOISE
        variants."""
        ctx = self.gpu.ctx
        prog = self.program(spec)
        prog.bind_textures({**self._noise_textures(), "uBakedNoise": baked})
        prog.set_many(self.uniforms())
        if view_proj is None:
            view_proj = frame.camera.projection_matrix(frame.aspect) @ frame.camera.view_matrix()
        prog.set_many({"uViewProj": view_proj, "uCameraPos": tuple(frame.camera.position)})
        target.use()
        ctx.enable(moderngl.DEPTH_TEST)
        spin = self.params["materials.spin"] * frame.time
        for name, mesh in self.meshes(frame):
            _, translation, (axis, degrees) = LAYOUT[name]
            if name == "slice":  # one-sided quad: seen from above or below
                ctx.disable(moderngl.CULL_FACE)
            else:
                ctx.enable(moderngl.CULL_FACE)
            prog.set("uModel", model_matrix(translation, axis, degrees, spin))
            mesh.draw(prog)
        ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)

"""The `planet` scene's effect: atmospheric scattering from the ground to space
(spec/002), in the thesis's three approximations plus Hillaire 2020.

Per frame:

1. shadow stage: the shadow map from the sun — re-rendered only when the sun direction (or the
   map size) changed (spec/002 §3.1, §4) — published as ``frame.shadows["sun"]``;
2. opaque stage: surfaces (mountains, city block) into a G-buffer: colour and camera-relative
   position; then the ground pass: the analytic Earth and the background where no mesh is;
3. fog stage: one full-screen scattering pass that finds what each pixel sees (G-buffer, the
   analytic Earth, or space) and applies the chosen method (``glsl/planet/composite.frag``):
   the sky and the aerial perspective of everything in front of it.

Fixed work kept out of the per-method pass, each with its earlier path one switch away (the
same image; ``natura bench planet``'s "changes" section times both in one interleaved run):
the land/sea noise baked once into a cubemap (``planet.ground_noise``), the hardware's depth
comparisons (``planet.shadow_compare``), and the ground pass (``planet.ground_pass``), so the
scattering pass reads every pixel's surface colour with one fetch.

Model no more than the view needs (beyond the thesis, docs/commands.md): methods 1–3 march one
ray per 2 × 2 or 4 × 4 pixels (``planet.march_scale``, ``render_reduced``), the mountains'
mesh is the coarsest whose cells span at most ``planet.mountain_lod_px`` pixels
(``mountain_grid``), and method 4's meshes' part is scissored to the screen bounds of the
meshes' chunks (``mesh_boxes``).

Slots: produces ``exposure`` (the thesis's pupil) and ``shadows``.

Coordinates: the scene's local frame has its origin on the sea surface, y up, the planet centre
at (0, −R, 0). The camera position is kept in double precision here; the GPU only ever sees
camera-relative vectors (float32 breaks at planet scale otherwise).
"""

from __future__ import annotations

import math
from typing import Any

import moderngl
import numpy as np

from ...frame import ShadowMap, Stage
from ...gpu.cache import MEMO, memoised
from ...gpu.programs import ProgramSpec, draw_fullscreen, fullscreen
from ...gpu.targets import depth_tested
from ...params import Param
from ...render import shadows
from ...render.shadow_maps import render_depth_pass
from ...render.shadows import COMPARE_MODES, configure_compare, depth_target, directional_view_proj
from ...sim import atmosphere as atm
from ..base import Effect, Pass
from . import hillaire
from .geometry import albedo_texture, boxes, mountains, normal_texture

METHODS = ("brute_force", "lut", "shadowed", "hillaire")
DEBUG_VIEWS = ("final", "in_scatter", "out_scatter")
SURFACES = ("by_method", "texture", "phong")
PC_RULES = ("by_method", "midpoint", "thesis")
#: method 1's universe sphere about the Earth's centre: 200 km above the sea (see
#: glsl/planet/composite.frag, "Method 1's universe sphere")
UNIVERSE_RADIUS = atm.BOTTOM_RADIUS_M + 200_000.0

GROUND_NOISE = ("baked", "live")
#: the resolution methods 1–3 march at, per side: every pixel's own ray (the thesis's), or one
#: ray per 2 × 2 block with depth-aware upsampling and a march of its own for every silhouette
#: pixel (planet/composite.frag's MARCH_PASS)
MARCH_SCALES = {"full": 1, "half": 2, "quarter": 4}
#: where the analytic ground and the space background are shaded: once into the G-buffer by the
#: ground pass (planet/ground.frag), or in the per-method scattering pass (the earlier path)
GROUND_PASS = ("gbuffer", "scattering")
#: half-angle of the baked ground noise's fine cap about the scene's origin (the space view's
#: horizon is 17° from it)
GROUND_CAP_DEG = 25.0
GROUND_CAP_TAN = math.tan(math.radians(GROUND_CAP_DEG))
#: ground-noise bakes kept on disk (22 MB each at 2048²): a size dragged in the panel
#: writes one file a size (and a GL 4.1 context has files of its own)
KEPT_GROUND_NOISE = 6


def composite_spec(method: str, compare: str = "hardware", noise: str = "baked",
                   ground: str = "gbuffer", part: int = 0, march: int = 1,
                   march_pass: int = 0, ozone: bool = False) -> ProgramSpec:
    """The scattering pass for ``method``, with the shadow comparisons ``compare`` (hardware or
    manual), the ground's noise ``noise`` (baked or live; only where the pass shades the ground
    itself) and ``ground``: ``gbuffer`` reads the analytic ground's and the background's colour
    from the G-buffer (the ground pass's, :func:`ground_spec`), ``scattering`` shades them here.
    Method 4 only: ``part`` (HILLAIRE_PART: 0 every pixel, 1 those no mesh covers, 2 the meshes;
    1 and 2 are drawn on the far plane, planet/ground.vert, against the G-buffer's depth) and
    ``march`` (HILLAIRE_MARCH of hillaire_lookup.glsl: 0 lookups, 1 both, 2 the march).
    Methods 1–3 only: ``march_pass`` (MARCH_PASS: 0 every pixel marched, 1 the reduced-resolution
    grid's march, 2 its depth-aware upsampling and composite, marking the pixels it cannot
    interpolate with window depth 1, 3 the march of those pixels alone: pass 0's program drawn
    on the far plane, planet/ground.vert, with the depth test '<=').
    ``ozone`` (method 4 only): HILLAIRE_OZONE, the lookups' transmittance from the transmittance
    LUT, which holds the ozone layer the sky-view LUT's and the volume's alphas do not."""
    defines: tuple = (("METHOD", METHODS.index(method) + 1),)
    if compare == "manual" and not (method == "hillaire" and ground == "gbuffer"):
        defines += (("SHADOW_COMPARE_MANUAL", 1),)  # method 4 reads no shadows from the G-buffer
    if ground == "gbuffer":
        defines += (("SURFACES_IN_GBUFFER", 1),)
    elif noise == "baked":
        defines += (("GROUND_NOISE_BAKED", 1),)
    vert = "common/fullscreen.vert"
    if method == "hillaire":
        defines += (("HILLAIRE_PART", int(part)), ("HILLAIRE_MARCH", int(march)))
        if ozone:
            defines += (("HILLAIRE_OZONE", 1),)
        if part:
            vert = "planet/ground.vert"
    elif march_pass:
        defines += (("MARCH_PASS", int(march_pass)),)
        if march_pass == 3:
            vert = "planet/ground.vert"
    return ProgramSpec("planet/composite", vert=vert, frag="planet/composite.frag",
                       defines=defines)


#: method 4's composite programs per (compare, noise, ground): the two lookup-only parts, drawn
#: against the G-buffer's depth, and one pass over every pixel with the march blended in (the
#: camera in the band above the atmosphere, a mesh past the volume's range, or a target whose
#: depth the G-buffer's cannot stand in for) or alone (from space)
HILLAIRE_PARTS = ((1, 0), (2, 0), (0, 1), (0, 2))


def ground_spec(compare: str = "hardware", noise: str = "baked") -> ProgramSpec:
    """The ground pass (planet/ground.frag): the analytic Earth and the background into the
    G-buffer where no mesh is, with the shadow comparisons ``compare`` and the noise ``noise``."""
    defines: tuple = ()
    if compare == "manual":
        defines += (("SHADOW_COMPARE_MANUAL", 1),)
    if noise == "baked":
        defines += (("GROUND_NOISE_BAKED", 1),)
    return ProgramSpec("planet/ground", defines=defines)


#: the defaults (hardware compares, the ground in the G-buffer) by method
COMPOSITE = {m: composite_spec(m) for m in METHODS}
#: every variant `natura shaders check` compiles: the defaults and each earlier path alone
COMPOSITE_VARIANTS = tuple(dict.fromkeys(
    composite_spec(m, c, n, g, part, march) for m in METHODS
    for c, n, g in (("hardware", "baked", "gbuffer"), ("manual", "baked", "gbuffer"),
                    ("hardware", "baked", "scattering"), ("manual", "baked", "scattering"),
                    ("hardware", "live", "scattering"))
    for part, march in (HILLAIRE_PARTS if m == "hillaire" else ((0, 1),)))) + tuple(
    # methods 1–3's reduced-resolution march and its upsampling
    composite_spec(m, c, n, g, march_pass=mp) for m in METHODS[:3]
    for c, n, g in (("hardware", "baked", "gbuffer"), ("manual", "baked", "gbuffer"),
                    ("hardware", "baked", "scattering"))
    for mp in (1, 2, 3))
GROUND = ground_spec()
GROUND_VARIANTS = (GROUND, ground_spec("manual"), ground_spec("hardware", "live"))
SURFACE = ProgramSpec("planet/surface")
SURFACE_MANUAL = ProgramSpec("planet/surface", defines=(("SHADOW_COMPARE_MANUAL", 1),))
GROUND_NOISE_BAKE = ProgramSpec("planet/ground_noise_bake", vert="common/fullscreen.vert",
                                frag="planet/ground_noise_bake.frag")
SHADOW_DEPTH = ProgramSpec("planet/shadow_depth")
#: `natura bench planet`'s yardstick for method 4's pass: one trilinear 3D read per pixel
LOOKUP_REFERENCE = fullscreen("planet/lookup_reference")
#: the meshes' depth pre-pass: the surfaces' own vertex stage (invariant gl_Position), no colour
SURFACE_DEPTH = ProgramSpec("planet/surface_depth", vert="planet/surface.vert",
                            frag="planet/shadow_depth.frag")

#: the mountains' meshes, finest first: cells per side of the 20 km heightfield (each coarser
#: grid's vertices are every other one of the finer's, so it keeps their heights)
MOUNTAIN_GRIDS = (192, 96)
LOD_SECTION = "spec/002 §5"  # the test scene's mountains (their level of detail is ours)

SHADOW_CENTRE = np.array([0.0, 800.0, -9000.0])
SHADOW_HALF = 17000.0


#: toward the sun from elevation and azimuth (0 north, 90 east) — the numpy model's function
sun_direction = atm.direction
#: the thesis's variable exposure clamp(1 − cos γ / 4, 0, 1) (spec/002 §1.6)
pupil = atm.pupil


#: the sun's elevation and azimuth are rounded to this for the sky's irradiance table (degrees)
SKY_IRRADIANCE_STEP_DEG = 0.25


def _sky_irradiance_table(model, elevation: float, azimuth: float) -> np.ndarray:
    """The irradiance table for a sun at (elevation, azimuth) degrees (memoised per process)."""
    return atm.sky_irradiance_table(atm.direction(elevation, azimuth), model)


def resolve_pc_rule(rule: str, method: str) -> str:
    """The τ(PC) rule ``planet.pc_rule`` means for ``method``: ``by_method`` is the thesis's
    (the whole step, §2.3) for method 1, whose figure it makes, and the midpoint rule for the
    others; ``midpoint`` and ``thesis`` mean themselves (the numpy twins take these two)."""
    if rule == "by_method":
        return "thesis" if method == "brute_force" else "midpoint"
    return rule


def light_view_proj(sun_dir: np.ndarray) -> np.ndarray:
    """Orthographic projection along the sun over the mountains and the city (spec/002 §3.1)."""
    return memoised(_light_view_proj, tuple(float(v) for v in np.asarray(sun_dir).reshape(3)))


def _light_view_proj(sun_dir: tuple) -> np.ndarray:
    return directional_view_proj(np.asarray(sun_dir), SHADOW_CENTRE, SHADOW_HALF, 30000.0,
                                 60000.0)


def caster_points(radius: float) -> np.ndarray:
    """(N, 3) float64 vertex positions of every shadow caster (the mountains and the city)."""
    return np.concatenate([np.asarray(build(radius)[0], dtype=np.float64).reshape(-1, 11)[:, :3]
                           for build in (mountains, boxes)])


#: texels the caster box is padded by on each side: the filter's radius, one more for a bilinear
#: comparison's neighbour, one for rasterisation (a texel is a caster's when its centre is covered)
CASTER_PAD_TEXELS = shadows.PCF_RADIUS + 2
#: light-space depth the nearest caster's is lowered by (a 24-bit depth's rounding is 6e-8)
CASTER_DEPTH_PAD = 1.0e-5


def mountain_bounds(radius: float) -> tuple[np.ndarray, np.ndarray]:
    """The mountains' axis-aligned bounds in the local frame: (lo, hi)."""
    pts = np.asarray(mountains(radius)[0], dtype=np.float64).reshape(-1, 11)[:, :3]
    return pts.min(axis=0), pts.max(axis=0)


def mountain_grid(camera_local, fov_deg: float, height_px: int, radius: float,
                  max_cell_px: float) -> int:
    """The coarsest of :data:`MOUNTAIN_GRIDS` whose cells, seen from ``camera_local`` at the
    mountains' nearest point, span at most ``max_cell_px`` pixels of a ``height_px``-tall image
    with a vertical field of view ``fov_deg`` (the finest when none does, or ``max_cell_px`` is
    0, or the camera is within the mountains' bounds)."""
    lo, hi = memoised(mountain_bounds, radius)
    cam = np.asarray(camera_local, dtype=np.float64)
    nearest = float(np.linalg.norm(cam - np.clip(cam, lo, hi)))
    pixel = nearest * 2.0 * math.tan(math.radians(fov_deg) / 2.0) / max(int(height_px), 1)
    if max_cell_px <= 0.0 or pixel <= 0.0:
        return MOUNTAIN_GRIDS[0]
    size = float(hi[0] - lo[0])
    fits = [g for g in MOUNTAIN_GRIDS if size / g / pixel <= max_cell_px]
    return min(fits) if fits else MOUNTAIN_GRIDS[0]


#: the mountains' bounds are kept per chunk of this many cells per side (method 4's scissor)
BOUNDS_CHUNK = 24


def mesh_boxes(radius: float) -> np.ndarray:
    """(N, 2, 3): axis-aligned (lo, hi) boxes that hold every mesh: one per chunk of
    ``BOUNDS_CHUNK``² cells of the finest mountains (whose box holds the coarser mesh's
    triangles too: their vertices are the finer's) and one per city box."""
    out = []
    verts = np.asarray(mountains(radius)[0], dtype=np.float64).reshape(-1, 11)[:, :3]
    n = int(round(np.sqrt(len(verts))))
    grid = verts.reshape(n, n, 3)
    for i in range(0, n - 1, BOUNDS_CHUNK):
        for j in range(0, n - 1, BOUNDS_CHUNK):
            chunk = grid[i:i + BOUNDS_CHUNK + 1, j:j + BOUNDS_CHUNK + 1].reshape(-1, 3)
            out.append((chunk.min(axis=0), chunk.max(axis=0)))
    city = np.asarray(boxes(radius)[0], dtype=np.float64).reshape(-1, 20, 11)[:, :, :3]
    out += [(b.min(axis=0), b.max(axis=0)) for b in city]   # 5 faces of 4 vertices per box
    return np.array(out)


def mesh_box_corners(radius: float) -> np.ndarray:
    """(N, 8, 3): the corners of each box of :func:`mesh_boxes`."""
    b = memoised(mesh_boxes, radius)
    pick = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)])
    return np.stack([b[:, pick[:, 0], 0], b[:, pick[:, 1], 1], b[:, pick[:, 2], 2]], axis=-1)


def caster_bounds(radius: float) -> tuple[np.ndarray, np.ndarray]:
    """The casters' (meshes') axis-aligned bounds in the local frame: (lo, hi)."""
    pts = memoised(caster_points, radius)
    return pts.min(axis=0), pts.max(axis=0)


def caster_box(points: np.ndarray, sun_dir: np.ndarray, size: int) -> tuple[tuple, float]:
    """Where the shadow map can hide the sun (planet/shadow.glsl's uShadowCasterBox and
    uShadowCasterDepth): the light-space (x0, y0, x1, y1) in [0, 1] of the casters' vertices,
    padded by ``CASTER_PAD_TEXELS`` texels of a ``size``² map, and their nearest depth. A point
    outside that box, or in front of that depth, passes every comparison: it is lit."""
    m = light_view_proj(sun_dir)
    p = (points @ m[:3, :3].T + m[:3, 3]) * 0.5 + 0.5       # orthographic: w = 1
    pad = CASTER_PAD_TEXELS / float(size)
    lo, hi = p.min(axis=0), p.max(axis=0)
    box = (float(lo[0] - pad), float(lo[1] - pad), float(hi[0] + pad), float(hi[1] + pad))
    return box, float(lo[2] - CASTER_DEPTH_PAD)


class Planet(Effect):
    name = "planet"
    title = "Atmospheric scattering"
    spec = "spec/002"
    programs = (COMPOSITE_VARIANTS + GROUND_VARIANTS
                + (SURFACE, SURFACE_MANUAL, SURFACE_DEPTH, SHADOW_DEPTH, GROUND_NOISE_BAKE,
                   LOOKUP_REFERENCE)
                + tuple(hillaire.HillaireLuts.programs))
    extra_groups = ("atmosphere", "hillaire")
    stages = (Stage.SHADOW, Stage.OPAQUE, Stage.FOG)
    produces = frozenset({"exposure", "shadows"})

    @classmethod
    def context_paths(cls, caps, params) -> dict[str, str]:
        aniso = params["planet.anisotropy"]
        chosen = aniso or (1 if caps.software else 8)
        scale = params["planet.march_scale"]
        return {"Hillaire aerial perspective": "a compute shader" if caps.compute
                else "fragment passes into a 2D atlas",
                "planet march scale (methods 1–3)": scale if scale != "auto" else
                f"{'quarter' if caps.software else 'half'} (auto: "
                f"{'a software renderer' if caps.software else 'a GPU'})",
                "planet texture anisotropy": f"{chosen}× ({'set' if aniso else 'auto'}"
                f"{'' if aniso else ': off on a software renderer'})"}

    @classmethod
    def python_params(cls) -> list[Param]:
        s = "spec/002"
        return atm.params_list() + hillaire.params() + [
            Param("planet.method", "shadowed", doc="1 brute force · 2 optical-depth LUT · 3 LUT + "
                  "shadows (light shafts) · 4 Hillaire 2020 multiple scattering", kind="choice",
                  choices=METHODS, section=f"{s} §2"),
            Param("planet.n_steps", 30, 1, 512,
                  "N_STEPS of the view-ray midpoint sum (methods 1–3)", kind="int",
                  section=f"{s} §1.7"),
            Param("planet.inner_steps", 30, 1, 512, "steps of the brute-force sun integral (method "
                  "1)", kind="int", section=f"{s} §2.3"),
            Param("planet.pc_rule", "by_method", doc="depth from the camera to each sample: "
                  "midpoint (half the current step), thesis (the whole step, as its code: ~50 % "
                  "error on the horizon at N = 30), or by_method (thesis for method 1, which "
                  "reproduces the thesis's figure with it; midpoint for methods 2–3)",
                  kind="choice", choices=PC_RULES, section=f"{s} §2.3"),
            Param("planet.lut_height", 256, 8, 2048, "optical-depth LUT rows (height)", kind="int",
                  section=f"{s} §1.8"),
            Param("planet.lut_angle", 256, 8, 2048, "optical-depth LUT columns (cos Φ)", kind="int",
                  section=f"{s} §1.8"),
            Param("planet.shadow_map_size", 4096, 64, 8192, "shadow-map resolution (texels per "
                  "side)", kind="int", section=f"{s} §3.1"),
            Param("planet.shadow_filter", True, doc="Gaussian-weighted bilinear neighbourhood "
                  "filter (off: nearest, unfiltered)", kind="bool", section=f"{s} §3.2"),
            Param("planet.shadow_compare", "hardware", doc="depth comparisons of the shadow "
                  "filter: hardware (sampler2DShadow, one read per bilinear comparison) or manual "
                  "(four texelFetch and a blend each: the earlier path, the same image)",
                  kind="choice", choices=COMPARE_MODES, section=f"{s} §3.2"),
            Param("planet.ground_noise", "baked", doc="the analytic Earth's land/sea noise: "
                  "baked (a cubemap made once, one lookup per pixel) or live (5 octaves of Perlin "
                  "noise per pixel, the reference)", kind="choice", choices=GROUND_NOISE,
                  section=f"{s} §5"),
            Param("planet.ground_pass", "gbuffer", doc="where the analytic ground and the "
                  "space background are shaded: gbuffer (once per frame into the G-buffer by the "
                  "ground pass, outside the per-method scattering pass, whose time is then the "
                  "atmosphere's alone) or scattering (in the scattering pass: the earlier path, "
                  "the same image)", kind="choice", choices=GROUND_PASS, section=f"{s} §5"),
            Param("planet.march_scale", "auto", doc="resolution the per-pixel march of "
                  "methods 1–3 runs at, per side: half (one ray per 2×2 pixels, each pixel's "
                  "in-scattering and transmittance interpolated from the 4 around it when they "
                  "saw its surface and change slowly, its own ray marched on silhouettes and "
                  "fast changes: the field's way with light shafts), quarter (one per 4×4), "
                  "auto (quarter on a software renderer, half on a GPU) or full (every pixel's "
                  "own ray: the thesis's, the reference)",
                  kind="choice", choices=("auto", *MARCH_SCALES),
                  section="spec/002 §2.5"),
            Param("planet.march_contrast", 0.1, 0.0, 1.0, "half march_scale: the largest "
                  "spread of the 4 grid values around a pixel, relative to the largest, that it "
                  "interpolates; beyond it the pixel marches its own ray (0: only pixels whose 4 "
                  "values are equal are interpolated)",
                  section="spec/002 §2.5"),
            Param("planet.mountain_lod_px", 10.0, 0.0, 64.0, "the mountains' mesh: the "
                  "coarsest of 192² and 96² cells whose cells span at most this many pixels at "
                  "the mountains' nearest point (their silhouette moves by a pixel or two; the "
                  "shadow map is drawn from the same mesh); 0: always the finest (the former "
                  "mesh, the reference)", unit="px", section=LOD_SECTION),
            Param("planet.depth_prepass", True, doc="draw the meshes' depth first, then shade "
                  "each covered pixel once (depth test '<='): the mountains' triangles overlap "
                  "about nine deep on screen, and without it (the earlier path, the same image) "
                  "every layer drawn in front of the depth so far is shaded", kind="bool",
                  section=f"{s} §3.3"),
            Param("planet.ground_noise_size", 2048, 64, 8192, "texels per side of the baked ground "
                  "noise's cap about the origin (its cubemap for the rest: a quarter of that)",
                  kind="int", section=f"{s} §5"),
            Param("planet.shadow_bias", 0.0004, 0.0, 0.01, "depth bias of the shadow comparison",
                  step=0.0001, section=f"{s} §3.1"),
            Param("planet.surface", "by_method", doc="surface shading: by_method (texture for "
                  "methods 1–2 as the thesis, Phong for 3–4), texture, or phong", kind="choice",
                  choices=SURFACES, section=f"{s} §3.3"),
            Param("planet.anisotropy", 0, 0, 16, "anisotropic filtering of surface textures (0 = "
                  "auto: 8 on a hardware GPU, off on a software renderer, where it costs ~30× the "
                  "surface pass)", kind="int"),
            Param("planet.normal_mapping", True, doc="normal maps in Phong shading", kind="bool",
                  section=f"{s} §3.3"),
            Param("planet.ambient", "constant", doc="the surfaces' ambient light: constant (the "
                  "thesis: planet.ka × the texture colour) or sky (beyond the thesis: the "
                  "single-scattering sky's irradiance on the surface's normal, × planet.kd)",
                  kind="choice", choices=("constant", "sky"), section=f"{s} §10.3"),
            Param("planet.ka", 0.25, 0.0, 1.0, "Phong ambient factor (times the texture colour)",
                  section=f"{s} §3.3"),
            Param("planet.kd", 1.0, 0.0, 2.0, "Phong diffuse factor", section=f"{s} §3.3"),
            Param("planet.ks", 0.15, 0.0, 1.0, "Phong specular factor", section=f"{s} §3.3"),
            Param("planet.shininess", 24.0, 1.0, 256.0, "Phong exponent", section=f"{s} §3.3"),
            Param("planet.sun_elevation", 35.0, -90.0, 90.0, "sun elevation (Up/Down keys)",
                  unit="deg", section=f"{s} §4"),
            Param("planet.sun_azimuth", 180.0, 0.0, 360.0, "sun azimuth (0 north, 90 east)",
                  unit="deg"),
            Param("planet.auto_sun", False, doc="move the sun automatically (M key)", kind="bool",
                  section=f"{s} §4"),
            Param("planet.sun_speed", 3.0, 0.0, 90.0, "automatic sun speed", unit="deg/s"),
            Param("planet.pupil", True, doc="variable exposure: darker looking at the sun",
                  kind="bool", section=f"{s} §1.6"),
            Param("planet.debug_view", "final", doc="final image, in-scattering on black, or "
                  "out-scattering on white", kind="choice", choices=DEBUG_VIEWS,
                  section=f"{s} §1.4, §1.5"),
            Param("planet.sun_disk", True, doc="draw the sun's disk (beyond the thesis, which "
                  "shows only the Mie halo)", kind="bool"),
            Param("planet.star_intensity", 0.08, 0.0, 5.0,
                  "brightness of the stars on the universe sphere"),
            Param("planet.universe_radius", UNIVERSE_RADIUS, 1.0e5, 1.0e9, "radius of the "
                  "universe sphere method 1 integrates rays into space to (default: 200 km above "
                  "the sea about the Earth's centre, a blue sky and a dark band at the horizon as "
                  "the thesis's figure; 1e7 with universe_centre = camera: the first sample at "
                  "167 km, a black sky above ~15°)", unit="m", section=f"{s} §2.4"),
            Param("planet.universe_centre", "earth", doc="centre of method 1's universe sphere: "
                  "the Earth's (a sphere containing the scene, as the thesis's) or the camera's (a "
                  "dome that follows it: every ray into space is universe_radius long)",
                  kind="choice", choices=("earth", "camera"), section=f"{s} §2.4"),
        ]

    #: what each method teaches (the panel shows the current one above the parameters)
    lesson_param = "planet.method"
    LESSONS = {
        "brute_force": "Method 1, brute force (spec/002 §2.3): a midpoint sum along the view "
                       "ray with a nested sum toward the sun at every sample, N_STEPS × "
                       "inner_steps density evaluations per pixel; the thesis's first "
                       "approximation ran at 26 FPS at 1280×720, noisy, its horizon displaced.",
        "lut": "Method 2, optical-depth LUT (spec/002 §2.4): the inner sun integral becomes one "
               "lookup in a table precomputed by height and cos Φ (the thesis's \"Chapman "
               "function\", spec/002 §1.8) and the view ray is clipped to the atmosphere: up to "
               "7× faster in the thesis.",
        "shadowed": "Method 3, LUT + shadows (spec/002 §2.5): a sun shadow map (spec/002 §3.1) "
                    "gives V(P) at every view-ray sample, so air in shadow scatters nothing and "
                    "light shafts appear; the thesis paid for it with a sharp drop in FPS.",
        "hillaire": "Method 4, Hillaire 2020 (beyond the thesis, which computes single "
                    "scattering, spec/002 §1.5): transmittance and multiple-scattering LUTs and "
                    "a per-frame sky-view LUT add the light scattered more than once, the "
                    "costly marches done once into small tables.",
    }

    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        self.shadow_passes = 0
        self._shadow_rendered = None  # the key the shadow map was last rendered for
        #: where the casters can hide the sun, for the key the shadow map was last rendered for
        self._caster_box: tuple[tuple, float] = ((1.0, 1.0, 0.0, 0.0), 2.0)
        #: (depth texture, framebuffer) of the shadow map, remade when its size changes
        self._shadow = self.keyed(self._make_shadow_map, release=self._free_all)
        self._lut = self.keyed(self._build_lut, release=gpu.free)
        #: the sky's irradiance table (planet.ambient = sky), rebuilt when the sun or the model
        #: changes
        self._sky_irradiance = self.keyed(self._build_sky_irradiance, release=gpu.free)
        #: the baked ground-noise cubemap, rebuilt when its size changes
        self._ground_noise = self.keyed(self._bake_ground_noise, release=self._free_all)
        self._meshes: dict | None = None   # (name, grid) → (vertices, indices)
        self._rect: tuple | None = None      # (key, mesh_rect) of the last view
        self._model: tuple | None = None   # (the atmosphere group's version, its model)
        #: cells per side of the mountains' mesh this frame (:func:`mountain_grid`)
        self.grid = MOUNTAIN_GRIDS[0]
        self._textures = None
        #: (colour, position, depth, framebuffer), remade when the target's size changes
        self._gbuffer = self.keyed(self._make_gbuffer, release=self._free_all)
        #: the reduced-resolution march's targets, remade when the size or the scale changes
        self._march_grid = self.keyed(self._make_march_grid, release=self._free_all)
        self.last_march_scale = 1  # pixels per side per marched ray in the last scattering pass
        self._hillaire = None
        self._reference_volume = None
        self._gradient = None
        self._stars = None
        self.sun_dir = sun_direction(params["planet.sun_elevation"], params["planet.sun_azimuth"])

    def model(self) -> "atm.AtmosphereParams":
        """The atmosphere of the ``atmosphere.*`` parameters, rebuilt when one of them changes
        (a pass asks for it about ten times a frame)."""
        version = self.params.version("atmosphere")
        if self._model is None or self._model[0] != version:
            self._model = (version, atm.from_params(self.params))
        return self._model[1]

    def camera_local(self, frame) -> np.ndarray:
        return np.asarray(frame.camera.position, dtype=np.float64)

    def model_uniforms(self, frame) -> dict:
        m = self.model()
        cam = self.camera_local(frame)
        centre = np.array([0.0, -m.bottom_radius, 0.0])
        return {
            **m.uniforms(),
            "uEarthCenter": tuple((centre - cam).astype(np.float32)),
            "uCameraRadius": float(np.linalg.norm(cam - centre)),
            "uCameraLocal": tuple(cam.astype(np.float32)),
            "uSunDir": tuple(self.sun_dir),
        }

    def universe_centre(self, frame) -> tuple:
        """Centre of method 1's universe sphere relative to the camera."""
        if self.params["planet.universe_centre"] == "camera":
            return (0.0, 0.0, 0.0)
        centre = np.array([0.0, -self.model().bottom_radius, 0.0])
        return tuple((centre - self.camera_local(frame)).astype(np.float32))

    def method(self) -> str:
        return self.params["planet.method"]

    def pc_rule(self) -> str:
        """The τ(PC) rule in use (``midpoint`` or ``thesis``)."""
        return resolve_pc_rule(self.params["planet.pc_rule"], self.method())

    def shading(self) -> int:
        s = self.params["planet.surface"]
        if s == "by_method":
            return 1 if self.method() in ("shadowed", "hillaire") else 0
        return 1 if s == "phong" else 0

    def uses_shadows(self) -> bool:
        return self.method() == "shadowed" or self.shading() == 1

    def update(self, frame, dt: float) -> None:
        p = self.params
        if p["planet.auto_sun"] and dt > 0:
            e = p["planet.sun_elevation"] + p["planet.sun_speed"] * dt
            if e > 90.0:  # over the top: continue down the other side
                e = 180.0 - e
                p.set("planet.sun_azimuth", (p["planet.sun_azimuth"] + 180.0) % 360.0)
            p.set("planet.sun_elevation", max(-90.0, min(90.0, e)))
        self.sun_dir = sun_direction(p["planet.sun_elevation"], p["planet.sun_azimuth"])
        cam = frame.camera
        self.grid = mountain_grid(self.camera_local(frame), cam.fov, frame.size[1],
                                  self.model().bottom_radius, p["planet.mountain_lod_px"])
        if p["planet.pupil"]:
            frame.exposure *= float(pupil(float(np.dot(frame.camera.forward(), self.sun_dir))))

    def _ensure_geometry(self) -> None:
        if self._meshes is not None:
            return
        r = self.model().bottom_radius
        self._meshes = {}
        builds = [(("mountains", g), memoised(mountains, r, 20000.0, g)) for g in MOUNTAIN_GRIDS]
        for name, (verts, idx) in builds + [(("city", 0), memoised(boxes, r))]:
            # built once per process
            vbo = self.gpu.buffer(self.name, f"{name[0]} {name[1]} vertices", verts.tobytes())
            ibo = self.gpu.buffer(self.name, f"{name[0]} {name[1]} indices", idx.tobytes())
            self._meshes[name] = (vbo, ibo)
        self._textures = (
            self.gpu.texture(self.name, "albedo", (256, 256), 4,
                             memoised(albedo_texture).tobytes(),
                             dtype="f1", repeat=True),
            self.gpu.texture(self.name, "normal map", (256, 256), 4,
                             memoised(normal_texture).tobytes(),
                             dtype="f1", repeat=True),
        )
        for tex in self._textures:
            tex.build_mipmaps()
            tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
        from ...bakes.cache import default_cache_dir
        from ...sim.textures import cached_texture

        stars = cached_texture("stars", default_cache_dir(), seed=7)  # the sky's field, cached
        self._stars = self.gpu.texture(self.name, "stars", (stars.shape[1], stars.shape[0]), 1,
                                       stars.tobytes(), repeat=True)

    def _draw_meshes(self, prog, depth_only: bool = False) -> None:
        layout = ("3f 32x", "in_position") if depth_only else \
            ("3f 3f 3f 2f", "in_position", "in_normal", "in_tangent", "in_uv")
        assert self._meshes is not None, "geometry first (_ensure_geometry)"
        for key in (("mountains", self.grid), ("city", 0)):
            vbo, ibo = self._meshes[key]
            prog.vao([(vbo, *layout)], index_buffer=ibo).render()

    def _free_all(self, objects) -> None:
        for obj in reversed(objects):
            self.gpu.free(obj)

    def optical_depth_lut(self):
        """The thesis's "Chapman function" table, rebuilt when the model or its size changes."""
        size = (self.params["planet.lut_angle"], self.params["planet.lut_height"])
        return self._lut.get(self.model().lut_key() + size)

    def _build_lut(self, key):
        size = key[-2:]
        # the table depends on the model only through its lut_key (the contract of the key):
        # one build per process, not per session
        data = MEMO.get((atm.OpticalDepthLut, key), lambda: atm.OpticalDepthLut(
            self.model(), n_height=size[1], n_angle=size[0]).table)
        lut = self.gpu.texture(self.name, "optical depth LUT", size, 3, data.astype("f4").tobytes(),
                               dtype="f4")
        lut.repeat_x = lut.repeat_y = False
        return lut

    def sky_irradiance_sun(self) -> tuple[float, float]:
        """The sun (elevation, azimuth) in degrees the irradiance table is built for: the
        parameters rounded to SKY_IRRADIANCE_STEP_DEG, so a moving sun rebuilds it in steps."""
        q = SKY_IRRADIANCE_STEP_DEG
        p = self.params
        return (round(float(p["planet.sun_elevation"]) / q) * q,
                round(float(p["planet.sun_azimuth"]) / q) * q % 360.0)

    def sky_irradiance(self):
        """The sky's irradiance table (app/sim/atmosphere.py, sky_irradiance_table) as an RGB32F
        texture, for the ground's and the meshes' ambient with planet.ambient = sky."""
        return self._sky_irradiance.get((self.model(),) + self.sky_irradiance_sun())

    def _build_sky_irradiance(self, key):
        model, el, az = key
        table = memoised(_sky_irradiance_table, model, el, az)
        w, h = atm.IRRADIANCE_SIZE
        tex = self.gpu.texture(self.name, "sky irradiance", (w, h), 3, table.tobytes(), dtype="f4")
        tex.repeat_x, tex.repeat_y = True, False
        return tex

    def ground_noise(self) -> tuple:
        """(cap, cubemap): the analytic Earth's noise f(n) baked into R32F textures — a gnomonic
        cap of ``planet.ground_noise_size``² about the scene's origin (half-angle
        ``GROUND_CAP_DEG``) and a cubemap of a quarter of that size for the rest of the sphere;
        baked when the size changes."""
        return self._ground_noise.get(int(self.params["planet.ground_noise_size"]))

    def _gradient_textures(self) -> dict:
        if self._gradient is None:
            from ...render.noise import GradientNoiseTextures

            self._gradient = GradientNoiseTextures(self.gpu, self.name)
        return self._gradient.textures(None)

    def _bake_ground_noise(self, size: int):
        """Render f(n) (glsl/planet/ground_noise_bake.frag) into the cap directly and into each
        cubemap face through a 2D R32F target copied into the face on the GPU (moderngl cannot
        attach a cube face to a framebuffer: ``Gpu.copy_to_cube_face``)."""
        from ...bakes.cache import BakeCache, cache_key, driver

        ctx = self.gpu.ctx
        linear = (moderngl.LINEAR, moderngl.LINEAR)
        cap = self.gpu.texture(self.name, "ground noise cap", (size, size), 1, dtype="f4",
                               filter=linear)
        n = max(16, size // 4)
        cube = self.gpu.texture_cube(self.name, "ground noise", n, 1, dtype="f4")
        cube.filter = linear
        prog = self.program(GROUND_NOISE_BAKE)
        # on disk beside the cloud noise (~0.7 s of llvmpipe at 2048² otherwise), keyed by the
        # program's files (names and content hashes: an exercise's copy shares it), the sizes,
        # the cap and the driver; a broken program neither reads nor writes it
        store = BakeCache()
        key = cache_key("ground-noise", {"size": size, "cube": n, "cap_tan": GROUND_CAP_TAN},
                        repr([(f.name, s and s[1]) for f, s in sorted(prog.stamps.items())]),
                        {"driver": driver(ctx)})
        file = store.path_for("ground-noise", size, key)
        found = None if prog.errors else store.load(file, key, "ground-noise",
                                                    (size * size + 6 * n * n,), "float32")
        if found is not None and found.data is not None:  # the cap's texels, then each face's
            cap.write(found.data[:size * size])
            for face, texels in enumerate(np.split(found.data[size * size:], 6)):
                cube.write(face, texels)
            return cap, cube
        face_tex = self.gpu.texture(self.name, "ground noise face", (n, n), 1, dtype="f4")
        fbos = [self.gpu.framebuffer(self.name, "ground noise face", [face_tex]),
                self.gpu.framebuffer(self.name, "ground noise cap", [cap])]
        try:
            prog.bind_textures(self._gradient_textures())
            prog.set("uCapTan", GROUND_CAP_TAN)
            ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
            fbos[0].use()
            for face in range(6):
                prog.set("uFace", face)
                draw_fullscreen(prog)
                self.gpu.copy_to_cube_face(cube, face, 0, n)  # on the GPU, no readback
            fbos[1].use()
            prog.set("uFace", 6)
            draw_fullscreen(prog)
        finally:
            for fbo in fbos:
                self.gpu.free(fbo)
            self.gpu.free(face_tex)
        if not prog.errors:
            texels = [cap.read(), *(cube.read(face) for face in range(6))]
            store.store(file, key, "ground-noise",
                        np.concatenate([np.frombuffer(t, np.float32) for t in texels]),
                        {"renderer": ctx.info.get("GL_RENDERER")})
            store.keep_newest("ground-noise", KEPT_GROUND_NOISE)
        return cap, cube

    def _make_shadow_map(self, size: int):
        self._shadow_rendered = None
        return depth_target(self.gpu, self.name, "shadow map", size)

    def shadow_map(self):
        """Depth from the sun; re-rendered only when what it shows changed: the sun's direction,
        the map's size or the casters (their geometry follows the planet's radius, and the
        mountains' mesh the camera's distance, ``planet.mountain_lod_px``)."""
        size = self.params["planet.shadow_map_size"]
        tex, _ = self._shadow.get(size)
        key = (tuple(np.round(self.sun_dir, 9)), size, self.model().bottom_radius, self.grid)
        if key != self._shadow_rendered:
            self._render_shadow_map()
            self._shadow_rendered = key
            self._caster_box = caster_box(memoised(caster_points, key[2]), self.sun_dir, size)
        return tex

    def _render_shadow_map(self) -> None:
        ctx = self.gpu.ctx
        self._ensure_geometry()
        _, fbo = self._shadow.get(self.params["planet.shadow_map_size"])
        prog = self.program(SHADOW_DEPTH)
        prog.set("uLightViewProj", light_view_proj(self.sun_dir))
        # the shared shadow module's depth pass (app/render/shadow_maps.py)
        render_depth_pass(ctx, fbo, prog, lambda: self._draw_meshes(prog, depth_only=True))
        self.shadow_passes += 1

    def _make_gbuffer(self, size):
        colour = self.gpu.texture(self.name, "gbuffer colour", size, 4, dtype="f4")
        position = self.gpu.texture(self.name, "gbuffer position", size, 4, dtype="f4")
        depth = self.gpu.depth_texture(self.name, "gbuffer depth", size)
        fbo = self.gpu.framebuffer(self.name, "gbuffer", [colour, position], depth)
        return colour, position, depth, fbo

    def _gbuffer_for(self, size):
        return self._gbuffer.get(tuple(size))

    @property
    def gbuffer(self):
        """(colour, position, depth, framebuffer) of the last surfaces pass, or None."""
        return self._gbuffer.value

    def _shared(self, prog, frame) -> dict:
        """Uniforms both passes read; returns their shared textures by sampler name (the
        shadow map is rendered here first when it is out of date)."""
        prog.set_many(self.model_uniforms(frame))
        p = self.params
        prog.set_many({
            "uShadowFiltered": p["planet.shadow_filter"],
            "uShadowBias": p["planet.shadow_bias"],
            "uShadowsEnabled": self.uses_shadows(),
            "uLightViewProj": light_view_proj(self.sun_dir),
            "uKa": p["planet.ka"],
            "uKd": p["planet.kd"],
        })
        textures = {"uOpticalDepthLut": self.optical_depth_lut()}
        sky = p["planet.ambient"] == "sky"
        prog.set("uSkyAmbient", sky)
        if sky and "uSkyIrradiance" in prog.samplers():
            textures["uSkyIrradiance"] = self.sky_irradiance()
        # a program that reads no shadow (method 4's lookups) skips the map's bookkeeping
        if self.uses_shadows() and "uShadowMap" in prog.samplers():
            tex = self.shadow_map()
            configure_compare(tex, p["planet.shadow_compare"])
            textures["uShadowMap"] = tex
            box, depth = self._caster_box
            prog.set_many({"uShadowCasterBox": box, "uShadowCasterDepth": depth})
        return textures

    def surface_spec(self) -> ProgramSpec:
        return SURFACE_MANUAL if self.params["planet.shadow_compare"] == "manual" else SURFACE

    def composite_spec(self, part: int = 0, march: int = 1, march_pass: int = 0) -> ProgramSpec:
        p = self.params
        return composite_spec(self.method(), p["planet.shadow_compare"], p["planet.ground_noise"],
                              p["planet.ground_pass"], part, march, march_pass,
                              self.model().ozone > 0.0)

    def ground_spec(self) -> ProgramSpec:
        p = self.params
        return ground_spec(p["planet.shadow_compare"], p["planet.ground_noise"])

    def _surroundings(self, prog, frame, textures: dict) -> None:
        """Uniforms and textures of planet/surroundings.glsl (the analytic ground and the
        background) into ``prog`` and ``textures``."""
        p = self.params
        prog.set_many({
            "uStarIntensity": p["planet.star_intensity"],
            "uSunDisk": p["planet.sun_disk"], "uSunDiskCos": math.cos(math.radians(0.27)),
            "uSunDiskRadiance": 100.0 * self.model().sun_intensity,
            "uGroundShading": self.shading(),
        })
        textures["uStarTex"] = self._stars
        if p["planet.ground_noise"] == "baked":
            cap, cube = self.ground_noise()
            textures.update({"uGroundNoiseCap": cap, "uGroundNoise": cube})
            prog.set("uGroundCapTan", GROUND_CAP_TAN)
        else:
            textures.update(self._gradient_textures())

    def projection(self, frame) -> np.ndarray:
        altitude = max(frame.camera.position[1], 0.0)
        near = float(np.clip(altitude * 1e-3, 0.1, 2000.0))
        cam = frame.camera
        from pyrr import matrix44

        proj = matrix44.create_perspective_projection(cam.fov, frame.aspect, near, 5.0e7,
                                                      dtype=np.float64).T
        view = cam.view_matrix()
        view[:3, 3] = 0.0  # rotation only: positions are camera-relative
        return proj @ view

    def render_surfaces(self, frame, size) -> None:
        ctx = self.gpu.ctx
        self._ensure_geometry()
        colour, position, depth, fbo = self._gbuffer_for(size)
        fbo.use()
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        prog = self.program(self.surface_spec())
        textures = self._shared(prog, frame)
        p = self.params
        aniso = p["planet.anisotropy"] or (1 if self.gpu.caps.software else 8)
        for tex in self._textures:
            tex.anisotropy = float(aniso)
        prog.bind_textures({**textures, "uAlbedo": self._textures[0],
                            "uNormalMap": self._textures[1]})
        fbo.use()  # the shadow map may have been rendered just now
        prog.set_many({
            "uTextureTile": 40.0, "uShading": self.shading(),
            "uNormalMapping": p["planet.normal_mapping"], "uKs": p["planet.ks"],
            "uShininess": p["planet.shininess"],
            "uViewProj": self.projection(frame),
        })
        ctx.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        if p["planet.depth_prepass"]:
            # depth first (no fragment work), then shade only the front surface: '<=' passes the
            # same depths (the vertex stage is shared and its gl_Position invariant)
            depth_prog = self.program(SURFACE_DEPTH)
            depth_prog.set_many({"uCameraLocal": tuple(self.camera_local(frame).astype(np.float32)),
                                 "uViewProj": self.projection(frame)})
            self._draw_meshes(depth_prog, depth_only=True)
            ctx.depth_func = "<="
            fbo.depth_mask = False
        try:
            self._draw_meshes(prog)
        finally:
            ctx.depth_func = "<"
            fbo.depth_mask = True
            ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
        if p["planet.ground_pass"] == "gbuffer":
            self.render_ground(frame, size)

    def render_ground(self, frame, size) -> None:
        """The analytic Earth and the background into the G-buffer where no mesh is (the far
        plane, depth test '<=' against the meshes' depth, no depth writes)."""
        _, _, _, fbo = self._gbuffer_for(size)
        prog = self.program(self.ground_spec())
        textures = self._shared(prog, frame)
        self._surroundings(prog, frame, textures)
        prog.set_many(frame.camera_uniforms())
        prog.bind_textures(textures)
        fbo.use()  # the shadow map may have been rendered just now
        with depth_tested(self.gpu.ctx, fbo):
            draw_fullscreen(prog)

    def _composite_program(self, frame, target, spec: ProgramSpec, extra: dict | None = None):
        """``spec``'s program with every uniform and texture of the scattering pass bound
        (and the textures ``extra`` by sampler name)."""
        prog = self.program(spec)
        textures = {**self._shared(prog, frame), **(extra or {})}
        p = self.params
        colour, position, _, _ = self._gbuffer_for(target.size)
        textures.update({"uGColor": colour, "uGPosition": position})
        prog.set_many(frame.camera_uniforms())
        prog.set_many({
            "uUniverseRadius": p["planet.universe_radius"],
            "uUniverseCenter": self.universe_centre(frame),
            "uDebugView": DEBUG_VIEWS.index(p["planet.debug_view"]),
            "uSteps": p["planet.n_steps"], "uInnerSteps": p["planet.inner_steps"],
            "uThesisPcRule": self.pc_rule() == "thesis",
        })
        if p["planet.ground_pass"] == "scattering":
            self._surroundings(prog, frame, textures)
        if self.method() == "hillaire":
            luts = self.hillaire()
            textures.update(luts.textures())
            prog.set_many(luts.lookup_uniforms())
        prog.bind_textures(textures)
        return prog

    def march_scale(self, target) -> int:
        """Full-resolution pixels per side of one marched ray of methods 1–3 on ``target``
        (``planet.march_scale``; 1 on a multisampled target or one the G-buffer does not
        match, whose pixels the G-buffer cannot stand in for)."""
        colour = self._gbuffer.value[0] if self._gbuffer.value is not None else None
        if (self.method() == "hillaire" or bool(getattr(target, "samples", False))
                or colour is None
                or tuple(colour.size) != tuple(target.size)):
            return 1
        choice = self.params["planet.march_scale"]
        if choice == "auto":
            choice = "quarter" if self.gpu.caps.software else "half"
        return MARCH_SCALES[choice]

    def _make_march_grid(self, key):
        """(in-scattering, transmittance, framebuffer, mask depth) of the reduced-resolution
        march: RGBA32F, nearest, ceil(size / scale) per side, and a full-size depth texture that
        marks the pixels the upsampling could not fill."""
        (w, h), scale = key
        size = ((w + scale - 1) // scale, (h + scale - 1) // scale)
        nearest = (moderngl.NEAREST, moderngl.NEAREST)
        inscatter = self.gpu.texture(self.name, "march grid in-scattering", size, 4, dtype="f4",
                                     filter=nearest)
        transmittance = self.gpu.texture(self.name, "march grid transmittance", size, 4,
                                         dtype="f4", filter=nearest)
        fbo = self.gpu.framebuffer(self.name, "march grid", [inscatter, transmittance])
        mask = self.gpu.depth_texture(self.name, "march mask", (w, h))
        return inscatter, transmittance, fbo, mask

    def render_reduced(self, frame, target, scale: int) -> None:
        """Methods 1–3 at ``scale``: the method's march for one pixel of every ``scale``²
        block into the grid (MARCH_PASS 1); every pixel composited with its in-scattering and
        transmittance interpolated from the 4 grid points around it where they saw its surface
        and change slowly (MARCH_PASS 2), which marks the others in a depth mask; then those
        alone march their own rays (MARCH_PASS 3: the depth test rejects the rest before they
        are shaded — a march compiled into the upsampling would cost every pixel its loops'
        masked passes on a software rasteriser)."""
        ctx = self.gpu.ctx
        w, h = (int(v) for v in target.size)
        inscatter, transmittance, fbo, mask = self._march_grid.get(((w, h), scale))
        grid = {"uAmortiseBlock": scale, "uAmortiseShift": scale.bit_length() - 1,
                "uAmortiseSub": (0, 0), "uAmortiseFullSize": (float(w), float(h))}
        ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
        prog = self._composite_program(frame, target, self.composite_spec(march_pass=1))
        prog.set_many(grid)
        fbo.use()  # the shadow map may have been rendered just now
        draw_fullscreen(prog)
        prog = self._composite_program(frame, target, self.composite_spec(march_pass=2),
                                       {"uMarchInscatter": inscatter,
                                        "uMarchTransmittance": transmittance})
        prog.set_many({**grid, "uMarchContrast": self.params["planet.march_contrast"]})
        out = ctx.framebuffer(color_attachments=[target.color], depth_attachment=mask)
        try:
            out.use()
            ctx.enable(moderngl.DEPTH_TEST)
            ctx.depth_func = "1"  # every pixel writes its mark
            draw_fullscreen(prog)
            # bound after the upsampling's draw: texture units are shared between programs
            march = self._composite_program(frame, target, self.composite_spec(march_pass=3))
            out.use()
            out.depth_mask = False
            ctx.depth_func = "<="  # the far plane passes only where the mark is 1
            draw_fullscreen(march)
        finally:
            ctx.depth_func = "<"
            ctx.disable(moderngl.DEPTH_TEST)
            out.depth_mask = True
            target.use()
            out.release()

    def marched_alone(self) -> np.ndarray | None:
        """(h, w) bool, row 0 at the top: the pixels of the last scattering pass of methods 1–3
        at a reduced march scale that marched their own ray (a silhouette, a fast change); None
        when that pass marched every pixel."""
        if self.last_march_scale == 1 or self._march_grid.value is None:
            return None
        mask = self._march_grid.value[3]
        w, h = mask.size
        return np.frombuffer(mask.read(), dtype=np.float32).reshape(h, w)[::-1] > 0.5

    def render_composite(self, frame, target) -> None:
        if self.method() == "hillaire":
            self.render_hillaire(frame, target)
            return
        scale = self.last_march_scale = self.march_scale(target)
        if scale > 1:
            self.render_reduced(frame, target, scale)
            return
        prog = self._composite_program(frame, target, self.composite_spec())
        target.use()
        self.gpu.ctx.disable(moderngl.DEPTH_TEST)
        draw_fullscreen(prog)

    def update_hillaire(self, frame) -> None:
        """Method 4's LUTs for this frame: each rebuilt only when what it depends on changed
        (:meth:`hillaire.HillaireLuts.update`)."""
        self.hillaire().update(self.model_uniforms(frame), frame.camera_uniforms())

    def far_meshes(self, frame) -> bool:
        """Whether a mesh may lie past 90 % of the aerial-perspective volume's range (the far
        corner of the meshes' bounding box from the camera), where the lookup hands over to the
        per-pixel march."""
        lo, hi = memoised(caster_bounds, self.model().bottom_radius)
        corner = np.maximum(np.abs(lo - self.camera_local(frame)),
                            np.abs(hi - self.camera_local(frame)))
        return float(np.linalg.norm(corner)) > 0.9 * float(self.params["hillaire.ap_range"])

    def mesh_rect(self, frame, size) -> tuple[int, int, int, int] | None:
        """The pixel rectangle (x, y, width, height) of a ``size`` image that holds every mesh
        pixel: the screen bounds of the projected corners of the boxes of :func:`mesh_boxes`
        (chunks of the mountains, the city's boxes) in front of the camera, a pixel wider each
        side, clamped to the image (width or height 0: no mesh on screen); None when a box
        reaches behind the camera's near plane (the whole image may hold meshes)."""
        radius = self.model().bottom_radius
        view_proj = self.projection(frame)
        key = (radius, tuple(self.camera_local(frame)), view_proj.tobytes(), tuple(size))
        if self._rect is not None and self._rect[0] == key:
            return self._rect[1]
        corners = memoised(mesh_box_corners, radius)                  # (N, 8, 3)
        m = view_proj[:, :3].T
        clip = (corners.reshape(-1, 3) - self.camera_local(frame)) @ m + view_proj[:, 3]
        clip = clip.reshape(-1, 8, 4)
        rect = self._screen_rect(clip, size)
        self._rect = (key, rect)
        return rect

    @staticmethod
    def _screen_rect(clip: np.ndarray, size) -> tuple[int, int, int, int] | None:
        """:meth:`mesh_rect` from the boxes' corners in clip space, (N, 8, 4)."""
        front = clip[..., 3] > 1.0e-3
        behind = ~front.any(axis=1)            # wholly behind the camera: not on screen
        if not np.all(front.all(axis=1) | behind):
            return None
        clip = clip[~behind].reshape(-1, 4)
        w, h = (int(v) for v in size)
        if not len(clip):
            return 0, 0, 0, 0
        px = (clip[:, :2] / clip[:, 3:4] * 0.5 + 0.5) * (w, h)
        x0, y0 = (int(np.clip(np.floor(v) - 1, 0, n)) for v, n in zip(px.min(axis=0), (w, h)))
        x1, y1 = (int(np.clip(np.ceil(v) + 1, 0, n)) for v, n in zip(px.max(axis=0), (w, h)))
        return x0, y0, max(x1 - x0, 0), max(y1 - y0, 0)

    def render_hillaire(self, frame, target) -> None:
        """Method 4's per-pixel pass (Hillaire 2020 §5.3–5.4): lookups only. Pixels no mesh covers
        read the sky-view LUT and the meshes the volume, each in a draw of its own on the far
        plane against the G-buffer's depth (the depth test picks the pixels before they are
        shaded); in the band above the atmosphere, from space, with a mesh past the volume's
        range, or on a target whose depth the G-buffer's cannot stand in for, one draw over
        every pixel with the per-pixel march compiled in."""
        self.update_hillaire(frame)  # nothing is rebuilt when the LUT pass did it this frame
        luts = self.hillaire()
        ctx = self.gpu.ctx
        _, _, depth, _ = self._gbuffer_for(target.size)
        march = luts.march_mode(self.far_meshes(frame))
        if march or target.samples or tuple(target.size) != tuple(depth.size):
            prog = self._composite_program(frame, target, self.composite_spec(0, max(march, 1)))
            target.use()
            ctx.disable(moderngl.DEPTH_TEST)
            draw_fullscreen(prog)
            return
        # the target's colour with the G-buffer's depth: no depth writes, only the tests
        fbo = ctx.framebuffer(color_attachments=[target.color], depth_attachment=depth)
        try:
            fbo.use()
            fbo.depth_mask = False
            ctx.enable(moderngl.DEPTH_TEST)
            rect = self.mesh_rect(frame, target.size)
            for part, test in ((1, "<="), (2, ">")):
                if part == 2 and rect is not None and (rect[2] <= 0 or rect[3] <= 0):
                    continue  # no mesh on screen
                prog = self._composite_program(frame, target, self.composite_spec(part, 0))
                # the meshes' part only within their rectangle: outside it the depth test would
                # reject every pixel, but a software rasteriser pays for visiting them
                scissor: Any = rect if part == 2 else None
                fbo.scissor = scissor
                fbo.use()  # the shadow map or a LUT may have been rendered just now
                ctx.depth_func = test
                draw_fullscreen(prog)
        finally:
            ctx.depth_func = "<"
            ctx.disable(moderngl.DEPTH_TEST)
            target.use()
            fbo.release()

    def hillaire(self) -> "hillaire.HillaireLuts":
        if self._hillaire is None:
            self._hillaire = hillaire.HillaireLuts(self.gpu, self.name, self.params)
        return self._hillaire

    def shadow_stage(self, frame) -> None:
        """Bring the sun's shadow map up to date and publish it in ``frame.shadows``."""
        tex = self.shadow_map()
        frame.shadows["sun"] = ShadowMap("sun", "directional", tex, light_view_proj(self.sun_dir),
                                         self.params["planet.shadow_bias"])

    def passes(self, frame, target) -> list[Pass]:
        out = []
        if self.uses_shadows():
            out.append(Pass("planet.shadow_map", lambda: self.shadow_stage(frame), Stage.SHADOW))
        out.append(Pass("planet.surfaces", lambda: self.render_surfaces(frame, target.size),
                        Stage.OPAQUE))
        if self.method() == "hillaire":
            out.append(Pass("planet.hillaire_luts", lambda: self.update_hillaire(frame),
                            Stage.FOG))
        out.append(Pass(f"planet.scattering[{self.method()}]",
                        lambda: self.render_composite(frame, target), Stage.FOG))
        return out

    def bench_passes(self, frame, target) -> list[Pass]:
        """The passes, with the shadow map and method 4's sky-view LUT and volume rebuilt every
        time (the frame rebuilds them only when the sun or the camera moves, as a moving camera
        does every frame), and ``reference.3d_lookup``: one trilinear read of a 3D texture per
        pixel, the yardstick of method 4's per-pixel pass."""
        out = self.passes(frame, target)
        for i, p in enumerate(out):
            if p.name == "planet.shadow_map":
                out[i] = Pass(p.name, self._render_shadow_map, Stage.SHADOW)
            elif p.name == "planet.hillaire_luts":
                out[i] = Pass(p.name, self._rebuild_hillaire(frame), Stage.FOG)
        out.append(Pass("reference.3d_lookup", lambda: self.render_lookup_reference(target),
                        Stage.POST))
        return out

    def _rebuild_hillaire(self, frame):
        def run():
            self.update_hillaire(frame)
            self.hillaire().rebuild_frame_luts()
        return run

    def render_lookup_reference(self, target) -> None:
        """``reference.3d_lookup``: planet/lookup_reference.frag over the whole target, reading
        a volume of the aerial perspective's size and format (RGBA32F, trilinear)."""
        if self._reference_volume is None:
            w, h, d = self.hillaire().sizes()["aerial_perspective"]
            data = np.random.default_rng(0).random((d, h, w, 4), dtype=np.float32)
            self._reference_volume = self.gpu.texture3d(
                self.name, "lookup reference volume", (w, h, d), 4, data=data.tobytes(),
                dtype="f4", repeat=False)
        prog = self.program(LOOKUP_REFERENCE)
        prog.bind_textures({"uVolume": self._reference_volume})
        target.use()
        self.gpu.ctx.disable(moderngl.DEPTH_TEST)
        draw_fullscreen(prog)

"""The village's grass (spec/003 §2.9): three methods behind one switch, ``grass.method`` (the
scene's G key cycles it), drawing the same number of blades, ``grass.blades``:

* ``geometry`` — the thesis's geometry-shader blades (§2.9 a, kept although the thesis
  rejected them): a pyramid per input triangle, the wind of spec/003 eq. 7.1, spec/003 eq. 7.2,
  spec/003 eq. 7.3 and spec/003 eq. 7.4. Its input is one small root triangle per blade, or
  (``grass.gs_input = grid``) the thesis's own failure: one blade per triangle of a grid mesh;
* ``billboard`` — the thesis's final grass (§2.9 b): crossed billboard units (spec/003 eq. 7.5
  to spec/003 eq. 7.12), the unit's wind (spec/003 eq. 7.13 to spec/003 eq. 7.17), alpha to
  coverage on a multisampled target and the alpha cutoff on a single-sample one;
  ⌈blades / 8⌉ units (each tuft is painted with 8 blades);
* ``instanced`` — beyond the thesis: instanced Bézier blades (Wohllaib 2021).

Culling and LOD (``grass.culling``): app/effects/grass/methods.py. What a blade is for each
method, and the units: app/sim/grass.py (its module docstring). The GrassGenerator's settings
and their defaults: docs/theory/003-toon-village.md (§2.9). Two defaults are ours, said in their
docs: three planes (the document's Fig. 104b; the repository's 1) and Scale 0.25 (0.5 m tufts).
Fig. 103's three unlabeled values (0.629, 0.461, 0.577) cannot be attributed to sliders and are
not used.

Placement: rejection sampling of ``terrain.grass_density`` over ``terrain.bounds`` with
``grass.seed``, the roots on ``terrain.height``; rebuilt only when the terrain's ``revision``,
the count or the seed change (each method's buffers when their own settings change too).

Slots: ``wind`` (else ``grass.wind_direction`` and ``grass.wind_intensity``), ``main_light``
and its ``ambient`` (without a sky, a fixed sun), the sun's map from ``shadows``
(``bind_published``; the grass casts none) and ``fog``. It draws in the opaque stage, after
the village, depth-tested and depth-writing.
"""

from __future__ import annotations

import dataclasses
import math

import moderngl
import numpy as np

from ...frame import Stage
from ...gpu.cache import MEMO, memoised
from ...gpu.programs import ProgramSpec
from ...params import Inspector, Param
from ...render.shadow_maps import bind_published, published_defines, receiver_variants
from ...sim import grass as gs
from ...sim.fog import fog_uniforms
from ..base import Effect, Pass
from .methods import (
    BILLBOARD,
    BILLBOARD_DEPTH,
    BILLBOARD_EQUAL,
    GS_PROGRAMS,
    INSTANCED,
    SHADED,
    CrossedBillboards,
    Cull,
    GeometryBlades,
    InstancedBlades,
    gs_program,
)

#: the light when no sky fills ``main_light``: toward the light, radiance, ambient
FALLBACK_LIGHT = ((0.4, 0.8, 0.3), (2.5, 2.4, 2.2), (0.25, 0.3, 0.38))
#: the repository's floor of (f + (1 − f)·saturate(n·l)) per method (GeometryGrass 0.5,
#: Grass_CrossBillboard 0.7; the instanced blades take the billboards')
REPOSITORY_FLOOR = {"geometry": 0.5, "billboard": 0.7, "instanced": 0.7}
LIGHTING = ("document", "repository")
GS_INPUTS = ("scattered", "grid")
MAX_BLADES = 2_000_000


class Grass(Effect):
    name = "grass"
    title = "Grass"
    spec = "spec/003"
    programs = (*GS_PROGRAMS, BILLBOARD, BILLBOARD_DEPTH, BILLBOARD_EQUAL, INSTANCED,
                *(v for spec in SHADED for v in receiver_variants(spec)))
    stages = (Stage.OPAQUE,)
    consumes = {"terrain": "required", "wind": "optional", "main_light": "optional",
                "shadows": "optional", "fog": "optional"}

    @classmethod
    def context_paths(cls, caps, params) -> dict[str, str]:
        how = ("one indirect draw per LOD" if caps.version_code >= 430 else
               "one instanced draw per run of visible tiles (no base instance before GL 4.2)")
        return {"instanced grass culling": how}

    @classmethod
    def python_params(cls) -> list[Param]:
        s, a, b = "spec/003 §2.9", "spec/003 §2.9 a", "spec/003 §2.9 b"
        return [
            Param("grass.method", "billboard", doc="geometry: the thesis's geometry-shader "
                  "pyramids (rejected by it); billboard: its final crossed billboards; "
                  "instanced: instanced Bézier blades (beyond the thesis)", kind="choice",
                  choices=gs.METHODS, section=s),
            Param("grass.blades", 40_000, 0, MAX_BLADES, "blades over the island, the same for "
                  "every method (the GrassGenerator's Density: blades per m² = this ÷ the "
                  "meadow's area); a billboard unit shows 8", kind="int", step=1000, section=s),
            Param("grass.seed", 7, 0, 1_000_000, "the placement's random seed", kind="int",
                  section=s),
            Param("grass.wind_direction", 90.0, 0.0, 360.0, "Wind Direction when no wind "
                  "effect fills the wind slot: the compass direction it blows toward (90 = +x, "
                  "the thesis's (1, 0, 0))", step=1.0, unit="°", section=s),
            Param("grass.wind_intensity", 0.5, 0.0, 1.0, "Wind Intensity w_i when no wind "
                  "effect fills the wind slot (the repository's default 0.5; from the slot: "
                  "min(speed / 20 m/s, 1))", step=0.01, section=s),
            Param("grass.wellness", 1.0, 0.0, 1.0, "Wellness: the chance of green blades "
                  "(smoothstep(wellness)) against brown ones, 0.1 of yellow (GrassGenerator)",
                  step=0.01, section=b),
            Param("grass.variety", 1.0, 0.0, 1.0, "Variety: the chances of the three tufts "
                  "(GrassGenerator's 0.5 + 0.5·variety for the first)", step=0.01, section=b),
            Param("grass.lighting", "document", doc="document: diffuse only, Lambert plus the "
                  "sky's ambient; repository: _LightColor0·(f + (1 − f)·saturate(n·l)), f 0.5 "
                  "for the pyramids and 0.7 for the billboards", kind="choice",
                  choices=LIGHTING, section=s),
            Param("grass.gs_sections", 3, 1, 4, "Sections S of each pyramid (Fig. 93b shows 3; "
                  "the repository's default is 2): 6(S − 1) + 3 triangles per blade",
                  kind="int", section=a),
            Param("grass.gs_height", gs.GS_HEIGHT, 0.0, 1.0, "Height of each pyramid (Fig. 93: "
                  "4.87 Unity units at 0.1 m per unit; the repository's range 0–10 units)",
                  step=0.001, unit="m", section=a),
            Param("grass.gs_input", "scattered", doc="scattered: one small root triangle per "
                  "blade at the jittered roots; grid: one blade per triangle of a regular grid "
                  "mesh over the meadow (the thesis's own failure: regular, mesh-dependent)",
                  kind="choice", choices=GS_INPUTS, section=a),
            Param("grass.gs_shrink", True, doc="shrink each base halfway to its centroid first "
                  "(the repository; the document does not)", kind="bool", section=a),
            Param("grass.gs_repository_height", False, doc="the repository's height: Height "
                  "+ ω Unity units (a per-blade variation from spec/003 eq. 7.2)", kind="bool",
                  section=a),
            Param("grass.bb_planes", 3, 1, 4, "planes crossed in each unit, 180°/n apart "
                  "(Fig. 104b; the thesis finds 1–3 enough; the repository's default 1)",
                  kind="int", section=b),
            Param("grass.bb_scale", 0.25, 0.0, 1.0, "Scale (_Scale): the quad's side is "
                  "(0.25 + Scale) m (the repository's (0.25 + _Scale)·10 units at 0.1 m per "
                  "unit; its default 0 gives 0.25 m tufts)", step=0.01, section=b),
            Param("grass.billboard_y", "average", doc="Billboard Y: the plane's y vector — "
                  "camera (its up: tufts turn about the view seen from above), world (0, 1, 0), "
                  "or average, normalize(u + (0, 1, 0)) (Fig. 98; the repository's default)",
                  kind="choice", choices=gs.BILLBOARD_Y, section=b),
            Param("grass.bb_angles", "document", doc="the planes' angles: document θ_k = "
                  "k·180°/n (plane 0 faces the camera); repository −90° + Δ/2 + k·Δ (−60°, 0°, "
                  "60° for three)", kind="choice", choices=gs.ANGLE_LAYOUTS, section=b),
            Param("grass.blade_height", 0.38, 0.02, 2.0, "instanced blades: mean height (each "
                  "0.6–1.25 of it)", step=0.01, unit="m", section=s),
            Param("grass.blade_width", 0.035, 0.002, 0.1, "instanced blades: mean width at the "
                  "root", step=0.001, unit="m", section=s),
            Param("grass.segments", 5, 1, 16, "instanced blades: segments of the Bézier strip "
                  "near the camera (2·segments − 1 triangles)", kind="int", section=s),
            Param("grass.lod_segments", 2, 1, 16, "instanced blades: segments beyond the LOD "
                  "distance", kind="int", section=s),
            Param("grass.lod_sections", 1, 1, 4, "geometry-shader blades: sections of each "
                  "pyramid beyond the LOD distance (at most grass.gs_sections)", kind="int",
                  section=a),
            Param("grass.lod_planes", 2, 1, 4, "crossed billboards: planes of each unit beyond "
                  "the LOD distance (at most grass.bb_planes; the first faces the camera)",
                  kind="int", section=b),
            Param("grass.lod_distance", 15.0, 0.0, 500.0, "every method: tiles nearer than "
                  "this get the full blade (sections, planes, segments), farther ones the LOD's",
                  step=0.5, unit="m", section=s),
            Param("grass.draw_distance", 90.0, 1.0, 2000.0, "every method: tiles farther than "
                  "this are culled (blades fade over its last 20 %)", step=1.0, unit="m",
                  section=s),
            Param("grass.depth_prepass", True, doc="crossed billboards on a single-sample "
                  "target: the alpha test alone writes the tufts' depth first, then they are "
                  "shaded with the depth test \"equal\" and no discard — each visible texel "
                  "once, not every overlapping tuft's (off: the thesis's one pass; with alpha "
                  "to coverage always one pass)", kind="bool", section=b),
            Param("grass.culling", True, doc="every method: cull tiles of 8 m on the CPU "
                  "(frustum and draw distance) and draw the LOD beyond the LOD distance, the "
                  "visible blades at equal counts (off: every blade at full detail, the "
                  "thesis's way)", kind="bool", section=s),
        ]

    #: what each method teaches (the panel shows the current one above the parameters)
    lesson_param = "grass.method"
    LESSONS = {
        "geometry": "Geometry-shader grass (spec/003 §2.9(a)): every input triangle grows a "
                    "pyramid blade of grass.gs_sections sections bent by the wind; the "
                    "thesis rejected it: the blades follow the mesh (regular, "
                    "mesh-dependent) and every section adds triangles.",
        "billboard": "Crossed billboards (spec/003 §2.9(b), the thesis's final grass): each "
                     "unit is 1–3 textured planes turned toward the camera about the Billboard "
                     "Y axis and cut out by alpha to coverage: a few triangles per tuft, not "
                     "per blade, at the price of flat tufts seen from above.",
        "instanced": "Instanced Bézier blades (beyond the thesis, which ends at spec/003 "
                     "§2.9(b)): one curved blade mesh drawn per instance and culled per tile, "
                     "so every blade is real geometry, its cost set by the count, not a mesh.",
    }

    def __init__(self, gpu, params, owner: str | None = None):
        super().__init__(gpu, params)
        #: the name the GPU resources are recorded under (a bench may run a second instance)
        self.owner = owner or self.name
        self._roots = self.keyed(self._place)
        self._placing: tuple = ()
        self.geometry = GeometryBlades(gpu, self.owner, self.keyed)
        self.billboard = CrossedBillboards(gpu, self.owner, self.keyed)
        self.instanced = InstancedBlades(gpu, self.owner, self.keyed)
        self._atlas = None
        self.time = 0.0
        self.wind = gs.grass_wind(None, 90.0, 0.0)
        self.last: dict = {}
        self._meadow: tuple | None = None  # (terrain key, area m²)
        self._terrain = None  # the last terrain drawn on (the panel's density)
        self._bound: dict[int, dict] = {}  # each program's textures, by id (bind)

    def program(self, spec):
        prog = self.gpu.program(self.owner, spec)
        if self._on_reload not in prog.on_reload:
            prog.on_reload.append(self._on_reload)
        return prog

    def _terrain_key(self, terrain) -> tuple:
        return (id(terrain), int(getattr(terrain, "revision", 0)))

    def _place(self, key) -> np.ndarray:
        terrain, blades, seed = self._placing
        return gs.sample_roots(terrain, blades, seed)

    def roots(self, terrain) -> np.ndarray:
        """The placed roots (blades, 3), rebuilt when the terrain, the count or the seed
        change."""
        blades, seed = int(self.params["grass.blades"]), int(self.params["grass.seed"])
        shared = getattr(terrain, "memo_key", None)
        if shared is not None:  # a terrain every session shares: placed once per process
            return MEMO.get((gs.sample_roots, shared, blades, seed),
                            lambda: gs.sample_roots(terrain, blades, seed))
        self._placing = (terrain, blades, seed)
        return self._roots.get((*self._terrain_key(terrain), blades, seed))

    def meadow_area(self, terrain) -> float:
        """The meadow's area [m²]: ∫ grass_density over the meadow's cells."""
        key = self._terrain_key(terrain)
        if self._meadow is None or self._meadow[0] != key:
            shared = getattr(terrain, "memo_key", None)
            if shared is not None:
                area = MEMO.get((gs.meadow_cells, "area", shared),
                                lambda: self._meadow_area(terrain))
            else:
                area = self._meadow_area(terrain)
            self._meadow = (key, area)
        return self._meadow[1]

    @staticmethod
    def _meadow_area(terrain) -> float:
        corners, cell = gs.meadow_cells(terrain)
        if not len(corners):
            return 0.0
        c = corners + cell / 2.0
        return float(np.sum(terrain.grass_density(c[:, 0], c[:, 1]))) * cell * cell

    def update(self, frame, dt: float) -> None:
        self.time = float(frame.time)
        p = self.params
        self.wind = gs.grass_wind(frame.wind, p["grass.wind_direction"],
                                  p["grass.wind_intensity"])

    def light(self, frame) -> tuple:
        """(toward the light, radiance, ambient) of the main light, or the fallback sun."""
        light = frame.main_light
        if light is None:
            d = np.asarray(FALLBACK_LIGHT[0]) / np.linalg.norm(FALLBACK_LIGHT[0])
            return tuple(d), FALLBACK_LIGHT[1], FALLBACK_LIGHT[2]
        ambient = light.ambient if light.ambient is not None else (0.05, 0.05, 0.06)
        return (tuple(float(c) for c in light.direction),
                tuple(float(c) for c in light.radiance), tuple(float(c) for c in ambient))

    def atlas(self):
        """The three generated tufts side by side, mipmapped."""
        if self._atlas is None:
            data = memoised(gs.tuft_atlas)
            h, w = data.shape[:2]
            tex = self.gpu.texture(self.owner, "tufts", (w, h), 4, data=data.tobytes(),
                                   dtype="f4")
            tex.build_mipmaps()
            tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
            tex.repeat_x = tex.repeat_y = False
            self._atlas = tex
        return self._atlas

    def _uniforms(self, prog, frame, method: str) -> None:
        p = self.params
        cam = frame.camera
        toward, radiance, ambient = self.light(frame)
        wind = self.wind
        ripe = gs.ripeness_weights(p["grass.wellness"])
        self.apply_params(prog)
        prog.set_many({
            "uViewProj": cam.projection_matrix(frame.aspect) @ cam.view_matrix(),
            "uCameraPos": tuple(cam.position), "uCameraForward": tuple(cam.forward()),
            "uLightDir": toward, "uLightRadiance": radiance, "uAmbient": ambient,
            "uLightingModel": LIGHTING.index(p["grass.lighting"]),
            "uRepositoryFloor": REPOSITORY_FLOOR[method],
            "uWindDir": wind.direction, "uWindIntensity": wind.intensity,
            "uWindVelocity": wind.velocity, "uTime": self.time,
            "uRipeness": (float(ripe[0]), float(ripe[0] + ripe[1]), 1.0),
            **fog_uniforms(frame.fog, cam.position, cam.near, cam.far),
        })
        r, u, _ = cam.basis()
        prog.set_many({"uCamRight": tuple(r), "uCamUp": tuple(u)})
        textures = bind_published(prog, frame.shadows)
        if method == "billboard":
            textures["uTufts"] = self.atlas()
        prog.bind_textures(textures)
        self._bound[id(prog)] = textures

    def bind(self, prog) -> None:
        """Bind ``prog``'s textures again (to the units its last uniforms gave them): a draw
        with two programs set up ahead (a depth pass, a LOD) binds each just before it draws,
        since the other's binding may have taken its units."""
        prog.bind_textures(self._bound.get(id(prog), {}))

    def draw(self, frame, target) -> None:
        terrain = frame.require("terrain", self.name)
        self._terrain = terrain
        p = self.params
        method = p["grass.method"]
        roots = self.roots(terrain)
        key = (*self._terrain_key(terrain), int(p["grass.blades"]), int(p["grass.seed"]))
        ctx = self.gpu.ctx
        target.use()
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.disable(moderngl.CULL_FACE)
        ctx.disable(moderngl.BLEND)
        seed = int(p["grass.seed"])
        blades = int(p["grass.blades"])
        cam = frame.camera
        cull = Cull(bool(p["grass.culling"]), cam.projection_matrix(frame.aspect)
                    @ cam.view_matrix(), tuple(cam.position), float(p["grass.lod_distance"]),
                    float(p["grass.draw_distance"]))
        if method == "geometry":
            sections = int(p["grass.gs_sections"])
            lods = {0: sections, 1: min(sections, int(p["grass.lod_sections"]))}
            progs = {lod: self._gs_program(frame, n, cull) for lod, n in lods.items()}
            height = float(p["grass.gs_height"])
            reach = round(2.0 * height + 0.3, 4)  # the tallest blade (+ω) and its bend
            mode = p["grass.gs_input"]
            if mode == "grid":
                def make():
                    return gs.grid_triangles(terrain, blades, seed), reach
            else:
                def make():
                    return gs.scatter_triangles(terrain, roots, seed), reach
            self.geometry.draw(progs, (*key, mode, reach), make, lods, cull, self.bind)
            self.last = dict(self.geometry.last, method=method)
        elif method == "billboard":
            two_pass = (bool(p["grass.depth_prepass"]) and getattr(target, "fbo", None)
                        is not None and not int(getattr(target, "samples", 0) or 0))
            progs = [self._billboard_program(frame, spec) for spec in
                     ((BILLBOARD_DEPTH, BILLBOARD_EQUAL) if two_pass else (BILLBOARD,))]
            for prog in progs:
                prog.set_many({"uFade": cull.enabled, "uDrawDistance": cull.draw_distance})
            planes = int(p["grass.bb_planes"])
            lods = {0: planes, 1: min(planes, int(p["grass.lod_planes"]))}
            variety, wellness = float(p["grass.variety"]), float(p["grass.wellness"])
            units = gs.units_for(len(roots))
            size = 0.25 + float(p["grass.bb_scale"])
            reach = round(2.0 * size + 0.1, 4)  # the quad above its root and its bend

            def make_units():
                return gs.make_units(roots[:units], seed, variety, wellness), reach

            def angles(n: int) -> None:
                a = gs.plane_angles(n, p["grass.bb_angles"])
                for prog in progs:
                    prog.set_many({"uAngleStart": float(a[0]), "uAngleStep": 180.0 / n})

            self.billboard.draw(progs, (*key, variety, wellness, reach), make_units, lods,
                                target, angles, cull, self.bind)
            self.last = dict(self.billboard.last, method=method)
        else:
            prog = self.program(self._receiver(frame, INSTANCED))
            self._uniforms(prog, frame, method)
            height = float(p["grass.blade_height"])
            prog.set_many({"uBladeHeight": height, "uBladeWidth": float(p["grass.blade_width"]),
                           "uDrawDistance": float(p["grass.draw_distance"])})
            reach = 1.25 * height + 0.1

            def make_roots():
                return roots, reach

            self.instanced.draw(prog, (*key, round(reach, 4)), make_roots,
                                int(p["grass.segments"]), int(p["grass.lod_segments"]), cull)
            self.last = dict(self.instanced.last, method=method)
        ctx.disable(moderngl.DEPTH_TEST)

    @staticmethod
    def _receiver(frame, spec: ProgramSpec) -> ProgramSpec:
        """``spec`` compiled for the shadow filter and taps the frame's maps were published
        with (``published_defines``): the filters not in use compiled out, the same image."""
        return dataclasses.replace(spec, defines=spec.defines + published_defines(frame.shadows))

    def _gs_program(self, frame, sections: int, cull: Cull):
        """The geometry-shader program of ``sections`` sections, its uniforms set."""
        p = self.params
        prog = self.program(self._receiver(frame, gs_program(sections)))
        self._uniforms(prog, frame, "geometry")
        prog.set_many({"uHeight": float(p["grass.gs_height"]),
                       "uShrinkBase": bool(p["grass.gs_shrink"]),
                       "uRepositoryHeight": bool(p["grass.gs_repository_height"]),
                       "uFade": cull.enabled, "uDrawDistance": cull.draw_distance})
        return prog

    def _billboard_program(self, frame, spec=BILLBOARD):
        p = self.params
        prog = self.program(self._receiver(frame, spec) if spec in SHADED else spec)
        self._uniforms(prog, frame, "billboard")
        planes = int(p["grass.bb_planes"])
        angles = gs.plane_angles(planes, p["grass.bb_angles"])
        prog.set_many({"uBillboardY": gs.BILLBOARD_Y.index(p["grass.billboard_y"]),
                       "uAngleStart": float(angles[0]), "uAngleStep": 180.0 / planes,
                       "uSize": 0.25 + float(p["grass.bb_scale"])})
        return prog

    def draw_units(self, frame, target, units: gs.Units) -> None:
        """Crossed-billboard ``units`` given explicitly, with the effect's billboard settings
        (the bench's side-view coverage of one unit or a row of them): drawn into ``target``
        like the billboard method, from a buffer made and freed here."""
        prog = self._billboard_program(frame)
        prog.set("uFade", False)
        planes = int(self.params["grass.bb_planes"])
        ctx = self.gpu.ctx
        target.use()
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.disable(moderngl.CULL_FACE)
        self.billboard.draw_once(prog, units, planes, target)
        ctx.disable(moderngl.DEPTH_TEST)

    def passes(self, frame, target) -> list[Pass]:
        return [Pass("grass", lambda: self.draw(frame, target), Stage.OPAQUE)]

    INSPECTOR = {
        "GrassGenerator": ["grass.blades", "grass.wellness", "grass.variety", "grass.bb_planes",
                           "grass.bb_scale", "grass.wind_direction", "grass.wind_intensity",
                           "grass.billboard_y"],
        "GeometryGrass": ["grass.gs_sections", "grass.gs_height", "grass.gs_input",
                          "grass.gs_shrink", "grass.gs_repository_height", "grass.blade_color"],
        "Grass-CrossBillboard": ["grass.cutoff", "grass.bb_angles", "grass.bb_bend",
                                 "grass.bb_steady", "grass.depth_prepass"],
        "Instanced blades": ["grass.blade_height", "grass.blade_width", "grass.segments",
                             "grass.lod_segments", "grass.gust", "grass.gust_scale",
                             "grass.translucency"],
        "Culling and LOD": ["grass.culling", "grass.lod_distance", "grass.draw_distance",
                            "grass.lod_sections", "grass.lod_planes", "grass.lod_segments"],
    }

    def panel_items(self) -> list:
        """The thesis's inspectors (the GrassGenerator, the two materials) and ours, with the
        generated tufts as a thumbnail once made."""
        popups = {t: [n for n in names if n in self.params] for t, names in self.INSPECTOR.items()}
        textures = {"tufts": self._atlas} if self._atlas is not None else {}
        return [Inspector("Grass (GrassGenerator and the grass materials)",
                          {t: n for t, n in popups.items() if n}, textures)]

    def panel_notes(self) -> list[str]:
        last = self.last
        if self._terrain is not None:
            self.meadow_area(self._terrain)
        if not last:
            return []
        w = self.wind
        lines = [f"{last['method']}: {last.get('blades', 0):,} blades drawn, "
                 f"{last.get('triangles', 0):,} triangles, {last.get('draws', 0)} draw(s)",
                 f"wind w_i {w.intensity:.2f} toward "
                 f"{math.degrees(math.atan2(w.direction[0], -w.direction[2])) % 360:.0f}° "
                 f"({w.speed:.1f} m/s)"]
        if self._meadow is not None and self._meadow[1] > 0:
            lines.append(f"density {int(self.params['grass.blades']) / self._meadow[1]:.1f} "
                         f"blades/m² over {self._meadow[1]:.0f} m² of meadow")
        if last.get("tiles") and self.params["grass.culling"]:
            lines.append(f"tiles culled {last['culled_tiles']} of {last['tiles']}")
        if last["method"] == "billboard":
            lines.append(f"{last.get('units', 0):,} units; "
                         + ("alpha to coverage" if last.get("alpha_to_coverage")
                            else "alpha cutoff (single-sample target)"))
        return lines

    def release(self) -> None:
        self.geometry.release()
        self.billboard.release()
        self.instanced.release()
        self._atlas = None
        self._meadow = None
        self._terrain = None
        for k in self._keyed:
            k.clear()
        self.gpu.release_owner(self.owner)

"""The sailing boat (spec/000 §1.3 FloatingObject, §1.4 NavigableObject and SailObject, §1.5 the
cloth shader, §4 items 7–8 the wake and the hull the waves went through).

* **update()** steps :class:`app.sim.boat.BoatSim` on the frame's ``water`` (required) and
  ``wind`` (optional: calm without it) — the captain's helm, throttle and sails are the
  parameters ``boat.helm``, ``boat.throttle`` and ``boat.sails`` — and fills ``wakes`` (the trail
  its stern leaves in world space) and ``dry_mask`` (made in the opaque pass). On the first frame
  (and after the clock jumps) the boat sails the last ``boat.spin_up`` seconds at once, so a
  single rendered frame shows it under way with its wake.
* **passes()**, opaque stage: the hull, deck, mast and boom (``boat/hull``: the main light plus
  the sky's reflection probe, which lights the boat as in the thesis), the mainsail, the jib
  and the masthead flag (``boat/cloth``: the thesis's cloth shader, the belly on the side the
  apparent wind fills), then the dry volume's front and back depths for the water.

Conventions (``app.sim.boat``): boat frame +y up, +z bow; headings are compass bearings.
"""

from __future__ import annotations

import math

import moderngl
import numpy as np

from ...frame import DryMask, Stage
from ...gpu.programs import ProgramSpec
from ...params import Param
from ...render.environment import flat_environment
from ...render.noise import GradientNoiseTextures
from ...sim import cloth, rigging
from ...sim.boat import METHODS, BoatSim
from ...sim.maths import compass_radians
from ..base import Effect, Pass
from . import details

HULL = ProgramSpec("boat/hull")
CLOTH = ProgramSpec("boat/cloth")
DRY = ProgramSpec("boat/dry_depth")

#: stations along the hull where the water's height against each side is sampled (the
#: waterline the shader wets and foams the hull at)
WATERLINE_STATIONS = 9


def _translate(v) -> np.ndarray:
    m = np.identity(4)
    m[:3, 3] = v
    return m


class Boat(Effect):
    name = "boat"
    title = "Sailing boat"
    spec = "spec/000"
    programs = (HULL, CLOTH, DRY)
    stages = (Stage.OPAQUE,)
    produces = frozenset({"wakes", "dry_mask"})
    consumes = {"water": "required", "wind": "optional", "environment": "optional",
                "main_light": "optional"}

    @classmethod
    def python_params(cls) -> list[Param]:
        s3, s4 = "spec/000 §1.3", "spec/000 §1.4"
        return [
            Param("boat.helm", 0.0, -1.0, 1.0, "Direction (rudder): +1 turns the bow to "
                  "starboard", step=0.01, section=s4),
            Param("boat.throttle", 0.0, -1.0, 1.0, "Throttle: the motor's push (forward force)",
                  step=0.01, section=s4),
            Param("boat.sails", 0.55, -1.0, 1.0, "Sails Direction: how far the sheet lets the "
                  "boom out (its size; the wind picks the side)", step=0.01, section=s4),
            Param("boat.buoyancy", "hydrostatic", doc="probes: the thesis's FloatingObject "
                  "(kinematic); probe_forces: force probes (Crest's BoatProbes); hydrostatic: "
                  "Kerner's pressure integration over the hull", kind="choice", choices=METHODS,
                  section=s3),
            Param("boat.probes", 4, 1, 32, "Floating Points: probe count of the probe methods",
                  kind="int", section=s3),
            Param("boat.displacement_stiffness", 6.0, 0.0, 100.0, "Displacement Stiffness: the "
                  "rate the floating object follows the water's displacement", step=0.1,
                  unit="1/s", section=s3),
            Param("boat.rotation_stiffness", 3.0, 0.0, 100.0, "Rotation Stiffness: the rate it "
                  "follows the water's normal", step=0.1, unit="1/s", section=s3),
            Param("boat.probe_distance", 1.0, 0.05, 10.0, "distance to the two extra surface "
                  "points of each floating point's normal (the thesis: one unit)", step=0.05,
                  unit="m", section=s3),
            Param("boat.mass", 2500.0, 300.0, 6000.0, "mass of the boat", step=10.0,
                  unit="kg"),
            Param("boat.hydrodynamics", True, doc="added mass and radiation damping of the hull "
                  "(a boundary-element solver's, tools/added_mass.py) in the force methods: "
                  "the water the hull moves makes it heave and pitch about 1.8× slower and "
                  "radiated waves damp it; off: the rigid body alone (before; the kinematic "
                  "floating points have no mass either way)", kind="bool",
                  section=s3),
            Param("boat.heading", 0.0, 0.0, 360.0, "heading the boat starts on (compass: 0 = "
                  "north, 90 = east)", step=1.0, unit="°"),
            Param("boat.navigation", "rudder", doc="thesis: NavigableObject's turn rate, the "
                  "boat turns standing still; rudder: a lift surface, no way no steering",
                  kind="choice", choices=("thesis", "rudder"), section=s4),
            Param("boat.sail_model", "lift", doc="thesis: SailObject's thrust, largest with the "
                  "sail across the wind; lift: lift and drag on the apparent wind (a no-go "
                  "zone upwind)", kind="choice", choices=("thesis", "lift"), section=s4),
            Param("boat.max_substep", 1.0 / 120.0, 1.0 / 480.0, 1.0 / 30.0, "longest step of "
                  "the rigid-body integrator (each frame is cut into equal substeps)",
                  step=0.001, unit="s"),
            Param("boat.spin_up", 25.0, 0.0, 120.0, "seconds sailed at once before the first "
                  "frame (a single frame then shows the boat under way and its wake)",
                  step=1.0, unit="s"),
            Param("boat.fittings", True, doc="draw the deck fittings (cabin, cockpit, rails, "
                  "hatches, winches: app/effects/boat/details.py) on the hull — visual only, the "
                  "physics floats the bare hull either way; off shows the bare hull's flush deck",
                  kind="bool", section=s3),
            Param("boat.wake", True, doc="leave a wake (foam in world space, a Kelvin wedge of "
                  "19.47°) — beyond the thesis, which left it out", kind="bool",
                  section="spec/000 §4"),
            *cloth.cloth_params("boat.sail_", cloth.SAIL_DEFAULTS),
            *cloth.cloth_params("boat.flag_", cloth.FLAG_DEFAULTS),
        ]

    #: what each buoyancy method teaches (boat.buoyancy)
    lesson_param = "boat.buoyancy"
    LESSONS = {
        "probes": "Floating points (spec/000 §1.3, the thesis's FloatingObject): the boat is "
                  "placed at the mean water height and normal of a few probes, kinematically: "
                  "it follows the surface without mass or inertia.",
        "probe_forces": "Force probes (beyond the thesis; Crest's BoatProbes): each probe "
                        "pushes up by its depth under the water, so the hull has mass and "
                        "inertia; the thesis's probes only place it (spec/000 §1.3).",
        "hydrostatic": "Hydrostatic pressure (beyond the thesis; Kerner): buoyancy integrated "
                       "over every submerged hull triangle, so heel and pitch come from the "
                       "hull's shape; the thesis averages a few probe heights (spec/000 §1.3).",
    }

    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        self.sim: BoatSim | None = None
        self._sim_key = None
        self._last_time: float | None = None
        self._meshes: dict | None = None
        self._dry: dict = {}
        self._noise = GradientNoiseTextures(gpu, self.name)
        self._flat_env = None
        self.sail_state = None
        self.wind = np.zeros(2)
        self.waterline: np.ndarray | None = None
        self._deck: details.Deck | None = None

    def _ensure_sim(self) -> BoatSim:
        p = self.params
        key = (p["boat.mass"], p["boat.navigation"], p["boat.sail_model"], p["boat.max_substep"])
        if self.sim is None or key != self._sim_key:
            self.sim = BoatSim(mass=key[0], method=p["boat.buoyancy"], probes=p["boat.probes"],
                               heading_deg=p["boat.heading"], max_substep=key[3],
                               navigation_mode=key[1], sail_mode=key[2])
            self._sim_key = key
            self._last_time = None
            self._free_dry()  # its volume is the new hull's
        return self.sim

    def _free_dry(self) -> None:
        """Free the dry mask's targets and volume (remade at the next draw)."""
        for k in ("front", "back", "vbo"):
            if self._dry.get(k) is not None:
                self.gpu.free(self._dry[k])
        self._dry = {}

    def update(self, frame, dt: float) -> None:
        p = self.params
        sim = self._ensure_sim()
        sim.method = p["boat.buoyancy"]
        sim.probes = p["boat.probes"]
        sim.hydrodynamics = p["boat.hydrodynamics"]
        sim.set_thesis_parameters(p["boat.displacement_stiffness"], p["boat.rotation_stiffness"],
                                  p["boat.probe_distance"])
        sim.controls.helm, sim.controls.throttle, sim.controls.sails = (
            p["boat.helm"], p["boat.throttle"], p["boat.sails"])
        water = frame.require("water", by=self.name)
        self.wind = np.zeros(2) if frame.wind is None else np.asarray(frame.wind, float)
        jumped = self._last_time is None or frame.time < self._last_time
        if jumped:
            sim.reset(math.radians(p["boat.heading"]))
            if p["boat.spin_up"] > 0:
                sim.spin_up(water, self.wind, frame.time, p["boat.spin_up"])
        elif dt > 0:
            sim.step(min(dt, 0.25), water, self.wind, frame.time)
        self._last_time = frame.time
        self.sail_state = sim.sail_state(self.wind)
        self.waterline = self._waterline(water)
        if p["boat.wake"]:
            frame.wakes = [*frame.wakes, sim.wake]

    def _waterline(self, water) -> np.ndarray:
        """(2, WATERLINE_STATIONS) boat-frame heights [m above the keel] where the water meets
        the port (row 0) and starboard (row 1) sides at the stations along the hull — what the
        hull shader wets and foams the topsides at (visual only; the buoyancy has its own
        sampling). The water is queried under each side's waterline point."""
        sim = self.sim
        assert sim is not None
        if self._deck is None:
            self._deck = details.Deck(sim.mesh)
        zs = np.linspace(self._deck.stern + 0.1, self._deck.stem - 0.1, WATERLINE_STATIONS)
        half = 0.85 * self._deck.breadth(zs)
        r, pos = sim.body.rotation, np.asarray(sim.body.position, float)
        out = np.zeros((2, len(zs)))
        for row, side in enumerate((-1.0, 1.0)):
            local = np.stack([side * half, np.full_like(zs, sim.draft), zs], axis=-1)
            world = local @ r.T + pos
            h = np.asarray(water.height(world[:, 0], world[:, 2]), float)
            ry = r[1]
            out[row] = (h - pos[1] - ry[0] * local[:, 0] - ry[2] * zs) / max(ry[1], 0.2)
        return np.where(np.isfinite(out), out, sim.draft)

    def _mesh_buffers(self) -> dict:
        if self._meshes is not None:
            return self._meshes
        gpu = self.gpu
        sim = self.sim
        assert sim is not None
        mesh = sim.mesh
        # the buoyancy's hull, flat-shaded, with the deck fittings standing on it (visual only:
        # the hull the physics integrates is unchanged), and the mast, in the boat frame; the
        # boom in its own frame (placed by boom_transform)
        fittings = bool(self.params["boat.fittings"])
        hull = np.vstack([details.hull_rows(mesh)]
                         + ([details.deck_fittings(mesh)] if fittings else [])
                         + [details.spar_rows(rigging.mast())])
        boom = details.spar_rows(rigging.boom())
        out = {"hull": (gpu.buffer(self.name, "hull", hull.tobytes()), len(hull)),
               "boom": (gpu.buffer(self.name, "boom", boom.tobytes()), len(boom)),
               "dry_ibo": gpu.buffer(self.name, "dry indices",
                                     mesh.triangles.astype("u4").tobytes())}
        for name, cm in (("main", rigging.mainsail()), ("jib", rigging.jib()),
                         ("flag", rigging.flag())):
            out[name] = (cm, gpu.buffer(self.name, f"{name} vertices", cm.vertex_data()),
                         gpu.buffer(self.name, f"{name} indices", cm.index_data()))
        holes_s, holes_f = self.params["boat.sail_holes"], self.params["boat.flag_holes"]
        for name, alpha, pattern in (
                ("sail", rigging.sail_alpha(holes=holes_s), rigging.sail_pattern()),
                ("flag", rigging.flag_alpha(holes=holes_f), rigging.flag_pattern())):
            h, w = alpha.shape
            out[f"{name}_alpha"] = gpu.texture(self.name, f"{name} alpha", (w, h), 1,
                                               data=alpha.tobytes(), dtype="f1")
            out[f"{name}_pattern"] = gpu.texture(self.name, f"{name} pattern", (w, h), 1,
                                                 data=pattern.tobytes(), dtype="f1")
        out["holes"] = (holes_s, holes_f)
        out["fittings"] = fittings
        self._meshes = out
        return out

    def _environment(self, frame):
        if frame.environment is not None:
            return frame.environment.cubemap(sun=False), True
        if self._flat_env is None:
            self._flat_env = flat_environment(self.gpu, self.name)
        return self._flat_env, False

    def passes(self, frame, target) -> list[Pass]:
        return [Pass("boat", lambda: self.draw(frame, target), Stage.OPAQUE)]

    def draw(self, frame, target) -> None:
        sim = self.sim
        if sim is None:
            return
        meshes = self._mesh_buffers()
        if meshes["holes"] != (self.params["boat.sail_holes"], self.params["boat.flag_holes"]) \
                or meshes["fittings"] != bool(self.params["boat.fittings"]):
            self.release_meshes()
            meshes = self._mesh_buffers()
        ctx = self.gpu.ctx
        vp = frame.camera.view_projection_relative(frame.aspect)  # as the water's
        model_rel = _translate(-np.asarray(frame.camera.position, float)) @ sim.model_matrix()
        env, use_probe = self._environment(frame)
        lods = float(max(0, int(math.log2(env.size[0]))))
        light = frame.light_uniforms() if frame.main_light is not None else {
            "uMainLightDir": (0.0, 0.7071, 0.7071), "uMainLightRadiance": (3.0, 3.0, 3.0)}
        target.use()
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.disable(moderngl.CULL_FACE)
        hull = self.program(HULL)
        hull.bind_textures({"uEnvironment": env})
        draft = sim.draft
        waterline = self.waterline if self.waterline is not None else np.full(
            (2, WATERLINE_STATIONS), draft)
        deck = self._deck or details.Deck(sim.mesh)
        common = {"uViewProjRel": vp, "uEnvironmentLods": lods, "uUseProbe": use_probe,
                  "uBootTop": (draft + 0.04, draft + 0.17), "uBottomColor": (0.05, 0.06, 0.12),
                  "uStripeColor": (0.45, 0.04, 0.03), "uSheerStripe": (0.05, 0.17),
                  "uSheerColor": (0.02, 0.05, 0.18), "uGloss": 0.6, "uTime": frame.time,
                  "uStations": (deck.stern + 0.1, deck.stem - 0.1),
                  "uBowWave": 0.08 + 0.08 * min(max(sim.speed(), 0.0), 4.0), **light}
        hull.set_many({**common, "uModelRel": model_rel})
        hull.set_array("uWaterline", [float(v) for v in waterline.reshape(-1)])
        fmt = (details.VERTEX_FORMAT, *details.VERTEX_ATTRIBUTES)
        buf, count = meshes["hull"]
        hull.vao([(buf, *fmt)]).render(moderngl.TRIANGLES, vertices=count)
        st = self.sail_state
        boom_angle = -st.boom if st is not None else 0.0  # the rig's sign: + toward boat +x
        boom_m = model_rel @ rigging.boom_transform(boom_angle)
        hull.set_many({"uModelRel": boom_m})
        buf, count = meshes["boom"]
        hull.vao([(buf, *fmt)]).render(moderngl.TRIANGLES, vertices=count)
        self._draw_cloth(frame, meshes, model_rel, vp, env, lods, light, boom_angle)
        self._draw_dry_mask(frame, target, model_rel, vp, meshes)
        ctx.disable(moderngl.DEPTH_TEST)

    def _draw_cloth(self, frame, meshes, model_rel, vp, env, lods, light, boom_angle) -> None:
        st = self.sail_state
        side = -float(st.side) if st is not None else 1.0  # the rig's +z is boat +x
        fill = float(st.fill) if st is not None else 0.0
        prog = self.program(CLOTH)
        flag_angle = self.flag_angle()
        for name, transform, prefix, tex in (
                ("main", rigging.boom_transform(boom_angle), "boat.sail_", "sail"),
                ("jib", rigging.jib_transform(0.8 * boom_angle), "boat.sail_", "sail"),
                ("flag", rigging.flag_transform(flag_angle), "boat.flag_", "flag")):
            cm, vbo, ibo = meshes[name]
            prog.bind_textures({"uAlpha": meshes[f"{tex}_alpha"],
                                "uPattern": meshes[f"{tex}_pattern"], "uEnvironment": env,
                                **self._noise.textures()})
            u = {"uModel": model_rel @ transform, "uViewProj": vp, "uTime": frame.time,
                 "uBellySide": side, "uFill": fill if name != "flag" else 0.0,
                 "uEnvironmentLods": lods, "uUnlit": False, **light,
                 **cloth.cloth_uniforms(self.params, prefix), **cm.uniforms()}
            prog.set_many(u)
            prog.vao([(vbo, rigging.CLOTH_FORMAT, *rigging.CLOTH_ATTRIBUTES)], ibo).render(
                moderngl.TRIANGLES)

    def flag_angle(self) -> float:
        """The masthead flag's angle about the mast [rad, the rig's sign: 0 streaming aft, +
        toward boat +x]: it streams downwind — the direction the frame's wind blows toward,
        relative to the heading (spec/000 §1.4: the pennant shows the wind). 0 in no wind."""
        wind = self.wind
        if self.sim is None or float(np.hypot(*wind)) <= 1e-3:
            return 0.0
        rel = compass_radians(wind[0], wind[1]) - self.sim.heading
        return math.remainder(rel - math.pi, 2.0 * math.pi)

    def _draw_dry_mask(self, frame, target, model_rel, vp, meshes) -> None:
        """Front faces nearest into one depth texture, back faces farthest into another."""
        sim = self.sim
        size = tuple(target.size)
        if self._dry.get("size") != size:
            self._free_dry()
            self._dry = {"size": size,
                         "front": self.gpu.target(self.name, "dry front", size, dtype="f1"),
                         "back": self.gpu.target(self.name, "dry back", size, dtype="f1"),
                         "vbo": self.gpu.buffer(self.name, "dry volume",
                                                sim.dry_volume().astype("f4").tobytes())}
            for k in ("front", "back"):
                self._dry[k].depth.compare_func = ""
                self._dry[k].depth.filter = (moderngl.NEAREST, moderngl.NEAREST)
        ctx = self.gpu.ctx
        prog = self.program(DRY)
        prog.set_many({"uModelRel": model_rel, "uViewProjRel": vp})
        vao = prog.vao([(self._dry["vbo"], "3f", "in_position")], meshes["dry_ibo"])
        ctx.enable(moderngl.CULL_FACE)
        try:
            for which, face, func, clear in (("front", "back", "<", 1.0),
                                             ("back", "front", ">", 0.0)):
                t = self._dry[which]
                t.use()
                t.clear(depth=clear)
                ctx.cull_face = face
                ctx.depth_func = func
                vao.render(moderngl.TRIANGLES)
        finally:
            ctx.cull_face = "back"
            ctx.depth_func = "<"
            ctx.disable(moderngl.CULL_FACE)
        target.use()
        frame.dry_mask = DryMask(self._dry["front"].depth, self._dry["back"].depth)

    def release_meshes(self) -> None:
        if self._meshes is not None:
            for v in self._meshes.values():
                for obj in (v if isinstance(v, tuple) else (v,)):
                    if hasattr(obj, "release") and not isinstance(obj, rigging.Mesh):
                        self.gpu.free(obj)
            self._meshes = None

    def panel_notes(self) -> list[str]:
        sim = self.sim
        if sim is None:
            return []
        s = sim.state()
        lines = [f"heading {math.degrees(sim.heading) % 360:.0f}° · speed {s.surge:.2f} m/s "
                 f"({s.surge / 0.5144:.1f} kn) · heel {math.degrees(s.heel):.1f}° · "
                 f"{sim.method} ({len(sim.mesh.triangles)} hull triangles)"]
        st = self.sail_state
        if st is not None:
            lines.append(f"apparent wind {math.degrees(st.awa):.0f}° off the bow · boom "
                         f"{math.degrees(st.boom):.0f}° · sail fill {st.fill:.2f}")
        return lines

    def release(self) -> None:
        self._meshes = None
        self._dry = {}
        self._flat_env = None
        super().release()

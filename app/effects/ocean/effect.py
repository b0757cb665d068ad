"""The open sea of the maritime thesis (spec/000 §1.1, §1.2, §1.3): three wave models switchable
live — sine (spec/000 §1.1(a)), a sum of Gerstner waves (spec/000 §1.1(c)) and the cascaded FFT
ocean (Tessendorf; spec/000 §1.1(d) and (e)) — rendered with the sky's reflection probe, the
main light's glitter, foam, an underwater view, and water-height queries for floating objects.

What lives where (``app/effects/ocean/``)
* ``effect.py`` — the effect: per-frame update, the surface and underwater passes, panel notes;
  ``deferred.py`` — the deferred surface pass's inputs and the far plane's band of rows;
* ``params.py`` — its parameters; ``sea.py`` — the sea state the parameters describe (models,
  Gerstner set, FFT cascades); ``foam.py`` — foam calibration; ``uniforms.py`` — what the
  programs are told; ``mesh.py`` — the level-of-detail polar grid; ``queries.py`` — water-height
  queries (the frame's ``water`` slot); ``fft.py`` — the GPU simulation (evolve, FFT, finalize,
  foam, readback);
* numpy reference and oceanography: ``app/sim/ocean.py`` (spectra, dispersion, Gerstner,
  synthesis, inversion) and ``app/sim/ocean_validation.py``; GLSL: ``glsl/ocean/`` (waves.glsl =
  the three models, shading.glsl = Fresnel, glitter, foam, underwater light).

Slots: produces ``water``, and ``wind`` from its own parameters when no effect before it filled
the slot (the maritime scene's one wind: then the sea is built on that wind); reads
``environment`` (fallback: a flat grey probe), ``main_light`` (fallback: a fixed white light),
``image`` (Snell's window refracts it), ``wakes``
(foam trails, glsl/common/wake.glsl; none: no wake) and ``dry_mask`` (the hulls it must not draw
through, glsl/common/dry_mask.glsl; none: nothing masked).
"""

from __future__ import annotations

import math

import moderngl
import numpy as np

from ...errors import NaturaError
from ...frame import Stage
from ...gpu import fft as gpu_fft
from ...gpu.copy import ColourCopy
from ...gpu.programs import ProgramSpec, draw_fullscreen, fullscreen
from ...params import Joint, Param
from ...render.environment import flat_environment
from ...sim import ocean as oc
from ...sim.maths import compass_degrees
from ..base import Effect, Pass
from .deferred import DeferredInputs, WakeMap, far_band, screen_rect
from .fft import BLEND, RESAMPLE
from .foam import FoamCalibration
from .mesh import OceanMesh
from .params import ocean_params, wind_vector
from .queries import WaterQueries
from .sea import SeaState
from .uniforms import OceanUniforms

SURFACE = ProgramSpec("ocean/surface")
FAR = fullscreen("ocean/far")
UNDERWATER = fullscreen("ocean/underwater")
# the deferred surface pass (deferred.py): inputs of the mesh and of the far plane, then shading
SURFACE_INPUTS = ProgramSpec("ocean/surface_inputs", vert="ocean/surface.vert",
                             frag="ocean/surface_inputs.frag")
FAR_INPUTS = ProgramSpec("ocean/far_inputs", vert="ocean/band.vert", frag="ocean/far_inputs.frag")
SHADE = ProgramSpec("ocean/shade", vert="ocean/band.vert", frag="ocean/shade.frag",
                    defines=(("OCEAN_EXPLICIT_GRADIENTS", 1),))
# the same, for a camera clearly above the water: the view from below is not compiled in (a
# software rasteriser would run it on every pixel, uniform branch or not)
SHADE_ABOVE = ProgramSpec("ocean/shade_above", vert="ocean/band.vert", frag="ocean/shade.frag",
                          defines=(("OCEAN_EXPLICIT_GRADIENTS", 1), ("OCEAN_SEEN_FROM_ABOVE", 1)))


def floating(spec: ProgramSpec) -> ProgramSpec:
    """``spec`` for a scene with floating objects: their wakes and dry volumes compiled in
    (OCEAN_FLOATING; a software rasteriser would run the wake's loop on every pixel of a scene
    without one, so the other scenes' programs leave it out)."""
    return ProgramSpec(spec.name + "_floating", vert=spec.vert or f"{spec.name}.vert",
                       frag=spec.frag or f"{spec.name}.frag",
                       defines=spec.defines + (("OCEAN_FLOATING", 1),))


FLOATING = {s.name: floating(s) for s in (SURFACE, SURFACE_INPUTS, SHADE, SHADE_ABOVE)}
# the deferred shading with the wake read from its map (wake_map.frag: once per block of pixels)
WAKE_MAP = fullscreen("ocean/wake_map")
FLOATING_WAKE_MAP = {s.name: ProgramSpec(s.name + "_floating_wake_map", vert=s.vert,
                                         frag=s.frag, defines=s.defines + (("OCEAN_FLOATING", 1),
                                                                           ("OCEAN_WAKE_MAP", 1)))
                     for s in (SHADE, SHADE_ABOVE)}
# the GPU simulation's programs (app/effects/ocean/fft.py, app/gpu/fft.py), listed so that
# `natura shaders check` compiles them and their @param annotations are found
SIMULATION = (
    ProgramSpec("ocean/spectrum_evolve", comp="ocean/spectrum_evolve.comp", requires_compute=True),
    ProgramSpec("ocean/ocean_finalize", comp="ocean/ocean_finalize.comp", requires_compute=True),
    ProgramSpec("ocean/direct_sum", comp="ocean/direct_sum.comp", requires_compute=True),
    fullscreen("ocean/spectrum_evolve"), fullscreen("ocean/ocean_finalize"),
    fullscreen("ocean/direct_sum"), BLEND, RESAMPLE,
) + gpu_fft.VARIANTS


def shading_path(caps, setting: str) -> str:
    """``ocean.shading`` on a context: ``auto`` is deferred on a software renderer (it shades
    whole 4×4 blocks, so the far rings' thin triangles cost it several times over), forward on
    a GPU."""
    if setting == "auto":
        return "deferred" if caps.software else "forward"
    return setting


class Ocean(SeaState, FoamCalibration, WaterQueries, OceanUniforms, Effect):
    name = "ocean"
    title = "Ocean"
    spec = "spec/000"
    programs = (SURFACE, FAR, UNDERWATER, SURFACE_INPUTS, FAR_INPUTS, SHADE,
                SHADE_ABOVE, WAKE_MAP) + tuple(FLOATING.values()) + tuple(
                    FLOATING_WAKE_MAP.values()) + SIMULATION
    #: water stage seen from above; fog stage near or under the surface (see passes())
    stages = (Stage.WATER, Stage.FOG)
    produces = frozenset({"wind", "water"})
    consumes = {"environment": "optional", "main_light": "optional", "image": "optional",
                "wind": "optional", "wakes": "optional", "dry_mask": "optional"}
    joints = (Joint(("ocean.patch_sizes", "ocean.cascades", "ocean.fft_size"),
                    "falling patch sizes that hold their bands at ocean.fft_size",
                    lambda sizes, count, n: bool(oc.cascade_bands(int(n), sizes[:count]))),)

    @classmethod
    def context_paths(cls, caps, params) -> dict[str, str]:
        from ...gpu.fft import choose_compute

        fft, shading = params["ocean.fft_path"], params["ocean.shading"]
        try:
            fft_path = "compute shaders" if choose_compute(caps, fft, "ocean.fft_path") \
                else "fragment passes"
        except NaturaError as exc:
            fft_path = f"refused: {exc}"
        return {"ocean FFT": f"{fft_path} (ocean.fft_path={fft})",
                "ocean surface": f"{shading_path(caps, shading)} (ocean.shading={shading})"}

    @classmethod
    def python_params(cls) -> list[Param]:
        return ocean_params()

    # -- life ------------------------------------------------------------------------------

    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        self.sim = None  # GpuOceanSim, only for the FFT model
        self._foam = self.keyed(self._calibrate_foam)  # (threshold, width) per cascade
        self._sim_path = None
        self._sim_key = None
        self._fft_ref: oc.FFTOcean | None = None
        self._waves = self.keyed(self._draw_waves)
        self.mesh = OceanMesh(self)
        self._scene_copy = ColourCopy(gpu, self.name, "scene copy")
        self._color_copy = ColourCopy(gpu, self.name, "color copy")
        self._inputs = DeferredInputs(gpu, self.name)
        self._wake_map = WakeMap(gpu, self.name)
        #: NDC rows (bottom, top) the last deferred frame drew the far plane over (None: none)
        self.far_band: tuple[float, float] | None = None
        self._flat_env = None
        self.time = 0.0
        self.camera_pos = np.zeros(3)
        self.query_time: float | None = None
        self._readback = None
        self.resolved_mss = 0.0
        self.cascade_bands: list[tuple[float, float, float]] = []
        self.underwater = False
        self.camera_height_water = 0.0
        self._fft_hs = 0.0
        self._sim_sizes: list[int] = []  # each cascade's grid as simulated (fit_view)
        self._sim_cascades: list[oc.Cascade] = []
        self._readback_groups: list = []  # the readback grouped by grid size (queries.py)
        #: the smallest pixel footprint on the water of the last view [m] (ocean.simulation=view)
        self.footprint = math.nan
        self._frame_dt = 1.0 / 30.0  # the frame interval, smoothed (slow cascades)
        self._bench_clock = 0  # frames the bench's simulate pass has advanced
        self._bench_sim = None  # (key, GpuOceanSim): the copy the bench times
        #: what the last simulated frame was computed from (update(): a standing clock with the
        #: same inputs simulates nothing), and whether the last update ran the simulation
        self._sim_inputs: tuple | None = None
        self.sim_ran = False

    # -- sea state -------------------------------------------------------------------------

    # -- frame -----------------------------------------------------------------------------

    def update(self, frame, dt: float) -> None:
        p = self.params
        self.time = frame.time
        self.camera_pos = np.asarray(frame.camera.position, dtype=float)
        # the scene's one wind, when an effect before the ocean filled the slot (spec/000 §1.4)
        own_wind = frame.wind is None
        if own_wind:
            self.frame_wind = None
        else:
            vx, vz = (float(v) for v in frame.wind)
            self.frame_wind = (math.hypot(vx, vz), compass_degrees(vx, vz))
        model = p["ocean.model"]
        if model == "fft":
            self._ensure_fft()
            self.fit_view(frame)
            thresholds = self.foam_thresholds()
            # what the simulation's output depends on: the same on a standing clock (dt ≤ 0,
            # the same time) leaves every texture as it is (the foam's decay is then 1 and its
            # update idempotent), so nothing is recomputed — the window's pause menu (dt = 0), a
            # still render, the bench's frame
            inputs = (self.sim, self._sim_key, tuple(self.sim.sizes), tuple(self.sim.periods),
                      float(frame.time), p["ocean.choppiness"], tuple(thresholds),
                      p["ocean.foam_decay"])
            still = (dt <= 0.0 and self._sim_inputs is not None
                     and len(inputs) == len(self._sim_inputs)
                     and all(a is b or a == b for a, b in zip(inputs, self._sim_inputs)))
            self._sim_inputs = inputs
            if still:
                got = self.sim.poll_readback()
                if self.query_time != float(frame.time):  # the newest request is this time's
                    got = self.sim.read_newest()  # sea: no stall left, its work is long done
            else:
                self.sim.update(frame.time, p["ocean.choppiness"], dt,
                                foam_threshold=[t for t, _ in thresholds],
                                foam_decay_time=p["ocean.foam_decay"],
                                foam_width=[w for _, w in thresholds])
                self.sim.request_readback()
                got = self.sim.poll_readback()  # the previous frame's request: no stall
            self.sim_ran = not still
            if got is None:  # the first frame of this sea: read it now (one stall), so floating
                got = self.sim.read_newest()  # objects and the camera never start on flat water
            if got is not None and got is not self._readback:
                self._readback = got
                self._readback_groups = oc.group_cascade_grids(got[1], self.patch_sizes())
                self.query_time = got[0]
        else:
            self._release_fft()
            self.query_time = frame.time
            if model == "gerstner":
                self.gerstner_waves()
                self.resolved_mss = oc.gerstner_moments(self.gerstner_waves())["mss"]
            else:
                a, k, _ = self.sine_wave()
                self.resolved_mss = 0.5 * (k * a) ** 2
        if own_wind:
            frame.wind = wind_vector(p["ocean.wind_direction"]) * p["ocean.wind"]
        frame.water = self
        self.camera_height_water = float(self.height(self.camera_pos[0], self.camera_pos[2]))
        self.underwater = bool(self.camera_pos[1] < self.camera_height_water)

    # -- queries ---------------------------------------------------------------------------

    # -- uniforms --------------------------------------------------------------------------

    def environment(self, frame):
        """The frame's environment probe without the sun disk — the main light's specular lobe
        draws the sun — or, the fallback when no effect fills the slot, a flat grey cubemap."""
        if frame.environment is not None:
            return frame.environment.cubemap(sun=False)  # the sun is the analytic glitter
        if self._flat_env is None:
            self._flat_env = flat_environment(self.gpu, self.name)
        return self._flat_env

    lesson_param = "ocean.model"  # LESSONS: what panel_notes begins with too
    LESSONS = {
        "sine": "Sine (spec/000 §1.1(a)): one wave with analytic normals — cheap, but it repeats "
                "every wavelength and a lone sine never looks like the sea.",
        "gerstner": "Gerstner (spec/000 §1.1(c)): waves drawn from the spectrum, crests sharpened "
                    "by horizontal motion; each wave's steepness s = k·A must stay ≤ 1 or the "
                    "crests loop.",
        "fft": "FFT (Tessendorf; spec/000 §1.1(d), §1.1(e)): every wave of the spectrum on a "
               "grid, per cascade; choppy displacement, foam where the Jacobian folds; tiles "
               "repeat only at their size.",
    }

    def panel_notes(self) -> list[str]:
        model = self.params["ocean.model"]
        lines = [self.LESSONS[model]]
        if self.frame_wind is not None:
            lines.append(f"wind {self.frame_wind[0]:.1f} m/s toward {self.frame_wind[1]:.0f}° from "
                         "the scene's wind (ocean.wind and ocean.wind_direction are not used)")
        lines.append(f"Hs {self.significant_height():.2f} m · slope variance "
                     f"{self.resolved_mss:.4f} (Cox–Munk {self.cox_munk_mss():.4f})")
        if model == "fft" and self.sim is not None:
            sizes = "/".join(str(n) for n in self.sim.sizes)
            lines.append(f"N {sizes} for {len(self.patch_sizes())} cascades "
                         f"({self.sim.path}); queries lag one frame (t = "
                         f"{self.query_time if self.query_time is not None else '—'})"
                         + ("" if self.sim_ran else "; clock standing: not simulated again"))
            if self.params["ocean.simulation"] == "view":
                slow = [f"{i}: every {1e3 * t:.0f} ms" for i, t in enumerate(self.sim.periods)
                        if t > 0.0]
                lines.append(f"view: smallest footprint {100.0 * self.footprint:.1f} cm; "
                             + ("snapshots interpolated for cascade " + ", ".join(slow)
                                if slow else "every cascade every frame"))
        if self.mesh.built:
            lines.append(f"mesh: {self.drawn_triangles:,} of {self.mesh_triangles:,} triangles "
                         "drawn" + ("; camera under water" if self.underwater else ""))
        return lines

    # -- passes ----------------------------------------------------------------------------

    @property
    def mesh_triangles(self) -> int:
        """Triangles of the whole surface mesh."""
        return self.mesh.triangles

    @property
    def drawn_triangles(self) -> int:
        """Triangles of the surface mesh the last frame drew (the wedges in view)."""
        return self.mesh.drawn

    def view_proj_rel(self, frame) -> np.ndarray:
        return frame.camera.view_projection_relative(frame.aspect)

    def view_mode(self) -> int:
        """0: the camera is clearly above the water, 1: clearly below, 2: within 0.5 m of it (the
        near plane may straddle the surface: decided per pixel)."""
        margin = 0.5
        if self.camera_pos[1] > self.camera_height_water + margin:
            return 0
        if self.camera_pos[1] < self.camera_height_water - margin:
            return 1
        return 2

    def may_be_underwater(self) -> bool:
        """Whether any pixel can start under water: the camera within the waves' reach."""
        return self.view_mode() != 0

    def stage(self) -> Stage:
        """The water stage while the camera is clearly above the surface (clouds below the
        camera then cover the sea, clipped by its depth); the fog stage near or under it, so the
        sea draws after the volumes and Snell's window shows the clouds (the surface pass copies
        the image before it draws)."""
        return Stage.WATER if self.view_mode() == 0 else Stage.FOG

    def render_surface(self, frame, target) -> None:
        """The sea's surface: ``ocean.shading = deferred`` (inputs, then one shading pass over
        the covered pixels) or ``forward`` (the mesh and the far plane shade as they draw);
        ``auto`` picks by the context (:func:`shading_path`)."""
        if shading_path(self.gpu.caps, self.params["ocean.shading"]) == "forward":
            self._render_forward(frame, target)
        else:
            self._render_deferred(frame, target)

    @staticmethod
    def variant(spec: ProgramSpec, frame) -> ProgramSpec:
        """The floating-objects variant of ``spec`` when the frame has a wake or a dry mask."""
        return FLOATING[spec.name] if (frame.wakes or frame.dry_mask is not None) else spec

    def _mesh_draw(self, prog, frame) -> None:
        p = self.params
        self.mesh.draw(prog, frame.camera, frame.aspect, p["ocean.mesh_segments"],
                       p["ocean.mesh_inner"], p["ocean.mesh_extent"], p["ocean.mesh_cull"],
                       p["ocean.mesh_aspect"])

    def _far_start(self) -> float:
        return 0.88 * self.params["ocean.mesh_extent"]

    def _render_forward(self, frame, target) -> None:
        ctx = self.gpu.ctx
        env = self.environment(frame)
        vp = self.view_proj_rel(frame)
        near_surface = self.may_be_underwater()
        scene_copy = self._scene_copy.of(target) if near_surface else None
        target.use()
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.disable(moderngl.CULL_FACE)
        prog = self.program(self.variant(SURFACE, frame))
        textures = self.wave_uniforms(prog)
        textures.update(self.shading_uniforms(prog, frame, env))
        textures.update(self.dry_mask_textures(prog, frame))
        self.wake_uniforms(prog, frame)
        textures["uSceneCopy"] = scene_copy
        prog.bind_textures(textures)
        prog.set_many({"uViewProjRel": vp, "uCameraPos": tuple(frame.camera.position),
                       "uViewport": tuple(float(s) for s in target.size),
                       "uViewMode": self.view_mode(),
                       "uInvViewProjRel": np.linalg.inv(vp)})
        self._mesh_draw(prog, frame)
        if frame.camera.position[1] > 0.0:
            far = self.program(FAR)
            textures = self.wave_uniforms(far)
            textures.update(self.shading_uniforms(far, frame, env))
            far.bind_textures(textures)
            far.set_many(frame.camera_uniforms())
            far.set_many({"uViewProjRel": vp, "uFarStart": self._far_start(),
                          "uViewport": tuple(float(s) for s in target.size)})
            draw_fullscreen(far)
        ctx.disable(moderngl.DEPTH_TEST)

    def _render_deferred(self, frame, target) -> None:
        scene_copy = self._scene_copy.of(target) if self.may_be_underwater() else None
        self._deferred_inputs(frame, target)
        wake_map = self._render_wake_map(frame, target)
        self._deferred_shade(frame, target, scene_copy, wake_map)

    def _render_wake_map(self, frame, target):
        """The wake's foam once per block of ``ocean.wake_stride`` pixels (``wake_map.frag``),
        over the screen rectangle the trail's bounds cover; None without a wake or at stride 1
        (the shading pass then evaluates it per pixel)."""
        stride = int(self.params["ocean.wake_stride"])
        trail = frame.wakes[0] if frame.wakes else None
        if stride <= 1 or trail is None or len(trail) == 0:
            return None
        size = (int(target.size[0]), int(target.size[1]))
        fbo = self._wake_map.of(size, stride)
        cam = np.asarray(frame.camera.position, dtype=float)
        reach = max(self.significant_height(), 0.5)  # crests, and the choppy displacement
        x0, z0, x1, z1 = trail.bounds(frame.time)
        rect = screen_rect(self.view_proj_rel(frame),
                           (x0 - reach - cam[0], z0 - reach - cam[2], x1 + reach - cam[0],
                            z1 + reach - cam[2]), (-reach - cam[1], reach - cam[1]), size)
        if rect[2] == 0:
            return self._wake_map.texture  # the trail is off screen: no foam
        # in map texels, one of margin for the filtered lookup
        mw, mh = self._wake_map.texture.size
        tx0, ty0 = max(rect[0] // stride - 1, 0), max(rect[1] // stride - 1, 0)
        tx1 = min(-(-(rect[0] + rect[2]) // stride) + 1, mw)
        ty1 = min(-(-(rect[1] + rect[3]) // stride) + 1, mh)
        prog = self.program(WAKE_MAP)
        self.wake_uniforms(prog, frame)
        prog.set("uWakeStride", stride)
        prog.bind_textures({"uInputSurf": self._inputs.surf})
        with self.gpu.ctx.scope(fbo, enable_only=moderngl.NOTHING):
            fbo.scissor = (tx0, ty0, tx1 - tx0, ty1 - ty0)
            fbo.use()
            draw_fullscreen(prog)
            fbo.scissor = None
        return self._wake_map.texture

    def _deferred_inputs(self, frame, target) -> None:
        """The mesh, then the far plane over its band, write their shading inputs, depth-tested
        against the target's depth as the forward passes are."""
        ctx = self.gpu.ctx
        vp = self.view_proj_rel(frame)
        viewport = tuple(float(s) for s in target.size)
        self._inputs.of(target).use()
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.disable(moderngl.CULL_FACE)
        prog = self.program(self.variant(SURFACE_INPUTS, frame))
        prog.bind_textures({**self.wave_uniforms(prog), **self.dry_mask_textures(prog, frame)})
        prog.set_many({"uViewProjRel": vp, "uCameraPos": tuple(frame.camera.position)})
        self._mesh_draw(prog, frame)
        self.far_band = (far_band(frame.camera, frame.aspect, int(target.size[1]),
                                  self._far_start()) if frame.camera.position[1] > 0.0 else None)
        if self.far_band is not None:
            far = self.program(FAR_INPUTS)
            far.set_many(frame.camera_uniforms())
            far.set_many({"uViewProjRel": vp, "uFarStart": self._far_start(),
                          "uViewport": viewport, "uBand": self.far_band, "uBandDepth": 0.0})
            far.vao().render(moderngl.TRIANGLE_STRIP, vertices=4)
        ctx.disable(moderngl.DEPTH_TEST)

    def _deferred_shade(self, frame, target, scene_copy, wake_map=None) -> None:
        """The shading where the inputs were written: a quad on the far plane, depth-tested
        GREATER (nothing drawn = depth 1 = rejected), the depth left as the inputs wrote it;
        the wake read from ``wake_map`` when given (:meth:`_render_wake_map`)."""
        ctx = self.gpu.ctx
        vp = self.view_proj_rel(frame)
        viewport = tuple(float(s) for s in target.size)
        env = self.environment(frame)  # may render the probe now: before the target is bound
        target.use()
        ctx.enable(moderngl.DEPTH_TEST)
        spec = SHADE_ABOVE if self.view_mode() == 0 else SHADE
        shade = self.program(FLOATING_WAKE_MAP[spec.name] if wake_map is not None
                             else self.variant(spec, frame))
        textures = self.wave_uniforms(shade)
        textures.update(self.shading_uniforms(shade, frame, env))
        if wake_map is not None:
            textures["uWakeMap"] = wake_map
            shade.set("uWakeStride", int(self.params["ocean.wake_stride"]))
        else:
            self.wake_uniforms(shade, frame)
        textures.update({"uSceneCopy": scene_copy, "uInputRel": self._inputs.rel,
                         "uInputSurf": self._inputs.surf, "uInputGrad": self._inputs.grad})
        shade.bind_textures(textures)
        shade.set_many({"uCameraPos": tuple(frame.camera.position), "uViewport": viewport,
                        "uViewMode": self.view_mode(), "uInvViewProjRel": np.linalg.inv(vp),
                        "uBand": (-1.0, 1.0), "uBandDepth": 1.0})
        ctx.depth_func = ">"
        target.fbo.depth_mask = False
        try:
            shade.vao().render(moderngl.TRIANGLE_STRIP, vertices=4)
        finally:
            target.fbo.depth_mask = True
            ctx.depth_func = "<"
            ctx.disable(moderngl.DEPTH_TEST)

    def render_underwater(self, frame, target) -> None:
        ctx = self.gpu.ctx
        color = self._color_copy.of(target)
        env = self.environment(frame)
        prog = self.program(UNDERWATER)
        textures = self.wave_uniforms(prog)
        textures.update(self.shading_uniforms(prog, frame, env))
        prog.set_many(frame.camera_uniforms())
        prog.set("uInvViewProjRel", np.linalg.inv(self.view_proj_rel(frame)))
        depth = target.depth
        old = depth.compare_func
        depth.compare_func = ""
        prog.bind_textures({**textures, "uColor": color, "uSceneDepth": depth})
        target.use()
        ctx.disable(moderngl.DEPTH_TEST)
        draw_fullscreen(prog)
        depth.compare_func = old

    def passes(self, frame, target) -> list[Pass]:
        stage = self.stage()
        out = [Pass("ocean.surface", lambda: self.render_surface(frame, target), stage)]
        if self.may_be_underwater():
            out.append(Pass("ocean.underwater", lambda: self.render_underwater(frame, target),
                            stage))
        return out

    def bench_passes(self, frame, target) -> list[Pass]:
        """The passes, after the FFT simulation's update (which the frame runs in update()).

        ``ocean.simulate`` runs a copy of the simulation (the same cascades, grids and periods)
        on a clock of its own that moves 1/30 s a call — the bench's frames stand still, and a
        slow cascade does nothing while its clock does: this is what a running frame pays,
        slow cascades included (their snapshot steps spread over the frames, and their blend).
        A copy, so that the frame's own simulation keeps its clock."""
        out = self.passes(frame, target)
        if self.sim is not None:
            p = self.params
            thresholds = self.foam_thresholds()

            sim = self._bench_simulation()

            def simulate():
                self._bench_clock += 1
                sim.update(frame.time + self._bench_clock / 30.0, p["ocean.choppiness"],
                           1.0 / 30.0, foam_threshold=[t for t, _ in thresholds],
                           foam_decay_time=p["ocean.foam_decay"],
                           foam_width=[w for _, w in thresholds])

            out.insert(0, Pass("ocean.simulate", simulate, self.stage()))
        return out

    def _bench_simulation(self):
        """The copy of the simulation :meth:`bench_passes` times (remade when the sea, its
        grids or its periods change)."""
        from .fft import GpuOceanSim

        key = (self._sim_key, tuple(self.sim.sizes), tuple(self.sim.periods), self.sim.path)
        if self._bench_sim is None or self._bench_sim[0] != key:
            if self._bench_sim is not None:
                self._bench_sim[1].release()
            sim = GpuOceanSim(self.gpu, self.name, use_compute=self.sim.use_compute)
            sim.set_spectrum(self._sim_cascades)
            sim.set_refresh(self.sim.periods)
            self._bench_sim = (key, sim)
        return self._bench_sim[1]

    def release(self) -> None:
        if self._bench_sim is not None:
            self._bench_sim[1].release()
            self._bench_sim = None
        self._sim_inputs = None
        self._release_fft()
        super().release()
        self._scene_copy.release()
        self._color_copy.release()
        self._inputs.release()
        self._wake_map.release()
        self._flat_env = None

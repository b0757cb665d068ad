"""The ocean's surface: the level-of-detail mesh and the far plane, drawn forward or deferred
(``ocean.shading``), the wake map, the view from below, and the stage the camera's place asks
for. Its programs are listed here; the effect declares them."""

from __future__ import annotations

from dataclasses import replace

import moderngl
import numpy as np

from ...frame import Stage
from ...gpu.copy import ColourCopy
from ...gpu.programs import ProgramSpec, draw_fullscreen, fullscreen
from ...gpu.targets import depth_tested
from ...render.environment import flat_environment
from .deferred import deferred_inputs, far_band, screen_rect, wake_map
from .mesh import OceanMesh
from .params import MODELS

SURFACE = ProgramSpec("ocean/surface")
FAR = fullscreen("ocean/far")
UNDERWATER = fullscreen("ocean/underwater")
# the deferred surface pass (deferred.py): inputs of the mesh and of the far plane, then shading
SURFACE_INPUTS = ProgramSpec("ocean/surface_inputs", vert="ocean/surface.vert",
                             frag="ocean/surface_inputs.frag")
FAR_INPUTS = ProgramSpec("ocean/far_inputs", vert="ocean/band.vert", frag="ocean/far_inputs.frag")
SHADE = ProgramSpec("ocean/shade", vert="ocean/band.vert", frag="ocean/shade.frag",
                    defines=(("OCEAN_EXPLICIT_GRADIENTS", 1), ("OCEAN_AMBIENT_VARYING", 1)))
# the same, for a camera clearly above the water: the view from below is not compiled in (a
# software rasteriser would run it on every pixel, uniform branch or not)
SHADE_ABOVE = ProgramSpec("ocean/shade_above", vert="ocean/band.vert", frag="ocean/shade.frag",
                          defines=(("OCEAN_EXPLICIT_GRADIENTS", 1), ("OCEAN_AMBIENT_VARYING", 1),
                                   ("OCEAN_SEEN_FROM_ABOVE", 1)))


def with_defines(spec: ProgramSpec, suffix: str, *defines: str) -> ProgramSpec:
    """``spec`` with ``defines`` set to 1, named ``spec.name + suffix``."""
    return ProgramSpec(spec.name + suffix, vert=spec.vert or f"{spec.name}.vert",
                       frag=spec.frag or f"{spec.name}.frag",
                       defines=spec.defines + tuple((d, 1) for d in defines))


# for a scene with floating objects: their wakes and dry volumes compiled in (a software
# rasteriser would run the wake's loop on every pixel of a scene without one)
FLOATING = {s.name: with_defines(s, "_floating", "OCEAN_FLOATING")
            for s in (SURFACE, SURFACE_INPUTS, SHADE, SHADE_ABOVE)}
# the deferred shading with the wake read from its map (wake_map.frag: once per block of pixels)
WAKE_MAP = fullscreen("ocean/wake_map")
#: trail samples the wake map evaluates per pass (a pass per chunk, each over its own rectangle:
#: young samples' rings are small, so most pixels evaluate a few chunks, not the whole trail)
WAKE_CHUNK = 8
FLOATING_WAKE_MAP = {s.name: with_defines(s, "_floating_wake_map", "OCEAN_FLOATING",
                                          "OCEAN_WAKE_MAP") for s in (SHADE, SHADE_ABOVE)}
#: the programs that include ocean/waves.glsl: each is built for one wave model (for_model)
WAVE_PROGRAMS = (SURFACE, FAR, UNDERWATER, SURFACE_INPUTS, SHADE, SHADE_ABOVE,
                 *FLOATING.values(), *FLOATING_WAKE_MAP.values())
_WAVE_NAMES = frozenset(s.name for s in WAVE_PROGRAMS)


#: the FFT's cascade counts (``ocean.cascades``) a program is built for
CASCADE_COUNTS = (1, 2, 3, 4)


def for_model(spec: ProgramSpec, model: int, cascades: int) -> ProgramSpec:
    """``spec`` built for wave model ``model`` (an index of ``MODELS``: OCEAN_WAVE_MODEL) and,
    for the FFT, its number of ``cascades`` (OCEAN_CASCADES), when it includes
    ocean/waves.glsl: the other models' code and the unused cascades' reads are left out (a
    software rasteriser would run them, masked, on every vertex and pixel)."""
    if spec.name not in _WAVE_NAMES:
        return spec
    fft = model == MODELS.index("fft")
    return replace(spec, defines=spec.defines + (("OCEAN_WAVE_MODEL", model),)
                   + ((("OCEAN_CASCADES", cascades),) if fft else ()))


PROGRAMS = (FAR_INPUTS, WAKE_MAP) + tuple(
    for_model(s, m, c) for s in WAVE_PROGRAMS for m in range(len(MODELS))
    for c in (CASCADE_COUNTS if MODELS[m] == "fft" else CASCADE_COUNTS[:1]))


def shading_path(caps, setting: str) -> str:
    """``ocean.shading`` on a context: ``auto`` is deferred on a software renderer (it shades
    whole 4×4 blocks, so the far rings' thin triangles cost it several times over), forward on
    a GPU."""
    if setting == "auto":
        return "deferred" if caps.software else "forward"
    return setting


class Surface:
    """The sea's passes (:meth:`render`, :meth:`render_underwater`) over the ``sea``'s waves,
    placed by the ``queries`` and set up by the ``uniforms``."""

    def __init__(self, effect, sea, queries, uniforms):
        self.gpu, self.name, self.params = effect.gpu, effect.name, effect.params
        self._program = effect.program
        self.sea, self.queries, self.uniforms = sea, queries, uniforms
        self.mesh = OceanMesh(effect)
        self._scene_copy = ColourCopy(self.gpu, self.name, "scene copy")
        self._color_copy = ColourCopy(self.gpu, self.name, "color copy")
        # remade when the target's size or depth texture (the wake map: or its stride) changes
        self._inputs = effect.keyed(lambda key: deferred_inputs(self.gpu, self.name, *key),
                                    release=self._free)
        self._input_textures: dict = {}  # the last deferred frame's inputs by sampler name
        self._wake_maps = effect.keyed(lambda key: wake_map(self.gpu, self.name, *key),
                                       release=self._free)
        #: NDC rows (bottom, top) the last deferred frame drew the far plane over (None: none)
        self.far_band: tuple[float, float] | None = None
        self._flat_env = None
        self.underwater = False
        self.camera_height_water = 0.0

    def program(self, spec: ProgramSpec):
        """The effect's program of ``spec`` for the sea's wave model and cascades
        (:func:`for_model`)."""
        return self._program(for_model(spec, MODELS.index(self.params["ocean.model"]),
                                       len(self.sea.patch_sizes())))

    def _free(self, objects) -> None:
        for obj in reversed(objects):
            self.gpu.free(obj)

    def place_camera(self) -> None:
        """The water's height under the camera (``queries``), for :meth:`view_mode`."""
        cam = self.queries.camera_pos
        self.camera_height_water = float(self.queries.height(cam[0], cam[2]))
        self.underwater = bool(cam[1] < self.camera_height_water)

    def environment(self, frame):
        """The frame's environment probe without the sun disk — the main light's specular lobe
        draws the sun — or, the fallback when no effect fills the slot, a flat grey cubemap."""
        if frame.environment is not None:
            return frame.environment.cubemap(sun=False)  # the sun is the analytic glitter
        if self._flat_env is None:
            self._flat_env = flat_environment(self.gpu, self.name)
        return self._flat_env

    def view_mode(self) -> int:
        """0: the camera is clearly above the water, 1: clearly below, 2: within 0.5 m of it (the
        near plane may straddle the surface: decided per pixel)."""
        margin, y = 0.5, self.queries.camera_pos[1]
        if y > self.camera_height_water + margin:
            return 0
        if y < self.camera_height_water - margin:
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

    def render(self, frame, target) -> None:
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
        vp = frame.camera.view_projection_relative(frame.aspect)
        scene_copy = self._scene_copy.of(target) if self.may_be_underwater() else None
        target.use()
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.disable(moderngl.CULL_FACE)
        prog = self.program(self.variant(SURFACE, frame))
        u = self.uniforms
        textures = {**u.surface_uniforms(prog, frame, env), **u.dry_mask_textures(prog, frame)}
        u.wake_uniforms(prog, frame)
        prog.bind_textures({**textures, "uSceneCopy": scene_copy})
        prog.set_many({"uViewProjRel": vp, "uCameraPos": tuple(frame.camera.position),
                       "uViewport": tuple(float(s) for s in target.size),
                       "uViewMode": self.view_mode(),
                       "uInvViewProjRel": np.linalg.inv(vp)})
        self._mesh_draw(prog, frame)
        if frame.camera.position[1] > 0.0:
            far = self.program(FAR)
            far.bind_textures(u.surface_uniforms(far, frame, env))
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
        chunk by chunk of :data:`WAKE_CHUNK` trail samples, each over the screen rectangle its
        own samples' bounds cover, blended by their max (the whole trail's foam is the max of
        its samples'); None without a wake or at stride 1 (the shading pass then evaluates it
        per pixel)."""
        stride = int(self.params["ocean.wake_stride"])
        trail = frame.wakes[0] if frame.wakes else None
        if stride <= 1 or trail is None or len(trail) == 0:
            return None
        size = (int(target.size[0]), int(target.size[1]))
        texture, fbo = self._wake_maps.get((size, stride))
        fbo.clear(0.0, 0.0, 0.0, 0.0)
        cam = np.asarray(frame.camera.position, dtype=float)
        reach = max(self.sea.significant_height(), 0.5)  # crests, and the choppy displacement
        view_proj = frame.camera.view_projection_relative(frame.aspect)
        prog = self.program(WAKE_MAP)
        self.uniforms.wake_uniforms(prog, frame)
        prog.set("uWakeStride", stride)
        prog.bind_textures({"uInputSurf": self._input_textures["uInputSurf"]})
        ctx = self.gpu.ctx
        mw, mh = texture.size
        with ctx.scope(fbo, enable_only=moderngl.BLEND):
            ctx.blend_equation = moderngl.MAX
            try:
                fbo.use()
                for first in range(0, len(trail), WAKE_CHUNK):
                    end = min(first + WAKE_CHUNK, len(trail))
                    # the chunk and the sample after it, where its last wash segment ends
                    x0, z0, x1, z1 = trail.bounds(frame.time, samples=slice(first, end + 1))
                    rect = screen_rect(view_proj, (x0 - reach - cam[0], z0 - reach - cam[2],
                                                   x1 + reach - cam[0], z1 + reach - cam[2]),
                                       (-reach - cam[1], reach - cam[1]), size)
                    if rect[2] == 0:
                        continue  # these samples are off screen: no foam
                    # in map texels, one of margin for the filtered lookup
                    tx0, ty0 = max(rect[0] // stride - 1, 0), max(rect[1] // stride - 1, 0)
                    tx1 = min(-(-(rect[0] + rect[2]) // stride) + 1, mw)
                    ty1 = min(-(-(rect[1] + rect[3]) // stride) + 1, mh)
                    prog.set_many({"uWakeFirst": first, "uWakeEnd": end,
                                   "uWakeBounds": (x0 - cam[0], z0 - cam[2], x1 - cam[0],
                                                   z1 - cam[2])})
                    fbo.scissor = (tx0, ty0, tx1 - tx0, ty1 - ty0)
                    draw_fullscreen(prog)
            finally:
                fbo.scissor = None
                ctx.blend_equation = moderngl.FUNC_ADD
        return texture

    def _deferred_inputs(self, frame, target) -> None:
        """The mesh, then the far plane over its band, write their shading inputs, depth-tested
        against the target's depth as the forward passes are."""
        ctx = self.gpu.ctx
        vp = frame.camera.view_projection_relative(frame.aspect)
        viewport = tuple(float(s) for s in target.size)
        size = (int(target.size[0]), int(target.size[1]))
        rel, surf, grad, fbo, clear = self._inputs.get((size, target.depth))
        self._input_textures = {"uInputRel": rel, "uInputSurf": surf, "uInputGrad": grad}
        clear.clear(0.0, 0.0, 0.0, 0.0)  # kind 0: not the sea
        fbo.use()
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.disable(moderngl.CULL_FACE)
        prog = self.program(self.variant(SURFACE_INPUTS, frame))
        u = self.uniforms
        prog.bind_textures({**u.wave_uniforms(prog), **u.dry_mask_textures(prog, frame)})
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
        vp = frame.camera.view_projection_relative(frame.aspect)
        viewport = tuple(float(s) for s in target.size)
        env = self.environment(frame)  # may render the probe now: before the target is bound
        target.use()
        spec = SHADE_ABOVE if self.view_mode() == 0 else SHADE
        shade = self.program(FLOATING_WAKE_MAP[spec.name] if wake_map is not None
                             else self.variant(spec, frame))
        textures = self.uniforms.surface_uniforms(shade, frame, env)
        if wake_map is not None:
            textures["uWakeMap"] = wake_map
            shade.set("uWakeStride", int(self.params["ocean.wake_stride"]))
        else:
            self.uniforms.wake_uniforms(shade, frame)
        textures.update({"uSceneCopy": scene_copy, **self._input_textures})
        shade.bind_textures(textures)
        shade.set_many({"uCameraPos": tuple(frame.camera.position), "uViewport": viewport,
                        "uViewMode": self.view_mode(), "uInvViewProjRel": np.linalg.inv(vp),
                        "uBand": (-1.0, 1.0), "uBandDepth": 1.0})
        with depth_tested(ctx, target.fbo, ">"):
            shade.vao().render(moderngl.TRIANGLE_STRIP, vertices=4)

    def render_underwater(self, frame, target) -> None:
        ctx = self.gpu.ctx
        color = self._color_copy.of(target)
        env = self.environment(frame)
        prog = self.program(UNDERWATER)
        textures = self.uniforms.surface_uniforms(prog, frame, env)
        prog.set_many(frame.camera_uniforms())
        vp = frame.camera.view_projection_relative(frame.aspect)
        prog.set("uInvViewProjRel", np.linalg.inv(vp))
        depth = target.depth
        old = depth.compare_func
        depth.compare_func = ""
        prog.bind_textures({**textures, "uColor": color, "uSceneDepth": depth})
        target.use()
        ctx.disable(moderngl.DEPTH_TEST)
        draw_fullscreen(prog)
        depth.compare_func = old

    def release(self) -> None:
        self._scene_copy.release()
        self._color_copy.release()
        self._flat_env = None

"""The procedural day–night sky of the maritime thesis (spec/000 §1.7, §2).

GPU side: ``glsl/sky/sky_radiance.glsl`` (the model, with its ``@param`` uniforms),
``sky.frag`` (what the camera sees) and the environment cubemap (``sky_cubemap.comp`` with
compute shaders, ``sky_face.frag`` without) that reflective effects read through the frame's
``environment`` slot. The cubemap is created on the first request and re-rendered (in the
environment stage) only when the hour, a sky parameter or the keyframes changed — the thesis's
reflection probe, rendered "only when needed".

Slots: produces ``hour``, ``sun``, ``moon``, ``main_light`` (sun by day, moon by night) and
``environment``.

CPU side: ``app.sim.daynight`` (hour, sun and moon, keyframes). The numpy twins the tests
compare the shader with are in ``app/sim/sky.py``.
"""

from __future__ import annotations

import moderngl

from ... import RESOURCES
from ...frame import Stage
from ...gpu.programs import ProgramSpec, draw_fullscreen, fullscreen
from ...gpu.targets import depth_tested
from ...params import Param, non_zero
from ...sim.daynight import DEFAULT_SUN_EXTINCTION, DayNight, Keyframes
from ...sim.sea_plane import GROUNDS, cox_munk_mss, ground_params
from ...sim.textures import cached_texture
from ..base import Effect, Pass

DEFAULT_KEYFRAMES = RESOURCES / "sky" / "keyframes.toml"

#: on the far plane: the sky draws after the opaque and water stages, only where they left it
SKY = ProgramSpec("sky/sky", vert="common/far_plane.vert", frag="sky/sky.frag")
SKY_FACE = fullscreen("sky/sky_face")
SKY_CUBEMAP = ProgramSpec("sky/sky_cubemap", requires_compute=True)

#: what the sky shows below the horizon (``sky.ground``; ``uGround`` in sky_radiance.glsl)
#: eye height (m) of the sea plane in the environment cubemap: a probe at sea level, so the
#: cubemap does not depend on the camera and is re-rendered only when the sky changes
CUBEMAP_EYE_HEIGHT = 2.0


class Sky(Effect):
    name = "sky"
    title = "Day–night sky"
    spec = "spec/000"
    programs = (SKY, SKY_FACE, SKY_CUBEMAP)
    extra_groups = ("time",)
    stages = (Stage.SKY, Stage.ENVIRONMENT)
    produces = frozenset({"hour", "sun", "moon", "main_light", "environment"})
    joints = (non_zero("sky.ecliptic", "axis"),)

    @classmethod
    def context_paths(cls, caps, params) -> dict[str, str]:
        return {"sky cubemap": "a compute shader" if caps.compute else
                "six fragment passes, each copied into its face on the GPU"}

    @classmethod
    def python_params(cls) -> list[Param]:
        s = "spec/000 §1.7"
        return [
            Param("time.hour", 12.0, 0.0, 24.0, "hour of day (SkyboxController.Time), wraps into "
                  "[0, 24)", step=0.05, unit="h", section=s),
            Param("time.playing", False, doc="time advances (SkyboxController.IsPlaying)",
                  kind="bool", section=s),
            Param("time.speed", 0.25, 0.0, 24.0, "hours of sky time per second (Planet Rotation "
                  "Speed)", step=0.01, unit="h/s", section=s),
            Param("sky.ecliptic", (0.0, 0.6, -1.0), -1.0, 1.0,
                  "Earth's rotation axis (Ecliptic): tilt toward north (−z) sets the noon sun "
                  "height", kind="vec3", step=0.01, section=s),
            Param("sky.moon_light", 0.08, 0.0, 1.0, "main-light intensity of the moon relative to "
                  "the sun", step=0.01, section=s),
            Param("sky.sun_extinction", DEFAULT_SUN_EXTINCTION, 0.0, 2.0,
                  "beyond the thesis: zenith optical depth per channel (R, G, B) that reddens the "
                  "sun and the main light toward the horizon (Kasten–Young air mass, relative to "
                  "the zenith); default Rayleigh (Hansen–Travis) + clear maritime aerosol "
                  "(Ångström β 0.05, α 1) at 680/550/440 nm; 0 = the thesis's constant colour",
                  kind="vec3", step=0.01, section=s),
            *ground_params("sky", s, "the thesis's clamped horizon colour (times "
                           "sky.below_horizon)", "the sky"),
            Param("sky.star_seed", 7, 0, 2**31 - 1, "seed of the procedural star field", kind="int",
                  section=s),
            Param("sky.cubemap_size", 128, 8, 2048, "environment cubemap face size (reflection "
                  "probe)", kind="int", step=8, unit="px", section=s),
        ]

    def __init__(self, gpu, params, keyframes: Keyframes | None = None):
        super().__init__(gpu, params)
        self.keyframes = keyframes or Keyframes.load(DEFAULT_KEYFRAMES)
        self.state = None
        self._state_key: tuple | None = None  # (hour, sky settings, keyframes) of self.state
        self.environment_renders = 0
        self._gradient = None
        self._gradient_version = None
        self._stars = self.keyed(self._make_stars, release=gpu.free)
        self._moon = self.keyed(self._make_moon, release=gpu.free)
        #: the environment cubemaps (with and without the sun), remade when their size changes
        self._cubes = {sun: self.keyed(lambda size, sun=sun: self._make_cube(size, sun),
                                       release=gpu.free)
                       for sun in (True, False)}
        self._cube_rendered: dict[bool, tuple | None] = {True: None, False: None}
        self._probe = _SkyProbe(self)

    def daynight(self) -> DayNight:
        p = self.params
        return DayNight(
            keyframes=self.keyframes,
            hour=p["time.hour"],
            ecliptic=p["sky.ecliptic"],
            speed=p["time.speed"],
            playing=p["time.playing"],
            sun_color=p["sky.sun_color"],
            moon_color=p["sky.moon_color"],
            moon_light=p["sky.moon_light"],
            sun_extinction=p["sky.sun_extinction"],
        )

    def update(self, frame, dt: float) -> None:
        dn = self.daynight()
        dn.advance(dt)
        if dn.hour != self.params["time.hour"]:
            self.params.set("time.hour", dn.hour)
        key = (dn.hour, self.params.version("sky"), id(self.keyframes), self.keyframes.version)
        if key != self._state_key:  # a standing clock and unchanged settings: the same state
            self.state = dn.state()
            self._state_key = key
        frame.hour = self.state.hour
        frame.sun, frame.moon, frame.main_light = (self.state.sun, self.state.moon,
                                                   self.state.main_light)
        frame.environment = self._probe

    def panel_items(self) -> list:
        return [self.keyframes]

    def _textures(self) -> None:
        gpu = self.gpu
        if self._gradient is None or self._gradient_version != self.keyframes.version:
            data = self.keyframes.texture_data()
            if self._gradient is not None and self._gradient.size == (data.shape[1], data.shape[0]):
                self._gradient.write(data.tobytes())
            else:
                if self._gradient is not None:
                    gpu.free(self._gradient)
                self._gradient = gpu.texture(self.name, "sky gradient keyframes",
                                             (data.shape[1], data.shape[0]), 4, data.tobytes())
            self._gradient_version = self.keyframes.version

    def _make_stars(self, seed: int):
        from ...bakes.cache import default_cache_dir  # $NATURA_CACHE, beside the noise bakes

        stars = cached_texture("stars", default_cache_dir(), seed=int(seed))
        return self.gpu.texture(self.name, "stars", (stars.shape[1], stars.shape[0]), 1,
                                stars.tobytes(), repeat=True)

    def _make_moon(self, _key):
        from ...bakes.cache import default_cache_dir

        moon = cached_texture("moon", default_cache_dir())
        return self.gpu.texture(self.name, "moon", (moon.shape[1], moon.shape[0]), 4,
                                moon.tobytes())

    def _bind(self, prog) -> None:
        st = self.state
        self._textures()
        prog.bind_textures({"uSkyGradient": self._gradient,
                            "uStarTex": self._stars.get(self.params["sky.star_seed"]),
                            "uMoonTex": self._moon.get(None)})
        rows = self._gradient.size[1]
        i0, i1, t = st.keyframe_rows
        prog.set_many({
            "uGradientRows": ((i0 + 0.5) / rows, (i1 + 0.5) / rows),
            "uGradientMix": t,
            "uGradientTexels": float(self._gradient.size[0]),
            "uKeyframeStars": st.stars,
            "uSunDir": tuple(st.sun_dir),
            "uMoonDir": tuple(st.moon_dir),
            "uWorldToMoon": st.world_to_moon,
            "uMainLightDir": tuple(float(v) for v in st.main_light.direction),
            "uMainLightRadiance": tuple(float(v) for v in st.main_light.radiance),
            "uSkyAmbient": tuple(float(v) for v in st.main_light.ambient or (0.0, 0.0, 0.0)),
            "uGround": GROUNDS.index(self.params["sky.ground"]),
            "uSeaMss": cox_munk_mss(self.params["sky.sea_wind"]),
            "uEyeHeight": CUBEMAP_EYE_HEIGHT,
            "uSeaGlitter": 1.0,
        })
        self.apply_params(prog)
        prog.set("uSunColor", tuple(st.sun.color))  # reddened by sky.sun_extinction (no-op at 0)

    def draw(self, frame, target) -> None:
        prog = self.program(SKY)
        self._bind(prog)
        prog.set_many(frame.camera_uniforms())
        prog.set("uEyeHeight", max(float(frame.camera.position[1]), 0.5))
        target.use()
        # the sky stage: only the pixels still on the far plane (nothing drawn there) are
        # shaded, and the depth is left as it is
        with depth_tested(self.gpu.ctx, target.fbo):
            draw_fullscreen(prog)

    def environment_key(self) -> tuple:
        return (round(self.state.hour, 6), self.params.version("sky"), self.keyframes.version)

    def environment(self, frame=None, force: bool = False, sun: bool = True):
        """The sky as a cubemap for reflections; re-rendered only when it changed.

        ``sun=False`` gives a second cubemap without the sun disk, for surfaces that light the sun
        analytically (the ocean's glitter): blurred mip levels of a map with a 400× sun smear it
        over one cube face, which shows as bright wedges in rough reflections."""
        cube = self._cubes[sun].get(self.params["sky.cubemap_size"])
        key = self.environment_key()
        if force or key != self._cube_rendered[sun]:
            self._render_cubemap(cube, sun=sun)
            self._cube_rendered[sun] = key
            self.environment_renders += 1
        return cube

    def _make_cube(self, size: int, sun: bool):
        cube = self.gpu.texture_cube(self.name,
                                     "environment" if sun else "environment without the sun", size)
        cube.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
        self._cube_rendered[sun] = None
        return cube

    def _render_cubemap(self, cube, use_compute: bool | None = None, sun: bool = True) -> None:
        """Render the sky into ``cube`` and build its mip levels."""
        size = cube.size[0]
        ctx = self.gpu.ctx
        if use_compute is None:
            use_compute = self.gpu.caps.compute
        prog = self.program(SKY_CUBEMAP if use_compute else SKY_FACE)
        self._bind(prog)
        if not sun:
            prog.set_many({"uSunIntensity": 0.0, "uSeaGlitter": 0.0})
        if use_compute:
            prog.set("uFaceSize", size)
            cube.bind_to_image(0, read=False, write=True)
            groups = (size + 7) // 8
            prog.program.run(groups, groups, 6)
            ctx.memory_barrier()
        else:
            # one face at a time into a float target, copied into the cube on the GPU; the
            # caller's framebuffer (this runs on request, inside its pass) is given back
            with self.gpu.keep_framebuffer():
                with self.gpu.scratch_target(self.name, "cubemap face", (size, size), dtype="f4",
                                             depth=False) as face_target:
                    for face in range(6):
                        face_target.use()
                        prog.set("uFace", face)
                        draw_fullscreen(prog)
                        self.gpu.copy_to_cube_face(cube, face, 0, size)
        cube.build_mipmaps()

    def refresh_environment(self) -> None:
        """Re-render the cubemaps made so far whose sky changed (the environment stage)."""
        for sun in (True, False):
            if self._cubes[sun].built:
                self.environment(sun=sun)

    def passes(self, frame, target) -> list[Pass]:
        out = [Pass("sky", lambda: self.draw(frame, target), Stage.SKY)]
        if self._cubes[True].built or self._cubes[False].built:
            out.append(Pass("sky.environment", self.refresh_environment, Stage.ENVIRONMENT))
        return out

    def bench_passes(self, frame, target) -> list[Pass]:
        out = self.passes(frame, target)
        if self._cubes[True].built:
            out.append(Pass("sky.cubemap", lambda: self.environment(frame, force=True),
                            Stage.ENVIRONMENT))
        if self._cubes[False].built:
            out.append(Pass("sky.cubemap (no sun)",
                            lambda: self.environment(frame, force=True, sun=False),
                            Stage.ENVIRONMENT))
        return out


class _SkyProbe:
    """The sky as the frame's ``environment`` slot (an :class:`app.frame.Environment`)."""

    def __init__(self, sky: Sky):
        self._sky = sky

    def cubemap(self, sun: bool = True):
        return self._sky.environment(sun=sun)

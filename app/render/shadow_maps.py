"""The shared shadow maps of every scene (spec/003 §2.8): a directional light's cascades, a spot
light's perspective map and a point light's six faces, all drawn with the one caster program
``common/shadow_caster`` (normal and linear biases, alpha cutout, dithered semitransparent
shadows) and read by ``glsl/common/shadow.glsl``.

Each class renders only when its key (the light, the settings, the camera for cascades and the
caller's caster revision) changed, and ``bind(program)`` sets every uniform shadow.glsl
declares for its light, returning the textures by sampler name for ``Program.bind_textures``
(which assigns the units: merge the dicts of every light and bind once).

Layouts: the sun's cascades share one depth atlas (``size``²; one tile for 0 cascades, a 2 × 2
grid of ``size``/2 tiles for 2 or 4: equal texel count whatever the cascade count) plus an
RG32F atlas of depth moments for VSM; the point light's faces lie in a 3 × 2 atlas of RG32F
(|l| + bias)/range with a depth buffer (a cube map emulated in 2D: the receiver picks the face).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import moderngl
import numpy as np

from ..gpu.programs import ProgramSpec
from ..sim import shadows as sh
from ..sim.maths import look_at, perspective
from .shadows import SHADOW_FILTERS, SHADOW_TAPS, ShadowSettings

CASTER = ProgramSpec("common/shadow_caster")
#: toward +x −x +y −y +z −z, with each face's up vector
CUBE_FACES = (((1, 0, 0), (0, -1, 0)), ((-1, 0, 0), (0, -1, 0)), ((0, 1, 0), (0, 0, 1)),
              ((0, -1, 0), (0, 0, -1)), ((0, 0, 1), (0, -1, 0)), ((0, 0, -1), (0, -1, 0)))

Casters = Callable[[Any], None]


def tile_matrix(tile) -> np.ndarray:
    """Clip → atlas (u, v, depth): NDC to [0, 1] then into the tile (u0, v0, u1, v1)."""
    u0, v0, u1, v1 = tile
    m = np.identity(4)
    m[0, 0], m[0, 3] = 0.5 * (u1 - u0), u0 + 0.5 * (u1 - u0)
    m[1, 1], m[1, 3] = 0.5 * (v1 - v0), v0 + 0.5 * (v1 - v0)
    m[2, 2], m[2, 3] = 0.5, 0.5
    return m


def _draw(ctx, fbo, viewport, prog, casters: Casters) -> None:
    fbo.use()
    fbo.viewport = viewport
    ctx.enable(moderngl.DEPTH_TEST)
    ctx.disable(moderngl.CULL_FACE)
    casters(prog)


class _Map:
    def __init__(self, gpu, owner: str, name: str):
        self.gpu, self.owner, self.name = gpu, owner, name
        self.size = 0
        self.key: Any = None
        self.renders = 0
        self.depth: Any = None
        self.colour: Any = None
        self.fbo: Any = None
        self.settings: ShadowSettings | None = None

    def _alloc(self, shape: tuple[int, int]) -> None:
        if self.fbo is not None and self.depth.size == shape:
            return
        self.release()
        self.depth = self.gpu.depth_texture(self.owner, f"{self.name} depth", shape)
        self.depth.compare_func = ""
        self.depth.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self.colour = self.gpu.texture(self.owner, f"{self.name} moments", shape, 2, dtype="f4")
        self.fbo = self.gpu.framebuffer(self.owner, self.name, [self.colour], self.depth)
        self.key = None

    def caster(self):
        return self.gpu.program(self.owner, CASTER)

    def taps_code(self) -> int:
        """shadow.glsl's ``uShadow*Taps`` of the last settings: ``auto`` resolved from the
        context (fast on a software renderer)."""
        return 0 if self.settings is None else self.settings.taps_code(self.gpu.caps.software)

    def release(self) -> None:
        for obj in (self.fbo, self.colour, self.depth):
            if obj is not None:
                self.gpu.free(obj)
        self.fbo = self.colour = self.depth = None

    def read_depth(self) -> np.ndarray:
        """The depth atlas as (h, w) float32, row 0 at v = 0."""
        w, h = self.depth.size
        return np.frombuffer(self.depth.read(), np.float32).reshape(h, w).copy()


class DirectionalShadow(_Map):
    """The sun's orthographic map: one over ``settings.fixed_centre``/``fixed_radius`` (0
    cascades) or 2 / 4 cascades over the camera frustum up to ``settings.distance``.

    PCSS's penumbra (:meth:`pcss_scales`): a light of angular radius θ (``pcss_light_size`` =
    tan θ) at infinity casts, from a blocker D metres above the receiver, a penumbra
    2 D tan θ wide, whatever the map's fit. With ``pcss_world`` false the former width,
    ∝ (d_r − d_b)/d_b of the map's normalised depths (a perspective light's formula), which
    changes with the fit radius and the near-plane offset: kept for the bench's before/after."""

    def __init__(self, gpu, owner: str):
        super().__init__(gpu, owner, "sun shadow")
        self.pcss_world = True
        self.matrices: list[np.ndarray] = []
        self.tiles: list[tuple[float, float, float, float]] = []
        self.splits = np.zeros(4)
        self.texel_world: list[float] = []
        self.depth_range: list[float] = []
        self.settings: ShadowSettings | None = None

    def fit(self, camera, aspect: float, toward_light, settings: ShadowSettings):
        """(clip matrices per cascade, tiles, split far ends, texel sizes, depth ranges)."""
        n = settings.cascades
        tile_n = settings.map_size if n == 0 else settings.map_size // 2
        grid = [(0.0, 0.0, 1.0, 1.0)] if n == 0 else [
            (0.5 * (i % 2), 0.5 * (i // 2), 0.5 * (i % 2) + 0.5, 0.5 * (i // 2) + 0.5)
            for i in range(n)]
        pad = settings.near_offset
        mats, texels, ranges = [], [], []
        if n == 0:
            ends = np.array([settings.distance])
            r = settings.fixed_radius
            mats.append(sh.ortho_fit(toward_light, settings.fixed_centre, r, tile_n, True, pad))
            texels.append(2 * r / tile_n)
            ranges.append(2 * r + pad)
        else:
            near = max(camera.near, 1e-3)
            far = max(min(camera.far, settings.distance), near)
            ends = sh.cascade_splits(near, far, n, settings.split_lambda)
            view = camera.view_matrix()
            z0 = near
            for z1 in ends:
                if settings.stable_fit:
                    c, r = sh.bounding_sphere(view, camera.fov, aspect, z0, z1)
                    m = sh.ortho_fit(toward_light, c, r, tile_n, True, pad)
                else:
                    corners = sh.frustum_corners(view, camera.fov, aspect, z0, z1)
                    m = sh.tight_fit(toward_light, corners, tile_n, pad)
                    r = 1.0 / m[0, 0]
                mats.append(m)
                texels.append(2 * r / tile_n)
                ranges.append(2 * r + pad)
                z0 = z1
        return mats, grid, ends, texels, ranges

    def render(self, casters: Casters, camera, aspect: float, toward_light,
               settings: ShadowSettings, revision: int = 0) -> bool:
        """Bring the map up to date; True when it was re-rendered."""
        self.settings = settings
        toward_light = np.asarray(toward_light, np.float64)
        if not np.all(np.isfinite(toward_light)) or np.linalg.norm(toward_light) < 1e-9:
            raise ValueError(f"sun direction {toward_light}: allowed a finite non-zero vector")
        toward_light = toward_light / np.linalg.norm(toward_light)
        cam_key = ((tuple(camera.position), camera.yaw, camera.pitch, camera.fov, camera.near,
                    camera.far, aspect) if settings.cascades else None)
        key = (tuple(np.round(toward_light, 9)), settings.map_key(), cam_key, revision)
        if not settings.sun_enabled:
            return False
        self._alloc((settings.map_size, settings.map_size))
        mats, tiles, ends, texels, ranges = self.fit(camera, aspect, toward_light, settings)
        if settings.stable_fit and settings.cascades:
            # a stable map only changes when a cascade's snapped matrix does
            snapped = tuple(np.round(np.concatenate([m.ravel() for m in mats]), 7))
            key = (key[0], settings.map_key(), snapped, revision)
        if key == self.key:
            return False
        self.key = key
        self.matrices = [tile_matrix(t) @ m for t, m in zip(tiles, mats)]
        self.tiles = tiles
        self.splits = np.full(4, ends[-1])
        self.splits[:len(ends)] = ends
        self.texel_world, self.depth_range = texels, ranges
        ctx = self.gpu.ctx
        self.fbo.use()
        self.fbo.viewport = (0, 0, settings.map_size, settings.map_size)
        self.fbo.clear(1.0, 1.0, 0.0, 1.0, depth=1.0)
        prog = self.caster()
        prog.set_many({"uShadowCasterLight": toward_light, "uShadowCasterKind": 0,
                       "uShadowCasterNormalBias": settings.normal_bias * sh.NORMAL_BIAS_TEXELS,
                       "uShadowCasterLinearBias": settings.linear_bias * sh.LINEAR_BIAS_TEXELS})
        size = settings.map_size
        for m, t, tw in zip(mats, tiles, texels):
            prog.set_many({"uShadowCasterViewProj": m, "uShadowCasterTexel": tw})
            vp = (int(t[0] * size), int(t[1] * size), int((t[2] - t[0]) * size),
                  int((t[3] - t[1]) * size))
            _draw(ctx, self.fbo, vp, prog, casters)
        self.fbo.viewport = (0, 0, size, size)
        self.renders += 1
        return True

    def pcss_scales(self, light_size: float) -> list[float]:
        """shadow.glsl's ``uShadowSunPcssScale`` per cascade: texels of penumbra per unit of
        normalised depth between blocker and receiver — 2 tan θ × the depth range (m) / the
        texel's size (m) (:func:`app.sim.shadows.pcss_penumbra_parallel` in texels); the former
        scale (``pcss_world`` false) is tan θ × range / texel, divided by d_b in the shader."""
        k = 2.0 if self.pcss_world else 1.0
        return [k * light_size * dr / max(tw, 1e-9)
                for dr, tw in zip(self.depth_range, self.texel_world)]

    def bind(self, program) -> dict[str, Any]:
        s = self.settings
        on = bool(s is not None and s.sun_enabled and self.fbo is not None)
        program.set("uShadowSunEnabled", on)
        if not on or s is None:
            return {}
        mats = list(self.matrices) + [self.matrices[-1]] * (4 - len(self.matrices))
        tiles = list(self.tiles) + [self.tiles[-1]] * (4 - len(self.tiles))
        program.set("uShadowSunMatrix", np.hstack(mats))  # column-major mat4 array
        program.set_array("uShadowSunTile", tiles)
        pcss = self.pcss_scales(s.pcss_light_size)
        program.set_many({
            "uShadowSunSplits": tuple(float(v) for v in self.splits),
            "uShadowSunCascades": len(self.matrices), "uShadowSunFilter": s.filter_index,
            "uShadowSunPcssScale": tuple((pcss + [pcss[-1]] * 4)[:4]),
            "uShadowSunPcssFit": not self.pcss_world,
            "uShadowSunVsmBlur": s.vsm_blur, "uShadowSunVsmBleed": s.vsm_bleed,
            "uShadowSunStrength": s.strength,
            "uShadowSunTexelWorld": tuple((list(self.texel_world) * 4)[:4]),
            "uShadowSunTaps": self.taps_code()})
        return {"uShadowSunMap": self.depth, "uShadowSunMoments": self.colour}


class SpotShadow(_Map):
    """A spot light's perspective map (the caster is the directional one's, spec/003 §2.8)."""

    def __init__(self, gpu, owner: str):
        super().__init__(gpu, owner, "spot shadow")
        self.matrix = np.identity(4)
        self.settings: ShadowSettings | None = None
        self.texel_per_m = 0.0
        self.position = np.zeros(3)

    def render(self, casters: Casters, position, direction, half_angle_deg: float,
               light_range: float, settings: ShadowSettings, revision: int = 0) -> bool:
        self.settings = settings
        if not settings.spot_enabled:
            return False
        pos = np.asarray(position, np.float64)
        d = np.asarray(direction, np.float64)
        d = d / np.linalg.norm(d)
        key = (tuple(pos), tuple(d), half_angle_deg, light_range, settings.map_key(), revision)
        size = settings.map_size
        self._alloc((size, size))
        if key == self.key:
            return False
        self.key = key
        up = np.array([0.0, 1.0, 0.0]) if abs(d[1]) < 0.99 else np.array([0.0, 0.0, 1.0])
        near = max(light_range * 1e-3, 0.02)
        vp = perspective(2 * half_angle_deg, 1.0, near, light_range) @ look_at(pos, pos + d, up)
        self.matrix = tile_matrix((0, 0, 1, 1)) @ vp
        self.texel_per_m = 2 * np.tan(np.radians(half_angle_deg)) / size
        self.position = pos
        self.fbo.use()
        self.fbo.clear(1.0, 1.0, 0.0, 1.0, depth=1.0)
        prog = self.caster()
        prog.set_many({"uShadowCasterLight": pos, "uShadowCasterKind": 1,
                       "uShadowCasterNormalBias": settings.normal_bias * sh.NORMAL_BIAS_TEXELS,
                       "uShadowCasterLinearBias": settings.linear_bias * sh.LINEAR_BIAS_TEXELS,
                       "uShadowCasterTexel": self.texel_per_m, "uShadowCasterViewProj": vp})
        _draw(self.gpu.ctx, self.fbo, (0, 0, size, size), prog, casters)
        self.renders += 1
        return True

    def bind(self, program) -> dict[str, Any]:
        s = self.settings
        on = bool(s is not None and s.spot_enabled and self.fbo is not None)
        program.set("uShadowSpotEnabled", on)
        if not on or s is None:
            return {}
        program.set_many({"uShadowSpotMatrix": self.matrix, "uShadowSpotFilter": s.filter_index,
                          "uShadowSpotPcssScale": s.pcss_light_size * 16.0,
                          "uShadowSpotVsmBlur": s.vsm_blur, "uShadowSpotVsmBleed": s.vsm_bleed,
                          "uShadowSpotStrength": s.strength,
                          "uShadowSpotTexelPerM": self.texel_per_m,
                          "uShadowSpotPosition": self.position,
                          "uShadowSpotTaps": self.taps_code()})
        return {"uShadowSpotMap": self.depth, "uShadowSpotMoments": self.colour}


class PointShadow(_Map):
    """A point light's six 90° faces in a 3 × 2 atlas of (|l| + linear bias)/range."""

    def __init__(self, gpu, owner: str):
        super().__init__(gpu, owner, "point shadow")
        self.faces: list[np.ndarray] = []
        self.position = np.zeros(3)
        self.range = 1.0
        self.settings: ShadowSettings | None = None

    @staticmethod
    def face_tile(f: int) -> tuple[float, float, float, float]:
        return ((f % 3) / 3, (f // 3) / 2, (f % 3 + 1) / 3, (f // 3 + 1) / 2)

    def render(self, casters: Casters, position, light_range: float, settings: ShadowSettings,
               revision: int = 0) -> bool:
        self.settings = settings
        if not settings.point_enabled:
            return False
        pos = np.asarray(position, np.float64)
        face = max(settings.map_size // 2, 16)
        self._alloc((3 * face, 2 * face))
        key = (tuple(pos), light_range, settings.map_key(), revision)
        if key == self.key:
            return False
        self.key, self.position, self.range = key, pos, float(light_range)
        near = max(light_range * 1e-3, 0.02)
        proj = perspective(90.0, 1.0, near, light_range)
        self.fbo.use()
        self.fbo.viewport = (0, 0, 3 * face, 2 * face)
        self.fbo.clear(1.0, 1.0, 0.0, 1.0, depth=1.0)
        prog = self.caster()
        prog.set_many({"uShadowCasterLight": pos, "uShadowCasterKind": 2,
                       "uShadowCasterRange": float(light_range),
                       "uShadowCasterPointBias":
                           settings.linear_bias * sh.LINEAR_BIAS_TEXELS * 2.0 / face,
                       "uShadowCasterNormalBias": settings.normal_bias * sh.NORMAL_BIAS_TEXELS,
                       "uShadowCasterLinearBias": 0.0, "uShadowCasterTexel": 2.0 / face})
        self.faces = []
        for f, (d, up) in enumerate(CUBE_FACES):
            vp = proj @ look_at(pos, pos + np.asarray(d, float), np.asarray(up, float))
            t = self.face_tile(f)
            self.faces.append(tile_matrix(t) @ vp)
            prog.set("uShadowCasterViewProj", vp)
            _draw(self.gpu.ctx, self.fbo, ((f % 3) * face, (f // 3) * face, face, face), prog,
                  casters)
        self.fbo.viewport = (0, 0, 3 * face, 2 * face)
        self.renders += 1
        return True

    def bind(self, program) -> dict[str, Any]:
        s = self.settings
        on = bool(s is not None and s.point_enabled and self.fbo is not None)
        program.set("uShadowPointEnabled", on)
        if not on or s is None:
            return {}
        program.set("uShadowPointFace", np.hstack(self.faces))
        program.set_many({"uShadowPointPosition": self.position, "uShadowPointRange": self.range,
                          "uShadowPointFilter": min(s.filter_index, 2),
                          "uShadowPointStrength": s.strength,
                          "uShadowPointTexelPerM": 2.0 / (self.colour.size[1] / 2),
                          "uShadowPointTaps": self.taps_code()})
        return {"uShadowPointMap": self.colour}


def frame_entry(light: str, kind: str, m: _Map, view_proj) -> Any:
    """The :class:`app.frame.ShadowMap` of one map (for ``frame.shadows[light]``): its depth
    atlas (the point light's (|l| + bias)/range atlas), first world → map matrix, and the
    map's own ``bind`` (every shadow.glsl uniform of the light, for another effect's program)."""
    from ..frame import ShadowMap

    tex = m.colour if kind == "point" else m.depth
    bias = m.settings.linear_bias if m.settings is not None else 0.0
    defines = receiver_defines(m.settings, m.gpu.caps.software) if m.settings else ()
    return ShadowMap(light, kind, tex, np.asarray(view_proj), bias,
                     bind=getattr(m, "bind", None), defines=defines)


#: shadow.glsl's switch of each light kind
_ENABLED = {"directional": "uShadowSunEnabled", "spot": "uShadowSpotEnabled",
            "point": "uShadowPointEnabled"}


def bind_published(program, shadows: dict) -> dict[str, Any]:
    """Bind a frame's ``shadows`` slot to a program that includes ``glsl/common/shadow.glsl``:
    every light kind off first, then each published map that shadow.glsl reads sets its own
    uniforms; returns their textures by sampler name (for one ``bind_textures`` call). A
    consumer of the slot (grass, water) receives the producer's shadows without knowing it."""
    for name in _ENABLED.values():
        program.set(name, False)
    textures: dict[str, Any] = {}
    for entry in shadows.values():
        if getattr(entry, "bind", None) is not None and entry.kind in _ENABLED:
            textures.update(entry.bind(program))
    return textures


def published_defines(shadows: dict) -> tuple[tuple[str, int], ...]:
    """The :func:`receiver_defines` every map of a frame's ``shadows`` slot was bound with, for
    a consumer's program (none when the maps disagree or none is published)."""
    found = {entry.defines for entry in shadows.values() if entry.defines}
    return found.pop() if len(found) == 1 else ()


def receiver_defines(settings, software: bool) -> tuple[tuple[str, int], ...]:
    """The defines that specialise a receiver program (glsl/common/shadow.glsl's header) to
    ``settings`` (a :class:`ShadowSettings`, or None for the default filter and full taps):
    ``SHADOW_FILTER`` and ``SHADOW_TAPS`` (``auto`` resolved by ``software``, as ``bind``
    does). The filters the receiver does not use are compiled out; ``bind`` still sets every
    uniform, so the specialised program and the generic one draw the same image. Every
    combination is one of :func:`receiver_variants`."""
    if settings is None:
        settings = ShadowSettings()
    return (("SHADOW_FILTER", settings.filter_index), ("SHADOW_TAPS", settings.taps_code(software)))


def receiver_variants(spec: ProgramSpec) -> tuple[ProgramSpec, ...]:
    """``spec`` with every :func:`receiver_defines` there is (5 filters × 2 tap sets): what an
    effect that draws its receivers specialised lists in its ``programs``, so ``natura shaders
    check`` compiles each one."""
    return tuple(ProgramSpec(spec.name, spec.vert, spec.frag, spec.comp,
                             spec.defines + (("SHADOW_FILTER", f), ("SHADOW_TAPS", t)),
                             spec.requires_compute)
                 for f in range(len(SHADOW_FILTERS)) for t in range(len(SHADOW_TAPS)))


class ShadowSet:
    """The three lights of a scene: ``bind(program)`` sets every light's uniforms (a light never
    rendered reads as disabled) and returns all their textures by sampler name."""

    def __init__(self, gpu, owner: str):
        self.sun = DirectionalShadow(gpu, owner)
        self.spot = SpotShadow(gpu, owner)
        self.point = PointShadow(gpu, owner)

    def bind(self, program) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for m in (self.sun, self.spot, self.point):
            out.update(m.bind(program))
        return out

    def defines(self) -> tuple[tuple[str, int], ...]:
        """:func:`receiver_defines` of the settings the maps were last given (one set for the
        three lights, as every scene uses them)."""
        settings = next((m.settings for m in (self.sun, self.spot, self.point)
                         if m.settings is not None), None)
        return receiver_defines(settings, self.sun.gpu.caps.software)

    def publish(self, frame) -> None:
        """Put every rendered map in ``frame.shadows`` ("sun", "spot", "point")."""
        if self.sun.fbo is not None and self.sun.matrices:
            frame.shadows["sun"] = frame_entry("sun", "directional", self.sun,
                                               self.sun.matrices[0])
        if self.spot.fbo is not None:
            frame.shadows["spot"] = frame_entry("spot", "spot", self.spot, self.spot.matrix)
        if self.point.fbo is not None and self.point.faces:
            frame.shadows["point"] = frame_entry("point", "point", self.point,
                                                 self.point.faces[0])

    def release(self) -> None:
        for m in (self.sun, self.spot, self.point):
            m.release()


def render_depth_pass(ctx, fbo, prog, draw: Callable[[], None]) -> None:
    """One depth-only pass into ``fbo`` (cleared to 1, depth test on, no culling), the shared
    entry the planet's sun map is drawn through."""
    fbo.use()
    fbo.clear(depth=1.0)
    ctx.enable(moderngl.DEPTH_TEST)
    ctx.disable(moderngl.CULL_FACE)
    draw()


PROBE = ProgramSpec("common/shadow_probe", vert="common/fullscreen.vert",
                    frag="common/shadow_probe.frag")


class MeshCasters:
    """A ``casters(program)`` callable over LabMeshes (world space): each with its alpha mode,
    opacity, cutoff and alpha texture (RGBA uint8 array or None) — what tests and the bench
    hand to the maps (a scene's effect provides its own)."""

    def __init__(self, gpu, owner: str, items):
        self.gpu, self.owner = gpu, owner
        self.items = []
        white = np.full((1, 1, 4), 255, np.uint8)
        for mesh, mode, opacity, cutoff, alpha in items:
            vbo = gpu.buffer(owner, f"{mesh.name} caster vbo", mesh.vertex_data())
            ibo = gpu.buffer(owner, f"{mesh.name} caster ibo", mesh.indices.astype("u4").tobytes())
            a = white if alpha is None else np.ascontiguousarray(alpha, np.uint8)
            tex = gpu.texture(owner, f"{mesh.name} alpha", (a.shape[1], a.shape[0]), 4,
                              data=a.tobytes(), dtype="f1")
            self.items.append((vbo, ibo, int(mode), float(opacity), float(cutoff), tex))

    def __call__(self, program) -> None:
        for vbo, ibo, mode, opacity, cutoff, tex in self.items:
            program.set_many({"uAlphaMode": mode, "uOpacity": opacity, "uCutoff": cutoff})
            program.bind_textures({"uAlphaTex": tex})
            program.vao([(vbo, "3f 3f 2f", "in_position", "in_normal", "in_uv")],
                        index_buffer=ibo).render(moderngl.TRIANGLES)


class ShadowProbe:
    """shadow.glsl's receivers at given points: ``visibility(shadows, points, normals,
    view_depth, light)`` → (visibility, cascade) arrays of the points' shape."""

    def __init__(self, gpu, owner: str):
        self.gpu, self.owner = gpu, owner

    def visibility(self, shadow_set: ShadowSet, points, normals, view_depth=None,
                   light: str = "sun") -> tuple[np.ndarray, np.ndarray]:
        lights = ("sun", "spot", "point")
        if light not in lights:
            raise ValueError(f"probe light {light!r}: allowed {', '.join(lights)}")
        p = np.asarray(points, np.float32).reshape(-1, 3)
        count = len(p)
        w = min(count, 1024)
        h = -(-count // w)
        pts = np.full((h * w, 4), -1.0, np.float32)
        nrm = np.zeros((h * w, 4), np.float32)
        pts[:count, :3] = p
        pts[:count, 3] = (np.zeros(count) if view_depth is None
                          else np.asarray(view_depth, np.float32).ravel())
        nrm[:count, :3] = np.asarray(normals, np.float32).reshape(-1, 3)
        nrm[:count, 3] = 1.0  # a point is there
        g = self.gpu
        tp = g.texture(self.owner, "probe points", (w, h), 4, data=pts.tobytes())
        tn = g.texture(self.owner, "probe normals", (w, h), 4, data=nrm.tobytes())
        out = g.texture(self.owner, "probe out", (w, h), 4)
        fbo = g.framebuffer(self.owner, "probe", [out])
        try:
            prog = g.program(self.owner, PROBE)
            textures = shadow_set.bind(prog)
            prog.set("uLight", lights.index(light))
            prog.bind_textures({"uPoints": tp, "uNormals": tn, **textures})
            fbo.use()
            fbo.viewport = (0, 0, w, h)
            g.ctx.disable(moderngl.DEPTH_TEST)
            prog.vao().render(moderngl.TRIANGLES, vertices=3)
            res = np.frombuffer(out.read(), np.float32).reshape(-1, 4)[:count]
        finally:
            for obj in (fbo, out, tp, tn):
                g.free(obj)
        shape = np.asarray(points).shape[:-1]
        return res[:, 0].reshape(shape), res[:, 1].astype(np.int64).reshape(shape)

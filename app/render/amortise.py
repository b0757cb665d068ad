"""Amortised rendering of an expensive full-screen layer, as the field renders its clouds (beyond
the theses; after Schneider 2015, "The real-time volumetric cloudscapes of Horizon: Zero Dawn"):
a fraction of the pixels is marched per frame at a reduced resolution, with blue-noise
jittered rays, and the rest is reprojected from the last frame or filled by depth-aware
upsampling. Effect-agnostic: both cloud models use it (``clouds.reprojection``,
``clouds_b.reprojection`` and their ``march_scale`` and ``refresh``). The numpy side — the
schedule, the blue noise, the rejection rules and the twins of the shader's filling — is
:mod:`app.sim.amortise` (its docstring has the scheme); the shaders are
``glsl/common/amortise.glsl`` (the march's side) and ``glsl/common/amortise_resolve.frag``.

What an effect does: declare :func:`amortise_params` and list :data:`PROGRAMS` in its
programs; march in a shader that includes ``amortise.glsl`` (``AmortisedPixel()``, the jitter
``AmortiseJitter(pixel)``, ``AmortiseAux(cloud distance, scene distance)`` at location 1); and
derive from :class:`app.render.layers.MarchedLayer`, whose ``render_layer`` runs
:meth:`Amortiser.render` (its ``march(grid, depth)`` binds ``grid.textures``, sets
``grid.uniforms`` and draws into ``grid``) and whose ``composite`` skips the near cut.

Still renders (``frame.interactive`` false: ``natura render``, the gallery, the tests, the
bench) converge before they return: the first render of a view resets the history with one
march of every full-resolution pixel (a grid at block 1) and its resolve — the state the window
reaches after ``schedule.cycle`` frames of a still camera, bit for bit, since a pixel's ray
depends on its full-resolution position only — so a still image is the full-resolution march
itself (with its blue-noise jitter). Rendering the same view again (the bench's repeated frame)
runs one ordinary step: what ``natura bench`` times is the steady-state cost per frame.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any, Callable

import moderngl
import numpy as np

from ..gpu.cache import memoised
from ..gpu.programs import draw_fullscreen, fullscreen
from ..params import Param, ParamSet
from ..sim.amortise import (
    REFRESHES,
    SCALES,
    LayerState,
    Schedule,
    block_position,
    blue_noise,
    choose_schedule,
    jitter_phase,
    reset_reason,
)

#: the resolve, one program per path (``AMORTISE_PATH``: 0 reset, 1 still, 2 moving; see
#: glsl/common/amortise_resolve.frag): an effect lists all three in its programs
RESOLVES = tuple(fullscreen("common/amortise_resolve", defines=(("AMORTISE_PATH", path),))
                 for path in (0, 1, 2))
#: the resolve's near cut as a pass of its own (``AMORTISE_NEAR``): it writes the pixels the
#: cut takes, and marks them in the history's depth so that the resolve proper skips them
NEAR_CUT = fullscreen("common/amortise_resolve", defines=(("AMORTISE_NEAR", 1),))
#: the gather of a banded march grid (see :func:`bands`)
GATHER = fullscreen("common/amortise_gather")
#: every program of the amortised march: an effect lists them in its programs
PROGRAMS = (*RESOLVES, NEAR_CUT, GATHER)
#: the tile of a tiled software rasteriser (llvmpipe: 64 × 64 pixels, one thread each)
TILE = 64
#: the side of its block of fragments shaded as one vector of lanes (llvmpipe: 4 × 4)
LANE = 4


def rasteriser_threads() -> int:
    """The threads llvmpipe shades with: ``LP_NUM_THREADS`` (0: the drawing thread alone),
    else one per CPU."""
    try:
        return max(1, int(os.environ["LP_NUM_THREADS"]))
    except (KeyError, ValueError):
        return max(1, os.cpu_count() or 1)


def bands(grid_size, threads: int, software: bool) -> int:
    """The bands a march grid is drawn in, or 0 to draw it as it is. A tiled software
    rasteriser shades each 64 × 64 tile on one thread, so a grid smaller than a tile per thread
    (quarter resolution, 1/16 refreshed: 40 × 23 rays at 640 × 360) marches on one of them:
    drawn in ``threads`` bands, whole tiles each, every thread marches one; band k holds
    the grid rows k, k + K, k + 2K … (interleaved: a band of the bottom rows alone would hold
    the sea, whose rays end at once, and another the sky), each row in ``LANE × LANE`` blocks
    of consecutive texels (glsl/common/amortise.glsl: a block's lanes then march rays of one
    elevation). A GPU, or a grid already as many tiles as threads, is drawn as it is."""
    w, h = (int(v) for v in grid_size)
    tiles = (-(-w // TILE)) * (-(-h // TILE))
    if not software or threads < 2 or tiles >= threads or h < 2:
        return 0
    return min(threads, h, TILE)
MODES = ("on", "window", "off")
#: the frame budget ``auto`` plans for when the scene has no ``output.frame_budget_ms``
DEFAULT_BUDGET_MS = 33.0
SECTION = "beyond the thesis: amortised march (Schneider 2015)"


def amortise_params(group: str, section: str = SECTION) -> list[Param]:
    """``<group>.reprojection``, ``<group>.march_scale`` and ``<group>.refresh``."""
    return [
        Param(f"{group}.reprojection", "on", doc="amortised march (Schneider 2015): a fraction "
              "of the pixels marched per frame at march_scale with blue-noise jitter, the rest "
              "reprojected from the last frame or filled by depth-aware upsampling; a still "
              "render converges first (every pixel marched once). off: the thesis's "
              "full-resolution march of every pixel every frame (the reference); window: "
              "amortised in the interactive window only", kind="choice", choices=MODES,
              section=section),
        Param(f"{group}.march_scale", "auto", doc="resolution of one frame's march grid, per "
              "side (auto: half or quarter, from the frame budget and the context's speed; "
              "full: every pixel's own ray)", kind="choice",
              choices=("auto", *SCALES), section=section),
        Param(f"{group}.refresh", "auto", doc="fraction of the march grid re-marched per frame "
              "(auto: from the frame budget); every pixel is refreshed once per "
              "(scale · refresh)² frames", kind="choice", choices=("auto", *REFRESHES),
              section=section),
    ]


def context_line(caps, params: ParamSet, group: str) -> str:
    """The context-path line of ``<group>``'s amortised march (``context_paths``)."""
    kind = "software renderer" if caps.software else "GPU"
    return (f"{params[f'{group}.reprojection']}: scale {params[f'{group}.march_scale']}, "
            f"refresh {params[f'{group}.refresh']} (auto: from the frame budget, planned "
            f"for a {kind})")


def amortised(params: ParamSet, group: str, interactive: bool) -> bool:
    """Whether ``<group>.reprojection`` amortises this frame."""
    mode = params[f"{group}.reprojection"]
    return mode == "on" or (mode == "window" and interactive)


def frame_budget_ms(params: ParamSet) -> float:
    """The frame budget ``auto`` plans for: ``output.frame_budget_ms`` where the scene has it."""
    try:
        return float(params["output.frame_budget_ms"])
    except Exception:  # noqa: BLE001 - a scene without the parameter
        return DEFAULT_BUDGET_MS


def schedule_for(params: ParamSet, group: str, size, software: bool,
                 full_march_ms_per_mpx: tuple[float, float]) -> Schedule:
    """The schedule of ``<group>.march_scale`` and ``<group>.refresh`` at ``size``;
    ``full_march_ms_per_mpx``: the effect's estimate of a full-resolution march per megapixel
    (software renderer, hardware GPU), which ``auto`` plans with."""
    cost = full_march_ms_per_mpx[0] if software else full_march_ms_per_mpx[1]
    return choose_schedule(params[f"{group}.march_scale"], params[f"{group}.refresh"],
                           tuple(size), cost, frame_budget_ms(params))


@dataclass
class MarchGrid:
    """Where and how one march pass draws: the framebuffer, and what it binds and sets."""

    fbo: Any
    size: tuple[int, int]
    uniforms: dict = field(default_factory=dict)
    textures: dict = field(default_factory=dict)

    def use(self) -> None:
        self.fbo.use()


class LayerHistory:
    """A full-resolution pair: the resolved layer (RGBA32F) and its aux (RGBA32F: cloud distance,
    clipped scene distance, marched fraction); bilinear, for the moving resolve. ``near`` is the
    depth both histories share: the near cut's mask (see :meth:`Amortiser._resolve`)."""

    def __init__(self, gpu, owner: str, size, near):
        self.color = gpu.texture(owner, "amortised layer", size, 4, dtype="f4")
        self.aux = gpu.texture(owner, "amortised layer aux", size, 4, dtype="f4")
        self.fbo = gpu.framebuffer(owner, "amortised layer", [self.color, self.aux],
                                   depth_attachment=near)
        self.size = tuple(int(v) for v in size)
        self._gpu, self._owner, self._near = gpu, owner, near
        self._over: tuple | None = None  # (a target's colour, a framebuffer over it and near)
        self.marked = False  # whether the last resolve into it marked the near cut in ``near``

    def over(self, target):
        """A framebuffer over ``target``'s colour with the near cut's mark as its depth (None
        when the sizes differ or nothing was marked), for the composite: drawn depth-tested
        ``<`` at depth ½, it skips the pixels the near cut took — where the layer is no cloud,
        (0, 0, 0, 1), and blending it would leave the image as it is."""
        if not self.marked or tuple(target.size) != self.size:
            return None
        if self._over is None or self._over[0] is not target.color:
            if self._over is not None:
                self._gpu.free(self._over[1])
            self._over = (target.color, self._gpu.framebuffer(
                self._owner, "amortised layer composite", [target.color],
                depth_attachment=self._near))
        return self._over[1]

    def read(self) -> np.ndarray:
        """(h, w, 4) float32, row 0 at the top: rgb premultiplied radiance, a transmittance."""
        w, h = self.size
        data = np.frombuffer(self.color.read(), dtype=np.float32).reshape(h, w, 4)
        return data[::-1].copy()

    def free(self, gpu) -> None:
        for obj in (*(self._over or ())[1:], self.fbo, self.color, self.aux):
            gpu.free(obj)
        self._over = None


class _Grid:
    """One frame's march target at ``block``: layer (RGBA32F) and aux (RG32F)."""

    def __init__(self, gpu, owner: str, size, block: int):
        self.size = ((size[0] + block - 1) // block, (size[1] + block - 1) // block)
        nearest = (moderngl.NEAREST, moderngl.NEAREST)
        self.layer = gpu.texture(owner, f"amortised march 1/{block}", self.size, 4, dtype="f4",
                                 filter=nearest)
        self.aux = gpu.texture(owner, f"amortised march aux 1/{block}", self.size, 2,
                               dtype="f4", filter=nearest)
        self.fbo = gpu.framebuffer(owner, f"amortised march 1/{block}", [self.layer, self.aux])
        self.bands = bands(self.size, rasteriser_threads(), gpu.caps.software)
        self.rows = -(-self.size[1] // self.bands) if self.bands else 0  # grid rows of a band
        self.band_shift = 0  # log2 of the fragment rows from one band to the next
        self.banded: tuple | None = None
        if self.bands:  # the banded target: each grid row in LANE × LANE blocks of texels
            # a band: its grid rows, LANE fragment rows each, in whole tiles (a power of two)
            tiles = -(-LANE * self.rows // TILE)
            self.band_shift = TILE.bit_length() - 1 + (tiles - 1).bit_length()
            size = (LANE * -(-self.size[0] // (LANE * LANE)),
                    ((self.bands - 1) << self.band_shift) + LANE * self.rows)
            layer = gpu.texture(owner, f"amortised march 1/{block} banded", size, 4, dtype="f4",
                                filter=nearest)
            aux = gpu.texture(owner, f"amortised march aux 1/{block} banded", size, 2,
                              dtype="f4", filter=nearest)
            fbo = gpu.framebuffer(owner, f"amortised march 1/{block} banded", [layer, aux])
            self.banded = (fbo, layer, aux, size)

    def free(self, gpu) -> None:
        for obj in (self.fbo, self.layer, self.aux, *(self.banded or ())[:3]):
            gpu.free(obj)


class Amortiser:
    """The history of one effect's amortised layer and the passes that keep it (see the
    module docstring). ``steps``, ``resets``, ``last_reset`` and ``last_schedule`` say what it
    did (the panel and the tests read them)."""

    def __init__(self, gpu, owner: str):
        self.gpu = gpu
        self.owner = owner
        self._pair: list[LayerHistory] = []
        self._near: tuple = ()  # the near cut's depth mask and a framebuffer to clear it
        self._grids: dict[int, _Grid] = {}
        self._noise = None
        self._last: LayerState | None = None
        self._origin: LayerState | None = None
        self._prev_view_proj: np.ndarray | None = None
        self._prev_position: np.ndarray | None = None
        self._prev_forward: np.ndarray | None = None
        self._converged: tuple | None = None
        self._schedule: Schedule | None = None
        self.counter = 0  # steps since the last reset
        self.steps = 0  # march passes run in all
        self.resets = 0
        self.last_reset: str | None = None  # why the last reset happened
        self.last_schedule: Schedule | None = None
        self.last_path: int | None = None  # the resolve's AMORTISE_PATH of the last step
        self._full = None  # the full-size target of the thesis's march (:meth:`full_layer`)

    def blue_noise(self):
        """The 64² blue-noise texture (R32F, nearest, repeating)."""
        if self._noise is None:
            data = memoised(blue_noise)
            self._noise = self.gpu.texture(self.owner, "blue noise", data.shape[::-1], 1,
                                           data=np.ascontiguousarray(data).tobytes(), dtype="f4",
                                           filter=(moderngl.NEAREST, moderngl.NEAREST),
                                           repeat=True)
        return self._noise

    def _ensure(self, size) -> None:
        size = tuple(int(v) for v in size)
        if self._pair and self._pair[0].size == size:
            return
        self.release()
        depth = self.gpu.depth_texture(self.owner, "amortised layer near cut", size)
        self._near = (self.gpu.framebuffer(self.owner, "amortised layer near cut", [],
                                           depth_attachment=depth), depth)
        self._pair = [LayerHistory(self.gpu, self.owner, size, depth),
                      LayerHistory(self.gpu, self.owner, size, depth)]

    def _grid(self, size, block: int) -> _Grid:
        g = self._grids.get(block)
        want = ((size[0] + block - 1) // block, (size[1] + block - 1) // block)
        if g is None or g.size != want:
            if g is not None:
                g.free(self.gpu)
            g = self._grids[block] = _Grid(self.gpu, self.owner, size, block)
        return g

    def release(self) -> None:
        """Free the history and the march targets (the blue noise is kept); the next step
        starts afresh."""
        for h in self._pair:
            h.free(self.gpu)
        for obj in self._near:
            self.gpu.free(obj)
        for g in self._grids.values():
            g.free(self.gpu)
        self._pair = []
        self._near = ()
        self._grids = {}
        self._last = self._origin = None
        self._converged = None

    def panel_notes(self, params: ParamSet, group: str) -> list[str]:
        """The panel's line on what the amortised march of ``group`` does now (none when off)."""
        s = self.last_schedule
        if s is None or not amortised(params, group, True):
            return []
        return [f"amortised march: {s.label()} — {100.0 * s.fraction:.3g} % of the pixels per "
                f"frame, every pixel once in {s.cycle} frames; {self.resets} resets "
                f"(last: {self.last_reset})"]

    def forget(self) -> None:
        """Drop every reference without freeing (the owner's resources were released)."""
        self._full = None
        self._pair = []
        self._near = ()
        self._grids = {}
        self._noise = None
        self._last = self._origin = None
        self._converged = None

    @property
    def layer(self) -> LayerHistory | None:
        """The last resolved layer (None before the first step)."""
        return self._pair[0] if self._pair else None

    def full_layer(self, size):
        """The full-size target of the thesis's march (RGBA32F, no depth: rgb premultiplied
        radiance, a transmittance), made again when ``size`` changes."""
        size = tuple(int(v) for v in size)
        if self._full is None or self._full.size != size:
            if self._full is not None:
                self.gpu.free(self._full)
            self._full = self.gpu.target(self.owner, "cloud layer", size, dtype="f4", depth=False)
        return self._full

    def render(self, frame, size, params: ParamSet, schedule: Callable[[Any], Schedule],
               state: Callable[[Any], LayerState], march: Callable[[MarchGrid], None],
               scene_depth=None, phase: float = 0.0):
        """This frame's layer of the owner's group: :meth:`step` when its reprojection
        amortises the frame (``schedule(size)`` and ``state(frame)`` asked then only), else the
        thesis's march of every pixel into :meth:`full_layer` at jitter phase ``phase``."""
        if amortised(params, self.owner, frame.interactive):
            return self.step(frame, size, schedule(size), state(frame), march, scene_depth)
        layer = self.full_layer(size)
        march(self.direct(layer.fbo, size, phase))
        return layer

    def direct(self, fbo, size, phase: float = 0.0) -> MarchGrid:
        """A grid for marching every pixel of ``size`` into ``fbo`` (no amortisation: the
        thesis's march), the jitter phase ``phase``."""
        return MarchGrid(fbo, tuple(size), self._uniforms(size, 1, (0, 0), phase, False),
                         {"uBlueNoise": self.blue_noise()})

    def _uniforms(self, size, block: int, sub, phase: float, amortised: bool) -> dict:
        return {"uAmortiseBands": 0, "uAmortiseBandRows": 0, "uAmortiseGridRows": 0,
                "uAmortiseGridColumns": 0, "uAmortiseBandShift": 0,
                "uAmortiseBlock": int(block), "uAmortiseShift": int(block).bit_length() - 1,
                "uAmortiseSub": (int(sub[0]), int(sub[1])),
                "uAmortiseFullSize": (float(size[0]), float(size[1])),
                "uJitterPhase": float(phase), "uAmortised": bool(amortised)}

    def _march(self, size, block: int, sub, phase: float,
               march: Callable[[MarchGrid], None]) -> _Grid:
        g = self._grid(size, block)
        uniforms = self._uniforms(size, block, sub, phase, True)
        if g.banded is None:
            march(MarchGrid(g.fbo, g.size, uniforms, {"uBlueNoise": self.blue_noise()}))
        else:  # drawn banded, one band per thread, then gathered into the grid
            fbo, layer, aux, banded_size = g.banded
            march(MarchGrid(fbo, banded_size, {**uniforms, "uAmortiseBands": g.bands,
                                               "uAmortiseBandRows": g.rows,
                                               "uAmortiseGridRows": g.size[1],
                                               "uAmortiseGridColumns": g.size[0],
                                               "uAmortiseBandShift": g.band_shift},
                            {"uBlueNoise": self.blue_noise()}))
            prog = self.gpu.program(self.owner, GATHER)
            prog.bind_textures({"uBanded": layer, "uBandedAux": aux})
            prog.set_many({"uAmortiseBands": g.bands, "uAmortiseBandShift": g.band_shift})
            g.fbo.use()
            self.gpu.ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
            draw_fullscreen(prog)
        self.steps += 1
        return g

    def step(self, frame, size, schedule: Schedule, state: LayerState,
             march: Callable[[MarchGrid], None], scene_depth=None,
             still: bool | None = None) -> LayerHistory:
        """One frame of the amortised layer at ``size`` (see the module docstring); ``still``
        (default: not ``frame.interactive``) converges a new view before returning."""
        size = tuple(int(v) for v in size)
        still = (not frame.interactive) if still is None else still
        self._ensure(size)
        cam = frame.camera
        view_proj = cam.view_projection_relative(frame.aspect)
        position = np.asarray(cam.position, dtype=np.float64)
        forward = np.asarray(cam.forward(), dtype=np.float64)
        self.last_schedule = schedule
        if still:
            key = (size, schedule, state.key, view_proj.tobytes(), position.tobytes(),
                   np.asarray(state.light_dir, float).tobytes(),
                   np.asarray(state.light_radiance, float).tobytes(),
                   np.asarray(state.field_offset, float).tobytes(), float(cam.near),
                   float(cam.far))
            if key != self._converged or self._last is None:
                self._reset(frame, size, schedule, state, march, scene_depth, "a new still view",
                            block=1)
                self.counter = 0
                self._converged = key
                return self._pair[0]
        else:
            self._converged = None
            move = (float(np.linalg.norm(position - self._prev_position))
                    if self._prev_position is not None else 0.0)
            turn = (float(np.degrees(np.arccos(np.clip(forward @ self._prev_forward, -1.0, 1.0))))
                    if self._prev_forward is not None else 0.0)
            why = reset_reason(state, self._last, self._origin, move, turn)
            if why is None and schedule != self._schedule:
                why = "the schedule changed"
            if why is not None:
                self._reset(frame, size, schedule, state, march, scene_depth, why)
                return self._pair[0]
        self.counter += 1
        block = schedule.block
        sub = block_position(self.counter, block)
        phase = jitter_phase(self.counter // (block * block))
        grid = self._march(size, block, sub, phase, march)
        self._resolve(frame, size, grid, block, sub, state, scene_depth, view_proj, position,
                      forward)
        return self._pair[0]

    def _reset(self, frame, size, schedule, state, march, scene_depth, why: str,
               block: int | None = None) -> None:
        self.resets += 1
        self.last_reset = why
        self._last = None
        self._schedule = schedule
        self.counter = 0
        block = schedule.scale if block is None else block
        grid = self._march(size, block, (0, 0), 0.0, march)
        cam = frame.camera
        self._resolve(frame, size, grid, block, (0, 0), state, scene_depth,
                      cam.view_projection_relative(frame.aspect),
                      np.asarray(cam.position, dtype=np.float64),
                      np.asarray(cam.forward(), dtype=np.float64))
        self._origin = state

    def _resolve(self, frame, size, grid: _Grid, block: int, sub, state: LayerState,
                 scene_depth, view_proj, position, forward) -> None:
        src, dst = self._pair
        last, prev_position, prev_view_proj = self._last, self._prev_position, self._prev_view_proj
        have = last is not None and prev_position is not None and prev_view_proj is not None
        shift = (np.asarray(state.field_offset, float) - np.asarray(last.field_offset, float)
                 if last is not None and have else np.zeros(3))
        delta = position - prev_position if prev_position is not None and have else np.zeros(3)
        still = bool(have and not shift.any() and not delta.any()
                     and prev_view_proj is not None and np.array_equal(view_proj, prev_view_proj))
        path = 0 if not have else 1 if still else 2
        self.last_path = path
        cam = frame.camera
        uniforms = {
            **frame.camera_uniforms(), **self._uniforms(size, block, sub, 0.0, True),
            "uHasSceneDepth": scene_depth is not None, "uCamNear": float(cam.near),
            "uCamFar": float(cam.far),
            "uPrevViewProj": self._prev_view_proj if have else np.identity(4),
            "uCameraDelta": tuple(float(v) for v in delta),
            "uFieldShift": tuple(float(v) for v in shift),
            "uNearCloud": float(state.near), "uFarCloud": float(state.far),
        }
        textures = {"uFresh": grid.layer, "uFreshAux": grid.aux, "uHistory": src.color,
                    "uHistoryAux": src.aux, "uSceneDepth": scene_depth,
                    "uBlueNoise": self.blue_noise()}
        # Two passes, each pixel written by one of them: the near cut (the boat, the near sea:
        # most of a maritime frame) writes its pixels and marks them in the depth; the resolve
        # proper is depth-tested against that mark. A rasteriser skips a block of fragments the
        # depth test rejects before shading — a software one too, which otherwise runs every
        # line of a shader with masks, taken or not. A frame that draws no surface before the
        # volumes (frame.image.opaque false) has nothing to cut: the mark stays clear and the
        # resolve proper alone writes every pixel (it makes the same cut itself).
        ctx = self.gpu.ctx
        ctx.disable(moderngl.BLEND | moderngl.DEPTH_TEST)
        dst.marked = frame.image is None or frame.image.opaque
        if dst.marked:
            ctx.enable(moderngl.DEPTH_TEST)
            self._near[0].clear(depth=1.0)
        dst.fbo.use()
        passes = ((NEAR_CUT, "1", True),) if dst.marked else ()
        try:
            for spec, func, write in (*passes, (RESOLVES[path], "<", False)):
                prog = self.gpu.program(self.owner, spec)
                prog.bind_textures(textures)
                prog.set_many(uniforms)
                ctx.depth_func = func  # always; then where the near cut left no mark
                dst.fbo.depth_mask = write
                draw_fullscreen(prog)
        finally:
            ctx.depth_func = "<"
            dst.fbo.depth_mask = True
            ctx.disable(moderngl.DEPTH_TEST)
        self._pair.reverse()  # dst, now [0]: the layer, and the next frame's history
        self._last = state
        self._prev_view_proj = view_proj
        self._prev_position = position
        self._prev_forward = forward

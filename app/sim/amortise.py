"""Amortised rendering of an expensive full-screen layer (beyond the theses; after Schneider 2015,
"The real-time volumetric cloudscapes of Horizon: Zero Dawn"): the numpy side of
:mod:`app.render.amortise` and ``glsl/common/amortise*.glsl`` — no GL here.

The scheme, for a layer such as the clouds (RGBA: premultiplied radiance, transmittance):

* **the schedule** (:class:`Schedule`): each frame marches one full-resolution pixel of every
  ``block × block`` block of the image, ``block = scale · refresh``: a march at ``1/scale`` of
  the resolution per side (½ or ¼), of which ``1/refresh²`` of the pixels (all, ¼ or 1/16) are
  re-marched per frame. Which pixel of its block a frame marches follows the Bayer order
  (:func:`bayer_matrix`, :func:`block_position`), so every pixel is marched once per
  ``block²`` frames and consecutive frames march well-spread pixels;
* **jitter**: a ray's first sample is offset along the ray by a blue-noise value
  (:func:`blue_noise`, void-and-cluster) plus the golden-ratio phase of the refresh cycle
  (:func:`jitter_phase`), so the banding a fixed step leaves becomes fine noise that changes
  from one refresh of a pixel to the next;
* **history**: a full-resolution image that holds each pixel's latest march, reprojected to the
  current view (the point at the pixel's cloud distance, moved back by the wind's shift of the
  field); it is not averaged (the jitter noise of one march is already below a display step,
  ``tests/gl/test_clouds_amortise.py``), so a still view converges to the full-resolution march
  itself once every pixel has been marched;
* **depth-aware filling** (:func:`depth_agree`, :func:`fill`): a pixel without history (the
  first frame, a disocclusion, a part of the view just turned into) takes the depth-weighted
  interpolation of this frame's marched pixels, using only those whose opaque-scene distance
  agrees with its own — clouds do not bleed over a mast or across the horizon;
* **rejection** (:func:`reset_reason`): a fast change of the light (time of day), of the wind,
  of the effect's parameters or a jump of the camera throws the whole history away.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: march scale per side: the choice → how many full-resolution pixels one march stands for
SCALES = {"full": 1, "half": 2, "quarter": 4}
#: refresh fraction: the choice → marched pixels per side of a refresh block (1/refresh²)
REFRESHES = {"all": 1, "1/4": 2, "1/16": 4}
#: the order ``auto`` tries (scale, refresh), most rays per frame first; at equal rays the
#: coarser scale, whose reset march (a whole low-resolution frame) costs less
AUTO_ORDER = ((2, 1), (4, 1), (2, 2), (4, 2), (2, 4), (4, 4))
#: the share of the frame budget the amortised march may take (``auto``)
BUDGET_SHARE = 0.25
#: golden ratio conjugate: the jitter phase of refresh cycle n is frac(n · φ)
PHI = (math.sqrt(5.0) - 1.0) / 2.0

#: rejection thresholds (see :func:`reset_reason`)
LIGHT_DEG_PER_FRAME = 0.25    # the light turned faster than this in one frame
LIGHT_DEG_DRIFT = 2.0         # ... or by more than this since the history began
LIGHT_RADIANCE_DRIFT = 0.05   # relative change of the light's radiance since the history began
WIND_MS_PER_FRAME = 1.0       # the wind velocity changed by more than this in one frame
SHIFT_JUMP_M = 50.0           # the field moved by more than this in one frame (time jumped)
CAMERA_JUMP_M = 500.0         # the camera moved by more than this in one frame
CAMERA_TURN_DEG = 20.0        # ... or turned by more than this

#: depth agreement (:func:`depth_agree`): relative and absolute tolerances
AGREE_RELATIVE = 0.05
AGREE_METRES = 1.0


@dataclass(frozen=True)
class Schedule:
    """``scale``: full-resolution pixels per side per march (1, 2, 4); ``refresh``: marched
    pixels per side of a refresh block (1, 2, 4: all, ¼ or 1/16 of them per frame)."""

    scale: int
    refresh: int

    @property
    def block(self) -> int:
        """Full-resolution pixels per side between the rays of one frame."""
        return self.scale * self.refresh

    @property
    def fraction(self) -> float:
        """Fraction of the full-resolution pixels marched per frame."""
        return 1.0 / self.block ** 2

    @property
    def cycle(self) -> int:
        """Frames until every full-resolution pixel has been marched once."""
        return self.block ** 2

    def label(self) -> str:
        s = {v: k for k, v in SCALES.items()}[self.scale]
        r = {v: k for k, v in REFRESHES.items()}[self.refresh]
        return f"{s}, refresh {r}"


def choose_schedule(scale: str, refresh: str, size: tuple[int, int], full_march_ms_per_mpx: float,
                    budget_ms: float) -> Schedule:
    """The schedule of the parameters; ``auto`` (either) is chosen from the frame budget: the
    first of :data:`AUTO_ORDER` (with the other choice fixed when it is not ``auto``) whose
    estimated march time, ``full_march_ms_per_mpx`` × megapixels × the marched fraction, fits
    :data:`BUDGET_SHARE` of ``budget_ms``; the last candidate when none does."""
    mpx = size[0] * size[1] / 1.0e6
    fixed_s = SCALES.get(scale)
    fixed_r = REFRESHES.get(refresh)
    if fixed_s is not None and fixed_r is not None:
        return Schedule(fixed_s, fixed_r)
    candidates = [Schedule(s, r) for s, r in AUTO_ORDER
                  if (fixed_s is None or s == fixed_s) and (fixed_r is None or r == fixed_r)]
    if not candidates:  # full scale with an auto refresh: every refresh of the full scale
        candidates = [Schedule(fixed_s or 1, r) for r in (1, 2, 4)]
    for c in candidates:
        if full_march_ms_per_mpx * mpx * c.fraction <= BUDGET_SHARE * budget_ms:
            return c
    return candidates[-1]


def bayer_matrix(n: int) -> np.ndarray:
    """The n × n Bayer ordered-dither matrix (n a power of two), values 0 … n² − 1:
    M₂ₙ = [[4M, 4M + 2], [4M + 3, 4M + 1]]."""
    if n < 1 or n & (n - 1):
        raise ValueError(f"bayer_matrix: n={n} is not a power of two")
    m = np.zeros((1, 1), dtype=np.int64)
    while m.shape[0] < n:
        m = np.block([[4 * m, 4 * m + 2], [4 * m + 3, 4 * m + 1]])
    return m


def block_position(step: int, block: int) -> tuple[int, int]:
    """The pixel (x, y) of each ``block × block`` block that refresh step ``step`` marches: the
    position of ``step mod block²`` in the Bayer matrix."""
    m = bayer_matrix(block)
    y, x = np.argwhere(m == step % (block * block))[0]
    return int(x), int(y)


def jitter_phase(cycle: int) -> float:
    """The jitter phase of refresh cycle ``cycle``: frac(cycle · φ) (0 for the first)."""
    return (cycle * PHI) % 1.0


def _toroidal_gaussians(n: int, sigma: float) -> np.ndarray:
    """Row c: the 1-D toroidal Gaussian centred on c (the 2-D kernel is separable)."""
    i = np.arange(n)
    d = np.abs(i[None, :] - i[:, None])
    d = np.minimum(d, n - d).astype(np.float64)
    return np.exp(-(d ** 2) / (2.0 * sigma * sigma))


def blue_noise(n: int = 64, sigma: float = 1.5, seed: int = 0) -> np.ndarray:
    """An ``n × n`` blue-noise threshold map by void-and-cluster (Ulichney 1993): float32 values
    (rank + 0.5)/n², each rank once, tiling seamlessly. The energy of a point set is the sum of
    toroidal Gaussians (σ = ``sigma`` pixels) about its points; ranks are given by removing
    the tightest cluster (highest energy) from the relaxed initial set, then adding into the
    largest void (lowest energy) until the map is full."""
    rng = np.random.default_rng(seed)
    total = n * n
    g = _toroidal_gaussians(n, sigma)
    big = 1.0e9  # keeps the pixels of the other kind out of an argmax / argmin

    class Pattern:
        """A point set with its energy, kept twice: the empty pixels pushed down (for the
        tightest cluster, an argmax) and the full ones pushed up (for the largest void)."""

        def __init__(self, ones: np.ndarray):
            self.ones = ones.copy()
            energy = np.zeros((n, n))
            for i in np.flatnonzero(ones):
                y, x = divmod(int(i), n)
                energy += np.outer(g[y], g[x])
            self.cluster = (energy.reshape(-1) - big * ~self.ones).copy()
            self.void = (energy.reshape(-1) + big * self.ones).copy()

        def toggle(self, i: int) -> None:
            y, x = divmod(i, n)
            add = np.outer(g[y], g[x]).reshape(-1)
            if self.ones[i]:
                self.ones[i] = False
                self.cluster -= add
                self.void -= add
                self.cluster[i] -= big
                self.void[i] -= big
            else:
                self.ones[i] = True
                self.cluster += add
                self.void += add
                self.cluster[i] += big
                self.void[i] += big

        def tightest_cluster(self) -> int:
            return int(np.argmax(self.cluster))

        def largest_void(self) -> int:
            return int(np.argmin(self.void))

    ones = np.zeros(total, dtype=bool)
    ones[rng.choice(total, size=max(1, total // 10), replace=False)] = True
    pat = Pattern(ones)
    for _ in range(4 * total):  # relax: move the tightest cluster into the largest void
        cluster = pat.tightest_cluster()
        pat.toggle(cluster)
        void = pat.largest_void()
        pat.toggle(void)
        if void == cluster:
            break
    rank = np.zeros(total, dtype=np.int64)
    start = int(pat.ones.sum())
    # phase 1: the initial points, from the tightest cluster down
    proto = Pattern(pat.ones)
    for r in range(start - 1, -1, -1):
        cluster = proto.tightest_cluster()
        proto.toggle(cluster)
        rank[cluster] = r
    # phases 2 and 3: fill the largest void until every pixel has a rank (the tightest cluster
    # of the empty pixels is the largest void of the full ones: one rule for both halves)
    for r in range(start, total):
        void = pat.largest_void()
        pat.toggle(void)
        rank[void] = r
    return ((rank + 0.5) / total).astype(np.float32).reshape(n, n)


def depth_agree(a, b) -> np.ndarray:
    """Whether two opaque-scene distances along neighbouring rays (already clipped at the
    layer's far distance) are the same surface: |a − b| ≤ 5 % of the larger + 1 m. Twin of
    ``AmortiseDepthAgree`` in glsl/common/amortise.glsl."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return np.abs(a - b) <= AGREE_RELATIVE * np.maximum(a, b) + AGREE_METRES


def fill(pixel: tuple[int, int], dist: float, fresh: np.ndarray, fresh_dist: np.ndarray,
         block: int, sub: tuple[int, int], size: tuple[int, int]) -> np.ndarray:
    """The depth-aware interpolation of one pixel from a frame's marched pixels (twin of
    ``AmortiseFill`` in glsl/common/amortise_resolve.frag). ``fresh`` (gh, gw, C): the marched
    values, grid texel t standing for the full-resolution pixel t·block + sub (x, y; rows in
    GL order, row 0 at the bottom); ``fresh_dist`` (gh, gw): their clipped scene distances;
    ``dist``: this pixel's. The four grid neighbours are weighted bilinearly, those whose
    distance does not agree (:func:`depth_agree`) or that lie off the image dropped; when none
    is left, the neighbour of the nearest distance."""
    gh, gw = fresh_dist.shape
    gx = (pixel[0] - sub[0]) / block
    gy = (pixel[1] - sub[1]) / block
    x0, y0 = math.floor(gx), math.floor(gy)
    fx, fy = gx - x0, gy - y0
    total = np.zeros(fresh.shape[-1])
    weight = 0.0
    best, best_d = None, math.inf
    for dy in (0, 1):
        for dx in (0, 1):
            tx = min(max(x0 + dx, 0), gw - 1, max(size[0] - 1 - sub[0], 0) // block)
            ty = min(max(y0 + dy, 0), gh - 1, max(size[1] - 1 - sub[1], 0) // block)
            w = (fx if dx else 1.0 - fx) * (fy if dy else 1.0 - fy)
            d = float(fresh_dist[ty, tx])
            if abs(d - dist) < best_d:
                best, best_d = (ty, tx), abs(d - dist)
            if depth_agree(dist, d) and w > 0.0:
                total += w * fresh[ty, tx]
                weight += w
    if weight > 1.0e-6:
        return total / weight
    return fresh[best].astype(np.float64)


def fill_nearest(pixel: tuple[int, int], dist: float, fresh: np.ndarray, fresh_dist: np.ndarray,
                 block: int, sub: tuple[int, int], size: tuple[int, int]) -> np.ndarray:
    """Nearest-depth upsampling of one pixel (twin of ``AmortiseFillNearest`` in
    glsl/common/amortise_resolve.frag, the fallback of a disoccluded pixel while the history
    is kept): of the four grid neighbours (as in :func:`fill`), the one whose clipped scene
    distance is closest to ``dist``; among equals, the one of the largest bilinear weight."""
    gh, gw = fresh_dist.shape
    gx = (pixel[0] - sub[0]) / block
    gy = (pixel[1] - sub[1]) / block
    x0, y0 = math.floor(gx), math.floor(gy)
    fx, fy = gx - x0, gy - y0
    best, best_delta = (0, 0), math.inf
    for dy in (0, 1):
        for dx in (0, 1):
            tx = min(max(x0 + dx, 0), gw - 1, max(size[0] - 1 - sub[0], 0) // block)
            ty = min(max(y0 + dy, 0), gh - 1, max(size[1] - 1 - sub[1], 0) // block)
            w = (fx if dx else 1.0 - fx) * (fy if dy else 1.0 - fy)
            delta = abs(float(fresh_dist[ty, tx]) - dist) - 1.0e-3 * w
            if delta < best_delta:
                best, best_delta = (ty, tx), delta
    return fresh[best].astype(np.float64)


@dataclass
class LayerState:
    """What an amortised layer's history depends on, as the effect sees it this frame."""

    #: every input a change of which throws the history away (parameters, textures, …)
    key: tuple
    light_dir: np.ndarray        # unit vector toward the light
    light_radiance: np.ndarray   # rgb (the ambient included)
    wind: np.ndarray             # the field's velocity, m/s (world x, y, z)
    field_offset: np.ndarray     # how far the field has moved in all, metres (world x, y, z)
    near: float                  # no cloud is nearer than this to the camera (metres)
    far: float                   # nor farther than this


def _angle_deg(a, b) -> float:
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    c = float(np.dot(a, b) / max(np.linalg.norm(a) * np.linalg.norm(b), 1e-30))
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def reset_reason(state: LayerState, last: LayerState | None, origin: LayerState | None,
                 cam_move_m: float = 0.0, cam_turn_deg: float = 0.0) -> str | None:
    """Why the history must be thrown away this frame (None: keep it). ``last``: last frame's
    state; ``origin``: the state when the history began (its last reset)."""
    if last is None or origin is None:
        return "no history"
    if state.key != last.key:
        return "parameters changed"
    if _angle_deg(state.light_dir, last.light_dir) > LIGHT_DEG_PER_FRAME:
        return "the light turned fast"
    if _angle_deg(state.light_dir, origin.light_dir) > LIGHT_DEG_DRIFT:
        return "the light turned"
    ref = float(np.max(np.abs(origin.light_radiance)))
    if np.max(np.abs(state.light_radiance - origin.light_radiance)) > LIGHT_RADIANCE_DRIFT * max(
            ref, 1e-6):
        return "the light's radiance changed"
    if np.linalg.norm(state.wind - last.wind) > WIND_MS_PER_FRAME:
        return "the wind changed"
    if np.linalg.norm(state.field_offset - last.field_offset) > SHIFT_JUMP_M:
        return "the field jumped"
    if cam_move_m > CAMERA_JUMP_M or cam_turn_deg > CAMERA_TURN_DEG:
        return "the camera jumped"
    return None

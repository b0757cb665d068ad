"""The boat's wake (beyond the maritime thesis, which left it out: spec/000 §4 item 7): foam that
trails in world space and opens into a Kelvin wedge. Twin of ``glsl/common/wake.glsl``.

The thesis's failure: a displacement texture or a triangular decal fixed to the boat turns
rigidly with it in a sharp turn (the texture has no inertia). Here the wake is a trail of
samples left where the stern *was*, each remembering its age a, the boat's speed U and its
direction of travel d when it was left; nothing is tied to the boat afterwards.

Kelvin's construction (Kelvin 1887; Lighthill, "Waves in Fluids", 1978, §3.10): a point P the
boat passed a seconds ago sent out waves in every direction θ from its course; the one that keeps
station with the boat has phase speed U·cos θ, and its energy travels at the group speed, half
of that, so it is now U·a·cos θ / 2 from P: on the circle of diameter U·a/2 from P toward the
boat (centre P + d·U·a/4, radius U·a/4). The circles' envelope, seen from the boat 3·U·a/4
ahead of the centre, is a wedge of half-angle asin(1/3) = 19.47° for any speed in deep water.
Each sample paints

* its **cusp** foam: that ring (its width at least the spacing between successive rings),
  brightest where it touches the envelope — at the ring points whose direction from the centre
  makes cos = 1/3 with the travel direction — so a straight run shows the two arms of the V and
  a turn bends them along the path actually sailed;
* its **wash**: a band along the path from it to the sample before it, as wide as the beam and
  spreading slowly: the turbulent foam of the hull and the rudder.

Both fade with age and need way on (a drifting boat leaves no wake): intensity × the speed
ramp smoothstep(0.3, 2.0, U).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ParamError
from .maths import smoothstep as _smoothstep

#: half-angle of the Kelvin wedge: asin(1/3) [rad]
KELVIN_HALF_ANGLE = math.asin(1.0 / 3.0)
#: angle between the travel direction and the ring's cusp point, seen from the ring's centre:
#: acos(1/3) [rad]
CUSP_ANGLE = math.acos(1.0 / 3.0)
#: samples the trail keeps (the shader's uniform arrays hold as many)
MAX_SAMPLES = 64


@dataclass
class WakeParams:
    spacing: float = 0.3        # s between samples
    cusp_life: float = 14.0     # s: cusp foam fades with age as exp(−a / life)
    wash_life: float = 4.0      # s: the wash's fade
    cusp_width: float = 0.35    # m: the ring's half-width (at least the ring spacing)
    wash_spread: float = 0.06   # the wash widens by this × U·a
    strength: float = 1.0       # foam scale

    def validate(self) -> None:
        for name, lo, hi in (("spacing", 0.02, 5.0), ("cusp_life", 0.1, 600.0),
                             ("wash_life", 0.1, 600.0), ("cusp_width", 0.01, 20.0),
                             ("wash_spread", 0.0, 1.0), ("strength", 0.0, 10.0)):
            v = getattr(self, name)
            if not (math.isfinite(v) and lo <= v <= hi):
                raise ParamError(f"boat.wake_{name}: {v!r} is outside the allowed range "
                                 f"[{lo:g}, {hi:g}]")


@dataclass
class WakeTrail:
    """Samples left behind a moving boat, newest first: world (x, z), time left, speed,
    unit direction of travel (x, z). ``beam`` [m] sets the wash's width."""

    params: WakeParams = field(default_factory=WakeParams)
    beam: float = 2.6
    positions: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    speeds: np.ndarray = field(default_factory=lambda: np.zeros(0))
    directions: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    _last: float | None = None

    def record(self, t: float, stern_xz, velocity_xz) -> None:
        """Leave a sample at the stern when ``spacing`` seconds have passed since the last one
        (time going back — a scrubbed clock — starts a new trail)."""
        if self._last is not None and t < self._last:
            self.clear()
        if self._last is not None and t - self._last < self.params.spacing:
            return
        v = np.asarray(velocity_xz, dtype=float)
        speed = float(np.hypot(v[0], v[1]))
        d = v / speed if speed > 1e-6 else np.array([0.0, 1.0])
        stern = np.asarray(stern_xz, float)[None]
        self.positions = np.vstack([stern, self.positions])[:MAX_SAMPLES]
        self.times = np.concatenate([[t], self.times])[:MAX_SAMPLES]
        self.speeds = np.concatenate([[speed], self.speeds])[:MAX_SAMPLES]
        self.directions = np.vstack([d[None], self.directions])[:MAX_SAMPLES]
        self._last = t

    def clear(self) -> None:
        self.positions, self.directions = np.zeros((0, 2)), np.zeros((0, 2))
        self.times, self.speeds, self._last = np.zeros(0), np.zeros(0), None

    def __len__(self) -> int:
        return len(self.times)

    def foam(self, x, z, t: float) -> np.ndarray:
        """Wake foam in [0, 1] at world points (x, z) at time t."""
        return wake_foam(np.asarray(x, float), np.asarray(z, float), self.positions,
                         t - self.times, self.speeds, self.directions, self.beam, self.params)

    def bounds(self, t: float, margin: float = 2.0,
               samples: slice = slice(None)) -> tuple[float, float, float, float]:
        """(x min, z min, x max, z max) of everything the trail (or its ``samples``: a chunk
        and the sample after it, where its last wash ends) can paint at time t."""
        pos = self.positions[samples]
        if len(pos) == 0:
            return (0.0, 0.0, -1.0, -1.0)
        r = (self.speeds[samples] * np.maximum(t - self.times[samples], 0.0) / 2.0 + self.beam
             + margin)
        return (float((pos[:, 0] - r).min()), float((pos[:, 1] - r).min()),
                float((pos[:, 0] + r).max()), float((pos[:, 1] + r).max()))


def wake_foam(x: np.ndarray, z: np.ndarray, positions: np.ndarray, ages: np.ndarray,
              speeds: np.ndarray, directions: np.ndarray, beam: float,
              params: WakeParams) -> np.ndarray:
    """Foam of trail samples at world points (the max over samples, in [0, 1]); the twin of
    ``WakeFoam`` in glsl/common/wake.glsl (Kelvin 1887: ring centre P + d·U·a/4, radius
    U·a/4, cusp at cos = 1/3), ~64 k (point, sample) pairs at a time: temporaries in cache."""
    p = params
    shape = np.broadcast(x, z).shape
    out = np.zeros(shape)
    if len(ages) == 0:
        return out
    a = np.maximum(ages, 0.0)
    way = _smoothstep(0.3, 2.0, speeds)
    radius = speeds * a / 4.0
    width = np.maximum(p.cusp_width, speeds * p.spacing / 4.0)
    reach = np.maximum(p.cusp_width, 0.75 * speeds * p.spacing)
    fade, grow = np.exp(-a / p.cusp_life), _smoothstep(0.0, 1.0, radius)
    nxt = np.minimum(np.arange(len(ages)) + 1, len(ages) - 1)
    sx, sz = (positions[nxt] - positions).T
    s2 = np.maximum(sx * sx + sz * sz, 1e-12)
    da, du = a[nxt] - a, speeds[nxt] - speeds
    x, z = np.broadcast_to(x, shape).ravel(), np.broadcast_to(z, shape).ravel()
    step = max(1, (1 << 16) // len(ages))
    for i in range(0, x.size, step):
        px = x[i:i + step, None] - positions[:, 0]
        pz = z[i:i + step, None] - positions[:, 1]
        cx = px - directions[:, 0] * radius  # from the ring's centre P + d·U·a/4
        cz = pz - directions[:, 1] * radius
        rc = np.hypot(cx, cz)
        ring = np.exp(-((rc - radius) / width) ** 2)
        cos_d = (cx * directions[:, 0] + cz * directions[:, 1]) / np.maximum(rc, 1e-6)
        # along the ring, the distance to its cusp point: at least the spacing of successive
        # cusps (0.75·U·spacing apart along the arm), so the arm is a line, not a string of beads
        arc = radius * np.abs(np.arccos(np.clip(cos_d, -1.0, 1.0)) - CUSP_ANGLE)
        cusp = np.exp(-(arc / reach) ** 2)
        cusp_foam = ring * cusp * fade * grow
        # the wash: a band along the path — the distance to the segment from each sample to
        # the one left before it, age and speed interpolated along it (discs would show beads)
        f = np.clip((px * sx + pz * sz) / s2, 0.0, 1.0)
        rw = np.hypot(px - f * sx, pz - f * sz)
        aw, uw = a + f * da, speeds + f * du
        half = 0.35 * beam + p.wash_spread * uw * aw
        wash = 0.7 * np.exp(-(rw / half) ** 2) * np.exp(-aw / p.wash_life)
        foam = np.maximum(cusp_foam, wash) * way * p.strength
        out.flat[i:i + step] = np.clip(foam.max(axis=-1), 0.0, 1.0)
    return out


def ridge_angle(along, across, foam, start: float = 8.0, stop: float | None = None,
                bin_width: float = 1.0, floor: float = 0.05, share: float = 0.8,
                crest_m: float = 1.0) -> dict:
    """The half-angle of the wake's foam ridge [degrees], measured where the foam is brightest
    and not at the outer edge of the foam band (a high percentile of bright pixels' angles
    reads the band's outer edge: 20.9° where the ridge lies at 19.5°).

    ``along`` [m] is the distance behind the wedge's apex (the stern now), ``across`` [m] the
    signed lateral offset, ``foam`` the foam there (any shape; flattened). Per bin of
    ``bin_width`` metres of ``along`` in [start, stop), on each side, the foam-weighted centroid
    of (along, |across|) over the points within ``share`` of that side's maximum and within
    ``crest_m`` metres of it across (the ridge's crest, at sub-sample precision) — skipped where
    the maximum is below ``floor``; then the least-squares line through the apex, |across| =
    tan θ · along. Returns ``angle`` (both sides), ``port`` and ``starboard`` (across > 0 and
    < 0 alone), ``points`` (the crest points used, per side) and ``rms_m`` (their rms lateral
    distance from the fitted line)."""
    x = np.asarray(along, float).ravel()
    y = np.asarray(across, float).ravel()
    f = np.asarray(foam, float).ravel()
    if not (x.shape == y.shape == f.shape):
        raise ValueError("ridge_angle: along, across and foam need the same number of points")
    end = float(x.max()) if stop is None and x.size else float(stop or 0.0)
    crest: dict[str, list[tuple[float, float]]] = {"port": [], "starboard": []}
    edges = np.arange(float(start), end, float(bin_width))
    for lo in edges:
        in_bin = (x >= lo) & (x < lo + bin_width)
        for side, on in (("port", y > 0.0), ("starboard", y < 0.0)):
            m = in_bin & on
            if not m.any():
                continue
            i = np.flatnonzero(m)[np.argmax(f[m])]
            peak = f[i]
            if peak < floor:
                continue
            # the crest around the maximum (not a brighter-than-share patch of the wash)
            top = m & (f >= share * peak) & (np.abs(np.abs(y) - abs(y[i])) <= crest_m)
            w = f[top]
            crest[side].append((float((x[top] * w).sum() / w.sum()),
                                float((np.abs(y[top]) * w).sum() / w.sum())))

    def fit(points):
        if len(points) < 2:
            return math.nan, math.nan
        p = np.asarray(points)
        slope = float((p[:, 0] * p[:, 1]).sum() / (p[:, 0] ** 2).sum())
        rms = float(np.sqrt(np.mean((p[:, 1] - slope * p[:, 0]) ** 2)))
        return math.degrees(math.atan(slope)), rms

    both, rms = fit(crest["port"] + crest["starboard"])
    return {"angle": both, "port": fit(crest["port"])[0],
            "starboard": fit(crest["starboard"])[0], "rms_m": rms,
            "points": {k: len(v) for k, v in crest.items()}}

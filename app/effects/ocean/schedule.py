"""When a slow cascade of the FFT ocean computes its snapshots (``ocean.simulation = view``).

A cascade whose waves change little within a frame (the long waves: ω small) is not simulated
every frame. It holds two snapshots, A at t_a and B at t_b = t_a + T, and the frame at time t
shows their linear interpolation with weight w = (t − t_a)/T (the error this leaves is
:func:`app.sim.ocean.interpolation_error`, and T is chosen from it:
:func:`app.sim.ocean.refresh_period`). Meanwhile the next snapshot C, at t_b + T, is computed a
few steps per frame — its spectrum's evolution, then the inverse FFT's passes one by one — so
that it is complete before t reaches t_b; then it is finalised into A's textures and the two
swap (A ← B, B ← C). The dispersion relation gives the exact phase at any time, so a snapshot
computed ahead of time is exactly the sea at its time.

This module is the plan alone (pure Python, tested in tests/unit); ``app/effects/ocean/fft.py``
runs it on the GPU.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

#: the frame interval assumed while the clock stands still (dt ≤ 0) before any frame moved it
NOMINAL_DT = 1.0 / 30.0


@dataclass(frozen=True)
class Action:
    """``kind`` ``"step"``: step ``index`` of the snapshot at ``time`` (index 0 evolves its
    spectrum to that time); ``"swap"``: finalise the snapshot at ``time`` into A's textures,
    then A ← B, B ← C."""

    kind: str
    time: float
    index: int = 0


@dataclass
class Plan:
    """The work of one frame of a slow cascade, in order: ``reset`` (compute A at ``t`` and B at
    ``t`` + T now, before anything else), then ``actions``, then the blend of A and B with
    ``weight``."""

    reset: bool
    actions: list[Action] = field(default_factory=list)
    weight: float = 0.0

    @property
    def steps(self) -> int:
        return sum(a.kind == "step" for a in self.actions)


@dataclass
class SnapshotSchedule:
    """The snapshot plan of one slow cascade: ``period`` T [s] between snapshots, ``steps`` of
    work in one snapshot before its finalisation (its evolution and its FFT passes), and
    ``key`` — whatever the snapshots were computed from besides the time (choppiness, foam
    settings): a new key starts over."""

    period: float
    steps: int
    key: object = None
    t_a: float | None = None  # time of snapshot A (None: none yet)
    done: int = 0  # steps of C done
    last_dt: float = NOMINAL_DT  # the last positive frame interval seen

    def __post_init__(self):
        if not (self.period > 0.0 and math.isfinite(self.period)):
            raise ValueError(f"snapshot period {self.period!r} s is not positive and finite")
        if self.steps < 1:
            raise ValueError(f"snapshot steps {self.steps!r}: at least one")

    @property
    def t_b(self) -> float:
        assert self.t_a is not None
        return self.t_a + self.period

    @property
    def t_c(self) -> float:
        """The time of the snapshot being computed."""
        assert self.t_a is not None
        return self.t_a + 2.0 * self.period

    def plan(self, t: float, dt: float, key: object = None) -> Plan:
        """The work of the frame at time ``t`` [s] that came ``dt`` [s] after the last one.

        Starts over (reset) on the first frame, on a new ``key``, and when t leaves [t_a, t_c]
        (the clock jumped back, or ahead past the snapshot in progress). Otherwise C's remaining
        steps are spread over the frames left before t_b — ⌈(t_b − t)/dt⌉ of them, dt the last
        positive interval while the clock stands still — so the frame before t_b completes it;
        once t ≥ t_b, what is left is done at once, then the swap."""
        if dt > 0.0 and math.isfinite(dt):
            self.last_dt = float(dt)
        if (self.t_a is None or key != self.key or not math.isfinite(t) or t < self.t_a
                or t > self.t_c):
            self.t_a = float(t)
            self.key = key
            self.done = 0
            return Plan(True, [], 0.0)
        actions: list[Action] = []
        while t >= self.t_b:
            actions += [Action("step", self.t_c, k) for k in range(self.done, self.steps)]
            actions.append(Action("swap", self.t_c))
            self.t_a = self.t_b
            self.done = 0
        frames_left = max(1, math.ceil((self.t_b - t) / self.last_dt - 1e-9))
        now = min(self.steps - self.done, math.ceil((self.steps - self.done) / frames_left))
        actions += [Action("step", self.t_c, k) for k in range(self.done, self.done + now)]
        self.done += now
        weight = min(max((t - self.t_a) / self.period, 0.0), 1.0)
        return Plan(False, actions, weight)

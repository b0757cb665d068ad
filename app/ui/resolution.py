"""Dynamic resolution for the window: the 3D scene's internal scale per side, chosen from the
frame times against ``output.frame_budget_ms`` (pure Python, no GL: tested without a window).

What a user sees is in docs/commands.md ("Dynamic resolution"); headless renders never come
here.

The rule (``output.scale=auto``), with hysteresis so that the scale does not oscillate:

* the scale moves in steps of 1/8 between 1 and :data:`~app.scenes.base.MIN_SCALE`, 0.5;
* after a change, the frame drawn at the new scale first is not judged (its targets and every
  history an effect keeps at the old size are made again), then the median frame time of the
  next frames (:data:`SAMPLES`, or at least :data:`MIN_SAMPLES` once they add up to
  :data:`DECIDE_MS`) is judged: one slow frame alone (a bake) moves nothing;
* above the budget, the scale drops at once to the largest step whose predicted time —
  the median times the ratio of pixel counts — is within :data:`DOWN_TARGET` of the budget
  (a 1 fps scene reaches 0.5 in one decision, not in four);
* below the budget, it rises one step only when even the pessimistic prediction (every
  millisecond scales with the pixel count) stays under :data:`UP_MARGIN` of the budget. A frame
  of fixed cost F plus P per scaled pixel then lands, after the step, under the budget it was
  lowered for: F + P·s'² ≤ (F + P·s²)·(s'/s)² ≤ UP_MARGIN·budget.
A scene whose frame is bound by the CPU stays at 0.5 over its budget: a smaller image would
not be faster.
"""

from __future__ import annotations

import statistics

from ..scenes.base import AUTO_SCALE, MIN_SCALE

#: the automatic scales, full first
LEVELS = (1.0, 0.875, 0.75, 0.625, MIN_SCALE)
#: frames judged after a change (fewer, but at least MIN_SAMPLES so that one spike — a bake, a
#: shader compiling — is not the median, when they already add up to DECIDE_MS)
SAMPLES, MIN_SAMPLES = 6, 3
DECIDE_MS = 1000.0
#: a drop aims at this fraction of the budget, a rise needs its prediction under UP_MARGIN
DOWN_TARGET = 0.9
UP_MARGIN = 0.8


def scaled_size(size: tuple[int, int], scale: float) -> tuple[int, int]:
    """The internal size of a ``size`` window at ``scale`` per side (at least 1×1)."""
    return (max(1, round(size[0] * scale)), max(1, round(size[1] * scale)))


class DynamicResolution:
    """The window's internal scale. Call :meth:`observe` once per frame with the frame time
    the user saw (ms) and the two parameters' values; read :attr:`scale` after it."""

    def __init__(self) -> None:
        self.scale = 1.0
        self.auto = True
        self._samples: list[float] = []
        self._skip = 1  # the first frame measures the window's start, not the scene
        #: every change as (frame number, old scale, new scale, median ms that decided it)
        self.changes: list[tuple[int, float, float, float]] = []
        self.frames = 0

    def _set(self, scale: float, median_ms: float) -> None:
        if scale != self.scale:
            self.changes.append((self.frames, self.scale, scale, median_ms))
            del self.changes[:-50]
            self.scale = scale
            self._skip = 1
        self._samples.clear()

    def observe(self, frame_ms: float, budget_ms: float, setting: float = AUTO_SCALE) -> float:
        """Take one frame's time and return the scale of the next frame."""
        self.frames += 1
        if setting != AUTO_SCALE:  # pinned
            self.auto = False
            self._set(float(setting), frame_ms)
            return self.scale
        if not self.auto:  # back to automatic from a pinned value: start judging afresh
            self.auto = True
            self._samples.clear()
            self._skip = 1
        if self._skip:
            self._skip -= 1
            return self.scale
        if not frame_ms > 0.0:  # a frame that took no time (paused drivers, a bad clock)
            return self.scale
        self._samples.append(float(frame_ms))
        if len(self._samples) < SAMPLES and (len(self._samples) < MIN_SAMPLES
                                             or sum(self._samples) < DECIDE_MS):
            return self.scale
        median = statistics.median(self._samples)
        self._set(self.decide(median, budget_ms), median)
        return self.scale

    def decide(self, median_ms: float, budget_ms: float) -> float:
        """The scale after a judged median frame time (the rule in the module's docstring)."""
        s = self.scale
        if median_ms > budget_ms:
            lower = [v for v in LEVELS if v < s - 1e-9]
            fits = [v for v in lower if median_ms * (v / s) ** 2 <= DOWN_TARGET * budget_ms]
            return fits[0] if fits else (lower[-1] if lower else s)
        higher = [v for v in LEVELS if v > s + 1e-9]
        if higher and median_ms * (higher[-1] / s) ** 2 <= UP_MARGIN * budget_ms:
            return higher[-1]  # the next step up (LEVELS is in decreasing order)
        return s

    def internal_size(self, size: tuple[int, int]) -> tuple[int, int]:
        return scaled_size(size, self.scale)

    def describe(self) -> str:
        how = "auto" if self.auto else "pinned"
        return f"scale {self.scale:.3g} ({how})"


def scale_line(resolution: DynamicResolution, internal: tuple[int, int],
               window: tuple[int, int], budget_ms: float) -> str:
    """The panel's line: the scale, how it is chosen, and the sizes it gives."""
    how = f"auto, budget {budget_ms:g} ms" if resolution.auto else "pinned: output.scale"
    return (f"scale {resolution.scale:.3g} ({how}): {internal[0]}x{internal[1]} of "
            f"{window[0]}x{window[1]}")

"""Foam calibration: the thresholds at which the sea's Jacobian makes foam, chosen so that the
foam covers the whitecap fraction oceanography gives for the wind (beyond the thesis), or the
upstream's fixed threshold."""

from __future__ import annotations

import numpy as np

from ...gpu.cache import MEMO
from ...sim import ocean as oc


class Foam:
    """Per-cascade foam thresholds of the :class:`~.sea.Sea` ``sea``."""

    def __init__(self, effect, sea):
        self.params, self.sea = effect.params, sea
        self._foam = effect.keyed(self._calibrate_foam)  # (threshold, width) per cascade

    def thresholds(self) -> list[tuple[float, float]]:
        """(threshold, ramp width) of the foam source per cascade (FFT) or for the wave set.

        Whitecap mode calibrates them on the sea's own Jacobian (the FFT's λ = 1 derivative fields
        at t = 0 of the cascades as simulated, rescaled for the choppiness; a grid of the
        Gerstner set), so that the foam covers Monahan & O'Muircheartaigh's whitecap fraction
        for the wind."""
        p, s = self.params, self.sea
        model = p["ocean.model"]
        if p["ocean.foam_mode"] == "jacobian":
            t = p["ocean.foam_threshold"]
            return [(t, t)] * (len(s.cascade_bands) if model == "fft" and s.cascade_bands else 1)
        if model == "gerstner":
            s.gerstner_waves()  # drawn now if the sea changed: the key names the current set
        sea = ((s._sim_key, tuple(s._sim_sizes)) if model == "fft" and s._sim_key
               else None if model == "fft" else s._waves.key)
        return self._foam.get((model, p["ocean.choppiness"], s.wind_speed(), sea))

    def _calibrate_foam(self, key) -> list[tuple[float, float]]:
        """The whitecap calibration for ``key`` = (model, choppiness, wind, sea state), made once
        per process (:data:`app.gpu.cache.MEMO`): the sea state (the FFT's spectrum, size,
        cascades and seed, or the Gerstner set's key) names everything it is computed from, and
        every session of a test module calibrates the same few seas (the FFT's t = 0 synthesis
        and the quantiles, or a 192² Gerstner grid, each time). Without a sea state yet (no
        FFT reference, no wave set drawn) it is computed each time, not shared."""
        if not isinstance(key[3], tuple):
            return list(self._whitecaps(key))
        return list(MEMO.get((Foam._whitecaps, key), lambda: self._whitecaps(key)))

    def _whitecaps(self, key) -> tuple[tuple[float, float], ...]:
        model, lam, wind, _ = key
        coverage = oc.whitecap_coverage(wind)
        if model == "fft" and self.sea._sim_cascades:
            # the sea as the GPU simulates it (each cascade on the grid the view chose)
            fields = [oc.synthesize(oc.evolve_amplitudes(c.h0, c.omega, 0.0), c.kx, c.kz, 1.0)
                      for c in self.sea._sim_cascades]
            jacs = [(1 + lam * f.ddx_dx) * (1 + lam * f.ddz_dz) - (lam * f.ddx_dz) ** 2
                    for f in fields]
        elif model == "gerstner":
            waves = self.sea.gerstner_waves()
            span = 2.0 * max(w.wavelength for w in waves)
            g = np.linspace(0.0, span, 192)
            x, z = np.meshgrid(g, g)
            jacs = [oc.gerstner(x, z, 0.0, waves, check=False).jacobian]
        else:
            jacs = [np.ones(4)]  # the sine wave has no horizontal motion: no foam
        # whitecaps break mostly on the long waves: each finer cascade gets half the foam of
        # the one before (57 / 29 / 14 % of the coverage for three)
        return tuple(oc.whitecap_thresholds(jacs, coverage,
                                            shares=[0.5**i for i in range(len(jacs))]))

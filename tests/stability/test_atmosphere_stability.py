"""The atmosphere's numpy model swept to where methods fail (spec/002 §9, issue 4): sun from
the zenith to 20° below the horizon, cameras from 0 m to 10 × the atmosphere's height,
g up to 0.999: no NaN/Inf, bounded values.
"""

from __future__ import annotations

import numpy as np

from app.sim import atmosphere as atm


def test_stability_sweep_is_finite(atmosphere_model, atmosphere_lut):
    """Sun from zenith to 20° below the horizon, cameras from 0 m to 10× the atmosphere height,
    rays up, down and along the horizon, g up to 0.999: no NaN/Inf, bounded values."""
    views = atm.direction([90.0, 45.0, 5.0, 0.5, 0.0, -0.5, -5.0, -45.0, -90.0],
                          np.linspace(0, 320, 9))
    for g in (0.76, 0.999):
        m = atmosphere_model.replace(g=g)
        for height in (0.0, 2.0, 10_000.0, 59_999.0, 60_000.0, 600_000.0):
            cam = atm.local_to_planet([0.0, height, 0.0], m)
            for sun_el in (90.0, 10.0, 0.0, -5.0, -20.0):
                sun = atm.direction(sun_el, 180.0)
                for kw in ({}, {"lut": atmosphere_lut}):
                    s = atm.single_scattering(cam, views, sun, m, steps=8, **kw)
                    assert (np.all(np.isfinite(s.in_scatter))
                            and np.all(np.isfinite(s.transmittance)))
                    assert (np.all(s.in_scatter >= 0.0)
                            and np.all((s.transmittance >= 0) & (s.transmittance <= 1)))
                    # energy: Σ β_s ρ e^(−τ) ds ≤ 1 − T ≤ 1, so L_in ≤ I · max phase
                    # (+ sum slack)
                    cos_theta = views @ sun
                    phase = np.maximum(atm.phase_rayleigh(cos_theta), atm.phase_mie(cos_theta, g))
                    bound = m.sun_intensity * phase
                    assert np.all(s.in_scatter <= 1.1 * bound[:, None])

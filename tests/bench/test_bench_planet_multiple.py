"""`natura bench planet`'s multiple-scattering section (numpy only): a small run writes its chart
and JSON-able numbers, and its summary names each LUT variant's worst error per sun elevation
and the reference's own figures."""

from __future__ import annotations

import json

import numpy as np
import pytest

from app.bench import planet
from app.sim import multiple_scattering as msr


@pytest.mark.slow
def test_multiple_scattering_section_reports_and_charts(tmp_path):
    grid = msr.Grid(n_h=6, n_mu_s=8, n_mu=12, n_phi=6, steps=16, sub=3)
    variants = {"paper": {"size": 16, "directions": 4}}
    ms = planet.multiple_scattering(grid=grid, orders=4, variants=variants, lut_steps=20)
    json.dumps(ms)                                          # plain numbers
    suns = ms["variants"]["paper"]["suns"]
    assert list(suns) == ["3.0", "10.0", "45.0"]
    for d in suns.values():
        err = np.asarray(d["away"]["error"])
        assert err.shape == (len(msr.ELEVATIONS), 3)
        # Hillaire is low near the horizon looking away from the sun, even on this small grid
        assert d["worst"] < 0 and err[0, 1] < -0.03
    assert 0.0 < ms["single_vs_atmosphere_reference"] < 2e-3
    lines = planet.multiple_summary(ms)
    assert lines[0].startswith("multiple scattering: Hillaire against the multi-order reference")
    assert any(ln.strip().startswith("paper") and "sun 10°" in ln for ln in lines)
    assert any("bound:" in ln for ln in lines)
    out = tmp_path / "bench-planet-multiple.png"
    planet.multiple_chart(ms, out)
    assert out.stat().st_size > 10_000

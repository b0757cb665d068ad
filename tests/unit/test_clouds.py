"""Cloud model A (spec/001): the numpy twins of app/sim/clouds.py give the digest's numbers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.sim import clouds as cl

# ---- A: helpers ------------------------------------------------------------------------------

def test_twins_give_the_digest_numbers():
    assert float(cl.remap(0.5, 0, 1, 10, 20)) == pytest.approx(15.0)
    assert float(cl.round_bottom(0.035)) == pytest.approx(0.5)
    assert float(cl.round_bottom(0.2)) == 1.0
    assert float(cl.round_top(0.6, 1.0)) == pytest.approx(0.5)
    assert float(cl.round_top(1.0, 1.0)) == 0.0
    assert float(cl.density_bottom(0.075)) == pytest.approx(0.0375)
    assert float(cl.density_bottom(0.5)) == pytest.approx(0.5)
    assert float(cl.density_top(0.95)) == pytest.approx(0.5)
    assert float(cl.height_density(0.5, 1.0, 0.5)) == pytest.approx(0.5)
    assert float(cl.beer(6.0, 0.5)) == pytest.approx(0.049787, abs=1e-6)  # A4
    assert float(cl.henyey_greenstein(0.3, 0.0)) == pytest.approx(0.0795775, abs=1e-7)  # A5
    assert float(cl.henyey_greenstein(1.0, 0.2)) == pytest.approx(0.149208, abs=1e-6)
    assert float(cl.henyey_greenstein(-1.0, 0.2)) == pytest.approx(0.044210, abs=1e-6)
    x = np.linspace(0.0, 3.0, 30001)  # A6: powder with b = 1 (x = b·d_s)
    p = cl.powder(1.0, x)
    assert p[0] == 0.0
    assert x[np.argmax(p)] == pytest.approx(math.log(3) / 2, abs=1e-3)
    assert p.max() == pytest.approx(4 / (3 * math.sqrt(3)), abs=1e-6)
    for c, value in ((1.0, 1.52959), (0.5, 0.40868), (0.0, 0.074822), (-1.0, 0.076139)):  # A7
        assert float(cl.in_out_scatter(c)) == pytest.approx(value, abs=1e-5)

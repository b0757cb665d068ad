"""Cloud Model B (spec/000 §1.6), criterion 17 on numpy: the Henyey–Greenstein twin of
app/sim/clouds_b.py is normalised.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.sim import clouds_b as twin

# ---- 17: phase, Beer, powder ---------------------------------------------------------------------

@pytest.mark.parametrize("g", [-0.8, 0.0, 0.5, 0.9])
def test_hg_normalised(g):
    # ∫ HG dΩ = 2π ∫_{-1}^{1} HG(μ) dμ; dense midpoint rule in μ (HG is smooth for
    # |g| ≤ 0.9)
    n = 400_000
    mu = -1.0 + (np.arange(n) + 0.5) * (2.0 / n)
    integral = 2.0 * math.pi * twin.henyey_greenstein(mu, g).sum() * (2.0 / n)
    assert integral == pytest.approx(1.0, abs=1e-3)

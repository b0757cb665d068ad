"""The numpy twins of app/sim/maths.py against glsl/common/math.glsl, run on the GPU."""

from __future__ import annotations

import numpy as np

from app.sim import maths
from tests.helpers.glsl_eval import evaluate_points

PROBE = "tests/math_probe"


def test_smoothsteps_and_saturate_match_glsl(gpu):
    rng = np.random.default_rng(3)
    x = rng.uniform(-1.0, 2.0, 500)
    e0 = rng.uniform(-0.5, 0.5, 500)
    e1 = e0 + rng.uniform(0.1, 1.5, 500)
    out = evaluate_points(gpu, np.stack([x, e0, e1], -1), PROBE, {"uProbeMode": 0})
    np.testing.assert_allclose(out[:, 0], maths.smoothstep(e0, e1, x), atol=2e-6)
    np.testing.assert_allclose(out[:, 1], maths.smoothstep_down(e1, e0, x), atol=2e-6)
    np.testing.assert_allclose(out[:, 2], maths.saturate(x), atol=0.0)


def test_safe_normalize_matches_glsl_with_its_fallback(gpu):
    rng = np.random.default_rng(4)
    v = rng.normal(size=(300, 3))
    v[:3] = 0.0  # the failure case: a vanished vector takes the fallback, never NaN
    out = evaluate_points(gpu, v, PROBE, {"uProbeMode": 1})[:, :3]
    twin = maths.safe_normalize(v, np.array([0.0, 1.0, 0.0]))
    np.testing.assert_allclose(out, twin, atol=2e-6)
    assert np.array_equal(twin[:3], np.tile([0.0, 1.0, 0.0], (3, 1)))


def test_compass_and_constants_match_glsl(gpu):
    deg = np.linspace(-360.0, 720.0, 97)
    out = evaluate_points(gpu, np.stack([deg, 0 * deg, 0 * deg], -1), PROBE, {"uProbeMode": 2})
    np.testing.assert_allclose(out[:, :2], np.array([maths.compass_xz(d) for d in deg]),
                               atol=2e-5)
    np.testing.assert_allclose(out[0, 2:], [maths.PI, maths.TWO_PI], rtol=1e-7)

"""The shared sea plane (glsl/common/sea_plane.glsl) against its numpy twin
(app/sim/sea_plane.py) per point, through the probe glsl/tests/sea_plane_probe.frag; and the
twin's own sanity (Fresnel at the horizon, the glitter's energy at the mirror direction)."""

from __future__ import annotations

import numpy as np
import pytest

from app.sim import sea_plane as twin
from tests.helpers.glsl_eval import evaluate_points

PROBE = "tests/sea_plane_probe"


def lower_directions(light_dir, n=600, seed=5) -> np.ndarray:
    """Unit directions below the horizon: random, grazing, straight down and around the light's
    mirror direction (the glitter)."""
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    d[:, 1] = -np.abs(d[:, 1])
    d[:40, 1] = -rng.uniform(1e-6, 2e-3, 40)  # grazing
    mirror = np.array([light_dir[0], -light_dir[1], light_dir[2]])
    d[40:200] = mirror + rng.normal(scale=0.15, size=(160, 3))
    d[40:200, 1] = -np.abs(d[40:200, 1])
    d[200] = (0.0, -1.0, 0.0)
    d[201] = mirror
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


@pytest.mark.parametrize("wind", [0.0, 5.0, 20.0])
def test_directions_and_lobes_match_the_twin(gpu, wind):
    mss = twin.cox_munk_mss(wind)
    p = lower_directions(np.array([0.6, 0.35, -0.72]))
    out = evaluate_points(gpu, p, PROBE, {"uProbeMode": 0, "uMss": mss}).astype(np.float64)
    assert np.abs(out[:, :3] - twin.sea_reflection_direction(p, mss)).max() < 2e-5
    assert np.abs(out[:, 3] - twin.sea_rough_incidence(p, mss)).max() < 2e-6
    assert (out[:, 1] >= np.sqrt(mss) - 1e-6).all()  # the waves never leave a grazing incidence
    out = evaluate_points(gpu, p, PROBE, {"uProbeMode": 1}).astype(np.float64)
    assert np.abs(out[:, :3] - twin.sea_horizon_direction(p)).max() < 2e-5
    rng = np.random.default_rng(1)
    q = np.stack([rng.uniform(0.0, 1.0, 500), np.full(500, mss), rng.uniform(-0.2, 1.2, 500)], -1)
    q[:3, 0] = (1.0, 0.0, 0.01)
    out = evaluate_points(gpu, q, PROBE, {"uProbeMode": 2}).astype(np.float64)
    want = twin.sea_beckmann(q[:, 0], mss)
    assert np.allclose(out[:, 0], want, rtol=2e-4, atol=1e-6 * want.max())
    assert np.allclose(out[:, 1], twin.schlick_fresnel(twin.SEA_F0, q[:, 2]), rtol=1e-5,
                       atol=1e-6)


@pytest.mark.parametrize("elevation,wind,glitter", [(35.0, 5.0, 1.0), (4.0, 2.0, 1.0),
                                                    (60.0, 12.0, 0.0), (-10.0, 5.0, 1.0)])
def test_sea_plane_radiance_matches_the_twin(gpu, elevation, wind, glitter):
    e, a = np.radians(elevation), np.radians(230.0)
    light = np.array([np.sin(a) * np.cos(e), np.sin(e), -np.cos(a) * np.cos(e)])
    mss = twin.cox_munk_mss(wind)
    args = {"horizon": (0.35, 0.4, 0.5), "sky_ambient": (0.1, 0.15, 0.25),
            "light_radiance": (1.2, 1.0, 0.7), "body_color": (0.01, 0.045, 0.06),
            "eye_height": 300.0, "haze_distance": 12000.0}
    p = lower_directions(light)
    uniforms = {"uProbeMode": 3, "uMss": mss, "uHorizon": args["horizon"],
                "uSkyAmbient": args["sky_ambient"], "uLightDir": tuple(light),
                "uLightRadiance": args["light_radiance"], "uBodyColor": args["body_color"],
                "uGlitter": glitter, "uEyeHeight": args["eye_height"],
                "uHazeDistance": args["haze_distance"]}
    got = evaluate_points(gpu, p, PROBE, uniforms)[:, :3].astype(np.float64)
    reflected = 0.2 + 0.5 * np.abs(twin.sea_reflection_direction(p, mss))
    horizon = np.asarray(args["horizon"]) + 0.1 * np.abs(twin.sea_horizon_direction(p)[:, :1])
    want = twin.sea_plane_radiance(p, reflected, horizon, args["sky_ambient"], light,
                                   args["light_radiance"], args["body_color"], mss, glitter,
                                   args["eye_height"], args["haze_distance"])
    assert np.isfinite(got).all()
    err = np.abs(got - want)
    assert (err <= 1e-4 * np.abs(want) + 1e-5).mean() > 0.995, err.max()
    assert err.max() <= 1e-3 * max(want.max(), 1e-6)
    # at the horizon the sea meets the horizon colour; the glitter peaks near the mirror
    grazing = p[:, 1] > -2e-3
    assert np.abs(want[grazing] - horizon[grazing]).max() < 0.05
    if glitter and elevation > 0:
        dull = twin.sea_plane_radiance(p, reflected, horizon, args["sky_ambient"], light,
                                       args["light_radiance"], args["body_color"], mss, 0.0,
                                       args["eye_height"], args["haze_distance"])
        spark = (want - dull).sum(axis=1)
        # (the column stretches toward the horizon: 1/(4 n·v) grows there)
        assert spark[201] > 0.3 * spark.max() and spark[201] > 100 * np.median(spark)


def test_twin_limits():
    # Fresnel: F0 straight down, total at grazing (before the waves' tilt)
    assert twin.schlick_fresnel(twin.SEA_F0, 1.0) == pytest.approx(twin.SEA_F0)
    assert twin.schlick_fresnel(twin.SEA_F0, 0.0) == pytest.approx(1.0)
    # Beckmann is normalised: ∫ D cos θh dω = 1 over the hemisphere of facet normals
    mss = twin.cox_munk_mss(5.0)
    th = np.linspace(0.0, np.pi / 2, 20001)
    integrand = twin.sea_beckmann(np.cos(th), mss) * np.cos(th) * np.sin(th) * 2.0 * np.pi
    assert np.trapezoid(integrand, th) == pytest.approx(1.0, rel=1e-3)
    # straight down, no haze, no light: the body's ambient plus F0 of the reflected sky
    r = twin.sea_plane_radiance(np.array([0.0, -1.0, 0.0]), (1.0, 1.0, 1.0), (0.0, 0.0, 0.0),
                                (0.5, 0.5, 0.5), np.array([0.6, -0.8, 0.0]), (0.0, 0.0, 0.0),
                                (0.1, 0.1, 0.1), 0.01, 1.0, 0.0, 1.0)
    assert r == pytest.approx(0.05 * (1 - twin.SEA_F0) + twin.SEA_F0)

"""The planet's fixed per-pixel work out of the per-method pass: the shadow filter's hardware
depth compares (``sampler2DShadow``, glsl/common/shadow_pcf.glsl) against the manual path, and
the baked ground noise (glsl/planet/ground_noise_bake.frag) against the live 5-octave sum; the
ground pass (glsl/planet/ground.frag: the analytic ground and the background into the G-buffer)
against shading them in the scattering pass; the shared PCF's numpy twin (app/render/shadows.py)
and the bench's "changes" section. Harness: tests/helpers/planet.py."""

from __future__ import annotations

import re

import numpy as np

from app import DEFAULT_SHADER_ROOT
from app.render import shadows
from tests.helpers.planet import DARK_SPACE, camera, sun_sets

GROUND = camera(pos=(0.0, 2.0, 60.0), pitch=4.0)
SPACE = camera(pos=(0.0, 300000.0, 60.0), pitch=-30.0)
SHADE = camera(pos=(-36.0, 600.0, -440.0), pitch=-90.0, fov=40.0)


def test_hardware_compares_give_the_manual_filters_image(planet):
    """Phong surfaces and ground, filtered and nearest, light shafts (method 3): the
    sampler2DShadow path equals the four-texelFetch path within 1e-5 relative."""
    for cam in (GROUND, SHADE):
        for filtered in (True, False):
            sets = {"planet.method": "shadowed", "planet.shadow_filter": filtered,
                    **sun_sets(30.0, 135.0)}
            manual = planet.shoot(cam, (96, 54), {**sets, "planet.shadow_compare": "manual"})
            hw = planet.shoot(cam, (96, 54), {**sets, "planet.shadow_compare": "hardware"})
            rel = np.abs(hw.rgb - manual.rgb) / np.maximum(np.abs(manual.rgb), 1e-6)
            assert rel.max() < 1e-5, (cam.position, filtered, rel.max())
    assert planet.effect.shadow_texture.compare_func == "<="


def test_baked_ground_noise_keeps_the_image(planet):
    """Ground view: the same image; space view (coastlines move by a fraction of a texel):
    mean |Δ| ≤ 1e-3 linear. The bake is made once and rebuilt only when its size changes."""
    effect = planet.effect
    for cam, mean_tol in ((GROUND, 1e-6), (SPACE, 1e-3)):
        sets = {"planet.method": "lut", **DARK_SPACE}
        live = planet.shoot(cam, (160, 90), {**sets, "planet.ground_noise": "live"})
        baked = planet.shoot(cam, (160, 90), {**sets, "planet.ground_noise": "baked"})
        d = np.abs(baked.rgb - live.rgb)
        assert d.mean() <= mean_tol, (cam.position, d.mean(), d.max())
        if cam is SPACE:
            assert d.max() < 0.2 and d.mean() > 0.0   # the bake is used and only moves coasts
    builds = effect.ground_noise_builds
    planet.shoot(SPACE, (64, 36), {"planet.method": "brute_force"})
    assert effect.ground_noise_builds == builds
    planet.shoot(SPACE, (64, 36), {"planet.method": "lut", "planet.ground_noise_size": 256})
    assert effect.ground_noise_builds == builds + 1


def test_ground_pass_keeps_the_image_and_leaves_the_scattering_pass_the_atmosphere(planet):
    """The analytic ground and the background shaded into the G-buffer (planet.ground_pass =
    gbuffer, the default) give the image of shading them in the scattering pass, bit for bit,
    for every method, lit or textured ground, on the ground and the space view; the default
    scattering pass then samples neither the stars nor the ground noise."""
    for cam in (GROUND, SPACE):
        for method in ("brute_force", "lut", "shadowed", "hillaire"):
            for noise in ("baked", "live"):
                sets = {"planet.method": method, "planet.ground_noise": noise}
                old = planet.shoot(cam, (64, 36), {**sets, "planet.ground_pass": "scattering"})
                new = planet.shoot(cam, (64, 36), {**sets, "planet.ground_pass": "gbuffer"})
                assert np.array_equal(new.rgb, old.rgb), (cam.position, method, noise)
                assert np.all(new.gpos[~new.mesh] == 0.0)
    shot = planet.shoot(GROUND, (64, 36), {"planet.method": "lut"})
    ground = ~shot.mesh & (np.arange(36)[:, None] > 20)   # below the horizon, no mesh
    assert ground.any() and np.all(shot.gcolour[ground].max(axis=-1) > 0.0)
    prog = planet.effect.program(planet.effect.composite_spec())
    assert not {"uStarTex", "uGroundNoise", "uGroundNoiseCap"} & set(prog.samplers())


def test_pcf_twin_matches_the_glsl_kernel():
    """The numpy twin's radius and σ are the shared GLSL file's defaults; its weights are the
    normalised Gaussian; a uniform map is fully lit or fully dark; one step edge gives the
    bilinear ramp."""
    text = (DEFAULT_SHADER_ROOT / "common" / "shadow_pcf.glsl").read_text(encoding="utf-8")
    assert int(re.search(r"#define SHADOW_PCF_RADIUS (\d+)", text).group(1)) == shadows.PCF_RADIUS
    assert float(re.search(r"#define SHADOW_PCF_SIGMA ([\d.]+)", text).group(1)) == \
        shadows.PCF_SIGMA
    w = shadows.pcf_weights()
    assert w.shape == (5, 5) and w[2, 2] == 1.0 and np.isclose(w[2, 3], np.exp(-0.5))
    depths = np.full((16, 16), 0.5)
    uv = np.array([[0.31, 0.62]])
    assert shadows.pcf_visibility(depths, uv, 0.4)[0] == 1.0
    assert shadows.pcf_visibility(depths, uv, 0.6)[0] == 0.0
    depths[:, 8:] = 0.0                       # texels 8.. occlude
    xs = (np.arange(7, 9, 0.25) + 0.5) / 16
    ramp = shadows.compare_bilinear(depths, np.stack([xs, np.full_like(xs, 0.5)], -1), 0.4)
    assert np.all(np.diff(ramp) <= 0) and ramp[0] == 1.0 and ramp[-1] == 0.0
    assert np.allclose(shadows.slope_bias(1e-3, [1.0, 0.0]), [1e-3, 5e-3])


def test_bench_changes_section_reports_ratios_and_errors(gl_ctx):
    from app.bench import planet as pbench
    from app.runtime import open_session, scene_params

    session = open_session("planet", scene_params("planet"), ctx=gl_ctx)
    try:
        c = pbench.changes(session, (32, 18), warmup=0, rounds=2)
    finally:
        session.release()
    sc = c["shadow_compare"]
    assert sc["error"]["ground"]["max_rel"] < 1e-5
    assert sc["frame_ratio_hardware_to_manual"]["median"] > 0.0
    g = c["ground_noise"]
    assert g["error"]["ground:lut"]["mean_abs"] < 1e-6
    gp = c["ground_pass"]
    assert all(e["max_abs"] == 0.0 for e in gp["error"].values()), gp["error"]
    assert gp["scattering"]["gbuffer_to_scattering"]["lut"]["median"] > 0.0
    for part in ("frame", "scattering"):
        assert set(g[part]["lut_speedup_over_brute_force"]) == {"live", "baked", "gbuffer"}
    lines = pbench.changes_summary(c)
    text = "\n".join(lines)
    assert "hardware depth compares / manual" in text and "LUT speed-up" in text
    assert "ground pass in the G-buffer" in text

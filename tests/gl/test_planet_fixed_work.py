"""The planet's fixed per-pixel work out of the per-method pass: the shadow filter's hardware
depth compares (``sampler2DShadow``, glsl/common/shadow_pcf.glsl) against the manual path, and
the baked ground noise (glsl/planet/ground_noise_bake.frag) against the live 5-octave sum; the
ground pass (glsl/planet/ground.frag: the analytic ground and the background into the G-buffer)
against shading them in the scattering pass; the shared PCF's numpy twin (app/render/shadows.py)
and the bench's "changes" section. Harness: tests/helpers/planet.py."""

from __future__ import annotations

import re

import numpy as np
import pytest

from app import DEFAULT_SHADER_ROOT
from app.render import shadows
from tests.helpers.planet import DARK_SPACE, camera, sun_sets

GROUND = camera(pos=(0.0, 2.0, 60.0), pitch=4.0)
SPACE = camera(pos=(0.0, 300000.0, 60.0), pitch=-30.0)
SHADE = camera(pos=(-36.0, 600.0, -440.0), pitch=-90.0, fov=40.0)
OUTSIDE = camera(pos=(0.0, 300.0, 6000.0), pitch=2.0)   # south of the city and the mountains


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
    assert planet.effect._shadow.value[0].compare_func == "<="


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
    builds = effect._ground_noise.builds
    planet.shoot(SPACE, (64, 36), {"planet.method": "brute_force"})
    assert effect._ground_noise.builds == builds
    planet.shoot(SPACE, (64, 36), {"planet.method": "lut", "planet.ground_noise_size": 256})
    assert effect._ground_noise.builds == builds + 1


def test_the_ground_noise_bake_is_cached_on_disk_and_read_back_bit_for_bit(
        gl_ctx, tmp_path, monkeypatch):
    """The first session bakes the ground noise into $NATURA_CACHE; the next one (another
    process, as a second ``natura render planet`` would be) loads those texels without baking;
    another size is a file of its own; a file damaged on disk is baked again."""
    from app.bakes import CACHE_ENV
    from app.runtime import open_session, render_frames, scene_params

    monkeypatch.setenv(CACHE_ENV, str(tmp_path))

    def session_texels(size: int):
        session = open_session("planet", scene_params(
            "planet", sets=[f"planet.ground_noise_size={size}", "planet.method=lut"]),
            ctx=gl_ctx)
        try:
            next(render_frames(session, (32, 18)))
            effect = session.scene.effect("planet")
            cap, cube = effect.ground_noise()
            return (cap.read() + b"".join(cube.read(f) for f in range(6)),
                    effect._gradient is not None)  # the bake's noise tables were made
        finally:
            session.release()

    baked, made_tables = session_texels(64)
    (file,) = tmp_path.glob("ground-noise-64-*.bake")
    loaded, made_again = session_texels(64)
    assert made_tables and not made_again and loaded == baked
    assert np.frombuffer(baked, np.float32).std() > 0.01  # a noise, not a cleared texture
    session_texels(128)
    assert len(list(tmp_path.glob("ground-noise-128-*.bake"))) == 1
    blob = bytearray(file.read_bytes())
    blob[-40] ^= 0xFF  # a flipped bit in the texels: the checksum no longer matches
    file.write_bytes(bytes(blob))
    rebaked, made = session_texels(64)
    assert made and rebaked == baked and file.read_bytes() != bytes(blob)


# eight views × two ground passes, each a program variant of its own: 0.5 s with the driver's
# shader cache warm, 8-10 s on a fresh machine (CI), where each variant is compiled
@pytest.mark.slow
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


def test_depth_prepass_keeps_the_image(planet):
    """The meshes' depth drawn first, then each covered pixel shaded once (planet.depth_prepass,
    the default) gives the image of shading every layer as it is drawn: the two passes share the
    vertex stage, whose gl_Position is invariant. Only where two triangles tie in depth (the
    test '<=' keeps the last one drawn, '<' the first) may a pixel differ: at most 1 % of the
    mesh pixels, each by less than 0.5/255 in display."""
    for cam in (GROUND, SHADE):
        sets = {"planet.method": "shadowed", **sun_sets(30.0, 135.0)}
        old = planet.shoot(cam, (96, 54), {**sets, "planet.depth_prepass": False})
        new = planet.shoot(cam, (96, 54), {**sets, "planet.depth_prepass": True})
        assert new.mesh.any() and np.array_equal(new.mesh, old.mesh)
        d = np.abs(new.display - old.display).max(axis=-1)
        assert np.count_nonzero(d) <= 0.01 * np.count_nonzero(new.mesh), cam.position
        assert d.max() < 0.5 / 255.0, (cam.position, d.max() * 255.0)


def test_hillaire_lookup_parts_give_the_one_pass_image(planet, monkeypatch):
    """Method 4's per-pixel pass as the paper's: two lookup-only programs drawn against the
    G-buffer's depth (the sky view where no mesh is, the volume on the meshes) give the image of
    the one pass over every pixel that carries the march as well (what the scene draws when a
    mesh may lie past 90 % of the volume's range) wherever every mesh is within that range;
    the meshes' part is drawn only within the screen rectangle of their bounding box."""
    from app.effects.planet.effect import Planet

    sets = {"planet.method": "hillaire", **sun_sets(20.0, 135.0)}
    rects = []
    for cam in (GROUND, SHADE, OUTSIDE):
        parts = planet.shoot(cam, (96, 54), sets, fresh=True)
        luts = planet.effect.hillaire()
        assert luts.march_mode(False) == 0   # inside the atmosphere: the lookups alone
        frame = planet.scene.frame((96, 54))
        assert not planet.effect.far_meshes(frame)
        rect = planet.effect.mesh_rect(frame, (96, 54))   # the meshes' part's scissor
        rects.append(rect)
        if rect is not None:                                # None: the camera is among them
            x, y, w, h = rect
            rows, cols = np.nonzero(parts.mesh)
            ys = 54 - 1 - rows                              # GL rows count from the bottom
            assert cols.min() >= x and cols.max() < x + w and ys.min() >= y and ys.max() < y + h
            assert w * h < 96 * 54                          # it does cut the pass
        with monkeypatch.context() as m:
            m.setattr(Planet, "far_meshes", lambda self, frame: True)
            assert luts.march_mode(True) == 1
            one = planet.shoot(cam, (96, 54), sets, fresh=True)
        assert parts.mesh.any() and (~parts.mesh).any()
        d = np.abs(parts.rgb - one.rgb) / np.maximum(np.abs(one.rgb), 1e-6)
        assert d.max() < 1e-5, (cam.position, d.max())
    assert rects[-1] is not None   # from outside the meshes' box: a rectangle


def test_bench_rebuilds_the_frame_luts_and_times_a_3d_lookup(planet):
    """The frame rebuilds method 4's sky view and volume only when the camera or the sun moved;
    `natura bench` times their rebuild (what a moving camera costs every frame) and
    ``reference.3d_lookup``, the yardstick of the per-pixel pass: one trilinear read of a 3D
    texture per pixel, whose image is that volume's content (finite, not empty)."""
    planet.shoot(GROUND, (64, 36), {"planet.method": "hillaire"}, fresh=True)
    eff = planet.effect
    frame = planet.scene.frame((64, 36), 0.0)
    target = planet.gpu.target("test", "bench planet", (64, 36))
    try:
        builds = eff.hillaire().builds
        before = dict(builds)
        for p in eff.passes(frame, target):      # a frame with the same camera and sun
            p.run()
        assert builds == before
        bench = {p.name: p for p in eff.bench_passes(frame, target)}
        assert {"planet.hillaire_luts", "planet.scattering[hillaire]",
                "reference.3d_lookup"} <= set(bench)
        bench["planet.hillaire_luts"].run()
        assert builds["skyview"] == before["skyview"] + 1
        assert builds["aerial_perspective"] == before["aerial_perspective"] + 1
        assert builds["transmittance"] == before["transmittance"]
        target.clear()
        bench["reference.3d_lookup"].run()
        img = target.read()[..., :3]
        assert np.all(np.isfinite(img)) and img.min() >= 0.0 and img.max() > 0.0
    finally:
        planet.gpu.free(target)

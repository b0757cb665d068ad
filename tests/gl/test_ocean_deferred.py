"""The ocean's deferred surface pass (``ocean.shading = deferred``, app/effects/ocean/deferred.py)
against today's forward pass: the same image (mean |Δ| ≤ 1e-3 in linear radiance, max bounded)
and the same depth for each wave model, above and under water, at pitches from straight down to
the horizon; the far plane's band of rows leaves no row at the horizon and no gap against the
mesh; nothing of the far plane is drawn when its band is empty."""

from __future__ import annotations

import numpy as np
import pytest

from app.sim.camera import Camera

SIZE = (96, 54)
VIEWS = {
    "above": ((0.0, 4.0, 0.0), -12.0),
    "horizon": ((0.0, 4.0, 0.0), 0.0),
    "down": ((3.0, 30.0, -7.0), -89.9),
    "waterline": ((0.0, 0.0, 0.0), 5.0),
    "under": ((0.0, -3.0, 0.0), 20.0),
    "altitude": ((0.0, 400.0, 0.0), -10.0),
}


def both(s):
    """(forward image, forward depth, deferred image, deferred depth) of one still frame."""
    s.ocean.params.set("ocean.shading", "forward")
    for _ in range(2):  # FFT readback and foam settle on a still sea
        s.frame()
    a = s.frame()[0]
    da = s.target.read_depth()
    s.ocean.params.set("ocean.shading", "deferred")
    b = s.frame()[0]
    db = s.target.read_depth()
    return a, da, b, db


@pytest.mark.parametrize("view", list(VIEWS))
@pytest.mark.parametrize("model", ["sine", "gerstner", "fft"])
def test_deferred_shading_matches_forward(ocean_shot, model, view):
    pos, pitch = VIEWS[view]
    cam = Camera(position=pos, yaw=262.0, pitch=pitch, fov=60.0, far=200000.0)
    s = ocean_shot(("ocean.model=" + model, "ocean.wind=12"), cam, size=SIZE)
    a, da, b, db = both(s)
    assert np.all(np.isfinite(b))
    diff = np.abs(a - b)
    assert diff.mean() <= 1e-3, f"mean |Δ| {diff.mean():.2e}"
    # the FFT's mip filter takes per-pixel explicit gradients (textureGrad) where the forward pass
    # had per-quad implicit ones: a few pixels differ, none wildly
    assert diff.max() <= 0.3 * max(float(a.max()), 1.0), f"max |Δ| {diff.max():.3g}"
    assert np.array_equal(np.isfinite(s.distance()), da < 1.0)
    assert np.max(np.abs(da - db)) <= 1e-6, "the same fragments win the depth test"


def test_far_band_leaves_no_row_at_the_horizon_and_no_gap_to_the_mesh(ocean_shot):
    cam = Camera(position=(0.0, 400.0, 0.0), yaw=30.0, pitch=-10.0, fov=60.0, far=200000.0)
    s = ocean_shot(("ocean.model=fft", "ocean.mesh_extent=600"), cam, size=(80, 45))
    s.ocean.params.set("ocean.shading", "forward")
    s.frame()
    forward = np.isfinite(s.distance())
    s.ocean.params.set("ocean.shading", "deferred")
    s.frame()
    deferred = np.isfinite(s.distance())
    assert s.ocean.surface.far_band is not None
    assert np.array_equal(forward, deferred), "the same pixels hold water"
    dirs = cam.ray_directions(80, 45)
    assert np.all(deferred[dirs[..., 1] < -0.003]), "every ray that meets the sea finds water"
    assert not np.any(deferred[dirs[..., 1] > 0.003]), "no water above the horizon"


@pytest.mark.parametrize("pitch", [89.9, -89.9])
def test_nothing_of_the_far_plane_is_drawn_when_its_band_is_empty(ocean_shot, pitch):
    """Looking straight up the horizon is below the screen; straight down from 4 m the mesh covers
    every pixel: either way the far plane has no row, is not drawn, and the image is forward's."""
    cam = Camera(position=(0.0, 4.0, 0.0), yaw=262.0, pitch=pitch, fov=60.0, far=200000.0)
    s = ocean_shot(("ocean.model=gerstner",), cam, size=(64, 36))
    a, _, b, _ = both(s)
    assert s.ocean.surface.far_band is None
    assert np.abs(a - b).mean() <= 1e-6
    if pitch > 0:
        assert not np.any(np.isfinite(s.distance())), "no water in the sky"


def test_deferred_inputs_are_made_once_per_target_size(ocean_shot):
    s = ocean_shot(("ocean.model=sine",), size=(48, 27))
    s.frame()
    names = sorted(a.name for a in s.session.gpu.owned_by("ocean") if "deferred" in a.name)
    s.frame()
    assert sorted(a.name for a in s.session.gpu.owned_by("ocean")
                  if "deferred" in a.name) == names
    assert len(names) == 5  # three input targets, their framebuffer, the clear's framebuffer


@pytest.mark.parametrize("model", ["sine", "gerstner", "fft"])
def test_the_passes_built_for_the_wave_model_draw_what_the_generic_ones_draw(ocean_shot, model,
                                                                             monkeypatch):
    """The sea's passes are built for the wave model in use (OCEAN_WAVE_MODEL) and the FFT's
    cascade count (OCEAN_CASCADES): the code they do not need left out, which a software
    rasteriser would run masked. The picture of the generic programs (model and count chosen
    per draw by uniforms), above the water and at the waterline (both shading programs),
    deferred and forward: bit for bit, or for the FFT within float32 rounding (its sums over
    the cascades, compiled with constant bounds, round differently)."""
    from app.effects.ocean import surface
    from app.effects.ocean.params import MODELS

    index = MODELS.index(model)
    for view in ("above", "waterline"):
        pos, pitch = VIEWS[view]
        cam = Camera(position=pos, yaw=262.0, pitch=pitch, fov=60.0, far=200000.0)
        s = ocean_shot(("ocean.model=" + model, "ocean.wind=12"), cam, size=SIZE)
        images = {}
        for how in ("built", "generic"):
            with monkeypatch.context() as m:
                if how == "generic":
                    m.setattr(surface, "for_model", lambda spec, *built_for: spec)
                for shading in ("deferred", "forward"):
                    s.ocean.params.set("ocean.shading", shading)
                    for _ in range(2):  # FFT readback and foam settle on a still sea
                        s.frame()
                    images[how, shading] = s.frame()[0]
            if how == "built":
                built = {(dict(p.defines).get("OCEAN_WAVE_MODEL"),
                          dict(p.defines).get("OCEAN_CASCADES"))
                         for p in s.ocean.gpu.shaders.programs() if "waves.glsl" in str(p.files)}
                assert built == {(index, 3 if model == "fft" else None)}, (view, built)
        for shading in ("deferred", "forward"):
            a, b = images["built", shading], images["generic", shading]
            if model != "fft":
                assert np.array_equal(a, b), (view, shading)
            else:  # the cascades' sums compiled with constant bounds: rounded another way
                assert np.abs(a - b).max() <= 1e-6, (view, shading)

"""Believable defaults: the scenes show what their effects are for, at their default settings.

* the clouds scene's sunlight takes its air-mass colour (Rayleigh + aerosol optical depths,
  Kasten–Young air mass: app.sim.daynight.zenith_optical_depth), so clouds at sunset are warmer
  than at noon;
* below the horizon the sky and clouds scenes show a sea (sky.ground = sea), not the thesis's
  flat clamped horizon colour: the lower half of the image is never one flat colour; the same
  under the Preetham sky (scene.sky = preetham: preetham.ground = sea, not the paper's clamped
  horizon colour), with the sun set where the day–night sky has it at noon and at sunset, whose
  colour (Preetham 1999's appendix A.1 transmittance) makes the sunset clouds warmer;
* the materials scene frames its three objects inside the image at 16:9 and at 4:3.

Each threshold fails with the former defaults (white sun, flat band, the old materials camera).
"""

from __future__ import annotations

import numpy as np
import pytest

from app.colour import to_srgb8
from app.effects.sky.effect import DEFAULT_KEYFRAMES
from app.runtime import open_session, render_frames, scene_params
from app.scenes.materials import MaterialsScene
from app.sim.daynight import DayNight, Keyframes

SIZE = (160, 90)
NOON, SUNSET = 12.0, 17.75  # the sun at 59° and at 3.2° above the horizon


def shoot(gl_ctx, scene: str, sets=(), size=SIZE, layer: bool = False):
    """→ (linear image (h, w, 3), sRGB8 as written to a PNG, the clouds' layer or None, the
    camera's ray directions (h, w, 3))."""
    params = scene_params(scene, sets=list(sets))
    session = open_session(scene, params, ctx=gl_ctx)
    try:
        image = next(iter(render_frames(session, size)))[..., :3]
        clouds = session.scene.effect("clouds")._layer.read() if layer else None
        srgb = to_srgb8(image, session.scene.exposure(), params["output.tonemap"])
        dirs = session.scene.camera.ray_directions(*size)
    finally:
        session.release()
    return image, srgb, clouds, dirs


def flat_fraction(pixels: np.ndarray) -> float:
    """The share of pixels that have the single most common exact sRGB8 value."""
    flat = pixels.reshape(-1, 3)
    _, counts = np.unique(flat, axis=0, return_counts=True)
    return float(counts.max() / len(flat))


def assert_lower_half_not_flat(srgb: np.ndarray, dirs: np.ndarray, what: str) -> None:
    h = srgb.shape[0]
    lower = srgb[h // 2:]
    # before: one exact colour covered 31 % (clouds) and 51 % (sky) of the lower half
    assert flat_fraction(lower) < 0.15, (what, flat_fraction(lower))
    below = dirs[..., 1] < -0.005
    assert below.sum() > 0.1 * below.size, what
    # before: below the horizon was one colour (fraction 1, spread 0)
    assert flat_fraction(srgb[below]) < 0.2, (what, flat_fraction(srgb[below]))
    lum = srgb[below].astype(np.float64) @ np.array([0.2126, 0.7152, 0.0722])
    assert lum.std() > 1.0, (what, lum.std())


def column_spread(srgb: np.ndarray, dirs: np.ndarray) -> float:
    """The median over the image's columns of the luminance spread (sRGB8 levels) of their
    pixels below the horizon."""
    lum = srgb.astype(np.float64) @ np.array([0.2126, 0.7152, 0.0722])
    below = dirs[..., 1] < -0.005
    spreads = [lum[below[:, j], j].std() for j in range(lum.shape[1]) if below[:, j].sum() > 3]
    return float(np.median(spreads))


def cloud_colour_ratio(image: np.ndarray, layer: np.ndarray) -> tuple[float, float]:
    """Mean R/B of the clouds' own light (layer rgb / opacity) and of the composite, over the
    pixels the clouds cover (opacity > 0.7)."""
    alpha = 1.0 - layer[..., 3]
    mask = alpha > 0.7
    assert mask.sum() > 100, mask.sum()
    own = layer[..., :3][mask] / alpha[mask][:, None]
    comp = image[mask]
    return (float((own[:, 0] / np.maximum(own[:, 2], 1e-6)).mean()),
            float((comp[:, 0] / np.maximum(comp[:, 2], 1e-6)).mean()))


def test_sunset_clouds_are_warmer_than_noon_clouds(gl_ctx):
    noon, noon_srgb, noon_layer, dirs = shoot(gl_ctx, "clouds", [f"time.hour={NOON}"], layer=True)
    dusk, dusk_srgb, dusk_layer, _ = shoot(gl_ctx, "clouds", [f"time.hour={SUNSET}"], layer=True)
    own_noon, comp_noon = cloud_colour_ratio(noon, noon_layer)
    own_dusk, comp_dusk = cloud_colour_ratio(dusk, dusk_layer)
    # before (white sun): own 1.00 / 1.00, composite 1.09 / 0.91 = 1.20
    assert own_dusk > 1.5 * own_noon, (own_dusk, own_noon)
    assert comp_dusk > 1.6 * comp_noon, (comp_dusk, comp_noon)
    assert_lower_half_not_flat(noon_srgb, dirs, "clouds noon")
    assert_lower_half_not_flat(dusk_srgb, dirs, "clouds sunset")


def test_thesis_sun_colour_stays_available(gl_ctx):
    """sky.sun_extinction = 0 gives the thesis's unreddened sun: sunset clouds are lit as at
    noon (their own colour has the R/B of a white light plus the sky's ambient)."""
    thesis = ["sky.sun_extinction=0,0,0", "clouds.sky_ambient=0"]
    image, _, layer, _ = shoot(gl_ctx, "clouds", [f"time.hour={SUNSET}", *thesis], layer=True)
    own, _ = cloud_colour_ratio(image, layer)
    assert own == pytest.approx(1.0, abs=0.02)


def preetham_sun(hour: float) -> list[str]:
    """--set lines that put the Preetham sky's own sun where the day–night sky has it."""
    d = DayNight(Keyframes.load(DEFAULT_KEYFRAMES), hour=hour).state().sun_dir
    elevation = np.degrees(np.arcsin(d[1]))
    azimuth = np.degrees(np.arctan2(d[0], -d[2])) % 360.0
    return ["scene.sky=preetham", f"preetham.sun_elevation={elevation:.4f}",
            f"preetham.sun_azimuth={azimuth:.4f}"]


@pytest.mark.parametrize("model", ["a", "b"])
def test_preetham_clouds_over_a_sea(gl_ctx, model):
    sets = [f"scene.model={model}"]
    noon, noon_srgb, noon_layer, dirs = shoot(gl_ctx, "clouds", [*sets, *preetham_sun(NOON)],
                                              layer=model == "a")
    dusk, dusk_srgb, dusk_layer, _ = shoot(gl_ctx, "clouds", [*sets, *preetham_sun(SUNSET)],
                                           layer=model == "a")
    # before (preetham.ground = horizon): below the horizon one exact colour covered 41 % at
    # noon (12 % at sunset, where the clamped colour still varies with the azimuth)
    assert_lower_half_not_flat(noon_srgb, dirs, f"preetham {model} noon")
    assert_lower_half_not_flat(dusk_srgb, dirs, f"preetham {model} sunset")
    # and the ground changes down each column (the clamped colour depends on the azimuth only):
    # before 0.12 (noon) and 0.03 (sunset) sRGB8 levels, the sea ≈ 17 and 19
    for srgb, when in ((noon_srgb, "noon"), (dusk_srgb, "sunset")):
        assert column_spread(srgb, dirs) > 3.0, (model, when, column_spread(srgb, dirs))
    if model == "a":  # the cloud layer is read back for model A only
        own_noon, comp_noon = cloud_colour_ratio(noon, noon_layer)
        own_dusk, comp_dusk = cloud_colour_ratio(dusk, dusk_layer)
        assert own_dusk > 1.5 * own_noon, (own_dusk, own_noon)
        assert comp_dusk > 1.6 * comp_noon, (comp_dusk, comp_noon)


@pytest.mark.parametrize("hour", [6.0, 9.0, 12.0, 17.5, 19.0, 0.0])
def test_sky_scene_lower_half_is_not_flat(gl_ctx, hour):
    _, srgb, _, dirs = shoot(gl_ctx, "sky", [f"time.hour={hour}"])
    assert_lower_half_not_flat(srgb, dirs, f"sky {hour} h")


@pytest.mark.parametrize("hour", [3.0, 6.0, 9.0, 15.0, 19.0, 21.0])
def test_clouds_scene_lower_half_is_not_flat_at_any_hour(gl_ctx, hour):
    """Noon and sunset are checked above; dawn, afternoon, dusk and night too."""
    _, srgb, _, dirs = shoot(gl_ctx, "clouds", [f"time.hour={hour}"])
    assert_lower_half_not_flat(srgb, dirs, f"clouds {hour} h")


@pytest.mark.parametrize("size", [(320, 180), (240, 180)], ids=["16:9", "4:3"])
def test_materials_objects_are_inside_the_frame(gl_ctx, size):
    image, _, _, _ = shoot(gl_ctx, "materials", size=size)
    background = np.asarray(MaterialsScene.background)
    obj = np.abs(image - background).max(axis=2) > 1e-3
    # before: 95 of 1000 (16:9) and 163 of 840 (4:3) border pixels showed an object
    border = np.concatenate([obj[:2].ravel(), obj[-2:].ravel(), obj[:, :2].ravel(),
                             obj[:, -2:].ravel()])
    assert not border.any(), int(border.sum())
    # and the objects are not lost in the frame: they span most of its width at 4:3
    xs = np.nonzero(obj.any(axis=0))[0]
    assert (xs.max() - xs.min()) / obj.shape[1] > (0.6 if size[0] / size[1] > 1.5 else 0.8)

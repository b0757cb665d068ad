"""Every view of every scene (the gallery's pictures, tools/gallery.py) renders as a picture: finite
radiance, not one flat colour, using the tonal range. Rendered small (128×72, exactly as
``natura render SCENE --view NAME --size 128x72``), the figures of ``app.teach.look``.

Thresholds, and why:
* ``nonfinite == 0`` — a NaN or Inf in the radiance is a bug at any size.
* ``luma_levels >= 48`` — a lit 3D scene spans many luma levels even at 128×72 (the views
  measured 83 to 229 when this was written: a moonlit sky with its stars is the fewest); a
  frame of one clear colour has 1–3, a flat two-tone frame a handful, a toon frame with bands
  but no gradient ~20.
* ``mode_fraction <= 0.6`` — at most 60 % of the pixels within 2/255 of the commonest luma:
  the most uniform views (a low sunset over a dark plain, the sky seen from under the sea)
  measured 0.42; a frame that fog, a clear colour or an empty sky dominates passes 0.7.
* ``luma_spread >= 16`` — p95 − p5 of luma: even the night views (24–26) use more than a
  sixteenth of the range; a washed-out frame does not.
* ``clipped <= 0.35`` — pure black or a channel at 255: space behind the Earth from orbit is
  28 % black, legitimately; a view blown out to white over a third of the frame is not.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from app.scenes import SCENES
from app.scenes.views import views_of
from app.teach.look import render_view
from tests.helpers.fixtures import BAKING_SCENES, bake_cloud_noise

SIZE = (128, 72)
ALL_VIEWS = [(scene, view.name) for scene in SCENES for view in views_of(scene)]


@pytest.fixture(scope="module")
def renders(gl_ctx):
    out = {}

    def render(scenes):
        for scene in scenes:
            for view in views_of(scene):
                out[(scene, view.name)] = render_view(view, SIZE, ctx=gl_ctx)

    # the scenes without cloud noise first: meanwhile another test process may be baking it
    render(s for s in SCENES if s not in BAKING_SCENES)
    bake_cloud_noise(gl_ctx)
    render(s for s in SCENES if s in BAKING_SCENES)
    return out


def test_there_are_views_to_check():
    assert len(ALL_VIEWS) >= 3 * len(SCENES)


@pytest.mark.parametrize("scene,view", ALL_VIEWS)
def test_the_view_is_a_picture(renders, scene, view):
    image, f = renders[(scene, view)]
    assert image.shape == (SIZE[1], SIZE[0], 3)
    assert f["nonfinite"] == 0
    assert np.asarray(image, float).std() > 2.0  # not constant
    assert f["luma_levels"] >= 48, f
    assert f["mode_fraction"] <= 0.6, f
    assert f["luma_spread"] >= 16, f
    assert f["clipped"] <= 0.35, f


#: how far a view's small render may fall from the look the gallery recorded for it at
#: 1280×720 (docs/gallery/SCENE/figures.json) before the test calls it washed out or blown:
#: resolution changes these figures little (the same picture, fewer pixels: the views measured
#: within ±12 of spread, ±0.04 of saturation and ±0.05 of clipping between the two sizes when
#: this was written), a washed-out or darkened view loses a third of its spread or more
SPREAD_KEPT = 0.75
SATURATION_DROP = 0.08
CLIPPED_RISE = 0.10
GALLERY = Path(__file__).resolve().parents[2] / "docs" / "gallery"


def _recorded(scene: str, view: str) -> dict | None:
    path = GALLERY / scene / "figures.json"
    if not path.is_file():
        return None
    return next((e["figures"] for e in json.loads(path.read_text()) if e["view"] == view), None)


def test_the_gallery_records_every_view():
    missing = [f"{scene}/{view}" for scene, view in ALL_VIEWS if _recorded(scene, view) is None]
    assert missing == [], f"run python tools/gallery.py --scenes ... for {missing}"


@pytest.mark.parametrize("scene,view", ALL_VIEWS)
def test_the_view_keeps_the_look_the_gallery_recorded(renders, scene, view):
    recorded = _recorded(scene, view)
    if recorded is None:
        pytest.fail(f"{scene}/{view} is not in the gallery: run python tools/gallery.py")
    _, f = renders[(scene, view)]
    assert f["luma_spread"] >= SPREAD_KEPT * recorded["luma_spread"], (f, recorded)
    assert f["saturation"] >= recorded["saturation"] - SATURATION_DROP, (f, recorded)
    assert f["clipped"] <= recorded["clipped"] + CLIPPED_RISE, (f, recorded)

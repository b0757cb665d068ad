"""Figures of a picture's look, computed from the 8-bit sRGB image itself, so that a change that
washes a view out, flattens it to one colour or clips it shows as a number (the gallery writes
them beside each view; ``tests/gl/test_gallery_views.py`` bounds them).

* ``luma_p5``, ``luma_p95``, ``luma_spread`` — percentiles of Rec. 709 luma (on the sRGB code
  values, 0–255) and their distance: how much of the tonal range the picture uses;
* ``luma_levels`` — distinct luma levels (0–255) the picture holds;
* ``mode_fraction`` — the share of pixels within 2/255 of the most common luma: a picture
  dominated by one flat colour (a clear colour, a fog, an empty sky) has most of its pixels
  there;
* ``saturation`` — mean HSV saturation (0 grey … 1 pure colour);
* ``clipped`` — the share of pixels with a channel at 255 or every channel at 0;
* ``horizon_contrast`` — for a view that shows a horizon (the camera's pitch and field of view
  put the row where rays run level inside the frame): the mean luma of a band above that row
  minus that of a band below it, over 255 (sky against sea or land; None without a horizon).
"""

from __future__ import annotations

import math
from contextlib import closing

import numpy as np

from ..colour import LUMINANCE, to_srgb8
from ..runtime import open_session, placed_camera, render_frames, scene_params

#: rows of the horizon bands, as a share of the image height
BAND = 0.06


def luma(srgb8: np.ndarray) -> np.ndarray:
    return np.asarray(srgb8[..., :3], dtype=np.float64) @ LUMINANCE


def horizon_row(height: int, pitch_deg: float, fov_deg: float) -> float | None:
    """Row (0 at the top) where the camera's rays are level, for a camera without roll; None
    when it is outside the image."""
    t = math.tan(math.radians(pitch_deg)) / math.tan(math.radians(fov_deg) * 0.5)
    if not -1.0 < t < 1.0:
        return None
    return (0.5 + 0.5 * t) * height  # NDC y = -tan(pitch)/tan(fov/2): above the centre


def figures(srgb8: np.ndarray, camera=None) -> dict[str, float | int | None]:
    img = np.asarray(srgb8)
    y = luma(img)
    levels = np.round(y).astype(int)
    hist = np.bincount(levels.ravel(), minlength=256)
    mode = int(hist.argmax())
    near = hist[max(mode - 2, 0):mode + 3].sum() / levels.size
    rgb = np.asarray(img[..., :3], dtype=np.float64)
    hi, lo = rgb.max(-1), rgb.min(-1)
    sat = np.where(hi > 0, (hi - lo) / np.maximum(hi, 1e-9), 0.0)
    clipped = ((rgb >= 255).any(-1) | (rgb <= 0).all(-1)).mean()
    p5, p95 = np.percentile(y, [5, 95])
    out: dict[str, float | int | None] = {
        "luma_p5": round(float(p5), 1), "luma_p95": round(float(p95), 1),
        "luma_spread": round(float(p95 - p5), 1),
        "luma_levels": int((hist > 0).sum()),
        "mode_fraction": round(float(near), 4),
        "saturation": round(float(sat.mean()), 4),
        "clipped": round(float(clipped), 4),
        "horizon_contrast": None,
    }
    if camera is not None:
        h = img.shape[0]
        row = horizon_row(h, camera.pitch, camera.fov)
        band = max(1, int(BAND * h))
        if row is not None and band <= row <= h - band:
            r = int(round(row))
            above, below = y[max(r - band, 0):r], y[r:r + band]
            out["horizon_contrast"] = round(float(above.mean() - below.mean()) / 255.0, 4)
    return out


def render_view(view, size: tuple[int, int], ctx=None) -> tuple[np.ndarray, dict]:
    """A view rendered as ``natura render SCENE --view NAME`` renders it: the 8-bit sRGB image
    and its :func:`figures`, plus ``nonfinite``: NaN or Inf values in the linear radiance."""
    params = scene_params(view.scene, view=view)
    camera = placed_camera(view.scene, params, view)
    with open_session(view.scene, params, ctx=ctx, camera=camera) as session:
        with closing(render_frames(session, size, warmup=view.frames - 1)) as frames:
            image = next(frames)
        srgb = to_srgb8(image[..., :3], session.scene.exposure(), params["output.tonemap"])
        out = figures(srgb, session.scene.camera)
        out["nonfinite"] = int((~np.isfinite(image[..., :3])).sum())  # before the tone map
        return srgb, out

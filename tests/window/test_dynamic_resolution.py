"""Dynamic resolution (app/ui/resolution.py) and ``natura bench --window``
(app/ui/window_bench.py): the controller's rule with made-up frame times (no window), the
``output.*`` parameters, headless renders at full scale whatever ``output.scale`` says, and the
real window under Xvfb — the scale drops with a tiny budget, the panel and the HUD stay sharp
while the scene is enlarged, ``output.scale`` pins it — the window bench's report, and the
display pass's enlargement against the full Catmull-Rom kernel (headless). No test
here asserts a time or an fps: the window's frames are fed a fixed 1/60 s where the rule is
checked, and the bench's figures are only checked for their form."""

from __future__ import annotations

import json
import os
import random
import sys

import numpy as np
import pytest

from app.errors import ParamError
from app.ui.resolution import (
    DOWN_TARGET,
    LEVELS,
    SAMPLES,
    UP_MARGIN,
    DynamicResolution,
    scale_line,
    scaled_size,
)
from tests.helpers.window_driver import NO_XVFB, XVFB_SKIP, drive, under_xvfb

pytestmark = pytest.mark.window
needs_xvfb = pytest.mark.skipif(NO_XVFB, reason=XVFB_SKIP)


def feed(res: DynamicResolution, times, budget=33.0, setting=0.0) -> list[float]:
    """The scale after each of ``times`` (ms; a callable of the scale gives the time)."""
    out = []
    for t in times:
        ms = t(res.scale) if callable(t) else t
        out.append(res.observe(ms, budget, setting))
    return out


# ---- the rule, without a window --------------------------------------------------------------

def test_a_slow_frame_drops_to_the_largest_step_predicted_to_fit():
    res = DynamicResolution()
    scales = feed(res, [50.0] * (1 + SAMPLES))  # the first frame is not judged
    assert scales[:-1] == [1.0] * SAMPLES
    # 50 ms × s² within 0.9 × 33 ms: 0.875 predicts 38.3 ms, 0.75 predicts 28.1 ms
    assert scales[-1] == 0.75
    assert 50.0 * 0.875**2 > DOWN_TARGET * 33.0 >= 50.0 * 0.75**2
    assert res.changes == [(1 + SAMPLES, 1.0, 0.75, 50.0)]


def test_a_very_slow_scene_reaches_half_scale_in_three_frames_not_six():
    res = DynamicResolution()
    scales = feed(res, [900.0] * 4)  # 1 fps: judged once three frames add up to over 1 s
    assert scales == [1.0, 1.0, 1.0, 0.5]
    assert feed(res, [900.0] * 20)[-1] == 0.5  # CPU-bound: it stays at the floor
    assert min(LEVELS) == 0.5


def test_a_fast_frame_rises_one_step_at_a_time_only_when_even_the_worst_case_fits():
    res = DynamicResolution()
    res.scale = 0.5
    budget = 33.0
    # 18 ms at 0.5: all-pixels prediction at 0.625 is 28.1 ms > 0.8 × 33 = 26.4: it stays
    assert feed(res, [18.0] * 20, budget)[-1] == 0.5
    assert 18.0 * (0.625 / 0.5) ** 2 > UP_MARGIN * budget
    scales = feed(res, [5.0] * 40, budget)
    steps = [b for a, b in zip([0.5, *scales], scales) if b != a]
    assert steps == [0.625, 0.75, 0.875, 1.0]


def test_a_pinned_scale_holds_whatever_the_frames_take_and_auto_starts_afresh():
    res = DynamicResolution()
    assert set(feed(res, [500.0] * 12, setting=1.0)) == {1.0} and not res.auto
    assert set(feed(res, [500.0] * 12, setting=0.6)) == {0.6}
    assert set(feed(res, [1.0] * 12, setting=0.6)) == {0.6}
    assert feed(res, [1.0], setting=0.0) == [0.6] and res.auto  # back to auto: judged afresh
    scales = feed(res, [1.0] * 12)
    assert scales[-1] > 0.6  # fast frames: it rises from the pinned value


def test_one_slow_frame_among_fast_ones_moves_nothing():
    """A bake or a shader compiling makes one frame take seconds: not a reason to drop."""
    res = DynamicResolution()
    assert set(feed(res, [10.0, 5000.0, 10.0, 10.0, 10.0, 10.0, 10.0, 10.0])) == {1.0}
    res.scale = 0.5
    assert feed(res, [5000.0, 5.0, 5.0])[-1] == 0.625  # nor a reason to stay down


def test_frames_of_no_time_are_not_judged():
    res = DynamicResolution()
    assert set(feed(res, [0.0, -5.0, float("nan")] * 10, budget=1.0)) == {1.0}


@pytest.mark.parametrize("fixed, per_pixel, budget", [
    (2.0, 60.0, 33.0), (10.0, 30.0, 33.0), (5.0, 200.0, 33.0), (30.0, 10.0, 33.0),
    (1.0, 25.0, 16.7), (40.0, 5.0, 33.0)])
def test_a_scene_of_fixed_plus_per_pixel_cost_settles_without_oscillating(fixed, per_pixel,
                                                                           budget):
    """A frame of F + P·s² ms, ±10 % noise: the scale settles in a few changes, then never
    moves again, at the largest step within the budget (or the floor when none is)."""
    rng = random.Random(7)
    res = DynamicResolution()
    feed(res, [lambda s: (fixed + per_pixel * s * s) * rng.uniform(0.9, 1.1)
               for _ in range(400)], budget)
    assert [c for c in res.changes if c[0] > 100] == [], res.changes
    assert len(res.changes) <= 4, res.changes
    assert all(new < old for _, old, new, _ in res.changes), res.changes  # never back up
    cost = fixed + per_pixel * res.scale ** 2
    assert cost <= budget or res.scale == min(LEVELS)
    higher = [s for s in LEVELS if s > res.scale]
    if higher:  # and as large as the budget allows: the next step up would not fit
        assert fixed + per_pixel * higher[-1] ** 2 > DOWN_TARGET * budget * 0.9


def test_the_internal_size_and_the_panels_line():
    assert scaled_size((640, 360), 0.5) == (320, 180)
    assert scaled_size((1280, 720), 0.875) == (1120, 630)
    assert scaled_size((1, 1), 0.5) == (1, 1)
    res = DynamicResolution()
    assert scale_line(res, (640, 360), (640, 360), 33.0) == \
        "scale 1 (auto, budget 33 ms): 640x360 of 640x360"
    feed(res, [1.0], setting=0.75)
    assert scale_line(res, (480, 270), (640, 360), 33.0).startswith("scale 0.75 (pinned")


# ---- the parameters ---------------------------------------------------------------------------

def test_the_output_parameters():
    from app.runtime import scene_params

    params = scene_params("sky")
    assert params["output.frame_budget_ms"] == 33.0 and params["output.scale"] == 0.0
    assert params.spec("output.frame_budget_ms").unit == "ms"
    for text, value in (("auto", 0.0), (" Auto ", 0.0), ("0", 0.0), ("1", 1.0), ("0.5", 0.5),
                        ("0.8", 0.8)):
        assert params.set("output.scale", text) == value
    for bad in ("0.3", "1.5", "-1", "half", "nan"):
        with pytest.raises(ParamError) as err:
            params.set("output.scale", bad)
        assert "\n" not in str(err.value) and "auto (or 0) or a number in [0.5, 1]" in str(
            err.value)
    assert scene_params("sky", sets=["output.scale=auto"])["output.scale"] == 0.0
    with pytest.raises(ParamError):
        params.set("output.frame_budget_ms", 0.0)
    assert params.set("output.upscale", "bilinear") == "bilinear"


def test_headless_render_is_full_scale_whatever_output_scale_says(tmp_path):
    """``natura render`` never scales: the same picture, at its --size, with output.scale at
    0.5 and a budget no frame meets as with the defaults."""
    from PIL import Image

    from tests.helpers.cli import run

    images = []
    for name, sets in (("default", []), ("half", ["--set", "output.scale=0.5", "--set",
                                                  "output.frame_budget_ms=1"])):
        r = run("render", "sky", "--size", "64x36", "--time", "10", "--out", f"{name}.png",
                *sets, cwd=tmp_path)
        assert r.returncode == 0, r.stderr
        images.append(np.asarray(Image.open(tmp_path / f"{name}.png")))
    assert images[0].shape[:2] == (36, 64)
    assert np.array_equal(images[0], images[1])


# ---- the real window under Xvfb ---------------------------------------------------------------

@needs_xvfb
@pytest.mark.slow  # a real window: about 15 s on two cores
def test_dynamic_resolution_in_the_maritime_window(tmp_path):
    r, _ = drive("dynamic-resolution", tmp_path)
    assert r["render_error"] == ""
    window = r["window"]
    assert window == [640, 360]
    auto = r["auto"]
    # a 1 ms budget: the scale drops below 1, the scene's target shrinks with it, and ImGui
    # (the panel, the HUD) still draws at the window's size
    assert auto[0]["scale"] == 1.0 and auto[-1]["scale"] < 1.0
    for a in auto:
        assert a["target"] == list(scaled_size(tuple(window), a["scale"]))
        assert a["imgui"] == window and a["imgui_fb_scale"] == [1.0, 1.0]
    assert r["auto_changes"] and r["auto_changes"][0][1:3] == [1.0, auto[-1]["scale"]]
    assert "fps" in r["fps_lines"][0]
    assert r["scale_lines"] == [f"scale {auto[-1]['scale']:.3g} (auto, budget 1 ms): "
                                f"{auto[-1]['target'][0]}x{auto[-1]['target'][1]} of 640x360"]
    # output.scale pins it, whatever the budget
    assert r["pinned_targets"] == {"1": [640, 360], "0.5": [320, 180]}
    assert r["pinned_half_after"] == 0.5
    assert r["pinned_line"] == ["scale 0.5 (pinned: output.scale): 320x180 of 640x360"]
    assert r["pinned_full_after"] == {"scale": 1.0, "target": [640, 360]}
    # the panel and the HUD are as sharp at 0.5 as at 1; the scene behind them is softer
    assert r["mask_pixels"]["panel"] > 20000 and r["mask_pixels"]["hud"] > 20000
    assert r["mask_pixels"]["scene"] > 20000 and r["hud_rects_same"]
    sharp = r["sharpness"]
    for ui in ("panel", "hud"):
        full, half = sharp[ui]
        assert half > 0.9 * full, (ui, sharp)
    full, half = sharp["scene"]
    assert half < 0.8 * full, sharp
    assert r["panel_diff"] < 4.0  # the panel's pixels barely change (its translucent back)
    # a screenshot at 0.5 is rendered at the window's size, and the scale comes back after it
    assert r["screenshots"] == [[640, 360]]
    assert r["after_screenshot_target"] == [320, 180]
    # the panel's own widget for output.scale
    assert r["scale_widgets"] == ["auto##output.scale", "auto##output.scale",
                                  "scale##output.scale"]


def _bench_window(tmp_path, *args):
    return under_xvfb([sys.executable, "-m", "app.cli", "bench", *args], cwd=tmp_path,
                      timeout=300)


@needs_xvfb
@pytest.mark.slow  # a real window: about 15 s on two cores
def test_natura_bench_window_reports_fps_and_the_scale(tmp_path):
    proc = _bench_window(tmp_path, "sky", "--window", "--size", "320x180", "--repeat", "6",
                         "--warmup", "2")
    assert proc.returncode == 0, proc.stderr[-2000:]
    report_path = tmp_path / "bench-results" / "sky-window-0001.json"
    report = json.loads(report_path.read_text())
    assert report["scene"] == "sky" and report["kind"] == "window"
    assert report["frames"] == 6 and len(report["times_ms"]) == 6
    assert report["warmup_frames"] == 2 and report["window_size"] == [320, 180]
    t = report["frame_ms"]
    assert t["min_ms"] <= t["p25_ms"] <= t["median_ms"] <= t["p75_ms"] <= t["max_ms"]
    assert report["fps"] == pytest.approx(1000.0 / t["median_ms"])
    s = report["scale"]
    assert s["auto"] and s["final"] in LEVELS and report["scale_setting"] == "auto"
    assert sum(s["share"].values()) == pytest.approx(1.0)
    assert report["internal_size"] == list(scaled_size((320, 180), s["final"]))
    assert report["render_error"] is None and report["renderer"]
    assert "fps" in proc.stdout and str(report_path.relative_to(tmp_path)) in proc.stdout
    # pinned at 1: every frame at full scale; --out names the report
    proc = _bench_window(tmp_path, "sky", "--window", "--size", "320x180", "--repeat", "3",
                         "--warmup", "1", "--set", "output.scale=1", "--out", "pinned.json")
    assert proc.returncode == 0, proc.stderr[-2000:]
    pinned = json.loads((tmp_path / "pinned.json").read_text())
    assert pinned["scale"]["share"] == {"1": 1.0} and not pinned["scale"]["auto"]
    assert pinned["internal_size"] == [320, 180] and pinned["scale_setting"] == 1.0


def test_natura_bench_window_without_a_display_or_with_a_pass_option(tmp_path):
    from tests.helpers.cli import run, usage_error

    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    line = usage_error(run("bench", "sky", "--window", cwd=tmp_path, env=env))
    assert "needs a display" in line and "xvfb-run" in line
    line = usage_error(run("bench", "sky", "--window", "--sizes", "64x36", cwd=tmp_path,
                           env=env))
    assert "--sizes" in line and "allowed" in line
    line = usage_error(run("bench", "boat", "--window", cwd=tmp_path))  # a numpy bench
    assert "--window is for scene benches" in line and "allowed" in line
    assert not (tmp_path / "bench-results").exists()


# ---- the display pass's enlargement (glsl/common/display.frag), on the headless context -------

def _catmull_rom_16(image: np.ndarray, out_size: tuple[int, int]) -> np.ndarray:
    """The reference: the full separable 4 × 4 Catmull-Rom kernel (16 taps, edge texels
    repeated beyond the border) at the centres of an ``out_size`` grid — written from the
    kernel's definition, not from the shader's five-tap shortcut."""
    def weights(t):
        return np.stack([(-t**3 + 2 * t**2 - t) / 2, (3 * t**3 - 5 * t**2 + 2) / 2,
                         (-3 * t**3 + 4 * t**2 + t) / 2, (t**3 - t**2) / 2], axis=-1)

    def along(axis_len, n_out):
        pos = (np.arange(n_out) + 0.5) / n_out * axis_len - 0.5
        base = np.floor(pos).astype(int)
        taps = np.clip(base[:, None] + np.arange(-1, 3)[None, :], 0, axis_len - 1)
        return taps, weights(pos - base)

    h, w = image.shape[:2]
    xs, wx = along(w, out_size[0])
    ys, wy = along(h, out_size[1])
    rows = np.einsum("xk,hxkc->hxc", wx, image[:, xs])  # (h, W, c)
    return np.einsum("yk,ykxc->yxc", wy, rows[ys])


def _display(gpu, image: np.ndarray, out_size: tuple[int, int], bicubic: bool) -> np.ndarray:
    """``image`` (linear, h × w × 3) through the window's display pass (tone map ``clamp``,
    exposure 1) into an 8-bit ``out_size`` framebuffer, as the window draws it."""
    from app.ui.display import draw_display

    h, w = image.shape[:2]
    rgba = np.concatenate([image, np.ones((h, w, 1))], axis=2).astype("f4")
    target = gpu.target("test", "scene", (w, h))
    target.color.write(rgba.tobytes())
    target.color.repeat_x = target.color.repeat_y = False  # as the window's target
    fbo = gpu.ctx.simple_framebuffer(out_size, components=4)
    try:
        fbo.use()
        gpu.ctx.viewport = (0, 0, *out_size)
        draw_display(gpu, target.color, 1.0, "clamp", bicubic=bicubic)
        data = np.frombuffer(fbo.read(components=3), dtype=np.uint8)
        return data.reshape(out_size[1], out_size[0], 3).astype(float)
    finally:
        fbo.release()
        gpu.free(target)


def test_the_bicubic_enlargement_follows_catmull_rom_and_is_exact_at_full_scale(gpu):
    """Half scale enlarged ×2 (and 0.625, ×1.6): the five-tap Catmull-Rom of the display pass
    is within 2/255 (mean 0.5/255) of the full 16-tap kernel on a smooth image (a sine of
    period 13 texels; the filters' bilinear taps are of limited precision on a GPU), and much
    nearer to it than bilinear is; at full scale both filters give the texels back exactly."""
    from app.colour import linear_to_srgb

    rng = np.random.default_rng(3)
    h, w = 18, 32
    y, x = np.mgrid[0:h, 0:w] / np.array([h, w])[:, None, None]
    image = np.stack([0.4 + 0.3 * np.sin(2 * np.pi * (2.5 * x + y) + phase)
                      for phase in (0.0, 1.0, 2.0)], axis=2)
    for out in ((64, 36), (51, 29)):  # scale 0.5, and about 0.625
        ref = linear_to_srgb(_catmull_rom_16(image, out)) * 255.0
        cubic = np.abs(_display(gpu, image, out, bicubic=True) - ref)
        linear = np.abs(_display(gpu, image, out, bicubic=False) - ref)
        assert cubic.max() <= 2.0 and cubic.mean() <= 0.5, (out, cubic.max(), cubic.mean())
        assert linear.mean() > 2.0 * cubic.mean() + 0.3, (out, linear.mean(), cubic.mean())
    noisy = rng.uniform(0.0, 1.0, (h, w, 3))  # every texel its own value: nothing to hide
    texels = np.round(linear_to_srgb(noisy) * 255.0)
    for bicubic in (True, False):
        assert np.abs(_display(gpu, noisy, (w, h), bicubic) - texels).max() <= 1.0

"""The toon look, measured (spec/003 §0's aim — "a less realistic, more child-friendly look",
"colores más intensos" — and §6 criterion 37): the same village view with the thesis's toon
look (Stepped CelShader / ComplexCelShader, spec/003 §2.12) against Lambert / Blinn–Phong
(``village.toon = 0``), everything else equal.

Measured on the **lit opaque objects** — the houses, the props and the people (the village's
debug view ``groups`` gives the mask), where the sun reaches them (its ``shadow`` view: full
visibility) — in the image a user gets (tone-mapped sRGB, 8 bits):

* ``levels``: the fewest distinct luma values (Rec. 709 weights on the 8-bit sRGB channels,
  rounded) that hold 95 % of the masked pixels (:data:`LEVEL_SHARE` left out) — a band is one
  heavily populated level, a gradient needs as many levels as it spans, and the few pixels of
  antialiased edges and texture detail fall in the 5 % left out; ``levels_all`` counts every
  distinct value;
* ``saturation``: the mean HSV saturation (max − min)/max of the masked pixels;
* ``ms``: the village pass with each look, interleaved rounds (what the toon look costs).

Both under the scene's own tone map (the village's preset: ``clamp``, Unity 5's LDR forward
output, which the thesis used) and under ACES (``by_tonemap``).

Criterion 37 asks for fewer levels and an equal or higher mean saturation with the toon look.
"""

from __future__ import annotations

import numpy as np

from ..colour import to_srgb8
from ..gpu.timing import time_interleaved
from ..runtime import open_session, render_frames, scene_params
from ..sim.camera import Camera

#: the levels counted hold all the masked pixels but this share
LEVEL_SHARE = 0.05
#: the view: from the plaza's south-west toward Lord Barus's hall and the vendor's house, the
#: afternoon sun from the west
CAMERA = Camera(position=(-9.0, 4.2, 12.0), yaw=20.0, pitch=-8.0, fov=60.0, near=0.1,
                far=2000.0)
HOUR = 15.0
LOOKS = {"toon": ["village.toon=2"], "lambert_blinn_phong": ["village.toon=0"]}
#: the tone maps the looks are also measured under (the scene's own first: the village's is
#: clamp, Unity 5's LDR output; ACES's shoulder desaturates the brighter toon bands)
TONEMAPS = ("clamp", "aces")
#: the debug view's flat colours of the groups counted (surface.frag's DebugGroupColour)
OBJECT_GROUPS = (1, 2, 5)  # walls, solids, people


def luma8(srgb8: np.ndarray) -> np.ndarray:
    """Rec. 709 luma of 8-bit sRGB pixels, rounded to integer levels."""
    return np.rint(srgb8[..., :3].astype(np.float64) @ [0.2126, 0.7152, 0.0722]).astype(int)


def saturation(srgb8: np.ndarray) -> np.ndarray:
    rgb = srgb8[..., :3].astype(np.float64)
    hi, lo = rgb.max(axis=-1), rgb.min(axis=-1)
    return np.where(hi > 0, (hi - lo) / np.maximum(hi, 1e-9), 0.0)


def levels(values: np.ndarray, share: float = LEVEL_SHARE) -> int:
    """The fewest distinct values that together hold all but ``share`` of ``values`` (the most
    populated first): a band is one level, a gradient needs as many as it spans; the stray
    pixels of antialiased edges and texture detail fall in the share left out."""
    if values.size == 0:
        return 0
    _, counts = np.unique(values, return_counts=True)
    held = np.cumsum(np.sort(counts)[::-1])
    return int(np.searchsorted(held, (1.0 - share) * values.size) + 1)


def run(gpu, quick: bool = False) -> dict:
    size = (320, 180) if quick else (640, 360)
    base = [f"time.hour={HOUR}", "village.msaa=0", "fog.mode=off"]
    out: dict = {"size": list(size), "hour": HOUR, "level_share": LEVEL_SHARE,
                 "camera": {"position": list(CAMERA.position), "yaw": CAMERA.yaw,
                            "pitch": CAMERA.pitch}, "looks": {}}
    sessions = {}
    try:
        def session(extra):
            params = scene_params("village", sets=[*base, *extra])
            if "fog.mode" not in params:  # pragma: no cover - the scene always has fog
                raise RuntimeError("the village scene has no fog.mode")
            cam = Camera(position=CAMERA.position, yaw=CAMERA.yaw, pitch=CAMERA.pitch,
                         fov=CAMERA.fov, near=CAMERA.near, far=CAMERA.far)
            s = open_session("village", params, ctx=gpu.ctx, camera=cam)
            s.params.set("village.camera", "free")
            return s

        # one session for the mask and both looks: the look is the uniform village.toon, so
        # the looks differ in nothing else (three sessions, and their first-frame bakes, before:
        # the same images, every figure identical); its debug views give the mask first
        probe = session(LOOKS["toon"])
        sessions["village"] = probe
        image_view = probe.params["village.debug"]
        probe.params.set("village.debug", "groups")
        groups = next(render_frames(probe, size))[..., :3]
        probe.params.set("village.debug", "shadow")
        shadow = next(render_frames(probe, size))[..., 0]
        probe.params.set("village.debug", image_view)
        objects = np.zeros(groups.shape[:2], bool)
        for g in OBJECT_GROUPS:
            colour = np.array([g & 1, (g >> 1) & 1, (g >> 2) & 1], np.float32) * 0.8 + 0.1
            objects |= np.all(np.abs(groups - colour) < 1e-3, axis=-1)
        lit = objects & (shadow > 0.999)
        out["masked_pixels"] = int(lit.sum())
        out["object_pixels"] = int(objects.sum())
        out["tonemap"] = probe.params["output.tonemap"]
        out["by_tonemap"] = {}

        def look_of(name: str) -> None:
            for assignment in LOOKS[name]:
                probe.params.set_from_string(assignment)

        for name in LOOKS:
            look_of(name)
            image = next(render_frames(probe, size))[..., :3]
            for tm in dict.fromkeys((out["tonemap"], *TONEMAPS)):
                srgb = to_srgb8(image, probe.scene.exposure(), tm)
                y = luma8(srgb)[lit]
                look = {"levels": levels(y), "levels_all": int(np.unique(y).size),
                        "saturation": float(saturation(srgb)[lit].mean()) if y.size else 0.0,
                        "mean_luma": float(y.mean()) if y.size else 0.0}
                out["by_tonemap"].setdefault(tm, {})[name] = look
                if tm == out["tonemap"]:
                    out["looks"][name] = dict(look)
        # the village pass with each look (what the toon look costs), interleaved
        target = probe.gpu.target("bench", "look", size)
        frame = probe.scene.frame(size)
        probe.scene.render(frame, target)  # slots (shadows) filled, as in a frame
        draw = probe.scene.effect("village").draw

        def variant(name: str):
            def run() -> None:
                look_of(name)
                draw(frame, target)
            return run

        variants = {name: variant(name) for name in LOOKS}
        timed = time_interleaved(gpu.ctx, variants, warmup=1, rounds=5 if quick else 15)
        summary = timed.summary("lambert_blinn_phong")
        for name in LOOKS:
            out["looks"][name]["village_pass_ms"] = summary[name]["median_ms"]
        out["toon_cost_ratio"] = summary["toon"]["ratio_to_lambert_blinn_phong"]["median"]
    finally:
        for s in sessions.values():
            s.release()
    toon, plain = out["looks"]["toon"], out["looks"]["lambert_blinn_phong"]
    out["fewer_levels"] = toon["levels"] < plain["levels"]
    out["saturation_not_lower"] = toon["saturation"] >= plain["saturation"]
    return out


def chart(report: dict, path, force: bool = False) -> None:
    from . import pyplot, write_chart

    plt = pyplot()

    names = list(report["looks"])
    looks = report["looks"]
    fig, axes = plt.subplots(1, 3, figsize=(10, 3.2))
    labels = ["toon (Stepped)" if n == "toon" else "Lambert / Blinn–Phong" for n in names]
    colours = ["#d95f02", "#7570b3"]
    axes[0].bar(labels, [looks[n]["levels"] for n in names], color=colours)
    axes[0].set_title(f"luma levels holding {1 - report['level_share']:.0%} of the pixels",
                      fontsize=9)
    axes[1].bar(labels, [looks[n]["saturation"] for n in names], color=colours)
    axes[1].set_title("mean HSV saturation", fontsize=9)
    axes[2].bar(labels, [looks[n]["village_pass_ms"] for n in names], color=colours)
    axes[2].set_title("village pass, ms (median)", fontsize=9)
    for ax in axes:
        ax.tick_params(axis="x", labelsize=7)
    write_chart(fig, path, force=force, title="spec/003 criterion 37: the toon look on the lit "
                f"houses, props and people ({report['masked_pixels']} px)")


def summary(report: dict) -> list[str]:
    t, p = report["looks"]["toon"], report["looks"]["lambert_blinn_phong"]
    others = [f"under {tm}: levels {v['toon']['levels']} / {v['lambert_blinn_phong']['levels']}, "
              f"saturation {v['toon']['saturation']:.3f} / "
              f"{v['lambert_blinn_phong']['saturation']:.3f}"
              for tm, v in report["by_tonemap"].items() if tm != report["tonemap"]]
    return [f"lit objects: {report['masked_pixels']} px of {report['object_pixels']} "
            f"(tone map {report['tonemap']})",
            f"luma levels: toon {t['levels']} (all {t['levels_all']}) against Lambert/Blinn–Phong "
            f"{p['levels']} (all {p['levels_all']})",
            f"mean saturation: toon {t['saturation']:.3f} against {p['saturation']:.3f}",
            f"village pass: toon {t['village_pass_ms']:.2f} ms, plain "
            f"{p['village_pass_ms']:.2f} ms (ratio {report['toon_cost_ratio']:.2f})", *others]

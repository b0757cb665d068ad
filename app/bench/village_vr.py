"""The village's VR figures (spec/003 §2.15): what the stereo pair costs. The thesis says VR
doubles the rendering and that Unity's eye render-texture scale trades resolution for cost, and
measures neither. Here, on the village scene itself (a head before Lord Barus's hall, the ring
and the markers drawn in every variant so that mono and stereo draw the same things) at a small
size, interleaved rounds (``app.gpu.timing.time_interleaved``) time

* ``mono`` — one frame from the head;
* ``stereo_S`` — the side-by-side pair (``app.render.stereo.StereoRenderer``) with each eye's
  render texture at scale S of its half (0.5, 0.75, 1; 1.5 in the full run): two eye frames and
  their copy into the frame;

and how many times per timed frame each variant rendered the sun's shadow map: the map is
cached while its key (light, settings, the snapped cascade fit of the camera) holds, and each
eye has its own camera, so the pair renders it once per eye, every frame, even for a still head;
in these rounds a mono frame follows a stereo one, whose right eye moved the fit, so it renders
it once — as a moving head's mono frame may (a still head's mono frames render it no more).

Reported: medians and quartiles in ms, the per-round ratio stereo/mono, and the eyes' pixels
relative to the mono frame's (2 · (W/2 · S) · (H · S) / (W · H) = S²): at S = 1 the pair shades
as many pixels as the mono frame, so what it adds is the per-frame work done twice (draw calls,
shadow maps, the sky's passes) and the copy; below 1 it shades fewer. On llvmpipe absolute
times mean little; the ratios within one run hold, within the spread their quartiles show.

``run(gpu, quick)`` → dict; ``chart(report, path)``; ``summary(report)`` → lines.
"""

from __future__ import annotations

from typing import Any, Callable

from ..gpu.device import Gpu
from ..gpu.timing import time_interleaved
from ..render.stereo import eye_size
from ..runtime import scene_params
from ..scenes import get_scene
from ..sim.camera import Camera
from . import pyplot, write_chart

SCENE = "village"
#: a head before Lord Barus's hall: near geometry, the ring, the characters' markers
HEAD: dict[str, Any] = {"position": (0.0, 3.2, -11.0), "yaw": 0.0, "pitch": -5.0,
                        "fov": 60.0, "near": 0.1, "far": 2000.0}
SETS = ("village.camera=free", "vr.health_ring=always", "vr.markers=always")
QUICK: dict[str, Any] = {"size": (160, 90), "scales": (0.5, 0.75, 1.0), "rounds": 5,
                         "budget_s": 4.0, "min_rounds": 3}
FULL: dict[str, Any] = {"size": (320, 180), "scales": (0.5, 0.75, 1.0, 1.5), "rounds": 15,
                        "budget_s": 60.0, "min_rounds": 5}


def run(gpu, quick: bool = False) -> dict:
    """ms of a mono frame against the stereo pair at each render scale (module docstring)."""
    cfg = QUICK if quick else FULL
    size = tuple(cfg["size"])
    params = scene_params(SCENE, sets=SETS)
    # a Gpu of its own on the caller's context: this scene's effects have the names of the
    # caller's (a village session's), and releasing them must not free the caller's resources
    caller = gpu
    gpu = Gpu(caller.ctx, caller.shaders.root)
    scene = get_scene(SCENE)(gpu, params, Camera(**HEAD))
    target = gpu.target("bench-vr", "frame", size)
    try:
        frame = scene.frame(size, 0.0)

        sun = _sun_map(scene)
        counts: dict[str, list[int]] = {}

        def render(name: str, enabled: bool, scale: float = 1.0) -> Callable[[], None]:
            counts[name] = [0, 0]  # shadow-map renders, frames

            def go() -> None:
                params.set_many({"vr.enabled": enabled, "vr.render_scale": scale})
                before = sun.renders if sun is not None else 0
                scene.render(frame, target)
                if sun is not None:
                    counts[name][0] += sun.renders - before
                counts[name][1] += 1
            return go

        variants: dict[str, Callable[[], None]] = {"mono": render("mono", False)}
        for s in cfg["scales"]:
            variants[f"stereo_{s:g}"] = render(f"stereo_{s:g}", True, s)
        # the warm-up round makes programs, targets and bakes, untimed
        timed = time_interleaved(gpu.ctx, variants, warmup=1, rounds=cfg["rounds"],
                                 budget_s=cfg["budget_s"], min_rounds=cfg["min_rounds"])
        shadow_maps = {name: (n / max(f, 1) if sun is not None else None)
                       for name, (n, f) in counts.items()}
    finally:
        gpu.free(target)
        scene.release()
        gpu.release()
    p25, med, p75 = timed.quartiles("mono")
    out: dict = {
        "scene": SCENE, "size": list(size), "renderer": gpu.caps.describe(),
        "rounds": timed.rounds, "quick": quick, "head": dict(HEAD),
        "mono": {"median_ms": med, "p25_ms": p25, "p75_ms": p75},
        "stereo": [],
    }
    w, h = size
    for s in cfg["scales"]:
        name = f"stereo_{s:g}"
        q25, qm, q75 = timed.quartiles(name)
        eyes = [eye_size(size, s, e) for e in ("left", "right")]
        out["stereo"].append({
            "scale": s, "eye_size": list(eyes[0]),
            "pixels_ratio": sum(a * b for a, b in eyes) / (w * h),
            "median_ms": qm, "p25_ms": q25, "p75_ms": q75,
            "ratio_to_mono": timed.ratio(name, "mono"),
        })
    out["shadow_maps_per_frame"] = shadow_maps
    return out


def _sun_map(scene):
    """The village's sun shadow map, which counts its renders (None if it keeps no count)."""
    sun = getattr(getattr(scene.effect("village"), "shadows", None), "sun", None)
    return sun if isinstance(getattr(sun, "renders", None), int) else None


def chart(section_report: dict, path, force: bool = False) -> None:
    """ms of the pair against the render scale (quartile bars), the mono frame as a band; the
    ratio stereo/mono and the pixel ratio S² on a second axis."""
    plt = pyplot()

    r = section_report
    rows = r["stereo"]
    scales = [row["scale"] for row in rows]
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    med = [row["median_ms"] for row in rows]
    err = [[m - row["p25_ms"] for m, row in zip(med, rows)],
           [row["p75_ms"] - m for m, row in zip(med, rows)]]
    ax.errorbar(scales, med, yerr=err, marker="o", capsize=3, label="stereo pair")
    mono = r["mono"]
    ax.axhline(mono["median_ms"], color="k", lw=1.0, label="mono frame")
    ax.axhspan(mono["p25_ms"], mono["p75_ms"], color="k", alpha=0.1)
    ax.set(xlabel="eye render scale (of each half)", ylabel="ms per frame (median, quartiles)")
    ax.set_ylim(bottom=0.0)
    ax2 = ax.twinx()
    ax2.plot(scales, [row["ratio_to_mono"]["median"] for row in rows], "s--", color="tab:red",
             label="stereo / mono")
    ax2.plot(scales, [row["pixels_ratio"] for row in rows], "^:", color="tab:purple",
             label="eye pixels / mono pixels")
    ax2.set_ylabel("ratio")
    ax2.set_ylim(bottom=0.0)
    lines = ax.get_legend_handles_labels()
    lines2 = ax2.get_legend_handles_labels()
    ax.legend(lines[0] + lines2[0], lines[1] + lines2[1], fontsize=7, loc="upper left")
    w, h = r["size"]
    write_chart(fig, path, force=force,
                title=f"VR cost: village {w}×{h}, {r['rounds']} interleaved rounds\n"
                      f"{r['renderer']}")


def summary(section_report: dict) -> list[str]:
    r = section_report
    w, h = r["size"]
    m = r["mono"]
    lines = [f"village {w}×{h}, {r['rounds']} rounds: mono {m['median_ms']:.1f} ms "
             f"[{m['p25_ms']:.1f}, {m['p75_ms']:.1f}]"]
    for row in r["stereo"]:
        q = row["ratio_to_mono"]
        ew, eh = row["eye_size"]
        lines.append(f"  stereo at scale {row['scale']:g} (eyes {ew}×{eh}, "
                     f"{row['pixels_ratio']:.2f}× the pixels): {row['median_ms']:.1f} ms, "
                     f"{q['median']:.2f}× mono [{q['p25']:.2f}, {q['p75']:.2f}]")
    sm = r["shadow_maps_per_frame"]
    if sm["mono"] is not None:
        lines.append("  sun shadow-map renders per timed frame: " + ", ".join(
            f"{k} {v:.2g}" for k, v in sm.items()))
    return lines

"""Speed against accuracy of an amortised cloud march (app/render/amortise.py; beyond the theses,
after Schneider 2015), for either cloud model: ``natura bench clouds`` charts model A,
``natura bench maritime`` model B.

For each march resolution (``<group>.march_scale``: half, quarter) and refresh fraction
(``<group>.refresh``: all, 1/4, 1/16), and for the thesis's march of every pixel
(``<group>.reprojection = off``, the lesson's reference):

* **cost**: ms of the effect's march pass (march + resolve) in the window's steady state — the
  camera still, the history kept, one ordinary step per frame (the median of ``repeat`` runs
  after ``warmup``; the variants are timed one after the other, since switching a schedule
  resets the history, so on a shared machine compare neighbouring rows with care);
* **error, still**: the window's image after one refresh cycle of a still camera
  (``schedule.cycle`` frames: every pixel marched once) against the reference;
* **error, panning**: the image after ``PAN_FRAMES`` frames of a camera turning at
  ``PAN_DEG_PER_S`` (30°/s) at the frame budget's rate (``output.frame_budget_ms``, 33 ms: 1°
  per frame), against the reference at the last frame's view; the time of day and the wind are
  held, so the error is the amortisation's alone.

The reference is independent of the amortisation: the thesis's full-resolution march of every
pixel, averaged over ``PHASES`` offsets of its jitter (the converged picture, not a reprojected
one), rendered with the very frame it grades (the other effects' state, a boat's pose or the
sea's, is the same in both). Errors are in 8-bit steps of the tone-mapped sRGB image
``natura render`` writes (the largest channel per pixel): mean and p99. The acceptance bound
of a converged still render is mean 1 and p99 8 (tests/gl/test_clouds_amortise.py).
"""

from __future__ import annotations

import numpy as np

from ..colour import to_srgb8
from ..gpu.timing import time_call

#: the (march_scale, refresh) rows of the chart
SCHEDULES = (("half", "all"), ("half", "1/4"), ("half", "1/16"),
             ("quarter", "all"), ("quarter", "1/4"), ("quarter", "1/16"))
PAN_DEG_PER_S = 30.0
PAN_FRAMES = 24
PHASES = 8
#: the acceptance bound of a converged still render (8-bit steps)
STILL_BOUND = {"mean": 1.0, "p99": 8.0}


def _srgb(session, image: np.ndarray) -> np.ndarray:
    return to_srgb8(image[..., :3], session.scene.exposure(),
                    session.params["output.tonemap"]).astype(np.float64)


def _error(session, image, reference) -> dict:
    d = np.abs(_srgb(session, image) - _srgb(session, reference)).max(axis=-1)
    return {"mean": float(d.mean()), "p99": float(np.percentile(d, 99))}


def _budget_ms(params) -> float:
    try:
        return float(params["output.frame_budget_ms"])
    except Exception:  # noqa: BLE001 - a scene without the parameter
        return 33.0


def sweep(session, group: str, size, warmup: int = 1, repeat: int = 3) -> dict:
    """The rows above for ``group`` (``clouds`` or ``clouds_b``) at ``size``; parameters,
    camera and the scene's interactivity are restored afterwards."""
    size = tuple(int(v) for v in size)
    p = session.params
    scene = session.scene
    eff = scene.effect(group)
    gpu = session.gpu
    cam = scene.camera
    yaw, pitch = cam.yaw, cam.pitch
    saved = {k: p[k] for k in (f"{group}.reprojection", f"{group}.march_scale",
                               f"{group}.refresh")}
    saved_phase = eff.jitter_phase
    step_deg = PAN_DEG_PER_S * _budget_ms(p) / 1000.0
    target = gpu.target("bench", f"{group} amortised", size)

    last: list = []

    def render(frame=None) -> np.ndarray:
        frame = frame if frame is not None else scene.frame(size, 0.0)
        last[:] = [frame]
        scene.render(frame, target)
        return target.read()

    def reference() -> np.ndarray:
        """The reference of the last frame rendered, with that very frame (what the other
        effects drew, a boat's pose, the sea's state, is the same in both)."""
        mode = p[f"{group}.reprojection"]
        p.set(f"{group}.reprojection", "off")
        total = np.zeros((size[1], size[0], 4))
        for k in range(PHASES):
            eff.jitter_phase = k / PHASES
            scene.render(last[0], target)
            total += target.read()
        eff.jitter_phase = saved_phase
        p.set(f"{group}.reprojection", mode)
        return total / PHASES

    def march_pass(frame):
        (march,) = [q for q in eff.passes(frame, target) if q.name == f"{group}.march"]
        return march.run

    rows = []
    try:
        cam.set(yaw=yaw, pitch=pitch)
        scene.interactive = True
        still_frame = scene.frame(size, 0.0)  # one still view for every row
        p.set(f"{group}.reprojection", "off")
        eff.jitter_phase = None if group == "clouds_b" else 0.0
        # the march is clipped at the scene's depth: the target holds the view's first
        render(still_frame)
        thesis_ms = time_call(gpu.ctx, f"{group}.march", march_pass(still_frame), warmup,
                              repeat).median_ms
        thesis = render(still_frame)
        eff.jitter_phase = saved_phase
        rows.append({"config": "thesis (every pixel)", "scale": "full", "refresh": "all",
                     "fraction": 1.0, "cycle": 1, "ms": thesis_ms,
                     "still": _error(session, thesis, reference()), "pan": None})
        for scale, refresh in SCHEDULES:
            p.set(f"{group}.reprojection", "on")
            p.set(f"{group}.march_scale", scale)
            p.set(f"{group}.refresh", refresh)
            cam.set(yaw=yaw, pitch=pitch)
            eff.amortiser.release()
            render(still_frame)  # a reset, then ordinary steps of the still camera
            step = march_pass(still_frame)
            ms = time_call(gpu.ctx, f"{group}.march", step, warmup, repeat).median_ms
            schedule = eff.amortiser.last_schedule
            while eff.amortiser.counter < schedule.cycle - 1:  # one refresh cycle in all
                step()
            still = render(still_frame)
            # graded at once: what the other effects hold on the GPU (the sea's last update)
            # is the same for the image and its reference
            still_error = _error(session, still, reference())
            eff.amortiser.release()
            render()  # the pan starts from a fresh history (a reset)
            for _ in range(min(schedule.cycle, 4)):
                render()
            resets = eff.amortiser.resets
            for i in range(PAN_FRAMES):
                cam.set(yaw=yaw + (i + 1) * step_deg, pitch=pitch)
                pan = render()
            rows.append({"config": f"{scale}, refresh {refresh}", "scale": scale,
                         "refresh": refresh, "fraction": schedule.fraction,
                         "cycle": schedule.cycle, "ms": ms,
                         "still": still_error,
                         "pan": _error(session, pan, reference()),
                         "resets_in_pan": eff.amortiser.resets - resets})
    finally:
        gpu.free(target)
        p.set_many(saved)
        eff.jitter_phase = saved_phase
        eff.amortiser.release()
        cam.set(yaw=yaw, pitch=pitch)
        scene.interactive = False
    # the default's schedule (auto) at this size, for the chart's marker
    default = eff.schedule(size)
    return {"group": group, "size": list(size), "pan_deg_per_s": PAN_DEG_PER_S,
            "pan_frames": PAN_FRAMES, "pan_deg_per_frame": step_deg, "phases": PHASES,
            "still_bound": STILL_BOUND, "default": default.label(), "rows": rows,
            "timing": "median of the march pass (march + resolve) per variant, run one after "
                      "the other; the error in 8-bit sRGB steps, largest channel"}


def plot(ax, report: dict) -> None:
    """The chart: ms of the march pass against the mean error, still and panning."""
    rows = report["rows"]
    amortised = [r for r in rows if r["pan"] is not None]
    for key, style, label in (("still", "o-", "still camera, one refresh cycle"),
                              ("pan", "s--", f"{report['pan_deg_per_s']:g}°/s pan, "
                                             f"{report['pan_frames']} frames")):
        for scale in ("half", "quarter"):
            pts = [r for r in amortised if r["scale"] == scale]
            ax.plot([r["ms"] for r in pts], [max(r[key]["mean"], 1e-3) for r in pts], style,
                    label=f"{scale} resolution, {label}")
            for r in pts:
                ax.annotate(r["refresh"], (r["ms"], max(r[key]["mean"], 1e-3)), fontsize=7,
                            textcoords="offset points", xytext=(3, 3))
    thesis = rows[0]
    ax.plot([thesis["ms"]], [max(thesis["still"]["mean"], 1e-3)], "*", ms=12,
            label="the thesis's march of every pixel (jitter at one offset)")
    ax.axhline(report["still_bound"]["mean"], color="k", ls=":", lw=1,
               label="converged-still bound (mean 1/255)")
    ax.set(xscale="log", yscale="log")
    ax.set_xlabel(f"ms of the march pass at {report['size'][0]}×{report['size'][1]} "
                  "(steady state)")
    ax.set_ylabel("mean |image − converged reference| (8-bit sRGB)")
    ax.set_title(f"{report['group']}: amortised march, speed against error "
                 f"(auto here: {report['default']})", fontsize=9)
    ax.legend(fontsize=6)


def summary(report: dict) -> list[str]:
    lines = [f"amortised march ({report['group']}, {report['size'][0]}x{report['size'][1]}; "
             f"auto: {report['default']}; error in 8-bit steps, mean / p99, against the "
             f"full-resolution march averaged over {report['phases']} jitter offsets)",
             "  config                     ms    per frame   still mean/p99   "
             f"pan {report['pan_deg_per_s']:g}°/s mean/p99"]
    for r in report["rows"]:
        pan = (f"{r['pan']['mean']:6.2f} / {r['pan']['p99']:4.0f}" if r["pan"] is not None
               else "     —")
        lines.append(f"  {r['config']:24s} {r['ms']:7.1f}   {100 * r['fraction']:6.2f} %   "
                     f"{r['still']['mean']:6.2f} / {r['still']['p99']:4.0f}    {pan}")
    return lines

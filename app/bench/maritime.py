"""``natura bench maritime``'s sweep: the maritime thesis's clouds (model B, ``clouds_b``)
amortised as the field renders them — ms of the march pass against the error of the image,
still and during a 30°/s pan, for each march resolution and refresh fraction, against the
full-resolution march averaged over its jittered offsets (app/bench/amortise.py has the
method). Written beside the JSON as ``<report>.png``.

Also the wake's Kelvin half-angle (:func:`wake_angle`): the foam the wake adds, rendered from
straight above after a straight run under motor in calm water, measured along its ridge (per
metre behind the stern, the crest of the foam on each side; a line through the stern fitted to
them: ``app.sim.wake.ridge_angle``) against the theory's asin(1/3) = 19.47° (Kelvin 1887). The
97th percentile of the bright foam's angles, which the figure used to be, reads the outer edge
of the foam band (about 21°) and is reported beside it.
"""

from __future__ import annotations

import math

import numpy as np

from . import amortise, at_most, pyplot, write_chart

#: the sweep's size, never above the bench's ``--size``
SWEEP_SIZE = (320, 180)


def sweep(session, size, warmup: int = 1, repeat: int = 3, sizes=None) -> dict:
    """The sweep from the chase camera's eye, held there: the chase camera reads a turn of the
    view as an orbit about the boat, so a pan would also move the eye (and, row after row, take
    it down under the waves)."""
    p = session.params
    session.scene.frame(at_most(size, SWEEP_SIZE), 0.0)  # the chase camera's eye, placed
    with p.kept(["maritime.camera"]):
        p.set("maritime.camera", "free")
        out = {"amortised": amortise.sweep(session, "clouds_b", at_most(size, SWEEP_SIZE),
                                           warmup, repeat)}
    out["wake"] = wake_angle(session.gpu.ctx, getattr(session.gpu.shaders, "root", None))
    return out


#: the wake figure's scene: flat water (no wind: a straight run; the swell of a 0.5 m/s wind
#: already yaws the boat by ±3°), under motor at noon, 40 s sailed before the frame (the trail
#: keeps 19 s; after 20 s the boat still gains 3 % of its speed along it, which bends the ridge
#: in by 0.1°); the clouds and the FFT small (out of view)
WAKE_SETS = ("maritime.weather=custom", "wind.speed=0", "ocean.foam_amount=0",
             "boat.throttle=1", "boat.navigation=thesis", "boat.spin_up=40",
             "maritime.camera=free", "time.hour=12", "ocean.fft_size=64",
             "clouds_b.volume_resolution=16", "clouds_b.detail_resolution=8")
#: the top-down render: size [px], camera height [m], field of view [°], its centre behind
#: the boat [m]; rendered with the wake per pixel (ocean.wake_stride 1) and per 3 × 3 block
#: (the default)
WAKE_SIZE = (160, 160)
WAKE_HEIGHT, WAKE_FOV, WAKE_BEHIND = 60.0, 60.0, 25.0
WAKE_STRIDES = (1, 3)
#: the ridge is read from this far behind the stern [m] (nearer, the hull's wash covers it) to
#: 2 m short of the farthest cusp of a steady sample, in bins of this width [m] (wider than the
#: beads a 3 × 3 block map makes of the cusp lines)
WAKE_START, WAKE_BIN = 8.0, 3.0
#: only the cusps of samples left at this share of the boat's speed now or more are read (a
#: boat still accelerating leaves the slower samples' cusps inside the wedge)
WAKE_STEADY = 0.97


def wake_angle(ctx, shader_root=None, size=WAKE_SIZE) -> dict:
    """The Kelvin half-angle of the rendered wake (module docstring), in a session of its own
    on ``ctx``. Per wake stride (``renders``: "1", "3"): ``ridge`` (app.sim.wake.ridge_angle:
    ``angle`` both sides, ``port``, ``starboard``, ``rms_m``, ``points``) and ``percentile_97``
    (the former figure: the bright foam's angles); ``twin``, the numpy twin's foam of the same
    trail at the same pixels read the same way; ``theory`` (asin(1/3)), ``metres_per_pixel``,
    ``span_m`` (the stretch read) and ``speed``."""
    from ..runtime import open_session, scene_params
    from ..sim.wake import KELVIN_HALF_ANGLE, ridge_angle

    with open_session("maritime", scene_params("maritime", shader_root, WAKE_SETS),
                      shader_root=shader_root, ctx=ctx) as s:
        sc = s.scene
        frame = sc.frame(size, 0.0)
        (trail,) = frame.wakes  # the boat's trail, through the frame's slot
        now = frame.time
        bow = trail.directions[0]  # the boat's course, along which its wake opens
        # the wedge's apex: the stern now, from the newest sample carried on at its speed
        apex = trail.positions[0] + bow * trail.speeds[0] * (now - trail.times[0])
        centre = apex - WAKE_BEHIND * bow
        sc.camera.set(position=(centre[0], WAKE_HEIGHT, centre[1]), yaw=0.0, pitch=-90.0,
                      fov=WAKE_FOV)
        target = s.gpu.target("bench-wake", "image", size)
        foams = {}
        for stride in WAKE_STRIDES:
            s.params.set("ocean.wake_stride", stride)
            images = {}
            for wake in (True, False):
                s.params.set("boat.wake", wake)
                frame = sc.frame(size, 0.0)  # dt = 0: the same boat and sea, with or without
                sc.render(frame, target)
                images[wake] = target.read()[..., :3].mean(axis=-1)
            foams[str(stride)] = images[True] - images[False]
        # pixel centres → world on the plane y = 0 (straight down, yaw 0: up is north)
        cam = sc.camera
        r, u, f = cam.basis()
        t = math.tan(math.radians(cam.fov) * 0.5)
        cols, rows = np.meshgrid(np.arange(size[0]), np.arange(size[1]))
        nx = ((cols + 0.5) / size[0] * 2 - 1) * t * size[0] / size[1]
        ny = (1 - (rows + 0.5) / size[1] * 2) * t
        d = f + nx[..., None] * r + ny[..., None] * u
        hit = np.asarray(cam.position) + d * (cam.position[1] / -d[..., 1:2])
        foams["twin"] = trail.foam(hit[..., 0], hit[..., 2], now)
        rel = hit[..., [0, 2]] - apex
        along, across = -(rel @ bow), rel @ np.array([-bow[1], bow[0]])
        # a sample's cusp is U·a/3 ahead of it
        cusp = -((trail.positions - apex) @ bow) - trail.speeds * (now - trail.times) / 3.0
        reach = float(cusp[trail.speeds >= WAKE_STEADY * trail.speeds[0]].max())
        speed = float(trail.speeds[0])
    out: dict = {"renders": {}, "theory": math.degrees(KELVIN_HALF_ANGLE),
                 "metres_per_pixel": 2 * WAKE_HEIGHT * t / size[1],
                 "span_m": [WAKE_START, reach - 2.0], "speed": speed}
    for key, foam in foams.items():
        ridge = ridge_angle(along, across, foam, start=WAKE_START, stop=reach - 2.0,
                            bin_width=WAKE_BIN, floor=0.25 * float(foam.max()))
        far = (foam > 0.25 * foam.max()) & (along > 12.0)
        angles = np.degrees(np.arctan2(np.abs(across[far]), along[far]))
        entry = {"ridge": ridge, "percentile_97": float(np.percentile(angles, 97))}
        if key == "twin":
            out["twin"] = entry
        else:
            out["renders"][key] = entry
    return out


def chart(report: dict, path, force: bool = False) -> None:
    plt = pyplot()

    fig, ax = plt.subplots(1, 1, figsize=(8, 5))
    amortise.plot(ax, report["sweep"]["amortised"])
    write_chart(fig, path, force, title=f"natura bench maritime — {report['renderer']}")


def summary(report: dict) -> str:
    lines = amortise.summary(report["sweep"]["amortised"])
    w = report["sweep"].get("wake")
    if w:
        lines.append(f"wake: Kelvin half-angle against the theory's {w['theory']:.2f}°, read "
                     f"{w['span_m'][0]:.0f}–{w['span_m'][1]:.0f} m behind the stern at "
                     f"{w['metres_per_pixel']:.2f} m/px — the foam ridge (port, starboard; the "
                     "crest's rms off the line) | the bright foam's 97th percentile (the outer "
                     "edge of the band)")
        for name, e in [*((f"render, wake stride {k}", v) for k, v in w["renders"].items()),
                        ("numpy twin, same trail", w["twin"])]:
            rg = e["ridge"]
            lines.append(f"  {name:24s} {rg['angle']:6.2f}° ({rg['port']:.2f}°, "
                         f"{rg['starboard']:.2f}°; {rg['rms_m']:.2f} m) | "
                         f"{e['percentile_97']:.2f}°")
    return "\n".join(lines)

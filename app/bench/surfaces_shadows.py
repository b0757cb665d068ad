"""Shadow accuracy against cost on the surfaces lab's floor (spec/003 §2.8): the shared shadow
module (app/render/shadow_maps.py, glsl/common/shadow.glsl) against the exact visibility of
:func:`app.sim.surfaces_scene.occluded` on :func:`~app.sim.surfaces_scene.default_scene`.

1. **Mismatch** — floor points on a grid, the sun's map at each size × bias setting × filter;
   a point mismatches where (visibility < ½) differs from the exact answer, split into acne
   (false shadow away from any true edge), Peter Panning (false light away from an edge) and
   aliasing (either, within one grid step of a true shadow edge), with the cost of a map
   render plus a receiver pass (``app.gpu.timing.time_interleaved``); 0 cascades against 4 at
   the same atlas size (equal texel count).
2. **Soft shadows** — the ground truth of an area light (a disc of angular radius
   :data:`LIGHT_RADIUS`) averaged from N jittered hard maps (256; 32 with ``quick``) against
   PCF, PCSS and VSM: mean absolute error, with the filter's ms.

API: ``run(gpu, quick=False) -> dict``, ``chart(report, path, force=False)``,
``summary(report) -> list[str]``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from functools import partial

import numpy as np

from ..gpu.timing import time_interleaved
from ..render.shadow_maps import MeshCasters, ShadowProbe, ShadowSet
from ..render.shadows import ShadowSettings
from ..sim import surfaces_scene as ss
from ..sim.camera import Camera

OWNER = "bench-shadows"
SUN = np.array([0.45, 1.0, 0.35]) / np.linalg.norm([0.45, 1.0, 0.35])
LIGHT_RADIUS = 0.05  # radians: the area light's angular radius for the soft-shadow truth
BIASES = {"none": (0.0, 0.0), "thesis 0.3+0.01": (0.3, 0.01), "linear 0.6": (0.3, 0.6)}


def _camera() -> Camera:
    return Camera(position=(0.0, 2.5, 4.5), yaw=0.0, pitch=-30.0, fov=60.0, near=0.1, far=30.0)


def _floor(n: int):
    xs = np.linspace(-3.95, 3.95, n)
    x, z = np.meshgrid(xs, xs)
    p = np.stack([x, np.zeros_like(x), z], -1)
    return p, np.tile([0.0, 1.0, 0.0], p.shape[:-1] + (1,))


def _truth(scene, p, light) -> np.ndarray:
    q = p.reshape(-1, 3) + [0.0, 1e-3, 0.0]
    return ss.occluded(scene, q, np.tile(light, (len(q), 1))).reshape(p.shape[:-1])


def _edges(truth: np.ndarray) -> np.ndarray:
    t = np.pad(truth, 1, mode="edge")
    out = np.zeros_like(truth)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            out |= t[1 + dy:t.shape[0] - 1 + dy, 1 + dx:t.shape[1] - 1 + dx] != truth
    return out


def _split(v, truth, edge) -> dict:
    shadowed = v < 0.5
    wrong = shadowed != truth
    return {"mismatch": float(wrong.mean()), "acne": float((wrong & shadowed & ~edge).mean()),
            "panning": float((wrong & ~shadowed & ~edge).mean()),
            "aliasing": float((wrong & edge).mean())}


def _casters(gpu, scene):
    floor = ss.Box("floor", (0.0, -0.05, 0.0), (4.0, 0.05, 4.0))
    return MeshCasters(gpu, OWNER, [(ss.mesh(o), 0, 1.0, 0.5, None)
                                    for o in [floor, *scene.solids()]])


def _disc(n: int, seed: int = 1) -> np.ndarray:
    """n directions jittered over the light's disc (stratified in rings × sectors)."""
    rng = np.random.default_rng(seed)
    u = (np.arange(n) + rng.random(n)) / n
    phi = 2 * np.pi * rng.permutation(n) / n + rng.random(n) * 2 * np.pi / n
    r = LIGHT_RADIUS * np.sqrt(u)
    b = np.cross([0.0, 0.0, 1.0], SUN)
    b /= np.linalg.norm(b)
    c = np.cross(SUN, b)
    d = SUN + np.tan(r)[:, None] * (np.cos(phi)[:, None] * b + np.sin(phi)[:, None] * c)
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def run(gpu, quick: bool = False) -> dict:
    """The sweep (see the module's docstring); ``gpu`` is an app.gpu.device.Gpu."""
    scene = ss.default_scene()
    cas = _casters(gpu, scene)
    shadows, probe = ShadowSet(gpu, OWNER), ShadowProbe(gpu, OWNER)
    cam = _camera()
    grid = 96 if quick else 256
    p, n = _floor(grid)
    depth = (p - np.asarray(cam.position)) @ cam.forward()
    truth = _truth(scene, p, SUN)
    edge = _edges(truth)
    sizes = (256, 1024) if quick else (256, 512, 1024, 2048)
    filters = ("hard", "four_tap", "pcf", "pcss", "vsm")
    base = ShadowSettings(cascades=0, fixed_radius=5.0, fixed_centre=(0.0, 0.5, 0.0),
                          distance=12.0)
    rev = [0]

    def measure(s: ShadowSettings) -> dict:
        rev[0] += 1
        shadows.sun.render(cas, cam, 1.0, SUN, s, revision=rev[0])
        v, _ = probe.visibility(shadows, p, n, depth)
        return _split(v, truth, edge)

    def _timed(s: ShadowSettings) -> None:
        rev[0] += 1
        shadows.sun.render(cas, cam, 1.0, SUN, s, revision=rev[0])
        probe.visibility(shadows, p, n, depth)

    rows = []
    variants: dict[str, Callable[[], None]] = {}
    for size in sizes:
        for bias, (nb, lb) in BIASES.items():
            for f in (filters if bias.startswith("thesis") else ("hard",)):
                for casc in ((0, 4) if f == "hard" and bias.startswith("thesis") else (0,)):
                    s = replace(base, map_size=size, normal_bias=nb, linear_bias=lb, filter=f,
                                cascades=casc)
                    name = f"{size} {bias} {f} c{casc}"
                    rows.append({"name": name, "size": size, "bias": bias, "filter": f,
                                 "cascades": casc, **measure(s)})

                    variants[name] = partial(_timed, s)
    timing = time_interleaved(gpu.ctx, variants, warmup=1, rounds=3 if quick else 7,
                              budget_s=6.0 if quick else 60.0, min_rounds=2)
    ref = rows[0]["name"]
    for r in rows:
        r["ms"] = timing.quartiles(r["name"])[1]
        r["ratio"] = timing.ratio(r["name"], ref)["median"]

    # soft shadows: the area light's truth from N hard maps against the soft filters
    count = 32 if quick else 256
    soft_size = 512 if quick else 1024
    s_hard = replace(base, map_size=soft_size, filter="hard")
    acc = np.zeros(p.shape[:-1])
    for d in _disc(count):
        rev[0] += 1
        shadows.sun.render(cas, cam, 1.0, d, s_hard, revision=rev[0])
        acc += probe.visibility(shadows, p, n, depth)[0]
    truth_soft = acc / count
    soft = []
    for f, extra in (("pcf", {}), ("pcss", {"pcss_light_size": float(np.tan(LIGHT_RADIUS))}),
                     ("vsm", {"vsm_blur": 2})):
        s = replace(base, map_size=soft_size, filter=f, **extra)
        rev[0] += 1
        shadows.sun.render(cas, cam, 1.0, SUN, s, revision=rev[0])
        v = probe.visibility(shadows, p, n, depth)[0]
        soft.append({"filter": f, "mae": float(np.abs(v - truth_soft).mean()),
                     "ms": next(r["ms"] for r in rows if r["size"] == sizes[-1]
                                and r["filter"] == f)})
    shadows.release()
    gpu.release_owner(OWNER)
    return {"quick": quick, "grid": grid, "sizes": list(sizes), "rows": rows, "soft": soft,
            "soft_maps": count, "light_radius": LIGHT_RADIUS}


def chart(report: dict, path, force: bool = False) -> None:
    """Mismatch against ms (every map size × bias × filter) and soft-shadow error against ms."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from . import write_chart

    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    for bias in BIASES:
        rs = [r for r in report["rows"] if r["bias"] == bias]
        a.scatter([r["ms"] for r in rs], [100 * r["mismatch"] for r in rs], label=bias, s=14)
        for r in rs:  # each point: map size, filter, cascades
            a.annotate(f"{r['size']} {r['filter']} c{r['cascades']}",
                       (r["ms"], 100 * r["mismatch"]), fontsize=6, xytext=(3, 2),
                       textcoords="offset points")
    a.set_xlabel("map + receiver ms")
    a.set_ylabel("mismatch % of floor points")
    a.set_yscale("symlog", linthresh=0.1)
    a.legend(fontsize=7)
    for r in report["soft"]:
        b.scatter([r["ms"]], [r["mae"]], s=20)
        b.annotate(r["filter"], (r["ms"], r["mae"]), fontsize=8)
    b.set_xlabel("ms")
    b.set_ylabel(f"mean |V − truth| ({report['soft_maps']} jittered maps)")
    a.set_title("mismatch (acne + Peter Panning + aliasing) against the ray cast", fontsize=9)
    b.set_title("soft shadow of an area light against jittered hard maps", fontsize=9)
    write_chart(fig, path, force=force, title="spec/003 §2.8 shadows on the lab floor")


def summary(report: dict) -> list[str]:
    lines = []
    size = report["sizes"][-1]
    for r in report["rows"]:
        if r["size"] == size and (r["filter"] == "hard" or r["bias"].startswith("thesis")):
            lines.append(f"shadows {r['name']}: mismatch {100 * r['mismatch']:.2f}% (acne "
                         f"{100 * r['acne']:.2f}, panning {100 * r['panning']:.2f}, aliasing "
                         f"{100 * r['aliasing']:.2f}), {r['ms']:.2f} ms (x{r['ratio']:.2f})")
    for r in report["soft"]:
        lines.append(f"soft shadow {r['filter']}: mean abs error {r['mae']:.4f} against "
                     f"{report['soft_maps']} jittered hard maps")
    return lines

"""Shadow accuracy against cost on the surfaces lab's floor (spec/003 §2.8): the shared shadow
module (app/render/shadow_maps.py, glsl/common/shadow.glsl) against the exact visibility of
:func:`app.sim.surfaces_scene.occluded` on :func:`~app.sim.surfaces_scene.default_scene`.

1. **Mismatch** — floor points on a grid, the sun's map at each size × bias setting × filter;
   a point mismatches where (visibility < ½) differs from the exact answer, split into acne
   (false shadow away from any true edge), Peter Panning (false light away from an edge) and
   aliasing (either, within one grid step of a true shadow edge), with the cost of a map
   render plus a receiver pass (``app.gpu.timing.time_interleaved``); 0 cascades against 4 at
   the same atlas size (equal texel count).
2. **Soft shadows** — the exact visibility of an area light (a disc of angular radius
   :data:`LIGHT_RADIUS`), ray cast in numpy against the scene's analytic primitives
   (:func:`area_visibility`: independent of the shadow maps it grades), against PCF, PCSS and
   VSM: mean absolute error over all floor points and over the penumbra (0 < V < 1 in the
   truth), with the filter's ms; the reference's own error is stated (its disc sampling
   against 4× the samples). The former reference, N jittered hard maps (256; 32 with
   ``quick``), is kept beside it, with its own error against the ray cast.
3. **Penumbra width against the map's fit** — the fraction of the floor in PCSS's penumbra
   (:data:`SOFT_LEVELS`) with the sun's map fitted over radii :data:`FIT_RADII` at the same
   texel size, against the ray-cast truth's: a directional light's penumbra is the
   blocker-to-receiver distance × 2 tan(angular radius), whatever the fit.

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
#: the ray-cast truth's directions over the light's disc: every floor point, then the penumbra
#: (dilated) again with more; the error is stated from the penumbra with 4× as many
TRUTH_DIRECTIONS = (64, 1024)
#: a point is soft (in the penumbra) where SOFT_LEVELS[0] < V < SOFT_LEVELS[1]
SOFT_LEVELS = (0.02, 0.98)
#: the sun's map over these fit radii (m) at the texel size of 1024 texels over 5 m
FIT_RADII = (5.0, 10.0, 20.0)
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


def disc_directions(toward_light, angular_radius: float, n: int) -> np.ndarray:
    """(n, 3) unit directions spread evenly over a disc light of ``angular_radius`` about
    ``toward_light`` (a Fibonacci spiral: radius θ √((k + ½)/n), angle k × the golden angle —
    equal areas of the disc's tangent plane, equal solid angles to O(θ²))."""
    b = np.asarray(toward_light, np.float64)
    b = b / np.linalg.norm(b)
    e1 = np.cross([0.0, 0.0, 1.0] if abs(b[2]) < 0.9 else [1.0, 0.0, 0.0], b)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(b, e1)
    k = np.arange(n) + 0.5
    r = np.tan(angular_radius) * np.sqrt(k / n)
    phi = k * np.pi * (3.0 - np.sqrt(5.0))
    d = b + r[:, None] * (np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2)
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def _lit_fraction(scene, q: np.ndarray, dirs: np.ndarray) -> np.ndarray:
    lit = np.zeros(len(q))
    for d in dirs:
        lit += ~ss.occluded(scene, q, np.broadcast_to(d, q.shape))
    return lit / len(dirs)


def area_visibility(scene, points, toward_light, angular_radius: float,
                    directions=TRUTH_DIRECTIONS) -> tuple[np.ndarray, dict]:
    """The exact visibility of a uniform disc light (the fraction of its solid angle a point
    sees) by ray casting against the scene's solids (:func:`app.sim.surfaces_scene.occluded`),
    not through any shadow map: (V with the points' shape, its error). Every point casts
    ``directions[0]`` rays; the points with 0 < V < 1, dilated by two grid steps (an edge
    missed by the coarse set lies within them), are cast again with ``directions[1]``. The
    error is that of the fine set estimated against 4× its directions on those points: mean
    and max |ΔV| (``error_mean``, ``error_max``), with the points' count."""
    p = np.asarray(points, np.float64)
    shape = p.shape[:-1]
    q = p.reshape(-1, 3) + [0.0, 1e-3, 0.0]
    coarse, fine = directions
    v = _lit_fraction(scene, q, disc_directions(toward_light, angular_radius, coarse))
    soft = ((v > 0) & (v < 1)).reshape(shape)
    grow = soft.copy()
    if len(shape) == 2:  # dilate by two grid steps
        for _ in range(2):
            g = np.pad(grow, 1)
            grow = (g[1:-1, 1:-1] | g[:-2, 1:-1] | g[2:, 1:-1] | g[1:-1, :-2] | g[1:-1, 2:])
    idx = np.flatnonzero(grow.ravel())
    v[idx] = _lit_fraction(scene, q[idx], disc_directions(toward_light, angular_radius, fine))
    finer = _lit_fraction(scene, q[idx], disc_directions(toward_light, angular_radius, 4 * fine))
    err = np.abs(v[idx] - finer)
    return v.reshape(shape), {"directions": [coarse, fine], "refined_points": int(len(idx)),
                              "error_mean": float(err.mean()) if len(idx) else 0.0,
                              "error_max": float(err.max()) if len(idx) else 0.0}


def inside(scene, points) -> np.ndarray:
    """True where a point lies inside a solid (the floor under the crate and the cylinders):
    no one sees it, and the maps' casters cover it; the soft figures leave these points out."""
    q = np.asarray(points, np.float64) + [0.0, 1e-3, 0.0]
    out = np.zeros(q.shape[:-1], bool)
    for o in scene.solids():
        if isinstance(o, ss.Sphere):
            out |= np.linalg.norm(q - o.centre, axis=-1) < o.radius
        elif isinstance(o, ss.Box):
            out |= np.all(np.abs(q - o.centre) < o.half, axis=-1)
        else:
            h = q - o.base
            out |= (np.hypot(h[..., 0], h[..., 2]) < o.radius) & (h[..., 1] > 0) \
                & (h[..., 1] < o.height)
    return out


def soft_fraction(v: np.ndarray, levels=SOFT_LEVELS) -> float:
    """The fraction of points in the penumbra, ``levels[0] < V < levels[1]``."""
    v = np.asarray(v)
    return float(((v > levels[0]) & (v < levels[1])).mean())


def errors(v: np.ndarray, truth: np.ndarray) -> dict:
    """Mean |V − truth| over every point and over the truth's penumbra (0 < truth < 1)."""
    d = np.abs(np.asarray(v, np.float64) - truth)
    pen = (truth > 0) & (truth < 1)
    return {"mae": float(d.mean()), "mae_penumbra": float(d[pen].mean()) if pen.any() else 0.0,
            "max": float(d.max())}


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

    ms = {f: next(r["ms"] for r in rows if r["size"] == sizes[-1] and r["filter"] == f)
          for f in ("pcf", "pcss", "vsm")}
    out = {"quick": quick, "grid": grid, "sizes": list(sizes), "rows": rows,
           **soft_shadows(scene, shadows, probe, cas, cam, p, n, depth, base, quick, ms, rev)}
    shadows.release()
    gpu.release_owner(OWNER)
    return out


def soft_shadows(scene, shadows, probe, cas, cam, p, n, depth, base: ShadowSettings,
                 quick: bool, ms: dict, rev: list) -> dict:
    """Sections 2 and 3 of the module's docstring: the filters against the ray-cast truth (and
    the jittered maps), and PCSS's penumbra over :data:`FIT_RADII`."""
    # soft shadows: the area light's exact visibility, ray cast, against the soft filters
    soft_size = 512 if quick else 1024
    truth_soft, truth_error = area_visibility(scene, p, SUN, LIGHT_RADIUS,
                                              (32, 256) if quick else TRUTH_DIRECTIONS)
    seen = ~inside(scene, p)
    truth_soft = truth_soft[seen]
    penumbra = (truth_soft > 0) & (truth_soft < 1)
    # the former reference: N jittered hard maps (shares the maps' aliasing)
    count = 32 if quick else 256
    s_hard = replace(base, map_size=soft_size, filter="hard")
    acc = np.zeros(p.shape[:-1])
    for d in _disc(count):
        rev[0] += 1
        shadows.sun.render(cas, cam, 1.0, d, s_hard, revision=rev[0])
        acc += probe.visibility(shadows, p, n, depth)[0]
    jittered = acc[seen] / count
    light_size = float(np.tan(LIGHT_RADIUS))

    def filtered(s: ShadowSettings, world: bool = True) -> np.ndarray:
        rev[0] += 1
        shadows.sun.pcss_world = world
        shadows.sun.render(cas, cam, 1.0, SUN, s, revision=rev[0])
        try:
            return probe.visibility(shadows, p, n, depth)[0][seen]
        finally:
            shadows.sun.pcss_world = True

    soft = []
    for f, extra in (("pcf", {}), ("pcss", {"pcss_light_size": light_size}),
                     ("vsm", {"vsm_blur": 2})):
        v = filtered(replace(base, map_size=soft_size, filter=f, **extra))
        soft.append({"filter": f, **errors(v, truth_soft),
                     "mae_jittered": float(np.abs(v - jittered).mean()),
                     "soft_fraction": soft_fraction(v), "ms": ms.get(f, float("nan"))})
    # the former sun PCSS (penumbra from the normalised depths, Gaussian PCF): before → after
    v = filtered(replace(base, map_size=soft_size, filter="pcss", pcss_light_size=light_size),
                 world=False)
    former = {"filter": "pcss", **errors(v, truth_soft),
              "mae_jittered": float(np.abs(v - jittered).mean()), "soft_fraction": soft_fraction(v)}
    # PCSS's penumbra against the map's fit: the same texel size over each radius
    texel = 2 * 5.0 / soft_size
    fits = []
    for radius in FIT_RADII[:2] if quick else FIT_RADII:
        size = int(round(2 * radius / texel))
        s = replace(base, map_size=size, fixed_radius=radius, filter="pcss",
                    pcss_light_size=light_size)
        v, v0 = filtered(s), filtered(s, world=False)
        fits.append({"radius": radius, "map_size": size, "soft_fraction": soft_fraction(v),
                     **errors(v, truth_soft), "former_soft_fraction": soft_fraction(v0)})
    return {"soft": soft, "pcss_former": former,
            "soft_maps": count, "light_radius": LIGHT_RADIUS,
            "truth": {**truth_error, "points": int(seen.sum()),
                      "penumbra_fraction": float(penumbra.mean()),
                      "soft_fraction": soft_fraction(truth_soft),
                      "jittered_mae": float(np.abs(jittered - truth_soft).mean()),
                      "jittered_max": float(np.abs(jittered - truth_soft).max())},
            "fits": fits}


def chart(report: dict, path, force: bool = False) -> None:
    """Mismatch against ms (every map size × bias × filter) and soft-shadow error against ms."""
    from . import pyplot, write_chart

    plt = pyplot()

    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    for bias in BIASES:
        rs = [r for r in report["rows"] if r["bias"] == bias]
        a.scatter([r["ms"] for r in rs], [100 * r["mismatch"] for r in rs], label=bias, s=14)
        for r in rs:  # each point: map size, filter, cascades
            a.annotate(f"{r['size']} {r['filter']} c{r['cascades']}",
                       (r["ms"], 100 * r["mismatch"]), fontsize=6, xytext=(3, 2),
                       textcoords="offset points")
    a.set(xlabel="map + receiver ms", ylabel="mismatch % of floor points")
    a.set_yscale("symlog", linthresh=0.1)
    a.legend(fontsize=7)
    for r in report["soft"]:
        b.scatter([r["ms"]], [r["mae"]], s=20, c="C0")
        b.scatter([r["ms"]], [r["mae_penumbra"]], s=20, c="C3", marker="s")
        b.annotate(r["filter"], (r["ms"], r["mae"]), fontsize=8)
        b.annotate(r["filter"], (r["ms"], r["mae_penumbra"]), fontsize=8)
    b.scatter([], [], c="C0", label="all floor points")
    b.scatter([], [], c="C3", marker="s",
              label=f"penumbra ({100 * report['truth']['penumbra_fraction']:.1f} % of the floor)")
    b.set_yscale("log")
    b.legend(fontsize=7)
    b.set(xlabel="ms", ylabel="mean |V − ray-cast truth|")
    a.set_title("mismatch (acne + Peter Panning + aliasing) against the ray cast", fontsize=9)
    b.set_title(f"soft shadow of a disc light (θ = {report['light_radius']} rad) against the "
                "ray cast", fontsize=9)
    write_chart(fig, path, force=force, title="spec/003 §2.8 shadows on the lab floor")


def summary(report: dict) -> list[str]:
    lines = []
    size = report["sizes"][-1]
    for r in report["rows"]:
        if r["size"] == size and (r["filter"] == "hard" or r["bias"].startswith("thesis")):
            lines.append(f"shadows {r['name']}: mismatch {100 * r['mismatch']:.2f}% (acne "
                         f"{100 * r['acne']:.2f}, panning {100 * r['panning']:.2f}, aliasing "
                         f"{100 * r['aliasing']:.2f}), {r['ms']:.2f} ms (x{r['ratio']:.2f})")
    t = report["truth"]
    lines.append(f"soft-shadow truth: disc light ray cast ({t['directions'][0]} directions, "
                 f"{t['directions'][1]} in the penumbra), error {t['error_mean']:.4f} mean, "
                 f"{t['error_max']:.3f} max on {t['refined_points']} points; penumbra "
                 f"{100 * t['penumbra_fraction']:.2f} % of the floor, soft "
                 f"{100 * t['soft_fraction']:.2f} %; {report['soft_maps']} jittered maps are "
                 f"{t['jittered_mae']:.4f} off it (max {t['jittered_max']:.2f})")
    f0 = report["pcss_former"]
    for r in report["soft"]:
        lines.append(f"soft shadow {r['filter']}: mean abs error {r['mae']:.4f} (penumbra "
                     f"{r['mae_penumbra']:.3f}) against the ray cast, {r['mae_jittered']:.4f} "
                     f"against the jittered maps; soft {100 * r['soft_fraction']:.2f} %"
                     + (f" (former sun PCSS: {f0['mae']:.4f}, penumbra {f0['mae_penumbra']:.3f},"
                        f" soft {100 * f0['soft_fraction']:.2f} %)" if r["filter"] == "pcss"
                        else ""))
    lines.append("PCSS soft fraction by fit radius (same texel): " + ", ".join(
        f"{f['radius']:g} m {100 * f['soft_fraction']:.2f} % (former "
        f"{100 * f['former_soft_fraction']:.2f} %)" for f in report["fits"])
        + f"; truth {100 * t['soft_fraction']:.2f} %")
    return lines

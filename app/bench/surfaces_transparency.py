"""The surfaces lab's transparency figures (spec/003 §2.4): each way of compositing the blended
quads — Unity's sorted blending (ZWrite on, the thesis's default), sorted with ZWrite off (its
workaround), weighted blended OIT (McGuire and Bavoil 2013) and depth peeling cut to k layers —
against the exact reference, depth peeling with as many layers as the view has (64 at most), on
the lab's views (``app.effects.surfaces.transparency.VIEWS``: the intersecting panes close up,
the blue pane over the cut-out fence, the smoke): the RMS and max error of the linear image and
the ms of each method in interleaved rounds (and Fig. 44c's wrong queue, the blue pane
queued Geometry, as ``sorted_blue_geometry``) (app.gpu.timing.time_interleaved), with the
peeled reference's time as the ratio's base. Also the alpha-test figures: the discarded
fraction of the gradient quad over Cutoff ∈ {0, 0.1, 0.5, 1} (criterion 16) and the pixels of
partial coverage alpha-to-coverage leaves on a 4× MSAA target (criterion 17).

The quads are drawn over a cleared background (no opaque scene), so every difference is the
transparency's own. ``run(gpu, size, quick)`` → dict; ``chart(report, path)``;
``summary(report)`` → lines.
"""

from __future__ import annotations

from functools import partial
from typing import Callable

import numpy as np

from ..effects.surfaces.transparency import VIEWS, Transparency, look_at
from ..gpu.timing import time_interleaved
from ..params import ParamSet
from ..sim import surfaces_scene as ss
from ..sim import transparency as tw
from . import write_chart

OWNER = "bench-surfaces-transparency"
BG = (0.3, 0.3, 0.35)
LIGHT = {"direction": (0.3, 0.8, 0.5), "radiance": (1.0, 1.0, 1.0), "ambient": (0.2, 0.2, 0.2)}
FLAT = {"direction": (0.0, 1.0, 0.0), "radiance": (0.0, 0.0, 0.0), "ambient": (1.0, 1.0, 1.0)}
#: method → the parameters it sets
METHODS = {
    "sorted": {"surfaces.transparency": "sorted"},
    "sorted_zwrite_off": {"surfaces.transparency": "sorted", "surfaces.zwrite_blended": False},
    #: the blue pane queued Geometry, before the cut-out fence (the thesis's Fig. 44c)
    "sorted_blue_geometry": {"surfaces.transparency": "sorted", "surfaces.blue_queue": "Geometry"},
    "wboit": {"surfaces.transparency": "wboit"},
    "peeled_1": {"surfaces.transparency": "peeled", "surfaces.peel_layers": 1},
    "peeled_2": {"surfaces.transparency": "peeled", "surfaces.peel_layers": 2},
}
REFERENCE = {"surfaces.transparency": "peeled", "surfaces.peel_layers": 64}
CUTOFFS = (0.0, 0.1, 0.5, 1.0)


class _Target:
    def __init__(self, ctx, size, samples=0):
        self.ctx, self.size, self.samples = ctx, tuple(size), samples
        self.colour = ctx.texture(self.size, 4, dtype="f4", samples=samples)
        self.depth = ctx.depth_texture(self.size, samples=samples)
        self.fbo = ctx.framebuffer([self.colour], self.depth)
        self.resolved = (ctx.framebuffer([ctx.texture(self.size, 4, dtype="f4")])
                         if samples else None)

    def clear(self):
        self.fbo.use()
        self.fbo.clear(*BG, 1.0, depth=1.0)

    def read(self):
        fbo = self.fbo
        if self.resolved is not None:
            self.ctx.copy_framebuffer(self.resolved, self.fbo)
            fbo = self.resolved
        w, h = self.size
        return np.frombuffer(fbo.read(components=4, dtype="f4"), "f4").reshape(h, w, 4)[::-1]

    def release(self):
        objs = [self.fbo, self.colour, self.depth]
        if self.resolved is not None:
            objs += [*self.resolved.color_attachments, self.resolved]
        for o in objs:
            o.release()


def _facing(kind):
    return ss.Quad("probe", (0.0, 0.0, -1.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0),
                   (1.0, 1.0, 1.0), kind)


def _alpha_test(tr, target_size) -> dict:
    size = (min(target_size[0], 128), min(target_size[1], 128))
    # 89.5°: the 2 m quad at 1 m fills the view, u from 0.004 to 0.996
    vp = look_at((0, 0, 0), (0, 0, -1), 89.5, size[0] / size[1])
    out: dict = {"cutoff": [], "a2c": {}}
    gradient = tr.build_quads([_facing("gradient")])
    leaves = tr.build_quads([_facing("leaves")])
    ctx = tr.gpu.ctx
    try:
        tr.overrides["probe"] = ("cutout", None)
        t = _Target(ctx, size)
        for c in CUTOFFS:
            tr.params.set("surfaces.cutoff", c)
            t.clear()
            tr.draw(t, vp, (0, 0, 0), FLAT, gradient)
            gone = np.abs(t.read()[..., :3] - BG).max(-1) < 1e-4
            out["cutoff"].append({"cutoff": c, "discarded": float(gone.mean())})
        t.release()
        tr.params.reset("surfaces.cutoff")
        ms = _Target(ctx, size, samples=4)
        for mode in ("alpha-to-coverage", "cutout"):
            tr.overrides["probe"] = (mode, None)
            ms.clear()
            tr.draw(ms, vp, (0, 0, 0), FLAT, leaves)
            rgb = ms.read()[..., :3]
            f = ((rgb - BG) / (1.0 - np.asarray(BG))).mean(-1)
            out["a2c"][mode] = int(((f > 0.03) & (f < 0.97)).sum())
        ms.release()
    finally:
        tr.overrides.clear()
        for _q, vbo, ibo, _t in gradient + leaves:
            tr.gpu.free(vbo)
            tr.gpu.free(ibo)
    return out


def run(gpu, size=(256, 256), quick: bool = False) -> dict:
    """Errors against the peeled reference and interleaved ms per method and view."""
    size = (128, 128) if quick else tuple(int(s) for s in size)
    params = ParamSet(Transparency.python_params())
    tr = Transparency(gpu, OWNER, params)
    target = _Target(gpu.ctx, size)
    quads = tr.scene_quads()
    rows = []
    try:
        for view, (eye, at, fov) in VIEWS.items():
            vp = look_at(eye, at, fov, size[0] / size[1])

            def draw(sets, vp=vp, eye=eye):
                for k, v in sets.items():
                    params.set(k, v)
                target.clear()
                tr.draw(target, vp, eye, LIGHT, quads)
                for k in sets:
                    params.reset(k)

            draw(REFERENCE)
            reference = target.read().copy()
            layers = tr.last["layers"]
            errs = {}
            for name, sets in METHODS.items():
                draw(sets)
                img = target.read()
                errs[name] = {**tw.errors(img, reference), "finite": bool(np.isfinite(img).all())}
            variants: dict[str, Callable[[], None]] = {
                name: partial(draw, sets) for name, sets in METHODS.items()}
            variants["peeled_reference"] = partial(draw, REFERENCE)
            timed = time_interleaved(gpu.ctx, variants, warmup=1, rounds=3 if quick else 9,
                                     budget_s=2.0 if quick else 8.0, min_rounds=3)
            summary = timed.summary("peeled_reference")
            for name in variants:
                entry = {"view": view, "method": name, "ms": summary[name]["median_ms"],
                         "reference_layers": layers}
                if name in errs:
                    entry.update(errs[name])
                    entry["ratio_to_reference"] = summary[name]["ratio_to_peeled_reference"][
                        "median"]
                else:
                    entry.update({"rms": 0.0, "max": 0.0, "finite": True,
                                  "ratio_to_reference": 1.0})
                rows.append(entry)
        alpha = _alpha_test(tr, size)
    finally:
        target.release()
        tr.release()
        gpu.release_owner(OWNER)
    return {"size": list(size), "quick": quick, "wboit_weight": "eq7", "rows": rows,
            "alpha_test": alpha}


def summary(report: dict) -> list[str]:
    s = report["size"]
    lines = [f"transparency at {s[0]}x{s[1]}: error vs depth peeling (all layers), RMS / max, "
             "and ms (ratio to the reference)"]
    for r in report["rows"]:
        lines.append(f"  {r['view']:10s} {r['method']:20s} RMS {r['rms']:.4f}  max "
                     f"{r['max']:.3f}  {r['ms']:7.2f} ms (×{r['ratio_to_reference']:.2f})")
    a = report["alpha_test"]
    lines.append("  cutoff sweep (gradient): " + ", ".join(
        f"{c['cutoff']:g} → {100 * c['discarded']:.1f} %" for c in a["cutoff"]))
    lines.append(f"  4× MSAA partial-coverage pixels: alpha-to-coverage "
                 f"{a['a2c']['alpha-to-coverage']}, hard clip {a['a2c']['cutout']}")
    return lines


def chart(report: dict, path, force: bool = False) -> None:
    """Per view, RMS error (log) against ms of each method."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    views = list(dict.fromkeys(r["view"] for r in report["rows"]))
    fig, axes = plt.subplots(1, len(views), figsize=(4 * len(views), 3.4), squeeze=False)
    for ax, view in zip(axes[0], views):
        for r in report["rows"]:
            if r["view"] != view:
                continue
            ax.scatter(r["ms"], max(r["rms"], 1e-5))
            ax.annotate(r["method"], (r["ms"], max(r["rms"], 1e-5)), fontsize=7)
        ax.set_yscale("log")
        ax.set_xlabel("ms")
        ax.set_ylabel("RMS error vs peeled reference")
        ax.set_title(view, fontsize=9)
    write_chart(fig, path, force=force, title="transparency: error against cost "
                "(spec/003 §2.4)")

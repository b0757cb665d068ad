"""The surfaces lab's transparency figures (spec/003 §2.4): each way of compositing the blended
quads — Unity's sorted blending (ZWrite on, the thesis's default), sorted with ZWrite off (its
workaround), weighted blended OIT (McGuire and Bavoil 2013) and depth peeling cut to k layers —
against an exact reference, on the lab's views (``app.effects.surfaces.transparency.VIEWS``:
the intersecting panes close up, the blue pane over the cut-out fence, the smoke) and on two
views through several blended layers per pixel (:data:`OIT_VIEWS`): the RMS and max error of
the linear image on every pixel and on the pixels with ≥ 2 layers (where the order matters:
with one layer over the background every method is exact, so an all-pixel mean mostly measures
how much of the view has one), each view's pixels by layer count, and the ms of each method in
interleaved rounds (and Fig. 44c's wrong queue, the blue pane queued Geometry, as
``sorted_blue_geometry``) (app.gpu.timing.time_interleaved), with depth peeling's time as the
ratio's base. Also the alpha-test figures: the discarded fraction of the gradient quad over
Cutoff ∈ {0, 0.1, 0.5, 1} (criterion 16) and the pixels of partial coverage alpha-to-coverage
leaves on a 4× MSAA target (criterion 17).

The reference is an A-buffer (:func:`capture_layers`, ``app.sim.transparency.a_buffer``): each
blended quad's fragments are drawn alone (over the depth of the opaque and cut-out quads),
their colour, alpha and depth read back, and numpy sorts them per pixel and composites them in
float64 — no GPU blending of two layers. Depth peeling with all layers (``peeled_reference``),
the former reference, is graded against it too: its difference is the references' own
error (float32 round-off: at most 8e-8 at 128² and 256²). A layer is a fragment of alpha above
``app.sim.transparency.LAYER_ALPHA``.

The quads are drawn over a cleared background (no opaque scene), so every difference is the
transparency's own. ``run(gpu, size, quick)`` → dict; ``chart(report, path)``;
``summary(report)`` → lines.
"""

from __future__ import annotations

from functools import partial
from typing import Callable

import numpy as np

from ..effects.surfaces.transparency import BLENDED, VIEWS, Transparency, look_at
from ..gpu.timing import time_interleaved
from ..params import ParamSet
from ..sim import surfaces_scene as ss
from ..sim import transparency as tw
from . import pyplot, write_chart

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
#: views of the lab through several blended layers per pixel (beside the lab's VIEWS, where the
#: blue pane and the smoke lie alone over the background): name → (eye, look-at, fov °).
#: ``panes_smoke`` looks through both crossing panes onto the smoke (at 128², 54 % of the pixels
#: hold 2 layers and 31 % 3: no background); ``blue_smoke`` through the blue pane onto the
#: smoke 5 m behind it, where WBOIT's depth weight has to tell the two apart
OIT_VIEWS = {
    "panes_smoke": ((1.6, 0.8, 3.8), (0.4, 1.1, -3.0), 26.0),
    "blue_smoke": ((-0.8, 0.8, 4.0), (-0.3, 1.1, -3.0), 26.0),
}
BENCH_VIEWS = {**VIEWS, **OIT_VIEWS}
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


def _depth(target) -> np.ndarray:
    w, h = target.size
    return np.frombuffer(target.depth.read(), "f4").reshape(h, w)[::-1].astype(np.float64)


def capture_layers(tr, target, vp, eye, light, quads) -> dict:
    """Every blended quad's fragments, one quad at a time, for the A-buffer reference
    (``app.sim.transparency.a_buffer``): the quads that write depth (opaque, cut-out) are drawn
    as every method draws them, then, over that depth, each blended quad alone with "over"
    onto black and onto white: α·c = the first, α = 1 − (white − black), its depth where it
    drew. Returns ``base`` (h, w, 3: the image under the blended quads), ``premultiplied``
    (K, h, w, 3), ``alpha`` and ``depth`` (K, h, w; window depth, 1 where absent) and
    ``names``. Single-sample targets only. No GPU blending of two layers is involved: the
    order of the layers is numpy's sort."""
    params = tr.params
    blended = [e for e in quads if tr.setting(e[0])[0] in BLENDED]
    base = [e for e in quads if not any(e is b for b in blended)]

    def under_base():
        target.clear()
        if base:
            tr.draw(target, vp, eye, light, base)

    under_base()
    out: dict = {"base": target.read()[..., :3].astype(np.float64), "names": [],
                 "premultiplied": [], "alpha": [], "depth": []}
    base_depth = _depth(target)
    keep = dict(tr.overrides)
    settings = {"surfaces.transparency": "sorted", "surfaces.zwrite_blended": True}
    before = {k: params[k] for k in settings}
    params.set_many(settings)
    try:
        for entry in blended:
            tr.overrides[entry[0].name] = ("blend", None)  # drawn with depth writes
            shots = []
            for grey in (0.0, 1.0):
                under_base()
                target.fbo.depth_mask = False
                target.fbo.clear(grey, grey, grey, 1.0)  # colour only: the base's depth stays
                target.fbo.depth_mask = True
                tr.draw(target, vp, eye, light, [entry])
                shots.append(target.read()[..., :3].astype(np.float64))
            depth = _depth(target)
            alpha = np.clip(1.0 - (shots[1] - shots[0]).mean(-1), 0.0, 1.0)
            drew = depth < base_depth
            alpha = np.where(drew, alpha, 0.0)
            out["names"].append(entry[0].name)
            out["premultiplied"].append(np.where(drew[..., None], shots[0], 0.0))
            out["alpha"].append(alpha)
            out["depth"].append(np.where(drew, depth, 1.0))
            del tr.overrides[entry[0].name]
    finally:
        tr.overrides.clear()
        tr.overrides.update(keep)
        params.set_many(before)
    for k in ("premultiplied", "alpha", "depth"):
        out[k] = np.asarray(out[k]).reshape((len(blended), *base_depth.shape,
                                             *((3,) if k == "premultiplied" else ())))
    return out


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
    """Errors against the A-buffer reference, on every pixel and on the pixels with ≥ 2
    layers, and interleaved ms per method and view (:data:`BENCH_VIEWS`)."""
    size = (128, 128) if quick else tuple(int(s) for s in size)
    params = ParamSet(Transparency.python_params())
    tr = Transparency(gpu, OWNER, params)
    target = _Target(gpu.ctx, size)
    quads = tr.scene_quads()
    rows = []
    views = {}
    try:
        for view, (eye, at, fov) in BENCH_VIEWS.items():
            vp = look_at(eye, at, fov, size[0] / size[1])

            def draw(sets, vp=vp, eye=eye):
                params.set_many(sets)
                target.clear()
                tr.draw(target, vp, eye, LIGHT, quads)
                for k in sets:
                    params.reset(k)

            frags = capture_layers(tr, target, vp, eye, LIGHT, quads)
            exact = tw.a_buffer(frags["premultiplied"], frags["alpha"], frags["depth"],
                                frags["base"])
            counts = tw.layer_counts(frags["alpha"])
            multi = counts >= 2
            hist = np.bincount(np.minimum(counts, 4).ravel(), minlength=5) / counts.size
            draw(REFERENCE)
            layers = tr.last["layers"]
            views[view] = {"layers": [float(h) for h in hist], "multi": float(multi.mean()),
                           "quads": frags["names"], "peeled_layers": layers}
            errs = {}
            for name, sets in {**METHODS, "peeled_reference": REFERENCE}.items():
                draw(sets)
                img = target.read()
                e = tw.errors(img, exact)
                m = tw.errors(img, exact, multi) if multi.any() else {"rms": None, "max": None}
                errs[name] = {**e, "rms_multi": m["rms"], "max_multi": m["max"],
                              "finite": bool(np.isfinite(img).all())}
            variants: dict[str, Callable[[], None]] = {
                name: partial(draw, sets) for name, sets in METHODS.items()}
            variants["peeled_reference"] = partial(draw, REFERENCE)
            timed = time_interleaved(gpu.ctx, variants, warmup=1, rounds=3 if quick else 9,
                                     budget_s=2.0 if quick else 8.0, min_rounds=3)
            summary = timed.summary("peeled_reference")
            for name in variants:
                ratio = (1.0 if name == "peeled_reference" else
                         summary[name]["ratio_to_peeled_reference"]["median"])
                rows.append({"view": view, "method": name, "ms": summary[name]["median_ms"],
                             "reference_layers": layers, "ratio_to_reference": ratio,
                             **errs[name]})
        alpha = _alpha_test(tr, size)
    finally:
        target.release()
        tr.release()
        gpu.release_owner(OWNER)
    return {"size": list(size), "quick": quick, "wboit_weight": "eq7", "reference": "a_buffer",
            "layer_alpha": tw.LAYER_ALPHA, "views": views, "rows": rows, "alpha_test": alpha}


def _fig(x: float, digits: int) -> str:
    """``x`` to ``digits`` decimals, or in powers of ten when that would read 0 (round-off)."""
    return f"{x:.1e}" if 0.0 < abs(x) < 0.5 * 10.0 ** -digits else f"{x:.{digits}f}"


def summary(report: dict) -> list[str]:
    s = report["size"]
    lines = [f"transparency at {s[0]}x{s[1]}: error vs the A-buffer (each blended quad's "
             "fragments sorted per pixel in numpy), RMS / max on every pixel | on the pixels "
             "with ≥ 2 layers, and ms (ratio to depth peeling)"]
    views = report.get("views", {})
    for r in report["rows"]:
        v = views.get(r["view"])
        if v and r["method"] == "sorted":
            share = " ".join(f"{k}{'+' if k == 4 else ''}: {100 * f:.0f} %"
                             for k, f in enumerate(v["layers"]))
            lines.append(f"  {r['view']}: pixels by layers {share}")
        multi = ("       —        " if r.get("rms_multi") is None else
                 f"{_fig(r['rms_multi'], 4)} / {_fig(r['max_multi'], 3)}")
        lines.append(f"  {r['view']:11s} {r['method']:20s} {_fig(r['rms'], 4)} / "
                     f"{_fig(r['max'], 3)} | {multi}  {r['ms']:7.2f} ms "
                     f"(×{r['ratio_to_reference']:.2f})")
    a = report["alpha_test"]
    lines.append("  cutoff sweep (gradient): " + ", ".join(
        f"{c['cutoff']:g} → {100 * c['discarded']:.1f} %" for c in a["cutoff"]))
    lines.append(f"  4× MSAA partial-coverage pixels: alpha-to-coverage "
                 f"{a['a2c']['alpha-to-coverage']}, hard clip {a['a2c']['cutout']}")
    return lines


def chart(report: dict, path, force: bool = False) -> None:
    """Per view, RMS error (log) against ms of each method."""
    plt = pyplot()

    views = list(dict.fromkeys(r["view"] for r in report["rows"]))
    fig, axes = plt.subplots(1, len(views), figsize=(4 * len(views), 3.4), squeeze=False)
    for ax, view in zip(axes[0], views):
        for i, r in enumerate(x for x in report["rows"] if x["view"] == view):
            colour = f"C{i % 10}"
            ax.scatter(r["ms"], max(r["rms"], 1e-5), color=colour)
            ax.annotate(r["method"], (r["ms"], max(r["rms"], 1e-5)), fontsize=7)
            if r.get("rms_multi") is not None:  # the pixels with ≥ 2 layers: open markers
                ax.scatter(r["ms"], max(r["rms_multi"], 1e-5), facecolors="none",
                           edgecolors=colour)
        ax.set(yscale="log", xlabel="ms", ylabel="RMS error vs A-buffer (open: ≥ 2 layers)")
        ax.set_title(view, fontsize=9)
    write_chart(fig, path, force=force, title="transparency: error against cost "
                "(spec/003 §2.4)")

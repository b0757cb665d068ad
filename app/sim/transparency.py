"""Transparency of the surfaces lab (spec/003 §2.4), in numpy: the render queues and Unity's draw
order, the alpha cutoff, and the compositing of transparent layers — sorted "over" blending,
front-to-back "under" compositing (depth peeling), and weighted blended order-independent
transparency (McGuire and Bavoil 2013) with its depth weights. The twin of
``glsl/surfaces/alpha.frag``, ``glsl/surfaces/oit_composite.frag`` and
``glsl/surfaces/peel_composite.frag``. No GL here.

Render queues (spec/003 §2.4) run from 0 to 5000: Background 1000, Geometry 2000, AlphaTest
2450, Transparent 3000, Overlay 4000, written with an offset as ``"Transparent+5"``,
``"Geometry-10"`` or as a bare integer. Unity draws queue by queue, ascending; within a queue
up to 2500 (the opaque ones) front to back, beyond it back to front, by the distance from the
camera to each object's centre — the sort whose failure on intersecting planes the thesis
shows (Fig. 45).

Colours here are linear RGB; a layer is (colour, alpha, view depth). Premultiplied colour is
colour × alpha.
"""

from __future__ import annotations

import re
from typing import Sequence

import numpy as np

#: Unity's named queues (spec/003 §2.4)
QUEUES = {"Background": 1000, "Geometry": 2000, "AlphaTest": 2450, "Transparent": 3000,
          "Overlay": 4000}
QUEUE_MIN, QUEUE_MAX = 0, 5000
#: queues up to this are opaque: sorted front to back; beyond it back to front
OPAQUE_LAST = 2500
_QUEUE = re.compile(r"^\s*([A-Za-z]+)\s*(?:([+-])\s*(\d+))?\s*$")
_ALLOWED = ("allowed Background, Geometry, AlphaTest, Transparent or Overlay with an optional "
            "+N/-N offset, or an integer 0…5000")

#: McGuire and Bavoil's depth weights (their equation numbers)
WEIGHTS = ("eq7", "eq8", "eq9", "eq10")


def parse_queue(value: str | int) -> int:
    """A render queue as Unity writes it — ``"Transparent"``, ``"Transparent+5"``,
    ``"Geometry-10"``, ``"2450"`` or an int — as its number in [0, 5000]. Bad input: one-line
    ValueError naming it and what is allowed."""
    if isinstance(value, bool):
        raise ValueError(f"render queue {value!r} is not a queue: {_ALLOWED}")
    if isinstance(value, (int, np.integer)):
        number = int(value)
    elif isinstance(value, str):
        text = value.strip()
        if re.fullmatch(r"[+-]?\d+", text):
            number = int(text)
        else:
            m = _QUEUE.match(text)
            names = {k.lower(): v for k, v in QUEUES.items()}
            if m is None or m.group(1).lower() not in names:
                raise ValueError(f"render queue {value[:60]!r} is not a queue: {_ALLOWED}")
            offset = int(m.group(3) or 0) * (-1 if m.group(2) == "-" else 1)
            number = names[m.group(1).lower()] + offset
    else:
        raise ValueError(f"render queue {type(value).__name__} is not a queue: {_ALLOWED}")
    if not QUEUE_MIN <= number <= QUEUE_MAX:
        raise ValueError(f"render queue {value!r} = {number} is out of range: {_ALLOWED}")
    return number


def format_queue(number: int) -> str:
    """The queue's name relative to the nearest named queue at or below it:
    2450 → "AlphaTest", 3005 → "Transparent+5", 1990 → "Background+990", 500 → "500"."""
    number = parse_queue(int(number))
    below = [(v, k) for k, v in QUEUES.items() if v <= number]
    if not below:
        return str(number)
    base, name = max(below)
    return name if number == base else f"{name}+{number - base}"


def is_opaque_queue(queue: int) -> bool:
    """Queues up to 2500 are drawn front to back (opaque), later ones back to front."""
    return int(queue) <= OPAQUE_LAST


def draw_order(queues: Sequence[int], centres, camera_pos) -> list[int]:
    """Unity's draw order of objects (indices into ``queues``): queue ascending; within a queue
    ≤ 2500 front to back, beyond 2500 back to front, by the distance from ``camera_pos`` to
    each object's centre; ties keep their given order (a stable sort)."""
    q = [int(v) for v in queues]
    c = np.asarray(centres, np.float64).reshape(len(q), 3) if q else np.zeros((0, 3))
    # hypot, not the root of the summed squares: a tiny offset (1e-193 m) squared underflows to
    # 0 and would tie with a centre at the camera
    dist = np.hypot.reduce(c - np.asarray(camera_pos, np.float64), axis=1)
    keys = [(q[i], dist[i] if is_opaque_queue(q[i]) else -dist[i], i) for i in range(len(q))]
    return [k[2] for k in sorted(keys)]


def cutout_kept(alpha, cutoff: float) -> np.ndarray:
    """``clip(alpha − Cutoff)``: a fragment is discarded when alpha − Cutoff < 0 (spec/003 §2.4),
    so Cutoff 0 keeps every fragment and Cutoff 1 discards every alpha below 1."""
    return np.asarray(alpha, np.float64) - float(cutoff) >= 0.0


def naive_kept(alpha) -> np.ndarray:
    """The naive test ``if (alpha == 0) discard``: alpha just above 0 survives (Fig. 42c's
    stray fragments)."""
    return np.asarray(alpha, np.float64) != 0.0


def discarded_fraction(alpha, cutoff: float) -> float:
    a = np.asarray(alpha, np.float64)
    return float(1.0 - cutout_kept(a, cutoff).mean()) if a.size else 0.0


def quad_radiance(albedo, tex_rgb, normal, to_camera, light_dir, radiance, ambient) -> np.ndarray:
    """albedo × texture × (ambient + radiance · max(n·l, 0)), two-sided: n faces the viewer."""
    n = np.asarray(normal, np.float64)
    v = np.asarray(to_camera, np.float64)
    flip = np.where(np.sum(n * v, axis=-1, keepdims=True) < 0.0, -1.0, 1.0)
    n = n * flip
    ndl = np.maximum(np.sum(n * np.asarray(light_dir, np.float64), axis=-1, keepdims=True), 0.0)
    return (np.asarray(albedo, np.float64) * np.asarray(tex_rgb, np.float64)
            * (np.asarray(ambient, np.float64) + np.asarray(radiance, np.float64) * ndl))


def _layers(colours, alphas, depths=None):
    c = np.asarray(colours, np.float64)
    a = np.asarray(alphas, np.float64)
    if c.ndim == 1:
        c = c[None]
    a = a.reshape(len(c))
    if depths is None:
        return c, a, None
    return c, a, np.asarray(depths, np.float64).reshape(len(c))


def over(colours, alphas, background) -> np.ndarray:
    """Layers composited back to front with ``Blend SrcAlpha OneMinusSrcAlpha`` in the order
    given (the first drawn first): C ← α·c + (1 − α)·C (Porter–Duff over)."""
    c, a, _ = _layers(colours, alphas)
    out = np.asarray(background, np.float64).copy()
    for ci, ai in zip(c, a):
        out = ai * ci + (1.0 - ai) * out
    return out


def under(colours, alphas, background) -> np.ndarray:
    """Layers given front to back, composited with the "under" operator as depth peeling does:
    C ← C + (1 − A)·α·c, A ← A + (1 − A)·α, then the background under it all."""
    c, a, _ = _layers(colours, alphas)
    acc = np.zeros(c.shape[-1] if c.size else 3)
    cover = 0.0
    for ci, ai in zip(c, a):
        acc = acc + (1.0 - cover) * ai * ci
        cover = cover + (1.0 - cover) * ai
    return acc + (1.0 - cover) * np.asarray(background, np.float64)


def sorted_exact(colours, alphas, depths, background) -> np.ndarray:
    """The exact composite: the layers sorted by depth per pixel, nearest in front (of equal
    depths, the first given in front, as depth peeling keeps it)."""
    c, a, z = _layers(colours, alphas, depths)
    order = np.argsort(z, kind="stable")[::-1]  # far to near
    return over(c[order], a[order], background)


def wboit_weight(z, alpha, eq: str = "eq7", window_depth=None) -> np.ndarray:
    """McGuire and Bavoil's depth weight w(z, α) of the view depth |z| (metres) and alpha.

    * eq7 — McGuire 2013 eq. 7: α · clamp(10 / (1e-5 + (|z|/5)² + (|z|/200)⁶), 1e-2, 3e3)
    * eq8 — McGuire 2013 eq. 8: α · clamp(10 / (1e-5 + (|z|/10)³ + (|z|/200)⁶), 1e-2, 3e3)
    * eq9 — McGuire 2013 eq. 9: α · clamp(0.03 / (1e-5 + (|z|/200)⁴), 1e-2, 3e3)
    * eq10 — McGuire 2013 eq. 10: α · max(1e-2, 3e3 · (1 − d)³), d the window depth
      (``window_depth``, gl_FragCoord.z)
    """
    z = np.abs(np.asarray(z, np.float64))
    a = np.asarray(alpha, np.float64)
    if eq == "eq7":
        w = 10.0 / (1e-5 + (z / 5.0) ** 2 + (z / 200.0) ** 6)
    elif eq == "eq8":
        w = 10.0 / (1e-5 + (z / 10.0) ** 3 + (z / 200.0) ** 6)
    elif eq == "eq9":
        w = 0.03 / (1e-5 + (z / 200.0) ** 4)
    elif eq == "eq10":
        if window_depth is None:
            raise ValueError("wboit weight eq10 needs window_depth: allowed a depth in [0, 1]")
        d = np.clip(np.asarray(window_depth, np.float64), 0.0, 1.0)
        return a * np.maximum(1e-2, 3e3 * (1.0 - d) ** 3)
    else:
        raise ValueError(f"wboit weight {eq!r}: allowed {', '.join(WEIGHTS)}")
    return a * np.clip(w, 1e-2, 3e3)


def wboit(colours, alphas, depths, background, eq: str = "eq7", window_depths=None
          ) -> np.ndarray:
    """Weighted blended OIT (McGuire 2013 eq. 6): accumulate Σ c·α·w (RGB of an RGBA16F target),
    the coverage 1 − Π (1 − α) (its alpha; one minus the revealage) and Σ α·w (an R16F
    target), then
    C = Σ c·α·w / max(Σ α·w, ε) · (1 − Π(1 − α)) + C₀ · Π(1 − α). Order independent; exact
    for one layer, and the coverage of the background is always exact."""
    c, a, z = _layers(colours, alphas, depths)
    bg = np.asarray(background, np.float64)
    if not len(c):
        return bg.copy()
    w = wboit_weight(z, a, eq, window_depths)
    accum = (c * (a * w)[:, None]).sum(0)
    weight = (a * w).sum()
    reveal = float(np.prod(1.0 - a))
    mean = accum / max(weight, 1e-5)
    return mean * (1.0 - reveal) + bg * reveal


def peel_layers(depths, layers: int) -> np.ndarray:
    """Which layers ``layers`` passes of depth peeling keep: the ``layers`` nearest (a
    boolean mask over the given layers); the rest are lost (their light is missing)."""
    z = np.asarray(depths, np.float64)
    order = np.argsort(z, kind="stable")
    keep = np.zeros(len(z), bool)
    keep[order[:max(int(layers), 0)]] = True
    return keep


def peeled(colours, alphas, depths, background, layers: int | None = None) -> np.ndarray:
    """Depth peeling: the nearest ``layers`` layers (all when None) under-composited front to
    back, then the background (equal to :func:`sorted_exact` when every layer is peeled)."""
    c, a, z = _layers(colours, alphas, depths)
    order = np.argsort(z, kind="stable")
    if layers is not None:
        order = order[:max(int(layers), 0)]
    return under(c[order], a[order], background)


def errors(image, reference, mask=None) -> dict:
    """RMS and max absolute error of an RGB(A) image against a reference (over ``mask``)."""
    a = np.asarray(image, np.float64)[..., :3]
    b = np.asarray(reference, np.float64)[..., :3]
    d = np.abs(a - b)
    if mask is not None:
        d = d[np.asarray(mask, bool)]
    if not d.size:
        return {"rms": 0.0, "max": 0.0}
    return {"rms": float(np.sqrt(np.mean(d ** 2))), "max": float(d.max())}


#: a fragment counts as a layer of its pixel when its alpha is above this (one 8-bit step is
#: 0.0039; below 1e-3 a layer changes the composite by less than 1e-3 of its contrast)
LAYER_ALPHA = 1e-3


def layer_counts(alphas, threshold: float = LAYER_ALPHA) -> np.ndarray:
    """Per pixel, how many of the layers (axis 0 of ``alphas``, shape (K, …)) have alpha above
    ``threshold``: 0 is the background alone, 1 a single layer (which "over", WBOIT and
    peeling all composite exactly), 2 and more the pixels where order matters."""
    a = np.asarray(alphas, np.float64)
    return (a > threshold).sum(axis=0) if a.size else np.zeros(a.shape[1:], int)


def a_buffer(premultiplied, alphas, depths, background) -> np.ndarray:
    """The exact composite of per-pixel fragment lists (an A-buffer, Carpenter 1984): ``K``
    layers given as premultiplied colours α·c (K, …, 3), alphas (K, …) and depths (K, …; any
    quantity increasing away from the eye), sorted per pixel and composited far to near with
    "over" in float64, C ← α·c + (1 − α)·C, over ``background`` (…, 3) or one colour. Absent
    layers are alpha 0 (their depth does not matter); of equal depths the first given is in
    front, as depth peeling keeps it. Independent of any GPU blending."""
    pc = np.asarray(premultiplied, np.float64)
    a = np.asarray(alphas, np.float64)
    z = np.asarray(depths, np.float64)
    out = np.broadcast_to(np.asarray(background, np.float64), pc.shape[1:]).copy()
    if not len(a):
        return out
    order = np.argsort(z, axis=0, kind="stable")[::-1]  # far to near
    a = np.take_along_axis(a, order, axis=0)
    pc = np.take_along_axis(pc, order[..., None], axis=0)
    for k in range(len(a)):
        out = pc[k] + (1.0 - a[k])[..., None] * out
    return out

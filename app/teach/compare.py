"""A/B comparison of two parameter sets of one scene: both images, each one's ms per frame, the
signed difference as a magnified heat map, and each one's error against the scene's reference.

What ``natura compare SCENE --a NAME=VALUE ... --b NAME=VALUE ...`` runs, and what the window's
A/B view calls on its live session (:func:`compare` with ``session=``).

How it measures
    Each side gets a scene of its own on one GL context (:func:`app.runtime.open_session`),
    built from the same base parameters (scene defaults, preset, ``--set``, ``--time``) with
    the side's ``NAME=VALUE`` sets on top, and the same camera. Two scenes rather than one
    whose parameters are switched back and forth: a switch can rebuild what a parameter keys
    (a LUT, a shadow map, a bake), and a timed frame must not include that. Each side renders
    one untimed warm-up frame (programs, bakes, lookup tables), then ``rounds`` rounds in which
    A and B each render one whole frame (update and passes, at a fixed simulation time) with
    ``ctx.finish()`` on both sides (:func:`app.gpu.timing.time_interleaved`, which shuffles
    the order inside each round so neither side always runs first). Machine load moves both
    sides alike, so their per-round ratio B/A is steadier than either time.

The difference
    Signed luminance (Rec. 709 weights on linear radiance) B − A, shown as a heat map: black
    where the sides agree, red where B is brighter, blue where B is darker, magnified by a gain
    that maps the 99th percentile of |B − A| to full colour (the largest |B − A| when fewer
    than 1 % of the pixels differ).

The reference
    Where a scene's bench measures its methods against a reference, the same reference is
    rendered here for each side: the side's own parameters with the reference's overrides on
    top (:data:`REFERENCES`), optionally supersampled. Error = mean |Y_side − Y_ref| over the
    mean Y_ref (luminance of linear radiance): a share of the reference's brightness. Scenes
    without one report None ("no reference").
"""

from __future__ import annotations

import contextlib
import copy
import io
import json
import math
import shlex
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable, Mapping

import numpy as np

from ..colour import LUMINANCE, linear_to_srgb, to_srgb8
from ..errors import ParamError, UsageError, one_line, quote
from ..gpu.shaders import resolve_shader_root
from ..gpu.timing import time_interleaved
from ..imageio import write_bytes_atomic, write_text_atomic
from ..params import ParamSet
from ..runtime import open_session, placed_camera, scene_params
from ..scenes import get_scene
from ..sim.camera import Camera
from .sweeps import format_value

#: the timed rounds by default
DEFAULT_ROUNDS = 5
LAYOUTS = ("side", "wipe")
#: the percentile of |B − A| the heat map's gain maps to full colour
GAIN_PERCENTILE = 99.0
#: a supersampled reference renders at most this many pixels (its factor is lowered to fit)
MAX_REFERENCE_PIXELS = 16 * 1024 * 1024
#: the heat map's colours (linear RGB) at full scale: B brighter, B darker
HEAT_POSITIVE = np.array([1.0, 0.25, 0.05])
HEAT_NEGATIVE = np.array([0.1, 0.4, 1.0])
HEAT_CAPTION = "heat map: black = equal, red = B brighter, blue = B darker"


@dataclass
class Side:
    label: str                 # e.g. "planet.method=lut"
    sets: list[str]            # the NAME=VALUE strings applied over the base
    image: np.ndarray          # (H, W, 3) float32 linear radiance, row 0 = top
    png: np.ndarray            # (H, W, 3) uint8 tone-mapped sRGB as `natura render` writes
    ms: float                  # median ms per frame (interleaved rounds with the other side)
    ms_quartiles: tuple[float, float]
    error: float | None        # error against the scene's reference (None: no reference)
    exposure: float = 1.0      # what the PNG was tone-mapped with (output.exposure × pupil)
    tonemap: str = "aces"
    reference: str | None = None  # this side's reference, in words (None: none applies)


@dataclass
class Comparison:
    scene: str
    size: tuple[int, int]
    a: Side
    b: Side
    diff: np.ndarray           # signed luminance difference B − A, (H, W) float32
    heat: np.ndarray           # (H, W, 3) uint8 magnified signed heat map of diff
    gain: float                # the magnification used
    reference: str | None      # what the reference is ("planet.method=... 4x steps", ...)
    caption: list[str]         # lines: both timings, their ratio, errors, the command
    rounds: int = DEFAULT_ROUNDS
    ratio: dict = field(default_factory=dict)   # per-round B/A: median, p25, p75, n
    diff_stats: dict = field(default_factory=dict)  # mean_abs, p99_abs, max_abs, mean ...
    renderer: str = ""
    command: str = ""
    #: the scene has a reference but it was not rendered (``reference=False``)
    reference_skipped: bool = False
    #: the scene's reference judges another method than what A and B differ in: why none
    reference_unrelated: str | None = None

    def figures(self) -> dict:
        """Every figure as plain JSON values (what ``natura compare`` writes beside the PNG)."""
        def side(s: Side) -> dict:
            return {"label": s.label, "sets": list(s.sets), "ms": s.ms,
                    "ms_p25": s.ms_quartiles[0], "ms_p75": s.ms_quartiles[1],
                    "error": s.error, "reference": s.reference, "exposure": s.exposure,
                    "tonemap": s.tonemap}

        return {"scene": self.scene, "size": list(self.size), "rounds": self.rounds,
                "renderer": self.renderer, "a": side(self.a), "b": side(self.b),
                "ratio_b_to_a": self.ratio, "difference": {**self.diff_stats, "gain": self.gain,
                                                           "heat_map": HEAT_CAPTION},
                "reference": self.reference, "reference_skipped": self.reference_skipped,
                "reference_unrelated": self.reference_unrelated,
                "error_metric":
                    "mean |Y_side − Y_reference| / mean Y_reference (Y: luminance of linear "
                    "radiance)",
                "caption": list(self.caption), "command": self.command}


@dataclass(frozen=True)
class Reference:
    """A scene's reference: ``overrides(params)`` gives the parameters to set over a side's own
    (None: the reference does not apply to that side), ``supersample`` renders it at that many
    times the size per axis and box-filters it down; ``label`` says what it is."""

    label: str
    overrides: Callable[[ParamSet], dict[str, Any] | None]
    supersample: int = 1
    #: the parameters (names, or prefixes ending in "_") whose methods this reference judges;
    #: empty: every parameter. A comparison of other parameters gets no error figures.
    judges: tuple[str, ...] = ()

    def judges_any(self, names: Iterable[str]) -> bool:
        """Whether a comparison differing in ``names`` is of a method this reference judges."""
        names = list(names)
        return not self.judges or not names or any(
            n == j or (j.endswith("_") and n.startswith(j)) for n in names for j in self.judges)


def _planet(p: ParamSet) -> dict[str, Any]:
    # the surface the side shades with (by_method means texture for methods 1–2, Phong for
    # 3–4): the reference changes the atmosphere, not the ground's shading model
    surface = p["planet.surface"]
    if surface == "by_method":
        surface = "phong" if p["planet.method"] in ("shadowed", "hillaire") else "texture"
    return {"planet.method": "brute_force", "planet.n_steps": 512, "planet.inner_steps": 512,
            "planet.pc_rule": "midpoint", "planet.ground_noise": "live",
            "planet.surface": surface}


#: as app/bench/clouds.py's REFERENCE (model A only; tests/cli/test_compare.py checks they agree)
CLOUDS_REFERENCE = {"clouds.steps": 512, "clouds.jitter": False, "clouds.reprojection": "off",
                    "clouds.adaptive_steps": False, "clouds.distance_steps": False,
                    "clouds.energy_conserving": True}
#: as app/bench/surfaces_transparency.py's REFERENCE
SURFACES_REFERENCE = {"surfaces.transparency": "peeled", "surfaces.peel_layers": 64}


def _clouds(p: ParamSet) -> dict[str, Any] | None:
    return dict(CLOUDS_REFERENCE) if p["scene.model"] == "a" else None


def _shading(p: ParamSet) -> dict[str, Any] | None:
    return {"shading.parallax_mode": 4} if p["shading.maps"] else None


def _materials(p: ParamSet) -> dict[str, Any]:
    return {"materials.filter_rings": False}


#: the scenes with a reference, each as its bench measures against (app/bench/<scene>.py)
REFERENCES: dict[str, Reference] = {
    "planet": Reference(
        "single scattering, method 1 at N = 512 × 512, midpoint τ(PC) rule, live ground "
        "noise, each side's surface shading (multiple scattering counts as error)", _planet),
    "clouds": Reference(
        "model A marched in 512 uniform steps, no jitter, no reprojection, energy-conserving "
        "(model B: none)", _clouds),
    # it judges the ring edges' filtering only: two noises (or two materials) differ by far
    # less than either differs from supersampled edges, so their errors would measure aliasing
    "materials": Reference("hard ring edges supersampled 8 × 8 (box filter)", _materials,
                           supersample=8, judges=("materials.filter_rings",)),
    "shading": Reference("parallax mode 4 (1024 layers and bisection), the rest as the side "
                         "(none without shading.maps)", _shading,
                         judges=("shading.parallax_", "shading.maps", "shading.wall_map",
                                 "shading.normal_", "shading.bumpiness")),
    "surfaces": Reference("transparency by depth peeling with 64 layers, the rest as the side",
                          lambda p: dict(SURFACES_REFERENCE)),
}


def reference_of(scene_name: str) -> Reference | None:
    """The scene's reference, or None (the caption then says "no reference")."""
    return REFERENCES.get(scene_name)


def normalize_sets(sets: Iterable[str] | Mapping[str, Any] | None) -> list[str]:
    """``NAME=VALUE`` strings from a list of them or a ``{name: value}`` mapping."""
    if sets is None:
        return []
    if isinstance(sets, Mapping):
        return [f"{k}={format_value(v)}" for k, v in sets.items()]
    if isinstance(sets, str):
        return [sets]
    return [str(s) for s in sets]


def apply_sets(params: ParamSet, sets: Iterable[str], what: str) -> None:
    """Apply ``NAME=VALUE`` strings; a bad one is one line naming ``what`` (``--a``) and it."""
    for s in sets:
        name, eq, _ = s.partition("=")
        if not eq or not name.strip():
            raise UsageError(f"{what} {quote(s)} is not NAME=VALUE: allowed e.g. "
                             "planet.method=lut (the names: natura params SCENE)")
        try:
            params.set_from_string(s)
        except ParamError as exc:
            raise UsageError(one_line(f"{what} {quote(s)}: {exc}")) from None
    try:
        params.check_joint()
    except ParamError as exc:
        raise UsageError(one_line(f"{what}: {exc}")) from None


def side_params(base: ParamSet, sets: Iterable[str], what: str) -> ParamSet:
    """A copy of ``base`` with ``sets`` applied (``base`` is left as it was)."""
    params = copy.deepcopy(base)
    apply_sets(params, sets, what)
    return params


def label_of(sets: list[str]) -> str:
    return " ".join(sets) if sets else "base (no changes)"


def luminance(rgb: np.ndarray) -> np.ndarray:
    """Luminance of linear radiance ``(h, w, 3|4)``; NaN and infinities count as 0."""
    x = np.nan_to_num(np.asarray(rgb, dtype=np.float64)[..., :3], nan=0.0, posinf=0.0,
                      neginf=0.0)
    return x @ LUMINANCE


def choose_gain(diff: np.ndarray) -> tuple[float, float]:
    """(gain, the |diff| it maps to full scale): the 99th percentile of |diff|, or its maximum
    when fewer than 1 % of the pixels differ; gain 1 when the images are equal."""
    mag = np.abs(np.asarray(diff, dtype=np.float64))
    scale = float(np.percentile(mag, GAIN_PERCENTILE)) if mag.size else 0.0
    if not scale > 0.0:
        scale = float(mag.max()) if mag.size else 0.0
    if not (scale > 0.0 and math.isfinite(scale)):
        return 1.0, 0.0
    return 1.0 / scale, scale


def heat_map(diff: np.ndarray, gain: float) -> np.ndarray:
    """``(h, w, 3)`` uint8 sRGB: black at 0, toward red where ``diff`` > 0 (B brighter) and
    blue where < 0, full colour at |diff| · gain ≥ 1."""
    t = np.clip(np.asarray(diff, dtype=np.float64) * gain, -1.0, 1.0)
    rgb = (np.maximum(t, 0.0)[..., None] * HEAT_POSITIVE
           + np.maximum(-t, 0.0)[..., None] * HEAT_NEGATIVE)
    return np.round(linear_to_srgb(rgb) * 255.0).astype(np.uint8)


def box_down(image: np.ndarray, factor: int) -> np.ndarray:
    """Average ``factor`` × ``factor`` blocks (a supersampled render back to its size)."""
    if factor == 1:
        return image
    h, w = image.shape[0] // factor, image.shape[1] // factor
    return image[:h * factor, :w * factor].reshape(h, factor, w, factor, -1).mean(axis=(1, 3))


def _supersample_factor(size: tuple[int, int], wanted: int, max_side: int) -> int:
    w, h = size
    s = max(1, wanted)
    while s > 1 and (w * s * h * s > MAX_REFERENCE_PIXELS or max(w, h) * s > max_side):
        s -= 1
    return s


def _camera_arg(cam) -> str:
    x, y, z = cam.position
    return ",".join(f"{v:.6g}" for v in (x, y, z, cam.yaw, cam.pitch, cam.fov))


def _command(scene_name: str, base: ParamSet, defaults: ParamSet, camera, default_camera,
             size, a_sets, b_sets, rounds: int) -> str:
    """The ``natura compare`` line that reproduces this comparison: the base as ``--set`` of
    what differs from the scene's defaults, the camera when it is not the scene's own."""
    parts = ["natura", "compare", scene_name, "--size", f"{size[0]}x{size[1]}"]
    for name, value in base.values().items():
        if name in defaults and defaults[name] != value:
            parts += ["--set", f"{name}={format_value(value)}"]
    if camera is not None and _camera_arg(camera) != _camera_arg(default_camera):
        parts += ["--camera", _camera_arg(camera)]
    if a_sets:
        parts += ["--a", *a_sets]
    if b_sets:
        parts += ["--b", *b_sets]
    if rounds != DEFAULT_ROUNDS:
        parts += ["--rounds", str(rounds)]
    return " ".join(shlex.quote(p) for p in parts)


def _ms(v: float) -> str:
    return f"{v:.3g}" if v < 10 else f"{v:.1f}"


def _pct(e: float | None) -> str:
    return "n/a" if e is None else f"{100.0 * e:.3g} %"


def caption_lines(cmp: Comparison) -> list[str]:
    """The caption: labels, both timings with their spread, the ratio, the errors, the
    difference and its gain, the renderer, and the command."""
    a, b, r, d = cmp.a, cmp.b, cmp.ratio, cmp.diff_stats
    w, h = cmp.size
    lines = [f"{cmp.scene} {w}x{h} · A: {a.label} · B: {b.label}",
             f"A {_ms(a.ms)} ms [{_ms(a.ms_quartiles[0])}–{_ms(a.ms_quartiles[1])}] · "
             f"B {_ms(b.ms)} ms [{_ms(b.ms_quartiles[0])}–{_ms(b.ms_quartiles[1])}] · "
             f"B/A {r['median']:.2f}× [{r['p25']:.2f}–{r['p75']:.2f}] (median [p25–p75] of "
             f"{cmp.rounds} interleaved rounds, whole frames)"]
    if cmp.reference_skipped:
        lines.append("error: the reference was skipped (--no-reference)")
    elif cmp.reference_unrelated:
        lines.append(f"error: none — {cmp.reference_unrelated}")
    elif cmp.reference is None:
        lines.append(f"error: no reference for the scene {cmp.scene!r}")
    elif a.error is None and b.error is None:
        lines.append(f"error: the reference ({cmp.reference}) applies to neither side")
    else:
        lines.append(f"error vs reference (mean |ΔY| / mean Y_ref): A {_pct(a.error)} · "
                     f"B {_pct(b.error)} — reference: {cmp.reference}")
    if d["max_abs"] == 0.0:
        lines.append("difference B − A: none (the images are identical)")
    else:
        lines.append(f"difference B − A (luminance): mean |ΔY| {d['mean_abs']:.3g} "
                     f"({_pct(d['mean_abs_rel_a'])} of A's mean Y), gain ×{cmp.gain:.3g} "
                     f"(|ΔY| {d['scale']:.3g} = full colour, the {GAIN_PERCENTILE:g}th "
                     f"percentile); {HEAT_CAPTION}")
    lines.append(f"renderer: {cmp.renderer}")
    lines.append(cmp.command)
    return lines


def _open_side(scene_name, params, root, ctx, camera, start_time, setup):
    session = open_session(scene_name, params, root, ctx=ctx, camera=copy.deepcopy(camera))
    session.scene.time = start_time
    if setup is not None:
        setup(session.scene)
    return session


def compare(scene_name: str | None, a_sets=(), b_sets=(), *, size=(320, 180), base_sets=(),
            preset=None, camera=None, hour=None, rounds: int = DEFAULT_ROUNDS,
            shader_root=None, ctx=None, session=None, params: ParamSet | None = None,
            reference: bool = True, setup=None, reference_cache: dict | None = None,
            progress: Callable[[str], None] | None = None) -> Comparison:
    """Render the scene with the sets ``a_sets`` and ``b_sets`` (``NAME=VALUE`` strings or a
    ``{name: value}`` mapping) over one base, time both in interleaved rounds, and measure
    their difference and each one's error against the scene's reference.

    The base is ``params`` (a ParamSet, copied) or the scene's defaults with ``preset``,
    ``base_sets`` and ``hour``; ``camera`` is a Camera or ``--camera`` text. With
    ``session`` (the window's live one) the base, the camera, the simulation time, the shader
    folder and the GL context are the session's; its scene and parameters are not touched
    (each side renders in a scene of its own, into its own targets, released afterwards: the
    caller binds its own framebuffer again). ``setup(scene)`` runs on each side's scene (a
    user mesh). ``reference=False`` skips the reference renders. Every set is checked before
    anything is rendered: a bad one is one :class:`UsageError` line naming it."""
    say = progress or (lambda text: None)
    start_time = 0.0
    if session is not None:
        scene_name = session.scene.name
        ctx = session.gpu.ctx
        root = session.gpu.shaders.root
        if params is None:
            params = session.params
        if camera is None:
            camera = session.scene.camera
        start_time = float(session.scene.time)
    else:
        root = resolve_shader_root(shader_root)
    w, h = (int(size[0]), int(size[1]))
    cls = get_scene(scene_name)
    # -- every input checked before any GL work
    if params is None:
        base = scene_params(scene_name, root, (), preset)
    else:
        base = copy.deepcopy(params)
        if preset:
            base.load_preset(Path(preset))
    apply_sets(base, normalize_sets(base_sets), "--set")
    if hour is not None:
        if "time.hour" not in base:
            raise UsageError(f"--time: scene {scene_name!r} has no time of day: allowed with "
                             "the scenes that have a day–night sky (see natura scenes)")
        base.set("time.hour", float(hour) % 24.0)
    if isinstance(camera, Camera):
        cam = copy.deepcopy(camera)
    else:  # the scene's own camera, or placed by ``--camera`` text
        cam = placed_camera(scene_name, base, None, None if camera is None else str(camera))
    a_list, b_list = normalize_sets(a_sets), normalize_sets(b_sets)
    pa = side_params(base, a_list, "--a")
    pb = side_params(base, b_list, "--b")
    ref = reference_of(scene_name) if reference else None
    differs = sorted(n for n in {s.partition("=")[0].strip() for s in (*a_list, *b_list)}
                     if n in pa and n in pb and pa[n] != pb[n])
    unrelated = None
    if ref is not None and not ref.judges_any(differs):
        unrelated = (f"no reference for {', '.join(differs)}: the scene's reference is of "
                     f"another method ({ref.label})")
        ref = None
    defaults = scene_params(scene_name, root)
    command = _command(scene_name, base, defaults, cam, cls.new_camera(), (w, h), a_list,
                       b_list, rounds)

    # -- the two sides, each in a scene of its own on one context
    say(f"opening {scene_name} twice (A: {label_of(a_list)}; B: {label_of(b_list)})")
    side_a = _open_side(scene_name, pa, root, ctx, cam, start_time, setup)
    sessions = [side_a]
    try:
        side_b = _open_side(scene_name, pb, root, side_a.gpu.ctx, cam, start_time, setup)
        sessions.append(side_b)
        gpu_ctx = side_a.gpu.ctx
        targets = {}
        runs = {}
        for name, s in (("A", side_a), ("B", side_b)):
            targets[name] = s.gpu.target("compare", f"side {name}", (w, h))

            def run(s=s, target=targets[name]):
                frame = s.scene.frame((w, h), dt=0.0)
                s.scene.render(frame, target)

            runs[name] = run
        say(f"timing A and B: 1 warm-up frame each, {rounds} interleaved rounds at {w}x{h}")
        timed = time_interleaved(gpu_ctx, runs, warmup=1, rounds=rounds)
        images, pngs, exposures, tonemaps = {}, {}, {}, {}
        for name, s in (("A", side_a), ("B", side_b)):
            images[name] = targets[name].read()[..., :3].astype(np.float32)
            exposures[name] = float(s.scene.exposure())
            tonemaps[name] = str(s.params["output.tonemap"])
            pngs[name] = to_srgb8(images[name], exposures[name], tonemaps[name])
        renderer = side_a.gpu.caps.describe()
        errors: dict[str, float | None] = {"A": None, "B": None}
        ref_labels: dict[str, str | None] = {"A": None, "B": None}
        if ref is not None:
            errors, ref_labels = _reference_errors(ref, {"A": side_a, "B": side_b}, images,
                                                   (w, h), say, reference_cache)
    finally:
        for s in reversed(sessions):
            s.release()
        if session is not None:  # leave no dead framebuffer bound in the window's context
            with contextlib.suppress(Exception):  # a context without a screen: none bound
                if ctx.screen is not None:
                    ctx.screen.use()

    ya, yb = luminance(images["A"]), luminance(images["B"])
    diff = (yb - ya).astype(np.float32)
    gain, scale = choose_gain(diff)
    mag = np.abs(diff.astype(np.float64))
    mean_a = float(ya.mean())
    stats = {"mean_abs": float(mag.mean()), "p99_abs": float(np.percentile(mag, 99)),
             "max_abs": float(mag.max()), "mean": float(diff.mean()), "scale": scale,
             "mean_abs_rel_a": float(mag.mean()) / mean_a if mean_a > 0 else None,
             "mean_luminance_a": mean_a, "mean_luminance_b": float(yb.mean()),
             # the share of pixels whose |ΔY| is above a millionth of A's mean luminance
             "changed_share": float((mag > 1e-6 * max(mean_a, 1e-30)).mean())}
    p25a, meda, p75a = timed.quartiles("A")
    p25b, medb, p75b = timed.quartiles("B")
    sides = {}
    for name, sets, med, q in (("A", a_list, meda, (p25a, p75a)),
                               ("B", b_list, medb, (p25b, p75b))):
        sides[name] = Side(label=label_of(sets), sets=list(sets), image=images[name],
                           png=pngs[name], ms=med, ms_quartiles=q, error=errors[name],
                           exposure=exposures[name], tonemap=tonemaps[name],
                           reference=ref_labels[name])
    cmp = Comparison(scene=scene_name, size=(w, h), a=sides["A"], b=sides["B"], diff=diff,
                     heat=heat_map(diff, gain), gain=gain,
                     reference=ref.label if ref is not None else None, caption=[],
                     rounds=timed.rounds, ratio=timed.ratio("B", "A"), diff_stats=stats,
                     renderer=renderer, command=command,
                     reference_skipped=not reference and reference_of(scene_name) is not None,
                     reference_unrelated=unrelated)
    cmp.caption = caption_lines(cmp)
    return cmp


def _reference_errors(ref: Reference, sides: dict, images: dict, size, say,
                      cache: dict | None = None):
    """Each side's error against its reference (the side's parameters with the overrides),
    rendered on the side's own scene once its timing is done; equal references render once —
    across comparisons too when they share ``cache`` (a report compares its first method with
    each of the others: the first one's reference is rendered once)."""
    w, h = size
    errors: dict[str, float | None] = {}
    labels: dict[str, str | None] = {}
    rendered: dict[str, np.ndarray] = {} if cache is None else cache
    for name, s in sides.items():
        overrides = ref.overrides(s.params)
        if overrides is None:
            errors[name], labels[name] = None, None
            continue
        params = s.params
        params.set_many(overrides)
        cam = s.scene.camera
        key = repr((s.scene.name, (w, h), ref.supersample, float(s.scene.time),
                    tuple(float(v) for v in cam.position), cam.yaw, cam.pitch, cam.fov,
                    sorted(params.values().items())))
        labels[name] = ref.label
        if key not in rendered:
            factor = _supersample_factor((w, h), ref.supersample, s.gpu.ctx.info.get(
                "GL_MAX_TEXTURE_SIZE", 8192))
            rw, rh = w * factor, h * factor
            say(f"rendering the reference for {name} at {rw}x{rh}"
                + (f" ({factor}×{factor} supersampled)" if factor > 1 else ""))
            with s.gpu.scratch_target("compare", f"reference {name}", (rw, rh)) as target:
                frame = s.scene.frame((rw, rh), dt=0.0)
                s.scene.render(frame, target)
                img = target.read()[..., :3].astype(np.float64)
            rendered[key] = box_down(img, factor)
        y_ref = luminance(rendered[key])
        mean_ref = float(y_ref.mean())
        d = float(np.abs(luminance(images[name]) - y_ref).mean())
        # a black reference has no relative error (None), unless the side is black too
        errors[name] = d / mean_ref if mean_ref > 0 else (0.0 if d == 0 else None)
    return errors, labels


#: characters the fallback bitmap font may lack, and what the image shows instead
_ASCII = str.maketrans({"−": "-", "–": "-", "—": "-", "×": "x", "Δ": "d", "τ": "tau",
                        "·": "|", "²": "2", "°": " deg", "≤": "<=", "≥": ">="})


def _font(size: int):
    """(font, whether it draws the caption's Unicode): matplotlib's DejaVu Sans (a dependency
    of the charts) found without importing matplotlib, else Pillow's default font."""
    import importlib.util

    from PIL import ImageFont

    spec = importlib.util.find_spec("matplotlib")
    folders = (spec.submodule_search_locations or ()) if spec is not None else ()
    for folder in folders:
        path = Path(folder) / "mpl-data" / "fonts" / "ttf" / "DejaVuSans.ttf"
        if path.is_file():
            try:
                return ImageFont.truetype(str(path), size), True
            except OSError:
                break
    try:
        return ImageFont.load_default(size=size), False
    except TypeError:  # Pillow < 10.1: the bitmap font, one size
        return ImageFont.load_default(), False


def _wrap(draw, text: str, font, width: int) -> list[str]:
    """``text`` in lines no wider than ``width`` pixels (breaking at spaces; a word longer
    than the width is cut by characters)."""
    out, line = [], ""
    for word in text.split(" "):
        trial = f"{line} {word}" if line else word
        if draw.textlength(trial, font=font) <= width:
            line = trial
            continue
        if line:
            out.append(line)
        line = word
        while draw.textlength(line, font=font) > width and len(line) > 1:
            cut = len(line) - 1
            while cut > 1 and draw.textlength(line[:cut], font=font) > width:
                cut -= 1
            out.append(line[:cut])
            line = line[cut:]
    out.append(line)
    return out


def caption_strip(lines: list[str], width: int, font_size: int = 12) -> np.ndarray:
    """The caption as an ``(h, width, 3)`` uint8 strip: light text on dark grey, each line
    wrapped to the width."""
    from PIL import Image, ImageDraw

    font, unicode = _font(font_size)
    pad = 4
    probe = ImageDraw.Draw(Image.new("RGB", (1, 1)))
    wrapped = [part for line in lines
               for part in _wrap(probe, line if unicode else line.translate(_ASCII), font,
                                 width - 2 * pad)]
    line_h = font_size + 3
    strip = Image.new("RGB", (width, len(wrapped) * line_h + 2 * pad), (24, 24, 28))
    draw = ImageDraw.Draw(strip)
    for i, text in enumerate(wrapped):
        draw.text((pad, pad + i * line_h), text, fill=(235, 235, 235), font=font)
    return np.asarray(strip)


def _tag(panel: np.ndarray, text: str, right: bool = False) -> np.ndarray:
    """A small label in a top corner of an image panel (when the panel is big enough)."""
    from PIL import Image, ImageDraw

    h, w = panel.shape[:2]
    if h < 40 or w < 60:
        return panel
    im = Image.fromarray(panel)
    draw = ImageDraw.Draw(im)
    font, unicode = _font(11)
    text = text if unicode else text.translate(_ASCII)
    tw = int(draw.textlength(text, font=font)) + 6
    x = w - tw - 2 if right else 2
    draw.rectangle((x, 2, x + tw, 17), fill=(0, 0, 0))
    draw.text((x + 3, 4), text, fill=(255, 255, 255), font=font)
    return np.asarray(im)


def compose(cmp: Comparison, layout: str = "side", wipe: float = 0.5) -> np.ndarray:
    """One uint8 image: A | B | heat map (``side``), or A left and B right of a vertical line
    at ``wipe`` (0..1 of the width) beside the heat map (``wipe``); the caption strip below."""
    if layout not in LAYOUTS:
        raise UsageError(f"--layout {quote(layout)} is unknown: allowed {', '.join(LAYOUTS)}")
    if not (isinstance(wipe, (int, float)) and math.isfinite(wipe) and 0.0 <= wipe <= 1.0):
        raise UsageError(f"--wipe {wipe!r} is out of range: allowed [0, 1]")
    a, b = cmp.a.png, cmp.b.png
    h, w = a.shape[:2]
    heat = _tag(cmp.heat, f"B − A ×{cmp.gain:.3g}")
    if layout == "side":
        panels = [_tag(a, "A"), _tag(b, "B"), heat]
    else:
        col = int(round(wipe * w))
        wiped = np.concatenate([a[:, :col], b[:, col:]], axis=1)
        wiped[:, min(max(col, 1), w) - 1] = 255  # the wipe's line
        if col > 0:
            wiped = _tag(wiped, "A")
        if col < w:
            wiped = _tag(wiped, "B", right=True)
        panels = [wiped, heat]
    top = np.concatenate(panels, axis=1)
    strip = caption_strip(cmp.caption, top.shape[1])
    return np.concatenate([top, strip], axis=0)


def encode_png(pixels: np.ndarray, optimize: bool = False) -> bytes:
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(pixels), "RGB").save(buf, format="PNG",
                                                             optimize=optimize)
    return buf.getvalue()


def write(cmp: Comparison, png_path, json_path=None, layout: str = "side", wipe: float = 0.5,
          force: bool = False) -> tuple[Path, Path | None]:
    """Write the composite PNG and (``json_path``) every figure as JSON, atomically, nothing
    overwritten without ``force`` (the caller checks both names before comparing)."""
    pixels = compose(cmp, layout, wipe)
    png = write_bytes_atomic(png_path, encode_png(pixels), force=force)
    out_json = None
    if json_path is not None:
        figures = {**cmp.figures(), "layout": layout, "wipe": wipe, "image": Path(png).name,
                   "image_size": [int(pixels.shape[1]), int(pixels.shape[0])]}
        out_json = write_text_atomic(json_path, json.dumps(figures, indent=2,
                                                           ensure_ascii=False) + "\n",
                                     force=force)
    return png, out_json

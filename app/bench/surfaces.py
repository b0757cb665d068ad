"""Speed against accuracy for the surfaces lab (spec/003 §2.4–2.8), each section against an
exact reference of the same analytic scene (app.sim.surfaces_scene):

1. **shadows** (app/bench/surfaces_shadows.py) — the shadow mismatch rate (acne, Peter
   Panning, aliasing) of the shared shadow module against the ray-cast visibility, per map
   size, bias setting, cascades and filter, against ms; the soft shadow of a disc light, ray
   cast in numpy (its error stated), against PCF, PCSS and VSM over all floor points and over
   the penumbra (the 256 jittered hard maps of the former reference beside it, with their own
   error); PCSS's penumbra over fit radii 5, 10 and 20 m; chart ``NAME.png``;
2. **transparency** (surfaces_transparency.py) — sorted blending, ZWrite off, weighted blended
   OIT and peeling with k layers against an A-buffer (each blended quad's fragments sorted per
   pixel in numpy), on every pixel and on the pixels with ≥ 2 layers, on the intersecting
   panes, the blue pane over the fence, the smoke and two views through several layers,
   against ms; the cutoff sweep and the
   alpha-to-coverage edge counts; chart ``NAME-transparency.png``;
3. **reflections** (surfaces_reflections.py) — each correction of the probe's lookup (cube,
   box projection, quadratic stretch, perfect sphere) against ray-cast reflections on the
   mirror floor and the mirror sphere, against ms; the thesis's metallic/dielectric weights
   against the split-sum GGX reference; chart ``NAME-reflections.png``;
4. **fresnel** (surfaces_fresnel.py, numpy) — Schlick against exact Fresnel for n = 1.31, 1.52
   and 2.42 (the thesis's Fig. 67 as numbers), and from inside the medium; chart
   ``NAME-fresnel.png``;
5. **speed** (surfaces_speed.py) — the lab's own frame at the bench's size: the reference
   (4× MSAA, the full shadow taps, the one generic program) against each speed knob and the
   defaults this renderer gets, ms in interleaved rounds against the 8-bit picture error;
   chart ``NAME-speed.png``.

``natura bench surfaces --repeat N`` with N ≤ :data:`QUICK_REPEAT` runs every section's quick
variant (fewer sizes and samples, the same figures); sections 1–4 render at their own sizes,
which the report records. On llvmpipe absolute times mean little; ratios within one
interleaved set hold.
"""

from __future__ import annotations

from pathlib import Path

from . import (
    surfaces_fresnel,
    surfaces_reflections,
    surfaces_shadows,
    surfaces_speed,
    surfaces_transparency,
)

#: the charts beside the report, in the order of the sections (the CLI checks them all first)
CHART_SUFFIXES = (".png", "-transparency.png", "-reflections.png", "-fresnel.png",
                  "-speed.png")
SECTIONS = (("shadows", surfaces_shadows), ("transparency", surfaces_transparency),
            ("reflections", surfaces_reflections), ("fresnel", surfaces_fresnel),
            ("speed", surfaces_speed))
#: a sweep asked for this many timed rounds or fewer runs the quick variants
QUICK_REPEAT = 5
#: the speed section's timed rounds stop past this many seconds (at least two run)
SPEED_BUDGET_S = 30.0


def sweep(session, size, warmup: int = 1, repeat: int = 7, sizes=None) -> dict:
    """Every section's report (the module's docstring), with ``quick`` when ``repeat`` ≤
    :data:`QUICK_REPEAT`. ``size`` and ``sizes`` are recorded; the sections choose theirs."""
    import time

    quick = repeat <= QUICK_REPEAT
    gpu = session.gpu
    out: dict = {"quick": quick, "seconds": {}}
    for key, module in SECTIONS:
        start = time.perf_counter()
        if key == "shadows":
            out[key] = module.run(gpu, quick=quick)
        elif key == "fresnel":
            out[key] = module.run(quick=quick)
        elif key == "speed":  # the lab's own frame at the bench's size
            out[key] = module.run(session, size, module.SURFACES, module.SURFACES_PASSES,
                                  warmup=warmup, rounds=max(3, repeat), budget_s=SPEED_BUDGET_S)
        else:
            out[key] = module.run(gpu, quick=quick)
        out["seconds"][key] = round(time.perf_counter() - start, 2)
    return out


def chart(report: dict, path, force: bool = False) -> None:
    """The four charts: ``path`` (shadows) and its siblings of :data:`CHART_SUFFIXES`."""
    path = Path(path)
    stem = path.with_suffix("")
    for (key, module), suffix in zip(SECTIONS, CHART_SUFFIXES):
        module.chart(report["sweep"][key], Path(f"{stem}{suffix}"), force=force)


def summary(report: dict) -> str:
    s = report["sweep"]
    lines = [f"surfaces sweeps ({'quick' if s['quick'] else 'full'}; seconds per section: "
             + ", ".join(f"{k} {v:g}" for k, v in s["seconds"].items()) + ")"]
    for key, module in SECTIONS:
        lines.append(f"-- {key}")
        if key == "speed":
            lines.extend(module.summary(s[key], "the lab's frame"))
        else:
            lines.extend(module.summary(s[key]))
    return "\n".join(lines)

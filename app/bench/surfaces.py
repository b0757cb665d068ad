"""Speed against accuracy for the surfaces lab (spec/003 §2.4–2.8), each section against an
exact reference of the same analytic scene (app.sim.surfaces_scene); each section's module
docstring says what it measures:

1. **shadows** (app/bench/surfaces_shadows.py), chart ``NAME.png``;
2. **transparency** (surfaces_transparency.py), chart ``NAME-transparency.png``;
3. **reflections** (surfaces_reflections.py), chart ``NAME-reflections.png``;
4. **fresnel** (surfaces_fresnel.py, numpy), chart ``NAME-fresnel.png``;
5. **speed** (surfaces_speed.py), chart ``NAME-speed.png``.

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

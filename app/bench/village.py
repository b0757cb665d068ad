"""Speed against accuracy for the toon village (spec/003 §2.9–2.11, §2.15, criterion 37), one
section per effect of the scene, each against its own reference; each section's module
docstring says what it measures:

1. **grass** (app/bench/village_grass.py), chart ``NAME.png``;
2. **fog** (village_fog.py), chart ``NAME-fog.png``;
3. **water** (village_water.py), chart ``NAME-water.png``;
4. **vr** (village_vr.py), chart ``NAME-vr.png``;
5. **look** (village_look.py), chart ``NAME-look.png``.

``natura bench village --repeat N`` with N ≤ :data:`QUICK_REPEAT` runs every section's quick
variant (fewer sizes and counts, the same figures). On llvmpipe absolute times mean little;
ratios within one interleaved set hold.
"""

from __future__ import annotations

import importlib
import time
from pathlib import Path

#: (key, module under app/bench, chart suffix), in the order of the sections
SECTIONS = (("grass", "village_grass", ".png"), ("fog", "village_fog", "-fog.png"),
            ("water", "village_water", "-water.png"), ("vr", "village_vr", "-vr.png"),
            ("look", "village_look", "-look.png"))
#: the charts beside the report (the CLI checks them all before anything runs)
CHART_SUFFIXES = tuple(suffix for _, _, suffix in SECTIONS)
#: a sweep asked for this many timed rounds or fewer runs the quick variants
QUICK_REPEAT = 5


def _module(name: str):
    return importlib.import_module(f"{__package__}.{name}")


def sweep(session, size, warmup: int = 1, repeat: int = 7, sizes=None) -> dict:
    """Every section's report, quick when ``repeat`` ≤ :data:`QUICK_REPEAT`; the sections
    choose their own sizes and record them."""
    quick = repeat <= QUICK_REPEAT
    out: dict = {"quick": quick, "seconds": {}}
    for key, name, _ in SECTIONS:
        start = time.perf_counter()
        out[key] = _module(name).run(session.gpu, quick=quick)
        out["seconds"][key] = round(time.perf_counter() - start, 2)
    return out


def chart(report: dict, path, force: bool = False) -> None:
    """The five charts: ``path`` (grass) and its siblings of :data:`CHART_SUFFIXES`."""
    stem = Path(path).with_suffix("")
    for key, name, suffix in SECTIONS:
        _module(name).chart(report["sweep"][key], Path(f"{stem}{suffix}"), force=force)


def summary(report: dict) -> str:
    s = report["sweep"]
    lines = [f"village sweeps ({'quick' if s['quick'] else 'full'}; seconds per section: "
             + ", ".join(f"{k} {v:g}" for k, v in s["seconds"].items()) + ")"]
    for key, name, _ in SECTIONS:
        lines.append(f"-- {key}")
        lines.extend(_module(name).summary(s[key]))
    return "\n".join(lines)

"""The sailing boat's speed polar: a chart and a few lines of figures.

The report is ``app.sim.sailing.speed_polar``'s dict: steady boat speed against the true wind
angle (degrees off the course, 0 = head to wind) for each true wind speed, the no-go angle, the
best VMG upwind and downwind, the beam-reach and largest speeds, and the hull speed. The chart is
the usual half polar (starboard tack; the port tack is its mirror image): one curve per wind
speed, radius in knots, the no-go wedge shaded, each best VMG marked.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..sim.sailing import KNOT, speed_polar
from . import pyplot, write_chart

#: the true wind angles' step [degrees]: the full polar's, and ``--quick``'s (the no-go angle is
#: refined by bisection to 0.1° either way; the VMG angles are on the coarser grid)
STEP, QUICK_STEP = 2.0, 5.0


def run(quick: bool = False) -> dict:
    """The polar of ``natura bench boat``: 4, 8 and 12 m/s, every 2° (5° when ``quick``)."""
    step = QUICK_STEP if quick else STEP
    return {**speed_polar(angles=np.arange(0.0, 180.0 + step / 2, step)), "quick": quick,
            "step": step}


def chart(report: dict, path, force: bool = False) -> None:
    """The polar (polar axes, one curve per wind speed, no-go wedge shaded), written through
    ``app.imageio.save_figure`` (atomic; an existing file is kept unless ``force``)."""
    plt = pyplot()

    twa = np.radians(np.asarray(report["twa"], dtype=np.float64))
    fig = plt.figure(figsize=(7.0, 8.5))
    ax: Any = fig.add_subplot(projection="polar")  # PolarAxes
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    ax.set_thetamin(0)
    ax.set_thetamax(180)
    top = max([max(s) for s in report["speed"]] + [report["hull_speed"]]) / KNOT * 1.1
    no_go = max(report["no_go"]) if report["no_go"] else 0.0
    wedge = np.radians(np.linspace(0.0, min(no_go, 180.0), 32))
    ax.fill_between(wedge, 0.0, top, color="0.85", zorder=0,
                    label=f"no-go (speed 0), up to {no_go:.0f}°")
    colours = plt.get_cmap("viridis")(np.linspace(0.1, 0.85, max(1, len(report["wind_speeds"]))))
    for i, vt in enumerate(report["wind_speeds"]):
        speed = np.asarray(report["speed"][i], dtype=np.float64) / KNOT
        # no line through the no-go zone: the speed falls to 0 there at a fold
        drawn = np.where((speed <= 0.0) & (twa < math.radians(report["no_go"][i])), np.nan,
                         speed)
        c = colours[i]
        ax.plot(twa, drawn, "-", color=c, lw=1.8,
                label=f"TWS {vt:g} m/s ({vt / KNOT:.0f} kn): no-go {report['no_go'][i]:.1f}°")
        ax.plot([math.radians(report["no_go"][i])] * 2, [0.0, top], ":", color=c, lw=0.9)
        for key, marker in (("upwind", "^"), ("downwind", "v")):
            v = report[key][i]
            theta = math.radians(v["twa"])
            r = float(np.interp(theta, twa, speed))
            ax.plot([theta], [r], marker, color=c, markersize=7)
    hull = report["hull_speed"] / KNOT
    ring = np.radians(np.linspace(0.0, 180.0, 181))
    ax.plot(ring, np.full_like(ring, hull), "--", color="firebrick", lw=0.9,
            label=f"hull speed {hull:.1f} kn")
    ax.set_ylim(0.0, top)
    ax.set_xlabel("boat speed [kn] against true wind angle (▲ best VMG upwind, ▼ downwind)")
    b = report.get("boat", {})
    fig.suptitle(f"speed polar — LWL {b.get('lwl', float('nan')):g} m, "
                 f"{b.get('displacement', float('nan')):g} kg, "
                 f"sail {b.get('sail_area', float('nan')):g} m²", fontsize=10)
    fig.legend(fontsize=8, loc="lower center", ncol=2)
    fig.subplots_adjust(left=0.02, right=0.9, top=0.93, bottom=0.2)
    write_chart(fig, path, force)


def summary(report: dict) -> str:
    """A few lines: per wind speed the no-go angle, best VMG up and down, beam and top speed."""
    hull = report["hull_speed"]
    lines = [f"hull speed {hull:.2f} m/s ({hull / KNOT:.1f} kn); {report.get('method', '')}"]
    for i, vt in enumerate(report["wind_speeds"]):
        up, down, top = report["upwind"][i], report["downwind"][i], report["max_speed"][i]
        beam = report["beam"][i]
        lines.append(f"TWS {vt:5.1f} m/s: no-go {report['no_go'][i]:5.1f}°, "
                     f"VMG up {up['vmg']:.2f} m/s at {up['twa']:.0f}°, "
                     f"down {down['vmg']:.2f} m/s at {down['twa']:.0f}°, "
                     f"beam {beam:.2f} m/s ({beam / KNOT:.1f} kn, {beam / hull:.2f}× hull), "
                     f"top {top['speed']:.2f} m/s at {top['twa']:.0f}°")
    return "\n".join(lines)

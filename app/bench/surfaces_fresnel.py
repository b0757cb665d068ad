"""The surfaces lab's Fresnel figures (spec/003 §2.7, the thesis's Fig. 67 as numbers), a
numpy-only section of its bench: Schlick's approximation (spec/003 eq. 5.27, spec/003 eq. 5.28,
spec/003 eq. 5.29) against the exact unpolarised Fresnel reflectance (spec/003 eq. 5.24,
spec/003 eq. 5.25, spec/003 eq. 5.26) from air into water (n = 1.31, the thesis's value), glass
(n = 1.52) and diamond (n = 2.42) over θ ∈ [0°, 90°]: both curves, the error curve, the largest
|Schlick − exact| and the angle where it occurs, and the hemisphere mean, cosine-weighted
(∫|e| cos θ dω / ∫cos θ dω = 2∫|e| cos θ sin θ dθ). Also the inside-the-medium case (n1 > n2,
toward air), which the thesis does not treat: the project's Schlick (at the transmitted angle,
R = 1 past the critical angle; ``FresnelSchlick``) and the naive one at the incident angle,
which misses total internal reflection near the critical angle.

``run(quick)`` → dict; ``chart(report, path, force)``; ``summary(report)`` → lines.
"""

from __future__ import annotations

import math

import numpy as np

from ..sim import optics as op
from . import pyplot, write_chart

INDICES = (1.31, 1.52, 2.42)
NAMES = {1.31: "water (thesis 1.31)", 1.52: "glass", 2.42: "diamond"}


def _errors(theta_deg: np.ndarray, approx: np.ndarray, exact: np.ndarray) -> dict:
    e = approx - exact
    k = int(np.argmax(np.abs(e)))
    th = np.radians(theta_deg)
    w = np.cos(th) * np.sin(th)
    mean = float(np.trapezoid(np.abs(e) * w, th) / np.trapezoid(w, th))
    return {"max_abs_error": float(abs(e[k])), "max_error_signed": float(e[k]),
            "max_error_at_deg": float(theta_deg[k]), "mean_abs_error_cos_weighted": mean}


def run(quick: bool = False) -> dict:
    theta = np.linspace(0.0, 90.0, 181 if quick else 1801)
    cos = np.cos(np.radians(theta))
    cos[-1] = 0.0
    outside, inside = [], []
    for n in INDICES:
        exact = op.fresnel_exact(cos, 1.0, n)
        schlick = op.fresnel_schlick(cos, 1.0, n)
        outside.append({"n1": 1.0, "n2": n, "c": float(op.fresnel_schlick(1.0, 1.0, n)),
                        "exact_normal": float(exact[0]), "exact": exact.tolist(),
                        "schlick": schlick.tolist(), **_errors(theta, schlick, exact)})
        exact_in = op.fresnel_exact(cos, n, 1.0)
        schlick_in = op.fresnel_schlick(cos, n, 1.0)
        naive = op.schlick_fresnel(((n - 1.0) / (n + 1.0)) ** 2, cos)
        inside.append({"n1": n, "n2": 1.0, "critical_deg": math.degrees(math.asin(1.0 / n)),
                       "exact": exact_in.tolist(), "schlick": schlick_in.tolist(),
                       "naive": naive.tolist(),
                       "schlick_errors": _errors(theta, schlick_in, exact_in),
                       "naive_errors": _errors(theta, naive, exact_in)})
    return {"theta_deg": theta.tolist(), "outside": outside, "inside": inside,
            "criterion_20": {"F1": float(op.fresnel_schlick(1.0, 1.0, 1.31)),
                             "F0": float(op.fresnel_schlick(0.0, 1.0, 1.31)),
                             "F_half": float(op.fresnel_schlick(0.5, 1.0, 1.31))}}


def chart(report: dict, path, force: bool = False) -> None:
    """Fig. 67's curves (air → n), Schlick − exact, and the inside-the-medium case."""
    plt = pyplot()

    th = np.asarray(report["theta_deg"])
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for k, r in enumerate(report["outside"]):
        c = f"C{k}"
        axes[0].plot(th, r["exact"], color=c, label=f"exact, {NAMES[r['n2']]}")
        axes[0].plot(th, r["schlick"], "--", color=c, label=f"Schlick, n = {r['n2']:g}")
        axes[1].plot(th, np.asarray(r["schlick"]) - np.asarray(r["exact"]), color=c,
                     label=f"n = {r['n2']:g}: max {r['max_abs_error']:.4f} at "
                           f"{r['max_error_at_deg']:.1f}°")
    axes[0].set_title("air → n: exact Fresnel vs Schlick (Fig. 67)", fontsize=9)
    axes[0].set_ylabel("reflectance R")
    axes[1].set_title("Schlick − exact, air → n", fontsize=9)
    axes[1].set_ylabel("ΔR")
    for k, r in enumerate(report["inside"]):
        c = f"C{k}"
        axes[2].plot(th, r["exact"], color=c, label=f"exact, n = {r['n1']:g} → 1")
        axes[2].plot(th, r["schlick"], "--", color=c, label="Schlick at θt (FresnelSchlick)")
        axes[2].plot(th, r["naive"], ":", color=c, label="Schlick at θi (naive)")
    axes[2].set_title("inside the medium (n → air): critical angle", fontsize=9)
    axes[2].set_ylabel("reflectance R")
    for ax in axes:
        ax.set_xlabel("incidence θ [°]")
        ax.legend(fontsize=6)
    write_chart(fig, path, force, title="surfaces Fresnel — Schlick vs exact "
                                        "(spec/003 eq. 5.26 vs spec/003 eq. 5.29)")


def summary(report: dict) -> list[str]:
    c20 = report["criterion_20"]
    lines = [f"criterion 20 (n = 1.31): Schlick F at cos 1: {c20['F1']:.4f}, at 0: "
             f"{c20['F0']:.4f}, at 0.5: {c20['F_half']:.4f}"]
    for r in report["outside"]:
        lines.append(f"  air → {r['n2']:.2f}: c {r['c']:.4f} = exact {r['exact_normal']:.4f}; "
                     f"Schlick − exact max {r['max_error_signed']:+.4f} at "
                     f"{r['max_error_at_deg']:.1f}°, cos-weighted mean "
                     f"{r['mean_abs_error_cos_weighted']:.5f}")
    for r in report["inside"]:
        s, n = r["schlick_errors"], r["naive_errors"]
        lines.append(f"  {r['n1']:.2f} → air (critical {r['critical_deg']:.1f}°): Schlick at θt "
                     f"max {s['max_abs_error']:.4f} at {s['max_error_at_deg']:.1f}° (mean "
                     f"{s['mean_abs_error_cos_weighted']:.4f}); naive at θi max "
                     f"{n['max_abs_error']:.4f} at {n['max_error_at_deg']:.1f}° (mean "
                     f"{n['mean_abs_error_cos_weighted']:.4f})")
    return lines

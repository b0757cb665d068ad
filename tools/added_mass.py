"""Added mass, radiation damping and hydrostatic stiffness of the generated hull, by a
boundary-element solver (capytaine), written to resources/boat/hydrodynamics.json.

capytaine is a tool dependency, not a runtime one: run this in a virtual environment of its own
(the runtime reads the committed numbers and never solves anything):

    python3 -m venv /tmp/capy-venv && /tmp/capy-venv/bin/pip install capytaine
    /tmp/capy-venv/bin/python tools/added_mass.py            # the hull at every tabulated mass
    /tmp/capy-venv/bin/python tools/added_mass.py --box      # the solver's check only

What it computes, per boat mass (the hull of ``app.sim.hull.make_hull()`` floated at its exact
draft, the centre of mass and inertia of ``app.sim.buoyancy.boat_body``):

* the radiation added mass A(ω) and damping B(ω) for heave, pitch (with their coupling) and
  roll, about the centre of mass, at ``OMEGAS`` (infinite depth, ρ = 1025 kg/m³);
* the hydrostatic stiffness of the immersed mesh (capytaine's own, from the panels);
* the coupled heave–pitch modes and the roll mode with the frequency-dependent A(ω), B(ω),
  each solved self-consistently (the mode's frequency is the one its coefficients are taken
  at): this is the reference ``natura bench boat`` grades the simulation against;
* the frequency-independent coefficients the runtime applies: heave terms at the heave mode's
  frequency, pitch terms at the pitch mode's, the coupling at their geometric mean, roll at the
  roll mode's.

The check (``--box``, and run before the hull): a 4 × 2 m box at 0.5 m draft heaves with
T = 2π·√(m/(ρ·g·A_w)) = 1.42 s without added mass and 2.16 s with it (issue 39).

Convergence (``--subdivide 2``, every panel split in four, 2.5 and 3 t): the reference periods
move by less than 0.5 % and the damping ratios by about 1 %: the reference's own error.

The file records a fingerprint of the hull mesh (``app.sim.hull.hull_fingerprint``); a unit test
fails when the generator changes and the numbers were not regenerated.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from app.sim import buoyancy as bu  # noqa: E402
from app.sim import hull as hl  # noqa: E402

OUT = ROOT / "resources" / "boat" / "hydrodynamics.json"
MASSES = (1000.0, 1500.0, 2000.0, 2500.0, 3000.0, 4000.0, 5000.0, 6000.0)
#: wave frequencies [rad/s]: periods 1.05 … 4.2 s, around every mode of the boats above (the
#: panels resolve waves to ω ≈ 5.5 rad/s: capytaine's λ/8 rule on the 0.29 m panels)
OMEGAS = tuple(float(w) for w in np.round(np.linspace(1.5, 6.0, 13), 4))
#: subdivision of the hull's triangles for the panels (each triangle into k²)
SUBDIVIDE = 1
G = 9.81


def _capytaine():
    try:
        import capytaine as cpt
    except ImportError:
        sys.exit("tools/added_mass.py: capytaine is not installed: run it with a venv that has "
                 "it (python3 -m venv /tmp/capy-venv && /tmp/capy-venv/bin/pip install "
                 "capytaine)")
    return cpt


def _solve(cpt, body, dofs, omegas, rho):
    """{(radiating, influenced): (A(ω), B(ω))} over ``omegas``."""
    solver = cpt.BEMSolver()
    problems = [cpt.RadiationProblem(body=body, radiating_dof=d, omega=w, rho=rho)
                for w in omegas for d in dofs]
    results = solver.solve_all(problems)
    out = {(r, i): (np.zeros(len(omegas)), np.zeros(len(omegas))) for r in dofs for i in dofs}
    for res in results:
        k = omegas.index(res.omega)
        for i in dofs:
            out[(res.radiating_dof, i)][0][k] = res.added_mass[i]
            out[(res.radiating_dof, i)][1][k] = res.radiation_damping[i]
    return out


def box_check(cpt, rho: float = 1025.0) -> dict:
    """The 4 × 2 × 0.5 m box's heave period without and with added mass (self-consistent)."""
    mesh = cpt.mesh_parallelepiped(size=(4.0, 2.0, 1.0), center=(0.0, 0.0, 0.0),
                                   resolution=(24, 12, 6))
    body = cpt.FloatingBody(mesh=mesh, dofs=cpt.rigid_body_dofs(rotation_center=(0, 0, 0)),
                            center_of_mass=(0, 0, 0), name="box").immersed_part()
    mass = rho * 4.0 * 2.0 * 0.5
    stiff = rho * G * 8.0
    omegas = [2.0, 2.5, 3.0, 3.5]
    coef = _solve(cpt, body, ["Heave"], omegas, rho)[("Heave", "Heave")]
    w = 2.0 * math.pi / 2.0
    for _ in range(30):
        a = float(np.interp(w, omegas, coef[0]))
        w = math.sqrt(stiff / (mass + a))
    return {"size": [4.0, 2.0, 0.5], "panels": int(body.mesh.nb_faces),
            "period_dry": 2.0 * math.pi * math.sqrt(mass / stiff),
            "period_added": 2.0 * math.pi / w, "added_mass_ratio": a / mass,
            "expected": {"period_dry": 1.42, "period_added": 2.16}}


def _mode(w, mass, stiff, added, damping, pick):
    """Self-consistent eigen-solve: iterate ω ← the picked mode's damped frequency."""
    om = w
    for _ in range(60):
        m = mass + np.array([[np.interp(om, OMEGAS, a) for a in row] for row in added])
        b = np.array([[np.interp(om, OMEGAS, x) for x in row] for row in damping])
        lam, vec = modes(m, b, stiff)
        k = pick(lam, vec)
        new = abs(lam[k].imag)
        if abs(new - om) < 1e-10:
            break
        om = new
    return lam[k], vec[:, k], om


def modes(mass, damping, stiff):
    """Eigenvalues and displacement shapes of M·ẍ + B·ẋ + C·x = 0 (those with Im λ > 0)."""
    n = len(mass)
    minv = np.linalg.inv(mass)
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-minv @ stiff, -minv @ damping]])
    lam, vec = np.linalg.eig(a)
    keep = lam.imag > 0
    return lam[keep], vec[:n, keep]


def hull_entry(cpt, mesh, mass: float, rho: float, subdivide: int = SUBDIVIDE) -> dict:
    draft = hl.draft_for_mass(mesh, mass, rho)
    body0 = bu.boat_body(mesh, mass, rho=rho)
    com_b = body0.com  # boat frame: x starboard-ish, y up from the keel, z to the bow
    inertia = body0.inertia_body
    panels = hl.subdivide(mesh, subdivide) if subdivide > 1 else mesh
    # boat (x, y, z) → capytaine (z, x, y − draft): a cyclic permutation (proper rotation), so
    # outward normals stay outward; capytaine's z is up, the free surface z = 0
    v = panels.vertices
    verts = np.stack([v[:, 2], v[:, 0], v[:, 1] - draft], axis=-1)
    faces = np.concatenate([panels.triangles, panels.triangles[:, 2:3]], axis=1)
    cog = (float(com_b[2]), float(com_b[0]), float(com_b[1] - draft))
    body = cpt.FloatingBody(mesh=cpt.Mesh(verts, faces, name="hull"),
                            dofs=cpt.rigid_body_dofs(rotation_center=cog),
                            center_of_mass=cog, mass=mass, name="hull").immersed_part()
    stiffness = body.compute_hydrostatic_stiffness(rho=rho, g=G)

    def c(i, j):
        return float(stiffness.sel(influenced_dof=i, radiating_dof=j))

    coef = _solve(cpt, body, ["Heave", "Pitch", "Roll"], list(OMEGAS), rho)

    def table(r, i):
        return [list(map(float, coef[(r, i)][0])), list(map(float, coef[(r, i)][1]))]

    # heave–pitch: capytaine's Heave (z) is the boat's y, its Pitch (about y) the boat's
    # rotation about x; roll (about capytaine's x) the boat's rotation about z
    m2 = np.diag([mass, float(inertia[0, 0])])
    k2 = np.array([[c("Heave", "Heave"), c("Heave", "Pitch")],
                   [c("Pitch", "Heave"), c("Pitch", "Pitch")]])
    a2 = [[coef[("Heave", "Heave")][0], coef[("Pitch", "Heave")][0]],
          [coef[("Heave", "Pitch")][0], coef[("Pitch", "Pitch")][0]]]
    b2 = [[coef[("Heave", "Heave")][1], coef[("Pitch", "Heave")][1]],
          [coef[("Heave", "Pitch")][1], coef[("Pitch", "Pitch")][1]]]
    half = float(np.ptp(mesh.vertices[:, 2])) / 2.0

    def heave_share(vec):  # |heave| against |pitch|·L/2
        return abs(vec[0]) / (abs(vec[0]) + abs(vec[1]) * half)

    w0 = math.sqrt(k2[0, 0] / mass) * 0.6
    lh, vh, wh = _mode(w0, m2, k2, a2, b2, lambda lam, vec: int(np.argmax(
        [heave_share(vec[:, k]) for k in range(len(lam))])))
    lp, vp, wp = _mode(w0, m2, k2, a2, b2, lambda lam, vec: int(np.argmin(
        [heave_share(vec[:, k]) for k in range(len(lam))])))
    m1 = np.array([[float(inertia[2, 2])]])
    k1 = np.array([[c("Roll", "Roll")]])
    lr, _, wr = _mode(math.sqrt(k1[0, 0] / m1[0, 0]) * 0.8, m1, k1,
                      [[coef[("Roll", "Roll")][0]]], [[coef[("Roll", "Roll")][1]]],
                      lambda lam, vec: 0)
    wm = math.sqrt(wh * wp)

    def at(r, i, w, k):
        return float(np.interp(w, OMEGAS, coef[(r, i)][k]))

    # the frequency-independent matrices, boat axes (vx, vy, vz, ωx, ωy, ωz) about the centre of
    # mass: boat y = capytaine Heave, boat ωx = capytaine Pitch, boat ωz = capytaine Roll
    a6, b6 = np.zeros((6, 6)), np.zeros((6, 6))
    for k, m6 in ((0, a6), (1, b6)):
        m6[1, 1] = at("Heave", "Heave", wh, k)
        m6[3, 3] = at("Pitch", "Pitch", wp, k)
        m6[1, 3] = at("Pitch", "Heave", wm, k)  # force in heave from pitching
        m6[3, 1] = at("Heave", "Pitch", wm, k)
        m6[5, 5] = at("Roll", "Roll", wr, k)

    def mode(lam, w):
        return {"period": 2.0 * math.pi / abs(lam.imag), "zeta": float(-lam.real / abs(lam)),
                "omega": float(w)}

    sub = mesh.submerged(draft)
    return {"mass": mass, "draft": draft, "com": [float(x) for x in com_b],
            "inertia": inertia.tolist(), "panels": int(body.mesh.nb_faces),
            "waterplane_area": sub.waterplane_area,
            "stiffness": {"heave": k2[0, 0], "heave_pitch": k2[0, 1], "pitch_heave": k2[1, 0],
                          "pitch": k2[1, 1], "roll": k1[0, 0]},
            "coefficients": {"heave": table("Heave", "Heave"), "pitch": table("Pitch", "Pitch"),
                             "heave_from_pitch": table("Pitch", "Heave"),
                             "pitch_from_heave": table("Heave", "Pitch"),
                             "roll": table("Roll", "Roll")},
            "reference": {"heave": mode(lh, wh), "pitch": mode(lp, wp), "roll": mode(lr, wr),
                          "heave_shape": [abs(complex(x)) for x in vh / abs(vh).max()],
                          "pitch_shape": [abs(complex(x)) for x in vp / abs(vp).max()]},
            "constant": {"added_mass": a6.tolist(), "damping": b6.tolist()}}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--box", action="store_true", help="the box check only")
    ap.add_argument("--masses", type=float, nargs="*", default=list(MASSES))
    ap.add_argument("--subdivide", type=int, default=SUBDIVIDE,
                    help="split each hull triangle into k² panels (the convergence check)")
    args = ap.parse_args(argv)
    cpt = _capytaine()
    start = time.time()
    box = box_check(cpt)
    print(f"box 4×2×0.5 m: heave {box['period_dry']:.3f} s dry, {box['period_added']:.3f} s with "
          f"added mass (A33/m {box['added_mass_ratio']:.3f}; issue: 1.42 → 2.16 s), "
          f"{time.time() - start:.0f} s", flush=True)
    if args.box:
        return 0
    mesh = hl.make_hull()
    rows = []
    for mass in args.masses:
        e = hull_entry(cpt, mesh, mass, hl.RHO_SEA, args.subdivide)
        r = e["reference"]
        print(f"{mass:6.0f} kg: heave {r['heave']['period']:.3f} s ζ {r['heave']['zeta']:.3f}, "
              f"pitch {r['pitch']['period']:.3f} s ζ {r['pitch']['zeta']:.3f}, roll "
              f"{r['roll']['period']:.3f} s ζ {r['roll']['zeta']:.3f}; A33/m "
              f"{e['constant']['added_mass'][1][1] / mass:.2f}, {e['panels']} panels, "
              f"{time.time() - start:.0f} s", flush=True)
        rows.append(e)
    data = {"what": "added mass, radiation damping and hydrostatic stiffness of the generated "
                    "hull (app/sim/hull.py make_hull) about the boat's centre of mass",
            "command": "/tmp/capy-venv/bin/python tools/added_mass.py  (capytaine in a venv of "
                       "its own: python3 -m venv /tmp/capy-venv && /tmp/capy-venv/bin/pip "
                       "install capytaine)",
            "solver": f"capytaine {cpt.__version__}, infinite depth, rho {hl.RHO_SEA}, g {G}",
            "hull_fingerprint": hl.hull_fingerprint(mesh), "subdivide": args.subdivide,
            "omegas": list(OMEGAS), "box": box, "masses": rows}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(data, indent=1) + "\n")
    print(f"→ {args.out} ({time.time() - start:.0f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())

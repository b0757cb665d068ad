"""The floating boat's physics validated and timed (numpy only, no GL): ``natura bench boat``.

``run(quick=False)`` → a report dict; ``chart(report, path)`` draws it; ``summary(report)`` is
its text.  Figures (the default 8 m hull, app/sim/hull.py; methods of app/sim/buoyancy.py):

1. **Archimedes** — the hydrostatic method settles (damped) in flat water to the exact draft
   of ``app.sim.hull.draft_for_mass`` for 1.5, 3 and 5 t; the probe methods' drafts beside it.
2. **Periods without the water's inertia** — undamped small oscillations in flat water, the
   body alone: the heave–pitch modes fitted (:func:`fit_modes`, two free-decay runs) against
   the coupled hydrostatic model M·ẍ + C·x = 0 (C from the BEM tool's panels,
   resources/boat/hydrodynamics.json: the integrator's check); roll against
   2π·sqrt(I_roll/(m·g·GM)), GM = KB + I_T/V − KG.
2b. **Modes with added mass and radiation damping** (:func:`modes`) — the heave, pitch and roll
   periods and damping ratios fitted to free-decay runs of each force method with the hull's
   frequency-independent coefficients, against the BEM reference: the coupled heave–pitch model
   with the frequency-dependent A(ω), B(ω), each mode at its own frequency
   (``app.sim.buoyancy.reference_modes``, tools/added_mass.py).  The decay is the amplitude
   ratio over one period, exp(−2π·ζ/√(1 − ζ²)).
3. **Kerner's drop test** — dropped from 2 m above its rest height and pushed 2 m under it: it
   settles both times, its energy decaying.
4. **Integrator energy error** — undamped heave (5 cm), the relative error of the total energy
   (kinetic + gravity + buoyancy potential) over 10 periods against the step: one step per
   frame (h = dt, the integrator itself) and the fixed substeps (h ≤ 1/240 s) per frame dt.
5. **In a sea** — heave tracking a long sine (correlation with the water height at the boat,
   amplitude ratio; the body alone); a storm (Hs = 6 m, wavelengths 50–160 m) at dt = 1/60 for
   10 simulated minutes (one in quick mode), with the added mass and damping: finite
   throughout.
6. **Speed against accuracy** — 4, 8, 16 and 32 force probes, the kinematic float (4 floating
   points) and the hydrostatic method against a reference — the hydrostatic method on the hull
   subdivided 16× (k = 4) — over poses in a short sine sea: error of force and torque relative
   to the weight (and weight × length), the flat-water equilibrium's draft and trim errors,
   against the median ms of one force evaluation and of one 1/60 s step, timed with
   ``time.perf_counter`` in interleaved rounds.

``run(quick=True)`` (``natura bench boat --quick``) is the same figures on less: two masses
(1.5 and 5 t), three frame steps (1/240, 1/60, 1/10 s) over 4 heave periods, shorter settling,
roll and tracking runs, a one-minute storm, 8 poses and 15 timing rounds — about a quarter of
the full run's time.
"""

from __future__ import annotations

import math
import random
import time

import numpy as np

from ..sim import buoyancy as bu
from ..sim import hull as hl
from ..sim.rigid_body import G, quat_from_axis_angle, quat_from_matrix
from . import pyplot, write_chart

MASSES = (1500.0, 3000.0, 5000.0)
MASS = 3000.0
DTS = (1.0 / 240.0, 1.0 / 120.0, 1.0 / 60.0, 1.0 / 30.0, 1.0 / 10.0)
PROBES = (4, 8, 16, 32)
#: what ``run(quick=True)`` keeps of them, and its storm's length [simulated minutes]
QUICK_MASSES = (1500.0, 5000.0)
QUICK_DTS = (1.0 / 240.0, 1.0 / 60.0, 1.0 / 10.0)
QUICK_STORM_MINUTES = 1.0


def _trim_heel(body) -> tuple[float, float]:
    """(trim [rad, bow down], heel [rad, starboard down]) of the body's orientation."""
    fwd, stbd = body.rotation[:, 2], body.rotation[:, 0]
    return math.asin(float(np.clip(-fwd[1], -1, 1))), math.asin(float(np.clip(-stbd[1], -1, 1)))


def _simulate(body, method, water, seconds: float, dt: float, record=None):
    """Step ``seconds`` at frame ``dt``; ``record(body, t)`` after each frame."""
    def fn(b, t):
        return method.forces(b, water, t)

    out = []
    for i in range(int(round(seconds / dt))):
        body.step(dt, fn)
        if record is not None:
            out.append(record(body, (i + 1) * dt))
    return out


def _crossing_period(t: np.ndarray, y: np.ndarray) -> float:
    """Mean period from the upward zero crossings of y (linear interpolation)."""
    s = np.nonzero((y[:-1] < 0) & (y[1:] >= 0))[0]
    tc = t[s] - y[s] * (t[s + 1] - t[s]) / (y[s + 1] - y[s])
    return float(np.mean(np.diff(tc))) if len(tc) > 1 else float("nan")



def settle(mesh, mass: float, method: str = "hydrostatic", seconds: float = 14.0,
           probes: int = 8) -> dict:
    """Start 10 cm high and heeled 3°, damp to rest in flat water; the final pose."""
    body = bu.boat_body(mesh, mass, max_substep=1.0 / 60.0)
    body.position = body.position + [0.0, 0.1, 0.0]
    body.set_orientation(quat_from_axis_angle((0, 0, 1), -0.05))
    m: bu.HydrostaticBuoyancy | bu.ProbeForces
    if method == "hydrostatic":
        m = bu.HydrostaticBuoyancy(mesh, linear_damping=2.0, angular_damping=2.0)
    else:
        m = bu.ProbeForces.for_hull(mesh, mass, probes, drag_up=4.0, drag_horizontal=2.0)
    _simulate(body, m, bu.FlatWater(), seconds, 1.0 / 60.0)
    trim, heel = _trim_heel(body)
    return {"draft": -float(body.position[1]), "trim": trim, "heel": heel,
            "speed": float(np.linalg.norm(body.velocity))}


def archimedes(mesh=None, masses=MASSES, quick: bool = False) -> dict:
    mesh = mesh or hl.make_hull()
    rows = []
    for mass in masses:
        exact = hl.draft_for_mass(mesh, mass)
        hyd = settle(mesh, mass, "hydrostatic", 10.0 if quick else 14.0)
        pr = settle(mesh, mass, "probes", 10.0 if quick else 14.0)
        rows.append({"mass": mass, "exact": exact, "hydrostatic": hyd["draft"],
                     "error": hyd["draft"] / exact - 1.0, "trim": hyd["trim"],
                     "heel": hyd["heel"], "probes8": pr["draft"], "probes8_trim": pr["trim"],
                     "float4": exact})  # the kinematic float puts its points on the water
    return {"rows": rows}



def fit_modes(t, signals, order: int = 4) -> list[dict]:
    """Damped sinusoids fitted to uniformly sampled ``signals`` (C, N) that share their poles
    (several channels of the same free decay): the matrix pencil method (Hua & Sarkar 1990) on
    the channels' stacked Hankel matrices, ``order`` poles (two per mode), then each channel's
    complex amplitudes by least squares.  → one dict per mode (Im s > 0), slowest first:
    ``period`` [s], ``zeta`` (damping ratio), ``decay`` (amplitude ratio over one period),
    ``amplitudes`` (|amplitude| per channel)."""
    y = np.atleast_2d(np.asarray(signals, float))
    n = y.shape[1]
    dt = float(t[1] - t[0])
    pencil = n // 3
    hankel = np.concatenate([np.lib.stride_tricks.sliding_window_view(c, pencil + 1) for c in y])
    _, _, vt = np.linalg.svd(hankel, full_matrices=False)
    v = vt[:order].T
    z = np.linalg.eigvals(np.linalg.pinv(v[:-1]) @ v[1:]).astype(complex)
    basis = z[None, :] ** np.arange(n)[:, None]
    amp = np.linalg.lstsq(basis, y.T.astype(complex), rcond=None)[0]
    s = np.log(z) / dt
    out = []
    for k in np.argsort(s.imag):
        if s[k].imag <= 1e-9:
            continue
        zeta = float(-s[k].real / abs(s[k]))
        out.append({"period": float(2.0 * math.pi / s[k].imag), "zeta": zeta,
                    "decay": float(math.exp(-2.0 * math.pi * zeta / math.sqrt(max(1.0 - zeta ** 2,
                                                                                  1e-12)))),
                    "amplitudes": [float(a) for a in np.abs(amp[k])]})
    return sorted(out, key=lambda m: -m["period"])


def free_decay_modes(mesh, mass: float, method, hydrodynamics: bool, seconds: float,
                     dt: float = 1.0 / 120.0, heave: float = 0.02, trim: float = 0.01,
                     hydro=None, substep: float = 1.0 / 240.0) -> dict:
    """Two free-decay runs in flat water (lifted ``heave`` [m]; trimmed ``trim`` [rad] about the
    centre of mass), heave of the centre of mass and trim × L/2 recorded every ``dt``, the two
    modes fitted to the four channels (:func:`fit_modes`): {"heave", "pitch"} each a mode dict
    (the heave mode: the larger share of heave in its amplitudes)."""
    half = 0.5 * float(np.ptp(mesh.vertices[:, 2]))
    channels = []
    for dy, dq in ((heave, 0.0), (0.0, trim)):
        body = bu.boat_body(mesh, mass, max_substep=substep, hydrodynamics=hydrodynamics)
        if hydro is not None:
            body.hydrodynamics = hydro
        rest = body.com_world.copy()
        body.set_orientation(quat_from_axis_angle((1, 0, 0), dq), keep="com")
        body.com_world = body.com_world + [0.0, dy, 0.0]
        rec = np.array(_simulate(body, method, bu.FlatWater(), seconds, dt,
                                 lambda b, t: (t, b.com_world[1] - rest[1],
                                               _trim_heel(b)[0] * half)))
        channels += [rec[:, 1], rec[:, 2]]
    fitted = fit_modes(rec[:, 0], np.array(channels), order=4)

    def share(m):
        a = m["amplitudes"]
        return (a[0] + a[2]) / max(a[0] + a[1] + a[2] + a[3], 1e-300)

    fitted = sorted(fitted, key=share)
    return {"pitch": fitted[0], "heave": fitted[-1]}


def roll_mode(mesh, mass: float, method, hydrodynamics: bool, seconds: float,
              dt: float = 1.0 / 120.0, heel: float = 0.02, substep: float = 1.0 / 240.0) -> dict:
    """The roll mode fitted to a free decay from ``heel`` [rad] (:func:`fit_modes`, one mode)."""
    body = bu.boat_body(mesh, mass, max_substep=substep, hydrodynamics=hydrodynamics)
    body.set_orientation(quat_from_axis_angle((0, 0, 1), -heel), keep="com")
    rec = np.array(_simulate(body, method, bu.FlatWater(), seconds, dt,
                             lambda b, t: (t, _trim_heel(b)[1])))
    return fit_modes(rec[:, 0], rec[:, 1:].T, order=2)[0]


def _dry_reference(mesh, mass: float) -> dict:
    """The coupled heave–pitch modes of the body alone, M·ẍ + C·x = 0: M = diag(m, I_pitch)
    of the body, C the BEM tool's hydrostatic stiffness of the panels (interpolated in mass)."""
    lo, hi, w = bu._row_for(mesh, mass, bu.HYDRODYNAMICS_FILE)
    k = {key: (1 - w) * lo["stiffness"][key] + w * hi["stiffness"][key]
         for key in ("heave", "heave_pitch", "pitch")}
    body = bu.boat_body(mesh, mass)
    m = np.diag([mass, float(body.inertia_body[0, 0])])
    c = np.array([[k["heave"], k["heave_pitch"]], [k["heave_pitch"], k["pitch"]]])
    lam, vec = np.linalg.eig(np.linalg.solve(m, c))
    half = 0.5 * float(np.ptp(mesh.vertices[:, 2]))
    share = np.abs(vec[0]) / (np.abs(vec[0]) + np.abs(vec[1]) * half)
    order = np.argsort(share)
    return {"pitch": 2 * math.pi / math.sqrt(lam[order[0]].real),
            "heave": 2 * math.pi / math.sqrt(lam[order[-1]].real)}


def periods(mesh=None, mass: float = MASS, quick: bool = False) -> dict:
    mesh = mesh or hl.make_hull()
    draft = hl.draft_for_mass(mesh, mass)
    sub = mesh.submerged(draft)
    method = bu.HydrostaticBuoyancy.undamped(mesh)
    water = bu.FlatWater()
    dry = _dry_reference(mesh, mass)
    fitted = free_decay_modes(mesh, mass, method, False, (3.0 if quick else 5.0) * dry["pitch"])
    heave, pitch = fitted["heave"]["period"], fitted["pitch"]["period"]
    # roll: GM = KB + BM − KG, BM = I_T/V, I_T = ∫ (2/3)·b³ dz over the waterline
    z = np.linspace(mesh.vertices[:, 2].min(), mesh.vertices[:, 2].max(), 2001)
    b = hl.waterline_half_beam(mesh, draft, z)
    i_t = float(np.sum(0.5 * ((2 / 3) * b[1:] ** 3 + (2 / 3) * b[:-1] ** 3) * np.diff(z)))
    body = bu.boat_body(mesh, mass, max_substep=1.0 / 120.0)
    gm = float(sub.centre[1]) + i_t / sub.volume - float(body.com[1])
    i_roll = float(body.inertia_body[2, 2])
    roll_expected = 2 * math.pi * math.sqrt(i_roll / (mass * G * gm))
    body.set_orientation(quat_from_axis_angle((0, 0, 1), -0.02), keep="com")
    rec = np.array(_simulate(body, method, water, (2.5 if quick else 4.5) * roll_expected,
                             1.0 / 120.0, lambda b, t: (t, _trim_heel(b)[1])))
    roll = _crossing_period(rec[:, 0], rec[:, 1])
    return {"heave": heave, "heave_expected": dry["heave"], "heave_error": heave / dry["heave"] - 1,
            "pitch": pitch, "pitch_expected": dry["pitch"],
            "pitch_error": pitch / dry["pitch"] - 1,
            "heave_uncoupled": 2 * math.pi * math.sqrt(mass / (hl.RHO_SEA * G
                                                               * sub.waterplane_area)),
            "waterplane_area": sub.waterplane_area, "roll": roll, "roll_expected": roll_expected,
            "gm": gm, "draft": draft}


#: the force methods :func:`modes` grades, without their own drag (the radiation damping alone)
MODE_METHODS = ("hydrostatic", "probe_forces")


def _mode_method(mesh, mass: float, name: str, drag: bool = False):
    if name == "hydrostatic":
        return bu.HydrostaticBuoyancy(mesh) if drag else bu.HydrostaticBuoyancy.undamped(mesh)
    if drag:
        return bu.ProbeForces.for_hull(mesh, mass, 8)
    return bu.ProbeForces.for_hull(mesh, mass, 8, drag_up=0.0, drag_horizontal=0.0)


def modes(mesh=None, mass: float = MASS, quick: bool = False) -> dict:
    """Heave, pitch and roll with the added mass and radiation damping, fitted, against the BEM
    reference; and the same fit of the body alone (the figures before the hydrodynamics)."""
    mesh = mesh or hl.make_hull()
    ref = bu.reference_modes(mesh, mass)
    seconds = 3.0 * ref["pitch"]["period"] if quick else 5.0 * ref["pitch"]["period"]
    rows = []
    variants = [(name, True, False) for name in MODE_METHODS]
    variants.append(("hydrostatic", True, True))  # the scene's: Kerner's drag on as well
    if not quick:
        variants.append(("probe_forces", True, True))
        variants.append(("hydrostatic", False, False))  # before: the body alone (as periods)
    substep = 1.0 / 120.0 if quick else 1.0 / 240.0
    for name, hydro, drag in variants:
        method = _mode_method(mesh, mass, name, drag)
        fit = free_decay_modes(mesh, mass, method, hydro, seconds if hydro else 8.0,
                               substep=substep)
        roll = roll_mode(mesh, mass, method, hydro, seconds * 1.2 if hydro else 8.0,
                         substep=substep)
        row = {"method": name, "hydrodynamics": hydro, "drag": drag,
               "heave": fit["heave"], "pitch": fit["pitch"], "roll": roll}
        for k in ("heave", "pitch", "roll"):
            row[k]["period_error"] = row[k]["period"] / ref[k]["period"] - 1.0
            row[k]["zeta_error"] = row[k]["zeta"] / ref[k]["zeta"] - 1.0
        rows.append(row)
    for k in ref:
        z = ref[k]["zeta"]
        ref[k]["decay"] = math.exp(-2.0 * math.pi * z / math.sqrt(1.0 - z * z))
    return {"mass": mass, "reference": ref, "rows": rows,
            "source": bu.hydrodynamics_table()["solver"]}



def drop_test(mesh=None, mass: float = MASS, quick: bool = False) -> dict:
    mesh = mesh or hl.make_hull()
    out = {}
    seconds = 12.0 if quick else 20.0
    for name, dy in (("dropped", 2.0), ("pushed", -2.0)):
        body = bu.boat_body(mesh, mass, max_substep=1.0 / 120.0)
        rest = bu.hydrostatic_energy(mesh, body)["total"]
        body.position = body.position + [0.0, dy, 0.0]
        method = bu.HydrostaticBuoyancy(mesh)
        rec = np.array(_simulate(body, method, bu.FlatWater(), seconds, 1.0 / 60.0,
                                 lambda b, t: (t, b.position[1],
                                               bu.hydrostatic_energy(mesh, b)["total"] - rest)))
        e = rec[:, 2]
        q = len(e) // 4
        windows = [float(np.max(np.abs(e[i * q:(i + 1) * q]))) for i in range(4)]
        out[name] = {"t": rec[:, 0].tolist(), "y": rec[:, 1].tolist(), "energy": e.tolist(),
                     "start_energy": float(e[0]), "final_energy": float(e[-1]),
                     "windows": windows, "final_offset": float(rec[-1, 1] - body.position[1]),
                     "final_y": float(rec[-1, 1]), "rest_y": -hl.draft_for_mass(mesh, mass),
                     "finite": bool(np.all(np.isfinite(rec)))}
    return out


def energy_error(mesh=None, mass: float = MASS, dts=DTS, periods_n: int = 10,
                 quick: bool = False) -> dict:
    mesh = mesh or hl.make_hull()
    draft = hl.draft_for_mass(mesh, mass)
    area = mesh.submerged(draft).waterplane_area
    period = 2 * math.pi * math.sqrt(mass / (hl.RHO_SEA * G * area))
    method = bu.HydrostaticBuoyancy.undamped(mesh)
    n = 4 if quick else periods_n
    rows = []
    for dt in dts:
        row = {"dt": dt}
        for scheme, sub in (("one_step", dt), ("substeps", 1.0 / 240.0)):
            if scheme == "substeps" and sub == dt:
                # at dt = 1/240 s the substeps are the one step: the same run (body, step and
                # records alike), so its figures are the one step's, not run again
                row[scheme] = dict(row["one_step"])
                continue
            body = bu.boat_body(mesh, mass, max_substep=sub)
            rest = bu.hydrostatic_energy(mesh, body)["total"]
            body.position = body.position + [0.0, 0.05, 0.0]
            e0 = bu.hydrostatic_energy(mesh, body)["total"] - rest
            es = np.array(_simulate(body, method, bu.FlatWater(), n * period, dt,
                                    lambda b, t: bu.hydrostatic_energy(mesh, b)["total"] - rest))
            row[scheme] = {"max": float(np.max(np.abs(es - e0)) / e0),
                           "drift": float((np.mean(es[-max(1, len(es) // n):]) - e0) / e0)}
        rows.append(row)
    return {"rows": rows, "period": period, "periods": n}



def sea(mesh=None, mass: float = MASS, quick: bool = False,
        storm_minutes: float | None = None) -> dict:
    mesh = mesh or hl.make_hull()
    water = bu.SineWater(amplitude=1.0, wavelength=80.0)
    body = bu.boat_body(mesh, mass, max_substep=1.0 / 120.0)
    draft = hl.draft_for_mass(mesh, mass)
    method = bu.HydrostaticBuoyancy(mesh)
    rec = np.array(_simulate(body, method, water, 24.0 if quick else 40.0, 1.0 / 60.0,
                             lambda b, t: (t, b.position[1] + draft,
                                           float(water.at(t).height(b.com_world[0],
                                                                    b.com_world[2])))))
    late = rec[len(rec) // 3:]
    corr = float(np.corrcoef(late[:, 1], late[:, 2])[0, 1])
    ratio = float(np.std(late[:, 1]) / np.std(late[:, 2]))
    storm = bu.storm_sea(6.0)
    # the scene's body: with the added mass and radiation damping
    body = bu.boat_body(mesh, mass, max_substep=1.0 / 60.0, hydrodynamics=True)
    minutes = storm_minutes if storm_minutes is not None else (2.0 if quick else 10.0)
    ys = np.array(_simulate(body, method, storm, 60.0 * minutes, 1.0 / 60.0,
                            lambda b, t: b.position[1] + draft))
    return {"tracking": {"t": rec[:, 0].tolist(), "heave": rec[:, 1].tolist(),
                         "water": rec[:, 2].tolist(), "correlation": corr, "ratio": ratio},
            "storm": {"minutes": minutes, "hs": storm.significant_height,
                      "finite": bool(np.all(np.isfinite(ys)) and body.finite()),
                      "heave_min": float(ys.min()), "heave_max": float(ys.max())}}



def _poses(n: int, seed: int = 1):
    rng = np.random.default_rng(seed)
    return [(float(rng.uniform(-0.3, 0.3)), float(rng.uniform(-0.25, 0.25)),
             float(rng.uniform(-0.08, 0.08)), float(rng.uniform(0, 2 * math.pi)))
            for _ in range(n)]


def speed_accuracy(mesh=None, mass: float = MASS, quick: bool = False) -> dict:
    mesh = mesh or hl.make_hull()
    fine = hl.subdivide(mesh, 4)
    water = bu.SineWater(amplitude=0.6, wavelength=12.0, direction=0.6)
    methods: dict[str, bu.HydrostaticBuoyancy | bu.ProbeForces] = {
        f"probes {n}": bu.ProbeForces.for_hull(mesh, mass, n) for n in PROBES}
    methods["hydrostatic"] = bu.HydrostaticBuoyancy(mesh)
    reference = bu.HydrostaticBuoyancy(fine)
    body = bu.boat_body(mesh, mass)
    rest = body.position.copy()
    err: dict[str, dict[str, list]] = {k: {"force": [], "torque": []} for k in methods}
    for dy, heel, trim, phase in _poses(8 if quick else 24):
        body.position = rest + [0.0, dy, 0.0]
        body.set_orientation(quat_from_matrix(hl.heel_trim_rotation(heel, trim)))
        w = water.at(phase / water.omega[0])
        fr, tr = reference.forces(body, w)
        scale = mass * G  # errors relative to the weight (and weight × length)
        for name, m in methods.items():
            f, t = m.forces(body, w)
            err[name]["force"].append(float(np.linalg.norm(f - fr)) / scale)
            err[name]["torque"].append(float(np.linalg.norm(t - tr)) / (scale * 8.0))
    # flat-water equilibrium against the exact one
    exact = hl.draft_for_mass(mesh, mass)
    rows = []
    for name, m in methods.items():
        n = int(name.split()[1]) if name.startswith("probes") else 0
        eq = settle(mesh, mass, "hydrostatic" if n == 0 else "probes",
                    8.0 if quick else 14.0, probes=n or 8)
        rows.append({"method": name, "force_error": float(np.median(err[name]["force"])),
                     "torque_error": float(np.median(err[name]["torque"])),
                     "draft_error": eq["draft"] - exact, "trim_error": eq["trim"]})
    floater = bu.ProbeFloat(bu.probe_layout(mesh, 4, exact)[0])
    timed = dict(methods)
    timing = time_methods(mesh, mass, timed, floater, water, rounds=15 if quick else 60)
    for r in rows:
        r.update(timing[r["method"]])
    rows.append({"method": "float 4 (kinematic)", **timing["float 4 (kinematic)"]})
    return {"rows": rows, "reference_triangles": len(fine.triangles),
            "triangles": len(mesh.triangles), "wave": {"amplitude": 0.6, "wavelength": 12.0}}


def time_methods(mesh, mass: float, methods: dict, floater, water, rounds: int = 60,
                 per_round: int = 10) -> dict:
    """Median ms of one force evaluation and of one 1/60 s frame (the body's substeps), each
    method once per round in a shuffled order (machine load moves all alike)."""
    body = bu.boat_body(mesh, mass)
    start = body.copy()
    samples: dict[str, dict[str, list]] = {k: {"eval": [], "frame": []} for k in methods}
    samples["float 4 (kinematic)"] = {"eval": [], "frame": []}
    names = list(samples)
    rng = random.Random(3)
    for _ in range(rounds):
        rng.shuffle(names)
        for name in names:
            b = start.copy()
            if name in methods:
                m = methods[name]
                t0 = time.perf_counter()
                for _ in range(per_round):
                    m.forces(b, water, 0.5)
                t1 = time.perf_counter()
                b.step(1.0 / 60.0, lambda body, t, m=m: m.forces(body, water, t))
                t2 = time.perf_counter()
                samples[name]["eval"].append((t1 - t0) / per_round)
            else:
                t0 = time.perf_counter()
                for _ in range(per_round):
                    floater.update(b, water, 1.0 / 60.0)
                t1 = time.perf_counter()
                floater.update(b, water, 1.0 / 60.0)
                t2 = time.perf_counter()
                samples[name]["eval"].append((t1 - t0) / per_round)
            samples[name]["frame"].append(t2 - t1)
    return {k: {"ms_eval": 1e3 * float(np.median(v["eval"])),
                "ms_frame": 1e3 * float(np.median(v["frame"]))} for k, v in samples.items()}



def run(quick: bool = False) -> dict:
    """Every figure of the module's docstring; ``quick``: the reduced run described there."""
    mesh = hl.make_hull()
    masses, dts = (QUICK_MASSES, QUICK_DTS) if quick else (MASSES, DTS)
    return {"scene": "boat", "quick": quick, "triangles": len(mesh.triangles),
            "archimedes": archimedes(mesh, masses, quick=quick),
            "periods": periods(mesh, quick=quick), "modes": modes(mesh, quick=quick),
            "drop": drop_test(mesh, quick=quick),
            "energy": energy_error(mesh, dts=dts, quick=quick),
            "sea": sea(mesh, quick=quick, storm_minutes=QUICK_STORM_MINUTES if quick else None),
            "speed": speed_accuracy(mesh, quick=quick)}


def chart(report: dict, path, force: bool = False) -> None:
    """Archimedes, drop test, energy error against dt, sea tracking, speed against accuracy."""
    plt = pyplot()

    fig, axes = plt.subplots(1, 5, figsize=(25, 4.6))
    ax = axes[0]
    rows = report["archimedes"]["rows"]
    x = np.arange(len(rows))
    for off, key, label in ((-0.25, "exact", "exact (Archimedes)"),
                            (0.0, "hydrostatic", "hydrostatic, settled"),
                            (0.25, "probes8", "8 force probes, settled")):
        ax.bar(x + off, [r[key] for r in rows], 0.25, label=label)
    ax.set_xticks(x, [f"{r['mass'] / 1000:g} t" for r in rows])
    ax.set_ylabel("draft [m]")
    p = report["periods"]
    title = (f"draft; body alone: heave {p['heave']:.3f} s (model {p['heave_expected']:.3f}), "
             f"roll {p['roll']:.2f} s")
    if "modes" in report:
        m, r = report["modes"]["rows"][0], report["modes"]["reference"]
        title += (f"\nwith the water's inertia: heave {m['heave']['period']:.2f} s, pitch "
                  f"{m['pitch']['period']:.2f} s (BEM {r['heave']['period']:.2f}, "
                  f"{r['pitch']['period']:.2f})")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=8)
    ax = axes[1]
    for name, style in (("dropped", "-"), ("pushed", "--")):
        d = report["drop"][name]
        ax.plot(d["t"], np.maximum(np.abs(d["energy"]), 1.0), style, label=f"{name} 2 m")
    ax.set(yscale="log", xlabel="t [s]", ylabel="|E − E_rest| [J]",
           title="Kerner's drop test: energy above rest")
    ax.legend(fontsize=8)
    ax = axes[2]
    e = report["energy"]
    dts = [r["dt"] for r in e["rows"]]
    for scheme, style in (("one_step", "o-"), ("substeps", "s--")):
        ax.plot(dts, [max(abs(r[scheme]["max"]), 1e-9) for r in e["rows"]], style,
                label=f"{'h = dt' if scheme == 'one_step' else 'h ≤ 1/240 s'}: max error")
        ax.plot(dts, [max(abs(r[scheme]["drift"]), 1e-9) for r in e["rows"]], style[0] + ":",
                label=f"{'h = dt' if scheme == 'one_step' else 'h ≤ 1/240 s'}: drift")
    ax.set(xscale="log", yscale="log", xlabel="frame dt [s]", ylabel="relative energy error")
    ax.set_title(f"undamped heave, {e['periods']} periods", fontsize=9)
    ax.legend(fontsize=7)
    ax = axes[3]
    tr = report["sea"]["tracking"]
    ax.plot(tr["t"], tr["water"], label="water at the boat")
    ax.plot(tr["t"], tr["heave"], label=f"heave (r = {tr['correlation']:.3f})")
    st = report["sea"]["storm"]
    ax.set_title(f"sine sea; storm Hs {st['hs']:.1f} m, {st['minutes']:g} min: "
                 f"{'finite' if st['finite'] else 'NOT FINITE'}", fontsize=9)
    ax.set_xlabel("t [s]")
    ax.legend(fontsize=8)
    ax = axes[4]
    for r in report["speed"]["rows"]:
        if "force_error" not in r:
            continue
        ax.plot([r["ms_eval"]], [max(r["force_error"], 1e-6)], "o")
        ax.annotate(r["method"], (r["ms_eval"], max(r["force_error"], 1e-6)), fontsize=8,
                    textcoords="offset points", xytext=(4, 4))
    ax.set(xscale="log", yscale="log", xlabel="ms per force evaluation",
           ylabel="force error / weight vs 16× hydrostatic")
    ax.set_title("speed against accuracy (sine sea, λ 12 m)", fontsize=9)
    write_chart(fig, path, force, title="natura bench boat")


def modes_summary(m: dict) -> list[str]:
    """The lines of :func:`modes`: the reference, then each variant."""
    r = m["reference"]
    lines = [f"modes at {m['mass']:.0f} kg, BEM reference ({m['source']}): "
             + ", ".join(f"{k} {r[k]['period']:.3f} s ζ {r[k]['zeta']:.3f}"
                         for k in ("heave", "pitch", "roll"))]
    for row in m["rows"]:
        what = (row["method"] + (", added mass + radiation damping" if row["hydrodynamics"]
                                 else ", body alone") + (", own drag" if row["drag"] else ""))
        lines.append(f"  {what}: " + ", ".join(
            f"{k} {row[k]['period']:.3f} s ({100 * row[k]['period_error']:+.1f} %) "
            f"ζ {row[k]['zeta']:.3f} decay/period {row[k]['decay']:.2f}"
            for k in ("heave", "pitch", "roll")))
    return lines


def summary(report: dict) -> str:
    lines = [f"hull: {report['triangles']} triangles"]
    for r in report["archimedes"]["rows"]:
        lines.append(f"{r['mass'] / 1000:4.1f} t: draft exact {r['exact']:.4f} m, hydrostatic "
                     f"{r['hydrostatic']:.4f} m ({100 * r['error']:+.3f} %, trim "
                     f"{math.degrees(r['trim']):+.3f}°), 8 probes {r['probes8']:.4f} m")
    p = report["periods"]
    lines.append(f"heave period {p['heave']:.4f} s (fitted mode, body alone), coupled "
                 f"hydrostatic model {p['heave_expected']:.4f} s ({100 * p['heave_error']:+.2f} %)"
                 + (f"; pitch {p['pitch']:.4f} s, model {p['pitch_expected']:.4f} s "
                    f"({100 * p['pitch_error']:+.2f} %)" if "pitch" in p else "")
                 + f"; roll {p['roll']:.3f} s, expected {p['roll_expected']:.3f} s "
                 f"(GM {p['gm']:.2f} m)")
    if "modes" in report:
        lines += modes_summary(report["modes"])
    for name in ("dropped", "pushed"):
        d = report["drop"][name]
        lines.append(f"drop test, {name} 2 m: energy above rest {d['start_energy']:.0f} J → "
                     f"{d['final_energy']:.2f} J, window maxima "
                     + ", ".join(f"{w:.0f}" for w in d["windows"]))
    for r in report["energy"]["rows"]:
        lines.append(f"dt 1/{1 / r['dt']:.0f} s: energy error h = dt max {r['one_step']['max']:.2e}"
                     f" drift {r['one_step']['drift']:+.2e}; substeps max "
                     f"{r['substeps']['max']:.2e} drift {r['substeps']['drift']:+.2e}")
    tr, st = report["sea"]["tracking"], report["sea"]["storm"]
    lines.append(f"sine sea: heave/water correlation {tr['correlation']:.3f}, amplitude ratio "
                 f"{tr['ratio']:.3f}; storm Hs {st['hs']:.1f} m for {st['minutes']:g} min: "
                 f"{'finite' if st['finite'] else 'NOT FINITE'}, heave {st['heave_min']:.2f}…"
                 f"{st['heave_max']:.2f} m")
    for r in report["speed"]["rows"]:
        acc = (f"force err {r['force_error']:.4f}, torque err {r['torque_error']:.4f}, "
               f"draft err {1000 * r['draft_error']:+.1f} mm, "
               f"trim {math.degrees(r['trim_error']):+.2f}°"
               if "force_error" in r else "kinematic")
        lines.append(f"{r['method']:20s} {r['ms_eval']:.3f} ms/eval, {r['ms_frame']:.3f} ms per "
                     f"1/60 s step; {acc}")
    return "\n".join(lines)

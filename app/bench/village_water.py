"""The toon village's water (spec/003 §2.10), a section of ``natura bench village``:

(a) **cost**: ms of the water pass — Simple and Complex, each with the depth fog off and with
    each of its three methods (document, repository, thickness) — over a synthetic scene (a
    checkered seabed sloping away under the water, its colour and depth written straight into
    the image: :class:`WaterRig`), in interleaved rounds (``app.gpu.timing.time_interleaved``),
    each run restoring the image first; the restore alone is timed in the same rounds and
    subtracted round by round (the water's net ms);
(b) **the Fresnel ramp** against the fifth power it replaces (the thesis baked
    0.018 + 0.982·(1 − u)^5, spec/003 eq. 7.22, into a ramp texture "to avoid the 5th power"):
    the ramp's largest error against the formula for widths 8 … 256, float (the effect's) and
    painted in 8 bits (the thesis's), read linearly (``app.sim.toon_water.fresnel_water_ramp``);
    on the GPU, the reflectance the water
    shows (``toon_water.output = 3``) with the ramp and with the power, their largest difference
    and the power's against the formula at each pixel's n·v; and the ms of the Complex water
    with each — is the texture cheaper than four multiplications on this renderer?

``run(gpu, quick)`` → dict; ``chart(report, path, force)``; ``summary(report)`` → lines.
:class:`WaterRig` is also the tests' stand (tests/gl/test_toon_water.py): the water alone
over an image whose every pixel's colour and depth the caller knows.
"""

from __future__ import annotations

import statistics
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..effects.toon_water import ToonWater
from ..frame import FrameContext, SceneImage
from ..gpu.timing import quartiles_of, time_interleaved
from ..params import ParamSet
from ..sim import toon_water as tw
from ..sim.camera import Camera
from ..sim.daynight import Light
from ..sim.sky import cubemap_face_direction
from . import pyplot, write_chart

OWNER = "bench-water"
#: a white light straight above, no ambient: the water's lit colour is toon_water.color itself
WHITE_TOP = Light("test", np.array([0.0, 1.0, 0.0]), (1.0, 1.0, 1.0), 1.0, (0.0, 0.0, 0.0))
#: the bench's view: 6 m above the water, 20° down, the seabed sloping away
BENCH_CAMERA = Camera(position=(0.0, 6.0, 0.0), yaw=0.0, pitch=-20.0, fov=60.0, near=0.1,
                      far=2000.0)


@dataclass
class Backdrop:
    """What the image holds before the water: linear colour (h, w, 3) and view depth (h, w)
    in metres along the camera's axis (inf: nothing, the far plane); row 0 at the top."""

    colour: np.ndarray
    z: np.ndarray


def seabed(camera: Camera, size: tuple[int, int], y0: float = -1.0, slope=(0.0, 0.12),
           colour: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None,
           sky=(0.45, 0.6, 0.85), extra: Callable | None = None) -> Backdrop:
    """A tilted seabed y = y0 + slope·(x, z) seen by ``camera`` (ray cast per pixel): its
    colour ``colour(x, z)`` (default a 1 m checker of sand and weed), the sky colour where the
    ray misses it. ``extra(d, t)`` may return (hit mask, t, rgb) of another surface in front."""
    w, h = size
    d = camera.ray_directions(w, h)
    o = np.asarray(camera.position, np.float64)
    gx, gz = slope
    denom = d[..., 1] - gx * d[..., 0] - gz * d[..., 2]
    num = y0 + gx * o[0] + gz * o[2] - o[1]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(np.abs(denom) > 1e-9, num / denom, np.inf)
    t = np.where(t > 0.0, t, np.inf)
    p = o + d * np.where(np.isfinite(t), t, 0.0)[..., None]
    if colour is None:
        def colour(x, z):
            k = (np.floor(x) + np.floor(z)).astype(int) % 2
            return np.where(k[..., None] == 0, [0.85, 0.72, 0.45], [0.25, 0.45, 0.2])
    rgb = np.where(np.isfinite(t)[..., None], colour(p[..., 0], p[..., 2]),
                   np.asarray(sky, np.float64))
    if extra is not None:
        mask, te, erg = extra(d, t)
        t = np.where(mask, te, t)
        rgb = np.where(mask[..., None], erg, rgb)
    along = d @ camera.forward()
    z = np.where(np.isfinite(t), t * along, np.inf)
    return Backdrop(rgb, z)


class CubeEnvironment:
    """An ``environment`` slot holding one cubemap (with or without the sun: the same)."""

    def __init__(self, cube):
        self.cube = cube

    def cubemap(self, sun: bool = True):
        return self.cube


def gradient_environment(gpu, owner: str, size: int = 16,
                         rgb: Callable[[np.ndarray], np.ndarray] | None = None):
    """A cubemap whose texel in direction d holds ``rgb(d)`` (default a smooth gradient over
    every channel: red with x, green with y, blue with z), float32, mipmapped."""
    if rgb is None:
        def rgb(d):
            return 0.5 + 0.5 * d
    cube = gpu.texture_cube(owner, "test environment", size, dtype="f4")
    c = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    s, t = np.meshgrid(c, c)  # row j: t
    for face in range(6):
        d = cubemap_face_direction(face, s, t)
        data = np.concatenate([rgb(d), np.ones(d.shape[:2] + (1,))], -1).astype("f4")
        cube.write(face, data.tobytes())
    cube.build_mipmaps()
    return CubeEnvironment(cube)


class WaterRig:
    """The water effect alone over a :class:`Backdrop` written into its image (a float target
    with depth), with its own parameters (``set``) and frame (``render``)."""

    def __init__(self, gpu, size: tuple[int, int] = (96, 54), owner: str = OWNER):
        self.gpu = gpu
        self.owner = owner
        self.size = (int(size[0]), int(size[1]))
        self.params = ParamSet(ToonWater.declare(gpu.shaders))
        self.effect = ToonWater(gpu, self.params)
        self.target = gpu.target(owner, "water rig image", self.size)
        self._saved = None

    def set(self, **values) -> WaterRig:
        self.params.set_many({f"toon_water.{k}": v for k, v in values.items()})
        return self

    def write_backdrop(self, backdrop: Backdrop, camera: Camera) -> None:
        """The backdrop's colour and window depth into the image (GL rows: bottom first)."""
        h, w = backdrop.z.shape
        rgba = np.concatenate([backdrop.colour, np.ones((h, w, 1))], -1)[::-1]
        self.target.color.write(np.ascontiguousarray(rgba, dtype="f4").tobytes())
        z = np.where(np.isfinite(backdrop.z), backdrop.z, camera.far)
        d = np.where(np.isfinite(backdrop.z), tw.window_depth(np.maximum(z, camera.near),
                                                              camera.near, camera.far), 1.0)
        self.target.depth.write(np.ascontiguousarray(d[::-1], dtype="f4").tobytes())

    def frame(self, camera: Camera, time: float = 0.0, light: Light | None = WHITE_TOP,
              environment=None, fog=None, terrain=None) -> FrameContext:
        frame = FrameContext(size=self.size, camera=camera, time=time, main_light=light,
                             environment=environment, fog=fog, terrain=terrain)
        frame.image = SceneImage(self.target)
        self.effect.update(frame, 0.0)
        return frame

    def render(self, camera: Camera, backdrop: Backdrop, time: float = 0.0, **slots) -> np.ndarray:
        """The water drawn over ``backdrop``: the image (h, w, 4), row 0 at the top."""
        self.write_backdrop(backdrop, camera)
        frame = self.frame(camera, time, **slots)
        self.effect.draw(frame, self.target)
        return self.target.read()

    def depth(self) -> np.ndarray:
        """The image's window depth after the last render (h, w), row 0 at the top."""
        return self.target.read_depth()

    def save(self) -> None:
        """Keep the image as it is now (the backdrop): :meth:`restore` puts it back."""
        if self._saved is None:
            colour = self.gpu.texture(self.owner, "saved colour", self.size, 4, dtype="f4")
            depth = self.gpu.depth_texture(self.owner, "saved depth", self.size)
            self._saved = self.gpu.framebuffer(self.owner, "saved", [colour], depth)
        self.gpu.ctx.copy_framebuffer(self._saved, self.target.fbo)

    def restore(self) -> None:
        self.gpu.ctx.copy_framebuffer(self.target.fbo, self._saved)

    def release(self) -> None:
        self.effect.release()
        self.gpu.release_owner(self.owner)


def _net(timed, name: str, reference: str, base: str) -> dict:
    """Median and quartiles over the rounds of (name − reference) ms, the raw median, and the
    per-round ratio of the net time to ``base``'s (load moves both sides of a round together)."""
    a, b = timed.timings[name].wall_ms, timed.timings[reference].wall_ms
    c = timed.timings[base].wall_ms
    diff = [x - y for x, y in zip(a, b)]
    ratio = [(x - y) / (z - y) for x, y, z in zip(a, b, c) if z - y > 0]
    q, r = quartiles_of(diff), quartiles_of(ratio)
    return {"net_ms": q[1], "net_p25_ms": q[0], "net_p75_ms": q[2],
            "raw_ms": statistics.median(a), "rounds": len(diff),
            f"ratio_to_{base.replace(' ', '_')}": r[1], "ratio_p25": r[0], "ratio_p75": r[2]}


VARIANTS = [(t, f) for t in ("simple", "complex") for f in ("off",) + tw.FOG_METHODS]
#: the variant every other's per-round ratio is taken to
BASE = "simple fog off"
RAMP_WIDTHS = (8, 16, 32, 64, 128, 256)


def ramp_errors(widths=RAMP_WIDTHS, samples: int = 20001) -> list[dict]:
    """The ramp of each width, float (the effect's) and painted in 8 bits (the thesis's), read
    linearly, against spec/003 eq. 7.22 on a dense u."""
    u = np.linspace(0.0, 1.0, samples)
    exact = tw.fresnel_water(u)
    out = []
    for w in widths:
        err = np.abs(tw.fresnel_water_ramp(tw.fresnel_ramp(w), u) - exact)
        err8 = np.abs(tw.fresnel_water_ramp(tw.fresnel_ramp(w, bits=8), u) - exact)
        k = int(np.argmax(err))
        out.append({"width": int(w), "max_error": float(err[k]), "at_u": float(u[k]),
                    "max_error_255": float(err[k] * 255.0),
                    "max_error_8bit": float(err8.max()),
                    "max_error_8bit_255": float(err8.max() * 255.0)})
    return out


def run(gpu, quick: bool = False) -> dict:
    size = (160, 90) if quick else (480, 270)
    rounds = 9 if quick else 25
    cam = BENCH_CAMERA
    rig = WaterRig(gpu, size)
    env = gradient_environment(gpu, OWNER)
    try:
        backdrop = seabed(cam, size)
        rig.write_backdrop(backdrop, cam)
        rig.save()
        frames: dict[str, FrameContext] = {}

        def variant(kind: str, fog: str, fresnel: str = "ramp"):
            def go():
                rig.set(type=kind, depth_fog=fog != "off", fresnel=fresnel)
                if fog != "off":
                    rig.set(fog_method=fog)
                rig.restore()
                rig.effect.draw(frames["f"], rig.target)
            return go

        frames["f"] = rig.frame(cam, 1.0, environment=env)
        variants = {"restore": rig.restore}
        for kind, fog in VARIANTS:
            variants[f"{kind} fog {fog}"] = variant(kind, fog)
        variants["complex pow5 fog thickness"] = variant("complex", "thickness", "pow5")
        timed = time_interleaved(gpu.ctx, variants, warmup=1, rounds=rounds)
        cost = {name: _net(timed, name, "restore", BASE) for name in variants
                if name != "restore"}
        cost["restore"] = {"raw_ms": timed.timings["restore"].median_ms}
        # (b) the reflectance the water shows, ramp against pow5, waves off (n = up)
        rig.set(type="complex", output=3, wave_intensity=0.0, highlight=0.0)
        shown = {}
        for fresnel in ("ramp", "pow5"):
            rig.set(fresnel=fresnel)
            shown[fresnel] = rig.render(cam, backdrop, 1.0, environment=env)[..., 0]
        water = rig.depth() < 1.0
        water &= ~np.isclose(shown["pow5"], 0.0)
        nv = np.clip(-cam.ray_directions(*size)[..., 1], 0.0, 1.0)
        formula = tw.fresnel_water(nv)
        gpu_ramp = float(np.abs(shown["ramp"] - shown["pow5"])[water].max())
        gpu_pow5 = float(np.abs(shown["pow5"] - formula)[water].max())
        ramp_ms = cost["complex fog thickness"]["net_ms"]
        pow5_ms = cost["complex pow5 fog thickness"]["net_ms"]
        per_round = _net(timed, "complex fog thickness", "restore",
                         "complex pow5 fog thickness")
        return {
            "size": list(size), "rounds": rounds, "camera": [*cam.position, cam.yaw, cam.pitch],
            "renderer": gpu.caps.renderer, "cost": cost,
            "ramp": {"width": tw.RAMP_WIDTH, "widths": ramp_errors(),
                     "gpu_ramp_vs_pow5_max": gpu_ramp, "gpu_pow5_vs_formula_max": gpu_pow5,
                     "gpu_pixels": int(water.sum()), "ramp_ms": ramp_ms, "pow5_ms": pow5_ms,
                     "ramp_over_pow5": per_round["ratio_to_complex_pow5_fog_thickness"],
                     "ramp_over_pow5_p25": per_round["ratio_p25"],
                     "ramp_over_pow5_p75": per_round["ratio_p75"]},
        }
    finally:
        gpu.free(env.cube)
        rig.release()


def chart(report: dict, path, force: bool = False) -> None:
    """Left: the net ms of each variant (interquartile bars). Right: the ramp's error against
    the formula per width (1/255 marked), and the GPU's ramp − pow5."""
    plt = pyplot()

    fig, (a, b) = plt.subplots(1, 2, figsize=(13, 4.5))
    names = [n for n in report["cost"] if n != "restore"]
    med = [report["cost"][n]["net_ms"] for n in names]
    lo = [m - report["cost"][n]["net_p25_ms"] for n, m in zip(names, med)]
    hi = [report["cost"][n]["net_p75_ms"] - m for n, m in zip(names, med)]
    colours = ["C0" if n.startswith("simple") else "C3" if "pow5" in n else "C1" for n in names]
    a.barh(range(len(names)), med, xerr=[lo, hi], color=colours)
    key = "ratio_to_" + BASE.replace(" ", "_")
    for i, n in enumerate(names):
        a.text(0.02 * max(med), i, f"×{report['cost'][n][key]:.2f}", va="center", fontsize=7,
               color="white")
    a.set_yticks(range(len(names)), names, fontsize=8)
    a.invert_yaxis()
    w, h = report["size"]
    a.set_xlabel(f"ms of the water pass at {w}×{h} (net of the image restore; ×: per-round "
                 f"ratio to {BASE})")
    a.set_title(f"cost, {report['renderer']}", fontsize=9)
    r = report["ramp"]
    widths = [x["width"] for x in r["widths"]]
    b.loglog(widths, [x["max_error"] for x in r["widths"]], "o-", label="float ramp, linear "
             "reads, against 0.018 + 0.982·(1 − u)^5")
    b.loglog(widths, [x["max_error_8bit"] for x in r["widths"]], "s--",
             label="the same painted in 8 bits (the thesis's GIMP ramp)")
    b.axhline(1 / 255, color="k", ls=":", label="1/255 (criterion 20)")
    b.axhline(max(r["gpu_ramp_vs_pow5_max"], 1e-6), color="C3", ls="--",
              label=f"GPU, width {r['width']}: ramp − pow5 max {r['gpu_ramp_vs_pow5_max']:.1e}")
    b.set(xlabel="ramp width [texels]", ylabel="largest |error|")
    b.set_title(f"Fresnel ramp: {r['ramp_ms']:.3f} ms vs pow5 {r['pow5_ms']:.3f} ms\n"
                f"(per-round ratio {r['ramp_over_pow5']:.2f}, quartiles "
                f"{r['ramp_over_pow5_p25']:.2f}–{r['ramp_over_pow5_p75']:.2f})", fontsize=9)
    b.legend(fontsize=7)
    write_chart(fig, path, force, title="village water — Simple and Complex, depth fogs, "
                                        "Fresnel ramp vs pow5 (spec/003 §2.10)")


def summary(report: dict) -> list[str]:
    c = report["cost"]
    w, h = report["size"]
    lines = [f"water pass at {w}×{h}, net ms (median of {c[BASE]['rounds']} interleaved "
             f"rounds; × the per-round ratio to {BASE}):"]
    key = "ratio_to_" + BASE.replace(" ", "_")
    for kind in ("simple", "complex"):
        lines.append(f"  {kind}: " + ", ".join(
            f"fog {f} {c[f'{kind} fog {f}']['net_ms']:.3f} (×{c[f'{kind} fog {f}'][key]:.2f})"
            for f in ("off",) + tw.FOG_METHODS))
    r = report["ramp"]
    widest = r["widths"][-1]
    lines.append(f"Fresnel ramp ({r['width']} texels): max error "
                 f"{widest['max_error_255']:.3f}/255 (numpy; "
                 f"{widest['max_error_8bit_255']:.2f}/255 painted in 8 bits); on the GPU ramp − "
                 f"pow5 {r['gpu_ramp_vs_pow5_max'] * 255:.3f}/255, pow5 − formula "
                 f"{r['gpu_pow5_vs_formula_max'] * 255:.3f}/255")
    lines.append(f"  Complex ms: ramp {r['ramp_ms']:.3f}, pow5 {r['pow5_ms']:.3f}; per-round "
                 f"ratio ramp/pow5 {r['ramp_over_pow5']:.2f} (quartiles "
                 f"{r['ramp_over_pow5_p25']:.2f}–{r['ramp_over_pow5_p75']:.2f})")
    return lines

"""The open sea of the maritime thesis (spec/000 §1.1–1.3): three wave models switchable live —
sine (eqs. 2.1–2.4), a sum of Gerstner waves (eqs. 2.5–2.8) and the cascaded FFT ocean
(Tessendorf; §1.1(d)–(e)) — rendered with the sky's reflection probe, the main light's glitter,
foam, an underwater view, and water-height queries for floating objects.

What lives where
* numpy reference and oceanography: ``app/sim/ocean.py`` (spectra, dispersion, Gerstner,
  synthesis, inversion); the GPU simulation (evolve, FFT, finalize, foam, readback):
  ``app/effects/ocean_fft.py``; GLSL: ``glsl/ocean/`` (waves.glsl = the three models,
  shading.glsl = Fresnel, glitter, foam, underwater light).
* Level of detail: a polar grid centred under the camera whose rings grow geometrically (cells
  about square, one connected mesh: no seams), displacement faded to flat water toward
  ``ocean.mesh_extent``, then an analytic plane to the horizon (``far.frag``).
* Water-height queries (:meth:`Ocean.water`): sine and Gerstner are evaluated exactly in numpy;
  the FFT reads back the displacement textures asynchronously — the answer describes the sea
  **one frame earlier** (the frame before the last ``update``), never stalls the GPU, and its
  time is ``Ocean.query_time``. Heights come from the iterative inversion of the horizontal
  displacement (spec/000 §1.3, 3 corrections + a final read).
"""

from __future__ import annotations

import math

import moderngl
import numpy as np

from ...errors import ParamError
from ...params import Param
from ...sim import ocean as oc
from ...frame import Stage
from ...gpu.copy import ColourCopy
from ...gpu.programs import ProgramSpec, draw_fullscreen, fullscreen
from ..base import Effect, Pass

MODELS = ("sine", "gerstner", "fft")
FFT_SIZES = ("64", "128", "256", "512")

SURFACE = ProgramSpec("ocean/surface")
FAR = fullscreen("ocean/far")
UNDERWATER = fullscreen("ocean/underwater")
# the GPU simulation's programs (app/effects/ocean_fft.py, app/gpu/fft.py), listed so that
# `natura shaders check` compiles them and their @param annotations are found
SIMULATION = (
    ProgramSpec("ocean/spectrum_evolve", comp="ocean/spectrum_evolve.comp", requires_compute=True),
    ProgramSpec("ocean/ocean_finalize", comp="ocean/ocean_finalize.comp", requires_compute=True),
    ProgramSpec("ocean/direct_sum", comp="ocean/direct_sum.comp", requires_compute=True),
    ProgramSpec("ocean/fft_radix2", comp="ocean/fft_radix2.comp", requires_compute=True,
                defines=(("FFT_N", 256), ("FFT_HALF_N", 128), ("FFT_LOG2N", 8))),
    fullscreen("ocean/spectrum_evolve"), fullscreen("ocean/ocean_finalize"), fullscreen("ocean/direct_sum"),
    ProgramSpec("ocean/fft_stage", vert="common/fullscreen.vert", frag="ocean/fft_stage.frag",
                defines=(("FFT_COUNT", 2),)),
)


def wind_vector(direction_deg: float) -> np.ndarray:
    """Unit (x, z) vector the wind blows toward: 0° = north (−z), 90° = east (+x)."""
    a = math.radians(direction_deg)
    return np.array([math.sin(a), -math.cos(a)])


def polar_grid(segments: int, inner: float, extent: float):
    """Rest-point mesh around the camera: a centre vertex, then rings r₀ = inner,
    r_{i+1} = r_i·(1 + 2π/segments) up to ``extent`` (cells about square).

    Returns (vertices (V, 3) float32 = (radius, angle, spacing), indices (M,) uint32), triangles
    counter-clockwise seen from above (front faces are the top of the sea), ordered segment by
    segment (all rings of wedge j, then wedge j + 1): a run of wedges is one contiguous range of
    ``len(indices) // segments`` indices each, so the renderer draws only the wedges in view."""
    growth = 1.0 + 2.0 * math.pi / segments
    radii = [0.0, inner]
    while radii[-1] < extent:
        radii.append(min(radii[-1] * growth, extent))
    radii = np.array(radii)
    theta = np.arange(segments) * (2.0 * math.pi / segments)
    spacing = np.maximum(radii * (2.0 * math.pi / segments), inner * 2.0 * math.pi / segments)
    # vertices column by column (all rings at angle θ_j), so a run of wedges also reads one
    # contiguous range of vertices: software rasterisers shade every vertex in the index range
    nr = len(radii) - 1
    col = np.stack([radii[1:], np.zeros(nr), spacing[1:]], axis=1)
    verts = [np.array([[0.0, 0.0, spacing[1]]])]
    for t in theta:
        c = col.copy()
        c[:, 1] = t
        verts.append(c)
    vertices = np.concatenate(verts).astype("f4")
    rings = np.arange(nr - 1)
    wedges = []
    for j in range(segments):
        nj = (j + 1) % segments
        a = 1 + j * nr + rings  # ring i at θ_j
        b = 1 + nj * nr + rings  # ring i at θ_{j+1}
        fan = np.array([[0, 1 + nj * nr, 1 + j * nr]])
        quads = np.concatenate([np.stack([a, b, b + 1], axis=1)[:, None],
                                np.stack([a, b + 1, a + 1], axis=1)[:, None]], axis=1).reshape(-1, 3)
        wedges.append(np.concatenate([fan, quads]))
    # (θ grows from +x toward +z, so θ_j → θ_{j+1} → outward is counter-clockwise seen from +y)
    return vertices, np.concatenate(wedges).astype("u4").ravel()


def visible_wedges(camera, aspect: float, segments: int, margin: int = 2):
    """Index ranges (first wedge, count) of the polar grid's wedges the camera can see, or None
    for all of them. The grid's angle θ runs from +x toward +z; a wedge is visible when its
    azimuth lies within the frustum's horizontal spread (from its corner rays) plus a margin —
    unless a corner ray points down or up steeply enough to see past the camera's feet."""
    r, u, f = camera.basis()
    th = math.tan(math.radians(camera.fov) * 0.5)
    corners = [f + sx * th * aspect * r + sy * th * u for sx in (-1, 1) for sy in (-1, 1)]
    fh = np.array([f[0], 0.0, f[2]])
    if np.linalg.norm(fh) < 1e-6:
        return None
    fh /= np.linalg.norm(fh)
    rh = np.array([-fh[2], 0.0, fh[0]])
    spread = 0.0
    for d in corners:
        ahead = float(d @ fh)
        if ahead <= 1e-3:
            return None
        spread = max(spread, abs(math.atan2(float(d @ rh), ahead)))
    step = 2.0 * math.pi / segments
    centre = math.atan2(fh[2], fh[0]) % (2.0 * math.pi)
    half = int(math.ceil(spread / step)) + margin
    if 2 * half + 1 >= segments:
        return None
    first = int(math.floor(centre / step)) - half
    return first % segments, 2 * half + 2


class Ocean(Effect):
    name = "ocean"
    title = "Ocean"
    spec = "spec/000"
    programs = (SURFACE, FAR, UNDERWATER) + SIMULATION
    #: water stage seen from above; fog stage near or under the surface (see passes())
    stages = (Stage.WATER, Stage.FOG)
    produces = frozenset({"wind", "water"})
    consumes = {"environment": "optional", "main_light": "optional", "image": "optional"}

    @classmethod
    def python_params(cls) -> list[Param]:
        s1, s2, s3 = "spec/000 §1.1", "spec/000 §1.2", "spec/000 §1.3"
        return [
            Param("ocean.model", "fft", doc="wave model: sine (eqs. 2.1–2.4), gerstner (eqs. 2.5–2.8) or fft "
                  "(Tessendorf cascades)", kind="choice", choices=MODELS, section=s1),
            Param("ocean.spectrum", "jonswap", doc="sea spectrum for the FFT and the Gerstner set: Phillips, "
                  "Pierson–Moskowitz or JONSWAP (with TMA in finite depth)", kind="choice", choices=oc.SPECTRA,
                  section=s1 + "(d)"),
            Param("ocean.wind", 10.0, 0.0, 40.0, "wind speed at 19.5 m (10 m for Phillips)", step=0.1, unit="m/s",
                  section=s1 + "(d)"),
            Param("ocean.wind_direction", 90.0, 0.0, 360.0, "direction the wind blows toward: 0 = north (−z), "
                  "90 = east (+x)", step=1.0, unit="°", section=s1 + "(d)"),
            Param("ocean.fetch", 100.0, 1.0, 2000.0, "JONSWAP fetch: distance the wind has blown over water",
                  step=1.0, unit="km", section=s1 + "(d)"),
            Param("ocean.gamma", 3.3, 1.0, 7.0, "JONSWAP peak enhancement γ", step=0.1, section=s1 + "(d)"),
            Param("ocean.depth", 1000.0, 1.0, 10000.0, "water depth d: dispersion ω² = g·k·tanh(k·d) and the TMA "
                  "correction", step=1.0, unit="m", section=s1 + "(d)"),
            Param("ocean.short_wave_fade", 0.01, 0.0, 1.0, "Tessendorf's small-wave suppression length ℓ: "
                  "spectrum × exp(−(k·ℓ)²)", step=0.001, unit="m", section=s1 + "(d)"),
            Param("ocean.choppiness", 1.0, 0.0, 4.0, "choppiness λ: horizontal displacement x + λ·D (crests "
                  "sharpen; the surface folds where the Jacobian < 0)", step=0.05, section=s1 + "(d)"),
            Param("ocean.fft_size", "256", doc="FFT grid N per cascade", kind="choice", choices=FFT_SIZES,
                  section=s1 + "(e)"),
            Param("ocean.cascades", 3, 1, 4, "number of cascades (non-overlapping wavenumber bands)", kind="int",
                  section=s1 + "(e)"),
            Param("ocean.patch_sizes", (250.0, 17.0, 5.0, 1.5), 0.1, 5000.0, "tile size L of each cascade, "
                  "strictly decreasing (the upstream's 250 / 17 / 5 m)", kind="vec4", step=0.1, unit="m",
                  section=s1 + "(e)"),
            Param("ocean.fft_path", "auto", doc="GPU FFT path: compute shaders (GL 4.3), fragment passes (GL 3.3) "
                  "or auto (compute on a GPU that has it; fragment on software renderers, where it is faster)", kind="choice", choices=("auto", "compute", "fragment"),
                  section=s1 + "(d)"),
            Param("ocean.seed", 0, 0, 1_000_000, "random seed of the wave amplitudes and phases", kind="int"),
            Param("ocean.foam_mode", "whitecaps", doc="whitecaps: foam thresholds set per cascade so foam covers "
                  "Monahan & O'Muircheartaigh's fraction of the sea for the wind (beyond the thesis); jacobian: "
                  "the upstream's fixed threshold (ocean.foam_threshold)", kind="choice",
                  choices=("whitecaps", "jacobian"), section=s2),
            Param("ocean.foam_threshold", 0.5, 0.01, 1.0, "jacobian mode: foam appears where the Jacobian drops "
                  "below this", step=0.01, section=s2),
            Param("ocean.foam_decay", 2.0, 0.05, 30.0, "foam fades as e^(−t/τ): τ", step=0.05, unit="s",
                  section=s2),
            Param("ocean.foam_amount", 1.0, 0.0, 4.0, "foam strength", step=0.05, section=s2),
            Param("ocean.sine_amplitude", 0.5, 0.0, 10.0, "sine wave amplitude A (eq. 2.1)", step=0.01, unit="m",
                  section=s1 + "(a)"),
            Param("ocean.sine_wavelength", 20.0, 0.1, 500.0, "sine wavelength 2π/k (ω from the dispersion "
                  "relation)", step=0.1, unit="m", section=s1 + "(a)"),
            Param("ocean.gerstner_waves", 16, 1, 64, "number of Gerstner waves, drawn from the spectrum (same Hs "
                  "and peak period as the FFT sea)", kind="int", section=s1 + "(c)"),
            Param("ocean.gerstner_steepness", 1.0, 0.0, 20.0, "scales every Gerstner wave's amplitude, so its "
                  "steepness s = k·A; each wave must keep s ≤ 1", step=0.05, section=s1 + "(c)"),
            Param("ocean.subgrid_slopes", True, doc="beyond the thesis: the glitter lobe gets the slope variance "
                  "the grid cannot hold (Cox–Munk minus what is resolved)", kind="bool", section=s2),
            Param("ocean.mesh_segments", 256, 32, 1024, "angular segments of the polar surface mesh (its density)",
                  kind="int", section=s1),
            Param("ocean.mesh_inner", 0.25, 0.01, 10.0, "radius of the mesh's first ring", step=0.01, unit="m",
                  section=s1),
            Param("ocean.mesh_extent", 3000.0, 50.0, 50000.0, "radius of the surface mesh; beyond it the sea is "
                  "an analytic plane to the horizon", step=10.0, unit="m", section=s1),
            Param("ocean.mesh_cull", True, doc="draw only the wedges of the surface mesh the camera can see",
                  kind="bool", section=s1),
            Param("ocean.query_iterations", 3, 0, 10, "corrections of the water-height inversion (the "
                  "upstream's 3)", kind="int", section=s3),
        ]

    # -- life ------------------------------------------------------------------------------
    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        self.sim = None  # GpuOceanSim, only for the FFT model
        self._foam_key = None
        self._foam: list[tuple[float, float]] = []
        self._sim_path = None
        self._sim_key = None
        self._fft_ref: oc.FFTOcean | None = None
        self._waves: list[oc.GerstnerWave] = []
        self._waves_key = None
        self._mesh = self.keyed(self._make_mesh, release=lambda objs: [gpu.free(o) for o in objs])
        self._scene_copy = ColourCopy(gpu, self.name, "scene copy")
        self._color_copy = ColourCopy(gpu, self.name, "color copy")
        self._flat_env = None
        self.time = 0.0
        self.camera_pos = np.zeros(3)
        self.query_time: float | None = None
        self._readback = None
        self.resolved_mss = 0.0
        self.cascade_bands: list[tuple[float, float, float]] = []
        self.underwater = False
        self.camera_height_water = 0.0
        self._fft_hs = 0.0
        self.mesh_triangles = 0
        self.drawn_triangles = 0

    # -- sea state -------------------------------------------------------------------------
    def spectrum_params(self) -> oc.SpectrumParams:
        p = self.params
        d = wind_vector(p["ocean.wind_direction"])
        return oc.SpectrumParams(kind=p["ocean.spectrum"], wind_speed=p["ocean.wind"],
                                 wind_direction=math.atan2(d[1], d[0]), fetch=p["ocean.fetch"] * 1000.0,
                                 gamma=p["ocean.gamma"], depth=p["ocean.depth"],
                                 short_wave_fade=p["ocean.short_wave_fade"])

    def patch_sizes(self) -> list[float]:
        return [float(s) for s in self.params["ocean.patch_sizes"][: self.params["ocean.cascades"]]]

    def fft_size(self) -> int:
        return int(self.params["ocean.fft_size"])

    def gerstner_waves(self) -> list[oc.GerstnerWave]:
        p = self.params
        key = (self.spectrum_params(), p["ocean.gerstner_waves"], p["ocean.gerstner_steepness"], p["ocean.seed"])
        if key != self._waves_key:
            waves = oc.gerstner_waves_from_spectrum(key[0], key[1], seed=key[3], steepness_scale=key[2])
            worst = max(range(len(waves)), key=lambda i: waves[i].steepness)
            if waves[worst].steepness > 1.0:
                limit = key[2] / waves[worst].steepness
                raise ParamError(
                    f"ocean.gerstner_steepness={key[2]:g} makes wave {worst} ({waves[worst].wavelength:.3g} m) "
                    f"reach steepness s = {waves[worst].steepness:.3g}: allowed 0 ≤ s ≤ 1 per wave "
                    f"(loops at the crests), so at most {limit:.3g} for this sea")
            oc.check_gerstner_steepness(waves)
            self._waves, self._waves_key = waves, key
        return self._waves

    def sine_wave(self) -> tuple[float, float, float]:
        """(amplitude, wavenumber, ω) of the sine model; ω from the dispersion relation."""
        p = self.params
        k = 2.0 * math.pi / p["ocean.sine_wavelength"]
        return p["ocean.sine_amplitude"], k, float(oc.dispersion_omega(k, p["ocean.depth"]))

    def significant_height(self) -> float:
        """Hs of what is drawn (m)."""
        model = self.params["ocean.model"]
        if model == "sine":
            return 2.0 * math.sqrt(2.0) * self.params["ocean.sine_amplitude"]
        if model == "gerstner":
            return oc.gerstner_moments(self.gerstner_waves())["hs"]
        return self._fft_hs

    def _ensure_fft(self) -> None:
        path = self.params["ocean.fft_path"]
        key = (self.spectrum_params(), self.fft_size(), tuple(self.patch_sizes()), self.params["ocean.seed"])
        if self.sim is not None and self._sim_path != path:
            self._release_fft()
        if key == self._sim_key:
            return
        ref = oc.FFTOcean(key[0], n=key[1], patch_sizes=key[2], choppiness=1.0, seed=key[3])
        if self.sim is None:
            from ...gpu.fft import resolve_compute
            from .fft import GpuOceanSim
            if path == "auto":  # llvmpipe runs the fragment path faster (evolve and finalize
                # as image stores cost it 2–3×: 79 against 98 ms per update at 256 × 3)
                use_compute = self.gpu.caps.compute and not self.gpu.caps.software
            else:
                use_compute = resolve_compute(self.gpu, path == "compute", "ocean.fft_path=compute")
            self.sim = GpuOceanSim(self.gpu, self.name, use_compute=use_compute)
            self._sim_path = path
        self.sim.set_spectrum(ref.cascades, key[1])
        self._fft_ref = ref
        self._sim_key = key
        self._readback = None
        self.query_time = None  # flat water until the new sea is read back
        # per-cascade band and slope variance for the glitter filter; Hs of the draw
        self.cascade_bands = []
        m0 = 0.0
        for c in ref.cascades:
            var, mss = c.moments()
            lo = max(c.band[0], 2.0 * math.pi / c.patch_size)
            self.cascade_bands.append((lo, min(c.band[1], math.pi * key[1] / c.patch_size), mss))
            m0 += var
        self.resolved_mss = sum(b[2] for b in self.cascade_bands)
        self._fft_hs = 4.0 * math.sqrt(m0)

    @property
    def reference(self) -> oc.FFTOcean | None:
        """The numpy ocean whose amplitudes the GPU simulation holds (None unless the FFT runs)."""
        return self._fft_ref

    def foam_thresholds(self) -> list[tuple[float, float]]:
        """(threshold, ramp width) of the foam source per cascade (FFT) or for the wave set.

        Whitecap mode calibrates them on the sea's own Jacobian (the FFT's λ = 1 derivative fields
        at t = 0, rescaled for the choppiness; a grid of the Gerstner set), so that the foam covers
        Monahan & O'Muircheartaigh's whitecap fraction for the wind."""
        p = self.params
        model = p["ocean.model"]
        if p["ocean.foam_mode"] == "jacobian":
            t = p["ocean.foam_threshold"]
            return [(t, t)] * (len(self.cascade_bands) if model == "fft" and self.cascade_bands else 1)
        key = (model, p["ocean.choppiness"], p["ocean.wind"], self._sim_key if model == "fft" else self._waves_key)
        if key != self._foam_key:
            coverage = oc.whitecap_coverage(p["ocean.wind"])
            if model == "fft" and self._fft_ref is not None:
                lam = p["ocean.choppiness"]
                if self._fft_ref.time is None:
                    self._fft_ref.update(0.0)
                jacs = [(1 + lam * c.fields.ddx_dx) * (1 + lam * c.fields.ddz_dz) - (lam * c.fields.ddx_dz) ** 2
                        for c in self._fft_ref.cascades]
            elif model == "gerstner":
                waves = self.gerstner_waves()
                span = 2.0 * max(w.wavelength for w in waves)
                g = np.linspace(0.0, span, 192)
                x, z = np.meshgrid(g, g)
                jacs = [oc.gerstner(x, z, 0.0, waves, check=False).jacobian]
            else:
                jacs = [np.ones(4)]  # the sine wave has no horizontal motion: no foam
            # whitecaps break mostly on the long waves: each finer cascade gets half the foam of
            # the one before (57 / 29 / 14 % of the coverage for three)
            self._foam = oc.whitecap_thresholds(jacs, coverage, shares=[0.5**i for i in range(len(jacs))])
            self._foam_key = key
        return self._foam

    def _release_fft(self) -> None:
        if self.sim is not None:
            self.sim.release()
            self.sim = None
            self._sim_key = None
            self._fft_ref = None
            self._readback = None
            self._fft_hs = 0.0

    # -- frame -----------------------------------------------------------------------------
    def update(self, frame, dt: float) -> None:
        p = self.params
        self.time = frame.time
        self.camera_pos = np.asarray(frame.camera.position, dtype=float)
        model = p["ocean.model"]
        if model == "fft":
            self._ensure_fft()
            thresholds = self.foam_thresholds()
            self.sim.update(frame.time, p["ocean.choppiness"], dt, foam_threshold=[t for t, _ in thresholds],
                            foam_decay_time=p["ocean.foam_decay"], foam_width=[w for _, w in thresholds])
            self.sim.request_readback()
            got = self.sim.poll_readback()  # the previous frame's request: no stall
            if got is not None:
                self._readback = got
                self.query_time = got[0]
        else:
            self._release_fft()
            self.query_time = frame.time
            if model == "gerstner":
                self.gerstner_waves()
                self.resolved_mss = oc.gerstner_moments(self._waves)["mss"]
            else:
                a, k, _ = self.sine_wave()
                self.resolved_mss = 0.5 * (k * a) ** 2
        frame.wind = wind_vector(p["ocean.wind_direction"]) * p["ocean.wind"]
        frame.water = self
        self.camera_height_water = float(self.height(self.camera_pos[0], self.camera_pos[2]))
        self.underwater = bool(self.camera_pos[1] < self.camera_height_water)

    # -- queries ---------------------------------------------------------------------------
    def fade_range(self) -> tuple[float, float]:
        """Distances from the camera [m] over which the displacement fades to flat water (the
        shaders' uFadeStart/uFadeEnd and the queries alike)."""
        extent = self.params["ocean.mesh_extent"]
        return 0.5 * extent, 0.9 * extent

    def _fade(self, x, z):
        start, end = self.fade_range()
        r = np.hypot(np.asarray(x) - self.camera_pos[0], np.asarray(z) - self.camera_pos[2])
        t = np.clip((r - start) / (end - start), 0.0, 1.0)
        return 1.0 - t * t * (3.0 - 2.0 * t)

    def displacement(self, x, z) -> np.ndarray:
        """(D_x, η, D_z) [m] of the rest points (x, z) as drawn (faded far from the camera)."""
        x = np.asarray(x, dtype=float)
        z = np.asarray(z, dtype=float)
        model = self.params["ocean.model"]
        if model == "sine":
            a, k, w = self.sine_wave()
            d = wind_vector(self.params["ocean.wind_direction"])
            eta = a * np.sin(k * (d[0] * x + d[1] * z) - w * self.time)
            out = np.stack([np.zeros_like(eta), eta, np.zeros_like(eta)], axis=-1)
        elif model == "gerstner":
            surf = oc.gerstner(x, z, self.time, self.gerstner_waves(), depth=self.params["ocean.depth"])
            out = surf.position - np.stack([x, np.zeros_like(x), z], axis=-1)
        else:
            if self._readback is None:
                out = np.zeros(x.shape + (3,))
            else:
                out = 0.0
                for size, grid in zip(self.patch_sizes(), self._readback[1]):
                    out = out + oc.sample_periodic_bilinear(grid[..., :3], size, x, z)
                out = np.broadcast_to(out, x.shape + (3,)).copy()
        return out * self._fade(x, z)[..., None]

    def height(self, x, z) -> np.ndarray:
        """Water height [m] above world points (x, z): :meth:`water` without the normal."""
        return oc.invert_horizontal_displacement(self.displacement, x, z,
                                                 self.params["ocean.query_iterations"])[2][..., 1]

    def normal(self, x, z) -> np.ndarray:
        """Unit normal of the water above world points (x, z): :meth:`water`'s normal."""
        return self.water(x, z).normal

    def water(self, x, z, iterations: int | None = None) -> oc.WaterQuery:
        """Height, displacement and unit normal of the water above world points (x, z).

        Sine and Gerstner: exact at the current time. FFT: from the last completed readback (one
        frame old, see the module docstring); flat water before the first one."""
        if iterations is None:
            iterations = self.params["ocean.query_iterations"]
        x0, z0, d, res = oc.invert_horizontal_displacement(self.displacement, x, z, iterations)
        # normal of the displaced surface by central differences around the rest point, with a
        # step well inside the shortest wave (or the finest FFT texel)
        e = self._difference_step()
        px1, px0 = self.displacement(x0 + e, z0), self.displacement(x0 - e, z0)
        pz1, pz0 = self.displacement(x0, z0 + e), self.displacement(x0, z0 - e)
        t = np.stack([2 * e + px1[..., 0] - px0[..., 0], px1[..., 1] - px0[..., 1], px1[..., 2] - px0[..., 2]], -1)
        b = np.stack([pz1[..., 0] - pz0[..., 0], pz1[..., 1] - pz0[..., 1], 2 * e + pz1[..., 2] - pz0[..., 2]], -1)
        n = np.cross(b, t)
        n /= np.linalg.norm(n, axis=-1, keepdims=True)
        return oc.WaterQuery(d[..., 1], d, n, x0, z0, res)

    def _difference_step(self) -> float:
        model = self.params["ocean.model"]
        if model == "sine":
            return min(0.05, self.params["ocean.sine_wavelength"] / 50.0)
        if model == "gerstner":
            return min(0.05, min(w.wavelength for w in self.gerstner_waves()) / 50.0)
        return min(0.05, 0.5 * min(self.patch_sizes()) / self.fft_size())

    # -- uniforms --------------------------------------------------------------------------
    def wave_uniforms(self, prog) -> dict:
        """Set the wave model's uniforms; returns its textures by sampler name (FFT)."""
        p = self.params
        cam = self.camera_pos
        model = MODELS.index(p["ocean.model"])
        fade_start, fade_end = self.fade_range()
        foam_t, foam_w = self.foam_thresholds()[0]
        prog.set_many({"uWaveModel": model, "uTime": float(self.time), "uFadeStart": fade_start,
                       "uFadeEnd": fade_end, "uFoamThreshold": foam_t, "uFoamWidth": foam_w})
        d = wind_vector(p["ocean.wind_direction"])
        if model == 0:
            a, k, w = self.sine_wave()
            phase = math.fmod(k * (d[0] * cam[0] + d[1] * cam[2]), 2.0 * math.pi)
            prog.set("uSine", (float(d[0]), float(d[1]), k, a))
            prog.set("uSinePhase", (-w, phase))
        elif model == 1:
            waves = self.gerstner_waves()
            a_rows, b_rows = [], []
            for wv in waves:
                dx, dz = np.asarray(wv.direction) / math.hypot(*wv.direction)
                k = 2.0 * math.pi / wv.wavelength
                om = float(oc.dispersion_omega(k, p["ocean.depth"]))
                ph = math.fmod(wv.phase + k * (dx * cam[0] + dz * cam[2]), 2.0 * math.pi)
                a_rows.append((dx, dz, k, wv.steepness / k))
                b_rows.append((om, ph, wv.steepness, 0.0))
            prog.set("uGerstnerCount", len(waves))
            prog.set_array("uGerstnerA", a_rows)
            prog.set_array("uGerstnerB", b_rows)
        else:
            sizes = self.patch_sizes()
            n = self.fft_size()
            rows = []
            for size in sizes + [1.0] * (4 - len(sizes)):
                # sample j of the grid sits at j·L/N, i.e. at texel centre (j + ½)/N
                uv = ((cam[0] / size + 0.5 / n) % 1.0, (cam[2] / size + 0.5 / n) % 1.0)
                rows.append((uv[0], uv[1], 1.0 / size, n / size))
            prog.set_array("uCascadeUV", rows)
            bands = self.cascade_bands + [(1.0, 2.0, 0.0)] * (4 - len(self.cascade_bands))
            prog.set_array("uCascadeBand", [(lo, hi, m, 0.0) for lo, hi, m in bands])
            weight = p["ocean.foam_amount"]
            prog.set("uFoamWeight", [weight] * 4)
            prog.set("uCascades", len(sizes))
            textures = {}
            for kind, held in (("uDisp", self.sim.disp), ("uDeriv", self.sim.deriv), ("uFoam", self.sim.foam)):
                for i in range(4):
                    textures[f"{kind}{i}"] = held[min(i, len(sizes) - 1)]
            return textures
        return {}

    def cox_munk_mss(self) -> float:
        """Cox & Munk 1954 clean-surface mean-square slope 0.003 + 5.12e-3·U."""
        return 0.003 + 5.12e-3 * self.params["ocean.wind"]

    def shading_uniforms(self, prog, frame, env) -> dict:
        """Set the shading uniforms; returns the environment cubemap by sampler name."""
        p = self.params
        subgrid = max(self.cox_munk_mss() - self.resolved_mss, 0.0) if p["ocean.subgrid_slopes"] else 0.0
        prog.set_many({"uEnvironmentLods": float(max(0, int(math.log2(env.size[0])))),
                       "uSubgridMss": subgrid, "uSeaHs": max(self.significant_height(), 1e-3)})
        if frame.main_light is not None:
            prog.set_many(frame.light_uniforms())
        else:
            prog.set_many({"uMainLightDir": (0.0, 0.7071, 0.7071), "uMainLightRadiance": (1.0, 1.0, 1.0)})
        self.apply_params(prog)
        return {"uEnvironment": env}

    def environment(self, frame):
        """The frame's environment probe without the sun disk — the main light's specular lobe
        draws the sun — or, the fallback when no effect fills the slot, a flat grey cubemap."""
        if frame.environment is not None:
            return frame.environment.cubemap(sun=False)  # the sun is the analytic glitter
        if self._flat_env is None:
            self._flat_env = self.gpu.texture_cube(self.name, "flat environment", 1, dtype="f4")
            for face in range(6):
                self._flat_env.write(face, np.array([0.3, 0.35, 0.4, 1.0], dtype="f4").tobytes())
        return self._flat_env

    LESSONS = {
        "sine": "Sine (eqs. 2.1–2.4): one wave with analytic normals — cheap, but it repeats "
                "every wavelength and a lone sine never looks like the sea.",
        "gerstner": "Gerstner (eqs. 2.5–2.8): waves drawn from the spectrum, crests sharpened by "
                    "horizontal motion; each wave's steepness s = k·A must stay ≤ 1 or the crests loop.",
        "fft": "FFT (Tessendorf): every wave of the spectrum on a grid, per cascade; choppy "
               "displacement, foam where the Jacobian folds; tiles repeat only at their size.",
    }

    def panel_notes(self) -> list[str]:
        model = self.params["ocean.model"]
        lines = [self.LESSONS[model]]
        lines.append(f"Hs {self.significant_height():.2f} m · slope variance {self.resolved_mss:.4f} "
                     f"(Cox–Munk {self.cox_munk_mss():.4f})")
        if model == "fft" and self.sim is not None:
            lines.append(f"N {self.fft_size()} × {len(self.patch_sizes())} cascades ({self.sim.path}); "
                         f"queries lag one frame (t = {self.query_time if self.query_time is not None else '—'})")
        if self._mesh.built:
            lines.append(f"mesh: {self.drawn_triangles:,} of {self.mesh_triangles:,} triangles drawn"
                         + ("; camera under water" if self.underwater else ""))
        return lines

    # -- passes ----------------------------------------------------------------------------
    def mesh(self):
        """(vertex buffer, index buffer) of the polar grid, rebuilt when its shape changes."""
        p = self.params
        return self._mesh.get((p["ocean.mesh_segments"], p["ocean.mesh_inner"], p["ocean.mesh_extent"]))

    def _make_mesh(self, key):
        verts, idx = polar_grid(*key)
        self.mesh_triangles = len(idx) // 3
        return (self.gpu.buffer(self.name, "mesh vertices", verts.tobytes()),
                self.gpu.buffer(self.name, "mesh indices", idx.tobytes()))

    def view_proj_rel(self, frame) -> np.ndarray:
        cam = frame.camera
        view = cam.view_matrix().copy()
        view[:3, 3] = 0.0  # camera-relative positions
        return cam.projection_matrix(frame.aspect) @ view

    def view_mode(self) -> int:
        """0: the camera is clearly above the water, 1: clearly below, 2: within 0.5 m of it (the
        near plane may straddle the surface: decided per pixel)."""
        margin = 0.5
        if self.camera_pos[1] > self.camera_height_water + margin:
            return 0
        if self.camera_pos[1] < self.camera_height_water - margin:
            return 1
        return 2

    def may_be_underwater(self) -> bool:
        """Whether any pixel can start under water: the camera within the waves' reach."""
        return self.view_mode() != 0

    def stage(self) -> Stage:
        """The water stage while the camera is clearly above the surface (clouds below the
        camera then cover the sea, clipped by its depth); the fog stage near or under it, so the
        sea draws after the volumes and Snell's window shows the clouds (the surface pass copies
        the image before it draws)."""
        return Stage.WATER if self.view_mode() == 0 else Stage.FOG

    def render_surface(self, frame, target) -> None:
        ctx = self.gpu.ctx
        env = self.environment(frame)
        vp = self.view_proj_rel(frame)
        near_surface = self.may_be_underwater()
        scene_copy = self._scene_copy.of(target) if near_surface else None
        target.use()
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.disable(moderngl.CULL_FACE)
        prog = self.program(SURFACE)
        textures = self.wave_uniforms(prog)
        textures.update(self.shading_uniforms(prog, frame, env))
        textures["uSceneCopy"] = scene_copy
        prog.bind_textures(textures)
        prog.set_many({"uViewProjRel": vp, "uCameraPos": tuple(frame.camera.position),
                       "uViewport": tuple(float(s) for s in target.size), "uViewMode": self.view_mode(),
                       "uInvViewProjRel": np.linalg.inv(vp)})
        vbo, ibo = self.mesh()
        vao = prog.vao([(vbo, "3f", "in_polar")], index_buffer=ibo)
        segments = self._mesh.key[0]
        per = 3 * self.mesh_triangles // segments  # indices per wedge
        wedges = visible_wedges(frame.camera, frame.aspect, segments) if self.params["ocean.mesh_cull"] else None
        if wedges is None:
            vao.render(moderngl.TRIANGLES)
            self.drawn_triangles = self.mesh_triangles
        else:
            first, count = wedges
            head = min(count, segments - first)
            vao.render(moderngl.TRIANGLES, vertices=head * per, first=first * per)
            if count > head:
                vao.render(moderngl.TRIANGLES, vertices=(count - head) * per, first=0)
            self.drawn_triangles = count * per // 3
        if frame.camera.position[1] > 0.0:
            far = self.program(FAR)
            textures = self.wave_uniforms(far)
            textures.update(self.shading_uniforms(far, frame, env))
            far.bind_textures(textures)
            far.set_many(frame.camera_uniforms())
            far.set_many({"uViewProjRel": vp, "uFarStart": 0.88 * self.params["ocean.mesh_extent"],
                          "uViewport": tuple(float(s) for s in target.size)})
            draw_fullscreen(far)
        ctx.disable(moderngl.DEPTH_TEST)

    def render_underwater(self, frame, target) -> None:
        ctx = self.gpu.ctx
        color = self._color_copy.of(target)
        env = self.environment(frame)
        prog = self.program(UNDERWATER)
        textures = self.wave_uniforms(prog)
        textures.update(self.shading_uniforms(prog, frame, env))
        prog.set_many(frame.camera_uniforms())
        prog.set("uInvViewProjRel", np.linalg.inv(self.view_proj_rel(frame)))
        depth = target.depth
        old = depth.compare_func
        depth.compare_func = ""
        prog.bind_textures({**textures, "uColor": color, "uSceneDepth": depth})
        target.use()
        ctx.disable(moderngl.DEPTH_TEST)
        draw_fullscreen(prog)
        depth.compare_func = old

    def passes(self, frame, target) -> list[Pass]:
        stage = self.stage()
        out = [Pass("ocean.surface", lambda: self.render_surface(frame, target), stage)]
        if self.may_be_underwater():
            out.append(Pass("ocean.underwater", lambda: self.render_underwater(frame, target), stage))
        return out

    def bench_passes(self, frame, target) -> list[Pass]:
        """The passes, after the FFT simulation's update (which the frame runs in update())."""
        out = self.passes(frame, target)
        if self.sim is not None:
            p = self.params
            thresholds = self.foam_thresholds()
            out.insert(0, Pass("ocean.simulate", lambda: self.sim.update(
                frame.time, p["ocean.choppiness"], frame.dt, foam_threshold=[t for t, _ in thresholds],
                foam_decay_time=p["ocean.foam_decay"], foam_width=[w for _, w in thresholds]), self.stage()))
        return out

    def release(self) -> None:
        self._release_fft()
        super().release()
        self._scene_copy.release()
        self._color_copy.release()
        self._flat_env = None

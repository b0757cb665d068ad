"""Method 4 of the planet scene, beyond the thesis: Hillaire's LUT atmosphere.

S. Hillaire, "A Scalable and Production Ready Sky and Atmosphere Rendering Technique",
EGSR 2020 — with the thesis's physical model and constants (spec/002 §1, §7;
``glsl/atmosphere/model.glsl``): a transmittance LUT, a multiple-scattering LUT (second-order
light Ψ = L_2nd / (1 − f_ms) with an isotropic phase over N² directions), a sky-view LUT and an
aerial-perspective volume over the camera frustum. The scene's composite pass includes
``glsl/atmosphere/hillaire/hillaire_lookup.glsl`` and calls ``HillaireSkyView`` (pixels no mesh
covers) and ``HillaireAerial`` (meshes): two reads each, the per-pixel pass of the paper;
``HillaireSkyRadiance``, ``HillaireAerialPerspective``, ``HillaireTransmittance`` and
``HillaireSunTransmittance`` remain for other callers (the probes, the preview).

``HillaireLuts(gpu, "planet", params)`` once; per frame ``update(model_uniforms, camera_frame)``
(``model_uniforms``: the model.glsl uniforms the scene sets for methods 1–3, as
:func:`model_uniforms` builds them) and ``bind(composite_program)`` (its six LUT samplers and
the uHillaire* uniforms). Every LUT is rebuilt only when a value it depends on changes
(Hillaire's paper builds the sky-view LUT and the volume every frame; a still camera under a
still sun needs neither again):

* transmittance and multiple scattering: the model (radii, β, H, P0), their sizes and sample
  counts, the albedo and the series switch — never the sun or the camera;
* sky view: those, the camera's altitude, the sun's elevation seen from the camera (μ_s), the
  multiple-scattering switch, its size and steps — not the camera's orientation;
* aerial perspective: those of the static LUTs, the camera (altitude, orientation, field of
  view, aspect), the sun's direction, the switch, its size, range and substeps.

G and the sun intensity are applied per pixel and never cause a rebuild. From space (above the
blend band) the lookups march the two static LUTs per pixel, so the sky view and the volume are
not built at all. ``builds`` counts each LUT's builds.

Conventions, and what differs from Hillaire's paper, are documented in the GLSL headers
(``glsl/atmosphere/hillaire/``): radiance is ``uSunIntensity`` × dimensionless integrals; the
Mie phase is applied per pixel (the sun halo as sharp as in methods 1–3); ozone off and ground
albedo 0 by default (the thesis has neither); the planet's shadow a hard test.

The near-camera source factors (``uHillaireSource*``: sunlight × σ_R and × σ_M, and σ_s Ψ_ms at
the camera, which the volume's lookup needs before its first slice) are computed here: the
sunlight exactly (:func:`app.sim.hillaire.sun_transmittance`), Ψ_ms from the multiple-scattering
LUT read back once after each build, interpolated as the GPU does.

Limits (measured in tests/**/test_hillaire*.py): the sky lookup is within 2 % of a brute-force
march's peak everywhere tested, the worst at rays grazing the ground horizon from altitude; the
volume's 32 rows blur the horizon row of the image (trilinear filtering between a column that
meets the ground and one that does not) — columns are therefore not clipped at the ground, which
keeps that row within ~2 %; llvmpipe ends any shader loop after 65 535 iterations per invocation,
so sample counts whose product exceeds that (ms_directions × ms_steps, …) are silently cut there.

Build times on llvmpipe (2 cores, paper sizes, median of 7): transmittance 2.8 ms,
multiple scattering 54 ms, sky view 15 ms, aerial perspective 4.9 ms (compute) / 36 ms
(fragment slices + GPU copy).
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import moderngl
import numpy as np

from ...gpu.programs import ProgramSpec, draw_fullscreen, fullscreen
from ...params import Param
from ...sim import hillaire as twin

GROUP = "hillaire"
SECTION = "Hillaire 2020"

TRANSMITTANCE = fullscreen("atmosphere/hillaire/transmittance_lut")
MULTISCATTERING = fullscreen("atmosphere/hillaire/multiscattering_lut")
SKYVIEW = fullscreen("atmosphere/hillaire/skyview_lut")
AERIAL_FRAGMENT = fullscreen("atmosphere/hillaire/aerial_perspective")
AERIAL_COMPUTE = ProgramSpec("atmosphere/hillaire/aerial_perspective_compute",
                             comp="atmosphere/hillaire/aerial_perspective.comp",
                             requires_compute=True)
#: a minimal composite (sky, lit ground sphere, aerial perspective): how to call the lookups
PREVIEW = fullscreen("atmosphere/hillaire/preview")
#: every program of method 4, for ``natura shaders check`` (via the scene's effect)
PROGRAMS: tuple[ProgramSpec, ...] = (TRANSMITTANCE, MULTISCATTERING, SKYVIEW, AERIAL_FRAGMENT,
                                     AERIAL_COMPUTE, PREVIEW)

#: model.glsl uniforms the transmittance and multiple-scattering LUTs depend on
STATIC_UNIFORMS = ("uBottomRadius", "uTopRadius", "uBetaRayleigh", "uBetaMieScatter", "uBetaMieExt",
                   "uHRayleigh", "uHMie", "uP0")

#: the LUT samplers bind() sets, in the order of LUT_NAMES
LUT_NAMES = ("transmittance", "multiscattering", "skyview0", "skyview1", "ap0", "ap1")
SAMPLERS = ("uHillaireTransmittanceLut", "uHillaireMultiScatteringLut",
            "uHillaireSkyViewRayleighMs", "uHillaireSkyViewMie", "uHillaireApRayleighMs",
            "uHillaireApMie")

#: the camera above the top by this fraction of the atmosphere's height: lookups fully marched
SPACE_BLEND = 0.1

#: spec/002 §7 defaults (thesis constants; radii per spec/002 §9)
BOTTOM_RADIUS = 6_360_000.0
ATMOSPHERE_HEIGHT = 60_000.0
BETA_RAYLEIGH = (5.8e-6, 13.5e-6, 33.1e-6)
BETA_MIE_SCATTER = 2.0e-5
H_RAYLEIGH = 7994.0
H_MIE = 1200.0


def params() -> list[Param]:
    """The ``hillaire.*`` parameters: LUT sizes, sample counts and switches."""
    s = SECTION

    def p(name, default, lo, hi, doc, **kw):
        return Param(f"{GROUP}.{name}", default, lo, hi, doc, section=kw.pop("section", s), **kw)

    return [
        p("transmittance_width", 256, 16, 2048, "transmittance LUT width (x_μ texels; paper 256)",
          kind="int", unit="px", section=f"{s} §4"),
        p("transmittance_height", 64, 4, 1024, "transmittance LUT height (x_r texels; paper 64)",
          kind="int", unit="px", section=f"{s} §4"),
        p("transmittance_steps", 40, 2, 2000, "samples per transmittance texel (t = d s³ midpoint)",
          kind="int", section=f"{s} §4"),
        p("ms_size", 32, 4, 256, "multiple-scattering LUT size, μ_s × h (paper 32 × 32)",
          kind="int", unit="px", section=f"{s} §5.5"),
        p("ms_directions", 64, 1, 4096, "directions of the Ψ_ms sphere integral, rounded down to "
          "N² (paper 64)", kind="int", section=f"{s} §5.5"),
        p("ms_steps", 20, 2, 500, "samples per direction of the Ψ_ms integral (paper 20)",
          kind="int", section=f"{s} §5.5"),
        Param(f"{GROUP}.multiple_scattering", True, doc="add the multiple-scattering term σ_s Ψ_ms "
              "(off: single scattering only, the thesis's integral)", kind="bool",
              section=f"{s} §5.5"),
        Param(f"{GROUP}.ms_infinite", True, doc="all orders through F_ms = 1/(1 − f_ms) "
              "(off: second order only, F_ms = 1)", kind="bool",
              section=f"{s} §5.5; Hillaire 2020 eq. 9"),
        p("ground_albedo", 0.0, 0.0, 1.0, "Lambertian ground albedo seen by Ψ_ms (0: the thesis "
          "has no ground reflection)", step=0.01, section=f"{s} §5.5; Hillaire 2020 eq. 6"),
        p("skyview_width", 192, 8, 2048, "sky-view LUT width (azimuth; paper 192)",
          kind="int", unit="px", section=f"{s} §5.3"),
        p("skyview_height", 108, 4, 2048, "sky-view LUT height (latitude, even; paper 108)",
          kind="int", step=2, unit="px", section=f"{s} §5.3"),
        p("skyview_steps", 30, 2, 2000, "samples per sky-view texel (paper 30)",
          kind="int", section=f"{s} §5.3"),
        p("ap_size", 32, 4, 512, "aerial-perspective volume width and height (froxels; paper 32)",
          kind="int", unit="px", section=f"{s} §5.4"),
        p("ap_slices", 32, 2, 512, "aerial-perspective depth slices (paper 32)",
          kind="int", section=f"{s} §5.4"),
        p("ap_range", 128_000.0, 1000.0, 2_000_000.0, "distance of the last slice; slices are "
          "quadratic in distance, the lookup marches past it", step=1000.0, unit="m",
          section=f"{s} §5.4"),
        p("ap_substeps", 2, 1, 64, "samples per aerial-perspective slice", kind="int",
          section=f"{s} §5.4"),
        p("march_steps", 32, 2, 2000, "samples of the per-pixel march used from space and past "
          "the volume's range", kind="int", section=f"{s} §6"),
    ]


DEFAULTS = {prm.short: prm.default for prm in params()}


@dataclass
class CameraFrame:
    """The camera the per-frame LUTs are built for (glsl/common/camera.glsl conventions):
    world-axis basis vectors, tan of half the vertical field of view, width / height, and
    optionally the exact altitude above the bottom sphere (else uCameraRadius − uBottomRadius,
    in double precision)."""

    right: tuple
    up: tuple
    forward: tuple
    tan_half_fov: float
    aspect: float
    height: float | None = None

    @classmethod
    def from_uniforms(cls, values: Mapping[str, Any], height: float | None = None) -> CameraFrame:
        """From camera.glsl uniform values (uCamRight, uCamUp, uCamForward, uTanHalfFov,
        uAspect)."""
        return cls(tuple(values["uCamRight"]), tuple(values["uCamUp"]),
                   tuple(values["uCamForward"]), float(values["uTanHalfFov"]),
                   float(values["uAspect"]), height)

    def uniforms(self) -> dict[str, Any]:
        return {"uCamRight": tuple(map(float, self.right)), "uCamUp": tuple(map(float, self.up)),
                "uCamForward": tuple(map(float, self.forward)),
                "uTanHalfFov": float(self.tan_half_fov),
                "uAspect": float(self.aspect), "uCameraPos": (0.0, 0.0, 0.0)}


def model_uniforms(altitude: float = 2.0, sun_elevation_deg: float = 90.0,
                   sun_azimuth_deg: float = 0.0, up=(0.0, 1.0, 0.0),
                   **overrides) -> dict[str, Any]:
    """model.glsl uniform values with the spec/002 §7 constants for a camera at ``altitude``
    metres above the bottom sphere (the planet centre straight below along ``up``) and the sun
    at the given elevation and azimuth (0° = −z, 90° = +x, as app.sim.camera's yaw).
    ``overrides`` replace values by uniform name (e.g. ``uMieG=0.9``)."""
    up = np.asarray(up, dtype=float)
    up = up / np.linalg.norm(up)
    top = overrides.get("uTopRadius", BOTTOM_RADIUS + ATMOSPHERE_HEIGHT)
    bottom = overrides.get("uBottomRadius", BOTTOM_RADIUS)
    radius = bottom + float(altitude)
    el, az = math.radians(sun_elevation_deg), math.radians(sun_azimuth_deg)
    # a horizontal frame around `up` (matches the world axes for up = +y)
    ref = np.array([0.0, 0.0, -1.0]) if abs(up[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    north = ref - up * (ref @ up)
    north /= np.linalg.norm(north)
    east = np.cross(north, up)
    sun = up * math.sin(el) + math.cos(el) * (north * math.cos(az) + east * math.sin(az))
    beta_m = BETA_MIE_SCATTER
    values = {
        "uEarthCenter": tuple(float(v) for v in -up * radius),
        "uCameraRadius": radius,
        "uBottomRadius": bottom,
        "uTopRadius": top,
        "uBetaRayleigh": BETA_RAYLEIGH,
        "uBetaMieScatter": (beta_m,) * 3,
        "uBetaMieExt": (1.1 * beta_m,) * 3,
        "uHRayleigh": H_RAYLEIGH,
        "uHMie": H_MIE,
        "uP0": 1.0,
        "uMieG": 0.76,
        "uSunIntensity": 30.0,
        "uSunDir": tuple(float(v) for v in sun / np.linalg.norm(sun)),
        "uOzoneAbsorption": (0.0, 0.0, 0.0),
    }
    values.update(overrides)
    return values


def _freeze(value: Any):
    if isinstance(value, np.ndarray):
        return tuple(float(v) for v in value.ravel())
    if isinstance(value, (list, tuple)):
        return tuple(float(v) for v in value)
    return float(value)


class HillaireLuts:
    """The four LUTs of method 4, their passes, and how a composite program reads them.

    ``params``: anything indexable by ``"hillaire.<name>"`` (a ParamSet, a dict); missing names
    take the defaults of :func:`params`. ``use_compute``: the compute path for the volume
    (default: when the context has GL ≥ 4.3), else fragment slices copied on the GPU.
    ``measure``: time each build with ``ctx.finish()`` on both sides (into ``timings``, seconds).
    """

    programs = PROGRAMS
    group = GROUP

    @staticmethod
    def python_params() -> list[Param]:
        return params()

    def __init__(self, gpu, owner: str, params: Mapping[str, Any] | None = None,
                 use_compute: bool | None = None, measure: bool = False):
        self.gpu = gpu
        self.ctx: moderngl.Context = gpu.ctx
        self.owner = owner
        self.params = params
        self.use_compute = gpu.caps.compute if use_compute is None else bool(use_compute)
        self.measure = measure
        self.builds = {"transmittance": 0, "multiscattering": 0, "skyview": 0,
                       "aerial_perspective": 0}
        #: what the sky view and the volume were last built for (None: to be built)
        self._skyview_key: tuple | None = None
        self._ap_key: tuple | None = None
        self._ms_table: np.ndarray | None = None   # the multiple-scattering LUT, read back
        self._source_key: tuple | None = None       # what _source was computed for
        self._source = {"uHillaireSourceRayleigh": (0.0, 0.0, 0.0),
                        "uHillaireSourceMie": (0.0, 0.0, 0.0),
                        "uHillaireSourceMultiple": (0.0, 0.0, 0.0)}
        self.timings: dict[str, float] = {}
        self._textures: dict[str, Any] = {}
        self._fbos: dict[str, Any] = {}
        self._static_key = None
        self._uniforms: dict[str, Any] = {}
        self._camera: CameraFrame | None = None
        self._height = 0.0
        self._space_weight = 0.0
        self._pbo = None
        #: rows of the fragment path's 2D target (None: the context's texture-size limit)
        self.fragment_rows: int | None = None

    def value(self, name: str):
        key = f"{GROUP}.{name}"
        if self.params is not None and key in self.params:
            return self.params[key]
        return DEFAULTS[name]

    def sizes(self) -> dict[str, tuple[int, ...]]:
        v = self.value
        sky_h = int(v("skyview_height"))
        sky_h += sky_h % 2  # each half of the sky-view LUT needs the same number of rows
        return {
            "transmittance": (int(v("transmittance_width")), int(v("transmittance_height"))),
            "multiscattering": (int(v("ms_size")), int(v("ms_size"))),
            "skyview": (int(v("skyview_width")), max(sky_h, 4)),
            "aerial_perspective": (int(v("ap_size")), int(v("ap_size")), int(v("ap_slices"))),
        }

    def ms_directions(self) -> int:
        """N of the N × N direction grid of the Ψ_ms integral."""
        return max(1, math.isqrt(int(self.value("ms_directions"))))

    def _texture(self, name: str, size: tuple[int, ...]):
        tex = self._textures.get(name)
        if tex is not None and tuple(tex.size) == tuple(size):
            return tex
        if tex is not None:
            self.gpu.free(tex)
        zeros = bytes(16 * math.prod(size))  # defined contents even before a pass writes them
        if len(size) == 3:
            tex = self.gpu.texture3d(self.owner, f"hillaire {name}", size, 4, data=zeros,
                                     dtype="f4", repeat=False)
        else:
            tex = self.gpu.texture(self.owner, f"hillaire {name}", size, 4, data=zeros, dtype="f4")
        self._textures[name] = tex
        return tex

    def _framebuffer(self, name: str, textures: list):
        fbo = self._fbos.get(name)
        if fbo is not None and [a.glo for a in fbo.color_attachments] == [t.glo for t in textures]:
            return fbo
        if fbo is not None:
            fbo.release()
        fbo = self.ctx.framebuffer(color_attachments=textures)
        self._fbos[name] = fbo
        return fbo

    def texture(self, name: str):
        """The LUT texture ``transmittance``, ``multiscattering``, ``skyview0``/``skyview1``
        or ``ap0``/``ap1`` (None before it is first built)."""
        return self._textures.get(name)

    def _program(self, spec: ProgramSpec):
        return self.gpu.program(self.owner, spec)

    def _common_uniforms(self, prog) -> None:
        prog.set_many(self._uniforms)
        prog.set("uHillaireCameraHeight", float(self._height))
        prog.set("uHillaireMsScale", 1.0 if self.value("multiple_scattering") else 0.0)

    def _static_textures(self) -> dict:
        return {"uHillaireTransmittanceLut": self._textures["transmittance"],
                "uHillaireMultiScatteringLut": self._textures.get("multiscattering")}

    def _draw(self, prog, fbo, size) -> None:
        with self.ctx.scope(fbo, enable_only=moderngl.NOTHING):
            fbo.viewport = (0, 0, int(size[0]), int(size[1]))
            draw_fullscreen(prog)

    def _timed(self, name: str, fn) -> None:
        if self.measure:
            self.ctx.finish()
            t0 = time.perf_counter()
            fn()
            self.ctx.finish()
            self.timings[name] = time.perf_counter() - t0
        else:
            fn()
        self.builds[name] += 1

    def build_transmittance(self) -> None:
        size = self.sizes()["transmittance"]
        tex = self._texture("transmittance", size)
        fbo = self._framebuffer("transmittance", [tex])
        prog = self._program(TRANSMITTANCE)

        def run():
            self._common_uniforms(prog)
            prog.set("uHillaireTargetSize", tuple(float(s) for s in size))
            prog.set("uHillaireTransmittanceSteps", int(self.value("transmittance_steps")))
            self._draw(prog, fbo, size)

        self._timed("transmittance", run)

    def build_multiscattering(self) -> None:
        size = self.sizes()["multiscattering"]
        tex = self._texture("multiscattering", size)
        fbo = self._framebuffer("multiscattering", [tex])
        prog = self._program(MULTISCATTERING)

        def run():
            self._common_uniforms(prog)
            prog.bind_textures({"uHillaireTransmittanceLut": self._textures["transmittance"]})
            prog.set_many({"uHillaireTargetSize": tuple(float(s) for s in size),
                           "uHillaireMsDirections": self.ms_directions(),
                           "uHillaireMsSteps": int(self.value("ms_steps")),
                           "uHillaireGroundAlbedo": float(self.value("ground_albedo")),
                           "uHillaireMsInfinite": 1.0 if self.value("ms_infinite") else 0.0})
            self._draw(prog, fbo, size)

        self._timed("multiscattering", run)

    def build_skyview(self) -> None:
        size = self.sizes()["skyview"]
        t0 = self._texture("skyview0", size)
        t1 = self._texture("skyview1", size)
        fbo = self._framebuffer("skyview", [t0, t1])
        prog = self._program(SKYVIEW)

        def run():
            self._common_uniforms(prog)
            prog.bind_textures(self._static_textures())
            prog.set("uHillaireTargetSize", tuple(float(s) for s in size))
            prog.set("uHillaireSkyViewSteps", int(self.value("skyview_steps")))
            self._draw(prog, fbo, size)

        self._timed("skyview", run)

    def _ap_uniforms(self, prog, size) -> None:
        self._common_uniforms(prog)
        prog.set_many(self._camera.uniforms())
        prog.bind_textures(self._static_textures())
        prog.set_many({"uHillaireApSize": tuple(int(s) for s in size),
                       "uHillaireApRange": float(self.value("ap_range")),
                       "uHillaireApSubsteps": int(self.value("ap_substeps"))})

    def build_aerial_perspective(self) -> None:
        size = self.sizes()["aerial_perspective"]
        v0 = self._texture("ap0", size)
        v1 = self._texture("ap1", size)
        if self.use_compute:
            prog = self._program(AERIAL_COMPUTE)

            def run():
                self._ap_uniforms(prog, size)
                v0.bind_to_image(0, read=False, write=True)
                v1.bind_to_image(1, read=False, write=True)
                prog.program.run((size[0] + 7) // 8, (size[1] + 7) // 8, 1)
                self.ctx.memory_barrier()
        else:
            # slices stacked in rows of a 2D target (as many per pass as the size limit allows),
            # copied into the volume through a pixel buffer without leaving the GPU
            w, h, d = size
            max_rows = self.fragment_rows or int(self.ctx.info.get("GL_MAX_TEXTURE_SIZE", 8192))
            chunk = max(1, min(d, max_rows // h))
            flat = (w, h * chunk)
            s0 = self._texture("ap_slices0", flat)
            s1 = self._texture("ap_slices1", flat)
            fbo = self._framebuffer("ap", [s0, s1])
            prog = self._program(AERIAL_FRAGMENT)
            nbytes = w * h * chunk * 16
            if self._pbo is None or self._pbo.size != nbytes:
                if self._pbo is not None:
                    self.gpu.free(self._pbo)
                self._pbo = self.gpu.buffer(self.owner, "hillaire ap copy", bytes(nbytes))

            def run():
                self._ap_uniforms(prog, size)
                for first in range(0, d, chunk):
                    count = min(chunk, d - first)
                    prog.set("uHillaireApFirstSlice", first)
                    self._draw(prog, fbo, (w, h * count))
                    for attachment, volume in ((0, v0), (1, v1)):
                        fbo.read_into(self._pbo, viewport=(0, 0, w, h * count), components=4,
                                      attachment=attachment, dtype="f4")
                        volume.write(self._pbo, viewport=(0, 0, first, w, h, count))

        self._timed("aerial_perspective", run)

    def _static(self) -> tuple:
        u = self._uniforms
        missing = [k for k in STATIC_UNIFORMS if k not in u]
        if missing:
            raise KeyError(f"HillaireLuts.update: model uniforms missing: {', '.join(missing)}")
        v = self.value
        return (tuple(_freeze(u[k]) for k in STATIC_UNIFORMS),
                _freeze(u.get("uOzoneAbsorption", (0.0, 0.0, 0.0))), self.sizes()["transmittance"],
                self.sizes()["multiscattering"], int(v("transmittance_steps")),
                self.ms_directions(), int(v("ms_steps")), float(v("ground_albedo")),
                bool(v("ms_infinite")))

    def update(self, uniforms: Mapping[str, Any],
               camera_frame: CameraFrame | Mapping[str, Any]) -> None:
        """Bring the LUTs up to date for this frame: each one is rebuilt only when a value it
        depends on changed (see the module doc); the sky view and the volume not at all while
        the camera is so far above the atmosphere that the lookups only march.

        ``uniforms``: model.glsl uniform values (see the module doc). ``camera_frame``: a
        :class:`CameraFrame`, or a mapping of camera.glsl uniform values."""
        self._uniforms = {k: v for k, v in uniforms.items()}
        frame = (camera_frame if isinstance(camera_frame, CameraFrame)
                 else CameraFrame.from_uniforms(camera_frame))
        self._camera = frame
        bottom = float(self._uniforms["uBottomRadius"])
        top = float(self._uniforms["uTopRadius"])
        if frame.height is not None:
            self._height = float(frame.height)
        else:
            self._height = float(self._uniforms["uCameraRadius"]) - bottom
        atm = top - bottom
        self._space_weight = min(max((self._height - atm) / (SPACE_BLEND * atm), 0.0), 1.0)
        key = self._static()
        if key != self._static_key:
            self.build_transmittance()
            self.build_multiscattering()
            self._ms_table = self.read("multiscattering")  # once per build: the camera's source
            self._static_key = key
            self._skyview_key = self._ap_key = None
        up = -np.asarray(_freeze(self._uniforms["uEarthCenter"]), dtype=float)
        up /= max(float(np.linalg.norm(up)), 1e-300)
        sun = np.asarray(_freeze(self._uniforms["uSunDir"]), dtype=float)
        mu_s = float(np.clip(sun @ up, -1.0, 1.0))
        ms_on = bool(self.value("multiple_scattering"))
        source_key = (self._static_key, self._height, mu_s, ms_on)
        if source_key != self._source_key:   # a numpy march: only when its inputs change
            self._source = self._camera_source(mu_s, ms_on)
            self._source_key = source_key
        sizes = self.sizes()
        if self._space_weight < 1.0:
            sky_key = (self._height, mu_s, ms_on, sizes["skyview"],
                       int(self.value("skyview_steps")))
            if sky_key != self._skyview_key:
                self.build_skyview()
                self._skyview_key = sky_key
            ap_key = (self._height, tuple(up), tuple(sun), ms_on, frame.right, frame.up,
                      frame.forward, float(frame.tan_half_fov), float(frame.aspect),
                      sizes["aerial_perspective"], float(self.value("ap_range")),
                      int(self.value("ap_substeps")), self.use_compute, self.fragment_rows)
            if ap_key != self._ap_key:
                self.build_aerial_perspective()
                self._ap_key = ap_key
        else:  # the lookups only march; keep valid (empty) textures bound
            for name, size in (("skyview0", sizes["skyview"]), ("skyview1", sizes["skyview"]),
                               ("ap0", sizes["aerial_perspective"]),
                               ("ap1", sizes["aerial_perspective"])):
                self._texture(name, size)
            self._skyview_key = self._ap_key = None

    def rebuild_frame_luts(self) -> None:
        """Rebuild the sky view and the volume for the camera and sun of the last
        :meth:`update` (what the paper does every frame; ``natura bench`` times this)."""
        if self._camera is None:
            raise RuntimeError("HillaireLuts.rebuild_frame_luts before update(): no camera yet")
        if self._space_weight < 1.0:
            self.build_skyview()
            self.build_aerial_perspective()

    def _camera_source(self, mu_s: float, ms_on: bool) -> dict:
        """The volume lookup's near-camera factors per unit sun intensity (uHillaireSource*):
        T_sun σ_R, T_sun σ^s_M and σ_s Ψ_ms at the camera (zero above the atmosphere)."""
        u = self._uniforms
        m = twin.Model.from_uniforms(u)
        h = self._height
        zero = (0.0, 0.0, 0.0)
        if h >= m.height:
            return {"uHillaireSourceRayleigh": zero, "uHillaireSourceMie": zero,
                    "uHillaireSourceMultiple": zero}
        rho_r, rho_m = (float(v) for v in m.density(h))
        scat_r = np.asarray(m.beta_rayleigh) * rho_r
        scat_m = np.asarray(m.beta_mie_scatter) * rho_m
        sun = np.asarray(twin.sun_transmittance(m, h, mu_s), dtype=float).reshape(3)
        psi = np.zeros(3) if not ms_on or self._ms_table is None else \
            twin.multiple_scattering_lookup(self._ms_table, m, h, mu_s)

        def vec(v):
            return tuple(float(x) for x in v)

        return {"uHillaireSourceRayleigh": vec(sun * scat_r),
                "uHillaireSourceMie": vec(sun * scat_m),
                "uHillaireSourceMultiple": vec((scat_r + scat_m) * psi)}

    def march_mode(self, far_meshes: bool = False) -> int:
        """HILLAIRE_MARCH for a composite program (hillaire_lookup.glsl): 2 above the blend band
        (the per-pixel march alone), 1 within it or when a mesh may lie past 90 % of the
        volume's range (``far_meshes``: both, chosen per pixel), else 0 (the lookups alone)."""
        if self._space_weight >= 1.0:
            return 2
        return 1 if self._space_weight > 0.0 or far_meshes else 0

    def textures(self) -> dict:
        """The six LUTs by the sampler names hillaire_lookup.glsl reads."""
        if self._camera is None:
            raise RuntimeError("HillaireLuts.textures before update(): no LUTs yet")
        return {sampler: self._textures[name] for name, sampler in zip(LUT_NAMES, SAMPLERS)}

    def lookup_uniforms(self) -> dict:
        """Every uHillaire* uniform hillaire_lookup.glsl reads besides the samplers."""
        r = float(self._uniforms.get("uBottomRadius", BOTTOM_RADIUS))
        h = max(float(self._height), 0.0)
        horizon = math.sqrt(h * (2.0 * r + h))   # hillaire_common.glsl's, in double precision
        return {"uHillaireCameraHeight": float(self._height),
                "uHillaireGroundAngle": math.atan2(r, horizon),
                "uHillaireHorizonCos": -horizon / (r + h),
                "uHillaireMsScale": 1.0 if self.value("multiple_scattering") else 0.0,
                "uHillaireApRange": float(self.value("ap_range")),
                "uHillaireSpaceWeight": float(self._space_weight),
                "uHillaireMarchSteps": int(self.value("march_steps")), **self._source}

    def bind(self, prog) -> None:
        """For a program that reads only the LUTs: bind :meth:`textures` (units assigned by
        ``Program.bind_textures``) and set :meth:`lookup_uniforms`. A program with samplers of
        its own merges :meth:`textures` into its own bind_textures call instead."""
        prog.bind_textures(self.textures())
        prog.set_many(self.lookup_uniforms())

    def read(self, name: str) -> np.ndarray:
        """A LUT as float32 numpy: (h, w, 4) for 2D (row 0 = texel row 0), (d, h, w, 4) for 3D."""
        tex = self._textures[name]
        data = np.frombuffer(tex.read(), dtype=np.float32)
        return data.reshape(*tuple(reversed(tex.size)), 4)

    def release(self) -> None:
        for fbo in self._fbos.values():
            fbo.release()
        self._fbos.clear()
        for tex in self._textures.values():
            self.gpu.free(tex)
        self._textures.clear()
        if self._pbo is not None:
            self.gpu.free(self._pbo)
            self._pbo = None
        self._static_key = self._skyview_key = self._ap_key = self._source_key = None

"""The ocean's parameters: wave model, sea state (spectrum, wind, fetch, depth), FFT size and
cascades, foam, the sine and Gerstner models, the surface mesh and the queries."""

from __future__ import annotations

import numpy as np

from ...params import Param
from ...sim import ocean as oc
from ...sim.maths import compass_xz

MODELS = ("sine", "gerstner", "fft")
FFT_SIZES = ("64", "128", "256", "512")


def wind_vector(direction_deg: float) -> np.ndarray:
    """Unit (x, z) vector the wind blows toward (the compass convention of app.sim.maths)."""
    return compass_xz(direction_deg)


def ocean_params() -> list[Param]:
    s1, s2, s3 = "spec/000 §1.1", "spec/000 §1.2", "spec/000 §1.3"
    return [
        Param("ocean.model", "fft", doc="wave model: sine (spec/000 §1.1(a)), gerstner "
              "(spec/000 §1.1(c)) or fft (Tessendorf cascades)", kind="choice", choices=MODELS,
              section=s1),
        Param("ocean.spectrum", "jonswap", doc="sea spectrum for the FFT and the Gerstner set: "
              "Phillips, Pierson–Moskowitz or JONSWAP (with TMA in finite depth)", kind="choice",
              choices=oc.SPECTRA, section=s1 + "(d)"),
        Param("ocean.wind", 10.0, 0.0, 40.0, "wind speed at 19.5 m (10 m for Phillips)", step=0.1,
              unit="m/s", section=s1 + "(d)"),
        Param("ocean.wind_direction", 90.0, 0.0, 360.0, "direction the wind blows toward: 0 = "
              "north (−z), 90 = east (+x)", step=1.0, unit="°", section=s1 + "(d)"),
        Param("ocean.fetch", 100.0, 1.0, 2000.0, "JONSWAP fetch: distance the wind has blown over "
              "water", step=1.0, unit="km", section=s1 + "(d)"),
        Param("ocean.gamma", 3.3, 1.0, 7.0, "JONSWAP peak enhancement γ", step=0.1,
              section=s1 + "(d)"),
        Param("ocean.depth", 1000.0, 1.0, 10000.0, "water depth d: dispersion ω² = g·k·tanh(k·d) "
              "and the TMA correction", step=1.0, unit="m", section=s1 + "(d)"),
        Param("ocean.short_wave_fade", 0.01, 0.0, 1.0, "Tessendorf's small-wave suppression length "
              "ℓ: spectrum × exp(−(k·ℓ)²)", step=0.001, unit="m", section=s1 + "(d)"),
        Param("ocean.choppiness", 1.0, 0.0, 4.0, "choppiness λ: horizontal displacement x + λ·D "
              "(crests sharpen; the surface folds where the Jacobian < 0)", step=0.05,
              section=s1 + "(d)"),
        Param("ocean.fft_size", "256", doc="FFT grid N per cascade", kind="choice",
              choices=FFT_SIZES, section=s1 + "(e)"),
        Param("ocean.cascades", 3, 1, 4, "number of cascades (non-overlapping wavenumber bands)",
              kind="int", section=s1 + "(e)"),
        Param("ocean.patch_sizes", (250.0, 17.0, 5.0, 1.5), 0.1, 5000.0, "tile size L of each "
              "cascade, strictly decreasing (the upstream's 250 / 17 / 5 m)", kind="vec4",
              step=0.1, unit="m", section=s1 + "(e)"),
        Param("ocean.simulation", "view", doc="full: the thesis — every cascade on an "
              "ocean.fft_size grid, simulated every frame; view: what the view resolves — each "
              "cascade's grid from the screen footprint of its wavelengths (at most "
              "ocean.fft_size), and cascades whose waves change slowly simulated a snapshot "
              "ahead and interpolated (ocean.refresh_tolerance) instead of every frame",
              kind="choice", choices=("view", "full"), section=s1 + "(e)"),
        Param("ocean.view_texel", 1.0, 0.25, 8.0, "view: the largest texel of a cascade's grid, "
              "in smallest pixel footprints on the water (1: no texel is magnified anywhere on "
              "screen; 2: up to twice, on the nearest rows)", step=0.25, section=s1 + "(e)"),
        Param("ocean.view_samples", 4.0, 1.0, 16.0, "view: texels per shortest wave of a "
              "cascade's band beyond which a finer grid adds nothing (the grid is otherwise as "
              "fine as the smallest pixel footprint on the water)", step=0.5,
              section=s1 + "(e)"),
        Param("ocean.refresh_tolerance", 0.03, 0.0, 0.5, "view: rms slope error a slow "
              "cascade's interpolation between snapshots may leave, as a fraction of the sea's "
              "rms slope; sets how far apart its snapshots are (0: every cascade every frame)",
              step=0.005, section=s1 + "(e)"),
        Param("ocean.fft_path", "auto", doc="GPU FFT path: compute shaders (GL 4.3), fragment "
              "passes (GL 3.3) or auto (compute on a GPU that has it; fragment on software "
              "renderers, where it is faster)", kind="choice",
              choices=("auto", "compute", "fragment"), section=s1 + "(d)"),
        Param("ocean.seed", 0, 0, 1_000_000, "random seed of the wave amplitudes and phases",
              kind="int"),
        Param("ocean.foam_mode", "whitecaps", doc="whitecaps: foam thresholds set per cascade so "
              "foam covers Monahan & O'Muircheartaigh's fraction of the sea for the wind (beyond "
              "the thesis); jacobian: the upstream's fixed threshold (ocean.foam_threshold)",
              kind="choice", choices=("whitecaps", "jacobian"), section=s2),
        Param("ocean.foam_threshold", 0.5, 0.01, 1.0, "jacobian mode: foam appears where the "
              "Jacobian drops below this", step=0.01, section=s2),
        Param("ocean.foam_decay", 2.0, 0.05, 30.0, "foam fades as e^(−t/τ): τ", step=0.05, unit="s",
              section=s2),
        Param("ocean.foam_amount", 1.0, 0.0, 4.0, "foam strength", step=0.05, section=s2),
        Param("ocean.sine_amplitude", 0.5, 0.0, 10.0, "sine wave amplitude A (spec/000 eq. 2.1)",
              step=0.01, unit="m", section=s1 + "(a)"),
        Param("ocean.sine_wavelength", 20.0, 0.1, 500.0, "sine wavelength 2π/k (ω from the "
              "dispersion relation)", step=0.1, unit="m", section=s1 + "(a)"),
        Param("ocean.gerstner_waves", 16, 1, 64, "number of Gerstner waves, drawn from the "
              "spectrum (same Hs and peak period as the FFT sea)", kind="int", section=s1 + "(c)"),
        Param("ocean.gerstner_steepness", 1.0, 0.0, 20.0, "scales every Gerstner wave's "
              "amplitude, so its steepness s = k·A; each wave must keep s ≤ 1", step=0.05,
              section=s1 + "(c)"),
        Param("ocean.subgrid_slopes", True, doc="beyond the thesis: the glitter lobe gets the "
              "slope variance the grid cannot hold (Cox–Munk minus what is resolved)", kind="bool",
              section=s2),
        Param("ocean.mesh_segments", 256, 32, 1024, "angular segments of the polar surface mesh "
              "(its density)", kind="int", section=s1),
        Param("ocean.mesh_inner", 0.25, 0.01, 10.0, "radius of the mesh's first ring", step=0.01,
              unit="m", section=s1),
        Param("ocean.mesh_extent", 3000.0, 50.0, 50000.0, "radius of the surface mesh; beyond it "
              "the sea is an analytic plane to the horizon", step=10.0, unit="m", section=s1),
        Param("ocean.shading", "auto", doc="surface pass: deferred (the mesh and the far "
              "plane write their shading inputs, one pass shades the covered pixels once; the far "
              "plane only over its band of rows), forward (each shades as it draws: pixels of "
              "tiny far triangles are shaded several times over on software rasterisers) or "
              "auto (deferred on a software renderer, which shades 4×4 blocks; forward on a GPU, "
              "which then skips writing and reading three RGBA32F targets)",
              kind="choice", choices=("auto", "deferred", "forward"), section=s1),
        Param("ocean.wake_stride", 3, 1, 4, "deferred shading: a floating object's wake foam "
              "is evaluated once per block of this many pixels a side and read back filtered (1: "
              "every pixel, as the forward path does; its loop over the trail's samples is most "
              "of the shading's cost on a software renderer: at 640x360 the map costs about "
              "half as much at 3 as at 2, and its foam's mean error is about 1 % of the per-pixel "
              "wake's foam: tests/gl/test_maritime.py)", kind="int",
              section="spec/000 §4"),
        Param("ocean.mesh_aspect", 8.0, 0.0, 64.0, "far cells of the surface mesh are stretched "
              "toward the horizon so that on screen each is 1/this as tall as it is wide (the "
              "view foreshortens them; 0: square cells everywhere, as in the thesis, most of "
              "them slivers far below a pixel tall)", step=0.5, section=s1),
        Param("ocean.mesh_cull", True, doc="draw only the wedges of the surface mesh the camera "
              "can see", kind="bool", section=s1),
        Param("ocean.query_iterations", 3, 0, 10, "corrections of the water-height inversion (the "
              "upstream's 3)", kind="int", section=s3),
    ]

"""The sea state the ocean effect draws: the chosen wave model's parameters (the sine wave, the
Gerstner set drawn from the spectrum, the FFT cascades and their GPU simulation), with what is
derived from them (Hs, the resolved slope variance, the cascades' wavenumber bands)."""

from __future__ import annotations

import math

from ...errors import ParamError
from ...gpu.cache import memoised
from ...sim import ocean as oc
from .params import wind_vector


def _wave_set(params: oc.SpectrumParams, count: int, seed: int,
              steepness: float) -> tuple[oc.GerstnerWave, ...]:
    """The Gerstner set of a sea state (:func:`app.sim.ocean.gerstner_waves_from_spectrum`),
    as a tuple of frozen waves: what :func:`memoised` shares between sessions."""
    return tuple(oc.gerstner_waves_from_spectrum(params, count, seed=seed,
                                                 steepness_scale=steepness))


def _shared_cascades(*args) -> tuple:
    """:func:`app.sim.ocean.cascade_arrays` shared by every session of the process (read-only
    arrays): every ocean session of a test module or a bench builds the same few seas."""
    return memoised(oc.cascade_arrays, *args)


class SeaState:
    """Mixin of :class:`~app.effects.ocean.Ocean`: the sea its parameters describe."""

    #: (speed m/s, direction °) of the frame's ``wind`` slot when an effect before the ocean
    #: filled it (the scene's one wind); None: the ocean's own parameters
    frame_wind: tuple[float, float] | None = None

    def wind_speed(self) -> float:
        """Wind speed [m/s] the sea is built on: the frame's wind, else ``ocean.wind``."""
        return self.frame_wind[0] if self.frame_wind is not None else self.params["ocean.wind"]

    def wind_direction(self) -> float:
        """Direction [°] the wind blows toward (0 = north, −z; 90 = east, +x): the frame's wind,
        else ``ocean.wind_direction``."""
        if self.frame_wind is not None:
            return self.frame_wind[1]
        return self.params["ocean.wind_direction"]

    def spectrum_params(self) -> oc.SpectrumParams:
        p = self.params
        d = wind_vector(self.wind_direction())
        return oc.SpectrumParams(kind=p["ocean.spectrum"], wind_speed=self.wind_speed(),
                                 wind_direction=math.atan2(d[1], d[0]),
                                 fetch=p["ocean.fetch"] * 1000.0,
                                 gamma=p["ocean.gamma"], depth=p["ocean.depth"],
                                 short_wave_fade=p["ocean.short_wave_fade"])

    def patch_sizes(self) -> list[float]:
        return [float(s) for s in self.params["ocean.patch_sizes"][: self.params["ocean.cascades"]]]

    def fft_size(self) -> int:
        return int(self.params["ocean.fft_size"])

    def gerstner_waves(self) -> list[oc.GerstnerWave]:
        """The Gerstner set drawn from the spectrum, redrawn when the sea state changes."""
        p = self.params
        return self._waves.get((self.spectrum_params(), p["ocean.gerstner_waves"],
                                p["ocean.gerstner_steepness"], p["ocean.seed"]))

    def _draw_waves(self, key) -> list[oc.GerstnerWave]:
        # a pure function of the key, drawn once per process (the polar spectrum it integrates
        # is ~0.1 s a draw; each session of a test module draws the same few sets)
        waves = list(memoised(_wave_set, key[0], key[1], key[3], key[2]))
        worst = max(range(len(waves)), key=lambda i: waves[i].steepness)
        if waves[worst].steepness > 1.0:
            limit = key[2] / waves[worst].steepness
            raise ParamError(
                f"ocean.gerstner_steepness={key[2]:g} makes wave {worst} "
                f"({waves[worst].wavelength:.3g} m) "
                f"reach steepness s = {waves[worst].steepness:.3g}: allowed 0 ≤ s ≤ 1 per wave "
                f"(loops at the crests), so at most {limit:.3g} for this sea")
        oc.check_gerstner_steepness(waves)
        return waves

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
        key = (self.spectrum_params(), self.fft_size(), tuple(self.patch_sizes()),
               self.params["ocean.seed"])
        if self.sim is not None and self._sim_path != path:
            self._release_fft()
        if key == self._sim_key:
            return
        ref = oc.FFTOcean(key[0], n=key[1], patch_sizes=key[2], choppiness=1.0, seed=key[3],
                          build=_shared_cascades)
        if self.sim is None:
            from ...gpu.fft import choose_compute
            from .fft import GpuOceanSim

            # auto: llvmpipe runs the fragment path faster (evolve and finalize as image
            # stores cost it 2–3×: 79 against 98 ms per update at 256 × 3)
            use_compute = choose_compute(self.gpu.caps, path, "ocean.fft_path")
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

    def _release_fft(self) -> None:
        if self.sim is not None:
            self.sim.release()
            self.sim = None
            self._sim_key = None
            self._fft_ref = None
            self._readback = None
            self._fft_hs = 0.0

    def cox_munk_mss(self) -> float:
        """Cox & Munk 1954 clean-surface mean-square slope 0.003 + 5.12e-3·U."""
        return 0.003 + 5.12e-3 * self.wind_speed()

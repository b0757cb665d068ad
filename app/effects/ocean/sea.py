"""The sea state the ocean effect draws: the chosen wave model's parameters (the sine wave, the
Gerstner set drawn from the spectrum, the FFT cascades and their GPU simulation), with what is
derived from them (Hs, the resolved slope variance, the cascades' wavenumber bands)."""

from __future__ import annotations

import math

from ...errors import ParamError
from ...gpu.cache import MEMO, memoised
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
        self._fft_ref = ref
        self._sim_key = key
        self._sim_sizes = []  # the view chooses them (fit_view), then the GPU gets the sea
        self._fft_hs = 4.0 * math.sqrt(sum(c.moments()[0] for c in ref.cascades))
        self._readback = None
        self.query_time = None  # flat water until the new sea is read back

    def fit_view(self, frame) -> None:
        """The FFT sea's grid per cascade and which cascades are slow, for this frame's view
        (``ocean.simulation``): full — every cascade at ``ocean.fft_size``, every frame; view —
        each cascade's N from the smallest pixel footprint on the water
        (:func:`app.sim.ocean.view_cascade_size`; the spectrum cropped, never redrawn:
        :func:`app.sim.ocean.crop_cascade`) and, for the cascades whose interpolation between
        snapshots a period of at least three frames apart stays within
        ``ocean.refresh_tolerance`` of the sea's rms slope, that period
        (:func:`app.sim.ocean.refresh_period`)."""
        p = self.params
        ref = self._fft_ref
        n_max = self.fft_size()
        full = p["ocean.simulation"] == "full"
        if full:
            sizes = [n_max] * len(ref.cascades)
        else:
            crest = 0.5 * (self._fft_hs or 0.0)
            clearance = float(frame.camera.position[1]) - crest
            self.footprint = oc.nearest_water_footprint(frame.camera, frame.aspect,
                                                        int(frame.size[1]), clearance)
            old = self._sim_sizes or [None] * len(ref.cascades)
            texel = self.footprint * p["ocean.view_texel"]
            sizes = [oc.view_cascade_size(c.patch_size, c.band[1], texel, n_max,
                                          p["ocean.view_samples"], current=cur)
                     for c, cur in zip(ref.cascades, old)]
        if sizes != self._sim_sizes:
            cascades = [oc.crop_cascade(c, n) for c, n in zip(ref.cascades, sizes)]
            self.sim.set_spectrum(cascades)
            self._set_simulated(cascades)
            self._sim_sizes = sizes
        if full or not p["ocean.refresh_tolerance"] > 0.0:
            periods = [0.0] * len(sizes)
        else:
            if frame.dt > 0.0:  # the frame interval: up at once, down smoothly (a standing
                dt = min(frame.dt, 1.0)  # clock keeps it)
                self._frame_dt = dt if dt > self._frame_dt else self._frame_dt + 0.1 * (
                    dt - self._frame_dt)
            periods = []
            for i, period in enumerate(self._refresh_periods()):
                was_slow = i < len(self.sim.periods) and self.sim.periods[i] > 0.0
                # slow from three frames per period; back to every frame under two
                periods.append(period if period >= (2.0 if was_slow else 3.0) * self._frame_dt
                               else 0.0)
        if periods != self.sim.periods:
            self.sim.set_refresh(periods)

    def _refresh_periods(self) -> list[float]:
        """Each simulated cascade's snapshot period for ``ocean.refresh_tolerance`` (shared by
        every session of the process: the same sea, sizes and tolerance give the same)."""
        tol = self.params["ocean.refresh_tolerance"]
        key = (SeaState._refresh_periods, self._sim_key, tuple(self._sim_sizes), tol)

        def build():
            cascades = self._sim_cascades
            slope = math.sqrt(sum(c.moments()[1] for c in cascades))
            return tuple(oc.refresh_period(c, tol * slope) for c in cascades)

        return list(MEMO.get(key, build))

    def _set_simulated(self, cascades) -> None:
        """The cascades the GPU holds: their bands and slope variance (the glitter's filter),
        and Hs of what is drawn."""
        self._sim_cascades = list(cascades)
        self.cascade_bands = []
        m0 = 0.0
        for c in cascades:
            var, mss = c.moments()
            n = c.h0.shape[-1]
            lo = max(c.band[0], 2.0 * math.pi / c.patch_size)
            self.cascade_bands.append((lo, min(c.band[1], math.pi * n / c.patch_size), mss))
            m0 += var
        self.resolved_mss = sum(b[2] for b in self.cascade_bands)
        self._fft_hs = 4.0 * math.sqrt(m0)

    @property
    def simulated(self) -> oc.FFTOcean | None:
        """The numpy ocean of the cascades as the GPU simulates them (each on the grid the
        view chose: ``ocean.simulation``), or None unless the FFT runs."""
        if self._fft_ref is None or not self._sim_cascades:
            return None
        return oc.FFTOcean.from_cascades(self._fft_ref.params, self._sim_cascades)

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
            self._sim_sizes = []
            self._sim_cascades = []

    def cox_munk_mss(self) -> float:
        """Cox & Munk 1954 clean-surface mean-square slope 0.003 + 5.12e-3·U."""
        return 0.003 + 5.12e-3 * self.wind_speed()

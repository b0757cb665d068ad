"""The ocean's simulation: the sea state its parameters describe (the sine wave, the Gerstner set
drawn from the spectrum, the FFT cascades), what is derived from it (Hs, the resolved slope
variance, the cascades' wavenumber bands) and the GPU simulation with its schedule."""

from __future__ import annotations

import functools
import math
from typing import Any

from ...errors import ParamError
from ...gpu.cache import MEMO, memoised
from ...sim import ocean as oc
from ...sim.maths import compass_degrees
from .params import wind_vector


def _wave_set(params: oc.SpectrumParams, count: int, seed: int,
              steepness: float) -> tuple[oc.GerstnerWave, ...]:
    """The Gerstner set of a sea state (:func:`app.sim.ocean.gerstner_waves_from_spectrum`),
    as a tuple of frozen waves: what :func:`memoised` shares between sessions."""
    return tuple(oc.gerstner_waves_from_spectrum(params, count, seed=seed,
                                                 steepness_scale=steepness))


class Sea:
    """The sea of :class:`~app.effects.ocean.Ocean`: its state per model and, for the FFT, the
    :class:`~.fft.GpuOceanSim` (``sim``), fitted to the view and stepped by :meth:`step`."""

    def __init__(self, effect):
        self.gpu, self.name, self.params = effect.gpu, effect.name, effect.params
        #: (speed m/s, direction °) of the frame's ``wind`` slot when an effect before the ocean
        #: filled it (the scene's one wind); None: the ocean's own parameters
        self.frame_wind: tuple[float, float] | None = None
        self.sim: Any = None  # GpuOceanSim, only for the FFT model
        self._waves = effect.keyed(self._draw_waves)
        self._sim_path = self._sim_key = None
        #: the numpy ocean whose amplitudes the GPU simulation holds (None unless the FFT runs)
        self.reference: oc.FFTOcean | None = None
        self.resolved_mss = self._fft_hs = 0.0
        self.cascade_bands: list[tuple[float, float, float]] = []
        self._sim_sizes: list[int] = []  # each cascade's grid as simulated (fit_view)
        self._sim_cascades: list[oc.Cascade] = []
        #: the smallest pixel footprint on the water of the last view [m] (ocean.simulation=view)
        self.footprint = math.nan
        self._frame_dt = 1.0 / 30.0  # the frame interval, smoothed (slow cascades)
        self._bench_sim, self._bench_clock = None, 0  # (key, the copy the bench times), frames
        #: what the last simulated frame was computed from (a standing clock with the same
        #: inputs simulates nothing), and whether the last step ran the simulation
        self._sim_inputs: tuple | None = None
        self.sim_ran = False

    def set_wind(self, frame) -> None:
        """The scene's one wind, when an effect before the ocean filled the slot (spec/000
        §1.4); else fills the slot from ``ocean.wind`` and ``ocean.wind_direction``."""
        if frame.wind is None:
            self.frame_wind = None
            p = self.params
            frame.wind = wind_vector(p["ocean.wind_direction"]) * p["ocean.wind"]
        else:
            vx, vz = (float(v) for v in frame.wind)
            self.frame_wind = (math.hypot(vx, vz), compass_degrees(vx, vz))

    def prepare(self, frame) -> bool:
        """This frame's sea for ``ocean.model``: the FFT's sea and grids fitted to the view (True
        when the sea is new: flat water until it is read back), or the other models' slopes."""
        model = self.params["ocean.model"]
        if model == "fft":
            new = self._ensure_fft()
            self.fit_view(frame)
            return new
        self._release_fft()
        if model == "gerstner":
            self.resolved_mss = oc.gerstner_moments(self.gerstner_waves())["mss"]
        else:
            a, k, _ = self.sine_wave()
            self.resolved_mss = 0.5 * (k * a) ** 2
        return False

    def step(self, frame, dt: float, thresholds, query_time):
        """Advance the FFT simulation to the frame and request its readback; returns the newest
        readback (time, fields), or None. What the output depends on, the same on a standing
        clock (dt ≤ 0), leaves every texture as it is (the foam's decay is then 1 and its update
        idempotent): nothing is recomputed (the window's pause menu, a still render, the bench's
        frame). ``query_time``: the time of the readback the queries hold."""
        p = self.params
        inputs = (self.sim, self._sim_key, tuple(self.sim.sizes), tuple(self.sim.periods),
                  float(frame.time), p["ocean.choppiness"], tuple(thresholds),
                  p["ocean.foam_decay"])
        still = (dt <= 0.0 and self._sim_inputs is not None
                 and len(inputs) == len(self._sim_inputs)
                 and all(a is b or a == b for a, b in zip(inputs, self._sim_inputs)))
        self._sim_inputs = inputs
        if still:
            got = self.sim.poll_readback()
            if query_time != float(frame.time):  # the newest request is this time's sea: no
                got = self.sim.read_newest()  # stall left, its work is long done
        else:
            self.simulate(self.sim, frame.time, dt, thresholds)
            self.sim.request_readback()
            got = self.sim.poll_readback()  # the previous frame's request: no stall
        self.sim_ran = not still
        if got is None:  # the first frame of this sea: read it now (one stall), so floating
            got = self.sim.read_newest()  # objects and the camera never start on flat water
        return got

    def simulate(self, sim, t: float, dt: float, thresholds) -> None:
        """One update of ``sim`` at time ``t`` [s] (the frame's and the bench's alike)."""
        p = self.params
        sim.update(t, p["ocean.choppiness"], dt, foam_threshold=[a for a, _ in thresholds],
                   foam_decay_time=p["ocean.foam_decay"], foam_width=[w for _, w in thresholds])

    def bench_simulate(self, t: float, thresholds):
        """The bench's ``ocean.simulate`` pass: a copy of the simulation (the same cascades,
        grids and periods) on a clock of its own that moves 1/30 s a call — the bench's frames
        stand still, and a slow cascade does nothing while its clock does. A copy, so that the
        frame's own simulation keeps its clock."""
        from .fft import GpuOceanSim

        key = (self._sim_key, tuple(self.sim.sizes), tuple(self.sim.periods), self.sim.path)
        if self._bench_sim is None or self._bench_sim[0] != key:
            if self._bench_sim is not None:
                self._bench_sim[1].release()
            sim = GpuOceanSim(self.gpu, self.name, use_compute=self.sim.use_compute)
            sim.set_spectrum(self._sim_cascades)
            sim.set_refresh(self.sim.periods)
            self._bench_sim = (key, sim)
        sim = self._bench_sim[1]

        def run():
            self._bench_clock += 1
            self.simulate(sim, t + self._bench_clock / 30.0, 1.0 / 30.0, thresholds)

        return run

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

    def _ensure_fft(self) -> bool:
        path = self.params["ocean.fft_path"]
        key = (self.spectrum_params(), int(self.params["ocean.fft_size"]),
               tuple(self.patch_sizes()), self.params["ocean.seed"])
        if self.sim is not None and self._sim_path != path:
            self._release_fft()
        if key == self._sim_key:
            return False
        # the cascades' arrays shared (read-only) by every session of the process that
        # builds the same sea
        ref = oc.FFTOcean(key[0], n=key[1], patch_sizes=key[2], choppiness=1.0, seed=key[3],
                          build=functools.partial(memoised, oc.cascade_arrays))
        if self.sim is None:
            from ...gpu.fft import choose_compute
            from .fft import GpuOceanSim

            # auto: llvmpipe runs the fragment path faster (evolve and finalize as image
            # stores cost it 2–3×: 79 against 98 ms per update at 256 × 3)
            use_compute = choose_compute(self.gpu.caps, path, "ocean.fft_path")
            self.sim = GpuOceanSim(self.gpu, self.name, use_compute=use_compute)
            self._sim_path = path
        self.reference, self._sim_key = ref, key
        self._sim_sizes = []  # the view chooses them (fit_view), then the GPU gets the sea
        self._fft_hs = 4.0 * math.sqrt(sum(c.moments()[0] for c in ref.cascades))
        return True

    def fit_view(self, frame) -> None:
        """The FFT sea's grid per cascade and which cascades are slow, for this frame's view, as
        ``ocean.simulation`` says (:func:`app.sim.ocean.view_cascade_size`, ``crop_cascade``,
        ``refresh_period``)."""
        p = self.params
        ref = self.reference
        n_max = int(self.params["ocean.fft_size"])
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
        key = (Sea._refresh_periods, self._sim_key, tuple(self._sim_sizes), tol)

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

    def _release_fft(self) -> None:
        if self.sim is not None:
            self.sim.release()
            self.sim = self._sim_key = self.reference = None
            self._fft_hs, self._sim_sizes, self._sim_cascades = 0.0, [], []

    def release(self) -> None:
        if self._bench_sim is not None:
            self._bench_sim[1].release()
            self._bench_sim = None
        self._sim_inputs = None
        self._release_fft()

"""The GPU side of the FFT ocean (Tessendorf 2001; spec/000 §1.1(d), §1.1(e), §1.3): spectrum
evolution, inverse FFT and the fields the surface samples, for 1–4 cascades.  The numpy
reference is ``app/sim/ocean.py`` (``evolve_amplitudes``, ``synthesize``, ``foam_step``); the
tests compare the two field by field (``tests/**/test_ocean_gpu*.py``).

Per frame, :meth:`GpuOceanSim.update` runs three stages (also callable one by one for benches,
see :meth:`GpuOceanSim.stages`):

1. **evolve** (``glsl/ocean/spectrum_evolve.*``) — spec/000 eq. 2.11 with the conjugate restored,
   h(k,t) = h₀(k)e^{iωt} + conj h₀(−k)e^{−iωt}, and the eight field spectra (η, λD_x, λD_z,
   ∂η/∂x, ∂η/∂z, λ∂D_x/∂x, λ∂D_z/∂z, λ∂D_x/∂z) packed as four complex fields in two RGBA32F
   textures per cascade (each field's spectrum is Hermitian, so the packing is exact);
2. **fft** — :class:`app.gpu.fft.GpuFFT` on all 2·cascades textures;
3. **finalize** (``glsl/ocean/ocean_finalize.*``) — per cascade ``disp[i]`` = (λD_x, η, λD_z, J),
   ``deriv[i]`` = (∂η/∂x, ∂η/∂z, λ∂D_x/∂x, λ∂D_z/∂z) (RGBA32F, mipmapped, repeat: they tile
   with period L_i), and ``foam[i]`` (R32F) updated as ``foam_step``; then mipmaps.

Both paths — compute shaders (GL ≥ 4.3) and full-screen fragment passes (GL 3.3) — compute
the same numbers.  In the fragment path foam ping-pongs between two textures, so the texture
object in ``foam[i]`` changes every update: read ``foam`` after each update, don't keep it.

ω(k) is uploaded as ν = ω/2π split in float64 into a 12-bit "hi" part and a float32 "lo" part
(RG32F), and t likewise, so that the phase ωt stays exact to ~1e-5 cycles even after days of
simulated time (plain float32 ωt loses ~0.3 rad per frame of jitter after a day).
"""

from __future__ import annotations

import math
from typing import Callable, Sequence

import moderngl
import numpy as np

from ...errors import ParamError
from ...gpu.fft import GpuFFT, check_fft_size, resolve_compute, twiddle_table
from ...gpu.programs import ProgramSpec, draw_fullscreen, fullscreen

MAX_CASCADES = 4
LOCAL = 8  # work group edge of the ocean compute shaders
MODE_ROW = 256  # modes per row of the direct-sum mode texture

EVOLVE = "ocean/spectrum_evolve"
FINALIZE = "ocean/ocean_finalize"
DIRECT_SUM = "ocean/direct_sum"

FIELD_KEYS = ("height", "disp_x", "disp_z", "jacobian", "slope_x", "slope_z", "ddx_dx", "ddz_dz",
              "ddx_dz", "foam")


def split_hi_lo(x, bits: int = 12) -> tuple[np.ndarray, np.ndarray]:
    """x (float64) = hi + lo with hi carrying ``bits`` significant bits (exact in float32) and lo
    the float32 rest: a product of two such hi parts is exact in float32."""
    x = np.asarray(x, dtype=np.float64)
    mant, expo = np.frexp(x)
    hi = np.ldexp(np.round(np.ldexp(mant, bits)), expo - bits)
    return hi.astype(np.float32), (x - hi).astype(np.float32)


def negate_index(a: np.ndarray) -> np.ndarray:
    """a(−k) on an FFT-ordered (N, N) grid: index j → (N − j) mod N on both axes."""
    return np.roll(np.flip(a, axis=(-2, -1)), 1, axis=(-2, -1))


def _rgba(*channels) -> bytes:
    return np.ascontiguousarray(np.stack(channels, axis=-1), dtype=np.float32).tobytes()


class GpuOceanSim:
    """Cascaded Tessendorf ocean on the GPU.

    ``GpuOceanSim(gpu, owner="ocean", use_compute=None)``; ``set_spectrum(cascades, n)`` with
    :class:`app.sim.ocean.Cascade` objects; ``update(t, choppiness, dt, ...)`` each frame; then
    sample ``disp[i]``, ``deriv[i]``, ``foam[i]`` (world xz / ``patch_sizes[i]`` as texture
    coordinates).  Every GL object is allocated through ``gpu`` under ``owner``; ``release()``
    frees them.
    """

    def __init__(self, gpu, owner: str = "ocean", use_compute: bool | None = None):
        self.gpu = gpu
        self.owner = owner
        self.use_compute = resolve_compute(gpu, use_compute, "ocean.use_compute")
        self.n: int | None = None
        self.patch_sizes: list[float] = []
        self.time: float | None = None
        self.disp: list[moderngl.Texture] = []
        self.deriv: list[moderngl.Texture] = []
        self._fft: GpuFFT | None = None
        self._objects: list = []
        self._programs: dict[str, object] = {}
        self._cascades: list = []
        self._h0: list = []
        self._freq: list = []
        self._wave: list = []
        self._foam_tex: list[list[moderngl.Texture]] = []  # [cascade][0 or 1]
        self._foam_cur = 0
        self._evolve_fbo: list = []
        self._finalize_fbo: list[list] = []  # [cascade][foam texture written]
        self._modes: list | None = None  # direct-sum mode textures, built on first use
        self._phase_table = None
        self._pbo: list[list] = []
        self._rb_next = 0
        self._rb_pending: tuple | None = None  # (time, slot) of the newest request
        self._rb_previous: tuple | None = None  # (time, slot) of the one before, not yet read
        self._rb_latest: tuple | None = None  # what poll_readback returns

    # -- resources -------------------------------------------------------------------------
    @property
    def cascade_count(self) -> int:
        return len(self.disp)

    @property
    def foam(self) -> list[moderngl.Texture]:
        """The current foam texture of each cascade (R32F, in [0, 1])."""
        return [pair[self._foam_cur] for pair in self._foam_tex]

    @property
    def path(self) -> str:
        return "compute" if self.use_compute else "fragment"

    def _own(self, obj):
        self._objects.append(obj)
        return obj

    def _program(self, name: str):
        prog = self._programs.get(name)
        if prog is None:
            spec = ProgramSpec(name, comp=f"{name}.comp") if self.use_compute else fullscreen(name)
            prog = self.gpu.program(self.owner, spec)
            self._programs[name] = prog
        return prog

    def _free_arrays(self) -> None:
        for obj in reversed(self._objects):
            self.gpu.free(obj)
        self._objects.clear()
        if self._fft is not None:
            self._fft.release()
            self._fft = None
        self.disp, self.deriv = [], []
        self._h0, self._freq, self._wave = [], [], []
        self._foam_tex, self._evolve_fbo, self._finalize_fbo = [], [], []
        self._modes = None
        self._phase_table = None
        self._pbo = []
        self._rb_pending = self._rb_previous = self._rb_latest = None
        self._foam_cur = 0

    def _allocate(self, n: int, count: int) -> None:
        gpu, owner = self.gpu, self.owner
        nearest = (moderngl.NEAREST, moderngl.NEAREST)
        size = (n, n)
        self._fft = GpuFFT(gpu, owner, n, count=2 * count, use_compute=self.use_compute)
        zeros = np.zeros((n, n), dtype=np.float32).tobytes()
        for i in range(count):
            self._h0.append(self._own(gpu.texture(owner, f"ocean h0 {i}", size, 4, dtype="f4",
                                                  filter=nearest)))
            self._freq.append(self._own(gpu.texture(owner, f"ocean frequency {i}", size, 2,
                                                    dtype="f4", filter=nearest)))
            self._wave.append(self._own(gpu.texture(owner, f"ocean wave vector {i}", size, 2,
                                                    dtype="f4", filter=nearest)))
            for lst, name in ((self.disp, "displacement"), (self.deriv, "derivatives")):
                tex = self._own(gpu.texture(owner, f"ocean {name} {i}", size, 4, dtype="f4",
                                            filter=(moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR),
                                            repeat=True))
                tex.build_mipmaps()  # allocate every level now: image units need a complete texture
                lst.append(tex)
            pair = [self._own(gpu.texture(owner, f"ocean foam {i}", size, 1, data=zeros,
                                          dtype="f4", repeat=True))]
            if not self.use_compute:
                pair.append(self._own(gpu.texture(owner, f"ocean foam {i} (ping-pong)", size, 1,
                                                  data=zeros, dtype="f4", repeat=True)))
                fields = self._fft.textures[2 * i: 2 * i + 2]
                self._evolve_fbo.append(self._own(gpu.framebuffer(owner, f"ocean spectrum {i}",
                                                                  fields)))
                self._finalize_fbo.append([
                    self._own(gpu.framebuffer(owner, f"ocean finalize {i}.{j}",
                                              [self.disp[i], self.deriv[i], pair[j]]))
                    for j in range(2)])
            else:
                pair.append(pair[0])  # foam is updated in place by the compute pass
            self._foam_tex.append(pair)
        self.n = n

    def set_spectrum(self, cascades: Sequence, n: int) -> None:
        """Upload h₀(k), conj h₀(−k), ω(k) and (k_x, k_z) of 1–4 :class:`app.sim.ocean.Cascade`
        (arrays (N, N) in numpy FFT order, [iz, ix]).  GL objects are re-allocated (and foam
        cleared) only when N or the cascade count changes."""
        n = check_fft_size(n)
        cascades = list(cascades)
        if not 1 <= len(cascades) <= MAX_CASCADES:
            raise ParamError(f"ocean.cascades: {len(cascades)} is outside the allowed range "
                             f"[1, {MAX_CASCADES}]")
        for i, c in enumerate(cascades):
            for name in ("h0", "omega", "kx", "kz"):
                shape = np.shape(getattr(c, name))
                if shape != (n, n):
                    raise ParamError(f"ocean.cascade {i}: {name} has shape {shape}, expected "
                                     f"({n}, {n})")
        if self.n != n or self.cascade_count != len(cascades):
            self._free_arrays()
            self._allocate(n, len(cascades))
        for i, c in enumerate(cascades):
            h0 = np.asarray(c.h0, dtype=np.complex128)
            h0m = np.conj(negate_index(h0))
            self._h0[i].write(_rgba(h0.real, h0.imag, h0m.real, h0m.imag))
            nu_hi, nu_lo = split_hi_lo(np.asarray(c.omega, dtype=np.float64) / (2.0 * np.pi))
            self._freq[i].write(_rgba(nu_hi, nu_lo))
            self._wave[i].write(_rgba(c.kx, c.kz))
        self._cascades = cascades
        self.patch_sizes = [float(c.patch_size) for c in cascades]
        for tex in self._modes or []:
            self.gpu.free(tex)
            self._objects.remove(tex)
        self._modes = None

    def release(self) -> None:
        """Free every GL object this simulation allocated."""
        self._free_arrays()
        for prog in self._programs.values():
            if any(a.obj is prog and a.owner == self.owner for a in self.gpu.allocations):
                self.gpu.free(prog)  # forgets the record; programs stay in the shared library
        self._programs.clear()
        self.n = None
        self.patch_sizes = []
        self._cascades = []

    # -- the stages ------------------------------------------------------------------------
    def _require(self) -> None:
        if self.n is None:
            raise RuntimeError("GpuOceanSim.set_spectrum(cascades, n) must be called first")

    @staticmethod
    def _check_choppiness(choppiness: float) -> float:
        if not (math.isfinite(choppiness) and 0.0 <= choppiness <= 4.0):
            raise ParamError(f"ocean.choppiness: {choppiness} is outside the allowed range [0, 4]")
        return float(choppiness)

    def _set_spectrum_uniforms(self, prog, i: int, t: float, choppiness: float) -> dict:
        """Set the evolution uniforms of cascade i; returns its spectrum textures by sampler."""
        t_hi, t_lo = split_hi_lo(float(t))
        prog.set("uTime", (float(t_hi), float(t_lo)))
        prog.set("uChoppiness", choppiness)
        prog.set("uN", self.n)
        return {"uH0": self._h0[i], "uFrequency": self._freq[i], "uWaveVector": self._wave[i]}

    def _groups(self) -> int:
        return (self.n + LOCAL - 1) // LOCAL

    def _write_fields(self, prog, i: int, extra_setup: Callable | None = None) -> None:
        """Run ``prog`` for cascade i, writing its two field textures (the FFT's data)."""
        fields = self._fft.textures[2 * i: 2 * i + 2]
        prog.bind_textures(extra_setup(prog, i) if extra_setup else {})
        if self.use_compute:
            fields[0].bind_to_image(0, read=False, write=True)
            fields[1].bind_to_image(1, read=False, write=True)
            prog.program.run(self._groups(), self._groups(), 1)
        else:
            self._evolve_fbo[i].use()
            draw_fullscreen(prog)

    def _run_per_cascade(self, prog, setup: Callable) -> None:
        ctx = self.gpu.ctx
        if self.use_compute:
            for i in range(self.cascade_count):
                self._write_fields(prog, i, setup)
            ctx.memory_barrier()
        else:
            with ctx.scope(self._evolve_fbo[0], enable_only=moderngl.NOTHING):
                for i in range(self.cascade_count):
                    self._write_fields(prog, i, setup)

    def evolve(self, t: float, choppiness: float) -> None:
        """Stage 1: h(k,t) and the packed field spectra of every cascade at time t [s]."""
        self._require()
        lam = self._check_choppiness(choppiness)
        prog = self._program(EVOLVE)
        self._run_per_cascade(prog, lambda p, i: self._set_spectrum_uniforms(p, i, t, lam))
        self.time = float(t)

    def fft(self) -> None:
        """Stage 2: inverse FFT of all 2·cascades field textures."""
        self._require()
        self._fft.inverse()

    def finalize(self, dt: float = 0.0, foam_threshold=0.5, foam_decay_time: float = 2.0,
                 update_foam: bool = True, foam_width=None) -> None:
        """Stage 3: ``disp``, ``deriv`` (then their mipmaps) and foam from the fields.

        Foam: e^{−dt/τ} decay, raised to clip((threshold − J)/width, 0, 1) (width = threshold
        unless given); threshold and width may be one number or one per cascade. dt ≤ 0 (or NaN)
        neither decays nor grows it.  ``update_foam=False`` carries foam over unchanged."""
        self._require()
        thresholds = self._per_cascade(foam_threshold, "ocean.foam_threshold")
        widths = (thresholds if foam_width is None
                  else self._per_cascade(foam_width, "ocean.foam_width"))
        for value in thresholds:
            if not (math.isfinite(value) and value > 0):
                raise ParamError(f"ocean.foam_threshold: {value} is outside the allowed range "
                                 "(0, inf)")
        for value in widths:
            if not (math.isfinite(value) and value > 0):
                raise ParamError(f"ocean.foam_width: {value} is outside the allowed range (0, inf)")
        if not (foam_decay_time > 0):  # inf is allowed: foam never decays
            raise ParamError(f"ocean.foam_decay_time: {foam_decay_time} s is outside the allowed "
                             "range (0, inf]")
        dt = float(dt) if (dt == dt and dt > 0) else 0.0
        decay = math.exp(-dt / foam_decay_time)
        prog = self._program(FINALIZE)
        prog.set("uFoamDecay", decay)
        prog.set("uFoamUpdate", 1 if update_foam else 0)
        prog.set("uN", self.n)
        ctx = self.gpu.ctx
        if self.use_compute:
            for i in range(self.cascade_count):
                prog.set("uFoamThreshold", thresholds[i])
                prog.set("uFoamWidth", widths[i])
                fields = self._fft.textures[2 * i: 2 * i + 2]
                fields[0].bind_to_image(0, read=True, write=False)
                fields[1].bind_to_image(1, read=True, write=False)
                self.disp[i].bind_to_image(2, read=False, write=True)
                self.deriv[i].bind_to_image(3, read=False, write=True)
                self._foam_tex[i][0].bind_to_image(4, read=True, write=True)
                prog.program.run(self._groups(), self._groups(), 1)
            ctx.memory_barrier()
        else:
            src = self._foam_cur
            with ctx.scope(self._finalize_fbo[0][1 - src], enable_only=moderngl.NOTHING):
                for i in range(self.cascade_count):
                    prog.set("uFoamThreshold", thresholds[i])
                    prog.set("uFoamWidth", widths[i])
                    self._finalize_fbo[i][1 - src].use()
                    fields = self._fft.textures[2 * i: 2 * i + 2]
                    prog.bind_textures({"uFields0": fields[0], "uFields1": fields[1],
                                        "uFoamBefore": self._foam_tex[i][src]})
                    draw_fullscreen(prog)
            self._foam_cur = 1 - src
        for tex in self.disp + self.deriv:
            tex.build_mipmaps()
        for tex in self.foam:  # mip-mapped too: seen from afar, foam must average, not sparkle
            tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
            tex.build_mipmaps()

    def update(self, t: float, choppiness: float, dt: float, foam_threshold=0.5,
               foam_decay_time: float = 2.0, foam_width=None) -> None:
        """One frame at time t [s]: evolve, FFT, finalize (foam advanced by dt [s])."""
        self.evolve(t, choppiness)
        self.fft()
        self.finalize(dt, foam_threshold, foam_decay_time, foam_width=foam_width)

    def _per_cascade(self, value, what: str) -> list[float]:
        if isinstance(value, (int, float)):
            return [float(value)] * self.cascade_count
        values = [float(v) for v in value]
        if len(values) != self.cascade_count:
            raise ParamError(f"{what}: {len(values)} values for {self.cascade_count} cascades")
        return values

    def stages(self, t: float = 1.0, choppiness: float = 1.0,
               dt: float = 1.0 / 60.0) -> dict[str, Callable]:
        """Named callables of the three stages, for timing them separately."""
        return {
            "ocean.evolve": lambda: self.evolve(t, choppiness),
            "ocean.fft": self.fft,
            "ocean.finalize": lambda: self.finalize(dt),
        }

    # -- direct summation (bench reference) ------------------------------------------------
    def _build_modes(self) -> None:
        n = self.n
        nyquist = np.zeros((n, n), dtype=bool)
        nyquist[n // 2, :] = nyquist[:, n // 2] = True
        self._modes = []
        for i, c in enumerate(self._cascades):
            h0 = np.asarray(c.h0, dtype=np.complex128)
            h0m = np.conj(negate_index(h0))
            iz, ix = np.nonzero(((h0 != 0) | (h0m != 0)) & ~nyquist)
            count = len(ix)
            width = max(1, min(count, MODE_ROW))
            rows = max(1, -(-count // width))
            data = np.zeros((rows * width, 3, 4), dtype=np.float32)
            nu_hi, nu_lo = split_hi_lo(np.asarray(c.omega, dtype=np.float64)[iz, ix]
                                       / (2.0 * np.pi))
            data[:count, 0] = np.stack([h0.real[iz, ix], h0.imag[iz, ix],
                                        h0m.real[iz, ix], h0m.imag[iz, ix]], -1)
            data[:count, 1] = np.stack([np.asarray(c.kx)[iz, ix], np.asarray(c.kz)[iz, ix],
                                        nu_hi, nu_lo], -1)
            data[:count, 2, 0] = ix
            data[:count, 2, 1] = iz
            tex = self._own(self.gpu.texture(self.owner, f"ocean direct-sum modes {i}",
                                             (3 * width, rows), 4,
                                             data=data.reshape(rows, width * 3, 4).tobytes(),
                                             dtype="f4",
                                             filter=(moderngl.NEAREST, moderngl.NEAREST)))
            tex.extra = {"modes": count, "width": width}
            self._modes.append(tex)
        if self._phase_table is None:
            self._phase_table = self._own(self.gpu.texture(
                self.owner, "ocean direct-sum phases", (n, 1), 2,
                data=twiddle_table(n, n).tobytes(), dtype="f4",
                filter=(moderngl.NEAREST, moderngl.NEAREST)))

    def mode_counts(self) -> list[int]:
        """Non-zero modes per cascade (what :meth:`direct_sum` sums over)."""
        self._require()
        if self._modes is None:
            self._build_modes()
        return [tex.extra["modes"] for tex in self._modes]

    def direct_sum(self, t: float, choppiness: float) -> None:
        """The same fields by direct summation over every non-zero mode (no FFT), written into
        the same ``disp``/``deriv`` textures; foam is carried over unchanged.

        Cost O(N²·modes) per cascade — a reference for benches at N ≤ 128, not a renderer."""
        self._require()
        lam = self._check_choppiness(choppiness)
        if self._modes is None:
            self._build_modes()
        prog = self._program(DIRECT_SUM)

        def setup(p, i):
            textures = self._set_spectrum_uniforms(p, i, t, lam)
            tex = self._modes[i]
            p.set("uModeCount", tex.extra["modes"])
            p.set("uModeWidth", tex.extra["width"])
            return {**textures, "uModes": tex, "uPhaseTable": self._phase_table}

        self._run_per_cascade(prog, setup)
        self.time = float(t)
        self.finalize(0.0, update_foam=False)

    # -- reading back ----------------------------------------------------------------------
    def read_fields(self, i: int) -> dict[str, np.ndarray]:
        """Synchronous readback of cascade i (stalls the GPU; for tests and tools): float32
        arrays [iz, ix] ``height, disp_x, disp_z, jacobian, slope_x, slope_z, ddx_dx, ddz_dz,
        ddx_dz, foam`` (displacements and their derivatives already times λ)."""
        self._require()
        n = self.n
        disp = np.frombuffer(self.disp[i].read(level=0), dtype=np.float32).reshape(n, n, 4)
        deriv = np.frombuffer(self.deriv[i].read(level=0), dtype=np.float32).reshape(n, n, 4)
        foam = np.frombuffer(self.foam[i].read(), dtype=np.float32).reshape(n, n)
        fields1 = self._fft.read(2 * i + 1)
        return {
            "height": disp[..., 1].copy(), "disp_x": disp[..., 0].copy(),
            "disp_z": disp[..., 2].copy(),
            "jacobian": disp[..., 3].copy(),
            "slope_x": deriv[..., 0].copy(), "slope_z": deriv[..., 1].copy(),
            "ddx_dx": deriv[..., 2].copy(), "ddz_dz": deriv[..., 3].copy(),
            "ddx_dz": fields1[..., 3].copy(),
            "foam": foam.copy(),
        }

    def request_readback(self) -> None:
        """Queue an asynchronous copy of level 0 of every ``disp`` texture (λD_x, η, λD_z, J)
        into pixel-pack buffers, remembering the simulation time (spec/000 §1.3: buoyancy reads
        the water on the CPU through an asynchronous readback)."""
        self._require()
        if not self._pbo:
            nbytes = self.n * self.n * 16
            self._pbo = [[self._own(self.gpu.buffer(self.owner, f"ocean readback {slot}.{i}",
                                                    bytes(nbytes)))
                          for i in range(self.cascade_count)] for slot in range(2)]
        slot = self._rb_next
        self._rb_next = 1 - slot
        for tex, buf in zip(self.disp, self._pbo[slot]):
            tex.read_into(buf, level=0)
        # an older unread request is dropped (its slot is reused next)
        self._rb_previous = self._rb_pending
        self._rb_pending = (self.time, slot)

    def read_newest(self):
        """The newest request's result *now* — a stall until the GPU has filled it; for the
        first frame of a sea, when there is no earlier request to map. ``(time, arrays)`` as
        :meth:`poll_readback`, or None without a request."""
        if self._rb_pending is None:
            return None
        return self._map(*self._rb_pending)

    def _map(self, t: float, slot: int):
        """Read readback ``slot`` (the request made at simulation time ``t``) as the latest."""
        n = self.n
        # one (C, N, N, 4) array: the height queries gather from every cascade at once
        arrays = np.stack([np.frombuffer(buf.read(), dtype=np.float32).reshape(n, n, 4)
                           for buf in self._pbo[slot]])
        self._rb_latest = (t, arrays)
        self._rb_previous = None
        return self._rb_latest

    def poll_readback(self):
        """``(time, (C, N, N, 4) float32 array: an (N, N, 4) grid per cascade)`` of the most
        recent request *before* the newest one, or None until there is one.

        One frame of lag, by design: the newest request's copy may still be queued behind this
        frame's work, so it is left alone; the previous request's buffers were filled a frame
        ago and map without stalling.  Calling again without a new request returns the same
        result.  Arrays are indexed [iz, ix] with channels (λD_x, η, λD_z, J)."""
        if self._rb_previous is not None:
            self._map(*self._rb_previous)
        return self._rb_latest

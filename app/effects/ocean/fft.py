"""The GPU side of the FFT ocean (Tessendorf 2001; spec/000 §1.1(d), §1.1(e), §1.3): spectrum
evolution, inverse FFT and the fields the surface samples, for 1–4 cascades.  The numpy
reference is ``app/sim/ocean.py`` (``evolve_amplitudes``, ``synthesize``, ``foam_step``); the
tests compare the two field by field (``tests/**/test_ocean_gpu*.py``).

Per frame, :meth:`GpuOceanSim.update` runs three stages per cascade:

1. **evolve** (``glsl/ocean/spectrum_evolve.*``) — spec/000 eq. 2.11 with the conjugate restored,
   h(k,t) = h₀(k)e^{iωt} + conj h₀(−k)e^{−iωt}, and the eight field spectra (η, λD_x, λD_z,
   ∂η/∂x, ∂η/∂z, λ∂D_x/∂x, λ∂D_z/∂z, λ∂D_x/∂z) packed as four complex fields in two RGBA32F
   textures (each field's spectrum is Hermitian, so the packing is exact);
2. **fft** — the cascade's :class:`app.gpu.fft.GpuFFT` on its two textures;
3. **finalize** (``glsl/ocean/ocean_finalize.*``) — ``disp[i]`` = (λD_x, η, λD_z, J),
   ``deriv[i]`` = (∂η/∂x, ∂η/∂z, λ∂D_x/∂x, λ∂D_z/∂z) (RGBA32F, mipmapped, repeat: they tile
   with period L_i), and ``foam[i]`` (R32F) updated as ``foam_step``; then mipmaps.

Each cascade has a grid of its own size (``sizes``), and each may be **slow**
(:meth:`GpuOceanSim.set_refresh`; the plan: ``app/effects/ocean/schedule.py``); a slow cascade's
snapshots are finalised and blended (``glsl/ocean/cascade_blend.frag``) by fragment passes on
either path.

Both paths — compute shaders (GL ≥ 4.3) and full-screen fragment passes (GL 3.3) — compute
the same numbers.  In the fragment path foam ping-pongs between two textures, so the texture
object in ``foam[i]`` changes every update: read ``foam`` after each update, don't keep it.

ω(k) is uploaded as ν = ω/2π split in float64 into a 12-bit "hi" part and a float32 "lo" part
(RG32F), and t likewise, so that the phase ωt stays exact to ~1e-5 cycles even after days of
simulated time (plain float32 ωt loses ~0.3 rad per frame of jitter after a day).
"""

from __future__ import annotations

import math
from typing import Sequence

import moderngl
import numpy as np

from ...errors import ParamError
from ...gpu.fft import GpuFFT, resolve_compute, twiddle_table
from ...gpu.programs import ProgramSpec, draw_fullscreen, fullscreen
from ...sim import ocean as oc
from .schedule import Plan, SnapshotSchedule

LOCAL = 8  # work group edge of the ocean compute shaders
MODE_ROW = 256  # modes per row of the direct-sum mode texture

EVOLVE = "ocean/spectrum_evolve"
FINALIZE = "ocean/ocean_finalize"
DIRECT_SUM = "ocean/direct_sum"
BLEND = fullscreen("ocean/cascade_blend")
RESAMPLE = fullscreen("ocean/cascade_blend", defines=(("CASCADE_RESAMPLE", 1),))


def split_hi_lo(x, bits: int = 12) -> tuple[np.ndarray, np.ndarray]:
    """x (float64) = hi + lo with hi carrying ``bits`` significant bits (exact in float32) and lo
    the float32 rest: a product of two such hi parts is exact in float32."""
    x = np.asarray(x, dtype=np.float64)
    mant, expo = np.frexp(x)
    hi = np.ldexp(np.round(np.ldexp(mant, bits)), expo - bits)
    return hi.astype(np.float32), (x - hi).astype(np.float32)


def _rgba(*channels) -> bytes:
    return np.ascontiguousarray(np.stack(channels, axis=-1), dtype=np.float32).tobytes()


NEAREST = (moderngl.NEAREST, moderngl.NEAREST)
MIPMAPPED = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)


class _Snapshots:
    """A slow cascade's two snapshot texture sets (A and B: displacement, derivatives, foam,
    unfiltered, and a framebuffer over the three) and its plan."""

    def __init__(self, gpu, owner: str, i: int, n: int, schedule: SnapshotSchedule):
        self.schedule = schedule
        self.sets = []
        for j in range(2):
            disp, deriv, foam = (gpu.texture(owner, f"ocean snapshot {i}.{j} {what}", (n, n),
                                             components, dtype="f4", filter=NEAREST)
                                 for what, components in (("displacement", 4), ("derivatives", 4),
                                                          ("foam", 1)))
            fbo = gpu.framebuffer(owner, f"ocean snapshot {i}.{j}", [disp, deriv, foam])
            self.sets.append((disp, deriv, foam, fbo))
        self.a = 0  # the set holding snapshot A; B is the other
        self.weight: float | None = None  # the last blend's weight (None: the display is stale)


class _Cascade:
    """The GL objects of one cascade at one grid size N: its spectrum (h₀, ν, k), its FFT and
    the textures the surface samples (``disp``, ``deriv``, ``foam``)."""

    def __init__(self, sim: "GpuOceanSim", i: int, n: int):
        gpu, owner = sim.gpu, sim.owner
        self.n = n
        self.fft = GpuFFT(gpu, owner, n, count=2, use_compute=sim.use_compute)
        zeros = np.zeros((n, n), dtype=np.float32).tobytes()

        def texture(name: str, components: int, **kw):
            return gpu.texture(owner, name, (n, n), components, dtype="f4", **kw)

        self.h0 = texture(f"ocean h0 {i}", 4, filter=NEAREST)
        self.freq = texture(f"ocean frequency {i}", 2, filter=NEAREST)
        self.wave = texture(f"ocean wave vector {i}", 2, filter=NEAREST)
        self.disp = texture(f"ocean displacement {i}", 4, filter=MIPMAPPED, repeat=True)
        self.deriv = texture(f"ocean derivatives {i}", 4, filter=MIPMAPPED, repeat=True)
        for tex in (self.disp, self.deriv):
            tex.build_mipmaps()  # allocate every level now: image units need a complete texture
        # the compute pass updates the foam in place; the fragment passes ping-pong
        foam = texture(f"ocean foam {i}", 1, data=zeros, repeat=True)
        self.foam_pair = [foam, foam if sim.use_compute else
                          texture(f"ocean foam {i} (ping-pong)", 1, data=zeros, repeat=True)]
        self.objects: list = [self.h0, self.freq, self.wave, self.disp, self.deriv, foam]
        if not sim.use_compute:
            # framebuffers after the textures: released before them (freed backwards)
            self.objects += [self.foam_pair[1], gpu.framebuffer(owner, f"ocean spectrum {i}",
                                                                self.fft.textures)]
        self.evolve_fbo = None if sim.use_compute else self.objects[-1]
        self.foam_cur = 0
        # framebuffers over (disp, deriv, foam pair[j]): the fragment finalize, the blend and
        # the resample write through them (made on first use on the compute path)
        self._out: list = [None, None]
        self.cascade = None  # the app.sim.ocean.Cascade uploaded
        self.snap: _Snapshots | None = None
        self.modes = None  # direct-sum mode texture, built on first use

    @property
    def foam(self):
        return self.foam_pair[self.foam_cur]

    def out_fbo(self, gpu, owner: str, j: int):
        if self._out[j] is None:
            self._out[j] = gpu.framebuffer(owner, "ocean cascade output",
                                           [self.disp, self.deriv, self.foam_pair[j]])
            self.objects.append(self._out[j])
        return self._out[j]

    def release(self, gpu) -> None:
        self.drop_snapshots(gpu)
        for obj in reversed(self.objects):
            gpu.free(obj)
        self.objects.clear()
        self.fft.release()

    def drop_snapshots(self, gpu) -> None:
        if self.snap is not None:
            for obj in reversed([obj for s in self.snap.sets for obj in s]):
                gpu.free(obj)
            self.snap = None


class GpuOceanSim:
    """Cascaded Tessendorf ocean on the GPU.

    ``GpuOceanSim(gpu, owner="ocean", use_compute=None)``; ``set_spectrum(cascades)`` with
    :class:`app.sim.ocean.Cascade` objects (each on a grid of its own size); optionally
    ``set_refresh(periods)``; ``update(t, choppiness, dt, ...)`` each frame; then sample
    ``disp[i]``, ``deriv[i]``, ``foam[i]`` (world xz / ``patch_sizes[i]`` as texture
    coordinates).  Every GL object is allocated through ``gpu`` under ``owner``; ``release()``
    frees them.
    """

    def __init__(self, gpu, owner: str = "ocean", use_compute: bool | None = None):
        self.gpu = gpu
        self.owner = owner
        self.use_compute = resolve_compute(gpu, use_compute, "ocean.use_compute")
        self.patch_sizes: list[float] = []
        self.time: float | None = None
        self._c: list[_Cascade] = []
        self._programs: dict[object, object] = {}
        self._phase_tables: dict[int, object] = {}
        self._pbo: list[list] = []
        self._rb_next = 0
        self._rb_pending: tuple | None = None  # (time, slot) of the newest request
        self._rb_previous: tuple | None = None  # (time, slot) of the one before, not yet read
        self._rb_latest: tuple | None = None  # what poll_readback returns
        #: per cascade: "fft" (simulated this frame), "snapshots" (a slow cascade's plan ran)
        self.last_work: list[str] = []

    # -- resources -------------------------------------------------------------------------
    @property
    def cascade_count(self) -> int:
        return len(self._c)

    @property
    def sizes(self) -> list[int]:
        """Each cascade's grid size N."""
        return [c.n for c in self._c]

    @property
    def disp(self) -> list[moderngl.Texture]:
        return [c.disp for c in self._c]

    @property
    def deriv(self) -> list[moderngl.Texture]:
        return [c.deriv for c in self._c]

    @property
    def foam(self) -> list[moderngl.Texture]:
        """The current foam texture of each cascade (R32F, in [0, 1])."""
        return [c.foam for c in self._c]

    @property
    def periods(self) -> list[float]:
        """Each cascade's snapshot period [s] (0: simulated every frame)."""
        return [c.snap.schedule.period if c.snap is not None else 0.0 for c in self._c]

    @property
    def path(self) -> str:
        return "compute" if self.use_compute else "fragment"

    def _program(self, name, compute: bool | None = None):
        """``name`` on this simulation's path (``compute`` forces one), or a ProgramSpec."""
        use = self.use_compute if compute is None else compute
        key = name if isinstance(name, ProgramSpec) else (name, use)
        prog = self._programs.get(key)
        if prog is None:
            if isinstance(name, ProgramSpec):
                spec = name
            else:
                spec = ProgramSpec(name, comp=f"{name}.comp") if use else fullscreen(name)
            prog = self.gpu.program(self.owner, spec)
            self._programs[key] = prog
        return prog

    def _free_arrays(self) -> None:
        for c in self._c:
            c.release(self.gpu)
        self._c = []
        for tex in self._phase_tables.values():
            self.gpu.free(tex)
        self._phase_tables = {}
        self._free_readback()

    def _free_readback(self) -> None:
        for slot in self._pbo:
            for buf in slot:
                self.gpu.free(buf)
        self._pbo = []
        self._rb_pending = self._rb_previous = self._rb_latest = None

    def set_spectrum(self, cascades: Sequence, n: int | None = None) -> None:
        """Upload h₀(k), conj h₀(−k), ω(k) and (k_x, k_z) of 1–4 :class:`app.sim.ocean.Cascade`
        (arrays (N, N) in numpy FFT order, [iz, ix]; each cascade's N its own, or all ``n``).
        A cascade's GL objects are re-allocated only when its N changes; its foam is then carried
        into the new grid (same tile), and cleared only when its tile size changed too. A slow
        cascade starts its snapshots over."""
        cascades = list(cascades)
        sizes = [int(n if n is not None else np.shape(c.h0)[-1]) for c in cascades]
        for old in self._c[len(cascades):]:
            old.release(self.gpu)
        del self._c[len(cascades):]
        resized = False
        for i, (c, size) in enumerate(zip(cascades, sizes)):
            old = self._c[i] if i < len(self._c) else None
            if old is None or old.n != size:
                new = _Cascade(self, i, size)
                if old is not None:
                    if old.cascade is not None and old.cascade.patch_size == c.patch_size:
                        self._resample_foam(old, new)
                    old.release(self.gpu)
                    self._c[i] = new
                else:
                    self._c.append(new)
                resized = True
            cg = self._c[i]
            h0 = np.asarray(c.h0, dtype=np.complex128)
            h0m = np.conj(oc._negate_index(h0))
            cg.h0.write(_rgba(h0.real, h0.imag, h0m.real, h0m.imag))
            nu_hi, nu_lo = split_hi_lo(np.asarray(c.omega, dtype=np.float64) / (2.0 * np.pi))
            cg.freq.write(_rgba(nu_hi, nu_lo))
            cg.wave.write(_rgba(c.kx, c.kz))
            cg.cascade = c
            if cg.modes is not None:
                self.gpu.free(cg.modes)
                cg.modes = None
            if cg.snap is not None:
                cg.snap.schedule.t_a = None  # the snapshots are of the old sea
        self.patch_sizes = [float(c.patch_size) for c in cascades]
        if resized:
            self._free_readback()

    def set_refresh(self, periods: Sequence[float]) -> None:
        """Each cascade's snapshot period T [s]: 0 simulates it every frame (the thesis), T > 0
        makes it slow — two snapshots T apart, interpolated (``app/effects/ocean/schedule.py``).
        A changed period starts that cascade's snapshots over."""
        self._require()
        for i, (c, period) in enumerate(zip(self._c, (float(p) for p in periods))):
            if period == 0.0:
                c.drop_snapshots(self.gpu)
            elif c.snap is None:
                steps = 1 + len(c.fft.steps())
                c.snap = _Snapshots(self.gpu, self.owner, i, c.n, SnapshotSchedule(period, steps))
            elif c.snap.schedule.period != period:
                c.snap.schedule = SnapshotSchedule(period, c.snap.schedule.steps)

    def release(self) -> None:
        """Free every GL object this simulation allocated."""
        self._free_arrays()
        for prog in self._programs.values():
            if any(a.obj is prog and a.owner == self.owner for a in self.gpu.allocations):
                self.gpu.free(prog)  # forgets the record; programs stay in the shared library
        self._programs.clear()
        self.patch_sizes = []

    # -- the stages ------------------------------------------------------------------------
    def _require(self) -> None:
        if not self._c:
            raise RuntimeError("GpuOceanSim.set_spectrum(cascades) must be called first")

    @staticmethod
    def _set_spectrum_uniforms(prog, c: _Cascade, t: float, choppiness: float) -> dict:
        """Set the evolution uniforms of cascade ``c``; returns its spectrum textures."""
        t_hi, t_lo = split_hi_lo(float(t))
        prog.set("uTime", (float(t_hi), float(t_lo)))
        prog.set("uChoppiness", choppiness)
        prog.set("uN", c.n)
        return {"uH0": c.h0, "uFrequency": c.freq, "uWaveVector": c.wave}

    def _write_fields(self, prog, c: _Cascade, textures: dict) -> None:
        """Run ``prog`` for cascade ``c``, writing its two field textures (the FFT's data)."""
        prog.bind_textures(textures)
        if self.use_compute:
            c.fft.textures[0].bind_to_image(0, read=False, write=True)
            c.fft.textures[1].bind_to_image(1, read=False, write=True)
            groups = (c.n + LOCAL - 1) // LOCAL
            prog.program.run(groups, groups, 1)
            self.gpu.ctx.memory_barrier()
        else:
            with self.gpu.ctx.scope(c.evolve_fbo, enable_only=moderngl.NOTHING):
                c.evolve_fbo.use()
                draw_fullscreen(prog)

    def _evolve_one(self, c: _Cascade, t: float, lam: float) -> None:
        prog = self._program(EVOLVE)
        self._write_fields(prog, c, self._set_spectrum_uniforms(prog, c, t, lam))

    @staticmethod
    def _stale(c: _Cascade) -> None:
        """A slow cascade's FFT textures were used for something else: its snapshot in
        progress is lost, its plan starts over."""
        if c.snap is not None:
            c.snap.schedule.t_a = None

    def _foam_settings(self, foam_threshold, foam_width):
        thresholds = self._per_cascade(foam_threshold, "ocean.foam_threshold")
        widths = (thresholds if foam_width is None
                  else self._per_cascade(foam_width, "ocean.foam_width"))
        return thresholds, widths

    @staticmethod
    def _decay(dt: float, foam_decay_time: float) -> float:
        dt = float(dt) if (dt == dt and dt > 0) else 0.0
        return math.exp(-dt / foam_decay_time)

    def _finalize_display(self, c: _Cascade, decay: float, threshold: float, width: float,
                          update_foam: bool = True) -> None:
        """Cascade ``c``'s FFT fields into the textures the surface samples (and its foam)."""
        prog = self._program(FINALIZE)
        uniforms = {"uFoamDecay": decay, "uFoamUpdate": 1 if update_foam else 0, "uN": c.n,
                    "uFoamThreshold": threshold, "uFoamWidth": width}
        if self.use_compute:
            prog.set_many(uniforms)
            c.fft.textures[0].bind_to_image(0, read=True, write=False)
            c.fft.textures[1].bind_to_image(1, read=True, write=False)
            c.disp.bind_to_image(2, read=False, write=True)
            c.deriv.bind_to_image(3, read=False, write=True)
            c.foam_pair[0].bind_to_image(4, read=True, write=True)
            groups = (c.n + LOCAL - 1) // LOCAL
            prog.program.run(groups, groups, 1)
            self.gpu.ctx.memory_barrier()
        else:
            src = c.foam_cur
            self._draw(prog, c.out_fbo(self.gpu, self.owner, 1 - src), uniforms,
                       {**self._fields(c), "uFoamBefore": c.foam_pair[src]})
            c.foam_cur = 1 - src

    def _draw(self, prog, fbo, uniforms: dict, textures: dict) -> None:
        """One full-screen pass of ``prog`` into ``fbo``."""
        prog.set_many(uniforms)
        with self.gpu.ctx.scope(fbo, enable_only=moderngl.NOTHING):
            fbo.use()
            prog.bind_textures(textures)
            draw_fullscreen(prog)

    @staticmethod
    def _fields(c: _Cascade) -> dict:
        return {"uFields0": c.fft.textures[0], "uFields1": c.fft.textures[1]}

    @staticmethod
    def _mipmaps(c: _Cascade) -> None:
        c.disp.build_mipmaps()
        c.deriv.build_mipmaps()
        # mip-mapped too: seen from afar, foam must average, not sparkle
        c.foam.filter = MIPMAPPED
        c.foam.build_mipmaps()

    def update(self, t: float, choppiness: float, dt: float, foam_threshold=0.5,
               foam_decay_time: float = 2.0, foam_width=None) -> None:
        """One frame at time t [s]: every cascade evolved, transformed and finalised (foam
        advanced by dt [s]) — or, for a slow cascade, its snapshot plan for this frame and the
        blend of its two snapshots."""
        self._require()
        lam = float(choppiness)
        thresholds, widths = self._foam_settings(foam_threshold, foam_width)
        decay = self._decay(dt, foam_decay_time)
        self.last_work = []
        for c, threshold, width in zip(self._c, thresholds, widths):
            if c.snap is None:
                self._evolve_one(c, t, lam)
                c.fft.inverse()
                self._finalize_display(c, decay, threshold, width)
                self._mipmaps(c)
                self.last_work.append("fft")
            else:
                key = (lam, threshold, width, foam_decay_time)
                plan = c.snap.schedule.plan(float(t), float(dt), key)
                self._run_plan(c, plan, t, dt, lam, threshold, width, foam_decay_time)
                self.last_work.append("snapshots")
        self.time = float(t)

    def _run_plan(self, c: _Cascade, plan: Plan, t: float, dt: float, lam: float,
                  threshold: float, width: float, tau: float) -> None:
        snap = c.snap
        period = snap.schedule.period
        steps = c.fft.steps()
        if plan.reset:
            # A at t from the foam shown so far, B at t + T from A's: both now
            for j, (when, foam_before, foam_dt) in enumerate(
                    ((t, c.foam, dt), (t + period, None, period))):
                self._evolve_one(c, when, lam)
                c.fft.inverse()
                before = foam_before if foam_before is not None else snap.sets[snap.a][2]
                self._finalize_snapshot(c, snap.sets[(snap.a + j) % 2], before,
                                        self._decay(foam_dt, tau), threshold, width)
        for action in plan.actions:
            if action.kind == "step":
                if action.index == 0:
                    self._evolve_one(c, action.time, lam)
                else:
                    steps[action.index - 1]()
            else:  # swap: C into A's set, from B's foam decayed over T
                b = snap.sets[1 - snap.a]
                self._finalize_snapshot(c, snap.sets[snap.a], b[2], self._decay(period, tau),
                                        threshold, width)
                snap.a = 1 - snap.a
        if plan.reset or plan.actions or snap.weight != plan.weight:
            self._blend(c, plan.weight)
            snap.weight = plan.weight

    def _finalize_snapshot(self, c: _Cascade, dest, foam_before, decay: float, threshold: float,
                           width: float) -> None:
        """The FFT fields into a snapshot set (the fragment finalize on either path)."""
        self._draw(self._program(FINALIZE, compute=False), dest[3],
                   {"uFoamDecay": decay, "uFoamUpdate": 1, "uN": c.n,
                    "uFoamThreshold": threshold, "uFoamWidth": width},
                   {**self._fields(c), "uFoamBefore": foam_before})

    def _blend(self, c: _Cascade, weight: float) -> None:
        """The surface's textures of a slow cascade: A + w·(B − A), then their mipmaps."""
        snap = c.snap
        self._blend_into(c, 0 if self.use_compute else 1 - c.foam_cur, BLEND, weight,
                         snap.sets[snap.a], snap.sets[1 - snap.a])

    def _resample_foam(self, old: _Cascade, new: _Cascade) -> None:
        """``old``'s foam (same tile, another N) into ``new``'s current foam texture."""
        held = (old.disp, old.deriv, old.foam)
        self._blend_into(new, new.foam_cur, RESAMPLE, 0.0, held, held)

    def _blend_into(self, c: _Cascade, j: int, spec: ProgramSpec, weight: float, a, b) -> None:
        """``spec`` over the (displacement, derivatives, foam) textures ``a`` and ``b`` into
        ``c``'s textures with foam ``foam_pair[j]``, then their mipmaps."""
        self._draw(self._program(spec), c.out_fbo(self.gpu, self.owner, j),
                   {"uWeight": float(weight), "uN": c.n},
                   {"uDispA": a[0], "uDispB": b[0], "uDerivA": a[1], "uDerivB": b[1],
                    "uFoamA": a[2], "uFoamB": b[2]})
        c.foam_cur = j
        self._mipmaps(c)

    def _per_cascade(self, value, what: str) -> list[float]:
        if isinstance(value, (int, float)):
            return [float(value)] * self.cascade_count
        values = [float(v) for v in value]
        if len(values) != self.cascade_count:
            raise ParamError(f"{what}: {len(values)} values for {self.cascade_count} cascades")
        return values

    # -- direct summation (bench reference) ------------------------------------------------
    def _build_modes(self, i: int, c: _Cascade) -> None:
        n = c.n
        nyquist = np.zeros((n, n), dtype=bool)
        nyquist[n // 2, :] = nyquist[:, n // 2] = True
        cascade = c.cascade
        h0 = np.asarray(cascade.h0, dtype=np.complex128)
        h0m = np.conj(oc._negate_index(h0))
        iz, ix = np.nonzero(((h0 != 0) | (h0m != 0)) & ~nyquist)
        count = len(ix)
        width = max(1, min(count, MODE_ROW))
        rows = max(1, -(-count // width))
        data = np.zeros((rows * width, 3, 4), dtype=np.float32)
        nu_hi, nu_lo = split_hi_lo(np.asarray(cascade.omega, dtype=np.float64)[iz, ix]
                                   / (2.0 * np.pi))
        data[:count, 0] = np.stack([h0.real[iz, ix], h0.imag[iz, ix],
                                    h0m.real[iz, ix], h0m.imag[iz, ix]], -1)
        data[:count, 1] = np.stack([np.asarray(cascade.kx)[iz, ix],
                                    np.asarray(cascade.kz)[iz, ix], nu_hi, nu_lo], -1)
        data[:count, 2, 0] = ix
        data[:count, 2, 1] = iz
        tex = self.gpu.texture(self.owner, f"ocean direct-sum modes {i}", (3 * width, rows), 4,
                               data=data.reshape(rows, width * 3, 4).tobytes(), dtype="f4",
                               filter=NEAREST)
        tex.extra = {"modes": count, "width": width}
        c.modes = tex
        c.objects.append(tex)
        if n not in self._phase_tables:
            self._phase_tables[n] = self.gpu.texture(
                self.owner, f"ocean direct-sum phases {n}", (n, 1), 2,
                data=twiddle_table(n, n).tobytes(), dtype="f4", filter=NEAREST)

    def _modes_of(self, i: int, c: _Cascade):
        if c.modes is None:
            self._build_modes(i, c)
        return c.modes

    def mode_counts(self) -> list[int]:
        """Non-zero modes per cascade (what :meth:`direct_sum` sums over)."""
        self._require()
        return [self._modes_of(i, c).extra["modes"] for i, c in enumerate(self._c)]

    def direct_sum(self, t: float, choppiness: float) -> None:
        """The same fields by direct summation over every non-zero mode (no FFT), written into
        the same ``disp``/``deriv`` textures; foam is carried over unchanged.

        Cost O(N²·modes) per cascade — a reference for benches at N ≤ 128, not a renderer."""
        self._require()
        lam = float(choppiness)
        prog = self._program(DIRECT_SUM)
        for i, c in enumerate(self._c):
            tex = self._modes_of(i, c)
            textures = self._set_spectrum_uniforms(prog, c, t, lam)
            prog.set("uModeCount", tex.extra["modes"])
            prog.set("uModeWidth", tex.extra["width"])
            self._write_fields(prog, c, {**textures, "uModes": tex,
                                         "uPhaseTable": self._phase_tables[c.n]})
            self._finalize_display(c, 1.0, 0.5, 0.5, update_foam=False)
            self._mipmaps(c)
            self._stale(c)
        self.time = float(t)

    # -- reading back ----------------------------------------------------------------------
    def read_fields(self, i: int) -> dict[str, np.ndarray]:
        """Synchronous readback of cascade i (stalls the GPU; for tests and tools): float32
        arrays [iz, ix] ``height, disp_x, disp_z, jacobian, slope_x, slope_z, ddx_dx, ddz_dz,
        ddx_dz, foam`` (displacements and their derivatives already times λ). ``ddx_dz`` is
        read from the FFT's output, which a slow cascade uses for its next snapshot: NaN there."""
        self._require()
        c = self._c[i]
        n = c.n
        disp = np.frombuffer(c.disp.read(level=0), dtype=np.float32).reshape(n, n, 4)
        deriv = np.frombuffer(c.deriv.read(level=0), dtype=np.float32).reshape(n, n, 4)
        foam = np.frombuffer(c.foam.read(level=0), dtype=np.float32).reshape(n, n)
        ddx_dz = (np.full((n, n), np.nan, dtype=np.float32) if c.snap is not None
                  else c.fft.read(1)[..., 3].copy())
        return {
            "height": disp[..., 1].copy(), "disp_x": disp[..., 0].copy(),
            "disp_z": disp[..., 2].copy(),
            "jacobian": disp[..., 3].copy(),
            "slope_x": deriv[..., 0].copy(), "slope_z": deriv[..., 1].copy(),
            "ddx_dx": deriv[..., 2].copy(), "ddz_dz": deriv[..., 3].copy(),
            "ddx_dz": ddx_dz,
            "foam": foam.copy(),
        }

    def request_readback(self) -> None:
        """Queue an asynchronous copy of level 0 of every ``disp`` texture (λD_x, η, λD_z, J)
        into pixel-pack buffers, remembering the simulation time (spec/000 §1.3: buoyancy reads
        the water on the CPU through an asynchronous readback)."""
        self._require()
        if not self._pbo:
            self._pbo = [[self.gpu.buffer(self.owner, f"ocean readback {slot}.{i}",
                                          bytes(c.n * c.n * 16))
                          for i, c in enumerate(self._c)] for slot in range(2)]
        slot = self._rb_next
        self._rb_next = 1 - slot
        for c, buf in zip(self._c, self._pbo[slot]):
            c.disp.read_into(buf, level=0)
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
        grids = [np.frombuffer(buf.read(), dtype=np.float32).reshape(c.n, c.n, 4)
                 for c, buf in zip(self._c, self._pbo[slot])]
        # one (C, N, N, 4) array when the cascades share N: the height queries gather from
        # every cascade at once
        arrays = np.stack(grids) if len({g.shape for g in grids}) == 1 else tuple(grids)
        self._rb_latest = (t, arrays)
        self._rb_previous = None
        return self._rb_latest

    def poll_readback(self):
        """``(time, arrays)`` of the most recent request *before* the newest one, or None until
        there is one: arrays is one (C, N, N, 4) float32 array when every cascade has the same
        N, else a tuple of each cascade's (N_i, N_i, 4) grid.

        One frame of lag, by design: the newest request's copy may still be queued behind this
        frame's work, so it is left alone; the previous request's buffers were filled a frame
        ago and map without stalling.  Calling again without a new request returns the same
        result.  Arrays are indexed [iz, ix] with channels (λD_x, η, λD_z, J)."""
        if self._rb_previous is not None:
            self._map(*self._rb_previous)
        return self._rb_latest

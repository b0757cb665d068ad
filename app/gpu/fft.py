"""Inverse 2D FFT on the GPU for the Tessendorf ocean (spec/000 §1.1(d); ``app/sim/ocean.py``
is its numpy twin).

``GpuFFT(gpu, owner, n, count=2)`` owns ``count`` N×N RGBA32F textures (``textures``); each
texel holds two complex numbers (re0, im0, re1, im1) in numpy FFT order, indexed [iz, ix]
(texel x = ix, texel y = iz).  :meth:`GpuFFT.inverse` replaces their contents with

    out[m_z, m_x] = Σ_{k_z, k_x} in[k_z, k_x]·e^{+2πi·(k_x·m_x + k_z·m_z)/N}

which is ``N²·numpy.fft.ifft2`` of each complex channel pair — rows (along x) first, then
columns.  N is a power of two in [4, 1024].

Two paths, picked by ``use_compute`` (``None`` → ``gpu.caps.compute``):

* **compute** (GL ≥ 4.3, ``glsl/ocean/fft_radix2.comp``): one dispatch per axis and texture;
  a work group of N/2 invocations transforms one whole row in shared memory (radix-2
  decimation in time, in place after a bit-reversed load, one barrier per stage).  The
  transform is in place in the textures.
* **fragment** (GL 3.3, ``glsl/ocean/fft_stage.frag``): one full-screen pass per radix-2
  Stockham stage, all ``count`` textures at once through MRT, ping-ponging with scratch
  textures; 2·log2 N passes — an even number, so the result is back in ``textures``.

Twiddles e^{+2πi·m/N} (m < N/2) are computed in float64 on the CPU from the integer m and
stored in an N/2 × 1 RG32F texture: no sin/cos of a large float32 angle anywhere.  Rounding
grows like log2 N·ε_f32·rms (about 1e-7 relative at N = 256, as the GPU ocean tests check).
"""

from __future__ import annotations

import math
from functools import partial
from typing import Callable

import moderngl
import numpy as np

from ..errors import ParamError
from .programs import ProgramSpec, draw_fullscreen, fullscreen

MIN_N = 4
MAX_N = 1024
MAX_COUNT = 8  # MRT attachments every GL 3.3 implementation offers

FFT_COMPUTE = "ocean/fft_radix2"
FFT_STAGE = "ocean/fft_stage"


def compute_spec(n: int) -> ProgramSpec:
    """The compute FFT's program for an n × n transform."""
    return ProgramSpec(FFT_COMPUTE, comp=f"{FFT_COMPUTE}.comp", requires_compute=True,
                       defines=(("FFT_N", n), ("FFT_HALF_N", n // 2),
                                ("FFT_LOG2N", int(math.log2(n)))))


def fragment_spec(count: int) -> ProgramSpec:
    """The fragment FFT's butterfly pass over ``count`` textures at once."""
    return fullscreen(FFT_STAGE, defines=(("FFT_COUNT", count),))


#: every program a GpuFFT may build (each size, each count): ``natura shaders check`` and its
#: ``--strict`` pass compile exactly what the app can ask for
VARIANTS = (tuple(compute_spec(1 << k) for k in range(MIN_N.bit_length() - 1,
                                                      MAX_N.bit_length()))
            + tuple(fragment_spec(c) for c in range(1, MAX_COUNT + 1)))


def choose_compute(caps, setting: str, what: str) -> bool:
    """A path setting ``auto | compute | fragment`` on a context: auto is compute on a GPU that
    has compute shaders and the fragment passes on a software renderer (llvmpipe runs image
    stores 2–3× slower than the same work as fragment passes) or before GL 4.3; compute on a
    context without it is a one-line ParamError naming ``what``."""
    if setting == "auto":
        return caps.compute and not caps.software
    if setting == "compute" and not caps.compute:
        raise ParamError(f"{what}=compute: compute shaders need GL ≥ 4.3, "
                         f"this context is {caps.describe()}: allowed auto or fragment")
    return setting == "compute"


def resolve_compute(gpu, use_compute: bool | None, what: str) -> bool:
    """None → whether the context has compute shaders; True on a context without them → a
    one-line ParamError naming ``what``."""
    chosen = gpu.caps.compute if use_compute is None else bool(use_compute)
    if chosen and not gpu.caps.compute:
        raise ParamError(f"{what}: compute shaders need GL ≥ 4.3, "
                         f"this context is {gpu.caps.describe()}")
    return chosen


def check_fft_size(n, what: str = "ocean.fft_size") -> int:
    """``n`` as an int if it is a power of two in [4, 1024]; a one-line ParamError otherwise."""
    ok = isinstance(n, (int, np.integer)) and not isinstance(n, bool)
    if not ok or not (MIN_N <= int(n) <= MAX_N) or int(n) & (int(n) - 1):
        raise ParamError(f"{what}: {n!r} is not allowed: a power of two in [{MIN_N}, {MAX_N}]")
    return int(n)


def twiddle_table(n: int, length: int | None = None) -> np.ndarray:
    """(length, 2) float32 table of e^{+2πi·m/N}, m = 0 … length−1 (default N/2), built in
    float64."""
    m = np.arange(n // 2 if length is None else length, dtype=np.float64)
    angle = 2.0 * np.pi * m / n
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1).astype(np.float32)


class GpuFFT:
    """In-place inverse 2D FFT of ``count`` N×N RGBA32F textures (two complex numbers a texel)."""

    def __init__(self, gpu, owner: str, n: int, count: int = 2, use_compute: bool | None = None):
        self.n = check_fft_size(n)
        if not isinstance(count, (int, np.integer)) or not 1 <= int(count) <= MAX_COUNT:
            raise ParamError(f"fft.count: {count!r} is outside the allowed range [1, {MAX_COUNT}]")
        self.count = int(count)
        self.gpu = gpu
        self.owner = owner
        self.use_compute = resolve_compute(gpu, use_compute, "fft.use_compute")
        self.log2n = int(math.log2(self.n))
        self._objects: list = []
        self._programs: list = []
        nearest = (moderngl.NEAREST, moderngl.NEAREST)
        size = (self.n, self.n)
        self.textures = [self._own(gpu.texture(owner, f"fft data {i}", size, 4, dtype="f4",
                                               filter=nearest))
                         for i in range(self.count)]
        self.twiddles = self._own(gpu.texture(owner, "fft twiddles", (self.n // 2, 1), 2,
                                              data=twiddle_table(self.n).tobytes(), dtype="f4",
                                              filter=nearest))
        if self.use_compute:
            self._prog = gpu.program(owner, compute_spec(self.n))
            self._scratch = []
            self._fbos = []
        else:
            self._prog = gpu.program(owner, fragment_spec(self.count))
            self._scratch = [self._own(gpu.texture(owner, f"fft scratch {i}", size, 4, dtype="f4",
                                                   filter=nearest))
                             for i in range(self.count)]
            self._fbos = [self._own(gpu.framebuffer(owner, "fft data", self.textures)),
                          self._own(gpu.framebuffer(owner, "fft scratch", self._scratch))]
        self._programs.append(self._prog)

    def _own(self, obj):
        self._objects.append(obj)
        return obj

    @property
    def path(self) -> str:
        return "compute" if self.use_compute else "fragment"

    def read(self, index: int) -> np.ndarray:
        """(N, N, 4) float32 contents of texture ``index``, indexed [iz, ix]."""
        raw = self.textures[index].read()
        return np.frombuffer(raw, dtype=np.float32).reshape(self.n, self.n, 4).copy()

    def inverse(self) -> None:
        """Replace every texture by its unnormalised inverse 2D FFT (N²·ifft2)."""
        if self.use_compute:
            self._inverse_compute()
        else:
            self._inverse_fragment()

    def steps(self) -> list[Callable[[], None]]:
        """The same transform as :meth:`inverse`, cut into steps to run in order, each setting
        every state it needs (other GL work may come between two of them, in other frames): one
        per radix-2 pass on the fragment path (2·log2 N), one per axis and texture on the
        compute path. The textures must not be touched by anything else until the last step."""
        if self.use_compute:
            return [partial(self._compute_step, axis, tex)
                    for axis in (0, 1) for tex in self.textures]
        return [partial(self._fragment_step, axis, stage)
                for axis in (0, 1) for stage in range(self.log2n)]

    def _compute_step(self, axis: int, tex) -> None:
        prog = self._prog
        prog.bind_textures({"uTwiddle": self.twiddles})
        prog.set("uAxis", axis)
        tex.bind_to_image(0, read=True, write=True)
        prog.program.run(self.n, 1, 1)
        self.gpu.ctx.memory_barrier()

    def _fragment_step(self, axis: int, stage: int) -> None:
        # pass p = axis·log2 N + stage reads set p mod 2 and writes the other (as inverse())
        src = (axis * self.log2n + stage) % 2
        sets = [self.textures, self._scratch]
        prog = self._prog
        with self.gpu.ctx.scope(self._fbos[1 - src], enable_only=moderngl.NOTHING):
            self._fbos[1 - src].use()
            prog.set("uN", self.n)
            prog.set("uAxis", axis)
            prog.set("uSpan", 1 << stage)
            prog.bind_textures({**{f"uSrc{i}": tex for i, tex in enumerate(sets[src])},
                                "uTwiddle": self.twiddles})
            draw_fullscreen(prog)

    def _inverse_compute(self) -> None:
        ctx = self.gpu.ctx
        prog = self._prog
        prog.bind_textures({"uTwiddle": self.twiddles})
        for axis in (0, 1):
            prog.set("uAxis", axis)
            for tex in self.textures:
                tex.bind_to_image(0, read=True, write=True)
                prog.program.run(self.n, 1, 1)
            ctx.memory_barrier()

    def _inverse_fragment(self) -> None:
        ctx = self.gpu.ctx
        prog = self._prog
        sets = [self.textures, self._scratch]
        src = 0
        with ctx.scope(self._fbos[1], enable_only=moderngl.NOTHING):
            prog.set("uN", self.n)
            for axis in (0, 1):
                prog.set("uAxis", axis)
                for stage in range(self.log2n):
                    dst = 1 - src
                    self._fbos[dst].use()
                    prog.bind_textures({**{f"uSrc{i}": tex for i, tex in enumerate(sets[src])},
                                        "uTwiddle": self.twiddles})
                    prog.set("uSpan", 1 << stage)
                    draw_fullscreen(prog)
                    src = dst
        assert src == 0  # 2·log2 N passes: the result is back in self.textures

    def release(self) -> None:
        for obj in reversed(self._objects):
            self.gpu.free(obj)
        self._objects.clear()
        for prog in self._programs:
            if any(a.obj is prog and a.owner == self.owner for a in self.gpu.allocations):
                self.gpu.free(prog)  # forgets the record; programs stay in the shared library
        self._programs.clear()
        self.textures = []

"""Baking a GLSL function into a 3D texture: a compute shader where GL ≥ 4.3, otherwise one
fragment pass per z slice read back into the volume (macOS GL 4.1 still works).

A bake is a pair of programs whose sources define ``vec4 BakeValue(vec3 uvw)`` and include
``bake3d_compute.glsl`` (compute) or ``bake3d_fragment.glsl`` (full-screen fragment).

Progress: the fragment path reports after each slice; the compute path dispatches the volume
in chunks of ``chunk_slices`` z slices (uniform ``uBakeZOffset``) with a ``finish()`` after each,
and reports after each chunk. Without ``chunk_slices`` the compute path is one dispatch, unless
a progress callback is given — then it picks about 16 chunks (see :func:`compute_chunks`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .programs import ProgramSpec, draw_fullscreen


@dataclass
class BakeResult:
    texture: object  # moderngl.Texture3D
    seconds: float
    path: str  # "compute" or "fragment"


#: The work group size of bake3d_compute.glsl.
LOCAL_SIZE = (8, 8, 1)


def compute_chunks(depth: int, chunk_slices: int | None, progress: bool) -> list[tuple[int, int]]:
    """(first slice, slice count) of each compute dispatch: one chunk unless ``chunk_slices``
    is given, or about 16 chunks when progress is wanted."""
    if chunk_slices is None:
        chunk_slices = depth if not progress else -(-depth // 16)
    group = LOCAL_SIZE[2]
    chunk = max(group, -(-int(chunk_slices) // group) * group)
    return [(z, min(chunk, depth - z)) for z in range(0, depth, chunk)]


def bake_volume(gpu, owner: str, name: str, size: tuple[int, int, int], compute: ProgramSpec,
                fragment: ProgramSpec, setup: Callable[[object], None],
                use_compute: bool | None = None,
                progress: Callable[[float], None] | None = None,
                chunk_slices: int | None = None) -> BakeResult:
    """Bake into a new RGBA32F 3D texture of ``size`` (linear filtering, repeat).

    ``progress(fraction)`` is called after each slice (fragment) or chunk of ``chunk_slices``
    slices (compute; see the module doc)."""
    ctx = gpu.ctx
    size = (int(size[0]), int(size[1]), int(size[2]))
    if use_compute is None:
        use_compute = gpu.caps.compute
    tex = gpu.texture3d(owner, name, size, 4, dtype="f4")
    ctx.finish()
    t0 = time.perf_counter()
    if use_compute:
        prog = gpu.program(owner, compute)
        setup(prog)
        prog.set("uBakeSize", size)
        tex.bind_to_image(0, read=False, write=True)
        gx, gy = [-(-s // n) for s, n in zip(size[:2], LOCAL_SIZE[:2])]
        chunks = compute_chunks(size[2], chunk_slices, progress is not None)
        for first, count in chunks:
            prog.set("uBakeZOffset", first)
            prog.program.run(gx, gy, -(-count // LOCAL_SIZE[2]))
            if len(chunks) > 1:
                ctx.finish()  # the fraction means work done, not work queued
            if progress:
                progress((first + count) / size[2])
        ctx.memory_barrier()
    else:
        prog = gpu.program(owner, fragment)
        setup(prog)
        prog.set("uBakeSize", size)
        with gpu.scratch_target(owner, f"{name} slice", size[:2], depth=False) as target:
            for z in range(size[2]):
                target.use()
                prog.set("uBakeSlice", z)
                draw_fullscreen(prog)
                data = target.fbo.read(components=4, dtype="f4")
                tex.write(data, viewport=(0, 0, z, size[0], size[1], 1))
                if progress:
                    progress((z + 1) / size[2])
    ctx.finish()
    return BakeResult(tex, time.perf_counter() - t0, "compute" if use_compute else "fragment")


def read_volume(texture) -> np.ndarray:
    """(depth, height, width, 4) float32 contents of an RGBA32F 3D texture."""
    w, h, d = texture.size
    return np.frombuffer(texture.read(), dtype=np.float32).reshape(d, h, w, 4)

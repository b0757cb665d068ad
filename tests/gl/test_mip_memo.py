"""app.gpu.cache.build_mipmaps: the levels the driver generated for one texture are defined
from bytes for the next of the same content, format and driver — bit-identical levels and the
GL state moderngl's build_mipmaps leaves."""

from __future__ import annotations

import ctypes
import os
import subprocess
import sys
from pathlib import Path

import moderngl
import numpy as np
import pytest

from app.gpu.cache import MEMO, _levels, build_mipmaps
from app.gpu.rawgl import gl_function

_FORMATS = {1: 0x1903, 2: 0x8227, 3: 0x1907, 4: 0x1908}
_TYPES = {"f1": (0x1401, 1), "f2": (0x140B, 2), "f4": (0x1406, 4)}


def _state(ctx, tex, target, image=None):
    """Every level's bytes (raw glGetTexImage of ``image``, default ``target``) and (base
    level, max level, min, mag filter)."""
    get = gl_function(ctx, "glGetTexImage", ctypes.c_uint, ctypes.c_int, ctypes.c_uint,
                      ctypes.c_uint, ctypes.c_void_p)
    param = gl_function(ctx, "glGetTexParameteriv", ctypes.c_uint, ctypes.c_uint,
                        ctypes.POINTER(ctypes.c_int))
    store = gl_function(ctx, "glPixelStorei", ctypes.c_uint, ctypes.c_int)
    tex.use(location=ctx.default_texture_unit)
    store(0x0D05, 1)
    kind, size = _TYPES[tex.dtype]
    levels = []
    for level, dims in enumerate(_levels(tex.size)):
        buf = ctypes.create_string_buffer(int(np.prod(dims)) * size * tex.components)
        get(image or target, level, _FORMATS[tex.components], kind, buf)
        levels.append(buf.raw)
    value = ctypes.c_int()
    state = []
    for name in (0x813C, 0x813D, 0x2801, 0x2800):
        param(target, name, ctypes.byref(value))
        state.append(value.value)
    return levels, state


@pytest.mark.parametrize("size,components,dtype", [((64, 32), 4, "f1"), ((20, 12), 3, "f1"),
                                                   ((16, 16), 4, "f4"), ((8, 4), 1, "f2")])
def test_remembered_levels_are_the_drivers_own(gl_ctx, size, components, dtype):
    _ = gl_ctx.error  # an error an earlier test left is not this one's
    rng = np.random.default_rng(size[0] * 7 + components * 3 + len(dtype))
    data = rng.random((size[1], size[0], components))
    data = (data * 255).astype(np.uint8) if dtype == "f1" else data.astype(
        np.float16 if dtype == "f2" else np.float32)
    reference = gl_ctx.texture(size, components, data.tobytes(), dtype=dtype)
    reference.build_mipmaps()
    first = gl_ctx.texture(size, components, data.tobytes(), dtype=dtype)
    build_mipmaps(first)  # generated (or, on a rerun, remembered)
    hits = MEMO.hits
    second = gl_ctx.texture(size, components, data.tobytes(), dtype=dtype)
    build_mipmaps(second)  # remembered: defined from bytes
    assert MEMO.hits == hits + 1
    want = _state(gl_ctx, reference, 0x0DE1)
    assert _state(gl_ctx, first, 0x0DE1) == want
    assert _state(gl_ctx, second, 0x0DE1) == want
    assert second.filter == reference.filter == (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    assert gl_ctx.error == "GL_NO_ERROR"
    for tex in (reference, first, second):
        tex.release()


def test_a_3d_texture_too(gl_ctx):
    _ = gl_ctx.error
    data = np.random.default_rng(4).random((8, 8, 8, 4)).astype(np.float32)
    reference = gl_ctx.texture3d((8, 8, 8), 4, data.tobytes(), dtype="f4")
    reference.build_mipmaps()
    texs = [gl_ctx.texture3d((8, 8, 8), 4, data.tobytes(), dtype="f4") for _ in range(2)]
    for tex in texs:
        build_mipmaps(tex)
    want = _state(gl_ctx, reference, 0x806F)
    assert all(_state(gl_ctx, tex, 0x806F) == want for tex in texs)
    assert gl_ctx.error == "GL_NO_ERROR"
    for tex in (reference, *texs):
        tex.release()


def test_a_cubemap_too(gl_ctx):
    _ = gl_ctx.error
    rng = np.random.default_rng(9)
    faces = [rng.random((16, 16, 4)).astype(np.float16) for _ in range(6)]

    def cube():
        tex = gl_ctx.texture_cube((16, 16), 4, dtype="f2")
        for face, data in enumerate(faces):
            tex.write(face, data.tobytes())
        return tex

    reference = cube()
    reference.build_mipmaps()
    texs = [cube() for _ in range(2)]
    for tex in texs:
        build_mipmaps(tex)
    for face in range(6):
        want = _state(gl_ctx, reference, 0x8513, 0x8515 + face)
        assert all(_state(gl_ctx, tex, 0x8513, 0x8515 + face) == want for tex in texs)
    assert gl_ctx.error == "GL_NO_ERROR"
    for tex in (reference, *texs):
        tex.release()


@pytest.mark.slow  # a pytest process of its own: ~3 s idle, more beside another worker
def test_levels_read_back_after_a_busy_context_are_the_textures_own(tmp_path):
    """The sequence that once remembered zeros: this module's tests, then the planet's
    surfaces in the same process (on llvmpipe, glGetTexImage of a level just generated read
    zeros for some levels, no error; every later planet session then sampled black albedo —
    the flat normal map test failed 6 runs of 6). build_mipmaps waits for the GPU before it
    reads the levels back: the same sequence passes."""
    root = Path(__file__).resolve().parents[2]
    env = {**os.environ, "NATURA_CACHE": str(tmp_path / "cache")}
    env.pop("PYTEST_XDIST_WORKER", None)
    proc = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-n", "0", "-p", "no:cacheprovider",
         f"--basetemp={tmp_path / 'run'}",
         "tests/gl/test_mip_memo.py::test_remembered_levels_are_the_drivers_own",
         "tests/gl/test_mip_memo.py::test_a_3d_texture_too",
         "tests/gl/test_mip_memo.py::test_a_cubemap_too", "tests/gl/test_planet_surfaces.py"],
        cwd=root, env=env, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-1000:]
    assert " passed" in proc.stdout and "failed" not in proc.stdout

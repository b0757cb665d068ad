"""The shared GPU helpers (app/gpu): textures bound by sampler name, uniform arrays, the float
colour copy, and the stage an effect picks per frame (the ocean above and under the water)."""

from __future__ import annotations

import moderngl
import numpy as np
import pytest

from app.frame import Stage
from app.gpu.copy import ColourCopy
from app.gpu.programs import ProgramSpec, draw_fullscreen, fullscreen
from app.runtime import open_session, render_frames, scene_params
from app.sim.camera import Camera


def test_textures_are_bound_by_sampler_name_and_every_sampler_gets_its_own_unit(gpu):
    prog = gpu.program("test", fullscreen("noise/noise_view"))
    samplers = prog.samplers()
    assert {"uVolume", "uMap", "uValueNoiseTex", "uPerlinPermutation"} <= set(samplers)
    tex = gpu.texture("test", "map", (2, 2), 4)
    prog.bind_textures({"uMap": tex, "uRemovedByTheCompiler": tex, "uVolume": None})
    units = [prog.program[name].value for name in samplers]
    assert prog.program["uMap"].value == 0, "the given texture takes the first unit"
    assert sorted(units) == list(range(len(samplers))), "one unit each, bound or not"


def test_uniform_arrays_are_padded_and_clipped(gpu):
    prog = gpu.program("test", ProgramSpec("ocean/surface"))
    length = prog.program["uGerstnerA"].array_length
    prog.set_array("uGerstnerA", [(1, 2, 3, 4)] * (length + 3))
    data = np.frombuffer(prog.program["uGerstnerA"].read(), dtype="f4").reshape(-1, 4)
    assert data.shape == (length, 4) and np.all(data == (1, 2, 3, 4))
    prog.set_array("uGerstnerA", [(5, 6, 7, 8)])
    data = np.frombuffer(prog.program["uGerstnerA"].read(), dtype="f4").reshape(-1, 4)
    assert np.all(data[0] == (5, 6, 7, 8)) and np.all(data[1:] == 0)
    prog.set_array("uNoSuchArray", [(1, 2, 3, 4)])  # tolerated, like set()


def test_the_colour_copy_keeps_float_radiance_and_follows_the_size(gpu):
    target = gpu.target("test", "t", (8, 4))
    target.clear((7.5, 0.25, 1e-4, 1.0))
    copy = ColourCopy(gpu, "test", "copy")
    tex = copy.of(target)
    got = np.frombuffer(tex.read(), dtype="f4").reshape(4, 8, 4)
    assert np.allclose(got[..., :3], (7.5, 0.25, 1e-4)), "no 8-bit clamp"
    assert copy.of(target) is tex
    bigger = gpu.target("test", "t2", (16, 4))
    assert copy.of(bigger) is not tex and copy.texture.size == (16, 4)
    copy.release()
    assert not [a for a in gpu.owned_by("test") if a.name == "copy"]


def test_the_full_screen_draw_covers_the_target(gpu):
    prog = gpu.program("test", fullscreen("common/constant"))
    target = gpu.target("test", "t", (5, 3))
    target.use()
    prog.set("uColor", (0.25, 0.5, 2.0, 1.0))
    gpu.ctx.disable(moderngl.DEPTH_TEST)
    draw_fullscreen(prog)
    assert np.allclose(target.read()[..., :3], (0.25, 0.5, 2.0))


@pytest.mark.parametrize("height, stage", [(4.0, Stage.WATER), (-3.0, Stage.FOG), (0.1, Stage.FOG)])
def test_the_ocean_picks_its_stage_by_where_the_camera_is(gl_ctx, height, stage):
    small = ["clouds_b.volume_resolution=16", "clouds_b.detail_resolution=8",
             "clouds_b.gradient_resolution=16"]
    params = scene_params("ocean", sets=["ocean.model=sine", "scene.clouds=b", *small])
    camera = Camera(position=(0.0, height, 0.0), pitch=10.0)
    session = open_session("ocean", params, ctx=gl_ctx, camera=camera)
    try:
        next(render_frames(session, (32, 18)))
        target = session.gpu.target("test", "t", (32, 18))
        frame = session.scene.last_frame
        order = [p.name for p in session.scene.passes(frame, target)]
        ocean = session.scene.effect("ocean")
        assert ocean.surface.stage() == stage
        clouds = order.index("clouds_b.march")
        assert (order.index("ocean.surface") < clouds) == (stage == Stage.WATER), order
        assert frame.water is ocean.queries and frame.environment is not None
    finally:
        session.release()


def _vertex_arrays(gpu) -> int:
    """How many vertex arrays the programs hold (cached by ``Program.vao``)."""
    return sum(len(prog._vaos) for prog in gpu.shaders.programs())


def test_freeing_a_buffer_releases_the_vertex_arrays_cached_for_it(gpu):
    """A deleted buffer still attached to a vertex array keeps its storage in the driver, so
    ``Gpu.free`` releases every array a program cached for the buffer (vertex or index): a
    mesh rebuilt on each live change (the village's terrain on ``village.resolution``) held
    ~3.5 MB a change, without bound, through the arrays of its old buffers."""
    caster = gpu.program("test", ProgramSpec("common/shadow_caster"))
    other = gpu.program("test", ProgramSpec("village/surface"))
    fmt = ("3f 3f 2f", "in_position", "in_normal", "in_uv")
    kept = gpu.buffer("test", "kept", bytes(32 * 3))
    for _ in range(20):
        vbo = gpu.buffer("test", "mesh", bytes(32 * 3))
        ibo = gpu.buffer("test", "indices", np.arange(3, dtype="u4").tobytes())
        arrays = [caster.vao([(vbo, *fmt)], ibo), other.vao([(vbo, *fmt)], ibo),
                  caster.vao([(kept, *fmt)], ibo)]
        gpu.free(vbo)
        assert _vertex_arrays(gpu) == 1, "the kept buffer's array stays until its indices go"
        gpu.free(ibo)
        assert all(isinstance(a.mglo, moderngl.InvalidObject) for a in arrays)
        assert _vertex_arrays(gpu) == 0
    lasting = caster.vao([(kept, *fmt)])
    assert caster.vao([(kept, *fmt)]) is lasting and _vertex_arrays(gpu) == 1
    assert [a.name for a in gpu.owned_by("test") if a.kind == "buffer"] == ["kept"]

"""The amortised layer (app/render/amortise.py, glsl/common/amortise_resolve.frag) on a probe with
a known answer (glsl/tests/amortise_probe.frag): the resolve against its numpy twins
(app.sim.amortise.fill), depth-aware filling across a synthetic depth edge and a thin "mast",
convergence to the full-resolution march, and the rejection of a disoccluded history."""

from __future__ import annotations

import numpy as np
import pytest

from app.frame import FrameContext
from app.gpu.programs import draw_fullscreen, fullscreen
from app.render.amortise import Amortiser
from app.sim.amortise import LayerState, Schedule, block_position, fill, fill_nearest
from app.sim.camera import Camera
from tests.helpers.images import read_aux

PROBE = fullscreen("tests/amortise_probe")
SIZE = (37, 23)  # not a multiple of any block: the last grid rows and columns lie off the image
OPAQUE = 500.0   # the probe's "object in front of the layer" distance, metres
NEAR_DEPTH = 0.9  # window depth of the near object (a few metres away)
EDGE = 17  # columns < EDGE: the near object
MAST = (28, 29)  # a 2-pixel-wide near column on the far side


def camera() -> Camera:
    return Camera(position=(0.0, 2.0, 0.0), yaw=0.0, pitch=10.0, fov=60.0, far=200000.0)


def depth_image(mast=MAST) -> np.ndarray:
    """Window depth, rows in GL order (row 0 at the bottom): a near block, far sky, a mast."""
    d = np.ones((SIZE[1], SIZE[0]), dtype=np.float32)
    d[:, :EDGE] = NEAR_DEPTH
    d[:, mast[0]:mast[1] + 1] = NEAR_DEPTH
    return d


class ProbeRig:
    def __init__(self, gpu):
        self.gpu = gpu
        self.amortiser = Amortiser(gpu, "test-amortise")
        self.target = gpu.target("test-amortise", "scene", SIZE)
        self.cam = camera()
        self.set_depth(depth_image())

    def set_depth(self, d: np.ndarray) -> None:
        self.target.depth.write(np.ascontiguousarray(d, dtype="f4").tobytes())

    def march(self, grid) -> None:
        prog = self.gpu.program("test-amortise", PROBE)
        prog.bind_textures({"uSceneDepth": self.target.depth, **grid.textures})
        prog.set_many(self.cam.uniforms(SIZE[0] / SIZE[1]))
        prog.set_many({"uCamNear": float(self.cam.near), "uCamFar": float(self.cam.far),
                       "uProbeOpaque": OPAQUE, **grid.uniforms})
        grid.use()
        self.gpu.ctx.disable(self.gpu.ctx.DEPTH_TEST | self.gpu.ctx.BLEND)
        draw_fullscreen(prog)

    def step(self, schedule, interactive=False, near=0.0):
        frame = FrameContext(size=SIZE, camera=self.cam, time=0.0, interactive=interactive)
        state = LayerState(key=(0,), light_dir=np.array([0.0, 1.0, 0.0]),
                           light_radiance=np.ones(3), wind=np.zeros(3),
                           field_offset=np.zeros(3), near=near, far=1.0e5)
        self.target.depth.compare_func = ""
        return self.amortiser.step(frame, SIZE, schedule, state, self.march, self.target.depth)

    def full(self) -> np.ndarray:
        """The probe marched at every pixel (GL row order)."""
        t = self.gpu.target("test-amortise", "full", SIZE, depth=False)
        self.target.depth.compare_func = ""
        self.march(self.amortiser.direct(t.fbo, SIZE))
        out = t.read()[::-1]
        self.gpu.free(t)
        return out

    def grid(self, block):
        g = self.amortiser._grids[block]
        gw, gh = g.size
        layer = np.frombuffer(g.layer.read(), dtype=np.float32).reshape(gh, gw, 4)
        aux = np.frombuffer(g.aux.read(), dtype=np.float32).reshape(gh, gw, 2)
        return layer, aux


@pytest.fixture
def rig(gpu):
    return ProbeRig(gpu)


def gl_rows(a: np.ndarray) -> np.ndarray:
    return a[::-1]


def bilinear(pixel, fresh, block, sub):
    """The same interpolation without the depth test (what would bleed)."""
    gh, gw = fresh.shape[:2]
    gx, gy = (pixel[0] - sub[0]) / block, (pixel[1] - sub[1]) / block
    x0, y0 = int(np.floor(gx)), int(np.floor(gy))
    fx, fy = gx - x0, gy - y0
    out = 0.0
    for dy in (0, 1):
        for dx in (0, 1):
            tx = min(max(x0 + dx, 0), gw - 1, (SIZE[0] - 1 - sub[0]) // block)
            ty = min(max(y0 + dy, 0), gh - 1, (SIZE[1] - 1 - sub[1]) // block)
            out = out + (fx if dx else 1 - fx) * (fy if dy else 1 - fy) * fresh[ty, tx]
    return out


def test_reset_fill_matches_the_twin_and_does_not_bleed(rig):
    schedule = Schedule(4, 1)
    layer = gl_rows(rig.step(schedule, interactive=True).read())  # the first frame: a reset
    aux = gl_rows(read_aux(rig.amortiser.layer))
    fresh, fresh_aux = rig.grid(4)
    worst_bleed = 0.0
    for y in range(SIZE[1]):
        for x in range(SIZE[0]):
            if x % 4 == 0 and y % 4 == 0:
                continue  # marched: the fresh value itself (checked below)
            want = fill((x, y), float(aux[y, x, 1]), fresh, np.minimum(fresh_aux[..., 1], 1e5),
                        4, (0, 0), SIZE)
            assert np.allclose(layer[y, x], want, atol=1e-5), (x, y, layer[y, x], want)
            worst_bleed = max(worst_bleed, float(np.abs(
                bilinear((x, y), fresh, 4, (0, 0)) - want).max()))
    full = rig.full()
    marched = layer[::4, ::4]
    assert np.array_equal(marched, full[::4, ::4])
    near = depth_image() < 1.0
    # no cloud over the near object or the mast, and none of their emptiness on the sky
    assert np.array_equal(layer[near], np.tile([0.0, 0.0, 0.0, 1.0], (near.sum(), 1)))
    sky = ~near
    assert np.all(layer[sky][:, 3] < 0.75) and np.all(layer[sky][:, 2] > 0.0)
    # the test can fail: plain bilinear filling would have bled across the edges
    assert worst_bleed > 0.2


def test_still_render_converges_to_the_full_resolution_march(rig):
    for schedule in (Schedule(2, 1), Schedule(4, 2)):
        before = rig.amortiser.steps
        layer = gl_rows(rig.step(schedule).read())
        full = rig.full()
        assert np.array_equal(layer, full), schedule
        assert rig.amortiser.steps == before + 1  # one march of every pixel
        # rendering the same view again is one ordinary step, and changes nothing
        before = rig.amortiser.steps
        again = gl_rows(rig.step(schedule).read())
        assert rig.amortiser.steps == before + 1 and np.array_equal(again, full)


def test_window_converges_after_one_cycle_of_a_still_camera(rig):
    schedule = Schedule(2, 2)  # every pixel once in 16 frames
    rig.step(schedule, interactive=True)  # the reset: a half-resolution frame, filled
    full = rig.full()
    for _ in range(schedule.cycle - 2):
        rig.step(schedule, interactive=True)
    marched = gl_rows(read_aux(rig.amortiser.layer))[..., 2]
    assert 0 < (marched == 0.0).sum() < marched.size // 8  # a pixel of each 4×4 block to go
    layer = gl_rows(rig.step(schedule, interactive=True).read())
    assert np.all(gl_rows(read_aux(rig.amortiser.layer))[..., 2] == 1.0)
    assert np.array_equal(layer, full)
    assert rig.amortiser.resets == 1


def test_disocclusion_rejects_the_history(rig):
    schedule = Schedule(2, 2)
    for _ in range(schedule.cycle + 1):
        rig.step(schedule, interactive=True)
    converged = gl_rows(rig.amortiser.layer.read())
    assert np.all(converged[:, MAST[0]:MAST[1] + 1] == [0.0, 0.0, 0.0, 1.0])
    rig.set_depth(depth_image(mast=(EDGE + 3, EDGE + 4)))  # the mast moves left
    layer = gl_rows(rig.step(schedule, interactive=True).read())
    full = rig.full()
    revealed = layer[:, MAST[0]:MAST[1] + 1]
    # its old pixels show the sky again: the old (0, 0, 0, 1) is not kept; each takes the
    # fresh march of the nearest-depth grid point (twin: fill_nearest), a sky one
    assert rig.amortiser.resets == 1 and rig.amortiser.last_path == 1
    assert np.all(revealed[..., 3] < 0.75)
    aux = gl_rows(read_aux(rig.amortiser.layer))
    block = schedule.block
    fresh, fresh_aux = rig.grid(block)
    sub = block_position(rig.amortiser.counter, block)
    for y in range(SIZE[1]):
        for x in range(MAST[0], MAST[1] + 1):
            if (x - sub[0]) % block == 0 and (y - sub[1]) % block == 0:
                continue
            want = fill_nearest((x, y), float(aux[y, x, 1]), fresh,
                                np.minimum(fresh_aux[..., 1], 1e5), block, sub, SIZE)
            assert np.allclose(layer[y, x], want, atol=1e-6), (x, y)
    assert np.abs(revealed - full[:, MAST[0]:MAST[1] + 1]).max() < 0.05


def test_a_turning_camera_reprojects_the_history(rig):
    schedule = Schedule(4, 4)  # every pixel once in 256 frames: the turn is reprojection
    for _ in range(2):
        rig.step(schedule)  # converge (a still render), then one ordinary step
    rig.cam.rotate(4.0, 1.0)  # a fast pan between two frames of the window
    layer = gl_rows(rig.step(schedule, interactive=True).read())
    assert rig.amortiser.last_path == 2 and rig.amortiser.resets == 1
    full = rig.full()
    near = depth_image() < 1.0
    edge = near.copy()  # pixels by a depth edge, or by the image's side the turn uncovered
    for axis in (0, 1):
        for s in (-2, -1, 1, 2):
            edge |= np.roll(near, s, axis=axis)
    edge[:, -3:] = edge[:, :3] = edge[-3:, :] = edge[:3, :] = True
    sky = ~edge
    err = np.abs(layer - full).max(axis=-1)
    # the world-fixed layer moved with the view: the history, read where it was (left in
    # place, it would be off by about 0.04)
    assert err[sky].max() < 0.01, err[sky].max()
    stale = np.abs(gl_rows(rig.amortiser._pair[1].read()) - full).max(axis=-1)
    assert stale[sky].max() > 0.02
    assert np.array_equal(layer[near], np.tile([0.0, 0.0, 0.0, 1.0], (near.sum(), 1)))


@pytest.mark.parametrize("schedule", [Schedule(4, 1), Schedule(2, 2)])
def test_a_banded_grid_marches_the_same_rays(gpu, monkeypatch, schedule):
    """A tiled software rasteriser marches a small grid on one thread (one 64 × 64 tile), so
    there it is drawn in bands, one tile each, and gathered (app.render.amortise.bands): the
    layer is the same, bit for bit, as the grid drawn as it is."""
    import app.render.amortise as am

    layers = {}
    for threads in (1, 2):
        monkeypatch.setattr(am, "rasteriser_threads", lambda t=threads: t)
        rig = ProbeRig(gpu)
        for _ in range(3):  # a reset, then amortised steps
            layer = rig.step(schedule, interactive=True).read()
        g = rig.amortiser._grids[schedule.block]
        assert g.bands == (2 if threads == 2 and gpu.caps.software else 0)
        layers[threads] = (layer, *rig.grid(schedule.block))
        rig.amortiser.release()
    for a, b in zip(layers[1], layers[2]):
        assert np.array_equal(a, b)


def test_bands_only_for_a_small_grid_on_a_software_renderer():
    from app.render.amortise import bands

    assert bands((40, 23), 2, True) == 2  # quarter, 1/16 at 640 × 360: one tile
    assert bands((40, 23), 8, True) == 8
    assert bands((40, 23), 2, False) == 0  # a GPU
    assert bands((40, 23), 1, True) == 0
    assert bands((160, 90), 2, True) == 0  # six tiles already
    assert bands((5, 1), 4, True) == 0  # one row
    assert bands((5, 3), 4, True) == 3  # never more bands than rows


@pytest.mark.parametrize("grid_size,threads", [((40, 23), 2), ((37, 40), 2), ((7, 5), 4)])
def test_a_banded_grid_marches_each_texel_once_and_a_block_one_row(gpu, monkeypatch, grid_size,
                                                                   threads):
    """The banded layout (glsl/common/amortise.glsl): every grid texel is marched by exactly one
    fragment, and the 16 fragments of each 4 × 4 block (one vector of llvmpipe's lanes) march
    texels of one grid row, so a loop over a ray's steps waits for rays of one elevation."""
    import app.render.amortise as am

    monkeypatch.setattr(am, "rasteriser_threads", lambda: threads)
    block = 4
    size = (grid_size[0] * block, grid_size[1] * block)
    amortiser = am.Amortiser(gpu, "test-amortise")
    g = amortiser._grid(size, block)
    assert g.size == grid_size and g.bands == min(threads, grid_size[1])
    fbo, _, _, banded_size = g.banded
    out = gpu.texture("test-amortise", "lanes", banded_size, 4, dtype="f4")
    target = gpu.framebuffer("test-amortise", "lanes", [out])
    prog = gpu.program("test-amortise", fullscreen("tests/amortise_lanes"))
    prog.set_many({"uAmortiseBands": g.bands, "uAmortiseBandRows": g.rows,
                   "uAmortiseGridRows": g.size[1], "uAmortiseGridColumns": g.size[0],
                   "uAmortiseBandShift": g.band_shift})
    target.use()
    gpu.ctx.disable(gpu.ctx.DEPTH_TEST | gpu.ctx.BLEND)
    draw_fullscreen(prog)
    w, h = banded_size
    px = np.frombuffer(out.read(), dtype=np.float32).reshape(h, w, 4)
    marched = px[..., 2] == 0.0
    texels = px[marched][:, :2].astype(int)
    assert len(texels) == grid_size[0] * grid_size[1]
    assert len({tuple(t) for t in texels}) == len(texels)
    assert texels[:, 0].max() == grid_size[0] - 1 and texels[:, 1].max() == grid_size[1] - 1
    for y in range(0, h - h % 4, 4):
        for x in range(0, w - w % 4, 4):
            rows = px[y:y + 4, x:x + 4][marched[y:y + 4, x:x + 4]][:, 1]
            assert len(set(rows.tolist())) <= 1, (x, y, rows)
    for obj in (target, out):
        gpu.free(obj)
    amortiser.release()

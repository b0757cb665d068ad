"""The stereo pair of app/render/stereo.py (spec/003 §2.15, criterion 35) on a tiny test scene
(glsl/tests/vr_boxes.*: flat-coloured squares facing the head, a near red one and a far blue
one, over grey): the two eyes are rendered with IPD-offset view matrices; a near object's
horizontal disparity exceeds a far one's and equals ipd·f/depth (measures.disparity_px);
the halves differ; each half is exactly a mono render from that eye's camera at the eye's
size (odd widths too), and below or above render scale 1 the same mono render resampled; the
eye textures follow the render scale."""

from __future__ import annotations

import moderngl
import numpy as np
import pytest

from app.errors import ParamError
from app.frame import FrameContext
from app.gpu.device import Gpu
from app.gpu.programs import ProgramSpec
from app.render.stereo import StereoRenderer, eye_camera, eye_size, eye_viewport
from app.runtime import scene_params
from app.sim import vr
from app.sim.camera import Camera
from tests.helpers import measures

PROBE = ProgramSpec("tests/vr_boxes")
GREY = (0.3, 0.3, 0.3)
HEAD = Camera(position=(0.0, 1.5, 0.0), yaw=0.0, pitch=0.0, fov=60.0, near=0.05, far=100.0)
#: (centre, half side, colour): squares facing the head (−z), at planar depths 1.5 and 12 m
SQUARES = (((-0.25, 1.5, -1.5), 0.12, (1.0, 0.1, 0.1)), ((1.6, 1.5, -12.0), 1.0, (0.1, 0.2, 1.0)))
NEAR_DEPTH, FAR_DEPTH = 1.5, 12.0


def square_vertices() -> np.ndarray:
    rows = []
    for (cx, cy, cz), h, colour in SQUARES:
        corners = [(cx - h, cy - h, cz), (cx + h, cy - h, cz), (cx + h, cy + h, cz),
                   (cx - h, cy - h, cz), (cx + h, cy + h, cz), (cx - h, cy + h, cz)]
        rows += [(*c, *colour) for c in corners]
    return np.asarray(rows, np.float32)


class BoxScene:
    """render_eye(frame, target) for StereoRenderer: the squares through frame.camera."""

    def __init__(self, gpu: Gpu):
        self.gpu = gpu
        self.vbo = gpu.buffer("test", "squares", square_vertices().tobytes())
        self.calls: list[tuple[str | None, tuple[int, int]]] = []

    def render_eye(self, frame, target) -> None:
        self.calls.append((frame.eye, tuple(frame.size)))
        assert tuple(target.size) == tuple(frame.size)
        prog = self.gpu.program("test", PROBE)
        prog.set("uViewProj", frame.camera.view_projection_relative(frame.aspect))
        prog.set("uCameraPos", tuple(frame.camera.position))
        target.use()
        target.clear((*GREY, 1.0))
        self.gpu.ctx.enable(moderngl.DEPTH_TEST)
        prog.vao([(self.vbo, "3f 3f", "in_position", "in_colour")]).render(moderngl.TRIANGLES)

    def mono(self, camera: Camera, size) -> np.ndarray:
        target = self.gpu.target("test", "mono", size)
        try:
            self.render_eye(FrameContext(size=tuple(size), camera=camera), target)
            return target.read()
        finally:
            self.gpu.free(target)


@pytest.fixture(scope="module")
def boxes(gl_ctx):
    gpu = Gpu(gl_ctx)
    scene = BoxScene(gpu)
    stereo = StereoRenderer(gpu, "test-stereo")
    yield scene, stereo
    stereo.release()
    gpu.release()


def render_pair(boxes, size, ipd=0.064, scale=1.0, camera=HEAD) -> np.ndarray:
    scene, stereo = boxes
    target = scene.gpu.target("test", "pair", size)
    try:
        frame = FrameContext(size=tuple(size), camera=camera)
        stereo.render(frame, target, ipd, scale, scene.render_eye)
        return target.read()
    finally:
        scene.gpu.free(target)


def halves(img: np.ndarray, size) -> dict[str, np.ndarray]:
    out = {}
    for eye in ("left", "right"):
        x, _, w, _ = eye_viewport(size, eye)
        out[eye] = img[:, x:x + w]
    return out


def _centroid_x(img: np.ndarray, channel: int) -> float:
    others = [c for c in range(3) if c != channel]
    mask = (img[..., channel] > 0.5) & (img[..., others].max(-1) < 0.25)
    assert mask.sum() > 4
    return float(np.nonzero(mask)[1].mean())


@pytest.mark.parametrize("ipd", [0.064, 0.2])
def test_a_near_objects_disparity_exceeds_a_far_ones_and_is_ipd_f_over_depth(boxes, ipd):
    size = (240, 120)
    pair = halves(render_pair(boxes, size, ipd=ipd), size)
    near = _centroid_x(pair["left"], 0) - _centroid_x(pair["right"], 0)
    far = _centroid_x(pair["left"], 2) - _centroid_x(pair["right"], 2)
    assert near > far + 1.0
    h = size[1]
    want = [float(measures.disparity_px(d, ipd, h, HEAD.fov)) for d in (NEAR_DEPTH, FAR_DEPTH)]
    assert near == pytest.approx(want[0], abs=1.0)
    assert far == pytest.approx(want[1], abs=1.0)
    assert not np.array_equal(pair["left"], pair["right"])


@pytest.mark.parametrize("size", [(160, 90), (161, 90), (97, 51)])
def test_each_half_is_the_mono_render_from_its_eye_at_the_eyes_size(boxes, size):
    scene, stereo = boxes
    scene.calls.clear()
    pair = halves(render_pair(boxes, size), size)
    assert [c[0] for c in scene.calls] == ["left", "right"]
    for eye, half in pair.items():
        cam = eye_camera(HEAD, 0.064, eye)
        assert np.allclose(cam.position, stereo.last_eyes[eye].position)
        want = scene.mono(cam, eye_size(size, 1.0, eye))
        assert half.shape == want.shape
        assert np.abs(half - want).max() < 1e-5, eye  # the copy's filter weights: 3e-6
    assert not np.array_equal(pair["left"][:, :size[0] // 2], pair["right"][:, :size[0] // 2])


def _upsample(img: np.ndarray, shape) -> np.ndarray:
    """Bilinear resampling at the pixel centres of ``shape`` (what eye_copy.frag does)."""
    h, w = shape
    uv = np.stack(np.meshgrid((np.arange(w) + 0.5) / w, (np.arange(h) + 0.5) / h), -1)
    return vr.sample_bilinear(img[::-1], uv)[::-1]  # rows bottom-up for the sampler


@pytest.mark.parametrize("scale", [0.25, 0.5, 2.0])
def test_render_scale_sizes_the_eye_textures_and_each_half_resamples_its_mono_render(boxes,
                                                                                    scale):
    scene, stereo = boxes
    size = (160, 90)
    scene.calls.clear()
    pair = halves(render_pair(boxes, size, scale=scale), size)
    want_size = (round(80 * scale), round(90 * scale))
    assert scene.calls == [("left", want_size), ("right", want_size)]
    assert tuple(stereo.targets["left"].size) == want_size
    for eye, half in pair.items():
        mono = scene.mono(eye_camera(HEAD, 0.064, eye), want_size)
        want = _upsample(mono, half.shape[:2])
        assert np.abs(half - want).max() < 2e-3, (eye, np.abs(half - want).max())


def test_the_eye_frame_is_a_copy_and_the_frame_is_left_alone(boxes):
    scene, stereo = boxes
    seen = []

    def render_eye(frame, target):
        seen.append(frame)
        scene.render_eye(frame, target)

    target = scene.gpu.target("test", "pair", (64, 32))
    frame = FrameContext(size=(64, 32), camera=HEAD, time=3.5, hour=18.0)
    try:
        stereo.render(frame, target, 0.064, 1.0, render_eye)
    finally:
        scene.gpu.free(target)
    assert frame.eye is None and frame.camera is HEAD and frame.size == (64, 32)
    for eye, f in zip(("left", "right"), seen):
        assert f.eye == eye and f.size == (32, 32) and f.time == 3.5 and f.hour == 18.0
        assert f.camera.fov == HEAD.fov  # the eye's own projection: aspect (W/2)/H
        assert f.aspect == pytest.approx(1.0)


def test_zero_ipd_gives_identical_halves(boxes):
    size = (160, 90)
    pair = halves(render_pair(boxes, size, ipd=0.0), size)
    assert np.abs(pair["left"] - pair["right"]).max() < 1e-5


def test_bad_ipd_or_scale_is_a_one_line_error():
    """The vr.ipd and vr.render_scale Params refuse them before any eye is rendered."""
    for assignment, match in (("vr.ipd=-0.01", "vr.ipd"), ("vr.render_scale=0", "render_scale")):
        with pytest.raises(ParamError, match=match) as info:
            scene_params("village", sets=[assignment])
        assert "\n" not in str(info.value)

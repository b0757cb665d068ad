"""The fog on the GPU (glsl/common/fog.glsl, glsl/fog/plane.*, glsl/fog/bench_surface.*,
app/effects/fog; spec/003 §2.11, §6 criteria 33–34):

* fog.glsl's and plane.glsl's functions against their numpy twins (app/sim/fog.py) through the
  probe glsl/tests/fog_probe.frag, height fog included;
* criterion 33: quads at thesis distances d ∈ {1, 2, 5, 10} (measured from the near plane,
  spec/003 eq. 7.24) render lerp(fogColour, objColour, f(d)) within 2/255 in a linear 8-bit
  target for the three modes at the thesis's values, per vertex and per pixel alike (a
  2-triangle quad at constant depth); on a large slanted triangle the two differ;
* criterion 34: the ground fog plane's coverage changes with the sin(t)-modulated cutoff as the
  twin predicts, and its texture's centroid moves linearly with time × Speed along the wind;
* the plane is depth-tested and writes no depth; FogGenerator's intensity changes both fogs;
* in the village scene the fog publishes the slot and draws its plane in the transparent stage.

The plane is drawn by the Fog effect on its own over a flat terrain (the village is not needed
for it) into 256² targets (one tile, at the texture's resolution); the scene test renders the
village at 160×90."""

from __future__ import annotations

import math

import moderngl
import numpy as np
import pytest

from app.effects.fog import Fog
from app.effects.fog.effect import PLANE
from app.frame import FrameContext, Stage
from app.gpu.programs import ProgramSpec
from app.gpu.shaders import ShaderLibrary
from app.params import ParamSet
from app.sim import fog as fs
from app.sim.camera import Camera
from tests.helpers import measures
from tests.helpers.glsl_eval import evaluate_points

PROBE = "tests/fog_probe"
SURFACE = ProgramSpec("fog/bench_surface")
OWNER = "test-fog"
NEAR, FAR = 0.1, 100.0
FOG_COLOUR = (0.8, 0.5, 0.2)
OBJ_COLOUR = (0.1, 0.3, 0.9)


def fog_params(*sets: str) -> ParamSet:
    params = ParamSet(Fog.declare(ShaderLibrary(None)))
    for s in sets:
        params.set_from_string(s)
    return params


# ---- the functions against the twins ---------------------------------------------------------

@pytest.mark.parametrize("cfg", [
    fs.FogSettings(mode="linear", start=0.0, end=10.0),
    fs.FogSettings(mode="linear", start=4.0, end=4.0),
    fs.FogSettings(mode="exp", density=0.75),
    fs.FogSettings(mode="exp2", density=0.75),
    fs.FogSettings(mode="exp2", density=0.0162),
    fs.FogSettings(mode="off"),
], ids=["linear", "linear-e=s", "exp", "exp2", "exp2-village", "off"])
def test_distance_and_factors_match_the_twin(gpu, cfg):
    w = np.concatenate([[-1.0, 0.0, NEAR, FAR, 2 * FAR], np.linspace(NEAR, FAR, 400),
                        fs.fog_view_depth([1.0, 2.0, 3.999, 4.001, 5.0, 10.0], NEAR, FAR)])
    pts = np.stack([w, np.zeros_like(w), np.zeros_like(w)], -1)
    got = evaluate_points(gpu, pts, PROBE, {"uProbeMode": 0,
                                           **fs.fog_uniforms(cfg, (0, 0, 0), NEAR, FAR)})
    d = fs.fog_distance(w, NEAR, FAR)
    assert np.allclose(got[:, 0], d, rtol=1e-5, atol=2e-5)
    assert np.allclose(got[:, 1], fs.fog_unity_clip_z(w, NEAR, FAR), rtol=1e-5, atol=1e-6)
    f = fs.fog_factor(d, cfg)
    keep = np.abs(d - cfg.start) > 1e-3  # the step of e = s is a hair's breadth either side
    assert np.abs(got[keep, 2] - f[keep]).max() < 1e-5  # fp32 exp
    assert np.abs(got[keep, 3] - f[keep]).max() < 1e-5  # FogVertexFactor of the clip position
    # spec/003 eq. 7.25 and spec/003 eq. 7.26, on the GPU
    assert got[3, 0] == pytest.approx(FAR, rel=1e-6) and got[2, 0] == pytest.approx(0.0, abs=1e-6)


def random_rays(n, seed, grazing=False):
    rng = np.random.default_rng(seed)
    o = np.stack([rng.uniform(-50, 50, n), rng.uniform(0.0, 40.0, n), rng.uniform(-50, 50, n)], -1)
    d = rng.normal(size=(n, 3))
    if grazing:
        d[:, 1] = rng.choice([0.0, 1e-7, -1e-5, 1e-3, -3e-3], n)
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    return o, o + d * rng.uniform(0.0, 400.0, (n, 1))


@pytest.mark.parametrize("grazing", [False, True], ids=["rays", "grazing"])
@pytest.mark.parametrize("a, b, y0", [(0.05, 0.35, 0.0), (0.3, 0.05, 2.0), (0.02, 2.0, 10.0),
                                      (0.1, 0.0, 0.0)])
def test_height_fog_matches_the_twin(gpu, grazing, a, b, y0):
    origins, ends = random_rays(96, int(a * 100 + b * 10 + grazing), grazing)
    cfg = fs.FogSettings(height=True, height_density=a, height_falloff=b, height_base=y0)
    got = []
    for o, p in zip(origins, ends):  # one camera per point: evaluate in small batches
        u = {"uProbeMode": 1, **fs.fog_uniforms(cfg, o, NEAR, FAR)}
        got.append(evaluate_points(gpu, p[None], PROBE, u)[0])
    got = np.array(got)
    want_t = fs.fog_height_transmittance(ends, origins, a, b, y0)
    want_tau = fs.fog_height_optical_depth(ends, origins, a, b, y0)
    assert np.isfinite(got).all()
    assert np.abs(got[:, 0] - want_t).max() < 2e-5
    assert np.allclose(got[:, 1], want_tau, rtol=2e-4, atol=1e-6)
    # the numeric reference, on the GPU too, where its midpoint rule is accurate (fewer than
    # 40 e-folds of density along the ray) and does not overflow
    fine = b * np.abs(ends[:, 1] - origins[:, 1]) < 40.0
    fine &= b * (y0 - np.minimum(ends[:, 1], origins[:, 1])) < 300.0
    assert fine.sum() >= 5
    with np.errstate(over="ignore"):
        ref = fs.fog_height_reference(ends[fine], origins[fine], a, b, y0, steps=4096)
    assert np.abs(got[fine, 0] - ref).max() < 5e-5


def test_plane_cutoff_and_alpha_match_the_twin(gpu):
    rng = np.random.default_rng(5)
    pts = np.stack([rng.uniform(0, 1, 500), rng.uniform(0, 1, 500), rng.uniform(0, 120, 500)], -1)
    got = evaluate_points(gpu, pts, PROBE, {"uProbeMode": 2})
    c = np.array([float(fs.plane_cutoff(p[1], p[2])) for p in pts])
    assert np.allclose(got[:, 0], c, atol=2e-6)
    assert np.allclose(got[:, 1], fs.plane_alpha(pts[:, 0], c), atol=2e-6)
    assert (c == 0).mean() > 0.3 and (got[:, 1] == 0).mean() > 0.15  # both clamps reached


# ---- criterion 33: quads at known distances --------------------------------------------------

class Target8:
    """A linear 8-bit RGBA target with depth (spec/003 §6: linear 8-bit RGBA, no MSAA)."""

    def __init__(self, gpu, size):
        self.size = size
        self.colour = gpu.texture(OWNER, "rgba8", size, 4, dtype="f1")
        self.depth = gpu.depth_texture(OWNER, "depth", size)
        self.fbo = gpu.framebuffer(OWNER, "fbo", [self.colour], self.depth)

    def clear(self):
        self.fbo.use()
        self.fbo.clear(0.0, 0.0, 0.0, 1.0, depth=1.0)

    def read(self):
        w, h = self.size
        raw = np.frombuffer(self.fbo.read(components=4, dtype="f1"), np.uint8)
        return raw.reshape(h, w, 4)[::-1].astype(np.float64) / 255.0


def camera():
    return Camera(position=(0.0, 0.0, 0.0), yaw=0.0, pitch=0.0, fov=60.0, near=NEAR, far=FAR)


def quads_at(distances, aspect):
    """Camera-facing 2-triangle quads, one per quarter of the screen, each at the view depth
    whose thesis distance is d."""
    cam = camera()
    tan = math.tan(math.radians(cam.fov) / 2)
    verts = []
    for i, d in enumerate(distances):
        w = float(fs.fog_view_depth(d, NEAR, FAR))
        x0, x1 = -1 + 0.5 * i + 0.05, -1 + 0.5 * (i + 1) - 0.05
        xs = np.array([x0, x1]) * w * tan * aspect
        ys = np.array([-0.8, 0.8]) * w * tan
        a, b, c, e = ((xs[0], ys[0]), (xs[1], ys[0]), (xs[1], ys[1]), (xs[0], ys[1]))
        for x, y in (a, b, c, a, c, e):
            verts.append((x, y, -w))
    return np.array(verts, "f4")


def draw(gpu, target, verts, cfg, cam):
    prog = gpu.program(OWNER, SURFACE)
    prog.set_many({"uViewProj": cam.projection_matrix(target.size[0] / target.size[1])
                   @ cam.view_matrix(), "uObjectColor": OBJ_COLOUR,
                   **fs.fog_uniforms(cfg, cam.position, cam.near, cam.far)})
    vbo = gpu.buffer(OWNER, "verts", verts.tobytes())
    target.clear()
    gpu.ctx.enable(moderngl.DEPTH_TEST)
    prog.vao([(vbo, "3f", "in_position")]).render(moderngl.TRIANGLES)
    gpu.ctx.disable(moderngl.DEPTH_TEST)
    img = target.read()
    gpu.free(vbo)
    return img


@pytest.mark.parametrize("cfg", [
    fs.FogSettings(mode="linear", start=0.0, end=10.0, colour=FOG_COLOUR),
    fs.FogSettings(mode="exp", density=0.75, colour=FOG_COLOUR),
    fs.FogSettings(mode="exp2", density=0.75, colour=FOG_COLOUR),
], ids=["linear", "exp", "exp2"])
def test_criterion_33_quads_render_the_lerp(gpu, cfg):
    size = (96, 32)
    target = Target8(gpu, size)
    verts = quads_at([1.0, 2.0, 5.0, 10.0], size[0] / size[1])
    images = {}
    for per_pixel in (False, True):
        c = fs.FogSettings(**{**cfg.__dict__, "per_pixel": per_pixel})
        images[per_pixel] = draw(gpu, target, verts, c, camera())
    for i, d in enumerate((1.0, 2.0, 5.0, 10.0)):
        want = fs.fog_apply(OBJ_COLOUR, fs.fog_factor(d, cfg), FOG_COLOUR)
        col = slice(24 * i + 6, 24 * i + 18)
        for per_pixel, img in images.items():
            patch = img[8:24, col, :3]
            assert np.abs(patch - want).max() <= 2.0 / 255.0 + 1e-9, (d, per_pixel)
    # a 2-triangle quad at constant depth: per vertex and per pixel agree
    assert np.abs(images[False] - images[True]).max() <= 1.0 / 255.0 + 1e-9
    if cfg.mode == "linear":  # Fig. 122a: f(5) = 0.5, the colour half way
        mid = images[False][16, 24 * 2 + 12, :3]
        assert np.allclose(mid, 0.5 * np.add(FOG_COLOUR, OBJ_COLOUR), atol=2.0 / 255.0)


def test_per_vertex_differs_from_per_pixel_on_a_large_triangle(gpu):
    """The thesis's per-vertex factor is interpolated across each triangle: on a 2-triangle
    ground running from the camera's feet to 90 m, exp2's bell is lost; finely tessellated, the
    two agree."""
    size = (64, 64)
    target = Target8(gpu, size)
    cam = Camera(position=(0.0, 2.0, 0.0), yaw=0.0, pitch=-20.0, fov=60.0, near=NEAR, far=FAR)
    cfg = fs.FogSettings(mode="exp2", density=0.06, colour=(1.0, 1.0, 1.0))

    def ground(cell):
        n = int(round(90.0 / cell))
        xs = np.linspace(-45.0, 45.0, n + 1)
        zs = np.linspace(0.0, -90.0, n + 1)
        tris = []
        for i in range(n):
            for j in range(n):
                a, b = (xs[i], zs[j]), (xs[i + 1], zs[j])
                c, e = (xs[i + 1], zs[j + 1]), (xs[i], zs[j + 1])
                tris += [a, b, c, a, c, e]
        t = np.array(tris)
        return np.stack([t[:, 0], np.zeros(len(t)), t[:, 1]], -1).astype("f4")

    out = {}
    for cell in (90.0, 1.0):
        v = ground(cell)
        out[cell] = [draw(gpu, target, v, fs.FogSettings(**{**cfg.__dict__, "per_pixel": pp}),
                          cam)[..., 0] for pp in (False, True)]
    coarse = np.abs(out[90.0][0] - out[90.0][1])
    fine = np.abs(out[1.0][0] - out[1.0][1])
    assert coarse.max() > 20.0 / 255.0
    assert fine.max() <= 3.0 / 255.0 and fine.mean() < 0.5 / 255.0
    assert np.abs(out[90.0][1] - out[1.0][1]).max() <= 1.0 / 255.0  # per pixel: mesh-free


# ---- criterion 34: the ground fog plane ------------------------------------------------------

class FlatTerrain:
    bounds = (-100.0, -100.0, 100.0, 100.0)
    sea_level = 0.0
    revision = 0

    def height(self, x, z):
        return np.full(np.broadcast(np.asarray(x), np.asarray(z)).shape, 1.6)

    def normal(self, x, z):
        shape = np.broadcast(np.asarray(x), np.asarray(z)).shape
        return np.broadcast_to(np.array([0.0, 1.0, 0.0]), shape + (3,))

    def grass_density(self, x, z):
        return np.zeros(np.broadcast(np.asarray(x), np.asarray(z)).shape)


TERRAIN = FlatTerrain()
TILE = 24.0
#: the plane's images: one tile at the texture's own resolution (mip level 0), so the texture is
#: sampled finely enough that its translation is a translation of the image (no aliasing)
SIZE = 256


def top_camera(height_above=10.0, plane_y=1.95):
    """Straight down over the plane: the square image covers exactly one texture tile (image
    right = +x = +u, image down = +z = +v), so the rendered wisps tile across its edges."""
    fov = math.degrees(2.0 * math.atan(TILE / 2.0 / height_above))
    return Camera(position=(TILE / 2, plane_y + height_above, TILE / 2), yaw=0.0, pitch=-90.0,
                  fov=fov, near=0.1, far=500.0)


class PlaneRig:
    """The fog effect alone over a flat terrain, drawn into a black float target (256²)."""

    def __init__(self, gpu, *sets, size=SIZE):
        self.gpu = gpu
        self.params = fog_params("fog.mode=off", *sets)
        self.fog = Fog(gpu, self.params)
        self.size = (size, size)
        self.target = gpu.target(OWNER, "plane", self.size)
        self.time = 0.0

    def frame(self, t, camera=None, wind=(3.0, 0.0)):
        dt = t - self.time
        self.time = t
        f = FrameContext(size=self.size, camera=camera or top_camera(), time=t)
        f.terrain = TERRAIN
        f.wind = np.asarray(wind, float)
        self.fog.update(f, max(dt, 0.0))
        return f

    def render(self, t, camera=None, wind=(3.0, 0.0), depth=1.0):
        f = self.frame(t, camera, wind)
        self.target.clear((0.0, 0.0, 0.0, 1.0), depth=depth)
        f.image = f.image_for(self.target)
        passes = self.fog.passes(f, self.target)
        for p in passes:
            assert p.stage == Stage.TRANSPARENT
            p.run()
        return self.target.read()


def bilinear_wrap(tex, u, v):
    """GL's bilinear lookup of a repeating texture (row 0 at v = 0) at (u, v)."""
    n = tex.shape[0]
    x, y = u * n - 0.5, v * n - 0.5
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = x - x0, y - y0

    def at(r, c):
        return tex[r % n, c % n]

    return ((1 - fx) * (1 - fy) * at(y0, x0) + fx * (1 - fy) * at(y0, x0 + 1)
            + (1 - fx) * fy * at(y0 + 1, x0) + fx * fy * at(y0 + 1, x0 + 1))


@pytest.fixture
def rig(gpu):
    r = PlaneRig(gpu)
    yield r
    r.fog.release()


def test_criterion_34_coverage_follows_the_sin_time_cutoff(rig):
    intensity = rig.params["fog.intensity"]
    # the image covers one tile at the texture's resolution: the twin samples its 8-bit texels
    # bilinearly at the pixels' uv (llvmpipe's 8-bit filter weights spread the alpha = 0
    # boundary a little: up to 4 % of the pixels when the cutoff is 0)
    tex = np.round(fs.fog_texture(256)[..., 3] * 255.0) / 255.0
    centres = (np.arange(SIZE) + 0.5) / SIZE
    cover = []
    for t in (30.0, 2.0, 4.0 * math.pi, 8.0 * math.pi - 2.0):  # sin(t/8) < 0, ¼, 1, ¼
        img = rig.render(t)
        assert np.isfinite(img).all()
        cover.append(float(np.mean(img[..., :3].max(-1) > 0.0)))
        c = float(fs.plane_cutoff(1.0 - intensity, t))
        u, v = np.meshgrid(centres + rig.fog.scroll[0], centres + rig.fog.scroll[1])
        want = float(np.mean(fs.plane_alpha(bilinear_wrap(tex, u, v), c) > 0.0))
        assert cover[-1] == pytest.approx(want, abs=0.04), (t, c)
    assert cover[0] > cover[1] > cover[2]  # the fog thins as the cutoff rises ...
    assert cover[3] > cover[2]  # ... and returns as it falls
    assert cover[2] < 0.5 * cover[0]


@pytest.mark.parametrize("speed", [0.5, 0.25])
def test_criterion_34_centroid_moves_linearly_with_time_and_speed(gpu, speed):
    rig = PlaneRig(gpu, f"fog.speed={speed}")
    try:
        t0 = 27.0  # sin(t/8) < 0 from 8π to 16π: the cutoff is 0, only the scroll changes

        def centroid(dt, wind=(3.0, 0.0)):
            rig.fog.scroll = np.zeros(2)
            rig.time = t0
            return measures.texture_centroid(rig.render(t0 + dt, wind=wind)[..., 0])

        c0 = centroid(0.0)
        shifts = np.array([(centroid(dt) - c0 + 0.5) % 1.0 - 0.5 for dt in (3.0, 6.0, 12.0)])
        want = speed * np.array([3.0, 6.0, 12.0]) / 20.0  # tiles, along the wind (+x = +u)
        assert np.allclose(shifts[:, 0], want, atol=2e-3), shifts
        assert np.abs(shifts[:, 1]).max() < 2e-3
        # a north wind (toward −z) moves it up the image (−v) instead
        s = (centroid(6.0, wind=(0.0, -2.0)) - c0 + 0.5) % 1.0 - 0.5
        assert s == pytest.approx([0.0, -speed * 6.0 / 20.0], abs=2e-3)
    finally:
        rig.fog.release()


def test_plane_is_depth_tested_and_writes_no_depth(rig):
    img = rig.render(30.0)
    assert img[..., :3].max() > 0.1
    depth = rig.target.read_depth()
    assert np.all(depth == 1.0)  # blended, ZWrite off
    hidden = rig.render(30.0, depth=0.0)  # everything already drawn is nearer: nothing shows
    assert hidden[..., :3].max() == 0.0
    (inspector,) = rig.fog.panel_items()  # the inspector shows what the draw made
    assert set(inspector.textures) == {"fog texture (Fig. 118)", "ground mask"}


def test_plane_is_fogged_lit_and_seen_from_below(rig):
    near = rig.render(30.0)
    lit = near[..., :3][near[..., :3].max(-1) > 1e-4]
    # no main light: tex.rgb·(1·(0.7 + 0.3·n·l)), l = n = up, over black: rgb·alpha
    assert 0.75 * fs.TEXTURE_MAX_ALPHA < lit.max() <= fs.TEXTURE_MAX_ALPHA + 1e-3
    below = top_camera()
    below.set(position=(TILE / 2, 1.95 - 10.0, TILE / 2), pitch=90.0)
    img = rig.render(30.0, camera=below)
    assert np.isfinite(img).all() and img[..., :3].max() > 0.05
    # the global fog colours the plane's far fragments too
    rig.params.set("fog.mode", "exp")
    rig.params.set("fog.density", 1.0)
    rig.params.set("fog.intensity", 1.0)
    fogged = rig.render(30.0)  # t = 0.5/m at 10 m: f = e^(−5), the plane takes the fog colour
    seen = fogged[..., :3].max(-1) > 1e-3
    colour = np.asarray(rig.fog.settings.colour)
    chroma = fogged[..., :3][seen] / fogged[..., :3][seen].sum(-1, keepdims=True)
    assert np.allclose(chroma, colour / colour.sum(), atol=0.01)
    plain = lit / lit.sum(-1, keepdims=True)
    assert np.abs(plain.mean(0) - colour / colour.sum()).max() > 0.04  # it was grey before


def test_generator_intensity_changes_both_fogs(gpu):
    out = {}
    for intensity in (0.2, 0.6):
        rig = PlaneRig(gpu, f"fog.intensity={intensity}", "fog.mode=exp2")
        try:
            img = rig.render(4.0 * math.pi)  # the cutoff at its peak, 1 − intensity
            out[intensity] = (float(np.mean(img[..., :3].max(-1) > 1e-4)),
                              rig.fog.settings.density)
        finally:
            rig.fog.release()
    assert out[0.6][0] > out[0.2][0]  # the plane: more of it survives the cutoff
    assert out[0.6][1] == pytest.approx(3.0 * out[0.2][1])  # the global fog: t ∝ intensity


def test_plane_program_is_the_effect_s():
    assert PLANE in Fog.programs and Fog.stages == (Stage.TRANSPARENT,)
    assert "fog" in Fog.produces


# ---- in the village ---------------------------------------------------------------------------

def test_village_publishes_the_fog_and_draws_the_plane(render):
    cam = Camera(position=(0.0, 6.0, 28.0), yaw=0.0, pitch=-14.0, fov=60.0, near=0.1,
                 far=2000.0)
    foggy, session = render("village", sets=["village.msaa=0"], camera=cam)
    scene = session.scene
    frame = scene.frame((160, 90), 0.0)
    assert isinstance(frame.fog, fs.FogSettings) and frame.fog.mode == "exp2"
    names = [p.name for p in scene.passes(frame, session.gpu.target(OWNER, "t", (16, 9)))
             if p.stage == Stage.TRANSPARENT]
    assert names and names[0] == "fog.plane"  # first of its stage (the thesis's lower queue)
    clear, _ = render("village", sets=["village.msaa=0", "fog.plane=false", "fog.mode=off"],
                      camera=cam)
    assert np.isfinite(foggy).all()
    diff = np.abs(foggy[..., :3] - clear[..., :3]).max(-1)
    assert (diff > 0.02).mean() > 0.3  # the plane and the distance fog change most pixels
    # the ground under the plane (lower image) whitens; the sky (top rows) is not fogged
    assert foggy[60:, :, :3].mean() > clear[60:, :, :3].mean()
    assert np.abs(foggy[:3, :, :3] - clear[:3, :, :3]).max() < 1e-6

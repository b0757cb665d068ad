"""The cloth shader of the sails and the flag (spec/000 §1.5) on the GPU: ``glsl/boat/cloth.vert``
against its numpy twin (app/sim/cloth.py) through transform feedback, and the GPU parts of
spec/000 §6 criterion 35 on a small render of the flag: Alpha holes are discarded (background)
pixels, the unlit colours lie in {ColorA, ColorB}, two flags differing only in TimeOffset give
different frames, and the lit cloth has no NaN.

The flag is drawn face-on with an orthographic view (uModel the identity: world = its local
frame) into a 96 × 64 float target.
"""

from __future__ import annotations

import moderngl
import numpy as np
import pytest

from app import DEFAULT_SHADER_ROOT
from app.gpu.programs import ProgramSpec
from app.render.environment import flat_environment
from app.render.noise import GradientNoiseTextures
from app.sim import cloth, rigging

CLOTH = ProgramSpec("boat/cloth")
OWNER = "test-boat-cloth"
SIZE = (96, 64)
BACKGROUND = (0.0, 0.0, 0.0, 0.0)
#: local x in [-0.05, 0.75], y in [-0.14, 0.56] onto the target; +z toward the viewer
VIEW = np.array([[2 / 0.8, 0, 0, -1 - 2 * -0.05 / 0.8],
                 [0, 2 / 0.7, 0, -1 - 2 * -0.14 / 0.7],
                 [0, 0, -0.5, 0],
                 [0, 0, 0, 1]], dtype=np.float64)


def _uniforms(mesh, p, t=0.0, side=1.0, fill=0.0):
    u = {cloth.UNIFORMS[k]: (tuple(map(float, v)) if isinstance(v, tuple) else float(v))
         for k, v in p.items() if k in cloth.UNIFORMS}
    u.update(mesh.uniforms())
    u.update({"uTime": float(t), "uBellySide": float(side), "uFill": float(fill),
              "uModel": np.eye(4), "uViewProj": VIEW})
    return u


def _set(prog, name, value):
    """Set a uniform of a raw moderngl program (matrices row-major in numpy)."""
    if name not in prog:
        return
    if isinstance(value, np.ndarray):
        prog[name].write(np.ascontiguousarray(value.T, dtype="f4").tobytes())
    else:
        prog[name].value = value


def _gpu_surface(gpu, mesh, p, t, side, fill):
    """Displaced positions and normals from the real vertex shader, by transform feedback."""
    ctx = gpu.ctx
    src = gpu.shaders.preprocess(DEFAULT_SHADER_ROOT / "boat" / "cloth.vert")
    prog = ctx.program(vertex_shader=src.text, varyings=["vWorldPos", "vWorldNormal"])
    perm = GradientNoiseTextures(gpu, OWNER)
    perm.texture().use(0)
    _set(prog, "uPerlinPermutation", 0)
    for k, v in _uniforms(mesh, p, t, side, fill).items():
        _set(prog, k, v)
    vbo = ctx.buffer(mesh.vertex_data())
    out = ctx.buffer(reserve=len(mesh.positions) * 6 * 4)
    vao = ctx.vertex_array(prog, [(vbo, rigging.CLOTH_FORMAT, *rigging.CLOTH_ATTRIBUTES)])
    # a draw needs a complete framebuffer bound, even with no fragment stage (the headless
    # context has no default one)
    gpu.target(OWNER, "feedback", (4, 4)).use()
    vao.transform(out, mode=moderngl.POINTS, vertices=len(mesh.positions))
    data = np.frombuffer(out.read(), dtype="f4").reshape(-1, 6).astype(np.float64)
    for obj in (vao, out, vbo, prog):
        obj.release()
    perm.release()
    return data[:, :3], data[:, 3:]


@pytest.mark.parametrize("which", ["flag", "mainsail"])
def test_gpu_displacement_and_normals_match_the_numpy_twin(gpu, which):
    if which == "flag":
        mesh, p, side, fill = rigging.flag(), cloth.defaults_values(cloth.FLAG_DEFAULTS), 1.0, 0.0
    else:
        mesh, p, side, fill = rigging.mainsail(), cloth.defaults_values(), -1.0, 0.7
    p.update(time_offset=1.3)
    for t in (0.0, 2.75, 41.2):
        pos, nrm = _gpu_surface(gpu, mesh, p, t, side, fill)
        want = cloth.displace(mesh.positions, mesh.uvs, mesh.pinned, t, p, mesh.corners, side,
                              fill)
        wn = cloth.displaced_normals(mesh.uvs, mesh.pinned, t, p, mesh.corners, mesh.pin_band,
                                     side, fill)
        moved = np.abs(want - mesh.positions).max()
        assert moved > 0.01
        assert np.abs(pos - want).max() < 2e-5 * max(1.0, np.abs(want).max())
        assert np.all(np.isfinite(nrm))
        assert np.abs(nrm - wn).max() < 2e-3


def _textures(gpu, holes, name):
    alpha = rigging.flag_alpha(holes=holes)
    pattern = rigging.flag_pattern()
    h, w = alpha.shape
    a = gpu.texture(OWNER, f"alpha-{name}", (w, h), 1, data=alpha.tobytes(), dtype="f1")
    b = gpu.texture(OWNER, f"pattern-{name}", (w, h), 1, data=pattern.tobytes(), dtype="f1")
    return a, b


def _render(gpu, p, holes=0.0, t=0.0, unlit=False, flip=False, model=None):
    mesh = rigging.flag()
    prog = gpu.program(OWNER, CLOTH)
    alpha, pattern = _textures(gpu, holes, f"{holes}-{unlit}-{flip}-{t}-{p['time_offset']}-"
                                           f"{model is None}")
    env = flat_environment(gpu, OWNER, (0.2, 0.25, 0.3, 1.0))
    perm = GradientNoiseTextures(gpu, OWNER)
    prog.bind_textures({"uAlpha": alpha, "uPattern": pattern, "uEnvironment": env,
                        **perm.textures()})
    u = _uniforms(mesh, p, t)
    if model is not None:
        u["uModel"] = model
    if flip:  # seen from behind: turned half about the flag's vertical centre line
        behind = np.array([[-1.0, 0, 0, 0.7], [0, 1, 0, 0], [0, 0, -1, 0], [0, 0, 0, 1]])
        u["uViewProj"] = VIEW @ behind
    u.update({"uColorA": (0.8, 0.1, 0.1), "uColorB": (0.1, 0.2, 0.9), "uUnlit": unlit,
              "uTranslucency": 0.4, "uMainLightDir": (0.3, 0.5, 0.81),
              "uMainLightRadiance": (3.0, 3.0, 2.8), "uEnvironmentLods": 0.0})
    prog.set_many(u)
    target = gpu.target(OWNER, "image", SIZE)
    target.use()
    target.clear(BACKGROUND)
    gpu.ctx.enable(moderngl.DEPTH_TEST)
    vbo = gpu.buffer(OWNER, "flag", mesh.vertex_data())
    ibo = gpu.buffer(OWNER, "flag-indices", mesh.index_data())
    prog.vao([(vbo, rigging.CLOTH_FORMAT, *rigging.CLOTH_ATTRIBUTES)], ibo).render(
        moderngl.TRIANGLES)
    gpu.ctx.disable(moderngl.DEPTH_TEST)
    assert not prog.errors, prog.errors
    return target.read()


def _still():
    return cloth.defaults_values(cloth.FLAG_DEFAULTS) | {"wave_height": 0.0,
                                                          "gradient_weight": (0.0, 0.0, 0.0)}


def _inside_flag():
    """Pixels whose centre lies well inside the flat flag's rectangle."""
    w, h = SIZE
    x = (np.arange(w) + 0.5) / w * 0.8 - 0.05
    y = 0.56 - (np.arange(h) + 0.5) / h * 0.7  # row 0 at the top
    X, Y = np.meshgrid(x, y)
    return (X > 0.02) & (X < 0.68) & (Y > 0.02) & (Y < 0.40)


def test_criterion_35_unlit_colours_are_color_a_or_color_b(gpu):
    img = _render(gpu, _still(), unlit=True)
    rgb = img[..., :3]
    a, b = np.array([0.8, 0.1, 0.1]), np.array([0.1, 0.2, 0.9])
    is_a = np.all(np.abs(rgb - a) < 1e-6, axis=-1)
    is_b = np.all(np.abs(rgb - b) < 1e-6, axis=-1)
    is_bg = img[..., 3] == 0.0
    assert np.all(is_a | is_b | is_bg)
    inside = _inside_flag()
    assert np.all(~is_bg[inside])  # an intact flag covers its rectangle
    assert is_a[inside].mean() > 0.3 and is_b[inside].mean() > 0.1  # the cross shows


def test_criterion_35_alpha_holes_are_background_pixels(gpu):
    intact = _render(gpu, _still(), holes=0.0, unlit=True)
    torn = _render(gpu, _still(), holes=0.8, unlit=True)
    inside = _inside_flag()
    assert np.mean(intact[..., 3][inside] == 0.0) == 0.0
    holes = np.mean(torn[..., 3][inside] == 0.0)
    assert holes > 0.02
    # the holes are where the alpha texture has them (nearest texel at each pixel centre)
    alpha = rigging.flag_alpha(holes=0.8)
    w, h = SIZE
    x = (np.arange(w) + 0.5) / w * 0.8 - 0.05
    y = 0.56 - (np.arange(h) + 0.5) / h * 0.7
    X, Y = np.meshgrid(x, y)
    iu = np.clip((X / 0.7 * alpha.shape[1]).astype(int), 0, alpha.shape[1] - 1)
    iv = np.clip((Y / 0.42 * alpha.shape[0]).astype(int), 0, alpha.shape[0] - 1)
    texel_hole = alpha[iv, iu] == 0
    agree = (torn[..., 3] == 0.0) == texel_hole
    assert agree[inside].mean() > 0.9


def test_criterion_35_flags_differing_only_in_time_offset_give_different_frames(gpu):
    p = cloth.defaults_values(cloth.FLAG_DEFAULTS)
    a = _render(gpu, p, t=2.0)
    b = _render(gpu, p | {"time_offset": 0.4}, t=2.0)
    assert np.abs(a - b).max() > 0.05
    assert np.mean(np.any(np.abs(a - b) > 1e-4, axis=-1)) > 0.02


def test_lit_cloth_is_finite_on_both_sides(gpu):
    p = cloth.defaults_values(cloth.FLAG_DEFAULTS)
    front = _render(gpu, p, t=1.1)
    back = _render(gpu, p, t=1.1, flip=True)
    for img in (front, back):
        assert np.all(np.isfinite(img))
        cloth_px = img[..., 3] > 0.0
        assert cloth_px.mean() > 0.3
        assert np.all(img[cloth_px][:, :3] > 0.0)  # ambient at least: never black
    # the front faces the light, the back receives only its transmitted share
    lum_f = front[..., :3][front[..., 3] > 0].mean()
    lum_b = back[..., :3][back[..., 3] > 0].mean()
    assert lum_b < 0.8 * lum_f
    # a mirroring model matrix (the cloth turned inside out about its plane): the side seen
    # is still lit as the side facing the light
    mirrored = _render(gpu, p, t=1.1, model=np.diag([1.0, 1.0, -1.0, 1.0]))
    lum_m = mirrored[..., :3][mirrored[..., 3] > 0].mean()
    assert lum_m == pytest.approx(lum_f, rel=0.15)

"""The GLSL twin of the atmosphere's optical-depth LUT lookup (``GLSL_LUT_UV``, spec/002 §9
criterion 4) evaluated on the test context against the numpy LUT of ``app/sim/atmosphere.py``.
"""

from __future__ import annotations

import moderngl
import numpy as np

from app.sim import atmosphere as atm


def test_glsl_twin_of_the_lut_lookup(gl_ctx, atmosphere_lut, atmosphere_model):
    """``GLSL_LUT_UV`` evaluated on the GL context equals the numpy twin (uv and depths)."""
    ctx = gl_ctx
    vs = ("#version 330 core\nvoid main() { vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);"
          " gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0); }")
    fs = ("#version 330 core\nuniform float uBottomRadius; uniform float uTopRadius;"
          " uniform float uHRayleigh;\n"
          "uniform float uHMie; uniform float uP0; uniform sampler2D uPoints;\n" + atm.GLSL_LUT_UV +
          "\nlayout(location = 0) out vec4 fragColor;\nlayout(location = 1) out vec4 fragOzone;\n"
          "void main() { vec2 q = texelFetch(uPoints, ivec2(gl_FragCoord.xy), 0).xy;\n"
          "  vec3 d = OpticalDepthToSun(q.x, q.y);\n"
          "  fragColor = vec4(OpticalDepthLutUv(q.x, q.y), d.xy); fragOzone = vec4(d.z); }")
    side = 32
    rng = np.random.default_rng(5)
    h = rng.uniform(0.0, atmosphere_model.top_height, side * side).astype(np.float32)
    mu = rng.uniform(-1.0, 1.0, side * side).astype(np.float32)
    h[:side], mu[:side] = np.linspace(0, atmosphere_model.top_height, side), 1.0
    points = np.zeros((side * side, 4), np.float32)
    points[:, 0], points[:, 1] = h, mu
    objs = []
    try:
        prog = ctx.program(vertex_shader=vs, fragment_shader=fs)
        src = ctx.texture((side, side), 4, points.tobytes(), dtype="f4")
        src.filter = (moderngl.NEAREST, moderngl.NEAREST)
        tex = ctx.texture(atmosphere_lut.size, 3, atmosphere_lut.table.tobytes(), dtype="f4")
        tex.repeat_x = tex.repeat_y = False
        out = ctx.texture((side, side), 4, dtype="f4")
        out_ozone = ctx.texture((side, side), 4, dtype="f4")
        fbo = ctx.framebuffer([out, out_ozone])
        vao = ctx.vertex_array(prog, [])
        objs = [prog, src, tex, out, out_ozone, fbo, vao]
        src.use(0)
        tex.use(1)
        prog["uPoints"] = 0
        prog["uOpticalDepthLut"] = 1
        for name, value in atmosphere_model.uniforms().items():
            if name in prog:
                prog[name].value = value
        fbo.use()
        vao.render(moderngl.TRIANGLES, vertices=3)
        res = np.frombuffer(fbo.read(components=4, dtype="f4"),
                            np.float32).reshape(-1, 4).astype(np.float64)
        ozone = np.frombuffer(fbo.read(components=4, dtype="f4", attachment=1),
                              np.float32).reshape(-1, 4)[:, 0].astype(np.float64)
    finally:
        for o in objs:
            o.release()
    h64, mu64 = h.astype(np.float64), mu.astype(np.float64)
    assert np.max(np.abs(res[:, :2] - atmosphere_lut.uv(h64, mu64)) * 256) < 0.01       # texels
    ground = atm.sun_ray_hits_ground(h64, mu64, atmosphere_model)
    assert np.array_equal(res[:, 2] >= 1e11, ground)
    want = atmosphere_lut.optical_depth_to_sun(h64, mu64)
    sky = ~ground
    assert np.allclose(res[sky, 2:], want[sky, :2], rtol=2e-3, atol=1e-3)
    # the ozone layer's density integral (third channel, no P0), metres
    assert np.allclose(ozone[sky], want[sky, 2], rtol=2e-3, atol=1.0)

"""The shading lab's lit surface, ``ProgramSpec("shading/surface")`` (glsl/shading/surface.vert,
glsl/shading/surface.frag, glsl/common/lighting.glsl), against its numpy twin
app/sim/lighting.py, per pixel: each lighting model and toon mode of spec/003 §2.1 and
spec/003 §2.12 on a UV sphere (app.render.meshes.uv_sphere) lit by one directional light; the
Stepped image's four levels (spec/003 §6 criterion 6); Gouraud against per-fragment lighting on
a coarse sphere; the point and spot lights added (ForwardAdd) and the spot's cone edge where
uSpotCos puts it; the emission mask with the light off (criterion 9); no NaN with the light
exactly behind or at grazing.

The sphere (radius 0.5, at the origin, uModel the identity) is seen orthographically along −z
from a camera at z = 50, so each pixel's normal, position and view vector are reconstructed
analytically; only pixels well inside the silhouette are compared (the mesh's polygon edge
differs from the circle there). Targets are float, tiny (40 × 40).
"""

from __future__ import annotations

import itertools
import math

import moderngl
import numpy as np
import pytest

from app.gpu.programs import ProgramSpec
from app.render.meshes import uv_sphere
from app.sim import lighting as lt

SURFACE = ProgramSpec("shading/surface")
OWNER = "test-shading-lighting"
SIZE = (40, 40)
RADIUS = 0.5
HALF = 0.55  # world half-width the view covers
CAMERA = (0.0, 0.0, 50.0)
VIEW = np.array([[1 / HALF, 0, 0, 0], [0, 1 / HALF, 0, 0], [0, 0, -1.0, 0], [0, 0, 0, 1]])
FORMAT = ("3f 3f 2f 4f", "in_position", "in_normal", "in_uv", "in_tangent")
RAMP = np.array([[0.1, 0.1, 0.3], [0.5, 0.4, 0.3], [1.0, 0.95, 0.8]])
SUN = tuple(float(c) for c in np.array([0.4, 0.5, 0.77]) / np.linalg.norm([0.4, 0.5, 0.77]))
TOL = 2 / 255
_count = itertools.count()


def _mesh_data(rings: int, segments: int) -> tuple[bytes, bytes]:
    """The UV sphere with its uv = (φ/2π, θ/π) and +u tangent (−sin φ, 0, cos φ), w = 1."""
    mesh = uv_sphere(RADIUS, rings, segments)
    theta = np.repeat(np.linspace(0, math.pi, rings + 1), segments + 1)
    phi = np.tile(np.linspace(0, 2 * math.pi, segments + 1), rings + 1)
    uv = np.stack([phi / (2 * math.pi), theta / math.pi], -1)
    tangent = np.stack([-np.sin(phi), np.zeros_like(phi), np.cos(phi), np.ones_like(phi)], -1)
    data = np.hstack([mesh.positions, mesh.normals, uv, tangent]).astype("f4").tobytes()
    return data, mesh.indices.astype("u4").tobytes()


FINE = (128, 256)
COARSE = (6, 12)


def _pixels(size=SIZE, inset=0.94):
    """Analytic p, n, v per pixel (rows top-down as RenderTarget.read gives them) and the mask of
    pixels inside ``inset`` of the silhouette."""
    w, h = size
    x = (-1 + (2 * np.arange(w) + 1) / w) * HALF
    y = (1 - (2 * np.arange(h) + 1) / h) * HALF
    xx, yy = np.meshgrid(x, y)
    r2 = xx * xx + yy * yy
    inside = r2 < (inset * RADIUS) ** 2
    p = np.stack([xx, yy, np.sqrt(np.clip(RADIUS ** 2 - r2, 0, None))], -1)
    n = p / RADIUS
    v = lt.safe_normalize(np.asarray(CAMERA) - p, (0.0, 0.0, 1.0))
    return p, n, v, inside


def _render(gpu, s: lt.Shading, lights: lt.Lights, mesh=FINE, albedo=(1.0, 1.0, 1.0),
            masks=None, time=0.0, size=SIZE):
    k = next(_count)
    prog = gpu.program(OWNER, SURFACE)
    ramp = gpu.texture(OWNER, f"ramp-{k}", (len(RAMP), 1), 3, data=RAMP.astype("f4").tobytes(),
                       filter=(moderngl.NEAREST, moderngl.NEAREST))
    m = np.asarray(masks if masks is not None else (0.0, 1.0, 0.0, 0.0), dtype="f4")
    mask_tex = gpu.texture(OWNER, f"masks-{k}", (1, 1), 4, data=m.tobytes(),
                           filter=(moderngl.NEAREST, moderngl.NEAREST))
    prog.bind_textures({"uRamp": ramp, "uMasks": mask_tex})
    prog.set_many({**s.uniforms(), **lights.uniforms(), "uModel": np.eye(4), "uViewProj": VIEW,
                   "uCameraPos": CAMERA, "uAlbedo": tuple(albedo),
                   "uUseMasks": masks is not None, "uTime": float(time)})
    for name, rows in lights.arrays().items():
        prog.set_array(name, rows)
    data, indices = _mesh_data(*mesh)
    vbo = gpu.buffer(OWNER, f"sphere-{k}", data)
    ibo = gpu.buffer(OWNER, f"sphere-indices-{k}", indices)
    target = gpu.target(OWNER, f"image-{k}", size)
    target.use()
    target.clear((0.0, 0.0, 0.0, 0.0))
    gpu.ctx.enable(moderngl.DEPTH_TEST)
    prog.vao([(vbo, *FORMAT)], ibo).render(moderngl.TRIANGLES)
    gpu.ctx.disable(moderngl.DEPTH_TEST)
    assert not prog.errors, prog.errors
    return target.read()


def _twin(s, lights, albedo=(1.0, 1.0, 1.0), spec_mask=1.0, emission=0.0, time=0.0,
          size=SIZE):
    p, n, v, inside = _pixels(size)
    c = lt.shade_surface(p, n, v, albedo, spec_mask, emission, s, lights, time, RAMP)
    return c, inside


CASES = {
    "lambert": lt.Shading(lighting_model=0),
    "phong": lt.Shading(lighting_model=1, specularity=0.6),
    "blinn_phong": lt.Shading(lighting_model=2, specularity=0.6),
    "blinn_phong_rim": lt.Shading(lighting_model=2, specularity=0.6, rim=True, rim_power=2.0,
                                  rim_color=(0.2, 0.3, 0.5)),
    "flat": lt.Shading(toon=1, specularity=0.6),
    "flat_hard": lt.Shading(toon=1, specularity=0.6, smoothness=1.0),
    "stepped": lt.Shading(toon=2, specularity=0.6),
    "stepped_repository": lt.Shading(toon=2, stepped_repository=True, specularity=0.6),
    "ramp": lt.Shading(toon=3, specularity=0.6),
}
#: modes with jumps: a pixel on a band edge may fall either side
DISCONTINUOUS = {"flat_hard", "stepped", "stepped_repository", "ramp"}


@pytest.mark.parametrize("case", list(CASES))
def test_gpu_matches_the_numpy_twin_per_pixel(gpu, case):
    s = CASES[case]
    lights = lt.Lights(sun_dir=SUN, sun_radiance=(1.0, 0.95, 0.9), ambient=(0.03, 0.03, 0.04))
    albedo = (0.8, 0.7, 0.6)
    img = _render(gpu, s, lights, albedo=albedo)
    want, inside = _twin(s, lights, albedo)
    assert np.all(np.isfinite(img))
    assert np.all(img[inside, 3] == 1.0)
    err = np.abs(img[inside, :3] - want[inside]).max(-1)
    if case in DISCONTINUOUS:
        assert (err <= TOL).mean() >= 0.97, (case, err.max())
    else:
        assert err.max() <= TOL, (case, err.max())


def test_stepped_image_has_only_the_four_levels_times_the_light(gpu):
    s = lt.Shading(toon=2, specularity=0.0)
    side = tuple(float(c) for c in np.array([1.0, 0.2, 0.35]) / np.linalg.norm([1.0, 0.2, 0.35]))
    img = _render(gpu, s, lt.Lights(sun_dir=side, sun_radiance=(1, 1, 1)))
    covered = img[..., 3] > 0
    values = img[covered, 0]
    levels = np.asarray(lt.STEPPED_LEVELS)
    nearest = np.abs(values[:, None] - levels[None, :]).min(-1)
    assert nearest.max() <= 1 / 255
    assert {int(i) for i in np.abs(values[:, None] - levels[None, :]).argmin(-1)} == {0, 1, 2, 3}
    assert np.allclose(img[covered, 0], img[covered, 1]) and values.min() >= 0.2 - 1 / 255


def test_gouraud_and_per_fragment_differ_on_a_coarse_spheres_highlight(gpu):
    s = lt.Shading(lighting_model=2, blinn_exponent=120.0, specularity=1.0)
    lights = lt.Lights(sun_dir=SUN, sun_radiance=(1, 1, 1))
    frag = _render(gpu, s, lights, mesh=COARSE)
    lt_g = lt.Shading(**{**s.__dict__, "gouraud": True})
    gour = _render(gpu, lt_g, lights, mesh=COARSE)
    covered = (frag[..., 3] > 0) & (gour[..., 3] > 0)
    assert np.all(np.isfinite(gour))
    diff = np.abs(frag[covered, :3] - gour[covered, :3]).max()
    assert diff > 0.1
    # per fragment the highlight peaks near 1 + diffuse; Gouraud smears it over triangles
    assert frag[covered, 0].max() > 1.2
    fine_frag = _render(gpu, s, lights)
    fine_gour = _render(gpu, lt_g, lights)
    both = (fine_frag[..., 3] > 0) & (fine_gour[..., 3] > 0)
    assert np.abs(fine_frag[both, :3] - fine_gour[both, :3]).max() < diff


def test_point_and_spot_lights_add_and_the_cone_edge_is_where_uspotcos_says(gpu):
    s = lt.Shading(lighting_model=0)
    sun = lt.Lights(sun_dir=SUN, sun_radiance=(0.5, 0.5, 0.5))
    point = lt.Lights(**{**sun.__dict__, "point_pos": [(0.8, -0.3, 0.8)],
                         "point_radiance": [(1.0, 0.6, 0.2)], "point_range": [2.0]})
    inner, outer = math.cos(math.radians(4.0)), math.cos(math.radians(6.0))
    spot = lt.Lights(sun_dir=SUN, sun_radiance=(0, 0, 0), spot_on=True, spot_pos=(0, 0, 3.0),
                     spot_dir=(0.0, 0.0, -1.0), spot_radiance=(1, 1, 1), spot_cos=(inner, outer))
    a, b, c = (_render(gpu, s, li) for li in (sun, point, spot))
    covered = a[..., 3] > 0
    assert np.all(b[covered, :3] >= a[covered, :3] - 1e-6)
    assert (b[covered, :3] - a[covered, :3]).max() > 0.1
    for img, li in ((b, point), (c, spot)):
        want, inside = _twin(s, li)
        assert np.abs(img[inside, :3] - want[inside]).max() <= TOL
    p, n, _, inside = _pixels()
    d = p - np.array([0, 0, 3.0])
    cos_axis = -d[..., 2] / np.linalg.norm(d, axis=-1)  # angle to the spot's axis (0, 0, −1)
    outside = inside & (cos_axis < outer - 2e-4)
    full = inside & (cos_axis > inner + 2e-4)
    assert outside.sum() > 20 and full.sum() > 5
    assert np.all(c[outside, :3] == 0.0)
    assert np.all(c[full, 0] > 0.5)


def test_emission_mask_with_the_light_off(gpu):
    s = lt.Shading(emission_color=(1.0, 0.75, 0.35))
    dark = lt.Lights(sun_dir=SUN, sun_radiance=(0, 0, 0))
    img = _render(gpu, s, dark, masks=(1.0, 0.0, 0.0, 1.0))
    covered = img[..., 3] > 0
    assert np.allclose(img[covered, :3], [1.0, 0.75, 0.35], atol=1e-6)
    flick = lt.Shading(flicker=1.0)
    means = [_render(gpu, flick, dark, masks=(1.0, 0.0, 0.0, 1.0), time=t)[covered, 0].mean()
             for t in (0.0, 0.37)]
    assert abs(means[0] - means[1]) > 1e-3
    assert np.isclose(means[1], lt.flicker_factor(0.37, 1.0), atol=1e-5)


@pytest.mark.parametrize("sun", [(0.0, 0.0, -1.0), (1.0, 0.0, 0.0)], ids=["behind", "grazing"])
def test_no_nan_with_the_light_behind_or_grazing(gpu, sun):
    lights = lt.Lights(sun_dir=sun, sun_radiance=(1, 1, 1), point_pos=[(0.0, 0.0, 0.5)],
                       point_radiance=[(1, 1, 1)], point_range=[0.0])
    for toon, model, gouraud in itertools.product(range(4), range(3), (False, True)):
        s = lt.Shading(toon=toon, lighting_model=model, specularity=1.0, smoothness=1.0,
                       rim=True, gouraud=gouraud)
        img = _render(gpu, s, lights, mesh=COARSE, size=(16, 16))
        assert np.all(np.isfinite(img)), (toon, model, gouraud)


def test_the_stepped_variants_differ_where_appendix_a_says(gpu):
    lights = lt.Lights(sun_dir=(1.0, 0.0, 0.0), sun_radiance=(1, 1, 1))
    doc, repo = (lt.Shading(toon=2, specularity=0.0, stepped_repository=r) for r in (False, True))
    a, b = _render(gpu, doc, lights), _render(gpu, repo, lights)
    (wa, inside), (wb, _) = _twin(doc, lights), _twin(repo, lights)
    gpu_differs = np.abs(a[inside, 0] - b[inside, 0]) > 1e-3
    twin_differs = np.abs(wa[inside, 0] - wb[inside, 0]) > 1e-3
    assert twin_differs.sum() > 20
    assert (gpu_differs == twin_differs).mean() >= 0.97
    _, n, _, _ = _pixels()
    ndotl = n[inside, 0]
    assert np.all((ndotl[twin_differs] > -0.1 - 1e-3) & (ndotl[twin_differs] <= 0.15 + 1e-3))

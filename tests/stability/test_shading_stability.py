"""The shading lab swept where it could fail (spec/003 §2.1–2.3, §2.12): the
sun exactly behind the camera (l = v) and exactly behind the objects (n·l = −1, and l = −v,
where Blinn–Phong's half vector is zero), grazing views of the wall — the camera in its plane,
a hair above and below it — with every parallax mode, layer count and depth, every toon mode
and lighting model, per vertex and per fragment, degenerate triangles and zero-area UVs in a
user's mesh, the spot light with a 1° cone and with equal inner and outer cosines, lamps at
range 0.1 and a lamp exactly on the surface. Every image: no NaN or Inf, no negative value,
bounded."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from app.bench.shading import WALL_CENTRE
from app.runtime import open_session, scene_params
from app.sim import lab_meshes
from app.sim.camera import Camera
from app.sim.parallax import view_at

SIZE = (64, 36)
MODELS, TOONS, GOURAUD = (0, 1, 2), (0, 1, 2, 3), (False, True)
#: the wall seen head-on from 3.25 m: its centre vertex is exactly on the view axis
HEAD_ON = Camera(position=(0.0, 0.75, 4.0), yaw=0.0, pitch=0.0, fov=40.0)


@pytest.fixture
def lab(gl_ctx):
    s = open_session("shading", scene_params("shading", sets=["shading.turntable=0"]),
                     ctx=gl_ctx)
    target = s.gpu.target("test", "image", SIZE)
    s.test_target = target  # type: ignore[attr-defined]
    yield s
    s.gpu.free(target)
    s.release()


def _render(s, camera: Camera | None = None, **values) -> np.ndarray:
    if camera is not None:
        s.scene.camera = camera
    for name, value in values.items():
        s.params.set(f"shading.{name}", value)
    frame = s.scene.frame(SIZE, 0.0)
    s.scene.render(frame, s.test_target)
    return s.test_target.read()[..., :3]


def _bound(s) -> float:
    """The most any pixel can get: every light's radiance at full strength (albedo ≤ 1 plus a
    specular ≤ 1 each), the ambient, the emission colour (≤ 4) and the rim (≤ 1)."""
    p = s.params
    lights = (p["shading.ambient"] + p["shading.sun_intensity"]
              + p["shading.lamps"] * p["shading.lamp_intensity"]
              + (p["shading.spot_intensity"] if p["shading.spot"] else 0.0))
    return 2.0 * lights + 4.0 + 1.0


def _check(s, img: np.ndarray, what) -> None:
    assert np.isfinite(img).all(), (what, int((~np.isfinite(img)).sum()))
    assert img.min() >= 0.0, (what, float(img.min()))
    assert img.max() <= _bound(s), (what, float(img.max()), _bound(s))


def _covered(s, img: np.ndarray) -> float:
    return float((np.abs(img - np.asarray(s.scene.background)).max(axis=-1) > 1e-4).mean())


def _every_model(s, camera, label, **fixed) -> None:
    for lm, toon, gouraud in itertools.product(MODELS, TOONS, GOURAUD):
        img = _render(s, camera, lighting_model=lm, toon=toon, gouraud=gouraud, **fixed)
        _check(s, img, (label, lm, toon, gouraud))


def _sun_of(direction) -> tuple[float, float]:
    """(elevation, azimuth) in degrees of the sun toward unit ``direction`` (the lab's
    convention: (cos e·sin a, sin e, −cos e·cos a))."""
    x, y, z = direction
    return float(np.degrees(np.arcsin(y))), float(np.degrees(np.arctan2(x, -z)) % 360.0)


@pytest.mark.parametrize("case", ["behind camera", "behind objects", "zenith", "nadir"])
def test_the_sun_exactly_behind_the_camera_or_the_objects(lab, case):
    """On the row of objects from the scene's view: the sun along the view axis toward the
    camera (l = v on the axis) or away from it (l = −v: the half vector is zero); straight up
    and straight down (n·l = −1 under the sphere and the table)."""
    cam = lab.scene.new_camera()
    forward = cam.forward()
    el, az = {"behind camera": _sun_of(-forward), "behind objects": _sun_of(forward),
              "zenith": (90.0, 0.0), "nadir": (-90.0, 0.0)}[case]
    _every_model(lab, cam, case, object="all", sun_elevation=el, sun_azimuth=az, lamps=0)
    img = _render(lab, cam, rim=True, stepped_repository=True, toon=2)
    _check(lab, img, (case, "rim, repository steps"))
    assert _covered(lab, img) > 0.05


@pytest.mark.parametrize("sun", [(0.0, 180.0), (0.0, 0.0)], ids=["l = v = n", "n.l = -1"])
def test_the_wall_head_on_with_the_sun_along_its_normal(lab, sun):
    """The wall's centre vertex exactly on the view axis: with the sun at (0, 0, 1) there
    l = v = n exactly, with it at (0, 0, −1) n·l = −1 and l + v = 0 exactly (Gouraud lights
    that very vertex); with every parallax mode."""
    for mode in range(5):
        _every_model(lab, HEAD_ON, (sun, mode), object="wall", sun_elevation=sun[0],
                     sun_azimuth=sun[1], parallax_mode=mode, lamps=0)
    assert _covered(lab, _render(lab, HEAD_ON)) > 0.15


def _grazing_camera(angle: float, azimuth: float, distance: float = 3.0) -> Camera:
    w = view_at(angle, azimuth)
    cam = Camera(position=tuple(WALL_CENTRE + distance * w), fov=30.0)
    return cam.look_at_direction(-w)


@pytest.mark.parametrize("angle", [0.0, 1e-3, 0.05, 0.5, 2.0, -0.05, -0.5])
def test_grazing_views_of_the_wall_with_every_parallax_mode(lab, angle):
    """The camera in the wall's plane (0°), a hair above it and a hair below it (seeing the
    front from behind: v.z < 0 in tangent space): every parallax mode at the extremes of
    layers and depth, and every lighting and toon mode with occlusion parallax."""
    for azimuth in (0.0, 30.0, 89.0):
        cam = _grazing_camera(angle, azimuth)
        for mode, layers, scale in itertools.product(range(5), (1, 12, 64), (0.0, 0.05, 0.2)):
            if mode in (0, 1, 4) and layers != 12:
                continue  # these modes read no layer count
            img = _render(lab, cam, object="wall", parallax_mode=mode, parallax_layers=layers,
                          parallax_scale=scale)
            _check(lab, img, (angle, azimuth, mode, layers, scale))
    lab.params.set("shading.parallax_scale", 0.2)
    _every_model(lab, _grazing_camera(angle, 30.0), ("grazing", angle), object="wall",
                 parallax_mode=3, parallax_layers=64)


def _degenerate_mesh() -> lab_meshes.LabMesh:
    """One proper quad, then a collinear triangle, a triangle with a repeated vertex, a
    triangle of one point, and a proper triangle whose three UVs coincide (zero UV area)."""
    p = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],          # quad
                  [0, 0, 0.5], [0.5, 0.5, 0.5], [1, 1, 0.5],           # collinear
                  [0.2, 0.3, 0.7], [0.2, 0.3, 0.7], [0.9, 0.1, 0.7],   # repeated vertex
                  [0.4, 0.4, 0.9], [0.4, 0.4, 0.9], [0.4, 0.4, 0.9],   # one point
                  [0, 0, 1.0], [1, 0, 1.2], [0, 1, 1.4]], np.float64)  # zero-area UVs
    uv = np.array([[0, 0], [1, 0], [1, 1], [0, 1],
                   [0, 0], [0.5, 0.5], [1, 1],
                   [0.1, 0.1], [0.1, 0.1], [0.1, 0.1],
                   [0.3, 0.3], [0.3, 0.3], [0.3, 0.3],
                   [0.5, 0.5], [0.5, 0.5], [0.5, 0.5]], np.float64)
    tri = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [7, 8, 9], [10, 11, 12], [13, 14, 15]])
    return lab_meshes.from_arrays("degenerate", p, tri, uvs=uv)


@pytest.mark.parametrize("with_uvs", [True, False])
def test_degenerate_triangles_and_zero_area_uvs_in_a_user_mesh(lab, with_uvs):
    mesh = _degenerate_mesh()
    if not with_uvs:  # the loader's own box mapping on the same triangles
        mesh = lab_meshes.from_arrays("degenerate", mesh.positions,
                                      mesh.indices.reshape(-1, 3))
    for name in ("normals", "smooth_normals", "uvs", "tangents"):
        assert np.isfinite(getattr(mesh, name)).all(), name
    fitted = lab.scene.effect("shading").set_user_mesh(mesh)
    assert np.isfinite(fitted.positions).all()
    cam = Camera(position=(0.0, 0.8, 3.0), yaw=0.0, pitch=-5.0, fov=40.0)
    for mode in range(5):
        _every_model(lab, cam, ("user", with_uvs, mode), parallax_mode=mode, spot=True,
                     lamps=4)
    assert _covered(lab, _render(lab, cam)) > 0.01


def test_a_user_mesh_of_one_point(lab):
    """Every triangle degenerate and every vertex the same point (zero extent: only moved)."""
    p = np.full((6, 3), 0.25)
    mesh = lab_meshes.from_arrays("point", p, np.arange(6).reshape(2, 3))
    lab.scene.effect("shading").set_user_mesh(mesh)
    _every_model(lab, HEAD_ON, "one point", spot=True, lamps=2)


def test_the_spot_with_a_tiny_cone_and_with_equal_cosines(lab, monkeypatch):
    """spot_angle 1° (the smallest), then the cone's inner and outer cosines made equal (the
    division GLSL's smoothstep leaves undefined), the spot aimed at the wall's centre."""
    eff = lab.scene.effect("shading")
    _every_model(lab, HEAD_ON, "spot 1°", object="wall", spot=True, spot_angle=1.0,
                 spot_intensity=500.0)
    plain = eff.light_uniforms

    def equal_cosines(frame):
        u = plain(frame)
        c = u["spot_cos"][1]
        return {**u, "spot_cos": (c, c)}

    monkeypatch.setattr(eff, "light_uniforms", equal_cosines)
    for angle in (1.0, 30.0, 89.0):
        _every_model(lab, HEAD_ON, ("equal cosines", angle), object="all", spot=True,
                     spot_angle=angle, spot_intensity=500.0)


def test_lamps_at_range_0_1_and_a_lamp_on_the_surface(lab, monkeypatch):
    """All four lamps at the shortest range, then one of them exactly on the wall's centre
    vertex (d = 0: l falls back to n) and the others a millimetre off it."""
    _every_model(lab, None, "range 0.1", object="all", lamps=4, lamp_range=0.1,
                 lamp_intensity=100.0)
    eff = lab.scene.effect("shading")
    plain = eff.light_uniforms

    def on_the_wall(frame):
        u = plain(frame)
        pos = np.array(u["pos"], np.float32)
        pos[0] = WALL_CENTRE
        pos[1] = WALL_CENTRE + (0.0, 0.0, 1e-3)
        pos[2] = WALL_CENTRE - (0.0, 0.0, 1e-3)
        pos[3] = WALL_CENTRE + (1e-3, 0.0, 0.0)
        return {**u, "pos": pos}

    monkeypatch.setattr(eff, "light_uniforms", on_the_wall)
    for rng in (0.1, 4.0):
        for mode in (0, 3):
            _every_model(lab, HEAD_ON, ("lamp on the wall", rng, mode), object="wall",
                         lamps=4, lamp_range=rng, lamp_intensity=100.0, parallax_mode=mode)

"""The surfaces lab scene (spec/003 §2.4–2.8) as a user runs it: the room renders finite and
lit; every switch of the panel changes the image; each failure of the thesis is one switch and
goes back; the probe and the shadow maps are re-rendered only when what they show changed;
and the stability cases (sun overhead and at the horizon, the camera inside a casting box)
give finite, non-black frames."""

from __future__ import annotations

import numpy as np
import pytest

from app.runtime import open_session, scene_params

SIZE = (128, 72)


@pytest.fixture(scope="module")
def lab(gl_ctx):
    s = open_session("surfaces", scene_params("surfaces"), ctx=gl_ctx)
    defaults = s.params.values()
    yield s, defaults
    s.release()


def _render(session, defaults, camera=None, **values):
    for name, value in defaults.items():
        session.params.set(name, value)
    for name, value in values.items():
        session.params.set(f"surfaces.{name}", value)
    frame = session.scene.frame(SIZE, 0.0)
    if camera is not None:
        frame.camera.position = np.asarray(camera, float)
    target = session.gpu.target("test", f"image {SIZE}", SIZE)
    session.scene.render(frame, target)
    img = target.read()[..., :3]
    session.gpu.free(target)
    return img


def test_the_room_renders_finite_and_lit(lab):
    s, d = lab
    img = _render(s, d)
    assert np.isfinite(img).all()
    lum = img.mean(axis=-1)
    assert lum.mean() > 0.05
    assert lum.std() > 0.02  # objects, shadows and walls, not a flat fill


@pytest.mark.parametrize("name, values", [
    ("reflection", ("none", "cube", "box", "approximation", "perfect")),
    ("fresnel", ("exact", "schlick")),
    ("msaa", ("0", "4")),
    ("lamp", (False, True)),
    ("spot", (False, True)),
    ("debug", ("none", "cascades", "shadow", "reflection")),
    ("n2", (1.0, 1.31, 2.42)),
    ("interfaces", (1, 2)),
    ("reflection_optimize", (False, True)),
    ("metallic_map", (False, True)),
])
def test_every_switch_changes_the_image(lab, name, values):
    s, d = lab
    images = [_render(s, d, **{name: v}) for v in values]
    for a, b in zip(images, images[1:]):
        assert np.abs(a - b).max() > 1e-3, name


@pytest.mark.parametrize("failure", ["queue_order", "intersecting", "zwrite_off", "acne",
                                     "peter_panning"])
def test_each_failure_is_one_switch_and_goes_back(lab, failure):
    from app.effects.surfaces.effect import FAILURES

    s, d = lab
    base = _render(s, d)
    img = _render(s, d, failure=failure)
    for name, value in FAILURES[failure].items():
        assert s.params[name] == value
    changed = [n for n, v in FAILURES[failure].items() if v != d[n]]
    if changed:
        assert np.abs(img - base).max() > 1e-3
    s.params.set("surfaces.failure", "none")
    s.scene.frame(SIZE, 0.0)
    for name in FAILURES[failure]:
        assert s.params[name] == s.params.spec(name).default


def test_probe_and_shadows_render_only_when_they_change(lab):
    s, d = lab
    _render(s, d)
    effect = s.scene.effect("surfaces")
    probe, sun = effect.probe.captures, effect.shadows.sun.renders
    _render(s, d)
    assert effect.probe.captures == probe and effect.shadows.sun.renders == sun
    _render(s, d, sun_elevation=40.0)
    assert effect.probe.captures == probe + 1 and effect.shadows.sun.renders == sun + 1


@pytest.mark.parametrize("values, camera", [
    ({"sun_elevation": 90.0}, None), ({"sun_elevation": 0.0}, None),
    ({"sun_elevation": 89.99, "shadow_cascades": "4"}, None),
    ({}, (-1.6, 0.4, -2.2)),  # inside the crate
    ({"shadow_filter": "pcss"}, (0.6, 1.2, -1.6)),  # inside the occluder slab
])
def test_stability(lab, values, camera):
    s, d = lab
    img = _render(s, d, camera=camera, **values)
    assert np.isfinite(img).all()
    assert img.max() > 0.0


def test_a_users_mesh_stands_in_the_room_and_casts(lab, tmp_path):
    """``--mesh FILE``: the mesh is fitted under the occluder, drawn, and the shadow maps and
    the probe are rendered again with it."""
    import trimesh

    from app.sim.mesh_files import load_mesh

    s, d = lab
    path = tmp_path / "torus.obj"
    trimesh.creation.torus(0.5, 0.2).export(path)
    effect = s.scene.effect("surfaces")
    before = _render(s, d)
    sun, probe = effect.shadows.sun.renders, effect.probe.captures
    fitted = effect.set_user_mesh(load_mesh(path))
    try:
        lo, hi = fitted.bounds()
        assert abs(lo[1]) < 1e-5 and hi[1] < 1.15  # on the floor, under the slab
        after = _render(s, d)
        assert np.isfinite(after).all()
        assert np.abs(after - before).max() > 0.05
        assert effect.shadows.sun.renders == sun + 1 and effect.probe.captures == probe + 1
    finally:
        effect.user_mesh = None
        effect._user_revision += 1


def test_a_receivers_filter_or_taps_rebinds_the_maps_without_rendering_them(lab):
    """The shadow maps' key is the light, the maps' own settings and the casters: a second frame
    with nothing moved renders none, a filter or tap change renders none (the receivers read
    the same maps), the spot's angle renders the spot's alone."""
    s, d = lab
    effect = s.scene.effect("surfaces")
    maps = (effect.shadows.sun, effect.shadows.point, effect.shadows.spot)
    _render(s, d)
    counts = [m.renders for m in maps]
    _render(s, d)
    _render(s, d, shadow_filter="pcss", shadow_taps="fast")
    assert [m.renders for m in maps] == counts
    _render(s, d, spot_angle=20.0)
    assert [m.renders for m in maps] == [counts[0], counts[1], counts[2] + 1]


def test_the_probes_first_capture_equals_its_next(lab):
    """The probe's capture binds the lights' specular LUT itself: the first frame of a session
    and a frame after a re-capture are the same image (the capture once read whatever texture
    its sampler's unit held)."""
    s, d = lab
    effect = s.scene.effect("surfaces")
    effect.probe.release()
    first = _render(s, d)
    _render(s, d, ambient=0.2)
    again = _render(s, d)
    assert effect.probe.captures >= 2
    assert np.array_equal(first, again)


@pytest.mark.parametrize("values", [{}, {"shadow_filter": "pcss", "shadow_taps": "fast"},
                                    {"shadow_filter": "vsm", "reflection": "none"}])
def test_the_specialised_programs_draw_the_generic_image(lab, values):
    """``surfaces.specialise`` (the lights' filter and taps and the probe's branch as constants)
    only changes what the shader compiles: the same image as the one program with uniforms."""
    s, d = lab
    on = _render(s, d, specialise=True, **values)
    off = _render(s, d, specialise=False, **values)
    assert np.abs(on - off).max() < 1e-4


def test_msaa_auto_follows_the_renderer_and_the_coverage(lab):
    """``surfaces.msaa=auto``: no MSAA on a software renderer, 4× on a GPU, and 4× whenever a
    quad is drawn with alpha-to-coverage (which needs it); 0 and 4 are pinned."""
    s, d = lab
    effect = s.scene.effect("surfaces")
    _render(s, d)
    assert effect.samples() == (0 if s.gpu.caps.software else 4)
    quad = effect.layout.quads[0].name.split("_")[0]
    _render(s, d, **{f"{quad}_mode": "alpha-to-coverage"})
    assert effect.samples() == 4
    for pinned in ("0", "4"):
        _render(s, d, msaa=pinned)
        assert effect.samples() == int(pinned)

"""The shading lab scene (spec/003 §2.1–2.3, §2.12): the test objects render finite; every
lighting model, toon mode, the Gouraud switch and the parallax modes change the image of the
objects (and nothing else); the lamps and the spot add light; a user's mesh replaces the row."""

from __future__ import annotations

import numpy as np
import pytest

from app.runtime import open_session, scene_params
from app.sim import lab_meshes

SIZE = (160, 90)


@pytest.fixture
def shading(gl_ctx):
    made = []

    def make(*sets):
        s = open_session("shading", scene_params("shading", sets=[*sets]), ctx=gl_ctx)
        made.append(s)
        return s
    yield make
    for s in made:
        s.release()


def _render(session, **values):
    for name, value in values.items():
        session.params.set(f"shading.{name}", value)
    frame = session.scene.frame(SIZE, 0.0)
    target = session.gpu.target("test", "image", SIZE)
    session.scene.render(frame, target)
    return target.read()[..., :3]


def test_the_test_objects_render_finite_on_the_background(shading):
    s = shading("shading.turntable=0", "shading.ground=none")  # the objects alone
    img = _render(s)
    assert np.isfinite(img).all()
    background = np.asarray(s.scene.background)
    covered = np.abs(img - background).max(axis=-1) > 1e-3
    assert 0.05 < covered.mean() < 0.6
    # five objects side by side: covered columns in at least five separate runs
    cols = covered.any(axis=0).astype(int)
    runs = int(((np.diff(cols) == 1).sum()) + cols[0])
    assert runs >= 5, runs


@pytest.mark.parametrize("name, values", [
    ("lighting_model", (0, 1, 2)), ("toon", (0, 1, 2, 3)), ("gouraud", (False, True)),
    ("rim", (False, True)), ("parallax_mode", (0, 1, 2, 3, 4)), ("spot", (False, True)),
    ("contour", ("none", "hull", "hull_smooth", "rim_threshold", "rim_soft", "rim_50x2",
                 "edges_sobel", "edges_roberts")),
    ("wall_map", ("bricks", "planks", "stones")),
])
def test_every_switch_changes_the_image(shading, name, values):
    s = shading("shading.turntable=0", "shading.lamps=1")
    images = [_render(s, **{name: v}) for v in values]
    for a, b in zip(images, images[1:]):
        assert np.isfinite(b).all()
        assert np.abs(a - b).max() > 1e-3, name


def test_the_lamps_add_light(shading):
    s = shading("shading.turntable=0")
    dark = _render(s, lamps=0).mean()
    lit = [_render(s, lamps=n).mean() for n in (1, 2, 4)]
    assert dark < lit[0] < lit[1] < lit[2]


def test_stepped_toon_leaves_few_levels_on_the_sphere(shading):
    s = shading("shading.turntable=0", "shading.object=sphere", "shading.lamps=0",
                "shading.specularity=0", "shading.ambient=0", "shading.ground=none")
    smooth = _render(s, toon=0)
    stepped = _render(s, toon=2)
    background = np.asarray(s.scene.background)
    on = np.abs(stepped - background).max(axis=-1) > 1e-3
    levels = np.unique(np.round(stepped[on][:, 0], 3))
    assert len(levels) <= 6 < len(np.unique(np.round(smooth[on][:, 0], 3)))


def test_a_user_mesh_replaces_the_row(shading):
    s = shading("shading.turntable=0", "shading.ground=none")
    cube = lab_meshes.from_arrays(
        "cube", np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float),
        np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                  [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]]))
    row = _render(s)
    s.scene.effect("shading").set_user_mesh(cube)
    assert s.params["shading.object"] == "user"
    one = _render(s)
    background = np.asarray(s.scene.background)
    assert (np.abs(one - background).max(axis=-1) > 1e-3).mean() < (
        np.abs(row - background).max(axis=-1) > 1e-3).mean()
    assert np.isfinite(one).all()


def test_bloom_runs_after_everything_and_brightens_around_the_lit_windows(shading):
    s = shading("shading.turntable=0", "shading.object=wall", "shading.emission_color=4,3,2",
                "shading.bloom_threshold=0.8")
    plain = _render(s, bloom=False)
    frame = s.scene.frame(SIZE, 0.0)
    target = s.gpu.target("test", "image", SIZE)
    s.params.set("shading.bloom", True)
    passes = s.scene.passes(frame, target)
    assert [p.name for p in passes][-1] == "shading.bloom"
    bloomed = _render(s, bloom=True)
    assert np.isfinite(bloomed).all()
    assert bloomed.sum() > plain.sum()


def test_the_ramp_is_edited_in_the_panel_and_the_ramp_mode_follows(shading):
    """spec/003 §2.12 Ramp: the bands are parameters (the inspector's Toon popup); darkening the
    light band darkens the lit side, and the other modes do not read it."""
    s = shading("shading.turntable=0", "shading.object=sphere", "shading.toon=3")
    before = _render(s)
    after = _render(s, ramp_light=(0.2, 0.2, 0.2))
    on = np.abs(before - np.asarray(s.scene.background)).max(axis=-1) > 1e-3
    assert on.sum() > 100
    assert after[on].mean() < 0.9 * before[on].mean()
    s.params.set("shading.toon", 0)
    plain = _render(s)
    assert np.array_equal(plain, _render(s, ramp_light=(1.0, 1.0, 1.0)))


def test_each_object_can_have_its_own_material(shading):
    """spec/003 Fig. 130: one inspector per material — the table switched to its own Stepped
    material changes the table's pixels and no other object's."""
    s = shading("shading.turntable=0", "shading.lamps=0")
    effect = s.scene.effect("shading")
    shared = _render(s)
    table = effect.material("table")
    assert table["shading.toon"] == s.params["shading.toon"]  # starts as the lab's
    table.set("shading.toon", 2)
    assert np.array_equal(_render(s), shared)  # not its own yet: the lab's values
    table.set("material.own", True)
    own = _render(s)
    changed = np.abs(own - shared).max(axis=-1) > 1e-3
    cols = np.nonzero(changed.any(axis=0))[0]
    assert changed.sum() > 20
    # the table stands second from the left: its columns only
    width = SIZE[0]
    assert cols.min() > 0.15 * width and cols.max() < 0.45 * width, (cols.min(), cols.max())
    titles = [item.title for item in effect.panel_items()]
    assert "table: CelShader" in titles and "wall: ComplexCelShader" in titles


def _frame_at(session, t: float) -> None:
    target = session.gpu.target("test", "image", SIZE)
    session.scene.render(session.scene.frame(SIZE, t), target)


def test_the_suns_map_renders_only_when_the_sun_or_a_caster_moves(shading):
    """A still row: the second frame renders no shadow map, nor does a filter or tap change;
    the sun's move renders it again, and so does the turntable turning the objects."""
    s = shading("shading.turntable=0")
    effect = s.scene.effect("shading")
    sun = effect.sun_shadow
    _frame_at(s, 0.0)
    count = sun.renders
    assert count >= 1
    _frame_at(s, 0.5)
    s.params.set("shading.shadow_filter", "pcf")
    s.params.set("shading.shadow_taps", "fast")
    _frame_at(s, 0.5)
    assert sun.renders == count
    s.params.set("shading.sun_elevation", s.params["shading.sun_elevation"] - 10.0)
    _frame_at(s, 0.5)
    assert sun.renders == count + 1
    s.params.set("shading.turntable", 30.0)
    _frame_at(s, 0.5)
    _frame_at(s, 1.0)
    assert sun.renders == count + 3


@pytest.mark.parametrize("taps", ["full", "fast"])
def test_the_specialised_receivers_draw_the_generic_image(shading, monkeypatch, taps):
    """The objects and the ground drawn with the programs specialised to the shadow filter and
    taps (``Shading.receiver``) and with the one program reading them as uniforms: one image."""
    from app.effects.shading.effect import Shading

    s = shading("shading.turntable=0", f"shading.shadow_taps={taps}")
    special = _render(s)
    monkeypatch.setattr(Shading, "receiver", lambda self, spec: spec)
    generic = _render(s)
    assert np.abs(special - generic).max() < 1e-4

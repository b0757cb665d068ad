"""VR mode's numpy side (spec/003 §2.15, criteria 35–36): the FixedHealth ring's twin
(app/sim/vr.py) — where spec/003 eq. 9.1 and spec/003 eq. 9.2 put it in each aspect form,
its angle, sections, gaps and colours —, the marker icons and billboards, the eye cameras of
app/render/stereo.py and the disparity of a parallel pair, and the one-line errors of bad
inputs."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from app.errors import ParamError
from app.render.stereo import eye_camera, eye_cameras, eye_size, eye_viewport
from app.runtime import scene_params
from app.sim import vr
from app.sim.camera import Camera
from tests.helpers import measures

FULL, EMPTY = (1.0, 0.0, 0.0), (1.0, 0.706, 0.706)


# -- the ring's position: spec/003 eq. 9.1 and eq. 9.2 ------------------------------------------
@pytest.mark.parametrize("w, h", [(1280, 720), (640, 720), (161, 90)])
def test_the_corrected_form_centres_the_ring_at_screen_x_y_and_keeps_it_round(w, h):
    cx, cy = vr.ring_centre_px(0.666, 0.579, w, h)
    assert cx == pytest.approx(0.666 * w) and cy == pytest.approx(0.579 * h)
    hx, hy = vr.ring_half_extent_px(0.014, w, h)
    assert hx == pytest.approx(hy)
    assert hx == pytest.approx(5 * 0.014 * w)  # 10·s of the width across


def test_the_documents_form_moves_the_centre_and_squashes_the_ring():
    w, h = 1280, 720
    cx, cy = vr.ring_centre_px(0.666, 0.579, w, h, "document")
    assert cx == pytest.approx(0.666 * w)
    # its centre lands at ar·(2Y − 1) in NDC, not at Y: 0.579·720 = 416.9 px, it is at 392.0
    assert cy == pytest.approx((h / w * (2 * 0.579 - 1) + 1) / 2 * h)
    assert abs(cy - 0.579 * h) > 20
    hx, hy = vr.ring_half_extent_px(0.014, w, h, "document")
    assert hy / hx == pytest.approx((h / w) ** 2)  # an ellipse, 0.32 as tall as wide


def test_the_repositorys_form_is_round_but_off_centre():
    w, h = 1280, 720
    hx, hy = vr.ring_half_extent_px(0.014, w, h, "repository")
    assert hx == pytest.approx(hy)
    _, cy = vr.ring_centre_px(0.666, 0.579, w, h, "repository")
    assert cy == pytest.approx((w / h * (2 * 0.579 - 1) + 1) / 2 * h)
    assert abs(cy - 0.579 * h) > 40


@settings(max_examples=60, deadline=None)
@given(x=st.floats(0, 1), y=st.floats(0, 1), s=st.floats(0.001, 0.2),
       side=st.integers(1, 4000), form=st.sampled_from(vr.ASPECT_FORMS))
def test_on_a_square_viewport_the_three_forms_agree_and_invert(x, y, s, side, form):
    obj = np.array([[-5.0, -5.0], [5.0, 5.0], [1.25, -3.5]])
    ref = vr.ring_clip_position(obj, x, y, s, side, side, "corrected")
    assert np.allclose(vr.ring_clip_position(obj, x, y, s, side, side, form), ref)
    # the uv at a clip position's pixel is the vertex's: the twin's inverse is exact
    px, py = (ref[:, 0] + 1) / 2 * side, (ref[:, 1] + 1) / 2 * side
    uv, inside = vr.ring_uv_at_pixels(px, py, x, y, s, side, side, form)
    assert np.allclose(uv, obj / 10 + 0.5, atol=1e-6)
    assert inside[2]


def test_an_unknown_aspect_form_or_angle_mode_is_refused_in_one_line():
    with pytest.raises(ValueError, match="allowed corrected, document, repository"):
        vr.ring_clip_position((0, 0), 0.5, 0.5, 0.01, 10, 10, "unity")
    with pytest.raises(ValueError, match="allowed full, acos"):
        vr.ring_angle((1.0, 0.0), "atan")


# -- the ring's angle, sections and gaps ---------------------------------------------------------
@settings(max_examples=200, deadline=None)
@given(theta=st.floats(0.0, 359.999), r=st.floats(0.01, 1.0))
def test_the_full_angle_covers_0_to_360_and_acos_mirrors_the_lower_half(theta, r):
    e = r * np.array([math.cos(math.radians(theta)), math.sin(math.radians(theta))])
    a = float(vr.ring_angle(e))
    assert 0.0 <= a < 360.0
    assert min(abs(a - theta), 360 - abs(a - theta)) < 1e-6
    acos = float(vr.ring_angle(e, "acos"))
    assert 0.0 <= acos <= 180.0
    mirrored = float(vr.ring_angle(e * np.array([1.0, -1.0]), "acos"))
    assert acos == pytest.approx(mirrored, abs=1e-9)  # the document's failure: no lower half


def test_the_centre_has_angle_zero_not_nan():
    assert vr.ring_angle((0.0, 0.0)) == 0.0 and vr.ring_angle((0.0, 0.0), "acos") == 0.0


def test_lives_8_gives_45_degree_sections_with_gaps_at_their_boundaries():
    angles = 22.5 + 45.0 * np.arange(8)
    section, gap = vr.ring_sections(angles, 8)
    assert np.array_equal(section, np.arange(8)) and np.all(gap == 1.0)
    boundaries = 45.0 * np.arange(8)
    for off in (-2.2, -1.0, 0.0, 1.0, 2.2):  # within 5 % of a step (2.25°) of a boundary
        _, g = vr.ring_sections((boundaries + off) % 360.0, 8)
        assert np.all(g < 1e-6), (off, g)
    _, g = vr.ring_sections(boundaries + 3.0, 8)  # past the gap
    assert np.all(g == 1.0)


@pytest.mark.parametrize("lives, remaining, full", [
    (8, 3, [0, 1, 2]), (13, 3, [0, 1, 2]), (25, 15, list(range(15))),
    (20, 12.35, list(range(13))),  # Fig. 145's inspector: 13 of 20 sections full
    (8, 20, list(range(8))),  # more remaining than lives: clamped, the ring full
    (8, -2, []), (8, 0, []),
])
def test_sections_below_remaining_are_full_and_the_rest_empty(lives, remaining, full):
    n, _ = vr.clamp_ring(lives, remaining)
    step = 360.0 / n
    angles = step * (np.arange(n) + 0.5)
    uv = 0.5 + 0.4 * np.stack([np.cos(np.radians(angles)), np.sin(np.radians(angles))], -1)
    frag = vr.ring_fragment(uv, np.ones(n), lives, remaining, 0.5, FULL, EMPTY)
    is_full = np.isclose(frag[:, 1], 0.0)  # Color Full has no green
    assert list(np.flatnonzero(is_full)) == full
    assert np.allclose(frag[~is_full, :3], EMPTY)
    assert np.allclose(frag[:, 3], 0.5)  # alpha = Visibility × mask (1 here)


@settings(max_examples=100, deadline=None)
@given(red=st.floats(0.0, 1.0), v=st.floats(0.0, 1.0), theta=st.floats(0.0, 359.9))
def test_alpha_is_visibility_times_the_mask_kept_above_one_half(red, v, theta):
    uv = 0.5 + 0.4 * np.array([math.cos(math.radians(theta)), math.sin(math.radians(theta))])
    frag = vr.ring_fragment(uv, red, 8, 3, v, FULL, EMPTY)
    _, gap = vr.ring_sections(vr.ring_angle(2 * uv - 1), 8)
    mask = red if red > 0.5 else 0.0
    assert float(frag[3]) == pytest.approx(v * mask * float(gap))
    assert np.all(frag[:3] <= mask * float(gap) + 1e-12)


def test_bad_lives_and_remaining_are_clamped_as_documented():
    assert vr.clamp_ring(0, 3) == (1, 1.0)
    assert vr.clamp_ring(8, 9) == (8, 8.0)
    assert vr.clamp_ring(8, -1) == (8, 0.0)


def test_the_ui_texture_is_a_ring_in_red():
    tex = vr.ring_mask_texture(256)
    c = (np.arange(256) + 0.5) / 256 * 2 - 1
    r = np.hypot(c[None, :], c[:, None])
    kept = tex[..., 0] > 0.5
    inside = (r > vr.RING_INNER + 0.01) & (r < vr.RING_OUTER - 0.01)
    outside = (r < vr.RING_INNER - 0.01) | (r > vr.RING_OUTER + 0.01)
    assert kept[inside].all() and not kept[outside].any()
    assert np.all(tex[..., 3] == 1.0) and np.all(tex[..., 1:3] == 0.0)
    with pytest.raises(ValueError, match="allowed 8 or more"):
        vr.ring_mask_texture(4)


def test_bilinear_sampling_matches_gl_at_texel_centres_and_between():
    tex = np.arange(12, dtype=np.float64).reshape(3, 4, 1)
    assert vr.sample_bilinear(tex, (0.125, 0.5 / 3))[0] == 0.0
    assert vr.sample_bilinear(tex, (0.25, 0.5 / 3))[0] == pytest.approx(0.5)
    assert vr.sample_bilinear(tex, (0.125, 1.0 / 3))[0] == pytest.approx(2.0)
    assert vr.sample_bilinear(tex, (-1.0, -1.0))[0] == 0.0  # clamped to the edge


def test_the_twin_image_is_centred_round_and_scales_with_element_size():
    w, h, x, y = 200, 160, 0.6, 0.45
    radii = []
    for s in (0.02, 0.04):  # rings 20 and 40 px in radius
        img = vr.ring_image(w, h, x, y, s, 8, 3, 1.0, FULL, EMPTY, background=(0, 0, 0))
        a = img.sum(-1) > 0
        cx, cy = measures.ring_centroid(a.astype(float))
        assert abs(cx - x * w) < 0.5 and abs(cy - y * h) < 0.5
        ys, xs = np.nonzero(a)
        assert abs((xs.max() - xs.min()) - (ys.max() - ys.min())) <= 1  # round
        radii.append((xs.max() - xs.min() + 1) / 2)
    assert radii[1] / radii[0] == pytest.approx(2.0, rel=0.05)


# -- markers -------------------------------------------------------------------------------------
def test_each_role_has_its_own_premultiplied_icon_on_a_centred_badge():
    icons = {role: vr.marker_icon(role, 64) for role in vr.ICON_ROLES}
    for role, icon in icons.items():
        assert icon.shape == (64, 64, 4) and icon.dtype == np.float32
        assert np.all(icon[..., :3] <= icon[..., 3:] + 1e-6), role  # premultiplied
        cx, cy = measures.ring_centroid(icon[..., 3])
        assert abs(cx - 32) < 0.05 and abs(cy - 32) < 0.05, role
        assert 0.55 < (icon[..., 3] > 0.5).mean() < 0.75  # a disc of radius 0.46
    roles = list(icons)
    for i, a in enumerate(roles):
        for b in roles[i + 1:]:
            assert np.abs(icons[a] - icons[b]).max() > 0.3, (a, b)
    assert np.array_equal(vr.marker_icon("blacksmith"), icons["villager"])
    assert vr.icon_index("missions") == 0 and vr.icon_index("anyone") == 2


def test_the_missions_glyph_is_an_upright_exclamation_mark():
    icon = vr.marker_icon("missions", 64)
    ink = icon[..., 1] < 0.25 * icon[..., 3]  # the glyph is dark on the yellow fill
    ink &= icon[..., 3] > 0.99
    rows = np.nonzero(ink[:, 28:36].any(axis=1))[0]  # row 0 is v = 0, the bottom
    bar_rows = rows[rows > 32]
    dot_rows = rows[rows < 32]
    assert bar_rows.size > 12 and dot_rows.size > 3  # a long bar above, a dot below


def test_billboard_corners_face_the_camera_and_surround_the_centre():
    cam = Camera(position=(1.0, 2.0, 3.0), yaw=40.0, pitch=-20.0)
    r, u, f = cam.basis()
    centre = vr.marker_centre((0.0, 1.8, -4.0), 0.55)
    assert np.allclose(centre, (0.0, 2.35, -4.0))
    c = vr.billboard_corners(centre, r, u, 0.5)
    assert np.allclose(c.mean(axis=0), centre)
    assert np.allclose((c - centre) @ f, 0.0)  # in a plane parallel to the image
    assert np.linalg.norm(c[1] - c[0]) == pytest.approx(0.5)


# -- the stereo pair (criterion 35, numpy side) --------------------------------------------------
def test_eye_cameras_are_the_head_moved_half_the_ipd_along_its_right_vector():
    head = Camera(position=(2.0, 1.6, -3.0), yaw=70.0, pitch=15.0, fov=75.0)
    left, right = eye_cameras(head, 0.064)
    r, _, _ = head.basis()
    assert np.allclose(np.subtract(right.position, left.position), 0.064 * r)
    assert np.allclose((np.add(left.position, right.position)) / 2, head.position)
    for eye in (left, right):
        assert (eye.yaw, eye.pitch, eye.fov, eye.near, eye.far) == (
            head.yaw, head.pitch, head.fov, head.near, head.far)  # parallel axes
    assert np.allclose(eye_camera(head, 0.0, "left").position, head.position)


@settings(max_examples=40, deadline=None)
@given(depth=st.floats(0.5, 200.0), ipd=st.floats(0.01, 0.2), lateral=st.floats(-0.3, 0.3))
def test_projected_disparity_is_ipd_times_focal_over_depth(depth, ipd, lateral):
    head = Camera(position=(0.0, 0.0, 0.0), yaw=0.0, pitch=0.0, fov=60.0, near=0.05)
    w, h = 80, 90
    point = np.array([lateral * depth, 0.1 * depth, -depth, 1.0])
    xs = []
    for cam in eye_cameras(head, ipd):
        clip = cam.projection_matrix(w / h) @ cam.view_matrix() @ point
        xs.append((clip[0] / clip[3] + 1) / 2 * w)
    want = float(measures.disparity_px(depth, ipd, h, 60.0))
    assert xs[0] - xs[1] == pytest.approx(want, rel=1e-6)


def test_near_disparity_exceeds_far_disparity():
    d = measures.disparity_px(np.array([1.0, 2.0, 10.0, 100.0]), 0.064, 720, 90.0)
    assert np.all(np.diff(d) < 0) and d[0] == pytest.approx(0.064 * 360)


@pytest.mark.parametrize("w", [1, 2, 3, 160, 161, 1281])
def test_eye_viewports_split_the_frame_and_eye_textures_follow_them(w):
    left, right = eye_viewport((w, 90), "left"), eye_viewport((w, 90), "right")
    assert left[0] == 0 and left[2] + right[2] == w and right[0] == left[2]
    assert left[2] == w // 2
    for eye, vp in (("left", left), ("right", right)):
        assert eye_size((w, 90), 1.0, eye) == (max(1, vp[2]), 90)
        sw, sh = eye_size((w, 90), 0.5, eye)
        assert sw == max(1, round(vp[2] * 0.5)) and sh == 45


@pytest.mark.parametrize("call, match", [
    (lambda: eye_camera(Camera(), 0.06, "middle"), "eye 'middle': allowed left, right"),
    (lambda: eye_viewport((160, 90), "both"), "eye 'both': allowed left, right"),
])
def test_bad_stereo_inputs_are_one_line_errors(call, match):
    with pytest.raises(ValueError, match=match) as info:
        call()
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("assignment, match", [
    ("vr.ipd=-0.01", r"vr.ipd='-0.01' is out of range: allowed a number in \[0, 0.2\]"),
    ("vr.ipd=nan", r"vr.ipd='nan' is not finite: allowed a number in \[0, 0.2\]"),
    ("vr.render_scale=inf", r"vr.render_scale='inf' is not finite"),
    ("vr.lives=0", r"vr.lives='0' is out of range: allowed an integer in \[1, 64\]"),
    ("vr.remaining=65", r"vr.remaining='65' is out of range: allowed a number in \[0, 64\]"),
    ("vr.render_scale=0", r"vr.render_scale='0' is out of range: allowed a number in "
     r"\[0.25, 2\]"),
    ("vr.visibility=1.5", r"vr.visibility='1.5' is out of range: allowed a number in \[0, 1\]"),
    ("vr.health_ring=sometimes", "allowed one of vr, always, off"),
    ("vr.ring_aspect=unity", "allowed one of corrected, document, repository"),
])
def test_bad_parameters_are_refused_in_one_line(assignment, match):
    with pytest.raises(ParamError, match=match) as info:
        scene_params("village", sets=[assignment])
    assert "\n" not in str(info.value)


def test_the_parameters_carry_fig_145s_values():
    p = scene_params("village")
    assert (p["vr.visibility"], p["vr.element_size"], p["vr.screen_x"], p["vr.screen_y"]) == (
        0.5, 0.014, 0.666, 0.579)
    assert (p["vr.lives"], p["vr.remaining"]) == (20, 12.35)
    assert p["vr.health_ring"] == "vr" and p["vr.markers"] == "vr"
    assert p["vr.ring_aspect"] == "corrected" and p["vr.ring_angle"] == "full"

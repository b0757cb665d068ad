"""VR mode — numpy twins of ``glsl/vr/`` (spec/003 §2.15): the FixedHealth ring (the one
head-locked element the thesis allows), the world-space markers above the characters, and the
disparity of a parallel-axis stereo pair.

**The ring** (``Custom/VR/FixedHealth``). A quad — Unity's built-in Plane mesh, 10 × 10 units in
its local (x, z), :data:`PLANE_HALF` = 5 — whose vertex shader writes the clip position
directly (spec/003 eq. 9.1, spec/003 eq. 9.2)::

    x = 2(X + s·obj_x) − 1          y = ar·(2(Y + s·obj_y) − 1),  ar = height/width (as written)

X, Y (Screen X, Screen Y) in [0, 1] of the viewport, s the Element Size: the fraction of the
viewport's width per unit of the Plane mesh, so the ring is 10·s of the width across (Fig. 145's
0.014: 14 % of the width, 179 px of a 1280-px-wide eye).

*Erratum.* The document's form multiplies the centre by ar too (it lands at
ar·(2Y − 1) in NDC, not at Y) and squashes the ring vertically by (H/W)² (an ellipse); the
thesis's repository multiplies y by width/height instead, which makes the ring round but moves
the centre to (W/H)·(2Y − 1). Criterion 36 wants it centred at (ScreenX, ScreenY) of the viewport
and round, so the default (:data:`ASPECT_FORMS` ``corrected``) applies the aspect to the offset
only: ``y = 2(Y + s·(W/H)·obj_y) − 1``; ``document`` and ``repository`` reproduce the two
published forms and their failures.

The fragment shader: ``e = 2·uv − 1``; the angle of e counter-clockwise from the screen's right
over the full 0–360° (:func:`ring_angle`; the document's acos of e·(1, 0) alone covers only
0–180°, mirroring the lower half onto the upper — kept as the ``acos`` mode; the repository fixes
it by quadrant); ``step = 360°/Lives``, ``section = floor(angle/step)``; a gap of
:data:`GAP_FRACTION` of a step on each side of every section boundary (the repository's
``saturate((a − t)·(step − a − t))``, a in degrees within the section, t = 5 % of a step); a
section is Color Full when ``Remaining·step > section·step`` (the repository's test), else Color
Empty; the UI texture's red channel is the ring's shape (:func:`ring_mask_texture`, generated
here; the repository keeps only texels above ½). Output (the repository's, kept)::

    rgb = C·mask·gap            alpha = Visibility·mask·gap       mask = red·[red > ½]

blended SrcAlpha/OneMinusSrcAlpha (so the colour of the antialiased edge is attenuated twice:
the repository's, kept). Remaining is clamped to [0, Lives] (more remaining than lives: the ring
full) and Lives is an integer ≥ 1 (the parameter's range refuses 0).

**Markers.** World-space icons (the thesis's world-space canvases above the NPCs): a billboard
:func:`marker_centre` above each character's head, facing the camera (its plane spanned by the
camera's right and up vectors, so both eyes of a stereo pair see the same quad), an icon per
role (:func:`marker_icon`, premultiplied alpha on a round badge).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike

#: half the side of Unity's built-in Plane mesh (10 × 10 units), the quad the ring is drawn on
PLANE_HALF = 5.0
#: spec/003 eq. 9.2's aspect factor: the corrected default, the document's h/w, the repository's w/h
ASPECT_FORMS = ("corrected", "document", "repository")
#: how the ring's angle is found: by quadrant over 0–360° (repository), or the document's acos
ANGLE_MODES = ("full", "acos")
#: the gap on each side of a section boundary, as a fraction of a step (the repository's 5 %)
GAP_FRACTION = 0.05
#: the ring's shape in the UI texture: inner and outer radius of e = 2·uv − 1
RING_INNER, RING_OUTER = 0.64, 0.96
#: when the ring and the markers are shown
SHOW_MODES = ("vr", "always", "off")
#: marker icons by role, in the shader's order; any other role gets the villager's
ICON_ROLES = ("missions", "shop", "villager")


def _aspect_form(form: str) -> str:
    if form not in ASPECT_FORMS:
        raise ValueError(f"ring aspect form {form!r}: allowed {', '.join(ASPECT_FORMS)}")
    return form


def ring_clip_position(obj: ArrayLike, screen_x: float, screen_y: float, size: float,
                       width: float, height: float, form: str = "corrected") -> np.ndarray:
    """Clip (NDC, w = 1) x and y of Plane-mesh points ``obj`` (..., 2) (spec/003 eq. 9.1,
    spec/003 eq. 9.2) for a viewport of ``width`` × ``height`` pixels."""
    o = np.asarray(obj, np.float64)
    x = 2.0 * (screen_x + size * o[..., 0]) - 1.0  # spec/003 eq. 9.1
    form = _aspect_form(form)
    if form == "corrected":
        y = 2.0 * (screen_y + size * (width / height) * o[..., 1]) - 1.0  # spec/003 eq. 9.2
    else:
        ar = height / width if form == "document" else width / height
        y = ar * (2.0 * (screen_y + size * o[..., 1]) - 1.0)  # spec/003 eq. 9.2
    return np.stack([x, y], axis=-1)


def ring_uv_at_pixels(px: ArrayLike, py: ArrayLike, screen_x: float, screen_y: float,
                      size: float, width: float, height: float,
                      form: str = "corrected") -> tuple[np.ndarray, np.ndarray]:
    """The ring quad's uv at window positions (px, py) (pixels, y up, pixel centres at i + ½)
    — the inverse of :func:`ring_clip_position` — and whether each lies on the quad."""
    px, py = np.broadcast_arrays(np.asarray(px, np.float64), np.asarray(py, np.float64))
    nx = 2.0 * px / width - 1.0
    ny = 2.0 * py / height - 1.0
    s = max(float(size), 1e-12)
    ox = ((nx + 1.0) / 2.0 - screen_x) / s
    form = _aspect_form(form)
    if form == "corrected":
        oy = ((ny + 1.0) / 2.0 - screen_y) / (s * width / height)
    else:
        ar = height / width if form == "document" else width / height
        oy = ((ny / ar + 1.0) / 2.0 - screen_y) / s
    uv = np.stack([ox, oy], axis=-1) / (2.0 * PLANE_HALF) + 0.5
    inside = np.all((uv >= 0.0) & (uv <= 1.0), axis=-1)
    return uv, inside


def ring_centre_px(screen_x: float, screen_y: float, width: float, height: float,
                   form: str = "corrected") -> tuple[float, float]:
    """Where the ring's centre lands, in window pixels (y up)."""
    c = ring_clip_position((0.0, 0.0), screen_x, screen_y, 0.0, width, height, form)
    return float((c[0] + 1.0) / 2.0 * width), float((c[1] + 1.0) / 2.0 * height)


def ring_half_extent_px(size: float, width: float, height: float,
                        form: str = "corrected") -> tuple[float, float]:
    """Half the quad's width and height in pixels (equal, i.e. round, only when corrected or
    as the repository writes it)."""
    a = ring_clip_position([(0.0, 0.0), (PLANE_HALF, PLANE_HALF)], 0.5, 0.5, size, width,
                           height, form)
    d = a[1] - a[0]
    return float(d[0] * width / 2.0), float(d[1] * height / 2.0)


def ring_angle(e: ArrayLike, mode: str = "full") -> np.ndarray:
    """The angle of e (..., 2) in degrees, counter-clockwise from +x: in [0, 360) by quadrant
    (``full``, the repository's fix) or the document's acos(ê·(1, 0)) in [0, 180] (``acos``);
    0 at e = 0."""
    if mode not in ANGLE_MODES:
        raise ValueError(f"ring angle mode {mode!r}: allowed {', '.join(ANGLE_MODES)}")
    e = np.asarray(e, np.float64)
    r = np.hypot(e[..., 0], e[..., 1])
    safe = r > 1e-9
    if mode == "acos":
        c = np.where(safe, e[..., 0] / np.where(safe, r, 1.0), 1.0)
        return np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))
    a = np.degrees(np.arctan2(e[..., 1], e[..., 0]))
    a = np.where(a < 0.0, a + 360.0, a)
    return np.where(safe, np.where(a >= 360.0, 0.0, a), 0.0)


def clamp_ring(lives: float, remaining: float) -> tuple[int, float]:
    """(Lives, Remaining) as the shader uses them: Lives an integer ≥ 1, Remaining in
    [0, Lives]."""
    n = max(1, int(round(lives)))
    return n, float(min(max(remaining, 0.0), n))


def ring_sections(angle: ArrayLike, lives: float) -> tuple[np.ndarray, np.ndarray]:
    """(section index, gap mask) at ``angle`` degrees for ``lives`` sections: the gap is 0
    within :data:`GAP_FRACTION` of a step of a section boundary, 1 elsewhere (the
    repository's saturate((a − t)(step − a − t)), degrees²)."""
    n, _ = clamp_ring(lives, 0.0)
    step = 360.0 / n
    a = np.asarray(angle, np.float64)
    section = np.floor(a / step)
    within = a - section * step
    t = GAP_FRACTION * step
    gap = np.clip((within - t) * ((step - within) - t), 0.0, 1.0)
    return section, gap


def ring_mask_texture(size: int = 256) -> np.ndarray:
    """The UI texture (size × size, float32 RGBA, row 0 at v = 0): a ring of radius
    [:data:`RING_INNER`, :data:`RING_OUTER`] of e = 2·uv − 1 in the red channel, its edges
    antialiased over one texel; alpha 1."""
    if size < 8:
        raise ValueError(f"ring texture size {size}: allowed 8 or more texels")
    c = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    r = np.hypot(c[None, :], c[:, None])
    w = 2.0 / size
    red = (np.clip((r - RING_INNER) / w + 0.5, 0.0, 1.0)
           * np.clip((RING_OUTER - r) / w + 0.5, 0.0, 1.0))
    out = np.zeros((size, size, 4), np.float32)
    out[..., 0] = red
    out[..., 3] = 1.0
    return out


def sample_bilinear(texture: np.ndarray, uv: ArrayLike) -> np.ndarray:
    """GL's LINEAR filter with clamp-to-edge at uv (..., 2) of ``texture`` (H, W, C) whose row
    0 is v = 0."""
    tex = np.asarray(texture, np.float64)
    h, w = tex.shape[:2]
    uv = np.asarray(uv, np.float64)
    tx = uv[..., 0] * w - 0.5
    ty = uv[..., 1] * h - 0.5
    x0, y0 = np.floor(tx), np.floor(ty)
    fx, fy = (tx - x0)[..., None], (ty - y0)[..., None]
    x0i, y0i = x0.astype(int), y0.astype(int)

    def at(x, y):
        return tex[np.clip(y, 0, h - 1), np.clip(x, 0, w - 1)]

    return ((at(x0i, y0i) * (1 - fx) + at(x0i + 1, y0i) * fx) * (1 - fy)
            + (at(x0i, y0i + 1) * (1 - fx) + at(x0i + 1, y0i + 1) * fx) * fy)


def ring_fragment(uv: ArrayLike, red: ArrayLike, lives: float, remaining: float,
                  visibility: float, colour_full: Sequence[float],
                  colour_empty: Sequence[float], angle_mode: str = "full") -> np.ndarray:
    """The FixedHealth fragment (..., 4): rgb = C·mask·gap, alpha = Visibility·mask·gap, C
    Color Full on sections below Remaining, else Color Empty; ``red`` is the UI texture's red
    channel at uv."""
    n, rem = clamp_ring(lives, remaining)
    e = 2.0 * np.asarray(uv, np.float64) - 1.0
    angle = ring_angle(e, angle_mode)
    section, gap = ring_sections(angle, n)
    step = 360.0 / n
    full = (rem * step) > (section * step)
    red = np.asarray(red, np.float64)
    mask = red * (red > 0.5)
    m = mask * gap
    colour = np.where(full[..., None], np.asarray(colour_full, np.float64)[:3],
                      np.asarray(colour_empty, np.float64)[:3])
    return np.concatenate([colour * m[..., None], (visibility * m)[..., None]], axis=-1)


def ring_image(width: int, height: int, screen_x: float, screen_y: float, size: float,
               lives: float, remaining: float, visibility: float, colour_full, colour_empty,
               background: ArrayLike = (0.0, 0.0, 0.0), form: str = "corrected",
               angle_mode: str = "full", texture: np.ndarray | None = None) -> np.ndarray:
    """The ring blended SrcAlpha/OneMinusSrcAlpha over a uniform ``background`` (height,
    width, 3), row 0 at the top — the twin of a whole draw."""
    tex = ring_mask_texture() if texture is None else texture
    px = np.arange(width) + 0.5
    py = (np.arange(height) + 0.5)[::-1]  # row 0 at the top
    uv, inside = ring_uv_at_pixels(px[None, :], py[:, None], screen_x, screen_y, size, width,
                                   height, form)
    red = sample_bilinear(tex, uv)[..., 0]
    frag = ring_fragment(uv, red, lives, remaining, visibility, colour_full, colour_empty,
                         angle_mode)
    a = np.where(inside, frag[..., 3], 0.0)[..., None]
    bg = np.broadcast_to(np.asarray(background, np.float64), (height, width, 3))
    return frag[..., :3] * a + bg * (1.0 - a)


def icon_index(role: str) -> int:
    """The index of a role's icon in :data:`ICON_ROLES` (unknown roles: the villager's)."""
    return ICON_ROLES.index(role) if role in ICON_ROLES else ICON_ROLES.index("villager")


def marker_centre(head: ArrayLike, lift: float) -> np.ndarray:
    """The marker's centre: ``lift`` metres above the top of the head."""
    return np.asarray(head, np.float64) + np.array([0.0, float(lift), 0.0])


def billboard_corners(centre: ArrayLike, right: ArrayLike, up: ArrayLike,
                      size: float) -> np.ndarray:
    """The four corners (4, 3) of a ``size`` × ``size`` quad facing the camera (spanned by its
    right and up vectors), in the order (−,−), (+,−), (−,+), (+,+)."""
    c = np.asarray(centre, np.float64)
    r, u = np.asarray(right, np.float64), np.asarray(up, np.float64)
    return np.array([c + 0.5 * size * (sx * r + sy * u)
                     for sx, sy in ((-1, -1), (1, -1), (-1, 1), (1, 1))])


def _disc(x, y, radius, soft):
    return np.clip((radius - np.hypot(x, y)) / soft + 0.5, 0.0, 1.0)


def _box(x, y, x0, x1, y0, y1, soft):
    return (np.clip((x - x0) / soft + 0.5, 0, 1) * np.clip((x1 - x) / soft + 0.5, 0, 1)
            * np.clip((y - y0) / soft + 0.5, 0, 1) * np.clip((y1 - y) / soft + 0.5, 0, 1))


#: per role: badge fill, its rim, the glyph's colour (linear)
ICON_COLOURS = {
    "missions": ((1.0, 0.74, 0.05), (0.35, 0.16, 0.02), (0.30, 0.10, 0.02)),
    "shop": ((0.95, 0.62, 0.12), (0.45, 0.26, 0.03), (0.50, 0.28, 0.03)),
    "villager": ((0.92, 0.92, 0.95), (0.20, 0.26, 0.40), (0.20, 0.26, 0.40)),
}


def marker_icon(role: str, size: int = 64) -> np.ndarray:
    """A role's icon (size × size, float32 premultiplied RGBA, row 0 at v = 0, so +v is up): a
    round badge with a rim and a glyph — "!" for missions, a coin (inner ring and a bar) for the
    shop, a speech bubble's three dots for anyone else. Its alpha is the badge's disc alone
    (centred, so the icon's coverage centroid is the marker's centre)."""
    if size < 8:
        raise ValueError(f"icon size {size}: allowed 8 or more texels")
    key = role if role in ICON_COLOURS else "villager"
    fill, rim, ink = (np.asarray(c, np.float64) for c in ICON_COLOURS[key])
    c = (np.arange(size) + 0.5) / size - 0.5  # [-0.5, 0.5], +y up (row 0 at v = 0)
    x, y = np.meshgrid(c, c)
    soft = 1.0 / size
    alpha = _disc(x, y, 0.46, soft)
    inner = _disc(x, y, 0.38, soft)
    if key == "missions":
        glyph = np.maximum(_box(x, y, -0.055, 0.055, -0.02, 0.27, soft),
                           _disc(x, y + 0.17, 0.06, soft))
    elif key == "shop":
        ring = np.clip(_disc(x, y, 0.27, soft) - _disc(x, y, 0.21, soft), 0.0, 1.0)
        glyph = np.maximum(ring, _box(x, y, -0.04, 0.04, -0.14, 0.14, soft))
    else:
        glyph = np.maximum.reduce([_disc(x - dx, y, 0.055, soft) for dx in (-0.16, 0.0, 0.16)])
    colour = rim[None, None] * (1.0 - inner[..., None]) + fill[None, None] * inner[..., None]
    colour = colour * (1.0 - glyph[..., None]) + ink[None, None] * glyph[..., None]
    out = np.zeros((size, size, 4), np.float32)
    out[..., :3] = colour * alpha[..., None]  # premultiplied
    out[..., 3] = alpha
    return out

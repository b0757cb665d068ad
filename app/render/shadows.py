"""Shadow-map helpers shared by every effect that casts shadows: the light's view and
orthographic projection for a directional light, and the depth target a shadow pass renders
into. What a receiver samples is published in the frame's ``shadows`` slot
(:class:`app.frame.ShadowMap`).

The receivers' filter is ``glsl/common/shadow_pcf.glsl`` (percentage-closer filtering, spec/002
§3.2); :func:`configure_compare` sets a depth texture up for its hardware comparisons, and
:func:`compare_bilinear`, :func:`pcf_weights` and :func:`pcf_visibility` are its numpy twin
(on a depth map read back as an array)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..sim.maths import look_at

#: the PCF kernel of glsl/common/shadow_pcf.glsl: (2 r + 1)² taps, Gaussian σ in texels
PCF_RADIUS = 2
PCF_SIGMA = 1.0
#: how a receiver compares depths: in hardware (sampler2DShadow) or by hand (sampler2D)
COMPARE_MODES = ("hardware", "manual")


def ortho(half: float, near: float, far: float) -> np.ndarray:
    """Orthographic projection of the square [−half, half]² between ``near`` and ``far``."""
    m = np.identity(4)
    m[0, 0] = m[1, 1] = 1.0 / half
    m[2, 2] = -2.0 / (far - near)
    m[2, 3] = -(far + near) / (far - near)
    return m


def directional_view_proj(toward_light, centre, half: float, distance: float,
                          depth: float) -> np.ndarray:
    """World → clip matrix of a directional light's shadow map covering the square of
    ``half``-width about ``centre``: the light's camera sits ``distance`` toward the light from
    the centre and sees ``depth`` metres from 1 m in front of it."""
    centre = np.asarray(centre, float)
    eye = centre + np.asarray(toward_light, float) * distance
    return ortho(half, 1.0, depth) @ look_at(eye, centre, np.array([0.0, 1.0, 0.0]))


def depth_target(gpu, owner: str, name: str, size: int):
    """(depth texture, framebuffer) of a ``size``² shadow map, allocated under ``owner``."""
    tex = gpu.depth_texture(owner, name, (size, size))
    return tex, gpu.framebuffer(owner, name, [], tex)


def configure_compare(tex, mode: str = "hardware") -> None:
    """Set a depth texture up for the receivers' comparisons: ``hardware`` — compare mode on
    (``'<='``: lit where the reference depth ≤ the stored one) with LINEAR filtering, so a
    ``sampler2DShadow`` read is one bilinear comparison; ``manual`` — compare mode off, NEAREST,
    for a ``sampler2D`` that reads depths (``texelFetch``) and compares them itself."""
    import moderngl

    if mode == "hardware":
        tex.compare_func = "<="
        tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
    else:
        tex.compare_func = ""
        tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
    tex.repeat_x = tex.repeat_y = False  # clamp to the edge: the filter never wraps


def pcf_weights(radius: int = PCF_RADIUS, sigma: float = PCF_SIGMA) -> np.ndarray:
    """(2 r + 1)² Gaussian weights exp(−(x² + y²) / 2σ²), indexed [y + r, x + r], unnormalised
    (``ShadowPcfWeight``)."""
    k = np.arange(-radius, radius + 1, dtype=np.float64)
    return np.exp(-0.5 * (k[:, None] ** 2 + k[None, :] ** 2) / (sigma * sigma))


def compare_bilinear(depths: np.ndarray, uv: np.ndarray, depth) -> np.ndarray:
    """``ShadowCompareBilinear``: the bilinear blend of the four texels' (depth ≤ stored)
    results at ``uv`` (…, 2), texel indices clamped to the map; ``depths`` (n, n), row 0 at
    v = 0."""
    n = depths.shape[0]
    st = np.asarray(uv, dtype=np.float64) * n - 0.5
    i = np.floor(st).astype(np.int64)
    f = st - i

    def lit(dx, dy):
        x = np.clip(i[..., 0] + dx, 0, n - 1)
        y = np.clip(i[..., 1] + dy, 0, n - 1)
        return (depth <= depths[y, x]).astype(np.float64)

    fx, fy = f[..., 0], f[..., 1]
    return ((lit(0, 0) * (1 - fx) + lit(1, 0) * fx) * (1 - fy)
            + (lit(0, 1) * (1 - fx) + lit(1, 1) * fx) * fy)


def pcf_visibility(depths: np.ndarray, uv: np.ndarray, depth, radius: int = PCF_RADIUS,
                   sigma: float = PCF_SIGMA) -> np.ndarray:
    """``ShadowPcf``: the normalised Gaussian sum of bilinear comparisons about ``uv``."""
    w = pcf_weights(radius, sigma)
    texel = 1.0 / depths.shape[0]
    uv = np.asarray(uv, dtype=np.float64)
    total = np.zeros(uv.shape[:-1])
    for y in range(-radius, radius + 1):
        for x in range(-radius, radius + 1):
            total += w[y + radius, x + radius] * compare_bilinear(
                depths, uv + np.array([x, y]) * texel, depth)
    return total / float(w.sum())


def slope_bias(bias: float, n_dot_l) -> np.ndarray:
    """``ShadowSlopeBias``: bias · (1 + 4 (1 − N·L))."""
    return bias * (1.0 + 4.0 * (1.0 - np.asarray(n_dot_l, dtype=np.float64)))


# -- the shared shadow module's settings (spec/003 §2.8) -----------------------------------------
#: receiver filters, in uniform order (uShadowSunFilter 0..4)
SHADOW_FILTERS = ("hard", "four_tap", "pcf", "pcss", "vsm")
SHADOW_SECTION = "spec/003 §2.8"
#: the receivers' tap sets, in uniform order (uShadowSunTaps 0, 1): full — the 5 × 5 PCF and
#: PCSS's 7 × 7 blocker search (the reference); fast — a 3 × 3 PCF and a 4 × 4 search over the
#: same footprint (PCSS keeps its 5 × 5 PCF: three taps spread over a wide penumbra band it).
#: ``auto`` (the parameter's default) is fast on a software renderer, full on a GPU
#: (:meth:`ShadowSettings.taps_code`)
SHADOW_TAPS = ("full", "fast")
TAPS_CHOICES = ("auto", *SHADOW_TAPS)


@dataclass(frozen=True)
class ShadowSettings:
    """Everything a shadow map and its receivers depend on (hashable: part of a map's key).
    Biases are in texels of the map (Unity's normal bias 0.3 and linear bias 0.01 by default,
    spec/003 §2.8 Fig. 86); ``distance`` and ``near_offset`` are metres (Unity's Shadow Distance
    and Near Plane Offset); ``fixed_centre``/``fixed_radius`` are the one map's area for 0
    cascades."""

    map_size: int = 1024
    cascades: int = 4
    split_lambda: float = 0.5
    stable_fit: bool = True
    linear_bias: float = 0.01
    normal_bias: float = 0.3
    filter: str = "four_tap"
    pcss_light_size: float = 0.02
    vsm_blur: int = 1
    vsm_bleed: float = 0.2
    dithered: bool = True
    sun_enabled: bool = True
    point_enabled: bool = True
    spot_enabled: bool = True
    strength: float = 1.0
    distance: float = 20.0
    near_offset: float = 20.0
    fixed_centre: tuple[float, float, float] = (0.0, 1.5, 0.0)
    fixed_radius: float = 6.0
    taps: str = "full"

    def __post_init__(self):
        if not (self.distance > 0 and self.fixed_radius > 0):
            raise ValueError(f"shadow distance {self.distance} / fixed radius "
                             f"{self.fixed_radius}: allowed > 0")

    @property
    def filter_index(self) -> int:
        return SHADOW_FILTERS.index(self.filter)

    def map_key(self) -> ShadowSettings:
        """What the maps themselves depend on: these settings with the receivers' own (filter,
        taps, PCSS light size, VSM blur and bleed, strength) at their defaults, so a change of
        filter re-binds the maps without re-rendering them."""
        from dataclasses import replace

        return replace(self, filter="four_tap", taps="full", pcss_light_size=0.02, vsm_blur=1,
                       vsm_bleed=0.2, strength=1.0)

    def resolved_taps(self, software: bool) -> str:
        """``full`` or ``fast``: ``auto`` is fast on a software renderer (``Caps.software``),
        full on a GPU."""
        if self.taps == "auto":
            return "fast" if software else "full"
        return self.taps

    def taps_code(self, software: bool) -> int:
        """shadow.glsl's ``uShadow*Taps`` (0 full, 1 fast)."""
        return SHADOW_TAPS.index(self.resolved_taps(software))

    @classmethod
    def from_params(cls, params, group: str) -> ShadowSettings:
        """The settings of ``<group>.shadow_*`` (the Params of :func:`shadow_params`)."""
        def p(name):
            return params[f"{group}.shadow_{name}"]
        return cls(map_size=int(p("map_size")), cascades=int(p("cascades")),
                   split_lambda=float(p("split_lambda")), stable_fit=bool(p("stable_fit")),
                   linear_bias=float(p("linear_bias")), normal_bias=float(p("normal_bias")),
                   filter=str(p("filter")), pcss_light_size=float(p("pcss_light_size")),
                   vsm_blur=int(p("vsm_blur")), vsm_bleed=float(p("vsm_bleed")),
                   dithered=bool(p("dithered")), sun_enabled=bool(p("sun")),
                   point_enabled=bool(p("point")), spot_enabled=bool(p("spot")),
                   strength=float(p("strength")), distance=float(p("distance")),
                   taps=str(params[f"{group}.shadow_taps"]) if f"{group}.shadow_taps" in params
                   else "full")


def shadow_params(group: str) -> list:
    """The Params of the shared shadow module under ``<group>.shadow_*`` (spec/003 §2.8)."""
    from ..params import Param

    g, s = f"{group}.shadow_", SHADOW_SECTION
    return [
        Param(g + "map_size", 1024, 64, 4096, "shadow-map resolution (texels per side; the "
              "cascades share it as a 2 × 2 atlas)", kind="int", section=s),
        Param(g + "cascades", "4", doc="cascaded shadow maps of the sun: 0 (one map over the "
              "room), 2 or 4 over the camera frustum", kind="choice", choices=("0", "2", "4"),
              section=s),
        Param(g + "split_lambda", 0.5, 0.0, 1.0, "cascade splits: λ blend of logarithmic (1) "
              "and uniform (0) splits (the practical split scheme)", section=s),
        Param(g + "stable_fit", True, doc="stable fit: bounding sphere per cascade, origin "
              "snapped to texels (no shimmering as the camera moves)", kind="bool", section=s),
        Param(g + "distance", 20.0, 1.0, 200.0, "shadow distance: the cascades' far end",
              unit="m", section=s),
        Param(g + "linear_bias", 0.01, 0.0, 2.0, "linear bias: the caster pushed away from the "
              "light by this many texels (too much: Peter Panning)", section=s),
        Param(g + "normal_bias", 0.3, 0.0, 3.0, "normal bias: the caster pushed inward along −n "
              "by sin(l, n) × this many texels (0: acne)", section=s),
        Param(g + "filter", "four_tap", doc="receiver filter: hard (one compare), four_tap (the "
              "thesis's soft shadows), pcf (Gaussian), pcss (contact-hardening), vsm (variance)",
              kind="choice", choices=SHADOW_FILTERS, section=s),
        Param(g + "taps", "auto", doc="the PCF and PCSS taps: full (the 5 × 5 Gaussian PCF, "
              "PCSS's 7 × 7 blocker search: the reference), fast (a 3 × 3 PCF, a 4 × 4 blocker "
              "search over the same footprint), auto (fast on a software renderer, full on a "
              "GPU)", kind="choice", choices=TAPS_CHOICES, section=s),
        Param(g + "pcss_light_size", 0.02, 0.0, 0.2, "PCSS light size (the light's angular "
              "size, tangent)", section=s),
        Param(g + "vsm_blur", 1, 0, 4, "VSM moments blur radius (texels)", kind="int",
              section=s),
        Param(g + "vsm_bleed", 0.2, 0.0, 0.9, "VSM light-bleeding reduction", section=s),
        Param(g + "dithered", True, doc="semitransparent casters cast dithered shadows (17 4×4 "
              "patterns by α)", kind="bool", section=s),
        Param(g + "sun", True, doc="the sun casts shadows", kind="bool", section=s),
        Param(g + "point", True, doc="point lights cast shadows (six-face map)", kind="bool",
              section=s),
        Param(g + "spot", True, doc="spot lights cast shadows (perspective map)", kind="bool",
              section=s),
        Param(g + "strength", 1.0, 0.0, 1.0, "shadow strength (0: no shadow)", section=s),
    ]

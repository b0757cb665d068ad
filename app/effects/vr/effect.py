"""VR mode (spec/003 §2.15): the parameters of the stereo pair, which the scene renders
(``app.render.stereo``: each eye its own camera moved by half the interpupillary distance,
its own projection and render texture at ``vr.render_scale``, composed side by side), and what
VR draws on top of the world:

* **the FixedHealth ring** (``Custom/VR/FixedHealth``, queue Overlay+2: the overlay stage,
  after everything, with the depth test off — ZTest Always — blended SrcAlpha/OneMinusSrcAlpha):
  the one head-locked element the thesis allows, a ring of ``Lives`` sections of which
  ``Remaining`` are full, at (Screen X, Screen Y) of each eye's image (``glsl/vr/health.*``,
  twin ``app/sim/vr.py``, whose docstring gives the erratum of spec/003 eq. 9.2);
* **world-space markers** above the characters of the frame's ``npcs`` slot (the thesis's
  world-space canvases instead of head-locked panels): a camera-facing icon per role — "!" for
  missions, a coin for the shop, a speech bubble for a villager — depth-tested, in the
  transparent stage (``glsl/vr/marker.*``). Without the slot there are none.

Both are shown in VR by default (``vr.health_ring``, ``vr.markers``: vr, always or off). "In
VR" means ``vr.enabled`` or a frame drawn for one eye (``frame.eye``).
"""

from __future__ import annotations

import moderngl
import numpy as np

from ...frame import Stage
from ...gpu.programs import ProgramSpec
from ...params import Param
from ...sim import vr as twin
from ..base import Effect, Pass

HEALTH = ProgramSpec("vr/health")
MARKER = ProgramSpec("vr/marker")
#: texels of the UI texture's side and of one marker icon's
RING_TEXELS, ICON_TEXELS = 256, 64
#: the Plane mesh's quad (its local x, z), drawn as a triangle strip
PLANE = np.array([(-1, -1), (1, -1), (-1, 1), (1, 1)], np.float32) * twin.PLANE_HALF
#: a marker's two triangles, as corners (±½, ±½)
CORNERS = np.array([(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (-0.5, 0.5), (0.5, -0.5),
                    (0.5, 0.5)], np.float32)


class Vr(Effect):
    name = "vr"
    title = "VR mode"
    spec = "spec/003"
    programs = (HEALTH, MARKER)
    stages = (Stage.TRANSPARENT, Stage.OVERLAY)
    consumes = {"npcs": "optional"}

    @classmethod
    def python_params(cls) -> list[Param]:
        s = "spec/003 §2.15"
        return [
            Param("vr.enabled", False, doc="side-by-side stereo: each eye its own view and "
                  "projection, the camera at the hero's head", kind="bool", section=s),
            Param("vr.ipd", 0.064, 0.0, 0.2, "interpupillary distance", step=0.001, unit="m",
                  section=s),
            Param("vr.render_scale", 1.0, 0.25, 2.0, "each eye's render texture, relative to "
                  "its half of the frame (Unity's eye texture resolution scale)", step=0.05,
                  section=s),
            Param("vr.health_ring", "vr", doc="the FixedHealth ring, head-locked: shown in VR, "
                  "always (also in mono) or off", kind="choice", choices=twin.SHOW_MODES,
                  section=s),
            Param("vr.ring_aspect", "corrected", doc="the aspect factor of spec/003 eq. 9.2: "
                  "corrected (round, centred at Screen X, Y), document (h/w as written: off "
                  "centre and squashed), repository (w/h on the whole y: round, off centre)",
                  kind="choice", choices=twin.ASPECT_FORMS, section=s),
            Param("vr.ring_angle", "full", doc="the ring's angle: full (by quadrant, 0–360°, "
                  "the repository) or acos (the document's, 0–180°: the lower half mirrors "
                  "the upper)", kind="choice", choices=twin.ANGLE_MODES, section=s),
            Param("vr.markers", "vr", doc="world-space icons above the characters (instead of "
                  "head-locked panels): shown in VR, always or off", kind="choice",
                  choices=twin.SHOW_MODES, section=s),
            Param("vr.marker_size", 0.5, 0.05, 5.0, "a marker icon's side", step=0.05,
                  unit="m", section=s),
            Param("vr.marker_lift", 0.55, 0.0, 5.0, "a marker's centre above the head",
                  step=0.05, unit="m", section=s),
            Param("vr.marker_intensity", 1.0, 0.0, 100.0, "radiance of the icons' colours "
                  "(they are unlit)", step=0.05, section=s),
        ]

    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        self._plane = None
        self._ring_mask = None
        self._icons = None
        self._markers = None  # (buffer, capacity in markers)

    def in_vr(self, frame) -> bool:
        return bool(self.params["vr.enabled"]) or frame.eye is not None

    def shown(self, what: str, frame) -> bool:
        """Whether ``vr.health_ring`` or ``vr.markers`` (``what``) shows in this frame."""
        mode = self.params[f"vr.{what}"]
        return mode == "always" or (mode == "vr" and self.in_vr(frame))

    def passes(self, frame, target) -> list[Pass]:
        out = []
        if frame.npcs and self.shown("markers", frame):
            out.append(Pass("vr markers", lambda: self.draw_markers(frame, target),
                            Stage.TRANSPARENT))
        if self.shown("health_ring", frame):
            out.append(Pass("vr health ring", lambda: self.draw_ring(frame, target),
                            Stage.OVERLAY))
        return out

    def ring_mask(self):
        if self._ring_mask is None:
            data = twin.ring_mask_texture(RING_TEXELS)
            self._ring_mask = self.gpu.texture(self.name, "ring mask",
                                               (RING_TEXELS, RING_TEXELS), 4,
                                               data=data.tobytes())
        return self._ring_mask

    def draw_ring(self, frame, target) -> None:
        """The FixedHealth ring over everything in ``target`` (ZTest Always, blended)."""
        if self._plane is None:
            self._plane = self.gpu.buffer(self.name, "plane quad", PLANE.tobytes())
        prog = self.program(HEALTH)
        self.apply_params(prog)
        prog.set_many({
            "uViewport": tuple(float(v) for v in target.size),
            "uAspectForm": twin.ASPECT_FORMS.index(self.params["vr.ring_aspect"]),
            "uAngleMode": twin.ANGLE_MODES.index(self.params["vr.ring_angle"]),
        })
        prog.bind_textures({"uRingMask": self.ring_mask()})
        ctx = self.gpu.ctx
        target.use()
        ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)  # ZTest Always; no depth write
        ctx.enable(moderngl.BLEND)
        ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        try:
            prog.vao([(self._plane, "2f", "in_position")]).render(moderngl.TRIANGLE_STRIP)
        finally:
            ctx.blend_func = moderngl.DEFAULT_BLENDING
            ctx.disable(moderngl.BLEND)

    def icons(self) -> list:
        """One mipmapped texture per role of ``ICON_ROLES`` (a far marker is minified)."""
        if self._icons is None:
            self._icons = []
            for role in twin.ICON_ROLES:
                tex = self.gpu.texture(self.name, f"{role} icon", (ICON_TEXELS, ICON_TEXELS),
                                       4, data=twin.marker_icon(role, ICON_TEXELS).tobytes(),
                                       filter=(moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR))
                tex.build_mipmaps()
                self._icons.append(tex)
        return self._icons

    def marker_vertices(self, frame) -> np.ndarray:
        """Six vertices per character of ``frame.npcs``: centre (3), corner (2), icon (1)."""
        lift = self.params["vr.marker_lift"]
        rows = []
        for npc in frame.npcs:
            centre = twin.marker_centre(npc.head, lift)
            icon = float(twin.icon_index(npc.role))
            for corner in CORNERS:
                rows.append((*centre, *corner, icon))
        return np.asarray(rows, np.float32).reshape(-1, 6)

    def _marker_buffer(self, count: int):
        if self._markers is None or self._markers[1] < count:
            if self._markers is not None:
                self.gpu.free(self._markers[0])
            capacity = max(8, count)
            buf = self.gpu.buffer(self.name, "markers", bytes(capacity * 6 * 6 * 4))
            self._markers = (buf, capacity)
        return self._markers[0]

    def draw_markers(self, frame, target) -> None:
        """An icon above each character, depth-tested against the image, blended."""
        data = self.marker_vertices(frame)
        count = len(data) // 6
        if count == 0:
            return
        buf = self._marker_buffer(count)
        buf.write(data.tobytes())
        cam = frame.camera
        right, up, _ = cam.basis()
        prog = self.program(MARKER)
        prog.set_many({
            "uViewProj": cam.view_projection_relative(frame.aspect),
            "uCameraPos": tuple(cam.position), "uCamRight": tuple(right), "uCamUp": tuple(up),
            "uMarkerSize": self.params["vr.marker_size"],
            "uIntensity": self.params["vr.marker_intensity"],
        })
        prog.bind_textures({f"uIcon{i}": tex for i, tex in enumerate(self.icons())})
        ctx = self.gpu.ctx
        target.use()
        ctx.enable(moderngl.DEPTH_TEST)
        ctx.disable(moderngl.CULL_FACE)
        ctx.depth_func = "<"
        ctx.enable(moderngl.BLEND)
        ctx.blend_func = moderngl.ONE, moderngl.ONE_MINUS_SRC_ALPHA  # premultiplied
        fbo = target.fbo
        fbo.depth_mask = False
        try:
            vao = prog.vao([(buf, "3f 2f 1f", "in_centre", "in_corner", "in_icon")])
            vao.render(moderngl.TRIANGLES, vertices=6 * count)
        finally:
            fbo.depth_mask = True
            ctx.blend_func = moderngl.DEFAULT_BLENDING
            ctx.disable(moderngl.BLEND)

    def panel_notes(self) -> list[str]:
        p = self.params
        lives, remaining = twin.clamp_ring(p["vr.lives"], p["vr.remaining"])
        full = min(lives, int(np.ceil(remaining)))
        return [f"health ring: {full} of {lives} sections full; {10 * p['vr.element_size']:.0%} "
                "of the eye's width across"]

    def release(self) -> None:
        self._plane = self._ring_mask = self._icons = self._markers = None
        super().release()

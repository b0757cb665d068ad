"""Dear ImGui (imgui-bundle ≥ 1.92) drawn with moderngl, fed by moderngl-window's events.

moderngl-window 3.1.1 ships a renderer for imgui-bundle that builds the font atlas once through
``ImFontAtlas.get_tex_data_as_rgba32``; Dear ImGui 1.92 replaced that with a texture protocol
(fonts are rasterised on demand, so the atlas grows and changes while the program runs). This
module owns a small renderer on that protocol, so Natura follows the current imgui-bundle:

* textures — the renderer sets ``BackendFlags_.renderer_has_textures``; every frame it walks
  ``platform_io.textures`` and honours each request: *want_create* (a moderngl texture, its id
  handed back with ``set_tex_id``), *want_updates* (only the listed rectangles are uploaded),
  *want_destroy* (released once ImGui no longer draws with it). Textures of the application
  (inspector thumbnails, the A/B images) are drawn after ``register_texture``;
* drawing — one vertex and one index buffer, grown as needed; per command a scissor and a
  texture; blending on, depth and culling off, and the state it changed restored afterwards
  (the scene's passes set theirs, but a frame must not inherit the UI's scissor);
* input — the window's key, character, mouse and wheel events become ImGui's input events,
  with the modifier keys and every letter, digit and function key mapped, so Ctrl+A / C / V / X
  / Z / Y work in text fields and the code editor (moderngl-window's own mixin maps only the
  navigation keys, and sends no modifiers).

Vertex offsets are not claimed (``renderer_has_vtx_offset`` stays off): ImGui then splits a
draw list whose vertices overflow the 16-bit indices, and every command starts at vertex 0.
"""

from __future__ import annotations

import ctypes
from typing import Any

import moderngl
import numpy as np
from imgui_bundle import imgui

VERTEX_SHADER = """
#version 330
uniform mat4 uProjection;
in vec2 in_position;
in vec2 in_uv;
in vec4 in_colour;
out vec2 vUv;
out vec4 vColour;
void main() {
    vUv = in_uv;
    vColour = in_colour;
    gl_Position = uProjection * vec4(in_position, 0.0, 1.0);
}
"""

FRAGMENT_SHADER = """
#version 330
uniform sampler2D uTexture;
in vec2 vUv;
in vec4 vColour;
out vec4 fragColour;
void main() {
    fragColour = vColour * texture(uTexture, vUv);
}
"""


def ortho(width: float, height: float) -> np.ndarray:
    """ImGui's display space (pixels, y down) to clip space, column-major for GLSL."""
    return np.array([[2.0 / width, 0.0, 0.0, 0.0],
                     [0.0, -2.0 / height, 0.0, 0.0],
                     [0.0, 0.0, -1.0, 0.0],
                     [-1.0, 1.0, 0.0, 1.0]], dtype="f4")


def key_map(keys) -> dict[int, Any]:
    """The window's key codes → ImGui keys: navigation, editing, modifiers, letters, digits and
    F1–F12 (a key the window library lacks is left out)."""
    K = imgui.Key
    pairs = {
        "TAB": K.tab, "LEFT": K.left_arrow, "RIGHT": K.right_arrow, "UP": K.up_arrow,
        "DOWN": K.down_arrow, "PAGE_UP": K.page_up, "PAGE_DOWN": K.page_down, "HOME": K.home,
        "END": K.end, "INSERT": K.insert, "DELETE": K.delete, "BACKSPACE": K.backspace,
        "SPACE": K.space, "ENTER": K.enter, "ESCAPE": K.escape,
        "LEFT_CTRL": K.left_ctrl, "RIGHT_CTRL": K.right_ctrl, "LEFT_SHIFT": K.left_shift,
        "RIGHT_SHIFT": K.right_shift, "LEFT_ALT": K.left_alt, "RIGHT_ALT": K.right_alt,
        "MINUS": K.minus, "EQUAL": K.equal, "COMMA": K.comma, "PERIOD": K.period,
        "SLASH": K.slash, "SEMICOLON": K.semicolon, "LEFT_BRACKET": K.left_bracket,
        "RIGHT_BRACKET": K.right_bracket, "BACKSLASH": K.backslash,
    }
    pairs.update({c: getattr(K, c.lower()) for c in "ABCDEFGHIJKLMNOPQRSTUVWXYZ"})
    pairs.update({f"NUMBER_{d}": getattr(K, f"_{d}") for d in range(10)})
    pairs.update({f"F{n}": getattr(K, f"f{n}") for n in range(1, 13)})
    out: dict[int, Any] = {}
    for name, imkey in pairs.items():
        code = getattr(keys, name, None)
        if code is not None:
            out[code] = imkey
    return out


class ImguiRenderer:
    """Draws ImGui's draw data into the window's framebuffer and feeds it the window's input.

    The ImGui context must exist (``imgui.create_context()``) before this is made; fonts added
    to ``io.fonts`` before the first frame are rasterised on demand through the texture
    requests, at any time."""

    def __init__(self, wnd):
        self.wnd = wnd
        self.ctx: moderngl.Context = wnd.ctx
        self.io = imgui.get_io()
        self.io.backend_flags |= imgui.BackendFlags_.renderer_has_textures
        pio = imgui.get_platform_io()
        side = int(self.ctx.info.get("GL_MAX_TEXTURE_SIZE", 4096))
        pio.renderer_texture_max_width = side
        pio.renderer_texture_max_height = side
        self.prog = self.ctx.program(vertex_shader=VERTEX_SHADER, fragment_shader=FRAGMENT_SHADER)
        self.prog["uTexture"].value = 0
        self._vbo = self.ctx.buffer(reserve=1 << 16, dynamic=True)
        self._ibo = self.ctx.buffer(reserve=1 << 15, dynamic=True)
        self._vao = self._make_vao()
        self._textures: dict[int, moderngl.Texture] = {}  # GL name → texture drawable by ImGui
        self._owned: dict[int, moderngl.Texture] = {}     # those ImGui asked for (its atlas)
        self.keymap = key_map(wnd.keys)
        self._modifiers = {"ctrl": imgui.Key.mod_ctrl, "shift": imgui.Key.mod_shift,
                           "alt": imgui.Key.mod_alt}
        self.resize(*wnd.size)

    def _make_vao(self) -> moderngl.VertexArray:
        return self.ctx.vertex_array(
            self.prog, [(self._vbo, "2f 2f 4f1", "in_position", "in_uv", "in_colour")],
            index_buffer=self._ibo, index_element_size=imgui.INDEX_SIZE)

    def register_texture(self, texture: moderngl.Texture) -> None:
        """Let ImGui draw an application texture (``imgui.image(ImTextureRef(tex.glo), …)``)."""
        self._textures[texture.glo] = texture

    def remove_texture(self, texture: moderngl.Texture) -> None:
        self._textures.pop(texture.glo, None)

    def update_textures(self) -> None:
        """Honour ImGui's texture requests (create, update rectangles, destroy)."""
        S = imgui.ImTextureStatus
        for tex in imgui.get_platform_io().textures:
            status = tex.status
            if status == S.ok or status == S.destroyed:
                continue
            if status == S.want_create:
                pixels = np.asarray(tex.get_pixels_array(), dtype=np.uint8)
                gl_tex = self.ctx.texture((tex.width, tex.height), tex.bytes_per_pixel,
                                          data=pixels.tobytes())
                gl_tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
                gl_tex.repeat_x = gl_tex.repeat_y = False
                if tex.bytes_per_pixel == 1:  # alpha-only atlas: white with that alpha
                    gl_tex.swizzle = "111R"
                self._owned[gl_tex.glo] = gl_tex
                self._textures[gl_tex.glo] = gl_tex
                tex.set_tex_id(gl_tex.glo)
                tex.set_status(S.ok)
            elif status == S.want_updates:
                gl_tex = self._owned.get(int(tex.tex_id))
                if gl_tex is not None:
                    bpp = tex.bytes_per_pixel
                    whole = np.asarray(tex.get_pixels_array(), dtype=np.uint8).reshape(
                        tex.height, tex.width, bpp)
                    for r in tex.updates:
                        block = np.ascontiguousarray(whole[r.y:r.y + r.h, r.x:r.x + r.w])
                        gl_tex.write(block.tobytes(), viewport=(r.x, r.y, r.w, r.h))
                tex.set_status(S.ok)
            elif status == S.want_destroy and tex.unused_frames > 0:
                self._release_owned(int(tex.tex_id))
                tex.set_tex_id(0)
                tex.set_status(S.destroyed)

    def _release_owned(self, glo: int) -> None:
        gl_tex = self._owned.pop(glo, None)
        self._textures.pop(glo, None)
        if gl_tex is not None:
            gl_tex.release()

    def render(self, draw_data) -> None:
        """Draw one frame's draw data into the bound framebuffer (the window's)."""
        self.update_textures()
        io = self.io
        dw, dh = io.display_size
        sx, sy = io.display_framebuffer_scale
        fb_w, fb_h = int(dw * sx), int(dh * sy)
        if fb_w <= 0 or fb_h <= 0 or draw_data is None:
            return
        draw_data.scale_clip_rects(io.display_framebuffer_scale)
        ctx = self.ctx
        saved_viewport = ctx.viewport
        ctx.viewport = (0, 0, fb_w, fb_h)
        ctx.enable_only(moderngl.BLEND)
        ctx.blend_equation = moderngl.FUNC_ADD
        ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        self.prog["uProjection"].write(ortho(dw, dh).tobytes())
        try:
            for commands in draw_data.cmd_lists:
                vsize = commands.vtx_buffer.size() * imgui.VERTEX_SIZE
                isize = commands.idx_buffer.size() * imgui.INDEX_SIZE
                self._upload(vsize, isize, commands)
                for cmd in commands.cmd_buffer:
                    texture = self._textures.get(int(cmd.get_tex_id()))
                    if texture is None:  # a texture released or never registered: skip it
                        continue
                    texture.use(0)
                    x0, y0, x1, y1 = cmd.clip_rect
                    if x1 <= x0 or y1 <= y0:
                        continue
                    ctx.scissor = (int(x0), int(fb_h - y1), int(x1 - x0), int(y1 - y0))
                    self._vao.render(moderngl.TRIANGLES, vertices=cmd.elem_count,
                                     first=cmd.idx_offset)
        finally:
            ctx.scissor = None
            ctx.disable(moderngl.BLEND)
            ctx.viewport = saved_viewport

    def _upload(self, vsize: int, isize: int, commands) -> None:
        grown = False
        if vsize > self._vbo.size:
            self._vbo.orphan(max(vsize, 2 * self._vbo.size))
            grown = True
        if isize > self._ibo.size:
            self._ibo.orphan(max(isize, 2 * self._ibo.size))
            grown = True
        if grown:
            self._vao.release()
            self._vao = self._make_vao()
        self._vbo.write(ctypes.string_at(commands.vtx_buffer.data_address(), vsize))
        self._ibo.write(ctypes.string_at(commands.idx_buffer.data_address(), isize))

    def shutdown(self) -> None:
        for glo in list(self._owned):
            self._release_owned(glo)
        for tex in imgui.get_platform_io().textures:
            if tex.status != imgui.ImTextureStatus.destroyed:
                tex.set_tex_id(0)
                tex.set_status(imgui.ImTextureStatus.destroyed)
        self._textures.clear()
        for obj in (self._vao, self._vbo, self._ibo, self.prog):
            obj.release()

    def resize(self, width: int, height: int) -> None:
        self.io.display_size = (float(width), float(height))
        bw, bh = self.wnd.buffer_size
        self.io.display_framebuffer_scale = (bw / max(width, 1), bh / max(height, 1))

    def key_event(self, key, action, modifiers) -> None:
        keys = self.wnd.keys
        if action not in (keys.ACTION_PRESS, keys.ACTION_RELEASE):
            return
        down = action == keys.ACTION_PRESS
        io = self.io
        for attr, imkey in self._modifiers.items():  # the modifier state with every key
            io.add_key_event(imkey, bool(getattr(modifiers, attr, False)))
        imkey = self.keymap.get(key)
        if imkey is not None:
            io.add_key_event(imkey, down)
            if imkey in (imgui.Key.left_ctrl, imgui.Key.right_ctrl):
                io.add_key_event(imgui.Key.mod_ctrl, down)
            elif imkey in (imgui.Key.left_shift, imgui.Key.right_shift):
                io.add_key_event(imgui.Key.mod_shift, down)
            elif imkey in (imgui.Key.left_alt, imgui.Key.right_alt):
                io.add_key_event(imgui.Key.mod_alt, down)

    def unicode_char_entered(self, char: str) -> None:
        for c in char:
            if c.isprintable():
                self.io.add_input_character(ord(c))

    def mouse_position_event(self, x, y, dx, dy) -> None:
        self.io.add_mouse_pos_event(float(x), float(y))

    mouse_drag_event = mouse_position_event

    def _mouse_button(self, x, y, button, down: bool) -> None:
        self.io.add_mouse_pos_event(float(x), float(y))
        m = self.wnd.mouse
        b = {m.left: 0, m.right: 1, m.middle: 2}.get(button)
        if b is not None:
            self.io.add_mouse_button_event(b, down)

    def mouse_press_event(self, x, y, button) -> None:
        self._mouse_button(x, y, button, True)

    def mouse_release_event(self, x, y, button) -> None:
        self._mouse_button(x, y, button, False)

    def mouse_scroll_event(self, dx, dy) -> None:
        self.io.add_mouse_wheel_event(float(dx), float(dy))

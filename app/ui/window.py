"""The desktop window: moderngl-window (pyglet) + an ImGui panel mirroring the theses' inspectors.

The keys come from the scene's key map (app/ui/keymap.py; docs/commands.md, "Window controls",
lists them). Shader files are polled every 0.25 s: a broken edit keeps the last good program
running and lists ``file:line`` errors in the panel. Dynamic resolution: app/ui/resolution.py
(the panel and the HUD are drawn after the enlarged scene, at the window's resolution).
"""

from __future__ import annotations

import collections
import contextlib
import os
import sys
import time
from pathlib import Path
from typing import Callable

import numpy as np

from ..errors import GpuUnavailableError, OutputExistsError
from ..gpu.context import describe_context
from ..imageio import next_free_path, write_png, write_text_atomic
from ..params import Inspector, ParamSet
from ..runtime import open_session, scene_params
from ..scenes.views import views_of
from ..sim.camera import Camera
from ..sim.daynight import Keyframes, hour_label
from .keymap import CHARACTER_KEYS, CHARACTERS, Controller, cycle_value, key_names
from .resolution import DynamicResolution, scale_line

POLL_SECONDS = 0.25
MOVE_SPEED = 5.0  # m/s
LOOK_DEGREES_PER_PIXEL = 0.15
#: what keys still do while the pause menu is open (everything else waits for Resume)
PAUSED_ACTIONS = {"pause_menu", "quit", "screenshot", "toggle_panel"}
#: keys of the window itself in every scene (before the scene's key map)
WINDOW_KEYS = {"F2": "toggle_editor", "F3": "toggle_compare"}
WINDOW_KEYS_HELP = (("F2", "shader editor"), ("F3", "compare A/B"),
                    ("Ctrl+F", "search the panel"))


def _fallback_font() -> Path | None:
    """matplotlib's DejaVu Sans (a dependency already): the maths signs and arrows of the digests
    (∈ ‖ ⌊ ⌋ ⟨ ⟩ ℝ ² …) that DroidSans and Inconsolata lack. Found without importing
    matplotlib (its data folder is ``mpl-data`` beside its package): the import cost every
    window's start about 0.1 s of CPU."""
    import importlib.util

    spec = importlib.util.find_spec("matplotlib")
    for folder in (spec.submodule_search_locations or ()) if spec is not None else ():
        path = Path(folder) / "mpl-data" / "fonts" / "ttf" / "DejaVuSans.ttf"
        if path.is_file():
            return path
    return None  # without it, missing glyphs show as "?"


def _load_font(imgui):
    """ImGui's built-in font is ASCII only: load imgui-bundle's DroidSans, whose glyphs Dear ImGui
    1.92 rasterises on demand (thesis sections §, units m², Greek β θ Φ, − · → ≤ …), and its
    Inconsolata for the shader editor, each with DejaVu Sans merged in for what it lacks.
    Returns the monospace font (None without it); without the files, the default font stays."""
    mono = None
    with contextlib.suppress(Exception):  # a font problem must not keep the window from opening
        import imgui_bundle

        fonts = Path(imgui_bundle.__file__).parent / "assets" / "fonts"
        atlas = imgui.get_io().fonts
        fallback = _fallback_font()

        def merge_fallback() -> None:
            if fallback is not None:
                cfg = imgui.ImFontConfig()
                cfg.merge_mode = True
                atlas.add_font_from_file_ttf(str(fallback), 15.0, cfg)

        if (fonts / "DroidSans.ttf").is_file():
            atlas.add_font_from_file_ttf(str(fonts / "DroidSans.ttf"), 15.0)
            merge_fallback()
        if (fonts / "Inconsolata-Medium.ttf").is_file():
            mono = atlas.add_font_from_file_ttf(str(fonts / "Inconsolata-Medium.ttf"), 15.0)
            merge_fallback()
    return mono


def display_problem() -> str | None:
    """None when a window can be opened, else why not, in a few words (for the CLI's message).
    pyglet 2.1 needs X11: on Wayland it goes through XWayland's DISPLAY."""
    if not sys.platform.startswith("linux"):
        return None
    display = os.environ.get("DISPLAY")
    if not display:
        if os.environ.get("WAYLAND_DISPLAY"):
            return "DISPLAY is unset (WAYLAND_DISPLAY is set, but the window needs X11: XWayland)"
        return "DISPLAY and WAYLAND_DISPLAY are unset"
    try:
        import pyglet.display  # this import does not create pyglet's shadow window

        pyglet.display.get_display()
    except Exception:
        return f"the X display {display!r} does not answer"
    return None


def _one_line(exc: BaseException) -> str:
    """An exception as one short line for the panel: the OS's reason and the path it names."""
    if isinstance(exc, OSError) and exc.strerror:
        return f"{exc.strerror}: {exc.filename}" if exc.filename else exc.strerror
    text = " ".join(str(exc).split())
    return text or type(exc).__name__


def _create_window(size, title, vsync: bool = True):
    import moderngl_window as mglw

    cls = mglw.get_local_window_cls("pyglet")
    last = None
    # 4.3 for compute shaders; 4.1 is macOS's last (forward-compatible core, as moderngl-window
    # asks); 3.3 the least Natura runs on
    for version in ((4, 3), (4, 1), (3, 3)):
        try:
            wnd = cls(title=title, gl_version=version, size=size, resizable=True, vsync=vsync,
                      samples=0, cursor=True, visible=True, fullscreen=False)
        except Exception as exc:  # pyglet.gl.ContextException
            last = exc
            continue
        mglw.activate_context(window=wnd)
        return wnd
    raise GpuUnavailableError(f"could not create an OpenGL 3.3+ window: {last}")


def panel_size(window: tuple[int, int]) -> tuple[float, float]:
    """The panel's first size in a window of ``window`` pixels: 380 x 620 from a 1520-pixel
    wide window up, a quarter of a narrower one's width (at least 220; it scrolls, and folds at
    its title bar), so the view stays mostly visible."""
    return (min(380.0, max(220.0, 0.25 * window[0])), 620.0)


def frame_line(ms: np.ndarray) -> str:
    """The panel's frame-time line from the last frame times (0: none measured): the last
    measured frame, the median and the rate; dashes until a frame has been measured."""
    measured = ms[ms > 0]
    if not measured.size:
        return "frame — ms   median — ms   — fps (measured from the second frame)"
    median = float(np.median(measured))
    return (f"frame {float(measured[-1]):6.2f} ms   median {median:6.2f} ms   "
            f"{1000.0 / median:5.1f} fps")


class NaturaWindow:
    def __init__(self, scene_name: str, params: ParamSet, camera: Camera, size=(1280, 720),
                 shader_root=None, screenshot_dir: str | os.PathLike = "screenshots",
                 preset_dir: str | os.PathLike = "presets",
                 keyframes_dir: str | os.PathLike = ".", quality=None, vsync: bool = True):
        from imgui_bundle import imgui

        from .imgui_renderer import ImguiRenderer

        self.imgui = imgui
        self.wnd = _create_window(size, f"Natura — {scene_name}", vsync=vsync)
        self.wnd.exit_key = None  # Esc is ours: it must not quit while typing in a text field
        self.ctx = self.wnd.ctx
        self.session = open_session(scene_name, params, shader_root, ctx=self.ctx, camera=camera)
        self.scene = self.session.scene
        self.scene.interactive = True
        #: the scene's starting values (what a view is applied over) and the view shown
        self.start_values = dict(scene_params(scene_name, shader_root).values())
        self.current_view: str | None = None
        print(f"natura: context: {describe_context(self.ctx)}", file=sys.stderr, flush=True)
        self.params = params
        self.home = Camera(**{k: getattr(camera, k) for k in ("position", "yaw", "pitch", "fov")})
        imgui.create_context()
        from imgui_bundle import implot

        self.implot = implot
        implot.create_context()
        imgui.get_io().set_ini_filename("")  # no imgui.ini in the user's folder
        self.mono_font = _load_font(imgui)
        self.ui = ImguiRenderer(self.wnd)
        from .panel import PanelState

        self.panel_state = PanelState()  # the panel's search text and open thesis section
        w = self.wnd
        w.key_event_func = self.on_key
        w.mouse_position_event_func = self.on_mouse_position
        w.mouse_drag_event_func = self.on_mouse_drag
        w.mouse_scroll_event_func = self.on_mouse_scroll
        w.mouse_press_event_func = self.on_mouse_press
        w.mouse_release_event_func = self.on_mouse_release
        w.unicode_char_entered_func = self.on_char
        w.resize_func = self.on_resize
        self.controller = Controller(keymap=self.scene.keymap, speed=MOVE_SPEED)
        # a key held when the window loses the keyboard never sends its release here: let go of
        # every held action then, or the camera flies on (pyglet's window: moderngl-window's
        # events have no focus loss)
        self.wnd._window.push_handlers(on_deactivate=self.controller.release_all)
        from pyglet.window import key as pyglet_key  # the window is always pyglet's: [ ] need it

        self._key_names = key_names(self.wnd.keys, pyglet_key)
        self.looking = False
        self.mouse_look = False
        self.show_panel = True
        self.frame_ms = collections.deque([0.0] * 240, maxlen=240)  # 0: not measured
        self.frame_text = frame_line(np.zeros(1))  # the panel's frame-time line, as drawn
        self.messages: collections.deque[str] = collections.deque(maxlen=6)
        self.screenshot_dir = Path(screenshot_dir)
        self.preset_dir = Path(preset_dir)
        self.keyframes_dir = Path(keyframes_dir)
        self.screenshot_requested = False
        self.screenshots: list[Path] = []
        self.render_error: str | None = None
        self.poll_error: str | None = None
        self._printed_errors: set[str] = set()  # shader errors already printed to the terminal
        self.progress_frames = 0
        self._last_poll = 0.0
        self.target = None  # the scene's radiance, at the internal size (dynamic resolution)
        self.window_size: tuple[int, int] = (0, 0)  # the window's framebuffer, pixels
        self.resolution = DynamicResolution()
        self._rendering = False  # inside render_scene (a resize then waits for its end)
        self._resize_pending: tuple[int, int] | None = None
        self.ui_mode = True  # toggle_ui: the HUD and panel take the mouse; False: navigation
        self.paused = False  # the pause menu is open
        self._before_pause: tuple[bool | None, bool] = (None, True)  # time.playing, ui_mode
        self.hud_state = None  # the scene's last HudState (scenes with a hud() method)
        self.hud_rects: dict = {}  # screen rectangles of the HUD's windows and pause buttons
        self.panel_rect = (0.0, 0.0, 0.0, 0.0)  # the panel's screen rectangle, as last drawn
        self.session.gpu.progress = self.show_progress
        from .editor import ShaderEditorPane

        self.editor = ShaderEditorPane(self._say, self._fail, self.mono_font)
        from .compare_view import ComparePane

        self.compare = ComparePane(self._say, self._fail,
                                   software=self.session.gpu.caps.software)
        self.compare_dir = Path(screenshot_dir)
        from .quality_view import QualityView

        self.quality = QualityView(quality)
        self.on_resize(*self.wnd.buffer_size)

    def _ui_wants_keyboard(self) -> bool:
        return self.imgui.get_io().want_capture_keyboard

    def _ui_wants_mouse(self) -> bool:
        shown = self.show_panel or self.paused or callable(getattr(self.scene, "hud", None))
        return shown and self.imgui.get_io().want_capture_mouse

    def set_ui_mode(self, on: bool) -> None:
        """The UI mode (the HUD and the panel take the mouse, the pointer is free) or free
        navigation (mouse look with the pointer captured; ImGui ignores the mouse)."""
        self.ui_mode = on
        self.mouse_look = not on
        self.looking = False
        self.wnd.mouse_exclusivity = not on
        io = self.imgui.get_io()
        no_mouse = int(self.imgui.ConfigFlags_.no_mouse)
        io.config_flags = (int(io.config_flags) & ~no_mouse) | (0 if on else no_mouse)

    def open_pause_menu(self) -> None:
        """Pause: time stops (time.playing false), the world stands still, the pointer is free
        for the menu's buttons."""
        if self.paused:
            return
        p = self.params
        self._before_pause = (p["time.playing"] if "time.playing" in p else None, self.ui_mode)
        if "time.playing" in p:
            p.set("time.playing", False)
        self.paused = True
        self.set_ui_mode(True)
        self._say("paused: Resume, or Esc again to quit")

    def resume(self) -> None:
        """Close the pause menu: time and the mode are as they were before it opened."""
        if not self.paused:
            return
        playing, ui_mode = self._before_pause
        self.paused = False
        if playing is not None and "time.playing" in self.params:
            self.params.set("time.playing", playing)
        self.set_ui_mode(ui_mode)

    def on_key(self, key, action, modifiers):
        self.ui.key_event(key, action, modifiers)
        k = self.wnd.keys
        name = self._key_names.get(key)
        if name is None or name in CHARACTER_KEYS:  # + - * / arrive as characters (on_char)
            return
        if action == k.ACTION_RELEASE:
            self.controller.release(name)  # always: no stuck keys
            return
        if name in WINDOW_KEYS:  # the teaching panes, in every scene, even while typing
            self.run_window_key(WINDOW_KEYS[name])
            return
        if name == "F" and getattr(modifiers, "ctrl", False):  # Ctrl+F: the panel's search
            self.show_panel = True
            self.panel_state.focus_search = True
            from .panel import next_event_id  # keys typed before Ctrl+F stay where they were

            self.panel_state.focus_after = next_event_id()
            self.panel_state.focus_ready = False
            return
        if self._ui_wants_keyboard() and name != "F12":
            return
        self.controller.press(name)
        self.run_events()

    def run_window_key(self, action: str) -> None:
        if action == "toggle_editor":
            self.editor.shown = not self.editor.shown
        elif action == "toggle_compare":
            self.compare.shown = not self.compare.shown

    def on_char(self, char):
        self.ui.unicode_char_entered(char)
        name = CHARACTERS.get(char)
        if name and not self._ui_wants_keyboard():
            self.controller.press(name)
            self.run_events()

    def run_events(self) -> None:
        """Carry out the one-shot actions the controller collected."""
        p = self.params
        for action, arg in self.controller.take_events():
            action = self.controller.keymap.resolve(action)
            if self.paused and action not in PAUSED_ACTIONS:
                continue
            if action == "quit":
                self.wnd.close()
            elif action == "pause_menu":  # Esc: the menu; Esc while it is open: quit
                if self.paused:
                    self.wnd.close()
                else:
                    self.open_pause_menu()
            elif action == "toggle_ui":
                self.set_ui_mode(not self.ui_mode)
            elif action == "screenshot":
                self.screenshot_requested = True
            elif action == "toggle_time" and "time.playing" in p:
                p.set("time.playing", not p["time.playing"])
            elif action in ("time_back", "time_forward") and "time.hour" in p:
                p.set("time.hour",
                      (p["time.hour"] + (0.25 if action == "time_forward" else -0.25)) % 24.0)
            elif action == "toggle_mouse":
                self.mouse_look = not self.mouse_look
                self.wnd.mouse_exclusivity = self.mouse_look
            elif action == "toggle_panel":
                self.show_panel = not self.show_panel
            elif action == "reset_camera":
                h = self.home
                self.scene.camera.set(position=h.position, yaw=h.yaw, pitch=h.pitch, fov=h.fov)
            elif action == "print_gl_version":
                self._say(f"OpenGL {self.ctx.info.get('GL_VERSION')} — "
                          f"{self.session.gpu.caps.renderer}")
            elif action == "print_camera":
                c = self.scene.camera
                self._say(f"camera ({c.position[0]:.2f}, {c.position[1]:.2f}, {c.position[2]:.2f}) "
                          f"yaw {c.yaw:.1f} pitch {c.pitch:.1f}")
            elif action == "print":
                self._say(arg)
            elif action.startswith("set:"):  # a key bound to a parameter value (e.g. ocean 1/2/3)
                name, _, value = action[4:].partition("=")
                if name in p:
                    p.set_from_string(f"{name}={value}")
                    self._say(f"{name} = {value}")
            elif action.startswith("toggle:"):  # a key that flips a boolean parameter
                name = action[7:]
                if name in p:
                    p.set(name, not p[name])
            elif action.startswith("cycle:"):  # a choice steps to its next one, wrapping
                name = action[6:]
                if name in p:
                    p.set(name, cycle_value(p.spec(name), p[name]))
                    self._say(f"{name} = {p[name]}")

    def _say(self, text: str) -> None:
        print(text)
        self.messages.append(text)

    def _fail(self, text: str) -> None:
        """A problem the window survives: one line in the panel, and on the terminal."""
        print(f"natura: {text}", file=sys.stderr, flush=True)
        self.messages.append(text)

    def _print_new_errors(self, errors) -> None:
        """Print each shader error whole to the terminal once, when it appears; an error that
        goes away and comes back is printed again."""
        current = {str(e) for e in errors}
        for text in sorted(current - self._printed_errors):
            print(f"natura: shader error: {text}", file=sys.stderr, flush=True)
        self._printed_errors = current

    def on_mouse_position(self, x, y, dx, dy):
        self.ui.mouse_position_event(x, y, dx, dy)
        if self.mouse_look:
            self.scene.camera.rotate(dx * LOOK_DEGREES_PER_PIXEL, -dy * LOOK_DEGREES_PER_PIXEL)

    def on_mouse_drag(self, x, y, dx, dy):
        self.ui.mouse_drag_event(x, y, dx, dy)
        if self.looking or self.mouse_look:
            self.scene.camera.rotate(dx * LOOK_DEGREES_PER_PIXEL, -dy * LOOK_DEGREES_PER_PIXEL)

    def on_mouse_scroll(self, dx, dy):
        self.ui.mouse_scroll_event(dx, dy)
        if not self._ui_wants_mouse():
            self.controller.speed = float(np.clip(self.controller.speed * 1.15**dy, 0.1, 5000.0))

    def on_mouse_press(self, x, y, button):
        self.ui.mouse_press_event(x, y, button)
        if button == self.wnd.mouse.right and not self._ui_wants_mouse():
            self.looking = True

    def on_mouse_release(self, x, y, button):
        self.ui.mouse_release_event(x, y, button)
        if button == self.wnd.mouse.right:
            self.looking = False

    def on_resize(self, width, height):
        self.ui.resize(width, height)
        if self._rendering:  # a progress frame (a bake) dispatched events mid-render: the
            self._resize_pending = (width, height)  # target is swapped after the render
            return
        if width > 0 and height > 0:
            self.window_size = (int(width), int(height))
            self._fit_target()

    def internal_size(self) -> tuple[int, int]:
        """The size the scene renders at: the window's, times the dynamic resolution's scale."""
        return self.resolution.internal_size(self.window_size)

    def _fit_target(self, size: tuple[int, int] | None = None) -> None:
        """Make the scene's target ``size`` (default: the internal size), unless it is."""
        size = self.internal_size() if size is None else size
        if self.target is not None and tuple(self.target.size) == tuple(size):
            return  # the same size again (pyglet repeats it when the window maps)
        if self.target is not None:
            self.session.gpu.free(self.target)
            self.target = None
        self.target = self.session.gpu.target("window", "scene radiance", size)
        # the display pass's bicubic taps beyond the border read the edge, not the other side
        self.target.color.repeat_x = self.target.color.repeat_y = False

    def update_scale(self, frame_ms: float) -> None:
        """Dynamic resolution: judge the last frame's time against the budget, and resize the
        scene's target when the scale changed (app/ui/resolution.py)."""
        p = self.params
        budget = p["output.frame_budget_ms"] if "output.frame_budget_ms" in p else 33.0
        setting = p["output.scale"] if "output.scale" in p else 1.0
        self.resolution.observe(frame_ms, budget, setting)
        if self.window_size[0] > 0:
            self._fit_target()

    def poll_shaders(self) -> None:
        now = time.perf_counter()
        if now - self._last_poll < POLL_SECONDS:
            return
        self._last_poll = now
        shaders = self.session.gpu.shaders
        try:
            for prog in shaders.poll():
                if prog.failed:
                    self.messages.append(f"{prog.name}: reload failed, "
                                         "still showing the last good version")
                elif prog.errors:  # compiled, but e.g. a broken @param or a retyped uniform
                    self.messages.append(f"{prog.name}: reloaded with "
                                         f"{len(prog.errors)} problem(s)")
                else:
                    self.messages.append(f"{prog.name}: reloaded")
            errors = shaders.errors()
        except Exception as exc:  # the library failed, not a shader: keep the window running
            text = f"shader reload failed: {_one_line(exc)}"
            if text != self.poll_error:
                self._fail(text)
            self.poll_error = text
            return
        self.poll_error = None
        self._print_new_errors(errors)

    def render_scene(self, dt: float) -> None:
        import moderngl

        from .display import draw_display

        ctx = self.ctx
        ctx.disable(moderngl.BLEND)  # the ImGui renderer leaves blending on
        error = None
        self._rendering = True
        try:
            frame = self.scene.frame(self.target.size, dt)
            self.scene.render(frame, self.target)
        except Exception as exc:  # keep the window alive; show why the image stopped updating
            error = f"render failed: {exc}"
        finally:
            self._rendering = False
        if self._resize_pending is not None:
            pending, self._resize_pending = self._resize_pending, None
            self.on_resize(*pending)
        self.wnd.use()
        ctx.viewport = (0, 0, *self.wnd.buffer_size)
        try:
            upscale = self.params["output.upscale"] if "output.upscale" in self.params else ""
            draw_display(self.session.gpu, self.target.color, self.scene.exposure(),
                         self.params["output.tonemap"],
                         bicubic=upscale == "bicubic" and self.target.size != self.window_size)
        except Exception as exc:  # e.g. the display shader itself is broken
            error = error or f"display failed: {exc}"
        if error is not None and error != self.render_error:
            print(f"natura: {error}", file=sys.stderr, flush=True)  # whole, once
        self.render_error = error

    def show_progress(self, label: str, fraction: float) -> None:
        """Draw one frame with a progress bar while a long GPU job (a bake) runs."""
        imgui = self.imgui
        self.wnd.use()
        self.wnd.clear(0.08, 0.08, 0.09, 1.0)
        imgui.get_io().delta_time = 1.0 / 60.0
        imgui.new_frame()
        w, h = self.wnd.size
        imgui.set_next_window_pos((w * 0.5 - 180, h * 0.5 - 30))
        imgui.set_next_window_size((360, 70))
        imgui.begin("Working", flags=imgui.WindowFlags_.no_decoration)
        imgui.text(label)
        imgui.progress_bar(float(fraction), (-1, 0), f"{fraction * 100:.0f} %")
        imgui.end()
        imgui.render()
        self.ui.render(imgui.get_draw_data())
        self.wnd.swap_buffers()
        self.progress_frames += 1

    def _folder_problem(self, folder: Path) -> str | None:
        """Why files cannot be written in ``folder`` (made if missing), or None."""
        if folder.exists() and not folder.is_dir():
            return f"{folder} is a file, not a folder"
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            return f"cannot make the folder {folder}: {exc.strerror or _one_line(exc)}"
        return None

    def _save(self, what: str, folder: Path, stem: str, suffix: str,
              write: Callable[[Path], object]) -> Path | None:
        """``write(path)`` into the first free ``STEM-NNNN.SUFFIX`` of ``folder``; never
        overwrites. A folder that cannot be written is a message, not a crash."""
        problem = self._folder_problem(folder)
        if problem:
            self._fail(f"{what} not saved: {problem}")
            return None
        for _ in range(100):  # another process may take the name between the check and the link
            path = next_free_path(folder, stem, suffix)
            try:
                write(path)
            except (FileExistsError, OutputExistsError):
                continue
            except Exception as exc:  # noqa: BLE001 - a message; the window goes on
                self._fail(f"{what} not saved in {folder}: {_one_line(exc)}")
                return None
            self.messages.append(f"saved {path}")
            return path
        self._fail(f"{what} not saved: no free name in {folder} after 100 tries")
        return None

    def save_screenshot(self) -> Path | None:
        """The scene, tone-mapped, as the first free ``SCENE-NNNN.png``."""
        path = self._save("screenshot", self.screenshot_dir, self.scene.name, ".png",
                          lambda p: write_png(p, self.target.read(), self.scene.exposure(),
                                              self.params["output.tonemap"]))
        if path is not None:
            self.screenshots.append(path)
        return path

    def save_preset(self) -> Path | None:
        text = self.params.preset_text(f"scene {self.scene.name}")
        return self._save("preset", self.preset_dir, self.scene.name, ".toml",
                          lambda p: write_text_atomic(p, text))

    def save_keyframes(self, keyframes) -> Path | None:
        text = keyframes.to_toml()
        return self._save("keyframes", self.keyframes_dir, "keyframes", ".toml",
                          lambda p: write_text_atomic(p, text))

    def views_panel(self) -> None:
        """The scene's views (one folder per scene under resources/presets/views/): a list to
        pick one from, with what it shows and teaches."""
        imgui = self.imgui
        try:
            views = views_of(self.scene.name)
        except Exception as exc:  # noqa: BLE001 - a broken view file must not close the panel
            imgui.text_wrapped(f"views unavailable: {_one_line(exc)}")
            return
        if not views or not imgui.collapsing_header(f"Views ({len(views)})"):
            return
        for view in views:
            if imgui.selectable(f"{view.title}##view-{view.name}",
                                self.current_view == view.name)[0]:
                self.apply_view(view)
            if imgui.is_item_hovered():
                imgui.set_tooltip(view.lesson)
        current = next((v for v in views if v.name == self.current_view), None)
        if current is not None:
            imgui.text_wrapped(current.lesson)

    def apply_view(self, view) -> None:
        """Start over from the scene's own values, then the view's parameters and camera."""
        for name, value in self.start_values.items():
            if self.params[name] != value:
                self.params.set(name, value)
        try:
            view.apply(self.params)
        except Exception as exc:  # noqa: BLE001 - shown, the window goes on
            self._fail(_one_line(exc))
            return
        if view.place(self.scene.camera):
            type(self.scene).on_user_camera(self.params)
        self.current_view = view.name
        self._say(f"view {view.name}: {view.title}")

    def context_paths(self) -> dict[str, str]:
        """The scene's paths on this context (``Effect.context_paths``), for the panel."""
        out: dict[str, str] = {}
        for effect in self.scene.instances:
            try:
                out.update(type(effect).context_paths(self.session.gpu.caps, self.params))
            except Exception as exc:  # noqa: BLE001 - a figure must not close the panel
                out[effect.name] = f"unavailable: {_one_line(exc)}"
        return out

    def build_panel(self, dt: float) -> None:
        from . import panel

        imgui = self.imgui
        imgui.set_next_window_pos((10, 10), imgui.Cond_.first_use_ever)
        imgui.set_next_window_size(panel_size(self.wnd.size), imgui.Cond_.first_use_ever)
        imgui.begin(f"Natura — {self.scene.title}###natura-panel")
        pos, size = imgui.get_window_pos(), imgui.get_window_size()
        self.panel_rect = (float(pos.x), float(pos.y), float(pos.x + size.x),
                           float(pos.y + size.y))
        gpu = self.session.gpu
        imgui.text(f"{gpu.caps.describe()}")
        paths = self.context_paths()
        if paths and imgui.tree_node("Paths on this context"):
            for what, how in paths.items():
                imgui.text_wrapped(f"{what}: {how}")
            imgui.tree_pop()
        ms = np.array(self.frame_ms, dtype=np.float32)
        self.frame_text = frame_line(ms)
        imgui.text(self.frame_text)
        imgui.text(scale_line(self.resolution, tuple(self.target.size), self.window_size,
                              self.params.get("output.frame_budget_ms", 33.0)))
        self.frame_plot(ms)
        try:
            errors = gpu.shaders.errors()
        except Exception as exc:
            errors = [f"shader errors unavailable: {_one_line(exc)}"]
        problems = [*errors, *(e for e in (self.render_error, self.poll_error) if e)]
        if problems:
            imgui.text_colored(panel.ERROR_COLOUR,
                               "Shader errors (the last good program keeps rendering):")
            panel.error_list(problems)
        if "time.hour" in self.params:
            playing = self.params["time.playing"]
            if imgui.button("Pause" if playing else "Resume"):
                self.params.set("time.playing", not playing)
            imgui.same_line()
            imgui.text(hour_label(self.params["time.hour"]))
            changed, hour = imgui.slider_float("time of day##scrub", self.params["time.hour"],
                                               0.0, 24.0, "%.2f h")
            if changed:
                self.params.set("time.hour", hour % 24.0)
        cam = self.scene.camera
        imgui.text(f"camera ({cam.position[0]:.1f}, {cam.position[1]:.1f}, "
                   f"{cam.position[2]:.1f})  yaw {cam.yaw:.0f}  pitch {cam.pitch:.0f}  "
                   f"speed {self.controller.speed:.1f} m/s"
                   + (f"  turbo {self.controller.turbo_speed:g} m/s" if self.controller.turbo
                      else ""))
        changed, fov = imgui.slider_float("fov##camera", cam.fov, 10.0, 120.0, "%.0f deg")
        if changed:
            cam.set(fov=fov)
        if imgui.button("Screenshot"):
            self.screenshot_requested = True
        imgui.same_line()
        if imgui.button("Save preset"):
            self.save_preset()
        imgui.same_line()
        if imgui.button("Reset all"):
            self.params.reset()
        self.views_panel()
        if imgui.button("Shader editor (F2)"):
            self.editor.shown = not self.editor.shown
        imgui.same_line()
        if imgui.button("Compare A/B (F3)"):
            self.compare.shown = not self.compare.shown
        if imgui.collapsing_header("Quality: time against error (measured)",
                                   imgui.TreeNodeFlags_.default_open
                                   if self.quality.picks else 0):
            self.quality.draw(self.scene.name, self.params, tuple(self.target.size))
        panel.scene_panel(self.params, self.scene, self.panel_state)
        for effect in self.scene.active_instances():
            for item in effect.panel_items():  # editors an effect offers besides its parameters
                if (isinstance(item, Keyframes)
                        and imgui.collapsing_header("Sky keyframes (every 3 h)")):
                    panel.keyframes_panel(item)
                    if imgui.button("Save keyframes"):
                        self.save_keyframes(item)
                elif isinstance(item, Inspector) and imgui.collapsing_header(
                        item.title, imgui.TreeNodeFlags_.default_open):
                    panel.inspector_panel(self.params, item, self.ui.register_texture)
        if imgui.collapsing_header("Resources"):
            for a in gpu.allocations:
                imgui.text(f"{a.owner}: {a.kind} {a.name}")
        if imgui.collapsing_header("Controls"):
            for keys, what in (*self.controller.keymap.help, *WINDOW_KEYS_HELP):
                imgui.text(f"{keys:14s} {what}")
        panel.messages(self.messages)
        imgui.end()

    def frame_plot(self, ms: np.ndarray) -> None:
        """The last 240 frame times (ImPlot), the y axis fitted to them."""
        implot = self.implot
        flags = (implot.Flags_.no_title | implot.Flags_.no_legend | implot.Flags_.no_menus
                 | implot.Flags_.no_box_select | implot.Flags_.no_mouse_text)
        if implot.begin_plot("##frametime", (-1, 90), flags):
            try:
                implot.setup_axes("", "ms", implot.AxisFlags_.no_tick_labels,
                                  implot.AxisFlags_.auto_fit)
                implot.setup_axis_limits(implot.ImAxis_.x1, 0, len(ms), implot.Cond_.always)
                implot.plot_line("frame", np.ascontiguousarray(ms, dtype=np.float32))
            finally:
                implot.end_plot()

    def build_editor(self) -> None:
        if not self.editor.shown:
            return
        shaders = self.session.gpu.shaders
        try:
            errors = shaders.errors()
        except Exception:  # noqa: BLE001 - the panel lists why
            errors = []
        self.editor.draw(shaders, errors, self.wnd.size)

    def build_hud(self) -> None:
        """The HUD of a scene that has a ``hud()`` method (app/ui/hud.py), and the pause menu."""
        from . import hud as hud_ui

        size = self.wnd.size
        rects: dict = {}
        figures = getattr(self.scene, "hud", None)
        if callable(figures):
            error = None
            try:
                self.hud_state = figures()
            except Exception as exc:  # a figure that cannot be computed must not close the window
                self.hud_state, error = None, _one_line(exc)
            rects = hud_ui.draw_hud(self.hud_state, self.params, size, ui_mode=self.ui_mode,
                                    paused=self.paused,
                                    keys_help=self.controller.keymap.help, error=error)
        if self.paused:
            choice = hud_ui.pause_menu(size, rects)
            if choice == "resume":
                self.resume()
            elif choice == "quit":
                self.wnd.close()
        self.hud_rects = rects

    def frame(self, dt: float, measured: bool = True) -> None:
        """One frame, ``dt`` seconds after the last. ``measured``: ``dt`` is the last frame's
        measured time (the first frame's is not: no frame came before it), which the panel
        shows and the dynamic resolution judges."""
        imgui = self.imgui
        if measured:
            self.frame_ms.append(dt * 1000.0)
            self.update_scale(dt * 1000.0)
        if self.screenshot_requested:  # a screenshot has the window's size, whatever the scale
            self._fit_target(self.window_size)
        self.poll_shaders()
        if self.paused:
            dt = 0.0  # the world stands still behind the pause menu
        elif not self._ui_wants_keyboard():
            self.controller.update(self.scene.camera, dt, self.params)
        if self.compare.requested:  # before the ImGui frame: it draws progress frames
            self.compare.requested = False
            self.compare.run(self.session, self.ui.register_texture,
                             lambda text: self.show_progress(text, 0.5))
        self.render_scene(dt)
        if self.screenshot_requested:
            self.screenshot_requested = False
            self.save_screenshot()
        io = imgui.get_io()
        io.delta_time = max(dt, 1e-5)
        ps = self.panel_state
        if ps.focus_search and ps.focus_after is not None and not ps.focus_ready:
            from .panel import queued_before  # Ctrl+F waits for the keys typed before it

            ps.focus_ready = not queued_before(ps.focus_after)
        imgui.new_frame()
        if self.show_panel:
            self.build_panel(dt)
        self.build_editor()
        if self.compare.shown:
            self.compare.draw(self.session, self.ui.register_texture, self.wnd.size,
                              self.compare_dir)
        self.build_hud()
        imgui.render()
        self.ui.render(imgui.get_draw_data())

    def run(self, frames: int | None = None) -> int:
        last = time.perf_counter()
        n = 0
        while not self.wnd.is_closing and (frames is None or n < frames):
            now = time.perf_counter()
            dt = 1.0 / 60.0 if n == 0 else now - last
            last = now
            self.wnd.clear(0.0, 0.0, 0.0, 1.0)
            self.frame(dt, measured=n > 0)
            self.wnd.swap_buffers()
            n += 1
        return n

    def close(self) -> None:
        self.compare.release(self.ui.remove_texture)
        self.ui.shutdown()
        self.implot.destroy_context()
        self.imgui.destroy_context()
        self.session.release()
        self.wnd.close()
        self.wnd.destroy()


def run_window(scene_name: str, params: ParamSet, camera: Camera, size=(1280, 720),
               shader_root=None, frames: int | None = None, setup=None, quality=None) -> int:
    """Open the window on a scene and run it (``frames`` at most); ``setup(scene)`` runs once
    the scene exists (``natura window shading --mesh FILE`` hands over the mesh there);
    ``quality`` is ``--quality auto``'s picks (their chart in the panel)."""
    win = NaturaWindow(scene_name, params, camera, size, shader_root, quality=quality)
    if setup is not None:
        setup(win.scene)
    try:
        win.run(frames)
    finally:
        win.close()
    return 0

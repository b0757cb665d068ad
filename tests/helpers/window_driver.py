"""Drives a real Natura window (run under Xvfb by the tests in tests/window) and prints its
findings as one ``RESULT {json}`` line on stdout.

The default run feeds the window's own event handlers (panel, mouse look, screenshots, live
shader edits on a copy of glsl/). The key runs (``fly-keys``, ``planet-keys``, ``ocean-models``,
``robustness``, ``cli-escape``, ``maritime-keys``, ``maritime-cli-escape``) type real X key
events with xdotool (:class:`XKeys`), so they go through pyglet's key codes and the window's key
names as a person's typing does.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

XVFB_SKIP = "no display: Xvfb not installed (apt-get install xvfb)"
#: what the window tests need: the X server itself, which xvfb_display starts
NO_XVFB = shutil.which("Xvfb") is None
XDOTOOL_SKIP = "xdotool not installed: no real key events (apt-get install xdotool)"


def under_xvfb(args, cwd, timeout=180) -> subprocess.CompletedProcess:
    """Run ``args`` on this process's Xvfb (:func:`xvfb_display`), without the caller's
    DISPLAY / WAYLAND_DISPLAY. The command runs in a session of its own: whatever it left
    running (a ``natura window`` a driver started) is ended with it, so no window of one test
    is on the display when the next starts."""
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env["DISPLAY"] = xvfb_display()
    # files, not pipes: a process left behind holding a pipe would keep the read from ending
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        proc = subprocess.Popen(args, cwd=cwd, env=env, stdout=out, stderr=err, text=True,
                                start_new_session=True)
        try:
            proc.wait(timeout=timeout)
        finally:
            with contextlib.suppress(ProcessLookupError, PermissionError):
                os.killpg(proc.pid, 9)  # the command's session: what it left behind
            proc.wait()
            if proc.returncode != 0:  # it may have died with a key held: a fresh server next
                _stop_xvfb()
        out.seek(0)
        err.seek(0)
        return subprocess.CompletedProcess(proc.args, proc.returncode, out.read(), err.read())


#: this process's X server: (the Xvfb process, its display), started on first use
_XVFB: list = []
_XVFB_STOP_REGISTERED: list = []


def _end_with_parent() -> None:
    """In the server's process before it starts: a SIGTERM when the test process ends, however
    it ends (a pytest-xdist worker may leave without running atexit)."""
    import ctypes
    import signal

    with contextlib.suppress(OSError, AttributeError):
        ctypes.CDLL("libc.so.6").prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG


def xvfb_display() -> str:
    """The display of one Xvfb per test process (per pytest-xdist worker), started on first
    use and ended when the process exits: ``xvfb-run`` for each command cost about a second of
    start-up (the server, its keymap, xauth) that every window test paid. Xvfb picks a free
    display itself (``-displayfd``), so two workers never take the same one. It does not reset
    when its last client leaves (``-noreset``: once in about 70 commands, one that connected
    just after the last had left found no display); a command's windows go with it, its keys
    are released when it ends normally, and after one that failed the next command gets a
    fresh server."""
    if _XVFB and _XVFB[0].poll() is None:
        return _XVFB[1]
    import atexit
    import select

    _XVFB.clear()
    read, write = os.pipe()
    server = subprocess.Popen(["Xvfb", "-displayfd", str(write), "-screen", "0",
                               "1280x720x24", "-nolisten", "tcp", "-noreset"], pass_fds=(write,),
                              stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL, start_new_session=True,
                              preexec_fn=_end_with_parent)
    os.close(write)
    number = b""
    deadline = time.monotonic() + 60
    while not number.endswith(b"\n") and time.monotonic() < deadline:
        ready, _, _ = select.select([read], [], [], max(0.0, deadline - time.monotonic()))
        chunk = os.read(read, 64) if ready else b""
        if not chunk:
            break
        number += chunk
    os.close(read)
    if not number.strip().isdigit():
        server.kill()
        server.wait()
        raise RuntimeError(f"Xvfb did not start (it said {number!r})")

    if not _XVFB_STOP_REGISTERED:
        atexit.register(_stop_xvfb)
        _XVFB_STOP_REGISTERED.append(True)
    _XVFB.extend([server, f":{int(number)}"])
    return _XVFB[1]


def _stop_xvfb() -> None:
    """End this process's Xvfb (the next :func:`xvfb_display` starts another)."""
    if not _XVFB:
        return
    server = _XVFB[0]
    _XVFB.clear()
    server.terminate()
    try:
        server.wait(10)
    except subprocess.TimeoutExpired:
        server.kill()
        server.wait()


def xvfb_server_num() -> int:
    """Where this process's search for a free X display starts: 99 (xvfb-run's own default)
    outside pytest-xdist, 200 + 20 × the worker's index under it (gw0, gw1, …)."""
    worker = os.environ.get("PYTEST_XDIST_WORKER", "")
    return 200 + 20 * int(worker[2:]) if worker.startswith("gw") and worker[2:].isdigit() else 99


def drive(mode: str, work, driver=__file__) -> tuple[dict, subprocess.CompletedProcess]:
    """Run ``driver``'s (this one's by default) ``mode`` in ``work`` under Xvfb: its RESULT
    (JSON) and the process."""
    proc = under_xvfb([sys.executable, str(driver), str(work), mode], cwd=work)
    lines = [line for line in proc.stdout.splitlines() if line.startswith("RESULT ")]
    assert proc.returncode == 0 and lines, proc.stdout[-3000:] + proc.stderr[-3000:]
    return json.loads(lines[-1][len("RESULT "):]), proc


def atomic_write(path: Path, text: str) -> None:
    tmp = path.with_name(path.name + ".tmp~")
    tmp.write_text(text)
    os.replace(tmp, path)  # like editors that save by rename


def main(work: str) -> int:
    from app import DEFAULT_SHADER_ROOT
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    work_dir = Path(work)
    shaders = work_dir / "glsl"
    shutil.copytree(DEFAULT_SHADER_ROOT, shaders)
    os.chdir(work_dir)
    out: dict = {}
    params = scene_params("sky", shader_root=shaders, sets=["time.hour=10"])
    win = W.NaturaWindow("sky", params, get_scene("sky").new_camera(), (320, 180), shaders,
                         screenshot_dir="shots")
    k = win.wnd.keys
    mods = win.wnd.modifiers
    w, h = win.wnd.buffer_size

    def frames(n, dt=1 / 60):
        for _ in range(n):
            win.wnd.clear()
            win.frame(dt)
            win.wnd.swap_buffers()

    def screen():
        data = win.ctx.screen.read(viewport=(0, 0, w, h), components=3)
        return np.frombuffer(data, dtype=np.uint8).reshape(h, w, 3)[::-1].astype(int)

    import imgui_bundle

    out["imgui_bundle"] = imgui_bundle.__version__
    out["gl"] = win.ctx.version_code
    frames(3)
    with_panel = screen()
    win.show_panel = False
    frames(2)
    without_panel = screen()
    win.show_panel = True
    out["panel_pixels"] = int((np.abs(with_panel - without_panel).sum(axis=2) > 30).sum())
    # F1 hides the panel; the rest runs without it so the scene fills the small window
    win.on_key(k.F1, k.ACTION_PRESS, mods)
    win.on_key(k.F1, k.ACTION_RELEASE, mods)
    out["f1_hides_panel"] = not win.show_panel
    # fly: W for 30 frames at 1/60 s
    win.on_mouse_position(w - 5, h - 5, 0, 0)
    frames(2)
    p0 = np.array(win.scene.camera.position)
    win.on_key(k.W, k.ACTION_PRESS, mods)
    frames(30)
    win.on_key(k.W, k.ACTION_RELEASE, mods)
    p1 = np.array(win.scene.camera.position)
    out["moved_forward_m"] = float(np.dot(p1 - p0, win.scene.camera.forward()))
    yaw0 = win.scene.camera.yaw
    win.on_mouse_press(w - 5, h - 5, win.wnd.mouse.right)
    win.on_mouse_drag(w - 45, h - 5, -40, 0)
    win.on_mouse_release(w - 45, h - 5, win.wnd.mouse.right)
    out["yaw_change"] = float((win.scene.camera.yaw - yaw0 + 180) % 360 - 180)
    playing0 = params["time.playing"]
    win.on_key(k.SPACE, k.ACTION_PRESS, mods)
    win.on_key(k.SPACE, k.ACTION_RELEASE, mods)
    out["space_toggles_time"] = params["time.playing"] != playing0
    win.on_key(k.SPACE, k.ACTION_PRESS, mods)
    win.on_key(k.SPACE, k.ACTION_RELEASE, mods)
    hour0 = params["time.hour"]
    win.on_key(k.RIGHT_BRACKET, k.ACTION_PRESS, mods)
    out["bracket_hour_step"] = params["time.hour"] - hour0
    # screenshots never overwrite
    (work_dir / "shots").mkdir()
    (work_dir / "shots" / "sky-0001.png").write_bytes(b"user file")
    win.on_key(k.P, k.ACTION_PRESS, mods)
    frames(1)
    win.on_key(k.F12, k.ACTION_PRESS, mods)
    frames(1)
    out["screenshots"] = [str(p) for p in win.screenshots]
    out["user_file_kept"] = (work_dir / "shots" / "sky-0001.png").read_bytes() == b"user file"
    # live edit: change the sky → image changes
    frag = shaders / "sky" / "sky.frag"
    good = frag.read_text()
    before = screen()
    atomic_write(frag, good.replace("fragColor = vec4(SkyRadiance(CameraRayDirection(vUV)), 1.0);",
                                    "fragColor = vec4(SkyRadiance(CameraRayDirection(vUV))"
                                    " * vec3(1.0, 0.0, 0.0), 1.0);"))
    time.sleep(W.POLL_SECONDS + 0.05)
    frames(2)
    edited = screen()
    out["edit_changed_image"] = float(np.abs(edited - before).mean())
    out["edit_green_mean"] = float(edited[..., 1].mean())
    # a typo: the last good program keeps rendering, the error names file:line
    lines = good.splitlines()
    bad_line = next(i for i, line in enumerate(lines, 1) if "fragColor =" in line)
    atomic_write(frag, good.replace("fragColor = vec4(", "fragColor = vec4(oops + "))
    time.sleep(W.POLL_SECONDS + 0.05)
    frames(2)
    errors = [str(e) for e in win.session.gpu.shaders.errors()]
    out["errors"] = errors
    out["expected_error_prefix"] = f"{frag.relative_to(work_dir)}:{bad_line}:"
    out["still_rendering_after_typo"] = float(np.abs(screen() - edited).mean())
    atomic_write(frag, good)
    time.sleep(W.POLL_SECONDS + 0.05)
    frames(2)
    out["errors_after_fix"] = [str(e) for e in win.session.gpu.shaders.errors()]
    out["restored_diff"] = float(np.abs(screen() - before).mean())
    # a new annotated uniform gets a parameter (and so a slider) with no Python change
    radiance = shaders / "sky" / "sky_radiance.glsl"
    text = radiance.read_text()
    text = text.replace("uniform float uBelowHorizon;",
                        "uniform float uNightTint; // @param 0.5 [0, 1] a student's new knob\n"
                        "uniform float uBelowHorizon;")
    text = text.replace("    return sky + (sun",
                        "    sky *= 1.0 + 0.0 * uNightTint;\n    return sky + (sun")
    atomic_write(radiance, text)
    time.sleep(W.POLL_SECONDS + 0.05)
    frames(2)
    out["new_param"] = "sky.night_tint" in params
    win.on_key(k.ESCAPE, k.ACTION_PRESS, mods)
    out["escape_closes"] = bool(win.wnd.is_closing)
    win.close()
    print("RESULT " + json.dumps(out))
    return 0




def bake_progress(work: str) -> int:
    """Open the noise lab on a cold cache: the bake must draw progress frames in the window."""
    os.environ["NATURA_CACHE"] = str(Path(work) / "cache")
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    params = scene_params("noise", sets=["noise.view=shape", "bake_shape.size=32"])
    win = W.NaturaWindow("noise", params, get_scene("noise").new_camera(), (320, 180))
    win.wnd.clear()
    win.frame(1 / 60)
    win.wnd.swap_buffers()
    eff = win.scene.effect("noise")
    out = {"progress_frames": win.progress_frames, "cache": eff.bakes.last.cache,
           "path": eff.bakes.last.path}
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


class _Xdo:
    """xdotool's own library (libxdo, of which the xdotool command is a front end) in this
    process: ``keydown`` / ``keyup`` send a key as ``xdotool keydown KEY`` does (through the X
    test extension, to the focused window; keysyms needing Shift or a spare keycode handled the
    same way) without starting a process for each key, tens of ms each on a loaded machine.
    None of it when the library cannot be loaded: the command is used then."""

    def __init__(self) -> None:
        import ctypes

        self.lib = ctypes.CDLL("libxdo.so.3")
        self.lib.xdo_new.restype = ctypes.c_void_p
        self.lib.xdo_new.argtypes = [ctypes.c_char_p]
        for name in ("xdo_send_keysequence_window_down", "xdo_send_keysequence_window_up"):
            fn = getattr(self.lib, name)
            fn.restype = ctypes.c_int
            fn.argtypes = [ctypes.c_void_p, ctypes.c_ulong, ctypes.c_char_p, ctypes.c_uint]
        self.xdo = self.lib.xdo_new(None)  # $DISPLAY
        if not self.xdo:
            raise OSError("xdo_new: no display")

    def key(self, action: str, key: str) -> None:
        fn = getattr(self.lib, f"xdo_send_keysequence_window_{action}")
        # window 0: CURRENTWINDOW, the focused one, through XTEST as xdotool does by default;
        # no delay (xdotool's 12 ms is the gap between the keys of one sequence)
        if fn(self.xdo, 0, key.encode(), 0) != 0:
            raise RuntimeError(f"libxdo could not send key{action} {key!r}")


def _xdo() -> _Xdo | None:
    try:
        return _Xdo()
    except OSError:
        return None


class XKeys:
    """Real key events for a window under Xvfb: xdotool focuses it and types through the X test
    extension, and the window's event dispatch (pyglet's, which each frame's swap_buffers runs)
    hands it ordinary presses.

    It waits until the window has received each press and release, so a slow frame never loses
    a key: the events waiting are dispatched first as a frame's end does (xdotool returns once
    the X server has the event, so it is almost always there at once, and no frame is drawn just
    to fetch it), else frame by frame. ``hold`` counts the frames the window updated with the
    action held, so a test can compare a motion with speed × frames × dt exactly. ``received``
    logs what the window got: (pyglet's symbol name, the window's key name, press/release) and
    characters.
    """

    def __init__(self, win, pattern: str, dt: float = 1 / 60):
        self.win, self.dt = win, dt
        self.received: list = []
        self.presses = 0  # key taps and holds typed (modifier keys down included)
        on_key, on_char = win.wnd.key_event_func, win.wnd.unicode_char_entered_func

        def spy_key(key, action, modifiers):
            try:
                from pyglet.window import key as pk

                symbol = pk.symbol_string(key)
            except Exception:
                symbol = str(key)
            press = action == win.wnd.keys.ACTION_PRESS
            self.received.append(("press" if press else "release", symbol,
                                  win._key_names.get(key)))
            on_key(key, action, modifiers)

        def spy_char(char):
            self.received.append(("char", char, None))
            on_char(char)

        on_motion = win.wnd.mouse_position_event_func

        def spy_motion(x, y, dx, dy):
            self.received.append(("motion", (dx, dy), None))
            on_motion(x, y, dx, dy)

        win.wnd.key_event_func, win.wnd.unicode_char_entered_func = spy_key, spy_char
        win.wnd.mouse_position_event_func = spy_motion
        self.xdo = _xdo()
        self.frames(2)
        found = subprocess.run(["xdotool", "search", "--sync", "--name", pattern],
                               capture_output=True, text=True, timeout=30).stdout.split()
        self.id = found[0]
        subprocess.run(["xdotool", "windowfocus", "--sync", self.id], check=True, timeout=30)
        self.frames(2)

    def frames(self, n: int) -> None:
        for _ in range(n):
            if self.win.wnd.is_closing:  # Esc closed it: pyglet's window is gone
                return
            self.win.wnd.clear()
            self.win.frame(self.dt)
            self.win.wnd.swap_buffers()

    def dispatch(self, arrived, wait_s: float = 0.05) -> bool:
        """Dispatch the X events waiting for the window (what swap_buffers does after a frame's
        flip) until ``arrived()`` holds, for at most ``wait_s``; no frame is drawn."""
        deadline = time.perf_counter() + wait_s
        while not self.win.wnd.is_closing:
            self.win.wnd._window.dispatch_events()  # moderngl-window's pyglet window
            if arrived() or time.perf_counter() > deadline:
                break
            time.sleep(0.002)
        return bool(arrived()) or bool(self.win.wnd.is_closing)

    def _until(self, kind: str, since: int, limit: int = 240, step=None,
               moved: bool = False) -> None:
        """Until an event of ``kind`` ("press"/"release"/"motion", with ``moved`` a motion by a
        nonzero move: toggling the pointer grab sends one of 0) arrives after ``since``:
        dispatched between frames when it is there, else after frames (``step``, one frame by
        default)."""
        def arrived():
            return any(e[0] == kind and (not moved or any(e[1])) for e in self.received[since:])

        for _ in range(limit):
            if self.dispatch(arrived):
                return
            (step or (lambda: self.frames(1)))()
        raise AssertionError(f"no {kind} event reached the window in {limit} frames: "
                             f"{self.received[since:]}")

    def pointer_home(self) -> None:
        """The pointer back where a new X server puts it, the screen's centre: the tests of one
        worker share its Xvfb, and with the pointer left inside the window by an earlier test,
        a move made under mouse look's pointer grab never reached the window."""
        w, h = subprocess.run(["xdotool", "getdisplaygeometry"], capture_output=True,
                              text=True, check=True, timeout=30).stdout.split()
        subprocess.run(["xdotool", "mousemove", "--sync", str(int(w) // 2), str(int(h) // 2)],
                       check=True, timeout=30)
        self.frames(1)

    def move_pointer(self, dx: int, dy: int) -> None:
        """``xdotool mousemove_relative`` by (dx, dy) pixels, then frames until the window's
        motion handler has had it (as for a key: the event's arrival, not a time)."""
        n = len(self.received)
        subprocess.run(["xdotool", "mousemove_relative", "--", str(dx), str(dy)], check=True,
                       timeout=30)
        self._until("motion", n, moved=True)
        self.frames(1)

    def send(self, action: str, key: str) -> None:
        """``xdotool key{action} KEY`` ("down" / "up"), in this process where libxdo loads."""
        if self.xdo is not None:
            self.xdo.key(action, key)
        else:
            subprocess.run(["xdotool", f"key{action}", key], check=True, timeout=30)

    def down(self, key: str) -> None:
        n = len(self.received)
        self.send("down", key)
        self.presses += 1
        self._until("press", n)

    def up(self, key: str, step=None) -> None:
        n = len(self.received)
        self.send("up", key)
        self._until("release", n, step=step)

    def tap(self, key: str, hold_frames: int = 1) -> None:
        """Press, ``hold_frames`` frames drawn with the key down (what a key press does is done
        by then: the window acts on the press itself), release, and one frame after it."""
        self.down(key)
        self.frames(hold_frames)
        self.up(key)
        self.frames(1)

    def hold(self, key: str, frames: int, action: str) -> int:
        """Hold ``key`` for about ``frames`` frames; returns how many frames the window updated
        with ``action`` held (the controller moves the camera at the start of a frame)."""
        held = self.win.controller.held
        count = 0

        def step():
            nonlocal count
            count += action in held
            self.frames(1)

        self.down(key)
        for _ in range(frames):
            step()
        self.up(key, step=step)
        self.frames(1)  # nothing held any more: this frame does not move
        assert action not in held, (key, action, held)
        return count


def _screen(win) -> np.ndarray:
    w, h = win.wnd.buffer_size
    data = win.ctx.screen.read(viewport=(0, 0, w, h), components=3)
    return np.frombuffer(data, dtype=np.uint8).reshape(h, w, 3)[::-1].astype(int)


def _escape_and_report(win, keys, out: dict, log: bool = True) -> int:
    """End a key-driven run the way a user does: Esc typed as an X event must close the window;
    then the findings (and, with ``log``, what was typed and what pyglet delivered) go to
    stdout as the RESULT line the tests read."""
    keys.tap("Escape")
    out["escape_closes"] = bool(win.wnd.is_closing)
    if log:
        out["presses"] = keys.presses
        out["received"] = keys.received
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


def fly_keys(work: str) -> int:
    """Natura's fly map (docs/commands.md "Window controls"), every key typed as a real X event
    in the sky window: W A S D, Q / E, Shift, M (mouse look, then real pointer motion), Space,
    [ / ], R, P and F12, F1, Up / Down (no planet here: they must not move the camera), Esc."""
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    os.chdir(work)
    params = scene_params("sky", sets=["time.hour=10", "time.playing=false"])
    win = W.NaturaWindow("sky", params, get_scene("sky").new_camera(), (320, 180),
                         screenshot_dir="shots")
    keys = XKeys(win, "^Natura .* sky$")
    cam = win.scene.camera
    out: dict = {"speed": win.controller.speed, "dt": keys.dt}
    # F1 hides the panel (its pixels go), F1 shows it again; the rest runs without it
    with_panel = _screen(win)
    keys.tap("F1")
    out["f1_hides"] = not win.show_panel
    keys.frames(1)
    out["f1_panel_pixels"] = int((np.abs(with_panel - _screen(win)).sum(axis=2) > 30).sum())
    keys.tap("F1")
    out["f1_again_shows"] = win.show_panel
    keys.tap("F1")
    moves = {}
    for key, action in (("w", "forward"), ("s", "back"), ("a", "left"), ("d", "right"),
                        ("q", "down"), ("e", "up")):
        r, _, f = (np.array(v) for v in cam.basis())
        direction = {"forward": f, "back": -f, "left": -r, "right": r,
                     "down": np.array([0.0, -1.0, 0.0]), "up": np.array([0.0, 1.0, 0.0])}[action]
        p0 = np.array(cam.position)
        n = keys.hold(key, 8, action)
        d = np.array(cam.position) - p0
        along = float(np.dot(d, direction))
        moves[key] = {"frames": n, "along_m": along,
                      "across_m": float(np.linalg.norm(d - along * direction))}
    out["moves"] = moves
    # Shift: 4x faster while held
    keys.down("Shift_L")
    out["shift_fast_held"] = "fast" in win.controller.held
    p0 = np.array(cam.position)
    n = keys.hold("w", 8, "forward")
    keys.up("Shift_L")
    keys.frames(1)
    out["shift_w"] = {"frames": n, "along_m": float(np.dot(np.array(cam.position) - p0,
                                                            np.array(cam.basis()[2])))}
    # R: back to the scene's starting view
    keys.tap("r")
    h = win.home
    out["r_resets"] = {"position_error_m": float(np.linalg.norm(np.subtract(cam.position,
                                                                            h.position))),
                       "yaw_error": float(abs(cam.yaw - h.yaw)),
                       "pitch_error": float(abs(cam.pitch - h.pitch))}
    # M: mouse look without a button; real pointer motion turns the camera, then M stops it
    keys.pointer_home()
    keys.tap("m")
    out["m_mouse_look"] = win.mouse_look
    yaw0 = cam.yaw
    keys.move_pointer(40, 0)
    out["m_mouse_yaw"] = float((cam.yaw - yaw0 + 180) % 360 - 180)
    keys.tap("m")
    out["m_again_off"] = not win.mouse_look
    yaw0 = cam.yaw
    keys.move_pointer(40, 0)
    out["m_off_mouse_yaw"] = float((cam.yaw - yaw0 + 180) % 360 - 180)
    # Space: time runs, then stops again
    keys.tap("space")
    out["space_plays"] = params["time.playing"]
    hour0 = params["time.hour"]
    keys.frames(10)
    out["space_hour_advance"] = (params["time.hour"] - hour0) % 24.0
    keys.tap("space")
    out["space_pauses"] = not params["time.playing"]
    # [ / ]: 15 minutes a press
    hours = [params["time.hour"]]
    for key in ["bracketright"] * 4 + ["bracketleft"] * 6:
        keys.tap(key)
        hours.append(params["time.hour"])
    out["bracket_hours"] = hours
    # Up / Down: the planet's sun; here nothing to move, and the camera stays put
    p0, yaw0 = np.array(cam.position), cam.yaw
    keys.tap("Up", hold_frames=4)
    keys.tap("Down", hold_frames=4)
    out["up_down_camera_still"] = bool(np.allclose(cam.position, p0) and cam.yaw == yaw0)
    out["render_error"] = str(win.render_error or "")
    # P and F12: one new screenshot each
    keys.tap("p")
    keys.frames(1)
    keys.tap("F12")
    keys.frames(1)
    out["screenshots"] = [str(p) for p in win.screenshots]
    out["shot_files"] = sorted(str(p) for p in Path("shots").glob("*.png"))
    return _escape_and_report(win, keys, out)


def planet_keys(work: str) -> int:
    """The atmosphere thesis's whole map (spec/002 §4) in the planet window, typed as X events:
    W A S D, Space / Ctrl (both Ctrls), Q / E turn, R / F pitch, O mouse capture, Z turbo,
    + − * / on the main keyboard and the keypad, T, V, P, Up / Down, M, F12, F1, Esc."""
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    os.chdir(work)
    params = scene_params("planet", sets=["planet.method=lut", "planet.shadow_map_size=256",
                                          "planet.lut_height=32", "planet.lut_angle=32"])
    win = W.NaturaWindow("planet", params, get_scene("planet").new_camera(), (160, 90))
    win.show_panel = False
    keys = XKeys(win, "^Natura .* planet$")
    cam, ctl = win.scene.camera, win.controller
    out: dict = {"speed": ctl.speed, "turn_rate": ctl.turn_rate, "sun_rate": ctl.sun_rate,
                 "dt": keys.dt, "auto_sun_before": params["planet.auto_sun"]}
    keys.tap("m")
    out["auto_sun_after_m"] = params["planet.auto_sun"]
    keys.tap("m")
    out["auto_sun_after_m_m"] = params["planet.auto_sun"]
    elevation = params["planet.sun_elevation"]
    n = keys.hold("Up", 20, "sun_up")
    out["sun_up"] = {"frames": n, "deg": params["planet.sun_elevation"] - elevation}
    elevation = params["planet.sun_elevation"]
    n = keys.hold("Down", 10, "sun_down")
    out["sun_down"] = {"frames": n, "deg": params["planet.sun_elevation"] - elevation}
    moves = {}
    for key, action in (("w", "forward"), ("s", "back"), ("a", "left"), ("d", "right"),
                        ("space", "up"), ("Control_L", "down"), ("Control_R", "down")):
        r, _, f = (np.array(v) for v in cam.basis())
        direction = {"forward": f, "back": -f, "left": -r, "right": r,
                     "down": np.array([0.0, -1.0, 0.0]), "up": np.array([0.0, 1.0, 0.0])}[action]
        p0 = np.array(cam.position)
        n = keys.hold(key, 6, action)
        along = float(np.dot(np.array(cam.position) - p0, direction))
        moves[key] = {"frames": n, "along_m": along}
    out["moves"] = moves
    turns = {}
    for key, action in (("q", "turn_left"), ("e", "turn_right"), ("r", "pitch_up"),
                        ("f", "pitch_down")):
        yaw0, pitch0 = cam.yaw, cam.pitch
        n = keys.hold(key, 6, action)
        turns[key] = {"frames": n, "yaw": float((cam.yaw - yaw0 + 180) % 360 - 180),
                      "pitch": float(cam.pitch - pitch0)}
    out["turns"] = turns
    keys.tap("o")
    out["o_mouse_look"] = win.mouse_look
    keys.tap("o")
    out["o_again_off"] = not win.mouse_look
    # Z turbo: W now moves at the turbo speed
    keys.tap("z")
    out["z_turbo"] = ctl.turbo
    p0 = np.array(cam.position)
    n = keys.hold("w", 3, "forward")
    out["turbo_w"] = {"frames": n, "m": float(np.linalg.norm(np.array(cam.position) - p0)),
                      "turbo_speed": ctl.turbo_speed}
    keys.tap("z")
    out["z_again_off"] = not ctl.turbo
    speeds = [ctl.turbo_speed]
    for key in ("plus", "minus", "asterisk", "slash", "KP_Add", "KP_Subtract", "KP_Multiply",
                "KP_Divide"):
        keys.tap(key)
        speeds.append(ctl.turbo_speed)
    out["turbo_speeds"] = speeds
    # T: camera controls off (W does nothing), T again: on
    keys.tap("t")
    out["t_controls_off"] = not ctl.controls_enabled
    p0 = np.array(cam.position)
    keys.down("w")
    keys.frames(4)
    keys.up("w")
    out["t_off_moved_m"] = float(np.linalg.norm(np.array(cam.position) - p0))
    keys.tap("t")
    out["t_controls_on"] = ctl.controls_enabled
    win.messages.append("-")
    keys.tap("v")
    out["v_message"] = win.messages[-1]
    win.messages.append("-")
    keys.tap("p")
    out["p_message"] = win.messages[-1]
    keys.tap("F1")
    out["f1_shows"] = win.show_panel
    keys.tap("F1")
    out["f1_hides"] = not win.show_panel
    keys.tap("F12")
    keys.frames(1)
    out["screenshots"] = [str(p) for p in win.screenshots]
    out["render_error"] = str(win.render_error or "")
    return _escape_and_report(win, keys, out)


def cli_escape(work: str) -> int:
    """``natura window sky`` as a user starts it; Esc typed into it ends the process."""
    os.chdir(work)
    root = Path(__file__).resolve().parents[2]
    env = {**os.environ, "PYTHONPATH": str(root)}
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "app.cli", "window", "sky", "--size",
                             "160x90"], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    out: dict = {}
    try:
        # --onlyvisible: a window found before it is mapped cannot take the focus (BadMatch)
        found = subprocess.run(["xdotool", "search", "--sync", "--onlyvisible", "--name",
                                "^Natura .* sky$"],
                               capture_output=True, text=True, timeout=60).stdout.split()
        subprocess.run(["xdotool", "windowfocus", "--sync", found[0]], check=True, timeout=30)
        out["window_seen_s"] = time.perf_counter() - t0
        time.sleep(0.5)  # frames running
        out["running_before_esc"] = proc.poll() is None
        t1 = time.perf_counter()
        subprocess.run(["xdotool", "key", "Escape"], check=True, timeout=30)
        out["returncode"] = proc.wait(timeout=30)
        out["exit_after_esc_s"] = time.perf_counter() - t1
    finally:
        if proc.poll() is None:
            proc.kill()
        stdout, stderr = proc.communicate()
    out["stderr"] = stderr[-2000:]
    print("RESULT " + json.dumps(out))
    return 0


def _spy(module, name: str, record: list, with_rect: bool = False):
    """Wrap ``module.name`` so each call records its first argument (and, with ``with_rect``,
    the drawn item's size and the window's width). Returns a function that undoes it."""
    original = getattr(module, name)

    def spy(*args, **kw):
        result = original(*args, **kw)
        entry = {"text": str(args[1] if name == "text_colored" else args[0])}
        if with_rect:
            size = module.get_item_rect_size()
            entry.update(width=float(size.x), height=float(size.y),
                         window_width=float(module.get_window_width()),
                         line_height=float(module.get_text_line_height()))
        record.append(entry)
        return result

    setattr(module, name, spy)
    return lambda: setattr(module, name, original)


def robustness(work: str) -> int:
    """What must not crash the window: screenshot, preset and keyframe folders that are files
    or cannot be written, a name taken between the check and the link, a shader typo (printed
    once, wrapped in the panel), a shader library or a scene that raises."""
    from app import DEFAULT_SHADER_ROOT
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    work_dir = Path(work)
    shaders = work_dir / "glsl"
    shutil.copytree(DEFAULT_SHADER_ROOT, shaders)
    os.chdir(work_dir)
    Path("screenshots").write_text("a file where the folder would be")
    Path("presets").write_text("a file where the folder would be")
    params = scene_params("sky", shader_root=shaders, sets=["time.hour=10"])
    win = W.NaturaWindow("sky", params, get_scene("sky").new_camera(), (640, 360), shaders)
    keys = XKeys(win, "^Natura .* sky$")
    out: dict = {}

    def outcome(name, *, made=()):
        out[name] = {"messages": list(win.messages)[-1:], "closing": bool(win.wnd.is_closing),
                     "made": [str(p) for p in made]}
        keys.frames(2)
        out[name]["frames_after"] = not win.wnd.is_closing

    keys.tap("p")  # screenshots/ is a file
    keys.frames(1)
    outcome("shot_folder_is_file", made=win.screenshots)
    out["shot_file_kept"] = Path("screenshots").read_text().startswith("a file")
    win.screenshot_dir = Path("/sys/natura-shots")  # a folder that cannot be made
    keys.tap("F12")
    keys.frames(1)
    outcome("shot_folder_cannot_be_made", made=win.screenshots)
    win.screenshot_dir = Path("/sys")  # a folder that exists but takes no files (even for root)
    keys.tap("p")
    keys.frames(1)
    outcome("shot_folder_read_only", made=win.screenshots)
    # a name race: the free name is taken between next_free_path and the link
    win.screenshot_dir = Path("shots")
    Path("shots").mkdir()
    taken = Path("shots") / "sky-0001.png"
    taken.write_bytes(b"someone else's file")
    calls = []
    real_next = W.next_free_path

    def racing_next(folder, stem, suffix):
        calls.append(stem)
        return taken if len(calls) == 1 else real_next(folder, stem, suffix)

    W.next_free_path = racing_next
    try:
        keys.tap("p")
        keys.frames(1)
    finally:
        W.next_free_path = real_next
    out["race"] = {"calls": len(calls), "screenshots": [str(p) for p in win.screenshots],
                   "taken_kept": taken.read_bytes() == b"someone else's file",
                   "messages": list(win.messages)[-1:]}
    # presets: a file in the way, a folder that takes no files, then a good one
    outcome("preset_folder_is_file", made=[p for p in [win.save_preset()] if p])
    out["preset_file_kept"] = Path("presets").read_text().startswith("a file")
    win.preset_dir = Path("/sys")
    outcome("preset_folder_read_only", made=[p for p in [win.save_preset()] if p])
    win.preset_dir = Path("my-presets")
    outcome("preset_saved", made=[p for p in [win.save_preset()] if p])
    keyframes = win.scene.effect("sky").panel_items()[0]
    win.keyframes_dir = Path("/sys")
    outcome("keyframes_read_only", made=[p for p in [win.save_keyframes(keyframes)] if p])
    win.keyframes_dir = Path(".")
    outcome("keyframes_saved", made=[p for p in [win.save_keyframes(keyframes)] if p])
    # a shader typo: printed to the terminal once, drawn whole (wrapped) in the panel
    frag = shaders / "sky" / "sky.frag"
    good = frag.read_text()
    atomic_write(frag, good.replace("fragColor = vec4(",
                                    "fragColor = vec4(an_undeclared_name_long_enough_to_wrap + "))
    drawn: list = []
    wraps: list = []
    undo = [_spy(win.imgui, "text_colored", drawn, with_rect=True),
            _spy(win.imgui, "push_text_wrap_pos", wraps)]
    try:
        for _ in range(3):  # three polls with the error standing
            time.sleep(W.POLL_SECONDS + 0.05)
            keys.frames(2)
    finally:
        for u in undo:
            u()
    errors = [str(e) for e in win.session.gpu.shaders.errors()]
    out["shader"] = {"errors": errors, "wrap_pushed": len(wraps),
                     "drawn": list({d["text"]: d for d in drawn if d["text"] in errors}.values())}
    atomic_write(frag, good)
    time.sleep(W.POLL_SECONDS + 0.05)
    keys.frames(2)
    out["shader"]["errors_after_fix"] = [str(e) for e in win.session.gpu.shaders.errors()]
    # the shader library raises: a message, the window keeps going
    library = win.session.gpu.shaders

    def broken_poll():
        raise RuntimeError("the shader library broke")

    library.poll = broken_poll
    try:
        for _ in range(2):
            time.sleep(W.POLL_SECONDS + 0.05)
            keys.frames(2)
        out["poll_error"] = {"error": win.poll_error, "closing": bool(win.wnd.is_closing),
                             "messages": list(win.messages)[-1:]}
    finally:
        del library.poll
    time.sleep(W.POLL_SECONDS + 0.05)
    keys.frames(2)
    out["poll_error"]["after"] = win.poll_error
    # the scene raises while building its frame: shown, not a crash
    scene = win.scene

    def broken_frame(*args, **kw):
        raise RuntimeError("the scene broke")

    scene.frame = broken_frame
    try:
        keys.frames(3)
        out["render_error"] = {"error": win.render_error, "closing": bool(win.wnd.is_closing)}
    finally:
        del scene.frame
    keys.frames(2)
    out["render_error"]["after"] = win.render_error
    return _escape_and_report(win, keys, out, log=False)


def focus_loss(work: str) -> int:
    """W held in the sky window, then the keyboard taken by another window (a real X focus
    change, xdotool windowfocus): the key's release never reaches the window, so it must let go
    of what was held when it loses the focus, and the camera stop."""
    import pyglet

    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    os.chdir(work)
    params = scene_params("sky", sets=["time.hour=10", "time.playing=false"])
    win = W.NaturaWindow("sky", params, get_scene("sky").new_camera(), (320, 180))
    other = pyglet.window.Window(64, 64, caption="natura focus taker")
    win.wnd._window.switch_to()  # pyglet made the new window's context current
    keys = XKeys(win, "^Natura .* sky$")  # the keyboard to the sky window
    cam = win.scene.camera
    out: dict = {}
    p0 = np.array(cam.position)
    keys.down("w")
    keys.frames(4)
    out["held_before"] = sorted(win.controller.held)
    p1 = np.array(cam.position)
    out["moved_while_held_m"] = float(np.linalg.norm(p1 - p0))
    found = subprocess.run(["xdotool", "search", "--sync", "--name", "^natura focus taker$"],
                           capture_output=True, text=True, timeout=30).stdout.split()
    subprocess.run(["xdotool", "windowfocus", "--sync", found[0]], check=True, timeout=30)
    out["let_go"] = keys.dispatch(lambda: not win.controller.held, wait_s=5.0)
    out["held_after"] = sorted(win.controller.held)
    p2 = np.array(cam.position)
    keys.frames(8)
    out["moved_after_m"] = float(np.linalg.norm(np.array(cam.position) - p2))
    keys.send("up", "w")  # to the other window now
    other.close()
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


def sky_keyframes(work: str) -> int:
    """The sky offers its keyframes to the panel (the window names no effect): the panel's
    "Sky keyframes" header is drawn in the sky scene and not in the materials scene."""
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    out = {}
    for scene in ("sky", "materials"):
        win = W.NaturaWindow(scene, scene_params(scene), get_scene(scene).new_camera(), (640, 480))
        headers = []
        original = win.imgui.collapsing_header

        def spy(label, *args, **kw):
            headers.append(label)
            return original(label, *args, **kw)

        win.imgui.collapsing_header = spy
        try:
            for _ in range(2):
                win.wnd.clear()
                win.frame(1 / 60)
                win.wnd.swap_buffers()
        finally:
            win.imgui.collapsing_header = original
        out[scene] = sorted(set(headers))
        win.close()
    print("RESULT " + json.dumps(out))
    return 0


def ocean_models(work: str) -> int:
    """Open the ocean and switch sine → Gerstner → FFT with the keys 1 / 2 / 3, typed as X
    events: each model must draw a different sea, with no render error."""
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    params = scene_params("ocean", sets=["ocean.fft_size=64", "ocean.mesh_segments=96",
                                         "time.hour=17"])
    win = W.NaturaWindow("ocean", params, get_scene("ocean").new_camera(), (320, 180))
    w, h = win.wnd.buffer_size
    win.show_panel = False
    keys = XKeys(win, "^Natura .* ocean$", dt=1 / 30)
    shots = {}
    for key, model in (("1", "sine"), ("2", "gerstner"), ("3", "fft")):
        keys.tap(key)  # the key map turns 1/2/3 into ocean.model
        assert win.params["ocean.model"] == model, (key, win.params["ocean.model"])
        keys.frames(3)
        data = win.ctx.screen.read(viewport=(0, 0, w, h), components=3)
        shots[model] = np.frombuffer(data, dtype=np.uint8).reshape(h, w, 3).astype(int)
    out = {"render_error": str(win.render_error or ""),
           "diff_sine_gerstner": float(np.abs(shots["sine"] - shots["gerstner"]).mean()),
           "diff_gerstner_fft": float(np.abs(shots["gerstner"] - shots["fft"]).mean()),
           "fft_sim": win.scene.effect("ocean").sea.sim is not None}
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


#: the maritime scene kept small for the window tests: tiny cloud bakes and FFT, no spin-up, a
#: short cloud march (8 view steps, 1 light step: the march is most of the frame at 320x180 on
#: llvmpipe; the window's size is the HUD's, 290 px wide)
MARITIME_SMALL = ["clouds_b.volume_resolution=16", "clouds_b.detail_resolution=8",
                  "clouds_b.gradient_resolution=16", "ocean.fft_size=64",
                  "clouds_b.max_steps=8", "clouds_b.num_steps_light=1", "ocean.mesh_segments=64",
                  "boat.spin_up=0", "time.hour=10", "time.playing=false"]


def maritime_keys(work: str) -> int:
    """The maritime map (spec/000 §2) typed as X events in the maritime window: Right / Left
    (helm), Up (throttle), X (sails), H (centre the helm), C (chase / free camera), Space (UI
    mode / free navigation), 4 (storm), T (time), Esc (the pause menu: Resume clicked with the
    real pointer, then Esc, Esc quits)."""
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    os.chdir(work)
    params = scene_params("maritime", sets=MARITIME_SMALL)
    win = W.NaturaWindow("maritime", params, get_scene("maritime").new_camera(), (320, 180))
    win.show_panel = False
    begun: list = []
    wrapped: list = []
    undo = [_spy(win.imgui, "begin", begun), _spy(win.imgui, "text_wrapped", wrapped)]
    t0 = time.perf_counter()
    keys = XKeys(win, "^Natura .* maritime$")
    out: dict = {"dt": keys.dt, "first_frames_s": time.perf_counter() - t0,
                 "hud_windows": sorted({b["text"] for b in begun})}

    def value(name):
        return params[name]

    helm0 = value("boat.helm")
    n = keys.hold("Right", 20, "hold:boat.helm=0.8")
    out["right"] = {"frames": n, "helm0": helm0, "helm": value("boat.helm")}
    helm0 = value("boat.helm")
    n = keys.hold("Left", 10, "hold:boat.helm=-0.8")
    out["left"] = {"frames": n, "helm0": helm0, "helm": value("boat.helm")}
    keys.tap("h")
    out["h_centres"] = value("boat.helm")
    throttle0 = value("boat.throttle")
    n = keys.hold("Up", 12, "hold:boat.throttle=0.5")
    out["up"] = {"frames": n, "throttle0": throttle0, "throttle": value("boat.throttle")}
    sails0 = value("boat.sails")
    n = keys.hold("x", 10, "hold:boat.sails=0.4")
    out["x"] = {"frames": n, "sails0": sails0, "sails": value("boat.sails")}
    throttle0 = value("boat.throttle")
    n = keys.hold("Down", 6, "hold:boat.throttle=-0.5")
    out["down"] = {"frames": n, "throttle0": throttle0, "throttle": value("boat.throttle")}
    sails0 = value("boat.sails")
    n = keys.hold("z", 6, "hold:boat.sails=-0.4")
    out["z"] = {"frames": n, "sails0": sails0, "sails": value("boat.sails")}
    out["held_after"] = sorted(win.controller.held)
    # C: the free camera, which W then flies; C again: the chase camera
    out["camera0"] = value("maritime.camera")
    keys.tap("c")
    out["c_camera"] = value("maritime.camera")
    cam = win.scene.camera
    p0 = np.array(cam.position)
    n = keys.hold("w", 6, "forward")
    out["free_w"] = {"frames": n, "m": float(np.dot(np.array(cam.position) - p0, cam.forward())),
                     "speed": win.controller.speed}
    keys.tap("c")
    out["cc_camera"] = value("maritime.camera")
    # Space: free navigation (mouse look, pointer captured, the HUD passive), Space: UI mode
    out["ui_mode0"] = win.ui_mode
    wrapped.clear()
    keys.tap("space")
    out["space"] = {"ui_mode": win.ui_mode, "mouse_look": win.mouse_look,
                    "exclusive": bool(win.wnd.mouse_exclusivity),
                    "mode_line": [w["text"] for w in wrapped if "Space" in w["text"]][-1]}
    wrapped.clear()
    keys.tap("space")
    out["space_again"] = {"ui_mode": win.ui_mode, "mouse_look": win.mouse_look,
                          "exclusive": bool(win.wnd.mouse_exclusivity),
                          "mode_line": [w["text"] for w in wrapped
                                                if "Space" in w["text"]][-1]}
    # 1 2 3 4: the weather states, each with its wind (the scene applies it on its next frame:
    # a tap draws two after the press)
    out["weather0"] = value("maritime.weather")
    out["weathers"] = []
    for key in ("1", "2", "3"):
        keys.tap(key)
        out["weathers"].append((value("maritime.weather"), value("wind.speed")))
    keys.tap("4")
    out["storm"] = {"weather": value("maritime.weather"), "wind_speed": value("wind.speed"),
                    "hud_weather": win.hud_state.weather if win.hud_state else None,
                    "hud_wind_speed": win.hud_state.wind_speed if win.hud_state else None}
    # T: time plays; Esc: the pause menu stops it; Resume (clicked) restores it
    keys.tap("t")
    out["t_playing"] = value("time.playing")
    begun.clear()
    keys.tap("Escape")
    out["esc"] = {"paused": win.paused, "playing": value("time.playing"),
                  "closing": bool(win.wnd.is_closing),
                  "windows": sorted({b["text"] for b in begun})}
    hour = value("time.hour")
    keys.frames(5)
    out["paused_hour_still"] = value("time.hour") == hour
    x0, y0, x1, y1 = win.hud_rects["Resume"]
    subprocess.run(["xdotool", "mousemove", "--window", keys.id, str(int((x0 + x1) / 2)),
                    str(int((y0 + y1) / 2))], check=True, timeout=30)
    keys.frames(3)
    # a press and a release a few frames apart, as a hand clicks (the renderer keeps only the
    # button's state, so a press and release within one frame would not reach ImGui)
    subprocess.run(["xdotool", "mousedown", "1"], check=True, timeout=30)
    keys.frames(3)
    subprocess.run(["xdotool", "mouseup", "1"], check=True, timeout=30)
    for _ in range(60):
        keys.frames(1)
        if not win.paused:
            break
    out["resume"] = {"paused": win.paused, "playing": value("time.playing"),
                     "ui_mode": win.ui_mode}
    # a frame before the next key, as a hand takes one: ImGui lets go of the keyboard the frame
    # after the menu's window (focused by the click) is gone; an Esc within that frame is ImGui's
    keys.frames(1)
    keys.tap("Escape")
    out["esc_again_paused"] = win.paused
    keys.tap("Escape")
    out["esc_esc_closes"] = bool(win.wnd.is_closing)
    out["render_error"] = str(win.render_error or "")
    out["presses"] = keys.presses
    for u in undo:
        u()
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


def _inspector_drawn(win, keys) -> dict:
    """Show the panel for two frames and list what its inspectors drew: the collapsing headers,
    the thumbnails (each drawn once a frame) and the buttons."""
    headers: list = []
    images: list = []
    buttons: list = []
    undo = [_spy(win.imgui, "collapsing_header", headers), _spy(win.imgui, "image", images),
            _spy(win.imgui, "button", buttons)]
    win.show_panel = True
    keys.frames(2)
    for u in undo:
        u()
    return {"headers": sorted({h["text"] for h in headers}), "images": len(images) // 2,
            "buttons": sorted({b["text"] for b in buttons})}


def shading_keys(work: str) -> int:
    """The shading lab's map (spec/003 §2.1–2.3, §2.12) typed as X events in its window: 1 / 2 /
    3 the lighting model, T four times through the toon modes back to none, G Gouraud, B the rim,
    V the parallax methods, O the objects; each key's parameter and the image it gives."""
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    os.chdir(work)
    params = scene_params("shading", sets=["shading.turntable=0"])
    win = W.NaturaWindow("shading", params, get_scene("shading").new_camera(), (320, 180))
    win.show_panel = False
    keys = XKeys(win, "^Natura .* shading$")
    out: dict = {"dt": keys.dt}

    def image_sum() -> float:  # of the last frame: a tap draws two with the new value
        return float(win.target.read()[..., :3].sum()) if win.target is not None else 0.0

    out["model"] = []
    for key in ("1", "2", "3"):
        keys.tap(key)
        out["model"].append((params["shading.lighting_model"], image_sum()))
    out["toon"] = []
    for _ in range(4):
        keys.tap("t")
        out["toon"].append((params["shading.toon"], image_sum()))
    keys.tap("g")
    out["gouraud"] = params["shading.gouraud"]
    keys.tap("b")
    out["rim"] = params["shading.rim"]
    out["parallax"] = []
    for _ in range(5):
        keys.tap("v")
        out["parallax"].append(params["shading.parallax_mode"])
    out["objects"] = []
    for _ in range(3):
        keys.tap("o")
        out["objects"].append(params["shading.object"])
    out["contours"] = []
    for _ in range(3):
        keys.tap("k")
        out["contours"].append((params["shading.contour"], image_sum()))
    keys.tap("l")
    out["bloom"] = params["shading.bloom"]
    # the panel's material inspector: its header, a popup button each, the maps' thumbnails
    out["inspector"] = _inspector_drawn(win, keys)
    out["render_error"] = str(win.render_error or "")
    keys.tap("Escape")
    out["closing"] = bool(win.wnd.is_closing)
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


#: the surfaces lab's keys the window test types: (key, surfaces.NAME it cycles, taps), and the
#: settings it starts from (small maps: the frame at 160x90 on llvmpipe)
SURFACES_LAB_KEYS = (("t", "transparency", 3), ("g", "reflection", 5),
                     ("k", "specular_model", 2), ("f", "fresnel", 2), ("h", "shadow_filter", 5),
                     ("j", "shadow_cascades", 3), ("x", "failure", 2), ("n", "msaa", 2),
                     ("v", "debug", 2))
SURFACES_SMALL = ["surfaces.probe_size=64", "surfaces.shadow_map_size=512", "surfaces.msaa=0"]
#: the village's keys the window test types once each (the camera through its three modes)
VILLAGE_LAB_KEYS = (("c", "village.camera", 3), ("g", "grass.method", 1), ("f", "fog.mode", 1),
                    ("h", "fog.height", 1), ("t", "village.toon", 1),
                    ("o", "toon_water.type", 1), ("l", "village.lamps_auto", 1))


def surfaces_keys(work: str) -> int:
    """The surfaces lab's map (spec/003 §2.4–2.8) typed as X events in its window: T the
    transparency methods, G the reflection lookups, K the specular model, F the Fresnel, H the
    shadow filters, J the cascades, X the failures, N MSAA, V the debug views; each key's
    parameter and its image."""
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    os.chdir(work)
    # small, MSAA off to start (N turns it on, then off): the lab's opaque pass is ~40 ms a
    # frame at 320x180 on llvmpipe, MSAA adds half again
    params = scene_params("surfaces", sets=SURFACES_SMALL)
    win = W.NaturaWindow("surfaces", params, get_scene("surfaces").new_camera(), (160, 90))
    win.show_panel = False
    keys = XKeys(win, "^Natura .* surfaces$")
    out: dict = {"dt": keys.dt}

    def image_sum() -> float:  # of the last frame: a tap draws two with the new value
        return float(win.target.read()[..., :3].sum()) if win.target is not None else 0.0

    keys.frames(1)
    for key, name, times in SURFACES_LAB_KEYS:
        out[name] = []
        for _ in range(times):
            keys.tap(key)
            out[name].append((params[f"surfaces.{name}"], image_sum()))
    # the panel's inspector: its header, a popup button per thesis section, the maps
    out["inspector"] = _inspector_drawn(win, keys)
    out["render_error"] = str(win.render_error or "")
    keys.tap("Escape")
    out["closing"] = bool(win.wnd.is_closing)
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


#: a light village for the window runs: a coarse island, few blades, small shadow maps
VILLAGE_SMALL = ["village.resolution=65", "village.shadow_map_size=512", "grass.blades=3000",
                 "village.msaa=0"]


def village_keys(work: str) -> int:
    """The village's map (spec/003 §1, §2.9–2.11, §2.15) typed as X events in its window: W
    walks the hero in the third person, C the cameras, G the grass methods, F the fog modes, H
    the height fog, T the toon modes, O the water types, L the lamps' clock, V the VR mode (the
    window then shows two eyes side by side); each key's parameter and its image."""
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    os.chdir(work)
    params = scene_params("village", sets=VILLAGE_SMALL)
    win = W.NaturaWindow("village", params, get_scene("village").new_camera(), (160, 90))
    win.show_panel = False
    keys = XKeys(win, "^Natura .* village$")
    out: dict = {"dt": keys.dt}

    def image():  # of the last frame: a tap draws two with the new value
        return win.target.read()[..., :3]

    keys.frames(1)
    hero0 = (params["village.hero_x"], params["village.hero_z"])
    n = keys.hold("w", 10, "forward")
    out["walk"] = {"frames": n, "from": hero0,
                   "to": (params["village.hero_x"], params["village.hero_z"]),
                   "camera": params["village.camera"]}
    # each key once from where the scene starts (its parameter steps, the image changes); the
    # camera through its three modes back to the third person
    for key, name, times in VILLAGE_LAB_KEYS:
        out[name] = [(params[name], float(image().sum()))]
        for _ in range(times):
            keys.tap(key)
            out[name].append((params[name], float(image().sum())))
    keys.tap("v")
    img = image()
    half = img.shape[1] // 2
    out["vr"] = {"enabled": params["vr.enabled"],
                 "halves_differ": float(np.abs(img[:, :half] - img[:, half:2 * half]).max())}
    keys.tap("v")
    out["vr_off"] = params["vr.enabled"]
    out["inspector"] = _inspector_drawn(win, keys)
    out["render_error"] = str(win.render_error or "")
    keys.tap("Escape")
    out["closing"] = bool(win.wnd.is_closing)
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


def _sharpness(image: np.ndarray, mask: np.ndarray) -> float:
    """The mean absolute difference between neighbouring pixels (both axes) inside ``mask``:
    text and edges drawn at the window's resolution keep it; an enlarged image loses it."""
    lum = image.astype(float).mean(axis=2)
    dx = np.abs(np.diff(lum, axis=1))[:-1, :]
    dy = np.abs(np.diff(lum, axis=0))[:, :-1]
    m = mask[:-1, :-1] & mask[1:, :-1] & mask[:-1, 1:]
    return float((dx + dy)[m].mean()) if m.any() else 0.0


def _rect_mask(shape, rect, shrink: int = 2) -> np.ndarray:
    """A mask of the screen rectangle ``rect`` (x0, y0, x1, y1), ``shrink`` pixels inside."""
    mask = np.zeros(shape[:2], dtype=bool)
    x0, y0, x1, y1 = (int(round(v)) for v in rect)
    mask[max(0, y0 + shrink):max(0, y1 - shrink), max(0, x0 + shrink):max(0, x1 - shrink)] = True
    return mask


def dynamic_resolution(work: str) -> int:
    """Dynamic resolution in the maritime window (640x360; its HUD and the panel on): with a
    1 ms budget the scale drops (the frames are fed 1/60 s, so the outcome does not depend on
    the machine's speed), the scene's target shrinks and ImGui still draws at the window's size;
    the scale pinned at 1 and at 0.5; the panel and the HUD as sharp at 0.5 as at 1 while the
    scene is softer; a screenshot at 0.5 has the window's size; the panel's fps and scale
    line."""
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W
    from app.ui.resolution import LEVELS

    os.chdir(work)
    params = scene_params("maritime", sets=[*MARITIME_SMALL, "output.frame_budget_ms=1"])
    win = W.NaturaWindow("maritime", params, get_scene("maritime").new_camera(), (640, 360),
                         screenshot_dir="shots")
    texts: list = []
    undo = _spy(win.imgui, "text", texts)
    out: dict = {"window": list(win.window_size), "levels": list(LEVELS)}

    def frames(n, dt=1 / 60):
        for _ in range(n):
            win.wnd.clear()
            win.frame(dt)
            win.wnd.swap_buffers()

    io = win.imgui.get_io()
    auto = []
    for _ in range(12):  # auto, 1 ms budget, each frame "took" 16.7 ms
        frames(1)
        auto.append({"scale": win.resolution.scale, "target": list(win.target.size),
                     "imgui": [float(io.display_size.x), float(io.display_size.y)],
                     "imgui_fb_scale": [float(io.display_framebuffer_scale.x),
                                        float(io.display_framebuffer_scale.y)]})
    out["auto"] = auto
    out["auto_changes"] = [list(c) for c in win.resolution.changes]
    out["scale_lines"] = [t["text"] for t in texts if t["text"].startswith("scale ")][-1:]
    out["fps_lines"] = [t["text"] for t in texts if "fps" in t["text"]][-1:]

    def shot(scale, panel):  # the scale pinned, time stood still: the same scene each time
        params.set("output.scale", scale)
        win.show_panel = panel
        frames(3, dt=0.0)
        return _screen(win), list(win.target.size), dict(win.hud_rects)

    full_panel, size_full, _ = shot(1.0, True)
    half_panel, size_half, _ = shot(0.5, True)
    full_bare, _, hud_full = shot(1.0, False)
    half_bare, _, hud_half = shot(0.5, False)
    out["pinned_targets"] = {"1": size_full, "0.5": size_half}
    from PIL import Image

    for name, image in (("full-panel", full_panel), ("half-panel", half_panel),
                        ("full-bare", full_bare), ("half-bare", half_bare)):
        Image.fromarray(image.astype(np.uint8)).save(f"{name}.png")  # to look at on a failure
    win.show_panel = True
    texts.clear()
    frames(8)  # pinned at 0.5 with the 1 ms budget: it stays
    out["pinned_half_after"] = win.resolution.scale
    out["pinned_line"] = [t["text"] for t in texts if t["text"].startswith("scale ")][-1:]
    params.set("output.scale", 1.0)
    frames(8)
    out["pinned_full_after"] = {"scale": win.resolution.scale, "target": list(win.target.size)}
    # where the panel draws: what changes when it is shown (at full scale both times)
    panel = np.abs(full_panel - full_bare).sum(axis=2) > 30
    hud = np.zeros(panel.shape, dtype=bool)
    for key in ("ship", "weather"):
        if key in hud_full:
            hud |= _rect_mask(panel.shape, hud_full[key])
    scene = np.ones(panel.shape, dtype=bool)  # in the shots without the panel
    for key in ("ship", "weather"):
        if key in hud_full:
            scene &= ~_rect_mask(panel.shape, hud_full[key], shrink=-6)
    out["hud_rects_same"] = hud_full == hud_half
    out["mask_pixels"] = {"panel": int(panel.sum()), "hud": int(hud.sum()),
                          "scene": int(scene.sum())}
    out["sharpness"] = {
        "panel": [_sharpness(full_panel, panel), _sharpness(half_panel, panel)],
        "hud": [_sharpness(full_bare, hud), _sharpness(half_bare, hud)],
        "scene": [_sharpness(full_bare, scene), _sharpness(half_bare, scene)],
    }
    out["panel_diff"] = float(np.abs(full_panel - half_panel)[panel].mean())
    # a screenshot at scale 0.5 is rendered at the window's size
    params.set("output.scale", 0.5)
    frames(2)
    win.screenshot_requested = True
    frames(1)
    out["screenshots"] = [list(Image.open(p).size) for p in win.screenshots]
    frames(2)
    out["after_screenshot_target"] = list(win.target.size)
    # the panel's widget of output.scale: "auto", and a slider over [0.5, 1] once pinned
    from app.ui import panel as P

    imgui = win.imgui
    widgets: list = []
    spies = [_spy(imgui, "checkbox", widgets), _spy(imgui, "slider_float", widgets)]
    for value in ("auto", "0.75"):
        params.set("output.scale", value)
        imgui.new_frame()
        imgui.begin("scale widget")
        P.param_widget(params, params.spec("output.scale"))
        imgui.end()
        imgui.render()
    for u in spies:
        u()
    out["scale_widgets"] = [w["text"] for w in widgets]
    out["render_error"] = str(win.render_error or "")
    undo()
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


def _read_lines(stream, lines: list) -> None:
    for line in iter(stream.readline, ""):
        lines.append(line)


def maritime_cli_escape(work: str) -> int:
    """``natura window maritime`` as a user starts it: the first Esc opens the pause menu (the
    process keeps running), the second quits it with exit status 0.

    The first Esc waits for the first frames: a key typed before them is lost, and so is every
    key after it (seen under Xvfb with pyglet 2.1). The menu's "paused" line on stdout
    (unbuffered) then says the Esc was handled, instead of a fixed wait."""
    import threading

    os.chdir(work)
    root = Path(__file__).resolve().parents[2]
    env = {**os.environ, "PYTHONPATH": str(root), "PYTHONUNBUFFERED": "1"}
    sets = [arg for s in MARITIME_SMALL for arg in ("--set", s)]
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "app.cli", "window", "maritime", "--size",
                             "320x180", *sets], env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    out: dict = {}
    lines: list[str] = []
    errors: list[str] = []
    readers = [threading.Thread(target=_read_lines, args=(stream, into), daemon=True)
               for stream, into in ((proc.stdout, lines), (proc.stderr, errors))]
    for reader in readers:
        reader.start()

    def wait_for(text: str, into: list, timeout: float = 60.0) -> None:
        deadline = time.perf_counter() + timeout
        while not any(text in line for line in into) and proc.poll() is None:
            if time.perf_counter() > deadline:
                break
            time.sleep(0.02)

    try:
        # --onlyvisible: a window found before it is mapped cannot take the focus (BadMatch)
        found = subprocess.run(["xdotool", "search", "--sync", "--onlyvisible", "--name",
                                "^Natura .* maritime$"],
                               capture_output=True, text=True, timeout=60).stdout.split()
        subprocess.run(["xdotool", "windowfocus", "--sync", found[0]], check=True, timeout=30)
        out["window_seen_s"] = time.perf_counter() - t0
        wait_for("natura: context:", errors)
        time.sleep(2.0)  # the first frames (the cloud bakes, the boat) run
        subprocess.run(["xdotool", "key", "Escape"], check=True, timeout=30)
        wait_for("paused", lines)
        out["first_esc_handled_s"] = time.perf_counter() - t0
        time.sleep(0.3)  # frames go on behind the menu: the first Esc did not quit
        out["running_after_first_esc"] = proc.poll() is None
        t1 = time.perf_counter()
        subprocess.run(["xdotool", "key", "Escape"], check=True, timeout=30)
        out["returncode"] = proc.wait(timeout=30)
        out["exit_after_second_esc_s"] = time.perf_counter() - t1
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.wait()
        for reader in readers:
            reader.join(10)
    out["stdout"] = "".join(lines)[-2000:]
    out["stderr"] = "".join(errors)[-2000:]
    print("RESULT " + json.dumps(out))
    return 0


if __name__ == "__main__":
    runs = {"bake-progress": bake_progress, "ocean-models": ocean_models,
            "planet-keys": planet_keys, "sky-keyframes": sky_keyframes, "fly-keys": fly_keys,
            "cli-escape": cli_escape, "robustness": robustness,
            "maritime-keys": maritime_keys, "maritime-cli-escape": maritime_cli_escape,
            "shading-keys": shading_keys, "surfaces-keys": surfaces_keys,
            "village-keys": village_keys, "dynamic-resolution": dynamic_resolution,
            "focus-loss": focus_loss}
    sys.exit(runs.get(sys.argv[2] if len(sys.argv) > 2 else "", main)(sys.argv[1]))

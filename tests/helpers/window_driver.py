"""Drives a real Natura window (run under Xvfb by tests/window/test_window.py) and prints JSON
results.

It feeds the window's own event handlers, so it exercises the same code as a person at the
keyboard: fly keys, mouse look, pause, screenshots, live shader edits on a copy of glsl/.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np


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
    out = {"progress_frames": win.progress_frames, "cache": eff.last_bake.cache,
           "path": eff.last_bake.path}
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


class XKeys:
    """Real key events for a window under Xvfb: xdotool focuses it and types through the X test
    extension, and the window's frames (which dispatch pyglet's events) see ordinary presses."""

    def __init__(self, win, pattern: str, dt: float = 1 / 60):
        self.win, self.dt = win, dt
        self.frames(2)
        found = subprocess.run(["xdotool", "search", "--sync", "--name", pattern],
                               capture_output=True, text=True, timeout=30).stdout.split()
        self.id = found[0]
        subprocess.run(["xdotool", "windowfocus", "--sync", self.id], check=True, timeout=30)
        self.frames(2)

    def frames(self, n: int) -> None:
        for _ in range(n):
            self.win.wnd.clear()
            self.win.frame(self.dt)
            self.win.wnd.swap_buffers()

    def tap(self, key: str, hold_frames: int = 2) -> None:
        subprocess.run(["xdotool", "keydown", key], check=True, timeout=30)
        self.frames(hold_frames)
        subprocess.run(["xdotool", "keyup", key], check=True, timeout=30)
        self.frames(2)


def planet_keys(work: str) -> int:
    """The atmosphere thesis's keys in the planet window, typed as X events: M toggles the
    automatic sun (a parameter action of the key map), Up held raises the sun."""
    from app.runtime import scene_params
    from app.scenes import get_scene
    from app.ui import window as W

    params = scene_params("planet", sets=["planet.method=lut", "planet.shadow_map_size=256",
                                          "planet.lut_height=32", "planet.lut_angle=32"])
    win = W.NaturaWindow("planet", params, get_scene("planet").new_camera(), (160, 90))
    win.show_panel = False
    keys = XKeys(win, "^Natura .* planet$")
    out = {"auto_sun_before": params["planet.auto_sun"]}
    keys.tap("m")
    out["auto_sun_after_m"] = params["planet.auto_sun"]
    keys.tap("m")
    out["auto_sun_after_m_m"] = params["planet.auto_sun"]
    elevation = params["planet.sun_elevation"]
    keys.tap("Up", hold_frames=30)
    out["sun_rise_deg"] = params["planet.sun_elevation"] - elevation
    out["render_error"] = str(win.render_error or "")
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
           "fft_sim": win.scene.effect("ocean").sim is not None}
    win.close()
    print("RESULT " + json.dumps(out))
    return 0


if __name__ == "__main__":
    runs = {"bake-progress": bake_progress, "ocean-models": ocean_models,
            "planet-keys": planet_keys, "sky-keyframes": sky_keyframes}
    sys.exit(runs.get(sys.argv[2] if len(sys.argv) > 2 else "", main)(sys.argv[1]))

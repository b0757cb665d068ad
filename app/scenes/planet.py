"""The ``planet`` scene: atmospheric scattering from the ground to space, with the atmosphere
thesis's own keys (spec/002 §4)."""

from __future__ import annotations

import math

from ..effects.planet import Planet
from ..errors import UsageError
from ..sim.atmosphere import BOTTOM_RADIUS_M
from ..sim.camera import Camera
from .base import Scene
from .keymaps import KeyMap

ATMOSPHERE_THESIS = KeyMap("atmosphere-thesis", {
    "W": "forward", "S": "back", "A": "left", "D": "right", "SPACE": "up", "LEFT_CTRL": "down",
    "RIGHT_CTRL": "down",
    "Q": "turn_left", "E": "turn_right", "R": "pitch_up", "F": "pitch_down", "O": "toggle_mouse",
    # + − * / arrive as characters
    "Z": "toggle_turbo", "PLUS": "turbo_faster", "MINUS": "turbo_slower",
    "ASTERISK": "turbo_faster_100", "SLASH": "turbo_slower_100",
    "T": "toggle_controls", "V": "print_gl_version", "P": "print_camera", "UP": "sun_up",
    "DOWN": "sun_down",
    "M": "toggle_auto_sun", "ESCAPE": "quit", "F12": "screenshot", "F1": "toggle_panel",
}, (
    ("W A S D", "move"), ("Space / Ctrl", "up / down"), ("Q / E", "turn left / right"),
    ("R / F", "pitch up / down"), ("O", "mouse capture"), ("Z", "turbo on/off"),
    ("+ / -", "turbo speed x2 / /2"), ("* or /", "turbo speed x100 / /100"),
    ("T", "camera controls on/off"),
    ("V", "print GL version"), ("P", "print camera position"), ("Up / Down", "move the sun"),
    ("M", "automatic sun"), ("F12", "screenshot"), ("F1", "panel"), ("Esc", "quit"),
), actions={"toggle_auto_sun": "toggle:planet.auto_sun"})


class PlanetScene(Scene):
    name = "planet"
    order = 40
    title = "Atmospheric scattering, ground to space"
    description = ("single scattering in the thesis's three approximations (brute force, "
                   "optical-depth LUT, LUT + shadow-map light shafts) and Hillaire 2020 multiple "
                   "scattering (spec/002)")
    effects = (Planet,)
    default_view = "shafts"
    default_camera = {"position": (0.0, 2.0, 60.0), "yaw": 0.0, "pitch": 4.0, "fov": 60.0,
                      "far": 5.0e7}
    keymap = ATMOSPHERE_THESIS

    @classmethod
    def check_camera(cls, camera: Camera, option: str = "--camera") -> None:
        """The planet is a sphere of radius ``BOTTOM_RADIUS_M`` centred at (0, −R, 0): the camera
        may stand anywhere within the far plane's distance of its centre (farther, the whole
        planet is clipped away and the frame is black)."""
        far = float(cls.default_camera["far"])
        x, y, z = (float(v) for v in camera.position)
        distance = math.hypot(x, y + BOTTOM_RADIUS_M, z)
        if not distance <= far:  # also NaN
            raise UsageError(f"{option}: {x:.6g},{y:.6g},{z:.6g} is {distance:.3g} m from the "
                             f"planet's centre (0,{-BOTTOM_RADIUS_M:g},0): allowed at most "
                             f"{far:g} m from it")

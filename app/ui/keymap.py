"""Key maps and the camera controller behind them, as plain Python (testable without a window).

A :class:`KeyMap` maps key names (``"W"``, ``"SPACE"``, ``"PLUS"``…) to actions; a
:class:`Controller` turns actions into camera motion, time and sun changes. The window
translates its key codes to names and forwards presses and releases.

Two maps: ``FLY`` (Natura's default, documented in the README) and ``ATMOSPHERE_THESIS``, the
annex of the atmospheric-scattering thesis (spec/002 §4: WASD, Space/Ctrl, Q/E turn, R/F pitch,
O mouse capture, Z turbo, + − * / turbo speed, T controls on/off, V GL version, P camera
position, Up/Down sun, M automatic sun, Esc).
"""

from __future__ import annotations

from dataclasses import dataclass, field

# actions held down while the key is pressed
HELD = {"forward", "back", "left", "right", "up", "down", "turn_left", "turn_right", "pitch_up", "pitch_down",
        "sun_up", "sun_down", "fast"}


@dataclass(frozen=True)
class KeyMap:
    name: str
    bindings: dict  # key name → action
    help: tuple = ()  # (keys, description) rows for the panel and README

    def action(self, key: str) -> str | None:
        return self.bindings.get(key)


FLY = KeyMap("fly", {
    "W": "forward", "S": "back", "A": "left", "D": "right", "Q": "down", "E": "up",
    "LEFT_SHIFT": "fast", "RIGHT_SHIFT": "fast", "M": "toggle_mouse", "SPACE": "toggle_time",
    "LEFT_BRACKET": "time_back", "RIGHT_BRACKET": "time_forward", "R": "reset_camera",
    "P": "screenshot", "F12": "screenshot", "F1": "toggle_panel", "ESCAPE": "quit",
    "UP": "sun_up", "DOWN": "sun_down",
}, (
    ("W A S D", "fly"), ("Q / E", "down / up"), ("Shift", "4x faster; wheel: base speed"),
    ("right drag", "look; M toggles mouse look"), ("Space", "pause / resume time"),
    ("[ / ]", "time -/+ 15 min"), ("Up / Down", "sun up / down (planet)"), ("R", "reset camera"),
    ("P or F12", "screenshot"), ("F1", "hide / show panel"), ("Esc", "quit"),
))

OCEAN = KeyMap("ocean", {**FLY.bindings, "NUMBER_1": "set:ocean.model=sine", "NUMBER_2": "set:ocean.model=gerstner",
                         "NUMBER_3": "set:ocean.model=fft"},
               FLY.help[:-2] + (("1 / 2 / 3", "waves: sine / Gerstner / FFT"),) + FLY.help[-2:])

ATMOSPHERE_THESIS = KeyMap("atmosphere-thesis", {
    "W": "forward", "S": "back", "A": "left", "D": "right", "SPACE": "up", "LEFT_CTRL": "down", "RIGHT_CTRL": "down",
    "Q": "turn_left", "E": "turn_right", "R": "pitch_up", "F": "pitch_down", "O": "toggle_mouse",
    "Z": "toggle_turbo", "PLUS": "turbo_faster", "MINUS": "turbo_slower",  # + − * / arrive as characters
    "ASTERISK": "turbo_faster_100", "SLASH": "turbo_slower_100",
    "T": "toggle_controls", "V": "print_gl_version", "P": "print_camera", "UP": "sun_up", "DOWN": "sun_down",
    "M": "toggle_auto_sun", "ESCAPE": "quit", "F12": "screenshot", "F1": "toggle_panel",
}, (
    ("W A S D", "move"), ("Space / Ctrl", "up / down"), ("Q / E", "turn left / right"),
    ("R / F", "pitch up / down"), ("O", "mouse capture"), ("Z", "turbo on/off"),
    ("+ / -", "turbo speed x2 / /2"), ("* or /", "turbo speed x100 / /100"), ("T", "camera controls on/off"),
    ("V", "print GL version"), ("P", "print camera position"), ("Up / Down", "move the sun"),
    ("M", "automatic sun"), ("F12", "screenshot"), ("F1", "panel"), ("Esc", "quit"),
))


@dataclass
class Controller:
    """Camera, time and sun state driven by actions. ``events`` collects one-shot requests the
    window carries out (quit, screenshot, print, toggles it owns)."""

    keymap: KeyMap = FLY
    speed: float = 5.0  # m/s
    turbo: bool = False
    turbo_speed: float = 1000.0  # m/s when turbo is on
    turn_rate: float = 60.0  # deg/s for Q/E, R/F
    sun_rate: float = 10.0  # deg/s for Up/Down
    controls_enabled: bool = True
    held: set = field(default_factory=set)
    events: list = field(default_factory=list)

    def press(self, key: str) -> str | None:
        action = self.keymap.action(key)
        if action is None:
            return None
        if action in HELD:
            self.held.add(action)
        elif action == "toggle_turbo":
            self.turbo = not self.turbo
        elif action == "turbo_faster":
            self.turbo_speed *= 2.0
            self.events.append(("print", f"turbo speed {self.turbo_speed:g} m/s"))
        elif action == "turbo_slower":
            self.turbo_speed /= 2.0
            self.events.append(("print", f"turbo speed {self.turbo_speed:g} m/s"))
        elif action == "turbo_faster_100":
            self.turbo_speed *= 100.0
            self.events.append(("print", f"turbo speed {self.turbo_speed:g} m/s"))
        elif action == "turbo_slower_100":
            self.turbo_speed /= 100.0
            self.events.append(("print", f"turbo speed {self.turbo_speed:g} m/s"))
        elif action == "toggle_controls":
            self.controls_enabled = not self.controls_enabled
            self.held.clear()
        else:
            self.events.append((action, None))
        return action

    def release(self, key: str) -> None:
        action = self.keymap.action(key)
        if action in HELD:
            self.held.discard(action)

    def take_events(self) -> list:
        out, self.events = self.events, []
        return out

    def update(self, camera, dt: float, params=None) -> None:
        """Move the camera (and the sun, through ``params``) for ``dt`` seconds of held keys."""
        h = self.held
        if params is not None and "planet.sun_elevation" in params:
            d = ((("sun_up" in h) - ("sun_down" in h)) * self.sun_rate * dt)
            if d:
                params.set("planet.sun_elevation", max(-90.0, min(90.0, params["planet.sun_elevation"] + d)))
        if not self.controls_enabled:
            return
        v = self.turbo_speed if self.turbo else self.speed * (4.0 if "fast" in h else 1.0)
        step = v * dt
        camera.rotate((("turn_right" in h) - ("turn_left" in h)) * self.turn_rate * dt,
                      (("pitch_up" in h) - ("pitch_down" in h)) * self.turn_rate * dt)
        camera.move(forward=(("forward" in h) - ("back" in h)) * step, right=(("right" in h) - ("left" in h)) * step,
                    up=(("up" in h) - ("down" in h)) * step)

"""The camera controller behind the key maps, as plain Python (testable without a window).

A scene's :class:`~app.scenes.keymaps.KeyMap` maps key names to actions; a :class:`Controller`
turns actions into camera motion, time and sun changes, and collects the one-shot actions the
window carries out. The window translates its key codes to names and forwards presses and
releases.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..scenes.keymaps import FLY, KeyMap

#: pyglet key symbols the window names itself, because moderngl-window 3.1.1's pyglet table
#: gets them wrong or leaves them out: it names BRACELEFT / BRACERIGHT (``{`` ``}``)
#: LEFT_BRACKET / RIGHT_BRACKET, but the ``[`` and ``]`` keys deliver BRACKETLEFT (0x5b) /
#: BRACKETRIGHT (0x5d), which it does not name at all; nor does it name the right Ctrl.
PYGLET_KEY_NAMES = {"BRACKETLEFT": "LEFT_BRACKET", "BRACKETRIGHT": "RIGHT_BRACKET",
                    "RCTRL": "RIGHT_CTRL"}

#: characters that arrive through the window's text event, whatever key typed them (the main
#: keyboard's shifted keys or the keypad): the atmosphere thesis's + − * /
CHARACTERS = {"+": "PLUS", "-": "MINUS", "*": "ASTERISK", "/": "SLASH"}
#: key names whose key event is ignored because their character (above) carries the action;
#: otherwise "-" and "/" would act twice
CHARACTER_KEYS = {"MINUS", "SLASH", "EQUAL"}


def key_names(keys, pyglet_key=None) -> dict[int, str]:
    """Window key code → key name (``keys.W`` → "W") for the key maps: moderngl-window's
    ``keys`` namespace, corrected by :data:`PYGLET_KEY_NAMES` from pyglet's key module."""
    names: dict[int, str] = {}
    for name in dir(keys):
        if name.isupper() and not name.startswith("ACTION_"):
            value = getattr(keys, name)
            if isinstance(value, int):
                names.setdefault(value, name)
    if pyglet_key is not None:
        for symbol, name in PYGLET_KEY_NAMES.items():
            code = getattr(pyglet_key, symbol, None)
            if isinstance(code, int):
                names[code] = name  # overrides: the symbol the key really delivers
    return names


# actions held down while the key is pressed
HELD = {"forward", "back", "left", "right", "up", "down", "turn_left", "turn_right", "pitch_up",
        "pitch_down", "sun_up", "sun_down", "fast"}


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
        sun = self.keymap.sun_parameter
        if params is not None and sun in params:
            d = ((("sun_up" in h) - ("sun_down" in h)) * self.sun_rate * dt)
            if d:
                params.set(sun, max(-90.0, min(90.0, params[sun] + d)))
        if not self.controls_enabled:
            return
        v = self.turbo_speed if self.turbo else self.speed * (4.0 if "fast" in h else 1.0)
        step = v * dt
        camera.rotate((("turn_right" in h) - ("turn_left" in h)) * self.turn_rate * dt,
                      (("pitch_up" in h) - ("pitch_down" in h)) * self.turn_rate * dt)
        camera.move(forward=(("forward" in h) - ("back" in h)) * step,
                    right=(("right" in h) - ("left" in h)) * step,
                    up=(("up" in h) - ("down" in h)) * step)

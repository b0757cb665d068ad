"""The camera controller behind the key maps, as plain Python (testable without a window).

A scene's :class:`~app.scenes.keymaps.KeyMap` maps key names to actions; a :class:`Controller`
turns actions into camera motion, time and sun changes, and collects the one-shot actions the
window carries out. The window translates its key codes to names and forwards presses and
releases.

A ``hold:NAME=RATE`` action moves parameter NAME by RATE per second while its key is down,
clamped to the parameter's range (the maritime helm, throttle and sails); the controller applies
it in :meth:`Controller.update`, like the held camera actions.
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
#: what each turbo key does to the turbo speed: × the first, ÷ the second
TURBO_STEPS = {"turbo_faster": (2.0, 1.0), "turbo_slower": (1.0, 2.0),
               "turbo_faster_100": (100.0, 1.0), "turbo_slower_100": (1.0, 100.0)}


def parse_hold(action: str) -> tuple[str, float]:
    """``hold:NAME=RATE`` → (NAME, RATE per second); a ValueError when it is not one."""
    if not action.startswith("hold:"):
        raise ValueError(f"not a hold action: {action!r}")
    name, sep, rate = action[5:].partition("=")
    if not name or not sep:
        raise ValueError(f"a hold action is hold:NAME=RATE, not {action!r}")
    return name, float(rate)


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
        if action in HELD or action.startswith("hold:"):
            self.held.add(action)
        elif action == "toggle_turbo":
            self.turbo = not self.turbo
        elif action in TURBO_STEPS:
            times, over = TURBO_STEPS[action]
            self.turbo_speed = self.turbo_speed * times / over
            self.events.append(("print", f"turbo speed {self.turbo_speed:g} m/s"))
        elif action == "toggle_controls":
            self.controls_enabled = not self.controls_enabled
            self.held.clear()
        else:
            self.events.append((action, None))
        return action

    def release(self, key: str) -> None:
        action = self.keymap.action(key)
        if action is not None:
            self.held.discard(action)

    def release_all(self) -> None:
        """Let go of every held action (the window lost the keyboard)."""
        self.held.clear()

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
        if params is not None:
            self._hold_params(params, dt)
        if not self.controls_enabled:
            return
        v = self.turbo_speed if self.turbo else self.speed * (4.0 if "fast" in h else 1.0)
        step = v * dt
        camera.rotate((("turn_right" in h) - ("turn_left" in h)) * self.turn_rate * dt,
                      (("pitch_up" in h) - ("pitch_down" in h)) * self.turn_rate * dt)
        camera.move(forward=(("forward" in h) - ("back" in h)) * step,
                    right=(("right" in h) - ("left" in h)) * step,
                    up=(("up" in h) - ("down" in h)) * step)

    def _hold_params(self, params, dt: float) -> None:
        """Apply the held ``hold:NAME=RATE`` actions: NAME moves RATE × dt, clamped to its
        range (two keys on one parameter add up; an unknown parameter is ignored)."""
        rates: dict[str, float] = {}
        for action in self.held:
            if isinstance(action, str) and action.startswith("hold:"):
                try:
                    name, rate = parse_hold(action)
                except ValueError:
                    continue
                if name in params:
                    rates[name] = rates.get(name, 0.0) + rate
        for name, rate in rates.items():
            if not rate or not dt:
                continue
            spec = params.spec(name)
            value = float(params[name]) + rate * dt
            if spec.lo is not None:
                value = max(float(spec.lo), value)
            if spec.hi is not None:
                value = min(float(spec.hi), value)
            if value != params[name]:
                params.set(name, value)


def cycle_value(spec, value):
    """The value a ``cycle:NAME`` action gives parameter ``spec`` now at ``value``: a choice's
    next choice (after the last, the first), a boolean's opposite, an integer's next value in
    its range (after the highest, the lowest: a mode switch such as shading.toon)."""
    if spec.kind == "choice" and spec.choices:
        choices = list(spec.choices)
        i = choices.index(value) if value in choices else -1
        return choices[(i + 1) % len(choices)]
    if spec.kind == "bool":
        return not value
    if spec.kind == "int":
        lo, hi = int(spec.lo), int(spec.hi)
        return lo if int(value) >= hi else int(value) + 1
    raise ValueError(f"cycle: {spec.name} is a {spec.kind}, not a choice, a boolean or an "
                     "integer")

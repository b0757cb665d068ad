"""Key maps: which key does what in a scene's window, as plain data (the window's
:class:`~app.ui.keymap.Controller` carries the actions out).

A :class:`KeyMap` maps key names (``"W"``, ``"SPACE"``, ``"PLUS"``…) to actions and lists
(keys, description) rows for the panel's Controls section. Actions are the controller's (move,
look, time, screenshot…), or act on a parameter without the window knowing the scene:

* ``set:NAME=VALUE`` — set a parameter (the ocean's 1 / 2 / 3 pick the wave model);
* ``toggle:NAME`` — flip a boolean parameter;
* a named action in ``KeyMap.actions`` — an alias for one of the above, so a map can keep
  the name its thesis gives a key (``toggle_auto_sun`` → ``toggle:planet.auto_sun``).

``FLY`` is Natura's default map (documented in docs/commands.md); scenes define their own maps
beside them (``app/scenes/ocean.py``, ``app/scenes/planet.py``).
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class KeyMap:
    name: str
    bindings: dict  # key name → action
    help: tuple = ()  # (keys, description) rows for the panel and docs/commands.md
    #: named actions → the parameter action they stand for (``set:…`` / ``toggle:…``)
    actions: dict = field(default_factory=dict)
    #: the parameter the held sun_up / sun_down actions move (degrees per second: the
    #: controller's sun_rate)
    sun_parameter: str = "planet.sun_elevation"

    def action(self, key: str) -> str | None:
        return self.bindings.get(key)

    def resolve(self, action: str) -> str:
        """The parameter action a named action stands for (the action itself otherwise)."""
        return self.actions.get(action, action)


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

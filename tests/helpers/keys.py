"""Key presses for the controller tests."""

from __future__ import annotations

from app.ui.keymap import HELD

#: one-shot actions the controller carries out itself
CONTROLLER_ACTIONS = {"toggle_turbo", "turbo_faster", "turbo_slower", "turbo_faster_100",
                      "turbo_slower_100", "toggle_controls"}
#: one-shot actions the window carries out (:meth:`app.ui.window.NaturaWindow.run_events`)
WINDOW_ACTIONS = {"quit", "screenshot", "toggle_time", "time_back", "time_forward",
                  "toggle_mouse", "toggle_panel", "reset_camera", "print_gl_version",
                  "print_camera", "toggle_ui", "pause_menu"}
#: actions on a parameter, by prefix: ``set:NAME=VALUE``, ``toggle:NAME``, ``cycle:NAME`` (a
#: choice steps to its next choice, wrapping), ``hold:NAME=RATE`` (held: RATE per second)
PARAM_PREFIXES = ("set:", "toggle:", "cycle:", "hold:")


def hold(controller, key: str, *update) -> None:
    """Press ``key``, run one ``controller.update(*update)`` (camera, seconds[, params]) with it
    held, release it."""
    controller.press(key)
    controller.update(*update)
    controller.release(key)


def action_kind(action: str) -> str | None:
    """What kind of action ``action`` is — "held", "controller", "window", or its parameter
    prefix ("set", "toggle", "cycle", "hold") — or None for an action nothing carries out."""
    if action in HELD:
        return "held"
    if action in CONTROLLER_ACTIONS:
        return "controller"
    if action in WINDOW_ACTIONS:
        return "window"
    for prefix in PARAM_PREFIXES:
        if action.startswith(prefix) and len(action) > len(prefix):
            return prefix[:-1]
    return None


def action_parameter(action: str) -> str | None:
    """The parameter a ``set:`` / ``toggle:`` / ``cycle:`` / ``hold:`` action names."""
    for prefix in PARAM_PREFIXES:
        if action.startswith(prefix):
            return action[len(prefix):].partition("=")[0]
    return None

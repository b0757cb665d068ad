"""A guard for calls that would block forever (opening a named pipe for reading): the call runs
in a thread, and a test fails only if it has not returned after ``HANG_S`` seconds — long enough
that a loaded machine never reaches it, so the verdict is about blocking, not about speed."""

from __future__ import annotations

import threading
from typing import Any, Callable

HANG_S = 120.0


def finishes(call: Callable[[], Any]) -> Any:
    """``call()``'s result (or its exception, raised here); fails if it blocks."""
    out: dict[str, Any] = {}

    def run() -> None:
        try:
            out["value"] = call()
        except BaseException as exc:  # handed to the caller's thread
            out["error"] = exc

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    thread.join(HANG_S)
    assert not thread.is_alive(), f"still blocked after {HANG_S:.0f} s: it would never return"
    if "error" in out:
        raise out["error"]
    return out.get("value")

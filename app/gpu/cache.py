"""A value rebuilt only when what it depends on changes.

Many resources are expensive to make and cheap to keep: a lookup table that depends on the
model's constants, a mesh that depends on its segment count, a texture that depends on a seed.
:class:`Keyed` holds one such value with the key it was built for; :meth:`Keyed.get` returns it
while the key is unchanged and otherwise releases the old value and builds a new one::

    self._lut = Keyed(self._build_lut, release=self.gpu.free)
    ...
    lut = self._lut.get((model.lut_key(), size))   # built on the first call and on changes

Keys are compared with ``==``; use tuples of plain values (numbers, strings, tuples).
"""

from __future__ import annotations

from typing import Any, Callable, Generic, TypeVar

T = TypeVar("T")

_UNSET: Any = object()


class Keyed(Generic[T]):
    """One value and the key it was built for."""

    def __init__(self, build: Callable[[Any], T], release: Callable[[T], None] | None = None):
        self._build = build
        self._release = release
        self.key: Any = _UNSET
        self.value: T | None = None
        self.builds = 0  # how many times build() ran

    @property
    def built(self) -> bool:
        return self.key is not _UNSET

    def get(self, key: Any) -> T:
        """The value for ``key``: the held one when the key is unchanged, else a new one."""
        if self.key is _UNSET or key != self.key:
            self.clear()
            value = self._build(key)
            self.value, self.key = value, key
            self.builds += 1
        return self.value  # type: ignore[return-value]

    def clear(self) -> None:
        """Release the value (if any) and forget the key."""
        if self.value is not None and self._release is not None:
            self._release(self.value)
        self.value = None
        self.key = _UNSET

"""A value rebuilt only when what it depends on changes.

Many resources are expensive to make and cheap to keep: a lookup table that depends on the
model's constants, a mesh that depends on its segment count, a texture that depends on a seed.
:class:`Keyed` holds one such value with the key it was built for; :meth:`Keyed.get` returns it
while the key is unchanged and otherwise releases the old value and builds a new one::

    self._lut = Keyed(self._build_lut, release=self.gpu.free)
    ...
    lut = self._lut.get((model.lut_key(), size))   # built on the first call and on changes

Keys are compared with ``==``; use tuples of plain values (numbers, strings, tuples).

:data:`MEMO` is the other kind: pure numpy builds (noise fields, meshes, placements) shared by
every session of the process, read-only, within a byte budget (:class:`Memo`).
"""

from __future__ import annotations

import dataclasses
from collections import OrderedDict
from typing import Any, Callable, Generic, TypeVar

import numpy as np

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


#: the bytes of arrays and the entries :data:`MEMO` keeps, least recently used out first (every
#: parity job's builds together are ~40 MB; values without arrays count no bytes)
MEMO_BUDGET = 256 << 20
MEMO_ENTRIES = 4096


def _arrays(value: Any):
    """The arrays and bytes in ``value``, its tuples, lists, dict values and dataclass fields."""
    if isinstance(value, (np.ndarray, bytes, bytearray)):
        yield value
    elif isinstance(value, (tuple, list, dict)):
        for v in value.values() if isinstance(value, dict) else value:
            yield from _arrays(v)
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        for f in dataclasses.fields(value):
            yield from _arrays(getattr(value, f.name))


def freeze(value: Any) -> Any:
    """``value``, every numpy array in it read-only: no holder of a shared value changes it."""
    for a in _arrays(value):
        if isinstance(a, np.ndarray):
            a.flags.writeable = False
    return value


def nbytes(value: Any) -> int:
    """Bytes of the numpy arrays (and bytes objects) in ``value``."""
    return sum(int(a.nbytes) if isinstance(a, np.ndarray) else len(a) for a in _arrays(value))


class Memo:
    """Pure builds kept across sessions: ``get(key, build)`` returns the value built for
    ``key`` by any earlier caller in this process, else builds, freezes (:func:`freeze`) and
    keeps it. The key must name everything the value depends on (the function's name and
    every argument); the arrays held take at most ``budget`` bytes, the least recently used
    dropped first (a value larger than the budget is returned but not kept).

    Why: a process that opens many sessions (compare, report, a bench) builds each noise field,
    mesh and placement once; a session's own :class:`Keyed` values still die with it."""

    def __init__(self, budget: int = MEMO_BUDGET):
        self.budget = int(budget)
        self._items: OrderedDict[Any, tuple[Any, int]] = OrderedDict()
        self.bytes = 0
        self.hits = 0
        self.builds = 0

    def __contains__(self, key: Any) -> bool:
        return key in self._items

    def get(self, key: Any, build: Callable[[], T]) -> T:
        item = self._items.get(key)
        if item is not None:  # now the most recently used
            self._items.move_to_end(key)
            self.hits += 1
            return item[0]
        value = freeze(build())
        self.builds += 1
        size = nbytes(value)
        if size <= self.budget:
            self._items[key] = (value, size)
            self.bytes += size
            while self.bytes > self.budget or len(self._items) > MEMO_ENTRIES:
                _, (_, dropped) = self._items.popitem(last=False)
                self.bytes -= dropped
        return value

    def clear(self) -> None:
        self._items.clear()
        self.bytes = 0


#: the process's memo of pure numpy builds (see :class:`Memo`)
MEMO = Memo()


def memoised(build: Callable[..., T], *args: Any) -> T:
    """``build(*args)`` shared by every session: ``MEMO.get((build, *args), …)``. The key holds
    the function itself, so a test that replaces a module's builder gets its own values."""
    return MEMO.get((build, *args), lambda: build(*args))

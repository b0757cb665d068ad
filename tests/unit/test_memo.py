"""The process-wide memo of pure builds (app.gpu.cache.Memo): a value is built once per key,
handed out read-only so no session can change it for another, and the arrays held stay within
the byte budget, least recently used out first."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from app.gpu.cache import Memo, freeze, nbytes


def test_a_key_is_built_once_and_its_arrays_are_read_only():
    memo = Memo(1 << 20)
    calls = []

    def build():
        calls.append(1)
        return np.arange(10.0), [np.zeros(3)], {"a": np.ones(2)}

    first = memo.get(("f", 1), build)
    again = memo.get(("f", 1), build)
    assert again is first and len(calls) == 1 and memo.hits == 1 and memo.builds == 1
    for arr in (first[0], first[1][0], first[2]["a"]):
        with pytest.raises(ValueError):
            arr[0] = 5.0
    memo.get(("f", 2), build)  # another key, another build
    assert len(calls) == 2


def test_the_budget_drops_the_least_recently_used_first():
    memo = Memo(3 * 800)
    for k in range(3):
        memo.get(k, lambda: np.zeros(100))  # 800 bytes each
    memo.get(0, lambda: pytest.fail("0 is held"))  # 0 is now the most recently used
    memo.get(3, lambda: np.zeros(100))  # over budget: 1 goes
    assert 1 not in memo and {0, 2, 3} <= {k for k in range(4) if k in memo}
    assert memo.bytes == 3 * 800
    big = memo.get("big", lambda: np.zeros(1000))  # larger than the budget: returned, not kept
    assert big.shape == (1000,) and "big" not in memo and memo.bytes == 3 * 800


def test_freeze_and_nbytes_walk_dataclasses():
    @dataclasses.dataclass
    class Mesh:
        vertices: np.ndarray
        indices: np.ndarray
        name: str = "m"

    m = freeze(Mesh(np.zeros((4, 3), np.float32), np.zeros(6, np.uint32)))
    assert not m.vertices.flags.writeable and not m.indices.flags.writeable
    assert nbytes(m) == 4 * 3 * 4 + 6 * 4
    assert nbytes((b"abc", 2.0)) == 3


def test_memoised_keys_on_the_function_and_its_arguments():
    from app.gpu.cache import MEMO, memoised

    calls = []

    def ramp(n):
        calls.append(n)
        return np.arange(float(n))

    def other(n):
        return np.zeros(n)

    try:
        a = memoised(ramp, 3)
        assert memoised(ramp, 3) is a and calls == [3]
        assert memoised(ramp, 4).shape == (4,) and calls == [3, 4]
        assert not memoised(other, 3).any()  # a replaced builder is not served ramp's value
    finally:
        for key in [(ramp, 3), (ramp, 4), (other, 3)]:
            MEMO._items.pop(key, None)
        MEMO.bytes = sum(size for _, size in MEMO._items.values())

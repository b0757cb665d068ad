"""app.sim.vec.cross is numpy.cross for 3-vectors, bit for bit (the physics' inner loops call it
instead), for single vectors, stacks and broadcasting."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from app.sim.vec import cross

FINITE = st.floats(-1e6, 1e6, allow_nan=False, width=64)


@given(arrays(np.float64, st.sampled_from([(3,), (7, 3), (2, 4, 3)]), elements=FINITE),
       arrays(np.float64, (3,), elements=FINITE))
def test_cross_is_numpy_cross_bit_for_bit(a, b):
    assert np.array_equal(cross(a, b), np.cross(a, b))
    assert np.array_equal(cross(b, a), np.cross(b, a))
    assert np.array_equal(cross(a, a), np.cross(a, a))


def test_cross_keeps_the_dtype_and_the_handedness():
    x, y = np.array([1.0, 0.0, 0.0], np.float32), np.array([0.0, 1.0, 0.0], np.float32)
    assert cross(x, y).dtype == np.float32 and cross(x, y).tolist() == [0.0, 0.0, 1.0]
    assert cross([0.0, 1.0, 0.0], [1.0, 0.0, 0.0]).tolist() == [0.0, 0.0, -1.0]

"""app.sim.vec.norm and app.sim.vec.length are numpy.linalg.norm (along an axis, and of a whole
vector) bit for bit (the physics' inner loops call them instead)."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from app.sim.vec import length, norm

FINITE = st.floats(-1e150, 1e150, allow_nan=False, width=64)


@given(arrays(np.float64, st.sampled_from([(3,), (1, 3), (7, 3), (2, 4, 3), (5, 4)]),
              elements=FINITE), st.booleans())
def test_norm_is_numpy_norm_bit_for_bit(a, keepdims):
    for axis in (-1, 0):
        assert np.array_equal(norm(a, axis=axis, keepdims=keepdims),
                              np.linalg.norm(a, axis=axis, keepdims=keepdims))


@given(arrays(np.float64, st.sampled_from([(3,), (4,), (2, 3)]), elements=FINITE))
def test_length_is_numpy_norm_bit_for_bit(v):
    assert length(v) == float(np.linalg.norm(v))
    assert isinstance(length(v), float)


def test_integers_and_lists_are_taken_as_floats():
    assert norm([[3, 4]]).tolist() == [5.0]
    assert length((3, 4, 12)) == 13.0 == float(np.linalg.norm((3, 4, 12)))
    assert math.isnan(length([math.nan, 1.0, 0.0]))

"""Number texts in messages: float32 values as the controllers display them."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from codegen.dialects.core.values import f32, format_fixed, format_general


@pytest.mark.slow
@settings(max_examples=3000, deadline=None)
@given(st.floats(width=32, allow_nan=True, allow_infinity=True))
def test_format_general_is_the_shortest_positional_float32_text(value):
    v = np.float32(value)
    text = format_general(v)
    if np.isnan(v):
        assert text == "nan"
    elif np.isinf(v):
        assert text == ("inf" if v > 0 else "-inf")
    else:
        assert text == np.format_float_positional(v, trim="-", unique=True)
        assert np.float32(text) == v


def test_format_fixed_rounds_half_away_from_zero_without_minus_zero():
    assert format_fixed(np.float32(2.5), 0) == "3"
    assert format_fixed(-0.004, 2) == "0.00"
    assert format_fixed(-2.5, 0) == "-3"
    assert format_fixed(1.005, 2) == "1.00"  # 1.005 is 1.00499999999999989... in binary
    assert format_fixed(float("nan"), 2) == "nan"


@pytest.mark.slow
@settings(max_examples=5000, deadline=None)
@given(st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-(2**70), 2**70)))
@pytest.mark.filterwarnings("ignore:overflow:RuntimeWarning")
def test_f32_rounds_exactly_as_numpy_float32(value):
    fast, slow = f32(value), np.float32(value)
    assert type(fast) is np.float32
    assert fast.tobytes() == slow.tobytes() or (np.isnan(fast) and np.isnan(slow))

"""The closed-form kernels' angle remainder ``_rem`` against IEEE ``math.remainder(v, 2π)``: the
same bits inside (−π, π) (where it returns v without dividing), the same angle to the rounding of
``v − k·2π`` elsewhere (a tie at an odd multiple of π may land on either side: −π or π), in
[−π, π]; compiled and plain Python give the same bits."""
import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from robokit.kernels.closed_form import _rem

_EDGES = [s * k * math.pi for k in (1, 3, 5, 7, 101) for s in (1.0, -1.0)]
_NEAR = [float(np.nextafter(e, t)) for e in _EDGES for t in (-np.inf, np.inf)]


def _bits(v):
    return np.float64(v).tobytes()


@settings(max_examples=400, deadline=None, derandomize=True)
@given(v=st.one_of(st.floats(-1e6, 1e6), st.floats(-10.0, 10.0), st.floats(-math.pi, math.pi),
                   st.sampled_from(_EDGES + _NEAR + [0.0, -0.0])))
def test_rem_is_the_ieee_remainder(v):
    r = _rem(v)
    assert _bits(r) == _bits(_rem.py_func(v))
    expected = math.remainder(v, 2.0 * math.pi)
    if -math.pi < v < math.pi:
        assert _bits(r) == _bits(v) == _bits(expected)
    assert abs(r) <= math.pi * (1.0 + 1e-15)
    d = abs(r - expected)
    d = min(d, abs(d - 2.0 * math.pi))  # a tie: −π and π are one angle
    assert d <= 4.0 * math.ulp(abs(v)) + 1e-15, (v, r, expected)


def test_rem_of_nan_is_nan():
    assert math.isnan(_rem(float("nan")))

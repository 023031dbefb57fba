"""The examples in the calibration modules' docstrings run and print what they say."""
import doctest
import importlib

import numpy as np
import pytest

import robokit

MODULES = ["chain", "kinematic", "regressor", "identification", "excitation", "data"]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(f"robokit.calibration.{name}")
    # the same namespace as tests/test_docstrings.py: the module's globals plus np and rk
    old = np.get_printoptions()
    np.set_printoptions(precision=4, suppress=True)
    try:
        result = doctest.testmod(module, extraglobs={"np": np, "rk": robokit},
                                 optionflags=doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS)
    finally:
        np.set_printoptions(**old)
    assert result.attempted > 0
    assert result.failed == 0

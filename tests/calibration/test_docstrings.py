"""The examples in the calibration modules' docstrings run and print what they say."""
import doctest
import importlib

import pytest

MODULES = ["chain", "kinematic", "regressor", "identification", "excitation", "data"]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(f"robokit.calibration.{name}")
    result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0
    assert result.failed == 0

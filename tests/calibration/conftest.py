"""Fixtures of the calibration tests: robots loaded once; the helpers in calibration_support.py put
on sys.path (the CLI helpers of tests/support/hardening_support.py are put there by tests/conftest.py)."""
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))

import calibration_support as cs  # noqa: E402

import robokit  # noqa: E402
from shared_robots import robot as shared_robot  # noqa: E402


@pytest.fixture(scope="session")
def robots():
    cache = {}

    def get(name):
        if name not in cache:
            cache[name] = cs.prismatic_arm() if name == "rpr" else shared_robot(name)
        return cache[name]

    return get

"""Helpers for the generated-C tests: compile a robot's files once per session and load them."""
import shutil

import pytest

from robokit.codegen import generate_c
from robokit.codegen.build import compile_library, find_compiler


@pytest.fixture(scope="session")
def cc():
    found = find_compiler()
    if found is None:
        pytest.skip("no C compiler on this machine (CI installs gcc)")
    return found


@pytest.fixture(scope="session")
def build(cc, tmp_path_factory):
    """build(robot, float32=False, name=None) -> CLibrary, compiled with the strict flags (-Werror) at -O1
    (quicker to compile than -O2; the CLI test and the benchmark use -O2)."""
    cache = {}

    def _build(robot, float32=False, name=None):
        key = (id(robot), float32, name)
        if key not in cache:
            folder = tmp_path_factory.mktemp("c")
            src = generate_c(robot, name=name, float32=float32)
            cache[key] = (robot, compile_library(src, folder, robot.n, float32=float32, flags=("-O1",), compiler=cc))
        return cache[key][1]

    return _build


def which_or_skip(tool, why):
    """The path of ``tool``, or skip the test saying ``why``."""
    found = shutil.which(tool)
    if found is None:
        pytest.skip(why)
    return found


@pytest.fixture(scope="session")
def nm():
    return which_or_skip("nm", "no nm on this machine")


@pytest.fixture(scope="session")
def clang():
    return which_or_skip("clang", "clang not installed (Debian: clang; .ci/run installs it)")

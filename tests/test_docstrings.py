"""Every public function and class says what it takes and returns (numpydoc), every function of
the seed library carries a worked example, and every example in a public docstring runs and
prints what it says.

"Public": the names in ``__all__`` of every module of :mod:`robokit` whose dotted path has no
component starting with ``_`` (the compiled kernels in :mod:`robokit.kernels` are internal and
excluded). The examples run as doctests in their module's namespace, with ``numpy`` as ``np`` and
``robokit`` as ``rk`` added; numbers are printed with ``np.set_printoptions(precision=4,
suppress=True)`` (``ELLIPSIS`` and ``NORMALIZE_WHITESPACE`` on).
"""
from __future__ import annotations

import doctest
import importlib
import inspect
import pkgutil
from typing import Any

import numpy as np
import pytest

import robokit

#: Sub-packages whose docstrings are checked, one test each (so a failure names its package).
PACKAGES = (
    "robokit", "robokit.spatial", "robokit.kinematics", "robokit.dynamics", "robokit.description",
    "robokit.control", "robokit.ik", "robokit.trajectory", "robokit.mobile", "robokit.viz",
    "robokit.workspace", "robokit.validation", "robokit.calibration", "robokit.collision",
    "robokit.motion", "robokit.codegen", "robokit.symbolic",
)


def _public_objects() -> dict[str, list[tuple[str, Any]]]:
    """Package → [(qualified name, object)] of the public functions and classes, each once."""
    seen: dict[int, tuple[str, Any]] = {}
    for info in pkgutil.walk_packages(robokit.__path__, "robokit."):
        parts = info.name.split(".")
        if any(p.startswith("_") for p in parts) or parts[1] == "kernels":
            continue
        importlib.import_module(info.name)
    modules = [robokit] + [importlib.import_module(n) for n in sorted(_module_names())]
    for mod in modules:
        for name in getattr(mod, "__all__", ()):
            obj = getattr(mod, name, None)
            if not (inspect.isfunction(obj) or inspect.isclass(obj)):
                continue
            if not getattr(obj, "__module__", "").startswith("robokit"):
                continue
            seen.setdefault(id(obj), (f"{obj.__module__}.{obj.__qualname__}", obj))
    by_package: dict[str, list[tuple[str, Any]]] = {p: [] for p in PACKAGES}
    for qualname, obj in seen.values():
        module = obj.__module__
        package = max((p for p in PACKAGES if module == p or module.startswith(p + ".")), key=len)
        by_package[package].append((qualname, obj))
    return by_package


def _module_names() -> list[str]:
    names = []
    for info in pkgutil.walk_packages(robokit.__path__, "robokit."):
        parts = info.name.split(".")
        if any(p.startswith("_") for p in parts) or parts[1] == "kernels":
            continue
        names.append(info.name)
    return names


def _takes_arguments(obj: Any) -> bool:
    target = obj.__init__ if inspect.isclass(obj) else obj
    try:
        params = list(inspect.signature(target).parameters.values())
    except (TypeError, ValueError):
        return False
    return any(p.name not in ("self", "cls") for p in params)


def _returns_something(obj: Any) -> bool:
    if inspect.isclass(obj):
        return False
    ann = inspect.signature(obj).return_annotation
    return ann not in (None, "None", inspect.Signature.empty)


def _section(doc: str, *titles: str) -> bool:
    lines = doc.splitlines()
    for i, line in enumerate(lines[:-1]):
        if line.strip() in titles and set(lines[i + 1].strip()) == {"-"}:
            return True
    return False


OBJECTS = _public_objects()


def _missing_sections(package: str) -> list[str]:
    missing = []
    for qualname, obj in OBJECTS[package]:
        doc = inspect.getdoc(obj) or ""
        if _takes_arguments(obj) and not _section(doc, "Parameters", "Attributes"):
            missing.append(f"{qualname}: no Parameters section")
        if _returns_something(obj) and not _section(doc, "Returns", "Yields"):
            missing.append(f"{qualname}: no Returns section")
    return missing


@pytest.mark.parametrize("package", PACKAGES)
def test_numpydoc_sections(package: str) -> None:
    """Parameters (or, for a data class, Attributes) when it takes arguments; Returns when it returns."""
    missing = _missing_sections(package)
    assert not missing, f"{len(missing)} public objects lack numpydoc sections:\n" + "\n".join(missing)


def test_every_seed_function_has_an_example() -> None:
    lacking = [n for n in robokit.SEED_FUNCTIONS if ">>>" not in (inspect.getdoc(getattr(robokit, n)) or "")]
    assert not lacking, f"seed functions without an example: {lacking}"


def _examples(package: str) -> list[doctest.DocTest]:
    finder = doctest.DocTestFinder(recurse=False)
    tests = []
    for qualname, obj in OBJECTS[package]:
        module = importlib.import_module(obj.__module__)
        for t in finder.find(obj, qualname, module=module):
            if t.examples:
                tests.append(t)
    return tests


@pytest.mark.parametrize("package", PACKAGES)
def test_examples_run(package: str) -> None:
    """Every ``>>>`` example of the package's public docstrings runs and prints what it shows."""
    flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    failures = []
    for test in _examples(package):
        old = np.get_printoptions()
        np.set_printoptions(precision=4, suppress=True)
        try:
            test.globs.update({"np": np, "rk": robokit, "robokit": robokit})
            runner = doctest.DocTestRunner(optionflags=flags)
            out: list[str] = []
            runner.run(test, out=out.append)
            if runner.failures:
                failures.append("".join(out))
        finally:
            np.set_printoptions(**old)
    assert not failures, "\n".join(failures)

"""Every public function, class and method says what it takes and returns (numpydoc), every
function of the seed library and every public method of the main types carries a worked example,
and every example in a public docstring runs and prints what it says.

Methods: the public methods (no leading ``_``) a public class defines. Those of the main types —
``Robot``, ``World``, ``Scene``, ``SymbolicArm`` and the result classes (:data:`MAIN_TYPES`) —
need Parameters (when they take arguments), Returns (when they return) and an Example; those of
every other public class need Parameters and Returns, except the few listed in
:data:`KNOWN_GAPS` (a ratchet: a listed method that gains its sections fails until it is
removed from the list). A class's examples run in one namespace, the class docstring's first and
then its methods' in definition order, like a notebook: a method's example may use the object
the class example made (so a ``Scene`` starts one viewer, not one per method).

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
import warnings
from typing import Any

import numpy as np
import pytest

import robokit

#: robokit's deprecation warnings (robokit/_deprecation.py): an example that triggers one fails.
_ROBOKIT_DEPRECATION = r".*is deprecated and will be removed in robokit "

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

#: The main types: every public method has Parameters, Returns and an Example.
MAIN_TYPES = {
    "robokit.description.robot.Robot", "robokit.collision.world.World", "robokit.viz.scene.Scene",
    "robokit.symbolic.SymbolicArm", "robokit.symbolic.SymbolicDynamics",
    "robokit.control.simulate.SimResult", "robokit.control.line.LineTrackingResult", "robokit.ik.solution.IKSolution",
    "robokit.ik.lm.IKResult", "robokit.workspace.capability.CapabilityMap",
    "robokit.calibration.kinematic.CalibrationResult", "robokit.calibration.identification.IdentificationResult",
    "robokit.trajectory.core.Trajectory", "robokit.ik.closed_form.AnalyticIK",
}

#: Public methods of the other classes still without Parameters/Returns (remove an entry when it is written).
KNOWN_GAPS: set[str] = set()


def _methods(cls: Any) -> list[tuple[str, Any]]:
    """(name, function) of the public methods ``cls`` defines (properties are attributes, not methods)."""
    out = []
    for name, member in vars(cls).items():
        if name.startswith("_") or isinstance(member, property):
            continue
        fn = getattr(member, "__func__", member)
        if inspect.isfunction(fn):
            out.append((name, fn))
    return out


def _method_gaps(package: str) -> list[str]:
    """What each public method of the package's public classes lacks (``KNOWN_GAPS`` not counted)."""
    missing = []
    for qualname, cls in OBJECTS[package]:
        if not inspect.isclass(cls):
            continue
        main = qualname in MAIN_TYPES
        for name, fn in _methods(cls):
            doc = inspect.getdoc(fn) or ""
            lacks = []
            if _takes_arguments(fn) and not _section(doc, "Parameters"):
                lacks.append("Parameters")
            if _returns_something(fn) and not _section(doc, "Returns", "Yields"):
                lacks.append("Returns")
            if main and ">>>" not in doc:
                lacks.append("an Example")
            if lacks and f"{qualname}.{name}" not in KNOWN_GAPS:
                missing.append(f"{qualname}.{name}: no {', '.join(lacks)}")
    return missing


def method_coverage() -> tuple[int, int]:
    """(public methods with Parameters, Returns and an Example as they need, public methods) — for reports."""
    done = total = 0
    for objs in OBJECTS.values():
        for _, cls in objs:
            if inspect.isclass(cls):
                for _, fn in _methods(cls):
                    doc = inspect.getdoc(fn) or ""
                    total += 1
                    done += ((not _takes_arguments(fn) or _section(doc, "Parameters"))
                             and (not _returns_something(fn) or _section(doc, "Returns", "Yields")) and ">>>" in doc)
    return done, total


@pytest.mark.parametrize("package", PACKAGES)
def test_public_methods_have_numpydoc_sections(package: str) -> None:
    missing = _method_gaps(package)
    assert not missing, f"{len(missing)} public methods lack numpydoc sections:\n" + "\n".join(missing)


def test_known_gaps_are_still_gaps() -> None:
    """The ratchet: an entry of KNOWN_GAPS whose method now has its sections (or is gone) must be removed."""
    by_name = {f"{q}.{n}": fn for objs in OBJECTS.values() for q, c in objs if inspect.isclass(c) for n, fn in _methods(c)}
    stale = []
    for entry in sorted(KNOWN_GAPS):
        fn = by_name.get(entry)
        doc = inspect.getdoc(fn) or "" if fn is not None else ""
        if fn is None or ((not _takes_arguments(fn) or _section(doc, "Parameters"))
                          and (not _returns_something(fn) or _section(doc, "Returns", "Yields"))):
            stale.append(entry)
    assert not stale, f"remove from KNOWN_GAPS (documented or gone): {stale}"


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


def _examples(package: str) -> list[list[doctest.DocTest]]:
    """The package's doctests, grouped: one group per function, one per class (its docstring's
    then its methods' examples, sharing one namespace)."""
    finder = doctest.DocTestFinder(recurse=False)
    groups = []
    for qualname, obj in OBJECTS[package]:
        module = importlib.import_module(obj.__module__)
        group = [t for t in finder.find(obj, qualname, module=module) if t.examples]
        if inspect.isclass(obj):
            for name, fn in _methods(obj):
                group += [t for t in finder.find(fn, f"{qualname}.{name}", module=module, globs=module.__dict__)
                          if t.examples]
        if group:
            groups.append(group)
    return groups


@pytest.mark.parametrize("package", PACKAGES)
def test_examples_run(package: str) -> None:
    """Every ``>>>`` example of the package's public docstrings runs and prints what it shows."""
    flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    failures = []
    for group in _examples(package):
        old = np.get_printoptions()
        np.set_printoptions(precision=4, suppress=True)
        globs = dict(group[0].globs)
        globs.update({"np": np, "rk": robokit, "robokit": robokit})
        try:
            for test in group:
                test.globs = globs  # one namespace per class: its methods' examples continue its own
                runner = doctest.DocTestRunner(optionflags=flags)
                out: list[str] = []
                with warnings.catch_warnings():  # an example must not use what robokit deprecates
                    warnings.filterwarnings("error", category=DeprecationWarning, message=_ROBOKIT_DEPRECATION)
                    runner.run(test, out=out.append, clear_globs=False)
                if runner.failures:
                    failures.append("".join(out))
        finally:
            np.set_printoptions(**old)
            for value in list(globs.values()):  # a Scene or viewer the examples opened
                if hasattr(value, "close") and type(value).__module__.startswith("robokit.viz"):
                    value.close()
    assert not failures, "\n".join(failures)

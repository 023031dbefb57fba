"""One naming rule: the seed library keeps the course's names; every other public conversion
reads ``X_from_Y``. Renamed functions keep their old name as an alias that warns
(``DeprecationWarning`` naming the new function) and returns the same result.
"""
from __future__ import annotations

import importlib
import pkgutil
import re
import warnings

import numpy as np
import pytest

import robokit
from robokit._deprecation import deprecated_alias

#: Public ``X_to_Y`` names allowed besides the seed library: none today. A name added here must also be
#: listed, with its reason, on the docs' Conventions page (docs/conventions.md, "Naming").
DOCUMENTED_EXCEPTIONS: frozenset[str] = frozenset()

#: old name → (module that still provides it, new name)
RENAMED = {
    "rpy_to_matrix": ("robokit.description", "matrix_from_rpy"),
    "matrix_to_rpy": ("robokit.description", "rpy_from_matrix"),
    "dh_to_urdf": ("robokit.description", "urdf_from_dh"),
    "urdf_to_dh": ("robokit", "dh_from_urdf"),
    "robot_to_mjcf": ("robokit.description.mjcf_write", "mjcf_from_robot"),
    "cartesian_to_joint": ("robokit.trajectory", "joint_trajectory_from_cartesian"),
    "jacobian_to_frame": ("robokit.kinematics", "jacobian_in_frame"),
    "reflect_to_joint": ("robokit.control", "joint_from_motor"),
}


def _public_names() -> dict[str, str]:
    """Public name → the first module whose ``__all__`` lists it (kernels and private modules skipped)."""
    out: dict[str, str] = {n: "robokit" for n in robokit.__all__}
    for info in pkgutil.walk_packages(robokit.__path__, "robokit."):
        parts = info.name.split(".")
        if any(p.startswith("_") for p in parts) or parts[1] == "kernels":
            continue
        mod = importlib.import_module(info.name)
        for n in getattr(mod, "__all__", ()):
            out.setdefault(n, info.name)
    return out


def test_no_public_x_to_y_name_outside_the_seed_library() -> None:
    allowed = set(robokit.SEED_FUNCTIONS) | DOCUMENTED_EXCEPTIONS
    bad = sorted(f"{mod}.{n}" for n, mod in _public_names().items()
                 if re.search(r"[a-z0-9]_to_[A-Za-z0-9]", n) and n not in allowed)
    assert not bad, f"public X_to_Y names break the X_from_Y rule (rename, keep a deprecated alias): {bad}"


def test_renamed_functions_are_public_and_old_names_are_not() -> None:
    names = _public_names()
    for old, (_, new) in RENAMED.items():
        assert new in names, new
        assert old not in names, old


@pytest.mark.parametrize("old", sorted(RENAMED))
def test_old_name_warns_and_names_the_new_one(old: str) -> None:
    module, new = RENAMED[old]
    alias = getattr(importlib.import_module(module), old)
    assert alias.__name__ == old and alias.__wrapped__.__name__ == new
    with pytest.warns(DeprecationWarning, match=rf"{old} is deprecated: use robokit\..*\.{new}\b"):
        with pytest.raises(TypeError):
            alias()  # each needs arguments: the warning comes first, then the new function's error


def test_alias_returns_the_new_functions_result() -> None:
    rpy = np.array([0.3, -0.4, 1.2])
    with pytest.warns(DeprecationWarning):
        R_old = robokit.description.rpy_to_matrix(rpy)
    R_new = robokit.description.matrix_from_rpy(rpy)
    # independent: URDF rpy = Rz(yaw) Ry(pitch) Rx(roll)
    c, s = np.cos, np.sin
    Rx = np.array([[1, 0, 0], [0, c(rpy[0]), -s(rpy[0])], [0, s(rpy[0]), c(rpy[0])]])
    Ry = np.array([[c(rpy[1]), 0, s(rpy[1])], [0, 1, 0], [-s(rpy[1]), 0, c(rpy[1])]])
    Rz = np.array([[c(rpy[2]), -s(rpy[2]), 0], [s(rpy[2]), c(rpy[2]), 0], [0, 0, 1]])
    np.testing.assert_allclose(R_new, Rz @ Ry @ Rx, atol=1e-12)
    np.testing.assert_array_equal(R_old, R_new)
    with pytest.warns(DeprecationWarning):
        G_old = robokit.control.reflect_to_joint(100, 2e-4, 1e-3, 0.1)
    np.testing.assert_allclose(G_old, (2.0, 10.0, 10.0))  # G²·Jm, G²·Bm, G·τ (Lecture 8)


def test_deprecated_alias_helper() -> None:
    def area_from_side(a: float, *, square: bool = True) -> float:
        return a * a if square else a

    side_to_area = deprecated_alias(area_from_side, "side_to_area")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert side_to_area(3.0) == 9.0 and side_to_area(3.0, square=False) == 3.0
    assert len(caught) == 2 and all(w.category is DeprecationWarning for w in caught)
    message = str(caught[0].message)
    assert "side_to_area is deprecated: use" in message and "area_from_side" in message
    assert caught[0].filename == __file__  # attributed to the caller, not to the helper
    assert "area_from_side" in (side_to_area.__doc__ or "")

"""Deprecated aliases: an old public name that keeps working and says which name replaced it.

robokit's naming rule (see the docs' *Conventions* page): the seed library keeps the names of the
course's function documentation (``euler_to_matrix``, ``Rp_to_trans``, …); every other public
conversion reads ``X_from_Y`` (``matrix_from_rpy``, ``urdf_from_dh``). A function renamed to the
rule keeps its old name as an alias made by :func:`deprecated_alias`: every call emits a
``DeprecationWarning`` naming the new function, attributed to the caller's line (Python shows it
in scripts' ``__main__``, notebooks and test runs, once per line by default), then calls the new
function with the same arguments.
Old names are not listed in any ``__all__`` (so star-imports and the API pages show only the new
ones) but stay importable from where they were.

This module is the one place robokit's deprecations live: :data:`DEPRECATIONS` lists each of
them — a renamed function, a renamed keyword argument, a former frame word, a default that
changes — with what replaces it and the release that removes it (``tests/test_deprecations.py``
checks that every deprecation the package emits is listed here). Renamed functions warn on every
call (:func:`deprecated_alias`); the others warn once per process (:func:`warn_once`).
"""
from __future__ import annotations

import functools
import warnings
from collections.abc import Callable
from typing import Any, TypeVar

__all__ = ["DEPRECATIONS", "FRAME_SYNONYMS", "REMOVAL", "deprecated_alias", "renamed_argument", "warn", "warn_once"]

F = TypeVar("F", bound=Callable[..., Any])

#: The release that removes the deprecations below (robokit is 0.2.x today).
REMOVAL = "0.4.0"

#: Every deprecation: the old spelling → (what replaces it, the release that removes it).
DEPRECATIONS: dict[str, tuple[str, str]] = {
    # renamed to the X_from_Y rule (deprecated_alias: every call warns)
    "dh_to_urdf": ("robokit.description.urdf_gen.urdf_from_dh", REMOVAL),
    "urdf_to_dh": ("robokit.description.urdf_to_dh.dh_from_urdf", REMOVAL),
    "rpy_to_matrix": ("robokit.description.dh.matrix_from_rpy", REMOVAL),
    "matrix_to_rpy": ("robokit.description.dh.rpy_from_matrix", REMOVAL),
    "robot_to_mjcf": ("robokit.description.mjcf_write.mjcf_from_robot", REMOVAL),
    "cartesian_to_joint": ("robokit.trajectory.cartesian.joint_trajectory_from_cartesian", REMOVAL),
    "jacobian_to_frame": ("robokit.kinematics.velocity.jacobian_in_frame", REMOVAL),
    "reflect_to_joint": ("robokit.control.motor.joint_from_motor", REMOVAL),
    # the former frame words (robokit.frames.as_frame: once per word per process)
    "reference='space'": ("Frame.WORLD", REMOVAL),
    "reference='body'": ("Frame.LOCAL", REMOVAL),
    "reference='tool'": ("Frame.LOCAL", REMOVAL),
    "reference='base'": ("Frame.LOCAL_WORLD_ALIGNED", REMOVAL),
    # defaults that become robokit.frames.DEFAULT_FRAME (omitting reference= warns once per function)
    # renamed keyword arguments (renamed_argument: once per name per process)
    "base_wrench(Ftip=)": ("F_tip=", REMOVAL),
    "ik_spherical_wrist(theta4_ref=)": ("wrist_ref=", REMOVAL),
    "ik_puma560(theta4_ref=)": ("wrist_ref=", REMOVAL),
    "package_path=": ("package_dirs= (the name robokit.load uses)", REMOVAL),
    "solve_ik(target=)": ("T=", REMOVAL),
    # a changed argument order (once per process)
    "solve_ik(robot, T, frame, q0)": ("solve_ik(robot, T, q0, frame=...)", REMOVAL),
    # a batch of configurations given to a one-configuration Robot method (once per method per process)
    "Robot.frame_pose((N, n) q)": ("Robot.frame_pose_batch(Q)", REMOVAL),
    "Robot.jacobian((N, n) q)": ("Robot.jacobian_batch(Q)", REMOVAL),
    "Robot.rnea((N, n) q)": ("Robot.rnea_batch(Q, dQ, ddQ)", REMOVAL),
    "Robot.crba((N, n) q)": ("Robot.crba_batch(Q)", REMOVAL),
    "Robot.aba((N, n) q)": ("Robot.aba_batch(Q, dQ, tau)", REMOVAL),
}

#: The former frame words and the canonical (lower-case Pinocchio) name each one means.
FRAME_SYNONYMS: dict[str, str] = {
    "space": "world", "body": "local", "tool": "local", "base": "local_world_aligned",
}

_WARNED: set[str] = set()


def warn_once(key: str, replacement: str | None = None, *, category: type[Warning] = DeprecationWarning,
              stacklevel: int | None = None) -> None:
    """Warn about the deprecation ``key`` of :data:`DEPRECATIONS`, once per process.

    Parameters
    ----------
    key : str
        A key of :data:`DEPRECATIONS`, e.g. ``"reference='base'"``.
    replacement : str, optional
        What to write instead (default: the registry's entry).
    category : type, optional
        ``DeprecationWarning`` (a name going away) or ``FutureWarning`` (a result that changes).
    stacklevel : int, optional
        As :func:`warnings.warn`; default: the first caller outside robokit (the user's line).

    Returns
    -------
    None
        The warning is emitted the first time only.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     warn_once("reference='space'"); warn_once("reference='space'")
    >>> len(w), str(w[0].message)
    (1, "reference='space' is deprecated and will be removed in robokit 0.4.0: use Frame.WORLD")
    """
    if key in _WARNED:
        return
    _WARNED.add(key)
    warn(key, replacement, category=category, stacklevel=stacklevel + 1 if stacklevel else None)


def warn(key: str, replacement: str | None = None, *, category: type[Warning] = DeprecationWarning,
         stacklevel: int | None = None) -> None:
    """Warn about the deprecation ``key`` of :data:`DEPRECATIONS` (every time; see :func:`warn_once`).

    Parameters
    ----------
    key : str
        A key of :data:`DEPRECATIONS`.
    replacement : str, optional
        What to write instead (default: the registry's entry).
    category : type, optional
        ``DeprecationWarning`` or ``FutureWarning``.
    stacklevel : int, optional
        As :func:`warnings.warn`; default: the first caller outside robokit.

    Returns
    -------
    None

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     warn("package_path=", category=FutureWarning); warn("package_path=", category=FutureWarning)
    >>> len(w), w[0].category.__name__
    (2, 'FutureWarning')
    """
    new, removal = DEPRECATIONS[key]
    if key.endswith("(reference omitted)"):
        message = (f"{key}: the default frame becomes robokit.Frame.LOCAL_WORLD_ALIGNED (robokit's one default) "
                   f"in robokit {removal}; pass {replacement or new}")
    else:
        message = f"{key} is deprecated and will be removed in robokit {removal}: use {replacement or new}"
    from robokit._stack import outside_level

    warnings.warn(message, category, stacklevel=stacklevel or outside_level())



def renamed_argument(key: str, new_value: Any, old_value: Any, unset: Any, where: str, default: Any = None) -> Any:
    """The value of a keyword argument that may still come under its former name.

    Parameters
    ----------
    key : str
        The key of :data:`DEPRECATIONS`, e.g. ``"base_wrench(Ftip=)"``.
    new_value, old_value : object
        The values given under the new and the old name (``unset`` when not given).
    unset : object
        The sentinel meaning "not given".
    where : str
        The function, for the error when both names are given.
    default : object, optional
        The new name's default, when it has one (a value equal to it counts as not given).

    Returns
    -------
    object
        ``old_value`` if it was given (warning once per process), else ``new_value``.

    Examples
    --------
    >>> _unset = object()
    >>> renamed_argument("base_wrench(Ftip=)", 1.0, _unset, _unset, "base_wrench")
    1.0
    """
    if old_value is unset:
        return new_value
    if new_value is not unset and (default is None or new_value != default):
        from robokit.errors import InputError

        raise InputError(f"{where}: give {DEPRECATIONS[key][0]} only (the other is its former name)")
    warn_once(key)
    return old_value


def deprecated_alias(new: F, old: str, removal: str | None = None) -> F:
    """``new`` under its former name ``old``, warning on every call.

    Parameters
    ----------
    new : callable
        The function (or class) under its current name.
    old : str
        The former name, e.g. ``"rpy_to_matrix"``.
    removal : str, optional
        The release that removes it (default: its :data:`DEPRECATIONS` entry, else :data:`REMOVAL`).

    Returns
    -------
    callable
        A function with ``new``'s signature that emits ``DeprecationWarning("old is deprecated:
        use module.new")`` (attributed to the caller's line) and returns ``new(*args, **kwargs)``.

    Examples
    --------
    >>> import warnings
    >>> def matrix_from_thing(x): return 2 * x
    >>> thing_to_matrix = deprecated_alias(matrix_from_thing, "thing_to_matrix")
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     thing_to_matrix(3), str(w[0].message).split(":")[0]
    (6, 'thing_to_matrix is deprecated')
    """
    target = f"{new.__module__}.{new.__qualname__}"
    removal = removal or DEPRECATIONS.get(old, ("", REMOVAL))[1]
    message = f"{old} is deprecated: use {target} (same arguments, same result); removed in robokit {removal}"

    @functools.wraps(new)
    def alias(*args: Any, **kwargs: Any) -> Any:
        warnings.warn(message, DeprecationWarning, stacklevel=2)
        return new(*args, **kwargs)

    alias.__name__ = old
    alias.__qualname__ = old
    alias.__doc__ = f"Deprecated alias of :func:`{target}` (renamed to the ``X_from_Y`` rule)."
    alias.__deprecated_for__ = target  # type: ignore[attr-defined]
    alias.__removal__ = removal  # type: ignore[attr-defined]
    return alias  # type: ignore[return-value]

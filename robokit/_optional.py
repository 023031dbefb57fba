"""Optional dependencies: imported on first use, with one line naming the extra that brings them.

The core install (``pip install robokit``) is the course library, DH/URDF/example-robot-data
robots, Pinocchio, the compiled kernels and the CLI's ``validate``/``convert``. Everything else
is an extra (``pip install 'robokit[viz]'``, or ``robokit[all]`` for every one). A function that
needs an extra imports it through :func:`require`; when the package is missing, the call raises
:class:`~robokit.errors.MissingExtraError` (an ``ImportError`` and an ``InputError``, so the CLI
prints one line and exits 2) naming the extra. An import still running after two seconds (a first
use on a new machine: TOPP-RA brings scipy and matplotlib, whose font cache is built once per
user) says so on stderr, then the elapsed time, then how long it took (:mod:`robokit._progress`).
"""
from __future__ import annotations

import importlib
import sys
from typing import Any

from robokit._progress import Slow
from robokit.errors import MissingExtraError

# top-level import name -> (distribution, extra that installs it)
EXTRAS: dict[str, tuple[str, str]] = {
    "meshcat": ("meshcat", "viz"),
    "trimesh": ("trimesh", "viz"),
    "collada": ("pycollada", "viz"),
    "ziglang": ("ziglang", "viz"),
    "rjsmin": ("rjsmin", "viz"),
    "IPython": ("ipython", "notebooks"),
    "ipywidgets": ("ipywidgets", "notebooks"),
    "anywidget": ("anywidget", "notebooks"),
    "matplotlib": ("matplotlib", "plot"),
    "sympy": ("sympy", "symbolic"),
    "distributed": ("distributed", "workspace"),
    "dask": ("dask", "workspace"),
    "xacro": ("xacro", "formats"),
    "mujoco": ("mujoco", "mujoco"),
    "toppra": ("toppra", "motion"),
    "ompl": ("ompl", "motion"),
}


def require(module: str, purpose: str = "") -> Any:
    """Import ``module`` (dotted names allowed), or raise ``MissingExtraError`` naming its extra.

    Parameters
    ----------
    module : the module to import, e.g. ``"meshcat.geometry"``; its top-level package must be
        one of :data:`EXTRAS`.
    purpose : what needs it, for the message (e.g. ``"the viewer"``).

    Examples
    --------
    >>> np_like = require("sympy")  # doctest: +SKIP
    """
    top = module.split(".")[0]
    dist, extra = EXTRAS[top]
    try:
        loaded = sys.modules.get(module)
        if loaded is not None:
            return loaded
        # a first import can be slow on a new machine (toppra pulls in scipy and matplotlib, whose
        # font cache is built once per user): after two seconds of silence, say so, then the time
        with Slow(f"robokit: {purpose or module}: importing {dist} (its first use in this process; the "
                  "first on a machine can take a while) ...", done=f"robokit: {dist} imported",
                  still=f"still importing {dist}", after=2.0):
            return importlib.import_module(module)
    except ModuleNotFoundError as exc:
        missing = (exc.name or "").split(".")[0]
        if missing != top:  # the package is there but one of *its* dependencies is not
            raise
        who = f"{purpose} needs" if purpose else "this needs"
        raise MissingExtraError(
            f"{who} {dist}, which robokit installs with its {extra!r} extra: "
            f"pip install 'robokit[{extra}]' (or 'robokit[all]')", extra=extra) from None


def available(module: str) -> bool:
    """True if ``module`` can be imported (without importing anything else of robokit's)."""
    try:
        importlib.import_module(module)
    except ModuleNotFoundError:
        return False
    return True

r"""Compiled course kernels: the lecture's recursions as plain loops over the joints, compiled
with numba (``@njit(cache=True)``).

* :mod:`robokit.kernels.lie` — small pose/twist/wrench helpers written entry by entry;
* :mod:`robokit.kernels.poe` — product-of-exponentials FK and Jacobians (space and body);
* :mod:`robokit.kernels.dynamics` — Newton–Euler inverse dynamics, CRBA mass matrix,
  forward dynamics by the articulated-body algorithm and by CRBA + Cholesky (Modern Robotics form);
* :mod:`robokit.kernels.packed` — a PoE model packed once into one read-only array (:func:`~robokit.kernels.packed.pack_model`)
  and the per-call and batched FK, Jacobian, RNEA, CRBA and ABA kernels that take it (the least
  dispatch per call: for objects that hold a fixed model, such as ``Robot``);
* :mod:`robokit.kernels.dh` — DH forward kinematics, the Jacobian by outward propagation,
  inward static forces, Craig's recursive Newton–Euler (both conventions, R and P joints);
* :mod:`robokit.kernels.ik` — damped least-squares / Levenberg–Marquardt IK for a PoE chain,
  joint limits and random restarts, compiled end to end;
* :mod:`robokit.kernels.simulation` — closed-loop simulation (built-in controllers, plant, integrator);
* :mod:`robokit.kernels.warm` — ``python -m robokit.kernels``: compile every kernel ahead of use.

Each kernel has a ``*_batch`` twin over a leading dimension of configurations, run in
parallel over the CPU cores. The seed functions (:func:`robokit.fkin_space`,
:func:`robokit.inverse_dynamics`, …) check their arguments and call these kernels; use them
directly only with C-contiguous float64 arrays of the documented shapes.

In a fresh environment a kernel's first calls run it as plain Python while a background
worker compiles it into numba's cache (``ROBOKIT_COMPILE=wait`` compiles in the calling process
instead, ``off`` never compiles; a notice on stderr says what happens); see
:mod:`robokit.kernels._jit` for the policy, where the cache lives and ``NUMBA_DISABLE_JIT=1`` to
run the same source as plain Python.
The submodules are imported on demand, so ``import robokit`` does not load numba.
"""
from __future__ import annotations

import os
from types import ModuleType

from robokit.errors import InputError

__all__ = ["lie", "poe", "dynamics", "packed", "dh", "ik", "simulation", "warm", "compile_mode", "ENV", "MODES"]

#: The environment variable that chooses what a kernel's first call does on a cache miss.
ENV = "ROBOKIT_COMPILE"
#: Its values: ``background`` (the default), ``wait``, ``off`` (see :mod:`robokit.kernels._jit`).
MODES = ("background", "wait", "off")


def compile_mode() -> str:
    """What a kernel's first call does when its machine code is not in numba's cache, from
    ``$ROBOKIT_COMPILE``: ``"background"`` (default: run as plain Python while a background
    worker compiles), ``"wait"`` (compile in the calling process) or ``"off"`` (never compile).
    The background worker itself always compiles (``"wait"``). Does not import numba.

    Returns
    -------
    str
        One of :data:`MODES`.

    Raises
    ------
    InputError
        When ``ROBOKIT_COMPILE`` is set to anything else.

    Examples
    --------
    >>> compile_mode() in MODES
    True
    """
    if os.environ.get("ROBOKIT_COMPILE_WORKER"):
        return "wait"
    mode = os.environ.get(ENV, "").strip().lower() or "background"
    if mode not in MODES:
        raise InputError(f"{ENV}: expected one of {', '.join(MODES)}; got {os.environ.get(ENV)!r}")
    return mode


def __getattr__(name: str) -> ModuleType:
    if name in __all__:
        import importlib

        return importlib.import_module(f"robokit.kernels.{name}")
    raise AttributeError(f"module 'robokit.kernels' has no attribute {name!r}")

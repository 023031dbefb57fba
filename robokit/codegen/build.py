r"""Compile generated C into a shared library and call it from Python through ``ctypes``.

Used by the tests and the benchmark, and handy to try the generated functions from a
notebook before flashing them: ``lib = compile_library(generate_c(robot), folder)`` then
``lib.fk(q)``, ``lib.ik(T)`` … Needs a C compiler (``cc``, or ``$CC``).
"""
from __future__ import annotations

import ctypes
import os
import shutil
import subprocess
from pathlib import Path
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike

from robokit.codegen.generate import CSource, write_c
from robokit.errors import InputError

__all__ = ["STRICT_FLAGS", "find_compiler", "compile_library", "CLibrary"]

#: The flags the generated code is written for (plus ``-Wdouble-promotion`` for ``--float32``).
STRICT_FLAGS = ("-std=c99", "-Wall", "-Wextra", "-Wpedantic", "-Werror", "-Wshadow")


def find_compiler() -> str | None:
    """The C compiler to use.

    Returns
    -------
    str or None
        The path of ``$CC`` if set and found, else of ``cc``, ``gcc`` or ``clang`` on the PATH;
        None when there is none.

    Examples
    --------
    >>> cc = find_compiler()      # e.g. '/usr/bin/cc'; None without a compiler
    >>> cc is None or os.path.isfile(cc)
    True
    """
    cc = os.environ.get("CC")
    if cc and shutil.which(cc):
        return shutil.which(cc)
    for name in ("cc", "gcc", "clang"):
        found = shutil.which(name)
        if found:
            return found
    return None


class CLibrary:
    """A compiled generated library: ``fk``, ``joint_poses``, ``jacobian``, ``ik``, ``gravity``, ``rnea`` on numpy arrays.

    Made by :func:`compile_library`; the methods call the C functions through :mod:`ctypes`.

    Parameters
    ----------
    path : pathlib.Path
        The shared library (``NAME.so``) to load.
    src : CSource
        The generated source it was compiled from.
    n : int
        The robot's number of joints.
    float32 : bool
        Whether the library computes in ``float``.

    Attributes
    ----------
    name : str
        The C prefix.
    n : int
        Number of joints.
    float32 : bool
        Whether the library computes in ``float``.
    has_ik : bool
        Whether ``NAME_ik`` exists.
    max_solutions : int
        ``NAME_MAX_SOLUTIONS`` (0 without IK).
    path : pathlib.Path
        The ``.so``.
    lib : ctypes.CDLL
        The loaded library.
    labels : list of str
        The IK solution labels, or [].

    Examples
    --------
    The planar arm's C code (needs a C compiler): the tip with the elbow at 90° and the gravity
    torques when stretched (links 1 m and 0.8 m, 2 kg and 1.5 kg, g = 9.81 m/s²):

    >>> import tempfile
    >>> from robokit.codegen.generate import generate_c
    >>> robot = rk.load("twolink")
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     lib = compile_library(generate_c(robot), tmp, robot.n, flags=("-O0",))
    ...     tip, tau = lib.fk([0.0, np.pi / 2])[:2, 3], lib.gravity([0.0, 0.0])
    >>> tip.round(4).tolist(), tau.round(4).tolist()
    ([1.0, 0.8], [46.107, 11.772])
    """

    def __init__(self, path: Path, src: CSource, n: int, float32: bool) -> None:
        self.path = path
        self.name = src.name
        self.n = n
        self.float32 = float32
        self.has_ik = src.has_ik
        self.lib = ctypes.CDLL(str(path))
        self._t = np.float32 if float32 else np.float64
        ct = ctypes.c_float if float32 else ctypes.c_double
        P = ctypes.POINTER(ct)
        self._ptr = P
        for fn, nargs in (("fk", 2), ("joint_poses", 2), ("jacobian", 2), ("gravity", 2), ("rnea", 4)):
            f = getattr(self.lib, f"{self.name}_{fn}")
            f.argtypes = [P] * nargs
            f.restype = None
        self.max_solutions = 0
        self.labels: list[str] = []
        if self.has_ik:
            f = getattr(self.lib, f"{self.name}_ik")
            f.argtypes = [P, P]
            f.restype = ctypes.c_int
            g = getattr(self.lib, f"{self.name}_ik_ex")
            g.argtypes = [P, ct, P, ctypes.POINTER(ctypes.c_int)]
            g.restype = ctypes.c_int
            self.max_solutions = int(ctypes.c_int.in_dll(self.lib, f"{self.name}_ik_max_solutions").value)
            count = int(ctypes.c_int.in_dll(self.lib, f"{self.name}_ik_label_count").value)
            names = (ctypes.c_char_p * count).in_dll(self.lib, f"{self.name}_ik_label_names")
            self.labels = [(x or b"").decode() for x in names]

    def _arr(self, x: ArrayLike, size: int) -> np.ndarray:
        a = np.ascontiguousarray(np.asarray(x, dtype=float).reshape(-1), dtype=self._t)
        if a.size != size:
            raise InputError(f"expected {size} values, got {a.size}")
        return a

    def _p(self, a: np.ndarray) -> object:
        return a.ctypes.data_as(self._ptr)

    def _of_q(self, fn: str, q: ArrayLike, size: int) -> np.ndarray:
        """Call ``NAME_<fn>(q, out)`` (one joint vector in, ``size`` values out), as float64."""
        qa, out = self._arr(q, self.n), np.zeros(size, self._t)
        getattr(self.lib, f"{self.name}_{fn}")(self._p(qa), self._p(out))
        return out.astype(float)

    def fk(self, q: ArrayLike) -> np.ndarray:
        """``NAME_fk``: the tool pose in the base frame.

        Parameters
        ----------
        q : (n,) array
            Joint values (rad, m).

        Returns
        -------
        (4, 4) array
            The pose (as float64, computed in the library's precision).

        Examples
        --------
        >>> lib.fk(np.zeros(lib.n))  # doctest: +SKIP
        """
        return self._of_q("fk", q, 16).reshape(4, 4)

    def joint_poses(self, q: ArrayLike) -> np.ndarray:
        """``NAME_joint_poses``: every joint frame's pose in the base frame.

        Parameters
        ----------
        q : (n,) array
            Joint values (rad, m).

        Returns
        -------
        (n, 4, 4) array
            Entry k − 1 is joint k's frame pose (Pinocchio's ``data.oMi[k]``), m.

        Examples
        --------
        >>> lib.joint_poses(np.zeros(lib.n)).shape  # doctest: +SKIP
        (6, 4, 4)
        """
        return self._of_q("joint_poses", q, 16 * self.n).reshape(self.n, 4, 4)

    def jacobian(self, q: ArrayLike) -> np.ndarray:
        """``NAME_jacobian``: the geometric Jacobian.

        Parameters
        ----------
        q : (n,) array
            Joint values (rad, m).

        Returns
        -------
        (6, n) array
            Rows (ω; v) in base axes, v of the tool origin.

        Examples
        --------
        >>> lib.jacobian(np.zeros(lib.n)).shape  # doctest: +SKIP
        (6, 6)
        """
        return self._of_q("jacobian", q, 6 * self.n).reshape(6, self.n)

    def gravity(self, q: ArrayLike) -> np.ndarray:
        """``NAME_gravity``: the gravity torques.

        Parameters
        ----------
        q : (n,) array
            Joint values (rad, m).

        Returns
        -------
        (n,) array
            Torques (N·m) or forces (N).

        Examples
        --------
        >>> lib.gravity(np.zeros(lib.n))  # doctest: +SKIP
        """
        return self._of_q("gravity", q, self.n)

    def rnea(self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike) -> np.ndarray:
        """``NAME_rnea``: inverse dynamics τ = M(q)q̈ + C(q, q̇)q̇ + g(q).

        Parameters
        ----------
        q, qd, qdd : (n,) arrays
            Joint values (rad, m), velocities (/s) and accelerations (/s²).

        Returns
        -------
        (n,) array
            Torques (N·m) or forces (N).

        Examples
        --------
        >>> lib.rnea(q, qd, qdd)  # doctest: +SKIP
        """
        a, b, c = self._arr(q, self.n), self._arr(qd, self.n), self._arr(qdd, self.n)
        out = np.zeros(self.n, self._t)
        getattr(self.lib, f"{self.name}_rnea")(self._p(a), self._p(b), self._p(c), self._p(out))
        return out.astype(float)

    def ik(self, T: ArrayLike, wrist_ref: float = 0.0) -> list[tuple[np.ndarray, str, bool, bool]]:
        """``NAME_ik_ex``: every closed-form solution, in the C function's order.

        Parameters
        ----------
        T : (4, 4) array
            Tool pose in the base frame (m).
        wrist_ref : float
            The free joint's value at a wrist singularity (rad).

        Returns
        -------
        list of (q (n,) array, label str, within_limits bool, degenerate bool)
            The label as ``ik_analytic`` writes it (with `` #2`` for a repeat).

        Examples
        --------
        >>> [label for _, label, _, _ in lib.ik(T)]  # doctest: +SKIP
        """
        if not self.has_ik:
            raise InputError(f"{self.name}: the generated code has no closed-form IK")
        Ta = self._arr(T, 16)
        q = np.zeros(self.max_solutions * self.n, self._t)
        info = (ctypes.c_int * (4 * self.max_solutions))()
        k = getattr(self.lib, f"{self.name}_ik_ex")(self._p(Ta), wrist_ref, self._p(q), info)
        out = []
        for i in range(k):
            label, rep, inside, degen = info[4 * i: 4 * i + 4]
            text = self.labels[label] + (f" #{rep}" if rep > 1 else "")
            out.append((q[i * self.n:(i + 1) * self.n].astype(float), text, bool(inside), bool(degen)))
        return out


def compile_library(src: CSource, folder: str | os.PathLike[str], n: int, float32: bool = False,
                    flags: Sequence[str] = (), compiler: str | None = None) -> CLibrary:
    """Write ``src`` into ``folder``, compile it with :data:`STRICT_FLAGS` into ``NAME.so``, load it.

    Parameters
    ----------
    src : CSource
        From :func:`robokit.codegen.generate_c`.
    folder : path
        An existing folder (the .h, .c, .o and .so go there).
    n : int
        The robot's number of joints.
    float32 : bool
        Whether ``src`` was generated with ``float32=True`` (adds ``-Wdouble-promotion``).
    flags : sequence of str, optional
        Extra compiler flags (default ``("-O2",)``).
    compiler : str, optional
        Path of the compiler (default :func:`find_compiler`).

    Returns
    -------
    CLibrary

    Raises
    ------
    RuntimeError
        If no compiler is found or the code does not compile (the compiler's message).

    Examples
    --------
    The planar arm (links 1 m and 0.8 m) compiled and called through ctypes (needs a C compiler):

    >>> import tempfile
    >>> from robokit.codegen.generate import generate_c
    >>> robot = rk.load("twolink")
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     lib = compile_library(generate_c(robot), tmp, robot.n, flags=("-O0",))
    ...     T = lib.fk([np.pi / 2, 0.0])
    >>> np.allclose(T, robot.frame_pose([np.pi / 2, 0.0])), T[:2, 3].round(4).tolist()
    (True, [0.0, 1.8])
    """
    cc = compiler or find_compiler()
    if cc is None:
        raise RuntimeError("no C compiler found (install gcc, or set CC)")
    folder = Path(folder)
    _, c_path = write_c(src, folder)
    obj = folder / f"{src.name}.o"
    so = folder / f"{src.name}.so"
    extra = list(flags) or ["-O2"]
    warn = list(STRICT_FLAGS) + (["-Wdouble-promotion"] if float32 else [])
    for cmd in ([cc, *warn, *extra, "-fPIC", "-c", str(c_path), "-o", str(obj)],
                [cc, "-shared", str(obj), "-o", str(so), "-lm"]):
        res = subprocess.run(cmd, capture_output=True, text=True)
        if res.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)} failed:\n{res.stderr}")
    return CLibrary(so, src, n, float32)

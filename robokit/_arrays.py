"""Boundary checks: turn array-likes into float64 arrays of the expected shape, or raise.

Every public function validates its arguments once, here, so that the numerical code
below it can assume clean input. Errors name the argument and what was received. Nothing is
cast silently: complex values, strings, booleans and other objects are refused
(:class:`robokit.errors.InputTypeError`), never turned into floats.
"""
from __future__ import annotations

from collections.abc import Sequence
from typing import Any, TypeAlias

from math import isfinite

import numpy as np

from robokit._deprecation import FRAME_SYNONYMS
from robokit.errors import InputError, InputTypeError
from robokit.frames import Frame, as_frame

_F64 = np.dtype(np.float64)

#: Largest magnitude of a number robokit reads from a file or takes as a measurement (SI units):
#: robot files (lengths, masses, inertias), scene files (sizes, poses), calibration and
#: identification data. Beyond it FK, dynamics and collision checks overflow to inf or NaN
#: (1e12 m is seven times the Earth–Sun distance; 1e12² still fits a double with room to spare).
MAX_MAGNITUDE = 1e12

#: A vector argument whose entries the code reads directly (``x[0]``): a sequence of floats or an array.
FloatVector: TypeAlias = "Sequence[float] | np.ndarray"


def _describe(a: object) -> str:
    arr = np.asarray(a)
    return f"shape {arr.shape}" if arr.ndim else f"value {arr!r}"


def shape_text(shape: tuple[int | None, ...]) -> str:
    """An expected shape as a message shows it: ``None`` sizes as letters, distinct ones when there are
    several (``(n, 3)``, ``(m, n)``, ``(k, m, n)``), so that a free shape never reads as a square one.

    Examples
    --------
    >>> shape_text((None, 3)), shape_text((None, None)), shape_text((3,))
    ('(n, 3)', '(m, n)', '(3,)')
    """
    free = sum(s is None for s in shape)
    letters = iter("kmn"[-free:] if 1 < free <= 3 else "n" * free)
    return "(" + ", ".join(next(letters) if s is None else str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"


def _real_array(x: object, name: str) -> np.ndarray:
    """``x`` as a float64 array, refusing what ``np.asarray(x, dtype=float)`` would cast silently:
    complex values (their imaginary part would be dropped), strings (``"0"`` would become 0.0),
    booleans (True would become 1.0), arbitrary objects, ragged nestings."""
    if isinstance(x, (str, bytes)):
        raise InputTypeError(f"{name}: expected numbers, got a string {x!r:.60}")
    try:
        arr = np.asarray(x)
    except (TypeError, ValueError):  # ragged nesting ("inhomogeneous shape"), objects numpy refuses
        raise InputError(f"{name}: expected an array of numbers, got {type(x).__name__} {x!r:.80}") from None
    kind = arr.dtype.kind
    if kind in "fiu":
        return arr.astype(float, copy=False) if kind != "f" or arr.dtype != np.float64 else arr
    if kind == "c":
        raise InputTypeError(f"{name}: expected real numbers, got complex values (dtype {arr.dtype})")
    if kind == "b":
        raise InputTypeError(f"{name}: expected numbers, got booleans (True/False)")
    if kind in "USa":
        raise InputTypeError(f"{name}: expected numbers, got strings (dtype {arr.dtype})")
    if kind == "O":
        import numbers

        for v in arr.flat:
            if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Real):
                shown = f"{type(v).__name__} {v!r:.40}"
                raise InputTypeError(f"{name}: expected an array of real numbers, got an entry {shown}")
        try:
            return arr.astype(float)
        except (OverflowError, TypeError, ValueError):
            raise InputError(f"{name}: a value is too large for a double") from None
    raise InputTypeError(f"{name}: expected an array of numbers, got dtype {arr.dtype}")


def as_array(x: object, name: str, shape: tuple[int | None, ...] | None = None, *, finite: bool = True,
             bounded: bool = False) -> np.ndarray:
    """Return ``x`` as a float64 array, checking its shape (``None`` in ``shape`` = any size).

    Parameters
    ----------
    x : array_like
        Real numbers (ints or floats; numpy arrays of integer or float dtype).
    name : str
        The argument's name, used in the messages.
    shape : tuple of int or None, optional
        Expected shape; ``None`` entries match any size.
    finite : bool
        Refuse NaN and ±inf.
    bounded : bool
        Refuse an entry beyond :data:`MAX_MAGNITUDE` (1e12) in magnitude: measurements and sizes
        are bounded like every number of a robot file.

    Returns
    -------
    numpy.ndarray
        float64, of the expected shape.

    Raises
    ------
    InputError
        Naming ``name``: the shape differs, (with ``finite``) an entry is NaN or infinite, or (with
        ``bounded``) an entry is out of range.
    InputTypeError
        Complex values, strings, booleans or other objects (never cast silently).

    Examples
    --------
    >>> as_array([1, 2.5], "q", (2,))
    array([1. , 2.5])
    >>> as_array([1 + 2j], "q")
    Traceback (most recent call last):
    ...
    robokit.errors.InputTypeError: q: expected real numbers, got complex values (dtype complex128)
    """
    if type(x) is np.ndarray and x.dtype is _F64 and (shape is None or x.shape == shape) and not bounded:
        # the fast path (a float64 array of exactly the expected shape): a sum of a short array's
        # floats tests finiteness (an overflow to inf only sends a finite array to the full checks)
        if not finite or (x.size <= 64 and isfinite(sum(x.ravel().tolist()))):
            return x
    arr = _real_array(x, name)
    if shape is not None:
        ok = arr.ndim == len(shape) and all(s is None or s == d for s, d in zip(shape, arr.shape))
        if not ok:
            raise InputError(f"{name}: expected shape {shape_text(shape)}, got {_describe(arr)}")
    if finite and not np.isfinite(arr).all():
        raise InputError(f"{name}: contains NaN or infinite values")
    if bounded and arr.size:
        big = float(np.nanmax(np.abs(arr))) if np.isfinite(arr).any() else 0.0
        if big > MAX_MAGNITUDE:
            k = np.unravel_index(int(np.nanargmax(np.abs(arr))), arr.shape)
            at = f"[{', '.join(map(str, k))}]" if arr.ndim else ""
            raise InputError(f"{name}{at}: {float(arr[k]):g} is out of range (at most {MAX_MAGNITUDE:g} in magnitude; "
                             "SI units)")
    return arr


def ndim(x: object, name: str) -> int:
    """The number of dimensions of an array-like.

    Parameters
    ----------
    x : array_like
        The argument.
    name : str
        Its name, for the message.

    Returns
    -------
    int
        ``np.ndim(x)``: 0 for a scalar, 1 for a flat list, 2 for a list of rows…

    Raises
    ------
    InputError
        For a ragged nesting numpy cannot make an array of (``[[0, 0], [0]]``).

    Examples
    --------
    >>> ndim([[0.0, 1.0]], "q")
    2
    """
    try:
        return int(np.ndim(x))  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected an array of numbers, got a ragged {type(x).__name__}") from None


def as_joints(x: object, n: int, name: str = "q", robot: str = "", *, batch: bool = False) -> np.ndarray:
    """Joint values for a robot of ``n`` joints: a real, finite float64 vector (n,) — or, with
    ``batch``, rows (N, n), C-contiguous.

    Parameters
    ----------
    x : array_like
        Joint values (rad for revolute, m for prismatic joints).
    n : int
        The robot's number of joints.
    name : str
        The argument's name (``q``, ``dq``, ``tau``…).
    robot : str
        The robot's name, for the message.
    batch : bool
        Expect (N, n) rows instead of one (n,) vector.

    Returns
    -------
    numpy.ndarray
        (n,) or (N, n) float64.

    Raises
    ------
    InputError
        ``q: expected shape (6,) for puma560, got (5,)``; NaN/inf; complex, strings, booleans.

    Examples
    --------
    >>> as_joints([0, 0.5], 2, "q", "pendulum")
    array([0. , 0.5])
    """
    arr = _real_array(x, name)
    want = (None, n) if batch else (n,)
    if arr.ndim != len(want) or arr.shape[-1] != n:
        owner = f" for {robot}" if robot else ""
        shown = "(N, " + str(n) + ")" if batch else f"({n},)"
        raise InputError(f"{name}: expected shape {shown}{owner}, got {arr.shape}")
    if not np.isfinite(arr).all():
        raise InputError(f"{name}: contains NaN or infinite values" + ("" if batch else f" ({arr.tolist()})"))
    return np.ascontiguousarray(arr) if batch else arr


def as_int(x: object, name: str, *, minimum: int | None = None, maximum: int | None = None) -> int:
    """An integer argument (a count, an index, a seed): Python or numpy integers; never a bool,
    a float (``2.0`` included: a count written as a float is usually a mistake), a string.

    Parameters
    ----------
    x : int
        The value.
    name : str
        The argument's name, used in the messages.
    minimum, maximum : int, optional
        Inclusive bounds.

    Returns
    -------
    int
        ``x`` as a Python ``int`` (a numpy integer converted).

    Raises
    ------
    InputError
        Out of bounds.
    InputTypeError
        A bool, a float, a string or another type.

    Examples
    --------
    >>> as_int(3, "orientations", minimum=1)
    3
    >>> as_int(True, "n")
    Traceback (most recent call last):
    ...
    robokit.errors.InputTypeError: n: expected an integer, got bool True
    """
    import numbers

    if isinstance(x, (bool, np.bool_)) or not isinstance(x, numbers.Integral):
        raise InputTypeError(f"{name}: expected an integer, got {type(x).__name__} {x!r:.40}")
    v = int(x)
    if minimum is not None and v < minimum:
        raise InputError(f"{name}: expected an integer >= {minimum}, got {v}")
    if maximum is not None and v > maximum:
        raise InputError(f"{name}: expected an integer <= {maximum}, got {v}")
    return v


def as_vector(x: object, name: str, n: int | None = None) -> np.ndarray:
    """A 1-D float64 array of length ``n`` (any length if ``None``)."""
    return as_array(x, name, (n,))


def as_matrix(x: object, name: str, rows: int | None = None, cols: int | None = None) -> np.ndarray:
    """A 2-D float64 array of the given size (``None`` = any)."""
    return as_array(x, name, (rows, cols))


def as_scalar(x: object, name: str, *, positive: bool = False, nonnegative: bool = False,
              bounded: bool = False) -> float:
    """A finite float; optionally > 0 or >= 0, and (``bounded``) at most :data:`MAX_MAGNITUDE`
    in magnitude."""
    if (type(x) is float and isfinite(x) and (x > 0.0 or not positive) and (x >= 0.0 or not nonnegative)
            and (not bounded or abs(x) <= MAX_MAGNITUDE)):
        return x  # the fast path: a finite Python float within the bounds
    arr = as_array(x, name, (), bounded=bounded)
    v = float(arr)
    if positive and not v > 0:
        raise InputError(f"{name}: expected a positive number, got {v!r}")
    if nonnegative and not v >= 0:
        raise InputError(f"{name}: expected a non-negative number, got {v!r}")
    return v


def as_count(x: object, name: str, low: int, high: int) -> int:
    """An integer count (a number of samples, iterations, evaluations) in ``[low, high]``, checked
    before anything of that size is allocated or run.

    Parameters
    ----------
    x : int
        The count (a Python or numpy integer; ``True``, floats and strings are refused).
    name : str
        The argument's name, for the message.
    low, high : int
        Smallest and largest count accepted.

    Returns
    -------
    int
        The count as a Python ``int``.

    Raises
    ------
    InputError
        ``samples: expected an integer in 3..1000000, got 10000000000``.

    Examples
    --------
    >>> as_count(501, "samples", 3, 10**6)
    501
    """
    import numbers

    if isinstance(x, (bool, np.bool_)) or not isinstance(x, numbers.Integral) or not low <= int(x) <= high:
        raise InputError(f"{name}: expected an integer in {low}..{high}, got {x!r:.40}")
    return int(x)


#: The ``reference=`` vocabulary of every Jacobian (and tip-wrench) function: accepted string →
#: the canonical name, the value of :class:`robokit.frames.Frame` (Pinocchio's ``ReferenceFrame``
#: lower-cased). ``"space"``, ``"body"``, ``"tool"`` and ``"base"`` are the deprecated words.
REFERENCES: dict[str, str] = {**{f.value: f.value for f in Frame}, **FRAME_SYNONYMS}


def check_reference(reference: object, name: str = "reference") -> Frame:
    """The :class:`~robokit.frames.Frame` named by ``reference`` (see :func:`robokit.frames.as_frame`):
    a ``Frame``, its lower-case value, a ``pinocchio.ReferenceFrame`` or a deprecated word (which
    warns once), else :class:`InputError` listing every accepted name. A ``Frame`` compares equal
    to its lower-case value, so ``check_reference("base") == "local_world_aligned"``."""
    return as_frame(reference, name)


# ---------------------------------------------------------------------------------------------
# arguments as the compiled kernels take them (the seed functions' fast paths)

#: numpy's flag bits for C-contiguous, aligned and writeable: what a kernel signature's
#: ``float64[::1]`` arrays must be (numba refuses a read-only or strided array for them).
_KERNEL_FLAGS = 0x0001 | 0x0100 | 0x0400
_WRITEABLE = 0x0400


def kernel_array(x: object, dtype: Any = None) -> np.ndarray:
    """``x`` as a compiled kernel takes an array: C-contiguous and writeable (a copy only when it is
    not — a Robot's read-only ``qlim``/``gravity`` included).

    Parameters
    ----------
    x : array_like
        The values (already checked).
    dtype : dtype, optional
        As :func:`numpy.ascontiguousarray`.

    Returns
    -------
    numpy.ndarray

    Examples
    --------
    >>> a = np.zeros(3); a.setflags(write=False)
    >>> kernel_array(a).flags.writeable, kernel_array(np.ones(2)).flags.c_contiguous
    (True, True)
    """
    a = np.ascontiguousarray(x, dtype)
    if a.flags.writeable:
        return a
    base = writeable_base(a)
    return a.copy() if base is None else base


def writeable_base(x: np.ndarray) -> np.ndarray | None:
    """The writeable array a read-only float64 array is a plain view of, else None.

    A :class:`~robokit.description.robot.Robot` shows its PoE parameters (``robot.poe``) as read-only
    views of private arrays built once; the compiled kernels, whose signatures take writeable arrays
    and which only read their model arguments, are given those arrays (no copy per call). A view
    qualifies when it is float64 with its base's shape and strides and its base is a writeable,
    C-contiguous, aligned float64 array: then it is the whole of its base, read the same way (a view
    addresses memory within its base's extent — numpy's ``base`` is the array that holds the memory —
    and the same shape and strides span that whole extent).

    Parameters
    ----------
    x : numpy.ndarray
        A read-only array.

    Returns
    -------
    numpy.ndarray or None
        ``x.base`` when it qualifies.

    Examples
    --------
    >>> a = np.zeros((2, 3)); v = a.view(); v.flags.writeable = False
    >>> writeable_base(v) is a, writeable_base(a[:, :2].copy()) is None
    (True, True)
    """
    b = x.base
    if (type(b) is np.ndarray and b.shape == x.shape and b.strides == x.strides and b.dtype is _F64
            and x.dtype is _F64 and b.flags.num & _KERNEL_FLAGS == _KERNEL_FLAGS):
        return b
    return None


def kernel_arrays(args: tuple[Any, ...], ndims: tuple[int, ...], _nd: Any = np.ndarray, _f: np.dtype = _F64,
                  _k: int = _KERNEL_FLAGS) -> tuple[np.ndarray, ...] | None:
    """The arguments as a compiled kernel's signature takes them — float64, C-contiguous, writeable
    arrays of the given numbers of dimensions — after at most one conversion each; None when one of
    them is not plainly an array of real numbers of that dimension (the caller's full checks then name it).

    Arrays that already fit are passed through as they are (no copy); other arrays (read-only,
    strided, transposed, integer) are copied once; lists and tuples (``Mlist``, ``Glist`` as the
    Modern Robotics book writes them: lists of arrays) are converted once with ``np.asarray`` —
    about 1 µs for a UR5's ``Mlist``, less than reading its elements' bytes to look a packed copy
    up would cost, so nothing is remembered between calls. Nothing is cast that :func:`as_array`
    would refuse (booleans, complex values, strings, objects). Values (finiteness) and sizes are
    left to the kernel, which checks them.

    Parameters
    ----------
    args : tuple
        The arguments, in the kernel's order.
    ndims : tuple of int
        The number of dimensions the kernel's signature gives each argument.
    _nd, _f, _k
        Not arguments: numpy's array type, float64 and the flag bits, bound as locals (the check
        runs on every seed-function call).

    Returns
    -------
    tuple of numpy.ndarray, or None

    Examples
    --------
    >>> a = np.zeros(3)
    >>> M, q = kernel_arrays(([np.eye(2), np.eye(2)], a), (3, 1))
    >>> M.shape, M.flags.c_contiguous, q is a
    ((2, 2, 2), True, True)
    >>> kernel_arrays(([True, False],), (1,)) is None  # booleans are refused, not cast
    True
    """
    i = 0
    for x in args:  # the common case first: every argument already fits, passed on as it is
        if type(x) is not _nd or x.dtype is not _f or x.ndim != ndims[i] or x.flags.num & _k != _k:
            return _converted(args, ndims)
        i += 1
    return args


def _converted(args: tuple[Any, ...], ndims: tuple[int, ...]) -> tuple[np.ndarray, ...] | None:
    """:func:`kernel_arrays` when some argument needs converting."""
    out = []
    for x, nd in zip(args, ndims):
        if type(x) is np.ndarray:
            flags = x.flags.num
            if x.dtype is _F64 and flags & _KERNEL_FLAGS == _KERNEL_FLAGS:
                arr = x
            elif not flags & _WRITEABLE and (base := writeable_base(x)) is not None:
                arr = base  # a read-only view (a Robot's poe) of a writeable array: the kernels only read it
            elif x.dtype.kind in "fiu":
                arr = np.array(x, dtype=np.float64, order="C")  # a fresh copy: contiguous, writeable
            else:
                return None
        elif type(x) is list or type(x) is tuple:
            found = _seen(x) if nd >= 2 else None
            if found is not None:
                arr = found
            else:
                try:
                    a = np.asarray(x)  # a new array (C order, writeable), even of read-only elements
                except (TypeError, ValueError):  # ragged
                    return None
                if a.dtype.kind not in "fiu":
                    return None
                arr = a if a.dtype is _F64 else a.astype(np.float64)
                if arr.ndim == nd >= 2:
                    _remember(x, arr)
        else:
            return None
        if arr.ndim != nd:
            return None
        out.append(arr)
    return tuple(out)


# Nested lists of numbers (``Mlist``, ``Glist``, ``Slist`` written out as Python lists, as a course
# notebook may): numpy's conversion costs 1–6 µs per argument (a UR5's Glist: 216 floats), more
# than the compiled call itself. The model's lists are usually the same objects call after call,
# so the last few conversions are remembered by the list's id() together with a snapshot of its
# structure (new lists holding the very same number objects); a later call reuses a conversion only
# when the argument still compares equal (==) to that snapshot: a list changed in place, or a new
# list that reuses a freed id(), compares unequal and is converted afresh. The comparison is done in
# C and mostly on identical objects: about 0.3 µs for a UR5's Mlist. Only lists nested two or more
# deep whose leaves are all Python ints and floats are remembered (never arrays: an element compared
# with an array has no single truth value; never booleans, which as_array refuses). Results are
# those of the fresh conversion: equal lists of numbers convert to equal float64 arrays (up to the
# sign of a zero: 0.0 == -0.0; and a remembered list changed in place to values that still compare
# equal — 1 to True, 1.0 to 1+0j — reuses its earlier conversion instead of being refused). The
# kernels never write their inputs, so one array serves every call.
_SEEN: dict[int, tuple[Any, np.ndarray]] = {}
_SEEN_MAX = 32


def _seen(x: Any) -> np.ndarray | None:
    """The remembered conversion of the nested list x, if x still equals its snapshot."""
    entry = _SEEN.get(id(x))
    if entry is None:
        return None
    try:
        same = entry[0] == x
    except (TypeError, ValueError):  # e.g. an element that is an array now
        return None
    return entry[1] if same is True else None


def _snapshot(x: Any) -> Any:
    """A structural copy of nested lists/tuples holding the same leaf objects, or None when a leaf
    is not a Python int or float (bool excluded)."""
    out = []
    for e in x:
        t = type(e)
        if t is float or t is int:
            out.append(e)
        elif t is list or t is tuple:
            sub = _snapshot(e)
            if sub is None:
                return None
            out.append(sub)
        else:
            return None
    return out if type(x) is list else tuple(out)


def _remember(x: Any, arr: np.ndarray) -> None:
    snap = _snapshot(x)
    if snap is None:
        return
    if len(_SEEN) >= _SEEN_MAX:
        try:  # the oldest (another thread may have taken it already)
            _SEEN.pop(next(iter(_SEEN)), None)
        except (StopIteration, RuntimeError):
            pass
    _SEEN[id(x)] = (snap, arr)

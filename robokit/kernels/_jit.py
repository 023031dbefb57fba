r"""How the course kernels are compiled: numba ``@njit(cache=True)``, and a one-line notice
on stderr the first time they are compiled.

Compilation and its cache
-------------------------
Every kernel is compiled by numba the first time a process uses it and written to numba's
on-disk cache; later processes load the machine code from there (a fraction of a second)
instead of compiling again. numba picks the cache directory in this order:

1. ``$NUMBA_CACHE_DIR`` when that environment variable is set;
2. the ``__pycache__`` folder next to the kernel's source file (``robokit/kernels/__pycache__``)
   when it can be written;
3. otherwise (for example a read-only ``site-packages``) a per-user folder,
   ``~/.cache/numba/…`` on Linux (numba's ``user_cache_dir``).

:func:`cache_dir` reports the folder one kernel actually uses. A cache entry is reused only
for the same source file contents, numba version and CPU; otherwise numba compiles again.

The notice
----------
``compiling course kernels (first run only) ...`` is printed once per process to stderr when
a kernel of this package misses the cache and is compiled. Detection costs nothing per call:
numba announces every compilation (its ``numba:compile`` event, fired only after a cache
miss), and a listener installed here prints on the first one that belongs to
``robokit.kernels``.

Setting ``NUMBA_DISABLE_JIT=1`` runs the very same source as plain Python (slow, but every
line can be stepped through in a debugger); nothing is compiled and no notice is printed.
"""
from __future__ import annotations

import sys
from typing import Any, Callable, TypeVar, overload

import numba
from numba.core import event as _event

__all__ = ["njit", "prange", "cache_dir", "jit_disabled"]

prange = numba.prange

_F = TypeVar("_F", bound=Callable[..., Any])

_NOTICE = "compiling course kernels (first run only) ..."


def jit_disabled() -> bool:
    """True when ``NUMBA_DISABLE_JIT`` is set: the kernels then run as plain Python."""
    return bool(getattr(numba.config, "DISABLE_JIT"))


@overload
def njit(signature: _F, *, parallel: bool = False) -> _F: ...
@overload
def njit(signature: str | None = None, *, parallel: bool = False) -> Callable[[_F], _F]: ...
def njit(signature: Any = None, *, parallel: bool = False) -> Any:
    """``numba.njit`` with this package's settings: on-disk cache, numpy's error model (a division
    by zero gives inf/NaN rather than raising, as numpy does), no fast-math (results must match
    Pinocchio to rounding). With a ``signature`` the kernel is compiled for exactly those
    argument types (contiguous float64 arrays), so no second specialisation is ever built;
    calling it with other types raises ``TypeError``.

    Used bare (``@njit``) for the small helpers, which compile as part of the kernel that calls them.
    """
    options: dict[str, Any] = dict(cache=True, error_model="numpy", parallel=parallel)
    if callable(signature):  # bare @njit
        return numba.njit(**options)(signature)
    if signature is None:
        return numba.njit(**options)
    return numba.njit(signature, **options)


class _CompileNotice(_event.Listener):
    """Prints the notice once, on the first compilation of a robokit kernel (a cache miss)."""

    printed = False

    def on_start(self, ev: _event.Event) -> None:
        if _CompileNotice.printed:
            return
        dispatcher = (ev.data or {}).get("dispatcher")
        func = getattr(dispatcher, "py_func", None)
        if func is not None and getattr(func, "__module__", "").startswith("robokit.kernels"):
            _CompileNotice.printed = True
            print(_NOTICE, file=sys.stderr, flush=True)

    def on_end(self, ev: _event.Event) -> None:
        pass


if not getattr(sys.modules[__name__], "_LISTENING", False):
    _event.register("numba:compile", _CompileNotice())
    _LISTENING = True


def cache_dir(kernel: object) -> str | None:
    """The folder where numba keeps ``kernel``'s compiled code (see the module docstring for the
    order numba tries), or None when the kernel is not cached (``NUMBA_DISABLE_JIT=1``).

    Example: ``cache_dir(robokit.kernels.poe.fkin_space_kernel)``.
    """
    cache = getattr(kernel, "_cache", None)
    impl = getattr(cache, "_impl", None)
    locator = getattr(impl, "locator", None)
    return None if locator is None else locator.get_cache_path()

r"""How the course kernels are compiled: numba ``@njit(cache=True)``, lazily on first call, with a
one-line notice on stderr for each kernel compiled.

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

Lazy compilation
----------------
Kernels declared with a signature (:func:`njit` ``(signature)``) compile on their **first call**,
not when their module is imported: a program compiles only the kernels it calls, and a parallel
``*_batch`` twin only on its first batched call. :func:`compile_now` does the same ahead of time,
and ``python -m robokit.kernels`` (:mod:`robokit.kernels.warm`) compiles every kernel in parallel
worker processes.

The notice
----------
When a kernel misses the cache and is compiled, one line goes to stderr, e.g.
``robokit: compiling dynamics kernels (2/9: inverse_dynamics) - each kernel once per machine on
first use, then loaded from numba's cache ...``: which kernel, and how many of its module's
kernels this process has compiled so far. Detection costs nothing per call: numba announces
every compilation (its ``numba:compile`` event, fired only after a cache miss), and a listener
installed here prints for the kernels of ``robokit.kernels`` (not for the small helpers compiled
inside them).

Setting ``NUMBA_DISABLE_JIT=1`` runs the very same source as plain Python (slow, but every
line can be stepped through in a debugger); nothing is compiled and no notice is printed.
"""
from __future__ import annotations

import sys
from typing import Any, Callable, TypeVar, overload

import numba
from numba.core import event as _event
from numba.core.dispatcher import Dispatcher

__all__ = ["njit", "prange", "cache_dir", "jit_disabled", "compile_now"]

prange = numba.prange

_F = TypeVar("_F", bound=Callable[..., Any])



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
    Pinocchio to rounding).

    With a ``signature`` the kernel is compiled for exactly those argument types (contiguous
    float64 arrays) — **lazily**, on its first call, not when its module is imported: the first
    call compiles that one signature (or loads it from numba's on-disk cache), then switches
    further compilation off, so no second specialisation is ever built and calling it with other
    types raises ``TypeError``. A parallel batch twin therefore costs nothing until the first
    batched call.

    Used bare (``@njit``) for the small helpers, which compile as part of the kernel that calls them.
    """
    options: dict[str, Any] = dict(cache=True, error_model="numpy", parallel=parallel)
    if callable(signature):  # bare @njit
        return numba.njit(**options)(signature)
    if signature is None:
        return numba.njit(**options)

    def decorate(func: _F) -> _F:
        dispatcher = numba.njit(**options)(func)
        if isinstance(dispatcher, Dispatcher):  # not under NUMBA_DISABLE_JIT
            _compile_on_first_call(dispatcher, signature)
        return dispatcher

    return decorate


def _compile_on_first_call(dispatcher: Dispatcher, signature: str) -> None:
    """Make ``dispatcher`` compile ``signature`` the first time it is called.

    numba's dispatcher calls its ``_compile_for_args`` when no compiled version matches the
    arguments; this replaces it, for this one dispatcher, by: compile the declared signature,
    disable further compilation, and hand back the dispatcher itself, which numba then calls with
    the arguments (a type mismatch then raises ``TypeError``). After the first call the dispatcher
    runs at full speed: the replacement is never reached again."""
    module = dispatcher.py_func.__module__.rsplit(".", 1)[-1]
    _KERNELS.setdefault(module, []).append(dispatcher.py_func.__name__)
    dispatcher._robokit_signature = signature  # type: ignore[attr-defined]

    def first_call(*args: Any, **kwargs: Any) -> Dispatcher:
        compile_now(dispatcher)
        return dispatcher

    setattr(dispatcher, "_compile_for_args", first_call)  # numba's hook, for this dispatcher only


def compile_now(kernel: Any) -> None:
    """Compile ``kernel``'s declared signature now (or load it from numba's cache) and switch
    further compilation off — what its first call would do. Nothing for a helper without a
    signature, or under ``NUMBA_DISABLE_JIT``.

    Example: ``compile_now(robokit.kernels.poe.fkin_space)``.
    """
    signature = getattr(kernel, "_robokit_signature", None)
    if signature is not None and isinstance(kernel, Dispatcher) and getattr(kernel, "_can_compile", False):
        kernel.compile(signature)
        kernel.disable_compile()


#: True in the worker processes of :mod:`robokit.kernels.warm` (their parent prints the progress).
quiet = False


#: The kernels declared with a signature, by kernel module (``"poe"`` → ``["fkin_space", …]``), in
#: definition order: what the notice counts.
_KERNELS: dict[str, list[str]] = {}
_COMPILED: dict[str, set[str]] = {}


def notice(module: str, name: str) -> str:
    """The line printed when kernel ``module.name`` is compiled (a cache miss), e.g.
    ``robokit: compiling dynamics kernels (3/11: mass_matrix) ...``: how many of that module's
    kernels this process has compiled so far, of how many the module has."""
    done = _COMPILED.setdefault(module, set())
    done.add(name)
    total = max(len(_KERNELS.get(module, ())), len(done))
    return (f"robokit: compiling {module} kernels ({len(done)}/{total}: {name}) - each kernel once per machine "
            "on first use, then loaded from numba's cache ...")


class _CompileNotice(_event.Listener):
    """Prints one line as each robokit kernel starts compiling (a cache miss; helpers compiled
    inside a kernel are not counted)."""

    def on_start(self, ev: _event.Event) -> None:
        dispatcher = (ev.data or {}).get("dispatcher")
        func = getattr(dispatcher, "py_func", None)
        module = getattr(func, "__module__", "")
        if not module.startswith("robokit.kernels."):
            return
        module = module.rsplit(".", 1)[-1]
        name = getattr(func, "__name__", "?")
        if not quiet and name in _KERNELS.get(module, ()) and name not in _COMPILED.get(module, ()):
            print(notice(module, name), file=sys.stderr, flush=True)

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

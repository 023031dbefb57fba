r"""How the course kernels are compiled: numba ``@njit(cache=True)``, lazily on first call, and —
on a cache miss — in a background process while the first calls run as plain Python.

Compilation and its cache
-------------------------
Every kernel is compiled by numba once per machine and written to numba's on-disk cache; later
processes load the machine code from there (milliseconds per kernel) instead of compiling again.
numba picks the cache directory in this order:

1. ``$NUMBA_CACHE_DIR`` when that environment variable is set;
2. the ``__pycache__`` folder next to the kernel's source file (``robokit/kernels/__pycache__``)
   when it can be written;
3. otherwise (for example a read-only ``site-packages``) a per-user folder,
   ``~/.cache/numba/…`` on Linux (numba's ``user_cache_dir``).

:func:`cache_dir` reports the folder one kernel actually uses. A cache entry is reused only
for the same numba version and CPU and the same text of *every* kernel file (numba itself looks at
the kernel's own file only; :mod:`robokit.kernels._cache` adds the others, which kernels call
across files); otherwise numba compiles again.

The first call
--------------
Kernels declared with a signature (:func:`njit` ``(signature)``) are not compiled when their
module is imported but on their **first call**, which depends on ``$ROBOKIT_COMPILE``
(:func:`compile_mode`):

``background`` (the default)
    A cache hit loads the machine code at once. On a cache miss the kernel is handed to a
    **background compile worker** — one child process per process (:mod:`robokit.kernels._background`)
    that compiles the kernels it is sent, one at a time, into the same numba cache — and the call
    runs the kernel's **interpreted twin** (:func:`interpreted`: the same source as plain Python,
    exactly what ``NUMBA_DISABLE_JIT=1`` runs). Each later call that still finds no machine code
    reads the worker's finished-notices (a non-blocking read of a pipe) and, once its kernel is
    done, loads it from the cache and switches to it for good. Kernels that should not run as
    Python — a large call of a parallel ``*_batch`` twin (10⁴ configurations as Python take far
    longer than compiling; small batches do run as Python) and the simulation loops — are sent
    to the front of the worker's queue and the call waits for them (:func:`njit`'s
    ``interpret_while_compiling``). The worker keeps going after its
    parent exits until every kernel it was sent is in the cache, so the next process is warm.
    When no worker can be started, or it fails, the kernel is compiled in the calling process,
    with a one-line note.
``wait``
    Compile in the calling process before running (a cache hit loads at once): robokit's
    behaviour before the background worker, and what the test suite uses (deterministic).
``off``
    Never compile: cached machine code is used when there is some, otherwise the kernel runs
    as plain Python.

Only the call that finds no machine code goes through any of this (numba's dispatcher calls
the hook ``_compile_for_args`` only then); once a kernel runs machine code its calls cost what
numba's dispatch costs, nothing more. The switch is guarded by a lock, so kernels may be called
from several threads. :func:`compile_now` compiles one kernel ahead of time, and
``python -m robokit.kernels`` (:mod:`robokit.kernels.warm`) every kernel, in parallel processes.

The notice
----------
The first background compile of a process prints one line to stderr, e.g. ``robokit: compiling
course kernels in the background (pid 1234; first poe.fkin_space) - running them as plain Python
until each is ready; later runs load them from numba's cache``; on a terminal, one short line as
each kernel switches to machine code; at exit, when the worker still has kernels to finish, how
many. A kernel compiled in the calling process (``wait``, or a fallback) prints
``robokit: compiling dynamics kernels (2/9: inverse_dynamics) - each kernel once per machine on
first use, then loaded from numba's cache ...``: which kernel, and how many of its module's
kernels this process has compiled so far; numba announces every compilation (its
``numba:compile`` event, fired only after a cache miss) and a listener installed here prints for
the kernels of ``robokit.kernels``. A batch or simulation kernel that waits for the worker says so,
then how long it has waited (the same line rewritten each second on a terminal, a line every 10 s
otherwise: a first ``simulate`` on a new machine can wait a minute) and, at the end, how long it took.

Setting ``NUMBA_DISABLE_JIT=1`` runs the very same source as plain Python (slow, but every
line can be stepped through in a debugger); nothing is compiled, no worker is started and no
notice is printed.
"""
from __future__ import annotations

import atexit
import os
import sys
import threading
import types as _pytypes
from typing import Any, Callable, TypeVar, overload

import numba
import numpy as np
from numba.core import event as _event
from numba.core import sigutils as _sigutils
from numba.core.compiler_lock import global_compiler_lock as _compiler_lock
from numba.core.dispatcher import Dispatcher, OmittedArg
from numba.core import types as _nbtypes

from robokit.kernels import ENV, MODES, compile_mode
from robokit.kernels import _cache

_cache.install()  # before any kernel is decorated: numba picks a function's cache locator then

__all__ = ["njit", "prange", "cache_dir", "jit_disabled", "compile_now", "compile_mode", "interpreted", "MODES",
           "ENV", "SMALL_BATCH", "FK_BATCH", "held_notices"]

prange = numba.prange

_F = TypeVar("_F", bound=Callable[..., Any])

#: The largest batch (configurations × joints, or targets) a ``parallel`` kernel runs as plain
#: Python while it compiles; larger calls wait for the machine code. Chosen where running as
#: Python stops being quicker than waiting for the compile (measured on UR5, 2 cores under load:
#: the mass-matrix batch as Python costs about 1 ms per configuration and joint, its compile 9 s).
SMALL_BATCH = 6000
#: The same for the kinematics batches (FK and Jacobians as Python: about 70 µs per configuration
#: and joint — 10⁴ UR5 configurations in 4–5 s against a 6–7 s compile).
FK_BATCH = 60000


def jit_disabled() -> bool:
    """True when ``NUMBA_DISABLE_JIT`` is set: the kernels then run as plain Python.

    Returns
    -------
    bool

    Examples
    --------
    >>> isinstance(jit_disabled(), bool)
    True
    """
    return bool(getattr(numba.config, "DISABLE_JIT"))


@overload
def njit(signature: _F, *, parallel: bool = False, interpret_while_compiling: bool | int | None = None,
         inline: bool = False, refcount: bool = True, contract: bool = False) -> _F: ...
@overload
def njit(signature: str | None = None, *, parallel: bool = False,
         interpret_while_compiling: bool | int | None = None, inline: bool = False,
         refcount: bool = True, contract: bool = False) -> Callable[[_F], _F]: ...
def njit(signature: Any = None, *, parallel: bool = False, interpret_while_compiling: bool | int | None = None,
         inline: bool = False, refcount: bool = True, contract: bool = False) -> Any:
    """``numba.njit`` with this package's settings: on-disk cache, numpy's error model (a division
    by zero gives inf/NaN rather than raising, as numpy does), no fast-math (results must match
    Pinocchio to rounding; only ``contract`` below, where a kernel asks for it), and the first-call
    policy of the module docstring.

    Parameters
    ----------
    signature : str or callable, optional
        The one numba signature the kernel is compiled for (contiguous float64 arrays). With a
        signature the kernel is compiled **lazily**, on its first call, not when its module is
        imported, and then further compilation is switched off: no second specialisation is ever
        built and calling it with other types raises ``TypeError``. Without one (bare ``@njit``,
        the small helpers and a few kernels taking mixed types) numba compiles per argument types;
        helpers compile as part of the kernel that calls them.
    parallel : bool
        numba's ``parallel=True`` (``prange`` loops over the CPU cores): the ``*_batch`` twins.
    interpret_while_compiling : bool or int, optional
        Whether a call that finds no machine code may run the kernel as plain Python while the
        background worker compiles it (``ROBOKIT_COMPILE=background``); an int: only while the
        call's batch — configurations × joints of its ``thetas``/``Q`` argument, or targets of
        ``Ts`` — is at most that, larger calls wait for the machine code. Default: True, and
        :data:`SMALL_BATCH` for ``parallel`` kernels (a batch over 10⁴ configurations as plain
        Python takes far longer than compiling). Kernels whose call is one long loop (the
        compiled simulation) pass False: they always wait.
    inline : bool
        numba's ``inline="always"``: a small helper called in a hot loop is copied into each
        kernel that calls it (numba's own inlining, before LLVM) rather than called. A call that
        LLVM does not inline passes every array as its data pointer, shape, strides and reference
        count, which costs tens of nanoseconds per call: measured on the calibrated IK's Newton
        polish, about a quarter of its time.
    refcount : bool
        False compiles the kernel without numba's reference counting (its runtime option ``_nrt``):
        every array view it takes (``work[8:14]``) and every array it is passed or passes on then
        costs nothing, where numba otherwise counts each one up and down with atomic instructions
        (tens of nanoseconds each: measured, about a fifth of the calibrated IK's Newton polish).
        Only for a kernel that creates no array (``np.empty`` and friends do not compile there)
        and keeps no view beyond the call (its caller's arrays outlive it) — and whose callees
        create none either: numba compiles the kernels it calls, when they have no machine code for
        those types yet, without reference counting too (a callee that allocates then fails to
        compile on a cold cache only).
    contract : bool
        Fused multiply-add: ``a·b + c`` in one rounding where the machine has FMA instructions
        (LLVM's ``contract``, the one fast-math flag allowed: no reordering of sums, no assumption
        about NaN, infinity or signed zeros, so every test of them stays as written). The result of
        each fused step is the exact one rounded once, where the unfused is rounded twice; a
        kernel's results then differ from the unfused ones by rounding (not to the bit). For
        arithmetic-bound kernels: measured on the calibrated IK's polish, 4–5 % of the UR5's solve;
        on the closed forms (bound by atan2, sqrt, sin and cos) no change. Every kernel states its
        fast-math (off unless asked), so a kernel it calls and numba compiles for it does not take
        the caller's (numba's kernels otherwise inherit their caller's flags, as with ``refcount``):
        only the helpers copied into it (``inline``) are fused.

    Returns
    -------
    numba Dispatcher (or the plain function under ``NUMBA_DISABLE_JIT``), or a decorator.

    Examples
    --------
    >>> import numpy as np
    >>> @njit("float64(float64[::1])")
    ... def total(x):
    ...     s = 0.0
    ...     for v in x:
    ...         s += v
    ...     return s
    >>> total(np.arange(4.0))
    6.0
    """
    options: dict[str, Any] = dict(cache=True, error_model="numpy", parallel=parallel)
    if inline:
        options["inline"] = "always"
    if not refcount:
        options["_nrt"] = False
    options["fastmath"] = {"contract"} if contract else False
    if interpret_while_compiling is None:
        interpret = SMALL_BATCH if parallel else sys.maxsize
    elif isinstance(interpret_while_compiling, bool):
        interpret = sys.maxsize if interpret_while_compiling else -1
    else:
        interpret = int(interpret_while_compiling)

    def decorate(func: _F, sig: str | None) -> _F:
        dispatcher = numba.njit(**options)(func)
        if isinstance(dispatcher, Dispatcher):  # not under NUMBA_DISABLE_JIT
            _install_first_call(dispatcher, sig, interpret)
        return dispatcher

    if callable(signature):  # bare @njit
        return decorate(signature, None)
    return lambda func: decorate(func, signature)


def _install_first_call(dispatcher: Dispatcher, signature: str | None, interpret: int) -> None:
    """Route ``dispatcher``'s calls that find no machine code through :func:`_first_call`.

    numba's dispatcher calls its ``_compile_for_args`` when no compiled version matches the
    arguments, and then calls whatever that returns with the same arguments: the dispatcher itself
    once machine code has been added, or here the kernel's interpreted twin while the worker is
    compiling. Once compiled, a signatured kernel has compilation switched off and this is never
    reached again: calls go straight to the machine code at full speed."""
    dispatcher._robokit_signature = signature  # type: ignore[attr-defined]
    dispatcher._robokit_interpret = interpret  # type: ignore[attr-defined]
    if signature is not None:
        module = dispatcher.py_func.__module__.rsplit(".", 1)[-1]
        _KERNELS.setdefault(module, []).append(dispatcher.py_func.__name__)

    def first_call(*args: Any, **kwargs: Any) -> Any:
        return _first_call(dispatcher, args)

    setattr(dispatcher, "_compile_for_args", first_call)  # numba's hook, for this dispatcher only


def compile_now(kernel: Any) -> None:
    """Compile ``kernel``'s declared signature now in this process (or load it from numba's
    cache) and switch further compilation off — what its first call does with
    ``ROBOKIT_COMPILE=wait``. Nothing for a kernel without a signature, or under
    ``NUMBA_DISABLE_JIT``.

    Parameters
    ----------
    kernel : numba Dispatcher
        A kernel declared with :func:`njit` ``(signature)``.

    Returns
    -------
    None

    Examples
    --------
    ``compile_now(robokit.kernels.poe.fkin_space)``.
    """
    signature = getattr(kernel, "_robokit_signature", None)
    if signature is not None and isinstance(kernel, Dispatcher) and getattr(kernel, "_can_compile", False):
        kernel.compile(signature)
        kernel.disable_compile()


# ---------------------------------------------------------------------------------------------
# the interpreted twins


_TWINS: dict[int, tuple[Dispatcher, Callable[..., Any]]] = {}
_TWIN_GLOBALS: dict[int, dict[str, Any]] = {}


def interpreted(kernel: Any) -> Callable[..., Any]:
    """The kernel as plain Python: its source function run with a copy of its module's globals in
    which every numba dispatcher (helpers, other kernels, ones imported from sibling modules) is
    replaced by its own interpreted twin — what ``NUMBA_DISABLE_JIT=1`` runs, for this kernel only.
    Built once per kernel.

    Parameters
    ----------
    kernel : numba Dispatcher or function

    Returns
    -------
    callable
        Same arguments and results as the kernel (numpy semantics: a Python-float division by
        zero raises where the compiled kernel gives inf).

    Examples
    --------
    >>> import numpy as np
    >>> from robokit.kernels import poe
    >>> interpreted(poe.fkin_space)(np.eye(4), np.eye(6)[:, :2].copy(), np.zeros(2))[0, 0]
    np.float64(1.0)
    """
    if not isinstance(kernel, Dispatcher):
        return kernel
    with _LOCK:
        return _twin(kernel)


def _twin(dispatcher: Dispatcher) -> Callable[..., Any]:
    found = _TWINS.get(id(dispatcher))
    if found is not None:
        return found[1]
    func = dispatcher.py_func
    twin = _pytypes.FunctionType(func.__code__, _twin_globals(func.__globals__), func.__name__, func.__defaults__,
                                 func.__closure__)
    twin.__kwdefaults__ = func.__kwdefaults__
    twin.__qualname__, twin.__doc__, twin.__module__ = func.__qualname__, func.__doc__, func.__module__
    _TWINS[id(dispatcher)] = (dispatcher, twin)
    return twin


def _twin_globals(module_globals: dict[str, Any]) -> dict[str, Any]:
    found = _TWIN_GLOBALS.get(id(module_globals))
    if found is None:
        found = _TWIN_GLOBALS[id(module_globals)] = dict(module_globals)  # memoised before filling: cycles end
        for key, value in module_globals.items():
            if isinstance(value, Dispatcher):
                found[key] = _twin(value)
            elif value is np:
                found[key] = _NUMPY
    return found


class _NumpyOwnRandom(_pytypes.ModuleType):
    """numpy as the twins see it: ``np.random`` is a generator of their own, one per thread, as
    numba's is — the same legacy Mersenne Twister, so ``np.random.seed(s)`` then ``uniform`` gives
    the compiled kernel's very numbers, without touching the user's global numpy generator."""

    _local = threading.local()

    def __getattr__(self, name: str) -> Any:
        return getattr(np, name)

    @property
    def random(self) -> Any:
        state = getattr(self._local, "state", None)
        if state is None:
            state = self._local.state = np.random.RandomState()
        return state


_NUMPY = _NumpyOwnRandom("numpy")
_NUMPY.__dict__.update({k: v for k, v in vars(np).items() if k != "random"})


# ---------------------------------------------------------------------------------------------
# the first call


_LOCK = threading.RLock()


class _Job:
    """One kernel signature handed to the background worker."""

    def __init__(self, number: int, dispatcher: Dispatcher, sig: Any) -> None:
        self.number, self.dispatcher, self.sig = number, dispatcher, sig
        self.state = "queued"  # → "ready" (in the cache) / "failed" (detail says why) / "loaded"
        self.detail = ""
        self.urgent = False
        self.module, self.func_name = dispatcher.py_func.__module__, dispatcher.py_func.__name__

    @property
    def name(self) -> str:
        func = self.dispatcher.py_func
        return f"{func.__module__.rsplit('.', 1)[-1]}.{func.__name__}"


class _Background:
    """This process's background compiles: the worker, the jobs, what has been said."""

    def __init__(self) -> None:
        self.worker: Any = None
        self.jobs: dict[tuple[int, Any], _Job] = {}
        self.by_number: dict[int, _Job] = {}
        self.checked: set[tuple[int, Any]] = set()  # looked up in the cache once already (mode "off")
        self.announced = False
        self.unavailable = ""  # why no worker could be used (then compiles happen in this process)
        self.exit_hook = False


_BG = _Background()


def _forget_worker_in_child() -> None:
    """After ``os.fork`` (multiprocessing's fork start method, Dask's forking workers) the child
    must not share its parent's worker pipes: it starts afresh with a worker of its own."""
    global _BG, _LOCK
    _BG, _LOCK = _Background(), threading.RLock()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_worker_in_child)


def _key(dispatcher: Dispatcher, sig: Any) -> tuple[int, Any]:
    return id(dispatcher), sig


def _fingerprint(args: tuple[Any, ...]) -> tuple[Any, ...] | None:
    """A cheap key for the numba types of ``args`` (arrays, Python scalars), or None."""
    parts: list[Any] = []
    for a in args:
        if isinstance(a, np.ndarray):
            f = a.flags
            parts.append((a.dtype.str, a.ndim, f.c_contiguous, f.f_contiguous, f.writeable, f.aligned))
        elif type(a) in (float, int, bool):
            parts.append(type(a))
        else:
            return None
    return tuple(parts)


def _argtypes(dispatcher: Dispatcher, args: tuple[Any, ...], fingerprint: tuple[Any, ...] | None = None) -> tuple[Any, ...]:
    """numba's types of ``args``, memoised by :func:`_fingerprint` (numba's ``typeof`` of an array
    costs tens of µs, and an interpreted kernel passes here on every call until it is compiled)."""
    found = _TYPES.get(fingerprint) if fingerprint is not None else None
    if found is None:
        found = tuple(_nbtypes.Omitted(a.value) if isinstance(a, OmittedArg) else dispatcher.typeof_pyval(a)
                      for a in args)
        if fingerprint is not None:
            _TYPES[fingerprint] = found
    return found


_TYPES: dict[tuple[Any, ...], tuple[Any, ...]] = {}


def _check_types(dispatcher: Dispatcher, signature: str, actual: tuple[Any, ...]) -> None:
    """TypeError, as the compiled kernel would raise, when argument types ``actual`` do not fit
    ``signature``."""
    formal, _ = _sigutils.normalize_signature(signature)
    if len(actual) != len(formal) or any(dispatcher.typingctx.can_convert(a, f) is None
                                         for a, f in zip(actual, formal)):
        raise TypeError(f"No matching definition for argument type(s) {', '.join(map(str, actual))}")


#: Per kernel, the argument fingerprints already checked against its signature.
_ACCEPTED: dict[int, set[tuple[Any, ...]]] = {}


def _load_cached(dispatcher: Dispatcher, sig: Any) -> bool:
    """Add ``sig``'s machine code from numba's on-disk cache if it is there (never compiles):
    the cache half of numba's ``Dispatcher.compile``."""
    with _compiler_lock:
        args, _ = _sigutils.normalize_signature(sig)
        if tuple(args) in dispatcher.overloads:
            return True
        cres = getattr(dispatcher, "_cache").load_overload(sig, dispatcher.targetctx)
        if cres is None:
            return False
        getattr(dispatcher, "_cache_hits")[sig] += 1
        if not cres.objectmode:
            dispatcher.targetctx.insert_user_function(cres.entry_point, cres.fndesc, [cres.library])
        dispatcher.add_overload(cres)
        return True


def _switch(dispatcher: Dispatcher) -> Dispatcher:
    """Machine code is in place: a signatured kernel compiles nothing more (later calls with other
    types raise TypeError and never reach the hook)."""
    if dispatcher._robokit_signature is not None and dispatcher._can_compile:  # type: ignore[attr-defined]
        dispatcher.disable_compile()
    return dispatcher


def _compile_here(dispatcher: Dispatcher, sig: Any) -> Dispatcher:
    dispatcher.compile(sig)
    return _switch(dispatcher)


def _first_call(dispatcher: Dispatcher, args: tuple[Any, ...]) -> Any:
    """What a call does when no machine code matches: see the module docstring."""
    signature = dispatcher._robokit_signature  # type: ignore[attr-defined]
    mode = compile_mode()
    if mode == "wait":
        with _LOCK:
            if signature is not None:
                compile_now(dispatcher)  # the compile notice comes from numba's event
                return dispatcher
            if _load_cached(dispatcher, _argtypes(dispatcher, args, _fingerprint(args))):
                return dispatcher
            func = dispatcher.py_func
            _note(notice(func.__module__.rsplit(".", 1)[-1], func.__name__))  # not announced by the event listener
            return getattr(Dispatcher, "_compile_for_args")(dispatcher, *args)  # numba's own path
    fingerprint = _fingerprint(args)
    if signature is not None:
        accepted = _ACCEPTED.setdefault(id(dispatcher), set())
        if fingerprint is None or fingerprint not in accepted:
            _check_types(dispatcher, signature, _argtypes(dispatcher, args, fingerprint))
            if fingerprint is not None:
                accepted.add(fingerprint)
        sig = signature
    else:
        sig = _argtypes(dispatcher, args, fingerprint)
    key = _key(dispatcher, sig)
    interpret = mode == "off" or _batch_work(dispatcher, args) <= dispatcher._robokit_interpret  # type: ignore[attr-defined]
    with _LOCK:
        if dispatcher._can_compile is False:  # type: ignore[attr-defined]
            return dispatcher  # another thread switched it meanwhile
        job = _BG.jobs.get(key)
        if job is None and key not in _BG.checked:
            _BG.checked.add(key)
            if _load_cached(dispatcher, sig):  # a cache hit: machine code in milliseconds
                return _switch(dispatcher)
        if mode == "off":
            return _run_interpreted(dispatcher, args)
        _collect()
        if job is None:
            job = _submit(dispatcher, sig, urgent=not interpret)
            if job is None:  # no worker: compile here, as ROBOKIT_COMPILE=wait does
                return _compile_here(dispatcher, sig)
        elif job.state == "queued" and not interpret and not job.urgent:
            job.urgent = True  # a large batch now waits for it: to the front of the worker's queue
            _BG.worker.submit(job.number, job.module, job.func_name, sig, urgent=True)
        if interpret and job.state == "queued":
            return _run_interpreted(dispatcher, args)
    if job.state == "queued":
        _wait_for(job)
    with _LOCK:
        return _finish(job)


#: The argument names of the batch kernels' leading dimension (configurations, targets).
_BATCH_ARGS = ("thetas", "Q", "Ts")


def _batch_work(dispatcher: Dispatcher, args: tuple[Any, ...]) -> int:
    """The size of a call, for the interpret-or-wait choice: configurations × joints of the batch
    argument (targets for (N, 4, 4) poses); 0 for a kernel without one."""
    code = dispatcher.py_func.__code__
    for name, value in zip(code.co_varnames[:code.co_argcount], args):
        if name in _BATCH_ARGS and isinstance(value, np.ndarray) and value.ndim >= 2:
            return int(value.shape[0]) * (int(value.shape[1]) if value.ndim == 2 else 1)
    return 0


def _run_interpreted(dispatcher: Dispatcher, args: tuple[Any, ...]) -> Callable[..., Any]:
    twin = _twin(dispatcher)
    if any(isinstance(a, OmittedArg) for a in args):
        return lambda *a: twin(*(x.value if isinstance(x, OmittedArg) else x for x in a))
    return twin


def _finish(job: _Job) -> Dispatcher:
    """Take a finished (or failed) job's machine code: from the cache, or compiled here."""
    dispatcher = job.dispatcher
    if dispatcher._can_compile is False:  # type: ignore[attr-defined]
        return dispatcher
    if job.state == "ready":
        if _load_cached(dispatcher, job.sig):
            job.state = "loaded"
            _progress(job)
            return _switch(dispatcher)
        job.state, job.detail = "failed", "its machine code was not found in numba's cache afterwards"
    if job.state == "failed":
        _note(f"robokit: background compile of {job.name} failed ({job.detail}); compiling it in this process")
        job.state = "loaded"
    return _compile_here(dispatcher, job.sig)


def _submit(dispatcher: Dispatcher, sig: Any, urgent: bool) -> _Job | None:
    func = dispatcher.py_func
    module = sys.modules.get(func.__module__)
    if getattr(module, func.__name__, None) is not dispatcher:
        return None  # not reachable by name from its module: the worker could not find it
    from robokit.kernels import _background

    for attempt in range(2):
        if _BG.worker is None or _BG.worker.dead:
            if _BG.unavailable:
                return None
            try:
                _BG.worker = _background.Worker()
            except (OSError, ValueError) as exc:
                _BG.unavailable = f"{type(exc).__name__}: {exc}"
                _note(f"robokit: cannot start the background compile worker ({_BG.unavailable}); "
                      "compiling kernels in this process")
                return None
        job = _Job(len(_BG.by_number) + 1, dispatcher, sig)
        job.urgent = urgent
        if _BG.worker.submit(job.number, func.__module__, func.__name__, sig, urgent=urgent):
            _BG.jobs[_key(dispatcher, sig)] = _BG.by_number[job.number] = job
            _announce(job)
            return job
        _BG.worker = None  # it had exited (idle): start a new one once
    return None


def _collect() -> None:
    """Read the worker's replies (never blocks); jobs of a worker that died fall back to here."""
    worker = _BG.worker
    if worker is None:
        return
    for status, number, detail in worker.poll():
        job = _BG.by_number.get(number)
        if job is not None and job.state == "queued":
            job.state, job.detail = ("ready", detail) if status == "ok" else ("failed", detail)
    if worker.dead:
        for job in _BG.by_number.values():
            if job.state == "queued":
                job.state, job.detail = "failed", "the worker exited"


def _wait_for(job: _Job) -> None:
    """Block until the worker has finished ``job`` (it was sent as urgent), with a notice."""
    import contextlib
    import select

    from robokit._progress import Slow

    line = (f"robokit: waiting for {job.name} to compile (a batch or long-loop kernel runs compiled only; "
            "once per machine, then loaded from numba's cache) ...")
    # the line at once, then the elapsed time (rewritten each second on a terminal, a line every 10 s
    # otherwise), then how long it took; while notices are held (validate's table) the line alone
    # goes to the holder, and no progress is printed into the table
    progress: Any = contextlib.nullcontext()
    if not quiet and _SINK is not None:
        _emit(line)
    elif not quiet:
        progress = Slow(line, after=0.0, done=f"robokit: {job.name} compiled", still=f"still compiling {job.name}")
    with progress:
        while True:
            with _LOCK:
                _collect()
                if job.state != "queued" or _BG.worker is None:
                    if job.state == "queued":
                        job.state, job.detail = "failed", "the worker exited"
                    return
                fd = _BG.worker.fileno
            select.select([fd], [], [], 0.5)


def _announce(job: _Job) -> None:
    if quiet:
        return
    if not _BG.announced:
        _BG.announced = True
        _emit(f"robokit: compiling course kernels in the background (pid {_BG.worker.pid}; first {job.name}) - "
              "running them as plain Python until each is ready; later runs load them from numba's cache")
    if not _BG.exit_hook:
        _BG.exit_hook = True
        atexit.register(_at_exit)


def _progress(job: _Job) -> None:
    if quiet or (_SINK is None and not sys.stderr.isatty()):
        return
    done = sum(j.state == "loaded" for j in _BG.by_number.values())
    _emit(f"robokit: {job.name} ready ({done}/{len(_BG.by_number)} background compiles in use)", progress=True)


def _note(line: str) -> None:
    if not quiet:
        _emit(line)


#: Where notices go while :func:`held_notices` is active (else stderr).
_SINK: Callable[[str, bool], None] | None = None


def _emit(line: str, progress: bool = False) -> None:
    """One notice line: to stderr, or to the sink of :func:`held_notices` (``progress``: a line that
    only reports progress, which a sink may drop)."""
    sink = _SINK
    if sink is None:
        print(line, file=sys.stderr, flush=True)
    else:
        sink(line, progress)


class held_notices:
    """Hold the compile notices while output must not be interleaved (``robokit validate``'s table).

    While active, every notice this module prints — the background compile's first line, a batch
    kernel waiting, a kernel compiled in the process, a fallback — is kept instead of printed, and
    ``on_line(line)`` (optional) is called with it (the table's status line shows it on a
    terminal). On exit the kept lines are printed to stderr, in order, without the progress lines
    ("X ready"). The exit notice (kernels still compiling) is printed at the process's exit as
    always, after everything.

    Parameters
    ----------
    on_line : callable, optional
        Called with each notice as it happens.

    Examples
    --------
    >>> with held_notices() as held:   # doctest: +SKIP
    ...     print_the_table()          # a compile notice now waits in held.lines
    >>> held.lines   # doctest: +SKIP
    ['robokit: compiling course kernels in the background (pid 1234; first poe.fkin_space) - ...']
    """

    def __init__(self, on_line: Callable[[str], None] | None = None) -> None:
        self.on_line = on_line
        self.lines: list[str] = []
        self._previous: Callable[[str, bool], None] | None = None

    def _keep(self, line: str, progress: bool) -> None:
        if not progress:
            self.lines.append(line)
        if self.on_line is not None:
            self.on_line(line)

    def __enter__(self) -> held_notices:
        global _SINK
        self._previous, _SINK = _SINK, self._keep
        return self

    def __exit__(self, *exc: Any) -> None:
        global _SINK
        _SINK = self._previous
        for line in self.lines:
            print(line, file=sys.stderr, flush=True)


def _at_exit() -> None:
    """At the parent's exit: say what the worker still has to do; close its input (it finishes and exits)."""
    with _LOCK:
        _collect()
        left = [j for j in _BG.by_number.values() if j.state == "queued"]
        worker = _BG.worker
        if worker is not None:
            worker.close()  # not waited for
        if left and worker is not None and not quiet:
            print(f"robokit: {len(left)} of {len(_BG.by_number)} kernels still compiling in the background "
                  f"(pid {worker.pid}); the next run loads them from numba's cache", file=sys.stderr, flush=True)


#: True in the worker processes of :mod:`robokit.kernels.warm` and in the background worker
#: (their parent prints the progress).
quiet = bool(os.environ.get("ROBOKIT_COMPILE_WORKER"))


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
            _emit(notice(module, name))

    def on_end(self, ev: _event.Event) -> None:
        pass


if not getattr(sys.modules[__name__], "_LISTENING", False):
    _event.register("numba:compile", _CompileNotice())
    _LISTENING = True


def machine_code(kernel: Any, spec: str) -> Any:
    """A compiled kernel's machine code for one set of argument types, as a callable that skips
    numba's type dispatch (about 0.1 µs of a call); None while the kernel has no machine code for
    them (not compiled yet, or running as plain Python: call the kernel itself then). The caller
    must pass exactly those types: the entry point converts without checking.

    ``spec`` names the argument types, one letter each: ``v`` a float64 1-D array in C order,
    ``m`` a float64 2-D array in C order, ``f`` a float64 (a Python float), ``i`` an int64 (a
    Python int)."""
    overloads = getattr(kernel, "overloads", None)
    if not overloads:
        return None
    from numba.core import types as nbt

    code = {"v": nbt.Array(nbt.float64, 1, "C"), "m": nbt.Array(nbt.float64, 2, "C"), "f": nbt.float64,
            "i": nbt.int64}
    cres = overloads.get(tuple(code[c] for c in spec))
    return None if cres is None else cres.entry_point


def cache_dir(kernel: object) -> str | None:
    """The folder where numba keeps ``kernel``'s compiled code (see the module docstring for the
    order numba tries), or None when the kernel is not cached (``NUMBA_DISABLE_JIT=1``).

    Example: ``cache_dir(robokit.kernels.poe.fkin_space_kernel)``.
    """
    cache = getattr(kernel, "_cache", None)
    impl = getattr(cache, "_impl", None)
    locator = getattr(impl, "locator", None)
    return None if locator is None else locator.get_cache_path()

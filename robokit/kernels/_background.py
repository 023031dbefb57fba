r"""The background compile worker: one child process per parent process that compiles kernels
into numba's on-disk cache while the parent runs them as plain Python.

Protocol (one line per message, ASCII):

* parent → worker, on the worker's stdin: ``<job> <module> <kernel> <signature> [urgent]``,
  the signature pickled and base64-encoded (a numba signature string or a tuple of numba types);
  ``urgent`` puts the job at the front of the queue (the parent is waiting for it);
* worker → parent, on the worker's stdout: ``ok <job> <seconds>`` once the compiled code is in
  the cache, or ``fail <job> <reason>``.

The worker compiles one kernel at a time, in the order asked (urgent jobs first). It exits when
its stdin reaches end-of-file (the parent closed it or exited) **after finishing every job it was
sent**, so the next process finds them in the cache; when it has been idle for
:data:`IDLE_SECONDS`; and in any case after :data:`LIFETIME_SECONDS` (a hard limit, SIGALRM). Its
stderr goes to the null device and it runs in its own session, so it never writes into the
parent's terminal or pipes, a Ctrl-C of the parent does not interrupt a compile half-way, and the
parent's exit never waits for it. numba writes each cache file to a temporary name and renames it
into place (``os.replace``), so a worker stopped at any moment leaves no half-written entry.
"""
from __future__ import annotations

import base64
import collections
import importlib
import os
import pickle
import select
import signal
import subprocess
import sys
import time
from typing import Any, BinaryIO

__all__ = ["Worker", "serve", "IDLE_SECONDS", "LIFETIME_SECONDS"]

#: The worker exits after this many seconds without a job.
IDLE_SECONDS = 60.0
#: The worker exits after this many seconds in any case.
LIFETIME_SECONDS = 1800

_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
_PACKAGE = os.path.join(_ROOT, "robokit")
# Started with ``-c`` so that the folder holding *this* robokit comes first on the worker's path:
# the worker must import the same source files as the parent, or numba's cache index (keyed by
# the source file) would not be the parent's.
_BOOT = ("import sys, os; r = sys.argv[1]; sys.path.insert(0, r) if r not in sys.path else None; "
         "import robokit; p = os.path.dirname(os.path.abspath(robokit.__file__)); "
         "from robokit.kernels._background import serve; sys.exit(serve(expected=sys.argv[2], found=p, lifetime=int(sys.argv[3])))")


def encode(sig: Any) -> str:
    """A signature (numba string or tuple of numba types) as one base64 token."""
    return base64.b64encode(pickle.dumps(sig, protocol=4)).decode("ascii")


def decode(token: str) -> Any:
    """The inverse of :func:`encode`."""
    return pickle.loads(base64.b64decode(token.encode("ascii")))


class Worker:
    """The parent's handle on its worker process: send jobs, collect finished ones without blocking."""

    def __init__(self) -> None:
        env = dict(os.environ, ROBOKIT_COMPILE_WORKER="1")
        self.proc = subprocess.Popen(
            [sys.executable, "-c", _BOOT, _ROOT, _PACKAGE, str(LIFETIME_SECONDS)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL, env=env, close_fds=True, start_new_session=True)
        assert self.proc.stdout is not None and self.proc.stdin is not None
        self._out = self.proc.stdout.fileno()
        os.set_blocking(self._out, False)
        self._buffer = b""
        self.dead = False

    @property
    def pid(self) -> int:
        """The worker's process id."""
        return self.proc.pid

    @property
    def fileno(self) -> int:
        """The descriptor of the worker's replies (for ``select``)."""
        return self._out

    def submit(self, job: int, module: str, name: str, sig: Any, urgent: bool = False) -> bool:
        """Queue one kernel; False when the worker can no longer take jobs."""
        if self.dead or self.proc.stdin is None:
            return False
        line = f"{job} {module} {name} {encode(sig)}{' urgent' if urgent else ''}\n"
        try:
            self.proc.stdin.write(line.encode("ascii"))
            self.proc.stdin.flush()
        except (OSError, ValueError):
            self.dead = True
            return False
        return True

    def poll(self) -> list[tuple[str, int, str]]:
        """The replies that have arrived, as ``(status, job, detail)``; never blocks. At end of file
        (the worker has exited) :attr:`dead` becomes True."""
        replies: list[tuple[str, int, str]] = []
        while not self.dead:
            try:
                chunk = os.read(self._out, 65536)
            except BlockingIOError:
                break
            except OSError:
                chunk = b""
            if not chunk:
                self.dead = True
                break
            self._buffer += chunk
        *lines, self._buffer = self._buffer.split(b"\n")
        for raw in lines:
            status, _, rest = raw.decode("ascii", "replace").partition(" ")
            job, _, detail = rest.partition(" ")
            if status in ("ok", "fail") and job.isdigit():
                replies.append((status, int(job), detail))
        return replies

    def close(self) -> None:
        """Close the worker's stdin: it finishes the jobs it has and exits (does not wait)."""
        try:
            if self.proc.stdin is not None:
                self.proc.stdin.close()
        except OSError:
            pass


def _compile(module: str, name: str, sig: Any) -> None:
    if not module.startswith("robokit.kernels."):
        raise ValueError(f"not a robokit kernel module: {module}")
    kernel = getattr(importlib.import_module(module), name)
    from numba.core import sigutils

    if tuple(sigutils.normalize_signature(sig)[0]) not in kernel.overloads:  # else: already compiled here
        kernel.compile(sig)


def serve(stdin: BinaryIO | None = None, stdout: BinaryIO | None = None, *, expected: str | None = None,
          found: str | None = None, lifetime: int | None = None) -> int:
    """The worker's loop (see the module docstring); returns its exit status.

    Parameters
    ----------
    stdin, stdout : binary streams
        Where jobs come from and replies go (default: the process's own).
    expected, found : str, optional
        The robokit package folder the parent uses and the one this process imported; when they
        differ every job fails (its cache would not be the parent's).
    lifetime : int, optional
        Seconds after which the process is ended by SIGALRM whatever it is doing (the worker
        passes :data:`LIFETIME_SECONDS`).

    Returns
    -------
    int
        0.

    Examples
    --------
    ``python -c "from robokit.kernels._background import serve; serve()"`` reads jobs from stdin.
    """
    if lifetime is not None and hasattr(signal, "alarm"):
        signal.alarm(lifetime)
    inp = (stdin or sys.stdin.buffer).fileno()
    out = stdout or sys.stdout.buffer
    mismatch = (expected is not None and found is not None
                and os.path.realpath(expected) != os.path.realpath(found))
    queue: collections.deque[list[str]] = collections.deque()
    buffer, eof, replying = b"", False, True
    while True:
        if not eof:
            ready, _, _ = select.select([inp], [], [], 0 if queue else IDLE_SECONDS)
            if ready:
                chunk = os.read(inp, 65536)
                eof = not chunk
                buffer += chunk
                *lines, buffer = buffer.split(b"\n")
                for raw in lines:
                    fields = raw.decode("ascii", "replace").split()
                    if len(fields) >= 4:
                        (queue.appendleft if fields[4:] == ["urgent"] else queue.append)(fields)
                continue  # read everything that is there before choosing the next job
            if not queue:
                return 0  # idle
        if not queue:
            return 0  # end of input and every job done
        job, module, name, token = queue.popleft()[:4]
        t0 = time.perf_counter()
        try:
            if mismatch:
                raise RuntimeError(f"the worker imported robokit from {found}, not {expected}")
            _compile(module, name, decode(token))
            reply = f"ok {job} {time.perf_counter() - t0:.2f}\n"
        except Exception as exc:  # reported to the parent, which then compiles the kernel itself
            reply = f"fail {job} {type(exc).__name__}: {' '.join(str(exc).split())[:300]}\n"
        if replying:
            try:
                out.write(reply.encode("ascii", "replace"))
                out.flush()
            except OSError:
                replying = False  # the parent has gone: keep compiling for the next process

r"""The Dask clusters a capability map runs on: robokit's own, locked; someone else's, bounded.

robokit's own cluster (``capability_map(..., client=None)``, ``robokit workspace`` without
``--scheduler``) is a ``distributed.LocalCluster`` on 127.0.0.1 whose scheduler and workers
speak TLS with credentials made for this run only (``Security.temporary()``: a fresh CA and
certificates, in memory, never written to disk; needs the ``cryptography`` package). A
client without these credentials cannot connect, so other users of the machine cannot run
code on the cluster. The dashboard is off unless asked for (``dashboard=True``, then on
127.0.0.1 only).

A scheduler given by address (``--scheduler tcp://host:port``) is first probed on a plain
socket: within :data:`SCHEDULER_TIMEOUT` seconds (or the smaller
``distributed.comm.timeouts.connect`` of the Dask configuration) it must send the opening
message of Dask's protocol, a frame of at most :data:`MAX_HANDSHAKE_BYTES` bytes. A server
that accepts and never answers, or that sends anything else (e.g. a length prefix of
gigabytes, which ``distributed`` would allocate), is refused with one line before
``distributed`` reads from it; the real connection is then made with the same time bound.
"""
from __future__ import annotations

import logging
import socket
import struct
import time
from typing import Any

from robokit._optional import require
from robokit.errors import InputError, MissingExtraError, RobokitError

__all__ = ["SCHEDULER_TIMEOUT", "MAX_HANDSHAKE_BYTES", "local_cluster", "probe_scheduler", "connect_scheduler"]

#: Longest wait (s) for a scheduler given by address to connect and answer.
SCHEDULER_TIMEOUT = 10.0
#: Largest opening message accepted from a scheduler in the probe (bytes).
MAX_HANDSHAKE_BYTES = 64 * 1024


def _timeout() -> float:
    dask = require("dask", "a capability map on a Dask cluster")
    parse_timedelta = require("dask.utils").parse_timedelta

    configured = parse_timedelta(dask.config.get("distributed.comm.timeouts.connect", SCHEDULER_TIMEOUT), "s")
    return float(min(SCHEDULER_TIMEOUT, configured or SCHEDULER_TIMEOUT))


def local_cluster(n_workers: int, dashboard: bool = False) -> tuple[Any, Any, Any]:
    """Start robokit's own TLS cluster on 127.0.0.1 and connect a client to it.

    Parameters
    ----------
    n_workers : int
        Worker processes (one thread each).
    dashboard : bool
        Serve Dask's dashboard on 127.0.0.1 (a free port; ``client.dashboard_link``).

    Returns
    -------
    cluster, client, security
        The ``LocalCluster``, a ``Client`` holding this run's credentials, and the
        ``distributed.security.Security`` with them (for tests and extra clients).

    Examples
    --------
    Starting worker processes takes seconds (and a ``__main__`` guard in a script), so the
    example is not run as a doctest:

    >>> cluster, client, security = local_cluster(1)  # doctest: +SKIP
    >>> client.scheduler.address.startswith("tls://127.0.0.1:")  # doctest: +SKIP
    True
    """
    _leave_if_a_worker_starting()
    try:
        import cryptography  # noqa: F401  (Security.temporary needs it)
    except ImportError:
        raise MissingExtraError("capability maps on a local cluster need the 'cryptography' package for the "
                                "cluster's TLS credentials, which robokit installs with its 'workspace' extra: "
                                "pip install 'robokit[workspace]', or pass client='serial'",
                                extra="workspace") from None
    distributed = require("distributed", "a capability map on a Dask cluster")
    Client, LocalCluster = distributed.Client, distributed.LocalCluster
    Security = require("distributed.security").Security

    security = Security.temporary()
    # the scheduler always runs an HTTP server (health checks; the dashboard's pages only when
    # asked): on 127.0.0.1 and a free port, never 8787 on every interface
    try:
        cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True, protocol="tls://",
                               host="127.0.0.1", security=security, silence_logs=logging.ERROR,
                               scheduler_kwargs={"dashboard": bool(dashboard), "dashboard_address": "127.0.0.1:0"})
    except Exception as exc:
        script = _unguarded_script_hint(exc)
        if script is None:
            raise
        raise RobokitError(script) from None  # Dask's chain says only "Nanny failed to start"
    try:
        client = Client(cluster, security=security)
    except BaseException:
        cluster.close()
        raise
    return cluster, client, security


def _leave_if_a_worker_starting() -> None:
    """Exit quietly when this process is one of a local cluster's workers still starting: ``spawn`` runs the
    user's script again in each worker, and a script that makes a map at its top level calls this again.

    Starting a cluster there fails (multiprocessing refuses to start processes while one is starting),
    and each worker printed Dask's error log and its tracebacks (some 200 lines a worker) before the
    parent's one clear error (:func:`_unguarded_script_hint`). The worker ends instead, with no output;
    the parent sees its workers fail to start and says what to do. The test is multiprocessing's own
    (``spawn._check_not_importing_main``): the process is still inheriting its parent's state."""
    import multiprocessing

    if getattr(multiprocessing.current_process(), "_inheriting", False):
        raise SystemExit(1)


def _unguarded_script_hint(exc: BaseException) -> str | None:
    """The message for worker processes that did not start while ``__main__`` is a script, else None.

    Dask starts a local cluster's workers with ``spawn``, which imports the main script again in each
    worker; a script that makes a map at its top level, without ``if __name__ == "__main__":``, makes
    every worker start a cluster of its own, which multiprocessing refuses (in the worker), and the
    parent sees only "Nanny failed to start"."""
    import sys

    path = getattr(sys.modules.get("__main__"), "__file__", None)
    if not path or "failed to start" not in str(exc):
        return None
    return (f"capability map: the local cluster's worker processes did not start. Dask starts each worker by "
            f"running your script ({path}) again: put the code that makes the map under "
            f"'if __name__ == \"__main__\":', or pass client='serial' to compute in this process")


def probe_scheduler(address: str, timeout: float | None = None) -> None:
    """Check on a plain socket that ``address`` (``tcp://host:port``) answers like a Dask scheduler.

    Parameters
    ----------
    address : str
        ``tcp://host:port`` (other schemes are not probed).
    timeout : float, optional
        Seconds for the whole probe (default :data:`SCHEDULER_TIMEOUT`, or less when the
        Dask configuration says so).

    Returns
    -------
    None
        InputError naming the address when it does not connect, does not answer in time, or
        its first message is not a Dask frame of at most :data:`MAX_HANDSHAKE_BYTES` bytes.

    Notes
    -----
    Dask's TCP protocol opens with each side sending a message: an 8-byte little-endian
    length L, then L bytes starting with the 8-byte number of frames and the frames' 8-byte
    lengths (``distributed.comm.tcp``); the probe reads at most
    ``8 + MAX_HANDSHAKE_BYTES`` bytes and checks these numbers add up.

    Examples
    --------
    >>> probe_scheduler("tcp://127.0.0.1:1", timeout=1)
    Traceback (most recent call last):
    robokit.errors.InputError: scheduler: cannot connect to 'tcp://127.0.0.1:1' (Connection refused)
    """
    comm = require("distributed.comm", "a Dask scheduler")
    parse_address, parse_host_port = comm.parse_address, comm.parse_host_port

    timeout = _timeout() if timeout is None else float(timeout)
    try:
        scheme, loc = parse_address(address)
    except (ValueError, TypeError) as exc:
        raise InputError(f"scheduler: {address!r} is not a scheduler address ({exc})") from None
    if scheme != "tcp":
        return
    try:
        host, port = parse_host_port(loc)
    except (ValueError, TypeError) as exc:
        raise InputError(f"scheduler: {address!r} is not a host:port address ({exc})") from None
    deadline = time.monotonic() + timeout

    def left() -> float:
        rest = deadline - time.monotonic()
        if rest <= 0:
            raise socket.timeout()
        return rest

    def read(sock: socket.socket, n: int) -> bytes:
        buf = b""
        while len(buf) < n:
            sock.settimeout(left())
            part = sock.recv(n - len(buf))
            if not part:
                raise InputError(f"scheduler: {address!r} closed the connection without answering like a Dask scheduler")
            buf += part
        return buf

    try:
        with socket.create_connection((host, int(port)), timeout=timeout) as sock:
            (length,) = struct.unpack("<Q", read(sock, 8))
            if not 16 <= length <= MAX_HANDSHAKE_BYTES:
                raise InputError(f"scheduler: {address!r} is not a Dask scheduler (its first message announces "
                                 f"{length} bytes; a scheduler's is at most {MAX_HANDSHAKE_BYTES})")
            body = read(sock, length)
            (n_frames,) = struct.unpack_from("<Q", body)
            if not 1 <= n_frames <= 64 or length < 8 * (n_frames + 1):
                raise InputError(f"scheduler: {address!r} is not a Dask scheduler (malformed first message)")
            sizes = struct.unpack_from(f"<{n_frames}Q", body, 8)
            if 8 * (n_frames + 1) + sum(sizes) != length:
                raise InputError(f"scheduler: {address!r} is not a Dask scheduler (malformed first message)")
    except socket.timeout:
        raise InputError(f"scheduler: {address!r} did not answer like a Dask scheduler within {timeout:g} s") from None
    except OSError as exc:
        raise InputError(f"scheduler: cannot connect to {address!r} ({exc.strerror or exc})") from None


def connect_scheduler(address: str) -> Any:
    """A ``distributed.Client`` of the scheduler at ``address``, probed first and time-bounded.

    Parameters
    ----------
    address : str
        A scheduler address (``tcp://host:port``, ``tls://…`` with credentials from the Dask
        configuration).

    Returns
    -------
    distributed.Client
        InputError naming the address if it cannot be reached within the bound.

    Examples
    --------
    >>> client = connect_scheduler("tcp://127.0.0.1:8786")  # doctest: +SKIP

    Nothing listens on port 1: refused with one line, before ``distributed`` reads anything.

    >>> connect_scheduler("tcp://127.0.0.1:1")
    Traceback (most recent call last):
    robokit.errors.InputError: scheduler: cannot connect to 'tcp://127.0.0.1:1' (Connection refused)
    """
    dask = require("dask", "a Dask scheduler")
    Client = require("distributed", "a Dask scheduler").Client

    timeout = _timeout()
    probe_scheduler(address, timeout)
    try:
        with dask.config.set({"distributed.comm.timeouts.connect": f"{timeout}s"}):
            return Client(address, timeout=f"{timeout}s")
    except (OSError, TimeoutError, ValueError) as exc:
        text = str(exc).strip().splitlines()
        raise InputError(f"scheduler: cannot connect to {address!r}: {text[0] if text else type(exc).__name__}") from None

"""Saying what a slow step is doing while it happens: one line, then the elapsed time, then the total.

A first use on a new machine can take a minute — numba compiling a simulation loop, TOPP-RA
importing scipy and matplotlib (whose font cache is built once per user). :class:`Slow` wraps such
a step: when it has run for ``after`` seconds it prints its line on stderr (``robokit: ...``),
then the elapsed time — on a terminal the same line rewritten every second, otherwise one short
line every ``every`` seconds (a log stays readable) — and, at the end, how long it took. A step
that finishes before ``after`` prints nothing, so a warm machine stays quiet.
"""
from __future__ import annotations

import os
import sys
import threading
import time
from types import TracebackType
from typing import TextIO

__all__ = ["Slow"]


class Slow:
    """Context manager: announce a step that is taking long, show its progress, then its total.

    Parameters
    ----------
    line : str
        What is happening and why, e.g. ``"robokit: retime: importing TOPP-RA (first use) ..."``.
    after : float
        Seconds of silence before the line (0: print it at once).
    every : float
        Seconds between progress lines when stderr is not a terminal.
    done : str
        What the closing line says finished (``"<done> in 12.3 s"``); printed only if the line was.
    stream : file-like, optional
        Where to print (default ``sys.stderr``).
    still : str
        The progress lines' text off a terminal: ``"robokit: ... <still>, 20 s"``.

    Examples
    --------
    >>> import io
    >>> out = io.StringIO()
    >>> with Slow("robokit: a slow step ...", after=0, done="robokit: the step", stream=out):
    ...     pass
    >>> out.getvalue().splitlines()[0]
    'robokit: a slow step ...'
    """

    def __init__(self, line: str, after: float = 1.0, every: float = 10.0, done: str = "",
                 stream: TextIO | None = None, still: str = "still working") -> None:
        self.line, self.after, self.every, self.done, self.still = line, float(after), float(every), done, still
        self.stream = stream
        self.announced = False
        self._stop = threading.Event()
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None
        self._t0 = 0.0
        self._tty = False

    def _out(self) -> TextIO:
        return self.stream if self.stream is not None else sys.stderr

    def _write(self, text: str) -> None:
        out = self._out()
        try:
            out.write(text)
            out.flush()
        except (OSError, ValueError):  # a closed or broken stream: the step itself goes on
            pass

    def _run(self) -> None:
        if self._stop.wait(self.after):
            return
        with self._lock:
            if self._stop.is_set():
                return
            self.announced = True
            self._write(self.line + ("" if self._tty else "\n"))
        step = 1.0 if self._tty else self.every
        while not self._stop.wait(step):
            with self._lock:
                if self._stop.is_set():
                    return
                elapsed = time.monotonic() - self._t0
                if self._tty:
                    self._write(f"\r{self.line} {elapsed:.0f} s")
                else:
                    self._write(f"robokit: ... {self.still}, {elapsed:.0f} s\n")

    def __enter__(self) -> Slow:
        self._t0 = time.monotonic()
        out = self._out()
        try:
            self._tty = bool(out.isatty()) and os.environ.get("TERM") != "dumb"
        except (AttributeError, ValueError):
            self._tty = False
        self._thread = threading.Thread(target=self._run, name="robokit-progress", daemon=True)
        self._thread.start()
        return self

    def __exit__(self, kind: type[BaseException] | None, value: BaseException | None,
                 tb: TracebackType | None) -> None:
        with self._lock:
            self._stop.set()
        if self._thread is not None:
            self._thread.join()
        if self.announced:
            elapsed = time.monotonic() - self._t0
            end = "\n" if self._tty else ""
            if kind is None and self.done:
                self._write(f"{end}{self.done} in {elapsed:.1f} s\n")
            elif end:
                self._write(end)

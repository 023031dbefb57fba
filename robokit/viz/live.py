"""A live meshcat viewer on loopback: start (or connect to) a server, get its URL, stop it."""
from __future__ import annotations

import subprocess
from typing import Any

__all__ = ["LiveViewer"]


class LiveViewer:
    """A meshcat server for interactive use.

    ``LiveViewer()`` starts a server on 127.0.0.1 (meshcat picks a free port from 7000);
    ``LiveViewer(zmq_url="tcp://127.0.0.1:6000")`` connects to a running one instead.
    ``close()`` stops a server this object started (none outlives the process).

    Parameters
    ----------
    zmq_url : str, optional
        The ZMQ address of a running meshcat server (default: start one).

    Attributes
    ----------
    vis : meshcat.Visualizer
        The visualizer to draw into (e.g. ``Scene(robot, vis=viewer.vis)``).
    url : str
        The page to open in a browser.
    process : subprocess.Popen or None
        The server process this viewer started.

    Examples
    --------
    >>> with LiveViewer() as viewer:   # doctest: +SKIP
    ...     print(viewer.url)
    http://127.0.0.1:7000/static/
    """

    def __init__(self, zmq_url: str | None = None) -> None:
        from robokit.viz.scene import new_visualizer

        self.vis = new_visualizer(zmq_url)
        self._own = zmq_url is None

    @property
    def url(self) -> str:
        """The viewer page's address (http://127.0.0.1:PORT/static/)."""
        return self.vis.url()

    @property
    def process(self) -> subprocess.Popen | None:
        """The server process this viewer started (None when connected to another one)."""
        return getattr(self.vis.window, "server_proc", None) if self._own else None

    def close(self) -> None:
        """Stop the server (if this viewer started it) and wait for it to exit."""
        from robokit.viz.scene import stop_server

        stop_server(self.process)

    def __enter__(self) -> LiveViewer:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

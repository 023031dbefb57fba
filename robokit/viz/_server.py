"""A meshcat server bound to 127.0.0.1 only, that exits when the process that started it dies.

meshcat's own server (``meshcat.servers.zmqserver``) makes its web server listen on every
address (0.0.0.0 and [::]) and runs in its own session, so it outlives a parent killed by
SIGTERM or SIGKILL. robokit starts this module instead (``python -m robokit.viz._server
PARENT_PID``): the same bridge with the web server bound to loopback, and a watchdog that
stops the server as soon as its parent process is gone.
"""
from __future__ import annotations

import os
import sys
from typing import Any, Sequence

from robokit._optional import require

HOST = "127.0.0.1"


def _bridge_class() -> type:
    bridge: Any = require("meshcat.servers.zmqserver", "the live viewer").ZMQWebSocketBridge

    class LoopbackBridge(bridge):
        def make_app(self) -> Any:
            app = super().make_app()
            listen = app.listen

            def listen_loopback(port: int, **kwargs: Any) -> Any:
                kwargs.setdefault("address", HOST)
                return listen(port, **kwargs)

            app.listen = listen_loopback
            return app

    return LoopbackBridge


def main(argv: Sequence[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    parent = int(argv[0]) if argv else os.getppid()
    import tornado.ioloop

    bridge = _bridge_class()(host=HOST)
    print(f"zmq_url={bridge.zmq_url}", flush=True)
    print(f"web_url={bridge.web_url}", flush=True)

    def watchdog() -> None:
        if os.getppid() != parent:  # re-parented: the process that started us is gone
            tornado.ioloop.IOLoop.current().stop()

    tornado.ioloop.PeriodicCallback(watchdog, 250).start()
    try:
        bridge.run()
    except KeyboardInterrupt:
        pass
    return 0


if __name__ == "__main__":
    sys.exit(main())

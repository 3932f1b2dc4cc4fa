"""Serving the explorer: a local Bokeh server (loopback by default) with every script and style
sheet served from the installed Panel and Bokeh packages, and the notebook configuration
(resources inlined into the notebook: no CDN either).

Each browser page gets its own sessions (settings and history) over the logs loaded once
(shared, never copied).
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from gyrobias.explore.state import Session

__all__ = ["LOOPBACK", "Served", "configure", "serve"]

LOOPBACK = "127.0.0.1"
#: Largest websocket message (and so upload) the server accepts, bytes.
MAX_MESSAGE_BYTES = 64 * 1024 * 1024

_configured = False


def configure() -> None:
    """Panel's settings for the explorer (once): resources from the installed packages."""
    global _configured
    if _configured:
        return
    import panel as pn
    from bokeh.settings import settings

    settings.resources.set_value("server")  # /static/ of the local server, never a CDN
    # in a notebook: the JS/CSS inlined into the output (pn.extension sets config.inline)
    pn.extension(inline=True, notifications=False)
    _configured = True


@dataclass
class Served:
    """A running explorer server: ``url``, ``port`` and ``stop()``."""

    server: Any
    url: str
    port: int
    thread: threading.Thread | None

    def stop(self) -> None:
        """Stop the server (and its thread)."""
        loop = self.server.io_loop
        loop.add_callback(self.server.stop)
        loop.add_callback(loop.stop)
        if self.thread is not None:
            self.thread.join(timeout=10)


def _page_factory(sessions: Sequence[Session], errors: Sequence[str]) -> Callable[[], Any]:
    def page() -> Any:
        from gyrobias.explore.app import ExploreApp

        fresh = [
            Session(s.log, s.source, allan=s._allan_input, settings=s.history[0]) for s in sessions
        ]
        return ExploreApp(fresh, errors).layout

    return page


def _free_port(host: str) -> int:
    import socket

    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as sock:
        sock.bind((host, 0))
        return int(sock.getsockname()[1])


def serve(
    sessions: Sequence[Session],
    errors: Sequence[str] = (),
    *,
    host: str = LOOPBACK,
    port: int = 0,
    show: bool = False,
    background: bool = True,
) -> Served:
    """Start the explorer's server on ``host:port`` (``port=0``: a free port).

    With ``background=True`` the server runs in a daemon thread and this returns at once;
    otherwise it blocks until interrupted (Ctrl-C). ``show`` opens the browser."""
    import panel as pn

    configure()
    origins = None  # Bokeh's default: pages of this server only (localhost / 127.0.0.1)
    if host != LOOPBACK:
        if port == 0:
            port = _free_port(host)
        origins = [f"{host}:{port}"]
    server = pn.serve(
        {"/": _page_factory(sessions, errors)},
        port=port,
        address=host,
        allow_websocket_origin=origins,
        show=False,
        start=False,
        title="gyrobias explore",
        websocket_max_message_size=MAX_MESSAGE_BYTES,
        verbose=False,
    )
    server.start()
    shown_host = host if ":" not in host else f"[{host}]"
    url = f"http://{shown_host}:{server.port}/"
    if show:
        import webbrowser

        server.io_loop.add_callback(lambda: webbrowser.open(url))
    if background:
        thread = threading.Thread(target=server.io_loop.start, daemon=True, name="gyrobias-explore")
        thread.start()
        return Served(server, url, int(server.port), thread)
    served = Served(server, url, int(server.port), None)
    print(f"gyrobias explore: serving on {url} (Ctrl-C to stop)", flush=True)
    try:
        server.io_loop.start()
    except KeyboardInterrupt:
        print("\ngyrobias explore: stopped", file=sys.stderr)
    return served

"""``gyrobias explore``: the interactive explorer of one or more logs, served locally.

Example::

    gyrobias explore imu.bag
    gyrobias explore run1.csv run2.csv --fs 100 --units deg/s --no-browser --port 8765

Serves on 127.0.0.1 (a free port unless ``--port``), prints the URL and opens the browser. A
log that cannot be read is reported in the app (and on stderr); the others are explored.
Another ``--host`` exposes the app (and so the logs) to the network: it needs
``--allow-remote`` and prints a warning.
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

from gyrobias.cli import _types
from gyrobias.cli._common import add_read_arguments, load_options, warn

__all__ = ["register", "run"]

LOOPBACK = "127.0.0.1"


def register(subparsers: Any) -> None:
    """Add the ``explore`` subcommand."""
    p = subparsers.add_parser(
        "explore",
        help="explore logs in the browser: select, clean, fit, export (needs gyrobias[explore])",
        description=(
            "Serve an interactive app on this machine: the rate against time, the part to\n"
            "analyse, outlier and drift removal, the Allan family and wavelet variance, the\n"
            "noise fit with the terms you choose, several logs overlaid, and every estimator\n"
            "export with the Python code and the command that reproduce it."
        ),
        epilog="examples: gyrobias explore imu.bag\n"
        "          gyrobias explore logs/ --fs 100 --units deg/s --no-browser",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "logs",
        type=_types.path,
        nargs="+",
        metavar="LOG",
        help="logs (as gyrobias allan reads them); a directory of logs gives each of them",
    )
    add_read_arguments(p)
    srv = p.add_argument_group("server")
    srv.add_argument(
        "--port",
        type=_types.non_negative_int,
        default=0,
        metavar="N",
        help="port to serve on (default 0: a free port)",
    )
    srv.add_argument(
        "--host",
        type=_types.text,
        default=LOOPBACK,
        metavar="ADDR",
        help="address to bind (default 127.0.0.1: this machine only)",
    )
    srv.add_argument(
        "--allow-remote",
        action="store_true",
        help="allow a --host other than the loopback address (the logs become readable by "
        "anyone who can reach it)",
    )
    srv.add_argument(
        "--no-browser", action="store_true", help="do not open the browser (print the URL only)"
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Execute ``gyrobias explore``."""
    if args.port > 65535:
        raise ValueError(f"--port must be at most 65535, got {args.port}")
    if args.host not in (LOOPBACK, "localhost", "::1"):
        if not args.allow_remote:
            raise ValueError(
                f"--host {args.host} serves the logs to the network: add --allow-remote to do so"
            )
        warn(
            f"serving on {args.host}: anyone who can reach this address can read the logs "
            "named on the command line and run analyses"
        )
    from gyrobias.explore import _require_panel, load_sessions

    _require_panel()
    options = load_options(args)
    # --start/--stop: the first selection of every log (checked before any log is read)
    from gyrobias.cli._common import selection_bounds

    selection_bounds(args)
    sessions, errors = load_sessions(args.logs, start=args.start, stop=args.stop, **options)
    for e in errors:
        warn(e)
    from gyrobias.explore.server import serve

    print(
        f"gyrobias explore: {len(sessions)} log(s) loaded"
        + (f", {len(errors)} could not be read (shown in the app)" if errors else ""),
        flush=True,
    )
    serve(
        sessions,
        errors,
        host=args.host,
        port=args.port,
        show=not args.no_browser,
        background=False,
    )
    sys.stdout.flush()
    return 0

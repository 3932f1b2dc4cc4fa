"""The ``gyrobias`` command line.

Each subcommand lives in its own module exposing ``register(subparsers)``, which adds an
argparse subparser and sets ``func=run`` (``run(args) -> int``). Modules of the ``gyrobias
experiment …`` group expose ``register_experiment(exp_subparsers)`` instead. To add a command,
append its module name to :data:`SUBCOMMANDS` or :data:`EXPERIMENTS`.

Every option value is checked by the argument layer (the ``type=`` converters of
:mod:`gyrobias.cli._types`); errors the library raises for bad input (``ValueError``,
``TypeError``, ``OSError`` such as ``FileNotFoundError``, ``MemoryError``, a missing optional
dependency) and usage errors are printed as one line ``gyrobias: error: …`` with exit code 2;
``--traceback`` shows the full traceback.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from collections.abc import Sequence

from gyrobias.cli._types import Parser

__all__ = ["EXPERIMENTS", "SUBCOMMANDS", "build_parser", "main"]

#: Modules with ``register(subparsers)``, in the order they appear in ``gyrobias --help``.
SUBCOMMANDS: list[str] = [
    "gyrobias.cli.allan",
    "gyrobias.cli.demo",
    "gyrobias.cli.predict",
    "gyrobias.cli.filter",
    "gyrobias.cli.kalman",
    "gyrobias.cli.fir",
    "gyrobias.cli.thermal",
    "gyrobias.cli.fleet",
    "gyrobias.cli.report",
    "gyrobias.cli.explore",
]

#: Modules with ``register_experiment(exp_subparsers)`` for the ``gyrobias experiment`` group
#: (the group is shown only when this list is non-empty).
EXPERIMENTS: list[str] = [
    "gyrobias.cli.experiment_table1",
    "gyrobias.cli.experiment_kalman",
]


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every registered subcommand.

    Building it imports no NumPy and not the compiled core: the subcommand modules import the
    library inside their ``run`` functions, and ``--version`` looks the version up only when
    given (``tests/test_cli_startup.py``)."""
    parser = Parser(
        prog="gyrobias",
        description="MEMS gyroscope noise analysis and bias prediction.",
    )
    parser.add_argument("--version", action=_VersionAction)
    parser.add_argument(
        "--traceback",
        action="store_true",
        help="show the full traceback on errors (for bug reports)",
    )
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name in SUBCOMMANDS:
        importlib.import_module(name).register(subparsers)
    if EXPERIMENTS:
        exp = subparsers.add_parser(
            "experiment", help="laboratory experiments (planning and evaluation)"
        )
        exp_subparsers = exp.add_subparsers(dest="experiment", metavar="EXPERIMENT", required=True)
        for name in EXPERIMENTS:
            importlib.import_module(name).register_experiment(exp_subparsers)
    return parser


class _VersionAction(argparse.Action):
    """``--version``: print ``gyrobias X.Y.Z`` and exit, the version looked up only then."""

    def __init__(self, option_strings: Sequence[str], dest: str = argparse.SUPPRESS) -> None:
        super().__init__(
            option_strings,
            dest,
            default=argparse.SUPPRESS,
            nargs=0,
            help="show the version and exit",
        )

    def __call__(self, parser: argparse.ArgumentParser, *_: object) -> None:
        parser._print_message(f"gyrobias {_version()}\n", sys.stdout)
        parser.exit()


def _version() -> str:
    """The version of the gyrobias package that is imported, without NumPy or the extension.

    In order: the metadata of the installed distribution whose files *are* the imported package
    (maturin writes the Cargo.toml version there, as into the extension; ``tests/test_version.py``
    checks that they agree); for a source tree (``PYTHONPATH=python``, ``scripts/dev-build``) the
    workspace version of its ``Cargo.toml``, which the extension is built with; else the
    extension's own. Another copy installed beside a source tree on ``PYTHONPATH`` is never
    asked: its metadata describes that copy, not the one imported.
    """
    from importlib.metadata import distributions
    from pathlib import Path

    import gyrobias

    init = Path(gyrobias.__file__ or "").resolve()
    for dist in distributions(name="gyrobias"):
        try:
            if Path(str(dist.locate_file("gyrobias/__init__.py"))).resolve() == init:
                return str(dist.version)
        except OSError:
            continue
    cargo = init.parent.parent.parent / "Cargo.toml"
    if init.parent.parent.name == "python" and cargo.is_file():
        import tomllib

        try:
            with cargo.open("rb") as f:
                return str(tomllib.load(f)["workspace"]["package"]["version"])
        except (OSError, KeyError, tomllib.TOMLDecodeError):
            pass
    from gyrobias._version import __version__

    return __version__


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line with ``argv`` (default ``sys.argv[1:]``); returns the exit code."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, usage errors
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    try:
        code = args.func(args)
    except BrokenPipeError:  # output piped into `head` etc.: stop quietly
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 1
    except KeyboardInterrupt:
        print("\ngyrobias: interrupted", file=sys.stderr)
        return 130
    except (ValueError, TypeError, OSError, ImportError, MemoryError) as exc:
        if args.traceback:
            raise
        print(f"gyrobias: error: {_message(exc)}", file=sys.stderr)
        return 2
    return int(code or 0)


def _message(exc: BaseException) -> str:
    """One line for ``exc``: its message, or for OS errors the reason and the file."""
    if isinstance(exc, OSError) and exc.strerror and exc.filename:
        return f"{exc.strerror}: '{exc.filename}'"
    text = str(exc) or type(exc).__name__
    return " ".join(text.split())

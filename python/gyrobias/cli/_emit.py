"""``--emit-c DIR`` and its options, shared by ``filter``, ``kalman design`` and ``fir design``."""

from __future__ import annotations

import argparse
from typing import Any

from gyrobias.cli import _types


def add_emit_arguments(parser: argparse.ArgumentParser, default_name: str) -> None:
    """Add ``--emit-c DIR``, ``--c-dtype``, ``--c-name`` and ``--full-scale``."""
    g = parser.add_argument_group("C code generation (gyrobias.codegen)")
    g.add_argument(
        "--emit-c",
        type=_types.path,
        metavar="DIR",
        help="write a C99 header/source pair of the filter into DIR",
    )
    g.add_argument(
        "--c-dtype",
        choices=("float32", "float64", "q31"),
        default="float32",
        help="arithmetic of the generated C (default float32)",
    )
    g.add_argument(
        "--c-name",
        type=_types.c_identifier,
        default=default_name,
        help=f"C prefix (default {default_name})",
    )
    g.add_argument(
        "--full-scale",
        type=_types.positive,
        metavar="RATE",
        help="q31: the rate that INT32 full scale stands for (states the error in its units)",
    )


def emit(obj: Any, args: argparse.Namespace) -> None:
    """Run ``obj.to_c`` with the parsed options and print what was written."""
    gen = obj.to_c(args.emit_c, name=args.c_name, dtype=args.c_dtype, full_scale=args.full_scale)
    print(f"wrote {gen.header} and {gen.source} ({gen.dtype}, state {gen.state_bytes} bytes)")
    if gen.q31:
        bound = gen.q31["error_bound"]
        b = bound[0] if isinstance(bound, tuple) else bound
        print(f"  Q31 worst-case error against float64: {b:.3g} of full scale")

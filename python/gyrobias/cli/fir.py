"""``gyrobias fir design``: design the Kaiser-window FIR low-pass of [TS], optionally as C.

Example::

    gyrobias fir design --fs 1000 --fpass 20 --fstop 60 --astop 60 --emit-c firmware/

Prints the design (taps, attenuation, delay); with ``--emit-c DIR`` writes a streaming FIR
``<name>.h``/``<name>.c`` with CMSIS-DSP coefficient arrays (``docs/guides/embedded_c.md``).
"""

from __future__ import annotations

import argparse
from typing import Any

from gyrobias.cli import _emit


def register(subparsers: Any) -> argparse.ArgumentParser:
    """Add the ``fir`` command group (``fir design``)."""
    p: argparse.ArgumentParser = subparsers.add_parser(
        "fir", help="Kaiser-window FIR low-pass design (and C code generation)"
    )
    sub = p.add_subparsers(dest="fir_command", metavar="ACTION", required=True)
    d = sub.add_parser(
        "design",
        help="design the filter; --emit-c writes it as C99",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    d.add_argument("--fs", type=float, required=True, metavar="HZ", help="sample rate")
    d.add_argument("--fpass", type=float, required=True, help="pass-band edge (Hz)")
    d.add_argument("--fstop", type=float, required=True, help="stop-band edge (Hz)")
    d.add_argument("--apass", type=float, default=0.0001, help="pass-band ripple (dB)")
    d.add_argument("--astop", type=float, default=100.0, help="stop-band attenuation (dB)")
    _emit.add_emit_arguments(d, "gyro_fir")
    d.set_defaults(func=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Run ``gyrobias fir design``; returns the exit status."""
    from gyrobias.fir import kaiser_lowpass

    f = kaiser_lowpass(args.fs, args.fpass, args.fstop, apass_db=args.apass, astop_db=args.astop)
    print(
        f"Kaiser FIR low-pass: {f.numtaps} taps, A = {f.attenuation_db:.4g} dB, "
        f"alpha = {f.alpha:.6g}, cut-off {f.cutoff:g} Hz, delay {f.delay} samples "
        f"({f.delay / f.fs * 1e3:.4g} ms)"
    )
    if args.emit_c is not None:
        _emit.emit(f, args)
    return 0

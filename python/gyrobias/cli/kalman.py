"""``gyrobias kalman design``: design the fixed-gain Kalman filter of [NR], optionally as C.

Example::

    gyrobias kalman design --fs 1000 --arw 0.005 --rrw 1e-4 --bandwidth 20 --emit-c firmware/
    gyrobias kalman design --fs 1000 --arw 0.3 --arw-unit "deg/sqrt(h)" --bandwidth 20 \\
        --emit-c firmware/ --c-dtype q31 --full-scale 2000

Prints the design (gain, pole, bandwidth, noise reduction); with ``--emit-c DIR`` writes
``<name>.h``/``<name>.c`` (see ``docs/guides/embedded_c.md``). ``gyrobias filter LOG ...
--emit-c DIR`` does the same for the filter it runs on a log.
"""

from __future__ import annotations

import argparse
from typing import Any

from gyrobias.cli import _emit
from gyrobias.cli.filter import _ARW_UNITS, _RRW_UNITS, _noise_in_base_units, describe


def register(subparsers: Any) -> argparse.ArgumentParser:
    """Add the ``kalman`` command group (``kalman design``)."""
    p: argparse.ArgumentParser = subparsers.add_parser(
        "kalman", help="fixed-gain Kalman filter design (and C code generation)"
    )
    sub = p.add_subparsers(dest="kalman_command", metavar="ACTION", required=True)
    d = sub.add_parser(
        "design",
        help="design the filter; --emit-c writes it as C99",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    d.add_argument("--fs", type=float, required=True, metavar="HZ", help="sample rate")
    d.add_argument("--arw", type=float, required=True, help="angle random walk N (see --arw-unit)")
    d.add_argument("--rrw", type=float, default=0.0, help="rate random walk K (see --rrw-unit)")
    d.add_argument("--arw-unit", choices=_ARW_UNITS, default="u/sqrt(s)")
    d.add_argument("--rrw-unit", choices=_RRW_UNITS, default="u/s^1.5")
    design = d.add_mutually_exclusive_group(required=True)
    design.add_argument("--bandwidth", type=float, help="target -3 dB bandwidth in Hz")
    design.add_argument("--q-omega", type=float, help="per-step rate process noise, (u/s)^2")
    d.add_argument("--form", choices=("standard", "paper"), default="standard")
    _emit.add_emit_arguments(d, "gyro_kf")
    d.set_defaults(func=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Run ``gyrobias kalman design``; returns the exit status."""
    from gyrobias.kalman import FixedGainKalman

    arw, rrw = _noise_in_base_units(args)
    kf = FixedGainKalman(
        args.fs,
        arw=arw,
        rrw=rrw,
        q_omega=args.q_omega,
        bandwidth=args.bandwidth,
        form=args.form,
    )
    print(describe(kf))
    if args.emit_c is not None:
        _emit.emit(kf, args)
    return 0

"""``gyrobias filter``: denoise a gyro log with the fixed-gain Kalman filter of [NR].

Example::

    gyrobias filter gyro.csv --fs 200 --bandwidth 10 --arw 0.08 --rrw 7e-4 -o filtered.csv
    gyrobias filter imu.bag --columns gyro --bandwidth 10 --arw 0.0014 -o filtered.npy

``--emit-c DIR`` also writes the designed filter as C99 (``gyrobias kalman design`` does that
without a log; see ``docs/guides/embedded_c.md``).

``--arw`` is in u/√s and ``--rrw`` in u/s^1.5, u being the angle unit of the log's rates
(``--arw-unit deg/sqrt(h)`` and ``--rrw-unit deg/h^1.5`` accept the customary units for logs in
deg/s). The output (CSV or .npy) has, for every channel, the rate estimate and the bias estimate
(columns ``rate_<name>,bias_<name>``). Logs are read like every command's
(:func:`gyrobias.cli._common.read_log`: text, .npy, bags, MCAP); the rate comes from ``--fs`` or
the timestamps.
"""

from __future__ import annotations

import argparse
import math
from typing import TYPE_CHECKING, Any

from gyrobias.cli import _emit, _types
from gyrobias.cli._common import add_read_arguments, read_log, require_fs

if TYPE_CHECKING:
    from gyrobias.kalman import FixedGainKalman

#: The ``--arw-unit`` and ``--rrw-unit`` choices (``filter`` and ``kalman design``); the factors
#: to base units are gyrobias.kalman's, applied by :func:`_noise_in_base_units`.
_ARW_UNITS = ("deg/sqrt(h)", "u/sqrt(s)")
_RRW_UNITS = ("deg/h^1.5", "u/s^1.5")


def _noise_in_base_units(args: argparse.Namespace) -> tuple[float, float]:
    """``(--arw, --rrw)`` in u/√s and u/s^1.5: times the factor of their ``--*-unit``."""
    from gyrobias.kalman import arw_from_deg_per_sqrt_hour, rrw_from_deg_per_hour_1p5

    arw = {"u/sqrt(s)": 1.0, "deg/sqrt(h)": arw_from_deg_per_sqrt_hour(1.0)}[args.arw_unit]
    rrw = {"u/s^1.5": 1.0, "deg/h^1.5": rrw_from_deg_per_hour_1p5(1.0)}[args.rrw_unit]
    return args.arw * arw, args.rrw * rrw


def register(subparsers: Any) -> argparse.ArgumentParser:
    """Add the ``filter`` subcommand to an argparse subparsers object."""
    p: argparse.ArgumentParser = subparsers.add_parser(
        "filter",
        help="denoise a gyro log with the fixed-gain [rate, bias] Kalman filter ([NR])",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "log", type=_types.path, help="log of rates: text, .npy, a ROS bag or an MCAP file"
    )
    p.add_argument(
        "--arw", type=_types.positive, required=True, help="angle random walk N (see --arw-unit)"
    )
    p.add_argument(
        "--rrw", type=_types.non_negative, default=0.0, help="rate random walk K (see --rrw-unit)"
    )
    p.add_argument("--arw-unit", choices=_ARW_UNITS, default="u/sqrt(s)")
    p.add_argument("--rrw-unit", choices=_RRW_UNITS, default="u/s^1.5")
    design = p.add_mutually_exclusive_group(required=True)
    design.add_argument("--bandwidth", type=_types.positive, help="target -3 dB bandwidth in Hz")
    design.add_argument(
        "--q-omega", type=_types.positive, help="per-step rate process noise, (u/s)^2"
    )
    p.add_argument("--form", choices=("standard", "paper"), default="standard")
    p.add_argument(
        "-o", "--output", type=_types.path, help="output file (.csv or .npy); default: summary only"
    )
    add_read_arguments(p)
    _emit.add_emit_arguments(p, "gyro_kf")
    p.set_defaults(func=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Run ``gyrobias filter``; returns the exit status.

    Bad input raises ``ValueError``/``OSError``, which the ``gyrobias`` entry point prints as
    one error line (exit code 2).
    """
    import numpy as np

    from gyrobias.kalman import FixedGainKalman

    log = read_log(args)
    z = np.ascontiguousarray(log.data)
    names = list(log.columns)
    fs = require_fs(log, args.log)
    arw, rrw = _noise_in_base_units(args)
    kf = FixedGainKalman(
        fs,
        arw=arw,
        rrw=rrw,
        q_omega=args.q_omega,
        bandwidth=args.bandwidth,
        form=args.form,
    )
    if args.emit_c is not None:  # before filtering: a bad name or path fails fast
        _emit.emit(kf, args)
    rate, bias = kf.filter(z)
    print(describe(kf))
    print(f"{z.shape[0]} samples x {z.shape[1]} channels from {args.log}")
    for a, name in enumerate(names):
        raw = float(np.std(np.diff(z[:, a]))) / math.sqrt(2.0)
        print(
            f"  {name}: white noise per sample {raw:.4g} -> {raw * kf.white_noise_gain:.4g} "
            f"(expected after filtering), final bias estimate {bias[-1, a] + 0.0:.6g}"
        )
    if args.output is not None:
        from gyrobias._files import atomic_binary

        out = np.empty((z.shape[0], 2 * z.shape[1]))
        out[:, 0::2] = rate
        out[:, 1::2] = bias
        # Atomically (temporary file beside it, then rename): an interrupted or failed run
        # never leaves a truncated output file.
        with atomic_binary(args.output) as fh:
            if args.output.suffix == ".npy":
                np.save(fh, out)
            else:
                header = ",".join(f"rate_{n},bias_{n}" for n in names)
                np.savetxt(fh, out, delimiter=",", header=header, comments="", fmt="%.10g")
        print(f"wrote {args.output}")
    return 0


def describe(kf: FixedGainKalman) -> str:
    """A short, human-readable summary of a filter design."""
    bw = kf.bandwidth
    bw_s = "above Nyquist" if bw is None else f"{bw:.4g} Hz"
    return (
        f"fixed-gain Kalman ([NR], form={kf.form}): fs {kf.fs:g} Hz, q_omega {kf.q_omega:.4g} "
        f"(u/s)^2, K_s = [{kf.gain[0]:.6g}, {kf.gain[1]:.6g}], pole {kf.pole:.6g}, "
        f"-3 dB bandwidth {bw_s}, DC gain {kf.dc_gain:.9g}, "
        f"white-noise reduction {1.0 / kf.white_noise_gain:.3g}x"
    )

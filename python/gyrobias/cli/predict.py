"""``gyrobias predict``: [BP]'s bias-prediction batch test on a real static log.

Example::

    gyrobias predict LOG.csv --fs 100 --column gz --calibration 1000 --horizon 1000 --plot win.png

The log is split into disjoint sections of calibration + horizon samples ([BP] §V-C); each
section's bias is predicted from its calibration part by the fractional Kalman predictor (KF),
the moving average (MA) and the calibration mean (CM), and the Table I statistics are printed
(mean and standard deviation of the integrated error and of the RSSE) with the ratios to CM.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Any

from gyrobias.cli import _types

if TYPE_CHECKING:
    import numpy as np
    from numpy.typing import NDArray

__all__ = ["demo_section", "register", "run"]


def register(subparsers: Any) -> None:
    """Add the ``predict`` subcommand."""
    p = subparsers.add_parser(
        "predict",
        help="bias-prediction batch test ([BP] Table I) on a static gyro log",
        description=(
            "Split a long static gyro log into disjoint sections, predict each section's bias "
            "from its calibration part with the fractional Kalman predictor, the moving average "
            "and the calibration mean, and print [BP] Table I's statistics."
        ),
        epilog="example: gyrobias predict log.csv --fs 100 --column gz --calibration 1000 --horizon 1000",
    )
    p.add_argument(
        "log", type=_types.path, metavar="LOG", help="log: text, .npy, a ROS bag or an MCAP file"
    )
    p.add_argument(
        "--calibration",
        type=_types.positive_int,
        default=1000,
        metavar="K",
        help="calibration samples per section (default 1000)",
    )
    p.add_argument(
        "--horizon",
        type=_types.positive_int,
        default=1000,
        metavar="H",
        help="predicted samples per section (default 1000)",
    )
    p.add_argument(
        "--d",
        type=_types.finite,
        default=0.5,
        help="memory parameter of the 1/f model (default 0.5)",
    )
    p.add_argument(
        "--q",
        type=_types.non_negative,
        default=1.0,
        help="driving-noise variance per sample (default 1; irrelevant for r = 0 and --mean sample)",
    )
    p.add_argument(
        "--r",
        type=_types.non_negative,
        default=0.0,
        help="white-noise variance per sample (default 0, as [BP])",
    )
    p.add_argument(
        "--mean",
        choices=("sample", "diffuse", "none"),
        default="sample",
        help="mean-state prior (default sample)",
    )
    p.add_argument(
        "--plot", type=_types.path, metavar="PNG", help="draw one example window with the ±2σ band"
    )
    p.add_argument(
        "--window",
        type=_types.non_negative_int,
        default=0,
        metavar="I",
        help="section drawn by --plot (default 0)",
    )
    from gyrobias.cli._common import add_read_arguments

    add_read_arguments(p, column_help="the channel, by name or 0-based index (default: the first)")
    p.set_defaults(func=run)


def _read_log(args: argparse.Namespace) -> tuple[NDArray[np.float64], float]:
    """One channel of the log and the sample rate (shared reader; sampling problems reported)."""
    import numpy as np

    from gyrobias.cli._common import read_log, require_fs

    log = read_log(args)
    if log.data.shape[1] > 1 and args.columns is not None:
        raise ValueError(
            f"predict analyses one channel; --column selected {len(log.columns)}: {', '.join(log.columns)}"
        )
    return np.ascontiguousarray(log.data[:, 0]), require_fs(log, args.log)


def plot_window(
    section: NDArray[np.float64],
    calibration: int,
    fs: float,
    predictor: Any,
    path: Path,
    title: str = "",
) -> None:
    """Draw one section: data, the KF forecast with its ±2σ band, MA and CM ([BP] Figs. 2–3)."""
    from gyrobias import predict
    from gyrobias.plotting import save_prediction_plot

    k, h = calibration, section.size - calibration
    pred = predictor.predict(section[:k], h)
    forecasts = {
        "fractional Kalman": pred.bias,
        "moving average": predict.moving_average(section[:k], h),
        "calibration mean": predict.calibration_mean(section[:k], h),
    }
    save_prediction_plot(section, k, fs, forecasts, path, std=pred.std, title=title)


def run(args: argparse.Namespace) -> int:
    """Execute ``gyrobias predict``."""
    from gyrobias.predict import FractionalKalmanPredictor, evaluate

    y, fs = _read_log(args)
    predictor = FractionalKalmanPredictor(d=args.d, q=args.q, r=args.r, mean=args.mean)
    ev = evaluate(y, calibration=args.calibration, horizon=args.horizon, predictor=predictor)
    print(f"{args.log}: {y.size} samples at {fs:g} Hz")
    print(ev.table())
    if args.plot is not None:
        n = args.calibration + args.horizon
        i = args.window
        if not 0 <= i < ev.sections:
            raise ValueError(f"--window must be in 0..{ev.sections - 1}, got {i}")
        plot_window(
            y[i * n : (i + 1) * n], args.calibration, fs, predictor, args.plot, f"section {i}"
        )
        print(f"plot written to {args.plot}")
    return 0


def demo_section(rate: NDArray[np.float64], fs: float, outdir: Path) -> None:
    """Bias prediction on the demo's simulated log (z axis): [BP]'s batch test and a plot."""
    import numpy as np

    from gyrobias.predict import FractionalKalmanPredictor, evaluate

    y = np.ascontiguousarray(np.asarray(rate, dtype=float)[:, -1])
    k = h = int(min(1000, max(2, y.size // 20)))
    print(
        "\n== bias prediction ([BP] §V-C): z axis, sections of "
        f"{k / fs:g} s calibration + {h / fs:g} s prediction"
    )
    # The predictor's model comes from the log itself: Allan analysis → noise coefficients
    # (N, B) → (r, q) by FractionalKalmanPredictor.from_noise, as a user would do it.
    from gyrobias import allan, noise

    coefficients = noise.fit(allan.adev(y, fs, confidence=None), terms=("N", "B", "K"))
    predictor = FractionalKalmanPredictor.from_noise(coefficients, fs, d=0.5)
    print(
        f"model from the log's Allan fit: d = 0.5, q = {predictor.q:.3g}, r = {predictor.r:.3g} (deg/s)²"
    )
    ev = evaluate(y, calibration=k, horizon=h, predictor=predictor)
    print(ev.table())
    try:
        path = Path(outdir) / "bias_prediction.png"
        plot_window(y[: k + h], k, fs, predictor, path, "demo: bias prediction (z axis)")
        print(f"plot: {path}")
    except ImportError:
        print("(matplotlib not installed: no plot)")

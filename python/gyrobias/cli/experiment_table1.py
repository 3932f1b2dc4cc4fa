"""``gyrobias experiment table1``: reproduce the simulated columns of [BP] Table I.

Data (SPEC §5): ``runs`` type-II ARFIMA(0, ½, 0) series of 2000 samples with driving standard
deviation σ = 2.5 (not stated in [BP]; inferred from its CM row) plus a constant bias, from the
core's generator (:func:`gyrobias.fractional.arfima`). Each series is split into 1000 calibration
and 1000 predicted samples; the fractional Kalman predictor (d = ½, r = 0, ``mean="sample"``),
the moving average and the calibration mean are compared by the integrated error and the RSSE.

Expected scale-free ratios to CM (20 000 runs): KF RSSE 0.982, IE std 0.939 (exact 0.9416);
MA 1.006 and 0.977 (exact 0.9804). With 1000 runs the s.e. is ≈ 0.0025 (RSSE ratio) and ≈ 0.011
(IE-std ratio).
"""

from __future__ import annotations

import argparse
import time
from typing import TYPE_CHECKING, Any

from gyrobias.cli import _types

if TYPE_CHECKING:
    import numpy as np

__all__ = ["register_experiment", "run", "simulate"]

EXPECTED_RATIOS = {"kf": (0.982, 0.9416), "ma": (1.006, 0.9804)}


def register_experiment(exp_subparsers: Any) -> None:
    """Add ``table1`` to the ``gyrobias experiment`` group."""
    p = exp_subparsers.add_parser(
        "table1",
        help="reproduce [BP] Table I (simulated 1/f data: KF vs moving average vs calibration mean)",
        description=__doc__.split("\n\n")[1] if __doc__ else None,
    )
    p.add_argument(
        "--runs",
        type=_types.positive_int,
        default=1000,
        help="simulated series (default 1000, as [BP])",
    )
    p.add_argument(
        "--seed", type=_types.non_negative_int, default=0, help="random seed (default 0)"
    )
    p.add_argument(
        "--sigma", type=_types.positive, default=2.5, help="driving noise std σ (default 2.5)"
    )
    p.add_argument(
        "--bias",
        type=_types.finite,
        default=0.0,
        help="constant bias added to every series (default 0)",
    )
    p.add_argument(
        "--calibration",
        type=_types.positive_int,
        default=1000,
        help="calibration samples (default 1000)",
    )
    p.add_argument(
        "--horizon", type=_types.positive_int, default=1000, help="predicted samples (default 1000)"
    )
    p.add_argument(
        "--mean",
        choices=("sample", "diffuse"),
        default="sample",
        help="KF mean-state prior (default sample)",
    )
    p.add_argument(
        "--threads", type=_types.positive_int, default=None, help="threads (default: all)"
    )
    p.set_defaults(func=run)


def simulate(runs: int, n: int, sigma: float, seed: int, bias: float = 0.0) -> np.ndarray:
    """``runs`` type-II ARFIMA(0, ½, 0) series of ``n`` samples from the core generator."""
    import numpy as np

    from gyrobias import fractional

    x = fractional.arfima(n, 0.5, sigma=sigma, size=runs, seed=seed, kind="type2")
    return np.asarray(x, dtype=float).reshape(runs, n) + bias


def run(args: argparse.Namespace) -> int:
    """Execute ``gyrobias experiment table1``."""
    from gyrobias.predict import PAPER_TABLE1, FractionalKalmanPredictor, evaluate

    if args.runs < 3:
        raise ValueError(f"--runs must be at least 3, got {args.runs}")
    k, h = args.calibration, args.horizon
    t0 = time.perf_counter()
    data = simulate(args.runs, k + h, args.sigma, args.seed, args.bias)
    t1 = time.perf_counter()
    ev = evaluate(
        data,
        calibration=k,
        horizon=h,
        predictor=FractionalKalmanPredictor(d=0.5, q=1.0, r=0.0, mean=args.mean),
        n_threads=args.threads,
    )
    t2 = time.perf_counter()
    print(
        f"[BP] Table I, simulated: {args.runs} runs of type-II ARFIMA(0, 1/2, 0), σ = {args.sigma:g}, "
        f"seed {args.seed}, KF mean={args.mean!r}"
    )
    print(
        f"{'method':<6} {'mean RSSE':>10} {'(paper)':>8} {'RSSE std':>9} {'(paper)':>8} "
        f"{'IE std':>9} {'(paper)':>8} {'mean IE':>9}"
    )
    for key, st in ev.methods.items():
        pp = PAPER_TABLE1[key]
        print(
            f"{key.upper():<6} {st.mean_rsse:>10.1f} {pp['mean_rsse']:>8.0f} {st.rsse_std:>9.1f} "
            f"{pp['rsse_std']:>8.1f} {st.ie_std:>9.0f} {pp['ie_std']:>8.0f} {st.mean_ie:>9.1f}"
        )
    print("ratios to CM (± bootstrap s.e.)         ours                 paper    expected (exact)")
    for key in ("kf", "ma"):
        r1, s1 = ev.ratio(key, "cm", "rsse")
        r2, s2 = ev.ratio(key, "cm", "ie_std")
        p1 = PAPER_TABLE1[key]["mean_rsse"] / PAPER_TABLE1["cm"]["mean_rsse"]
        p2 = PAPER_TABLE1[key]["ie_std"] / PAPER_TABLE1["cm"]["ie_std"]
        e1, e2 = EXPECTED_RATIOS[key]
        print(
            f"  {key.upper()}/CM mean RSSE               {r1:.4f} ± {s1:.4f}     {p1:.4f}   {e1:.4f}"
        )
        print(
            f"  {key.upper()}/CM IE std                  {r2:.4f} ± {s2:.4f}     {p2:.4f}   {e2:.4f}"
        )
    print(f"time: simulation {t1 - t0:.2f} s, prediction and statistics {t2 - t1:.2f} s")
    return 0

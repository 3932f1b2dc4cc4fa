"""``gyrobias demo``: a simulated 3-axis MEMS gyro log with known noise terms, analysed end to end.

The log is simulated with :func:`gyrobias.noise.simulate` (angle random walk, bias
instability, rate random walk and a turn-on bias, different per axis), analysed with the
overlapping Allan deviation, and the plot and the log are saved to ``--outdir``. Later parts
of the library add their own sections: modules listed in :data:`SECTIONS` provide
``demo_section(rate, fs, outdir)`` (plus ``true_coefficients=`` when they accept it), called
in order with the same simulated log.
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

from gyrobias.cli import _types

if TYPE_CHECKING:
    import numpy as np

__all__ = ["SECTIONS", "TRUE_COEFFICIENTS", "register", "run"]

#: Modules providing ``demo_section(rate, fs, outdir)``; appended to extend the demo.
SECTIONS: list[str] = [
    "gyrobias.cli.noise",
    "gyrobias.cli.predict",
    "gyrobias.cli.experiment_kalman",
]

#: The simulated gyro, per axis (x, y, z), in customary units. Typical of a consumer/industrial
#: MEMS gyro: ARW 0.25–0.35 deg/√h, bias instability 4–6 deg/h, RRW 8–12 deg/h^1.5.
TRUE_COEFFICIENTS: dict[str, tuple[float, float, float]] = {
    "arw_deg_per_sqrt_h": (0.30, 0.25, 0.35),
    "bias_instability_deg_per_h": (5.0, 4.0, 6.0),
    "rrw_deg_per_h_1_5": (10.0, 8.0, 12.0),
    "bias_deg_per_s": (0.05, -0.03, 0.02),
}
AXES = ("x", "y", "z")


def register(subparsers: Any) -> None:
    """Add the ``demo`` subcommand."""
    p = subparsers.add_parser(
        "demo",
        help="simulate a 3-axis MEMS gyro with known noise and analyse it",
        description=(
            "Simulate a realistic 3-axis MEMS gyro log with known angle random walk, bias "
            "instability and rate random walk, print its Allan deviation next to the true "
            "coefficients, and save the plot and the log in OUTDIR."
        ),
    )
    p.add_argument(
        "--outdir",
        type=_types.path,
        default=Path("gyrobias-out"),
        help="where plots and the log go (default gyrobias-out/)",
    )
    p.add_argument(
        "--seed", type=_types.non_negative_int, default=2012, help="random seed (default 2012)"
    )
    p.add_argument(
        "--hours",
        type=_types.positive,
        default=2.0,
        help="length of the simulated log in hours (default 2)",
    )
    p.add_argument(
        "--fs", type=_types.positive, default=100.0, help="sample rate in Hz (default 100)"
    )
    p.set_defaults(func=run)


def _simulate(n: int, fs: float, seed: int) -> np.ndarray:
    """(n, 3) rate in deg/s; coefficients converted from customary to deg-based SI units."""
    import numpy as np

    from gyrobias import _core, noise

    c = TRUE_COEFFICIENTS
    seeds = _core.random.seeds(len(AXES), seed)  # one stream per axis, from the core's generator
    columns = []
    for i in range(len(AXES)):
        axis = noise.simulate(
            n,
            fs,
            arw=c["arw_deg_per_sqrt_h"][i] / 60.0,  # deg/√h → deg/√s (√3600 s = 60 √s)
            bias_instability=c["bias_instability_deg_per_h"][i] / 3600.0,  # deg/h → deg/s
            rrw=c["rrw_deg_per_h_1_5"][i] / 3600.0**1.5,  # deg/h^1.5 → deg/s^1.5
            bias=c["bias_deg_per_s"][i],
            axes=1,
            seed=int(seeds[i]),
        )
        columns.append(np.asarray(axis, dtype=np.float64).reshape(n))
    return np.column_stack(columns)


def run(args: argparse.Namespace) -> int:
    """Execute ``gyrobias demo``."""
    import numpy as np

    from gyrobias import allan
    from gyrobias._validation import positive_float, sample_rate

    hours = positive_float("--hours", args.hours)
    fs = sample_rate(args.fs)  # the core's check of fs, before n = hours·3600·fs
    n = int(round(hours * 3600.0 * fs))
    if n < 1000:
        raise ValueError(
            f"--hours {hours:g} at --fs {fs:g} gives only {n} samples; use at least 1000"
        )
    outdir: Path = args.outdir
    outdir.mkdir(parents=True, exist_ok=True)

    t = time.perf_counter()
    rate = _simulate(n, fs, args.seed)
    t_sim = time.perf_counter() - t
    print(
        f"Simulated 3-axis MEMS gyro: {hours:g} h at {fs:g} Hz ({n} samples per axis, seed {args.seed}, "
        f"{t_sim:.2f} s)\n"
    )
    c = TRUE_COEFFICIENTS
    print("True noise terms          " + "".join(f"{a:>10}" for a in AXES))
    rows = [
        ("ARW          [deg/√h]", "arw_deg_per_sqrt_h"),
        ("bias instab. [deg/h]", "bias_instability_deg_per_h"),
        ("RRW          [deg/h^1.5]", "rrw_deg_per_h_1_5"),
        ("bias         [deg/s]", "bias_deg_per_s"),
    ]
    for label, key in rows:
        print(f"{label:<26}" + "".join(f"{v:>10.3g}" for v in c[key]))

    t = time.perf_counter()
    results = allan.adev(rate, fs, units="deg/s", axis_names=list(AXES))
    t_adev = time.perf_counter() - t
    assert isinstance(results, tuple)
    print(
        f"\nOverlapping Allan deviation, 68.3 % confidence intervals ({t_adev:.2f} s for all axes)"
    )
    for r in results:
        print(f"\nADEV of axis {r.axis} [deg/s]")
        print(r.table())

    log_path = outdir / "demo_log.npy"
    from gyrobias._files import atomic_binary

    with atomic_binary(log_path) as fh:
        np.save(fh, rate)
    print(
        f"\nwrote {log_path} (rate in deg/s, columns x, y, z); try:\n"
        f"  gyrobias allan {log_path} --fs {fs:g} --units deg/s --plot {outdir / 'my_adev.png'}"
    )
    try:
        from gyrobias.plotting import save_allan_plot

        plot_path = outdir / "allan.png"
        save_allan_plot(results, plot_path, title=f"Simulated MEMS gyro, {hours:g} h at {fs:g} Hz")
        print(f"wrote {plot_path}")
    except ImportError as exc:  # the demo's numbers are still useful without matplotlib
        print(f"(no plot: {exc})")

    for name in SECTIONS:
        section = importlib.import_module(name).demo_section
        if "true_coefficients" in inspect.signature(section).parameters:
            section(rate, fs, outdir, true_coefficients=TRUE_COEFFICIENTS)
        else:
            section(rate, fs, outdir)
    return 0

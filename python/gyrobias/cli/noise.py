"""Command-line pieces of the noise-coefficient identification.

``add_fit_arguments(parser)`` adds ``--fit``, ``--fit-method``, ``--bound-confidence``,
``--export FMT=PATH`` (estimator parameter files, :mod:`gyrobias.exports`), ``--strict`` and
the deprecated alias
``--kalibr PATH`` (= ``--export kalibr=PATH``, the same writer) to the ``gyrobias allan``
parser; ``run_fit(args, results)`` fits each Allan result, prints the coefficients with
uncertainties and units, writes the export files, and leaves the coefficients in
``args.noise_coefficients`` for the plot. ``demo_section(...)`` is the demo's part.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from gyrobias.cli import _types

if TYPE_CHECKING:
    import numpy as np

    from gyrobias.noise import NoiseCoefficients

__all__ = [
    "add_fit_arguments",
    "add_fit_range_arguments",
    "demo_section",
    "fit_range_options",
    "run_fit",
]


def add_fit_arguments(parser: argparse.ArgumentParser) -> None:
    """Add ``--fit``, ``--fit-method``, ``--fit-terms``, ``--bound-confidence``, ``--export``,
    ``--export-rate``, ``--strict`` and the deprecated ``--kalibr`` to ``parser``."""
    group = parser.add_argument_group("noise coefficients (IEEE 952)")
    group.add_argument(
        "--fit",
        action="store_true",
        help="identify Q, N (ARW/VRW), B, K (RRW), R with uncertainties and draw the model",
    )
    group.add_argument(
        "--fit-method",
        choices=("joint", "ieee"),
        default="joint",
        help="joint weighted NNLS fit (default) or IEEE-952 slope read-off",
    )
    group.add_argument(
        "--fit-terms",
        type=_types.term_list,
        metavar="LIST",
        default="Q,N,B,K,R",
        help="comma-separated model terms: Q,N,B,K,R and Gauss–Markov GM,GM2 (default Q,N,B,K,R)",
    )
    add_fit_range_arguments(group)
    group.add_argument(
        "--bound-confidence",
        type=_types.finite,  # in (0, 1): the core's check (run_fit)
        metavar="P",
        default=0.95,
        help="one-sided confidence level of the upper bounds of terms the log does not show "
        "(default 0.95)",
    )
    group.add_argument(
        "--kalibr",
        type=_types.path,
        metavar="PATH",
        default=None,
        help="deprecated alias of --export kalibr=PATH (the same writer)",
    )
    group.add_argument(
        "--export",
        type=_types.export_spec,
        metavar="FMT=PATH",
        action="append",
        default=None,
        help="write estimator parameters (implies --fit): FMT is kalibr, openvins, vins, orbslam3, "
        "liosam, matlab, json, or all (PATH a directory); repeatable, e.g. --export vins=vins.yaml",
    )
    group.add_argument(
        "--export-rate",
        type=_types.positive,
        metavar="HZ",
        default=None,
        help="IMU rate written into the exports (default: the log's sample rate)",
    )
    group.add_argument(
        "--strict",
        action="store_true",
        help="refuse to export a required term the log only bounds from above (default: write "
        "the upper bound at --bound-confidence, marked UPPER BOUND in a comment)",
    )


def add_fit_range_arguments(group: argparse._ArgumentGroup) -> None:
    """Add ``--fit-tau-range MIN,MAX`` and ``--lines auto|none|F[:HW],…`` (the joint fit's
    ``tau_range`` and ``lines`` of :func:`gyrobias.noise.fit`) to ``group``."""
    group.add_argument(
        "--fit-tau-range",
        type=_types.tau_range,
        metavar="MIN,MAX",
        default=None,
        help="fit only the Allan points with MIN <= τ <= MAX seconds (joint fit; turns the "
        "automatic range selection off)",
    )
    group.add_argument(
        "--lines",
        type=_types.line_list,
        metavar="auto|none|F[:HW],…",
        default="auto",
        help="periodic disturbances modelled by a sinusoidal term (joint fit): auto (default, "
        "the lines found in the rate), none, or frequencies in Hz: F a seed, F:HW refined within "
        "F ± HW, F:0 held at F",
    )


def fit_range_options(args: argparse.Namespace, method: str) -> dict[str, Any]:
    """The ``tau_range`` and ``lines`` keyword arguments of :func:`gyrobias.noise.fit` from
    ``--fit-tau-range`` and ``--lines``; both apply to the joint fit only (a ``ValueError``
    for ``--fit-method ieee``, whose ranges are its slope regions)."""
    tau_range = getattr(args, "fit_tau_range", None)
    lines = getattr(args, "lines", "auto")
    if method != "joint":
        if tau_range is not None:
            raise ValueError("--fit-tau-range applies to --fit-method joint only")
        if lines != "auto":
            raise ValueError("--lines applies to --fit-method joint only")
        return {}
    return {"tau_range": tau_range, "lines": lines}


def _display(c: NoiseCoefficients) -> NoiseCoefficients:
    return c.to("ieee") if c.data_unit is not None else c


def run_fit(args: argparse.Namespace, results: Sequence[Any]) -> None:
    """Fit every Allan result, print the table, write the ``--export`` files.

    The coefficients are stored in ``args.noise_coefficients`` (a list, same order as
    ``results``) for the caller's plot. Does nothing unless ``--fit``, ``--export`` or
    ``--kalibr`` was given. ``--kalibr PATH`` is a deprecated alias of ``--export
    kalibr=PATH``: it goes through the same writer (:func:`gyrobias.exports.export`). Exits with
    a message when the fit or an export is impossible.
    """
    from gyrobias import _core
    from gyrobias.noise import NoiseCoefficients, fit

    # Refused even when nothing is fitted (an ignored option is still checked); the range is
    # the core's check, named as the user typed it.
    bound_confidence = _core.validate.probability(
        "--bound-confidence", float(getattr(args, "bound_confidence", 0.95))
    )
    want_fit = bool(getattr(args, "fit", False))
    kalibr = getattr(args, "kalibr", None)
    export_specs = _parse_exports(getattr(args, "export", None))
    if kalibr is not None:
        export_specs.append(("kalibr", Path(kalibr)))
    args.noise_coefficients = []
    if not want_fit and not export_specs:
        return
    method = getattr(args, "fit_method", "joint")
    terms = [
        t.strip() for t in str(getattr(args, "fit_terms", "Q,N,B,K,R")).split(",") if t.strip()
    ]
    extra = fit_range_options(args, method)
    coefficients: list[NoiseCoefficients] = []
    for r in results:
        try:
            c = fit(r, method=method, terms=terms, bound_confidence=bound_confidence, **extra)
        except ValueError as exc:
            name = f" axis {r.axis}" if getattr(r, "axis", None) else ""
            raise ValueError(f"noise fit{name} failed: {exc}") from None
        assert isinstance(c, NoiseCoefficients)
        coefficients.append(c)
        print(_display(c).summary())
        print()
        if c.diagnostics is not None and not c.diagnostics.passed:
            name = f" axis {c.axis}" if c.axis else ""
            print(
                f"gyrobias: warning: the noise model does not fit{name} (goodness-of-fit p = "
                f"{c.diagnostics.p_value:.2g} < 0.001); see the WARNING lines above",
                file=sys.stderr,
            )
    args.noise_coefficients = coefficients
    if kalibr is not None and not any(c.sensor for c in coefficients):
        raise ValueError(
            "--kalibr needs the data unit (e.g. --units deg/s or rad/s, m/s^2) to write SI values"
        )
    if export_specs:
        _write_exports(
            export_specs,
            coefficients,
            getattr(args, "export_rate", None),
            rostopic=getattr(args, "rostopic", None) or "/imu0",
            strict=bool(getattr(args, "strict", False)),
        )
    if kalibr is not None:  # after the files: an error stays the only stderr line
        print(
            "gyrobias: warning: --kalibr is deprecated; use --export kalibr=PATH (same file)",
            file=sys.stderr,
        )


def _parse_exports(specs: Sequence[tuple[str, str]] | None) -> list[tuple[str, Path]]:
    """``[("vins", "out.yaml"), ...]`` (checked by :func:`_types.export_spec`) with paths."""
    return [(fmt, Path(path)) for fmt, path in specs or ()]


def _write_exports(
    specs: list[tuple[str, Path]],
    coefficients: Sequence[NoiseCoefficients],
    rate: float | None,
    *,
    rostopic: str = "/imu0",
    strict: bool = False,
) -> None:
    from gyrobias.exports import DEFAULT_FILENAMES, export, export_all

    gyro = [c for c in coefficients if c.sensor == "gyro"]
    accel = [c for c in coefficients if c.sensor == "accel"]
    if not gyro and not accel:
        raise ValueError(
            "--export needs the data unit (e.g. --units deg/s or m/s^2) to write SI values"
        )
    for fmt, path in specs:
        try:
            if fmt == "all":
                export_all(
                    gyro or None,
                    path,
                    accel=accel or None,
                    rate=rate,
                    rostopic=rostopic,
                    strict=strict,
                )
                print(
                    f"wrote {', '.join(str(path / n) for n in DEFAULT_FILENAMES.values())}",
                    file=sys.stderr,
                )
            else:
                export(
                    gyro or None,
                    fmt,
                    path,
                    accel=accel or None,
                    rate=rate,
                    rostopic=rostopic,
                    strict=strict,
                )
                print(f"wrote {path} ({fmt})", file=sys.stderr)
            bounded = sorted(
                {
                    f"{c.sensor} {t.symbol} (axis {c.axis or '?'})"
                    for c in coefficients
                    for t in (c.N, c.K)
                    if t.bounded
                }
            )
            if bounded:
                print(
                    f"gyrobias: note: --export {fmt}: upper bounds written for terms the log does "
                    f"not show ({', '.join(bounded)}), marked UPPER BOUND in the file; --strict "
                    "refuses them",
                    file=sys.stderr,
                )
        except (ValueError, OSError) as exc:  # one line "gyrobias: error: ...", exit 2
            raise ValueError(f"--export {fmt}: cannot write {path}: {exc}") from None


_TRUE_KEYS = {
    "quantization": "Q",
    "arw": "N",
    "bias_instability": "B",
    "rrw": "K",
    "rate_ramp": "R",
}

#: Customary-unit keys (the demo's table) → (simulate keyword, factor to deg/s-based units).
_CUSTOMARY_KEYS = {
    "arw_deg_per_sqrt_h": ("arw", 1.0 / 60.0),
    "bias_instability_deg_per_h": ("bias_instability", 1.0 / 3600.0),
    "rrw_deg_per_h_1_5": ("rrw", 1.0 / 216000.0),
}


def _true_per_axis(
    true_coefficients: Mapping[str, Any] | None, n_axes: int
) -> dict[str, list[float]]:
    """Normalise the true coefficients to {simulate keyword: [value per axis]} in base units."""
    import numpy as np

    out: dict[str, list[float]] = {}
    for key, value in (true_coefficients or {}).items():
        if key in _CUSTOMARY_KEYS:
            key, factor = _CUSTOMARY_KEYS[key]
        elif key in _TRUE_KEYS:
            factor = 1.0
        else:
            continue
        values = np.broadcast_to(np.asarray(value, dtype=np.float64), (n_axes,))
        out[key] = [float(v) * factor for v in values]
    return out


def demo_section(
    rate: np.ndarray,
    fs: float,
    outdir: Path,
    true_coefficients: Mapping[str, Any] | None = None,
    *,
    unit: str = "deg/s",
) -> None:
    """Fit the simulated log and print recovered vs true coefficients side by side.

    Parameters
    ----------
    rate : ndarray, shape (n,) or (n, axes)
        Simulated rate in ``unit``.
    fs : float
        Sample rate in Hz.
    outdir : Path
        Where ``noise_fit.png`` is written.
    true_coefficients : mapping, optional
        The simulated coefficients: :func:`gyrobias.noise.simulate` keywords (``arw``,
        ``bias_instability``, ``rrw``, ``quantization``, ``rate_ramp`` in base units of
        ``unit``) or the demo's customary keys (``arw_deg_per_sqrt_h``,
        ``bias_instability_deg_per_h``, ``rrw_deg_per_h_1_5``); each a scalar or one value per
        axis. Without it only the recovered values are printed.
    """
    import numpy as np

    from gyrobias import noise
    from gyrobias.allan import adev
    from gyrobias.noise import fit
    from gyrobias.units import conversion_factor

    data = np.asarray(rate, dtype=np.float64)
    matrix = data.reshape(-1, 1) if data.ndim == 1 else data
    names = ["x", "y", "z"] if matrix.shape[1] == 3 else [str(i) for i in range(matrix.shape[1])]
    try:
        results = adev(matrix, fs, taus="octave", units=unit, axis_names=names)
    except ValueError:  # confidence intervals not available: SP1065 approximate EDF instead
        results = adev(matrix, fs, taus="octave", units=unit, axis_names=names, confidence=None)
    assert isinstance(results, tuple)
    fits = [fit(r) for r in results]
    ieee = [c.to("ieee") for c in fits]
    sensor = ieee[0].sensor or "gyro"
    truth = _true_per_axis(true_coefficients, len(names))
    print("Noise coefficients: recovered (joint weighted fit, ±1σ) vs simulated (true)")
    header = f"  {'term':<30} " + "  ".join(f"{'axis ' + n:>30}" for n in names) + "  unit"
    print(header)
    for key, symbol in _TRUE_KEYS.items():
        term0 = ieee[0][symbol]
        if key not in truth and all(c[symbol].value is None for c in ieee):
            continue
        factor = 1.0
        if fits[0][symbol].unit is not None and term0.unit is not None:
            factor = conversion_factor(fits[0][symbol].unit or "", term0.unit)
        cells = []
        for a, c in enumerate(ieee):
            t = c[symbol]
            got = f"{t.value:.4g} ± {t.uncertainty:.2g}" if t.value is not None else "missing"
            if key in truth:
                got += f" ({truth[key][a] * factor:.4g})"
            cells.append(got)
        label = f"{symbol} {noise.TERM_NAMES[sensor][symbol]}"
        print(f"  {label:<30} " + "  ".join(f"{c:>30}" for c in cells) + f"  {term0.unit or ''}")
    from gyrobias.plotting import save_noise_model_plot

    try:
        outdir.mkdir(parents=True, exist_ok=True)
        path = outdir / "noise_fit.png"
        save_noise_model_plot(
            fits[0], path, title=f"Allan deviation and fitted noise model (axis {names[0]})"
        )
        print(f"  plot: {path}")
    except ImportError:
        print("  (matplotlib not installed: no plot)")

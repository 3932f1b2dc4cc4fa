"""A self-contained one-page HTML noise report of an IMU log.

:func:`build_report` analyses every channel of a :class:`gyrobias.io.GyroLog` — overlapping
Allan deviation with confidence intervals, the joint noise fit with uncertainties and goodness
of fit, the conservative (overbounding) set — and renders one HTML page with the log summary and
timestamp report, a plot per channel, the coefficient tables, warnings, and every estimator
export (best fit and conservative) as copyable text. Plots are SVG embedded as ``data:`` URIs;
there is no external script, style sheet, font or image, so the file works offline, and a print
style sheet lays it out on A4.
"""

from __future__ import annotations

import base64
import dataclasses
import datetime as _dt
import html
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from gyrobias import _core
from gyrobias._validation import checked_path, choice, optional_text, pair, real, sequence
from gyrobias.exports import DEFAULT_FILENAMES, FORMATS, atomic_write, export

if TYPE_CHECKING:
    from gyrobias.allan import AllanResult
    from gyrobias.conservative import ConservativeCoefficients
    from gyrobias.io import GyroLog
    from gyrobias.noise import NoiseCoefficients

__all__ = ["ChannelReport", "build_report", "write_report"]


@dataclass(frozen=True)
class ChannelReport:
    """Everything the report shows for one channel."""

    name: str
    unit: str | None
    allan: AllanResult | None
    fit: NoiseCoefficients | None = None
    conservative: ConservativeCoefficients | None = None
    errors: tuple[str, ...] = field(default=())


def _analyse(
    log: GyroLog,
    units: Sequence[str | None],
    confidence: float | None,
    method: str,
    conservative_confidence: float,
    bound_confidence: float,
    fit_options: Mapping[str, Any],
) -> list[ChannelReport]:
    from gyrobias import allan, noise

    assert log.fs is not None
    out = []
    for j, name in enumerate(log.columns):
        unit = units[j]
        errors: list[str] = []
        column = log.data[:, j]
        # NaN from --fill-gaps or from the outlier step are gaps the estimator skips.
        gaps = "omit" if np.isnan(column).any() else "error"
        try:
            r = allan.adev(
                column, log.fs, confidence=confidence, units=unit, axis_names=[name], gaps=gaps
            )
        except ValueError as exc:
            out.append(ChannelReport(name, unit, None, errors=(f"Allan analysis failed: {exc}",)))
            continue
        assert not isinstance(r, tuple)
        check = r.stationarity
        if check is not None and log.selection is not None and log.selection.start_s:
            # times in the log as read (the fit's warnings repeat them)
            object.__setattr__(r, "stationarity", check.shifted(log.selection.start_s))
        fit = cons = None
        try:
            fit = noise.fit(r, method=method, bound_confidence=bound_confidence, **fit_options)
        except ValueError as exc:
            errors.append(f"noise fit failed: {exc}")
        if fit is not None:
            try:
                cons = fit.conservative(conservative_confidence)
            except ValueError as exc:
                errors.append(f"conservative set not available: {exc}")
        out.append(ChannelReport(name, unit, r, fit, cons, tuple(errors)))
    return out


_CSS = """
:root { --ink: #1b1f24; --muted: #57606a; --line: #d0d7de; --bg: #f6f8fa; --warn: #9a6700; --bad: #cf222e; }
* { box-sizing: border-box; }
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial, sans-serif;
       color: var(--ink); max-width: 60rem; margin: 2rem auto; padding: 0 1rem; line-height: 1.45; }
h1 { font-size: 1.6rem; margin-bottom: 0.2rem; }
h2 { font-size: 1.25rem; border-bottom: 1px solid var(--line); padding-bottom: 0.2rem; margin-top: 2rem; }
h3 { font-size: 1.05rem; margin: 1.2rem 0 0.4rem; }
.meta { color: var(--muted); margin-top: 0; }
table { border-collapse: collapse; margin: 0.5rem 0 1rem; font-size: 0.9rem; }
th, td { border: 1px solid var(--line); padding: 0.25rem 0.55rem; text-align: left; vertical-align: top; }
th { background: var(--bg); }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
figure { margin: 0.5rem 0 1rem; }
figure img { width: 100%; max-width: 44rem; height: auto; display: block; }
figcaption { color: var(--muted); font-size: 0.85rem; }
.warnings li { color: var(--warn); }
.error { color: var(--bad); }
.ok { color: #1a7f37; }
pre { background: var(--bg); border: 1px solid var(--line); padding: 0.6rem; overflow-x: auto;
      font-size: 0.78rem; line-height: 1.35; white-space: pre; }
.export { position: relative; }
button.copy { position: absolute; top: 0.3rem; right: 0.3rem; font-size: 0.75rem; cursor: pointer; }
.channel { break-inside: avoid-page; }
footer { color: var(--muted); font-size: 0.8rem; margin-top: 2rem; border-top: 1px solid var(--line); }
@page { size: A4; margin: 14mm 12mm; }
@media print {
  body { max-width: none; margin: 0; padding: 0; font-size: 9.5pt; }
  h2 { break-after: avoid-page; }
  figure, table, .export { break-inside: avoid-page; }
  figure img { max-width: 17cm; }
  pre { white-space: pre-wrap; word-break: break-all; font-size: 7.5pt; }
  button.copy { display: none; }
}
"""

_SCRIPT = """
document.querySelectorAll("button.copy").forEach(function (b) {
  b.addEventListener("click", function () {
    var text = document.getElementById(b.dataset.target).textContent;
    if (navigator.clipboard) { navigator.clipboard.writeText(text); }
    b.textContent = "copied";
    setTimeout(function () { b.textContent = "copy"; }, 1500);
  });
});
"""


def _e(value: Any) -> str:
    return html.escape(str(value), quote=True)


def _num(v: float | None, digits: int = 4) -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "—"
    return f"{v:.{digits}g}"


def _svg_img(svg: str, alt: str) -> str:
    data = base64.b64encode(svg.encode("utf-8")).decode("ascii")
    return f'<img src="data:image/svg+xml;base64,{data}" alt="{_e(alt)}">'


def _duration(seconds: float) -> str:
    if seconds >= 3600.0:
        return f"{seconds / 3600.0:.3g} h"
    if seconds >= 60.0:
        return f"{seconds / 60.0:.3g} min"
    return f"{seconds:.3g} s"


def _log_section(log: GyroLog, title: str, cleaning: str | None = None) -> str:
    s = log.sampling
    assert log.fs is not None
    rows = [
        ("file", title),
        ("samples × channels", f"{log.n_samples} × {len(log.columns)} ({', '.join(log.columns)})"),
        ("sample rate", f"{log.fs:.9g} Hz ({s.fs_source or 'given'})"),
        ("duration", _duration(log.n_samples / log.fs)),
        *(
            [("analysed span", f"τ computed on {log.selection}")]
            if log.selection is not None
            else []
        ),
        *([("cleaning", cleaning)] if cleaning is not None else []),
        ("time column", log.time_column or "none"),
        (
            "units",
            ", ".join(
                f"{c}: {u or '?'}"
                for c, u in zip(log.columns, log.units or (None,) * len(log.columns))
            ),
        ),
    ]
    if log.topic:
        rows.append(("topic", str(log.topic)))
    if s.time_unit is not None:
        rows += [
            ("timestamps read as", s.time_unit),
            ("median interval", f"{_num(s.median_interval)} s"),
            ("jitter", f"{100 * (s.jitter or 0.0):.3g} %"),
            (
                "gaps",
                f"{s.n_gaps} (longest {_num(s.longest_gap)} s, {s.missing_samples} samples missing)",
            ),
            ("repeated timestamps", str(s.n_duplicates)),
        ]
    body = "".join(f"<tr><th>{_e(k)}</th><td>{_e(v)}</td></tr>" for k, v in rows)
    parts = ['<section id="log"><h2>Log and timestamps</h2>', f"<table>{body}</table>"]
    if s.warnings:
        parts.append(
            '<ul class="warnings">' + "".join(f"<li>{_e(w)}</li>" for w in s.warnings) + "</ul>"
        )
    else:
        parts.append('<p class="ok">Sampling: no irregularities found.</p>')
    parts.append("</section>")
    return "".join(parts)


def _coefficient_table(c: NoiseCoefficients) -> str:
    shown = c.to("ieee") if c.data_unit is not None else c
    rows = []
    for t in shown.terms:
        if t.value is None and t.upper_bound is not None:
            level = "?" if t.bound_confidence is None else f"{100 * t.bound_confidence:.4g} %"
            rows.append(
                f"<tr><td>{t.symbol}</td><td>{_e(t.name)}</td><td class=num>≤ {_num(t.upper_bound)}"
                f" <b>(upper bound, {level})</b></td><td>{_e(t.unit or '')}</td>"
                f"<td>not visible above the others: {_e(t.bound_reason or '')}</td></tr>"
            )
            continue
        if t.value is None:
            rows.append(
                f"<tr><td>{t.symbol}</td><td>{_e(t.name)}</td><td colspan=3>missing: {_e(t.missing)}</td></tr>"
            )
            continue
        unc = t.uncertainty
        note = ""
        if unc is not None and t.value < 2.0 * unc:
            note = " (not significant, &lt; 2σ)"
        rng = f"{t.tau_range[0]:.3g}–{t.tau_range[1]:.3g} s" if t.tau_range else "—"
        rows.append(
            f"<tr><td>{t.symbol}</td><td>{_e(t.name)}</td><td class=num>{_num(t.value)} ± {_num(unc, 2)}{note}</td>"
            f"<td>{_e(t.unit or '')}</td><td>{rng}</td></tr>"
        )
    head = "<tr><th></th><th>term</th><th>value ± 1σ</th><th>unit</th><th>τ range</th></tr>"
    return f"<table>{head}{''.join(rows)}</table>"


def _fit_quality(c: NoiseCoefficients) -> tuple[str, list[str]]:
    """One line on goodness of fit and the fit's warnings."""
    warnings: list[str] = []
    diagnostics = c.diagnostics
    parts = [
        f"{c.method} fit over τ {c.tau_range[0]:.3g}–{c.tau_range[1]:.3g} s, EDF from {c.edf_source}"
    ]
    if c.chi2 is not None and c.dof:
        parts.append(f"weighted χ²/ν = {c.chi2 / c.dof:.3g} (ν = {c.dof})")
    if diagnostics is not None:
        parts.append(f"p-value {diagnostics.p_value:.3g}")
        warnings += [str(w) for w in diagnostics.warnings]
    elif c.chi2 is not None and c.dof and c.chi2 / c.dof > 3.0:
        warnings.append(
            f"χ²/ν = {c.chi2 / c.dof:.3g}: the five-term model does not explain the curve within its "
            "intervals; treat the uncertainties with care"
        )
    for t in c.terms:
        if t.value is not None and t.uncertainty is not None and t.value < 2.0 * t.uncertainty:
            warnings.append(f"{t.symbol} ({t.name}) is not significant (value < 2σ)")
    return "; ".join(parts), warnings


def _conservative_table(cc: ConservativeCoefficients) -> str:
    shown = cc.coefficients.to("ieee") if cc.coefficients.data_unit else cc.coefficients
    best = cc.best.to("ieee") if cc.best.data_unit else cc.best
    rows = []
    for s in ("Q", "N", "B", "K", "R"):
        t, b, f = shown[s], best[s], cc.inflation[s]
        if t.value is None and b.value is None:
            continue
        infl = "—" if f is None else ("new term" if math.isinf(f) else f"×{f:.3g}")
        rows.append(
            f"<tr><td>{s}</td><td class=num>{_num(t.value)}</td><td class=num>{_num(b.value)}</td>"
            f"<td>{_e(t.unit or b.unit or '')}</td><td class=num>{infl}</td></tr>"
        )
    head = "<tr><th></th><th>conservative</th><th>best fit</th><th>unit</th><th>inflation</th></tr>"
    lead = (
        f"<p>Model Allan deviation ≥ the {100 * cc.confidence:.3g} % one-sided upper confidence bound at "
        f"all {cc.taus.size} τ used (smallest margin ×{cc.margin:.4g}); Lethander &amp; Taylor, "
        "NAVIGATION 70(3), 2023.</p>"
    )
    return lead + f"<table>{head}{''.join(rows)}</table>"


def _channel_section(ch: ChannelReport, index: int) -> str:
    from gyrobias.plotting import allan_report_svg

    sensor = ch.fit.sensor if ch.fit is not None and ch.fit.sensor else "channel"
    unit = f", {ch.unit}" if ch.unit else ""
    parts = [
        f'<section class="channel" id="ch{index}"><h2>{_e(ch.name)} ({_e(sensor)}{_e(unit)})</h2>'
    ]
    check = ch.allan.stationarity if ch.allan is not None else None
    not_static = check.warnings if check is not None else ()
    if not_static:
        parts.append(
            '<ul class="warnings not-static">'
            + "".join(f"<li><strong>Not a static log.</strong> {_e(w)}</li>" for w in not_static)
            + "</ul>"
        )
    if ch.allan is not None and not np.any(np.asarray(ch.allan.avar) > 0.0):
        parts.append(
            '<p class="error">No plot: the Allan deviation is zero at every τ (constant data).</p>'
        )
    elif ch.allan is not None:
        try:
            svg = allan_report_svg(
                ch.allan, ch.fit, ch.conservative, title=f"Allan deviation of {ch.name}"
            )
            parts.append(
                f"<figure>{_svg_img(svg, f'Allan deviation of {ch.name}')}<figcaption>Overlapping Allan "
                "deviation with its confidence intervals (bars), the fitted noise model (solid) and the "
                "conservative model (dashed) above the upper confidence bounds (triangles).</figcaption></figure>"
            )
        except ImportError as exc:
            parts.append(f'<p class="error">No plot: {_e(exc)}</p>')
    if ch.fit is not None:
        quality, warnings = _fit_quality(ch.fit)
        warnings = [w for w in warnings if w not in not_static]  # shown above
        parts.append(f"<h3>Noise coefficients (IEEE 952)</h3><p>{_e(quality)}</p>")
        parts.append(_coefficient_table(ch.fit))
        if warnings:
            parts.append(
                '<ul class="warnings">' + "".join(f"<li>{_e(w)}</li>" for w in warnings) + "</ul>"
            )
    if ch.conservative is not None:
        parts.append("<h3>Conservative set</h3>" + _conservative_table(ch.conservative))
    for err in ch.errors:
        parts.append(f'<p class="error">{_e(err)}</p>')
    parts.append("</section>")
    return "".join(parts)


def _exports_section(channels: list[ChannelReport], rate: float | None) -> str:
    best = [c.fit for c in channels if c.fit is not None and c.fit.sensor is not None]
    cons = [
        c.conservative.coefficients
        for c in channels
        if c.conservative is not None and c.conservative.coefficients.sensor
    ]
    parts = ['<section id="exports"><h2>Estimator parameters</h2>']
    if not best:
        parts.append(
            '<p class="error">No exports: estimator files need SI values, so the channels need a unit '
            "(e.g. --units deg/s, or m/s^2 for accelerometers).</p></section>"
        )
        return "".join(parts)
    parts.append(
        "<p>Each value is the largest over the channels of its sensor. Keys, units and the continuous / "
        "discrete convention of every format are listed in the convention table of the gyrobias documentation (Estimator parameters).</p>"
    )
    n = 0
    for label, group in (("best fit", best), ("conservative set", cons)):
        if not group:
            continue
        gyro = [c for c in group if c.sensor == "gyro"] or None
        accel = [c for c in group if c.sensor == "accel"] or None
        parts.append(f"<h3>From the {label}</h3>")
        for fmt in FORMATS:
            n += 1
            try:
                text = export(gyro, fmt, accel=accel, rate=rate)
            except ValueError as exc:
                parts.append(f'<p><b>{fmt}</b>: <span class="error">{_e(exc)}</span></p>')
                continue
            ident = f"export-{n}"
            marked = ""
            if "UPPER BOUND" in text:
                marked = (
                    ' <span class="error"><b>contains upper bounds</b> (terms the log does not '
                    "show; marked UPPER BOUND in the file)</span>"
                )
            parts.append(
                f'<div class="export"><p><b>{fmt}</b> — <code>{DEFAULT_FILENAMES[fmt]}</code>{marked}</p>'
                f'<button class="copy" data-target="{ident}" type="button">copy</button>'
                f'<pre><code id="{ident}">{_e(text)}</code></pre></div>'
            )
    parts.append("</section>")
    return "".join(parts)


def _check_log(log: Any) -> None:
    """Type and shape of ``log`` (a :class:`gyrobias.io.GyroLog` with samples and a rate)."""
    from gyrobias.io import GyroLog

    if not isinstance(log, GyroLog):
        raise TypeError(f"log must be a GyroLog (from gyrobias.io.load), got {type(log).__name__}")
    shape = np.shape(log.data)
    if len(shape) != 2 or shape[1] != len(log.columns):
        raise ValueError(
            f"log.data must have shape (samples, {len(log.columns)}) for its "
            f"{len(log.columns)} channels, got {shape}"
        )
    if shape[0] == 0 or shape[1] == 0:
        raise ValueError(f"log has no samples (data of shape {shape})")
    if log.fs is None:
        raise ValueError(
            "log: no sample rate (give fs= to gyrobias.io.load, or --fs on the command line)"
        )


def build_report(
    log: GyroLog,
    *,
    units: str | Sequence[str | None] | None = None,
    confidence: float | None = 0.683,
    method: str = "joint",
    conservative_confidence: float = 0.95,
    rate: float | None = None,
    title: str | None = None,
    bound_confidence: float = 0.95,
    outliers: float | None = None,
    detrend: str | None = None,
    tau_range: tuple[float, float] | None = None,
    lines: str | Sequence[float | tuple[float, float]] | None = "auto",
) -> str:
    """Analyse every channel of ``log`` and return the report as one HTML document.

    Parameters
    ----------
    log : GyroLog
        A loaded log (:func:`gyrobias.io.load`) with a sample rate.
    units : str or sequence of str, optional
        Unit of every channel, or one per channel (``"deg/s"``, ``"rad/s"``, ``"m/s^2"``, ``"g"``);
        default: the log's own units (``GyroLog.units``). Without units the coefficients stay
        in data units and no estimator file is written.
    confidence : float or None
        Level of the Allan confidence intervals (two-sided; default 0.683 ≈ 1σ).
    method : {"joint", "ieee"}
        Identification method.
    conservative_confidence : float
        One-sided level of the conservative set (default 0.95).
    rate : float, optional
        IMU rate written into the exports (default: the log's sample rate).
    title : str, optional
        Page title (default: the log's file name).
    bound_confidence : float
        One-sided confidence level of the upper bounds of terms the log does not show
        (:func:`gyrobias.noise.fit`; default 0.95), shown with each bound and in the exports'
        ``UPPER BOUND`` marks.
    outliers : float, optional
        Remove the samples whose robust z-score exceeds this threshold before the analysis
        (:func:`gyrobias.cleaning.remove_outliers`; they become gaps).
    detrend : {"linear", "quadratic"}, optional
        Remove each channel's drift after the outliers (:func:`gyrobias.cleaning.detrend`).
        Both steps (:func:`gyrobias.cleaning.clean`) are stated in the log table.
    tau_range : (float, float), optional
        ``method="joint"`` only: fit the Allan points in this τ range (seconds).
    lines : "auto", sequence or None
        ``method="joint"`` only: the lines modelled by a sinusoid (:func:`gyrobias.noise.fit`).

    Returns
    -------
    str
        Self-contained HTML (no network access needed to display or print it).

    Raises
    ------
    TypeError
        ``log`` is not a :class:`gyrobias.io.GyroLog`.
    ValueError
        A log without samples or a sample rate, data not of shape (samples, channels),
        ``units`` with the wrong number of entries, or no channel that could be analysed
        (e.g. all NaN); a channel that fails while others succeed is reported on the page.
        An invalid option (``method``, ``confidence``, ``conservative_confidence`` or
        ``bound_confidence`` outside (0, 1), ``rate`` not finite and > 0) raises before any
        channel is analysed.
    """
    _check_log(log)
    # The options apply to every channel: refuse a bad one here (the per-channel isolation
    # below is for failures of the data, which must not turn into a page of errors for a typo).
    choice("method", method, ("joint", "ieee"))
    _core.validate.probability(
        "conservative_confidence", real("conservative_confidence", conservative_confidence)
    )
    if confidence is not None:
        _core.validate.probability("confidence", real("confidence", confidence))
    bound_confidence = _core.validate.probability(
        "bound_confidence", real("bound_confidence", bound_confidence)
    )
    if rate is not None:
        _core.validate.positive("rate", real("rate", rate))
    optional_text("title", title)
    k = len(log.columns)
    if units is None:
        per_channel: list[str | None] = list(log.units) if log.units else [None] * k
    elif isinstance(units, str):
        per_channel = [units] * k
    else:
        per_channel = sequence("units", units)
        if len(per_channel) != k:
            raise ValueError(f"units has {len(per_channel)} entries for {k} channels")
    fit_options: dict[str, Any] = {}
    if tau_range is not None:  # low < high: noise.fit's (the core's) check
        tau_range = pair("tau_range", tau_range)
    if tau_range is not None or not (isinstance(lines, str) and lines == "auto"):
        if method != "joint":
            raise ValueError("tau_range and lines apply to method='joint' only")
        fit_options = {"tau_range": tau_range, "lines": lines}
    cleaned = None
    if outliers is not None or detrend is not None:
        from gyrobias import cleaning

        assert log.fs is not None  # _check_log
        cleaned = cleaning.clean(
            log.data, log.fs, outliers=outliers, detrend=detrend, units=per_channel
        )
        log = dataclasses.replace(log, data=cleaned.data)
    channels = _analyse(
        log,
        per_channel,
        confidence,
        method,
        conservative_confidence,
        bound_confidence,
        fit_options,
    )
    if all(ch.allan is None for ch in channels):
        # Nothing to report: a page of error messages would pass for a report.
        reasons = "; ".join(f"{ch.name}: {', '.join(ch.errors)}" for ch in channels)
        raise ValueError(f"log: no channel could be analysed ({reasons})")
    from gyrobias._version import __version__

    name = title or Path(log.path).name
    now = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    body = [
        f"<header><h1>Noise report: {_e(name)}</h1>",
        (
            f'<p class="meta">gyrobias {_e(__version__)} · {now} · overlapping Allan deviation, IEEE-952 '
            f"{_e(method)} fit, conservative set at {100 * conservative_confidence:.3g} %</p></header>"
        ),
        _log_section(log, str(log.path), None if cleaned is None else cleaned.describe()),
        *(_channel_section(ch, i) for i, ch in enumerate(channels)),
        _exports_section(channels, rate),
        (
            "<footer><p>Model σ²(τ) = 3Q²/τ² + N²/τ + (0.664282·B)² + K²τ/3 + R²τ²/2 (IEEE Std 952, Annex C). "
            "N and K are two-sided densities (Kalibr's convention); a datasheet's one-sided noise density "
            "is √2·N. Uncertainties are standard (1σ). Confidence intervals: NIST SP 1065 §5.</p></footer>"
        ),
    ]
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>Noise report: {_e(name)}</title><style>{_CSS}</style></head><body>"
        + "\n".join(body)
        + f"<script>{_SCRIPT}</script></body></html>\n"
    )


def write_report(path: str | os.PathLike[str], log: GyroLog, **kwargs: Any) -> Path:
    """:func:`build_report` written atomically to ``path``; returns the path."""
    target = checked_path("path", path)  # before the report is built
    return atomic_write(target, build_report(log, **kwargs))

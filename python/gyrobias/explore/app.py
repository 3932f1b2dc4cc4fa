"""The explorer's user interface (Panel on Bokeh): widgets bound to :class:`Session` objects.

Every number on screen comes from the session (:mod:`gyrobias.explore.state`), which calls the
public API; this module only draws. Plots are Bokeh figures built once, whose data sources are
replaced on each change (a redraw sends only the new points). The rate of a long log is drawn
from a min/max envelope of the visible time span (:func:`gyrobias.cleaning.minmax_envelope`),
recomputed on the server after each pan or zoom.
"""

from __future__ import annotations

import html
import io as _stdio
import math
import threading
import time
import traceback
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import panel as pn
from bokeh.events import RangesUpdate, SelectionGeometry
from bokeh.models import (  # type: ignore[attr-defined]
    BoxAnnotation,
    BoxSelectTool,
    ColumnDataSource,
    HoverTool,
    Span,
    Whisker,
)
from bokeh.palettes import Category10_10
from bokeh.plotting import figure

from gyrobias.explore.state import FORMATS, METHODS, TERMS, Session, export_filename

__all__ = ["ExploreApp", "ENVELOPE_BINS"]

#: Bins of the rate envelope across the visible span (two points each: min and max).
ENVELOPE_BINS = 1200
#: Largest upload (a log sent from the browser), MB: refused in the browser beyond it.
UPLOAD_LIMIT_MB = 200
#: At most this many outlier markers are drawn (the count is always exact).
MAX_OUTLIER_MARKERS = 5000
_COLORS = Category10_10
_DEVIATION_LABELS = {
    "adev": "ADEV (overlapping Allan)",
    "mdev": "MDEV (modified Allan)",
    "hdev": "HDEV (overlapping Hadamard)",
    "totdev": "TOTDEV (total)",
    "theo1": "Théo1",
    "wvar": "wavelet variance (classical, as ADEV-equivalent √(2ν²))",
    "wvar-robust": "wavelet variance (robust, as ADEV-equivalent √(2ν²))",
}
_READY = "<span class='gb-idle'>ready: {view}</span>"
_WORKING = "<span class='gb-working'>working…</span>"
_WORKING_DONE = "<span class='gb-working'>working… {done:.0%}</span>"
#: Seconds between two progress messages sent to the page.
_PROGRESS_EVERY = 0.25
_CSS = """
.gb-pre { font-family: monospace; font-size: 12px; white-space: pre; overflow-x: auto; }
.gb-steps li { margin: 2px 0; }
"""


def _envelope(data: Any, lo: int, hi: int, bins: int) -> tuple[Any, Any, Any]:
    """Rows ``lo:hi`` of ``data`` (n, k) as a min/max envelope
    (:func:`gyrobias.cleaning.minmax_envelope`, one pass in the core over a view: no copy):
    each bin's middle row, and its minimum and maximum per channel, shape (bins, k)."""
    from gyrobias import cleaning

    env = cleaning.minmax_envelope(data[lo:hi], bins)
    starts = np.asarray(env.starts)
    middle = (starts[:-1] + starts[1:] - 1) // 2 + lo
    return middle, np.asarray(env.lower), np.asarray(env.upper)


def load_upload(name: str, content: Any, *, units: str | None = None) -> Session:
    """A session of an uploaded log: ``content`` (bytes, at most :data:`UPLOAD_LIMIT_MB`) is
    read by :func:`gyrobias.io.load` from a temporary file in a private directory, deleted as
    soon as it is read (nothing else on the server's disk is reachable from the browser)."""
    import tempfile
    from pathlib import Path

    from gyrobias import io
    from gyrobias.explore.state import Source

    if isinstance(content, str):
        content = content.encode("utf-8")
    if not isinstance(content, (bytes, bytearray)):
        raise TypeError(f"an upload must be bytes, got {type(content).__name__}")
    if len(content) > UPLOAD_LIMIT_MB * 1_000_000:
        raise ValueError(f"the file is larger than the upload limit ({UPLOAD_LIMIT_MB} MB)")
    safe = Path(name).name or "upload"  # never a path: the name only
    options: dict[str, Any] = {} if units is None else {"units": units}
    with tempfile.TemporaryDirectory(prefix="gyrobias-upload-") as tmp:
        path = Path(tmp) / safe
        path.write_bytes(bytes(content))
        log = io.load(path, spill=False, **options)
    source = Source.from_options(Path(safe), options)
    return Session(log, Source(source.path, source.options, f"{safe} (uploaded)"))


class _View:
    """A tab: ``panel`` is shown; ``refresh()`` redraws it from the session."""

    title = ""

    def __init__(self, app: ExploreApp) -> None:
        self.app = app
        self.panel: Any = pn.Column()

    def refresh(self) -> None:  # pragma: no cover - every view overrides it
        raise NotImplementedError

    def prefetch(self) -> None:
        """The view's numerics (cached in the session), run off the event loop; no drawing."""


def _heading(text: str, level: int = 4) -> Any:
    """A heading as an HTML pane (no Markdown parsed while the first page is built)."""
    return pn.pane.HTML(f"<h{level}>{html.escape(text)}</h{level}>", margin=(0, 10))


def _message(text: str, kind: str = "warning") -> Any:
    return pn.pane.Alert(html.escape(text), alert_type=kind, sizing_mode="stretch_width")


def _pre(text: str, cls: str) -> Any:
    return pn.pane.HTML(
        f'<pre class="gb-pre {cls}">{html.escape(text)}</pre>',
        sizing_mode="stretch_width",
        stylesheets=[_CSS],
    )


class _LogView(_View):
    title = "Log"

    def __init__(self, app: ExploreApp) -> None:
        super().__init__(app)
        self.figures: list[Any] = []
        self.sources: list[list[ColumnDataSource]] = []
        self.shade: list[BoxAnnotation] = []
        self.info = pn.pane.HTML(sizing_mode="stretch_width", stylesheets=[_CSS])
        self.built_for: Session | None = None

    def _build(self, session: Session) -> None:
        log = session.log
        assert log is not None
        self.figures, self.sources, self.shade = [], [], []
        x_range = None
        fs = session.fs
        for unit, cols in session.unit_groups():
            fig = figure(
                height=240,
                sizing_mode="stretch_width",
                x_axis_label="time from the start of the log (s)",
                y_axis_label=f"rate [{unit}]" if unit else "rate",
                tools="xpan,xwheel_zoom,reset,save",
                active_scroll="xwheel_zoom",
                output_backend="webgl",
            )
            if x_range is None:
                x_range = fig.x_range
            else:
                fig.x_range = x_range
            box = BoxSelectTool(dimensions="width", persistent=False)
            fig.add_tools(box)
            fig.toolbar.active_drag = box
            srcs = []
            for c in cols:
                src = ColumnDataSource({"t": [], "lo": [], "hi": []})
                color = _COLORS[c % len(_COLORS)]
                fig.varea(
                    "t",
                    "lo",
                    "hi",
                    source=src,
                    fill_color=color,
                    fill_alpha=0.55,
                    legend_label=log.columns[c],
                )
                srcs.append(src)
            fig.legend.location = "top_left"
            fig.legend.click_policy = "hide"
            shade = BoxAnnotation(fill_color="#2a7ab0", fill_alpha=0.12, left=0, right=0)
            fig.add_layout(shade)
            fig.on_event(SelectionGeometry, self._on_select)
            fig.on_event(RangesUpdate, self._on_range)
            self.figures.append(fig)
            self.sources.append(srcs)
            self.shade.append(shade)
        self.groups = session.unit_groups()
        self.fs = fs
        self.built_for = session
        self.panel[:] = [
            pn.pane.HTML(
                "<p>Drag on a plot to select the part to analyse (or type it at the left); "
                "scroll to zoom. The rate is drawn as its minimum and maximum per pixel.</p>"
            ),
            *[pn.pane.Bokeh(f, sizing_mode="stretch_width") for f in self.figures],
            self.info,
        ]
        self._draw(0, log.n_samples)

    def _time(self, session: Session, rows: Any) -> Any:
        log = session.log
        assert log is not None
        if log.time is not None:
            return np.asarray(log.time)[np.minimum(rows, log.n_samples - 1)]
        return rows / session.fs

    def _draw(self, lo: int, hi: int) -> None:
        session = self.built_for
        assert session is not None and session.log is not None
        data = session.log.data
        lo, hi = max(0, lo), min(session.log.n_samples, hi)
        if hi - lo < 2:
            return
        idx, mn, mx = _envelope(data, lo, hi, ENVELOPE_BINS)
        t = self._time(session, idx)
        for (_unit, cols), srcs in zip(self.groups, self.sources):
            for c, src in zip(cols, srcs):
                src.data = {"t": t, "lo": mn[:, c], "hi": mx[:, c]}

    def _on_range(self, event: Any) -> None:
        session = self.built_for
        if session is None or event.x0 is None or event.x1 is None:
            return
        fs = session.fs
        lo = int(math.floor(float(event.x0) * fs)) - 1
        hi = int(math.ceil(float(event.x1) * fs)) + 2
        try:
            self._draw(lo, hi)
        except Exception as exc:  # a redraw never kills the page
            self.app.show_error(exc)

    def _on_select(self, event: Any) -> None:
        if not event.final:
            return
        g = event.geometry
        x0, x1 = float(g.get("x0", 0.0)), float(g.get("x1", 0.0))
        start = max(0.0, min(x0, x1))
        stop = max(x0, x1)
        self.app.apply(start=round(start, 6), stop=round(stop, 6))

    def refresh(self) -> None:
        session = self.app.session
        if session.log is None:
            self.panel[:] = [_message("An Allan result was given: there is no log to show.")]
            self.built_for = None
            return
        if self.built_for is not session:
            self._build(session)
        s = session.settings
        for shade in self.shade:
            if s.start is None and s.stop is None:
                shade.visible = False
            else:
                shade.visible = True
                shade.left = s.start or 0.0
                shade.right = s.stop if s.stop is not None else session.duration
        self.info.object = self.app.sampling_html(session)


class _CleanView(_View):
    title = "Clean"

    def prefetch(self) -> None:
        if self.app.session.log is not None:
            self.app.session.cleaned()

    def __init__(self, app: ExploreApp) -> None:
        super().__init__(app)
        self.fig = figure(
            height=300,
            sizing_mode="stretch_width",
            x_axis_label="time from the start of the log (s)",
            y_axis_label="rate",
            tools="xpan,xwheel_zoom,reset,save",
            output_backend="webgl",
        )
        self.before = ColumnDataSource({"t": [], "lo": [], "hi": []})
        self.after = ColumnDataSource({"t": [], "lo": [], "hi": []})
        self.flagged = ColumnDataSource({"t": [], "y": []})
        self.fig.varea(
            "t", "lo", "hi", source=self.before, fill_color="#bbbbbb", legend_label="selection"
        )
        self.fig.varea(
            "t",
            "lo",
            "hi",
            source=self.after,
            fill_color="#1f77b4",
            fill_alpha=0.6,
            legend_label="after the cleaning steps",
        )
        self.fig.scatter(
            "t",
            "y",
            source=self.flagged,
            marker="x",
            color="#d62728",
            size=7,
            legend_label="outliers removed",
        )
        self.channel = pn.widgets.Select(label="channel", options=[], width=200)
        self.channel.param.watch(lambda *_: self.refresh(), "value")
        self.table = pn.pane.HTML(sizing_mode="stretch_width", stylesheets=[_CSS])
        self.panel[:] = [
            self.channel,
            pn.pane.Bokeh(self.fig, sizing_mode="stretch_width"),
            self.table,
        ]

    def refresh(self) -> None:
        session = self.app.session
        if session.log is None:
            self.panel[:] = [_message("An Allan result was given: there is nothing to clean.")]
            return
        cols = list(session.columns)
        if list(self.channel.options) != cols:
            self.channel.options = cols
            self.channel.value = cols[0]
        c = cols.index(self.channel.value) if self.channel.value in cols else 0
        part = session.selection()
        cleaned = session.cleaned()
        n = part.n_samples
        t_all = part.time if part.time is not None else None
        offset = part.selection.start_index if part.selection is not None else 0

        def times(rows: Any) -> Any:
            rows = np.minimum(np.asarray(rows), n - 1)
            if t_all is not None:
                return np.asarray(t_all)[rows]
            return (rows + offset) / session.fs

        idx, mn, mx = _envelope(part.data, 0, n, ENVELOPE_BINS)
        self.before.data = {"t": times(idx), "lo": mn[:, c], "hi": mx[:, c]}
        # the kept samples (a bin of removed samples only is a break in the band)
        idx, mn, mx = _envelope(cleaned.data, 0, n, ENVELOPE_BINS)
        self.after.data = {"t": times(idx), "lo": mn[:, c], "hi": mx[:, c]}
        if cleaned.outlier_mask is not None:
            rows = np.flatnonzero(np.asarray(cleaned.outlier_mask)[:, c])[:MAX_OUTLIER_MARKERS]
            self.flagged.data = {"t": times(rows), "y": np.asarray(part.data[rows, c])}
        else:
            self.flagged.data = {"t": [], "y": []}
        self.fig.yaxis.axis_label = f"{cols[c]} [{session.log.units[c] or 'data unit'}]"
        s = session.settings
        rows_html = []
        for k, name in enumerate(cols):
            trend = cleaned.trend[k] if cleaned.trend else ()
            rows_html.append(
                f"<tr><td>{html.escape(name)}</td><td class='gb-outliers'>{cleaned.outliers[k]}</td>"
                f"<td>{', '.join(f'{v:.6g}' for v in trend) or '—'}</td></tr>"
            )
        self.table.object = (
            f"<p>{n} samples selected; outliers: "
            f"{'off' if s.outliers is None else f'beyond {s.outliers:g} σ'}; drift: "
            f"{s.detrend or 'kept'}.</p><table><tr><th>channel</th><th>outliers removed</th>"
            f"<th>drift polynomial (gyrobias.cleaning.detrend coefficients)</th></tr>"
            + "".join(rows_html)
            + "</table>"
        )


def _dev_arrays(r: Any) -> tuple[Any, Any, Any, Any]:
    """(τ, deviation, low, high) of an Allan result or a wavelet variance (as √(2ν²))."""
    if hasattr(r, "scales"):
        tau = np.asarray(r.scales) / 2.0
        dev = np.sqrt(2.0 * np.asarray(r.variance))
        return tau, dev, np.sqrt(2.0 * np.asarray(r.ci_low)), np.sqrt(2.0 * np.asarray(r.ci_high))
    dev = np.asarray(r.adev)
    lo = None if r.ci_low is None else np.asarray(r.ci_low)
    hi = None if r.ci_high is None else np.asarray(r.ci_high)
    return np.asarray(r.taus), dev, lo, hi


def _loglog(title: str, height: int = 380) -> Any:
    fig = figure(
        height=height,
        sizing_mode="stretch_width",
        x_axis_type="log",
        y_axis_type="log",
        x_axis_label="τ (s)",
        y_axis_label="deviation",
        title=title,
        tools="pan,wheel_zoom,box_zoom,reset,save",
    )
    fig.add_tools(HoverTool(tooltips=[("τ", "@tau{0.000e}"), ("σ", "@dev{0.000e}")]))
    return fig


class _Curves:
    """A log-log figure built once whose curves are updated in place (a redraw sends only the
    new points): ``show(name, ...)`` draws or updates a curve, ``finish(names)`` hides the
    others (and their legend entries)."""

    def __init__(self, title: str, height: int = 380) -> None:
        self.fig = _loglog(title, height)
        self.items: dict[str, tuple[ColumnDataSource, ColumnDataSource, list[Any], Any]] = {}
        self.pane = pn.pane.Bokeh(self.fig, sizing_mode="stretch_width")

    def show(
        self,
        name: str,
        tau: Any,
        dev: Any,
        color: str,
        *,
        lo: Any = None,
        hi: Any = None,
        points: bool = True,
        dash: str = "solid",
        width: float = 1.0,
    ) -> None:
        dev = np.asarray(dev)
        ok = np.isfinite(dev) & (dev > 0)
        data = {"tau": np.asarray(tau)[ok], "dev": dev[ok]}
        band = {"tau": data["tau"], "lo": data["dev"], "hi": data["dev"]}
        if lo is not None and hi is not None:
            band = {"tau": data["tau"], "lo": np.asarray(lo)[ok], "hi": np.asarray(hi)[ok]}
        item = self.items.get(name)
        if item is None:
            src, bsrc = ColumnDataSource(data), ColumnDataSource(band)
            renderers = [
                self.fig.line(
                    "tau",
                    "dev",
                    source=src,
                    color=color,
                    line_dash=dash,
                    line_width=width,
                    legend_label=name,
                )
            ]
            if points:
                renderers.append(
                    self.fig.scatter(
                        "tau", "dev", source=src, color=color, size=4, legend_label=name
                    )
                )
            whisker = Whisker(source=bsrc, base="tau", lower="lo", upper="hi", line_color=color)
            self.fig.add_layout(whisker)
            self.items[name] = (src, bsrc, renderers, whisker)
            self.fig.legend.location = "bottom_left"
            self.fig.legend.click_policy = "hide"
        else:
            src, bsrc, renderers, whisker = item
            src.data = data
            bsrc.data = band
            for r in renderers:
                r.visible = True
        self.items[name][3].visible = lo is not None and hi is not None

    def finish(self, names: Any) -> None:
        """Hide every curve not in ``names``."""
        keep = set(names)
        for name, (_s, _b, renderers, whisker) in self.items.items():
            if name not in keep:
                for r in renderers:
                    r.visible = False
                whisker.visible = False
        for item in self.fig.legend.items:
            label = getattr(item.label, "value", item.label)  # a bokeh Value or a string
            item.visible = label in keep


class _StabilityView(_View):
    title = "Stability"

    def prefetch(self) -> None:
        self.app.session.stability()

    def __init__(self, app: ExploreApp) -> None:
        super().__init__(app)
        self.kind = pn.widgets.Select(
            label="statistic", options={v: k for k, v in _DEVIATION_LABELS.items()}, width=380
        )
        self.kind.param.watch(self._on_kind, "value")
        self.layout = pn.widgets.RadioButtonGroup(
            label="axes", options=["overlaid", "apart"], value="overlaid"
        )
        self.layout.param.watch(lambda *_: self.refresh(), "value")
        self.plots = pn.Column(sizing_mode="stretch_width")
        self.figures: dict[Any, _Curves] = {}
        self.panel[:] = [pn.Row(self.kind, self.layout), self.plots]

    def _on_kind(self, event: Any) -> None:
        if not self.app.syncing:
            self.app.apply(deviation=event.new)

    def refresh(self) -> None:
        session = self.app.session
        s = session.settings
        self.app.syncing = True
        try:
            self.kind.value = s.deviation
        finally:
            self.app.syncing = False
        results = session.stability()
        label = _DEVIATION_LABELS[s.deviation]
        apart = self.layout.value == "apart"
        wanted: dict[str, list[tuple[int, Any]]] = {}
        for k, r in enumerate(results):
            key = f"{r.axis}" if apart else f"{r.unit}"
            wanted.setdefault(key, []).append((k, r))
        panes = []
        for key, members in wanted.items():
            fkey = (session.source.label, apart, key)
            curves = self.figures.get(fkey)
            if curves is None:
                curves = self.figures[fkey] = _Curves("", height=300 if apart else 380)
            unit = members[0][1].unit or "data unit"
            curves.fig.title.text = f"{label}: {key} [{unit}]" if apart else f"{label} [{unit}]"
            for k, r in members:
                tau, dev, lo, hi = _dev_arrays(r)
                curves.show(str(r.axis), tau, dev, _COLORS[k % len(_COLORS)], lo=lo, hi=hi)
            curves.finish(str(r.axis) for _, r in members)
            panes.append(curves.pane)
        if list(self.plots.objects) != panes:
            self.plots[:] = panes


class _FitView(_View):
    title = "Fit"

    def prefetch(self) -> None:
        session = self.app.session
        session.coefficients()
        if session.settings.method != "gmwm":
            session.conservative()

    def __init__(self, app: ExploreApp) -> None:
        super().__init__(app)
        self.channel = pn.widgets.Select(label="channel", options=[], width=200)
        self.channel.param.watch(lambda *_: self.refresh(), "value")
        self.plot = pn.Column(sizing_mode="stretch_width")
        self.summary = pn.pane.HTML(sizing_mode="stretch_width", stylesheets=[_CSS])
        self.diagnostics = pn.pane.HTML(sizing_mode="stretch_width", stylesheets=[_CSS])
        self.lines = pn.widgets.CheckBoxGroup(label="detected lines", options=[], inline=False)
        self.lines.param.watch(self._on_lines, "value")
        self.conservative = pn.pane.HTML(sizing_mode="stretch_width", stylesheets=[_CSS])
        self.curves = _Curves("fit")
        fig = self.curves.fig
        self.used = BoxAnnotation(fill_color="#2ca02c", fill_alpha=0.07)
        fig.add_layout(self.used)
        self.excluded: list[Any] = []
        self.spans = [Span(dimension="height", line_dash="dotted") for _ in range(2)]
        for span in self.spans:
            fig.add_layout(span)
        box = BoxSelectTool(dimensions="width", persistent=False)
        fig.add_tools(box)
        fig.toolbar.active_drag = box
        fig.on_event(SelectionGeometry, self._on_select)
        self.plot[:] = [self.curves.pane]
        self.panel[:] = [
            pn.pane.Markdown(
                "Drag across the plot to set the τ range of the fit (or type it at the left)."
            ),
            self.channel,
            self.plot,
            pn.Row(
                pn.Column("### Coefficients", self.summary, sizing_mode="stretch_width"),
                pn.Column(
                    "### Diagnostics",
                    self.diagnostics,
                    "### Spectral lines",
                    self.lines,
                    width=420,
                ),
            ),
            "### Conservative set (overbounds the curve at 95 %)",
            self.conservative,
        ]
        self._detected: list[float] = []

    def _on_lines(self, event: Any) -> None:
        if self.app.syncing:
            return
        chosen = tuple(float(f) for f in event.new)
        if set(chosen) == set(self._detected):
            self.app.apply(lines="auto")
        elif not chosen:
            self.app.apply(lines="none")
        else:
            self.app.apply(lines=tuple(sorted(chosen)))

    def refresh(self) -> None:
        session = self.app.session
        s = session.settings
        fits = session.coefficients()
        cols = list(session.columns)
        if list(self.channel.options) != cols:
            self.channel.options = cols
            self.channel.value = cols[0]
        k = cols.index(self.channel.value) if self.channel.value in cols else 0
        c = fits[k]
        self.summary.object = (
            '<pre class="gb-pre gb-summary">'
            + html.escape("\n\n".join(f.to("ieee").summary() for f in fits))
            + "</pre>"
        )
        # the plot: measured curve with intervals, total model, each term's asymptote
        r = c.allan
        curves = self.curves
        curves.fig.title.text = f"{s.method} fit, channel {cols[k]} [{c.data_unit or 'data unit'}]"
        shown = []
        if r is not None:
            tau, dev, lo, hi = _dev_arrays(r)
            curves.show("measured", tau, dev, "#333333", lo=lo, hi=hi)
            grid = np.geomspace(tau[0], tau[-1], 200)
            total, parts = c.model(grid)
            curves.show("model", grid, total, "#d62728", points=False, width=2.0)
            shown += ["measured", "model"]
            for j, (sym, v) in enumerate(parts.items()):
                v = np.asarray(v)
                if np.any(np.isfinite(v) & (v > 0)):
                    color = _COLORS[(j + 1) % len(_COLORS)]
                    curves.show(sym, grid, v, color, points=False, dash="dashed")
                    shown.append(sym)
        curves.finish(shown)
        d = c.diagnostics
        self.used.visible = d is not None
        if d is not None:
            self.used.left, self.used.right = d.tau_range
        excluded = list(d.excluded) if d is not None else []
        while len(self.excluded) < len(excluded):
            box = BoxAnnotation(fill_color="#7f7f7f", fill_alpha=0.15)
            curves.fig.add_layout(box)
            self.excluded.append(box)
        for i, box in enumerate(self.excluded):
            box.visible = i < len(excluded)
            if i < len(excluded):
                box.left, box.right = excluded[i][0], excluded[i][1]
        for span, t in zip(self.spans, s.tau_range or (None, None)):
            span.visible = t is not None
            if t is not None:
                span.location = t
        self.diagnostics.object = _diagnostics_html(c)
        # lines: detected ones (joint/GMWM with lines="auto" or chosen ones)
        detected = sorted({float(line.frequency) for f in fits for line in _lines_of(f)})
        self._detected = detected
        chosen: list[float] = (
            detected
            if s.lines == "auto"
            else ([] if s.lines == "none" else [float(f) for f in s.lines])
        )
        self.app.syncing = True
        try:
            options = sorted(set(detected) | set(chosen))
            self.lines.options = {f"{f:.6g} Hz": f for f in options}
            self.lines.value = [f for f in chosen if f in options]
        finally:
            self.app.syncing = False
        if s.method == "gmwm":
            self.conservative.object = (
                "<p>The conservative set is built from an Allan fit (joint or IEEE).</p>"
            )
        else:
            try:
                cons = session.conservative()
                self.conservative.object = (
                    '<pre class="gb-pre gb-conservative">'
                    + html.escape("\n\n".join(_conservative_text(x) for x in cons))
                    + "</pre>"
                )
            except ValueError as exc:
                self.conservative.object = f"<p>{html.escape(str(exc))}</p>"

    def _on_select(self, event: Any) -> None:
        if not event.final:
            return
        g = event.geometry
        x0, x1 = float(g.get("x0", 0.0)), float(g.get("x1", 0.0))
        lo, hi = sorted((x0, x1))
        if lo > 0 and hi > lo:
            self.app.apply(tau_range=(float(f"{lo:.4g}"), float(f"{hi:.4g}")))


def _lines_of(c: Any) -> Sequence[Any]:
    d = c.diagnostics
    return () if d is None else tuple(d.lines)


def _conservative_text(x: Any) -> str:
    c = x.coefficients.to("ieee")
    head = f"axis {c.axis}: margin {x.margin:.3g}" if hasattr(x, "margin") else f"axis {c.axis}"
    rows = [head]
    for t in c.terms:
        if t.value is not None:
            infl = x.inflation.get(t.symbol)
            rows.append(
                f"  {t.symbol} {t.value:.4g} {t.unit or ''}"
                + (f"  (×{infl:.3g} the best fit)" if infl is not None else "")
            )
    return "\n".join(rows)


def _diagnostics_html(c: Any) -> str:
    d = c.diagnostics
    if d is None:
        return "<p>No diagnostics.</p>"
    nu = d.dof
    red = d.chi2 / nu if nu else float("nan")
    parts = [
        f"<p class='gb-diag'>χ²/ν = {d.chi2:.4g}/{nu} = {red:.3g}, p = {d.p_value:.3g} "
        f"({'passed' if d.passed else 'REJECTED'}); τ used {d.tau_range[0]:.4g}–{d.tau_range[1]:.4g} s</p>"
    ]
    if d.excluded:
        parts.append(
            "<p>Excluded τ:</p><ul>"
            + "".join(
                f"<li>{f'{a:.4g}' if a == b else f'{a:.4g}–{b:.4g}'} s: {html.escape(why)}</li>"
                for a, b, why in d.excluded
            )
            + "</ul>"
        )
    bounds = [t for t in c.to("ieee").terms if t.bounded]
    if bounds:
        parts.append(
            "<p>Upper bounds (terms the log does not show):</p><ul>"
            + "".join(
                f"<li>{t.symbol} ≤ {t.upper_bound:.4g} {html.escape(t.unit or '')} "
                f"({100 * (t.bound_confidence or 0):.3g} %)</li>"
                for t in bounds
            )
            + "</ul>"
        )
    if d.warnings:
        parts.append("<ul>" + "".join(f"<li>{html.escape(w)}</li>" for w in d.warnings) + "</ul>")
    return "".join(parts)


class _CompareView(_View):
    title = "Compare"

    def __init__(self, app: ExploreApp) -> None:
        super().__init__(app)
        self.choice = pn.widgets.MultiChoice(
            label="curves", options=[], sizing_mode="stretch_width"
        )
        self.choice.param.watch(lambda *_: self.refresh(), "value")
        self.plots = pn.Column(sizing_mode="stretch_width")
        self.figures: dict[Any, _Curves] = {}
        self.panel[:] = [
            pn.pane.Markdown(
                "ADEV of every log and channel loaded, each with its own part and cleaning steps."
            ),
            self.choice,
            self.plots,
        ]

    def refresh(self) -> None:
        keys = [
            f"{i}: {s.source.label} · {col}"
            for i, s in enumerate(self.app.sessions)
            for col in s.columns
        ]
        if list(self.choice.options) != keys:
            self.choice.options = keys
            self.choice.value = keys[: min(len(keys), 12)]
        wanted: dict[Any, list[tuple[int, str, Any]]] = {}
        for k, key in enumerate(self.choice.value):
            i = int(key.split(":", 1)[0])
            col = key.rsplit(" · ", 1)[1]
            session = self.app.sessions[i]
            try:
                r = session.allan()[list(session.columns).index(col)]
            except Exception as exc:  # one failing log does not hide the others
                self.app.show_error(exc, f"{session.source.label}: ")
                continue
            wanted.setdefault(r.unit, []).append((k, key.split(": ", 1)[1], r))
        panes = []
        for unit, members in wanted.items():
            curves = self.figures.get(unit)
            if curves is None:
                curves = self.figures[unit] = _Curves(f"ADEV [{unit or 'data unit'}]")
            for k, name, r in members:
                tau, dev, lo, hi = _dev_arrays(r)
                curves.show(name, tau, dev, _COLORS[k % len(_COLORS)], lo=lo, hi=hi)
            curves.finish(name for _, name, _ in members)
            panes.append(curves.pane)
        if list(self.plots.objects) != panes:
            self.plots[:] = panes


class _ExportView(_View):
    title = "Export"

    def __init__(self, app: ExploreApp) -> None:
        super().__init__(app)
        self.buttons = [
            pn.widgets.FileDownload(
                callback=self._exporter(fmt),
                filename=export_filename(fmt),
                label=f"{fmt} ({export_filename(fmt)})",
                color="primary",
                css_classes=[f"gb-download-{fmt}"],
            )
            for fmt in FORMATS
        ]
        self.report = pn.widgets.FileDownload(
            callback=self._report,
            filename="report.html",
            label="HTML report (report.html)",
            css_classes=["gb-download-report"],
        )
        self.code_download = pn.widgets.FileDownload(
            callback=lambda: _stdio.BytesIO(self.app.session.python_code().encode()),
            filename="reproduce.py",
            label="Python code (reproduce.py)",
            css_classes=["gb-download-code"],
        )
        self.code = pn.pane.HTML(sizing_mode="stretch_width", stylesheets=[_CSS])
        self.cli = pn.pane.HTML(sizing_mode="stretch_width", stylesheets=[_CSS])
        self.panel[:] = [
            "### Estimator files (gyrobias.exports.export of the fit on screen)",
            pn.FlexBox(*self.buttons),
            pn.Row(self.report, self.code_download),
            "### Python code that reproduces what is on screen",
            self.code,
            "### The same with the command line",
            self.cli,
        ]

    def _exporter(self, fmt: str) -> Callable[[], Any]:
        def make() -> Any:
            try:
                return _stdio.BytesIO(self.app.session.export(fmt).encode("utf-8"))
            except Exception as exc:
                self.app.show_error(exc, f"{fmt}: ")
                return None

        return make

    def _report(self) -> Any:
        try:
            return _stdio.BytesIO(self.app.session.report_html().encode("utf-8"))
        except Exception as exc:
            self.app.show_error(exc, "report: ")
            return None

    def refresh(self) -> None:
        session = self.app.session
        self.code.object = f'<pre class="gb-pre gb-code">{html.escape(session.python_code())}</pre>'
        try:
            cmd = session.cli_command()
        except ValueError as exc:
            cmd = f"# {exc}"
        self.cli.object = f'<pre class="gb-pre gb-cli">{html.escape(cmd)}</pre>'


class _LazyViews:
    """The views of the tabs, each built on first access (``views[i]``) into its tab's holder."""

    def __init__(self, app: ExploreApp, kinds: Sequence[type[_View]]) -> None:
        self.app = app
        self.kinds = tuple(kinds)
        self.holders = [pn.Column(sizing_mode="stretch_width") for _ in self.kinds]
        self._built: list[_View | None] = [None] * len(self.kinds)

    def __len__(self) -> int:
        return len(self.kinds)

    def __getitem__(self, i: int) -> _View:
        view = self._built[i]
        if view is None:
            view = self.kinds[i](self.app)
            self._built[i] = view
            self.holders[i][:] = [view.panel]
        return view


class ExploreApp:
    """The explorer: a Panel layout over one or more :class:`Session` objects.

    Parameters
    ----------
    sessions : sequence of Session
        The logs (the first one is shown first).
    errors : sequence of str
        Messages about inputs that could not be read (shown at the top).
    """

    def __init__(self, sessions: Sequence[Session], errors: Sequence[str] = ()) -> None:
        self.sessions = list(sessions)
        self.syncing = False
        self._work = threading.Lock()  # one analysis at a time per page
        self._generation = 0
        self.alerts = pn.Column(sizing_mode="stretch_width", css_classes=["gb-alerts"])
        #: Inputs that could not be read: shown for the whole visit.
        self.load_errors = pn.Column(
            *[_message(e, "danger") for e in errors],
            sizing_mode="stretch_width",
            css_classes=["gb-load-errors"],
        )
        self.busy = pn.indicators.LoadingSpinner(value=False, size=24)
        #: "ready" / "working…" in words (what tests and screenshots wait for)
        self.state = pn.pane.HTML(_READY.format(view="—"), css_classes=["gb-state"])
        if not self.sessions:
            if not errors:
                self.load_errors.append(_message("No log given.", "danger"))
            self.layout: Any = pn.Column(
                "# gyrobias explore",
                "No log could be read; run gyrobias explore again with a readable log.",
                self.load_errors,
                sizing_mode="stretch_width",
            )
            return
        self.active = 0
        self._build_controls()
        #: The tabs' views, each built when first shown (the first page builds the log view's
        #: models only)
        self.views = _LazyViews(
            self,
            (_LogView, _CleanView, _StabilityView, _FitView, _CompareView, _ExportView),
        )
        self.tabs = pn.Tabs(
            *[(kind.title, holder) for kind, holder in zip(self.views.kinds, self.views.holders)],
            dynamic=True,
            sizing_mode="stretch_width",
        )
        self.tabs.param.watch(lambda *_: self.schedule(), "active")
        self.layout = pn.Row(
            self.controls,
            pn.Column(self.load_errors, self.alerts, self.tabs, sizing_mode="stretch_width"),
            sizing_mode="stretch_width",
        )
        self.sync_widgets()
        self.refresh()

    # -- controls -----------------------------------------------------------------------------

    def _build_controls(self) -> None:
        w = pn.widgets
        self.source = w.Select(
            label="log",
            options={s.source.label or f"log {i}": i for i, s in enumerate(self.sessions)},
            css_classes=["gb-source"],
        )
        self.source.param.watch(self._on_source, "value")
        self.start = w.FloatInput(
            label="start (s)", value=None, start=0.0, width=135, css_classes=["gb-start"]
        )
        self.stop = w.FloatInput(
            label="stop (s)", value=None, start=0.0, width=135, css_classes=["gb-stop"]
        )
        self.whole = w.Button(label="whole log", css_classes=["gb-whole"])
        self.outliers_on = w.Checkbox(label="remove outliers", css_classes=["gb-outliers-on"])
        self.sigma = w.FloatInput(label="threshold (σ)", value=5.0, start=0.5, step=0.5)
        self.detrend = w.RadioButtonGroup(
            label="drift",
            options=["none", "linear", "quadratic"],
            value="none",
            css_classes=["gb-detrend"],
        )
        self.method = w.Select(label="estimator", options=list(METHODS), css_classes=["gb-method"])
        self.terms = w.CheckButtonGroup(
            label="terms", options=list(TERMS), value=[], css_classes=["gb-terms"]
        )
        self.tau_lo = w.FloatInput(
            label="τ min (s)", value=None, width=135, css_classes=["gb-tau-min"]
        )
        self.tau_hi = w.FloatInput(
            label="τ max (s)", value=None, width=135, css_classes=["gb-tau-max"]
        )
        self.tau_auto = w.Button(label="automatic τ range", css_classes=["gb-tau-auto"])
        self.lines = w.Select(label="spectral lines", options=["auto", "none"], value="auto")
        self.undo = w.Button(label="undo", color="warning", css_classes=["gb-undo"])
        self.upload = pn.widgets.FileDropper(
            max_file_size=f"{UPLOAD_LIMIT_MB}MB",
            max_total_file_size=f"{UPLOAD_LIMIT_MB}MB",
            multiple=False,
            chunk_size=4_000_000,
            layout="compact",
            css_classes=["gb-upload"],
        )
        self.upload_units = w.TextInput(
            label="units of the uploaded log", placeholder="e.g. deg/s (bags: rad/s, m/s^2)"
        )
        self.upload.param.watch(self._on_upload, "value")
        self.steps = pn.pane.HTML(stylesheets=[_CSS], css_classes=["gb-steps"])
        for widget in (self.start, self.stop):
            widget.param.watch(self._on_part, "value")
        self.whole.on_click(lambda *_: self.apply(start=None, stop=None))
        self.outliers_on.param.watch(self._on_outliers, "value")
        self.sigma.param.watch(self._on_outliers, "value")
        self.detrend.param.watch(
            lambda e: self._guarded(detrend=None if e.new == "none" else e.new), "value"
        )
        self.method.param.watch(lambda e: self._guarded(method=e.new), "value")
        self.terms.param.watch(
            lambda e: self._guarded(terms=tuple(t for t in TERMS if t in e.new)), "value"
        )
        for widget in (self.tau_lo, self.tau_hi):
            widget.param.watch(self._on_tau, "value")
        self.tau_auto.on_click(lambda *_: self.apply(tau_range=None))
        self.lines.param.watch(self._on_lines_select, "value")
        self.undo.on_click(self._on_undo)
        self.controls = pn.Column(
            pn.Row(_heading("gyrobias explore", 2), self.busy, self.state),
            self.source,
            _heading("Part"),
            pn.Row(self.start, self.stop),
            self.whole,
            _heading("Outliers"),
            self.outliers_on,
            self.sigma,
            _heading("Drift"),
            self.detrend,
            _heading("Fit"),
            self.method,
            self.terms,
            pn.Row(self.tau_lo, self.tau_hi),
            self.tau_auto,
            self.lines,
            _heading("Steps"),
            self.steps,
            self.undo,
            _heading(f"Add a log (at most {UPLOAD_LIMIT_MB} MB)"),
            self.upload_units,
            self.upload,
            width=320,
        )

    @property
    def session(self) -> Session:
        return self.sessions[self.active]

    def _guarded(self, **changes: Any) -> None:
        if not self.syncing:
            self.apply(**changes)

    def _on_source(self, event: Any) -> None:
        if self.syncing:
            return
        self.active = int(event.new)
        self.sync_widgets()
        self.schedule()

    def _on_part(self, _: Any) -> None:
        if self.syncing:
            return
        start, stop = self.start.value, self.stop.value
        self.apply(
            start=None if start is None else float(start),
            stop=None if stop is None else float(stop),
        )

    def _on_outliers(self, _: Any) -> None:
        if self.syncing:
            return
        sigma = self.sigma.value
        self.apply(outliers=float(sigma) if self.outliers_on.value and sigma is not None else None)

    def _on_tau(self, _: Any) -> None:
        if self.syncing:
            return
        lo, hi = self.tau_lo.value, self.tau_hi.value
        if lo is None or hi is None:
            return  # waiting for the other end
        self.apply(tau_range=(float(lo), float(hi)))

    def _on_lines_select(self, event: Any) -> None:
        if not self.syncing and event.new in ("auto", "none"):
            self.apply(lines=event.new)

    def _on_undo(self, _: Any) -> None:
        self.session.undo()
        self.sync_widgets()
        self.schedule()

    def _on_upload(self, event: Any) -> None:
        """A log uploaded in the browser: read from a private temporary copy, deleted at once."""
        if not event.new:
            return
        units = (self.upload_units.value or "").strip() or None
        for name, content in dict(event.new).items():
            try:
                session = load_upload(str(name), content, units=units)
            except Exception as exc:  # a message, never a dead page
                self.show_error(exc, f"{name}: ")
                continue
            self.sessions.append(session)
        self.syncing = True
        try:
            self.source.options = {
                s.source.label or f"log {i}": i for i, s in enumerate(self.sessions)
            }
        finally:
            self.syncing = False
        self.active = len(self.sessions) - 1
        self.sync_widgets()
        self.schedule()

    def sync_widgets(self) -> None:
        """Show the current settings in the controls (after undo or a drag)."""
        s = self.session.settings
        self.syncing = True
        try:
            self.source.value = self.active
            self.start.value = s.start
            self.stop.value = s.stop
            self.outliers_on.value = s.outliers is not None
            if s.outliers is not None:
                self.sigma.value = s.outliers
            self.detrend.value = s.detrend or "none"
            self.method.value = s.method
            self.terms.value = list(s.terms)
            self.tau_lo.value = None if s.tau_range is None else s.tau_range[0]
            self.tau_hi.value = None if s.tau_range is None else s.tau_range[1]
            options = ["auto", "none"]
            value = s.lines if isinstance(s.lines, str) else ",".join(f"{f:g}" for f in s.lines)
            if value not in options:
                options.append(value)
            self.lines.options = options
            self.lines.value = value
            self.undo.disabled = not self.session.can_undo
            self.steps.object = (
                "<ol class='gb-steps'>"
                + "".join(f"<li>{html.escape(t)}</li>" for t in s.steps())
                + "</ol>"
            )
        finally:
            self.syncing = False

    # -- changes -------------------------------------------------------------------------------

    def apply(self, **changes: Any) -> None:
        """Change the settings (one undoable step) and redraw; a refused change is a message."""
        try:
            self.session.update(**changes)
        except (ValueError, TypeError) as exc:
            self.show_error(exc)
            self.sync_widgets()
            return
        self.sync_widgets()
        self.schedule()

    def show_error(self, exc: BaseException, prefix: str = "") -> None:
        """A message at the top of the page (never a traceback in the browser)."""
        if not isinstance(exc, (ValueError, TypeError, OSError, ImportError, MemoryError)):
            traceback.print_exception(exc)  # on the server's terminal, for bug reports
        self.alerts[:] = [_message(f"{prefix}{exc}", "danger")]

    def schedule(self) -> None:
        """Redraw the visible tab after a change. Served, the numerics run in a worker thread
        (the core releases the GIL) while the busy indicator shows, and the drawing follows on
        the server's event loop with the document lock (``add_next_tick_callback``, Bokeh's
        thread-safe entry); otherwise (a notebook, the tests) at once."""
        import panel as pn

        doc = pn.state.curdoc
        if doc is None or doc.session_context is None:
            self.refresh()
            return
        self.busy.value = True
        self.state.object = _WORKING
        self._generation += 1
        generation = self._generation
        view = self.views[self.tabs.active]

        report = self._progress_reporter(doc, generation)

        def work() -> None:
            with self._work:
                if generation == self._generation:  # a newer change supersedes this one
                    for session in self.sessions:
                        session.progress = report
                    try:
                        view.prefetch()
                    except Exception:  # noqa: S110 - refresh() recomputes and shows the message
                        pass
                    finally:
                        for session in self.sessions:
                            session.progress = None
            doc.add_next_tick_callback(lambda: self._finish(generation))

        threading.Thread(target=work, daemon=True, name="gyrobias-explore-work").start()

    def _progress_reporter(self, doc: Any, generation: int) -> Callable[[float], None]:
        """A ``progress=`` callback for the worker thread: the fraction done of a long
        computation (Théo1 of a long log takes seconds) is shown beside the busy indicator,
        sent to the page through ``doc`` at most every ``_PROGRESS_EVERY`` seconds and only
        while the change that started it is the newest."""
        last = [time.monotonic()]

        def report(done: float) -> None:
            now = time.monotonic()
            if now - last[0] < _PROGRESS_EVERY or generation != self._generation:
                return
            last[0] = now
            text = _WORKING_DONE.format(done=min(max(float(done), 0.0), 1.0))

            def show() -> None:
                if generation == self._generation and self.busy.value:
                    self.state.object = text

            doc.add_next_tick_callback(show)

        return report

    def _finish(self, generation: int) -> None:
        if generation != self._generation:
            return
        self.refresh()

    def refresh(self) -> None:
        """Redraw the visible tab (busy indicator on meanwhile)."""
        if not self.sessions:
            return
        self.busy.value = True
        self.state.object = _WORKING
        self.alerts.clear()
        view = self.views[self.tabs.active]
        try:
            view.refresh()
        except Exception as exc:  # a message, never a dead page
            self.show_error(exc, f"{view.title}: ")
        finally:
            self.busy.value = False
            self.state.object = _READY.format(view=view.title)

    def sampling_html(self, session: Session) -> str:
        """The sampling report of the log (rate, jitter, gaps, repairs)."""
        log = session.log
        assert log is not None
        r = log.sampling
        rows = [
            ("file", f"{session.source.label} ({r.source_format or 'array'})"),
            ("samples × channels", f"{log.n_samples} × {len(log.columns)}"),
            ("sample rate", f"{session.fs:.9g} Hz ({r.fs_source or 'given'})"),
            ("duration", f"{session.duration:.6g} s"),
            ("jitter", "—" if r.jitter is None else f"{100 * r.jitter:.3g} %"),
            ("gaps", f"{r.n_gaps} ({r.missing_samples} samples missing)"),
            ("repeated stamps", str(r.n_duplicates)),
            ("repairs", "; ".join(r.repairs) or "none"),
            ("units", ", ".join(str(u) for u in log.units)),
        ]
        if log.topic:
            rows.insert(1, ("topic", log.topic))
        body = "".join(
            f"<tr><th style='text-align:left'>{html.escape(k)}</th><td>{html.escape(v)}</td></tr>"
            for k, v in rows
        )
        warn = "".join(f"<li>{html.escape(w)}</li>" for w in log.warnings)
        return f"<h4>Sampling report</h4><table class='gb-sampling'>{body}</table>" + (
            f"<ul>{warn}</ul>" if warn else ""
        )

    def servable(self) -> Any:
        """The layout, marked servable (``panel serve``)."""
        return self.layout.servable(title="gyrobias explore")

    def _repr_mimebundle_(self, include: Any = None, exclude: Any = None) -> Any:
        """Inline display in Jupyter (the layout's, resources inlined: no CDN)."""
        return self.layout._repr_mimebundle_(include, exclude)

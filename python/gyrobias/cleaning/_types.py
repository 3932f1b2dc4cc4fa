"""The cleaning steps' value types: :class:`OutlierResult`, :class:`DetrendResult` and
:class:`Envelope`.

Value types only: this module imports no algorithm module (``tests/test_imports.py``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["CleaningResult", "DetrendResult", "Envelope", "OutlierResult", "derivative_unit"]

#: ``order`` of :func:`gyrobias.cleaning.detrend` → its name (the CLI's ``--detrend``).
ORDER_NAMES: dict[int, str] = {1: "linear", 2: "quadratic"}


def derivative_unit(unit: str | None, power: int) -> str | None:
    """The unit of ``unit`` per second to the ``power`` (``"deg/s"``, 1 → ``"deg/s^2"``).

    >>> derivative_unit("deg/s", 2), derivative_unit("m/s^2", 1), derivative_unit("g", 1)
    ('deg/s^3', 'm/s^3', 'g/s')
    """
    if unit is None or power == 0:
        return unit
    base, slash, denominator = unit.rpartition("/")
    if slash and denominator == "s":
        return f"{base}/s^{1 + power}"
    if slash and denominator.startswith("s^") and denominator[2:].isdigit():
        return f"{base}/s^{int(denominator[2:]) + power}"
    return f"{unit}/s" if power == 1 else f"{unit}/s^{power}"


def _channel_list(values: NDArray[Any]) -> list[Any]:
    return [v.item() for v in values]


@dataclass(frozen=True, eq=False)
class OutlierResult:
    """The outcome of :func:`gyrobias.cleaning.remove_outliers` (Stable32's *Outliers* step).

    Attributes
    ----------
    data : ndarray, shape (n,) or (n, k)
        A copy of the input with every outlier replaced by NaN (a gap); the shape of the input.
    mask : ndarray of bool, shape of ``data``
        ``True`` where this step flagged a sample (NaN already in the input are not flagged).
    count : ndarray of int64, shape (k,)
        Flagged samples per channel.
    threshold : float
        The robust z-score above which a sample is an outlier.
    center : ndarray, shape (k,)
        Median of each channel's finite samples, in the channel's unit.
    scale : ndarray, shape (k,)
        Scale of the robust z-score per channel (``1.4826·MAD``, or ``1.2533·mean|x − m|``
        when the MAD is 0), in the channel's unit.
    units : tuple of (str or None)
        Unit of each channel (``None``: not given).
    method : str
        ``"mad"``.
    """

    data: NDArray[np.float64]
    mask: NDArray[np.bool_]
    count: NDArray[np.int64]
    threshold: float
    center: NDArray[np.float64]
    scale: NDArray[np.float64]
    units: tuple[str | None, ...]
    method: str = "mad"

    @property
    def total(self) -> int:
        """Flagged samples over all channels."""
        return int(self.count.sum())

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready summary (no sample arrays): method, threshold and, per channel, count,
        center, scale and unit."""
        return {
            "method": self.method,
            "threshold": self.threshold,
            "count": _channel_list(self.count),
            "center": _channel_list(self.center),
            "scale": _channel_list(self.scale),
            "units": list(self.units),
        }

    def __repr__(self) -> str:
        return (
            f"OutlierResult(method={self.method!r}, threshold={self.threshold:g}, "
            f"count={self.count.tolist()}, shape={self.data.shape})"
        )


@dataclass(frozen=True, eq=False)
class DetrendResult:
    """The outcome of :func:`gyrobias.cleaning.detrend` (Stable32's *Drift* step).

    Attributes
    ----------
    data : ndarray, shape (n,) or (n, k)
        The residual: the input minus each channel's fitted polynomial (NaN stay NaN).
    coefficients : ndarray, shape (k, order + 1)
        Per channel, ``c0, c1[, c2]`` of the removed polynomial ``c0 + c1·t + c2·t²``, t in
        seconds from the first sample.
    order : int
        1 (linear) or 2 (quadratic).
    fs : float
        Sample rate (Hz) the time axis was built with.
    units : tuple of (str or None)
        Unit of each channel; ``coefficient_units`` derives the coefficients' units from it.
    """

    data: NDArray[np.float64]
    coefficients: NDArray[np.float64]
    order: int
    fs: float
    units: tuple[str | None, ...]

    @property
    def kind(self) -> str:
        """``"linear"`` or ``"quadratic"`` (the CLI's ``--detrend`` value)."""
        return ORDER_NAMES[self.order]

    @property
    def coefficient_units(self) -> tuple[tuple[str | None, ...], ...]:
        """Per channel, the units of ``c0, c1[, c2]``: rate, rate/s[, rate/s²]."""
        return tuple(
            tuple(derivative_unit(u, p) for p in range(self.order + 1)) for u in self.units
        )

    def to_dict(self) -> dict[str, Any]:
        """A JSON-ready summary (no sample arrays): kind, order and, per channel, the
        coefficients with their units."""
        return {
            "kind": self.kind,
            "order": self.order,
            "coefficients": self.coefficients.tolist(),
            "coefficient_units": [list(u) for u in self.coefficient_units],
        }

    def __repr__(self) -> str:
        return (
            f"DetrendResult(kind={self.kind!r}, coefficients={self.coefficients.tolist()}, "
            f"shape={self.data.shape})"
        )


@dataclass(frozen=True, eq=False)
class Envelope:
    """The min/max envelope of :func:`gyrobias.cleaning.minmax_envelope`.

    Attributes
    ----------
    lower, upper : ndarray, shape (bins, k)
        Per bin, each channel's minimum and maximum (NaN ignored; NaN for a bin of gaps only).
    starts : ndarray of int64, shape (bins + 1,)
        First sample of each bin, then the number of samples: bin ``b`` holds samples
        ``starts[b] .. starts[b + 1] - 1``.
    """

    lower: NDArray[np.float64]
    upper: NDArray[np.float64]
    starts: NDArray[np.int64]

    @property
    def bins(self) -> int:
        """Number of bins."""
        return int(self.lower.shape[0])

    def __repr__(self) -> str:
        return f"Envelope(bins={self.bins}, channels={self.lower.shape[1]})"


@dataclass(frozen=True, eq=False)
class CleaningResult:
    """The outcome of :func:`gyrobias.cleaning.clean`: Stable32's Outliers then Drift steps.

    Attributes
    ----------
    data : ndarray, shape (n,) or (n, k)
        The cleaned samples (outliers NaN, drift removed); the input itself when no step ran.
    outliers : OutlierResult or None
        The outlier step (``None``: not asked for).
    drift : DetrendResult or None
        The drift step (``None``: not asked for).
    gaps : int or None
        NaN samples (gaps) in ``data`` as the last step left it, counted by the core in the pass
        that wrote it (``None``: not counted; :attr:`has_gaps` then looks at ``data``).
    """

    data: NDArray[np.float64]
    outliers: OutlierResult | None = None
    drift: DetrendResult | None = None
    gaps: int | None = None

    @property
    def has_gaps(self) -> bool:
        """Whether ``data`` holds NaN (then the Allan functions need ``gaps="omit"``): from
        ``gaps`` when the steps counted them (no scan of the samples), else by looking."""
        if self.gaps is not None:
            return self.gaps > 0
        return bool(np.isnan(self.data).any())

    def describe(self) -> str | None:
        """One line for outputs, e.g. ``"outliers > 5σ (MAD) removed: 3, 0, 1; linear drift
        removed"``; ``None`` when no step ran."""
        parts = []
        if self.outliers is not None:
            counts = ", ".join(str(c) for c in self.outliers.count.tolist())
            parts.append(
                f"outliers > {self.outliers.threshold:g}σ (MAD) removed per channel: {counts}"
            )
        if self.drift is not None:
            parts.append(f"{self.drift.kind} drift removed")
        return "; ".join(parts) or None

    def to_dict(self) -> dict[str, Any]:
        """``{"outliers": …, "drift": …}`` (each ``None`` or its ``to_dict()``)."""
        return {
            "outliers": None if self.outliers is None else self.outliers.to_dict(),
            "drift": None if self.drift is None else self.drift.to_dict(),
        }

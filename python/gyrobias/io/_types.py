"""The loader's value types: :class:`GyroLog` (the samples, names, units, rate and time) and
:class:`SamplingReport` (what the timestamps say about the sampling). No reading code here."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class SamplingReport:
    """What the timestamps (or their absence) say about the sampling of a log.

    Attributes
    ----------
    n_samples : int
        Number of samples (rows).
    fs : float or None
        Sample rate used for the log, Hz (user-given, else estimated; ``None`` if neither).
    fs_source : {"user", "timestamps", "file", None}
        Where ``fs`` came from (``"file"``: the ``// Sample rate: … Hz`` line of an Xsens-style
        preamble of a log without timestamps).
    fs_estimated : float or None
        Rate from the timestamps, Hz: 1 / mean of the regular intervals (those that are
        neither gaps nor zero), rounded to 9 significant digits.
    median_interval : float or None
        Median interval between timestamps, s.
    jitter : float or None
        Relative standard deviation of the intervals (excluding gaps) about the median interval.
    time_unit : str or None
        Unit the time column was read in (``"s"``, ``"ms"``, ``"us"`` or ``"ns"``).
    duration : float or None
        Last minus first timestamp, s.
    n_gaps : int
        Intervals longer than ``GAP_FACTOR`` (1.5) × the median interval.
    gap_rows : ndarray of int
        Data-row index (0-based) of the sample *after* each gap.
    gap_durations : ndarray of float
        Length of each gap interval, s.
    missing_samples : int
        Samples the gaps would hold at the median interval (Σ round(gap / median) − 1).
    n_duplicates : int
        Intervals of exactly zero (repeated timestamps).
    duplicate_rows : ndarray of int
        Data-row index of the second sample of each repeated timestamp.
    warnings : tuple of str
        Human-readable findings (irregular sampling, disagreeing ``fs``, repairs); empty if
        all is well.
    n_out_of_order : int
        Samples whose timestamp is earlier than the one before them in the file (only
        non-zero with ``repair="sort"``: otherwise they are an error).
    out_of_order_rows : ndarray of int
        File-order index (0-based) of each such sample.
    n_exact_duplicates : int
        Samples repeating the previous one exactly (same timestamp and values), after sorting.
    repairs : tuple of str
        What ``repair=`` and ``fill_gaps=`` changed, one sentence each (also in ``warnings``).
    filled_samples : int
        NaN rows inserted by ``fill_gaps=True``.
    source_format : str or None
        ``"text"``, ``"npy"``, ``"ROS1 bag"``, ``"ROS2 bag (sqlite3)"``, ``"ROS2 bag (mcap)"``,
        ``"MCAP"`` or ``"ROS2 sqlite3 (.db3)"``.

    Notes
    -----
    Row indices (``gap_rows``, ``duplicate_rows``) refer to the samples after the repairs
    and before ``fill_gaps``.
    """

    n_samples: int
    fs: float | None
    fs_source: str | None
    fs_estimated: float | None = None
    median_interval: float | None = None
    jitter: float | None = None
    time_unit: str | None = None
    duration: float | None = None
    n_gaps: int = 0
    gap_rows: NDArray[np.int64] = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    gap_durations: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    missing_samples: int = 0
    n_duplicates: int = 0
    duplicate_rows: NDArray[np.int64] = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    warnings: tuple[str, ...] = ()
    n_out_of_order: int = 0
    out_of_order_rows: NDArray[np.int64] = field(
        default_factory=lambda: np.zeros(0, dtype=np.int64)
    )
    n_exact_duplicates: int = 0
    repairs: tuple[str, ...] = ()
    filled_samples: int = 0
    source_format: str | None = None

    @property
    def longest_gap(self) -> float | None:
        """Longest gap interval in seconds (``None`` without gaps)."""
        return float(self.gap_durations.max()) if self.n_gaps else None

    @property
    def regular(self) -> bool:
        """``True`` when nothing was found to warn about."""
        return not self.warnings

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (rows 0-based data rows, times in seconds)."""
        return {
            "n_samples": self.n_samples,
            "fs_hz": self.fs,
            "fs_source": self.fs_source,
            "fs_estimated_hz": self.fs_estimated,
            "median_interval_s": self.median_interval,
            "jitter": self.jitter,
            "time_unit": self.time_unit,
            "duration_s": self.duration,
            "n_gaps": self.n_gaps,
            "gap_rows": self.gap_rows.tolist(),
            "gap_durations_s": self.gap_durations.tolist(),
            "longest_gap_s": self.longest_gap,
            "missing_samples": self.missing_samples,
            "n_duplicates": self.n_duplicates,
            "duplicate_rows": self.duplicate_rows.tolist(),
            "n_out_of_order": self.n_out_of_order,
            "out_of_order_rows": self.out_of_order_rows.tolist(),
            "n_exact_duplicates": self.n_exact_duplicates,
            "repairs": list(self.repairs),
            "filled_samples": self.filled_samples,
            "source_format": self.source_format,
            "warnings": list(self.warnings),
        }

    def __str__(self) -> str:
        parts = [f"{self.n_samples} samples"]
        if self.fs is not None:
            parts.append(f"fs = {self.fs:g} Hz ({self.fs_source})")
        if self.jitter is not None:
            parts.append(f"jitter {100 * self.jitter:.3g} %")
        if self.time_unit is not None:
            parts.append(f"{self.n_gaps} gaps, {self.n_duplicates} repeated timestamps")
            if self.n_out_of_order:
                parts.append(f"{self.n_out_of_order} out of order")
        text = ", ".join(parts)
        return "\n".join([text, *("warning: " + w for w in self.warnings)])


@dataclass(frozen=True)
class GyroLog:
    """A loaded gyro log.

    Attributes
    ----------
    data : ndarray or numpy.memmap, shape (n, k)
        The selected channels as float64, one column per channel, in file units. A log
        loaded with ``spill`` is a :class:`numpy.memmap` of a temporary file (read it block
        by block to keep the memory bounded). With ``fill_gaps=True``, missing samples are
        NaN rows.
    columns : tuple of str
        Channel names (header names, ``"col<i>"`` for files without a header / ``.npy``,
        ``gyro_x`` … ``accel_z`` for bags).
    fs : float or None
        Sample rate in Hz: the user's ``fs`` if given, else estimated from the timestamps,
        else ``None``.
    time : ndarray, shape (n,), or None
        Timestamps in seconds relative to the first sample (exact for integer nanosecond stamps).
    time_start : float or None
        First timestamp as given in the file, converted to seconds.
    time_column : str or None
        Name of the time column used.
    path : pathlib.Path
        The source file.
    sampling : SamplingReport
        Findings about the sampling (rate, jitter, gaps, repeated timestamps).
    units : tuple of str or None
        Unit of each channel (``"rad/s"``, ``"m/s^2"`` for bags; from ``units=`` for other
        formats; ``None`` where unknown).
    topic : str or None
        The bag topic read.
    """

    data: NDArray[np.float64]
    columns: tuple[str, ...]
    fs: float | None
    time: NDArray[np.float64] | None
    time_start: float | None
    time_column: str | None
    path: Path
    sampling: SamplingReport
    units: tuple[str | None, ...] = ()
    topic: str | None = None

    def __post_init__(self) -> None:
        if not self.units:
            object.__setattr__(self, "units", (None,) * len(self.columns))

    @property
    def warnings(self) -> tuple[str, ...]:
        """The sampling report's warnings (irregular sampling, disagreeing ``fs``)."""
        return self.sampling.warnings

    @property
    def n_samples(self) -> int:
        """Number of samples (rows)."""
        return int(self.data.shape[0])

    def unit_groups(self) -> list[tuple[str | None, list[int]]]:
        """Channels grouped by unit, in order of first appearance: ``[(unit, [column indices])]``.

        A 6-axis IMU log gives ``[("rad/s", [0, 1, 2]), ("m/s^2", [3, 4, 5])]``, so that each
        sensor can be analysed with its own unit.
        """
        groups: dict[str | None, list[int]] = {}
        for i, u in enumerate(self.units):
            groups.setdefault(u, []).append(i)
        return list(groups.items())

    def __getitem__(self, name: str) -> NDArray[np.float64]:
        """One channel by name, as a 1-D view."""
        try:
            return self.data[:, self.columns.index(name)]
        except ValueError:
            raise KeyError(f"no channel {name!r}; channels are {', '.join(self.columns)}") from None

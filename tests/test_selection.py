"""Time selection: :func:`gyrobias.io.parse_time_bound` and :meth:`GyroLog.select`, against
slicing by hand (the expected rows are computed here from the definition — a sample at time
``t`` is selected when ``start <= t < stop`` — not with the selection code)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gyrobias import allan
from gyrobias.io import GyroLog, SamplingReport, Selection, TimeBound, load, parse_time_bound


def _log(n: int, fs: float | None, time: np.ndarray | None = None, k: int = 2) -> GyroLog:
    data = np.random.default_rng(n).normal(size=(n, k))
    return GyroLog(
        data=data,
        columns=tuple(f"c{i}" for i in range(k)),
        fs=fs,
        time=time,
        time_start=None if time is None else 1.7e9,
        time_column=None if time is None else "t",
        path=Path("x.csv"),
        sampling=SamplingReport(n, fs, "user" if time is None else "timestamps"),
    )


# --------------------------------------------------------------------------- the grammar


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("1200", TimeBound(seconds=1200.0)),
        ("1200s", TimeBound(seconds=1200.0)),
        (" 90min ", TimeBound(seconds=5400.0)),
        ("0.5h", TimeBound(seconds=1800.0)),
        (".25h", TimeBound(seconds=900.0)),
        ("1e3", TimeBound(seconds=1000.0)),
        ("250000n", TimeBound(index=250000)),
        ("0n", TimeBound(index=0)),
        (12, TimeBound(seconds=12.0)),
        (np.int64(3), TimeBound(seconds=3.0)),
        (2.5, TimeBound(seconds=2.5)),
        (np.float32(0.5), TimeBound(seconds=0.5)),
        (0, TimeBound(seconds=0.0)),
    ],
)
def test_parse_time_bound(text: str | float, expected: TimeBound) -> None:
    assert parse_time_bound(text) == expected


def test_parse_time_bound_none_and_str() -> None:
    assert parse_time_bound(None) is None
    assert str(parse_time_bound("250000n")) == "250000n"
    assert str(parse_time_bound(" 0.5h")) == "0.5h"
    assert str(parse_time_bound(1800)) == "1800s"


@pytest.mark.parametrize(
    ("value", "error", "match"),
    [
        (-1.0, ValueError, "stop=-1.0 must be >= 0"),
        ("-2min", ValueError, "must be >= 0"),
        ("-3n", ValueError, "sample index is a non-negative integer"),
        ("1.5n", ValueError, "sample index is a non-negative integer"),
        ("1e3n", ValueError, "sample index is a non-negative integer"),
        ("10 days", ValueError, "stop='10 days' is not a time"),
        ("", ValueError, "not a time"),
        ("nan", ValueError, "not a time"),
        (float("nan"), ValueError, "stop=nan must be finite"),
        (float("inf"), ValueError, "must be finite"),
        ("1e400", ValueError, "must be finite"),
        (True, TypeError, "stop must be seconds"),
        ([1.0], TypeError, "stop must be seconds"),
    ],
)
def test_parse_time_bound_refuses(value: object, error: type[Exception], match: str) -> None:
    with pytest.raises(error, match=match):
        parse_time_bound(value, name="stop")  # type: ignore[arg-type]


# --------------------------------------------------------------------------- select


def _by_hand(t: np.ndarray, start: float | None, stop: float | None) -> tuple[int, int]:
    """Rows with start <= t - t[0] < stop, by a boolean mask (contiguous for sorted t)."""
    rel = t - t[0]
    mask = np.ones(len(t), dtype=bool)
    if start is not None:
        mask &= rel >= start
    if stop is not None:
        mask &= rel < stop
    rows = np.flatnonzero(mask)
    return int(rows[0]), int(rows[-1]) + 1


def test_select_by_seconds_without_timestamps_is_a_view() -> None:
    log = _log(10_000, 100.0)
    part = log.select(start=12.345, stop="1min")
    i0, i1 = _by_hand(np.arange(10_000) / 100.0, 12.345, 60.0)
    assert (i0, i1) == (1235, 6000)
    np.testing.assert_array_equal(part.data, log.data[i0:i1])
    assert np.shares_memory(part.data, log.data)
    assert part.time is None and part.fs == 100.0 and part.columns == log.columns
    assert part.selection == Selection(12.35, 60.0, 1235, 6000, 100.0, 10_000)
    assert part.selection.n_samples == part.n_samples == 4765
    assert part.selection.describe() == "12.35–60 s of 100 s"
    assert log.selection is None  # nothing passed in is modified
    assert log.data.shape == (10_000, 2)


def test_select_bounds_on_sample_times_are_inclusive_exclusive() -> None:
    # 0.3 s at 100 Hz is 30.000000000000004 samples in floating point: still sample 30.
    log = _log(1000, 100.0)
    part = log.select(0.3, 0.7)
    assert (part.selection.start_index, part.selection.stop_index) == (30, 70)
    assert log.select("30n", "70n").selection == part.selection


def test_select_with_jittered_timestamps() -> None:
    rng = np.random.default_rng(4)
    n = 20_000
    t = np.cumsum(rng.uniform(0.009, 0.011, size=n))
    t -= t[0]
    log = _log(n, 100.0, time=t)
    for start, stop in [(10.0, 150.0), (None, 33.3), (0.0, None), (57.123, 57.2)]:
        part = log.select(start, stop)
        i0, i1 = _by_hand(t, start, stop)
        np.testing.assert_array_equal(part.data, log.data[i0:i1])
        np.testing.assert_array_equal(part.time, t[i0:i1])  # not re-based
        assert part.selection.start_s == t[i0]
        assert part.selection.stop_s == (t[i1] if i1 < n else t[-1] + 0.01)
        assert part.time_start == log.time_start
        assert np.shares_memory(part.time, t)


def test_select_of_a_selection_counts_from_its_first_sample() -> None:
    log = _log(36_000, 10.0)
    a = log.select("0.25h", "0.75h")
    with pytest.raises(ValueError, match="select no sample"):
        a.select(60.0, "600n")  # 60 s after a's start is a's sample 600: an empty span
    c = a.select(60.0, "1200n")
    np.testing.assert_array_equal(c.data, log.data[9600:10200])
    assert c.selection == Selection(960.0, 1020.0, 9600, 10200, 3600.0, 36_000)
    assert c.selection.describe() == "16–17 min of 60 min"


def test_select_refuses() -> None:
    log = _log(1000, 100.0)  # 10 s
    with pytest.raises(ValueError, match="start=-1"):
        log.select(start=-1)
    with pytest.raises(
        ValueError, match=r"start=10s is at or beyond the end of the log \(1000 samples, 10 s\)"
    ):
        log.select(start=10)
    with pytest.raises(ValueError, match="start=1000n is at or beyond the end"):
        log.select(start="1000n")
    with pytest.raises(ValueError, match="stop=10.5s is beyond the end"):
        log.select(stop=10.5)
    with pytest.raises(ValueError, match="stop=1001n is beyond the end"):
        log.select(stop="1001n")
    with pytest.raises(ValueError, match="start=5s must be before stop=5s"):
        log.select(5, 5)
    with pytest.raises(ValueError, match="start=6s must be before stop=2s"):
        log.select(6, "2s")
    with pytest.raises(ValueError, match="select no sample"):
        log.select(1.001, 1.005)  # between samples 100 and 101
    with pytest.raises(ValueError, match="select no sample"):
        log.select("500n", 2.0)  # index after the time
    with pytest.raises(TypeError, match="start must be seconds"):
        log.select(start=b"1")  # type: ignore[arg-type]
    assert log.select(stop=10).n_samples == 1000  # the end of the log itself is allowed
    nofs = _log(100, None)
    with pytest.raises(ValueError, match="neither timestamps nor a sample rate"):
        nofs.select(start=1.0)
    part = nofs.select("10n", "20n")
    assert part.selection == Selection(None, None, 10, 20, None, 100)
    assert str(part.selection) == "samples 10–20 of 100"


def test_select_keeps_a_memory_mapped_log_mapped(tmp_path: Path) -> None:
    x = np.random.default_rng(2).normal(size=(50_000, 3))
    np.save(tmp_path / "x.npy", x)
    log = load(tmp_path / "x.npy", fs=200.0, spill=True)
    assert isinstance(log.data, np.memmap)
    part = log.select("10s", "200s")
    assert isinstance(part.data, np.memmap)
    assert np.shares_memory(part.data, log.data)
    np.testing.assert_array_equal(part.data, x[2000:40000])


def test_adev_of_a_selection_equals_adev_of_the_slice() -> None:
    log = _log(200_000, 100.0, k=1)
    part = log.select("5min", "30min")
    by_hand = allan.adev(log.data[30_000:180_000, 0], 100.0)
    got = allan.adev(part.data[:, 0], 100.0)
    np.testing.assert_array_equal(got.taus, by_hand.taus)
    np.testing.assert_array_equal(got.adev, by_hand.adev)


@settings(max_examples=60, deadline=None)
@given(
    n=st.integers(1, 3000),
    fs=st.sampled_from([1.0, 7.0, 100.0, 400.0, 1000.0 / 3]),
    a=st.floats(0, 1),
    b=st.floats(0, 1),
    by_index=st.booleans(),
)
def test_select_property_matches_mask(
    n: int, fs: float, a: float, b: float, by_index: bool
) -> None:
    log = _log(n, fs, k=1)
    lo, hi = sorted((a, b))
    if by_index:
        i0, i1 = int(lo * n), int(hi * n)
        if i0 >= i1 or i0 >= n:
            with pytest.raises(ValueError):
                log.select(f"{i0}n", f"{i1}n")
            return
        part = log.select(f"{i0}n", f"{i1}n")
    else:
        start, stop = lo * n / fs, hi * n / fs
        t = np.arange(n) / fs
        rel = np.round((t - start) * fs, 6)  # a sample within 1e-6 interval of a bound is on it
        rows = np.flatnonzero((rel >= 0) & (np.round((t - stop) * fs, 6) < 0))
        if start >= stop or len(rows) == 0:
            with pytest.raises(ValueError):
                log.select(start, stop)
            return
        part = log.select(start, stop)
        i0, i1 = int(rows[0]), int(rows[-1]) + 1
    np.testing.assert_array_equal(part.data, log.data[i0:i1])
    assert (part.selection.start_index, part.selection.stop_index) == (i0, i1)
    assert np.shares_memory(part.data, log.data)

"""gyrobias.io.load: units, repairs, fill_gaps, spilling to disk, and the pyarrow CSV path."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import gyrobias
from gyrobias import _core
from gyrobias.io import _store, load, text

RNG = np.random.default_rng(77)
#: The block iterator of the spill store, before a test patches it (to force small blocks).
_BLOCKS = _store.blocks


def _csv(path: Path, t: np.ndarray, x: np.ndarray, header: str = "t,gx,gy,gz,ax,ay,az") -> Path:
    rows = np.column_stack([t, x])
    path.write_text(
        header + "\n" + "".join(",".join(repr(float(v)) for v in r) + "\n" for r in rows)
    )
    return path


# --------------------------------------------------------------------------- units


def test_units_one_per_channel_and_by_name(tmp_path: Path) -> None:
    t = np.arange(100) / 100.0
    path = _csv(tmp_path / "imu.csv", t, RNG.normal(size=(100, 6)))
    assert load(path).units == (None,) * 6
    assert load(path, units="deg/s").units == ("deg/s",) * 6
    six = load(path, units="deg/s,deg/s,deg/s,g,g,g")
    assert six.units == ("deg/s",) * 3 + ("g",) * 3
    assert six.unit_groups() == [("deg/s", [0, 1, 2]), ("g", [3, 4, 5])]
    named = load(path, columns="gx,az", units={"gx": "rad/s", "az": "m/s^2"})
    assert named.units == ("rad/s", "m/s^2")
    assert load(path, columns="gx,az", units="az=mg").units == (None, "mg")
    assert load(path, columns=["gx", "ax"], units=["deg/s", None]).units == ("deg/s", None)
    with pytest.raises(ValueError, match=r"units has 2 entries for 6 channels"):
        load(path, units="deg/s,g")
    with pytest.raises(ValueError, match="units names channel"):
        load(path, columns="gx", units="ax=g")
    with pytest.raises(ValueError, match="units: "):
        load(path, units="furlong/fortnight")


def test_units_from_the_column_headers(tmp_path: Path) -> None:
    # x-io logs state each channel's unit in its header ("Gyroscope X (deg/s)", "... (g)",
    # "... (uT)"); without units= they were loaded unitless, so the fit had no unit at all.
    names = ["Gyroscope X (deg/s)", "gy [rad/s]", "Accelerometer X (g)", "Magnetometer X (uT)"]
    path = tmp_path / "xio.csv"
    path.write_text(
        "Timestamp (us),"
        + ",".join(names)
        + "\n"
        + "".join(f"{20000 * i},0.1,0.2,1.0,20.5\n" for i in range(50))
    )
    log = load(path)
    assert log.units == ("deg/s", "rad/s", "g", None)  # uT is not a unit gyrobias knows
    given = load(path, units=[None, "deg/s", None, "g"]).units  # a given unit wins
    assert given == ("deg/s", "deg/s", "g", "g")
    assert load(path, units="rad/s").units == ("rad/s",) * 4
    assert load(path, columns="1").units == ("deg/s",)


# --------------------------------------------------------------------------- repairs and gaps


def test_csv_repair_sort_and_dedup(tmp_path: Path) -> None:
    n = 200
    t = np.arange(n) / 100.0
    x = RNG.normal(size=(n, 1))
    perm = np.arange(n)
    perm[[50, 51, 52]] = [52, 50, 51]
    t_w, x_w = t[perm], x[perm]
    t_w = np.insert(t_w, 120, t_w[119])
    x_w = np.insert(x_w, 120, x_w[119], axis=0)
    path = _csv(tmp_path / "r.csv", t_w, x_w, header="t,g")
    with pytest.raises(ValueError, match=r"out of order in 't' at line 53 .*--repair sort"):
        load(path)
    fixed = load(path, repair=("sort", "dedup"))
    np.testing.assert_array_equal(fixed.data, x)
    rep = fixed.sampling
    assert rep.n_out_of_order == 1 and rep.out_of_order_rows.tolist() == [51]
    assert rep.repairs[0].startswith("sorted by timestamp") and rep.repairs[0] in rep.warnings
    assert "dropped 1 sample" in rep.repairs[1] and not rep.regular
    with pytest.raises(ValueError, match="repair must be one of"):
        load(path, repair="shuffle")
    np.save(tmp_path / "n.npy", x)
    with pytest.raises(ValueError, match="repair needs timestamps"):
        load(tmp_path / "n.npy", fs=1.0, repair="sort")


def test_same_stamp_different_values_is_kept(tmp_path: Path) -> None:
    t = np.arange(10) / 10.0
    t[5] = t[4]
    x = np.arange(10.0).reshape(-1, 1)
    rep = load(_csv(tmp_path / "d.csv", t, x, header="t,g"), repair="dedup")
    assert (
        rep.n_samples == 10
        and rep.sampling.n_duplicates == 1
        and rep.sampling.n_exact_duplicates == 0
    )


def test_fill_gaps_inserts_nan_rows_at_the_right_places(tmp_path: Path) -> None:
    fs = 50.0
    keep = np.ones(1000, dtype=bool)
    keep[300:340] = False  # 40 missing
    keep[700:701] = False  # 1 missing: an interval of 2 samples is a gap (> 1.5×)
    t_full = np.arange(1000) / fs
    x_full = RNG.normal(size=(1000, 2))
    path = _csv(tmp_path / "g.csv", t_full[keep], x_full[keep], header="t,a,b")
    log = load(path, fill_gaps=True)
    assert log.n_samples == 1000 and log.sampling.filled_samples == 41
    nan_rows = np.isnan(log.data).all(axis=1)
    np.testing.assert_array_equal(nan_rows, ~keep)
    np.testing.assert_array_equal(log.data[keep], x_full[keep])
    assert log.time is not None
    np.testing.assert_allclose(log.time, t_full, rtol=0, atol=1e-12)
    assert "filled with NaN rows" in log.sampling.warnings[0]
    assert any("inserted 41 NaN row(s)" in r for r in log.sampling.repairs)
    plain = load(path)
    assert plain.n_samples == 959 and plain.sampling.missing_samples == 41
    assert "--fill-gaps" in plain.sampling.warnings[0]
    no_gaps = _csv(tmp_path / "ok.csv", t_full, x_full, header="t,a,b")
    assert load(no_gaps, fill_gaps=True).n_samples == 1000


@settings(max_examples=25, deadline=None)
@given(st.lists(st.integers(1, 6), min_size=1, max_size=5), st.integers(0, 2**31))
def test_fill_gaps_property(
    tmp_path_factory: pytest.TempPathFactory, holes: list[int], seed: int
) -> None:
    # any set of holes: filling restores the full length, NaN exactly at the holes
    rng = np.random.default_rng(seed)
    n = 200
    keep = np.ones(n, dtype=bool)
    starts = rng.choice(np.arange(5, n - 10), size=len(holes), replace=False)
    for s, h in zip(starts, holes):
        keep[s : s + h] = False
    keep[0] = keep[-1] = True
    t = np.arange(n) * 0.01
    x = rng.normal(size=(n, 1))
    path = tmp_path_factory.mktemp("fill") / "f.csv"
    _csv(path, t[keep], x[keep], header="t,g")
    log = load(path, fill_gaps=True)
    assert log.n_samples == n
    np.testing.assert_array_equal(np.isnan(log.data[:, 0]), ~keep)


def test_fill_gaps_needs_time(tmp_path: Path) -> None:
    np.save(tmp_path / "a.npy", np.ones((10, 1)))
    with pytest.raises(ValueError, match="fill_gaps needs timestamps"):
        load(tmp_path / "a.npy", fs=1.0, fill_gaps=True)


# --------------------------------------------------------------------------- spill


def test_spill_npy_maps_the_file_and_copies_selections(tmp_path: Path) -> None:
    x = RNG.normal(size=(5000, 3))
    np.save(tmp_path / "x.npy", x)
    whole = load(tmp_path / "x.npy", fs=100.0, spill=True)
    assert (
        isinstance(whole.data, np.memmap) and not whole.data.flags.writeable
    )  # the file, read-only
    np.testing.assert_array_equal(whole.data, x)
    part = load(tmp_path / "x.npy", fs=100.0, spill=True, columns=[2, 0])
    assert isinstance(part.data, np.memmap)
    np.testing.assert_array_equal(part.data, x[:, [2, 0]])
    ref = gyrobias.allan.adev(x, 100.0, confidence=None)
    got = gyrobias.allan.adev(whole.data, 100.0, confidence=None)
    for a, b in zip(ref, got):  # type: ignore[arg-type]
        np.testing.assert_array_equal(a.avar, b.avar)
    assert not isinstance(load(tmp_path / "x.npy", fs=100.0).data, np.memmap)  # default: in memory
    with pytest.raises(TypeError, match="spill must be"):
        load(tmp_path / "x.npy", fs=100.0, spill="yes")  # type: ignore[arg-type]


def test_spill_csv_and_fill_keep_values(tmp_path: Path) -> None:
    t = np.arange(3000) / 100.0
    t[2000:] += 1.0
    x = RNG.normal(size=(3000, 2))
    path = _csv(tmp_path / "s.csv", t, x, header="t,a,b")
    log = load(path, spill=True, spill_dir=tmp_path, fill_gaps=True)
    assert isinstance(log.data, np.memmap)
    np.testing.assert_array_equal(log.data[:2000], x[:2000])
    np.testing.assert_array_equal(log.data[-1000:], x[2000:])
    assert np.isnan(log.data[2000:2100]).all()
    assert [p.name for p in tmp_path.iterdir()] == ["s.csv"]  # no temporary file left behind


@pytest.mark.parametrize("kind", ["csv_int_ns", "csv_float_s", "npy", "fill_gaps", "sort"])
def test_spilled_time_vector_is_a_memmap_equal_to_the_in_memory_one(
    tmp_path: Path, kind: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Issue 12: with spill the time vector goes to disk too, computed block by block."""
    n = 5000
    t = np.arange(n) * 0.01 + 3.0
    t[1500:] += 0.5  # a gap: 50 samples missing
    x = RNG.normal(size=(n, 2))
    kw: dict[str, object] = {}
    if kind == "csv_int_ns":
        stamps = (np.arange(n, dtype=np.int64) * 10_000_000) + 1_700_000_000_000_000_000
        stamps[1500:] += 500_000_000
        path = tmp_path / "s.csv"
        with path.open("w") as fh:
            fh.write("time_ns,a,b\n")
            for s_, row in zip(stamps, x):
                fh.write(f"{s_},{float(row[0])!r},{float(row[1])!r}\n")
    elif kind == "npy":
        path = tmp_path / "s.npy"
        np.save(path, np.column_stack([t, x]))
        kw = {"time_column": 0}
    else:
        path = _csv(tmp_path / "s.csv", t, x, header="t,a,b")
        if kind == "fill_gaps":
            kw = {"fill_gaps": True}
        elif kind == "sort":
            lines = path.read_text().splitlines()
            lines[100], lines[101] = lines[101], lines[100]
            path.write_text("\n".join(lines) + "\n")
            kw = {"repair": "sort"}
    ref = load(path, **kw)  # type: ignore[arg-type]
    # Small blocks: the block boundaries fall inside the gap, the swapped rows and everywhere.
    monkeypatch.setattr(_store, "blocks", lambda m, rows=777: _BLOCKS(m, rows))
    spilled = load(path, spill=True, spill_dir=tmp_path, **kw)  # type: ignore[arg-type]
    assert isinstance(spilled.data, np.memmap) and isinstance(spilled.time, np.memmap)
    assert ref.time is not None and not isinstance(ref.time, np.memmap)
    np.testing.assert_array_equal(spilled.time, ref.time)
    np.testing.assert_array_equal(spilled.data, ref.data)
    assert repr(spilled.sampling) == repr(ref.sampling)  # every field (arrays by value)
    assert spilled.time_start == ref.time_start
    assert not [p for p in tmp_path.iterdir() if p.name.startswith("gyrobias-")]  # unlinked


@given(
    st.lists(st.integers(-3, 4), min_size=0, max_size=400),
    st.booleans(),
)
def test_step_rows_equal_numpy_diff(steps: list[int], as_float: bool) -> None:
    """The core's backward / repeated stamp rows equal ``flatnonzero(op(diff(t), 0)) + 1``."""
    t = np.cumsum(np.asarray([0, *steps], dtype=np.int64)) * 1_000_000_007
    if as_float:
        t = t.astype(np.float64) * 1e-9
    for op, core in (
        (np.less, _core.timestamps.backward_rows),
        (np.equal, _core.timestamps.repeated_rows),
    ):
        np.testing.assert_array_equal(core(t), np.flatnonzero(op(np.diff(t), 0)) + 1)


def _numpy_sampling(steps: np.ndarray) -> dict[str, object]:
    """NumPy reference of the sampling statistics (the loader's former Python implementation)."""
    positive = steps[steps > 0]
    median = float(np.median(positive))
    gap = steps > 1.5 * median
    regular = steps[(steps > 0) & ~gap]
    mean = float(np.mean(regular)) if regular.size else float(np.mean(positive))
    return {
        "median": median,
        "gap_rows": np.flatnonzero(gap) + 1,
        "duplicate_rows": np.flatnonzero(steps == 0) + 1,
        "fs": float(f"{1.0 / mean:.9g}"),
        "jitter": float(np.std(regular)) / median if regular.size > 1 else 0.0,
        "missing": int(np.sum(np.rint(steps[gap] / median) - 1)),
    }


@given(
    st.lists(
        st.one_of(
            st.floats(0.009, 0.011),
            st.just(0.0),
            st.floats(0.02, 1.0),
        ),
        min_size=3,
        max_size=300,
    ).filter(lambda v: any(x > 0 for x in v))
)
def test_sampling_statistics_match_numpy(steps: list[float]) -> None:
    """The core's sampling statistics against NumPy: rows, counts and the median exactly; the
    rate and jitter to 1e-12 relative (compensated vs pairwise sums: a few ulps)."""
    iv = np.asarray(steps)
    got = _core.timestamps.analyse(iv)
    ref = _numpy_sampling(iv)
    assert got.median_interval == ref["median"]
    np.testing.assert_array_equal(got.gap_rows, ref["gap_rows"])
    np.testing.assert_array_equal(got.duplicate_rows, ref["duplicate_rows"])
    assert got.missing_samples == ref["missing"]
    assert got.fs_estimated == pytest.approx(ref["fs"], rel=1e-8)  # 9 digits: 1 unit in the last
    assert got.jitter == pytest.approx(ref["jitter"], rel=1e-12, abs=1e-15)


@given(
    st.lists(st.integers(0, 3_000_000_000), min_size=2, max_size=300),
    st.sampled_from([1.0, 1e3, 1e6, 1e9]),
    st.booleans(),
)
def test_stamps_analysed_like_their_differences(
    steps: list[int], per_second: float, as_float: bool
) -> None:
    """``analyse_stamps`` (intervals formed on the fly, median by radix selection) gives what
    ``analyse`` gives on NumPy's ``diff(t) / per_second``, field for field; the median positive
    step is NumPy's median; the seconds written in place are NumPy's ``(t - t0) / per_second``."""
    t = np.cumsum(np.asarray(steps, dtype=np.int64)) + 1_600_000_000_000_000_000
    if as_float:
        t = t.astype(np.float64) * 1e-6
    if not np.any(np.diff(t) > 0):
        with pytest.raises(ValueError, match="does not advance"):
            _core.timestamps.analyse_stamps(t, per_second)
        return
    got = _core.timestamps.analyse_stamps(t, per_second)
    want = _core.timestamps.analyse(np.diff(t).astype(np.float64) / per_second)
    for name in ("median_interval", "fs_estimated", "jitter", "missing_samples"):
        assert getattr(got, name) == getattr(want, name), name
    for name in ("gap_rows", "gap_durations", "duplicate_rows"):
        np.testing.assert_array_equal(getattr(got, name), getattr(want, name))
    d = np.diff(t).astype(np.float64)
    assert _core.timestamps.median_positive_step(t) == float(np.median(d[d > 0]))
    seconds = t.copy()
    _core.timestamps.seconds_in_place(seconds, t[0].item(), per_second)
    ref = (t - t[0]).astype(np.float64) / per_second
    np.testing.assert_array_equal(seconds.view(np.float64), ref)


def test_auto_spill_threshold() -> None:
    from gyrobias.io._store import Store, physical_memory

    store = Store(None)
    assert not store.wants_spill(1 << 20)
    assert store.wants_spill(physical_memory())


# --------------------------------------------------------------------------- pyarrow CSV


def _arrow_used(monkeypatch: pytest.MonkeyPatch) -> list[bool]:
    calls: list[bool] = []
    real = text._read_arrow

    def spy(*args: object, **kwargs: object) -> object:
        out = real(*args, **kwargs)  # type: ignore[arg-type]
        calls.append(out is not None)
        return out

    monkeypatch.setattr(text, "_read_arrow", spy)
    # the core's parser reads these files first; these tests are about the pyarrow fallback
    # (quoted cells, non-ASCII text) behind it (tests/test_io_text_fast.py covers the core)
    monkeypatch.setattr(text, "_core_reads", lambda *a: False)
    return calls


def test_arrow_reads_plain_csv_and_falls_back_on_comments(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pytest.importorskip("pyarrow")
    calls = _arrow_used(monkeypatch)
    t = np.arange(500) / 100.0
    x = RNG.normal(size=(500, 6))
    path = _csv(tmp_path / "a.csv", t, x)
    log = load(path)
    assert calls == [True]
    np.testing.assert_array_equal(log.data, x)
    # a comment between the rows: pyarrow refuses, numpy.loadtxt reads it
    lines = path.read_text().splitlines()
    lines.insert(100, "# operator note")
    path.write_text("\n".join(lines) + "\n")
    calls.clear()
    again = load(path)
    assert calls == [False]
    np.testing.assert_array_equal(again.data, x)


def test_arrow_integer_nanosecond_stamps_are_exact(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pytest.importorskip("pyarrow")
    calls = _arrow_used(monkeypatch)
    stamps = 1_700_000_000_123_456_789 + np.arange(300, dtype=np.int64) * 2_500_000
    path = tmp_path / "ns.csv"
    path.write_text("stamp,a\n" + "".join(f"{s},{i}\n" for i, s in enumerate(stamps)))
    log = load(path, time_column="stamp")
    assert calls == [True]
    assert (
        log.fs == 400.0 and log.sampling.jitter is not None and log.sampling.jitter < 1e-12
    )  # np.std rounding
    assert log.time is not None
    np.testing.assert_array_equal(
        log.time, (np.arange(300, dtype=np.int64) * 2_500_000) / 1e9
    )  # exact


@settings(max_examples=30, deadline=None)
@given(
    st.lists(st.floats(allow_nan=False, allow_infinity=False, width=64), min_size=3, max_size=40),
    st.sampled_from([",", ";", "\t"]),
    st.booleans(),
)
def test_arrow_equals_loadtxt_property(
    tmp_path_factory: pytest.TempPathFactory, values: list[float], delimiter: str, header: bool
) -> None:
    pytest.importorskip("pyarrow")
    rows = np.array(values[: len(values) // 3 * 3]).reshape(-1, 3)
    path = tmp_path_factory.mktemp("arrow") / "p.csv"
    text = (delimiter.join("abc") + "\n" if header else "") + "".join(
        delimiter.join(repr(float(v)) for v in r) + "\n" for r in rows
    )
    path.write_text(text)
    log = load(path, fs=1.0)
    np.testing.assert_array_equal(log.data, rows)  # correctly rounded parsing, like numpy
    ref = np.loadtxt(path, delimiter=delimiter, skiprows=int(header), ndmin=2)
    np.testing.assert_array_equal(log.data, ref)


def test_bad_cells_still_name_line_and_column_with_arrow(tmp_path: Path) -> None:
    pytest.importorskip("pyarrow")
    big = tmp_path / "big.csv"
    t = np.arange(50_000) / 100.0
    rows = "".join(f"{v!r},{i}\n" for i, v in enumerate(t.tolist()))
    big.write_text("t,g\n" + rows + "500.0,x\n")
    with pytest.raises(
        ValueError, match=r"big.csv: 'x' \(not a number\) in column 'g' at line 50002"
    ):
        load(big)


# --------------------------------------------------------------------------- corrupt files


@pytest.mark.parametrize(
    ("name", "make"),
    [
        ("cut.csv.gz", lambda good: good[: len(good) // 2]),
        ("junk.csv.gz", lambda good: b"hello, not gzip at all"),
        ("junk.csv.xz", lambda good: b"\xfd7zXZ\x00garbage"),
        ("junk.csv.bz2", lambda good: b"BZh91AY&SYgarbage"),
    ],
)
def test_corrupt_compressed_files_name_the_file(tmp_path: Path, name: str, make: object) -> None:
    import gzip

    text = "t,g\n" + "".join(f"{i / 100},{i}\n" for i in range(2000))
    path = tmp_path / name
    path.write_bytes(make(gzip.compress(text.encode())))  # type: ignore[operator]
    with pytest.raises(ValueError, match=f"{name}: cannot read the file"):
        load(path)


# --------------------------------------------------------------------------- progress


def test_progress_reports_fractions_and_changes_nothing(tmp_path: Path) -> None:
    pytest.importorskip("pyarrow")
    t = np.arange(20_000) / 100.0
    x = RNG.normal(size=(20_000, 2))
    path = _csv(tmp_path / "p.csv", t, x, header="t,a,b")
    seen: list[float] = []
    with_bar = load(path, progress=seen.append)
    without = load(path)
    np.testing.assert_array_equal(with_bar.data, without.data)
    assert with_bar.sampling.to_dict() == without.sampling.to_dict()
    assert seen and seen[-1] == 1.0 and all(0.0 <= f <= 1.0 for f in seen)
    assert seen == sorted(seen)

"""Tests of gyrobias.io.load: round trips through every supported format and every error path."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import gyrobias
from gyrobias.cli import main
from gyrobias.io import GyroLog, SamplingReport, load

RNG = np.random.default_rng(20121)


def _write(
    path: Path, header: str | None, rows: np.ndarray, delimiter: str = ",", fmt: str = "%.17g"
) -> Path:
    lines = [] if header is None else [header]
    lines += [delimiter.join(fmt % v for v in row) for row in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def _log(n: int = 200, fs: float = 100.0, k: int = 3) -> tuple[np.ndarray, np.ndarray]:
    t = np.arange(n) / fs
    return t, RNG.normal(0.0, 0.1, (n, k))


# --------------------------------------------------------------------------- round trips


def test_csv_with_header_and_time_column_round_trip(tmp_path: Path) -> None:
    t, x = _log()
    path = _write(tmp_path / "log.csv", "t,gx,gy,gz", np.column_stack([t, x]))
    log = load(path)
    assert isinstance(log, GyroLog)
    assert log.columns == ("gx", "gy", "gz")
    assert log.time_column == "t"  # found by name
    assert log.data.dtype == np.float64 and log.data.flags.c_contiguous
    np.testing.assert_array_equal(log.data, x)  # %.17g round-trips float64 exactly
    assert log.fs == 100.0  # 9 significant digits drop the text rounding of t
    assert log.sampling.fs_source == "timestamps"
    assert log.sampling.time_unit == "s"
    assert log.sampling.n_gaps == 0 and log.sampling.n_duplicates == 0
    assert log.warnings == () and log.sampling.regular
    assert log.time is not None
    np.testing.assert_allclose(log.time, t, rtol=0, atol=1e-12)
    assert log.path == path
    np.testing.assert_array_equal(log["gy"], x[:, 1])
    with pytest.raises(KeyError, match="gx, gy, gz"):
        log["nope"]


def test_column_selection_by_name_index_and_string(tmp_path: Path) -> None:
    t, x = _log()
    path = _write(tmp_path / "log.csv", "time,gx,gy,gz", np.column_stack([t, x]))
    by_name = load(path, columns=["gz", "gx"])
    assert by_name.columns == ("gz", "gx")
    np.testing.assert_array_equal(by_name.data, x[:, [2, 0]])
    by_index = load(path, columns=[3, 1])
    np.testing.assert_array_equal(by_index.data, x[:, [2, 0]])
    by_string = load(path, columns="gz, gx")
    np.testing.assert_array_equal(by_string.data, by_name.data)
    # the auto-detected time column becomes data when the user asks for it
    with_t = load(path, columns=["time", "gx"], fs=100.0)
    assert with_t.time is None and with_t.columns == ("time", "gx")


def test_no_header_integer_indices(tmp_path: Path) -> None:
    t, x = _log()
    path = _write(tmp_path / "log.txt", None, np.column_stack([t, x]), delimiter=" ")
    log = load(path, time_column=0, columns=[1, 3])
    assert log.columns == ("col1", "col3")
    np.testing.assert_array_equal(log.data, x[:, [0, 2]])
    assert log.fs == 100.0 and log.time_column == "col0"
    # "col<i>" and digit strings work too, e.g. from the command line
    np.testing.assert_array_equal(load(path, time_column="0", columns="col1,3").data, log.data)
    # without a header nothing is taken for time: every column is data, fs must be given
    plain = load(path, fs=50.0)
    assert plain.data.shape == (200, 4) and plain.time is None
    assert plain.fs == 50.0 and plain.sampling.fs_source == "user"
    none = load(path)
    assert none.fs is None and none.sampling.fs_source is None


@pytest.mark.parametrize(
    ("delimiter", "name"),
    [("\t", "log.tsv"), (";", "log.csv"), (",", "log.dat"), ("  ", "log.txt")],
)
def test_delimiter_detection(tmp_path: Path, delimiter: str, name: str) -> None:
    t, x = _log(50)
    path = _write(
        tmp_path / name, delimiter.join(["t", "a", "b", "c"]), np.column_stack([t, x]), delimiter
    )
    log = load(path)
    assert log.columns == ("a", "b", "c")
    np.testing.assert_array_equal(log.data, x)
    # explicit delimiter gives the same
    np.testing.assert_array_equal(load(path, delimiter=delimiter.strip() or None).data, x)


def test_skip_rows_comments_blank_lines_and_bom(tmp_path: Path) -> None:
    path = tmp_path / "log.csv"
    path.write_text(
        "\ufeffdevice: XYZ-100\nfirmware 1.2\n# a comment\n\nt,gx\n0.0,1\n# mid\n0.5,2\n\n1.0,3\n",
        encoding="utf-8",
    )
    log = load(path, skip_rows=2)
    assert log.columns == ("gx",)
    np.testing.assert_array_equal(log.data[:, 0], [1.0, 2.0, 3.0])
    assert log.fs == 2.0


def test_npy_1d_and_2d(tmp_path: Path) -> None:
    x = RNG.normal(size=(300, 3)).astype(np.float32)
    np.save(tmp_path / "a.npy", x)
    log = load(tmp_path / "a.npy", fs=200.0)
    assert log.columns == ("col0", "col1", "col2") and log.fs == 200.0
    np.testing.assert_array_equal(log.data, x.astype(np.float64))
    assert log.data.dtype == np.float64
    np.save(tmp_path / "b.npy", x[:, 0])
    one = load(tmp_path / "b.npy", fs=200.0)
    assert one.data.shape == (300, 1)
    # a time column in an .npy array (ns, as integers)
    stamps = 1_600_000_000_000_000_000 + np.arange(300, dtype=np.int64) * 5_000_000
    np.save(tmp_path / "c.npy", np.column_stack([stamps, np.arange(300) * 2]))
    timed = load(tmp_path / "c.npy", time_column=0)
    assert timed.fs == 200.0 and timed.sampling.time_unit == "ns"
    np.testing.assert_array_equal(timed.data[:, 0], np.arange(300) * 2.0)


@pytest.mark.parametrize("dtype", ["<f8", ">f8", "<f4", ">i4", "<i8", "<u2"])
@pytest.mark.parametrize("order", ["C", "F"])
@pytest.mark.parametrize("block_bytes", [64, 8 << 20])
def test_npy_rows_read_like_numpy(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, dtype: str, order: str, block_bytes: int
) -> None:
    # the reader reads C-order files by blocks (readinto, no mapping); every dtype and byte
    # order, a column subset, a time column and block boundaries inside the data (64 bytes:
    # a block of 1-2 rows) give what numpy's own load gives
    from gyrobias.io import npy

    monkeypatch.setattr(npy, "_BLOCK_BYTES", block_bytes)
    n = 257
    x = np.empty((n, 5), dtype=dtype, order=order)
    x[:] = RNG.integers(0, 1000, size=(n, 5))
    x[:, 0] = np.arange(n) * 4 + 7  # strictly increasing stamps
    path = tmp_path / "a.npy"
    np.save(path, x)
    ref = np.load(path).astype(np.float64)
    whole = load(path, fs=10.0)
    np.testing.assert_array_equal(whole.data, ref)
    part = load(path, columns=[3, 1], fs=10.0)
    np.testing.assert_array_equal(part.data, ref[:, [3, 1]])
    timed = load(path, time_column=0, columns=[2, 4], time_unit="ms")
    np.testing.assert_array_equal(timed.data, ref[:, [2, 4]])
    assert timed.fs == pytest.approx(250.0)


def test_npy_shorter_than_its_header(tmp_path: Path) -> None:
    # a file cut after its header declared more rows: a clear error, not a short log
    path = tmp_path / "cut.npy"
    np.save(path, np.ones((1000, 3)))
    data = path.read_bytes()
    path.write_bytes(data[: len(data) - 24 * 10 - 5])
    with pytest.raises(ValueError, match=r"cut\.npy"):
        load(path, fs=1.0)
    # the file shrinking between the header and the rows (the block reader's own check)
    from gyrobias.io.npy import _read_rows

    whole = tmp_path / "whole.npy"
    np.save(whole, np.ones((100, 3)))
    offset = whole.stat().st_size - 100 * 24
    table = np.empty((120, 3))
    with pytest.raises(
        ValueError, match=r"whole\.npy: the file ends early \(at row 100 of the 120"
    ):
        _read_rows(whole, offset, 120, 3, np.dtype("<f8"), [0, 1, 2], None, True, table, None)


def test_nanosecond_time_column_exact(tmp_path: Path) -> None:
    # epoch nanoseconds (~1.7e18) are beyond float64's exact integers (2^53 ≈ 9e15): read as
    # int64 they still give exact intervals and hence zero jitter
    n = 500
    stamps = 1_700_000_000_123_456_789 + np.arange(n, dtype=np.int64) * 2_500_000  # 400 Hz
    x = RNG.normal(size=(n, 2))
    path = tmp_path / "ns.csv"
    path.write_text(
        "stamp,a,b\n" + "".join(f"{s},{float(a)!r},{float(b)!r}\n" for s, (a, b) in zip(stamps, x))
    )
    log = load(path, time_column="stamp")
    assert log.sampling.time_unit == "ns"  # by magnitude: median step 2.5e6 ≥ 1000
    assert log.fs == 400.0
    assert log.sampling.jitter == 0.0
    np.testing.assert_array_equal(log.time, (np.arange(n, dtype=np.int64) * 2_500_000) / 1e9)
    assert log.time_start == pytest.approx(1_700_000_000.123456789, abs=1e-6)
    np.testing.assert_array_equal(log.data, x)


@pytest.mark.parametrize(
    ("name", "scale", "unit"),
    [("t_ms", 1e3, "ms"), ("time_us", 1e6, "us"), ("time_ns", 1e9, "ns"), ("t_s", 1.0, "s")],
)
def test_time_unit_from_column_suffix(tmp_path: Path, name: str, scale: float, unit: str) -> None:
    t, x = _log(100, fs=50.0, k=1)
    path = _write(
        tmp_path / "log.csv", f"{name},g", np.column_stack([np.rint(t * scale * 1e3) / 1e3, x])
    )
    log = load(path)
    assert log.sampling.time_unit == unit
    assert log.fs == pytest.approx(50.0, rel=1e-9)


@pytest.mark.parametrize(
    ("name", "scale", "unit"),
    [
        ("Timestamp (us)", 1e6, "us"),  # x-IMU3 GUI export
        ("Time (s)", 1.0, "s"),  # NGIMU
        ("time [ms]", 1e3, "ms"),
        ("t (µs)", 1e6, "us"),
        ("TIME (ns)", 1e9, "ns"),
    ],
)
def test_time_column_with_unit_in_parentheses(
    tmp_path: Path, name: str, scale: float, unit: str
) -> None:
    # A real x-IMU3 log (scikit-kinematics 0.10.4, tests/data/data_xio3/Inertial.csv) has a
    # "Timestamp (us)" column at 50 Hz: it was not found as the time column, and named, it was
    # read as nanoseconds (median step 20000 ≥ 1000), giving fs = 49914 Hz.
    t, x = _log(100, fs=50.0, k=1)
    path = _write(
        tmp_path / "log.csv",
        f"{name},Gyroscope X (deg/s)",
        np.column_stack([np.rint(t * scale * 1e3) / 1e3, x]),
    )
    log = load(path)
    assert log.time_column == name
    assert log.sampling.time_unit == unit
    assert log.fs == pytest.approx(50.0, rel=1e-9)
    assert log.columns == ("Gyroscope X (deg/s)",)
    assert log.units == ("deg/s",)


def test_xsens_preamble_is_skipped_and_its_rate_used(tmp_path: Path) -> None:
    # Xsens MT Manager text exports (e.g. scikit-kinematics 0.10.4 tests/data/data_xsens2.txt)
    # open with "//" lines; the loader took "//" for the header ("unknown column 'Gyr_X';
    # available: //, Start, Time:, 0") and needed --skip-rows and --fs.
    rows = "".join(f" {i}\t0.1\t0.2\t{0.001 * i:.6f}\t\n" for i in range(2552, 2652))
    path = tmp_path / "MT_0001.txt"
    path.write_text(
        "// Start Time: 0\n// Sample rate: 120.0Hz\n// Scenario: 5.9\n// Firmware Version: 2.5.1\n"
        "Counter\tAcc_X\tGyr_X\tGyr_Y\t\n" + rows
    )
    log = load(path, columns="Gyr_X,Gyr_Y", units="rad/s")
    assert log.fs == 120.0 and log.sampling.fs_source == "file"
    np.testing.assert_allclose(log.data[:, 1], 0.001 * np.arange(2552, 2652))
    assert load(path, columns="Gyr_X", fs=100.0).sampling.fs_source == "user"  # given wins
    assert main(["allan", str(path), "--columns", "Gyr_X", "--no-confidence"]) == 0
    no_rate = tmp_path / "no_rate.txt"
    no_rate.write_text(
        "// Start Time: 0\nCounter\tGyr_X\n" + "".join(f"{i}\t0.1\n" for i in range(50))
    )
    assert load(no_rate, columns="Gyr_X").fs is None


@pytest.mark.parametrize(
    ("step", "unit", "fs"),
    [
        (9091, "us", 1e6 / 9091),  # YEI 3-Space ChipTimeUS at 110 Hz
        (20000, "us", 50.0),  # micros() at 50 Hz
        (1000, "us", 1000.0),
        (100_000, "ns", 10_000.0),
        (1_000_000, "ns", 1000.0),
        (999, "s", 1 / 999),
    ],
)
def test_time_unit_guess_from_the_median_step(
    tmp_path: Path, step: int, unit: str, fs: float
) -> None:
    # A real YEI log (scikit-kinematics 0.10.4 tests/data/data_yei.txt: "# Data format:
    # %int(ChipTimeUS),..." then bare rows) had its microsecond stamps read as nanoseconds:
    # fs = 109955 Hz for a 110 Hz sensor. Steps from 1000 to 1e5 are now microseconds.
    path = tmp_path / "yei.txt"
    path.write_text(
        '# Data format: "%int(ChipTimeUS),%float(RawGyroX)"\n'
        + "".join(f"{90198 + step * i},{0.001 * (i % 7)}\n" for i in range(200))
    )
    log = load(path, time_column=0)
    assert log.sampling.time_unit == unit
    assert log.fs == pytest.approx(fs, rel=1e-6)


def test_explicit_time_unit_overrides(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "log.csv", "t,g", np.column_stack([np.arange(100) * 10, np.ones(100)]), fmt="%d"
    )
    guessed = load(path)  # 10-unit steps read as seconds: implausible, so warned about
    assert guessed.fs == pytest.approx(0.1)
    assert any("time_unit" in w for w in guessed.warnings)
    ms = load(path, time_unit="ms")
    assert ms.fs == pytest.approx(100.0) and ms.warnings == ()


# --------------------------------------------------------------------------- sampling report


def test_gap_detection(tmp_path: Path) -> None:
    t = np.arange(1000) / 100.0
    t[600:] += 3.0  # 3 s gap before row 600 → 300 missing samples at 100 Hz
    t[800:] += 0.5  # 0.5 s gap before row 800 → 50 missing
    path = _write(tmp_path / "gaps.csv", "t,g", np.column_stack([t, np.zeros(1000)]))
    rep = load(path).sampling
    assert rep.n_gaps == 2
    np.testing.assert_array_equal(rep.gap_rows, [600, 800])
    np.testing.assert_allclose(rep.gap_durations, [3.01, 0.51], rtol=1e-9)
    assert rep.longest_gap == pytest.approx(3.01)
    assert rep.missing_samples == 350
    assert rep.fs == pytest.approx(100.0)  # gaps do not bias the rate estimate
    assert len(rep.warnings) == 1 and "2 gap(s)" in rep.warnings[0] and "row 600" in rep.warnings[0]
    d = rep.to_dict()
    assert (
        d["gap_rows"] == [600, 800]
        and d["n_gaps"] == 2
        and d["longest_gap_s"] == pytest.approx(3.01)
    )


def test_gap_threshold_is_one_and_a_half_median(tmp_path: Path) -> None:
    t = np.arange(100) * 0.01
    t[50:] += 0.0049  # interval 1.49× the median: not a gap
    t[70:] += 0.0052  # 1.52×: a gap
    rep = load(_write(tmp_path / "g.csv", "t,g", np.column_stack([t, np.zeros(100)]))).sampling
    np.testing.assert_array_equal(rep.gap_rows, [70])


def test_jitter_reported(tmp_path: Path) -> None:
    n = 5000
    steps = 0.01 * (1.0 + 0.05 * RNG.uniform(-1, 1, n - 1))  # ±5 % uniform: s.d. 5 %/√3 ≈ 2.9 %
    t = np.concatenate([[0.0], np.cumsum(steps)])
    rep = load(_write(tmp_path / "j.csv", "t,g", np.column_stack([t, np.zeros(n)]))).sampling
    # s.d. of the steps relative to their median; sampling error of the s.d. ~1 %/√n·… ≪ 0.1 %
    assert rep.jitter == pytest.approx(0.05 / np.sqrt(3.0), rel=0.05)
    assert rep.n_gaps == 0
    assert any("jitter" in w for w in rep.warnings)
    assert rep.fs == pytest.approx(1.0 / np.mean(steps), rel=1e-8)
    # small jitter is not warned about
    t2 = np.arange(n) * 0.01 + RNG.uniform(-1e-6, 1e-6, n)
    quiet = load(_write(tmp_path / "q.csv", "t,g", np.column_stack([t2, np.zeros(n)]))).sampling
    assert quiet.jitter is not None and 0 < quiet.jitter < 1e-3 and quiet.warnings == ()


def test_duplicate_timestamps_reported(tmp_path: Path) -> None:
    t = np.arange(100) * 0.01
    t[41] = t[40]
    rep = load(_write(tmp_path / "d.csv", "t,g", np.column_stack([t, np.zeros(100)]))).sampling
    assert rep.n_duplicates == 1
    np.testing.assert_array_equal(rep.duplicate_rows, [41])
    assert any("repeated timestamp" in w and "row 41" in w for w in rep.warnings)


def test_user_fs_disagreeing_with_timestamps(tmp_path: Path) -> None:
    t, x = _log(200, fs=100.0, k=1)
    path = _write(tmp_path / "log.csv", "t,g", np.column_stack([t, x]))
    ok = load(path, fs=100.5)  # 0.5 %: within the 1 % tolerance
    assert ok.fs == 100.5 and ok.warnings == () and ok.sampling.fs_source == "user"
    off = load(path, fs=102.0)  # 2 %
    assert off.fs == 102.0  # the user's rate is used …
    assert off.sampling.fs_estimated == 100.0
    assert (
        len(off.warnings) == 1 and "102" in off.warnings[0] and "2 %" in off.warnings[0]
    )  # … and reported


def test_sampling_report_str_and_defaults() -> None:
    rep = SamplingReport(n_samples=10, fs=5.0, fs_source="user")
    assert rep.regular and rep.longest_gap is None
    assert "10 samples" in str(rep) and "5 Hz" in str(rep)


def test_caller_file_unchanged_and_array_independent(tmp_path: Path) -> None:
    x = RNG.normal(size=(50, 2))
    np.save(tmp_path / "a.npy", x)
    log = load(tmp_path / "a.npy", fs=1.0)
    log.data[0, 0] = 99.0
    np.testing.assert_array_equal(np.load(tmp_path / "a.npy"), x)


@given(
    st.lists(st.floats(-1e6, 1e6, allow_nan=False, allow_subnormal=False), min_size=2, max_size=30),
    st.sampled_from([",", ";", "\t", " "]),
)
def test_text_round_trip_property(
    tmp_path_factory: pytest.TempPathFactory, values: list[float], delimiter: str
) -> None:
    x = np.array(values).reshape(-1, 1)
    rows = np.column_stack([x, -x])
    path = tmp_path_factory.mktemp("prop") / "p.csv"
    path.write_text("\n".join(delimiter.join(repr(float(v)) for v in row) for row in rows) + "\n")
    log = load(path, fs=1.0)
    np.testing.assert_array_equal(log.data, rows)


def test_exported_from_package() -> None:
    assert gyrobias.io.load is load


# --------------------------------------------------------------------------- errors


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match="no such file.*missing.csv"):
        load(tmp_path / "missing.csv")


def test_directory(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="directory"):
        load(tmp_path)


@pytest.mark.parametrize("text", ["", "\n\n", "# only a comment\n"])
def test_empty_file(tmp_path: Path, text: str) -> None:
    path = tmp_path / "e.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match="e.csv: the file is empty"):
        load(path)


def test_header_without_rows(tmp_path: Path) -> None:
    path = tmp_path / "h.csv"
    path.write_text("t,gx,gy\n")
    with pytest.raises(ValueError, match=r"header \(t, gx, gy\) but no data rows"):
        load(path)


def test_unknown_column_lists_available(tmp_path: Path) -> None:
    t, x = _log(10)
    path = _write(tmp_path / "log.csv", "t,gx,gy,gz", np.column_stack([t, x]))
    with pytest.raises(
        ValueError, match="unknown column 'wx' in log.csv; available: t, gx, gy, gz"
    ):
        load(path, columns=["gx", "wx"])
    with pytest.raises(ValueError, match="unknown time column 'time'.*available: t, gx"):
        load(path, time_column="time")
    with pytest.raises(
        ValueError, match=r"column index 4 out of range: log.csv has 4 columns \(0..3\)"
    ):
        load(path, columns=[4])
    with pytest.raises(ValueError, match="time column is also listed"):
        load(path, columns=["t", "gx"], time_column="t")
    with pytest.raises(ValueError, match="more than once"):
        load(path, columns=["gx", 1])
    with pytest.raises(ValueError, match="columns is empty"):
        load(path, columns=[])
    with pytest.raises(TypeError, match="column name or integer index"):
        load(path, columns=[1.5])  # type: ignore[list-item]


def test_unknown_column_without_header(tmp_path: Path) -> None:
    path = _write(tmp_path / "n.csv", None, np.ones((5, 3)))
    with pytest.raises(ValueError, match="unknown column 'gx'.*available: col0, col1, col2"):
        load(path, columns=["gx"], fs=1.0)


def test_only_time_column(tmp_path: Path) -> None:
    path = _write(tmp_path / "t.csv", "t", np.arange(5.0).reshape(-1, 1))
    with pytest.raises(ValueError, match="no data columns besides the time column"):
        load(path)


def test_non_numeric_cell_names_line_and_column(tmp_path: Path) -> None:
    path = tmp_path / "bad.csv"
    path.write_text("t,gx,gy\n0,1,2\n# note\n0.01,2,3\n0.02,oops,4\n")
    with pytest.raises(
        ValueError, match=r"bad.csv: 'oops' \(not a number\) in column 'gx' at line 5"
    ):
        load(path)


def test_empty_cell(tmp_path: Path) -> None:
    path = tmp_path / "bad.csv"
    path.write_text("t,gx,gy\n0,1,2\n0.01,,3\n")
    with pytest.raises(ValueError, match="an empty cell in column 'gx' at line 3"):
        load(path)


def test_decimal_comma_hint(tmp_path: Path) -> None:
    path = tmp_path / "eu.csv"
    path.write_text("t;gx\n0;1,5\n0,01;2,5\n")
    with pytest.raises(ValueError, match="decimal commas are not supported"):
        load(path)


@pytest.mark.parametrize("bad", ["nan", "NaN", "inf", "-inf"])
def test_nan_cell_names_line_and_column(tmp_path: Path, bad: str) -> None:
    path = tmp_path / "nan.csv"
    path.write_text(f"t,gx,gy\n0,1,2\n\n0.01,2,3\n0.02,3,{bad}\n0.03,4,{bad}\n")
    with pytest.raises(
        ValueError, match=r"in column 'gy' at line 5 \(2 non-finite value\(s\) in all\)"
    ):
        load(path)


def test_nan_in_npy_names_row(tmp_path: Path) -> None:
    x = np.ones((10, 2))
    x[7, 1] = np.nan
    np.save(tmp_path / "n.npy", x)
    with pytest.raises(ValueError, match="nan in column 'col1' at row 7"):
        load(tmp_path / "n.npy", fs=1.0)


def test_nan_in_time_column(tmp_path: Path) -> None:
    path = tmp_path / "t.csv"
    path.write_text("t,g\n0,1\nnan,2\n0.02,3\n")
    with pytest.raises(ValueError, match="nan in the time column 't' at line 3"):
        load(path)


def test_ragged_rows(tmp_path: Path) -> None:
    path = tmp_path / "r.csv"
    path.write_text("t,gx,gy\n0,1,2\n0.01,2\n0.02,3,4\n")
    with pytest.raises(ValueError, match="r.csv: line 3 has only 2 fields"):
        load(path)


def test_header_field_count_mismatch(tmp_path: Path) -> None:
    path = tmp_path / "m.csv"
    path.write_text("t,gx\n0,1,2\n0.01,2,3\n")
    with pytest.raises(ValueError, match="header has 2 names but line 2 has 3 fields"):
        load(path)


def test_out_of_order_timestamps_is_an_error_naming_the_line(tmp_path: Path) -> None:
    path = tmp_path / "o.csv"
    path.write_text("t,g\n0.00,1\n0.01,1\n0.03,1\n0.02,1\n0.04,1\n")
    with pytest.raises(ValueError, match=r"out of order in 't' at line 5 \(0.02 after 0.03"):
        load(path)
    stamps = np.array([0, 10, 30, 20], dtype=np.int64)
    np.save(tmp_path / "o.npy", np.column_stack([stamps, stamps]))
    with pytest.raises(ValueError, match="out of order.*at row 3"):
        load(tmp_path / "o.npy", time_column=0)


def test_constant_time_column(tmp_path: Path) -> None:
    path = tmp_path / "c.csv"
    path.write_text("t,g\n1,1\n1,2\n1,3\n")
    with pytest.raises(ValueError, match="does not advance"):
        load(path)


@pytest.mark.parametrize(
    ("kwargs", "pattern"),
    [
        ({"time_unit": "min"}, "time_unit must be one of"),
        ({"fs": 0.0}, "fs must be finite and > 0"),
        ({"fs": float("nan")}, "fs must be finite and > 0"),
        ({"skip_rows": -1}, "skip_rows must be an integer from 0"),
    ],
)
def test_bad_options(tmp_path: Path, kwargs: dict[str, object], pattern: str) -> None:
    path = _write(tmp_path / "a.csv", "t,g", np.ones((3, 2)))
    with pytest.raises(ValueError, match=pattern):
        load(path, **kwargs)  # type: ignore[arg-type]


def test_npy_errors(tmp_path: Path) -> None:
    np.save(tmp_path / "s.npy", np.array(["a", "b"]))
    with pytest.raises(ValueError, match="not real numeric"):
        load(tmp_path / "s.npy", fs=1.0)
    np.save(tmp_path / "3d.npy", np.ones((2, 2, 2)))
    with pytest.raises(
        ValueError, match=re.escape("1-D or 2-D array (samples × channels), got shape (2, 2, 2)")
    ):
        load(tmp_path / "3d.npy", fs=1.0)
    np.save(tmp_path / "e.npy", np.ones((0, 3)))
    with pytest.raises(ValueError, match="empty"):
        load(tmp_path / "e.npy", fs=1.0)
    (tmp_path / "junk.npy").write_bytes(b"not numpy at all")
    with pytest.raises(ValueError, match="junk.npy: not a readable .npy file"):
        load(tmp_path / "junk.npy", fs=1.0)


@pytest.mark.parametrize("suffix", [".gz", ".bz2", ".xz"])
def test_compressed_text(tmp_path: Path, suffix: str) -> None:
    import bz2
    import gzip
    import lzma

    opener: Any = {".gz": gzip.open, ".bz2": bz2.open, ".xz": lzma.open}[suffix]
    t, x = _log(100)
    text = "t,a,b,c\n" + "".join(
        f"{ti!r},{a!r},{b!r},{c!r}\n" for ti, (a, b, c) in zip(t.tolist(), x.tolist())
    )
    path = tmp_path / f"log.csv{suffix}"
    with opener(path, "wt") as fh:
        fh.write(text)
    log = load(path)
    assert log.columns == ("a", "b", "c") and log.fs == 100.0
    np.testing.assert_array_equal(log.data, x)

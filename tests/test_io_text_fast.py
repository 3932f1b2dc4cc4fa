"""The core's text parser (``gyrocore::text`` via ``gyrobias.io.text._read_core``) against the
previous paths: pyarrow's CSV reader with numpy.loadtxt behind it, and numpy.loadtxt alone.

Every variant of a text log is loaded three ways and must give the same outcome: the same
values bit for bit (and the same time stamps, columns and sampling report), or the same error
message. The float parser is checked against Python's ``float()``.
"""

from __future__ import annotations

import bz2
import gzip
import lzma
import math
import struct
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import gyrobias
from gyrobias import _core
from gyrobias.io import text as text_mod

_WRITERS: dict[str, Callable[[Path, bytes], None]] = {
    "": lambda p, b: p.write_bytes(b),
    ".gz": lambda p, b: p.write_bytes(gzip.compress(b)),
    ".bz2": lambda p, b: p.write_bytes(bz2.compress(b)),
    ".xz": lambda p, b: p.write_bytes(lzma.compress(b)),
}


def _outcome(path: Path, kwargs: dict[str, Any]) -> tuple[Any, ...]:
    """What loading gives: the values' bits, times, names and report, or the error message."""
    try:
        log = gyrobias.io.load(path, **kwargs)
    except (ValueError, TypeError, OSError) as exc:
        return ("error", type(exc).__name__, str(exc))
    data = np.asarray(log.data)
    time = None if log.time is None else np.asarray(log.time).view(np.uint64).tolist()
    report = log.sampling
    return (
        "ok",
        data.shape,
        data.view(np.uint64).tolist(),
        time,
        log.columns,
        log.time_column,
        log.time_start,
        report.fs,
        report.time_unit,
        report.n_gaps,
        report.warnings,
    )


def _three_ways(
    path: Path, kwargs: dict[str, Any], monkeypatch: pytest.MonkeyPatch
) -> tuple[tuple[Any, ...], tuple[Any, ...], tuple[Any, ...], bool]:
    """(core, pyarrow+loadtxt, loadtxt alone) outcomes and whether the core read the file."""
    used: list[bool] = []
    real = text_mod._read_core

    def spy(*args: Any, **kw: Any) -> Any:
        try:
            out = real(*args, **kw)
        except ValueError:  # a bad cell or short row, worded by the core's path
            used.append(True)
            raise
        used.append(out is not None)
        return out

    with monkeypatch.context() as m:
        m.setattr(text_mod, "_read_core", spy)
        fast = _outcome(path, kwargs)
    with monkeypatch.context() as m:
        m.setattr(text_mod, "_core_reads", lambda *a: False)
        previous = _outcome(path, kwargs)
        m.setattr(text_mod, "_read_arrow", lambda *a, **k: None)
        loadtxt = _outcome(path, kwargs)
    return fast, previous, loadtxt, bool(used) and used[-1]


def _table(rows: int = 50, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t = np.arange(rows) / 100.0
    return np.column_stack([t, rng.normal(0.0, 0.01, (rows, 3))])


def _csv(table: np.ndarray, delim: str = ",", header: str | None = "t,gx,gy,gz") -> str:
    """Times as ``repr`` (``0.3``), the channels with 17 significant digits."""
    lines = [] if header is None else [header.replace(",", delim)]
    lines += [delim.join([repr(float(row[0]))] + [f"{v:.17g}" for v in row[1:]]) for row in table]
    return "\n".join(lines) + "\n"


_BASE = _csv(_table())


def _sub(old: str, new: str, text: str = _BASE, count: int = 1) -> str:
    """``text`` with ``old`` replaced (which must occur: a variant that changes nothing would
    test nothing)."""
    assert old in text, old
    return text.replace(old, new, count)


_NS = "t_ns,gx,gy\n" + "".join(
    f"{1_700_000_000_000_000_000 + 5_000_000 * i},{0.1 * i:.17g},{-0.01 * i:.17g}\n"
    for i in range(40)
)

#: name -> (file text, load options, whether the core reads it)
VARIANTS: dict[str, tuple[str, dict[str, Any], bool]] = {
    "comma": (_BASE, {}, True),
    "semicolon": (_csv(_table(), ";"), {}, True),
    "tab": (_csv(_table(), "\t"), {}, True),
    "pipe_given": (_csv(_table(), "|"), {"delimiter": "|"}, True),
    "whitespace": (_csv(_table(), " "), {}, True),
    "whitespace_runs": (_sub(",", "  \t ", count=-1), {}, True),
    "crlf": (_sub("\n", "\r\n", count=-1), {}, True),
    "no_trailing_newline": (_BASE.rstrip("\n"), {}, True),
    "blank_lines": (_sub("\n0.1,", "\n\n\n0.1,"), {}, True),
    "comment_lines": (_sub("\n0.2,", "\n# restart\n0.2,"), {}, True),
    "inline_comment": (_sub("\n", " # note\n", count=-1), {}, True),
    "other_comment": (_sub("\n0.2,", "\n% x\n0.2,"), {"comments": "%"}, True),
    "no_comments": (_BASE, {"comments": ""}, True),
    "spaces_around_cells": (_sub(",", " , ", count=-1), {}, True),
    "trailing_delimiter": (_sub("\n", ",\n", count=-1), {}, True),
    "extra_fields": (_sub("\n0.3,", "\n0.3,9,"), {}, True),
    "bom": ("\ufeff" + _BASE, {}, True),
    "bom_no_header": ("\ufeff" + _csv(_table(), header=None), {"time_column": 0}, True),
    "no_header": (_csv(_table(), header=None), {"fs": 100.0}, True),
    "no_header_time": (_csv(_table(), header=None), {"time_column": 0}, True),
    "skip_rows": ("junk\nmore junk\n" + _BASE, {"skip_rows": 2}, True),
    "xsens_preamble": ("// Start Time: 0\n// Sample rate: 100.0Hz\n" + _BASE, {}, True),
    "columns_reordered": (_BASE, {"columns": ["gz", "gx"]}, True),
    "column_indices": (_BASE, {"columns": [3, 1], "time_column": 0}, True),
    "time_in_middle": ("gx,t,gy\n1,0,2\n3,0.01,4\n5,0.02,6\n", {}, True),
    "ns_int_time": (_NS, {}, True),
    "int_then_float_time": (
        "t_us,g\n" + "".join(f"{10_000 * i},{i}\n" for i in range(30)) + "300000.5,1\n",
        {},
        True,
    ),
    "signed_int_time": ("t_us,g\n+0,1\n+10000,2\n+20000,3\n", {}, True),
    "special_numbers": (
        "t,g\n0,+1.5\n0.01,1.\n0.02,.5\n0.03,1E+05\n0.04,-0\n0.05,1e-320\n",
        {},
        True,
    ),
    "huge_values": ("t,g\n0,1.7976931348623157e308\n0.01,-1.7976931348623157e308\n", {}, True),
    "long_mantissa": ("t,g\n0,0." + "1" * 40 + "\n0.01,2.000000000000000000000000001\n", {}, True),
    "fill_gaps": (_sub("\n0.2,", "\n0.9,"), {"fill_gaps": True}, True),
    "repair_sort": (_sub("\n0.2,", "\n0.001,"), {"repair": "sort"}, True),
    "repair_dedup": (_BASE + _BASE.splitlines()[-1] + "\n", {"repair": "dedup"}, True),
    "spill": (_BASE, {"spill": True}, True),
    # errors: the messages must be the same
    "bad_cell": (_sub("\n0.3,", "\n0.3,abc,"), {}, True),
    "bad_cell_in_time": (_sub("\n0.3,", "\nx3,"), {}, True),
    "empty_cell": (_sub("\n0.3,", "\n0.3,,"), {}, True),
    "blank_only_line": (_sub("\n0.3,", "\n   \n0.3,"), {}, True),
    "decimal_comma": ("t;g\n0;1,5\n0,01;2,5\n", {}, True),
    "ragged_short": (_sub("\n0.3,", "\n0.3\n0.31,"), {}, True),
    "ragged_short_selected": (_sub("\n0.3,", "\n0.3,1\n0.31,"), {"columns": ["gz"]}, True),
    "bad_cell_unselected": (_sub("\n0.3,", "\n0.3,x,"), {"columns": ["gz"]}, True),
    "nan_cell": (_sub("\n0.3,", "\n0.3,nan,"), {}, True),
    "inf_cell": (_sub("\n0.3,", "\n0.3,-Infinity,"), {}, True),
    "nan_time": (_sub("\n0.3,", "\nNaN,"), {}, True),
    "out_of_order": (_sub("\n0.2,", "\n0.001,"), {}, True),
    "not_a_number_int_time": ("t_us,g\n0,1\n10000,2\n1e4x,3\n", {}, True),
    "bad_after_blank_and_comment": (
        _sub("\n0.4,", "\n0.4,?,", _sub("\n0.2,", "\n\n# c\n0.2,")),
        {},
        True,
    ),
    # what the core leaves to the other paths
    "quoted_cells": (_sub("\n0.3,", '\n"0.3",'), {}, False),
    "non_ascii_comment": (_sub("\n0.2,", "\n# café\n0.2,"), {}, False),
    "lone_cr": (_sub("\n0.3,", "\r0.3,"), {}, False),
    "control_char": (_sub("\n0.3,", "\n0.3\x0c,"), {}, False),
    "multichar_delimiter": (_sub(",", "::", count=-1), {"delimiter": "::"}, False),
}


@pytest.mark.parametrize("suffix", ["", ".gz", ".bz2", ".xz"])
@pytest.mark.parametrize("name", sorted(VARIANTS))
def test_core_reads_like_the_previous_paths(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, name: str, suffix: str
) -> None:
    content, kwargs, core_reads = VARIANTS[name]
    if suffix and name in ("spill", "fill_gaps", "repair_sort", "repair_dedup"):
        pytest.skip("options already covered by the plain file")
    path = tmp_path / f"log_{name}.csv{suffix}"
    _WRITERS[suffix](path, content.encode("utf-8"))
    fast, previous, loadtxt, used = _three_ways(path, kwargs, monkeypatch)
    assert fast == previous
    if name != "quoted_cells":  # pyarrow unquotes cells, loadtxt does not (both as before)
        assert fast == loadtxt
    assert used == core_reads


def test_many_chunks_and_a_short_row_estimate(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Lines cut across buffer boundaries, a line longer than the buffer, a result array grown
    past its estimate, and a row count stated in every message."""
    table = _table(3000, seed=3)
    content = _csv(table)
    long_comment = "# " + "x" * 5000 + "\n"
    content = _sub("\n0.5,", "\n" + long_comment + "0.5,", content)
    path = tmp_path / "log.csv"
    path.write_text(content)
    monkeypatch.setattr(text_mod, "CHUNK_BYTES", 4096)
    monkeypatch.setattr(text_mod, "_estimate_rows", lambda *a: 10)
    fast, previous, loadtxt, used = _three_ways(path, {}, monkeypatch)
    assert used and fast == previous == loadtxt
    bad = path.with_name("bad.csv")
    bad.write_text(_sub("\n29.5,", "\n29.5,1,2\n29.505,x,", content))
    fast, previous, loadtxt, used = _three_ways(bad, {}, monkeypatch)
    assert fast[0] == "error" and fast == previous == loadtxt
    assert np.array_equal(gyrobias.io.load(path).data, table[:, 1:])


_FLOAT_TEXT = st.one_of(
    st.floats(allow_nan=False).map(repr),
    st.floats(allow_nan=False, allow_infinity=False).map(lambda v: f"{v:.17g}"),
    st.floats(allow_nan=False, allow_infinity=False).map(lambda v: f"{v:+.16e}"),
    st.floats(allow_nan=False, allow_infinity=False).map(lambda v: f"{v:.30f}"),
    st.builds(
        lambda m, e, s: f"{s}{m}e{e}",
        st.integers(0, 10**25),
        st.integers(-400, 400),
        st.sampled_from(["", "+", "-"]),
    ),
    st.integers(0, 2**64 - 1).map(
        lambda bits: repr(struct.unpack("<d", struct.pack("<Q", bits))[0])
    ),
    st.text(alphabet="0123456789.+-eEnaifty ", max_size=12),
)


@given(_FLOAT_TEXT)
@settings(max_examples=600)
def test_float_parser_is_python_float(cell: str) -> None:
    """Correctly rounded, and the same grammar as float() on these characters (which is
    loadtxt's: it strips blanks and calls the same conversion)."""
    got = _core.text.parse_float(cell.encode())
    try:
        want: float | None = float(cell)
    except ValueError:
        want = None
    if want is None or got is None:
        assert got is want
    elif math.isnan(want):
        assert math.isnan(got)
    else:
        assert struct.pack("<d", got) == struct.pack("<d", want)


@pytest.mark.parametrize(
    ("cell", "bits"),
    [
        ("1e-320", 1e-320),
        ("1.7976931348623157e308", 1.7976931348623157e308),
        ("-0", -0.0),
        ("+0.5", 0.5),
        ("  2.5\t", 2.5),
        ("inf", math.inf),
        ("-Infinity", -math.inf),
        ("4.9406564584124654e-324", 5e-324),
        ("2.4703282292062327e-324", 0.0),
        ("2.4703282292062328e-324", 5e-324),
        ("1.7976931348623158e308", 1.7976931348623157e308),
        ("1.7976931348623159e308", math.inf),
    ],
)
def test_float_parser_edge_cases(cell: str, bits: float) -> None:
    got = _core.text.parse_float(cell.encode())
    assert got is not None and struct.pack("<d", got) == struct.pack("<d", bits)
    assert struct.pack("<d", float(cell)) == struct.pack("<d", bits)
    assert _core.text.parse_float(b"nan") is not None
    for bad in [b"", b" ", b"1_0", b"0x10", b"nan(1)", b"1e", b".", b"1d5", b"++1"]:
        assert _core.text.parse_float(bad) is None


@given(st.integers(-(2**63), 2**63 - 1), st.sampled_from(["", "+", " "]))
def test_int_parser_is_exact(value: int, prefix: str) -> None:
    text = f"{prefix}{value}" if value >= 0 else str(value)
    assert _core.text.parse_int(text.encode()) == value
    assert _core.text.parse_int(str(2**63).encode()) is None


_CELL = st.one_of(
    st.floats(allow_nan=False, allow_infinity=False, width=64).map(lambda v: f"{v:.17g}"),
    st.floats(allow_nan=False, allow_infinity=False).map(repr),
    st.integers(-(10**6), 10**6).map(str),
    st.sampled_from(["", " ", "x", "1,5", "nan", "-inf", " 7 ", "1e", "+.5", "'3'"]),
)


@given(
    rows=st.lists(st.lists(_CELL, min_size=1, max_size=5), min_size=1, max_size=12),
    delim=st.sampled_from([",", ";", "\t", " "]),
    extra=st.lists(st.sampled_from(["", "# c", "   ", "\r"]), max_size=3),
    header=st.booleans(),
)
@settings(max_examples=120, deadline=None)
def test_random_files_read_like_loadtxt(
    tmp_path_factory: pytest.TempPathFactory,
    rows: list[list[str]],
    delim: str,
    extra: list[str],
    header: bool,
) -> None:
    """Random cells, ragged rows, blank, comment and CR-ended lines: the core gives what the
    previous paths give (values or message)."""
    lines = [delim.join(r) for r in rows]
    for k, e in enumerate(extra):
        lines.insert((7 * k) % (len(lines) + 1), e)
    width = max(len(r) for r in rows)
    head = [delim.join(f"c{i}" for i in range(width))] if header else []
    path = tmp_path_factory.mktemp("rand") / "log.csv"
    path.write_text("\n".join(head + lines) + "\n")
    mp = pytest.MonkeyPatch()
    try:
        fast, previous, loadtxt, _ = _three_ways(path, {"fs": 100.0, "time_column": False}, mp)
    finally:
        mp.undo()
    assert fast == previous == loadtxt


@pytest.mark.parametrize("cell", ["'3'", 'a"b', "x'y\"z", "'"])
def test_bad_cell_with_quotes_is_named_alike(tmp_path: Path, cell: str) -> None:
    """numpy quotes a bad cell with ``repr`` (double quotes around a single quote): every path
    still names the cell, its column and line (found by the random-file test above)."""
    path = tmp_path / "log.csv"
    path.write_text(f"0.5\n{cell}\n")
    fast, previous, loadtxt, _ = _three_ways(
        path, {"fs": 100.0, "time_column": False}, pytest.MonkeyPatch()
    )
    assert fast == previous == loadtxt
    assert fast[:2] == ("error", "ValueError") and f"'{cell}' (not a number)" in fast[2]
    assert "line 2" in fast[2]


def test_core_path_needs_no_pyarrow(tmp_path: Path) -> None:
    """CSV reading needs no extra: with pyarrow unimportable the core still reads the file."""
    import subprocess
    import sys

    path = tmp_path / "log.csv"
    path.write_text(_BASE)
    code = (
        "import sys; sys.modules['pyarrow'] = None\n"
        "from gyrobias.io import text\n"
        "used = []\n"
        "real = text._read_core\n"
        "text._read_core = lambda *a, **k: used.append(1) or real(*a, **k)\n"
        "import gyrobias.io\n"
        f"log = gyrobias.io.load({str(path)!r})\n"
        "assert used and 'pyarrow' not in {m for m in sys.modules if sys.modules[m]}\n"
        "print(log.data.shape)"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120
    )
    assert out.stdout.strip() == "(50, 3)"

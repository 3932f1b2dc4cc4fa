"""Delimited text logs (CSV/TSV/whitespace, also ``.gz``/``.bz2``/``.xz``): the core's parser
(``gyrocore::text``, streaming, in parallel, numpy.loadtxt's grammar and errors); pyarrow's
CSV reader (when installed) and then :func:`numpy.loadtxt` for the files it leaves to them;
errors name the line and column."""

from __future__ import annotations

import ast
import bz2
import gzip
import lzma
import os
import re
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from gyrobias import _core
from gyrobias.io._store import Sink, Store
from gyrobias.io.columns import ColumnSpec, _select

_OPENERS: dict[str, Any] = {".gz": gzip.open, ".bz2": bz2.open, ".xz": lzma.open}  # as np.loadtxt
_DECOMPRESSORS: dict[str, Any] = {
    ".gz": lambda raw: gzip.GzipFile(fileobj=raw, mode="rb"),
    ".bz2": bz2.BZ2File,
    ".xz": lzma.LZMAFile,
}
_INT_RE = re.compile(r"^[+-]?\d+$")
#: numpy quotes the cell with ``repr`` (double quotes when it holds a single quote).
_LOADTXT_CELL = re.compile(
    r"could not convert string ('.*'|\".*\") to \w+ at row (\d+), column (\d+)"
)
_LOADTXT_COLS = re.compile(r"number of columns changed from (\d+) to (\d+) at row (\d+)")
_LOADTXT_INDEX = re.compile(r"invalid column index (\d+) at row (\d+) with (\d+) columns")


#: Lines starting with this before the header are a preamble (Xsens MT Manager exports:
#: ``// Start Time: 0``, ``// Sample rate: 120.0Hz``, …): skipped like comments.
PREAMBLE = "//"
_PREAMBLE_RATE = re.compile(
    r"^//\s*(?:sample|sampling|update|output)[ _-]?(?:rate|frequency)\s*[:=]\s*"
    r"([0-9]+(?:\.[0-9]*)?(?:[eE][+-]?[0-9]+)?)\s*hz\s*$",
    re.IGNORECASE,
)


def _content_lines(p: Path, skip_rows: int, comments: str) -> Iterator[tuple[int, str]]:
    """(1-based line number, stripped text) of non-blank, non-comment lines after ``skip_rows``
    and after a ``//`` preamble."""
    opener = _OPENERS.get(p.suffix.lower(), open)
    in_preamble = True
    with opener(p, "rt", encoding="utf-8-sig", errors="replace") as fh:
        for number, line in enumerate(fh, start=1):
            if number <= skip_rows:
                continue
            text = line.strip()
            if not text or (comments and text.startswith(comments)):
                continue
            if in_preamble and text.startswith(PREAMBLE):
                continue
            in_preamble = False
            yield number, text


def _preamble_rate(p: Path, skip_rows: int) -> tuple[float, str] | None:
    """The sample rate a ``//`` preamble states (``// Sample rate: 120.0Hz``) and that line."""
    opener = _OPENERS.get(p.suffix.lower(), open)
    with opener(p, "rt", encoding="utf-8-sig", errors="replace") as fh:
        for number, line in enumerate(fh, start=1):
            text = line.strip()
            if number <= skip_rows or not text:
                continue
            if not text.startswith(PREAMBLE):
                return None
            m = _PREAMBLE_RATE.match(text)
            if m is not None and float(m.group(1)) > 0:
                return float(m.group(1)), text
    return None


def _split(line: str, delimiter: str | None) -> list[str]:
    return [f.strip().strip("\"'") for f in (line.split(delimiter) if delimiter else line.split())]


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _detect_delimiter(lines: list[str]) -> str | None:
    """The first of ``;``, tab, ``,`` that occurs in every sample line, else ``None`` (whitespace).

    ``;`` and tab come first: where they separate fields, a comma is a decimal separator
    (which is then reported as a non-numeric cell), never the other way round. Lines with a
    different number of fields are reported by the parser, naming the line.
    """
    for cand in (";", "\t", ","):
        if all(cand in line for line in lines):
            return cand
    return None


def _read_text(
    p: Path,
    columns: Sequence[ColumnSpec] | None,
    time_column: ColumnSpec | Literal[False] | None,
    time_unit: str,
    delimiter: str | None,
    skip_rows: int,
    comments: str,
    store: Store,
    progress: Callable[[float], None] | None,
) -> tuple[NDArray[np.float64], list[str], NDArray[Any] | None, str | None, Any]:
    sample: list[tuple[int, str]] = []
    for item in _content_lines(p, skip_rows, comments):
        sample.append(item)
        if len(sample) >= 20:
            break
    if not sample:
        raise ValueError(f"{p.name}: the file is empty (no data rows)")
    if delimiter is None:
        delimiter = _detect_delimiter([s for _, s in sample])
    first_fields = _split(sample[0][1], delimiter)
    has_header = not all(_is_number(f) for f in first_fields)
    header = first_fields if has_header else None
    data_start = sample[1][0] if has_header and len(sample) > 1 else sample[0][0]
    if has_header and len(sample) == 1:
        raise ValueError(
            f"{p.name}: the file has a header ({', '.join(first_fields)}) but no data rows"
        )
    n_cols = len(_split(sample[1 if has_header else 0][1], delimiter))
    if header is not None and len(header) != n_cols:
        raise ValueError(
            f"{p.name}: the header has {len(header)} names but line {data_start} has {n_cols} fields"
        )
    idx, t_idx = _select(columns, time_column, header, n_cols, p.name)
    names = [header[i] if header is not None else f"col{i}" for i in idx]
    t_name = None if t_idx is None else (header[t_idx] if header is not None else f"col{t_idx}")

    def line_of(row: int) -> int:
        """File line (1-based) of data row ``row`` (0-based); scans the file, error path only."""
        for k, (number, _) in enumerate(
            item for item in _content_lines(p, skip_rows, comments) if item[0] >= data_start
        ):
            if k == row:
                return number
        return -1

    usecols = ([t_idx] if t_idx is not None else []) + idx

    def col_name(file_col: int) -> str:
        """Name of 0-based file column ``file_col`` for messages."""
        return f"'{header[file_col]}'" if header is not None else f"{file_col}"

    first_data = _split(sample[1 if has_header else 0][1], delimiter)
    int_time = t_idx is not None and bool(_INT_RE.match(first_data[t_idx])) and time_unit != "s"
    if int_time and t_idx is not None:  # every sampled stamp must be an integer, not just the first
        for number, text in sample:
            fields = _split(text, delimiter)
            if number >= data_start and len(fields) > t_idx and not _INT_RE.match(fields[t_idx]):
                int_time = False
    if _core_reads(delimiter, comments):
        # the core's parser: the whole file in one streaming pass straight into the result
        for as_int in (True, False) if int_time else (False,):
            try:
                parsed = _read_core(
                    p,
                    delimiter,
                    comments,
                    data_start,
                    t_idx,
                    idx,
                    as_int,
                    store,
                    progress,
                    _estimate_rows(p, sample, data_start),
                    col_name,
                    line_of,
                )
            except _NotInteger:
                continue  # a time stamp that is a number but no integer: read them as floats
            if parsed is None:
                break  # something the core does not read as loadtxt does: the paths below
            return parsed[1], names, parsed[0], t_name, line_of
    if delimiter is not None and len(delimiter) == 1 and p.suffix.lower() not in _OPENERS:
        data_lines = [text for number, text in sample if number >= data_start]
        mean_line = (sum(len(t) for t in data_lines) + len(data_lines)) / max(len(data_lines), 1)
        estimated_rows = int(p.stat().st_size / max(mean_line, 1.0)) + 1
        for as_int in (True, False) if int_time else (False,):
            fast = _read_arrow(
                p,
                delimiter,
                data_start,
                n_cols,
                t_idx,
                idx,
                as_int,
                store,
                progress,
                estimated_rows,
            )
            if fast is not None:
                return fast[1], names, fast[0], t_name, line_of
    kw: dict[str, Any] = {
        "delimiter": delimiter,
        "skiprows": data_start - 1,
        "comments": comments or None,
        "usecols": usecols,
        "ndmin": 2,
        "encoding": "utf-8-sig",
    }

    if int_time:
        # integer stamps (typically epoch nanoseconds, ~1e18) are read exactly as int64: as
        # float64 they would carry a ±128 ns rounding error that shows up as jitter
        dtype = [("t", np.int64)] + [(f"c{k}", np.float64) for k in range(len(idx))]
        try:
            rec = _loadtxt(p, kw, dtype, col_name, line_of, int_column=t_idx)
        except _NotInteger:
            int_time = False
        else:
            rec = rec.reshape(-1)
            t_raw: NDArray[Any] | None = rec["t"].copy()
            table = np.empty((len(rec), len(idx)))
            for k in range(len(idx)):
                table[:, k] = rec[f"c{k}"]
            del rec
            return table, names, t_raw, t_name, line_of
    full = _loadtxt(p, kw, np.float64, col_name, line_of)
    if t_idx is not None:
        t_raw = full[:, 0].copy()
        table = np.ascontiguousarray(full[:, 1:])
    else:
        t_raw = None
        table = full
    del full
    return table, names, t_raw, t_name, line_of


def _line_offset(p: Path, line: int) -> int:
    """Byte offset of the start of 1-based ``line`` (counting lines as :func:`open` does)."""
    offset = 0
    with open(p, "rb") as fh:
        for _ in range(line - 1):
            chunk = fh.readline()
            if not chunk:
                break
            offset += len(chunk)
    return offset


def _read_arrow(
    p: Path,
    delimiter: str,
    data_start: int,
    n_cols: int,
    t_idx: int | None,
    idx: Sequence[int],
    int_time: bool,
    store: Store,
    progress: Callable[[float], None] | None,
    estimated_rows: int,
) -> tuple[NDArray[Any] | None, NDArray[np.float64]] | None:
    """Parse the data rows with pyarrow's streaming CSV reader: (raw times, table), or ``None``.

    ``None`` means "use numpy.loadtxt": pyarrow is missing, or it rejected the file (a bad
    cell, a ragged row, a comment line, a non-integer time); loadtxt then either reads it or
    reports the exact line and column. Nothing pyarrow reads differently from loadtxt is
    accepted: empty cells and NA spellings are not missing values here, and the rows start at
    the byte offset of the first data line (no row counting).
    """
    try:
        import pyarrow as pa  # type: ignore[import-untyped, unused-ignore]
        import pyarrow.csv as pacsv  # type: ignore[import-untyped, unused-ignore]
    except ImportError:
        return None
    names = [f"c{i}" for i in range(n_cols)]
    types = {names[i]: pa.float64() for i in idx}
    if t_idx is not None:
        types[names[t_idx]] = pa.int64() if int_time else pa.float64()
    include = ([names[t_idx]] if t_idx is not None else []) + [names[i] for i in idx]
    read_opts = pacsv.ReadOptions(column_names=names, block_size=1 << 22, use_threads=True)
    parse_opts = pacsv.ParseOptions(delimiter=delimiter, ignore_empty_lines=True)
    convert_opts = pacsv.ConvertOptions(
        column_types=types,
        include_columns=include,
        null_values=[],
        true_values=[],
        false_values=[],
        strings_can_be_null=False,
        quoted_strings_can_be_null=False,
    )
    sink = store.sink(len(idx), estimated_rows)
    # the raw stamps go to disk with the samples (a log larger than memory)
    stamps = Sink(store, 1, sink.spilled, estimated_rows, np.int64 if int_time else np.float64)
    try:
        source = pa.OSFile(str(p), "r")  # plain reads: a mapping would count the file as resident
        try:
            source.seek(_line_offset(p, data_start))
            reader = pacsv.open_csv(
                source,
                read_options=read_opts,
                parse_options=parse_opts,
                convert_options=convert_opts,
            )
            for batch in reader:
                m = batch.num_rows
                block = sink.reserve(m)
                for k, i in enumerate(idx):
                    block[:, k] = batch.column(names[i]).to_numpy()
                sink.commit(m)
                if t_idx is not None:
                    stamps.reserve(m)[:, 0] = batch.column(names[t_idx]).to_numpy()
                    stamps.commit(m)
                if progress is not None:
                    progress(min(sink.rows / estimated_rows, 0.99))
        finally:
            source.close()
    except (pa.ArrowException, ValueError, OSError):
        sink.finish()
        return None
    table = sink.finish()
    if table.shape[0] == 0:
        return None  # loadtxt reports the empty file in its words
    if progress is not None:
        progress(1.0)
    t_raw = None
    if t_idx is not None:
        t_raw = stamps.finish().reshape(-1)
    return t_raw, table


class _NotInteger(Exception):
    pass


def _bad_cell(p: Path, text: str, col: int, col_name: Any, line_of: Any, row: int) -> ValueError:
    """The error for a cell that is not a number: 0-based file column ``col``, data row ``row``
    (counted as numpy.loadtxt counts rows), the cell's raw ``text``."""
    what = "an empty cell" if not text.strip() else f"'{text}' (not a number)"
    hint = ""
    if re.fullmatch(r"[+-]?\d+,\d+", text.strip()):
        hint = " (decimal commas are not supported)"
    return ValueError(f"{p.name}: {what} in column {col_name(col)} at line {line_of(row)}{hint}")


def _too_few_fields(p: Path, row: int, fields: int, line_of: Any) -> ValueError:
    """The error for data row ``row`` (0-based, loadtxt's count) having only ``fields`` fields."""
    return ValueError(f"{p.name}: line {line_of(row)} has only {fields} fields")


#: Delimiters the core's parser reads (others, multi-character ones included, go to loadtxt).
_CORE_DELIMITERS = (",", ";", "\t", "|", ":")
#: Bytes of text per call of the core's parser (whole lines; the buffer is reused).
CHUNK_BYTES = 1 << 23


def _core_reads(delimiter: str | None, comments: str) -> bool:
    """Whether the core's parser reads this format exactly as numpy.loadtxt does."""
    if delimiter is not None and delimiter not in _CORE_DELIMITERS:
        return False
    return not comments or (
        all(0x21 <= ord(c) < 0x7F for c in comments) and comments[0] != delimiter
    )


def _estimate_rows(p: Path, sample: list[tuple[int, str]], data_start: int) -> int:
    """Data rows a text file probably holds: its size over the mean line length.

    For a plain file the mean comes from 64 KiB read at five places (the first lines of a log
    are often shorter: small time stamps); for a compressed one, from the sampled lines and an
    assumed compression ratio of 3 (the result array is trimmed, or grown, to the real count).
    """
    size = p.stat().st_size
    if p.suffix.lower() in _OPENERS:
        data = [text for number, text in sample if number >= data_start]
        mean = (sum(len(t) for t in data) + len(data)) / max(len(data), 1)
        return int(3 * size / max(mean, 1.0)) + 1
    span = 1 << 16
    lines = 0
    read = 0
    with open(p, "rb") as fh:
        for k in range(5):
            fh.seek(max(0, min(size - span, (size - span) * k // 4)))
            block = fh.read(span)
            first = block.find(b"\n") + 1 if k else 0  # from a line start
            last = block.rfind(b"\n") + 1
            if last > first:
                lines += block.count(b"\n", first, last)
                read += last - first
    mean = read / lines if lines else 1.0
    return int(size / max(mean, 1.0)) + 1


def _read_core(
    p: Path,
    delimiter: str | None,
    comments: str,
    data_start: int,
    t_idx: int | None,
    idx: Sequence[int],
    int_time: bool,
    store: Store,
    progress: Callable[[float], None] | None,
    estimated_rows: int,
    col_name: Any,
    line_of: Any,
) -> tuple[NDArray[Any] | None, NDArray[np.float64]] | None:
    """The data rows parsed by the core (``gyrocore::text``): (raw times, table), or ``None``.

    The file is read (and decompressed) in chunks of :data:`CHUNK_BYTES` into one reused
    buffer; each chunk's whole lines are parsed in parallel straight into the result array
    (in memory, or the block written to the spill file). A bad cell or a short row raises the
    message the numpy.loadtxt path gives; ``None`` means the file holds something the core
    does not read exactly as loadtxt (non-ASCII text, quotes, lone carriage returns, control
    characters) or no rows at all, and the other paths read it.
    """
    fmt = _core.text.Format(
        delimiter,
        comments,
        ([t_idx] if t_idx is not None else []) + list(idx),
        t_idx is not None,
    )
    raw = open(p, "rb")  # noqa: SIM115 - closed below, also when a decompressor wraps it
    try:
        size = os.fstat(raw.fileno()).st_size
        suffix = p.suffix.lower()
        fh: Any = raw
        skip = data_start - 1  # lines before the first data row
        if suffix in _OPENERS:
            fh = _DECOMPRESSORS[suffix](raw)  # streaming: bounded memory
        else:
            prefix = _skip_lines(raw, skip)
            if prefix is None:
                return None
            skip = 0
        sink = store.sink(len(idx), estimated_rows)
        stamps = (
            Sink(store, 1, sink.spilled, estimated_rows, np.int64 if int_time else np.float64)
            if t_idx is not None
            else None
        )
        buf = bytearray(CHUNK_BYTES)
        have = 0
        eof = False
        at_start = data_start == 1
        try:
            while True:
                if not eof and have < len(buf):
                    got = fh.readinto(memoryview(buf)[have:])
                    eof = not got
                    have += got or 0
                    if not eof and have < len(buf):
                        continue  # fill the buffer
                if at_start and skip == 0:
                    at_start = False
                    if buf[:3] == b"\xef\xbb\xbf":  # loadtxt reads the file as utf-8-sig
                        buf[: have - 3] = buf[3:have]
                        have -= 3
                while skip and have:  # compressed: the header lines
                    j = buf.find(b"\n", 0, have)
                    if j < 0 and not eof:
                        break
                    cut = have if j < 0 else j + 1
                    if _lone_cr(bytes(buf[:cut])):
                        return None  # text mode counts such lines differently
                    buf[: have - cut] = buf[cut:have]
                    have -= cut
                    skip -= 1
                if skip:
                    if eof:
                        break
                    continue
                if have == 0:
                    break
                end = have if eof else buf.rfind(b"\n", 0, have) + 1
                if end == 0:  # a line longer than the buffer: make room
                    buf.extend(bytes(len(buf)))
                    continue
                text = np.frombuffer(buf, dtype=np.uint8, count=end)
                lines = _core.text.lines_in(text)  # room for every line: parsed in parallel
                block = sink.reserve(lines)
                times = None if stamps is None else stamps.reserve(lines)[:, 0]
                res = _core.text.parse_into(text, fmt, block, times)
                del text, block, times
                if res.stop == "bad_cell":
                    row = sink.rows + res.row
                    if int_time and res.column == t_idx and _is_number(res.text):
                        raise _NotInteger
                    raise _bad_cell(p, res.text, res.column, col_name, line_of, row)
                if res.stop == "too_few_fields":
                    raise _too_few_fields(p, sink.rows + res.row, res.column, line_of)
                if res.stop != "done":  # "unsupported" ("full" cannot happen: room for every line)
                    return None
                sink.commit(res.rows)
                if stamps is not None:
                    stamps.commit(res.rows)
                buf[: have - end] = buf[end:have]
                have -= end
                if progress is not None:
                    progress(min(raw.tell() / max(size, 1), 0.99))
        finally:
            table = sink.finish()
            t_raw = None if stamps is None else stamps.finish().reshape(-1)
    finally:
        if fh is not raw:
            fh.close()
        raw.close()
    if table.shape[0] == 0:
        return None  # loadtxt reports the empty file in its words
    if progress is not None:
        progress(1.0)
    return t_raw, table


def _lone_cr(line: bytes) -> bool:
    """Whether ``line`` holds a carriage return that does not end it as ``\\r\\n``."""
    body = line[:-2] if line.endswith(b"\r\n") else line
    return b"\r" in body


def _skip_lines(raw: Any, count: int) -> int | None:
    """Skips ``count`` lines of the binary file ``raw`` (positioned at 0); their byte length, or
    ``None`` when they hold a lone carriage return (text mode counts such lines differently)."""
    offset = 0
    for _ in range(count):
        line = raw.readline()
        if not line:
            break
        if _lone_cr(line):
            return None
        offset += len(line)
    raw.seek(offset)
    return offset


def _loadtxt(
    p: Path,
    kw: dict[str, Any],
    dtype: Any,
    col_name: Any,
    line_of: Any,
    int_column: int | None = None,
) -> Any:
    """np.loadtxt with its errors turned into messages naming the file line and column.

    Raises ``_NotInteger`` when the ``int_column`` (0-based file column) holds a non-integer
    number, so that the caller can re-read it as float.
    """
    try:
        out = np.loadtxt(p, dtype=dtype, **kw)
    except ValueError as exc:
        msg = str(exc)
        m = _LOADTXT_CELL.search(msg)
        if m:
            text, row, col = ast.literal_eval(m.group(1)), int(m.group(2)), int(m.group(3))
            # numpy counts data rows from 0 (skipping comments) and file columns from 1
            if int_column is not None and col == int_column + 1 and _is_number(text):
                raise _NotInteger from None
            raise _bad_cell(p, text, col - 1, col_name, line_of, row) from None
        m = _LOADTXT_COLS.search(msg)
        if m:
            raise ValueError(
                f"{p.name}: line {line_of(int(m.group(3)))} has {m.group(2)} fields, "
                f"the lines before it have {m.group(1)}"
            ) from None
        m = _LOADTXT_INDEX.search(msg)
        if m:  # this numpy message counts rows from 1
            raise _too_few_fields(p, int(m.group(2)) - 1, int(m.group(3)), line_of) from None
        raise ValueError(f"{p.name}: {msg}") from None
    except IndexError:
        raise ValueError(
            f"{p.name}: some line has fewer fields than the selected columns need"
        ) from None
    if len(out) == 0:
        raise ValueError(f"{p.name}: the file is empty (no data rows)")
    return out

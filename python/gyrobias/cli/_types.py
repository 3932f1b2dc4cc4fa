"""Argument types of the ``gyrobias`` command line: every option value is checked by argparse.

Each converter turns the option's text into its value or raises
:class:`argparse.ArgumentTypeError` with a message in the package's one style (``must be …,
got …``); :class:`Parser` prints it as one line ``gyrobias: error: --fs must be …, got …`` and
exits with 2, so a bad option value never reaches the library (no traceback, no half-written
output). The ranges here are the generic domain of each kind of value (a rate is finite and
> 0, a level lies strictly between 0 and 1); the precise preconditions stay with the functions
the commands call, whose ``ValueError`` is printed the same way by :func:`gyrobias.cli.main`.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
from pathlib import Path
from typing import NoReturn

from gyrobias._cnames import reserved_c_name

__all__ = [
    "TERMS",
    "Parser",
    "c_identifier",
    "column_list",
    "count",
    "delimiter",
    "export_spec",
    "finite",
    "format_lines",
    "line_list",
    "non_negative",
    "non_negative_int",
    "path",
    "positive",
    "positive_int",
    "probability",
    "repair_spec",
    "term_list",
    "tau_range",
    "text",
    "unit_spec",
]

_ARGUMENT = re.compile(r"^argument ([^:]+): (.*)$", re.DOTALL)


class Parser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose usage errors are one line ``gyrobias: error: …`` (exit 2).

    argparse prints the usage and ``gyrobias allan: error: argument --fs: …``; this parser
    prints ``gyrobias: error: --fs must be finite and > 0, got 'nan'`` instead (the usage stays
    available with ``--help``). Subparsers inherit the class.
    """

    def error(self, message: str) -> NoReturn:
        match = _ARGUMENT.match(message)
        if match and match.group(2).startswith("must "):
            # "argument --fs: must be …" → "--fs must be …" (the package's message style)
            name = match.group(1).split("/")[-1]
            message = f"{name} {match.group(2)}"
        line = " ".join(message.split())
        sys.stderr.write(f"gyrobias: error: {line}\n")
        sys.exit(2)


def _fail(what: str, value: str) -> NoReturn:
    raise argparse.ArgumentTypeError(f"must be {what}, got {value!r}")


def _float(value: str, what: str) -> float:
    try:
        v = float(value)
    except ValueError:
        _fail(what, value)
    if not math.isfinite(v):
        _fail(what, value)
    return v


def finite(value: str) -> float:
    """A finite number (``nan``, ``inf`` and text are refused)."""
    return _float(value, "finite")


def positive(value: str) -> float:
    """A finite number > 0 (rates, durations, densities, bandwidths)."""
    v = _float(value, "finite and > 0")
    if v <= 0.0:
        _fail("finite and > 0", value)
    return v


def non_negative(value: str) -> float:
    """A finite number ≥ 0 (a variance or a density that may be zero)."""
    v = _float(value, "finite and >= 0")
    if v < 0.0:
        _fail("finite and >= 0", value)
    return v


def probability(value: str) -> float:
    """A level strictly between 0 and 1 (confidence levels)."""
    v = _float(value, "a number strictly between 0 and 1")
    if not 0.0 < v < 1.0:
        _fail("a number strictly between 0 and 1", value)
    return v


def _int(value: str, low: int, what: str) -> int:
    try:
        v = int(value, 10)
    except ValueError:
        _fail(what, value)
    if v < low or v >= 2**63:
        _fail(what, value)
    return v


def non_negative_int(value: str) -> int:
    """An integer from 0 to 2**63 − 1 (seeds, rows to skip, an index)."""
    return _int(value, 0, "an integer >= 0")


def positive_int(value: str) -> int:
    """An integer from 1 to 2**63 − 1 (counts, worker and thread numbers)."""
    return _int(value, 1, "an integer >= 1")


def count(value: str) -> int:
    """An alias of :func:`positive_int` for sample counts."""
    return _int(value, 1, "an integer >= 1")


_DELIMITER_NAMES = {"\\t": "\t", "tab": "\t", "whitespace": " ", "space": " ", " ": " "}
_DELIMITER_REFUSED = set("\"'\r\n.-+eE#") | set("0123456789")


def delimiter(value: str) -> str:
    """One field separator: a single character (``,`` ``;`` ``|`` …) or ``tab``/``\\t``/``whitespace``.

    Returns the character; ``" "`` stands for any run of whitespace (the loader's ``None``).
    Digits, signs, ``.``, ``e``, quotes, ``#`` and line breaks are refused: they are part of
    the numbers, the comments or the lines themselves.
    """
    if value in _DELIMITER_NAMES:
        return _DELIMITER_NAMES[value]
    # an ASCII character (the readers split on bytes; pyarrow refuses anything else)
    if len(value) != 1 or value in _DELIMITER_REFUSED or not value.isascii():
        _fail("one character such as , ; | or tab or whitespace", value)
    return value


def _items(value: str, what: str) -> list[str]:
    items = [v.strip() for v in value.split(",")]
    if not value.strip() or any(not v for v in items):
        _fail(what, value)
    return items


def column_list(value: str) -> str:
    """A comma-separated list of channel names or 0-based indices, none empty."""
    items = _items(value, "a comma-separated list of column names or 0-based indices")
    for item in items:
        if item.lstrip("-").isdigit() and int(item) < 0:
            _fail("a comma-separated list of column names or 0-based indices (>= 0)", value)
        if not item.isprintable():  # names reach files: the library's one-line rule
            _fail("a comma-separated list of column names or 0-based indices", value)
    return value


def unit_spec(value: str) -> str:
    """A unit for all channels, one per channel, or ``name=unit`` pairs; each unit is parsed."""
    from gyrobias.units import _parse_unit

    items = _items(value, "a unit (deg/s), one per channel or name=unit pairs")
    for item in items:
        unit = item.partition("=")[2] if "=" in item else item
        try:
            _parse_unit(unit.strip())
        except ValueError as exc:
            raise argparse.ArgumentTypeError(
                f"must be known units (one, one per channel or name=unit), got {value!r}: {exc}"
            ) from None
    return value


def repair_spec(value: str) -> str:
    """``sort``, ``dedup``, both (comma-separated) or empty."""
    if not value.strip():
        return ""
    items = _items(value, "a comma-separated subset of sort, dedup")
    if any(item not in ("sort", "dedup") for item in items):
        _fail("a comma-separated subset of sort, dedup", value)
    return value


def path(value: str) -> Path:
    """A file or directory name: not empty, no line breaks or NUL (the OS refuses those)."""
    if not value or any(c in value for c in "\n\r\x00"):
        _fail("a file name (not empty, on one line)", value)
    return Path(value)


def c_identifier(value: str) -> str:
    """A C identifier (``[A-Za-z_][A-Za-z0-9_]*``): written into generated C as a prefix."""
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", value):
        _fail("a C identifier ([A-Za-z_][A-Za-z0-9_]*)", value)
    reserved = reserved_c_name(value)
    if reserved is not None:
        _fail(f"a C identifier that is no standard header or reserved name ({reserved})", value)
    return value


def text(value: str) -> str:
    """Free text that ends up in files (a topic, a name): one line of printable text (the
    library's rule, :func:`gyrobias._validation.text`: no line break of any kind — ``\\x85``
    and ``\\u2028`` included — no control or format character, no lone surrogate)."""
    if not value or not value.isprintable() or len(value) > 200:
        _fail("non-empty printable text on one line (at most 200 characters)", value)
    return value


#: The noise terms ``--fit-terms`` / ``--terms`` accept (those of :func:`gyrobias.noise.fit`).
TERMS = ("Q", "N", "B", "K", "R", "GM", "GM2")


def term_list(value: str) -> str:
    """A comma-separated list of noise-term symbols (:data:`TERMS`), none repeated."""
    what = f"a comma-separated list of {', '.join(TERMS)}"
    items = _items(value, what)
    if any(item not in TERMS for item in items) or len(set(items)) != len(items):
        _fail(what, value)
    return value


def export_spec(value: str) -> tuple[str, str]:
    """``FMT=PATH`` with a known estimator format (or ``all``) → ``(fmt, path)``."""
    from gyrobias.exports import FORMATS

    fmt, sep, path = value.partition("=")
    fmt = fmt.strip().lower()
    if not sep or not path.strip():
        _fail("FMT=PATH", value)
    if fmt not in (*FORMATS, "all"):
        _fail(f"FMT=PATH with FMT one of {', '.join(FORMATS)}, all", value)
    return fmt, path.strip()


def tau_range(value: str) -> tuple[float, float]:
    """``MIN,MAX``: a τ range in seconds, 0 < MIN < MAX, both finite (``--fit-tau-range``)."""
    what = "MIN,MAX in seconds with 0 < MIN < MAX"
    parts = value.split(",")
    if len(parts) != 2:
        _fail(what, value)
    low, high = (_float(p.strip(), what) for p in parts)
    if not 0.0 < low < high:
        _fail(what, value)
    return (low, high)


def line_list(value: str) -> str | list[float | tuple[float, float]] | None:
    """``auto``, ``none`` or ``F[:HW],…`` (Hz; ``F`` a seed, ``F:HW`` a window, ``F:0`` held)
    for :func:`gyrobias.noise.fit`'s ``lines`` (``--lines``)."""
    text_value = value.strip().lower()
    if text_value == "auto":
        return "auto"
    if text_value == "none":
        return None
    what = "auto, none or FREQ[:HALFWIDTH],… in Hz (FREQ > 0, 0 <= HALFWIDTH < FREQ)"
    out: list[float | tuple[float, float]] = []
    for item in _items(value, what):
        freq_text, colon, width_text = item.partition(":")
        freq = _float(freq_text, what)
        if freq <= 0.0:
            _fail(what, value)
        if not colon:
            out.append(freq)
            continue
        width = _float(width_text, what)
        if not 0.0 <= width < freq:
            _fail(what, value)
        out.append((freq, width))
    return out


def format_lines(lines: str | list[float | tuple[float, float]] | None) -> str:
    """The ``--lines`` text of a :func:`line_list` value (for the outputs)."""
    if lines is None:
        return "none"
    if isinstance(lines, str):
        return lines
    return ",".join(f"{x[0]:g}:{x[1]:g}" if isinstance(x, tuple) else f"{x:g}" for x in lines)

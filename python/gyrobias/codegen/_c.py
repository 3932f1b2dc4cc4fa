"""Shared pieces of the C templates: names, literals, file headers, atomic writing."""

from __future__ import annotations

import math
import os
import re
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from gyrobias import _core
from gyrobias._cnames import reserved_c_name
from gyrobias._validation import checked_path, real
from gyrobias._version import __version__

#: C99 keywords (ISO/IEC 9899:1999 §6.4.1) and the C11/C23 ones a newer compiler may reserve.
C_KEYWORDS = frozenset(
    """auto break case char const continue default do double else enum extern float for goto if
    inline int long register restrict return short signed sizeof static struct switch typedef
    union unsigned void volatile while _Bool _Complex _Imaginary _Alignas _Alignof _Atomic
    _Generic _Noreturn _Static_assert _Thread_local alignas alignof bool constexpr false
    nullptr static_assert thread_local true typeof typeof_unqual""".split()
)
_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
#: C99 §5.2.4.1 guarantees 31 significant initial characters of an external identifier; the
#: longest suffix the emitters append is ``_predict_one`` (12 characters).
MAX_NAME = 19
DTYPES = ("float64", "float32", "q31")


def gyrobias_version() -> str:
    """The installed gyrobias version."""
    return __version__


def check_name(name: object) -> str:
    """``name`` if it is a usable C identifier prefix, else ``ValueError``."""
    if not isinstance(name, str):
        raise TypeError(f"name must be a str, got {type(name).__name__}")
    if not _IDENT.match(name):
        raise ValueError(f"name must be a C identifier ([A-Za-z_][A-Za-z0-9_]*), got {name!r}")
    if name in C_KEYWORDS:
        raise ValueError(f"name must not be a C keyword, got {name!r}")
    if name.startswith("__") or (name.startswith("_") and name[1:2].isupper()):
        raise ValueError(f"name must not be a reserved C identifier (__x, _X), got {name!r}")
    reserved = reserved_c_name(name)
    if reserved is not None:
        raise ValueError(f"name must not be a C standard header or reserved identifier: {reserved}")
    if len(name) > MAX_NAME:
        raise ValueError(
            f"name must have at most {MAX_NAME} characters (C99 guarantees 31 significant "
            f"characters for the generated names), got {len(name)}"
        )
    return name


def check_dtype(dtype: object) -> str:
    """Normalise ``dtype`` ("float64", "float32", "q31" or the NumPy float types)."""
    if dtype is np.float64 or dtype is np.float32:
        return np.dtype(dtype).name
    if isinstance(dtype, np.dtype) and dtype.name in ("float32", "float64"):
        return dtype.name
    if not isinstance(dtype, str) or dtype not in DTYPES:
        raise ValueError(f"dtype must be 'float64', 'float32' or 'q31', got {dtype!r}")
    return dtype


def check_directory(path: object) -> Path:
    """The output directory: existing and writable, or creatable (its parent writable)."""
    # an empty string is refused (Path("") is "." and would write into the current directory)
    p = checked_path("path", path, "a directory path")
    if p.exists():
        if not p.is_dir():
            raise ValueError(f"path must be a directory, got the file {str(p)!r}")
        if not os.access(p, os.W_OK | os.X_OK):
            raise ValueError(f"path must be a writable directory, got {str(p)!r}")
        return p
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir() or not os.access(parent, os.W_OK | os.X_OK):
        raise ValueError(
            f"path must be a writable directory (or one that can be created), got {str(p)!r}"
        )
    return p


def float_literal(x: float, dtype: str) -> str:
    """Exact C literal of ``x`` rounded to ``dtype`` (hexadecimal float, C99 §6.4.4.2)."""
    if dtype == "float32":
        v = float(np.float32(x))
        if not math.isfinite(v):
            raise ValueError(f"the coefficient {x!r} overflows float32")
        return f"{v.hex()}f"
    if not math.isfinite(x):
        raise ValueError(f"the coefficient {x!r} is not finite")
    return float(x).hex()


def int_literal(v: int, bits: int = 32) -> str:
    """Integer literal of ``v`` for ``int32_t``/``int64_t`` (INT32_MIN spelled safely)."""
    if bits == 32:
        if v == -(2**31):
            return "INT32_MIN"
        return f"INT32_C({v})"
    return f"INT64_C({v})"


def array_body(items: list[str], per_line: int = 4, indent: str = "    ") -> str:
    """The items of a C initializer list, ``per_line`` per line."""
    lines = [
        indent + ", ".join(items[i : i + per_line]) + ("," if i + per_line < len(items) else "")
        for i in range(0, len(items), per_line)
    ]
    return "\n".join(lines)


C_TYPES = {"float64": "double", "float32": "float", "q31": "int32_t"}

FP_NOTE = """\
 * Floating point: IEEE-754 arithmetic with every operation rounded to the type (C99
 * FLT_EVAL_METHOD == 0: x86-64 SSE, AArch64, Cortex-M with FPU) and no contraction into fused
 * multiply-adds: compile with -ffp-contract=off (GCC in ISO mode -std=c99 does not contract;
 * Clang does by default, so the source also says #pragma STDC FP_CONTRACT OFF for it) and
 * never with -ffast-math. Then the outputs equal, bit for bit, gyrobias'
 *   {ref}."""

Q31_NOTE = """\
 * Fixed point (Q31): a sample X (int32_t) stands for X * 2^-31 of full scale FS, the value you
 * choose for INT32 range (e.g. the gyro's +-2000 deg/s: X = rate / FS * 2^31). Coefficients
 * are round(c * 2^n) (to nearest, ties away from zero) with the largest shift n that fits;
 * products are formed in int64_t and brought back with a rounding shift (round half up:
 * (v >> n) + ((v >> (n - 1)) & 1)); results saturate to [INT32_MIN, INT32_MAX]. Requires >> of
 * a negative int64_t to be arithmetic (GCC, Clang, Arm, IAR; checked at compile time)."""


@dataclass(frozen=True)
class GeneratedC:
    """The files written by a ``to_c`` call.

    Attributes
    ----------
    header, source : pathlib.Path
        ``<name>.h`` and ``<name>.c``.
    name : str
        The C prefix of every generated identifier.
    dtype : str
        ``"float64"``, ``"float32"`` or ``"q31"``.
    state_bytes : int
        ``sizeof`` the state struct on an LP64/ILP32 target with natural alignment.
    q31 : dict
        For ``dtype="q31"``: the shifts, integer coefficients, the worst-case error bound
        against float64 and the RMS quantisation noise (units of full scale; with
        ``full_scale`` also in the rate's units). Empty otherwise.
    """

    header: Path
    source: Path
    name: str
    dtype: str
    state_bytes: int
    q31: dict[str, Any] = field(default_factory=dict)


def write_pair(directory: Path, name: str, header: str, source: str) -> tuple[Path, Path]:
    """Write ``<name>.h`` and ``<name>.c`` atomically (temporary files beside them, renamed)."""
    directory.mkdir(parents=False, exist_ok=True)
    targets = [(directory / f"{name}.h", header), (directory / f"{name}.c", source)]
    temps: list[str] = []
    try:
        for target, text in targets:
            fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=directory)
            temps.append(tmp)
            with os.fdopen(fd, "w", encoding="ascii", newline="\n") as fh:
                fh.write(text)
        for (target, _), tmp in zip(targets, temps, strict=True):
            os.replace(tmp, target)
    except BaseException:
        for tmp in temps:
            if os.path.exists(tmp):
                os.unlink(tmp)
        raise
    return targets[0][0], targets[1][0]


def preamble(title: str, name: str, lines: list[str], note: str) -> str:
    """The leading comment shared by header and source."""
    body = "\n".join(f" * {line}" if line else " *" for line in lines)
    return (
        f"/* {name}: {title}\n"
        f" * Generated by gyrobias {gyrobias_version()}; do not edit (regenerate instead).\n"
        f" *\n{body}\n *\n{note}\n"
        " *\n * Dependency-free C99: no dynamic allocation, no recursion, no global mutable state\n"
        " * (coefficients are static const). Every function takes the state explicitly.\n */\n"
    )


SOURCE_PRELUDE = """#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif
"""

Q31_HELPERS = """/* >> of a negative value must be arithmetic (implementation-defined in C99). */
typedef char {name}_arithmetic_shift_check[((-INT64_C(5)) >> 1) == -INT64_C(3) ? 1 : -1];

static int32_t {name}_sat32(int64_t v)
{{
    return v > INT32_MAX ? INT32_MAX : (v < INT32_MIN ? INT32_MIN : (int32_t)v);
}}

/* v * 2^-n rounded to nearest, ties up; cannot overflow. */
static int64_t {name}_rshift(int64_t v, unsigned int n)
{{
    return (v >> n) + ((v >> (n - 1u)) & 1);
}}
"""


def check_full_scale(full_scale: float | None) -> float | None:
    """``full_scale`` (> 0, the rate Q31 full scale stands for) or None."""
    if full_scale is None:
        return None
    # finite and > 0: the core's check (inf passed the `> 0` test before)
    return _core.validate.positive("full_scale", real("full_scale", full_scale))


def check_arguments(
    name: object, dtype: object, path: object, full_scale: float | None
) -> tuple[str, str, Path, float | None]:
    """The arguments every emitter shares, checked in this order (the first bad one is
    reported): ``(name, dtype, directory, full_scale)`` as :func:`check_name`,
    :func:`check_dtype`, :func:`check_directory` and :func:`check_full_scale` return them."""
    return (
        check_name(name),
        check_dtype(dtype),
        check_directory(path),
        check_full_scale(full_scale),
    )

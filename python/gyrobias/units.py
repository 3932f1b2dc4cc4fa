"""Units of noise coefficients: parsing, dimensions and conversion.

Coefficients are stored in the base units of the data (for a rate in ``u/s``: Q in u, N in
u/√s, B in u/s, K in u/s^1.5, R in u/s²) and converted here to the customary units. Unit strings
are products and quotients of the symbols below with powers::

    deg/√h    deg/h^1.5    rad/s/√Hz    rad/s^2/sqrt(Hz)    m/s/sqrt(h)    mg    deg/h²

``a/b/c`` means ``a/(b·c)``; ``√x`` and ``sqrt(x)`` are square roots; powers are ``^p`` (p an
integer or decimal, possibly negative), ``²`` or ``³``; ``·`` or ``*`` multiply. ``1/√Hz = √s``.

Symbols (SI value):

========================  =====================================================
angle                     rad, mrad, urad (µrad), deg (°), arcmin, arcsec
length                    m, mm, um (µm)
acceleration              g = 9.80665 m/s², mg, ug (µg)
time                      s, ms, min, h (hr)
frequency                 Hz
========================  =====================================================

Conversions of the IEEE-952 coefficients (SPEC §1)::

    N[deg/√h] = 60·N[deg/√s]        B[deg/h] = 3600·B[deg/s]
    K[deg/h^1.5] = 216000·K[deg/s^1.5]    R[deg/h²] = 3600²·R[deg/s²]

Kalibr's continuous-time densities are ``N`` in rad/s/√Hz (``gyroscope_noise_density``) and
``K`` in rad/s²/√Hz (``gyroscope_random_walk``); a datasheet's one-sided noise density ``nd`` is
``√2·N`` (SPEC §1).
"""

from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass
from fractions import Fraction

from gyrobias._validation import text as _text

__all__ = [
    "CUSTOMARY",
    "SYMBOLS",
    "Unit",
    "base_unit",
    "conversion_factor",
    "parse_unit",
    "sensor_kind",
]

_G = 9.80665
_DEG = math.pi / 180.0

#: Unit symbols: SI factor and dimension (angle, length, time).
SYMBOLS: dict[str, tuple[float, tuple[int, int, int]]] = {
    "rad": (1.0, (1, 0, 0)),
    "mrad": (1e-3, (1, 0, 0)),
    "urad": (1e-6, (1, 0, 0)),
    "µrad": (1e-6, (1, 0, 0)),
    "deg": (_DEG, (1, 0, 0)),
    "°": (_DEG, (1, 0, 0)),
    "arcmin": (_DEG / 60.0, (1, 0, 0)),
    "arcsec": (_DEG / 3600.0, (1, 0, 0)),
    "m": (1.0, (0, 1, 0)),
    "mm": (1e-3, (0, 1, 0)),
    "um": (1e-6, (0, 1, 0)),
    "µm": (1e-6, (0, 1, 0)),
    "g": (_G, (0, 1, -2)),
    "mg": (_G * 1e-3, (0, 1, -2)),
    "ug": (_G * 1e-6, (0, 1, -2)),
    "µg": (_G * 1e-6, (0, 1, -2)),
    "s": (1.0, (0, 0, 1)),
    "sec": (1.0, (0, 0, 1)),
    "ms": (1e-3, (0, 0, 1)),
    "min": (60.0, (0, 0, 1)),
    "h": (3600.0, (0, 0, 1)),
    "hr": (3600.0, (0, 0, 1)),
    "Hz": (1.0, (0, 0, -1)),
}

#: Time exponent p of each coefficient relative to the data unit D: the term is in D·s^p.
TERM_TIME_POWER: dict[str, Fraction] = {
    "Q": Fraction(1),
    "N": Fraction(1, 2),
    "B": Fraction(0),
    "K": Fraction(-1, 2),
    "R": Fraction(-1),
}

#: Customary units per sensor kind and system.
CUSTOMARY: dict[str, dict[str, dict[str, str]]] = {
    "gyro": {
        "ieee": {"Q": "deg", "N": "deg/√h", "B": "deg/h", "K": "deg/h^1.5", "R": "deg/h²"},
        "si": {"Q": "rad", "N": "rad/s/√Hz", "B": "rad/s", "K": "rad/s²/√Hz", "R": "rad/s²"},
    },
    "accel": {
        "ieee": {"Q": "m/s", "N": "m/s/√h", "B": "mg", "K": "m/s/h^1.5", "R": "m/s/h²"},
        "si": {"Q": "m/s", "N": "m/s²/√Hz", "B": "m/s²", "K": "m/s³/√Hz", "R": "m/s³"},
    },
}
CUSTOMARY["gyro"]["kalibr"] = CUSTOMARY["gyro"]["si"]
CUSTOMARY["accel"]["kalibr"] = CUSTOMARY["accel"]["si"]

Dims = tuple[Fraction, Fraction, Fraction]


@dataclass(frozen=True)
class Unit:
    """A parsed unit: SI factor and dimension exponents (angle, length, time)."""

    factor: float
    dims: Dims

    def __mul__(self, other: Unit) -> Unit:
        return Unit(self.factor * other.factor, tuple(a + b for a, b in zip(self.dims, other.dims)))  # type: ignore[arg-type]

    def __truediv__(self, other: Unit) -> Unit:
        return Unit(self.factor / other.factor, tuple(a - b for a, b in zip(self.dims, other.dims)))  # type: ignore[arg-type]

    def __pow__(self, p: Fraction) -> Unit:
        return Unit(self.factor ** float(p), tuple(a * p for a in self.dims))  # type: ignore[arg-type]


_ONE = Unit(1.0, (Fraction(0), Fraction(0), Fraction(0)))
_TOKEN = re.compile(r"\s*(sqrt|√|\^|\*|·|/|\(|\)|²|³|-?\d+(?:\.\d+)?|[A-Za-zµ°]+)")


def _valid_units_message(text: str) -> str:
    examples = sorted(
        {u for kind in CUSTOMARY.values() for system in kind.values() for u in system.values()}
    )
    return (
        f"unknown unit {text!r}; valid symbols are {', '.join(SYMBOLS)} combined with '/', '·' or "
        f"'*', powers '^p', '²', '³' and '√'/'sqrt()'; customary units: {', '.join(examples)}"
    )


def parse_unit(text: str) -> Unit:
    """Parse a unit string (see the module docs for the grammar).

    Raises
    ------
    ValueError
        On an unknown symbol or malformed string, naming ``text``; the message lists the valid
        symbols.
    """
    return _named("text", text)


def _named(name: str, text: str) -> Unit:
    """:func:`_parse_unit` with the argument's ``name`` in front of its message.

    The text is checked first (:func:`gyrobias._validation.text`: a string, one printable line,
    bounded length — which also bounds the parser's nesting depth); a unit whose factor leaves
    float64 (``deg^99999``) is a ``ValueError`` like any other unparsable unit.
    """
    _text(name, text)
    try:
        return _parse_unit(text)
    except ValueError as exc:
        raise ValueError(f"{name}: {exc}") from None


def _parse_unit(text: str) -> Unit:
    """:func:`parse_unit` without naming the argument (for callers that name it themselves).

    Parsed once per string (a :class:`Unit` is immutable; errors are not cached): converting
    a fit's coefficients parses the same few units for every term, channel and redraw.
    Every unit string goes through here: a text that is not one printable line of at most
    200 characters (which also bounds the parser's nesting depth) or whose factor to SI leaves
    float64 (``deg^99999``) is a ``ValueError`` like any other unparsable unit.
    """
    if isinstance(text, str):
        return _parse_cached(text)
    return _parse_text(text)


def _parse_text(text: str) -> Unit:
    """:func:`_parse_unit` without the cache."""
    if not isinstance(text, str) or not text.strip():
        raise ValueError(_valid_units_message(str(text)))
    if len(text) > 200 or not text.isprintable():
        shown = repr(text[:60]) + ("..." if len(text) > 60 else "")
        raise ValueError(
            f"unknown unit {shown}: a unit is one printable line of at most 200 characters"
        )
    try:
        unit = _parse_checked(text)
    except (OverflowError, ZeroDivisionError, RecursionError):
        raise ValueError(_valid_units_message(text)) from None
    if not (math.isfinite(unit.factor) and unit.factor > 0.0):
        raise ValueError(
            f"the unit {text!r} has a factor of {unit.factor!r} to SI, outside float64's range"
        )
    return unit


def _parse_checked(text: str) -> Unit:
    """The recursive-descent parser of :func:`_parse_unit` (its input already checked)."""
    tokens: list[str] = []
    pos = 0
    while pos < len(text):
        if text[pos:].strip() == "":
            break
        match = _TOKEN.match(text, pos)
        if match is None:
            raise ValueError(_valid_units_message(text))
        tokens.append(match.group(1))
        pos = match.end()

    def atom(i: int) -> tuple[Unit, int]:
        if i >= len(tokens):
            raise ValueError(_valid_units_message(text))
        tok = tokens[i]
        if tok in ("sqrt", "√"):
            inner, j = atom(i + 1)
            return inner ** Fraction(1, 2), j
        if tok == "(":
            inner, j = expr(i + 1)
            if j >= len(tokens) or tokens[j] != ")":
                raise ValueError(_valid_units_message(text))
            return power(inner, j + 1)
        if tok == "1":
            return power(_ONE, i + 1)
        if tok in SYMBOLS:
            factor, dims = SYMBOLS[tok]
            return power(Unit(factor, tuple(Fraction(d) for d in dims)), i + 1)  # type: ignore[arg-type]
        raise ValueError(_valid_units_message(text))

    def power(base: Unit, i: int) -> tuple[Unit, int]:
        if i < len(tokens):
            if tokens[i] == "²":
                return base ** Fraction(2), i + 1
            if tokens[i] == "³":
                return base ** Fraction(3), i + 1
            if tokens[i] == "^":
                if i + 1 >= len(tokens):
                    raise ValueError(_valid_units_message(text))
                exp_tok = tokens[i + 1]
                try:
                    p = Fraction(exp_tok)
                except ValueError:
                    raise ValueError(_valid_units_message(text)) from None
                return base**p, i + 2
        return base, i

    def expr(i: int) -> tuple[Unit, int]:
        value, i = atom(i)
        while i < len(tokens) and tokens[i] in ("/", "*", "·"):
            op = tokens[i]
            rhs, i = atom(i + 1)
            value = value / rhs if op == "/" else value * rhs
        return value, i

    unit, end = expr(0)
    if end != len(tokens):
        raise ValueError(_valid_units_message(text))
    return unit


#: :func:`_parse_text` of the strings seen so far (errors are not cached: raised each time)
_parse_cached = functools.lru_cache(maxsize=512)(_parse_text)


def checked_units(name: str, value: object) -> str | None:
    """``value`` if it is ``None`` or a unit :func:`parse_unit` accepts, else an error naming ``name``.

    The one unit check of every public function that takes ``units``: a unit that labels a
    result or a plot must be one gyrobias can convert.

    Raises
    ------
    TypeError
        If ``value`` is neither ``None`` nor a string.
    ValueError
        If the string is not a unit (the message lists the valid symbols).

    Examples
    --------
    >>> checked_units("units", "deg/s")
    'deg/s'
    >>> checked_units("units", "furlong")
    Traceback (most recent call last):
    ...
    ValueError: units: unknown unit 'furlong'; ...
    """
    if value is None:
        return None
    if not isinstance(value, str):
        raise TypeError(f"{name} must be a unit string or None, got {type(value).__name__}")
    _named(name, value)
    return value


def conversion_factor(from_unit: str, to_unit: str) -> float:
    """Factor f with ``value[to_unit] = f · value[from_unit]``.

    Raises
    ------
    ValueError
        Unknown units, or units of different dimensions.
    """
    a = _named("from_unit", from_unit)
    b = _named("to_unit", to_unit)
    if a.dims != b.dims:
        raise ValueError(f"cannot convert {from_unit!r} to {to_unit!r}: different dimensions")
    return a.factor / b.factor


def sensor_kind(data_unit: str) -> str:
    """``"gyro"`` for an angular-rate unit, ``"accel"`` for an acceleration unit."""
    dims = _named("data_unit", data_unit).dims
    if dims == (Fraction(1), Fraction(0), Fraction(-1)):
        return "gyro"
    if dims == (Fraction(0), Fraction(1), Fraction(-2)):
        return "accel"
    raise ValueError(
        f"data unit {data_unit!r} is neither an angular rate (e.g. 'deg/s', 'rad/s') nor an "
        f"acceleration (e.g. 'm/s^2', 'g')"
    )


_TIME_SUFFIX = {
    Fraction(1): "·s",
    Fraction(1, 2): "·√s",
    Fraction(0): "",
    Fraction(-1, 2): "/√s",
    Fraction(-1): "/s",
    Fraction(-3, 2): "/s^1.5",
    Fraction(-2): "/s²",
    Fraction(-5, 2): "/s^2.5",
    Fraction(-3): "/s³",
}


def base_unit(data_unit: str, symbol: str) -> str:
    """The unit of coefficient ``symbol`` for data in ``data_unit`` (e.g. "deg/s", "N" → "deg/√s")."""
    if not isinstance(symbol, str) or symbol not in TERM_TIME_POWER:
        raise ValueError(
            f"symbol must be one of {', '.join(map(repr, TERM_TIME_POWER))}; got {symbol!r}"
        )
    p = TERM_TIME_POWER[symbol]
    _named("data_unit", data_unit)
    m = re.fullmatch(r"(.+?)/s(?:\^(\d)|(²)|(³))?", data_unit.strip())
    if m:
        numerator = m.group(1)
        t = (
            1
            if m.group(2) is None and m.group(3) is None and m.group(4) is None
            else (int(m.group(2)) if m.group(2) else (2 if m.group(3) else 3))
        )
        exponent = p - t
    else:
        numerator = f"({data_unit})" if "/" in data_unit else data_unit
        exponent = p
    return numerator + _TIME_SUFFIX[exponent]

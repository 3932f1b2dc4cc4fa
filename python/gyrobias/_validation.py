"""Argument normalisation shared by the public wrappers.

The wrappers convert what users pass (lists, integer or float32 arrays, non-contiguous views)
into C-contiguous float64 arrays that the Rust core borrows without copying, and reject wrong
types and shapes with messages that name the argument. Numerical preconditions (finite values,
lengths, parameter ranges) are checked by the core itself.
"""

from __future__ import annotations

import re
import secrets
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobias import _core
from gyrobias._files import checked_path as checked_path  # the one path check (a leaf)


def asarray(name: str, value: Any) -> NDArray[Any]:
    """``np.asarray(value)``, with NumPy's error for ragged input ("setting an array element with
    a sequence") turned into a ``ValueError`` naming ``name``."""
    try:
        return np.asarray(value)
    except (ValueError, TypeError) as exc:
        raise ValueError(
            f"{name} must be a rectangular array of numbers, got a ragged or mixed sequence "
            f"({type(value).__name__})"
        ) from exc


def as_float_array(name: str, value: Any, ndims: tuple[int, ...] = (1,)) -> NDArray[np.float64]:
    """Return ``value`` as a C-contiguous float64 array with one of ``ndims`` dimensions.

    No copy is made when ``value`` already is such an array. The caller's array is never
    modified by gyrobias.

    Raises
    ------
    TypeError
        If ``value`` is not numeric (strings, objects, complex, booleans).
    ValueError
        If the number of dimensions is not in ``ndims`` or the array is empty.
    """
    arr = asarray(name, value)
    if arr.dtype.kind not in "iuf":
        raise TypeError(
            f"{name} must be a real numeric array (int or float), got dtype {arr.dtype}"
        )
    if arr.ndim not in ndims:
        want = " or ".join(f"{d}-D" for d in ndims)
        raise ValueError(
            f"{name} must be a {want} array, got a {arr.ndim}-D array of shape {arr.shape}"
        )
    if arr.size == 0:
        raise ValueError(f"{name} is empty")
    return np.ascontiguousarray(arr, dtype=np.float64)


_SIZE_LIMIT = 2**63


def real(name: str, value: Any) -> float:
    """``value`` as a Python float if it is a real number (not a bool), else ``TypeError``.

    Only the type is checked: finiteness and ranges are the core's preconditions, whose
    messages name ``name`` too.
    """
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}")
    return _float(name, value)


def _float(name: str, value: Any) -> float:
    """``float(value)``; an integer beyond float64's range is a ``ValueError`` naming ``name``
    (Python raises ``OverflowError``)."""
    try:
        return float(value)
    except OverflowError:
        raise ValueError(
            f"{name} must be finite in float64, got an integer of {int(value).bit_length()} bits"
        ) from None


def sample_rate(value: Any) -> float:
    """``value`` as the sample rate ``fs`` in Hz, safe to divide by.

    Only the type is checked here (``TypeError``); the range — finite, > 0 and with a finite
    period ``1/fs`` — is the core's check (``gyrocore::validate::sample_period``), whose
    ``ValueError`` names ``fs``. Wrappers that compute with ``fs`` themselves (``t0 = 1/fs``,
    ``r = N²·fs``, …) call this before doing so; wrappers that only pass ``fs`` to a core
    function that checks it need just :func:`real`.
    """
    fs = real("fs", value)
    _core.validate.sample_period(fs)
    return fs


def integer(name: str, value: Any) -> int:
    """``value`` as a Python int if it is an integer (not a bool), else ``TypeError`` naming it.

    Only the type is checked: a count passed on to the core is converted by the binding's one
    count extractor, which refuses a negative value or one the core cannot represent with a
    ``ValueError`` naming ``name``; ranges beyond that (``n >= 2``, …) are the core's checks. A
    count that Python itself computes with before the core sees it goes through :func:`count`.
    """
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}")
    return int(value)


def count(name: str, value: Any) -> int:
    """:func:`integer` from 0 to 2**63 − 1, else ``ValueError`` naming ``name``.

    For the few counts the Python layer computes with itself (a frequency grid, the product of
    a batch shape, sections cut from a log) and the core never sees as given: the range is then
    Python's check, there is no second one.
    """
    v = integer(name, value)
    if not 0 <= v < _SIZE_LIMIT:
        raise ValueError(f"{name} must be an integer from 0 to 2**63 - 1, got {v}")
    return v


def axis_names(value: Any, n_axes: int) -> Any:
    """``value`` (``None`` or one name per axis) if it names all ``n_axes`` axes, else ``ValueError``.

    The one check that ``axis_names`` fits the data (a shape check): every public function
    taking ``axis_names`` calls it, and wrappers (``fleet``) leave it to the function they call.
    Each name is :func:`text` (it reaches estimator files, plots and reports).
    """
    if value is None:
        return None
    # a string names one axis per character (axis_names="xyz"), as documented
    names = list(value) if isinstance(value, str) else sequence("axis_names", value)
    if len(names) != n_axes:
        raise ValueError(f"axis_names has {len(names)} names for {n_axes} axes")
    for i, item in enumerate(names):
        text(f"axis_names[{i}]", item)
    return value


#: Longest free text (a name, a title, a label) gyrobias accepts, in characters.
TEXT_LIMIT = 200


def _shown(value: str) -> str:
    """``repr`` of ``value`` cut to a readable length (for messages)."""
    return repr(value) if len(value) <= 60 else repr(value[:60]) + f"... ({len(value)} characters)"


def text(name: str, value: Any, *, limit: int = TEXT_LIMIT) -> str:
    """``value`` if it is one line of printable text of at most ``limit`` characters, else an
    error naming ``name``.

    The one check of every user string that can reach a written file or a page (axis, channel
    and column names, topics, titles, labels): ``TypeError`` for a non-string; ``ValueError``
    for a line break of any kind (``\\n``, ``\\r``, ``\\x85``, ``\\u2028``, …), another control
    or format character, a lone surrogate (it cannot be encoded) or a text longer than
    ``limit``. Printable is Python's :meth:`str.isprintable` (Unicode letters, marks, numbers,
    punctuation, symbols and the ASCII space): non-ASCII names such as ``"Gyro-Ä"`` or ``"ω_z"``
    are accepted.
    """
    if not isinstance(value, str):
        raise TypeError(f"{name} must be a string, got {type(value).__name__}")
    if len(value) > limit:
        raise ValueError(f"{name} must be at most {limit} characters, got {_shown(value)}")
    for i, ch in enumerate(value):
        if not ch.isprintable():
            raise ValueError(
                f"{name} must be one line of printable text, got {_shown(value)} "
                f"(character U+{ord(ch):04X} at position {i})"
            )
    return value


def names(name: str, value: Any) -> list[str]:
    """``value`` as a list of strings: one string (one name) or a :func:`sequence` of them,
    each :func:`string`; else ``TypeError``/``ValueError`` naming ``name`` (the one parser of
    name lists such as ``terms``; which names are valid is the caller's check)."""
    items = [value] if isinstance(value, str) else sequence(name, value)
    return [string(name, item) for item in items]


def optional_text(name: str, value: Any, *, limit: int = TEXT_LIMIT) -> str | None:
    """:func:`text`, or ``None`` for ``None``."""
    return None if value is None else text(name, value, limit=limit)


def sequence(name: str, value: Any) -> list[Any]:
    """``value`` as a list if it is a sequence of items (list, tuple, array, any iterable but a
    string or a mapping), else ``TypeError`` naming ``name``.

    The one check of sequence arguments: ``None``, a number, a string (a sequence of
    characters, never meant as one) or a mapping given where items are expected is a
    ``TypeError`` saying so, not Python's ``'int' object is not iterable`` from deeper down.
    """
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Iterable):
        raise TypeError(f"{name} must be a sequence (list or tuple), got {type(value).__name__}")
    return list(value)


def boolean(name: str, value: Any) -> bool:
    """``value`` if it is a bool (``True``/``False``, not ``1``/``0`` or ``"yes"``), else ``TypeError``."""
    if not isinstance(value, bool):
        raise TypeError(f"{name} must be a bool, got {type(value).__name__}")
    return value


def seed(name: str, value: Any) -> int:
    """A 64-bit seed for the core's generator: ``value`` itself, or a fresh one if ``None``.

    ``TypeError`` for anything but an integer or ``None``; ``None`` draws a seed from the
    operating system's entropy. The seed crosses into the core as an unsigned 64-bit integer:
    one outside ``[0, 2**64)`` is refused by the binding's count extractor (a ``ValueError``
    naming the argument).
    """
    if value is None:
        return secrets.randbits(64)  # entropy for a seed; the numbers are the core's generator
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer or None, got {type(value).__name__}")
    return int(value)


def positive_float(name: str, value: Any) -> float:
    """``value`` as a finite positive float, else ``ValueError``/``TypeError`` naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}")
    v = _float(name, value)
    if not np.isfinite(v) or v <= 0.0:
        raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    return v


def non_negative_float(name: str, value: Any) -> float:
    """``value`` as a finite float ≥ 0, else ``ValueError``/``TypeError`` naming ``name``.

    For the magnitudes the Python layer computes with itself (unit conversions of densities and
    variances): the range is the core's check (``gyrocore::validate::non_negative``), called
    before Python computes; only the type is checked here.
    """
    return _core.validate.non_negative(name, real(name, value))


def finite_result(name: str, value: Any, result: float) -> float:
    """``result`` (computed from the argument ``name`` = ``value``) if it is finite, else
    ``ValueError``: the argument is too large (or small) for the computation in float64."""
    if not np.isfinite(result):
        raise ValueError(f"{name} must give a finite result in float64, got {value!r}")
    return result


def callback(name: str, value: Any) -> Any:
    """``value`` if it is ``None`` or callable, else ``TypeError`` naming ``name`` (checked
    before any work starts, not when the callback is first called)."""
    if value is not None and not callable(value):
        raise TypeError(f"{name} must be callable or None, got {type(value).__name__}")
    return value


def pair(name: str, value: Any) -> tuple[float, float]:
    """``value`` as two real numbers ``(low, high)``; ``TypeError``/``ValueError`` naming ``name``
    for anything else (a scalar, a string, three numbers: never silently the first two)."""
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__"):
        raise TypeError(f"{name} must be a pair (low, high) of numbers, got {type(value).__name__}")
    if len(value) != 2:
        raise ValueError(f"{name} must be a pair (low, high) of numbers, got {len(value)} values")
    return real(name, value[0]), real(name, value[1])


_ROS_NAME = re.compile(r"[~/A-Za-z][A-Za-z0-9_/]*")


def ros_topic(name: str, value: Any) -> str:
    """``value`` if it is a ROS graph name (``/imu0``, ``~raw``, ``imu/data``), else an error.

    A topic is written verbatim into YAML files (Kalibr, OpenVINS, …): restricting it to the
    characters ROS allows in names (letters, digits, ``_`` and ``/``, starting with a letter,
    ``/`` or ``~``) is what keeps ``"a\nb: c"`` from adding a key ``b`` to the file.
    """
    if not isinstance(value, str):
        raise TypeError(f"{name} must be a ROS topic name (a string), got {type(value).__name__}")
    text(name, value)  # one printable line of bounded length, like every name
    if not _ROS_NAME.fullmatch(value):
        raise ValueError(
            f"{name} must be a ROS topic name (letters, digits, '_' and '/', starting with a "
            f"letter, '/' or '~'), got {value!r}"
        )
    return value


def choice(name: str, value: Any, options: tuple[str, ...]) -> str:
    """``value`` if it is one of ``options``, else ``ValueError`` listing them."""
    if not isinstance(value, str) or value not in options:
        shown = _shown(value) if isinstance(value, str) else repr(value)
        raise ValueError(f"{name} must be one of {', '.join(map(repr, options))}; got {shown}")
    return value


def string(name: str, value: Any) -> str:
    """``value`` if it is a ``str``, else ``TypeError`` naming ``name``.

    Only the type is checked: which names are valid (a ``form``, a ``padtype``, …) is decided
    by the core's parser, whose message names ``name`` and lists the options.
    """
    if not isinstance(value, str):
        raise TypeError(f"{name} must be a string, got {type(value).__name__}")
    return encodable(name, value)


def encodable(name: str, value: str) -> str:
    """``value`` if it can be encoded as UTF-8 (no lone surrogate such as ``"\\udcff"``,
    which a file name decoded with ``surrogateescape`` can hold), else ``ValueError`` naming
    ``name`` — not the ``UnicodeEncodeError`` of the core's string conversion or of a write."""
    try:
        value.encode("utf-8")
    except UnicodeEncodeError as exc:
        raise ValueError(
            f"{name} must be valid Unicode text, got {_shown(value)} (a lone surrogate "
            f"U+{ord(value[exc.start]):04X} at position {exc.start} cannot be encoded)"
        ) from None
    return value


def instance(name: str, value: Any, types: type | tuple[type, ...], what: str) -> Any:
    """``value`` if it is an instance of ``types``, else ``TypeError`` naming ``name``.

    The one check of arguments that must be a gyrobias object (an ``AllanResult``,
    ``NoiseCoefficients``, a fleet table, a matplotlib ``Axes``): ``what`` says what is
    expected (``"an AllanResult"``), so a string or ``None`` given instead is refused where it
    enters, not with ``'str' object has no attribute 'taus'`` from deeper down.
    """
    if not isinstance(value, types):
        raise TypeError(f"{name} must be {what}, got {type(value).__name__}")
    return value


def optional_instance(name: str, value: Any, types: type | tuple[type, ...], what: str) -> Any:
    """:func:`instance`, or ``None`` for ``None``."""
    return None if value is None else instance(name, value, types, what + " or None")


def instances(name: str, value: Any, cls: type, what: str) -> list[Any]:
    """``value`` as a non-empty list of ``cls`` objects: one object, or a :func:`sequence` of
    them; else ``TypeError``/``ValueError`` naming ``name`` (or ``name[i]`` for an item)."""
    items = [value] if isinstance(value, cls) else sequence(name, value)
    if not items:
        raise ValueError(f"{name} is empty: at least one {cls.__name__} is needed")
    for i, item in enumerate(items):
        instance(f"{name}[{i}]", item, cls, what)
    return items


def mapping(name: str, value: Any) -> Mapping[Any, Any]:
    """``value`` if it is a mapping (a ``dict``), else ``TypeError`` naming ``name``."""
    if not isinstance(value, Mapping):
        raise TypeError(f"{name} must be a mapping (dict), got {type(value).__name__}")
    return value


def optional_path(name: str, value: Any, what: str = "a file path") -> Path | None:
    """:func:`checked_path` (:mod:`gyrobias._files`), or ``None`` for ``None``."""
    return None if value is None else checked_path(name, value, what)

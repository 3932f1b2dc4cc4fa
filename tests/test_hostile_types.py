"""Hostile input, issue 34 section 5: every public parameter given an object of the wrong type.

The walk takes every public function and method (``public_api()`` of the hostile registry,
itself the modules' ``__all__``), reads its parameters from its *signature* (a new parameter
joins the walk by itself) and calls it once per value of :data:`WRONG` — a string, ``None``,
an int, a float, a bool, a bare ``object()``, an empty list and dict, bytes, a 200-bit
integer, a lone surrogate and a deeply nested unit string — with every other argument valid
(the valid calls are ``BASE`` of ``tests/test_hostile.py`` plus :data:`MORE_BASE` here).

The contract: the call succeeds (the value is legitimately acceptable) or raises
``TypeError``/``ValueError`` (``MemoryError`` for sizes) whose message names the parameter —
never ``AttributeError``, ``KeyError``, ``IndexError``, ``OverflowError``, ``RecursionError``,
``UnicodeEncodeError`` or a message from inside NumPy/Python (``'int' object is not
iterable``) without the parameter's name. Exceptions, each with its reason: the file system's
own ``OSError`` for a path that is a valid path string (``File name too long``) and
:data:`CROSS_PARAMETER` refusals of a valid value that name the other parameter it conflicts
with. The command line's options are walked by ``test_hostile.test_cli_option_values_are_one_line_exit_2``.
"""

from __future__ import annotations

import re
import sys
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import gyrobias
from gyrobias import allan, noise
from tests.hostile_registry import kinds_of, parameters, public_api
from tests.test_hostile import _TMP, BASE, FX, _fleet_table, _tmp
from tests.test_hostile_classes import _EXTRA_BASE


@pytest.fixture(autouse=True, scope="module")
def _module_tmp(tmp_path_factory: pytest.TempPathFactory) -> Any:
    _TMP.insert(0, tmp_path_factory.mktemp("hostile_types"))
    yield
    _TMP.pop(0)


#: The wrong-type objects, by label.
WRONG: dict[str, Any] = {
    "str": "x",
    "None": None,
    "int": 1,
    "float": 1.5,
    "bool": True,
    "object": object(),
    "list": [],
    "dict": {},
    "bytes": b"x",
    "huge": 2**200,
    "surrogate": "\ud800",
    "nested": "(" * 3000 + "deg" + ")" * 3000,
}

#: Kinds whose parameters are not walked: fields of result records (stored as constructed by
#: gyrobias, see ``hostile_registry.KINDS``), ``**kwargs`` forwarded to a function walked on
#: its own, and the command line's argparse internals (walked through ``cli.main``).
NOT_WALKED_KINDS = ("field", "forwarded", "cli")

#: Functions with walked parameters but no valid call here, with the reason.
NOT_WALKED: dict[str, str] = {
    "explore.app.ExploreApp.__init__": "the Panel application object (needs a Bokeh document); "
    "its sessions and errors come from load_sessions/explore, which are walked",
    "explore.app.ExploreApp.sampling_html": "a widget callback of the Panel application",
    "explore.app.ExploreApp.show_error": "a widget callback of the Panel application",
    "explore.server.serve": "opens a network port and blocks; its sessions come from "
    "load_sessions, which is walked",
}


def _dynamic() -> Any:
    return allan.dynamic_adev(FX.rate, 100.0, window=1000, step=1000)


def _wvar() -> Any:
    return noise.wvar(FX.rate[:2000], 100.0)


def _session() -> Any:
    from gyrobias.explore import load_sessions

    sessions, errors = load_sessions([FX.log.path], fs=100.0, units="deg/s")
    assert sessions, errors
    return sessions[0]


def _bag() -> Path:
    from tests.test_bags import imu_data, regular, write_bag

    path = _tmp() / "topics_bag"
    if not path.exists():
        write_bag(path, "mcap-dir", regular(50), imu_data(50))
    return path


#: Valid calls of the functions that ``BASE`` (tests/test_hostile.py) does not give one.
MORE_BASE: dict[str, Callable[[], tuple[Callable[..., Any], dict[str, Any]]]] = {
    "allan.DynamicAllanResult.plot": lambda: (_dynamic().plot, {}),
    "noise.NoiseCoefficients.plot": lambda: (FX.coefficients.plot, {}),
    "noise.NoiseCoefficients.to": lambda: (FX.gyro.to, {"system": "si"}),
    "noise.WaveletVariance.plot": lambda: (_wvar().plot, {}),
    "plotting.plot_noise_model": lambda: (
        gyrobias.plotting.plot_noise_model,
        {"coefficients": FX.coefficients},
    ),
    "plotting.plot_wvar": lambda: (gyrobias.plotting.plot_wvar, {"result": _wvar()}),
    "fleet.term_columns": lambda: (gyrobias.fleet.term_columns, {"table": _fleet_table()}),
    "io.GyroLog.select": lambda: (FX.log.select, {"start": "1s", "stop": "10s"}),
    # messages name the bound by `name` (the caller's argument): here the walked `value`
    "io.parse_time_bound": lambda: (gyrobias.io.parse_time_bound, {"value": "1s", "name": "value"}),
    "io.topics": lambda: (gyrobias.io.topics, {"path": _bag()}),
    "kalman.FixedGainKalman.estimates": lambda: (
        FX.kalman.estimates,
        {"state": FX.kalman.filter(FX.rate[:100]).state},
    ),
    "thermal.TemperatureModel.from_dict": lambda: (
        gyrobias.thermal.TemperatureModel.from_dict,
        {"data": FX.model.to_dict()},
    ),
    "explore.explore": lambda: (
        gyrobias.explore.explore,
        {"obj": FX.rate[:2000], "fs": 100.0, "units": "deg/s"},
    ),
    "explore.load_sessions": lambda: (
        gyrobias.explore.load_sessions,
        {"paths": [FX.log.path], "fs": 100.0, "units": "deg/s"},
    ),
    "explore.Session.__init__": lambda: (
        gyrobias.explore.Session,
        {"log": FX.log, "source": _session().source},
    ),
    "explore.Session.cli_command": lambda: (_session().cli_command, {}),
    "explore.Session.conservative": lambda: (_session().conservative, {}),
    "explore.Session.export": lambda: (_session().export, {"fmt": "kalibr"}),
    "explore.Session.python_code": lambda: (_session().python_code, {}),
    "explore.Settings.__init__": lambda: (gyrobias.explore.Settings, {}),
    "explore.Source.from_options": lambda: (
        gyrobias.explore.Source.from_options,
        {"path": FX.log.path, "options": {"fs": 100.0}},
    ),
}

#: Refusals of a valid value because of another argument, naming that argument (the walk's
#: other arguments are fixed): (function, parameter, value label) → reason.
CROSS_PARAMETER: dict[tuple[str, str, str], str] = {
    **{
        (key, name, "huge"): "fs = 2**200 Hz makes the fixed transition band of fpass/fstop "
        "need more taps than allowed: refused naming fstop"
        for key, name in (
            ("fir.kaiser_lowpass", "fs"),
            ("fir.kaiser_lowpass", "astop_db"),
            ("thermal.analyse_log", "astop_db"),
        )
    },
    **{
        (key, "rrw", "huge"): "rrw = 2**200 gives q_b beyond float64 next to q_omega: refused "
        "naming q_omega"
        for key in ("kalman.FixedGainKalman.__init__", "kalman.bandwidth_for_qomega")
    },
    ("kalman.qomega_for_bandwidth", "fs", "int"): "bandwidth 5 Hz above the Nyquist frequency "
    "of fs = 1 Hz: refused naming bandwidth",
    ("kalman.qomega_for_bandwidth", "fs", "float"): "bandwidth 5 Hz above the Nyquist "
    "frequency of fs = 1.5 Hz: refused naming bandwidth",
    ("kalman.qomega_for_bandwidth", "rrw", "int"): "rrw = 1 alone gives a wider bandwidth than "
    "5 Hz: refused naming bandwidth",
    ("kalman.qomega_for_bandwidth", "rrw", "float"): "rrw = 1.5 alone gives a wider bandwidth "
    "than 5 Hz: refused naming bandwidth",
    ("kalman.qomega_for_bandwidth", "rrw", "huge"): "rrw = 2**200 alone gives a wider "
    "bandwidth than 5 Hz: refused naming bandwidth",
    **{
        ("spectral.lssa", "known_periods", label): "a known period of 1 s (True) or 2**200 s at "
        "integer times is a constant column: a singular problem (GyroLinAlgError, a ValueError, "
        "naming the known periods)"
        for label in ("bool", "huge")
    },
    ("plotting.save_prediction_plot", "calibration", "int"): "calibration = 1 leaves 149 "
    "samples for forecasts of 50: refused naming forecasts",
    ("spectral.lssa", "known_periods", "int"): "a known period of 1 s at integer times is a "
    "constant column: a singular problem (GyroLinAlgError naming the known constituents)",
}

#: Members still failing the walk when this pass ended (xfail, strict: they flip to failures
#: once fixed, so the entry must then be removed), with the reason.
KNOWN_OPEN: dict[tuple[str, str], str] = {}

#: Messages from inside Python/NumPy that must never reach a user, named or not.
_INTERNAL = re.compile(
    r"object is not iterable|has no attribute|not subscriptable|unhashable type|has no len\(\)"
    r"|codec can't encode|cannot unpack|not enough values to unpack|too many values to unpack"
    r"|could not convert string to float|argument must be a string or a real number"
    r"|expected str, bytes or os.PathLike|setting an array element with a sequence"
    r"|int too large to convert|dictionary update sequence"
)


def _factory(key: str) -> Callable[[], tuple[Callable[..., Any], dict[str, Any]]] | None:
    return BASE.get(key) or _EXTRA_BASE.get(key) or MORE_BASE.get(key)


def _members() -> list[Any]:
    out = []
    for key, func in sorted(public_api().items()):
        if key.startswith("cli."):
            continue
        kinds = kinds_of(key)
        for name in parameters(func):  # from the signature: a new parameter is walked at once
            kind, _ = kinds.get(name, ("unclassified", False))
            if kind in NOT_WALKED_KINDS:
                continue
            marks = (
                [pytest.mark.xfail(reason=KNOWN_OPEN[(key, name)], strict=True)]
                if (key, name) in KNOWN_OPEN
                else []
            )
            out.append(pytest.param(key, name, id=f"{key}-{name}", marks=marks))
    return out


def _names(name: str, message: str) -> bool:
    return re.search(rf"(?<![A-Za-z0-9_]){re.escape(name)}(?![A-Za-z0-9_])", message) is not None


def _check(key: str, name: str, kind: str, label: str, value: Any) -> str | None:
    """``None`` if the call with ``name=value`` behaves, else what went wrong."""
    factory = _factory(key)
    assert factory is not None
    func, kwargs = factory()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            func(**{**kwargs, name: value})
    except (TypeError, ValueError, MemoryError) as exc:
        message = str(exc)
        if _INTERNAL.search(message):
            return f"{type(exc).__name__} from inside: {message[:200]}"
        if (key, name, label) in CROSS_PARAMETER:
            return None
        if isinstance(exc, UnicodeError):
            return f"{type(exc).__name__}: {message[:200]}"
        if not _names(name, message):
            return f"{type(exc).__name__} not naming {name!r}: {message[:200]}"
    except KeyError as exc:
        if key.endswith(".__getitem__") and isinstance(value, str):
            return None  # the mapping protocol: an unknown key (of the right type) is a KeyError
        return f"KeyError: {exc}"
    except OSError as exc:
        if kind in ("path_in", "path_out") and isinstance(value, str):
            return None  # the file system's own refusal of a valid path string
        return f"{type(exc).__name__}: {str(exc)[:200]}"
    except Exception as exc:  # noqa: BLE001 - every other type is the finding
        return f"{type(exc).__name__}: {str(exc)[:200]}"
    return None


@pytest.mark.parametrize(("key", "name"), _members())
def test_every_parameter_refuses_wrong_types_naming_itself(
    key: str, name: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    if key in NOT_WALKED:
        pytest.skip(NOT_WALKED[key])
    if key.startswith(("plotting.", "explore.")) or key.endswith(".plot"):
        pytest.importorskip("matplotlib")
    assert _factory(key) is not None, (
        f"{key}: give it a valid call in MORE_BASE (or BASE) so its {name!r} is walked"
    )
    monkeypatch.chdir(tmp_path)  # a string value may be a valid relative output path
    kind, none_ok = kinds_of(key).get(name, ("unclassified", False))
    problems = []
    for label, value in WRONG.items():
        if value is None and none_ok:
            continue
        problem = _check(key, name, kind, label, value)
        if problem:
            problems.append(f"{label}: {problem}")
    if "matplotlib.pyplot" in sys.modules:
        sys.modules["matplotlib.pyplot"].close("all")
    assert not problems, f"{key}({name}=...):\n  " + "\n  ".join(problems)


def test_the_walk_covers_every_public_parameter() -> None:
    """Every parameter of every public function is walked or excluded by kind with a reason."""
    walked = {(k, n) for k, n in (p.values for p in _members())}
    total = sum(
        1
        for key, func in public_api().items()
        if not key.startswith("cli.")
        for _ in parameters(func)
    )
    assert len(walked) > 300, (len(walked), total)
    assert set(NOT_WALKED) <= {k for k, _ in walked}, "stale NOT_WALKED entries"
    assert {k for k, _, _ in CROSS_PARAMETER} <= {k for k, _ in walked}


def test_the_walk_can_fail() -> None:
    """The checker flags the internal errors of the issue (it is not vacuous)."""

    def attribute(x: Any) -> Any:
        return x.shape

    def iterate(x: Any) -> Any:
        return list(x)

    for func in (attribute, iterate):
        BASE["_probe"] = lambda func=func: (func, {"x": np.zeros(2)})
        try:
            assert _check("_probe", "x", "object", "int", 5) is not None
        finally:
            del BASE["_probe"]

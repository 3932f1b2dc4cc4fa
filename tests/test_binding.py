"""The raw binding ``gyrobias._core``: submodule layout and memory layout of array arguments.

Every 2-D entry point of the binding reads its arrays in C (row-major) order whatever their
memory layout: a Fortran-ordered or strided array must give bit for bit the result of the same
values in a C-contiguous array (before the fix, ``allan.analyse`` of a Fortran-ordered
(samples × axes) array returned another axis' variances). Output arrays the core writes into
must be C-contiguous and are rejected otherwise.
"""

from __future__ import annotations

import importlib
import pickle
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from gyrobias import _core

SUBMODULES = (
    "allan",
    "fir",
    "fractional",
    "kalman",
    "noise",
    "predict",
    "spectral",
    "stats",
    "thermal",
    "validate",
)


@pytest.mark.parametrize("name", SUBMODULES)
def test_submodules_are_importable_by_dotted_name(name: str) -> None:
    module = importlib.import_module(f"gyrobias._core.{name}")
    assert module is getattr(_core, name)
    assert module.__name__ == f"gyrobias._core.{name}"
    for attr in dir(module):
        obj = getattr(module, attr)
        if callable(obj) and not attr.startswith("_"):
            assert obj.__module__ == module.__name__, attr


def _rng_matrix(rows: int, cols: int, seed: int = 1) -> np.ndarray:
    return np.random.default_rng(seed).normal(size=(rows, cols))


def _layouts(a: np.ndarray) -> list[np.ndarray]:
    """``a`` as a Fortran-ordered copy and as a strided (non-contiguous) view."""
    fortran = np.asfortranarray(a)
    assert not fortran.flags.c_contiguous
    wide = np.zeros((a.shape[0], 2 * a.shape[1]))
    wide[:, ::2] = a
    strided = wide[:, ::2]
    assert not strided.flags.c_contiguous and not strided.flags.f_contiguous
    return [fortran, strided]


def _same(x: Any, y: Any) -> None:
    """Bit-identical results (arrays, scalars, dicts, tuples and lists of them)."""
    if isinstance(x, dict):
        assert x.keys() == y.keys()
        for k in x:
            _same(x[k], y[k])
    elif isinstance(x, (list, tuple)):
        assert len(x) == len(y)
        for a, b in zip(x, y, strict=True):
            _same(a, b)
    else:
        np.testing.assert_array_equal(x, y)


KF = _core.kalman.FixedGainKalman(100.0, 0.01, 1e-4, 1e-6, None, "standard")
PREDICTOR = _core.predict.CompiledPredictor(40, 5, 0.4, 1.0, 0.1, "sample", 0.0, 1.0, 1)
TAPS = np.array([0.25, 0.5, 0.25])
T = np.arange(60.0)
Y = np.sin(0.3 * T)

# (name, function of the 2-D array, shape of the 2-D array)
ENTRY_POINTS: list[tuple[str, Callable[[np.ndarray], Any], tuple[int, int]]] = [
    (
        "allan.analyse",
        lambda a: _core.allan.analyse(a, 0.01, "rate", "overlapping", "octave", 10, None, 0.683),
        (400, 3),
    ),
    ("fir.filter_rows", lambda a: _core.fir.filter_rows(TAPS, a, True, "odd", 3), (3, 50)),
    (
        "fir.filter_stream_rows x",
        lambda a: _core.fir.filter_stream_rows(TAPS, a, np.zeros((3, 2))),
        (3, 50),
    ),
    (
        "fir.filter_stream_rows state",
        lambda a: _core.fir.filter_stream_rows(TAPS, np.ones((3, 7)), a),
        (3, 2),
    ),
    ("fractional.diff", lambda a: _core.fractional.diff(a, 0.4, "auto"), (3, 50)),
    ("fractional.integrate", lambda a: _core.fractional.integrate(a, 0.4, "auto"), (3, 50)),
    ("fractional.elw", lambda a: _core.fractional.elw(a, None, -0.5, 1.5, "none"), (3, 200)),
    (
        "predict.fractional_kalman",
        lambda a: _core.predict.fractional_kalman(
            a, 5, 0.4, 1.0, 0.1, "sample", 0.0, 1.0, "schur", 1
        ),
        (3, 40),
    ),
    ("predict.calibration_mean", lambda a: _core.predict.calibration_mean(a, 5), (3, 40)),
    ("predict.moving_average", lambda a: _core.predict.moving_average(a, 5), (3, 40)),
    ("predict.CompiledPredictor.predict", lambda a: PREDICTOR.predict(a, 1), (3, 40)),
    (
        "spectral.lssa cov",
        lambda a: _core.spectral.lssa(
            T, Y, np.array([0.05, 0.1]), None, a @ a.T + 60 * np.eye(60), False, np.array([]), None
        ),
        (60, 60),
    ),
    (
        "spectral.lssa columns",
        lambda a: _core.spectral.lssa(
            T, Y, np.array([0.05, 0.1]), None, None, True, np.array([]), a
        ),
        (60, 2),
    ),
    (
        "kalman.FixedGainKalman.filter_into z",
        lambda a: (
            KF.filter_into(
                a,
                np.empty(a.shape),
                np.empty(a.shape),
                KF.initial_state([0.0] * a.shape[1], [0.0] * a.shape[1]),
            ).rate
        ),
        (100, 3),
    ),
]


@pytest.mark.parametrize(("name", "call", "shape"), ENTRY_POINTS, ids=[e[0] for e in ENTRY_POINTS])
def test_any_memory_layout_reads_row_major(
    name: str, call: Callable[[np.ndarray], Any], shape: tuple[int, int]
) -> None:
    a = _rng_matrix(*shape)
    if name == "spectral.lssa cov":
        a = a / 10.0
    expected = call(np.ascontiguousarray(a))
    for layout in _layouts(a):
        _same(call(layout), expected)


def test_allan_fortran_order_gives_each_axis_its_own_variance() -> None:
    # The case: three axes with very different scales.
    a = _rng_matrix(1000, 3) * np.array([1.0, 100.0, 1e4])
    raw = _core.allan.analyse(
        np.asfortranarray(a), 1.0, "rate", "overlapping", "octave", 10, None, None
    )
    for axis, r in enumerate(raw):
        single = _core.allan.analyse(
            np.ascontiguousarray(a[:, axis : axis + 1]),
            1.0,
            "rate",
            "overlapping",
            "octave",
            10,
            None,
            None,
        )[0]
        np.testing.assert_array_equal(r["variance"], single["variance"])


@pytest.mark.parametrize("which", ["rate", "bias"])
def test_kalman_out_arrays_must_be_c_contiguous(which: str) -> None:
    z = _rng_matrix(50, 2)
    out = {"rate": np.empty(z.shape), "bias": np.empty(z.shape)}
    out[which] = np.asfortranarray(out[which])
    state = KF.initial_state([0.0, 0.0], [0.0, 0.0])
    with pytest.raises(TypeError, match=which):
        KF.filter_into(z, out["rate"], out["bias"], state)


def test_kalman_state_pickles_by_its_dotted_module() -> None:
    state = KF.initial_state([1.0], [2.0])
    assert type(state).__module__ == "gyrobias._core.kalman"
    assert pickle.loads(pickle.dumps(state)) == state

"""Hostile input: every outcome is a valid result or a ValueError/TypeError naming an argument.

Anything else — another exception type, a Rust panic (``PanicException``), NaN or zeros instead
of an answer, a modified input array, a crashed interpreter — fails a test here:

- hypothesis throws mixtures of valid and hostile arguments (NaN, inf, ±1e300, subnormals,
  empty / 0-D / 3-D arrays, strings, None, bools, huge and negative integers) at the public
  functions and at the command line, and classifies each outcome;
- requests for impossible amounts of memory run in a subprocess, so an abort ("memory
  allocation of … bytes failed") is a failing test instead of a dead test run;
- the silent-garbage cases of issue 10 are checked for the right answer or a named error;
- the caller's arrays are never modified, and 8 threads calling at once get bit-identical results.

Budget: each property test runs at most 30 examples (deterministic under the default profile).
"""

from __future__ import annotations

import contextlib
import io
import os
import subprocess
import sys
import textwrap
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import gyrobias
from gyrobias import allan, fir, fractional, kalman, noise, predict, spectral, thermal
from gyrobias.cli import main as cli_main

BUDGET = settings(max_examples=int(os.environ.get("ROBUSTNESS_EXAMPLES", "30")), deadline=None)

# --- strategies --------------------------------------------------------------------------------

nasty_floats = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 1e300, -1e300, 1e-300, 5e-324, 1e-9, 1e9]),
)
nasty_scalars = st.one_of(
    nasty_floats,
    # Sizes that are either small or impossible: a merely large size (1e9 samples) would really
    # be allocated in-process; the subprocess tests below cover the range in between.
    st.integers(-(10**20), 10**4),
    st.integers(10**15, 10**20),
    st.booleans(),
    st.none(),
    st.text(max_size=3),
)
nasty_arrays = st.one_of(
    arrays(np.float64, st.integers(0, 40), elements=nasty_floats),
    arrays(np.float64, st.tuples(st.integers(0, 30), st.integers(0, 4)), elements=nasty_floats),
    arrays(np.int64, st.integers(0, 20), elements=st.integers(-(2**62), 2**62)),
    st.just(np.array(3.0)),
    st.just(np.zeros((2, 2, 2))),
    st.just(np.array([1 + 2j, 3.0])),
    st.just(np.array(["a", "b", "c"])),
    st.lists(nasty_floats, max_size=10),
    st.none(),
    st.text(max_size=3),
)
clean = np.random.default_rng(7).normal(0.0, 1.0, 300)
good_arrays = st.sampled_from(
    [clean, clean[:40], np.cumsum(clean), np.stack([clean, 2 * clean], 1)]
)


def maybe(good: st.SearchStrategy[Any], bad: st.SearchStrategy[Any]) -> st.SearchStrategy[Any]:
    """Mostly valid arguments (to reach deep code paths), sometimes hostile ones."""
    return st.one_of(good, good, bad)


positive = st.floats(0.01, 1e4)
small_counts = st.integers(1, 200)

# --- classification ----------------------------------------------------------------------------


def _names(kwargs: dict[str, Any], extra: tuple[str, ...]) -> tuple[str, ...]:
    return (*kwargs, *extra)


def classify(call: Callable[[], Any], names: tuple[str, ...]) -> str:
    """``"ok"``, or the exception's class name after checking it names an argument.

    ValueError, TypeError and (for impossible sizes) MemoryError are the valid refusals; every
    other exception propagates and fails the test.
    """
    try:
        result = call()
    except (ValueError, TypeError, MemoryError) as exc:
        message = str(exc)
        assert message, f"{type(exc).__name__} without a message"
        assert any(name in message for name in names), (
            f"{type(exc).__name__} does not name an argument {names}: {message}"
        )
        return type(exc).__name__
    assert result is not None
    return "ok"


def unchanged(before: Any, after: Any) -> None:
    if isinstance(before, np.ndarray):
        assert isinstance(after, np.ndarray)
        np.testing.assert_array_equal(after, before)
        assert after.dtype == before.dtype and after.shape == before.shape


def snapshot(value: Any) -> Any:
    return value.copy() if isinstance(value, np.ndarray) else value


def checked(func: Callable[..., Any], names: tuple[str, ...], *args: Any, **kwargs: Any) -> str:
    """Classify ``func(*args, **kwargs)`` and check that no array argument was modified."""
    before = [snapshot(a) for a in args] + [snapshot(v) for v in kwargs.values()]
    outcome = classify(lambda: func(*args, **kwargs), _names(kwargs, names))
    after = [*args, *kwargs.values()]
    for b, a in zip(before, after):
        unchanged(b, a)
    return outcome


# --- public functions under hostile input ------------------------------------------------------

ALLAN = [allan.adev, allan.avar, allan.mdev, allan.hdev, allan.totdev]


@BUDGET
@given(
    func=st.sampled_from(ALLAN),
    data=maybe(good_arrays, nasty_arrays),
    fs=maybe(positive, nasty_scalars),
    taus=maybe(
        st.sampled_from(["octave", "decade", "log", "all"]), st.one_of(nasty_scalars, nasty_arrays)
    ),
    per_decade=maybe(st.integers(1, 50), nasty_scalars),
    data_type=maybe(st.sampled_from(["rate", "angle"]), nasty_scalars),
    confidence=maybe(st.sampled_from([None, 0.683, 0.95]), nasty_scalars),
    units=maybe(
        st.sampled_from([None, "deg/s", "rad/s"]), st.sampled_from(["furlong", "", "deg/s/s/s", 3])
    ),
)
def test_allan_family(func: Any, data: Any, fs: Any, **kwargs: Any) -> None:
    checked(func, ("data", "fs"), data, fs, **kwargs)


@BUDGET
@given(
    x=maybe(good_arrays, nasty_arrays),
    d=maybe(st.floats(-2.0, 2.0), nasty_scalars),
    method=maybe(st.sampled_from(["auto", "direct", "fft"]), nasty_scalars),
    func=st.sampled_from(["diff", "integrate"]),
)
def test_fractional_diff_integrate(x: Any, d: Any, method: Any, func: str) -> None:
    checked(getattr(fractional, func), ("x", "w", "d"), x, d, method=method)


@BUDGET
@given(
    d=maybe(st.floats(-1.0, 1.0), nasty_scalars),
    n=maybe(st.integers(0, 500), nasty_scalars),
    sigma=maybe(positive, nasty_scalars),
    size=maybe(st.sampled_from([None, 2, (2, 3)]), nasty_scalars),
)
def test_fractional_generators(d: Any, n: Any, sigma: Any, size: Any) -> None:
    checked(fractional.weights, ("d", "n"), d, n)
    if isinstance(n, int) and n > 10_000:
        return  # large sizes: see the subprocess tests
    checked(fractional.arfima, ("n", "d"), n, d, sigma=sigma, size=size, seed=1)


@BUDGET
@given(
    x=maybe(good_arrays, nasty_arrays),
    m=maybe(st.sampled_from([None, 10, 30]), nasty_scalars),
    bounds=maybe(st.just((-0.5, 2.0)), st.tuples(nasty_floats, nasty_floats)),
)
def test_fractional_elw(x: Any, m: Any, bounds: Any) -> None:
    checked(fractional.elw, ("x",), x, m=m, bounds=bounds)


@BUDGET
@given(
    n=maybe(small_counts, st.one_of(st.integers(-5, 0), st.booleans(), st.none(), nasty_floats)),
    fs=maybe(positive, nasty_scalars),
    arw=maybe(st.floats(0.0, 1.0), nasty_scalars),
    rrw=maybe(st.floats(0.0, 1.0), nasty_scalars),
    axes=maybe(st.integers(1, 3), st.one_of(st.integers(-3, 0), nasty_floats)),
)
def test_noise_simulate(n: Any, fs: Any, arw: Any, rrw: Any, axes: Any) -> None:
    checked(noise.simulate, ("n", "fs"), n, fs, arw=arw, rrw=rrw, axes=axes, seed=3)


@BUDGET
@given(
    y=maybe(good_arrays, nasty_arrays),
    horizon=maybe(st.integers(1, 50), st.one_of(st.integers(-5, 0), nasty_floats, st.none())),
    func=st.sampled_from(["calibration_mean", "moving_average", "kf"]),
    d=maybe(st.floats(0.05, 0.95), nasty_scalars),
)
def test_predict(y: Any, horizon: Any, func: str, d: Any) -> None:
    if func == "kf":

        def call(y: Any, horizon: Any) -> Any:
            return predict.FractionalKalmanPredictor(d=d).predict(y, horizon)

        checked(call, ("y", "calibration", "horizon", "d"), y, horizon)
    else:
        checked(getattr(predict, func), ("y", "calibration", "horizon"), y, horizon)


@BUDGET
@given(
    fs=maybe(st.floats(50.0, 500.0), nasty_scalars),
    arw=maybe(st.floats(1e-4, 1.0), nasty_scalars),
    rrw=maybe(st.floats(0.0, 1e-2), nasty_scalars),
    q_omega=maybe(st.floats(1e-8, 1.0), nasty_scalars),
    z=maybe(good_arrays, nasty_arrays),
)
def test_kalman(fs: Any, arw: Any, rrw: Any, q_omega: Any, z: Any) -> None:
    def design_and_filter(fs: Any, z: Any) -> Any:
        return kalman.FixedGainKalman(fs, arw=arw, rrw=rrw, q_omega=q_omega).filter(z)

    checked(design_and_filter, ("fs", "arw", "rrw", "q_omega", "z"), fs, z)


@BUDGET
@given(
    fs=maybe(st.floats(100.0, 1000.0), nasty_scalars),
    fpass=maybe(st.floats(1.0, 20.0), nasty_scalars),
    fstop=maybe(st.floats(25.0, 45.0), nasty_scalars),
    x=maybe(good_arrays, nasty_arrays),
)
def test_fir(fs: Any, fpass: Any, fstop: Any, x: Any) -> None:
    def design_and_apply(fs: Any, x: Any) -> Any:
        return fir.apply(fir.kaiser_lowpass(fs, fpass, fstop, astop_db=40.0).taps, x)

    checked(design_and_apply, ("fs", "fpass", "fstop", "x", "taps"), fs, x)


@BUDGET
@given(
    x=maybe(good_arrays, nasty_arrays),
    fs=maybe(positive, nasty_scalars),
    nperseg=maybe(st.sampled_from([None, 16, 64]), nasty_scalars),
    func=st.sampled_from(["psd", "noise_density", "fit_ar1"]),
)
def test_spectral_thermal(x: Any, fs: Any, nperseg: Any, func: str) -> None:
    if func == "fit_ar1":
        checked(thermal.fit_ar1, ("x", "fs"), x, fs)
    else:
        checked(getattr(spectral, func), ("x", "fs", "nperseg"), x, fs, nperseg=nperseg)


@BUDGET
@given(
    t=maybe(st.just(np.sort(np.random.default_rng(2).uniform(0, 100, 80))), nasty_arrays),
    y=maybe(st.just(np.sin(np.linspace(0, 30, 80))), nasty_arrays),
    trend=st.booleans(),
)
def test_lssa(t: Any, y: Any, trend: bool) -> None:
    checked(spectral.lssa, ("t", "y", "freqs"), t, y, trend=trend)


# --- the command line --------------------------------------------------------------------------

tokens = st.sampled_from(
    [
        "allan",
        "filter",
        "predict",
        "thermal",
        "demo",
        "--fs",
        "100",
        "-1",
        "nan",
        "1e308",
        "--units",
        "furlong",
        "deg/s",
        "--taus",
        "log",
        "--per-decade",
        "1000000000",
        "missing.csv",
        "--fit",
        "--bandwidth",
        "0",
        "--arw",
        "-3",
        "--columns",
        "9",
        "--",
    ]
)


@BUDGET
@given(argv=st.lists(tokens, max_size=8))
@example(argv=["thermal", "--fs", "100", "allan"])  # issue 19 explore: "gyrobias thermal: error:"
def test_cli_never_tracebacks(argv: list[str]) -> None:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = cli_main(argv)
    assert code in (0, 2), (argv, code, err.getvalue())
    assert "Traceback" not in err.getvalue()
    if code == 2 and "usage:" not in err.getvalue():
        lines = err.getvalue().strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("gyrobias: error: "), err.getvalue()


# --- impossible sizes: in a subprocess, so an abort fails the test -----------------------------

ALLOCATION_CASES = {
    "adev per_decade=10**9": (
        "r = gyrobias.allan.adev(np.ones(1000) + np.arange(1000) % 7, 100.0, taus='log', "
        "per_decade=10**9, confidence=None); print('ok', len(r.taus))",
        ("ok 500", "ValueError"),
    ),
    "arfima 10**12": ("gyrobias.fractional.arfima(10**12, 0.5)", ("MemoryError",)),
    "arfima 10**9 x 10**9": (
        "gyrobias.fractional.arfima(10**9, 0.5, size=10**9)",
        ("MemoryError",),
    ),
    "weights 10**14": ("gyrobias.fractional.weights(0.4, 10**14)", ("MemoryError",)),
    "simulate 10**13": ("gyrobias.noise.simulate(10**13, 100.0, arw=0.1)", ("MemoryError",)),
    "simulate axes": (
        "gyrobias.noise.simulate(10**7, 100.0, arw=0.1, axes=10**9)",
        ("MemoryError",),
    ),
    "calibration_mean horizon": (
        "gyrobias.predict.calibration_mean(np.ones(10), 10**14)",
        ("MemoryError",),
    ),
    "kf horizon": (
        "gyrobias.predict.FractionalKalmanPredictor().predict(np.ones(10), 10**14)",
        ("MemoryError",),
    ),
}


@pytest.mark.parametrize("name", list(ALLOCATION_CASES))
def test_impossible_sizes_raise_instead_of_aborting(name: str) -> None:
    code, expected = ALLOCATION_CASES[name]
    script = textwrap.dedent(
        f"""
        import numpy as np, gyrobias
        try:
            {code}
        except (MemoryError, ValueError) as exc:
            print(type(exc).__name__, exc)
        """
    )
    proc = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, f"interpreter died ({proc.returncode}): {proc.stderr[-500:]}"
    assert proc.stdout.startswith(expected), proc.stdout + proc.stderr


# --- counts that no machine integer holds ------------------------------------------------------

_Y = np.random.default_rng(3).normal(size=300)
_TAPS = np.array([0.25, 0.5, 0.25])
_KF = predict.FractionalKalmanPredictor(d=0.4)
_CURVE = allan.adev(noise.simulate(20_000, 100.0, arw=0.01, rrw=1e-4, seed=2), 100.0)

# (public function and argument, call with the count as that argument)
COUNT_CASES: dict[str, Callable[[Any], Any]] = {
    "noise.simulate n": lambda v: noise.simulate(v, 100.0, arw=0.1, seed=1),
    "noise.simulate axes": lambda v: noise.simulate(10, 100.0, arw=0.1, axes=v, seed=1),
    "noise.simulate seed": lambda v: noise.simulate(10, 100.0, arw=0.1, seed=v),
    "noise.fit min_points": lambda v: noise.fit(_CURVE, method="ieee", min_points=v),
    "noise.gmwm bootstrap": lambda v: noise.gmwm(_Y, 100.0, bootstrap=v, seed=1),
    "noise.gmwm seed": lambda v: noise.gmwm(_Y, 100.0, seed=v),
    "kalman.riccati_gain iterations": lambda v: kalman.riccati_gain(1.0, 0.1, 1.0, iterations=v),
    "predict.calibration_mean horizon": lambda v: predict.calibration_mean(_Y, v),
    "predict.moving_average horizon": lambda v: predict.moving_average(_Y, v),
    "predict.FractionalKalmanPredictor.predict horizon": lambda v: _KF.predict(_Y[:50], v),
    "predict.FractionalKalmanPredictor.predict n_threads": lambda v: _KF.predict(
        _Y[:50], 5, n_threads=v
    ),
    "predict.FractionalKalmanPredictor.compile calibration_length": lambda v: _KF.compile(v, 5),
    "predict.FractionalKalmanPredictor.compile horizon": lambda v: _KF.compile(50, v),
    "predict.FractionalKalmanPredictor.compile n_threads": lambda v: _KF.compile(
        50, 5, n_threads=v
    ),
    "predict.CompiledPredictor.predict n_threads": lambda v: _KF.compile(50, 5).predict(
        _Y[:50], n_threads=v
    ),
    "predict.evaluate n_threads": lambda v: predict.evaluate(
        _Y, calibration=50, horizon=10, n_threads=v
    ),
    "predict.evaluate calibration": lambda v: predict.evaluate(_Y, calibration=v, horizon=10),
    "predict.evaluate horizon": lambda v: predict.evaluate(_Y, calibration=50, horizon=v),
    "fractional.weights n": lambda v: fractional.weights(0.4, v),
    "fractional.arfima n": lambda v: fractional.arfima(v, 0.4, seed=1),
    "fractional.arfima size": lambda v: fractional.arfima(10, 0.4, size=v, seed=1),
    "fractional.arfima seed": lambda v: fractional.arfima(10, 0.4, seed=v),
    "fractional.elw m": lambda v: fractional.elw(_Y, m=v),
    "fractional.elw_objective m": lambda v: fractional.elw_objective(_Y, [0.1, 0.2], m=v),
    "fir.apply padlen": lambda v: fir.apply(_TAPS, _Y, padlen=v),
    "fir.KaiserLowpass.frequency_response n": lambda v: fir.kaiser_lowpass(
        100.0, 10.0, 20.0
    ).frequency_response(n=v),
    "spectral.psd nperseg": lambda v: spectral.psd(_Y, 100.0, nperseg=v),
    "spectral.psd noverlap": lambda v: spectral.psd(_Y, 100.0, nperseg=64, noverlap=v),
    "allan.adev per_decade": lambda v: allan.adev(_Y, 100.0, taus="log", per_decade=v),
}


@pytest.mark.parametrize("value", [2**64, 2**70, -1])
@pytest.mark.parametrize("case", list(COUNT_CASES))
def test_counts_beyond_machine_integers_are_named_value_errors(case: str, value: int) -> None:
    """A count of 2**64 or more, or a negative one, is a ValueError naming the argument (never
    pyo3's OverflowError from converting it, nor an error about another argument)."""
    name = case.rsplit(" ", 1)[1]
    with pytest.raises(ValueError, match=name):
        COUNT_CASES[case](value)


#: Counts for which ``None`` is a valid value meaning "the default".
_NONE_MEANS_DEFAULT = ("seed", "m", "nperseg", "noverlap", "padlen", "size", "n_threads")


@pytest.mark.parametrize(
    ("case", "value"),
    [
        (case, value)
        for case in COUNT_CASES
        for value in (2.5, "3", None)
        if not (value is None and case.rsplit(" ", 1)[1] in _NONE_MEANS_DEFAULT)
    ],
)
def test_non_integer_counts_are_type_errors_naming_the_argument(case: str, value: Any) -> None:
    """A float, a numeric string or None where a count is expected is a TypeError naming the
    argument (the binding's count extractor says so too; pyo3's own message did not name it).
    ``None`` is left out where it means the default."""
    name = case.rsplit(" ", 1)[1]
    with pytest.raises(TypeError, match=rf"\b{name}\b.*integer|integer.*\b{name}\b"):
        COUNT_CASES[case](value)


def test_binding_counts_are_named_value_errors() -> None:
    """The same at the binding itself: every integer argument of ``_core`` is converted by one
    extractor that names it."""
    from gyrobias import _core

    for value in (2**64, -1):
        for call, name in [
            (lambda v: _core.noise.simulate(v, 100.0, 0, 0.1, 0, 0, 0, None, 0, 1, 1), "n"),
            (lambda v: _core.noise.simulate(10, 100.0, 0, 0.1, 0, 0, 0, None, 0, 1, v), "seed"),
            (lambda v: _core.fractional.weights(0.4, v), "n"),
            (lambda v: _core.fractional.elw(np.ones((1, 50)), v, -0.5, 1.5, "none"), "m"),
            (lambda v: _core.kalman.riccati_gain(1.0, 0.1, 1.0, v), "iterations"),
            (
                lambda v: _core.kalman.KalmanState((0.0,), (0.0,), (0.0,), (0.0,), (1.0, 0.0), v),
                "samples",
            ),
            (lambda v: _core.predict.calibration_mean(np.ones((1, 5)), v), "horizon"),
            (lambda v: _core.spectral.critical_value(v, 1, 0.05), "n"),
            (lambda v: _core.fir.filter_rows(_TAPS, np.ones((1, 9)), True, "odd", v), "padlen"),
        ]:
            with pytest.raises(ValueError, match=f"{name} must be an integer"):
                call(value)
    with pytest.raises(TypeError, match="^n must be an integer, got float"):
        _core.fractional.weights(0.4, 2.5)  # type: ignore[arg-type]


# --- silent garbage ----------------------------------------------------------------------------


def test_fractional_diff_of_huge_order_is_a_named_error() -> None:
    x = np.random.default_rng(1).normal(size=1000)
    with pytest.raises(ValueError, match="d"):
        fractional.diff(x, 1e6)
    with pytest.raises(ValueError, match="d"):
        fractional.weights(1e6, 1000)


def test_unknown_units_are_rejected_everywhere() -> None:
    x = np.random.default_rng(1).normal(size=400)
    with pytest.raises(ValueError, match="units"):
        allan.adev(x, 100.0, units="furlong")


# --- inputs are never modified; threads give bit-identical results -----------------------------

rate = np.random.default_rng(5).normal(0.0, 0.1, (20_000, 2))
CONCURRENT: dict[str, Callable[[], Any]] = {
    "adev": lambda: [r.avar for r in allan.adev(rate, 100.0, taus="log", per_decade=5)],
    "adev ci": lambda: [r.ci_high for r in allan.adev(rate, 100.0)],
    "mdev": lambda: [r.avar for r in allan.mdev(rate[:5000], 100.0)],
    "diff": lambda: fractional.diff(rate, 0.4, axis=0),
    "arfima": lambda: fractional.arfima(4000, 0.4, size=3, seed=9),
    "simulate": lambda: noise.simulate(10_000, 100.0, arw=0.01, rrw=1e-4, axes=2, seed=4),
    "predict": lambda: predict.FractionalKalmanPredictor(d=0.4).predict(rate[:400, 0], 50).bias,
    "kalman": lambda: (
        kalman.FixedGainKalman(100.0, arw=0.01, rrw=1e-4, q_omega=1e-6).filter(rate).rate
    ),
    "fir": lambda: fir.apply(fir.kaiser_lowpass(100.0, 10.0, 20.0).taps, rate, axis=0),
    "psd": lambda: spectral.psd(rate[:, 0], 100.0).psd,
}


@pytest.mark.parametrize("name", list(CONCURRENT))
def test_eight_threads_give_bit_identical_results(name: str) -> None:
    call = CONCURRENT[name]
    before = rate.copy()
    reference = call()
    with ThreadPoolExecutor(max_workers=8) as pool:
        results = list(pool.map(lambda _: call(), range(8)))
    for r in results:
        for a, b in zip(
            np.atleast_1d(np.asarray(reference, dtype=object)),
            np.atleast_1d(np.asarray(r, dtype=object)),
        ):
            np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    np.testing.assert_array_equal(rate, before)


def test_public_api_is_covered() -> None:
    """A new public function should get a hostile-input test above."""
    covered = {
        "adev",
        "avar",
        "mdev",
        "hdev",
        "totdev",
        "diff",
        "integrate",
        "weights",
        "arfima",
        "elw",
        "simulate",
        "calibration_mean",
        "moving_average",
        "psd",
        "noise_density",
        "fit_ar1",
        "lssa",
        "apply",
        "kaiser_lowpass",
    }
    assert covered <= {
        n for m in (allan, fractional, noise, predict, spectral, thermal, fir) for n in m.__all__
    }
    assert gyrobias.__version__


# --- fleet and report entry points -----------------------------------------------------------


FLEET_RATE = np.random.default_rng(11).normal(0.0, 0.01, (3, 2000))


@pytest.mark.parametrize(
    ("sources", "fs", "exc", "names"),
    [
        (np.zeros((0, 2000)), 100.0, ValueError, ("sources",)),  # no unit
        (np.zeros((3, 0)), 100.0, ValueError, ("sources",)),  # units of no sample
        (np.zeros(2000), 100.0, ValueError, ("sources",)),  # 1-D: one log, not a fleet
        (np.zeros((2, 2, 2, 2)), 100.0, ValueError, ("sources",)),
        (FLEET_RATE.astype(complex), 100.0, TypeError, ("sources",)),
        (np.array([["a", "b"], ["c", "d"]]), 100.0, TypeError, ("sources",)),
        (FLEET_RATE, 0.0, ValueError, ("fs",)),
        (FLEET_RATE, -100.0, ValueError, ("fs",)),
        (FLEET_RATE, float("nan"), ValueError, ("fs",)),
        (FLEET_RATE, "100", TypeError, ("fs",)),
        (FLEET_RATE, None, ValueError, ("fs",)),  # arrays carry no sample rate
    ],
)
def test_fleet_array_sources_refuse_bad_input(
    sources: Any, fs: Any, exc: type[Exception], names: tuple[str, ...]
) -> None:
    pytest.importorskip("pandas")
    from gyrobias import fleet

    before = snapshot(sources)
    with pytest.raises(exc) as info:
        fleet.analyse(sources, fs=fs, num_workers=1)
    assert any(n in str(info.value) for n in names), str(info.value)
    unchanged(before, sources)


def test_fleet_nan_unit_is_a_named_error_row_not_garbage() -> None:
    # The fleet isolates failures per unit (module docs): a unit with NaN is an error row that
    # names the non-finite sample, and the other units are analysed as usual — never NaN
    # coefficients presented as a result.
    pytest.importorskip("pandas")
    from gyrobias import fleet

    rate = FLEET_RATE.copy()
    rate[1, 17] = np.nan
    table = fleet.analyse(rate, fs=100.0, num_workers=1)
    errors = table["error"].tolist()
    assert [e is None or e != e for e in errors] == [True, False, True]  # None/NaN: no error
    assert "non-finite" in errors[1] and "17" in errors[1], errors[1]
    np.testing.assert_array_equal(np.isnan(rate), np.isnan(FLEET_RATE) | (rate != rate))
    all_nan = np.full((2, 2000), np.nan)
    assert table_errors(fleet.analyse(all_nan, fs=100.0, num_workers=1)) == 2


def table_errors(table: Any) -> int:
    return int(table["error"].notna().sum())


def _gyro_log(tmp_path: Any, **changes: Any) -> Any:
    """A log loaded from a .npy file, with some fields replaced (as a caller might build one)."""
    import dataclasses

    from gyrobias import io as gio

    np.save(tmp_path / "log.npy", np.random.default_rng(3).normal(0.0, 0.01, (4000, 1)))
    return dataclasses.replace(gio.load(tmp_path / "log.npy", fs=100.0), **changes)


@pytest.mark.parametrize(
    ("log", "exc"),
    [
        ("log.npy", TypeError),  # a path, not a loaded log
        (np.zeros((100, 1)), TypeError),  # an array, not a loaded log
        ("empty", ValueError),
        ("1-D", ValueError),
        ("columns", ValueError),
        ("all NaN", ValueError),
        ("no fs", ValueError),
    ],
)
def test_report_refuses_bad_logs(log: Any, exc: type[Exception], tmp_path: Any) -> None:
    from gyrobias import report

    rate = np.random.default_rng(3).normal(0.0, 0.01, (4000, 1))
    cases = {
        "empty": lambda: _gyro_log(tmp_path, data=np.zeros((0, 1))),
        "1-D": lambda: _gyro_log(tmp_path, data=rate[:, 0]),
        "columns": lambda: _gyro_log(tmp_path, columns=("gx", "gy")),
        "all NaN": lambda: _gyro_log(tmp_path, data=np.full((4000, 1), np.nan)),
        "no fs": lambda: _gyro_log(tmp_path, fs=None),
    }
    value = cases[log]() if isinstance(log, str) and log in cases else log
    for entry in (
        lambda: report.build_report(value),
        lambda: report.write_report(tmp_path / "out" / "r.html", value),
    ):
        with pytest.raises(exc, match="log"):
            entry()
    assert not (tmp_path / "out").exists()

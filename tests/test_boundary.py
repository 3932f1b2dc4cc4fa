"""One owner per check at the Python/Rust boundary (issue 10).

Each numerical precondition has exactly one owner: the core (``gyrocore``) for ranges and the
names of options, the binding's one count extractor (``count.rs``) for what an integer argument
can represent, the Python layer (``_validation``) for types and shapes. These tests pin the
owner by its message — the core's messages start ``invalid <name>:`` — and pin that a value
the Python layer computes with (``t0 = 1/fs``) is checked by the core *before* Python divides
by it, so a bad ``fs`` is never a ``ZeroDivisionError`` or a silently wrong result.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import gyrobias
from gyrobias import _core, allan, fractional, noise, predict, spectral, thermal
from gyrobias.cli import main

SRC = Path(gyrobias.__file__).parent

_RATE = np.random.default_rng(11).normal(0.0, 0.1, 4000)
_CORE_FS = r"^fs must be finite and > 0"

# --- fs: the core owns fs > 0, also where Python divides by it ---------------------------------

# (public function, call with fs)
FS_CASES: dict[str, Callable[[Any], Any]] = {
    "allan.adev": lambda fs: allan.adev(_RATE, fs),
    "allan.adev_batch": lambda fs: allan.adev_batch(_RATE.reshape(2, -1), fs),
    "allan.mdev": lambda fs: allan.mdev(_RATE, fs),
    "allan.tdev": lambda fs: allan.tdev(_RATE, fs),
    "allan.theo1": lambda fs: allan.theo1(_RATE[:200], fs),
    "allan.dynamic_adev": lambda fs: allan.dynamic_adev(_RATE, fs, window=1000, step=500),
    "noise.gmwm": lambda fs: noise.gmwm(_RATE, fs),
    "noise.simulate": lambda fs: noise.simulate(10, fs, arw=0.1, seed=1),
    "thermal.fit_ar1": lambda fs: thermal.fit_ar1(_RATE, fs=fs),
    "thermal.analyse_log": lambda fs: thermal.analyse_log(_RATE, fs, 25.0),
    "predict.FractionalKalmanPredictor.from_noise": lambda fs: (
        predict.FractionalKalmanPredictor.from_noise(arw=0.01, bias_instability=0.001, fs=fs)
    ),
    "spectral.psd": lambda fs: spectral.psd(_RATE, fs),
}


@pytest.mark.parametrize("fs", [0.0, -0.0, -100.0, np.nan, np.inf, 1e-320])
@pytest.mark.parametrize("case", list(FS_CASES))
def test_bad_fs_is_the_cores_value_error(case: str, fs: float) -> None:
    """``fs`` ≤ 0, NaN, inf and a subnormal ``fs`` (whose period ``1/fs`` overflows) give the
    core's ValueError naming ``fs`` — never a ZeroDivisionError, an error about ``dt``/``r``
    (what Python derived from ``fs``) or a result."""
    with pytest.raises(ValueError, match=_CORE_FS):
        FS_CASES[case](fs)


@pytest.mark.parametrize(
    ("kwargs", "pattern"),
    [
        ({"arw": -0.01}, r"^arw must be finite and >= 0"),
        ({"arw": np.inf}, r"^arw must be finite and >= 0"),
        ({"arw": 1e200}, r"^invalid arw: r = N²·fs overflows"),
        ({"bias_instability": 0.0}, r"^bias_instability must be finite and > 0"),
        ({"bias_instability": 1e-200}, r"^invalid bias_instability: its square"),
    ],
)
def test_from_noise_mapping_is_the_cores(kwargs: dict[str, float], pattern: str) -> None:
    """q = B², r = N²·fs and their preconditions are the core's (predict::noise_parameters);
    B = 1e-200 used to give q = 0 and the core's error about a q the user never gave."""
    args = {"arw": 0.01, "bias_instability": 0.001, "fs": 100.0, **kwargs}
    with pytest.raises(ValueError, match=pattern):
        predict.FractionalKalmanPredictor.from_noise(**args)
    p = predict.FractionalKalmanPredictor.from_noise(arw=0.01, bias_instability=0.001, fs=100.0)
    assert (p.q, p.r) == (0.001**2, 0.01**2 * 100.0)


def test_io_load_fs_is_checked_by_the_core(tmp_path: Path) -> None:
    path = tmp_path / "r.npy"
    np.save(path, _RATE)
    for fs in (0.0, -1.0, np.nan, 1e-320):
        with pytest.raises(ValueError, match=_CORE_FS):
            gyrobias.io.load(path, fs=fs)
    with pytest.raises(TypeError, match="fs must be a real number"):
        gyrobias.io.load(path, fs="100")  # type: ignore[arg-type]


def test_sample_period_binding() -> None:
    assert _core.validate.sample_period(100.0) == 0.01
    with pytest.raises(ValueError, match=_CORE_FS):
        _core.validate.sample_period(0.0)
    with pytest.raises(ValueError, match=r"fs must be .*finite period"):
        _core.validate.sample_period(1e-320)


def test_demo_fs_error_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["demo", "--fs", "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and re.match(r"gyrobias: error: --fs must be finite", err[0])


# --- option names: the core's parsers, their messages unchanged ------------------------------


@pytest.mark.parametrize(
    "call",
    [
        lambda: allan.adev(_RATE, 100.0, taus="weekly"),
        lambda: allan.mdev(_RATE, 100.0, taus="weekly"),
        lambda: allan.tdev(_RATE, 100.0, taus="weekly"),
        lambda: allan.theo1(_RATE[:200], 100.0, taus="weekly"),
        lambda: allan.dynamic_adev(_RATE, 100.0, window=1000, step=500, taus="weekly"),
    ],
)
def test_unknown_tau_spec_is_the_cores_error(call: Callable[[], Any]) -> None:
    with pytest.raises(ValueError, match=r"^taus must be 'octave', 'decade', 'log', 'all'"):
        call()


def test_unknown_conservative_term_is_the_cores_error() -> None:
    rate = noise.simulate(20_000, 100.0, arw=0.01, rrw=1e-4, seed=3)
    c = noise.fit(allan.adev(rate, 100.0, units="deg/s"), terms=("N", "K"))
    with pytest.raises(ValueError, match=r'^invalid terms: unknown term "X"'):
        c.conservative(terms=("X",))
    with pytest.raises(ValueError, match=r'^invalid terms: unknown term "X"'):
        c.conservative(terms="X")


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: fractional.diff(_RATE, 0.3, method="slow"), "method"),
        (lambda: fractional.arfima(100, 0.3, kind="odd", seed=1), "kind"),
        (lambda: fractional.elw(_RATE, level="high"), "level"),
        (lambda: spectral.psd(_RATE, 100.0, window="hamming"), "window"),
        (lambda: fractional.arfima(100, 0.3, sigma=0.0, seed=1), "sigma"),
        (lambda: spectral.psd(_RATE, 100.0, nperseg=1), "nperseg"),
    ],
)
def test_option_errors_are_the_cores(call: Callable[[], Any], name: str) -> None:
    with pytest.raises(ValueError, match=rf"^(invalid {name}: |{name} must )"):
        call()


def test_negative_noverlap_is_the_binding_count_error() -> None:
    with pytest.raises(ValueError, match=r"^noverlap must be an integer from 0"):
        spectral.psd(_RATE, 100.0, nperseg=64, noverlap=-1)


# --- workers and axis names: one owner each ----------------------------------------------------


def test_cli_workers_is_checked_by_the_argument_layer(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Every option value is checked by argparse (issue 27), before any log is read."""
    np.save(tmp_path / "u.npy", _RATE)
    assert main(["fleet", str(tmp_path / "u.npy"), "--fs", "100", "--workers", "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["gyrobias: error: --workers must be an integer >= 1, got '0'"]


def test_axis_names_length_is_allans_check_in_the_fleet(tmp_path: Path) -> None:
    pytest.importorskip("dask")
    from gyrobias import fleet

    data = np.random.default_rng(2).normal(size=(3, 4000, 2))
    with pytest.raises(ValueError, match=r"^axis_names has 3 names for 2 axes$"):
        fleet.analyse(data, fs=100.0, axis_names=["x", "y", "z"], num_workers=1)
    np.save(tmp_path / "u.npy", data[0])
    table = fleet.analyse(
        str(tmp_path / "u.npy"), fs=100.0, axis_names=["x", "y", "z"], num_workers=1
    )
    assert table["error"].tolist() == ["ValueError: axis_names has 3 names for 2 axes"]


# --- counts: one extractor, TypeError naming the argument ------------------------------------


_BINDING_COUNT_CALLS: list[tuple[Callable[[Any], Any], str]] = [
    (lambda v: _core.fractional.weights(0.4, v), "n"),
    (lambda v: _core.kalman.riccati_gain(1.0, 0.1, 1.0, v), "iterations"),
    (lambda v: _core.predict.calibration_mean(np.ones((1, 5)), v), "horizon"),
    (lambda v: _core.spectral.critical_value(v, 1, 0.05), "n"),
    (lambda v: _core.noise.simulate(10, 100.0, 0, 0.1, 0, 0, 0, None, 0, 1, v), "seed"),
    (lambda v: _core.fractional.elw(np.ones((1, 50)), v, -0.5, 1.5, "none"), "m"),
    (lambda v: _core.fir.filter_rows(np.ones(3), np.ones((1, 9)), True, "odd", v), "padlen"),
]


@pytest.mark.parametrize(
    ("call", "name", "value"),
    [
        (call, name, value)
        for call, name in _BINDING_COUNT_CALLS
        for value in (2.5, 3.0, "3", None, True, np.float64(3.0))
        # m=None is the ELW's default bandwidth, not an error.
        if not (name == "m" and value is None)
    ],
)
def test_binding_non_integer_counts_are_type_errors_naming_them(
    call: Callable[[Any], Any], name: str, value: Any
) -> None:
    with pytest.raises(TypeError, match=rf"^{name} must be an integer, got \w+"):
        call(value)


@pytest.mark.parametrize("value", [5, np.int64(5), np.uint8(5), np.int32(5), np.uint64(5)])
def test_binding_counts_accept_python_and_numpy_integers(value: Any) -> None:
    np.testing.assert_array_equal(
        _core.fractional.weights(0.4, value), _core.fractional.weights(0.4, 5)
    )


# --- m / n_terms arrays: converted by the binding, naming them ---------------------------------

_CURVE = allan.adev(noise.simulate(20_000, 100.0, arw=0.01, rrw=1e-4, seed=2), 100.0)


def _raw_fit(m: Any, n_terms: Any) -> Any:
    c = _CURVE
    return _core.noise.fit(c.taus, c.avar, m, n_terms, True, c.edf, ["N", "K"], None, None, False)


@pytest.mark.parametrize("which", ["m", "n_terms"])
def test_integer_arrays_go_through_the_count_conversion(which: str) -> None:
    c = _CURVE
    good = {"m": c.m, "n_terms": c.n_terms}
    ref = _raw_fit(c.m, c.n_terms)["squared"]
    for same in (
        np.asarray(good[which], dtype=np.int32),
        np.asarray(good[which], dtype=np.uint64),
        np.asfortranarray(good[which])[::1],
        [int(v) for v in good[which]],
    ):
        args = {**good, which: same}
        assert _raw_fit(args["m"], args["n_terms"])["squared"] == ref
    negative = np.array(good[which], dtype=np.int64)
    negative[2] = -1
    bad_cases: list[tuple[Any, type[Exception], str]] = [
        (negative, ValueError, rf"^{which} must hold integers .* got -1 at index 2"),
        (
            [*good[which][:-1].tolist(), 2**70],
            ValueError,
            rf"^{which} must hold integers .* at index {len(good[which]) - 1}",
        ),
        (
            np.asarray(good[which], dtype=np.float64),
            TypeError,
            rf"^{which} must be an integer array",
        ),
        (np.ones(len(good[which]), dtype=bool), TypeError, rf"^{which} must be an integer array"),
        (np.asarray(good[which])[None, :], ValueError, rf"^{which} must be a 1-D integer array"),
    ]
    for bad, exc, pattern in bad_cases:
        args = {**good, which: bad}
        with pytest.raises(exc, match=pattern):
            _raw_fit(args["m"], args["n_terms"])


def test_noise_fit_of_a_curve_with_negative_factors_names_m() -> None:
    """A result with m = −1 (negative τ, or hand-set ``factors``) used to be cast to uint64
    (2**64 − 1) silently."""
    from dataclasses import replace

    m = _CURVE.m.copy()
    m[0] = -1
    for method in ("joint", "ieee"):
        with pytest.raises(ValueError, match=r"^m must hold integers .* got -1 at index 0"):
            noise.fit(replace(_CURVE, factors=m), method=method)
    with pytest.raises(ValueError, match=r"^m must hold integers .* got -1 at index 0"):
        noise.fit(replace(_CURVE, taus=np.where(np.arange(m.size) == 0, -0.01, _CURVE.taus)))
    for method in ("joint", "ieee"):
        with pytest.raises(TypeError, match=r"^n_terms must be an integer array"):
            noise.fit(replace(_CURVE, n_terms=_CURVE.n_terms + 0.5), method=method)


# --- no check written twice --------------------------------------------------------------------


def _calls(name: str) -> list[tuple[str, int, str]]:
    """``(file, line, first argument)`` of every call of ``name(...)`` in the package."""
    found = []
    for path in sorted(SRC.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Name)
                and node.func.id == name
                and node.args
                and isinstance(node.args[0], ast.Constant)
            ):
                found.append((path.name, node.lineno, str(node.args[0].value)))
    return found


def test_python_checks_nothing_the_core_checks() -> None:
    """Ranges of ``fs`` and option names parsed by the core are not checked again in Python."""
    assert [c for c in _calls("positive_float") if c[2] in ("fs", "--fs", "sigma")] == []
    core_parsed = {"taus", "terms", "method", "kind", "level", "window"}
    # noise.fit's method ('joint'/'ieee') picks a Python code path; it is not a core option
    # (report.build_report refuses it before any channel runs); Evaluation.ratio's method is a
    # key of its own table.
    # cleaning.remove_outliers' method ('mad', the only one) is a Python-side name; the core
    # takes none.
    python_paths = {
        ("fitting.py", "method"),
        ("report.py", "method"),
        ("predict.py", "method"),
        ("__init__.py", "method"),
    }
    offending = [
        c for c in _calls("choice") if c[2] in core_parsed and c[0:3:2] not in python_paths
    ]
    assert offending == []
    text = "\n".join(p.read_text(encoding="utf-8") for p in SRC.rglob("*.py"))
    assert text.count("names for {n_axes} axes") == 1  # _validation.axis_names
    assert "--workers must be" not in text
    assert "dtype=np.uint64" not in text.replace("generate_state(1, dtype=np.uint64)", "")


# --- atomic output of `gyrobias filter` ----------------------------------------------------------


@pytest.mark.parametrize("suffix", [".csv", ".npy"])
def test_cli_filter_failure_mid_write_leaves_no_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, suffix: str
) -> None:
    log = tmp_path / "gyro.npy"
    np.save(log, np.random.default_rng(4).normal(size=(400, 2)))
    out = tmp_path / f"filtered{suffix}"
    argv = ["filter", str(log), "--fs", "200", "--bandwidth", "10", "--arw", "0.01", "-o", str(out)]
    writer = "savetxt" if suffix == ".csv" else "save"
    real_writer = getattr(np, writer)

    def interrupted(fh: Any, *args: Any, **kwargs: Any) -> None:
        fh.write(b"half a file")  # some bytes reach the file, then the run dies
        raise KeyboardInterrupt

    monkeypatch.setattr(np, writer, interrupted)
    assert main(argv) == 130  # "gyrobias: interrupted"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["gyro.npy"]  # no target, no temp file
    # An existing output survives a failed run untouched.
    out.write_bytes(b"previous result")
    assert main(argv) == 130
    assert out.read_bytes() == b"previous result"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["gyro.npy", out.name])
    # And a run that succeeds replaces it with the whole file.
    monkeypatch.setattr(np, writer, real_writer)
    assert main(argv) == 0
    back = np.loadtxt(out, delimiter=",", skiprows=1) if suffix == ".csv" else np.load(out)
    assert back.shape == (400, 4)


# --- representable counts: the binding's check, not a second one in Python ---------------------

# Counts the Python layer computes with before the core sees them (a frequency grid, a batch
# shape's product): their range is Python's own (and only) check. (The batch test's sections
# are cut by the core: its calibration and horizon reach the binding as given.)
_PYTHON_OWNED = {
    "noise.fit min_points",  # refused even where the joint fit ignores it (issue 27)
    "fir.KaiserLowpass.frequency_response n",
    "fractional.arfima size",
}


@pytest.mark.parametrize("value", [2**64, -1])
def test_unrepresentable_counts_are_the_binding_check(value: int) -> None:
    """Every other count reaches the binding as given: its count extractor's message (not a
    Python copy of the same range check with another bound) is what the user sees."""
    from tests.test_robustness import COUNT_CASES

    for case, call in COUNT_CASES.items():
        name = case.rsplit(" ", 1)[1]
        pattern = (
            rf"^{name} must be an integer from 0 to 2\*\*63 - 1"
            if case in _PYTHON_OWNED
            else rf"^{name} must be an integer from 0 to 2\*\*64 - 1"
        )
        if name == "n_threads" and value == -1:
            # refused before any work (options rule: even where no method uses threads)
            pattern = r"^n_threads must be a positive integer or None, got -1"
        with pytest.raises(ValueError, match=pattern):
            call(value)

"""Hostile input, fourth pass (issue 34): text that reaches a file, generated C, values no
sensor can produce, and internal exception types — each class walked over every member.

The members come from the hostile registry (``tests/hostile_registry.py``, itself checked
against the public signatures): every parameter of kind ``text`` for the free-text class,
every ``to_c``/``emit_*`` for generated C, every real-valued kind for huge integers, every
``unit`` for unit strings. Sizes that reach an allocation are ``tests/test_hostile_sizes.py``.
"""

from __future__ import annotations

import dataclasses
import html.parser
import io as _io
import json
import math
import re
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import gyrobias
from gyrobias import _validation, allan, exports, fractional, kalman, noise, predict
from gyrobias.cli import main as cli_main
from tests.hostile_registry import REGISTRY, entries, kinds_of
from tests.test_hostile import _TMP, BASE, FX, _tmp


@pytest.fixture(autouse=True, scope="module")
def _module_tmp(tmp_path_factory: pytest.TempPathFactory) -> Any:
    """The scratch directory the BASE calls of ``tests/test_hostile.py`` write into."""
    _TMP.insert(0, tmp_path_factory.mktemp("hostile_classes"))
    yield
    _TMP.pop(0)


# --- 1. free text -----------------------------------------------------------------------------

#: Text that must never reach a file as it is: every kind of line break, a control character,
#: a format character, a lone surrogate, and a text too long to be a name.
BREAKING = ["a\nb: 1", "a\rb: 1", "a\x85b", "a\u2028b", "a\u2029b", "a\x00b", "a\x1bb",
            "a\u200eb", "a\udcffb", "x" * 201]  # fmt: skip
#: Printable text that is valid in a name and must come back from every file exactly.
PRINTABLE = ["quote'd \"x\"", "#comment", "---", "</script><b>x</b>", "*/ int x; /*",
             "Gyro-Ä ω_z °/s", "key: value", "[1, 2]", "&amp; <x>", "% matlab"]  # fmt: skip


@pytest.mark.parametrize("value", BREAKING)
def test_text_check_refuses_what_would_break_a_line(value: str) -> None:
    with pytest.raises(ValueError, match=r"^label must be"):
        _validation.text("label", value)


@pytest.mark.parametrize("value", PRINTABLE)
def test_text_check_keeps_printable_text(value: str) -> None:
    assert _validation.text("label", value) == value


def test_text_check_refuses_non_strings() -> None:
    for value in (5, None, b"x", ["x"]):
        with pytest.raises(TypeError, match=r"^label must be a string"):
            _validation.text("label", value)


#: Members of the text class without a valid call in BASE, and the reason.
TEXT_UNCHECKED = {
    ("exports.atomic_write", "text"): "a whole file's text (many lines by design): only its "
    "encoding is checked, by test_atomic_write_refuses_unencodable_text",
    ("cli.allan.ProgressBar.__init__", "label"): "the CLI's own constant label",
}

#: Calls for the text members whose function has no entry in test_hostile.BASE.
_EXTRA_BASE = {
    "allan.AllanResult.plot": lambda: (FX.allan.plot, {}),
    "plotting.plot_allan": lambda: (gyrobias.plotting.plot_allan, {"results": FX.allan}),
    "plotting.plot_fleet": lambda: (
        gyrobias.plotting.plot_fleet,
        {"table": gyrobias.fleet.analyse(np.stack([FX.rate[:2000]] * 2), fs=100.0, num_workers=1)},
    ),
}


def _text_members() -> list[tuple[str, str]]:
    out = [(k, n) for k, n, _ in entries("text") if (k, n) not in TEXT_UNCHECKED]
    # names of a log's columns and its topic: kinds spec/key in the registry, text all the same
    out += [("io.load", "columns"), ("io.load", "time_column"), ("io.load", "topic")]
    return out


def _text_value(key: str, name: str, payload: str) -> Any:
    """``payload`` in the shape the parameter takes (one name per axis, a list of labels)."""
    if name == "axis_names":
        return [payload]
    if name == "labels":
        return (payload, payload) if key == "plotting.save_comparison_plot" else [payload]
    if name == "columns":
        return [payload]
    return payload


@pytest.mark.parametrize(("key", "name"), _text_members(), ids=str)
def test_every_text_parameter_refuses_line_breaks(key: str, name: str) -> None:
    """Every string that can reach a file, a plot or a page refuses every kind of line break,
    control characters and lone surrogates with an error naming it — before anything is
    written or computed."""
    if key.startswith("plotting.") or key == "allan.AllanResult.plot":
        pytest.importorskip("matplotlib")
    factory = BASE.get(key) or _EXTRA_BASE[key]
    for payload in BREAKING:
        func, kwargs = factory()
        with pytest.raises((ValueError, TypeError)) as info, warnings.catch_warnings():
            warnings.simplefilter("ignore")
            func(**{**kwargs, name: _text_value(key, name, payload)})
        message = str(info.value)
        assert re.search(rf"(?<![A-Za-z0-9_]){re.escape(name)}", message), (key, payload, message)


def test_cli_text_options_follow_the_library_rule() -> None:
    from gyrobias.cli import _types

    for payload in BREAKING:
        with pytest.raises(Exception, match="must be"):
            _types.text(payload)
    for payload in PRINTABLE:
        assert _types.text(payload) == payload


def test_atomic_write_refuses_unencodable_text() -> None:
    target = _tmp() / "surrogate.txt"
    with pytest.raises(ValueError, match=r"^text must be valid Unicode"):
        exports.atomic_write(target, "a\udcffb")
    assert not target.exists()
    assert not list(_tmp().glob(".surrogate.txt*"))  # no temporary file left behind


def _with_axis(c: Any, axis: str) -> Any:
    """Coefficients carrying ``axis`` as they would after a file's column name reached them
    (the dataclass field, past the entry checks): the writers must hold on their own."""
    return dataclasses.replace(c, axis=axis)


def _parse_yaml(text: str) -> Any:
    from ruamel.yaml import YAML

    return YAML(typ="safe", pure=True).load(text.replace("%YAML:1.0\n", "", 1))


def _sheet() -> Any:
    return noise.from_datasheet(
        arw="0.3 deg/sqrt(h)",
        rrw="3 deg/h^1.5",
        vrw="0.05 m/s/sqrt(h)",
        accel_random_walk="1e-4 m/s^2.5",
    )


def _baseline() -> dict[str, str]:
    ds = _sheet()
    return exports.export_all([ds.gyro, ds.gyro], accel=[ds.accel], rate=200.0)


@pytest.mark.parametrize("payload", BREAKING[:-1] + PRINTABLE)
def test_every_written_file_parses_back_to_what_was_meant(payload: str) -> None:
    """Axis names (any content, even what the entry check refuses) in every estimator file:
    each YAML parses to exactly the keys and numbers of the file without them (PyYAML too,
    which Kalibr uses), JSON holds the name verbatim, MATLAB gains no line of code."""
    base = _baseline()
    ds = _sheet()
    gyro = [_with_axis(ds.gyro, payload), _with_axis(ds.gyro, "y")]
    accel = [_with_axis(ds.accel, payload)]
    out = _tmp() / f"parse{abs(hash(payload))}"
    texts = exports.export_all(gyro, out, accel=accel, rate=200.0)
    for fmt, text in texts.items():
        written = (out / exports.DEFAULT_FILENAMES[fmt]).read_bytes().decode("utf-8")
        assert written == text
        if fmt == "json":
            doc = json.loads(text)
            assert doc["gyro"][0]["axis"] == payload and doc["accel"][0]["axis"] == payload
            assert doc["estimator_values"] == json.loads(base[fmt])["estimator_values"]
        elif fmt == "matlab":
            code = [ln for ln in text.splitlines() if not ln.startswith("%")]
            base_code = [ln for ln in base[fmt].splitlines() if not ln.startswith("%")]
            assert code == base_code, (payload, text)
        else:
            assert _parse_yaml(text) == _parse_yaml(base[fmt]), (fmt, payload, text)
            yaml = pytest.importorskip("yaml")
            assert yaml.safe_load(text.replace("%YAML:1.0\n", "", 1)) == yaml.safe_load(
                base[fmt].replace("%YAML:1.0\n", "", 1)
            )
            assert payload not in text or payload.isprintable()  # escaped in comments


def test_yaml_files_are_byte_identical_to_the_string_built_ones() -> None:
    """The serializer keeps the layout the estimators have always been given: the Kalibr file
    of the docs' example, byte for byte (key order, comment position, number format)."""
    ds = noise.from_datasheet(
        arw="0.3 deg/sqrt(h)",
        rrw="3 deg/h^1.5",
        vrw="0.05 m/s/sqrt(h)",
        accel_random_walk="1e-4 m/s^2.5",
    )
    text = exports.export(ds.gyro, "kalibr", accel=ds.accel, rate=200)
    assert text == (
        "# Kalibr IMU noise model written by gyrobias (from: datasheet coefficients)\n"
        "# N, K: IEEE-952 coefficients (two-sided densities); see the convention table of the "
        "gyrobias docs (Estimator parameters).\n"
        "# Kalibr discretises with update_rate: sigma_d = sigma*sqrt(rate), sigma_bd = "
        "sigma_b/sqrt(rate).\n"
        "accelerometer_noise_density: 8.333333e-04  # m/s^2/sqrt(Hz), continuous\n"
        "accelerometer_random_walk: 1.000000e-04  # m/s^3/sqrt(Hz), continuous\n"
        "gyroscope_noise_density: 8.726646e-05  # rad/s/sqrt(Hz), continuous\n"
        "gyroscope_random_walk: 2.424068e-07  # rad/s^2/sqrt(Hz), continuous\n"
        "rostopic: /imu0\n"
        "update_rate: 200  # Hz\n"
    )
    vins = exports.export(ds.gyro, "vins", rate=200).splitlines()
    assert vins[-4:] == [
        "# acc_n: not written: no accelerometer coefficients given",
        "gyr_n: 1.234134e-03  # rad/s, discrete",
        "# acc_w: not written: no accelerometer coefficients given",
        "gyr_w: 1.714075e-08  # rad/s per step, discrete",
    ]
    only_accel = exports.export(None, "liosam", accel=ds.accel).splitlines()
    assert only_accel[-2:] == [
        "  imuAccBiasN: 1.000000e-04  # m/s^3/sqrt(Hz)",
        "  # imuGyrBiasN: not written: no gyroscope coefficients given",
    ]


def test_importing_gyrobias_does_not_load_the_yaml_writer() -> None:
    import subprocess
    import sys

    code = "import sys, gyrobias, gyrobias.exports; print('ruamel' in ' '.join(sys.modules))"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.stdout.strip() == "False", done.stdout + done.stderr


class _Page(html.parser.HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.title = ""
        self.scripts = 0
        self._in_title = False

    def handle_starttag(self, tag: str, attrs: Any) -> None:
        self._in_title = tag == "title"
        self.scripts += tag == "script"

    def handle_endtag(self, tag: str) -> None:
        self._in_title = False

    def handle_data(self, data: str) -> None:
        if self._in_title:
            self.title += data


@pytest.mark.parametrize("payload", PRINTABLE)
def test_report_title_and_channel_names_are_escaped(payload: str) -> None:
    """The HTML report: the title parses back verbatim and no payload adds a script."""
    pytest.importorskip("matplotlib")
    log = dataclasses.replace(FX.log, columns=(payload,))
    page = gyrobias.report.build_report(log, title=payload)
    parsed = _Page()
    parsed.feed(page)
    assert parsed.title == f"Noise report: {payload}"
    assert parsed.scripts == _page_scripts()


def _page_scripts() -> int:
    parsed = _Page()
    parsed.feed(gyrobias.report.build_report(FX.log, title="plain"))
    return parsed.scripts


# --- 4. generated C -----------------------------------------------------------------------------


def _emitters() -> list[str]:
    return [k for k in REGISTRY if k.endswith(".to_c") or k.startswith("codegen.emit_")]


@pytest.mark.parametrize("key", _emitters())
def test_every_c_emitter_refuses_header_names_and_the_empty_path(key: str, tmp_path: Path) -> None:
    func, kwargs = BASE[key]()
    for name in ("stdint", "stdio", "math", "string", "STDLIB", "errno", "strfoo", "isx", "eio"):
        with pytest.raises(ValueError, match=r"^name must not be a C standard header"):
            func(**{**kwargs, "path": tmp_path / "c", "name": name})
    with pytest.raises(ValueError, match=r"^path must be a directory path, got an empty"):
        func(**{**kwargs, "path": ""})
    assert not list(tmp_path.iterdir())  # nothing written by any refusal


def test_fir_with_zero_taps_is_refused(tmp_path: Path) -> None:
    empty = dataclasses.replace(FX.lowpass, taps=np.empty(0))
    with pytest.raises(ValueError, match=r"^taps must be a non-empty"):
        empty.to_c(tmp_path)
    assert not list(tmp_path.iterdir())


def test_cli_c_name_refuses_header_names() -> None:
    from gyrobias.cli import _types

    with pytest.raises(Exception, match="standard header"):
        _types.c_identifier("stdint")
    err = _io.StringIO()
    import contextlib

    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(_io.StringIO()):
        code = cli_main(
            ["fir", "design", "--fs", "100", "--fpass", "10", "--fstop", "30", "--c-name", "math"]
        )
    assert code == 2 and "standard header" in err.getvalue(), err.getvalue()


# --- 3. values no sensor can produce ------------------------------------------------------------

_X = np.random.default_rng(5).normal(size=4000)


def test_lines_at_infinity_are_refused() -> None:
    r = allan.adev(FX.rate, 100.0, units="deg/s")
    for f in (math.inf, -math.inf, math.nan, -23.0):
        with pytest.raises(ValueError, match=r"^lines"):
            noise.fit(r, lines=[f])
        with pytest.raises(ValueError, match=r"lines"):
            noise.gmwm(FX.rate, 100.0, lines=[f], seed=1)


_EXPORT_NUMBERS = [math.nan, math.inf, -math.inf, 0.0, -1.0]


@pytest.mark.parametrize("fmt", exports.FORMATS)
def test_every_exporter_refuses_a_bad_rate(fmt: str) -> None:
    """Every format's numeric option, whether or not the format writes it (LIO-SAM wrote
    ``rate=nan`` without a word)."""
    for rate in _EXPORT_NUMBERS:
        with pytest.raises(ValueError, match=r"rate"):
            exports.export(FX.gyro, fmt, rate=rate)
        with pytest.raises(ValueError, match=r"rate"):
            FX.datasheet.export(fmt, rate=rate)
    with pytest.raises(ValueError, match=r"update_rate"):
        exports.write_kalibr(_tmp() / "k.yaml", gyro=[FX.gyro], update_rate=math.nan)


def test_variances_beyond_float64_are_refused_with_the_reason() -> None:
    with pytest.raises(ValueError, match=r"^sigma must be at most 1.34"):
        noise.gauss_markov_avar(1.797e308, 10.0, [1.0, 10.0])
    with pytest.raises(ValueError, match=r"^amplitude must be at most 1.34"):
        noise.sinusoid_avar(1e300, 23.0, [0.01, 0.1], fs=100.0)
    # just inside: finite, and sigma² times the unit-sigma curve
    big = noise.gauss_markov_avar(1e154, 10.0, [1.0, 10.0])
    np.testing.assert_allclose(big, 1e308 * noise.gauss_markov_avar(1.0, 10.0, [1.0, 10.0]))


@pytest.mark.parametrize("scale", [2.0**500, 1e153, 1e-160, 1e-300, 2.0**-1060])
def test_wavelet_variance_is_scaled_internally(scale: float) -> None:
    """wvar of data near 1e153 (squares overflow) or subnormal (squares underflow) equals the
    unit-scale result times scale² (rtol 1e-12: a power of two is exact, a decimal scale
    rounds each sample once) — or is refused naming data when float64 cannot hold it."""
    ref = noise.wvar(_X, 100.0, robust=False)
    try:
        got = noise.wvar(_X * scale, 100.0, robust=False)
    except ValueError as exc:
        assert str(exc).startswith("data") or "data" in str(exc), exc
        assert (
            not np.isfinite(ref.variance * scale**2).all()
            or (ref.variance * scale**2 < 1e-300).any()
        )
        return
    np.testing.assert_allclose(got.variance, ref.variance * scale**2, rtol=1e-12)


def test_wavelet_variance_beyond_float64_is_refused() -> None:
    with pytest.raises(ValueError, match=r"exceeds float64"):
        noise.wvar(_X * 1e155 + 1e155, 100.0)


# --- 5. internal exception types ----------------------------------------------------------------


def _numeric_members() -> list[tuple[str, str]]:
    return [
        (k, n)
        for kind in ("pos", "nonneg", "real", "level")
        for k, n, _ in entries(kind)
        if k in BASE and not k.startswith("cli.")
    ]


@pytest.mark.parametrize(("key", "name"), _numeric_members(), ids=str)
def test_huge_integers_are_value_errors(key: str, name: str) -> None:
    """10**400 (no float64 holds it): a ValueError naming the argument, never OverflowError."""
    func, kwargs = BASE[key]()
    with pytest.raises((ValueError, TypeError)) as info, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        func(**{**kwargs, name: 10**400})
    assert name in str(info.value), str(info.value)


@pytest.mark.parametrize(
    ("key", "name"),
    [(k, n) for k, n, _ in entries("unit") if k in BASE and not k.startswith("cli.")],
    ids=str,
)
def test_unit_strings_refuse_nesting_surrogates_and_huge_ints(key: str, name: str) -> None:
    func, kwargs = BASE[key]()
    for value in ("(" * 5000 + "deg" + ")" * 5000, "deg/s\udcff", 10**400, "deg^99999999999"):
        with pytest.raises((ValueError, TypeError)) as info:
            func(**{**kwargs, name: value})
        assert name in str(info.value), (value, str(info.value)[:200])


#: Sequence arguments (kind ``spec`` in the registry) that take a list of items.
SEQUENCES = [
    ("noise.gmwm", "terms"),
    ("noise.fit", "terms"),
    ("conservative.conservative", "terms"),
    ("noise.NoiseCoefficients.conservative", "terms"),
    ("fleet.analyse", "terms"),
    ("exports.write_kalibr", "gyro"),
    ("exports.write_kalibr", "accel"),
    ("exports.export", "gyro"),
    ("exports.export", "accel"),
    ("thermal.analyse_logs", "logs"),
    ("thermal.build_temperature_model", "logs"),
    ("thermal.TemperatureModel.from_analyses", "analyses"),
    ("io.load", "columns"),
    ("predict.evaluate", "methods"),
]


@pytest.mark.parametrize(("key", "name"), SEQUENCES, ids=str)
def test_sequence_arguments_refuse_scalars_with_the_name(key: str, name: str) -> None:
    assert kinds_of(key)[name][0] in ("spec", "object")
    for value in (5, 2.5, object()) + (
        (None,) if name not in ("gyro", "accel", "columns", "terms") else ()
    ):
        func, kwargs = BASE[key]()
        with pytest.raises((TypeError, ValueError)) as info, warnings.catch_warnings():
            warnings.simplefilter("ignore")
            func(**{**kwargs, name: value})
        assert name in str(info.value), (value, str(info.value))
        assert "not iterable" not in str(info.value)


def test_named_internal_errors_of_the_issue() -> None:
    with pytest.raises(TypeError, match=r"^predictor must be"):
        predict.evaluate(FX.rate[:600], calibration=100, horizon=50, predictor="kf")
    with pytest.raises(TypeError, match=r"^methods must be a sequence"):
        predict.evaluate(FX.rate[:600], calibration=100, horizon=50, methods=5)
    kf = kalman.FixedGainKalman(100.0, arw=0.01, rrw=1e-4, q_omega=1e-6)
    for out in ((np.zeros(5), [0.0] * 5), (np.zeros(5), np.zeros(5, np.float32))):
        with pytest.raises(TypeError, match=r"^out\[1\] must be a writable C-contiguous"):
            kf.filter(np.ones(5), out=out)
    for func in (fractional.diff, fractional.integrate):
        with pytest.raises(ValueError, match=r"^d must be finite"):
            func(_X[:50], 10**400)
    with pytest.raises(TypeError, match=r"^data_unit must be a string"):
        gyrobias.units.sensor_kind(10**400)
    with pytest.raises(ValueError, match=r"^text must be at most 200 characters"):
        gyrobias.units.parse_unit("(" * 5000 + "deg" + ")" * 5000)
    with pytest.raises(ValueError, match=r"^mean must be valid Unicode"):
        predict.FractionalKalmanPredictor(d=0.4, mean="\udcff")


# --- 3b. every public function at extreme data scales ----------------------------------------------

#: Array parameters that carry the data (its scale is what the extremes vary).
_DATA_NAMES = ("data", "x", "z", "y", "log", "rate", "w", "calibration", "batch", "section")
_SCALES = [2.0**-1040, 1e-160, 1e153, 1e300]


def _floats(obj: Any, depth: int = 0) -> list[float]:
    """Every float a result holds (arrays, dataclass fields, tuples), for the finiteness check."""
    if depth > 3:
        return []
    if isinstance(obj, (float, np.floating)):
        return [float(obj)]
    if isinstance(obj, np.ndarray):
        return [float(v) for v in obj.ravel()[:2000]] if obj.dtype.kind == "f" else []
    if isinstance(obj, (tuple, list)):
        return [v for item in obj[:8] for v in _floats(item, depth + 1)]
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return [
            v
            for f in dataclasses.fields(obj)
            if f.name not in ("ci_low", "ci_high", "p_value", "chi2", "uncertainty", "edf")
            and not (
                f.name in _BEYOND_FLOAT64
                and getattr(obj, _BEYOND_FLOAT64[f.name], None) is not None
            )
            for v in _floats(getattr(obj, f.name), depth + 1)
        ]
    return []


def _extreme_members() -> list[tuple[str, str]]:
    return [
        (k, n)
        for k, n, _ in entries("array")
        if n in _DATA_NAMES and k in BASE and not k.startswith(("plotting.", "cli."))
    ]


#: Members whose results legitimately hold non-finite values at an extreme scale, with reason.
EXTREME_UNCHECKED: dict[tuple[str, str], str] = {
    ("allan.dynamic_adev", "data"): "a variance of data near 1e300 (1e600) is beyond float64: "
    "the dynamic result holds variances only and reports them as inf (left valid: the static "
    "statistics carry the exact deviation, see test_allan_statistics_of_subnormal_and_huge_data)",
}

#: Fields that may hold inf where the quantity itself is beyond float64 while the result
#: carries it exactly in another form (the field named): AllanResult.avar (variance of data
#: near 1e300) next to AllanResult.deviation, and AllanResult.data_variance next to
#: data_deviation, both computed before the scale was restored and finite.
_BEYOND_FLOAT64 = {"avar": "deviation", "data_variance": "data_deviation"}


@pytest.mark.parametrize(("key", "name"), _extreme_members(), ids=str)
def test_every_data_function_is_finite_or_refuses_at_extreme_scales(key: str, name: str) -> None:
    """Data scaled to subnormal, tiny, huge and near-overflow magnitudes: a result without
    NaN/inf the caller did not put in, or a ValueError saying why — never inf/NaN/0 garbage
    returned as values."""
    if (key, name) in EXTREME_UNCHECKED:
        pytest.skip(EXTREME_UNCHECKED[(key, name)])
    problems = []
    for scale in _SCALES:
        func, kwargs = BASE[key]()
        base = np.asarray(kwargs[name], dtype=np.float64)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                result = func(**{**kwargs, name: base * scale})
        except (ValueError, MemoryError) as exc:
            assert str(exc), key
            continue
        bad = [v for v in _floats(result) if not math.isfinite(v)]
        if bad:
            problems.append(f"scale {scale:g}: {len(bad)} non-finite values, e.g. {bad[:3]}")
    assert not problems, f"{key}({name}=...): " + "; ".join(problems)


@pytest.mark.parametrize("kind", ["adev", "mdev", "hdev", "totdev", "theo1", "mtotdev"])
@pytest.mark.parametrize("scale", [2.0**-1040, 1e-310, 2.0**1023 / 8])
def test_allan_statistics_of_subnormal_and_huge_data_are_the_scaled_ones(
    kind: str, scale: float
) -> None:
    """Subnormal data (every deviation was 0) and data near float64's top: the deviation is
    the unit-scale deviation times the scale. Tolerance: a sample at 2^-1040 keeps 34
    significant bits (relative rounding 6e-11 each, ~2e-9 in the last τ's few terms), hence
    rtol 1e-7 there; power-of-two scales of normal data are exact (rtol 1e-12)."""
    ref = getattr(allan, kind)(_X[:1000], 100.0, confidence=None).adev
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the variance of data near 2^1020 is inf (see adev)
        got = getattr(allan, kind)(_X[:1000] * scale, 100.0, confidence=None).adev
    assert np.all(got > 0.0), got[:4]
    np.testing.assert_allclose(got / scale, ref, rtol=1e-7 if scale < 1e-300 else 1e-12)


def test_elw_objective_of_constant_or_extreme_series() -> None:
    for x in (np.full(8, 2, dtype=np.int8), np.zeros(20)):
        with pytest.raises(ValueError, match=r"x: is constant"):
            fractional.elw_objective(x, [0.1, 0.3])
    y = _X[:500]
    ref = fractional.elw_objective(y, [0.0, 0.3])
    for scale in (2.0**600, 2.0**-600):
        got = fractional.elw_objective(y * scale, [0.0, 0.3])
        # R(d) of c·x is R(d) of x + ln c² (the periodogram scales with c²)
        np.testing.assert_allclose(got, ref + 2.0 * math.log(scale), rtol=1e-12, atol=1e-9)


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("lines", [[(23.0, 0.5)], [23.0], [(31.0, 0.0)], "auto"])
def test_gmwm_sinusoids_never_exceed_what_the_data_allow(seed: int, lines: Any) -> None:
    """Every estimated sinusoid of ``noise.gmwm``: a sine of amplitude Ω₀ alone has variance
    Ω₀²/2, so a fit on data of variance v either keeps Ω₀ <= √(2v) or is refused saying so
    (the issue's log: std 0.0562 allowed 0.0795, gmwm returned 0.131 with a passing test)."""
    rate = noise.simulate(
        40_000, 100.0, arw=0.01, rrw=1e-4, seed=seed, sinusoids=[(23.0, 0.002 * (seed + 1))]
    )
    limit = math.sqrt(2.0 * float(np.var(rate)))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            c = noise.gmwm(rate, 100.0, units="deg/s", lines=lines, seed=seed)
    except ValueError as exc:
        assert "more than the data allow" in str(exc), exc
        return
    for s in c.sinusoids:
        if s.amplitude.value is not None:
            assert s.amplitude.to("deg/s").value <= limit * (1 + 1e-9), (s, limit)

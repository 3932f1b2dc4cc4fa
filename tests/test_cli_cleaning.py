"""``--outliers``, ``--detrend``, ``--fit-tau-range`` and ``--lines`` on ``gyrobias allan``,
``report`` and ``fleet`` (issue 35), each against the public Python API on the same data: what
the command line does is a few lines of ``io``/``cleaning``/``allan``/``noise``.

Order: ``--start/--stop`` → outliers → drift → statistics → fit.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from gyrobias import allan, cleaning, fleet, noise
from gyrobias.cli import build_parser, main

FS = 50.0
N = 36_000  # 12 min at 50 Hz
SPIKES = (1000, 7000, 20_000)


def _rate(seed: int, n: int = N) -> np.ndarray:
    rate = noise.simulate(n, FS, arw=0.2 / 60, bias_instability=3 / 3600, axes=2, seed=seed)
    rate += np.arange(n)[:, None] / FS * np.array([2e-5, -1e-5])  # a drift, deg/s per s
    rate[[s for s in SPIKES if s < n], 0] += 1.0  # spikes of ~300σ
    return rate


def _csv(path: Path, rate: np.ndarray) -> Path:
    t = np.arange(len(rate)) / FS
    np.savetxt(
        path, np.column_stack([t, rate]), delimiter=",", header="t,gx,gy", comments="", fmt="%.17g"
    )
    return path


def _read_back(path: Path) -> np.ndarray:
    return np.loadtxt(path, delimiter=",", skiprows=1)[:, 1:]


def _python_api(path: Path) -> tuple[cleaning.CleaningResult, tuple[allan.AllanResult, ...]]:
    """What ``--start 2min --outliers 5 --detrend linear`` computes, by hand."""
    part = _read_back(path)[6000:]
    cleaned = cleaning.clean(part, FS, outliers=5.0, detrend="linear", units="deg/s")
    curves = allan.adev(cleaned.data, FS, gaps="omit", units="deg/s", axis_names=["gx", "gy"])
    assert isinstance(curves, tuple)
    return cleaned, curves


def test_the_log_commands_have_the_options() -> None:
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    for name in ("allan", "report", "fleet"):
        opts = {o for a in sub.choices[name]._actions for o in a.option_strings}
        assert {"--outliers", "--detrend", "--fit-tau-range", "--lines"} <= opts, name


def test_allan_cleaning_and_fit_options_equal_the_python_api(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _csv(tmp_path / "log.csv", _rate(1))
    out = tmp_path / "out.json"
    args = ["allan", str(path), "--units", "deg/s", "--start", "2min", "--outliers", "5"]
    args += ["--detrend", "linear", "--fit", "--fit-tau-range", "0.04,60", "--lines", "none"]
    assert main([*args, "--json", str(out)]) == 0
    text = capsys.readouterr().out
    cleaned, curves = _python_api(path)
    assert cleaned.outliers is not None and cleaned.outliers.count.tolist() == [2, 0]
    assert "cleaning: outliers > 5σ (MAD) removed per channel: 2, 0; linear drift removed" in text
    doc = json.loads(out.read_text())
    assert doc["cleaning"] == cleaned.to_dict()
    assert doc["fit_options"] == {"method": "joint", "tau_range_s": [0.04, 60.0], "lines": "none"}
    for axis, ref in zip(doc["axes"], curves):
        np.testing.assert_array_equal(axis["taus"], ref.taus)
        np.testing.assert_array_equal(axis["deviation"], ref.adev)
    fits = noise.fit(curves, tau_range=(0.04, 60.0), lines=None)
    for c_json, c in zip(doc["noise_coefficients"], fits):
        assert c_json == c.to_dict()


def test_allan_without_cleaning_says_so(tmp_path: Path) -> None:
    path = _csv(tmp_path / "log.csv", _rate(2))
    out = tmp_path / "out.json"
    assert main(["allan", str(path), "--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert doc["cleaning"] is None and doc["fit_options"] is None


def test_report_shows_the_cleaning(tmp_path: Path) -> None:
    path = _csv(tmp_path / "log.csv", _rate(3))
    html = tmp_path / "r.html"
    args = ["report", str(path), "--units", "deg/s", "--outliers", "5", "--detrend", "quadratic"]
    assert main([*args, "--fit-tau-range", "0.1,100", "-o", str(html)]) == 0
    page = html.read_text()
    assert "outliers &gt; 5σ (MAD) removed per channel: 3, 0; quadratic drift removed" in page


def test_fleet_cleaning_and_fit_options_equal_the_python_api(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    paths = [_csv(tmp_path / f"unit{i}.csv", _rate(10 + i)) for i in range(2)]
    out = tmp_path / "fleet.parquet"
    code = main(
        ["fleet", str(tmp_path / "unit*.csv"), "--units", "deg/s", "--start", "2min"]
        + ["--outliers", "5", "--detrend", "linear", "--fit-tau-range", "0.04,60"]
        + ["--lines", "none", "--out", str(out), "--workers", "1"]
    )
    assert code == 0
    assert "cleaning of every log: outliers > 5σ (MAD) removed; linear drift removed" in (
        capsys.readouterr().out
    )
    table = pd.read_parquet(out)
    for path in paths:
        cleaned, curves = _python_api(path)
        fits = noise.fit(curves, tau_range=(0.04, 60.0), lines=None)
        rows = table[table["source"] == str(path)]
        for (_, row), r, c in zip(rows.iterrows(), curves, fits):
            assert row["cleaning"] == cleaned.describe()
            np.testing.assert_array_equal(row["adev"], r.adev)
            assert c.N.value is not None and row["N"] == pytest.approx(c.N.value, rel=1e-12)
    # The same through the Python fleet API.
    again = fleet.analyse(
        paths,
        units="deg/s",
        start="2min",
        outliers=5.0,
        detrend="linear",
        tau_range=(0.04, 60.0),
        lines=None,
        num_workers=1,
    )
    np.testing.assert_allclose(again["N"], table["N"], rtol=1e-12)


def test_fleet_cleaning_of_arrays() -> None:
    units = np.stack([_rate(20 + i)[:, 0] for i in range(2)])
    table = fleet.analyse(units, fs=FS, outliers=5.0, detrend="quadratic", num_workers=1)
    for i in range(2):
        c = cleaning.clean(units[i], FS, outliers=5.0, detrend="quadratic")
        ref = allan.adev(c.data, FS, gaps="omit")
        assert isinstance(ref, allan.AllanResult)
        np.testing.assert_array_equal(table["adev"].iloc[i], ref.adev)
        assert table["cleaning"].iloc[i] == c.describe()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--outliers", "0"], "--outliers must be finite and > 0, got '0'"),
        (["--outliers", "-2"], "--outliers must be finite and > 0"),
        (["--outliers", "nan"], "--outliers must be finite and > 0"),
        (["--outliers", "five"], "--outliers must be finite and > 0"),
        (["--detrend", "cubic"], "--detrend: invalid choice: 'cubic'"),
        (["--fit-tau-range", "10"], "--fit-tau-range must be MIN,MAX in seconds"),
        (["--fit-tau-range", "10,1"], "--fit-tau-range must be MIN,MAX in seconds"),
        (["--fit-tau-range", "0,1"], "with 0 < MIN < MAX, got '0,1'"),
        (["--fit-tau-range", "1,inf"], "--fit-tau-range must be MIN,MAX"),
        (["--fit-tau-range", "a,b"], "--fit-tau-range must be MIN,MAX"),
        (["--lines", "some"], "--lines must be auto, none or FREQ[:HALFWIDTH]"),
        (["--lines", "5,"], "--lines must be auto, none"),
        (["--lines", "-5"], "--lines must be auto, none"),
        (["--lines", "5:6"], "0 <= HALFWIDTH < FREQ"),
        (["--lines", "5:x"], "--lines must be auto, none"),
        (["--fit-method", "ieee", "--fit-tau-range", "1,10"], "--fit-tau-range applies to"),
        (["--fit-method", "ieee", "--lines", "none"], "--lines applies to --fit-method joint"),
    ],
)
def test_bad_values_are_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], message: str
) -> None:
    path = _csv(tmp_path / "log.csv", _rate(4, n=3000))
    for command in (
        ["allan", str(path), "--fit"],
        ["report", str(path), "-o", str(tmp_path / "r.html")],
        ["fleet", str(path), "--workers", "1"],
    ):
        assert main([*command, *args]) == 2, command
        err = capsys.readouterr().err
        assert err.startswith("gyrobias: error: ") and message in err, (command, err)
        assert err.count("\n") == 1 and "Traceback" not in err
    assert not (tmp_path / "r.html").exists()


def test_outliers_with_a_statistic_that_cannot_skip_gaps(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _csv(tmp_path / "log.csv", _rate(5, n=3000))
    assert main(["allan", str(path), "--kind", "totdev", "--outliers", "5"]) == 2
    err = capsys.readouterr().err
    assert "--outliers replaces outliers by gaps (NaN), and this TOTDEV cannot skip" in err
    assert "use --kind adev, mdev, hdev" in err
    assert err.count("\n") == 1
    # Nothing flagged: no gaps, TOTDEV runs.
    assert main(["allan", str(path), "--kind", "totdev", "--outliers", "1e9"]) == 0


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("auto", "auto"),
        ("none", None),
        ("23", [23.0]),
        ("23:0,5.5:0.1", [(23.0, 0.0), (5.5, 0.1)]),
    ],
)
def test_lines_values(text: str, value: object) -> None:
    args = build_parser().parse_args(["allan", "x.csv", "--lines", text])
    assert args.lines == value

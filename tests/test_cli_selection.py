"""``--start`` / ``--stop`` on the commands that read a log (issue 33), against slicing by hand,
and ``gyrobias fleet --bound-confidence``.

Every command that reads a log gets the options from ``cli._common.add_read_arguments`` and
applies them in ``read_log`` (``GyroLog.select``): ``allan``, ``report`` and ``fleet`` show the
span in their output; the others (``predict``, ``filter``, ``thermal``) analyse the span.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from gyrobias import allan, fleet, noise
from gyrobias.cli import build_parser, main

FS = 50.0
N = 36_000  # 12 min at 50 Hz


def _rate(seed: int, n: int = N) -> np.ndarray:
    return noise.simulate(n, FS, arw=0.2 / 60, bias_instability=3 / 3600, axes=2, seed=seed)


def _csv(path: Path, rate: np.ndarray) -> Path:
    t = np.arange(len(rate)) / FS
    np.savetxt(
        path,
        np.column_stack([t, rate]),
        delimiter=",",
        header="t,gx,gy",
        comments="",
        fmt="%.17g",
    )
    return path


def _read_back(path: Path) -> np.ndarray:
    return np.loadtxt(path, delimiter=",", skiprows=1)[:, 1:]


def test_every_command_reading_a_log_has_start_and_stop() -> None:
    import argparse

    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    with_read = [
        name
        for name, p in sub.choices.items()
        if any("--spill" in a.option_strings for a in p._actions)
    ]
    assert {"allan", "report", "fleet", "predict", "filter"} <= set(with_read)
    for name in with_read:
        opts = {o for a in sub.choices[name]._actions for o in a.option_strings}
        assert {"--start", "--stop"} <= opts, name


def test_allan_start_stop_equals_the_slice(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _csv(tmp_path / "log.csv", _rate(1))
    out = tmp_path / "out.json"
    code = main(
        ["allan", str(path), "--units", "deg/s", "--start", "2min", "--stop", "9000n"]
        + ["--json", str(out)]
    )
    assert code == 0
    text = capsys.readouterr().out
    assert "τ computed on 2–3 min of 12 min (samples 6000–9000 of 36000)" in text
    assert "3000 samples × 2 channels" in text
    doc = json.loads(out.read_text())
    assert doc["selection"] == {
        "start_s": 120.0,
        "stop_s": 180.0,
        "start_index": 6000,
        "stop_index": 9000,
        "n_samples": 3000,
        "total_s": 720.0,
        "total_samples": 36000,
        "text": "2–3 min of 12 min",
    }
    # The slice by hand, from the file as written (no selection code involved).
    by_hand = allan.adev(_read_back(path)[6000:9000], FS, units="deg/s")
    for axis, ref in zip(doc["axes"], by_hand):
        np.testing.assert_array_equal(axis["taus"], ref.taus)
        np.testing.assert_array_equal(axis["deviation"], ref.adev)
    # Without a selection: no line, and the JSON says so.
    assert main(["allan", str(path), "--json", str(out)]) == 0
    assert "τ computed on" not in capsys.readouterr().out
    assert json.loads(out.read_text())["selection"] is None


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--start", "1 day"], "--start='1 day' is not a time"),
        (["--start", "-5"], "--start='-5' must be >= 0"),
        (["--stop", "13min"], "--stop=13min is beyond the end of the log (36000 samples, 12 min)"),
        (["--start", "12min"], "--start=12min is at or beyond the end of the log"),
        (["--start", "300", "--stop", "5min"], "--start=300 must be before --stop=5min"),
        (["--stop", "1.5n"], "a sample index is a non-negative integer"),
    ],
)
def test_bad_selection_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], message: str
) -> None:
    path = _csv(tmp_path / "log.csv", _rate(2))
    for command in (["allan", str(path)], ["report", str(path), "-o", str(tmp_path / "r.html")]):
        assert main([*command, *args]) == 2
        err = capsys.readouterr().err
        assert err.startswith("gyrobias: error: ") and message in err, err
        assert err.count("\n") == 1 and "Traceback" not in err
    assert not (tmp_path / "r.html").exists()


def test_report_shows_the_span(tmp_path: Path) -> None:
    path = _csv(tmp_path / "log.csv", _rate(3))
    html = tmp_path / "r.html"
    assert main(["report", str(path), "--units", "deg/s", "--start", "60", "-o", str(html)]) == 0
    page = html.read_text()
    assert "analysed span" in page
    assert "τ computed on 1–12 min of 12 min (samples 3000–36000 of 36000)" in page
    assert "33000 × 2" in page


def test_predict_analyses_the_span(tmp_path: Path) -> None:
    # predict reads through read_log too: the span is what it sees (fewer samples).
    path = _csv(tmp_path / "log.csv", _rate(4))
    from gyrobias.cli._common import read_log

    args = build_parser().parse_args(["predict", str(path), "--start", "5min", "--stop", "6min"])
    log = read_log(args)
    np.testing.assert_array_equal(log.data, _read_back(path)[15000:18000])


def test_fleet_start_stop_and_bound_confidence(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    paths = [_csv(tmp_path / f"unit{i}.csv", _rate(10 + i)) for i in range(3)]
    out = tmp_path / "fleet.parquet"
    code = main(
        ["fleet", str(tmp_path / "unit*.csv"), "--units", "deg/s", "--start", "1min"]
        + ["--stop", "7min", "--bound-confidence", "0.8", "--out", str(out), "--workers", "1"]
    )
    assert code == 0
    text = capsys.readouterr().out
    assert "τ computed on" in text and "1–7 min of 12 min" in text
    table = pd.read_parquet(out)
    assert set(table["selection"]) == {"1–7 min of 12 min (samples 3000–21000 of 36000)"}
    assert (table["n_samples"] == 18000).all() and (table["bound_confidence"] == 0.8).all()
    for path in paths:
        ref = allan.adev(_read_back(path)[3000:21000], FS, units="deg/s")
        rows = table[table["source"] == str(path)]
        fits = noise.fit(ref, bound_confidence=0.8)
        for (_, row), r, c in zip(rows.iterrows(), ref, fits):
            np.testing.assert_array_equal(row["adev"], r.adev)
            for t in c.terms:
                if t.bounded:  # the bound at the level asked for, in the table
                    assert row[f"{t.symbol}_upper_bound"] == pytest.approx(t.upper_bound)
                    assert math.isnan(row[t.symbol])
                elif t.value is not None:
                    assert row[t.symbol] == pytest.approx(t.value)
                    assert math.isnan(row[f"{t.symbol}_upper_bound"])
    # At least one term is a bound on 6-min logs (K, R), and it moves with the level.
    bounds = [c for c in table.columns if c.endswith("_upper_bound")]
    assert table[bounds].notna().to_numpy().any()
    high = fleet.analyse(paths, units="deg/s", start="1min", stop="7min", num_workers=1)
    both = table[bounds].to_numpy(), high[bounds].to_numpy()
    known = np.isfinite(both[0]) & np.isfinite(both[1])
    assert known.any() and (both[0][known] < both[1][known]).all()


def test_fleet_selection_on_arrays_and_errors(tmp_path: Path) -> None:
    units = np.stack([_rate(20 + i)[:, 0] for i in range(2)])
    table = fleet.analyse(units, fs=FS, start="30s", stop="10000n", num_workers=1)
    for i in range(2):
        ref = allan.adev(units[i, 1500:10000], FS)
        np.testing.assert_array_equal(table["adev"].iloc[i], ref.adev)
    assert (table["n_samples"] == 8500).all()
    with pytest.raises(ValueError, match="stop=20min is beyond the end"):
        fleet.analyse(units, fs=FS, stop="20min")
    with pytest.raises(ValueError, match="bound_confidence"):
        fleet.analyse(units, fs=FS, bound_confidence=1.5)
    # A file the span does not fit is an error row, the others are analysed.
    short = _csv(tmp_path / "short.csv", _rate(30, n=6000))  # 2 min
    long = _csv(tmp_path / "long.csv", _rate(31))
    t = fleet.analyse([short, long], start="3min", num_workers=1)
    errors = t.set_index("source")["error"]
    assert "start=3min is at or beyond the end of the log" in errors[str(short)]
    assert t[t["source"] == str(long)]["error"].isna().all()


def test_fleet_bound_confidence_is_checked(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["fleet", "x.csv", "--bound-confidence", "1.5"]) == 2
    assert "bound_confidence" in capsys.readouterr().err

"""The shared "reading the log" options of the gyrobias commands (cli/_common.py)."""

from __future__ import annotations

import inspect
import json
from pathlib import Path

import numpy as np
import pytest

import gyrobias
from gyrobias.cli import build_parser, main


def _imu_csv(path: Path, n: int = 20_000, fs: float = 100.0, seed: int = 3) -> Path:
    """A 6-axis text log: gyro in deg/s, accelerometer in g (white noise)."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs
    gyro = rng.normal(0.0, 0.05, (n, 3))
    acc = rng.normal(0.0, 0.002, (n, 3))
    acc[:, 2] += 1.0
    table = np.column_stack([t, gyro, acc])
    np.savetxt(path, table, delimiter=",", header="t,gx,gy,gz,ax,ay,az", comments="", fmt="%.10g")
    return path


def test_six_axis_text_log_with_units_to_one_kalibr_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    import yaml

    log = _imu_csv(tmp_path / "imu.csv")
    imu, js = tmp_path / "imu.yaml", tmp_path / "a.json"
    code = main(
        [
            "allan",
            str(log),
            "--units",
            "deg/s,deg/s,deg/s,g,g,g",
            "--kalibr",
            str(imu),
            "--json",
            str(js),
            "--no-progress",
        ]
    )
    assert code == 0
    out = capsys.readouterr().out
    assert "ADEV of gx [deg/s]" in out and "ADEV of az [g]" in out
    assert "velocity random walk" in out and "angle random walk" in out
    doc = yaml.safe_load(imu.read_text())
    # white noise σ per sample at fs: N = σ/√fs, in SI (rad/s/√Hz and m/s²/√Hz); the joint
    # fit on 2·10⁴ samples recovers it within a few % (estimator scatter ≈ 1 % at τ0)
    assert doc["gyroscope_noise_density"] == pytest.approx(0.05 / 10.0 * np.pi / 180.0, rel=0.1)
    assert doc["accelerometer_noise_density"] == pytest.approx(0.002 / 10.0 * 9.80665, rel=0.1)
    assert doc["rostopic"] == "/imu0"  # not a bag: Kalibr's default topic
    saved = json.loads(js.read_text())
    assert saved["units"] == ["deg/s"] * 3 + ["g"] * 3
    assert [a["unit"] for a in saved["axes"]] == ["deg/s"] * 3 + ["g"] * 3


def test_every_log_command_has_the_same_reading_options() -> None:
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    wanted = {
        "--columns",
        "--fs",
        "--time-column",
        "--topic",
        "--stamp",
        "--repair",
        "--fill-gaps",
        "--spill",
        "--progress",
        "--no-progress",
        "--delimiter",
        "--skip-rows",
        "--time-unit",
    }
    for name in ("allan", "predict", "filter", "thermal"):
        options = {o for a in sub.choices[name]._actions for o in a.option_strings}  # type: ignore[attr-defined]
        assert wanted <= options, (name, wanted - options)


def test_filter_reads_through_io_load(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # the rate comes from the time column now that filter uses the shared reader
    log = _imu_csv(tmp_path / "imu.csv", n=2000)
    out = tmp_path / "f.npy"
    assert (
        main(
            [
                "filter",
                str(log),
                "--columns",
                "gz",
                "--bandwidth",
                "5",
                "--arw",
                "0.005",
                "-o",
                str(out),
            ]
        )
        == 0
    )
    assert "fs 100 Hz" in capsys.readouterr().out
    assert np.load(out).shape == (2000, 2)


def test_predict_rate_from_timestamps_and_one_channel(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    log = _imu_csv(tmp_path / "imu.csv", n=6000)
    assert (
        main(["predict", str(log), "--column", "gz", "--calibration", "500", "--horizon", "500"])
        == 0
    )
    assert "at 100 Hz" in capsys.readouterr().out
    assert main(["predict", str(log), "--columns", "gx,gy"]) == 2
    assert "predict analyses one channel" in capsys.readouterr().err


def test_repair_and_fill_gaps_options(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "g.csv"
    t = np.arange(3000) / 100.0
    t[2000:] += 0.5
    x = np.random.default_rng(1).normal(size=3000)
    rows = list(zip(t.tolist(), x.tolist()))
    rows[100], rows[101] = rows[101], rows[100]
    path.write_text("t,g\n" + "".join(f"{a!r},{b!r}\n" for a, b in rows))
    assert main(["allan", str(path), "--no-confidence"]) == 2
    assert "--repair sort" in capsys.readouterr().err
    js = tmp_path / "r.json"
    code = main(
        [
            "allan",
            str(path),
            "--no-confidence",
            "--repair",
            "sort",
            "--fill-gaps",
            "--json",
            str(js),
        ]
    )
    captured = capsys.readouterr()
    assert "sorted by timestamp" in captured.err
    if "gaps" in inspect.signature(gyrobias.allan.adev).parameters:  # gap-aware Allan available
        assert code == 0
        assert json.loads(js.read_text())["sampling"]["filled_samples"] == 50
    else:  # the NaN rows cannot be analysed: one line saying so, no traceback
        assert code == 2 and "cannot skip gaps" in captured.err and "Traceback" not in captured.err


def test_units_must_fit_the_channels(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    log = _imu_csv(tmp_path / "imu.csv", n=500)
    assert main(["allan", str(log), "--units", "deg/s,g"]) == 2
    assert "units has 2 entries for 6 channels" in capsys.readouterr().err


def test_read_log_api_for_other_commands(tmp_path: Path) -> None:
    # what a new command (report, fleet, …) does: add the group, parse, read
    import argparse

    from gyrobias.cli._common import add_read_arguments, read_log, require_fs

    p = argparse.ArgumentParser()
    p.add_argument("log", type=Path)
    add_read_arguments(p)
    args = p.parse_args(
        [str(_imu_csv(tmp_path / "x.csv", n=300)), "--columns", "ax,az", "--units", "g"]
    )
    log = read_log(args)
    assert (
        log.columns == ("ax", "az")
        and log.units == ("g", "g")
        and require_fs(log, args.log) == 100.0
    )
    assert isinstance(log, gyrobias.io.GyroLog)


def test_fill_gaps_feeds_the_gap_aware_allan(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # a log with a 10 % block missing: the CLI's result is the estimator's on the full-length
    # record with NaN exactly where the samples are missing
    n, fs = 20_000, 100.0
    rate = np.random.default_rng(8).normal(0.0, 0.1, n)
    keep = np.ones(n, dtype=bool)
    keep[9_000:11_000] = False
    t = np.arange(n) / fs
    path = tmp_path / "holes.csv"
    path.write_text(
        "t,g\n"
        + "".join(
            f"{a!r},{b!r}\n" for a, b in zip(t[keep].tolist(), rate[keep].tolist(), strict=True)
        )
    )
    js = tmp_path / "h.json"
    assert main(["allan", str(path), "--fill-gaps", "--no-confidence", "--json", str(js)]) == 0
    assert "filled with NaN rows" in capsys.readouterr().err
    marked = np.where(keep, rate, np.nan)
    ref = gyrobias.allan.adev(marked, fs, confidence=None, gaps="omit")
    doc = json.loads(js.read_text())
    np.testing.assert_array_equal(doc["axes"][0]["taus"], ref.taus)
    np.testing.assert_allclose(doc["axes"][0]["deviation"], ref.adev, rtol=1e-15)

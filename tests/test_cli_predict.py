"""Tests of the ``predict`` and ``experiment table1`` subcommands and the demo section."""

from __future__ import annotations

import argparse

import numpy as np
import pytest

from gyrobias.cli import experiment_table1
from gyrobias.cli import predict as cli_predict
from tests.reference_predict import arfima_type2


def _parser():
    parser = argparse.ArgumentParser(prog="gyrobias")
    sub = parser.add_subparsers(dest="command", required=True)
    cli_predict.register(sub)
    exp = sub.add_parser("experiment").add_subparsers(dest="experiment", required=True)
    experiment_table1.register_experiment(exp)
    return parser


def _log(tmp_path, n=6000):
    rng = np.random.default_rng(0)
    gz = 0.05 + arfima_type2(n, 0.5, 0.01, 1, rng)[0] + 0.002 * rng.standard_normal(n)
    t = np.arange(n) / 100.0
    path = tmp_path / "log.csv"
    np.savetxt(
        path, np.column_stack([t, gz * 0.5, gz]), delimiter=",", header="t,gx,gz", comments=""
    )
    return path, gz


def test_predict_cli_on_csv(tmp_path, capsys):
    path, gz = _log(tmp_path)
    png = tmp_path / "win.png"
    args = _parser().parse_args(
        [
            "predict",
            str(path),
            "--fs",
            "100",
            "--column",
            "gz",
            "--calibration",
            "1000",
            "--horizon",
            "1000",
            "--plot",
            str(png),
        ]
    )
    assert args.func(args) == 0
    out = capsys.readouterr().out
    assert "3 sections" in out and "fractional Kalman" in out and "KF/CM" in out
    assert png.exists() and png.stat().st_size > 1000
    # The printed CM statistics are those of the column read.
    from gyrobias.predict import evaluate

    ev = evaluate(gz, calibration=1000, horizon=1000, methods=("cm",))
    assert f"{ev.methods['cm'].mean_rsse:.4g}" in out


def test_predict_cli_bad_column(tmp_path):
    path, _ = _log(tmp_path, 3000)
    args = _parser().parse_args(["predict", str(path), "--fs", "100", "--column", "nope"])
    with pytest.raises(ValueError, match="nope"):
        args.func(args)
    args = _parser().parse_args(["predict", str(tmp_path / "missing.npy"), "--fs", "100"])
    with pytest.raises(FileNotFoundError):
        args.func(args)


def test_predict_cli_npy(tmp_path, capsys):
    _, gz = _log(tmp_path, 4000)
    path = tmp_path / "log.npy"
    np.save(path, gz)
    args = _parser().parse_args(
        ["predict", str(path), "--fs", "100", "--calibration", "500", "--horizon", "500"]
    )
    assert args.func(args) == 0
    assert "4 sections" in capsys.readouterr().out


def test_table1_cli_prints_paper_and_ratios(monkeypatch, capsys):
    # The library uses the core generator (gyrobias.fractional.arfima); here the NumPy
    # reference generator stands in so the report format is tested independently of it.
    def fake(runs, n, sigma, seed, bias=0.0):
        return bias + arfima_type2(n, 0.5, sigma, runs, np.random.default_rng(seed))

    monkeypatch.setattr(experiment_table1, "simulate", fake)
    args = _parser().parse_args(["experiment", "table1", "--runs", "200", "--seed", "3"])
    assert args.func(args) == 0
    out = capsys.readouterr().out
    assert "KF/CM mean RSSE" in out and "0.9820" in out and "2280" in out


def test_table1_with_core_generator(capsys):
    from gyrobias import fractional

    # The experiment's data are the core generator's type-II ARFIMA(0, 1/2, 0) series.
    expected = fractional.arfima(50, 0.5, sigma=2.0, size=3, seed=1, kind="type2")
    np.testing.assert_array_equal(experiment_table1.simulate(3, 50, 2.0, 1), expected)
    args = _parser().parse_args(["experiment", "table1", "--runs", "300", "--seed", "1"])
    assert args.func(args) == 0
    out = capsys.readouterr().out
    # "  KF/CM mean RSSE   ours ± s.e.   paper   expected": the simulated ratio agrees with the
    # exact expectation within 4 bootstrap standard errors (a 6e-5 two-sided false alarm).
    rows = [line.split() for line in out.splitlines() if "/CM mean RSSE" in line]
    assert [r[0] for r in rows] == ["KF/CM", "MA/CM"]
    for row in rows:
        ours, se, expected_ratio = float(row[3]), float(row[5]), float(row[7])
        assert se > 0
        assert abs(ours - expected_ratio) < 4 * se, row


def test_demo_section(tmp_path, capsys):
    rng = np.random.default_rng(1)
    n = 30_000
    rate = np.column_stack(
        [arfima_type2(n, 0.5, 1e-3, 1, rng)[0] + 1e-3 * rng.standard_normal(n) for _ in range(3)]
    )
    cli_predict.demo_section(rate, 100.0, tmp_path)
    out = capsys.readouterr().out
    assert "bias prediction" in out and "KF/CM" in out
    assert (tmp_path / "bias_prediction.png").exists()

"""Tests of the gyrobias command line, run in-process through gyrobias.cli.main."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import gyrobias
from gyrobias.cli import main
from gyrobias.cli.allan import ProgressBar

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _csv(
    path: Path, n: int = 4000, fs: float = 100.0, *, ns: bool = False, gap_at: int | None = None
) -> Path:
    rng = np.random.default_rng(3)
    x = rng.normal(0.0, 0.05, (n, 3))
    if ns:
        t = 1_700_000_000_000_000_000 + np.arange(n, dtype=np.int64) * int(round(1e9 / fs))
        if gap_at is not None:
            t[gap_at:] += 2_000_000_000
        stamps = [str(v) for v in t]
        head = "time_ns,gx,gy,gz"
    else:
        tt = np.arange(n) / fs
        if gap_at is not None:
            tt[gap_at:] += 2.0
        stamps = [f"{v:.6f}" for v in tt]
        head = "t,gx,gy,gz"
    rows = (f"{s},{a:.8f},{b:.8f},{c:.8f}" for s, (a, b, c) in zip(stamps, x.tolist()))
    path.write_text(head + "\n" + "\n".join(rows) + "\n")
    return path


def test_version(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"gyrobias {gyrobias.__version__}"


def test_help_lists_subcommands(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    assert "allan" in out and "demo" in out


def test_no_command_is_a_usage_error(capsys: pytest.CaptureFixture[str]) -> None:
    assert main([]) == 2
    assert "required: COMMAND" in capsys.readouterr().err


def test_allan_table_json_and_plot(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    log = _csv(tmp_path / "log.csv")
    out_json, out_png = tmp_path / "out.json", tmp_path / "out.png"
    code = main(
        [
            "allan",
            str(log),
            "--columns",
            "gx,gz",
            "--units",
            "deg/s",
            "--no-confidence",
            "--json",
            str(out_json),
            "--plot",
            str(out_png),
        ]
    )
    captured = capsys.readouterr()
    assert code == 0, captured.err
    out = captured.out
    assert "fs = 100 Hz, estimated from the time column 't'" in out
    assert "ADEV of gx [deg/s]" in out and "ADEV of gz [deg/s]" in out and "ADEV of gy" not in out
    assert "tau [s]" in out
    assert captured.err == ""  # regular sampling: no warnings

    # the printed table is the library's result, row by row
    expected = gyrobias.allan.adev(
        gyrobias.io.load(log, columns=["gx"]).data[:, 0], 100.0, confidence=None
    )
    assert isinstance(expected, gyrobias.AllanResult)
    for tau, dev in zip(expected.taus, expected.adev):
        assert f"{tau:12.6g} {dev:22.6e}" in out

    doc = json.loads(out_json.read_text())
    assert doc["command"] == "allan" and doc["kind"] == "adev"
    assert doc["fs_hz"] == 100.0 and doc["fs_source"] == "timestamps"
    assert doc["units"] == "deg/s" and doc["columns"] == ["gx", "gz"]
    assert doc["sampling"]["n_samples"] == 4000 and doc["sampling"]["n_gaps"] == 0
    assert [a["axis"] for a in doc["axes"]] == ["gx", "gz"]
    np.testing.assert_allclose(doc["axes"][0]["deviation"], expected.adev, rtol=1e-15)
    np.testing.assert_allclose(doc["axes"][0]["taus"], expected.taus, rtol=1e-15)
    assert doc["axes"][0]["unit"] == "deg/s"

    data = out_png.read_bytes()
    assert data.startswith(PNG_SIGNATURE) and len(data) > 20_000


def test_allan_with_confidence_intervals(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The default run (68.3 % intervals): CI columns and noise types in table and JSON."""
    log = _csv(tmp_path / "log.csv")
    out_json = tmp_path / "ci.json"
    code = main(
        [
            "allan",
            str(log),
            "--units",
            "deg/s",
            "--json",
            str(out_json),
            "--plot",
            str(tmp_path / "ci.png"),
        ]
    )
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert "CI low" in captured.out and "CI high" in captured.out
    assert "68.3 % confidence intervals" in captured.out
    assert "white rate (angle random walk)" in captured.out  # the simulated noise is white
    doc = json.loads(out_json.read_text())
    axis = doc["axes"][0]
    assert doc["confidence"] == 0.683
    low, dev, high = (np.array(axis[k]) for k in ("ci_low", "deviation", "ci_high"))
    assert np.all(low < dev) and np.all(dev < high)
    assert len(axis["noise_type"]) == len(axis["taus"])


def test_allan_kinds_and_options(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    log = _csv(tmp_path / "log.csv")
    for kind in ("mdev", "hdev", "totdev"):
        assert main(["allan", str(log), "--kind", kind, "--no-confidence", "--columns", "gy"]) == 0
        assert f"{kind.upper()} of gy" in capsys.readouterr().out
    assert (
        main(
            [
                "allan",
                str(log),
                "--non-overlapping",
                "--no-confidence",
                "--taus",
                "all",
                "--columns",
                "gx",
            ]
        )
        == 0
    )
    out = capsys.readouterr().out
    assert "(non-overlapping)" in out
    non = gyrobias.allan.adev(
        gyrobias.io.load(log, columns=["gx"]).data[:, 0],
        100.0,
        taus="all",
        overlapping=False,
        confidence=None,
    )
    assert isinstance(non, gyrobias.AllanResult)
    assert out.count("\n") >= len(non.taus)  # every m printed
    assert (
        main(
            [
                "allan",
                str(log),
                "--taus",
                "log",
                "--per-decade",
                "3",
                "--no-confidence",
                "--columns",
                "gx",
            ]
        )
        == 0
    )


def test_allan_ns_time_column_and_gap_warning(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    log = _csv(tmp_path / "ns.csv", ns=True, gap_at=1000)
    out_json = tmp_path / "g.json"
    assert main(["allan", str(log), "--no-confidence", "--json", str(out_json)]) == 0
    captured = capsys.readouterr()
    assert "estimated from the time column 'time_ns' (read as ns" in captured.out
    assert captured.err.startswith("gyrobias: warning: 1 gap(s) in the timestamps")
    doc = json.loads(out_json.read_text())
    assert doc["sampling"]["gap_rows"] == [1000]
    assert doc["sampling"]["warnings"] and doc["sampling"]["time_unit"] == "ns"


def test_allan_fs_option_and_disagreement(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    log = _csv(tmp_path / "log.csv")
    assert main(["allan", str(log), "--fs", "50", "--no-confidence"]) == 0
    captured = capsys.readouterr()
    assert "estimated from the time column" not in captured.out
    assert "at 50 Hz" in captured.out
    assert (
        "gyrobias: warning: given fs = 50 Hz disagrees with the timestamps (100 Hz)" in captured.err
    )


def test_allan_npy_needs_fs(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    np.save(tmp_path / "r.npy", np.random.default_rng(0).normal(size=(3000, 2)))
    assert main(["allan", str(tmp_path / "r.npy")]) == 2
    err = capsys.readouterr().err
    assert err.startswith(
        "gyrobias: error: r.npy has no time column: give the sample rate with --fs"
    )
    assert err.count("\n") == 1
    assert (
        main(
            ["allan", str(tmp_path / "r.npy"), "--fs", "200", "--no-confidence", "--units", "rad/s"]
        )
        == 0
    )
    assert "ADEV of col1 [rad/s]" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["allan", "{tmp}/missing.csv"], "no such file"),
        (
            ["allan", "{log}", "--columns", "gx,wz"],
            "unknown column 'wz' in log.csv; available: t, gx, gy, gz",
        ),
        (
            ["allan", "{log}", "--kind", "mdev", "--non-overlapping"],
            "--non-overlapping applies to --kind adev and hdev only",
        ),
        (
            ["allan", "{log}", "--confidence", "1.5"],
            "--confidence must be a number strictly between 0 and 1, got '1.5'",
        ),
        (["allan", "{log}", "--fs", "-3"], "--fs must be finite and > 0, got '-3'"),
        (
            ["allan", "{log}", "--per-decade", "0", "--taus", "log"],
            "--per-decade must be an integer >= 1, got '0'",
        ),
        (["allan", "{bad}"], "'x' (not a number) in column 'gy' at line 3"),
        (["allan", "{log}", "--time-column", "t", "--no-time-column"], "contradict"),
        (
            ["allan", "{log}", "--no-confidence", "--plot", "{tmp}/no/such/dir/p.png"],
            "No such file or directory",
        ),
    ],
)
def test_errors_are_one_clean_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], argv: list[str], message: str
) -> None:
    log = _csv(tmp_path / "log.csv", n=300)
    bad = tmp_path / "bad.csv"
    bad.write_text("t,gx,gy\n0,1,2\n0.01,2,x\n")
    args = [a.format(tmp=tmp_path, log=log, bad=bad) for a in argv]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.startswith("gyrobias: error: ")
    assert message in err
    assert err.count("\n") == 1 and "Traceback" not in err


def test_usage_errors_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["allan"]) == 2
    assert "required: LOG" in capsys.readouterr().err
    assert main(["allan", "x.csv", "--kind", "xdev"]) == 2
    assert "invalid choice: 'xdev'" in capsys.readouterr().err


def test_traceback_flag_reraises(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError):
        main(["--traceback", "allan", str(tmp_path / "missing.csv")])


def test_progress_bar(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    log = _csv(tmp_path / "log.csv")
    assert main(["allan", str(log), "--no-confidence", "--progress"]) == 0
    err = capsys.readouterr().err
    assert "adev of 4000 samples × 3:" in err and "100 %" in err  # forced on, although not a TTY
    assert "reading log.csv:" in err
    # no progress output unless asked for (stderr is not a terminal here), nor with --no-progress
    assert main(["allan", str(log), "--no-confidence"]) == 0
    assert capsys.readouterr().err == ""
    assert main(["allan", str(log), "--no-confidence", "--no-progress"]) == 0
    assert capsys.readouterr().err == ""


class _FakeTTY:
    def __init__(self) -> None:
        self.text = ""

    def write(self, s: str) -> int:
        self.text += s
        return len(s)

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return True


def test_progress_bar_redraws_in_place_on_a_terminal() -> None:
    tty = _FakeTTY()
    bar = ProgressBar("work", stream=tty)
    bar(0.0)
    bar(0.5)
    bar(1.0)
    bar.close()
    assert tty.text.count("\r") >= 3
    assert " 50 %" in tty.text and "100 %" in tty.text


def test_python_dash_m(tmp_path: Path) -> None:
    # Run the gyrobias that this test imported (installed, or the source tree in development).
    env = {"PYTHONPATH": str(Path(gyrobias.__file__).parent.parent), "PATH": "/usr/bin:/bin"}
    proc = subprocess.run(
        [sys.executable, "-m", "gyrobias", "allan", str(tmp_path / "none.csv")],
        capture_output=True,
        text=True,
        env=env,
        check=False,
    )
    assert proc.returncode == 2
    assert proc.stderr == f"gyrobias: error: no such file: '{tmp_path / 'none.csv'}'\n"


def test_demo(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    outdir = tmp_path / "demo"
    assert main(["demo", "--outdir", str(outdir), "--hours", "0.5", "--seed", "1"]) == 0
    out = capsys.readouterr().out
    assert "True noise terms" in out and "ARW" in out and "deg/√h" in out
    assert "ADEV of axis x [deg/s]" in out and "ADEV of axis z" in out
    assert "CI low" in out
    png = (outdir / "allan.png").read_bytes()
    assert png.startswith(PNG_SIGNATURE) and len(png) > 20_000
    rate = np.load(outdir / "demo_log.npy")
    assert rate.shape == (180_000, 3)
    # the simulated ARW shows at τ = t0: σ(t0) = N/√t0 with N = 0.30/60 deg/√s for axis x.
    # The estimator's relative scatter is ≈ 1/√(2·edf) ≈ 0.2 % (edf ≈ 9·10^4 of 1.8·10^5
    # samples), bias instability adds (0.664·B/σ)²/2 ≈ 0.02 %; 2 % is ten times the scatter.
    x = gyrobias.allan.adev(rate[:, 0], 100.0, taus=[0.01], confidence=None)
    assert isinstance(x, gyrobias.AllanResult)
    assert x.adev[0] == pytest.approx(0.30 / 60.0 / np.sqrt(0.01), rel=0.02)


@pytest.mark.parametrize("spelling", ["\\t", "tab", "\t"])
def test_tab_delimiter_spellings(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], spelling: str
) -> None:
    path = tmp_path / "log.txt"
    path.write_text("t\tg\n" + "".join(f"{i / 10}\t{(-1) ** i}\n" for i in range(200)))
    assert main(["allan", str(path), "--delimiter", spelling, "--no-confidence"]) == 0
    assert "estimated from the time column 't'" in capsys.readouterr().out


def test_allan_fit_kalibr_and_per_axis_fit_plots(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    import yaml

    rate = gyrobias.noise.simulate(
        200_000, 100.0, arw=0.3 / 60, bias_instability=5 / 3600, axes=2, seed=4
    )
    np.save(tmp_path / "g.npy", rate)
    png, imu, js = tmp_path / "fit.png", tmp_path / "imu.yaml", tmp_path / "a.json"
    code = main(
        [
            "allan",
            str(tmp_path / "g.npy"),
            "--fs",
            "100",
            "--units",
            "deg/s",
            "--fit",
            "--kalibr",
            str(imu),
            "--plot",
            str(png),
            "--json",
            str(js),
        ]
    )
    assert code == 0
    out = capsys.readouterr().out
    assert "angle random walk" in out and "deg/√h" in out
    # Several axes: the combined plot plus one fitted-model plot per axis.
    for path in (png, tmp_path / "fit_col0.png", tmp_path / "fit_col1.png"):
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 10_000
    doc = yaml.safe_load(imu.read_text())
    # N = 0.3 deg/√h = 0.3/60·π/180 rad/s/√Hz ≈ 8.7e-5; the fit recovers it within a few %.
    assert doc["gyroscope_noise_density"] == pytest.approx(0.3 / 60 * np.pi / 180, rel=0.05)
    assert doc["update_rate"] == 100
    assert len(json.loads(js.read_text())["noise_coefficients"]) == 2

"""One export path (issue 26 item 3): the Python API, the CLI (``--export``, the deprecated
``--kalibr`` alias) and the HTML report write every estimator format from the same code, so
the same log gives the same files — here a real-like log whose z axis does not show its rate
random walk (K bounded, marked in every file)."""

from __future__ import annotations

import html
import json
import re
from pathlib import Path

import numpy as np
import pytest
import yaml

import gyrobias
from gyrobias.cli import main
from gyrobias.exports import DEFAULT_FILENAMES, FORMATS
from gyrobias.report import build_report

FS = 100.0
N = 120_000


@pytest.fixture(scope="module")
def log_path(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """20 min at 100 Hz, deg/s: x and y with a visible rate random walk, z (noisier, no K)
    with none — its K is bounded, and its bound is the largest over the axes."""
    sim = gyrobias.noise.simulate
    x = sim(N, FS, arw=0.2 / 60, bias_instability=3 / 3600, rrw=1.5e-4, seed=14)
    y = sim(N, FS, arw=0.2 / 60, bias_instability=3 / 3600, rrw=1.5e-4, seed=15)
    z = sim(N, FS, arw=2.0 / 60, bias_instability=3 / 3600, seed=13)
    t = np.arange(N) / FS
    path = tmp_path_factory.mktemp("paths") / "imu.csv"
    rows = np.column_stack([t, x, y, z])
    np.savetxt(path, rows, delimiter=",", header="t,gx,gy,gz", comments="", fmt="%.10g")
    return path


@pytest.fixture(scope="module")
def fits(log_path: Path) -> tuple[gyrobias.noise.NoiseCoefficients, ...]:
    log = gyrobias.io.load(log_path, units="deg/s")
    r = gyrobias.allan.adev(log.data, log.fs, units="deg/s", axis_names=list(log.columns))
    out = gyrobias.noise.fit(r)
    assert [c.K.bounded for c in out] == [False, False, True], [str(c.K) for c in out]
    bound = out[2].K.upper_bound
    assert bound is not None and all(bound > (c.K.value or 0.0) for c in out[:2])
    return out


@pytest.fixture(scope="module")
def api(fits: tuple[gyrobias.noise.NoiseCoefficients, ...]) -> dict[str, str]:
    return gyrobias.exports.export_all(list(fits))


def _numbers(text: str) -> list[float]:
    return [float(v) for v in re.findall(r"-?\d+\.\d+e[+-]\d+", text)]


def test_every_format_writes_and_marks_the_bound(
    api: dict[str, str], fits: tuple[gyrobias.noise.NoiseCoefficients, ...], tmp_path: Path
) -> None:
    assert set(api) == set(FORMATS)
    for fmt, text in api.items():
        assert "UPPER BOUND" in text, fmt
    kalibr = yaml.safe_load(api["kalibr"])
    bound = fits[2].K.to("rad/s²/√Hz").upper_bound
    assert kalibr["gyroscope_random_walk"] == pytest.approx(bound, rel=1e-6)
    vins = yaml.safe_load(api["vins"].replace("%YAML:1.0\n", ""))
    assert vins["gyr_w"] == pytest.approx(bound / np.sqrt(FS), rel=1e-6)
    doc = json.loads(api["json"])
    assert doc["estimator_values"]["gyro"]["K"]["upper_bound"] is True
    assert doc["estimator_values"]["gyro"]["N"]["upper_bound"] is False
    for fmt in FORMATS:
        with pytest.raises(ValueError, match="only bounded"):
            gyrobias.exports.export(list(fits), fmt, strict=True)
    # The keyword Kalibr writer is the same code.
    assert gyrobias.exports.write_kalibr(tmp_path / "k.yaml", gyro=list(fits)) == api["kalibr"]


def test_api_cli_and_report_write_the_same_files(
    log_path: Path, api: dict[str, str], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "cli"
    common = ["allan", str(log_path), "--units", "deg/s", "--no-progress", "--fit"]
    assert main([*common, "--export", f"all={out}"]) == 0
    err = capsys.readouterr().err
    assert "upper bounds written" in err
    cli = {fmt: (out / name).read_text() for fmt, name in DEFAULT_FILENAMES.items()}
    # The deprecated alias routes to the same writer.
    alias = tmp_path / "alias.yaml"
    assert main([*common, "--kalibr", str(alias)]) == 0
    assert "deprecated" in capsys.readouterr().err
    assert alias.read_text() == api["kalibr"]
    # --strict refuses the bound: exit 2, one line, no file.
    strict = tmp_path / "strict.yaml"
    assert main([*common, "--export", f"kalibr={strict}", "--strict"]) == 2
    msg = capsys.readouterr().err.strip().splitlines()
    assert msg[-1].startswith("gyrobias: error:") and "only bounded" in msg[-1]
    assert not strict.exists()

    log = gyrobias.io.load(log_path, units="deg/s")
    page = build_report(log)
    blocks = re.findall(r'<code id="export-(\d+)">(.*?)</code>', page, flags=re.S)
    report = {fmt: html.unescape(text) for fmt, (_, text) in zip(FORMATS, blocks)}
    assert "contains upper bounds" in page
    for fmt in FORMATS:
        assert cli[fmt] == api[fmt], fmt
        assert report[fmt] == api[fmt], fmt
        assert _numbers(api[fmt]), fmt


def test_bound_confidence_is_written_in_every_mark(
    log_path: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # The level is the caller's (bound_confidence / --bound-confidence), and every file, the
    # CLI and the report say it in their UPPER BOUND marks.
    log = gyrobias.io.load(log_path, units="deg/s")
    r = gyrobias.allan.adev(log.data, log.fs, units="deg/s", axis_names=list(log.columns))
    fits = gyrobias.noise.fit(r, bound_confidence=0.8)
    assert fits[2].K.bounded and fits[2].K.bound_confidence == 0.8
    api = gyrobias.exports.export_all(list(fits))
    for fmt, text in api.items():
        marks = [line for line in text.splitlines() if "UPPER BOUND" in line]
        assert marks, fmt
        assert all("80 %" in line and "95 %" not in line for line in marks), (fmt, marks)
    out = tmp_path / "cli"
    common = ["allan", str(log_path), "--units", "deg/s", "--no-progress", "--fit"]
    assert main([*common, "--bound-confidence", "0.8", "--export", f"all={out}"]) == 0
    assert "80 % upper bound" in capsys.readouterr().out
    for fmt, name in DEFAULT_FILENAMES.items():
        assert (out / name).read_text() == api[fmt], fmt
    page = build_report(log, bound_confidence=0.8)
    assert "(upper bound, 80 %)" in page
    blocks = re.findall(r'<code id="export-(\d+)">(.*?)</code>', page, flags=re.S)
    for fmt, (_, text) in zip(FORMATS, blocks):
        assert html.unescape(text) == api[fmt], fmt
    html_out = tmp_path / "report.html"
    report_cli = ["report", str(log_path), "--units", "deg/s", "-o", str(html_out)]
    assert main([*report_cli, "--bound-confidence", "0.8"]) == 0
    assert "(upper bound, 80 %)" in html_out.read_text()
    capsys.readouterr()
    # Out of (0, 1): exit 2 with one line naming the option, also when nothing is fitted.
    for argv in (
        [*common, "--bound-confidence", "1.5"],
        ["allan", str(log_path), "--units", "deg/s", "--no-progress", "--bound-confidence", "0"],
        [*report_cli, "--bound-confidence", "1"],
    ):
        assert main(argv) == 2, argv
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("gyrobias: error:"), err
        assert "bound-confidence" in err[0] or "bound_confidence" in err[0], err
    with pytest.raises(ValueError, match="bound_confidence"):
        build_report(log, bound_confidence=1.0)

"""``gyrobias report``: the HTML page parsed, rendered in headless Chromium, and its CLI;
``gyrobias allan --export``."""

from __future__ import annotations

import base64
import json
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

import gyrobias
from gyrobias import io, report
from gyrobias.cli import main


class Collector(HTMLParser):
    """Tags, attributes and text of a page (the standard library's parser, nothing to install)."""

    def __init__(self) -> None:
        super().__init__()
        self.tags: list[tuple[str, dict[str, str | None]]] = []
        self.text: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.tags.append((tag, dict(attrs)))

    def handle_data(self, data: str) -> None:
        self.text.append(data)


def demo_log(tmp_path: Path) -> Path:
    """A gyro log like the demo's (.npy, deg/s, no time column) and a 6-axis CSV with time."""
    rate = gyrobias.noise.simulate(
        120_000, 100.0, arw=0.3 / 60, bias_instability=5 / 3600, rrw=300 / 216000, axes=2, seed=4
    )
    np.save(tmp_path / "demo_log.npy", rate)
    return tmp_path / "demo_log.npy"


def parse(text: str) -> Collector:
    c = Collector()
    c.feed(text)
    c.close()
    return c


def test_report_is_self_contained_and_complete(tmp_path: Path) -> None:
    path = demo_log(tmp_path)
    log = io.load(path, fs=100.0)
    html = report.build_report(log, units="deg/s", title="demo")
    page = parse(html)
    tags = [t for t, _ in page.tags]
    text = "".join(page.text)
    # No network: no external script, style sheet, font or image.
    for tag, attrs in page.tags:
        for key in ("src", "href"):
            value = attrs.get(key)
            assert value is None or value.startswith("data:"), (tag, key, value)
    assert (
        "@import" not in html
        and "url(" not in html
        and "http://" not in html.replace("http://www.w3.org", "")
    )
    # One embedded SVG plot per channel, each a valid SVG document.
    images = [a["src"] for t, a in page.tags if t == "img"]
    assert len(images) == 2
    for src in images:
        assert src is not None and src.startswith("data:image/svg+xml;base64,")
        svg = base64.b64decode(src.split(",", 1)[1]).decode()
        assert svg.startswith("<svg") and svg.rstrip().endswith("</svg>")
    assert (
        tags.count("table") >= 1 + 2 * 2
    )  # log summary, coefficients and conservative per channel
    for needle in (
        "Log and timestamps",
        "angle random walk",
        "Conservative set",
        "inflation",
        "χ²/ν",
        "@page",
        "A4",
    ):
        assert needle in html, needle
    # Every export, best fit and conservative, as copyable text.
    codes = [a.get("id") for t, a in page.tags if t == "code" and a.get("id")]
    assert len(codes) == 2 * len(gyrobias.exports.FORMATS)
    assert text.count("gyroscope_noise_density") >= 4 and "imuSensor(" in text
    assert tags.count("button") == len(codes)


def test_report_without_units_and_with_failures(tmp_path: Path) -> None:
    rate = np.column_stack(
        [gyrobias.noise.simulate(20_000, 50.0, arw=0.01, seed=1), np.zeros(20_000)]
    )
    path = tmp_path / "log.csv"
    t = np.arange(20_000) / 50.0
    np.savetxt(path, np.column_stack([t, rate]), delimiter=",", header="time,gx,flat", comments="")
    log = io.load(path)
    html = report.build_report(log)
    assert "No exports" in html and "noise fit failed" in html  # constant channel: a clear message
    assert "timestamps read as" in html
    with pytest.raises(ValueError, match="units has 1 entries for 2 channels"):
        report.build_report(log, units=["deg/s"])


def _chromium() -> str | None:
    return (
        shutil.which("chromium")
        or shutil.which("chromium-browser")
        or shutil.which("google-chrome")
    )


@pytest.mark.skipif(
    _chromium() is None, reason="needs Chromium (.ci/run installs the Debian package)"
)
def test_report_renders_in_headless_chromium(tmp_path: Path) -> None:
    import matplotlib.image

    html_path = tmp_path / "report.html"
    assert (
        main(
            [
                "report",
                str(demo_log(tmp_path)),
                "--fs",
                "100",
                "--units",
                "deg/s",
                "-o",
                str(html_path),
            ]
        )
        == 0
    )
    shot = tmp_path / "shot.png"
    browser = _chromium()
    assert browser is not None
    subprocess.run(
        [
            browser,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--window-size=1000,1800",
            f"--screenshot={shot}",
            html_path.as_uri(),
        ],
        check=True,
        capture_output=True,
        timeout=120,
    )
    image = matplotlib.image.imread(shot)[..., :3]
    assert image.shape[0] == 1800 and image.shape[1] == 1000
    ink = np.mean(image < 0.6)  # dark pixels: text, plot lines
    colour = np.mean(np.ptp(image, axis=2) > 0.3)  # saturated pixels: the plot's model lines
    # A blank or error page has (almost) no ink and no colour; the report has a plot on screen.
    assert 0.005 < ink < 0.5, ink
    assert colour > 1e-4, colour


def test_report_cli_defaults_and_errors(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = demo_log(tmp_path)
    assert main(["report", str(path), "--fs", "100", "--units", "deg/s,deg/s"]) == 0
    out = path.with_suffix(".html")
    assert out.is_file() and "wrote" in capsys.readouterr().out
    assert main(["report", str(path)]) == 2  # no fs, no time column
    err = capsys.readouterr().err
    assert err.startswith("gyrobias: error:") and "--fs" in err and "Traceback" not in err


def test_allan_export_cli(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = demo_log(tmp_path)
    vins = tmp_path / "vins.yaml"
    alld = tmp_path / "all"
    code = main(
        [
            "allan",
            str(path),
            "--fs",
            "100",
            "--units",
            "deg/s",
            "--export",
            f"vins={vins}",
            "--export",
            f"all={alld}",
            "--export-rate",
            "200",
        ]
    )
    assert code == 0
    assert "gyr_n" in vins.read_text() and "200 Hz" in vins.read_text()
    assert sorted(p.name for p in alld.iterdir()) == sorted(
        gyrobias.exports.DEFAULT_FILENAMES.values()
    )
    assert json.loads((alld / "noise.json").read_text())["rate_hz"] == 200.0
    argv = ["allan", str(path), "--fs", "100", "--units", "deg/s", "--export", "rovio=x.yaml"]
    capsys.readouterr()
    assert main(argv) == 2  # usage errors: one line, exit 2
    assert capsys.readouterr().err.startswith("gyrobias: error: --export must be FMT=PATH")
    assert main(["allan", str(path), "--fs", "100", "--export", f"json={tmp_path / 'j.json'}"]) == 2
    assert "data unit" in capsys.readouterr().err

"""The whole user path on real sensor logs (tests/data/real_logs: x-io NGIMU and x-IMU3 logs
shipped by scikit-kinematics 0.10.4, BSD-3-Clause): loading x-io headers, the default fit of a
log too short to show B/K/R, every export and the report with every format's file."""

from __future__ import annotations

import hashlib
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

import gyrobias
from gyrobias import allan, exports, noise
from gyrobias.cli import main

DATA = Path(__file__).parent / "data" / "real_logs"
NGIMU = DATA / "ngimu_sensors.csv"
XIMU3 = DATA / "ximu3_inertial.csv"
SHA256 = {
    NGIMU: "5bb127f5886477f71e405df9662e61291ecc6a2b9f01751a1983d87d8f32b38d",
    XIMU3: "6f7a9f0ead32451ce8e881650a3702757ac17228a9bb38fc246cb6044c24f6ee",
}
#: Rows of the NGIMU log at rest (moved before: gyro up to 60 deg/s), see the README.
STATIC = slice(179, 499)


class _Page(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.classes: list[tuple[str, str]] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.classes += [(tag, c) for c in (dict(attrs).get("class") or "").split()]


def _static_csv(tmp_path: Path) -> Path:
    """The NGIMU log's static rows, header kept (what a user cuts out of such a log)."""
    lines = NGIMU.read_text().splitlines(keepends=True)
    out = tmp_path / "ngimu_static.csv"
    out.write_text(lines[0] + "".join(lines[1:][STATIC]))
    return out


def test_files_are_the_published_ones() -> None:
    for path, digest in SHA256.items():
        assert hashlib.sha256(path.read_bytes()).hexdigest() == digest, path.name


def test_x_io_headers_give_time_rate_and_units() -> None:
    ngimu = gyrobias.io.load(NGIMU, columns=[1, 2, 3])
    assert ngimu.time_column == "Time (s)" and ngimu.sampling.time_unit == "s"
    assert ngimu.fs == pytest.approx(49.91, abs=0.01)
    assert ngimu.units == ("deg/s",) * 3
    ximu3 = gyrobias.io.load(XIMU3)
    assert ximu3.time_column == "Timestamp (us)" and ximu3.sampling.time_unit == "us"
    assert ximu3.fs == pytest.approx(49.91, abs=0.01)
    assert ximu3.units == ("deg/s",) * 3 + ("g",) * 3


def test_default_fit_of_the_static_segment_bounds_what_the_log_cannot_show() -> None:
    log = gyrobias.io.load(NGIMU, columns=[1, 2, 3])
    rate = np.asarray(log.data)[STATIC]
    fits = noise.fit(allan.adev(rate, log.fs, units="deg/s"))
    gm = noise.gmwm(rate, log.fs, units="deg/s")
    assert isinstance(fits, tuple) and isinstance(gm, tuple)
    for c, g in zip(fits, gm):
        # ARW 0.8–1.5 deg/√h (0.0137–0.0233 deg/√s on this unit); fit and GMWM agree to 10 %.
        assert 0.5 < c.N.to("deg/sqrt(h)").value < 2.0
        assert g.N.value == pytest.approx(c.N.value, rel=0.1)
        # 6.4 s cannot show a rate random walk: bounded from above, never zero or refused.
        assert c.K.upper_bound is not None and c.K.upper_bound > 0
    wv = noise.wvar(rate, log.fs, units="deg/s", robust=True)
    assert isinstance(wv, tuple) and all(np.all(w.ci_low <= w.ci_high) for w in wv)


def test_every_export_writes_the_static_segments_fit(tmp_path: Path) -> None:
    log = gyrobias.io.load(_static_csv(tmp_path), columns=[1, 2, 3])
    c = noise.fit(allan.adev(log.data, log.fs, units="deg/s"))
    assert isinstance(c, tuple)
    for fmt in exports.FORMATS:
        text = exports.export(c, fmt, rate=log.fs)
        assert "UPPER BOUND" in text, fmt  # K is only bounded: written, and marked
        assert c[0].export(fmt)
    with pytest.raises(ValueError, match="strict"):
        exports.export(c, "kalibr", strict=True)
    assert (
        main(["allan", str(log.path), "--columns", "1,2,3", "--export", f"all={tmp_path / 'x'}"])
        == 0
    )
    assert len(list((tmp_path / "x").iterdir())) == len(exports.FORMATS)


@pytest.mark.parametrize("which", ["ngimu_static", "ximu3_moving"])
def test_report_shows_every_formats_file(tmp_path: Path, which: str) -> None:
    path = _static_csv(tmp_path) if which == "ngimu_static" else XIMU3
    out = tmp_path / "report.html"
    assert main(["report", str(path), "--columns", "1,2,3", "-o", str(out)]) == 0
    page = _Page()
    page.feed(out.read_text())
    # Best fit and conservative set: every format's file each, no error paragraph (the
    # report's error style marks only the files' "contains upper bounds" notes).
    assert page.classes.count(("div", "export")) == 2 * len(exports.FORMATS)
    assert ("p", "error") not in page.classes

"""The explorer in a real browser (issue 35): Playwright driving the system Chromium.

The app is served in-process on a free loopback port (and once through ``gyrobias explore
--no-browser --port 0`` in a subprocess); the test loads a simulated log and a ROS2 bag, selects
a part, removes a drift, switches a term off, types the τ range and downloads the Kalibr file,
then checks that the file, the coefficients on the page and the output of the page's
reproducing Python code (run in a subprocess) all equal what the library computes on the same
selection, and that the page made no request outside 127.0.0.1. Every wait is on an explicit
DOM state (a text, an element), never a sleep.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("panel")
playwright_sync = pytest.importorskip("playwright.sync_api")


def _chromium() -> str | None:
    return (
        os.environ.get("GYROBIAS_CHROMIUM")
        or shutil.which("chromium")
        or shutil.which("chromium-browser")
        or shutil.which("google-chrome")
    )


pytestmark = pytest.mark.skipif(
    _chromium() is None, reason="needs Chromium (.ci/run installs the Debian package)"
)

FS = 100.0
#: (start, stop, τ range) typed for the simulated log (10 min at 100 Hz) and the bag (2 min at
#: 200 Hz)
CSV_CHOICE = (60.0, 540.0, (0.02, 40.0))
BAG_CHOICE = (10.0, 110.0, (0.01, 10.0))
TIMEOUT = 60_000  # ms: first loads on a busy 2-core machine


def _simulated_log(path: Path) -> Path:
    from gyrobias import noise

    n = 60_000
    cols = [
        noise.simulate(n, FS, arw=0.2 / 60, bias_instability=3 / 3600, seed=s) for s in range(3)
    ]
    rate = np.column_stack(cols)
    rate += np.linspace(0.0, 0.05, n)[:, None]  # a drift to remove
    t = np.arange(n) / FS
    np.savetxt(path, np.column_stack([t, rate]), delimiter=",", header="time,gx,gy,gz", comments="")
    return path


def _bag(path: Path) -> Path:
    from tests.test_bags import imu_data, regular, write_bag

    n = 24_000
    return write_bag(path, "db3", regular(n, 200.0), imu_data(n, seed=5))


def _expected(
    path: Path, choice: tuple[float, float, tuple[float, float]], **load: Any
) -> tuple[list[str], str]:
    """The library's coefficients (summaries) and Kalibr file on the test's selection, computed
    with the public API directly (not through the app's state object)."""
    from gyrobias import allan, cleaning, exports, io, noise

    start, stop, tau = choice
    log = io.load(path, **load).select(start=start, stop=stop)
    data = cleaning.detrend(log.data, log.fs, order=1).data
    fits: list[Any] = []
    for unit, cols in log.unit_groups():
        names = [log.columns[c] for c in cols]
        results = allan.adev(
            data[:, cols], log.fs, taus="octave", confidence=0.683, units=unit, axis_names=names
        )
        fits += noise.fit(
            results, method="joint", terms=["Q", "N", "B", "K"], tau_range=tau, lines="auto"
        )
    gyro = [c for c in fits if c.sensor == "gyro"] or None
    accel = [c for c in fits if c.sensor == "accel"] or None
    text = exports.export(gyro, "kalibr", accel=accel, rostopic=log.topic or "/imu0")
    return [c.to("ieee").summary() for c in fits], text


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, Path, Path]]:
    from gyrobias.explore import load_sessions
    from gyrobias.explore.server import serve

    tmp = tmp_path_factory.mktemp("explore")
    csv = _simulated_log(tmp / "sim.csv")
    bag = _bag(tmp / "imu_bag")
    sessions, errors = load_sessions([csv], units="deg/s")
    more, more_errors = load_sessions([bag])
    assert not errors and not more_errors, (errors, more_errors)
    srv = serve(sessions + more, ["missing.csv: an input that could not be read"])
    try:
        yield srv.url, csv, bag
    finally:
        srv.stop()


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    with playwright_sync.sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=_chromium(), args=["--no-sandbox"])
        try:
            yield b
        finally:
            b.close()


def _tab(page: Any, name: str) -> None:
    page.locator(".bk-tab", has_text=re.compile(f"^{name}$")).click()


def _type(page: Any, cls: str, value: str) -> None:
    box = page.locator(f".{cls} input")
    box.fill(value)
    box.press("Enter")


def _drive(
    page: Any, log_label: str | None, choice: tuple[float, float, tuple[float, float]]
) -> None:
    """Select the part, remove a linear drift, switch R and GM off... and type the τ range."""
    expect = playwright_sync.expect
    start, stop, tau = choice
    if log_label is not None:
        page.locator(".gb-source select").select_option(label=log_label)
        expect(page.locator(".gb-sampling")).to_contain_text(log_label, timeout=TIMEOUT)
    _type(page, "gb-start", repr(start))
    _type(page, "gb-stop", repr(stop))
    steps = page.locator("ol.gb-steps")
    expect(steps).to_contain_text(f"part {start:g} s – {stop:g} s", timeout=TIMEOUT)
    page.locator(".gb-detrend button", has_text="linear").click()
    expect(steps).to_contain_text("linear drift removed", timeout=TIMEOUT)
    page.locator(".gb-terms button", has_text=re.compile("^R$")).click()
    expect(steps).to_contain_text("joint fit of Q,N,B,K,", timeout=TIMEOUT)
    _type(page, "gb-tau-min", repr(tau[0]))
    _type(page, "gb-tau-max", repr(tau[1]))
    expect(steps).to_contain_text(f"τ {tau[0]:g}–{tau[1]:g} s", timeout=TIMEOUT)


def _check(
    page: Any,
    tmp: Path,
    path: Path,
    choice: tuple[float, float, tuple[float, float]],
    **load: Any,
) -> None:
    expect = playwright_sync.expect
    summaries, kalibr = _expected(path, choice, **load)
    _tab(page, "Fit")
    expect(page.locator(".gb-state")).to_have_text("ready: Fit", timeout=TIMEOUT)
    shown = page.locator("pre.gb-summary")
    expect(shown).to_have_text("\n\n".join(summaries), timeout=TIMEOUT)
    expect(page.locator(".gb-alerts")).to_have_text("", timeout=TIMEOUT)  # the plot drew too
    expect(page.locator(".gb-diag")).to_contain_text("χ²/ν", timeout=TIMEOUT)
    _tab(page, "Export")
    code = page.locator("pre.gb-code")
    expect(code).to_contain_text("cleaning.clean", timeout=TIMEOUT)
    with page.expect_download(timeout=TIMEOUT) as info:
        page.locator(".gb-download-kalibr").click()
    downloaded = tmp / "downloaded.yaml"
    info.value.save_as(downloaded)
    assert downloaded.read_text(encoding="utf-8") == kalibr
    # the page's reproducing code, alone in a fresh interpreter, prints the same coefficients
    # and writes the same file
    script = tmp / "reproduce.py"
    script.write_text(code.inner_text(), encoding="utf-8")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    done = subprocess.run(
        [sys.executable, str(script)],
        cwd=tmp,
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout == "".join(s + "\n" for s in summaries)
    assert (tmp / "imu.yaml").read_text(encoding="utf-8") == kalibr


def test_explore_in_chromium(served: tuple[str, Path, Path], browser: Any, tmp_path: Path) -> None:
    url, csv, bag = served
    page = browser.new_page(viewport={"width": 1400, "height": 1000}, accept_downloads=True)
    requests: list[str] = []
    page.on("request", lambda r: requests.append(r.url))
    page.goto(url)
    expect = playwright_sync.expect
    expect(page.locator(".gb-sampling")).to_contain_text("sim.csv", timeout=TIMEOUT)
    expect(page.locator(".gb-load-errors")).to_contain_text("missing.csv", timeout=TIMEOUT)
    _drive(page, None, CSV_CHOICE)
    (tmp_path / "csv").mkdir()
    _check(page, tmp_path / "csv", csv, CSV_CHOICE, units="deg/s")
    # undo: the τ range goes, then comes back when typed again
    page.locator(".gb-undo button").click()
    expect(page.locator("ol.gb-steps")).not_to_contain_text("τ 0.02", timeout=TIMEOUT)
    # a part dragged on the rate plot (Bokeh's box select along time) replaces the typed one
    _tab(page, "Log")
    expect(page.locator(".gb-state")).to_have_text("ready: Log", timeout=TIMEOUT)
    canvas = page.locator(".bk-Canvas >> visible=true").first
    box = canvas.bounding_box()
    assert box is not None
    y = box["y"] + 0.5 * box["height"]
    page.mouse.move(box["x"] + 0.45 * box["width"], y)
    page.mouse.down()
    page.mouse.move(box["x"] + 0.55 * box["width"], y, steps=8)
    page.mouse.move(box["x"] + 0.65 * box["width"], y, steps=8)
    page.mouse.up()
    dragged = page.locator("ol.gb-steps li").first
    expect(dragged).to_contain_text("part ", timeout=TIMEOUT)
    expect(dragged).not_to_contain_text(f"part {CSV_CHOICE[0]:g} s", timeout=TIMEOUT)
    lo, hi = (float(v) for v in re.findall(r"([\d.]+) s", dragged.inner_text())[:2])
    assert 0.0 < lo < hi < 600.0, (lo, hi)
    # the ROS2 bag
    _tab(page, "Log")
    _drive(page, bag.name, BAG_CHOICE)
    (tmp_path / "bag").mkdir()
    _check(page, tmp_path / "bag", bag, BAG_CHOICE)
    # every view draws (no error message on any tab)
    for name in ("Log", "Clean", "Stability", "Fit", "Compare", "Export"):
        _tab(page, name)
        expect(page.locator(".gb-state")).to_have_text(f"ready: {name}", timeout=TIMEOUT)
        expect(page.locator(".gb-alerts")).to_have_text("", timeout=TIMEOUT)
    # blob: URLs of the page itself (a download) are local too
    local = re.compile(r"^(blob:)?(ws|http)://127\.0\.0\.1:\d+/")
    outside = [u for u in requests if not local.match(u)]
    assert not outside, outside
    page.close()


def test_cli_serves_on_loopback_and_prints_the_url(tmp_path: Path) -> None:
    import urllib.request

    csv = _simulated_log(tmp_path / "sim.csv")
    err = tmp_path / "stderr.txt"
    with (
        err.open("w") as stderr,
        subprocess.Popen(
            [
                sys.executable,
                "-m",
                "gyrobias",
                "explore",
                str(csv),
                "--units",
                "deg/s",
                "--no-browser",
                "--port",
                "0",
            ],
            stdout=subprocess.PIPE,
            stderr=stderr,
            text=True,
            env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
        ) as proc,
    ):
        try:
            assert proc.stdout is not None
            url = None
            for line in proc.stdout:
                m = re.search(r"serving on (http://127\.0\.0\.1:\d+/)", line)
                if m:
                    url = m.group(1)
                    break
            assert url is not None, err.read_text()
            with urllib.request.urlopen(url, timeout=60) as resp:
                page = resp.read().decode()
                assert resp.status == 200
            assert "bokeh" in page.lower() and "cdn." not in page  # scripts from this server
        finally:
            proc.terminate()
            proc.communicate(timeout=30)

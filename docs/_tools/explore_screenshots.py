"""Screenshots of every view of ``gyrobias explore`` for docs/guides/explore.md, taken at docs build.

Run by the Sphinx extension ``docs/_ext/explore_shots.py`` (``make docs``) before the pages are
read: it serves the explorer on a free loopback port over two simulated logs, drives it in
headless Chromium (Playwright with the system browser, as tests/test_explore_browser.py does) and
writes one PNG per view into ``docs/guides/_explore/`` (generated, not committed).

Usage: ``python docs/_tools/explore_screenshots.py [OUTDIR]``.
"""

from __future__ import annotations

import os
import re
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

OUT = Path(__file__).resolve().parents[1] / "guides" / "_explore"
VIEWS = ("Log", "Clean", "Stability", "Fit", "Compare", "Export")
TIMEOUT = 120_000  # ms


def chromium() -> str:
    found = (
        os.environ.get("GYROBIAS_CHROMIUM")
        or shutil.which("chromium")
        or shutil.which("chromium-browser")
        or shutil.which("google-chrome")
    )
    if found is None:
        raise SystemExit(
            "explore screenshots: no Chromium found (install the Debian package chromium or set "
            "GYROBIAS_CHROMIUM)"
        )
    return found


def simulated_logs(tmp: Path) -> list[Path]:
    """Two 20-minute, 100 Hz, 3-axis gyro logs: one with a drift, a 23 Hz line and spikes."""
    from gyrobias import noise

    n, fs = 120_000, 100.0
    paths = []
    for k in range(2):
        cols = [
            noise.simulate(
                n,
                fs,
                arw=0.2 / 60,
                bias_instability=(3 + k) / 3600,
                rrw=10 / 216000,
                sinusoids=[(23.0, 0.02)] if k == 0 else (),
                seed=10 * k + s,
            )
            for s in range(3)
        ]
        rate = np.column_stack(cols)
        if k == 0:
            rate += np.linspace(0.0, 0.03, n)[:, None]
            rate[np.arange(5_000, n, 17_000), 1] += 0.8
        t = np.arange(n) / fs
        path = tmp / f"gyro_{'ab'[k]}.csv"
        np.savetxt(
            path, np.column_stack([t, rate]), delimiter=",", header="time,gx,gy,gz", comments=""
        )
        paths.append(path)
    return paths


def main(out: Path = OUT) -> None:
    from playwright.sync_api import expect, sync_playwright

    from gyrobias.explore import load_sessions
    from gyrobias.explore.server import serve

    out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        sessions, errors = load_sessions(simulated_logs(Path(tmp)), units="deg/s")
        if errors:
            raise SystemExit("; ".join(errors))
        srv = serve(sessions)
        try:
            with sync_playwright() as pw:
                browser = pw.chromium.launch(executable_path=chromium(), args=["--no-sandbox"])
                page = browser.new_page(viewport={"width": 1400, "height": 1000})
                page.goto(srv.url)
                expect(page.locator(".gb-sampling")).to_contain_text("gyro_a", timeout=TIMEOUT)
                steps = page.locator("ol.gb-steps")

                def typed(cls: str, value: str) -> None:
                    box = page.locator(f".{cls} input")
                    box.fill(value)
                    box.press("Enter")

                typed("gb-start", "120")
                typed("gb-stop", "1080")
                expect(steps).to_contain_text("part 120 s", timeout=TIMEOUT)
                page.locator(".gb-outliers-on input").check()
                expect(steps).to_contain_text("outliers", timeout=TIMEOUT)
                page.locator(".gb-detrend button", has_text="linear").click()
                expect(steps).to_contain_text("linear drift removed", timeout=TIMEOUT)
                page.locator(".gb-terms button", has_text=re.compile("^R$")).click()
                expect(steps).to_contain_text("joint fit of Q,N,B,K,", timeout=TIMEOUT)
                for view in VIEWS:
                    page.locator(".bk-tab", has_text=re.compile(f"^{view}$")).click()
                    marker = {
                        "Log": ".gb-sampling",
                        "Clean": ".gb-outliers",
                        "Stability": "canvas >> visible=true",
                        "Fit": ".gb-diag",
                        "Compare": "canvas >> visible=true",
                        "Export": "pre.gb-code",
                    }[view]
                    state = page.locator(".gb-state")
                    expect(state).to_have_text(f"ready: {view}", timeout=TIMEOUT)
                    expect(page.locator(marker).first).to_be_visible(timeout=TIMEOUT)
                    expect(page.locator(".gb-alerts")).to_have_text("", timeout=TIMEOUT)
                    page.wait_for_load_state("networkidle")
                    page.screenshot(path=str(out / f"{view.lower()}.png"))
                browser.close()
        finally:
            srv.stop()
    print(f"explore screenshots: {', '.join(v.lower() + '.png' for v in VIEWS)} in {out}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else OUT)

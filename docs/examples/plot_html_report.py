"""
The HTML noise report
=====================

``gyrobias report LOG`` (or :func:`gyrobias.report.write_report`) writes one self-contained
HTML page per log: the log and its timestamps, an Allan plot per channel with intervals and the
fitted and conservative models, the coefficient table with uncertainties and goodness of fit,
and every estimator export. Here a simulated 3-axis log is written as CSV, loaded, reported,
and the page is photographed with headless Chromium.

When Chromium is not installed (``apt-get install chromium`` on Debian), the example still
builds: it draws the report's first Allan figure (the same SVG the page embeds, drawn by
:func:`gyrobias.plotting.plot_allan`) and says so in the figure's title.
"""

import shutil
import subprocess
import tempfile
from pathlib import Path

import matplotlib.image
import matplotlib.pyplot as plt
import numpy as np

from gyrobias import allan, io, noise, report

fs = 100.0
rate = noise.simulate(
    90_000, fs, arw=0.2 / 60, bias_instability=3 / 3600, rrw=10 / 216_000, axes=3, seed=8
)
workdir = Path(tempfile.mkdtemp(prefix="gyrobias-report-"))
csv = workdir / "bench.csv"
t = np.arange(rate.shape[0]) / fs
np.savetxt(csv, np.column_stack([t, rate]), delimiter=",", header="t,gx,gy,gz", comments="")

log = io.load(csv)
page = report.write_report(workdir / "report.html", log, units="deg/s")
print(f"{page.name}: {page.stat().st_size / 1024:.0f} kB, self-contained (plots embedded as SVG)")

browser = (
    shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")
)
shot = workdir / "report.png"
if browser is not None:
    subprocess.run(
        [
            browser,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--window-size=1000,1400",
            f"--screenshot={shot}",
            page.as_uri(),
        ],
        check=True,
        capture_output=True,
        timeout=120,
    )
if shot.exists():
    fig, ax = plt.subplots(figsize=(7, 9.8))
    ax.imshow(matplotlib.image.imread(shot))
    ax.set_axis_off()
    ax.set_title("report.html in headless Chromium (top of the page)")
    fig.tight_layout()
else:
    print("Chromium is not installed: showing the report's first Allan figure instead")
    ax = allan.adev(log.data[:, 0], fs, units="deg/s").plot(fit=True)
    ax.set_title("Chromium not installed: the report's Allan figure for gx (no screenshot)")
    fig = ax.figure

"""The base install works without the extras, and a missing extra is one line naming it (issue 25).

``pip install gyrobias`` brings numpy, tqdm and ruamel.yaml only (the YAML writer, imported lazily). The tests run with every extra installed,
so each case starts a fresh interpreter in which the extras' packages cannot be imported
(``sys.modules[name] = None`` makes ``import name`` raise ``ImportError``, as if it were not
installed): ``import gyrobias``, ``gyrobias --help`` and an analysis must work, and a command
that needs an extra must stop with one line ``gyrobias: error: ...`` naming the
``pip install 'gyrobias[...]'`` to run, exit code 2, no traceback.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

#: The packages of the extras (plot/report, io, fleet) and the test-only references.
EXTRAS = (
    "matplotlib",
    "rosbags",
    "pyarrow",
    "dask",
    "distributed",
    "pandas",
    "scipy",
    "yaml",
    "panel",
    "bokeh",
)

_RUN = """
import sys
for name in {blocked!r}:
    sys.modules[name] = None
from gyrobias.cli import main
code = main(sys.argv[1:])
heavy = sorted(m for m in {extras!r} if sys.modules.get(m) is not None)
print("loaded:", ",".join(heavy))
sys.exit(code)
"""


def _cli(*argv: str, blocked: tuple[str, ...] = EXTRAS) -> subprocess.CompletedProcess[str]:
    code = _RUN.format(blocked=blocked, extras=EXTRAS)
    return subprocess.run(
        [sys.executable, "-c", code, *argv], capture_output=True, text=True, timeout=300
    )


@pytest.fixture
def log_csv(tmp_path: Path) -> Path:
    path = tmp_path / "log.csv"
    rate = np.random.default_rng(3).normal(0.0, 0.1, (4000, 3))
    np.savetxt(path, rate, delimiter=",", header="gx,gy,gz", comments="")
    return path


def test_package_and_help_need_no_extra() -> None:
    code = "import sys\nfor n in {0!r}: sys.modules[n] = None\nimport gyrobias\nprint(gyrobias.__version__)"
    done = subprocess.run(
        [sys.executable, "-c", code.format(EXTRAS)], capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr
    helped = _cli("--help")
    assert helped.returncode == 0, helped.stderr
    assert "usage: gyrobias" in helped.stdout


def test_help_loads_no_heavy_dependency_even_when_installed() -> None:
    # With every extra importable, `gyrobias --help` still imports none of them (lazy imports).
    done = _cli("--help", blocked=())
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip().splitlines()[-1] == "loaded:"


def test_analysis_without_extras(log_csv: Path) -> None:
    done = _cli("allan", str(log_csv), "--fs", "100", "--no-progress")
    assert done.returncode == 0, done.stderr
    assert "loaded:" in done.stdout and done.stdout.strip().splitlines()[-1] == "loaded:"


@pytest.mark.parametrize(
    ("argv", "extra"),
    [
        (("allan", "{log}", "--fs", "100", "--no-progress", "--plot", "{out}.png"), "plot"),
        (("fleet", "{log}", "--fs", "100", "--no-progress", "--out", "{out}.csv"), "fleet"),
        (("allan", "{bag}", "--no-progress"), "io"),
        (("explore", "{log}", "--fs", "100", "--no-browser"), "explore"),
    ],
    ids=["plot", "fleet", "bag", "explore"],
)
def test_missing_extra_is_one_line_naming_it(
    argv: tuple[str, ...], extra: str, log_csv: Path, tmp_path: Path
) -> None:
    bag = tmp_path / "imu.bag"
    bag.write_bytes(b"#ROSBAG V2.0\n")  # never opened: the reader is missing first
    args = [a.format(log=log_csv, out=tmp_path / "out", bag=bag) for a in argv]
    done = _cli(*args)
    assert done.returncode == 2, (done.stdout, done.stderr)
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("gyrobias: error: "), done.stderr
    assert f"gyrobias[{extra}]" in lines[0], lines[0]
    assert "Traceback" not in done.stderr


def test_report_without_matplotlib_says_which_extra_draws_its_plots(
    log_csv: Path, tmp_path: Path
) -> None:
    # The page is still written (tables, exports); each plot's place names the extra.
    out = tmp_path / "report.html"
    done = _cli("report", str(log_csv), "--fs", "100", "--no-progress", "-o", str(out))
    assert done.returncode == 0, done.stderr
    page = out.read_text(encoding="utf-8")
    assert "No plot:" in page and "gyrobias[plot]" in page

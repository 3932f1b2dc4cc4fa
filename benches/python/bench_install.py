"""Install footprint and start-up latency (issue 25 item 4), measured in one run.

Run: ``python benches/python/bench_install.py [--wheel dist/gyrobias-*.whl] [--here]``.

- Two fresh virtual environments (no system site-packages), one with ``pip install <wheel>``
  (the base install), one with ``<wheel>[all]``: the number of packages installed (pip,
  setuptools and wheel excluded) and their size in MB (site-packages on disk, pip and
  setuptools excluded). Needs PyPI or a warm pip cache.
- In each: ``import gyrobias`` (lazy: no NumPy), its first use ``gyrobias.adev`` (NumPy and
  the core loaded), ``gyrobias --help``, ``--version``, ``gyrobias allan --help`` and
  ``python -m gyrobias --help`` in fresh interpreters (best of ``--repeats``), beside the
  same-run baselines ``python -c pass`` and ``import numpy`` (gyrobias' one heavy import): what
  gyrobias adds on top of NumPy is the difference; the command line's help and version import
  neither NumPy nor the core (``tests/test_cli_startup.py``). A CLI called in loops should
  answer well under a second; with ``[all]`` installed the heavy extras must still not be
  imported by these.
- ``--here``: the latency only, in the current environment.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import sysconfig
import tempfile
import time
import venv
from pathlib import Path

TOOLS = {"pip", "setuptools", "wheel"}


def best_time(cmd: list[str], repeats: int) -> float:
    """Best wall-clock time of ``repeats`` runs of ``cmd`` (a fresh process each), seconds."""
    best = float("inf")
    for _ in range(repeats):
        t = time.perf_counter()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        best = min(best, time.perf_counter() - t)
    return best


def latency(python: str, script: str, repeats: int) -> dict[str, float]:
    # ``import gyrobias`` alone is lazy (no NumPy, no core); the first use of a name such as
    # ``gyrobias.adev`` loads them, as the start of any computation does.
    return {
        "python -c pass": best_time([python, "-c", "pass"], repeats),
        "import numpy": best_time([python, "-c", "import numpy"], repeats),
        "import gyrobias": best_time([python, "-c", "import gyrobias"], repeats),
        "gyrobias.adev (loaded)": best_time(
            [python, "-c", "import gyrobias; gyrobias.adev"], repeats
        ),
        "gyrobias --help": best_time([script, "--help"], repeats),
        "gyrobias --version": best_time([script, "--version"], repeats),
        "gyrobias allan --help": best_time([script, "allan", "--help"], repeats),
        "python -m gyrobias --help": best_time([python, "-m", "gyrobias", "--help"], repeats),
    }


def report_latency(python: str, script: str, repeats: int) -> None:
    times = latency(python, script, repeats)
    for name, t in times.items():
        print(f"    {name:<20} {t * 1e3:7.1f} ms")
    print(
        f"    loading gyrobias adds "
        f"{1e3 * (times['gyrobias.adev (loaded)'] - times['import numpy']):.0f} ms to "
        f"`import numpy`; `gyrobias --help` is "
        f"{times['gyrobias --help'] / times['import numpy']:.2f}x `import numpy` and "
        f"{1e3 * (times['gyrobias --help'] - times['python -c pass']):.0f} ms over `python -c pass`"
    )


def footprint(wheel: Path, extra: str, repeats: int) -> tuple[int, float, list[str]]:
    """(packages, MB, names) of a fresh venv with ``wheel`` (and ``extra``); prints latency."""
    with tempfile.TemporaryDirectory() as tmp:
        env_dir = Path(tmp) / "venv"
        venv.create(env_dir, with_pip=True)
        bindir = "Scripts" if os.name == "nt" else "bin"
        python = str(env_dir / bindir / ("python.exe" if os.name == "nt" else "python"))
        spec = f"{wheel.resolve()}{extra}"
        subprocess.run(
            [python, "-m", "pip", "install", "-q", "--disable-pip-version-check", spec],
            check=True,
        )
        listing = subprocess.run(
            [python, "-m", "pip", "list", "--format=freeze", "--disable-pip-version-check"],
            check=True,
            capture_output=True,
            text=True,
        ).stdout.split()
        names = sorted(
            line.split("==")[0] for line in listing if line.split("==")[0].lower() not in TOOLS
        )
        site = Path(
            subprocess.run(
                [python, "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"],
                check=True,
                capture_output=True,
                text=True,
            ).stdout.strip()
        )
        size = 0
        for path in site.rglob("*"):
            top = path.relative_to(site).parts[0].lower()
            if top.split("-")[0] in TOOLS or top in ("_distutils_hack", "pkg_resources"):
                continue
            if path.is_file() and not path.is_symlink():
                size += path.stat().st_size
        print(f"  gyrobias{extra or ' (base)'}: start-up, best of {repeats} fresh processes")
        report_latency(python, str(env_dir / bindir / "gyrobias"), repeats)
        return len(names), size / 1e6, names


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--wheel", type=Path, help="the wheel (default: the one in dist/)")
    parser.add_argument("--here", action="store_true", help="latency in this environment only")
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()

    if args.here:
        script = str(Path(sysconfig.get_path("scripts")) / "gyrobias")
        print(f"start-up latency, best of {args.repeats} fresh processes ({sys.executable}):")
        report_latency(sys.executable, script, args.repeats)
        return
    wheel = args.wheel
    if wheel is None:
        found = sorted(Path("dist").glob("gyrobias-*.whl"))
        if not found:
            sys.exit("no wheel in dist/: run `make wheel` or pass --wheel")
        wheel = found[-1]
    print(f"install footprint of {wheel.name} (fresh venvs, pip/setuptools excluded):")
    for extra in ("", "[all]"):
        count, mb, names = footprint(wheel, extra, args.repeats)
        print(f"  gyrobias{extra or ' (base)':<8} {count:3d} packages {mb:7.1f} MB")
        print(f"    {' '.join(names)}")


if __name__ == "__main__":
    main()

"""Log-reading benchmark: ``gyrobias.io.load`` against a baseline measured side by side in one run.

Run: ``python benches/python/bench_io.py [--quick] [--only csv|bag|sqlite] [--repeats 3] [--keep DIR]``
(bags need ``pip install '.[io]'``). Prints one table, a row per input format:

| column | meaning |
|---|---|
| format | the file read |
| baseline | what gyrobias is compared with, timed in the same run (best of ``--repeats``) |
| gyrobias | ``gyrobias.io.load(path)`` (best of ``--repeats``), the sampling report included |
| ratio | baseline time / gyrobias time |
| peak memory | ``VmHWM`` of a fresh process loading the file, above the same process's imports, and the size of the result (data + time) for comparison |

Targets (issue 37): CSV ≥ 4× ``numpy.loadtxt`` on 10⁶ rows × (time + 3 channels) and on 10⁷ rows
× (time + 6 channels), 17 significant digits; bags ≥ 2× iterating their raw messages with
rosbags; peak memory the result plus a bounded working set (``spill=True``: the result on disk).

Rows are produced by the ``*_rows`` functions below and printed by :func:`print_table`; a new
format adds a function returning :class:`Row` objects.
"""

from __future__ import annotations

import argparse
import bz2
import gzip
import lzma
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from _timing import best_of

import gyrobias


@dataclass(frozen=True)
class Row:
    """One line of the table."""

    format: str
    baseline: str
    baseline_s: float
    gyrobias_s: float
    peak_mb: float | None = None  # VmHWM above the imports, fresh process (None: not measured)
    result_mb: float | None = None  # size of the loaded data + time
    note: str = ""

    @property
    def ratio(self) -> float:
        return self.baseline_s / self.gyrobias_s


def print_table(rows: list[Row]) -> None:
    """The rows as a Markdown table (the performance page shows it as printed)."""
    print()
    print("| format | baseline (same run) | gyrobias.io.load | ratio | peak memory |")
    print("|---|---|---|---|---|")
    for r in rows:
        mem = "—"
        if r.peak_mb is not None:
            mem = f"{r.peak_mb:.0f} MB"
            if r.result_mb is not None:
                mem += f" (result {r.result_mb:.0f} MB)"
        note = f" {r.note}" if r.note else ""
        print(
            f"| {r.format} | {r.baseline} {r.baseline_s:.3g} s | {r.gyrobias_s:.3g} s | "
            f"{r.ratio:.1f}× | {mem}{note} |"
        )


def peak_rss_mb(statement: str) -> float:
    """Peak resident memory (VmHWM, MB) of a fresh Python running ``statement``, above the same
    process's peak after its imports (gyrobias, numpy, pyarrow.csv when installed).

    VmHWM belongs to the new address space of the exec'd process (``ru_maxrss`` would carry the
    forking parent's peak over the exec).
    """
    code = (
        "import gyrobias, gyrobias.io\n"
        "try:\n    import pyarrow.csv\nexcept ImportError:\n    pass\n"
        "def hwm():\n"
        "    return int([l for l in open('/proc/self/status') if l.startswith('VmHWM')][0].split()[1])\n"
        "base = hwm()\n"
        f"{statement}\n"
        "print(hwm() - base)"
    )
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    out = subprocess.run(
        [sys.executable, "-c", code], check=True, capture_output=True, text=True, env=env
    )
    return int(out.stdout.split()[-1]) * 1024 / 1e6  # kB (KiB) -> MB, the result's unit


# ---------------------------------------------------------------------------------------------
# CSV


def write_csv(path: Path, rows: int, channels: int) -> None:
    """``t,c0,…`` with 17-significant-digit values (the worst case for parsers), 100 Hz."""
    rng = np.random.default_rng(0)
    block = 200_000
    names = ",".join(["t", *(f"g{i}" for i in range(channels))])
    with open(path, "w") as fh:
        fh.write(names + "\n")
        for start in range(0, rows, block):
            m = min(block, rows - start)
            table = np.column_stack(
                [(start + np.arange(m)) / 100.0, rng.normal(0.0, 0.01, (m, channels))]
            )
            np.savetxt(fh, table, delimiter=",", fmt="%.17g")


def _compressed(src: Path, suffix: str) -> Path:
    out = src.with_name(src.name + suffix)
    if not out.exists():
        opener: Callable[..., object] = {".gz": gzip.open, ".bz2": bz2.open, ".xz": lzma.open}[
            suffix
        ]
        with open(src, "rb") as fin, opener(out, "wb") as fout:  # type: ignore[attr-defined]
            while chunk := fin.read(1 << 24):
                fout.write(chunk)  # type: ignore[attr-defined]
    return out


def csv_rows(work: Path, quick: bool, repeats: int, memory: bool) -> list[Row]:
    """CSV rows: 10⁶ × (t + 3) plain and compressed, 10⁷ × (t + 6) plain (10× smaller with
    ``--quick``), each against numpy.loadtxt of the same file."""
    cases = (
        [(100_000, 3, True), (1_000_000, 6, False)]
        if quick
        else [
            (1_000_000, 3, True),
            (10_000_000, 6, False),
        ]
    )
    rows: list[Row] = []
    for n, k, with_compressed in cases:
        path = work / f"log_{n}x{k + 1}.csv"
        if not path.exists():
            t = time.perf_counter()
            write_csv(path, n, k)
            print(
                f"wrote {path.name}: {path.stat().st_size / 1e6:.0f} MB in "
                f"{time.perf_counter() - t:.0f} s",
                file=sys.stderr,
            )
        variants = [path]
        if with_compressed:
            variants += [_compressed(path, s) for s in (".gz", ".bz2", ".xz")]
        result_mb = n * (k + 1) * 8 / 1e6
        for p in variants:
            log = gyrobias.io.load(p)  # warm-up; and the values must be loadtxt's
            ref = np.loadtxt(p, delimiter=",", skiprows=1)
            assert np.array_equal(log.data, ref[:, 1:]), f"{p.name}: values differ from loadtxt"
            del log, ref
            ours = best_of(lambda p=p: gyrobias.io.load(p), repeats)
            base = best_of(lambda p=p: np.loadtxt(p, delimiter=",", skiprows=1), repeats)
            label = f"CSV {n:.0e} rows × (t + {k}), {p.stat().st_size / 1e6:.0f} MB"
            if p.suffix != ".csv":
                label += f" {p.suffix}"
            peak = peak_rss_mb(f"log = gyrobias.io.load({str(p)!r})") if memory else None
            rows.append(Row(label, "numpy.loadtxt", base, ours, peak, result_mb))
            print(f"{label}: loadtxt {base:.3f} s, gyrobias {ours:.3f} s", file=sys.stderr)
        if memory:
            spilled = peak_rss_mb(f"log = gyrobias.io.load({str(path)!r}, spill=True)")
            rows.append(
                Row(
                    f"same, spill=True ({path.stat().st_size / 1e6:.0f} MB file)",
                    "numpy.loadtxt",
                    rows[-len(variants)].baseline_s,
                    best_of(lambda p=path: gyrobias.io.load(p, spill=True), repeats),
                    spilled,
                    0.0,
                    "(result on disk)",
                )
            )
    return rows


# ---------------------------------------------------------------------------------------------
# Bags


def bag_rows(
    work: Path, quick: bool, repeats: int, memory: bool, labels: tuple[str, ...] = ()
) -> list[Row]:
    """Bag rows: every bag format of issue 37 (``_bench_bags.FORMATS``: ROS1 plain/lz4/bz2
    chunks, ROS2 sqlite3, MCAP plain/zstd/lz4 chunks), 300,000 ``sensor_msgs/Imu`` (30,000
    with ``--quick``), against rosbags opening the bag and iterating the topic's raw messages
    without deserializing them (target ≥ 2×). ``labels``: only these formats (default all)."""
    try:
        import rosbags  # noqa: F401
    except ImportError:
        print("bags: rosbags not installed (pip install '.[io]')", file=sys.stderr)
        return []
    import _bench_bags

    n = 30_000 if quick else 300_000
    rows = []
    for label, kind, compression in _bench_bags.FORMATS:
        if labels and label not in labels:
            continue
        path = _bench_bags.write_bag(work, kind, compression, n)
        log = gyrobias.io.load(path)
        assert np.array_equal(log.data, _bench_bags.messages(kind == "ros1", n)[2]), label
        assert _bench_bags.raw_iteration(path) == n, label
        ours = best_of(lambda p=path: gyrobias.io.load(p), repeats)
        base = best_of(lambda p=path: _bench_bags.raw_iteration(p), repeats)
        peak = peak_rss_mb(f"log = gyrobias.io.load({str(path)!r})") if memory else None
        rows.append(
            Row(f"{label}, {n} Imu", "rosbags raw iteration", base, ours, peak, n * 7 * 8 / 1e6)
        )
    return rows


SECTIONS: dict[str, Callable[[Path, bool, int, bool], list[Row]]] = {
    "csv": csv_rows,
    "bag": bag_rows,
    # the ROS2 sqlite3 row of the bag section alone
    "sqlite": lambda w, q, r, m: bag_rows(w, q, r, m, ("ROS2 sqlite3 (.db3)",)),
}


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="10x smaller files")
    ap.add_argument("--only", choices=sorted(SECTIONS), action="append", help="sections to run")
    ap.add_argument("--repeats", type=int, default=3, help="best of this many runs (default 3)")
    ap.add_argument("--no-memory", action="store_true", help="skip the peak-memory processes")
    ap.add_argument(
        "--keep",
        type=Path,
        default=os.environ.get("GYROBIAS_BENCH_DIR") or None,
        help="directory to keep (and reuse) the test files in (default: $GYROBIAS_BENCH_DIR, "
        "else a temporary one)",
    )
    args = ap.parse_args()
    print(
        f"gyrobias {gyrobias.__version__}; numpy {np.__version__}; {os.cpu_count()} CPUs; "
        f"load average {os.getloadavg()[0]:.2f}"
    )
    with tempfile.TemporaryDirectory() as tmp:
        work = args.keep or Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        rows: list[Row] = []
        for name in args.only or list(SECTIONS):
            rows += SECTIONS[name](work, args.quick, args.repeats, not args.no_memory)
        print_table(rows)
    print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()

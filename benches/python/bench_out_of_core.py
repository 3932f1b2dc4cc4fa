"""Out-of-core Allan deviation: peak resident memory of a memory-mapped 1.3 GB ``.npy`` log.

Run: ``python benches/python/bench_out_of_core.py [--quick]``.

Target (issue 12 item 5): overlapping ADEV with noise identification and confidence intervals
of ``np.load(path, mmap_mode="r")`` streams through the core with a peak resident set of at most
25 % of the file's size, measured by ``/usr/bin/time -v`` ("Maximum resident set size") around a
fresh interpreter. The same run prints the baseline interpreter (NumPy + gyrobias imported) and
the time. The results equal the in-memory call bit for bit (``tests/test_allan_stream.py``).
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ANALYSE = """
import sys, numpy as np, gyrobias
x = np.load(sys.argv[1], mmap_mode="r")
r = gyrobias.allan.adev(x, 100.0, confidence=0.683)
print(len(r.taus), float(r.adev[0]))
"""
BASELINE = "import numpy as np, gyrobias"


def peak_rss(code: str, *args: str) -> tuple[int, float]:
    """``(maximum resident set size in bytes, wall seconds)`` of ``python -c code args``."""
    t0 = time.perf_counter()
    out = subprocess.run(
        ["/usr/bin/time", "-v", sys.executable, "-c", code, *args],
        check=True,
        capture_output=True,
        text=True,
    )
    wall = time.perf_counter() - t0
    match = re.search(r"Maximum resident set size \(kbytes\): (\d+)", out.stderr)
    assert match, out.stderr
    return int(match.group(1)) * 1024, wall


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="a 130 MB log instead of 1.3 GB")
    args = parser.parse_args()
    n = 16_250_000 if args.quick else 162_500_000  # float64: 130 MB / 1.3 GB
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "log.npy"
        out = np.lib.format.open_memmap(path, mode="w+", dtype=np.float64, shape=(n,))
        rng = np.random.default_rng(0)
        step = 10_000_000
        level = 0.0
        for a in range(0, n, step):  # white + random-walk rate, written in pieces
            b = min(a + step, n)
            walk = level + np.cumsum(rng.normal(0.0, 1e-3, b - a))
            out[a:b] = 0.5 + rng.normal(0.0, 1.0, b - a) + walk
            level = float(walk[-1])
        out.flush()
        del out
        size = path.stat().st_size
        base, _ = peak_rss(BASELINE)
        peak, wall = peak_rss(ANALYSE, str(path))
    ratio = peak / size
    print(
        f"out-of-core adev with confidence intervals, {n:.3e} samples ({size / 1e9:.2f} GB .npy, mmap_mode='r')"
    )
    print(
        f"  peak RSS (/usr/bin/time -v)   {peak / 1e6:9.1f} MB = {100 * ratio:5.1f} % of the file   (target <= 25 %)"
    )
    print(f"  interpreter baseline          {base / 1e6:9.1f} MB")
    print(f"  wall time                     {wall:9.1f} s")
    print(json.dumps({"out_of_core_peak_rss_fraction": ratio, "out_of_core_seconds": wall}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

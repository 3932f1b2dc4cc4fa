"""Log-reading benchmark: gyrobias.io.load against numpy.loadtxt, measured side by side in one run.

Run: ``python benches/python/bench_io.py [--rows N] [--quick]`` (needs ``pip install '.[io]'``).

Targets (issue 12): reading a 1e7-row, 4-column CSV (time + 3 gyro axes) ≥ 4× faster than
``numpy.loadtxt`` of the same file; reading a ROS bag of IMU messages, per message; the peak
resident memory of loading a CSV with ``spill=True`` (the data in a memory-mapped temporary
file) against loading it into memory, each in a fresh process (its ``VmHWM``).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _timing import best_of

import gyrobias


def write_csv(path: Path, rows: int) -> None:
    """``t,gx,gy,gz`` with 17-significant-digit values (the worst case for parsers)."""
    rng = np.random.default_rng(0)
    block = 1_000_000
    with open(path, "w") as fh:
        fh.write("t,gx,gy,gz\n")
        for start in range(0, rows, block):
            m = min(block, rows - start)
            table = np.column_stack([(start + np.arange(m)) / 100.0, rng.normal(0.0, 0.01, (m, 3))])
            np.savetxt(fh, table, delimiter=",", fmt="%.17g")


def write_bag(path: Path, n: int) -> None:
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.ROS1_NOETIC)
    types = ts.types
    vec = types["geometry_msgs/msg/Vector3"]
    rng = np.random.default_rng(1)
    data = rng.normal(size=(n, 6))
    with Writer(path) as writer:
        conn = writer.add_connection("/imu", "sensor_msgs/msg/Imu", typestore=ts)
        for i in range(n):
            t = 1_700_000_000_000_000_000 + i * 5_000_000
            msg = types["sensor_msgs/msg/Imu"](
                header=types["std_msgs/msg/Header"](
                    seq=i,
                    stamp=types["builtin_interfaces/msg/Time"](sec=t // 10**9, nanosec=t % 10**9),
                    frame_id="imu",
                ),
                orientation=types["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
                orientation_covariance=np.zeros(9),
                angular_velocity=vec(x=data[i, 0], y=data[i, 1], z=data[i, 2]),
                angular_velocity_covariance=np.zeros(9),
                linear_acceleration=vec(x=data[i, 3], y=data[i, 4], z=data[i, 5]),
                linear_acceleration_covariance=np.zeros(9),
            )
            writer.write(conn, t, ts.serialize_ros1(msg, "sensor_msgs/msg/Imu"))


def peak_rss_mb(statement: str) -> float:
    """Peak resident memory (VmHWM, MB) of a fresh Python that imports gyrobias and runs ``statement``.

    VmHWM belongs to the new address space of the exec'd process (``ru_maxrss`` would carry the
    forking parent's peak over the exec).
    """
    code = (
        "import gyrobias, pyarrow.csv\n"
        f"{statement}\n"
        "print([l for l in open('/proc/self/status') if l.startswith('VmHWM')][0].split()[1])"
    )
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True)
    return int(out.stdout.split()[-1]) / 1024.0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=10_000_000)
    ap.add_argument("--quick", action="store_true", help="1e6 rows and a small bag")
    args = ap.parse_args()
    rows = 1_000_000 if args.quick else args.rows
    repeats = 2  # the first call also imports pyarrow
    print(f"gyrobias {gyrobias.__version__}; numpy {np.__version__}")
    with tempfile.TemporaryDirectory() as tmp:
        csv = Path(tmp) / "log.csv"
        t = time.perf_counter()
        write_csv(csv, rows)
        size = csv.stat().st_size
        print(
            f"CSV: {rows:.3g} rows × 4 columns, {size / 1e6:.0f} MB (written in {time.perf_counter() - t:.1f} s)"
        )

        ours = best_of(lambda: gyrobias.io.load(csv), repeats)
        base = best_of(lambda: np.loadtxt(csv, delimiter=",", skiprows=1), 1)
        log = gyrobias.io.load(csv)
        ref = np.loadtxt(csv, delimiter=",", skiprows=1)
        assert np.array_equal(log.data, ref[:, 1:]), "pyarrow and loadtxt disagree"
        del ref
        print(f"  gyrobias.io.load   {ours:7.2f} s  (incl. the sampling report)")
        print(f"  numpy.loadtxt      {base:7.2f} s")
        print(f"  ratio              {base / ours:7.1f}x  (target >= 4x)")

        base_mb = peak_rss_mb("pass")
        mem = peak_rss_mb(f"log = gyrobias.io.load({str(csv)!r})")
        spilled = peak_rss_mb(f"log = gyrobias.io.load({str(csv)!r}, spill=True)")
        data_mb = rows * 3 * 8 / 1e6
        print(
            f"  peak RSS above the imports ({base_mb:.0f} MB): in memory {mem - base_mb:.0f} MB, "
            f"spill=True {spilled - base_mb:.0f} MB (result: data {data_mb:.0f} MB + time "
            f"{rows * 8 / 1e6:.0f} MB)"
        )

        try:
            import rosbags  # noqa: F401
        except ImportError:
            print("bag: rosbags not installed (pip install '.[io]')")
            return
        n = 20_000 if args.quick else 200_000
        bag = Path(tmp) / "imu.bag"
        write_bag(bag, n)
        from gyrobias.io import _bag

        fast = best_of(lambda: gyrobias.io.load(bag), repeats)
        slow = best_of(
            lambda: _bag.read_bag(
                bag, None, "header", None, lambda m: np.empty((m, 6)), fast=False
            ),
            1,
        )
        print(f"ROS1 bag: {n} sensor_msgs/Imu messages, {bag.stat().st_size / 1e6:.0f} MB")
        print(f"  gyrobias.io.load   {fast:7.2f} s  ({1e6 * fast / n:.2f} µs per message)")
        print(
            f"  rosbags deserialize{slow:7.2f} s  ({1e6 * slow / n:.2f} µs per message); ratio {slow / fast:.1f}x"
        )


if __name__ == "__main__":
    main()

"""Bag rows of ``bench_io.py``: ``gyrobias.io.load`` against rosbags iterating the raw messages.

Every format of issue 37 (ROS1 plain/lz4/bz2 chunks, ROS2 sqlite3, MCAP plain/zstd/lz4 chunks)
is written here with the formats' own writers (rosbags; the ``mcap`` package for lz4 chunks,
which rosbags cannot write) from the same 300,000 ``sensor_msgs/Imu`` messages. The messages are
serialized once with rosbags and patched with NumPy (stamp, angular velocity, linear
acceleration), so writing the bags takes seconds instead of minutes.

The baseline is rosbags' ``AnyReader`` opened on the bag and iterating the topic's raw messages
without deserializing them (the least any rosbags-based reader does); the target is
``gyrobias.io.load`` ≥ 2× faster, both measured in the same run (``bench_io.py --only bag``).
Run alone, this script measures the peak memory of loading a large bag (default 4.3 M messages,
a 3-hour 400 Hz recording): ``python benches/python/_bench_bags.py [N]``.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np

IMU = "sensor_msgs/msg/Imu"
T0 = 1_700_000_000_000_000_000
#: (label, writer kind, compression) of every benchmarked bag.
FORMATS = (
    ("ROS1 .bag", "ros1", "none"),
    ("ROS1 .bag, lz4 chunks", "ros1", "lz4"),
    ("ROS1 .bag, bz2 chunks", "ros1", "bz2"),
    ("ROS2 sqlite3 (.db3)", "db3", "none"),
    ("MCAP", "mcap", "none"),
    ("MCAP, zstd chunks", "mcap", "zstd"),
    ("MCAP, lz4 chunks", "mcap", "lz4"),
)


def _template(ros1: bool) -> tuple[bytes, int, int, int]:
    """A serialized Imu (frame ``imu_link``) and the offsets of its stamp, gyro and accel."""
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    t = ts.types
    header: dict[str, Any] = {
        "stamp": t["builtin_interfaces/msg/Time"](sec=0, nanosec=0),
        "frame_id": "imu_link",
    }
    if ros1:
        header["seq"] = 0
    vec = t["geometry_msgs/msg/Vector3"]
    msg = t[IMU](
        header=t["std_msgs/msg/Header"](**header),
        orientation=t["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
        orientation_covariance=np.zeros(9),
        angular_velocity=vec(x=0.0, y=0.0, z=0.0),
        angular_velocity_covariance=np.zeros(9),
        linear_acceleration=vec(x=0.0, y=0.0, z=0.0),
        linear_acceleration_covariance=np.zeros(9),
    )
    raw = bytes(ts.serialize_ros1(msg, IMU) if ros1 else ts.serialize_cdr(msg, IMU))
    stamp = 4  # after seq (ROS1) or after the CDR encapsulation header (ROS2)
    end = len(raw) - 72  # the linear acceleration covariance closes the message
    return raw, stamp, end - 24 - 72 - 24, end - 24


def messages(ros1: bool, n: int, seed: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(raw (n, L) uint8, stamps int64 ns, data (n, 6))`` of a 200 Hz IMU log."""
    raw, stamp, gyro, accel = _template(ros1)
    rng = np.random.default_rng(seed)
    data = rng.normal(0.0, 0.01, (n, 6))
    data[:, 5] += 9.81
    stamps = T0 + np.arange(n, dtype=np.int64) * 5_000_000
    buf = np.tile(np.frombuffer(raw, dtype=np.uint8), (n, 1))
    buf[:, stamp : stamp + 4] = (stamps // 10**9).astype("<u4").view(np.uint8).reshape(n, 4)
    buf[:, stamp + 4 : stamp + 8] = (stamps % 10**9).astype("<u4").view(np.uint8).reshape(n, 4)
    buf[:, gyro : gyro + 24] = data[:, :3].astype("<f8").view(np.uint8).reshape(n, 24)
    buf[:, accel : accel + 24] = data[:, 3:].astype("<f8").view(np.uint8).reshape(n, 24)
    return buf, stamps, data


def write_bag(directory: Path, kind: str, compression: str, n: int) -> Path:
    """Write ``n`` Imu messages on ``/imu`` in one format; returns the path to load."""
    from rosbags.typesys import Stores, get_typestore

    ros1 = kind == "ros1"
    buf, stamps, _ = messages(ros1, n)
    ts = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    name = f"{kind}_{compression}"
    if ros1:
        from rosbags.rosbag1 import Writer as Writer1

        path = directory / f"{name}.bag"
        w1 = Writer1(path)
        if compression != "none":
            w1.set_compression(getattr(Writer1.CompressionFormat, compression.upper()))
        with w1:
            conn = w1.add_connection("/imu", IMU, typestore=ts)
            for i in range(n):
                w1.write(conn, int(stamps[i]), buf[i].tobytes())
        return path
    if kind == "mcap" and compression == "lz4":
        return _write_mcap_lz4(directory / f"{name}.mcap", buf, stamps, ts)
    from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin
    from rosbags.rosbag2 import Writer as Writer2

    plugin = StoragePlugin.SQLITE3 if kind == "db3" else StoragePlugin.MCAP
    target = directory / name
    w2 = Writer2(target, version=9, storage_plugin=plugin)
    if compression == "zstd":
        w2.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
    with w2:
        conn = w2.add_connection("/imu", IMU, typestore=ts)
        for i in range(n):
            w2.write(conn, int(stamps[i]), buf[i].tobytes())
    if kind == "mcap":  # the standalone .mcap storage file
        inner = next(target.glob("*.mcap"))
        single = directory / f"{name}.mcap"
        inner.rename(single)
        for f in target.iterdir():
            f.unlink()
        target.rmdir()
        return single
    return target


def _write_mcap_lz4(path: Path, buf: np.ndarray, stamps: np.ndarray, ts: Any) -> Path:
    """An MCAP file with lz4 chunks (the ``mcap`` package's writer; rosbags writes zstd only)."""
    from mcap.writer import CompressionType, Writer

    msgdef = ts.generate_msgdef(IMU, ros_version=2)[0]
    with open(path, "wb") as fh:
        w = Writer(fh, compression=CompressionType.LZ4)
        w.start(profile="ros2", library="gyrobias bench")
        schema = w.register_schema(name=IMU, encoding="ros2msg", data=msgdef.encode())
        channel = w.register_channel(topic="/imu", message_encoding="cdr", schema_id=schema)
        for i in range(len(stamps)):
            t = int(stamps[i])
            w.add_message(channel, log_time=t, data=buf[i].tobytes(), publish_time=t, sequence=i)
        w.finish()
    return path


def raw_iteration(path: Path) -> int:
    """The baseline: rosbags opens the bag and iterates the topic's raw messages."""
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    count = 0
    with AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as reader:
        conns = [c for c in reader.connections if c.topic == "/imu"]
        for _ in reader.messages(connections=conns):
            count += 1
    return count


def peak_rss_mb(statement: str) -> float:
    """VmHWM (MB) of a fresh Python that imports gyrobias and rosbags and runs ``statement``."""
    code = (
        "import gyrobias, gyrobias.io, rosbags.highlevel\n"
        f"{statement}\n"
        "print([l for l in open('/proc/self/status') if l.startswith('VmHWM')][0].split()[1])"
    )
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True)
    return int(out.stdout.split()[-1]) * 1024 / 1e6  # kB (KiB) -> MB, the result's unit


def memory_rows(
    directory: Path, n: int, formats: tuple[str, ...]
) -> list[tuple[str, float, float]]:
    """``(format, peak RSS above the imports MB, result MB)`` of loading an ``n``-message bag
    in a fresh process (``VmHWM``); the bag is deleted afterwards."""
    out = []
    base_mb = peak_rss_mb("pass")
    for label, kind, compression in FORMATS:
        if label not in formats:
            continue
        path = write_bag(directory, kind, compression, n)
        peak = peak_rss_mb(f"log = gyrobias.io.load({str(path)!r})") - base_mb
        out.append((label, peak, n * 7 * 8 / 1e6))
        if path.is_dir():
            for f in path.iterdir():
                f.unlink()
            path.rmdir()
        else:
            path.unlink()
    return out


if __name__ == "__main__":
    import argparse
    import tempfile

    ap = argparse.ArgumentParser(
        description="peak memory of loading an N-message ROS1 bag and MCAP (zstd) file "
        "(the timed rows are bench_io.py's bag section)"
    )
    ap.add_argument("messages", type=int, nargs="?", default=4_300_000)
    ap.add_argument("--dir", type=Path, help="directory for the bags (default: a temporary one)")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(dir=args.dir) as tmp:
        for label, peak, result in memory_rows(
            Path(tmp), args.messages, ("ROS1 .bag", "MCAP, zstd chunks")
        ):
            print(
                f"{label}, {args.messages} messages: peak RSS {peak:.0f} MB above the imports "
                f"(result {result:.0f} MB: data + time)"
            )

"""ROS1 ``.bag``, ROS2 bag directories (sqlite3 / MCAP storage), ``.db3`` and ``.mcap`` files.

Read with the pure-Python `rosbags` library (no ROS install). Messages of type
``sensor_msgs/msg/Imu`` (ROS1 ``sensor_msgs/Imu``) become six channels: the angular velocity in
rad/s and the linear acceleration in m/s² (REP 103/145), with ``header.stamp`` or the bag's
receive time as int64 nanoseconds.

The core's reader (:mod:`gyrobias.io._bagcore`) is tried first; a bag it leaves is read here
with rosbags: messages in batches of :data:`BATCH` into a buffer of bounded size. A batch whose
messages all have the standard layout and the same length (one ``frame_id``) is decoded at
fixed byte offsets with NumPy; anything else goes through rosbags' deserializer, which is the
reference both fast paths are tested against.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobias.io import _bagcore

__all__ = ["BAG_SUFFIXES", "CHANNELS", "IMU_TYPE", "UNITS", "is_bag", "read_bag", "topics"]

IMU_TYPE = "sensor_msgs/msg/Imu"
#: Channel names of an IMU topic, in column order.
CHANNELS = ("gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z")
#: Units of the channels (sensor_msgs/Imu: REP 103).
UNITS = ("rad/s", "rad/s", "rad/s", "m/s^2", "m/s^2", "m/s^2")
BAG_SUFFIXES = (".bag", ".mcap", ".db3")
#: Messages decoded per batch (bounds the raw-message buffer to a few tens of MB).
BATCH = 65_536

_FIELDS = (
    "std_msgs/msg/Header",
    "geometry_msgs/msg/Vector3",
    "geometry_msgs/msg/Quaternion",
    IMU_TYPE,
)


class BagError(ValueError):
    """A problem with a bag, already phrased for the user (the file name is in the message)."""


def is_bag(p: Path) -> bool:
    """Whether ``p`` is read as a bag: a ``.bag``/``.mcap``/``.db3`` file or a ROS2 bag directory."""
    if p.is_dir():
        return (p / "metadata.yaml").is_file()
    return p.suffix.lower() in BAG_SUFFIXES


def _import() -> Any:
    try:
        from rosbags.highlevel import AnyReader
    except ImportError as exc:  # pragma: no cover - the io extra is installed in tests
        raise ImportError(
            f"reading ROS bags and MCAP files needs the 'rosbags' package ({exc}); "
            "install it with: pip install 'gyrobias[io]'"
        ) from None
    return AnyReader


def _open(p: Path) -> Any:
    """An opened AnyReader (the caller closes it); every failure becomes a ``BagError``."""
    any_reader = _import()
    from rosbags.typesys import Stores, get_typestore

    try:
        reader = any_reader([p], default_typestore=get_typestore(Stores.ROS2_HUMBLE))
        reader.open()
    except Exception as exc:  # rosbags/sqlite/zstd/lz4/struct errors on corrupt input: any type
        raise BagError(f"{p.name}: not a readable ROS bag or MCAP file ({_why(exc)})") from None
    return reader


def _why(exc: BaseException) -> str:
    text = " ".join(str(exc).split()) or type(exc).__name__
    return text if len(text) <= 200 else text[:197] + "..."


def topics(path: Path) -> list[tuple[str, str, int]]:
    """Every topic of a bag as ``(name, message type, message count)``, sorted by name."""
    reader = _open(path)
    try:
        return _topic_list(reader)
    finally:
        reader.close()


def _topic_list(reader: Any) -> list[tuple[str, str, int]]:
    out = []
    for name, info in sorted(reader.topics.items()):
        out.append((name, str(info.msgtype or "mixed types"), int(info.msgcount)))
    return out


def _describe(listing: Sequence[tuple[str, str, int]]) -> str:
    return "; ".join(
        f"{name} ({typ}, {count} message{'s' * (count != 1)})" for name, typ, count in listing
    )


def _choose_topic(p: Path, reader: Any, topic: str | None) -> tuple[str, list[Any], int]:
    listing = _topic_list(reader)
    if not listing:
        raise BagError(f"{p.name}: the bag is empty (no topics)")
    if topic is not None:
        match = [t for t in listing if t[0] == topic]
        if not match:
            raise BagError(f"{p.name}: no topic {topic!r}; topics: {_describe(listing)}")
        name, typ, count = match[0]
        if typ != IMU_TYPE:
            raise BagError(
                f"{p.name}: topic {name} has type {typ}, not {IMU_TYPE} (ROS1 sensor_msgs/Imu); "
                f"topics: {_describe(listing)}"
            )
    else:
        imu = [t for t in listing if t[1] == IMU_TYPE]
        if len(imu) != 1:
            what = (
                "no IMU topic"
                if not imu
                else f"{len(imu)} IMU topics, choose one with topic= (--topic)"
            )
            raise BagError(f"{p.name}: {what} ({IMU_TYPE}); topics: {_describe(listing)}")
        name, typ, count = imu[0]
    if count < 2:
        raise BagError(
            f"{p.name}: topic {name} has {count} message{'s' * (count != 1)}; "
            "a noise analysis needs at least 2"
        )
    connections = [c for c in reader.connections if c.topic == name]
    return name, connections, count


def _standard_layout(reader: Any, ros1: bool) -> bool:
    """Whether the bag's Imu definition is the standard one that the fast decoder assumes."""
    from rosbags.typesys import Stores, get_typestore

    ref = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    try:
        return all(reader.typestore.fielddefs[t] == ref.fielddefs[t] for t in _FIELDS)
    except KeyError:
        return False


def _fast_decode(
    raws: Sequence[bytes | memoryview], ros1: bool
) -> tuple[NDArray[np.float64], NDArray[np.int64]] | None:
    """Decode a batch of same-length standard Imu messages at fixed offsets; ``None`` if not possible.

    ROS1 layout: ``seq u4, sec u4, nsec u4, len u4, frame_id[len]``, then float64 orientation (4),
    its covariance (9), angular velocity (3), covariance (9), linear acceleration (3), covariance
    (9), unaligned little-endian. CDR (ROS2): a 4-byte encapsulation header (byte 1: 1 = little
    endian), ``sec i4, nanosec u4, len u4, frame_id[len]`` (NUL included), float64s aligned to 8
    bytes counted after the encapsulation header.
    """
    length = len(raws[0])
    if any(len(r) != length for r in raws) or length < 20:
        return None
    buf = np.frombuffer(b"".join(raws), dtype=np.uint8).reshape(len(raws), length)
    if ros1:
        order, base, sec_type = "<", 0, "u4"
    else:
        if not (np.all(buf[:, 0] == 0) and np.all(buf[:, 1] == buf[0, 1]) and buf[0, 1] in (0, 1)):
            return None
        order, base, sec_type = ("<" if buf[0, 1] == 1 else ">"), 4, "i4"
    head = base + (4 if ros1 else 0)  # ROS1 has seq before the stamp
    sid = np.ascontiguousarray(buf[:, head + 8 : head + 12]).view(f"{order}u4").ravel()
    if np.any(sid != sid[0]):
        return None
    pos = head + 12 + int(sid[0])
    if not ros1:
        pos = base + (-(-(pos - base) // 8)) * 8
    gyro, acc = pos + 13 * 8, pos + 25 * 8
    if acc + 24 + 72 != length:
        return None
    sec = (
        np.ascontiguousarray(buf[:, head : head + 4])
        .view(f"{order}{sec_type}")
        .ravel()
        .astype(np.int64)
    )
    nsec = (
        np.ascontiguousarray(buf[:, head + 4 : head + 8])
        .view(f"{order}u4")
        .ravel()
        .astype(np.int64)
    )
    out = np.empty((len(raws), 6))
    out[:, :3] = np.ascontiguousarray(buf[:, gyro : gyro + 24]).view(f"{order}f8")
    out[:, 3:] = np.ascontiguousarray(buf[:, acc : acc + 24]).view(f"{order}f8")
    return out, sec * 1_000_000_000 + nsec


def _slow_decode(
    reader: Any, raws: Sequence[bytes | memoryview], msgtype: str
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    out = np.empty((len(raws), 6))
    stamps = np.empty(len(raws), dtype=np.int64)
    for i, raw in enumerate(raws):
        m = reader.deserialize(raw, msgtype)
        w, a = m.angular_velocity, m.linear_acceleration
        out[i] = (w.x, w.y, w.z, a.x, a.y, a.z)
        stamps[i] = int(m.header.stamp.sec) * 1_000_000_000 + int(m.header.stamp.nanosec)
    return out, stamps


def read_bag(
    p: Path,
    topic: str | None,
    stamp: str,
    progress: Callable[[float], None] | None,
    allocate: Callable[[int], NDArray[np.float64]],
    *,
    fast: bool = True,
    allocate_stamps: Callable[[int], NDArray[np.int64]] | None = None,
    core: bool = True,
) -> tuple[NDArray[np.float64], NDArray[np.int64], str, str, str]:
    """Read one IMU topic: (n × 6 data, int64 ns stamps, time-column name, topic, format).

    ``allocate(n)`` returns the ``(n, 6)`` float64 output array (in memory or memory-mapped),
    ``allocate_stamps(n)`` the ``(n,)`` int64 stamps (default: in memory).
    ``stamp`` is ``"header"`` (``header.stamp``) or ``"receive"`` (the bag's record time).
    ``fast=False`` forces rosbags' deserializer for every message (the tests' reference);
    ``core=False`` reads the messages with rosbags (decoding them in batches with NumPy)
    instead of with the core's reader (:mod:`gyrobias.io._bagcore`), which is tried first and
    leaves to rosbags every bag it does not read (other layouts, damage, ...).
    """
    new_stamps = allocate_stamps or (lambda k: np.empty(k, dtype=np.int64))
    t_name = "header.stamp" if stamp == "header" else "receive time"
    if fast and core and p.is_file() and p.suffix.lower() == ".bag":
        got1 = _bagcore.read_ros1(p, topic, stamp == "receive", progress, allocate, new_stamps)
        if got1 is not None:
            return got1[0], got1[1], t_name, got1[2], "ROS1 bag"
    if fast and core and _bagcore.is_sqlite_bag(p):
        got3 = _bagcore.read_sqlite_bag(
            p, topic, stamp == "receive", progress, allocate, new_stamps
        )
        if got3 is not None:
            return got3[0], got3[1], t_name, got3[2], got3[3]
    reader = _open(p)
    try:
        name, connections, count = _choose_topic(p, reader, topic)
        ros1 = not reader.is2
        fast = fast and _standard_layout(reader, ros1)
        if fast and core and not ros1:
            got2 = _bagcore.read_ros2(
                reader, name, count, stamp == "receive", progress, allocate, new_stamps
            )
            if got2 is not None:
                return got2[0], got2[1], t_name, name, _format(p, reader)
        data = allocate(count)
        stamps = new_stamps(count)
        n = 0
        raws: list[bytes | memoryview] = []
        recv: list[int] = []
        msgtype = connections[0].msgtype

        def flush() -> None:
            nonlocal n, data, stamps
            decoded = _fast_decode(raws, ros1) if fast else None
            block, hstamps = decoded if decoded is not None else _slow_decode(reader, raws, msgtype)
            ts = np.asarray(recv, dtype=np.int64) if stamp == "receive" else hstamps
            m = len(raws)
            if n + m > len(stamps):  # the index undercounted: grow (rare)
                bigger = allocate(max(2 * len(stamps), n + m))
                bigger[:n] = data[:n]
                data = bigger
                more = new_stamps(len(bigger))
                more[:n] = stamps[:n]
                stamps = more
            data[n : n + m] = block
            stamps[n : n + m] = ts
            n += m
            raws.clear()
            recv.clear()
            if progress is not None:
                progress(min(n / count, 1.0))

        try:
            for _, t, raw in reader.messages(connections=connections):
                raws.append(raw)
                recv.append(t)
                if len(raws) >= BATCH:
                    flush()
            if raws:
                flush()
        except BagError:
            raise
        except Exception as exc:  # truncated chunks, bad compression, undecodable messages
            raise BagError(
                f"{p.name}: cannot read message {n + len(raws) + 1} of {name} ({_why(exc)})"
            ) from None
        if n < 2:
            raise BagError(
                f"{p.name}: topic {name} has {n} readable message(s); a noise analysis needs at least 2"
            )
        fmt = _format(p, reader)
        return data[:n], stamps[:n], t_name, name, fmt
    finally:
        reader.close()


def _format(p: Path, reader: Any) -> str:
    if not reader.is2:
        return "ROS1 bag"
    if p.is_dir():
        kinds = {f.suffix for f in p.iterdir()}
        return "ROS2 bag (mcap)" if ".mcap" in kinds else "ROS2 bag (sqlite3)"
    return "MCAP" if p.suffix.lower() == ".mcap" else "ROS2 sqlite3 (.db3)"

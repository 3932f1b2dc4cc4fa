"""The core's bag reader (gyrobias.io._bagcore + gyrocore::bags) against rosbags, value for value.

Every format and chunk compression of issue 37 is written here with its own writer (rosbags;
the ``mcap`` package for lz4 MCAP chunks, which rosbags cannot write). The reference is the
rosbags path of ``_bag.read_bag`` (``core=False``; ``fast=False`` is rosbags' deserializer
for every message); ``load`` with the core reader disabled gives the reference ``GyroLog``.
"""

from __future__ import annotations

import shutil
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gyrobias import _core
from gyrobias.io import _bag, _bagcore, load
from tests.test_bags import IMU, T0, TS1, TS2, imu_data, imu_message, regular

pytest.importorskip("rosbags")

from rosbags.rosbag1 import Writer as Writer1  # noqa: E402
from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin  # noqa: E402
from rosbags.rosbag2 import Writer as Writer2  # noqa: E402

#: (writer, chunk compression) of every format the core reads.
CASES = [
    ("ros1", "none"),
    ("ros1", "lz4"),
    ("ros1", "bz2"),
    ("db3", "none"),
    ("mcap-dir", "none"),
    ("mcap-dir", "zstd"),
    ("mcap", "none"),
    ("mcap", "zstd"),
    ("mcap", "lz4"),
]
FRAMES = ["", "a", "ab", "imu", "imu0", "imu_l", "imu_li", "imu_lin", "imu_link"]


def serialized(
    ros1: bool, stamps: Sequence[int], data: np.ndarray, frames: Sequence[str]
) -> list[bytes]:
    ts = TS1 if ros1 else TS2
    ser = ts.serialize_ros1 if ros1 else ts.serialize_cdr
    return [
        bytes(
            ser(imu_message(ros1, int(t), data[i, :3], data[i, 3:], frames[i % len(frames)]), IMU)
        )
        for i, t in enumerate(stamps)
    ]


def write(
    path: Path,
    kind: str,
    compression: str,
    stamps: Sequence[int] | np.ndarray,
    data: np.ndarray,
    *,
    receive: Sequence[int] | np.ndarray | None = None,
    frames: Sequence[str] = FRAMES,
    raws: list[bytes] | None = None,
    connections: int = 1,
) -> Path:
    """An Imu topic ``/imu`` (plus a String topic) in one format; returns the path to load."""
    ros1 = kind == "ros1"
    receive = stamps if receive is None else receive
    raws = serialized(ros1, stamps, data, frames) if raws is None else raws
    ts = TS1 if ros1 else TS2
    note = ts.types["std_msgs/msg/String"](data="hello")
    note_raw = (
        ts.serialize_ros1(note, "std_msgs/msg/String")
        if ros1
        else ts.serialize_cdr(note, "std_msgs/msg/String")
    )
    if kind == "mcap" and compression == "lz4":
        return _mcap_lz4(path.with_suffix(".mcap"), raws, receive)
    if ros1:
        target = path.with_suffix(".bag")
        w1 = Writer1(target)
        w1.chunk_threshold = 64 * 1024  # several chunks
        if compression != "none":
            w1.set_compression(getattr(Writer1.CompressionFormat, compression.upper()))
        with w1:
            conns = [
                w1.add_connection("/imu", IMU, typestore=ts, callerid=f"/node{k}")
                for k in range(connections)
            ]
            other = w1.add_connection("/note", "std_msgs/msg/String", typestore=ts)
            for i, (r, raw) in enumerate(zip(receive, raws)):
                w1.write(conns[i % connections], int(r), raw)
                if i % 100 == 0:
                    w1.write(other, int(r), note_raw)
        return target
    plugin = StoragePlugin.SQLITE3 if kind == "db3" else StoragePlugin.MCAP
    w2 = Writer2(path, version=9, storage_plugin=plugin)
    if compression == "zstd":
        w2.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
    with w2:
        conn = w2.add_connection("/imu", IMU, typestore=ts)
        other = w2.add_connection("/note", "std_msgs/msg/String", typestore=ts)
        for i, (r, raw) in enumerate(zip(receive, raws)):
            w2.write(conn, int(r), raw)
            if i % 100 == 0:
                w2.write(other, int(r), note_raw)
    if kind == "mcap":
        inner = next(path.glob("*.mcap"))
        single = path.parent / f"{path.name}_single.mcap"
        shutil.move(inner, single)
        shutil.rmtree(path)
        return single
    return path


def _mcap_lz4(
    path: Path, raws: list[bytes], receive: Sequence[int] | np.ndarray, chunked: bool = True
) -> Path:
    from mcap.writer import CompressionType, Writer

    msgdef = TS2.generate_msgdef(IMU, ros_version=2)[0]
    with open(path, "wb") as fh:
        w = Writer(fh, compression=CompressionType.LZ4, chunk_size=64 * 1024, use_chunking=chunked)
        w.start(profile="ros2", library="gyrobias tests")
        schema = w.register_schema(name=IMU, encoding="ros2msg", data=msgdef.encode())
        channel = w.register_channel(topic="/imu", message_encoding="cdr", schema_id=schema)
        for i, (r, raw) in enumerate(zip(receive, raws)):
            w.add_message(channel, log_time=int(r), data=raw, publish_time=int(r), sequence=i)
        w.finish()
    return path


def alloc(m: int) -> np.ndarray:
    return np.empty((m, 6))


def core_read(path: Path, stamp: str) -> tuple[Any, ...] | None:
    """The core reader alone (``None``: it leaves the bag to rosbags)."""
    new = lambda k: np.empty(k, dtype=np.int64)  # noqa: E731
    if path.suffix == ".bag":
        got = _bagcore.read_ros1(path, None, stamp == "receive", None, alloc, new)
        return None if got is None else (got[0], got[1])
    reader = _bag._open(path)
    try:
        name, _, count = _bag._choose_topic(path, reader, None)
        return _bagcore.read_ros2(reader, name, count, stamp == "receive", None, alloc, new)
    finally:
        reader.close()


def without_core(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(_bagcore, "read_ros1", lambda *a, **k: None)
    monkeypatch.setattr(_bagcore, "read_ros2", lambda *a, **k: None)


def assert_same_log(a: Any, b: Any) -> None:
    np.testing.assert_array_equal(a.data, b.data)
    np.testing.assert_array_equal(a.time, b.time)
    assert a.time_start == b.time_start and a.fs == b.fs
    assert (a.columns, a.units, a.topic, a.time_column) == (
        b.columns,
        b.units,
        b.topic,
        b.time_column,
    )
    da, db = a.sampling.to_dict(), b.sampling.to_dict()
    assert da.keys() == db.keys()
    for k in da:
        if isinstance(da[k], float) and np.isnan(da[k]):
            assert np.isnan(db[k]), k
        else:
            assert np.array_equal(da[k], db[k]), k


# --------------------------------------------------------------------------- value for value


@pytest.mark.parametrize(("kind", "compression"), CASES)
def test_core_reader_equals_rosbags_every_format(
    tmp_path: Path, kind: str, compression: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    n = 1500
    data = imu_data(n, seed=7)
    stamps = regular(n)
    rng = np.random.default_rng(3)
    receive = stamps + 1_000_000 + np.cumsum(rng.integers(0, 3, n)) * 10_000  # late, jittery
    path = write(tmp_path / "b", kind, compression, stamps, data, receive=receive)
    for stamp, expected in (("header", stamps), ("receive", receive)):
        core = core_read(path, stamp)
        assert core is not None, "the core reader must take every standard bag"
        ref = _bag.read_bag(path, None, stamp, None, alloc, fast=False)
        np.testing.assert_array_equal(core[0], ref[0])
        np.testing.assert_array_equal(core[1], ref[1])
        np.testing.assert_array_equal(core[0], data)
        np.testing.assert_array_equal(core[1], expected)
        seen: list[float] = []
        log = load(path, stamp=stamp, progress=seen.append)
        assert seen and seen[-1] == 1.0
        with monkeypatch.context() as m:
            without_core(m)
            assert_same_log(log, load(path, stamp=stamp))


@pytest.mark.parametrize(
    ("kind", "compression"), [("ros1", "lz4"), ("db3", "none"), ("mcap", "zstd")]
)
def test_repairs_gaps_columns_and_spill_equal_the_reference(
    tmp_path: Path, kind: str, compression: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    n = 800
    data = imu_data(n, seed=5)
    stamps = regular(n)
    stamps[[100, 101]] = stamps[[101, 100]]  # a swapped pair
    stamps = np.insert(stamps, 201, stamps[200])  # an exact duplicate
    data = np.insert(data, 201, data[200], axis=0)
    stamps[301:] += 500_000_000  # a gap
    receive = T0 + 1_000_000 + np.arange(len(stamps)) * 5_000_000  # in recording order
    path = write(tmp_path / "m", kind, compression, stamps, data, receive=receive)
    assert core_read(path, "header") is not None
    options: list[dict[str, Any]] = [
        {"repair": "sort"},
        {"repair": "sort,dedup", "fill_gaps": True},
        {"repair": "sort", "columns": "accel_z,gyro_x"},
        {"stamp": "receive", "fill_gaps": True},
        {"repair": "sort", "spill": True, "spill_dir": tmp_path},
    ]
    for kw in options:
        got = load(path, **kw)
        with monkeypatch.context() as m:
            without_core(m)
            assert_same_log(got, load(path, **kw))
    with pytest.raises(ValueError, match=r"out of order in 'header.stamp' at row 101"):
        load(path)


# --------------------------------------------------------------------------- fallback


def test_fallback_to_rosbags(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    n = 400
    data = imu_data(n, seed=2)
    stamps = regular(n)
    backward = stamps.copy()
    backward[[10, 11]] = backward[[11, 10]]  # receive times out of order: readers sort them
    bags = [
        write(tmp_path / "two", "ros1", "none", stamps, data, connections=2),
        write(tmp_path / "back1", "ros1", "lz4", stamps, data, receive=backward),
        write(tmp_path / "backm", "mcap", "zstd", stamps, data, receive=backward),
        _mcap_lz4(tmp_path / "flat.mcap", serialized(False, stamps, data, ["imu"]), stamps, False),
    ]
    bags.append(_custom_imu_bag(tmp_path / "custom.bag", stamps, data))
    for path in bags:
        assert core_read(path, "header") is None, path.name
        # rosbags returns messages in receive-time order: the header stamps of the swapped
        # pair are then out of order (repair="sort")
        log = load(path, repair="sort")
        ref = _bag.read_bag(path, None, "header", None, alloc, fast=False)
        np.testing.assert_array_equal(np.sort(log.data, axis=0), np.sort(ref[0], axis=0))
        with monkeypatch.context() as m:
            without_core(m)
            assert_same_log(log, load(path, repair="sort"))


def _custom_imu_bag(path: Path, stamps: np.ndarray, data: np.ndarray) -> Path:
    """A ROS1 bag whose sensor_msgs/Imu definition has an extra field (another md5sum)."""
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    ts = get_typestore(Stores.EMPTY)
    deps = ("std_msgs/msg/Header", "geometry_msgs/msg/Vector3", "geometry_msgs/msg/Quaternion")
    ts.register({k: TS1.fielddefs[k] for k in deps})
    text = TS1.generate_msgdef(IMU)[0].split("=" * 80)[0].strip() + "\nfloat64 temperature\n"
    ts.register(get_types_from_msg(text, IMU))
    msgdef, md5 = ts.generate_msgdef(IMU)
    t = ts.types
    vec = t["geometry_msgs/msg/Vector3"]
    with Writer1(path) as w:
        conn = w.add_connection("/imu", IMU, msgdef=msgdef, md5sum=md5)
        for i, s in enumerate(stamps):
            s = int(s)
            msg = t[IMU](
                header=t["std_msgs/msg/Header"](
                    seq=i,
                    stamp=t["builtin_interfaces/msg/Time"](sec=s // 10**9, nanosec=s % 10**9),
                    frame_id="imu",
                ),
                orientation=t["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
                orientation_covariance=np.zeros(9),
                angular_velocity=vec(x=data[i, 0], y=data[i, 1], z=data[i, 2]),
                angular_velocity_covariance=np.zeros(9),
                linear_acceleration=vec(x=data[i, 3], y=data[i, 4], z=data[i, 5]),
                linear_acceleration_covariance=np.zeros(9),
                temperature=25.0,
            )
            w.write(conn, s, ts.serialize_ros1(msg, IMU))
    return path


def test_other_layouts_keep_the_reference_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    n = 300
    data = imu_data(n, seed=2)
    stamps = regular(n)
    raws = serialized(False, stamps, data, ["imu"])
    raws[7] = raws[7] + bytes(8)  # trailing bytes: rosbags' deserializer refuses them too
    path = write(tmp_path / "long", "db3", "none", stamps, data, raws=raws)
    assert core_read(path, "header") is None
    with pytest.raises(ValueError) as core:
        load(path)
    with monkeypatch.context() as m:
        without_core(m)
        with pytest.raises(ValueError) as ref:
            load(path)
    assert str(core.value) == str(ref.value)
    assert "cannot read message" in str(core.value)


# --------------------------------------------------------------------------- damage


@pytest.mark.parametrize(("kind", "compression"), CASES)
def test_truncated_and_flipped_bags_give_the_reference_outcome(
    tmp_path: Path, kind: str, compression: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    n = 300
    path = write(tmp_path / "d", kind, compression, regular(n), imu_data(n, seed=1))
    target = (
        path if path.is_file() else next(p for p in path.iterdir() if p.suffix in (".db3", ".mcap"))
    )
    good = target.read_bytes()
    rng = np.random.default_rng(4)
    cuts = [len(good) // 3, len(good) // 2, len(good) - 100, len(good) - 7]
    flips = rng.integers(0, len(good) * 8, 12).tolist()
    for damage in [("cut", c) for c in cuts] + [("flip", b) for b in flips]:
        raw = bytearray(good)
        if damage[0] == "cut":
            raw = raw[: damage[1]]
        else:
            raw[damage[1] // 8] ^= 1 << (damage[1] % 8)
        target.write_bytes(bytes(raw))
        outcomes = []
        for core in (True, False):
            with monkeypatch.context() as m:
                if not core:
                    without_core(m)
                try:
                    log = load(path)
                    outcomes.append(("ok", log.data.tobytes(), log.time.tobytes()))  # type: ignore[union-attr]
                except ValueError as exc:
                    outcomes.append(("error", str(exc), b""))
        assert outcomes[0] == outcomes[1], damage
    target.write_bytes(good)


# --------------------------------------------------------------------------- the core's decoder


def _ros1_record(fields: dict[str, bytes], data: bytes) -> bytes:
    head = b"".join(
        len(f).to_bytes(4, "little") + f for f in (k.encode() + b"=" + v for k, v in fields.items())
    )
    return len(head).to_bytes(4, "little") + head + len(data).to_bytes(4, "little") + data


@settings(max_examples=25, deadline=None, derandomize=True)
@given(
    st.lists(st.floats(width=64), min_size=6, max_size=60),
    st.lists(st.text(alphabet="abc_/0123456789", max_size=12), min_size=1, max_size=4),
    st.booleans(),
)
def test_core_decoder_property(values: list[float], frames: list[str], ros1: bool) -> None:
    # rosbags' serializers are the reference: any floats (NaN payloads included, compared bit
    # for bit), any frame_id lengths mixed in one chunk
    rows = len(values) // 6
    data = np.array(values[: rows * 6]).reshape(rows, 6)
    stamps = T0 + np.arange(rows, dtype=np.int64) * 1_000_003
    raws = serialized(ros1, stamps, data, frames)
    out = np.full((rows + 1, 6), -1.0)
    got = np.zeros(rows + 1, dtype=np.int64)
    if ros1:
        chunk = index = b""
        for t, raw in zip(stamps.tolist(), raws):
            time = (t // 10**9).to_bytes(4, "little") + (t % 10**9).to_bytes(4, "little")
            index += time + len(chunk).to_bytes(4, "little")
            fields = {"op": b"\x02", "conn": (5).to_bytes(4, "little"), "time": time}
            chunk += _ros1_record(fields, raw)
        r = _core.bags.ros1_chunk(chunk, index, 5, False, -(2**63), out, got, 1)
        assert r == (rows, int(stamps[-1]), True)
    else:
        lengths = np.array([len(r) for r in raws], dtype=np.int64)
        assert _core.bags.cdr_messages(b"".join(raws), lengths, True, out, got, 1) == rows
    assert out[1:].view(np.int64).tolist() == data.view(np.int64).tolist()
    np.testing.assert_array_equal(got[1:], stamps)
    assert out[0].tolist() == [-1.0] * 6 and got[0] == 0  # rows before start are left alone

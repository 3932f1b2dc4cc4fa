"""ROS1 bags, ROS2 bags (sqlite3 and MCAP storage) and MCAP files through gyrobias.io and the CLI.

Every bag is written here with rosbags' own writers (no files from elsewhere). rosbags'
deserializer is the reference for the loader's fixed-offset decoder.
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

import gyrobias
from gyrobias.cli import main
from gyrobias.io import _bag, load, topics

pytest.importorskip("rosbags")

from rosbags.rosbag1 import Writer as Writer1  # noqa: E402
from rosbags.rosbag2 import StoragePlugin  # noqa: E402
from rosbags.rosbag2 import Writer as Writer2  # noqa: E402
from rosbags.typesys import Stores, get_typestore  # noqa: E402

TS1 = get_typestore(Stores.ROS1_NOETIC)
TS2 = get_typestore(Stores.ROS2_HUMBLE)
IMU = "sensor_msgs/msg/Imu"
T0 = 1_700_000_000_000_000_000  # epoch ns
FORMATS = ["ros1", "db3", "mcap-dir", "mcap"]


def imu_message(
    ros1: bool,
    stamp_ns: int,
    gyro: Sequence[float],
    accel: Sequence[float],
    frame: str = "imu_link",
) -> Any:
    ts = TS1 if ros1 else TS2
    types = ts.types
    header_kw: dict[str, Any] = {
        "stamp": types["builtin_interfaces/msg/Time"](
            sec=stamp_ns // 10**9, nanosec=stamp_ns % 10**9
        ),
        "frame_id": frame,
    }
    if ros1:
        header_kw["seq"] = 0
    vec = types["geometry_msgs/msg/Vector3"]
    return types[IMU](
        header=types["std_msgs/msg/Header"](**header_kw),
        orientation=types["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0),
        orientation_covariance=np.zeros(9),
        angular_velocity=vec(x=float(gyro[0]), y=float(gyro[1]), z=float(gyro[2])),
        angular_velocity_covariance=np.zeros(9),
        linear_acceleration=vec(x=float(accel[0]), y=float(accel[1]), z=float(accel[2])),
        linear_acceleration_covariance=np.zeros(9),
    )


def write_bag(
    path: Path,
    fmt: str,
    stamps: Sequence[int] | np.ndarray,
    data: np.ndarray,
    *,
    topic: str = "/imu",
    receive: Sequence[int] | np.ndarray | None = None,
    extra: Sequence[tuple[str, str, list[Any]]] = (),
    frames: Sequence[str] | None = None,
) -> Path:
    """Write an IMU topic (rows of data: gyro xyz, accel xyz) and extra topics; returns the path to load."""
    ros1 = fmt == "ros1"
    ts = TS1 if ros1 else TS2
    receive = stamps if receive is None else receive
    if ros1:
        target = path.with_suffix(".bag")
        writer: Any = Writer1(target)
    else:
        target = path
        plugin = StoragePlugin.SQLITE3 if fmt == "db3" else StoragePlugin.MCAP
        writer = Writer2(target, version=9, storage_plugin=plugin)
    serialize = ts.serialize_ros1 if ros1 else ts.serialize_cdr
    with writer:
        if len(stamps):
            conn = writer.add_connection(topic, IMU, typestore=ts)
        for i, (t, r) in enumerate(zip(stamps, receive)):
            frame = frames[i % len(frames)] if frames else "imu_link"
            msg = imu_message(ros1, int(t), data[i, :3], data[i, 3:], frame)
            writer.write(conn, int(r), serialize(msg, IMU))
        for name, msgtype, msgs in extra:
            c = writer.add_connection(name, msgtype, typestore=ts)
            for k, m in enumerate(msgs):
                writer.write(c, T0 + k, serialize(m, msgtype))
    if fmt == "mcap":  # a standalone .mcap file: the storage file of a ROS2 MCAP bag
        inner = next(target.glob("*.mcap"))
        single = path.parent / f"{path.name}_single.mcap"
        shutil.move(inner, single)
        shutil.rmtree(target)
        return single
    return target


def imu_data(n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    out = rng.normal(0.0, 0.01, (n, 6))
    out[:, 5] += 9.81
    return out


def regular(n: int, fs: float = 200.0) -> np.ndarray:
    return T0 + np.rint(np.arange(n) * 1e9 / fs).astype(np.int64)


# --------------------------------------------------------------------------- round trips


@pytest.mark.parametrize("fmt", FORMATS)
def test_bag_round_trip_every_format(tmp_path: Path, fmt: str) -> None:
    n = 500
    data = imu_data(n)
    path = write_bag(tmp_path / "b", fmt, regular(n), data)
    log = load(path)
    assert log.columns == ("gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z")
    assert log.units == ("rad/s",) * 3 + ("m/s^2",) * 3
    assert log.topic == "/imu" and log.time_column == "header.stamp"
    np.testing.assert_array_equal(log.data, data)  # float64 stored and read bit for bit
    assert log.fs == 200.0 and log.sampling.time_unit == "ns" and log.sampling.jitter == 0.0
    assert log.sampling.regular and log.sampling.n_gaps == 0
    assert log.time_start == pytest.approx(T0 / 1e9)
    assert (
        log.sampling.source_format
        == {
            "ros1": "ROS1 bag",
            "db3": "ROS2 bag (sqlite3)",
            "mcap-dir": "ROS2 bag (mcap)",
            "mcap": "MCAP",
        }[fmt]
    )
    assert log.unit_groups() == [("rad/s", [0, 1, 2]), ("m/s^2", [3, 4, 5])]
    assert topics(path) == [("/imu", IMU, n)]
    seen: list[float] = []
    np.testing.assert_array_equal(load(path, progress=seen.append).data, data)  # same values
    assert seen and seen[-1] == 1.0


@pytest.mark.parametrize("fmt", ["ros1", "db3"])
def test_fast_decoder_equals_rosbags_deserializer(tmp_path: Path, fmt: str) -> None:
    # frame ids of every length mod 8 exercise the CDR alignment; mixed lengths in one batch
    # take the deserializer path, so write one bag per frame id plus one with all of them
    n = 40
    data = imu_data(n, seed=3)
    stamps = regular(n)
    for k, frame in enumerate(
        ["", "a", "ab", "imu", "imu0", "imu_l", "imu_li", "imu_lin", "imu_link"] + [None]
    ):  # type: ignore[list-item]
        frames = ["", "a", "ab", "imu", "imu0"] if frame is None else [frame]
        path = write_bag(tmp_path / f"f{k}", fmt, stamps, data, frames=frames)
        fast = _bag.read_bag(path, None, "header", None, lambda m: np.empty((m, 6)))
        slow = _bag.read_bag(path, None, "header", None, lambda m: np.empty((m, 6)), fast=False)
        np.testing.assert_array_equal(fast[0], slow[0])
        np.testing.assert_array_equal(fast[1], slow[1])
        np.testing.assert_array_equal(fast[0], data)
        np.testing.assert_array_equal(fast[1], stamps)


@settings(max_examples=15, deadline=None)
@given(
    st.lists(st.floats(allow_nan=False, allow_infinity=False, width=64), min_size=12, max_size=36),
    st.text(alphabet="abc_/0123456789", max_size=12),
    st.booleans(),
)
def test_decoder_property(
    tmp_path_factory: pytest.TempPathFactory, values: list[float], frame: str, ros1: bool
) -> None:
    rows = len(values) // 6
    data = np.array(values[: rows * 6]).reshape(rows, 6)
    stamps = T0 + np.arange(rows, dtype=np.int64) * 1_000_003
    ts = TS1 if ros1 else TS2
    serialize = ts.serialize_ros1 if ros1 else ts.serialize_cdr
    raws = [
        serialize(imu_message(ros1, int(t), d[:3], d[3:], frame), IMU) for t, d in zip(stamps, data)
    ]
    decoded = _bag._fast_decode(raws, ros1)
    assert decoded is not None
    np.testing.assert_array_equal(decoded[0], data)
    np.testing.assert_array_equal(decoded[1], stamps)


def test_topic_selection_columns_and_receive_time(tmp_path: Path) -> None:
    n = 300
    data = imu_data(n)
    stamps = regular(n)
    receive = stamps + 2_000_000 + (np.arange(n) % 3) * 100_000  # late and jittery
    extra_data = imu_data(50, seed=9)
    extra_msgs = [
        imu_message(False, int(t), d[:3], d[3:]) for t, d in zip(regular(50, 10.0), extra_data)
    ]
    string = TS2.types["std_msgs/msg/String"]
    path = write_bag(
        tmp_path / "multi",
        "db3",
        stamps,
        data,
        topic="/imu0",
        receive=receive,
        extra=[
            ("/imu1", IMU, extra_msgs),
            ("/note", "std_msgs/msg/String", [string(data="hello")]),
        ],
    )
    with pytest.raises(ValueError) as err:
        load(path)
    msg = str(err.value)
    assert msg.startswith("multi: 2 IMU topics, choose one with topic= (--topic)")
    for part in (
        "/imu0 (sensor_msgs/msg/Imu, 300 messages)",
        "/imu1 (sensor_msgs/msg/Imu, 50 messages)",
        "/note (std_msgs/msg/String, 1 message)",
    ):
        assert part in msg
    one = load(path, topic="/imu1")
    np.testing.assert_array_equal(one.data, extra_data)
    assert one.fs == 10.0
    gyro = load(path, topic="/imu0", columns="gyro")
    assert gyro.columns == ("gyro_x", "gyro_y", "gyro_z") and gyro.units == ("rad/s",) * 3
    np.testing.assert_array_equal(gyro.data, data[:, :3])
    az = load(path, topic="/imu0", columns=["accel_z", 0])
    np.testing.assert_array_equal(az.data, data[:, [5, 0]])
    assert az.units == ("m/s^2", "rad/s")
    rx = load(path, topic="/imu0", stamp="receive")
    assert rx.time_column == "receive time"
    assert rx.time_start == pytest.approx((T0 + 2_000_000) / 1e9)
    assert rx.sampling.jitter is not None and rx.sampling.jitter > 0.01
    with pytest.raises(
        ValueError, match="topic /note has type std_msgs/msg/String, not sensor_msgs/msg/Imu"
    ):
        load(path, topic="/note")
    with pytest.raises(ValueError, match="no topic '/nope'; topics: /imu0"):
        load(path, topic="/nope")


def test_units_for_bags(tmp_path: Path) -> None:
    path = write_bag(tmp_path / "u", "ros1", regular(20), imu_data(20))
    assert load(path, units="gyro_x=rad/s").units[0] == "rad/s"  # agreeing units are accepted
    with pytest.raises(ValueError, match=r"stores gyro_x in rad/s \(sensor_msgs/Imu\), not deg/s"):
        load(path, units="deg/s")
    for kwargs in ({"delimiter": ","}, {"time_column": "t"}, {"skip_rows": 1}, {"time_unit": "s"}):
        with pytest.raises(ValueError, match="does not apply to bags"):
            load(path, **kwargs)  # type: ignore[arg-type]


# --------------------------------------------------------------------------- timestamps


def test_out_of_order_duplicates_gaps_and_repairs(tmp_path: Path) -> None:
    n = 400
    data = imu_data(n, seed=5)
    stamps = regular(n)
    order = np.arange(n)
    order[[100, 101]] = [101, 100]  # one swapped pair
    stamps_written = stamps[order]
    data_written = data[order]
    # an exact duplicate message after row 200 and a 0.5 s gap (100 samples) before row 300
    dup_at = 200
    stamps_written = np.insert(stamps_written, dup_at + 1, stamps_written[dup_at])
    data_written = np.insert(data_written, dup_at + 1, data_written[dup_at], axis=0)
    stamps_written[301:] += 500_000_000
    receive = T0 + 1_000_000 + np.arange(len(stamps_written)) * 5_000_000  # in recording order
    path = write_bag(tmp_path / "messy", "mcap", stamps_written, data_written, receive=receive)
    with pytest.raises(
        ValueError, match=r"out of order in 'header.stamp' at row 101 .*repair='sort'"
    ):
        load(path)
    log = load(path, repair="sort")
    rep = log.sampling
    assert rep.n_out_of_order == 1 and rep.out_of_order_rows.tolist() == [101]
    assert rep.n_exact_duplicates == 1 and rep.duplicate_rows.tolist() == [201]
    assert rep.n_gaps == 1 and rep.gap_rows.tolist() == [301] and rep.missing_samples == 100
    assert any("sorted by timestamp" in w for w in rep.warnings)
    assert any(
        "repeat the previous one exactly" in w and "--repair dedup" in w for w in rep.warnings
    )
    np.testing.assert_array_equal(log.data[:201], data[:201])
    clean = load(path, repair=["sort", "dedup"])
    assert (
        clean.n_samples == n
        and clean.sampling.n_duplicates == 0
        and clean.sampling.n_exact_duplicates == 1
    )
    assert len(clean.sampling.repairs) == 2 and "dropped 1 sample" in clean.sampling.repairs[1]
    np.testing.assert_array_equal(clean.data, data)
    filled = load(path, repair="sort,dedup", fill_gaps=True)
    assert filled.n_samples == n + 100 and filled.sampling.filled_samples == 100
    assert np.isnan(filled.data[300:400]).all() and np.isfinite(filled.data[:300]).all()
    np.testing.assert_array_equal(filled.data[400:], data[300:])
    assert filled.time is not None
    np.testing.assert_allclose(np.diff(filled.time), 0.005, rtol=0, atol=1e-9)
    d = filled.sampling.to_dict()
    assert d["filled_samples"] == 100 and d["n_out_of_order"] == 1 and d["source_format"] == "MCAP"


# --------------------------------------------------------------------------- bad input


def test_bad_bags_give_one_line_errors(tmp_path: Path) -> None:
    string = TS2.types["std_msgs/msg/String"]
    cases: list[tuple[Path, str]] = []
    cases.append(
        (
            write_bag(
                tmp_path / "noimu",
                "db3",
                [],
                np.zeros((0, 6)),
                extra=[("/chatter", "std_msgs/msg/String", [string(data="x")] * 3)],
            ),
            r"noimu: no IMU topic \(sensor_msgs/msg/Imu\); topics: /chatter \(std_msgs/msg/String, 3 messages\)",
        )
    )
    cases.append(
        (write_bag(tmp_path / "empty", "ros1", [], np.zeros((0, 6))), "empty.bag: the bag is empty")
    )
    cases.append(
        (
            write_bag(tmp_path / "one", "mcap-dir", regular(1), imu_data(1)),
            "one: topic /imu has 1 message; a noise analysis needs at least 2",
        )
    )
    good = write_bag(tmp_path / "good", "ros1", regular(3000), imu_data(3000))
    truncated = tmp_path / "truncated.bag"
    truncated.write_bytes(good.read_bytes()[: good.stat().st_size // 2])
    cases.append((truncated, "truncated.bag: "))
    junk = tmp_path / "junk.mcap"
    junk.write_bytes(b"\x89MCAP0\r\n" + bytes(range(256)) * 4)
    cases.append((junk, "junk.mcap: not a readable ROS bag or MCAP file"))
    zero = tmp_path / "zero.db3"
    zero.write_bytes(b"")
    cases.append((zero, "zero.db3: "))
    for path, pattern in cases:
        with pytest.raises(ValueError, match=pattern):
            load(path)
    for path, _ in cases:
        code = main(["allan", str(path), "--no-confidence"])
        assert code == 2


def test_cli_errors_for_bags_are_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    good = write_bag(tmp_path / "good", "ros1", regular(3000), imu_data(3000))
    truncated = tmp_path / "cut.bag"
    truncated.write_bytes(good.read_bytes()[:-700])
    assert main(["allan", str(truncated)]) == 2
    err = capsys.readouterr().err
    assert (
        err.startswith("gyrobias: error: cut.bag: ")
        and err.count("\n") == 1
        and "Traceback" not in err
    )


def test_pipes_and_devices_are_refused(tmp_path: Path) -> None:
    import os

    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    with pytest.raises(ValueError, match="not a regular file"):
        load(fifo)
    with pytest.raises(ValueError, match="not a regular file"):
        load("/dev/null")


# --------------------------------------------------------------------------- spill


def test_spilled_bag_is_a_memmap_with_the_same_values(tmp_path: Path) -> None:
    n = 1000
    data = imu_data(n)
    path = write_bag(tmp_path / "s", "db3", regular(n), data)
    log = load(path, spill=True, spill_dir=tmp_path, columns="accel")
    assert isinstance(log.data, np.memmap)
    np.testing.assert_array_equal(log.data, data[:, 3:])
    # The time vector is spilled with the samples (issue 12), equal to the in-memory one.
    in_memory = load(path, columns="accel")
    assert isinstance(log.time, np.memmap) and not isinstance(in_memory.time, np.memmap)
    np.testing.assert_array_equal(log.time, in_memory.time)
    assert log.time_start == in_memory.time_start
    assert not [p for p in tmp_path.iterdir() if p.name.startswith("gyrobias-")]  # unlinked at once
    ref = gyrobias.allan.adev(data[:, 3:], 200.0, confidence=None)
    got = gyrobias.allan.adev(log.data, 200.0, confidence=None)
    for a, b in zip(ref, got):  # type: ignore[arg-type]
        np.testing.assert_array_equal(a.avar, b.avar)


# --------------------------------------------------------------------------- CLI end to end


@pytest.mark.parametrize("fmt", ["ros1", "db3", "mcap"])
def test_allan_fit_kalibr_from_a_bag(
    tmp_path: Path, fmt: str, capsys: pytest.CaptureFixture[str]
) -> None:
    import yaml

    n, fs = 20_000, 200.0
    arw_g, vrw_a = 2e-3, 3e-2  # rad/s/√Hz and m/s²/√Hz (white noise: σ per sample = N·√fs)
    rng = np.random.default_rng(11)
    data = np.empty((n, 6))
    data[:, :3] = rng.normal(0.0, arw_g * np.sqrt(fs), (n, 3))
    data[:, 3:] = rng.normal(0.0, vrw_a * np.sqrt(fs), (n, 3))
    data[:, 5] += 9.81
    path = write_bag(tmp_path / "imu", fmt, regular(n, fs), data)
    imu = tmp_path / "imu.yaml"
    png = tmp_path / "adev.png"
    # the figures take seconds: draw them once, for one gyro and one accelerometer axis
    plot = ["--plot", str(png), "--columns", "gyro_x,accel_z"] if fmt == "mcap" else []
    code = main(["allan", str(path), "--fit", "--kalibr", str(imu), "--no-progress", *plot])
    out = capsys.readouterr().out
    assert code == 0
    assert "ADEV of gyro_x [rad/s]" in out and "ADEV of accel_z [m/s^2]" in out
    assert ("ADEV of gyro_y" in out) == (not plot)
    doc = yaml.safe_load(imu.read_text())
    # a white-noise-only log: the fitted N is the simulated density within a few % (the
    # estimator's scatter at τ0 with 2·10⁴ samples is ≈ 0.7 %, the joint fit's ±1σ a few %)
    assert doc["gyroscope_noise_density"] == pytest.approx(arw_g, rel=0.1)
    assert doc["accelerometer_noise_density"] == pytest.approx(vrw_a, rel=0.1)
    assert doc["update_rate"] == 200 and doc["rostopic"] == "/imu"
    if plot:
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert (tmp_path / "adev_gyro_x.png").exists() and (tmp_path / "adev_accel_z.png").exists()

"""ROS2 sqlite3 bags read by the core (gyrocore::bags::read_sqlite, rusqlite) against rosbags.

``_bagcore.read_sqlite_bag`` reads a ``.db3`` file or a sqlite3 bag directory without opening
it with rosbags: the small tables are checked as rosbags' ``AnyReader.open`` checks them and
the core reads the topic's rows with rosbags' query. Each result is compared value for value
with the rosbags path of ``_bag.read_bag`` (``core=False``; ``fast=False``: rosbags'
deserializer for every message), every bag it leaves must give the reference outcome, and the
user's files must be left exactly as they were.
"""

from __future__ import annotations

import hashlib
import shutil
import sqlite3
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gyrobias import _core
from gyrobias.io import _bag, _bagcore, load
from tests.test_bags import IMU, TS2, imu_data, regular
from tests.test_bags_core import alloc, assert_same_log, serialized, without_core, write

pytest.importorskip("rosbags")

from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin  # noqa: E402
from rosbags.rosbag2 import Writer as Writer2  # noqa: E402


def stamps_alloc(k: int) -> np.ndarray:
    return np.empty(k, dtype=np.int64)


def fast_read(path: Path, stamp: str, topic: str | None = None) -> Any:
    return _bagcore.read_sqlite_bag(path, topic, stamp == "receive", None, alloc, stamps_alloc)


def reference(path: Path, stamp: str, topic: str | None = None) -> Any:
    return _bag.read_bag(path, topic, stamp, None, alloc, fast=False, core=False)


def bare_db3(directory: Path) -> Path:
    """The storage file of a one-file bag directory, moved out of it (a plain ``.db3``)."""
    inner = next(directory.glob("*.db3"))
    single = directory.parent / f"{directory.name}.db3"
    shutil.move(inner, single)
    shutil.rmtree(directory)
    return single


def snapshot(directory: Path) -> dict[str, tuple[int, int, str]]:
    """Every file under ``directory``: size, mtime (ns) and SHA-256."""
    return {
        str(f.relative_to(directory)): (
            f.stat().st_size,
            f.stat().st_mtime_ns,
            hashlib.sha256(f.read_bytes()).hexdigest(),
        )
        for f in sorted(directory.rglob("*"))
        if f.is_file()
    }


@pytest.mark.parametrize("bare", [False, True])
def test_fast_path_equals_rosbags_value_for_value(tmp_path: Path, bare: bool) -> None:
    n = 1200
    data = imu_data(n, seed=11)
    stamps = regular(n)
    # receive times in runs of 3 ties: the order of equal timestamps is SQLite's for rosbags'
    # query, which the core runs verbatim
    receive = regular(1)[0] + np.repeat(np.arange(n // 3), 3) * 5_000_000
    path = write(tmp_path / "b", "db3", "none", stamps, data, receive=receive)
    if bare:
        path = bare_db3(path)
    for stamp in ("header", "receive"):
        got = fast_read(path, stamp)
        assert got is not None, "the fast path must take a standard sqlite3 bag"
        ref = reference(path, stamp)
        np.testing.assert_array_equal(got[0], ref[0])
        np.testing.assert_array_equal(got[1], ref[1])
        assert (got[2], got[3]) == (ref[3], ref[4])
        np.testing.assert_array_equal(got[0], data)


def _split(tmp_path: Path, data: np.ndarray, stamps: np.ndarray, parts: list[slice]) -> Path:
    """A two-file bag directory: one bag per part, the files gathered with a merged
    ``metadata.yaml`` (rosbags' writer does not split); the second file has no ``/note``."""
    from ruamel.yaml import YAML

    target = tmp_path / "split"
    metas = []
    for k, part in enumerate(parts):
        one = tmp_path / f"part{k}"
        w = Writer2(one, version=9, storage_plugin=StoragePlugin.SQLITE3)
        with w:
            conn = w.add_connection("/imu", IMU, typestore=TS2)
            if k == 0:
                w.add_connection("/note", "std_msgs/msg/String", typestore=TS2)
            for raw, t in zip(serialized(False, stamps[part], data[part], ["imu"]), stamps[part]):
                w.write(conn, int(t), raw)
        yaml = YAML(typ="safe")
        metas.append(yaml.load((one / "metadata.yaml").read_text()))
        target.mkdir(exist_ok=True)
        shutil.move(next(one.glob("*.db3")), target / f"split_{k}.db3")
        shutil.rmtree(one)
    info = metas[0]["rosbag2_bagfile_information"]
    info["relative_file_paths"] = [f"split_{k}.db3" for k in range(len(parts))]
    info["message_count"] = len(stamps)
    for t in info["topics_with_message_count"]:
        if t["topic_metadata"]["name"] == "/imu":
            t["message_count"] = len(stamps)
    info["files"] = []
    yaml = YAML(typ="safe")
    yaml.default_flow_style = False
    with open(target / "metadata.yaml", "w") as fh:
        yaml.dump(metas[0], fh)
    return target


def test_split_bag_reads_its_files_in_order(tmp_path: Path) -> None:
    n = 900
    data = imu_data(n, seed=3)
    stamps = regular(n)
    path = _split(tmp_path, data, stamps, [slice(0, 400), slice(400, n)])
    for stamp in ("header", "receive"):
        got = fast_read(path, stamp)
        assert got is not None
        ref = reference(path, stamp)
        np.testing.assert_array_equal(got[0], ref[0])
        np.testing.assert_array_equal(got[1], ref[1])
        np.testing.assert_array_equal(got[0], data)
        np.testing.assert_array_equal(got[1], stamps)


def test_split_bag_with_a_file_without_the_topic(tmp_path: Path) -> None:
    """The second file holds only ``/note``: it is scanned (as rosbags' open does), not read."""
    from ruamel.yaml import YAML

    n = 600
    data = imu_data(n, seed=6)
    stamps = regular(n)
    path = _split(tmp_path, data, stamps, [slice(0, 400), slice(400, n)])
    other = tmp_path / "other"
    w = Writer2(other, version=9, storage_plugin=StoragePlugin.SQLITE3)
    with w:
        conn = w.add_connection("/note", "std_msgs/msg/String", typestore=TS2)
        note = TS2.serialize_cdr(TS2.types["std_msgs/msg/String"](data="x"), "std_msgs/msg/String")
        for t in stamps[400:]:
            w.write(conn, int(t), bytes(note))
    shutil.move(next(other.glob("*.db3")), path / "split_1.db3")
    yaml = YAML(typ="safe")
    meta = yaml.load((path / "metadata.yaml").read_text())
    for t in meta["rosbag2_bagfile_information"]["topics_with_message_count"]:
        t["message_count"] = 400 if t["topic_metadata"]["name"] == "/imu" else n - 400
    with open(path / "metadata.yaml", "w") as fh:
        yaml.dump(meta, fh)
    got = fast_read(path, "header")
    assert got is not None
    ref = reference(path, "header")
    np.testing.assert_array_equal(got[0], ref[0])
    np.testing.assert_array_equal(got[1], ref[1])
    np.testing.assert_array_equal(got[0], data[:400])


def test_damage_in_any_file_of_a_split_bag_gives_the_reference_outcome(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """rosbags' open scans every file's messages table: a damaged page anywhere is its error,
    the fast path (which scans every file too) must not read around it."""
    n = 900
    path = _split(tmp_path, imu_data(n, seed=8), regular(n), [slice(0, 400), slice(400, n)])
    second = path / "split_1.db3"
    good = second.read_bytes()
    for cut in (len(good) // 3, len(good) - 4096, len(good) - 1):
        second.write_bytes(good[:cut])
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
        assert outcomes[0] == outcomes[1], cut
    second.write_bytes(good)


@pytest.mark.parametrize("mode", ["file", "message"])
def test_compressed_bags_keep_the_reference_values(
    tmp_path: Path, mode: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """zstd per file or per message: rosbags opens them (the fast path declines); per file,
    the core then reads the storage files rosbags decompressed, per message rosbags reads."""
    n = 500
    data = imu_data(n, seed=9)
    stamps = regular(n)
    path = tmp_path / mode
    w = Writer2(path, version=9, storage_plugin=StoragePlugin.SQLITE3)
    w.set_compression(getattr(CompressionMode, mode.upper()), CompressionFormat.ZSTD)
    with w:
        conn = w.add_connection("/imu", IMU, typestore=TS2)
        for raw, t in zip(serialized(False, stamps, data, ["imu"]), stamps):
            w.write(conn, int(t), raw)
    assert fast_read(path, "header") is None
    reader = _bag._open(path)
    try:
        name, _, count = _bag._choose_topic(path, reader, None)
        core = _bagcore.read_ros2(reader, name, count, False, None, alloc, stamps_alloc)
    finally:
        reader.close()
    assert (core is not None) == (mode == "file")
    log = load(path)
    np.testing.assert_array_equal(log.data, data)
    with monkeypatch.context() as m:
        without_core(m)
        assert_same_log(log, load(path))


def test_reading_leaves_every_file_unchanged(tmp_path: Path) -> None:
    """A WAL-mode database, also under a name that needs URI escaping: no ``-wal``/``-shm``
    file appears, no byte or mtime changes (the core opens ``?mode=ro&immutable=1``)."""
    n = 300
    data = imu_data(n, seed=1)
    stamps = regular(n)
    base = tmp_path / "bags"
    base.mkdir()
    path = write(base / "b", "db3", "none", stamps, data)
    db = next(path.glob("*.db3"))
    con = sqlite3.connect(db)
    assert con.execute("PRAGMA journal_mode=WAL").fetchone() == ("wal",)
    con.close()
    # rosbags opens 'file:<path>?immutable=1' unescaped: it cannot read this name (nor can the
    # fast path, which then leaves it to rosbags' error); the core escapes it
    odd = base / "c?d#e %41.db3"
    shutil.copy2(db, odd)
    before = snapshot(base)
    for target in (path, odd):
        out = np.empty((n, 6))
        _core.bags.read_sqlite([db if target == path else odd], "/imu", True, out, stamps_alloc(n))
        np.testing.assert_array_equal(out, data)
        got = fast_read(target, "header")
        assert (got is not None) == (target == path)
        load(path)
        assert snapshot(base) == before
    assert not list(base.rglob("*-wal")) and not list(base.rglob("*-shm"))


def test_core_reader_errors_are_value_errors(tmp_path: Path) -> None:
    n = 200
    data = imu_data(n, seed=2)
    db = bare_db3(write(tmp_path / "e", "db3", "none", regular(n), data))
    out, st_ = np.empty((n, 6)), stamps_alloc(n)
    assert _core.bags.sqlite_count([db], "/imu") == n
    assert _core.bags.sqlite_count([db], "/absent") == 0
    seen: list[float] = []
    assert (
        _core.bags.read_sqlite(
            [db, db], "/imu", False, np.empty((2 * n, 6)), stamps_alloc(2 * n), seen.append
        )
        == 2 * n
    )
    assert seen[0] == 0.0 and seen[-1] == 1.0 and seen == sorted(seen)
    cases: list[tuple[list[Path], str, np.ndarray, np.ndarray, str]] = [
        ([db], "/absent", out, st_, "/absent is not in the bag"),
        ([db], "/note", out, st_, "std_msgs/msg/String"),
        ([db], "/imu", out[: n - 1], st_[: n - 1], "more messages than the 199 output rows"),
        ([db], "/imu", out[:10], st_, "shape mismatch in data"),
    ]
    junk = tmp_path / "junk.db3"
    junk.write_bytes(b"not a database at all" * 100)
    cut = tmp_path / "cut.db3"
    cut.write_bytes(db.read_bytes()[: db.stat().st_size // 2])
    empty = tmp_path / "empty.db3"
    sqlite3.connect(empty).close()
    for bad in (junk, cut, empty, tmp_path / "missing.db3"):
        cases.append(([bad], "/imu", out, st_, "not a readable ROS2 sqlite3 bag"))
    for paths, topic, d, s, message in cases:
        with pytest.raises(ValueError, match=message):
            _core.bags.read_sqlite(paths, topic, False, d, s)
    assert not (tmp_path / "missing.db3").exists()

    def stop(_: float) -> None:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        _core.bags.read_sqlite([db], "/imu", False, out, st_, stop)
    with pytest.raises(TypeError):
        _core.bags.read_sqlite(str(db), "/imu", False, out, st_)  # type: ignore[arg-type]


def test_bags_the_fast_path_leaves_give_the_reference_outcome(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Every bag the fast path declines: rosbags' error or values, exactly as before."""
    from ruamel.yaml import YAML

    n = 300
    data = imu_data(n, seed=4)
    stamps = regular(n)
    one = bare_db3(write(tmp_path / "one", "db3", "none", stamps[:1], data[:1]))
    raws = serialized(False, stamps, data, ["imu"])
    raws[5] = raws[5] + bytes(8)  # another layout: rosbags' deserializer refuses it too
    longer = write(tmp_path / "long", "db3", "none", stamps, data, raws=raws)
    under = write(tmp_path / "under", "db3", "none", stamps, data)
    over = write(tmp_path / "over", "db3", "none", stamps, data)
    yaml = YAML(typ="safe")
    for bag, count in ((under, n - 10), (over, n + 10)):  # metadata.yaml counts disagree
        meta = yaml.load((bag / "metadata.yaml").read_text())
        for t in meta["rosbag2_bagfile_information"]["topics_with_message_count"]:
            if t["topic_metadata"]["name"] == "/imu":
                t["message_count"] = count
        with open(bag / "metadata.yaml", "w") as fh:
            yaml.dump(meta, fh)
    good = bare_db3(write(tmp_path / "good", "db3", "none", stamps, data))
    cases: list[tuple[Path, dict[str, Any], bool]] = [
        (one, {}, False),
        (longer, {}, False),
        (under, {}, False),
        (over, {}, True),
        (good, {"topic": "/note"}, False),
        (good, {"topic": "/nothing"}, False),
    ]
    for path, kw, taken in cases:
        assert (fast_read(path, "header", kw.get("topic")) is not None) == taken, path.name
        outcomes = []
        for core in (True, False):
            with monkeypatch.context() as m:
                if not core:
                    without_core(m)
                try:
                    log = load(path, **kw)
                    outcomes.append(("ok", log.data.tobytes(), log.time.tobytes()))  # type: ignore[union-attr]
                except ValueError as exc:
                    outcomes.append(("error", str(exc), b""))
        assert outcomes[0] == outcomes[1], path.name


@settings(max_examples=8, deadline=None, derandomize=True)
@given(st.lists(st.integers(0, 2), min_size=3, max_size=40), st.booleans())
def test_order_of_equal_receive_times_is_rosbags(steps: list[int], receive: bool) -> None:
    """Receive times with runs of ties: the core's rows come in rosbags' order."""
    import tempfile

    n = len(steps)
    data = imu_data(n, seed=n)
    stamps = regular(n)
    recv = regular(1)[0] + np.cumsum(steps).astype(np.int64)
    with tempfile.TemporaryDirectory() as tmp:
        path = write(Path(tmp) / "t", "db3", "none", stamps, data, receive=recv)
        stamp = "receive" if receive else "header"
        got = fast_read(path, stamp)
        assert got is not None
        ref = reference(path, stamp)
        np.testing.assert_array_equal(got[0], ref[0])
        np.testing.assert_array_equal(got[1], ref[1])


@pytest.mark.parametrize(("version", "definitions"), [(8, True), (9, False)])
def test_bag_versions_and_missing_definitions_equal_rosbags(
    tmp_path: Path, version: int, definitions: bool
) -> None:
    """rosbag2 version 8, and a bag whose ``message_definitions`` table is empty (rosbags then
    uses its Humble types): the fast path takes them, value for value, directory and file."""
    n = 250
    data = imu_data(n, seed=version)
    stamps = regular(n)
    path = tmp_path / f"v{version}"
    w = Writer2(path, version=version, storage_plugin=StoragePlugin.SQLITE3)
    with w:
        conn = w.add_connection("/imu", IMU, typestore=TS2)
        for raw, t in zip(serialized(False, stamps, data, ["imu"]), stamps):
            w.write(conn, int(t), raw)
    if not definitions:
        con = sqlite3.connect(next(path.glob("*.db3")))
        con.execute("DELETE FROM message_definitions")
        con.commit()
        con.close()
    for bare in (False, True):
        target = bare_db3(path) if bare else path
        got = fast_read(target, "receive")
        assert got is not None
        ref = reference(target, "receive")
        np.testing.assert_array_equal(got[0], ref[0])
        np.testing.assert_array_equal(got[1], ref[1])
        np.testing.assert_array_equal(got[0], data)

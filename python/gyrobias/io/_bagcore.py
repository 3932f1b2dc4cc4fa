"""The core's bag reader: ``sensor_msgs/Imu`` decoded in bulk from the serialized bytes.

The containers are walked here (ROS1 bag index and chunk records, MCAP top-level records),
their chunks decompressed by the same libraries rosbags uses (``lz4.frame``, ``bz2``,
``zstd``; in worker threads, which release the GIL), and every
decompressed chunk handed whole to ``gyrocore::bags``, which decodes the topic's messages at
their fixed offsets straight into the output arrays. Only one chunk (per worker) is in memory
at a time. The sqlite3 store (``.db3``) is read whole by the core
(``gyrocore::bags::read_sqlite``: SQLite opened read-only and immutable, rosbags' query), the
blobs decoded as SQLite steps through them.

Every function returns ``None`` when it does not apply or meets anything unexpected: another
message layout, several connections on the topic, receive times out of order (the readers
return messages in receive-time order; a file-order walk then differs), a count that disagrees
with the bag's index, or any corrupt byte. The caller then reads the bag with rosbags, which
gives the same values and raises today's error for a damaged bag.
"""

from __future__ import annotations

import os
import struct
import zlib
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from gyrobias import _core

if TYPE_CHECKING:
    from concurrent.futures import Future

__all__ = ["ROS1_IMU_MD5", "is_sqlite_bag", "read_ros1", "read_ros2", "read_sqlite_bag"]

IMU_TYPE = "sensor_msgs/msg/Imu"
#: md5sum of the ROS1 ``sensor_msgs/Imu`` definition: the layout the core decodes.
ROS1_IMU_MD5 = "6a62c6daae103f4ff57a132d6f95cec2"
#: Chunks decompressed ahead of the decoder, per worker thread.
AHEAD = 2

Result = tuple[NDArray[np.float64], NDArray[np.int64], int]
Allocate = Callable[[int], NDArray[Any]]
#: Reads and decompresses one chunk: the bytes arguments of the core's decoder.
Job = Callable[[], tuple[bytes, ...]]


class _Unsupported(Exception):
    """The bag is not for the core's reader: read it with rosbags."""


def _workers() -> int:
    return max(1, min(4, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else 1))


def _pipeline(jobs: Iterable[Job]) -> Iterator[tuple[bytes, ...]]:
    """Results of ``jobs`` in order, computed by worker threads a few jobs ahead."""
    from concurrent.futures import ThreadPoolExecutor

    workers = _workers()
    with ThreadPoolExecutor(max_workers=workers) as pool:
        pending: deque[Future[tuple[bytes, ...]]] = deque()
        try:
            for job in jobs:
                pending.append(pool.submit(job))
                if len(pending) > AHEAD * workers:
                    yield pending.popleft().result()
            while pending:
                yield pending.popleft().result()
        finally:
            for f in pending:
                f.cancel()


# --------------------------------------------------------------------------- ROS1


def _fields(header: bytes) -> dict[bytes, bytes]:
    """A ROS1 record header: ``u32 len, name=value`` fields."""
    out = {}
    pos = 0
    while pos < len(header):
        (n,) = struct.unpack_from("<I", header, pos)
        field = header[pos + 4 : pos + 4 + n]
        if len(field) != n or b"=" not in field:
            raise _Unsupported("bad record header")
        name, _, value = field.partition(b"=")
        out[name] = value
        pos += 4 + n
    return out


def _record(fh: Any, read: bool = True) -> tuple[dict[bytes, bytes], bytes]:
    """The next record's header fields and data (``read=False``: the data is skipped)."""
    head = fh.read(4)
    if len(head) != 4:
        raise _Unsupported("truncated record")
    n = struct.unpack("<I", head)[0]
    header = fh.read(n)
    size = fh.read(4)
    if len(header) != n or len(size) != 4:
        raise _Unsupported("truncated record")
    n = struct.unpack("<I", size)[0]
    if not read:
        fh.seek(n, os.SEEK_CUR)
        return _fields(header), b""
    data = fh.read(n)
    if len(data) != n:
        raise _Unsupported("truncated record")
    return _fields(header), data


def _ros1_type(name: str) -> str:
    pkg, _, msg = name.partition("/")
    return f"{pkg}/msg/{msg}" if "/" not in msg and pkg and msg else name


def _ros1_decompressor(kind: bytes) -> Callable[[bytes], bytes]:
    if kind == b"none":
        return lambda b: b
    if kind == b"bz2":
        import bz2

        return bz2.decompress
    if kind == b"lz4":
        from lz4.frame import decompress  # type: ignore[import-untyped]  # a rosbags dependency

        return decompress  # type: ignore[no-any-return]
    raise _Unsupported(f"chunk compression {kind!r}")


def read_ros1(
    p: Path,
    topic: str | None,
    receive: bool,
    progress: Callable[[float], None] | None,
    allocate: Allocate,
    allocate_stamps: Allocate,
) -> tuple[NDArray[np.float64], NDArray[np.int64], str] | None:
    """A ROS1 ``.bag``: ``(data, stamps, topic)``, or ``None`` for rosbags to read it."""
    try:
        with open(p, "rb") as fh:
            if fh.read(13) != b"#ROSBAG V2.0\n":
                return None
            head, _ = _record(fh)
            if head.get(b"op") != b"\x03":
                return None
            (index_pos,) = struct.unpack("<Q", head[b"index_pos"])
            (conn_count,) = struct.unpack("<I", head[b"conn_count"])
            (chunk_count,) = struct.unpack("<I", head[b"chunk_count"])
            if index_pos == 0:
                return None  # unindexed (an interrupted recording): rosbags says so
            fh.seek(index_pos)
            conns: dict[int, tuple[str, str, str, str]] = {}
            for _ in range(conn_count):
                h, d = _record(fh)
                if h.get(b"op") != b"\x07":
                    return None
                info = _fields(d)
                conns[struct.unpack("<I", h[b"conn"])[0]] = (
                    h[b"topic"].decode(),
                    _ros1_type(info[b"type"].decode()),
                    info.get(b"md5sum", b"").decode(),
                    info.get(b"message_definition", b"").decode(),
                )
            chunks: list[tuple[int, dict[int, int]]] = []
            for _ in range(chunk_count):
                h, d = _record(fh)
                if h.get(b"op") != b"\x06" or len(d) % 8:
                    return None
                counts = dict(struct.iter_unpack("<II", d))
                chunks.append((struct.unpack("<Q", h[b"chunk_pos"])[0], counts))
        conn, name, count = _ros1_topic(conns, chunks, topic)
        _ros1_definitions(conns)
        data = allocate(count)
        stamps = allocate_stamps(count)
        jobs = [_ros1_job(p, pos, counts, conn) for pos, counts in chunks]
        n = _walk(jobs, _core.bags.ros1_chunk, conn, receive, count, data, stamps, progress)
        if n != count:
            return None  # the index and the chunks disagree: rosbags decides
        return data, stamps, name
    except MemoryError:
        raise
    except Exception:  # noqa: BLE001 - anything unexpected: the reference reader decides
        return None


def _ros1_definitions(conns: dict[int, tuple[str, str, str, str]]) -> None:
    """The checks rosbags' ``AnyReader`` makes when it opens a bag: every connection's message
    definition parses, the definitions agree with each other and with their md5sums; and the
    Imu layout is the standard one (what the core decodes)."""
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    typs: dict[str, Any] = {}
    digests: dict[str, str] = {}
    for _, typ, md5, msgdef in conns.values():
        typs.update(get_types_from_msg(msgdef, typ))
        if md5:
            digests[typ] = md5
    store = get_typestore(Stores.EMPTY)
    store.register(typs)
    for typ, md5 in digests.items():
        if store.generate_msgdef(typ)[1] != md5:
            raise _Unsupported("md5sum mismatch")
    ref = get_typestore(Stores.ROS1_NOETIC)
    for t in _FIELDS:
        if store.fielddefs.get(t) != ref.fielddefs[t]:
            raise _Unsupported("not the standard Imu layout")


_FIELDS = (
    "std_msgs/msg/Header",
    "geometry_msgs/msg/Vector3",
    "geometry_msgs/msg/Quaternion",
    IMU_TYPE,
)


def _ros1_topic(
    conns: dict[int, tuple[str, str, str, str]],
    chunks: list[tuple[int, dict[int, int]]],
    topic: str | None,
) -> tuple[int, str, int]:
    """The topic the reference reader would choose, if it is one the core reads."""
    topic = _imu_topic([(t, typ) for t, typ, _, _ in conns.values()], topic)
    ids = [c for c, (t, _, _, _) in conns.items() if t == topic]
    if len(ids) != 1 or conns[ids[0]][2] != ROS1_IMU_MD5:
        raise _Unsupported("several connections or another definition")
    count = sum(counts.get(ids[0], 0) for _, counts in chunks)
    if count < 2:
        raise _Unsupported("fewer than 2 messages")
    return ids[0], topic, count


def _ros1_job(p: Path, pos: int, counts: dict[int, int], conn: int) -> Job:
    """Read and decompress the chunk at ``pos`` and read its index data for ``conn``."""

    def job() -> tuple[bytes, ...]:
        index = None
        with open(p, "rb") as fh:
            fh.seek(pos)
            h, data = _record(fh, read=conn in counts)
            for _ in counts:  # one index data record per connection follows the chunk
                hi, di = _record(fh)
                if hi.get(b"op") != b"\x04" or hi.get(b"ver") != b"\x01\x00\x00\x00":
                    raise _Unsupported("not index data")
                if struct.unpack("<I", hi[b"conn"])[0] == conn:
                    index = di
        if h.get(b"op") != b"\x05":
            raise _Unsupported("not a chunk")
        decompress = _ros1_decompressor(h.get(b"compression", b""))
        if conn not in counts:
            return ()  # checked like rosbags' open does, nothing to decode
        if index is None or len(index) != 12 * counts[conn]:
            raise _Unsupported("no index data")
        raw = decompress(data)
        if len(raw) != struct.unpack("<I", h[b"size"])[0]:
            raise _Unsupported("chunk size")
        return raw, index

    return job


def _walk(
    jobs: Iterable[Job],
    decode: Callable[..., tuple[int, int, bool]],
    ident: int,
    receive: bool,
    count: int,
    data: NDArray[np.float64],
    stamps: NDArray[np.int64],
    progress: Callable[[float], None] | None,
) -> int:
    """Decode every chunk's messages of ``ident`` in order; the rows written."""
    n = 0
    last = -(2**63)
    for parts in _pipeline(jobs):
        if not parts:
            continue
        rows, last, ordered = decode(*parts, ident, receive, last, data, stamps, n)
        if not ordered:
            raise _Unsupported("receive times out of order")
        n += rows
        if progress is not None:
            progress(min(n / count, 1.0))
    return n


# --------------------------------------------------------------------------- ROS2


def read_ros2(
    reader: Any,
    name: str,
    count: int,
    receive: bool,
    progress: Callable[[float], None] | None,
    allocate: Allocate,
    allocate_stamps: Allocate,
) -> tuple[NDArray[np.float64], NDArray[np.int64]] | None:
    """A ROS2 bag or MCAP file opened by rosbags (``reader``), topic ``name`` chosen from its
    listing: ``(data, stamps)``, or ``None`` for rosbags to read it."""
    try:
        (inner,) = reader.readers
        storage = inner.storage
        storages = getattr(storage, "storages", [storage])
        meta = getattr(storage, "metadata", None)
        if getattr(meta, "compression_mode", None) == "message":
            return None  # zstd per message: rosbags
        kinds = {type(s).__name__ for s in storages}
        if kinds == {"Sqlite3Reader"}:
            # Every storage file holding the topic, in rosbags' order ("file" compression:
            # the files rosbags decompressed for its own reading).
            files = []
            for store in storages:
                ids = [c.id for c in store.connections if c.topic == name]
                if len(ids) > 1:
                    return None
                if ids:
                    files.append(Path(store.path))
            data = allocate(count)
            stamps = allocate_stamps(count)
            n = _core.bags.read_sqlite(files, name, receive, data, stamps, progress)
        elif kinds == {"McapReader"} and len(storages) == 1 and _plain(meta):
            (store,) = storages
            ids = [c.id for c in store.connections if c.topic == name]
            if len(ids) != 1:
                return None
            data = allocate(count)
            stamps = allocate_stamps(count)
            n = _walk(
                _mcap_jobs(Path(store.path), ids[0]),
                _core.bags.mcap_chunk,
                ids[0],
                receive,
                count,
                data,
                stamps,
                progress,
            )
            if n != count:
                return None
        else:
            return None
        return data[:n], stamps[:n]
    except MemoryError:
        raise
    except Exception:  # noqa: BLE001 - anything unexpected: the reference reader decides
        return None


def _plain(meta: Any) -> bool:
    """Whether a bag directory's metadata (``None``: a single storage file) has no compression."""
    return getattr(meta, "compression_mode", None) in (None, "", "none")


def _zstd() -> Callable[[bytes], bytes]:
    try:
        from compression import zstd  # type: ignore[import-not-found, unused-ignore]
    except ImportError:
        from backports import zstd  # type: ignore[import-not-found, no-redef, unused-ignore]
    return zstd.decompress  # type: ignore[no-any-return]


def _mcap_decompressor(kind: str) -> Callable[[bytes], bytes]:
    if kind == "":
        return lambda b: b
    if kind == "zstd":
        return _zstd()
    if kind == "lz4":
        from lz4.frame import decompress

        return decompress  # type: ignore[no-any-return]
    raise _Unsupported(f"chunk compression {kind!r}")


_CHUNK = struct.Struct("<QQQI")


def _mcap_jobs(path: Path, channel: int) -> Iterator[Job]:
    """The MCAP data section's chunks, read in file order, as decompression jobs."""
    with open(path, "rb") as fh:
        if fh.read(8) != b"\x89MCAP0\r\n":
            raise _Unsupported("not MCAP")
        while True:
            head = fh.read(9)
            if len(head) != 9:
                raise _Unsupported("truncated")
            op = head[0]
            (length,) = struct.unpack_from("<Q", head, 1)
            if op in (0x0F, 0x02):  # DataEnd, Footer: the data section is over
                return
            if op == 0x05:  # a message outside chunks
                if struct.unpack("<H", fh.read(2))[0] == channel:
                    raise _Unsupported("unchunked messages")
                fh.seek(length - 2, os.SEEK_CUR)
                continue
            if op != 0x06:
                fh.seek(length, os.SEEK_CUR)
                continue
            body = fh.read(length)
            if len(body) != length:
                raise _Unsupported("truncated chunk")
            yield _mcap_job(body)


def _mcap_job(body: bytes) -> Job:
    def job() -> tuple[bytes, ...]:
        _, _, size, crc = _CHUNK.unpack_from(body, 0)
        (clen,) = struct.unpack_from("<I", body, 28)
        kind = body[32 : 32 + clen].decode()
        (rlen,) = struct.unpack_from("<Q", body, 32 + clen)
        start = 40 + clen
        if start + rlen > len(body):
            raise _Unsupported("chunk records overrun")
        raw = _mcap_decompressor(kind)(body[start : start + rlen])
        if len(raw) != size or (crc and zlib.crc32(raw) != crc):
            raise _Unsupported("chunk size or checksum")
        return (raw,)

    return job


# --------------------------------------------------------------------------- ROS2 sqlite3

#: A topic as rosbags lists it: (name, type, serialization format, digest, QoS, definition).
_Topic = tuple[str, str, str, str, Any, Any]


def is_sqlite_bag(p: Path) -> bool:
    """Whether ``p`` is a ``.db3`` file or a bag directory (``metadata.yaml``)."""
    if p.is_dir():
        return (p / "metadata.yaml").is_file()
    return p.suffix.lower() == ".db3" and p.is_file()


def read_sqlite_bag(
    p: Path,
    topic: str | None,
    receive: bool,
    progress: Callable[[float], None] | None,
    allocate: Allocate,
    allocate_stamps: Allocate,
) -> tuple[NDArray[np.float64], NDArray[np.int64], str, str] | None:
    """A ROS2 sqlite3 bag read without opening it with rosbags: ``(data, stamps, topic,
    format)``, or ``None`` for the reference path (rosbags' ``AnyReader``) to read it.

    Opening the bag with rosbags counts every topic's messages with a join of the ``topics``
    and ``messages`` tables (half the time of reading the messages). Here the small tables
    are read with the same queries and checked as ``AnyReader.open`` checks them (tables,
    schema version, every message definition parsing and matching its type hash, the
    directory's ``metadata.yaml``), the topic is chosen as ``_bag._choose_topic`` chooses it,
    only its messages are counted (a ``.db3`` file; a directory's ``metadata.yaml`` gives
    the counts rosbags uses) and the core reads them (``gyrocore::bags::read_sqlite``,
    rosbags' query). Every case that would raise an error there, or is not plainly the
    standard layout, returns ``None``: rosbags then gives today's error or values.
    """
    try:
        if p.is_dir():
            conns, files, counts = _sqlite_directory(p)
            kinds = {f.suffix for f in p.iterdir()}
            fmt = "ROS2 bag (mcap)" if ".mcap" in kinds else "ROS2 bag (sqlite3)"
        else:
            file_conns, _ = _sqlite_tables(p)
            conns, files, counts = file_conns, [(p, file_conns)], None
            fmt = "ROS2 sqlite3 (.db3)"
        _ros2_definitions(conns)
        name = _ros2_topic(conns, topic)
        chosen = [c for c in conns if c[0] == name]
        # The files whose messages rosbags yields for the topic: a storage connection
        # matching the bag's (topic, type, serialization format and QoS, digest).
        paths = []
        stored_count = 0
        for path, stored in files:
            match = [s for s in stored if any(_same(s, c) for c in chosen)]
            if len(match) > 1 or len([s for s in stored if s[0] == name]) != len(match):
                raise _Unsupported("a storage connection rosbags would skip")
            # Every row of every file's messages table is visited, as rosbags' open visits them
            # to count (a damaged page anywhere is then its error, not a partial read here).
            if not match:
                _sqlite_scan(path)
                continue
            paths.append(path)
            if len(stored) == 1:
                # the file holds only this topic (an IMU-only recording): every row is read
                # below, and counting all rows takes the small timestamp index
                stored_count += _sqlite_scan(path, whole=False)
            else:
                stored_count += _core.bags.sqlite_count([path], name)
        if counts is None:
            count = stored_count
        else:
            count = sum(counts[k] for k, c in enumerate(conns) if c[0] == name)
        if count < 2:
            return None
        data = allocate(count)
        stamps = allocate_stamps(count)
        n = _core.bags.read_sqlite(paths, name, receive, data, stamps, progress)
        if n < 2:
            return None
        return data[:n], stamps[:n], name, fmt
    except MemoryError:
        raise
    except Exception:  # noqa: BLE001 - anything unexpected: the reference reader decides
        return None


def _same(stored: _Topic, listed: _Topic) -> bool:
    """rosbags' match of a storage connection to the bag's (``Reader.messages``)."""
    return (
        stored[0] == listed[0]
        and stored[1] == listed[1]
        and stored[2:5:2] == listed[2:5:2]
        and (not stored[3] or not listed[3] or stored[3] == listed[3])
    )


def _sqlite_tables(path: Path) -> tuple[list[_Topic], list[tuple[str, str, str]]]:
    """The connections of one storage file, read as rosbags' ``Sqlite3Reader`` reads them
    (without the message counts), and its message definitions ``(type, encoding, text)``."""
    import apsw  # a rosbags dependency: its sqlite3 storage reads with it
    from rosbags.interfaces import MessageDefinition, MessageDefinitionFormat
    from rosbags.rosbag2.metadata import parse_qos

    con = apsw.Connection(
        f"file:{path}?immutable=1", flags=apsw.SQLITE_OPEN_READONLY | apsw.SQLITE_OPEN_URI
    )
    try:
        cur = con.cursor()
        tables = cur.execute(
            'SELECT count(*) FROM sqlite_master WHERE type="table" AND name IN ("messages", "topics")'
        ).fetchone()
        if tables is None or tables[0] != 2:
            raise _Unsupported("missing tables")
        if cur.execute("PRAGMA table_info(schema)").fetchall():
            row = cur.execute("SELECT schema_version FROM schema").fetchone()
            schema = row[0] if row is not None else -1
        elif any(x[1] == "offered_qos_profiles" for x in cur.execute("PRAGMA table_info(topics)")):
            schema = 2
        else:
            schema = 1
        msgtypes: list[tuple[str, str, str]] = []
        if schema >= 4:
            msgtypes = [
                (x[0], x[1], x[2])
                for x in cur.execute(
                    "SELECT topic_type, encoding, encoded_message_definition,"
                    " type_description_hash FROM message_definitions ORDER BY id"
                )
            ]
        fmts = {"ros2msg": MessageDefinitionFormat.MSG, "ros2idl": MessageDefinitionFormat.IDL}

        def msgdef(typ: str) -> Any:
            found = next((x for x in msgtypes if x[0] == typ), None)
            if found is None:
                return MessageDefinition(MessageDefinitionFormat.NONE, "")
            return MessageDefinition(fmts[found[1]], found[2])

        qos = ", offered_qos_profiles" if schema >= 2 else ""
        digest = ", type_description_hash" if schema >= 4 else ""
        conns: list[_Topic] = []
        query = f"SELECT name, type, serialization_format{qos}{digest} FROM topics ORDER BY id"
        for row in cur.execute(query):
            conns.append(
                (
                    row[0],
                    row[1],
                    row[2],
                    row[4] if schema >= 4 else "",
                    parse_qos(row[3]) if schema >= 2 else [],
                    msgdef(row[1]),
                )
            )
        return conns, msgtypes
    finally:
        con.close()


def _sqlite_scan(path: Path, whole: bool = True) -> int:
    """The rows of the ``messages`` table of a storage file: ``whole``, every row visited (an
    aggregate without ``WHERE`` evaluates each one), else counted (SQLite takes an index)."""
    import apsw

    con = apsw.Connection(
        f"file:{path}?immutable=1", flags=apsw.SQLITE_OPEN_READONLY | apsw.SQLITE_OPEN_URI
    )
    try:
        query = "SELECT count(topic_id) FROM messages" if whole else "SELECT count(*) FROM messages"
        row = con.execute(query).fetchone()
        return int(row[0]) if row is not None else 0
    finally:
        con.close()


def _sqlite_directory(
    p: Path,
) -> tuple[list[_Topic], list[tuple[Path, list[_Topic]]], list[int]]:
    """A bag directory as rosbags' ``rosbag2.Reader.open`` reads it: the connections of
    ``metadata.yaml`` (definitions from the storage files), each storage file's connections,
    the message counts of ``metadata.yaml``. Anything rosbags would refuse is ``_Unsupported``."""
    from pathlib import PurePath

    from rosbags.interfaces import MessageDefinitionFormat
    from rosbags.rosbag2.metadata import parse_qos
    from ruamel.yaml import YAML

    dct = YAML(typ="safe").load((p / "metadata.yaml").read_text())
    meta = dct["rosbag2_bagfile_information"]
    if meta["version"] > 9 or meta["storage_identifier"] != "sqlite3":
        raise _Unsupported("version or storage")
    if meta.get("compression_mode", "").lower() not in ("", "none"):
        raise _Unsupported("compressed bag")
    paths = [p / PurePath(x).name for x in meta["relative_file_paths"]]
    if not all(x.exists() for x in paths):
        raise _Unsupported("missing files")
    # rosbags' ReaderMetadata arithmetic (a key or type it would refuse raises here too)
    duration = meta["duration"]["nanoseconds"]
    _ = meta["starting_time"]["nanoseconds_since_epoch"] + duration + 1, meta["message_count"]
    files = [(x, _sqlite_tables(x)[0]) for x in paths]
    conns: list[_Topic] = []
    counts: list[int] = []
    for x in meta["topics_with_message_count"]:
        t = x["topic_metadata"]
        if t["serialization_format"] != "cdr":
            raise _Unsupported("not cdr")
        typ = t["type"]
        # The definition of the first storage connection of the same type that has one.
        defs = [c[5] for _, st in files for c in st if c[1] == typ]
        found = [d for d in defs if d.format != MessageDefinitionFormat.NONE]
        conns.append(
            (
                t["name"],
                typ,
                t["serialization_format"],
                t.get("type_description_hash", ""),
                parse_qos(t.get("offered_qos_profiles", [])),
                found[0] if found else _no_definition(),
            )
        )
        counts.append(int(x["message_count"]))
    return conns, files, counts


def _no_definition() -> Any:
    from rosbags.interfaces import MessageDefinition, MessageDefinitionFormat

    return MessageDefinition(MessageDefinitionFormat.NONE, "")


def _ros2_definitions(conns: list[_Topic]) -> None:
    """The checks rosbags' ``AnyReader`` makes when it opens a ROS2 bag (its typestore from
    the stored definitions, or the default Humble one; every type hash), then the Imu layout
    is the standard one (what the core decodes)."""
    from rosbags.interfaces import MessageDefinitionFormat
    from rosbags.typesys import Stores, get_types_from_idl, get_types_from_msg, get_typestore

    humble = get_typestore(Stores.ROS2_HUMBLE)
    typs: dict[str, Any] = {}
    digests: dict[str, str] = {}
    defined = [c for c in conns if c[5].format != MessageDefinitionFormat.NONE]
    if defined:
        for _, typ, _, digest, _, msgdef in defined:
            if msgdef.format == MessageDefinitionFormat.MSG:
                typs.update(get_types_from_msg(msgdef.data, typ))
            else:
                sep = "=" * 80 + "\n"
                if msgdef.data.startswith(f"{sep}IDL: "):
                    for part in msgdef.data.split(sep)[1:]:
                        hdr, idl = part.split("\n", 1)
                        if not hdr.startswith("IDL: "):
                            raise _Unsupported("IDL header")
                        typs.update(get_types_from_idl(idl))
                else:
                    typs.update(get_types_from_idl(msgdef.data))
            if digest:
                digests[typ] = digest
    elif conns:
        typs.update(humble.fielddefs)
    store = get_typestore(Stores.EMPTY)
    store.register(typs)
    for typ, digest in digests.items():
        if store.hash_rihs01(typ) != digest:
            raise _Unsupported("type hash mismatch")
    for t in _FIELDS:
        if store.fielddefs.get(t) != humble.fielddefs[t]:
            raise _Unsupported("not the standard Imu layout")


def _ros2_topic(conns: list[_Topic], topic: str | None) -> str:
    """The topic ``_bag._choose_topic`` would choose, if it is an Imu topic it would read."""
    return _imu_topic([(c[0], c[1]) for c in conns], topic)


def _imu_topic(connections: list[tuple[str, str]], topic: str | None) -> str:
    """``topic``, or the one Imu topic of the ``(topic, type)`` connections when it is None, if
    every connection of it is an Imu (else :class:`_Unsupported`: the reference reader reads it)."""
    types: dict[str, set[str]] = {}
    for t, typ in connections:
        types.setdefault(t, set()).add(typ)
    if topic is None:
        imu = [t for t, ts in types.items() if ts == {IMU_TYPE}]
        if len(imu) != 1:
            raise _Unsupported("no unique IMU topic")
        topic = imu[0]
    if types.get(topic) != {IMU_TYPE}:
        raise _Unsupported("not an IMU topic")
    return topic

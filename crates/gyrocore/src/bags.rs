//! Bulk decoding of `sensor_msgs/Imu` messages from the bytes of ROS bags and MCAP files.
//!
//! The message layouts are fixed (REP 103 / `sensor_msgs/Imu`): a header (stamp and a
//! `frame_id` string), the orientation quaternion and its covariance, the angular velocity and
//! its covariance, the linear acceleration and its covariance, all float64. Two serializations:
//!
//! * **ROS1** (little endian, unaligned): `seq u32, sec u32, nsec u32, len u32, frame_id[len]`,
//!   then 37 float64 (4 + 9 + 3 + 9 + 3 + 9): 296 bytes after the string.
//! * **CDR** (ROS2): a 4-byte encapsulation header (`0x00 0x01` little endian, `0x00 0x00` big
//!   endian, two option bytes), then `sec i32, nanosec u32, len u32, frame_id[len]` (`len`
//!   counts the terminating NUL), the float64s aligned to 8 bytes counted from the end of the
//!   encapsulation header.
//!
//! A message is accepted only if its length is exactly the layout's (a different length means a
//! different message definition). The containers walked here are the already decompressed
//! *chunks*: a ROS1 bag chunk (records `u32 header_len, header fields, u32 data_len, data`; the
//! message records have `op = 0x02`, fields `conn` and `time`) and the records of an MCAP chunk
//! (`u8 opcode, u64 length, body`; Message records have opcode `0x05`: `channel_id u16,
//! sequence u32, log_time u64, publish_time u64, data`). Every read is bounds-checked: corrupt
//! or truncated bytes give [`Error::InvalidParameter`] (naming the chunk or message and the
//! byte offset), never a panic.
//!
//! Output: rows of six float64 (`gyro_x..z` in rad/s, `accel_x..z` in m/s²) written from row
//! `start` of a preallocated `(n, 6)` array, with either the header stamp (`sec·10⁹ + nsec`) or
//! the container's receive time (ROS1 record `time`, MCAP `log_time`) as int64 nanoseconds.

use std::path::Path;

use crate::allan::Progress;
use crate::error::{Error, Result};

/// Channels per message: angular velocity x, y, z and linear acceleration x, y, z.
pub const CHANNELS: usize = 6;
/// Bytes of the 37 float64 of an Imu after the header.
const FLOATS: usize = 37 * 8;
/// Offset of the angular velocity after the header (orientation 4 + covariance 9 float64).
const GYRO: usize = 13 * 8;
/// Offset of the linear acceleration after the header (+ angular velocity 3 + covariance 9).
const ACCEL: usize = 25 * 8;
const NS: i64 = 1_000_000_000;

/// The serialization of the messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// ROS1 (`rosbag` v2.0 files).
    Ros1,
    /// OMG CDR with its encapsulation header (ROS2: sqlite3 and MCAP storage).
    Cdr,
}

/// Which time becomes a row's stamp.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stamp {
    /// The message's `header.stamp`.
    Header,
    /// The time the recorder received the message (ROS1 record time, MCAP `log_time`).
    Receive,
}

/// One decoded message.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Imu {
    /// Angular velocity x, y, z (rad/s), linear acceleration x, y, z (m/s²).
    pub values: [f64; CHANNELS],
    /// `header.stamp` as nanoseconds (`sec·10⁹ + nanosec`).
    pub header_ns: i64,
}

/// What a chunk walk wrote.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChunkScan {
    /// Rows written (from `start`).
    pub rows: usize,
    /// Receive time of the last message of the topic seen (`previous` if none).
    pub last_receive: i64,
    /// Whether every receive time was at least the one before it (the first compared with
    /// `previous`): the readers return messages in receive-time order, so a walk in file
    /// order gives their rows only when this holds.
    pub ordered: bool,
}

fn corrupt(name: &'static str, reason: String) -> Error {
    Error::InvalidParameter { name, reason }
}

fn bytes_at<'a>(buf: &'a [u8], at: usize, len: usize, name: &'static str) -> Result<&'a [u8]> {
    at.checked_add(len)
        .and_then(|end| buf.get(at..end))
        .ok_or_else(|| {
            corrupt(
                name,
                format!(
                    "truncated: {len} bytes needed at offset {at}, {} available",
                    buf.len()
                ),
            )
        })
}

fn u16_le(buf: &[u8], at: usize, name: &'static str) -> Result<u16> {
    let b = bytes_at(buf, at, 2, name)?;
    Ok(u16::from_le_bytes([b[0], b[1]]))
}

fn u32_at(buf: &[u8], at: usize, little: bool, name: &'static str) -> Result<u32> {
    let b = bytes_at(buf, at, 4, name)?;
    let a = [b[0], b[1], b[2], b[3]];
    Ok(if little {
        u32::from_le_bytes(a)
    } else {
        u32::from_be_bytes(a)
    })
}

fn u64_le(buf: &[u8], at: usize, name: &'static str) -> Result<u64> {
    let b = bytes_at(buf, at, 8, name)?;
    let mut a = [0u8; 8];
    a.copy_from_slice(b);
    Ok(u64::from_le_bytes(a))
}

fn f64_at(buf: &[u8], at: usize, little: bool) -> f64 {
    // Callers have checked the message length, so the 8 bytes are there.
    let mut a = [0u8; 8];
    if let Some(b) = buf.get(at..at + 8) {
        a.copy_from_slice(b);
    }
    if little {
        f64::from_le_bytes(a)
    } else {
        f64::from_be_bytes(a)
    }
}

fn usize_of(v: u64, name: &'static str) -> Result<usize> {
    usize::try_from(v).map_err(|_| corrupt(name, format!("length {v} exceeds the address space")))
}

/// Decodes one serialized `sensor_msgs/Imu`.
///
/// # Errors
/// [`Error::InvalidParameter`] (`message`) when the bytes are not a standard Imu in this
/// encoding: too short, an unknown CDR encapsulation, or a length other than the layout's.
pub fn decode(msg: &[u8], encoding: Encoding) -> Result<Imu> {
    const NAME: &str = "message";
    let (little, base, header_ns) = match encoding {
        Encoding::Ros1 => {
            let sec = u32_at(msg, 4, true, NAME)?;
            let nsec = u32_at(msg, 8, true, NAME)?;
            (true, 4usize, i64::from(sec) * NS + i64::from(nsec))
        }
        Encoding::Cdr => {
            let head = bytes_at(msg, 0, 4, NAME)?;
            if head[0] != 0 || head[1] > 1 {
                return Err(corrupt(
                    NAME,
                    format!(
                        "CDR encapsulation {:#04x}{:02x} is not plain CDR",
                        head[0], head[1]
                    ),
                ));
            }
            let little = head[1] == 1;
            // sec is int32 in builtin_interfaces/Time: reinterpret the bits as signed.
            let sec = i64::from(i32::from_ne_bytes(
                u32_at(msg, 4, little, NAME)?.to_ne_bytes(),
            ));
            let nsec = u32_at(msg, 8, little, NAME)?;
            (little, 4usize, sec * NS + i64::from(nsec))
        }
    };
    // The frame_id length follows the stamp in both encodings (after seq in ROS1).
    let len_at = base + 8;
    let len = u32_at(msg, len_at, little, NAME)? as usize;
    let mut floats = (len_at + 4)
        .checked_add(len)
        .ok_or_else(|| corrupt(NAME, format!("frame_id length {len} is impossible")))?;
    if encoding == Encoding::Cdr {
        floats = base + (floats - base).div_ceil(8) * 8;
    }
    if floats.checked_add(FLOATS) != Some(msg.len()) {
        return Err(corrupt(
            NAME,
            format!(
                "{} bytes, not the {} of a sensor_msgs/Imu with a {len}-byte frame_id",
                msg.len(),
                floats.saturating_add(FLOATS)
            ),
        ));
    }
    let g = floats + GYRO;
    let a = floats + ACCEL;
    Ok(Imu {
        values: [
            f64_at(msg, g, little),
            f64_at(msg, g + 8, little),
            f64_at(msg, g + 16, little),
            f64_at(msg, a, little),
            f64_at(msg, a + 8, little),
            f64_at(msg, a + 16, little),
        ],
        header_ns,
    })
}

/// The output arrays: `data` is `(n, 6)` row-major, `stamps` has `n` entries.
fn check_out(data: &[f64], stamps: &[i64], start: usize) -> Result<usize> {
    let n = stamps.len();
    if data.len() != n.saturating_mul(CHANNELS) {
        return Err(Error::ShapeMismatch {
            name: "data",
            reason: format!(
                "{} values for {n} stamps, {} expected",
                data.len(),
                n.saturating_mul(CHANNELS)
            ),
        });
    }
    if start > n {
        return Err(Error::InvalidParameter {
            name: "start",
            reason: format!("must be at most the {n} output rows, got {start}"),
        });
    }
    Ok(n)
}

struct Writer<'a> {
    data: &'a mut [f64],
    stamps: &'a mut [i64],
    row: usize,
    stamp: Stamp,
    last: i64,
    ordered: bool,
}

impl Writer<'_> {
    fn push(&mut self, msg: &[u8], encoding: Encoding, receive: i64) -> Result<()> {
        if self.row >= self.stamps.len() {
            return Err(corrupt(
                "data",
                format!(
                    "more messages than the {} output rows (the bag's index undercounts)",
                    self.stamps.len()
                ),
            ));
        }
        let imu = decode(msg, encoding)?;
        let at = self.row * CHANNELS;
        self.data[at..at + CHANNELS].copy_from_slice(&imu.values);
        self.stamps[self.row] = match self.stamp {
            Stamp::Header => imu.header_ns,
            Stamp::Receive => receive,
        };
        self.ordered &= receive >= self.last;
        self.last = receive;
        self.row += 1;
        Ok(())
    }
}

/// The fields of a ROS1 record header that the walk needs.
struct Ros1Header {
    op: Option<u8>,
    conn: Option<u32>,
    time: Option<i64>,
}

fn ros1_header(h: &[u8], at: usize) -> Result<Ros1Header> {
    const NAME: &str = "chunk";
    let mut out = Ros1Header {
        op: None,
        conn: None,
        time: None,
    };
    let mut pos = 0usize;
    while pos < h.len() {
        let len = u32_at(h, pos, true, NAME)? as usize;
        let field = bytes_at(h, pos + 4, len, NAME)
            .map_err(|_| corrupt(NAME, format!("record header field overruns at offset {at}")))?;
        pos += 4 + len;
        let Some(eq) = field.iter().position(|&b| b == b'=') else {
            return Err(corrupt(
                NAME,
                format!("record header field without '=' at offset {at}"),
            ));
        };
        let (name, value) = (&field[..eq], &field[eq + 1..]);
        match name {
            b"op" if value.len() == 1 => out.op = Some(value[0]),
            b"conn" if value.len() == 4 => out.conn = Some(u32_at(value, 0, true, NAME)?),
            b"time" if value.len() == 8 => {
                let sec = u32_at(value, 0, true, NAME)?;
                let nsec = u32_at(value, 4, true, NAME)?;
                out.time = Some(i64::from(sec) * NS + i64::from(nsec));
            }
            _ => {}
        }
    }
    Ok(out)
}

/// Decodes the Imu messages of connection `conn` in a decompressed ROS1 bag chunk into rows
/// `start..` of `data` (`(n, 6)` row-major) and `stamps` (`n`), in the chunk's record order.
///
/// `index` is the data of the bag's index data record of this connection for this chunk
/// (`sec u32, nsec u32, offset u32` per message): each message must sit at its entry's offset
/// with its entry's time, as the index-driven readers require. `previous` is the receive time
/// of the topic's last message before this chunk (for [`ChunkScan::ordered`]; `i64::MIN` for
/// the first chunk).
///
/// # Errors
/// [`Error::InvalidParameter`] for a truncated or malformed record, a message that disagrees
/// with `index` (time, offset or count), a message that is not a standard Imu, or more
/// messages than output rows; [`Error::ShapeMismatch`] when `data` does not have 6 values per
/// stamp.
#[allow(clippy::too_many_arguments)]
pub fn ros1_chunk(
    chunk: &[u8],
    index: &[u8],
    conn: u64,
    stamp: Stamp,
    previous: i64,
    data: &mut [f64],
    stamps: &mut [i64],
    start: usize,
) -> Result<ChunkScan> {
    const NAME: &str = "chunk";
    check_out(data, stamps, start)?;
    if index.len() % 12 != 0 {
        return Err(corrupt(
            "index",
            format!("{} bytes, not 12 per message", index.len()),
        ));
    }
    let mut w = Writer {
        data,
        stamps,
        row: start,
        stamp,
        last: previous,
        ordered: true,
    };
    let mut entry = 0usize;
    let mut pos = 0usize;
    while pos < chunk.len() {
        let at = pos;
        let hlen = u32_at(chunk, pos, true, NAME)? as usize;
        let header = bytes_at(chunk, pos + 4, hlen, NAME)?;
        pos += 4 + hlen;
        let dlen = u32_at(chunk, pos, true, NAME)? as usize;
        let body = bytes_at(chunk, pos + 4, dlen, NAME)?;
        pos += 4 + dlen;
        let h = ros1_header(header, at)?;
        if h.op == Some(0x02) && h.conn.map(u64::from) == Some(conn) {
            let time = h.time.ok_or_else(|| {
                corrupt(
                    NAME,
                    format!("message record without a time at offset {at}"),
                )
            })?;
            let e = entry * 12;
            let expected = bytes_at(index, e, 12, "index").map_err(|_| {
                corrupt(
                    "index",
                    format!("lists fewer messages than the chunk (offset {at})"),
                )
            })?;
            let sec = u32_at(expected, 0, true, "index")?;
            let nsec = u32_at(expected, 4, true, "index")?;
            let offset = u32_at(expected, 8, true, "index")? as usize;
            if offset != at || i64::from(sec) * NS + i64::from(nsec) != time {
                return Err(corrupt(
                    "index",
                    format!("entry {entry} disagrees with the message record at offset {at}"),
                ));
            }
            entry += 1;
            w.push(body, Encoding::Ros1, time)?;
        }
    }
    if entry * 12 != index.len() {
        return Err(corrupt(
            "index",
            format!("lists {} messages, the chunk has {entry}", index.len() / 12),
        ));
    }
    Ok(ChunkScan {
        rows: w.row - start,
        last_receive: w.last,
        ordered: w.ordered,
    })
}

/// Decodes the Imu messages of channel `channel` in the decompressed records of an MCAP chunk
/// (CDR) into rows `start..` of `data` and `stamps`, in record order; the receive time is the
/// Message record's `log_time`. Arguments and result as [`ros1_chunk`].
///
/// # Errors
/// As [`ros1_chunk`].
pub fn mcap_chunk(
    records: &[u8],
    channel: u64,
    stamp: Stamp,
    previous: i64,
    data: &mut [f64],
    stamps: &mut [i64],
    start: usize,
) -> Result<ChunkScan> {
    const NAME: &str = "chunk";
    check_out(data, stamps, start)?;
    let mut w = Writer {
        data,
        stamps,
        row: start,
        stamp,
        last: previous,
        ordered: true,
    };
    let mut pos = 0usize;
    while pos < records.len() {
        let at = pos;
        let op = bytes_at(records, pos, 1, NAME)?[0];
        let len = usize_of(u64_le(records, pos + 1, NAME)?, NAME)?;
        let body = bytes_at(records, pos + 9, len, NAME)?;
        pos += 9 + len;
        if op == 0x05 {
            if body.len() < 22 {
                return Err(corrupt(
                    NAME,
                    format!(
                        "message record of {} bytes at offset {at} (22 at least)",
                        body.len()
                    ),
                ));
            }
            if u64::from(u16_le(body, 0, NAME)?) == channel {
                let log_time = i64::from_le_bytes(u64_le(body, 6, NAME)?.to_le_bytes());
                w.push(&body[22..], Encoding::Cdr, log_time)?;
            }
        }
    }
    Ok(ChunkScan {
        rows: w.row - start,
        last_receive: w.last,
        ordered: w.ordered,
    })
}

/// Decodes CDR Imu messages stored back to back in `buf` (`lengths[i]` bytes each, e.g. the
/// `data` blobs of a ROS2 sqlite3 bag) into rows `start..` of `data`; their header stamps go to
/// `stamps` when `header_stamps` is true (else `stamps` is left alone). Returns the rows written
/// (`lengths.len()`).
///
/// # Errors
/// [`Error::InvalidParameter`] when the lengths do not add up to `buf`, a message is not a
/// standard Imu, or there are more messages than output rows; [`Error::ShapeMismatch`] as
/// [`ros1_chunk`].
pub fn cdr_messages(
    buf: &[u8],
    lengths: &[i64],
    header_stamps: bool,
    data: &mut [f64],
    stamps: &mut [i64],
    start: usize,
) -> Result<usize> {
    let n = check_out(data, stamps, start)?;
    if lengths.len() > n - start {
        return Err(Error::InvalidParameter {
            name: "lengths",
            reason: format!(
                "{} messages for {} free output rows",
                lengths.len(),
                n - start
            ),
        });
    }
    let mut pos = 0usize;
    for (k, &len) in lengths.iter().enumerate() {
        let len = usize::try_from(len).map_err(|_| Error::InvalidParameter {
            name: "lengths",
            reason: format!("must be non-negative, got {len} at index {k}"),
        })?;
        let msg = bytes_at(buf, pos, len, "buf")?;
        pos += len;
        let imu = decode(msg, Encoding::Cdr)?;
        let row = start + k;
        data[row * CHANNELS..(row + 1) * CHANNELS].copy_from_slice(&imu.values);
        if header_stamps {
            stamps[row] = imu.header_ns;
        }
    }
    if pos != buf.len() {
        return Err(Error::InvalidParameter {
            name: "lengths",
            reason: format!("add up to {pos} bytes, buf has {}", buf.len()),
        });
    }
    Ok(lengths.len())
}

/// Rows between two progress reports (and cancellation checks) of [`read_sqlite`].
const SQLITE_BATCH: usize = 65_536;

/// The message type the sqlite3 reader decodes.
const IMU_TYPE: &str = "sensor_msgs/msg/Imu";

fn sqlite_error(e: &rusqlite::Error) -> Error {
    corrupt("path", format!("not a readable ROS2 sqlite3 bag ({e})"))
}

/// An SQLite URI opening `path` read-only and immutable (`file:…?mode=ro&immutable=1`): no
/// lock, no journal, no `-wal`/`-shm` file is ever created beside the bag, and the file is
/// never written. Every byte outside the URI's unreserved characters is percent-encoded, so
/// any file name (`?`, `#`, `%`, spaces, non-UTF-8 bytes) is the file it names.
// Infallible on Unix (any path's bytes can be escaped); elsewhere a path must be Unicode.
#[cfg_attr(unix, allow(clippy::unnecessary_wraps))]
fn sqlite_uri(path: &Path) -> Result<String> {
    #[cfg(unix)]
    let bytes: Vec<u8> = {
        use std::os::unix::ffi::OsStrExt;
        path.as_os_str().as_bytes().to_vec()
    };
    #[cfg(not(unix))]
    let bytes: Vec<u8> = {
        let s = path
            .to_str()
            .ok_or_else(|| corrupt("path", format!("{} is not valid Unicode", path.display())))?;
        let s = s.replace('\\', "/");
        // A drive letter (C:/…) becomes the URI path /C:/….
        if s.as_bytes().get(1) == Some(&b':') {
            format!("/{s}").into_bytes()
        } else {
            s.into_bytes()
        }
    };
    let mut uri = String::with_capacity(bytes.len() + 32);
    uri.push_str("file:");
    for &b in &bytes {
        if b.is_ascii_alphanumeric() || b"/-._~".contains(&b) {
            uri.push(char::from(b));
        } else {
            const HEX: &[u8; 16] = b"0123456789ABCDEF";
            uri.push('%');
            uri.push(char::from(HEX[usize::from(b >> 4)]));
            uri.push(char::from(HEX[usize::from(b & 15)]));
        }
    }
    uri.push_str("?mode=ro&immutable=1");
    Ok(uri)
}

/// Decodes the `sensor_msgs/msg/Imu` messages of topic `topic` of ROS2 sqlite3 storage files
/// (`.db3`; a split bag's files in their order) into `data` (`(n, 6)` row-major) and `stamps`
/// (`n`) from row 0; returns the rows written (at most `n`, the caller's message count).
///
/// Each file is opened read-only and immutable (URI `?mode=ro&immutable=1`, the same open as
/// rosbags' reader: no lock, no `-wal`/`-shm` file beside it, never written) and its rows come
/// from rosbags' own query, `SELECT topics.id, messages.timestamp, messages.data FROM messages
/// JOIN topics ON messages.topic_id = topics.id WHERE topics.id IN (?) ORDER BY timestamp`, so
/// they arrive in the same order, ties included (a first pass over the table in storage order
/// is kept when the topic's timestamps come strictly increasing: the one order that query can
/// give then); the files follow each other as in rosbags' reader of a bag directory. The receive time is `messages.timestamp`. The blobs are decoded
/// as SQLite steps through them: the working set is SQLite's page cache (a few MB), whatever
/// the bag's size. `progress` gets the fraction of the `n` rows done every 65,536 rows; a
/// `false` from its hook stops the read with [`Error::Cancelled`].
///
/// # Errors
/// [`Error::InvalidParameter`] (`path`) when a file is not a readable sqlite3 bag (not a
/// database, corrupt or truncated pages, no `topics`/`messages` table); (`topic`) when the
/// topic is missing from a file, listed more than once, or not a CDR `sensor_msgs/msg/Imu`;
/// (`message`) for a blob that is not a standard Imu; (`data`) for more messages than `n`;
/// [`Error::ShapeMismatch`] when `data` does not have 6 values per stamp.
pub fn read_sqlite<P: AsRef<Path>>(
    paths: &[P],
    topic: &str,
    stamp: Stamp,
    data: &mut [f64],
    stamps: &mut [i64],
    progress: &Progress<'_>,
) -> Result<usize> {
    let n = check_out(data, stamps, 0)?;
    let mut w = Writer {
        data,
        stamps,
        row: 0,
        stamp,
        last: i64::MIN,
        ordered: true,
    };
    progress.add_total(n as f64);
    progress.start();
    let mut reported = 0usize;
    for path in paths {
        sqlite_file(path.as_ref(), topic, &mut w, &mut |rows| {
            // a file read again (see sqlite_file) reports rows already counted: no step back
            if rows > reported {
                progress.advance((rows - reported) as f64);
                reported = rows;
            }
            progress.check()
        })?;
    }
    progress.finish();
    progress.check()?;
    Ok(w.row)
}

/// The number of messages of topic `topic` in ROS2 sqlite3 storage files (files without the
/// topic count 0): `SELECT count(*) FROM messages WHERE topic_id = ?` on each file, opened as
/// in [`read_sqlite`]; the size of the output arrays of a later [`read_sqlite`].
///
/// # Errors
/// [`Error::InvalidParameter`] (`path`) when a file is not a readable sqlite3 bag; (`topic`)
/// when the topic is listed more than once in a file.
pub fn sqlite_count<P: AsRef<Path>>(paths: &[P], topic: &str) -> Result<usize> {
    let mut total = 0usize;
    for path in paths {
        let con = sqlite_open(path.as_ref())?;
        let sql = |e: rusqlite::Error| sqlite_error(&e);
        let Some((id, _, _)) = topic_row(&con, topic)? else {
            continue;
        };
        let count: i64 = con
            .query_row(
                "SELECT count(*) FROM messages WHERE topic_id = ?1",
                [id],
                |r| r.get(0),
            )
            .map_err(sql)?;
        total = total.saturating_add(usize::try_from(count).unwrap_or(usize::MAX));
    }
    Ok(total)
}

fn sqlite_open(path: &Path) -> Result<rusqlite::Connection> {
    use rusqlite::OpenFlags;
    let flags = OpenFlags::SQLITE_OPEN_READ_ONLY
        | OpenFlags::SQLITE_OPEN_URI
        | OpenFlags::SQLITE_OPEN_NO_MUTEX;
    rusqlite::Connection::open_with_flags(sqlite_uri(path)?, flags).map_err(|e| sqlite_error(&e))
}

/// `(id, type, serialization_format)` of the row of the `topics` table named `topic` (`None`
/// when there is none).
///
/// # Errors
/// [`Error::InvalidParameter`] (`topic`) when it is listed more than once; (`path`) when the
/// table cannot be read.
fn topic_row(con: &rusqlite::Connection, topic: &str) -> Result<Option<(i64, String, String)>> {
    let sql = |e: rusqlite::Error| sqlite_error(&e);
    let mut ids = con
        .prepare("SELECT id, type, serialization_format FROM topics WHERE name = ?1")
        .map_err(sql)?;
    let mut rows: Vec<(i64, String, String)> = ids
        .query_map([topic], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))
        .map_err(sql)?
        .collect::<rusqlite::Result<_>>()
        .map_err(sql)?;
    if rows.len() > 1 {
        return Err(corrupt(
            "topic",
            format!("{topic} is listed {} times", rows.len()),
        ));
    }
    Ok(rows.pop())
}

/// One storage file of [`read_sqlite`], appended to `w`; `report(rows)` every batch.
fn sqlite_file(
    path: &Path,
    topic: &str,
    w: &mut Writer<'_>,
    report: &mut dyn FnMut(usize) -> Result<()>,
) -> Result<()> {
    let con = sqlite_open(path)?;
    let sql = |e: rusqlite::Error| sqlite_error(&e);
    let id = match topic_row(&con, topic)? {
        Some((id, typ, format)) if typ == IMU_TYPE && format == "cdr" => id,
        Some((_, typ, format)) => {
            return Err(corrupt(
                "topic",
                format!("{topic} is {typ} ({format}), not {IMU_TYPE} (cdr)"),
            ));
        }
        None => return Err(corrupt("topic", format!("{topic} is not in the bag"))),
    };
    // First the table in storage order (no index lookups, twice as fast): when the topic's
    // timestamps come strictly increasing, that is the only order `ORDER BY timestamp` can
    // give, whatever SQLite's plan; otherwise (ties or a step back) the rows are read again
    // with rosbags' query, whose order for ties is SQLite's.
    let (first, previous) = (w.row, w.last);
    {
        let mut scan = con
            .prepare("SELECT timestamp, data FROM messages WHERE topic_id = ?1")
            .map_err(sql)?;
        let mut rows = scan.query([id]).map_err(sql)?;
        let mut increasing = true;
        let mut last = i64::MIN;
        while let Some(row) = rows.next().map_err(sql)? {
            let receive = row.get_ref(0).and_then(|v| Ok(v.as_i64()?)).map_err(sql)?;
            if receive <= last {
                increasing = false;
                break;
            }
            last = receive;
            let blob = row.get_ref(1).and_then(|v| Ok(v.as_blob()?)).map_err(sql)?;
            w.push(blob, Encoding::Cdr, receive)?;
            if w.row % SQLITE_BATCH == 0 {
                report(w.row)?;
            }
        }
        if increasing {
            return report(w.row);
        }
    }
    w.row = first;
    w.last = previous;
    let mut query = con
        .prepare(
            "SELECT topics.id,messages.timestamp,messages.data FROM messages JOIN topics \
             ON messages.topic_id=topics.id WHERE topics.id IN (?1) ORDER BY timestamp",
        )
        .map_err(sql)?;
    let mut rows = query.query([id]).map_err(sql)?;
    while let Some(row) = rows.next().map_err(sql)? {
        let receive = row.get_ref(1).and_then(|v| Ok(v.as_i64()?)).map_err(sql)?;
        let blob = row.get_ref(2).and_then(|v| Ok(v.as_blob()?)).map_err(sql)?;
        w.push(blob, Encoding::Cdr, receive)?;
        if w.row % SQLITE_BATCH == 0 {
            report(w.row)?;
        }
    }
    report(w.row)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ROS1 Imu with the given frame id, stamp and values (angular velocity, acceleration).
    fn ros1_msg(frame: &str, sec: u32, nsec: u32, v: [f64; 6]) -> Vec<u8> {
        let mut m = Vec::new();
        m.extend_from_slice(&7u32.to_le_bytes()); // seq
        m.extend_from_slice(&sec.to_le_bytes());
        m.extend_from_slice(&nsec.to_le_bytes());
        m.extend_from_slice(&u32::try_from(frame.len()).unwrap().to_le_bytes());
        m.extend_from_slice(frame.as_bytes());
        floats(&mut m, v, true);
        m
    }

    fn floats(m: &mut Vec<u8>, v: [f64; 6], little: bool) {
        let mut all = vec![0.0, 0.0, 0.0, 1.0];
        all.extend([0.5; 9]);
        all.extend(&v[..3]);
        all.extend([0.25; 9]);
        all.extend(&v[3..]);
        all.extend([0.125; 9]);
        for x in all {
            m.extend_from_slice(&if little {
                x.to_le_bytes()
            } else {
                x.to_be_bytes()
            });
        }
    }

    fn cdr_msg(frame: &str, sec: i32, nsec: u32, v: [f64; 6], little: bool) -> Vec<u8> {
        let mut m = vec![0u8, u8::from(little), 0, 0];
        let put = |m: &mut Vec<u8>, x: u32| {
            m.extend_from_slice(&if little {
                x.to_le_bytes()
            } else {
                x.to_be_bytes()
            });
        };
        put(&mut m, u32::from_ne_bytes(sec.to_ne_bytes()));
        put(&mut m, nsec);
        put(&mut m, u32::try_from(frame.len() + 1).unwrap());
        m.extend_from_slice(frame.as_bytes());
        m.push(0);
        while (m.len() - 4) % 8 != 0 {
            m.push(0);
        }
        floats(&mut m, v, little);
        m
    }

    const V: [f64; 6] = [1.5, -2.25, 3.0e-3, 9.81, -0.5, 1e300];

    #[test]
    fn decodes_every_frame_length_and_byte_order() {
        for frame in [
            "", "a", "ab", "imu", "imu0", "imu_l", "imu_li", "imu_lin", "imu_link",
        ] {
            let r = decode(&ros1_msg(frame, 17, 999_999_999, V), Encoding::Ros1).unwrap();
            assert_eq!(r.values, V);
            assert_eq!(r.header_ns, 17 * NS + 999_999_999);
            for little in [true, false] {
                let c = decode(&cdr_msg(frame, -3, 5, V, little), Encoding::Cdr).unwrap();
                assert_eq!(c.values, V);
                assert_eq!(c.header_ns, -3 * NS + 5);
            }
        }
    }

    #[test]
    fn other_lengths_and_encapsulations_are_refused() {
        let mut m = ros1_msg("imu", 1, 2, V);
        m.push(0);
        assert!(decode(&m, Encoding::Ros1).is_err());
        let mut c = cdr_msg("imu", 1, 2, V, true);
        c[1] = 3; // PL_CDR
        assert!(decode(&c, Encoding::Cdr).is_err());
        let ok = cdr_msg("imu", 1, 2, V, true);
        for cut in 0..ok.len() {
            assert!(decode(&ok[..cut], Encoding::Cdr).is_err());
        }
        // a frame_id length near u32::MAX neither overflows nor panics
        let mut big = ros1_msg("imu", 1, 2, V);
        big[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(decode(&big, Encoding::Ros1).is_err());
    }

    fn ros1_record(fields: &[(&str, &[u8])], data: &[u8]) -> Vec<u8> {
        let mut h = Vec::new();
        for (name, value) in fields {
            let len = u32::try_from(name.len() + 1 + value.len()).unwrap();
            h.extend_from_slice(&len.to_le_bytes());
            h.extend_from_slice(name.as_bytes());
            h.push(b'=');
            h.extend_from_slice(value);
        }
        let mut r = u32::try_from(h.len()).unwrap().to_le_bytes().to_vec();
        r.extend(h);
        r.extend_from_slice(&u32::try_from(data.len()).unwrap().to_le_bytes());
        r.extend_from_slice(data);
        r
    }

    fn time(sec: u32, nsec: u32) -> Vec<u8> {
        let mut t = sec.to_le_bytes().to_vec();
        t.extend_from_slice(&nsec.to_le_bytes());
        t
    }

    #[test]
    fn ros1_chunk_takes_its_connection_in_record_order() {
        let mut chunk = ros1_record(&[("op", &[7]), ("conn", &3u32.to_le_bytes())], b"x=y");
        let mut index = Vec::new();
        for (k, conn) in [3u32, 4, 3, 3].into_iter().enumerate() {
            let k32 = u32::try_from(k).unwrap();
            let msg = ros1_msg("imu", 10 + k32, 0, V);
            let t = time(100 - k32, 0); // receive times decrease: not ordered
            if conn == 3 {
                index.extend_from_slice(&t);
                index.extend_from_slice(&u32::try_from(chunk.len()).unwrap().to_le_bytes());
            }
            chunk.extend(ros1_record(
                &[("op", &[2]), ("conn", &conn.to_le_bytes()), ("time", &t)],
                &msg,
            ));
        }
        let mut data = vec![0.0; 4 * 6];
        let mut stamps = vec![0; 4];
        let scan = ros1_chunk(
            &chunk,
            &index,
            3,
            Stamp::Header,
            i64::MIN,
            &mut data,
            &mut stamps,
            1,
        )
        .unwrap();
        assert_eq!(scan.rows, 3);
        assert!(!scan.ordered);
        assert_eq!(scan.last_receive, 97 * NS);
        assert_eq!(&stamps[1..], &[10 * NS, 12 * NS, 13 * NS]);
        assert_eq!(&data[6..12], &V);
        let scan = ros1_chunk(
            &chunk,
            &index,
            3,
            Stamp::Receive,
            i64::MIN,
            &mut data,
            &mut stamps,
            1,
        )
        .unwrap();
        assert_eq!(&stamps[1..], &[100 * NS, 98 * NS, 97 * NS]);
        assert_eq!(scan.rows, 3);
        // too few rows, every truncation and bit flip: errors or values, never a panic
        assert!(
            ros1_chunk(
                &chunk,
                &index,
                3,
                Stamp::Header,
                0,
                &mut data,
                &mut stamps,
                2
            )
            .is_err()
        );
        // an index that disagrees in time, offset or count
        for (at, bit) in [(0, 1u8), (8, 1), (20, 4)] {
            let mut bad = index.clone();
            bad[at] ^= bit;
            assert!(
                ros1_chunk(&chunk, &bad, 3, Stamp::Header, 0, &mut data, &mut stamps, 0).is_err()
            );
        }
        let short = &index[..24];
        assert!(
            ros1_chunk(
                &chunk,
                short,
                3,
                Stamp::Header,
                0,
                &mut data,
                &mut stamps,
                0
            )
            .is_err()
        );
        for cut in 0..chunk.len() {
            let _ = ros1_chunk(
                &chunk[..cut],
                &index,
                3,
                Stamp::Header,
                0,
                &mut data,
                &mut stamps,
                0,
            );
        }
        for bit in 0..chunk.len() * 8 {
            let mut c = chunk.clone();
            c[bit / 8] ^= 1 << (bit % 8);
            let _ = ros1_chunk(&c, &index, 3, Stamp::Header, 0, &mut data, &mut stamps, 0);
        }
    }

    fn mcap_message(channel: u16, log_time: u64, data: &[u8]) -> Vec<u8> {
        let mut r = vec![0x05];
        r.extend_from_slice(&(22 + data.len() as u64).to_le_bytes());
        r.extend_from_slice(&channel.to_le_bytes());
        r.extend_from_slice(&9u32.to_le_bytes());
        r.extend_from_slice(&log_time.to_le_bytes());
        r.extend_from_slice(&(log_time + 1).to_le_bytes());
        r.extend_from_slice(data);
        r
    }

    #[test]
    fn mcap_chunk_takes_its_channel() {
        let mut recs = vec![0x04];
        recs.extend_from_slice(&3u64.to_le_bytes());
        recs.extend_from_slice(&[1, 2, 3]); // a channel record: skipped
        for (k, ch) in [1u16, 2, 1].into_iter().enumerate() {
            let k32 = i32::try_from(k).unwrap();
            recs.extend(mcap_message(
                ch,
                50 + k as u64,
                &cdr_msg("imu", k32, 1, V, true),
            ));
        }
        let mut data = vec![0.0; 2 * 6];
        let mut stamps = vec![0; 2];
        let scan = mcap_chunk(&recs, 1, Stamp::Receive, 50, &mut data, &mut stamps, 0).unwrap();
        assert_eq!(scan.rows, 2);
        assert!(scan.ordered);
        assert_eq!(stamps, vec![50, 52]);
        mcap_chunk(&recs, 1, Stamp::Header, 51, &mut data, &mut stamps, 0).unwrap();
        assert_eq!(stamps, vec![1, 2 * NS + 1]);
        assert_eq!(data[..6], V);
        for cut in 0..recs.len() {
            let _ = mcap_chunk(&recs[..cut], 1, Stamp::Header, 0, &mut data, &mut stamps, 0);
        }
        for bit in 0..recs.len() * 8 {
            let mut c = recs.clone();
            c[bit / 8] ^= 1 << (bit % 8);
            let _ = mcap_chunk(&c, 1, Stamp::Header, 0, &mut data, &mut stamps, 0);
        }
    }

    #[test]
    fn cdr_messages_back_to_back() {
        let a = cdr_msg("", 1, 2, V, true);
        let b = cdr_msg("imu_link", 3, 4, V, false);
        let buf = [a.clone(), b.clone()].concat();
        let lengths = [a.len() as i64, b.len() as i64];
        let mut data = vec![0.0; 3 * 6];
        let mut stamps = vec![-1; 3];
        assert_eq!(
            cdr_messages(&buf, &lengths, true, &mut data, &mut stamps, 1).unwrap(),
            2
        );
        assert_eq!(stamps, vec![-1, NS + 2, 3 * NS + 4]);
        assert_eq!(data[12..], V);
        assert!(cdr_messages(&buf, &lengths, true, &mut data, &mut stamps, 2).is_err());
        assert!(cdr_messages(&buf[1..], &lengths, true, &mut data, &mut stamps, 0).is_err());
        assert!(cdr_messages(&buf, &[-1, 5], true, &mut data, &mut stamps, 0).is_err());
        assert!(cdr_messages(&buf, &lengths, true, &mut data[1..], &mut stamps, 0).is_err());
    }

    /// A minimal rosbag2 sqlite3 file: `/imu` (Imu, cdr) with messages at `receive`, and
    /// `/note` (a String topic).
    fn sqlite_bag(name: &str, receive: &[i64]) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("gyrocore-bags-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("b?#% .db3");
        let _ = std::fs::remove_file(&path);
        let con = rusqlite::Connection::open(&path).unwrap();
        con.execute_batch(
            "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, \
             serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);
             CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, \
             timestamp INTEGER NOT NULL, data BLOB NOT NULL);
             CREATE INDEX timestamp_idx ON messages (timestamp ASC);
             INSERT INTO topics VALUES (1, '/note', 'std_msgs/msg/String', 'cdr', '');
             INSERT INTO topics VALUES (2, '/imu', 'sensor_msgs/msg/Imu', 'cdr', '');",
        )
        .unwrap();
        for (k, &t) in receive.iter().enumerate() {
            let k32 = i32::try_from(k).unwrap();
            let mut v = V;
            v[0] = f64::from(k32);
            let msg = cdr_msg("imu", k32, 0, v, k % 2 == 0);
            con.execute(
                "INSERT INTO messages (topic_id, timestamp, data) VALUES (2, ?1, ?2)",
                rusqlite::params![t, msg],
            )
            .unwrap();
            con.execute(
                "INSERT INTO messages (topic_id, timestamp, data) VALUES (1, ?1, x'00010000')",
                [t],
            )
            .unwrap();
        }
        path
    }

    #[test]
    fn sqlite_reads_the_topic_in_timestamp_order() {
        // out of insertion order, with ties: rows come by timestamp, ties by insertion
        let receive = [30, 10, 20, 10, 40];
        let path = sqlite_bag("order", &receive);
        let dir = path.parent().unwrap().to_path_buf();
        assert_eq!(sqlite_count(&[&path], "/imu").unwrap(), 5);
        assert_eq!(sqlite_count(&[&path], "/absent").unwrap(), 0);
        let mut data = vec![0.0; 10 * 6];
        let mut stamps = vec![0; 10];
        let two = [&path, &path];
        let rows = read_sqlite(
            &two,
            "/imu",
            Stamp::Receive,
            &mut data,
            &mut stamps,
            &Progress::none(),
        )
        .unwrap();
        assert_eq!(rows, 10);
        assert_eq!(&stamps[..5], &[10, 10, 20, 30, 40]);
        let firsts: Vec<f64> = (0..5).map(|r| data[r * 6]).collect();
        assert_eq!(firsts, vec![1.0, 3.0, 2.0, 0.0, 4.0]);
        assert_eq!(&data[7..12], &V[1..]);
        read_sqlite(
            &[&path],
            "/imu",
            Stamp::Header,
            &mut data[..30],
            &mut stamps[..5],
            &Progress::none(),
        )
        .unwrap();
        assert_eq!(&stamps[..5], &[NS, 3 * NS, 2 * NS, 0, 4 * NS]);
        // errors, never a panic, and nothing created beside the file
        let none = &Progress::none();
        let (d, s) = (&mut data[..30], &mut stamps[..5]);
        assert!(read_sqlite(&[&path], "/absent", Stamp::Header, d, s, none).is_err());
        assert!(read_sqlite(&[&path], "/note", Stamp::Header, d, s, none).is_err());
        assert!(
            read_sqlite(
                &[&path],
                "/imu",
                Stamp::Header,
                &mut data[..24],
                &mut stamps[..4],
                none
            )
            .is_err()
        );
        let junk = dir.join("junk.db3");
        std::fs::write(&junk, b"not sqlite at all, not sqlite at all").unwrap();
        assert!(
            read_sqlite(
                &[&junk],
                "/imu",
                Stamp::Header,
                &mut data[..30],
                &mut stamps[..5],
                none
            )
            .is_err()
        );
        let bytes = std::fs::read(&path).unwrap();
        for cut in [0, 100, bytes.len() / 2, bytes.len() - 1] {
            std::fs::write(&junk, &bytes[..cut]).unwrap();
            let _ = read_sqlite(
                &[&junk],
                "/imu",
                Stamp::Header,
                &mut data[..30],
                &mut stamps[..5],
                none,
            );
        }
        let mut names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        names.sort();
        assert_eq!(names, vec!["b?#% .db3", "junk.db3"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn sqlite_strictly_increasing_topic_is_read_in_one_pass() {
        let path = sqlite_bag("increasing", &[5, 7, 9]);
        let mut data = vec![0.0; 3 * 6];
        let mut stamps = vec![0; 3];
        let none = &Progress::none();
        let rows = read_sqlite(
            &[&path],
            "/imu",
            Stamp::Receive,
            &mut data,
            &mut stamps,
            none,
        );
        assert_eq!(rows.unwrap(), 3);
        assert_eq!(stamps, vec![5, 7, 9]);
        assert_eq!([data[0], data[6], data[12]], [0.0, 1.0, 2.0]);
        std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
    }

    #[test]
    fn sqlite_uri_escapes_every_special_byte() {
        let uri = sqlite_uri(Path::new("/a b/c?d#e%f.db3")).unwrap();
        assert_eq!(uri, "file:/a%20b/c%3Fd%23e%25f.db3?mode=ro&immutable=1");
    }
}

//! Bindings of `gyrocore::bags`.

use std::path::PathBuf;

use gyrocore::bags::{self, Stamp};
use numpy::{PyReadonlyArray1, PyReadwriteArray1, PyReadwriteArray2};
use pyo3::prelude::*;

use crate::allan::PyHook;
use crate::array::{c_order, c_order_mut};
use crate::count;
use crate::error::core;

fn stamp_kind(receive: bool) -> Stamp {
    if receive {
        Stamp::Receive
    } else {
        Stamp::Header
    }
}

/// Imu messages of one connection of a decompressed ROS1 bag chunk, checked against its index
/// data, into `data[start:]` and `stamps[start:]` (`gyrocore::bags::ros1_chunk`); returns
/// `(rows, last_receive, ordered)`.
#[pyfunction]
#[pyo3(signature = (chunk, index, conn, receive, previous, data, stamps, start))]
#[allow(clippy::too_many_arguments)]
fn ros1_chunk(
    py: Python<'_>,
    chunk: &[u8],
    index: &[u8],
    #[pyo3(from_py_with = count::conn)] conn: u64,
    receive: bool,
    previous: i64,
    mut data: PyReadwriteArray2<'_, f64>,
    mut stamps: PyReadwriteArray1<'_, i64>,
    #[pyo3(from_py_with = count::start)] start: usize,
) -> PyResult<(usize, i64, bool)> {
    let d = c_order_mut("data", &mut data)?;
    let s = c_order_mut("stamps", &mut stamps)?;
    let scan = core(py.detach(|| {
        bags::ros1_chunk(
            chunk,
            index,
            conn,
            stamp_kind(receive),
            previous,
            d,
            s,
            start,
        )
    }))?;
    Ok((scan.rows, scan.last_receive, scan.ordered))
}

/// Imu messages of one channel of a decompressed MCAP chunk's records into `data[start:]` and
/// `stamps[start:]` (`gyrocore::bags::mcap_chunk`); returns `(rows, last_receive, ordered)`.
#[pyfunction]
#[pyo3(signature = (records, channel, receive, previous, data, stamps, start))]
#[allow(clippy::too_many_arguments)]
fn mcap_chunk(
    py: Python<'_>,
    records: &[u8],
    #[pyo3(from_py_with = count::channel)] channel: u64,
    receive: bool,
    previous: i64,
    mut data: PyReadwriteArray2<'_, f64>,
    mut stamps: PyReadwriteArray1<'_, i64>,
    #[pyo3(from_py_with = count::start)] start: usize,
) -> PyResult<(usize, i64, bool)> {
    let d = c_order_mut("data", &mut data)?;
    let s = c_order_mut("stamps", &mut stamps)?;
    let scan = core(py.detach(|| {
        bags::mcap_chunk(records, channel, stamp_kind(receive), previous, d, s, start)
    }))?;
    Ok((scan.rows, scan.last_receive, scan.ordered))
}

/// CDR Imu messages stored back to back into `data[start:]` (and their header stamps into
/// `stamps[start:]` when `header_stamps`) (`gyrocore::bags::cdr_messages`); returns the rows.
#[pyfunction]
#[pyo3(signature = (buf, lengths, header_stamps, data, stamps, start))]
#[allow(clippy::needless_pass_by_value)]
fn cdr_messages(
    py: Python<'_>,
    buf: &[u8],
    lengths: PyReadonlyArray1<'_, i64>,
    header_stamps: bool,
    mut data: PyReadwriteArray2<'_, f64>,
    mut stamps: PyReadwriteArray1<'_, i64>,
    #[pyo3(from_py_with = count::start)] start: usize,
) -> PyResult<usize> {
    let l = c_order(&lengths);
    let d = c_order_mut("data", &mut data)?;
    let s = c_order_mut("stamps", &mut stamps)?;
    core(py.detach(|| bags::cdr_messages(buf, &l, header_stamps, d, s, start)))
}

/// The Imu messages of topic `topic` of ROS2 sqlite3 storage files (in order), read and decoded
/// in the core, into `data` and `stamps` from row 0 (`gyrocore::bags::read_sqlite`); returns the rows
/// written. `progress(fraction)` is called from the core; an exception it raises stops the
/// read and is re-raised.
#[pyfunction]
#[pyo3(signature = (paths, topic, receive, data, stamps, progress=None))]
#[allow(clippy::needless_pass_by_value)]
fn read_sqlite(
    py: Python<'_>,
    paths: Vec<PathBuf>,
    topic: &str,
    receive: bool,
    mut data: PyReadwriteArray2<'_, f64>,
    mut stamps: PyReadwriteArray1<'_, i64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<usize> {
    let d = c_order_mut("data", &mut data)?;
    let s = c_order_mut("stamps", &mut stamps)?;
    PyHook::new(progress).run(py, |p| {
        bags::read_sqlite(&paths, topic, stamp_kind(receive), d, s, p)
    })
}

/// The messages of topic `topic` in ROS2 sqlite3 storage files
/// (`gyrocore::bags::sqlite_count`).
#[pyfunction]
#[allow(clippy::needless_pass_by_value)]
fn sqlite_count(py: Python<'_>, paths: Vec<PathBuf>, topic: &str) -> PyResult<usize> {
    core(py.detach(|| bags::sqlite_count(&paths, topic)))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("CHANNELS", bags::CHANNELS)?;
    m.add_function(wrap_pyfunction!(ros1_chunk, m)?)?;
    m.add_function(wrap_pyfunction!(mcap_chunk, m)?)?;
    m.add_function(wrap_pyfunction!(cdr_messages, m)?)?;
    m.add_function(wrap_pyfunction!(read_sqlite, m)?)?;
    m.add_function(wrap_pyfunction!(sqlite_count, m)?)
}

"""Reading IMU logs (CSV/TSV/text, ``.npy``, ROS1/ROS2 bags, MCAP) with sampling checks.

:func:`load` returns a :class:`GyroLog`: the selected channels as an ``(n, k)`` float64 array,
their names and units, the sample rate, the time vector (if the log has one) and a
:class:`SamplingReport`. Allan analysis assumes uniform sampling, so the loader does not
silently assume a rate: when the log carries timestamps it estimates the rate from the
intervals and reports jitter, gaps (positions and sizes), repeated and out-of-order stamps,
and a user-given ``fs`` that disagrees with the timestamps. Out-of-order stamps are an error
unless ``repair="sort"`` is asked for; every repair is stated in the report's warnings.

Formats (chosen by the file name):

- CSV/TSV/whitespace-separated text, also ``.gz``/``.bz2``/``.xz``: the columns by header name
  (or ``col<i>``), time from a ``t``/``time``/``timestamp`` column; units from ``units=``.
- ``.npy`` (1-D or 2-D): columns ``col<i>``, time from ``time_column=``.
- ROS1 ``.bag``, ROS2 bag directories (sqlite3 or MCAP storage), ``.db3`` and ``.mcap`` files: a
  ``sensor_msgs/Imu`` topic as ``gyro_x``, ``gyro_y``, ``gyro_z`` in rad/s and ``accel_x``,
  ``accel_y``, ``accel_z`` in m/s², time from ``header.stamp`` (or the receive time).

Logs larger than memory
-----------------------
``spill=True`` (``None``: when the samples exceed a quarter of the memory) puts the samples,
the raw stamps and the time vector in memory-mapped, already unlinked temporary files, written
block by block; a float64 ``.npy`` is mapped directly. A bag is decoded batch by batch
(65 536 messages) into that spill file rather than fed to the Allan analysis message by
message, by design: the out-of-core Allan kernel (``_core.allan.analyse_stream``) reads its
source several times and at several places at once (the mean, the integration constants,
then every τ's windows ``x[c]``, ``x[c+m]``, ``x[c+2m]`` through up to 13 cursors per pass, then
the noise identification), so a bag as source would be decompressed and deserialised a dozen
times or more, while the spill file is a decoded float64 copy (48 bytes per message for six
channels, a fraction of a ``sensor_msgs/Imu`` message) that the kernel reads with bounded
memory. Not bounded yet: the sampling report's statistics take full-length temporaries of the
intervals (the exact median needs them), about one time column each.

The package, by task
--------------------

- **Loading** (:mod:`gyrobias.io.reader`): :func:`load`, :func:`topics`.
- **Results** (:mod:`gyrobias.io._types`, value types only): :class:`GyroLog`,
  :class:`SamplingReport`.
- Formats: :mod:`gyrobias.io.text` (delimited text), :mod:`gyrobias.io.npy`, ``_bag`` (ROS bags,
  MCAP); channel selection and units: :mod:`gyrobias.io.columns`; timestamps, the sampling
  report, repairs and gap filling: :mod:`gyrobias.io.timestamps`; memory-mapped spill files:
  ``_store``.

Examples
--------
>>> import gyrobias, tempfile, pathlib
>>> path = pathlib.Path(tempfile.mkdtemp()) / "log.csv"
>>> _ = path.write_text("t,gx\\n0.00,0.1\\n0.01,0.2\\n0.02,0.1\\n0.03,0.3\\n")
>>> log = gyrobias.io.load(path, columns=["gx"], time_column="t", units="deg/s")
>>> log.columns, log.units, log.fs, log.data.shape
(('gx',), ('deg/s',), 100.0, (4, 1))
"""

from gyrobias.io._types import (
    GyroLog,
    SamplingReport,
    Selection,
    TimeBound,
    parse_time_bound,
    resolve_selection,
)
from gyrobias.io.reader import load, topics
from gyrobias.io.timestamps import FS_TOLERANCE as FS_TOLERANCE
from gyrobias.io.timestamps import GAP_FACTOR as GAP_FACTOR
from gyrobias.io.timestamps import JITTER_WARN as JITTER_WARN
from gyrobias.io.timestamps import NS_THRESHOLD as NS_THRESHOLD
from gyrobias.io.timestamps import US_THRESHOLD as US_THRESHOLD

__all__ = [
    # loading
    "load",
    "topics",
    "parse_time_bound",
    "resolve_selection",
    # results
    "GyroLog",
    "SamplingReport",
    "Selection",
    "TimeBound",
]

"""Explore a log in the browser: look at the rate, pick the part, clean it, fit the terms you
choose, export — inline in Jupyter or as a local app (``gyrobias explore LOG``).

``gyrobias.explore(obj)`` returns the app (a Panel object that displays inline in a notebook):
``obj`` is a path (or a list of paths), a :class:`gyrobias.io.GyroLog`, an array of samples with
``fs=``, or an :class:`gyrobias.allan.AllanResult` (or a sequence of them: the fit only). The
app's state (:mod:`gyrobias.explore.state`) is plain Python; the Python code and the
``gyrobias`` command that reproduce what is on screen are derived from it.

Needs the ``explore`` extra (Panel and Bokeh): ``pip install 'gyrobias[explore]'``. Every script
and style sheet is served from the installed packages: the app needs no network.
"""

from __future__ import annotations

import os
import sys
import types
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from gyrobias.explore.state import Session, Settings, Source

if TYPE_CHECKING:
    from gyrobias.explore.app import ExploreApp

__all__ = ["Session", "Settings", "Source", "explore", "load_sessions"]

#: Suffixes of the files a fleet directory contributes (a directory that is not a ROS2 bag).
LOG_SUFFIXES = (".csv", ".tsv", ".txt", ".npy", ".bag", ".mcap", ".db3", ".gz", ".bz2", ".xz")


def _require_panel() -> None:
    try:
        import bokeh  # noqa: F401
        import panel  # noqa: F401
    except ImportError as exc:
        raise ImportError(
            f"the explorer needs Panel and Bokeh ({exc}); install them with: "
            "pip install 'gyrobias[explore]'"
        ) from None


def _expand(path: Path) -> list[Path]:
    """A file, a ROS2 bag directory, or a fleet directory's logs (sorted)."""
    if path.is_dir() and not (path / "metadata.yaml").exists():
        found = sorted(
            p for p in path.iterdir() if p.is_file() and p.suffix.lower() in LOG_SUFFIXES
        )
        found += sorted(p for p in path.iterdir() if p.is_dir() and (p / "metadata.yaml").exists())
        if not found:
            raise ValueError(f"{path}: a directory without logs (nor a ROS2 bag)")
        return found
    return [path]


def load_sessions(
    paths: Sequence[str | os.PathLike[str]],
    *,
    start: Any = None,
    stop: Any = None,
    **options: Any,
) -> tuple[list[Session], list[str]]:
    """Read every log (a fleet directory gives its logs) with :func:`gyrobias.io.load`'s
    ``options``: the sessions and a message for each input that could not be read.

    ``start`` / ``stop`` (as :meth:`gyrobias.io.GyroLog.select` reads them) are the first
    selection of every log, in seconds."""
    from gyrobias import io

    sessions: list[Session] = []
    errors: list[str] = []
    from gyrobias._validation import checked_path, sequence

    items = sequence("paths", paths)  # a list of paths (one string is not a list of them)
    for i, raw in enumerate(items):
        try:  # a wrong type is a TypeError naming paths[i]; a bad path string an error listed
            files = _expand(checked_path(f"paths[{i}]", raw))
        except (ValueError, OSError) as exc:
            errors.append(str(exc))
            continue
        for path in files:
            try:
                log = io.load(path, **options)
                settings = Settings()
                if start is not None or stop is not None:
                    span = log.select(start, stop).selection
                    assert span is not None
                    settings = Settings(
                        start=span.start_s if start is not None else None,
                        stop=span.stop_s if stop is not None else None,
                    )
                sessions.append(Session(log, Source.from_options(path, options), settings=settings))
            except (ValueError, TypeError, OSError, MemoryError, ImportError) as exc:
                errors.append(f"{path.name}: {exc}")
            except Exception as exc:  # a corrupt file must give a message, not a dead app
                errors.append(f"{path.name}: cannot be read ({type(exc).__name__}: {exc})")
    return sessions, errors


def _sessions_of(obj: Any, fs: float | None, units: Any, options: dict[str, Any]) -> Any:
    from gyrobias.io import GyroLog

    if isinstance(obj, (str, os.PathLike)):
        return load_sessions([obj], fs=fs, units=units, **options)
    if isinstance(obj, GyroLog):
        opts: dict[str, Any] = {}
        if any(u is not None for u in obj.units) and not obj.topic:
            opts["units"] = obj.units[0] if len(set(obj.units)) == 1 else list(obj.units)
        if obj.sampling.fs_source == "user":
            opts["fs"] = obj.fs
        return [Session(obj, Source.from_options(obj.path, opts))], []
    if hasattr(obj, "avar"):
        obj = [obj]
    if isinstance(obj, Sequence) and obj and all(hasattr(r, "avar") for r in obj):
        return [Session(None, Source(None, (), "Allan result"), allan=list(obj))], []
    if isinstance(obj, Sequence) and obj and all(isinstance(p, (str, os.PathLike)) for p in obj):
        return load_sessions(list(obj), fs=fs, units=units, **options)
    from gyrobias._validation import as_float_array

    data = as_float_array("obj", obj, ndims=(1, 2))
    if fs is None:
        raise ValueError("an array needs its sample rate: gyrobias.explore(data, fs=...)")
    log = io_from_array(data, fs, units)
    return [Session(log, Source(None, (), "array"))], []


def io_from_array(data: Any, fs: float, units: Any = None) -> Any:
    """A :class:`gyrobias.io.GyroLog` of an in-memory array (columns ``col0``, ...)."""
    from gyrobias._validation import as_float_array, sample_rate, sequence
    from gyrobias.io import GyroLog
    from gyrobias.io._types import SamplingReport
    from gyrobias.units import checked_units

    fs = sample_rate(fs)
    matrix = as_float_array("data", data, ndims=(1, 2))
    if matrix.ndim == 1:
        matrix = matrix[:, None]
    if matrix.ndim != 2 or matrix.shape[0] < 2:
        raise ValueError(f"data must have shape (samples, channels), got {matrix.shape}")
    k = matrix.shape[1]
    per = (
        (checked_units("units", units),) * k
        if isinstance(units, str) or units is None
        else tuple(checked_units(f"units[{i}]", u) for i, u in enumerate(sequence("units", units)))
    )
    if len(per) != k:
        raise ValueError(f"units has {len(per)} entries for {k} channels")
    report = SamplingReport(n_samples=matrix.shape[0], fs=float(fs), fs_source="user")
    return GyroLog(
        data=matrix,
        columns=tuple(f"col{i}" for i in range(k)),
        fs=float(fs),
        time=None,
        time_start=None,
        time_column=None,
        path=Path("<array>"),
        sampling=report,
        units=per,
    )


def explore(obj: Any, *, fs: float | None = None, units: Any = None, **options: Any) -> ExploreApp:
    """The explorer app for ``obj``; displays inline in Jupyter (``.servable()`` / ``.show()``
    for a page of its own).

    Parameters
    ----------
    obj : path, sequence of paths, GyroLog, array_like or AllanResult
        What to explore: log files (a fleet directory gives its logs; a ROS2 bag directory is
        one log), a loaded log, samples (shape ``(n,)`` or ``(n, channels)``) with ``fs``, or
        Allan-deviation results (the fit view only).
    fs : float, optional
        Sample rate (Hz) of an array, or of a log without timestamps.
    units : str or sequence of str, optional
        Unit of the samples (``"deg/s"``, per channel ``["deg/s", ..., "m/s^2"]``).
    **options
        Further keywords of :func:`gyrobias.io.load` (``columns``, ``topic``, ...).

    Returns
    -------
    ExploreApp
        The app; ``app.sessions`` holds the state of each log.
    """
    _require_panel()
    from gyrobias.explore.app import ExploreApp
    from gyrobias.explore.server import configure

    configure()
    sessions, errors = _sessions_of(obj, fs, units, options)
    return ExploreApp(sessions, errors)


class _CallableModule(types.ModuleType):
    """``gyrobias.explore(obj)`` calls :func:`explore`; ``gyrobias.explore.Session`` etc. stay
    the module's names (the subpackage and the function share the name)."""

    def __call__(
        self, obj: Any, *, fs: float | None = None, units: Any = None, **options: Any
    ) -> ExploreApp:
        return explore(obj, fs=fs, units=units, **options)


sys.modules[__name__].__class__ = _CallableModule

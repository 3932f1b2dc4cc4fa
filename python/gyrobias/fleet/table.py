"""The fleet table: its column layout (one row per unit and axis, one column group per term),
optional-dependency imports, and :func:`write_table`.

Imports no gyrobias module but :mod:`gyrobias._files`, so :mod:`gyrobias.plotting` can read the
layout without depending on the analysis.
"""

from __future__ import annotations

import importlib
import os
from typing import Any

from gyrobias._files import atomic_binary, checked_path

__all__ = ["term_columns", "write_table"]  # TERMS, GM_PARAMETERS: documented in gyrobias.fleet

#: A pandas DataFrame (pandas is imported lazily: it belongs to the ``fleet`` extra).
DataFrame = Any

#: Noise terms with their own columns (IEEE 952 symbols).
TERMS: tuple[str, ...] = ("Q", "N", "B", "K", "R")
#: Parameters of a Gauss–Markov term with their own columns (``GM1_sigma``, …).
GM_PARAMETERS: tuple[str, ...] = ("sigma", "correlation_time")


def _gm_columns(n_gm: int) -> list[str]:
    """``GM1_sigma``, ``GM1_correlation_time``, … for ``n_gm`` Gauss–Markov terms."""
    return [f"GM{k}_{p}" for k in range(1, n_gm + 1) for p in GM_PARAMETERS]


def term_columns(table: Any) -> list[str]:
    """The value columns of a fleet table that hold a term: Q, N, B, K, R, then ``GMk_…``.

    ``GM1_sigma`` [rate unit] and ``GM1_correlation_time`` [s] (``GM2_…`` for the second
    term) are there when :func:`analyse` was given ``terms`` with ``"GM"``/``"GM2"``. Each has
    ``_uncertainty``, ``_unit``, ``_z`` and ``_upper_bound`` companions like the IEEE terms.
    """
    check_table(table)
    present = set(table.columns)
    return [c for c in (*TERMS, *_gm_columns(2)) if c in present]


# --------------------------------------------------------------------------------- the table

_COUNTS = ("n_samples", "n_gaps", "missing_samples", "n_duplicates", "dof")


def _columns(n_gm: int = 0) -> list[str]:
    cols = [
        "source",
        "axis",
        "sensor",
        "data_unit",
        "fs",
        "duration",
        "n_samples",
        "selection",
        "cleaning",
        "n_gaps",
        "missing_samples",
        "longest_gap",
        "n_duplicates",
        "sampling_warnings",
        "fit_method",
        "bound_confidence",
    ]
    for t in (*TERMS, *_gm_columns(n_gm)):
        cols += [t, f"{t}_uncertainty", f"{t}_unit", f"{t}_z", f"{t}_upper_bound"]
    cols += [
        "chi2",
        "dof",
        "chi2_reduced",
        "p_value",
        "fit_warnings",
        "out_of_family",
        "out_of_family_terms",
        "error",
        "adev_tau",
        "adev",
    ]
    return cols


def _require(name: str) -> Any:
    try:
        return importlib.import_module(name)
    except ImportError as exc:
        raise ImportError(
            f"gyrobias.fleet needs {name}, which is not installed; install the fleet extra with "
            'pip install "gyrobias[fleet]" (dask[distributed], pandas, pyarrow)'
        ) from exc


def check_table(table: Any) -> None:
    """``TypeError`` naming ``table`` unless it is a fleet table (a DataFrame from
    :func:`analyse`), instead of an ``AttributeError`` from deep inside pandas."""
    if not (hasattr(table, "to_parquet") and hasattr(table, "columns")):
        raise TypeError(
            f"table must be the pandas.DataFrame of gyrobias.fleet.analyse, got "
            f"{type(table).__name__}"
        )
    if "error" not in table.columns or "axis" not in table.columns:
        raise ValueError(
            "table must be the table of gyrobias.fleet.analyse (columns axis, error, …)"
        )


def write_table(table: DataFrame, path: str | os.PathLike[str]) -> None:
    """Write the fleet table as Parquet (pyarrow), atomically (temp file beside it, then rename).

    The Allan curves ``adev_tau``/``adev`` become list columns; ``pandas.read_parquet`` reads
    the file back.
    """
    check_table(table)
    target = checked_path("path", path)
    _require("pyarrow")
    with atomic_binary(target) as fh:
        table.to_parquet(fh, engine="pyarrow", index=False)

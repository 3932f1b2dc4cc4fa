"""The column layout of a fleet table (one row per unit and axis, one column per term).

Shared by :mod:`gyrobias.fleet`, which builds the table, and :mod:`gyrobias.plotting`, which
draws it; a leaf module (no gyrobias imports), so neither has to import the other.
"""

from __future__ import annotations

from typing import Any

__all__ = ["GM_PARAMETERS", "TERMS", "term_columns"]

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
    ``_uncertainty``, ``_unit`` and ``_z`` companions like the IEEE terms.
    """
    present = set(table.columns)
    return [c for c in (*TERMS, *_gm_columns(2)) if c in present]

"""Out-of-family scores and the fleet summary: robust z-scores (median/MAD), the weighted χ²
homogeneity test and Birge ratio.

The statistics are the core's (``gyrocore::fleet``: median, scaled MAD, robust z, weighted χ²,
Birge ratio, p-value); this module groups the table by axis and term and words the result."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobias import _core
from gyrobias._validation import real
from gyrobias.fleet.table import (
    _COUNTS,
    TERMS,
    DataFrame,
    _columns,
    _gm_columns,
    _require,
    check_table,
    term_columns,
)

#: ``|z|`` above which a term is out of family (Iglewicz & Hoaglin's modified-z cut-off).
OUT_OF_FAMILY_THRESHOLD: float = 3.5
#: Fewest units with a term (per axis) for a median/MAD comparison.
MIN_UNITS: int = 5
#: Significance level of the "is the spread real?" chi-square test in :func:`summary`.
SPREAD_ALPHA: float = 0.01
#: The spread must also exceed the uncertainties by this factor (Birge ratio) to count as real:
#: the joint fit's uncertainties are calibrated to about 15 % (docs/explanations/identification.md, joint fit).
SPREAD_MIN_RATIO: float = 1.2


def _finish(pd: Any, rows: list[dict[str, Any]], threshold: float, n_gm: int = 0) -> DataFrame:
    table = pd.DataFrame.from_records(rows, columns=_columns(n_gm))
    terms = (*TERMS, *_gm_columns(n_gm))
    for name in _COUNTS:
        table[name] = table[name].astype("Int64")
    for name in (
        "fs",
        "duration",
        "longest_gap",
        "chi2",
        "chi2_reduced",
        "p_value",
        "bound_confidence",
        *terms,
        *(f"{t}_uncertainty" for t in terms),
        *(f"{t}_upper_bound" for t in terms),
    ):
        table[name] = table[name].astype("float64")
    z = {t: np.full(len(table), np.nan) for t in terms}
    flag = np.zeros(len(table), dtype=bool)
    known = np.zeros(len(table), dtype=bool)
    ok = table["error"].isna().to_numpy()
    for idx in table[ok].groupby("axis", dropna=False, sort=False).groups.values():
        pos = table.index.get_indexer(idx)
        for t in terms:
            values = table[t].to_numpy()[pos]
            unc = table[f"{t}_uncertainty"].to_numpy()[pos]
            have = np.isfinite(values)
            if have.sum() < MIN_UNITS:
                continue
            # an unknown (non-finite) uncertainty counts as 0: the core's rule
            z[t][pos[have]] = _robust_z(values[have], unc[have])
            known[pos[have]] = True
    terms_out = []
    for i in range(len(table)):
        out = [t for t in terms if np.isfinite(z[t][i]) and abs(z[t][i]) > threshold]
        flag[i] = bool(out)
        terms_out.append(",".join(out) or None)
    for t in terms:
        table[f"{t}_z"] = z[t]
    table["out_of_family"] = pd.array(
        [bool(f) if k else None for f, k in zip(flag, known)], dtype="boolean"
    )
    table["out_of_family_terms"] = terms_out
    return table


def _robust_z(values: NDArray[np.float64], unc: NDArray[np.float64]) -> NDArray[np.float64]:
    """z_i = (X_i − m) / √(σ_fleet² + u_i² + (π/2)s²/n): ``gyrocore::fleet::robust_z``."""
    return _core.fleet.robust_z(values, unc)


def _chi2_sf(x: float, dof: int) -> float:
    """Upper tail ``P(χ²_ν > x)``: the core's regularised incomplete gamma ``Q(ν/2, x/2)``."""
    return _core.stats.chi2_sf(x, float(dof))


def _spread(
    x: NDArray[np.float64], u: NDArray[np.float64], test: _core.fleet.SpreadTest
) -> dict[str, Any]:
    """The statistics of one term over the units that have it at the levels of ``test``
    (``gyrocore::fleet::spread``; see :func:`summary`)."""
    s = _core.fleet.spread(
        np.ascontiguousarray(x, dtype=np.float64),
        np.ascontiguousarray(u, dtype=np.float64),
        test,
    )
    return {
        "median": s.median,
        "spread": s.spread,
        "mean_uncertainty": s.mean_uncertainty,
        "intrinsic_spread": s.intrinsic_spread,
        "chi2": s.chi2,
        "dof": s.dof,
        "birge_ratio": s.birge_ratio,
        "p_value": s.p_value,
        "spread_real": s.real,
    }


def summary(
    table: DataFrame, *, alpha: float = SPREAD_ALPHA, min_ratio: float = SPREAD_MIN_RATIO
) -> DataFrame:
    """Per axis and term: median, spread, mean uncertainty, and whether the spread is real.

    Parameters
    ----------
    table : pandas.DataFrame
        The result of :func:`analyse` (or its Parquet file read back).
    alpha : float
        Significance level of the homogeneity test.
    min_ratio : float
        Smallest Birge ratio that counts as a real spread (see Notes).

    Returns
    -------
    pandas.DataFrame
        One row per (axis, term) with any value: ``axis``, ``term`` (Q, N, B, K, R, or a
        Gauss–Markov column such as ``GM1_sigma``), ``unit``, ``n`` (units
        with the term), ``median``, ``spread`` (1.4826·MAD), ``mean_uncertainty`` (RMS of the
        reported 1σ uncertainties), ``intrinsic_spread`` (``√max(spread² − mean_uncertainty²,
        0)``), ``chi2``, ``dof``, ``birge_ratio`` (``√(χ²/dof)``), ``p_value``,
        ``spread_real`` and ``n_out_of_family``.

    Notes
    -----
    "Is the spread real?" is a homogeneity test: if every unit had the same true value, the
    statistic ``χ² = Σ_i (X_i − X̄_w)²/u_i²`` about the weighted mean ``X̄_w = Σ X_i/u_i² /
    Σ 1/u_i²`` would follow a chi-square law with ``n − 1`` degrees of freedom. The spread is
    called real when ``p < alpha`` (exact upper tail, :func:`_chi2_sf`) **and** the
    Birge ratio ``√(χ²/(n−1)) ≥ min_ratio``: the joint fit's uncertainties are themselves
    right to about 15 %, so a scatter only slightly larger than them is not evidence of real
    unit-to-unit differences however many units there are.
    """
    pd = _require("pandas")
    check_table(table)
    # A test level in (0, 1) and a Birge-ratio floor > 0: checked once, by the core, when the
    # test is built (before any work, so levels are refused even for a table without values).
    test = _core.fleet.SpreadTest(real("alpha", alpha), real("min_ratio", min_ratio))
    out = []
    ok = table[table["error"].isna()]
    for axis, group in ok.groupby("axis", dropna=False, sort=False):
        for t in term_columns(table):
            values = group[t].to_numpy(dtype=np.float64)
            unc = group[f"{t}_uncertainty"].to_numpy(dtype=np.float64)
            have = np.isfinite(values)
            if not have.any():
                continue
            stats = _spread(values[have], unc[have], test)
            units = group[f"{t}_unit"].dropna()
            flagged = (
                group["out_of_family_terms"]
                .dropna()
                .map(lambda text, t=t: t in str(text).split(","))
            )
            out.append(
                {
                    "axis": axis,
                    "term": t,
                    "unit": None if units.empty else str(units.iloc[0]),
                    "n": int(have.sum()),
                    **stats,
                    # astype(bool): under pandas 3 an empty map result keeps the string
                    # dtype, whose sum is "" (int("") fails)
                    "n_out_of_family": int(flagged.astype(bool).sum()),
                }
            )
    result = pd.DataFrame.from_records(
        out,
        columns=[
            "axis",
            "term",
            "unit",
            "n",
            "median",
            "spread",
            "mean_uncertainty",
            "intrinsic_spread",
            "chi2",
            "dof",
            "birge_ratio",
            "p_value",
            "spread_real",
            "n_out_of_family",
        ],
    )
    result["dof"] = result["dof"].astype("Int64")
    result["spread_real"] = result["spread_real"].astype("boolean")
    return result

"""Fleets: the noise terms of many IMU logs in one table, on Dask, locally or on a cluster.

:func:`analyse` runs the single-unit pipeline — :func:`gyrobias.io.load`,
:func:`gyrobias.allan.adev` with confidence intervals, :func:`gyrobias.noise.fit` — on every unit
of a fleet and returns one pandas ``DataFrame`` row per unit and axis. The work is a Dask task
per log file (or per block of units of an in-memory array): by default on Dask's local threaded
scheduler (the Rust kernels release the GIL, so threads run them in parallel), or on a
``distributed.Client`` (a ``LocalCluster`` or a remote scheduler's address). A log that cannot be
read or analysed is a row with its ``error``, never a crashed run. :func:`summary` condenses the
table per axis and term: median, robust spread, the mean reported uncertainty and whether the
unit-to-unit spread is real.

Needs the ``fleet`` extra: ``pip install "gyrobias[fleet]"`` (dask[distributed], pandas, pyarrow).

Out-of-family flag
------------------
For each term ``X`` (Q, N, B, K, R and the Gauss–Markov columns ``GMk_sigma``,
``GMk_correlation_time`` when they were fitted) and axis, over the ``n`` units whose fit has
the term (at least
:data:`MIN_UNITS`), with ``u_i`` the unit's standard uncertainty::

    m       = median_i X_i
    s       = 1.4826 · median_i |X_i − m|                 (MAD: the s.d. for normal data)
    σ_fleet = √max(s² − median_i u_i², 0)                 (unit-to-unit spread, noise removed)
    z_i     = (X_i − m) / √(σ_fleet² + u_i² + (π/2)·s²/n)

``(π/2)·s²/n`` is the variance of the median itself. A unit whose own estimate is uncertain
(short log, a term barely visible) therefore needs a larger deviation to be flagged. A row is
``out_of_family`` when ``|z_i| > 3.5`` for any term (:data:`OUT_OF_FAMILY_THRESHOLD`, the
modified-z-score cut-off of Iglewicz & Hoaglin 1993); ``out_of_family_terms`` names them and the
``X_z`` columns hold the scores. With fewer than :data:`MIN_UNITS` units the flag is ``<NA>``.
Scores are compared within an axis name (``x`` with ``x``); name the axes alike
(``axis_names=``) when logs of different formats are mixed.

False alarms (Monte Carlo, ``tests/test_fleet.py``; one family with a 5 % true spread and 1σ
uncertainties of 1–8 %): ``z`` has unit standard deviation, and ``|z| > 3.5`` happens for
0.9 % / 0.5 % / 0.06 % of the terms at 10 / 40 / 400 units (0.05 % for a known normal law; small
fleets pay for estimating the median and MAD). A unit 6 family standard deviations away is
flagged in more than 90 % of the cases at 40 units.

References
----------
.. [IH93] B. Iglewicz, D. C. Hoaglin, "How to Detect and Handle Outliers", ASQC (1993), §3.
.. [IEEE952] IEEE Std 952-1997, Annex C (the noise terms).

Examples
--------
>>> import numpy as np, gyrobias
>>> from gyrobias import fleet
>>> rate = np.stack([gyrobias.noise.simulate(20_000, 100.0, arw=0.2 / 60, seed=s) for s in range(6)])
>>> table = fleet.analyse(rate, fs=100.0, units="deg/s")          # (units, n): 6 units, 1 axis
>>> len(table), table.loc[0, "N_unit"], bool(abs(table.N.median() * 60 - 0.2) < 0.02)
(6, 'deg/√s', True)
>>> int(table.out_of_family.sum())
0
"""

from gyrobias.fleet.analysis import analyse
from gyrobias.fleet.spread import (
    MIN_UNITS,
    OUT_OF_FAMILY_THRESHOLD,
    SPREAD_ALPHA,
    SPREAD_MIN_RATIO,
    summary,
)
from gyrobias.fleet.table import GM_PARAMETERS, TERMS, term_columns, write_table

__all__ = [
    # analysis
    "analyse",
    # out-of-family scores and the summary
    "MIN_UNITS",
    "OUT_OF_FAMILY_THRESHOLD",
    "SPREAD_ALPHA",
    "SPREAD_MIN_RATIO",
    "summary",
    # the table
    "GM_PARAMETERS",
    "TERMS",
    "term_columns",
    "write_table",
]

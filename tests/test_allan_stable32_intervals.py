"""Confidence intervals against Stable32's published tables (issue 11 item 6).

Oracle: the Stable32 1.5x/1.60 result tables shipped with AllanTools 2024.6's test suite
(provenance in tests/data/README.md): five records (NBS PHASE.DAT, HP 5071A Cs clock, GPS 1PPS,
OCXO frequency, Keysight 53230A noise floor) × ADEV, OADEV, MDEV, TDEV, HDEV, OHDEV, TOTDEV, each
row with Stable32's identified α and its 68.3 % interval ("Min Sigma", "Max Sigma").

gyrobias computes every table with its own identification (lag-1 ACF on the rate averages where
the decimated series has ≥ 30 points, B1 ratio and R(n) below — NIST SP1065 §5.6, Stable32's
rule) and its own EDF, and must reproduce Stable32's bounds: median relative error ≤ 5e-3 and 90th
percentile ≤ 2e-2 over all bounds (issue 11's goal). Run this file as a script to print the
figures per table.
"""

from __future__ import annotations

import functools
import gzip
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import gyrobias
from gyrobias import _core, allan

DATA = Path(__file__).parent / "data"
S = "stable32_intervals/"
F = "allan_family/"

#: record → (series file, data_type, {statistic: Stable32 table}).
SETS: dict[str, tuple[str, str, dict[str, str]]] = {
    "phasedat": (
        S + "phasedat_phase.txt.gz",
        "angle",
        {k: f"{S}phasedat_{k}_octave.txt" for k in ("adev", "oadev", "mdev", "tdev", "hdev")}
        | {"ohdev": S + "phasedat_ohdev_octave.txt", "totdev": S + "phasedat_totdev_octave.txt"},
    ),
    "cs5071a": (
        F + "cs5071a_phase.txt.gz",
        "angle",
        {k: f"{S}cs5071a_{k}_decade.txt" for k in ("adev", "oadev", "mdev", "ohdev")}
        | {"tdev": F + "cs5071a_tdev_decade.txt", "hdev": F + "cs5071a_hdev_decade.txt"},
        # Cs5071A/totdev_decade.txt is left out: that Stable32 run had the noise type fixed to
        # white FM (α = 0 on every row, also at τ = 1 s where every other Cs table reads white
        # PM, and its bounds are α = 0's), so it says nothing about identification.
    ),
    "gps": (
        F + "gps_1pps_phase.txt.gz",
        "angle",
        {"adev": S + "gps_adev_decade.txt"}
        | {k: f"{S}gps_{k}_octave.txt" for k in ("oadev", "mdev", "ohdev", "totdev")}
        | {"tdev": F + "gps_tdev_octave.txt", "hdev": F + "gps_hdev_octave.txt"},
    ),
    "ocxo": (
        F + "ocxo_frequency.txt.gz",
        "rate",
        {k: f"{S}ocxo_{k}_octave.txt" for k in ("adev", "oadev", "mdev", "ohdev", "totdev")}
        | {"tdev": F + "ocxo_tdev_octave.txt", "hdev": F + "ocxo_hdev_octave.txt"},
    ),
    "keysight": (
        F + "keysight_tic_phase.txt.gz",
        "angle",
        {k: f"{S}keysight_{k}.txt" for k in ("oadev", "mdev", "ohdev", "totdev")}
        | {"tdev": F + "keysight_tdev.txt", "hdev": F + "keysight_hdev.txt"},
    ),
}

#: Rows (record, statistic, m) where gyrobias' α differs from Stable32's, with (Stable32's α,
#: ours). GPS at m = 8192 (30 points): gyrobias' check of the ACF against R(n) (not in Stable32;
#: allan::noise_id "Consistency with the local slope") reads phase noise, as R(n) = 0.11 and the
#: ADEV slope τ^−1.05 from 4096 to 8192 s do; Stable32's ACF reads white FM. All others have
#: fewer than 30 decimated points (B1/R(n) territory, ≤ 27 rate averages), where
#: Stable32 itself gives different α for different statistics at the same τ and data (Cs 5071A at
#: τ = 2·10⁴ s: ADEV/HDEV −1, OADEV/MDEV/TDEV/OHDEV 0; OCXO at 2048 s: ADEV/HDEV −2, the others 0)
#: — it evidently uses statistic-specific ratios that SP1065 does not spell out. gyrobias uses one
#: identification per τ for every statistic (B1 of the non-overlapping averages, R(n) of the
#: overlapping sums). TOTDEV rows differ where Stable32's TOTDEV α differs from its own OADEV α.
KNOWN_DIFFERENCES: dict[tuple[str, str, int], tuple[int, int]] = {
    ("phasedat", "totdev", 256): (0, 1),  # 4 points
    ("cs5071a", "adev", 100000): (-1, 1),  # 6 points
    ("cs5071a", "oadev", 20000): (0, -1),  # 28 points
    ("cs5071a", "oadev", 40000): (0, -1),  # 14 points
    ("cs5071a", "oadev", 100000): (0, 1),  # 6 points
    ("cs5071a", "mdev", 20000): (0, -1),  # 28 points
    ("cs5071a", "mdev", 40000): (0, -1),  # 14 points
    ("cs5071a", "mdev", 100000): (0, 1),  # 6 points
    ("cs5071a", "ohdev", 20000): (0, -1),  # 28 points
    ("cs5071a", "ohdev", 40000): (0, -1),  # 14 points
    ("cs5071a", "ohdev", 100000): (0, 1),  # 6 points
    ("cs5071a", "tdev", 20000): (0, -1),  # 28 points
    ("cs5071a", "tdev", 40000): (0, -1),  # 14 points
    ("cs5071a", "tdev", 100000): (0, 1),  # 6 points
    ("cs5071a", "hdev", 100000): (-1, 1),  # 6 points
    ("gps", "oadev", 8192): (0, 1),  # 30 points
    ("gps", "mdev", 8192): (0, 1),  # 30 points
    ("gps", "ohdev", 8192): (0, 1),  # 30 points
    ("gps", "totdev", 8192): (0, 1),  # 30 points
    ("gps", "totdev", 32768): (1, 0),  # 8 points
    ("gps", "tdev", 8192): (0, 1),  # 30 points
    ("gps", "hdev", 8192): (0, 1),  # 30 points
    ("ocxo", "adev", 1024): (-2, -1),  # 20 points
    ("ocxo", "adev", 2048): (-2, -1),  # 10 points
    ("ocxo", "oadev", 2048): (0, -1),  # 10 points
    ("ocxo", "oadev", 4096): (0, -2),  # 5 points
    ("ocxo", "mdev", 2048): (0, -1),  # 10 points
    ("ocxo", "mdev", 4096): (0, -2),  # 5 points
    ("ocxo", "ohdev", 2048): (0, -1),  # 10 points
    ("ocxo", "ohdev", 4096): (0, -2),  # 5 points
    ("ocxo", "totdev", 2048): (0, -1),  # 10 points
    ("ocxo", "totdev", 4096): (0, -2),  # 5 points
    ("ocxo", "totdev", 8192): (0, -2),  # 3 points
    ("ocxo", "tdev", 2048): (0, -1),  # 10 points
    ("ocxo", "tdev", 4096): (0, -2),  # 5 points
    ("ocxo", "hdev", 1024): (-2, -1),  # 20 points
    ("ocxo", "hdev", 2048): (-2, -1),  # 10 points
    ("keysight", "totdev", 8192): (0, 1),  # 7 points
    ("keysight", "totdev", 16384): (0, 1),  # 4 points
}

#: Rows where the same α gives a (documented) different interval: (tolerance, why).
INTERVAL_EXCEPTIONS: dict[tuple[str, str, int], tuple[float, str]] = {
    # TOTDEV white FM at m = 1: SP1065 Table 11's b·N/m = 1.5·1001 = 1502 degrees of freedom
    # from the N − 2 = 999 terms of the sum; gyrobias caps the EDF at the number of terms
    # (allan::edf, "Cap"), Stable32 does not: bounds 0.4 % narrower in Stable32.
    ("phasedat", "totdev", 1): (5e-3, "EDF capped at the 999 terms"),
    # TOTDEV flicker PM: SP1065 Table 5's simple formula (AllanTools' choice); Stable32's
    # bounds imply an EDF ≈ 1.5 % larger (allan::edf module docs).
    ("gps", "totdev", 65536): (5e-3, "flicker-PM TOTDEV EDF formula"),
}

#: Relative error goals of issue 11 (median and 90th percentile over all bounds).
MEDIAN_GOAL = 5e-3
P90_GOAL = 2e-2


@dataclass(frozen=True)
class Row:
    m: int
    alpha: int
    low: float
    dev: float
    high: float


@dataclass(frozen=True)
class Compared:
    record: str
    kind: str
    row: Row
    points: int  # decimated angle points ⌈N/m⌉
    alpha: int  # ours
    low: float
    dev: float
    high: float

    @property
    def errors(self) -> tuple[float, float]:
        return abs(self.low / self.row.low - 1.0), abs(self.high / self.row.high - 1.0)


def read_table(name: str) -> list[Row]:
    """AF, Tau, #, Alpha, Min Sigma, Sigma, Max Sigma rows of a Stable32 table."""
    rows = []
    for line in (DATA / name).read_text().splitlines():
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        f = line.split()
        rows.append(Row(int(f[0]), int(f[3]), float(f[4]), float(f[5]), float(f[6])))
    return rows


@functools.cache
def series(record: str) -> np.ndarray:
    path = DATA / SETS[record][0]
    with gzip.open(path, "rt") as fh:
        values = np.loadtxt(fh, comments="#", dtype=np.float64)
    if record == "ocxo":  # counter readings in Hz → fractional frequency
        values = values / 1.0e7 - 1.0
    return values


def _compute(record: str, kind: str) -> gyrobias.AllanResult:
    _, data_type, tables = SETS[record]
    taus = np.array([float(r.m) for r in read_table(tables[kind])])
    x = series(record)
    common = {"taus": taus, "data_type": data_type, "confidence": 0.683}
    result = {
        "adev": lambda: allan.adev(x, 1.0, overlapping=False, **common),
        "oadev": lambda: allan.adev(x, 1.0, **common),
        "mdev": lambda: allan.mdev(x, 1.0, **common),
        "tdev": lambda: allan.tdev(x, 1.0, **common),
        "hdev": lambda: allan.hdev(x, 1.0, overlapping=False, **common),
        "ohdev": lambda: allan.hdev(x, 1.0, **common),
        "totdev": lambda: allan.totdev(x, 1.0, **common),
    }[kind]()
    assert isinstance(result, gyrobias.AllanResult)
    return result


@functools.cache
def compared(record: str, kind: str) -> tuple[Compared, ...]:
    rows = read_table(SETS[record][2][kind])
    r = _compute(record, kind)
    assert r.ci_low is not None and r.ci_high is not None and r.alpha is not None
    n_phase = len(series(record)) + (1 if SETS[record][1] == "rate" else 0)
    out = []
    for i, row in enumerate(rows):
        assert int(r.m[i]) == row.m
        out.append(
            Compared(
                record,
                kind,
                row,
                -(-n_phase // row.m),
                int(r.alpha[i]),
                float(r.ci_low[i]),
                float(r.adev[i]),
                float(r.ci_high[i]),
            )
        )
    return tuple(out)


TABLES = [(rec, kind) for rec, (_, _, tables) in SETS.items() for kind in tables]


def all_errors() -> np.ndarray:
    return np.array([e for rec, kind in TABLES for c in compared(rec, kind) for e in c.errors])


def _alpha_range(kind: str) -> tuple[int, int]:
    return (-4 if kind in ("hdev", "ohdev") else -2), 2


def test_bounds_reproduce_stable32() -> None:
    errors = all_errors()
    assert len(errors) == 2 * sum(len(compared(rec, kind)) for rec, kind in TABLES)
    assert np.median(errors) <= MEDIAN_GOAL, np.median(errors)
    assert np.percentile(errors, 90) <= P90_GOAL, np.percentile(errors, 90)


@pytest.mark.parametrize(("record", "kind"), TABLES, ids=[f"{r}-{k}" for r, k in TABLES])
def test_identified_noise_per_row(record: str, kind: str) -> None:
    lo, hi = _alpha_range(kind)
    for c in compared(record, kind):
        stable32 = min(max(c.row.alpha, lo), hi)
        key = (record, kind, c.row.m)
        if key in KNOWN_DIFFERENCES:
            assert c.points < 100, key  # only where B1/R(n) decide or check
            assert (stable32, c.alpha) == KNOWN_DIFFERENCES[key], (key, c.alpha)
            continue
        assert c.alpha == stable32, (key, c.points, c.alpha, stable32)
        # Same α → same interval relative to the deviation: 1e-3 = Stable32's 5 printed digits
        # on σ and bounds and its 3-4 digit Greenhall tables. (Relative, because Stable32
        # computes the OCXO frequency record's deviations on the frequency data: its TOTDEV
        # there differs from the integrated-phase one by up to 1.2 %, TDEV by 1.2e-3.)
        width = (
            abs((c.low / c.dev) / (c.row.low / c.row.dev) - 1.0),
            abs((c.high / c.dev) / (c.row.high / c.row.dev) - 1.0),
        )
        tol = INTERVAL_EXCEPTIONS.get(key, (1e-3, ""))[0]
        assert max(width) < tol, (key, width)


def test_long_tau_white_fm_is_not_read_as_white_pm() -> None:
    """The issue's example: Cs 5071A at τ = 10⁴ s (56 decimated points) is white FM for
    Stable32; the old phase-domain test read white PM and claimed ~5·10⁵ degrees of freedom."""
    r = _compute("cs5071a", "oadev")
    assert r.alpha is not None and r.edf is not None and r.n_terms is not None
    i = int(np.flatnonzero(r.m == 10_000)[0])
    assert r.alpha[i] == 0
    assert r.edf[i] < 100  # ≈ 55 averages of white FM: Greenhall gives 82.6
    assert np.all(r.edf <= r.n_terms)


# --- properties --------------------------------------------------------------------------------


_KINDS = {
    "adev": (allan.adev, {}, "overlapping"),
    "adev_no": (allan.adev, {"overlapping": False}, "non-overlapping"),
    "mdev": (allan.mdev, {}, "modified"),
    "hdev": (allan.hdev, {}, "hadamard"),
    "totdev": (allan.totdev, {}, "total"),
}


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(min_value=0, max_value=2**32 - 1),
    n=st.integers(min_value=20, max_value=3000),
    walk=st.floats(min_value=0.0, max_value=3.0),
    kind=st.sampled_from(sorted(_KINDS)),
    power=st.integers(min_value=-40, max_value=40),
)
def test_edf_bounded_and_identification_scale_free(
    seed: int, n: int, walk: float, kind: str, power: int
) -> None:
    """EDF ≤ number of terms summed, at every τ, whatever the noise; and scaling the data by a
    power of two (exact in floating point) changes neither the identification nor the EDF."""
    rng = np.random.default_rng(seed)
    y = rng.normal(size=n) + walk * rng.normal(size=n).cumsum() / math.sqrt(n)
    function, kwargs, _ = _KINDS[kind]
    a = function(y, 1.0, taus="all", confidence=0.683, **kwargs)
    b = function(y * 2.0**power, 1.0, taus="all", confidence=0.683, **kwargs)
    assert isinstance(a, gyrobias.AllanResult) and isinstance(b, gyrobias.AllanResult)
    assert a.edf is not None and a.n_terms is not None and b.edf is not None
    assert np.all(a.edf <= a.n_terms), (a.m[a.edf > a.n_terms], a.edf[a.edf > a.n_terms])
    np.testing.assert_array_equal(a.alpha, b.alpha)
    np.testing.assert_array_equal(a.edf, b.edf)


def _power_law(alpha: int, n: int, rng: np.random.Generator) -> np.ndarray:
    """Rate samples with S ∝ f^α (α = 2 white angle, 0 white rate, −2 random-walk rate)."""
    w = rng.normal(size=n + 1)
    return {2: np.diff(w), 0: w[:n], -2: w[:n].cumsum()}[alpha]


@pytest.mark.parametrize("alpha", [2, 0, -2])
def test_few_point_identification_follows_the_local_slope(alpha: int) -> None:
    """Where the points are few (B1/R(n)), the identified α agrees with the local ADEV/MDEV
    slope: μ_A = d ln σ²/d ln τ of the Allan variance is −α − 1 for the rate noises (−2 for
    angle noise), and MDEV falls faster than ADEV (μ −3 vs −2) only for white angle noise.

    30 records of 16 384 samples per noise; at τ = 1024, 2048 (17 and 9 decimated points) the
    slopes from τ/2 to τ give an independent, slope-based α. Measured (seeds below): the two
    agree on 80 / 72 / 67 % of the cases for white angle / white rate / random-walk rate noise
    (both scatter with so few averages); the identification finds the simulated α in 100 / 85
    / 68 %, the slope rule in 80 / 87 / 82 %. Asserted: ≥ 60 % agreement and ≥ 60 % correct.
    """
    rng = np.random.default_rng(7 + alpha)
    n = 16_384
    agree = correct = total = 0
    for _ in range(30):
        y = _power_law(alpha, n, rng)
        # τ = 1024, 2048 have 17 and 9 decimated points; each slope is taken from τ/2 to τ.
        taus = np.array([512.0, 1024.0, 2048.0])
        r = allan.adev(y, 1.0, taus=taus, confidence=0.683)
        md = allan.mdev(y, 1.0, taus=taus)
        assert r.alpha is not None
        for j in range(2):
            mu_a = 2 * math.log(r.adev[j + 1] / r.adev[j]) / math.log(2)
            mu_m = 2 * math.log(md.adev[j + 1] / md.adev[j]) / math.log(2)
            if mu_m - mu_a < -0.5:  # MDEV steeper: angle noise
                slope_alpha = 2
            else:
                slope_alpha = int(np.clip(round(-mu_a - 1), -2, 0))
            agree += int(r.alpha[j + 1] == slope_alpha)
            correct += int(r.alpha[j + 1] == alpha)
            total += 1
    assert agree >= 0.6 * total, (agree, total)
    assert correct >= 0.6 * total, (correct, total)


def test_raw_binding_reports_the_same_alpha() -> None:
    """The wrapper does not re-identify: the core's α and EDF reach the result unchanged."""
    x = series("phasedat")
    raw = _core.allan.analyse(
        x.reshape(-1, 1), 1.0, "angle", "overlapping", "octave", 10, None, 0.683
    )[0]
    r = allan.adev(x, 1.0, data_type="angle", confidence=0.683)
    np.testing.assert_array_equal(raw["alpha"], r.alpha)
    np.testing.assert_array_equal(raw["edf"], r.edf)


if __name__ == "__main__":  # pragma: no cover - report helper
    errors = all_errors()
    print(
        f"all bounds: n={len(errors)} median {np.median(errors):.2e} p90 "
        f"{np.percentile(errors, 90):.2e} max {errors.max():.2e}"
    )
    for rec, kind in TABLES:
        e = np.array([x for c in compared(rec, kind) for x in c.errors])
        diff = [
            (c.row.m, c.points, c.row.alpha, c.alpha)
            for c in compared(rec, kind)
            if c.alpha != min(max(c.row.alpha, _alpha_range(kind)[0]), 2)
        ]
        print(
            f"{rec:9s} {kind:7s} rows {len(e) // 2:3d} median {np.median(e):.1e} "
            f"p90 {np.percentile(e, 90):.1e} max {e.max():.1e} alpha differs {diff}"
        )

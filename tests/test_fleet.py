"""gyrobias.fleet: Dask fleets (threads and a 2-worker LocalCluster) against the single-unit API."""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest
from distributed import Client, LocalCluster
from hypothesis import example, given
from hypothesis import strategies as st
from scipy import stats

import gyrobias
from gyrobias import _core, allan, fleet, io, noise
from gyrobias.cli import main

FS = 100.0
N_SAMPLES = 12_000  # 2 min at 100 Hz: every τ up to 60 s, fast enough for a dozen units
ARW = 0.2 / 60.0  # deg/√s
BIAS = 3.0 / 3600.0  # deg/s
OUTLIER = 4  # this unit's ARW is three times the fleet's
TERM_COLUMNS = [c for t in fleet.TERMS for c in (t, f"{t}_uncertainty")]


def _unit(seed: int) -> np.ndarray:
    arw = ARW * (3.0 if seed == OUTLIER else 1.0)
    return noise.simulate(N_SAMPLES, FS, arw=arw, bias_instability=BIAS, axes=3, seed=seed)


@pytest.fixture(scope="module")
def logs(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Eight units in three formats (CSV with timestamps, CSV without, NPY) and one corrupt file."""
    d = tmp_path_factory.mktemp("fleet")
    for seed in range(8):
        rate = _unit(seed)
        if seed % 3 == 0:
            t = np.arange(N_SAMPLES) / FS
            np.savetxt(
                d / f"unit{seed}.csv",
                np.column_stack([t, rate]),
                delimiter=",",
                header="t,gx,gy,gz",
                comments="",
                fmt="%.17g",
            )
        elif seed % 3 == 1:
            np.savetxt(d / f"unit{seed}.txt", rate, fmt="%.17g")
        else:
            np.save(d / f"unit{seed}.npy", rate)
    (d / "unit9.npy").write_bytes(b"\x93NUMPY corrupt header, not an array")
    return d


@pytest.fixture(scope="module")
def client() -> Iterator[Client]:
    """A 2-worker LocalCluster (threads in this process: no worker start-up, no pickling)."""
    with (
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0"
        ) as cluster,
        Client(cluster) as c,
    ):
        yield c


def _reference_rows(path: Path, axis_names: list[str] | None = None) -> list[dict[str, Any]]:
    """The single-unit API on one log: io.load, allan.adev (with CIs), noise.fit."""
    log = io.load(path, fs=FS)
    names = axis_names or list(log.columns)
    results = allan.adev(log.data, FS, units="deg/s", axis_names=names)
    rows = []
    for r, c in zip(results, noise.fit(results)):
        row: dict[str, Any] = {
            "axis": r.axis,
            "taus": r.taus,
            "adev": r.adev,
            "chi2": c.chi2,
            "dof": c.dof,
            "p_value": c.diagnostics.p_value,
        }
        for t in c.terms:
            row[t.symbol] = math.nan if t.value is None else t.value
            row[f"{t.symbol}_uncertainty"] = math.nan if t.uncertainty is None else t.uncertainty
            row[f"{t.symbol}_unit"] = t.unit
        rows.append(row)
    return rows


def _assert_matches_single_unit(
    table: pd.DataFrame, source: str, ref: list[dict[str, Any]]
) -> None:
    rows = table[table["source"] == source]
    assert list(rows["axis"]) == [r["axis"] for r in ref]
    for (_, row), expected in zip(rows.iterrows(), ref):
        assert row["error"] is None or (
            isinstance(row["error"], float) and math.isnan(row["error"])
        )
        # Same code path on the same data: bit-identical, whatever the scheduler or thread count.
        got = row[TERM_COLUMNS].to_numpy(dtype=np.float64)
        want = np.array([expected[c] for c in TERM_COLUMNS], dtype=np.float64)
        np.testing.assert_array_equal(got, want)
        np.testing.assert_array_equal(row["adev_tau"], expected["taus"])
        np.testing.assert_array_equal(row["adev"], expected["adev"])
        assert row["chi2"] == expected["chi2"] and row["dof"] == expected["dof"]
        assert row["p_value"] == expected["p_value"]
        assert [row[f"{t}_unit"] for t in fleet.TERMS] == [
            expected[f"{t}_unit"] for t in fleet.TERMS
        ]
        assert (
            row["fs"] == FS and row["n_samples"] == N_SAMPLES and row["duration"] == N_SAMPLES / FS
        )
        assert row["sensor"] == "gyro" and row["data_unit"] == "deg/s"


def test_local_cluster_matches_single_unit_api_and_reports_the_corrupt_file(
    logs: Path, client: Client
) -> None:
    names = ["x", "y", "z"]
    table = fleet.analyse(
        str(logs / "unit*"), fs=FS, units="deg/s", client=client, axis_names=names
    )
    good = sorted(p for p in logs.iterdir() if p.name != "unit9.npy")
    assert len(table) == 3 * len(good) + 1
    for path in good:
        _assert_matches_single_unit(table, str(path), _reference_rows(path, names))
    bad = table[table["source"] == str(logs / "unit9.npy")]
    assert len(bad) == 1
    assert "unit9.npy" in bad["error"].iloc[0] and "ValueError" in bad["error"].iloc[0]
    assert bad[["N", "N_uncertainty"]].isna().all(axis=None)
    assert pd.isna(bad["out_of_family"].iloc[0])
    # Gap summary: the timestamped CSVs have timestamps and no gaps; the others have none to check.
    csv = table[table["source"].str.endswith(".csv")]
    assert (csv["n_gaps"] == 0).all() and (csv["missing_samples"] == 0).all()
    assert (
        table[table["source"].str.endswith(".npy") & table["error"].isna()]["n_gaps"].isna().all()
    )
    # The outlier unit is out of family through N on every axis, nobody else is.
    flagged = table[table["out_of_family"].fillna(False).astype(bool)]
    assert set(flagged["source"]) == {str(logs / f"unit{OUTLIER}.txt")}
    assert list(flagged["out_of_family_terms"]) == ["N", "N", "N"]
    assert (flagged["N_z"] > 10).all()


def test_bags_on_the_cluster_match_single_unit_api(tmp_path: Path, client: Client) -> None:
    """ROS1 and ROS2 (sqlite3, MCAP) bags: gyro rows in rad/s, accel rows in m/s², as io reads them."""
    from tests.test_bags import regular, write_bag

    paths = []
    for seed, fmt in enumerate(("ros1", "db3", "mcap")):
        gyro = noise.simulate(3000, 200.0, arw=1e-3, axes=3, seed=seed)
        accel = 9.81 * np.array([0.0, 0.0, 1.0]) + noise.simulate(
            3000, 200.0, arw=2e-3, axes=3, seed=seed + 10
        )
        paths.append(
            write_bag(tmp_path / f"imu{seed}", fmt, regular(3000), np.hstack([gyro, accel]))
        )
    table = fleet.analyse([str(p) for p in paths], client=client)
    assert table["error"].isna().all(), table["error"].dropna().tolist()
    for p in paths:
        log = io.load(p)
        rows = table[table["source"] == str(p)]
        assert list(rows["axis"]) == list(log.columns)
        assert list(rows["sensor"]) == ["gyro"] * 3 + ["accel"] * 3
        assert list(rows["N_unit"]) == ["rad/√s"] * 3 + ["m/s^1.5"] * 3
        assert (rows["fs"] == log.fs).all() and (rows["n_gaps"] == 0).all()
        results = allan.adev(log.data, log.fs, axis_names=list(log.columns))
        for (_, row), r, unit in zip(rows.iterrows(), results, log.units):
            c = noise.fit(r, unit=unit)
            want = [v for t in c.terms for v in (t.value, t.uncertainty)]
            np.testing.assert_array_equal(
                row[TERM_COLUMNS].to_numpy(dtype=np.float64),
                np.array([np.nan if v is None else v for v in want], dtype=np.float64),
            )
            assert [row[f"{t.symbol}_unit"] for t in c.terms] == [t.unit for t in c.terms]


def test_threaded_scheduler_equals_cluster(logs: Path, client: Client) -> None:
    paths = [logs / "unit0.csv", logs / "unit2.npy", str(logs / "unit[5-7]*")]
    threaded = fleet.analyse(paths, fs=FS, units="deg/s")
    cluster = fleet.analyse(paths, fs=FS, units="deg/s", client=client)
    assert list(threaded["source"]) == list(cluster["source"])
    pd.testing.assert_frame_equal(
        threaded.drop(columns=["adev_tau", "adev"]), cluster.drop(columns=["adev_tau", "adev"])
    )
    # Fewer than MIN_UNITS units per axis: no fleet comparison, the flag is <NA>.
    assert threaded["out_of_family"].isna().all()


def test_array_sources_match_single_unit_api(client: Client) -> None:
    data = np.stack([_unit(seed) for seed in range(6)])  # (units, n, axes)
    before = data.copy()
    for where in (None, client):
        table = fleet.analyse(data, fs=FS, units="deg/s", client=where)
        assert list(table["source"]) == [f"array[{i}]" for i in range(6) for _ in range(3)]
        assert list(table["axis"]) == ["col0", "col1", "col2"] * 6
        for i in range(6):
            results = allan.adev(data[i], FS, units="deg/s", axis_names=["col0", "col1", "col2"])
            for (_, row), r, c in zip(
                table[table["source"] == f"array[{i}]"].iterrows(), results, noise.fit(results)
            ):
                np.testing.assert_array_equal(row["adev"], r.adev)
                want = [v for t in c.terms for v in (t.value, t.uncertainty)]
                np.testing.assert_array_equal(
                    row[TERM_COLUMNS].to_numpy(dtype=np.float64),
                    np.array([np.nan if v is None else v for v in want], dtype=np.float64),
                )
    np.testing.assert_array_equal(data, before)  # the caller's array is not modified
    single = fleet.analyse(data[:, :, 1], fs=FS, units="deg/s", axis_names=["y"])  # (units, n)
    assert list(single["axis"]) == ["y"] * 6
    np.testing.assert_array_equal(
        single["N"].to_numpy(), table[table["axis"] == "col1"]["N"].to_numpy()
    )


# ------------------------------------------------------------------------ Gauss–Markov terms

GM_TIME = 2.0  # s: well inside the 2-minute logs' τ range
GM_SIGMA = 0.01  # deg/s


def _gm_unit(seed: int, axes: int = 2) -> np.ndarray:
    phi = math.exp(-1.0 / (FS * GM_TIME))
    return noise.simulate(
        N_SAMPLES,
        FS,
        arw=ARW,
        ar1=(phi, GM_SIGMA * math.sqrt(1.0 - phi * phi)),
        axes=axes,
        seed=100 + seed,
    )


def _assert_gm_columns_match(
    rows: pd.DataFrame, results: Any, terms: tuple[str, ...], n_gm: int
) -> None:
    """GM columns of a unit's rows equal noise.fit(adev(...), terms=terms), term by term."""
    assert len(rows) == len(results)
    for (_, row), r in zip(rows.iterrows(), results):
        c = noise.fit(r, terms=terms)
        assert row["error"] is None
        assert len(c.gauss_markov) == n_gm
        for k, g in enumerate(c.gauss_markov, start=1):
            for p in fleet.GM_PARAMETERS:
                term = getattr(g, p)
                name = f"GM{k}_{p}"
                want = [
                    np.nan if term.value is None else term.value,
                    np.nan if term.uncertainty is None else term.uncertainty,
                ]
                np.testing.assert_array_equal(
                    row[[name, f"{name}_uncertainty"]].to_numpy(dtype=np.float64), want
                )
                assert row[f"{name}_unit"] == term.unit
        # ... and the IEEE terms are those of the same fit (with the GM term in the model).
        want = [v for t in c.terms for v in (t.value, t.uncertainty)]
        np.testing.assert_array_equal(
            row[TERM_COLUMNS].to_numpy(dtype=np.float64),
            np.array([np.nan if v is None else v for v in want], dtype=np.float64),
        )


@pytest.mark.parametrize("scheduler", ["threads", "cluster"])
def test_gauss_markov_columns_match_single_unit_api(
    tmp_path: Path, client: Client, scheduler: str
) -> None:
    terms = ("N", "B", "K", "GM")
    paths = []
    for seed in range(6):
        rate = _gm_unit(seed)
        if seed % 2:
            np.save(tmp_path / f"gm{seed}.npy", rate)
            paths.append(tmp_path / f"gm{seed}.npy")
        else:
            t = np.arange(N_SAMPLES) / FS
            np.savetxt(
                tmp_path / f"gm{seed}.csv",
                np.column_stack([t, rate]),
                delimiter=",",
                header="t,gx,gy",
                comments="",
                fmt="%.17g",
            )
            paths.append(tmp_path / f"gm{seed}.csv")
    table = fleet.analyse(
        paths,
        fs=FS,
        units="deg/s",
        terms=terms,
        axis_names=["x", "y"],
        client=client if scheduler == "cluster" else None,
    )
    gm_cols = [
        f"GM1_{p}{suffix}"
        for p in fleet.GM_PARAMETERS
        for suffix in ("", "_uncertainty", "_unit", "_z")
    ]
    assert set(gm_cols) <= set(table.columns) and "GM2_sigma" not in table.columns
    assert fleet.term_columns(table) == [*fleet.TERMS, "GM1_sigma", "GM1_correlation_time"]
    for path in paths:
        log = io.load(path, fs=FS)
        results = allan.adev(log.data, FS, units="deg/s", axis_names=["x", "y"])
        _assert_gm_columns_match(table[table["source"] == str(path)], results, terms, 1)
    assert (table["GM1_sigma_unit"] == "deg/s").all()
    assert (table["GM1_correlation_time_unit"] == "s").all()
    # The fit found the term (2 s, 0.01 deg/s) in every unit: 6 units ≥ MIN_UNITS, so the GM
    # columns have robust z-scores and take part in the flag; the summary has them too.
    assert np.isfinite(table["GM1_sigma"]).all()
    assert np.isfinite(table["GM1_sigma_z"]).all()
    assert np.isfinite(table["GM1_correlation_time_z"]).all()
    summ = fleet.summary(table)
    gm = summ[summ["term"] == "GM1_correlation_time"]
    assert list(gm["axis"]) == ["x", "y"] and (gm["unit"] == "s").all() and (gm["n"] == 6).all()
    assert ((gm["median"] > GM_TIME / 3) & (gm["median"] < 3 * GM_TIME)).all()
    assert set(summ["term"]) == {"N", "B", "K", "GM1_sigma", "GM1_correlation_time"}


def test_a_gauss_markov_outlier_is_flagged_by_its_gm_columns() -> None:
    data = np.stack([_gm_unit(seed, axes=1) for seed in range(8)])
    phi = math.exp(-1.0 / (FS * GM_TIME))
    data[3] = noise.simulate(
        N_SAMPLES, FS, arw=ARW, ar1=(phi, 5 * GM_SIGMA * math.sqrt(1.0 - phi * phi)), seed=3
    )
    table = fleet.analyse(data, fs=FS, units="deg/s", terms=("N", "GM"))
    flagged = table[table["out_of_family"].fillna(False).astype(bool)]
    assert list(flagged["source"]) == ["array[3]"]
    assert "GM1_sigma" in flagged["out_of_family_terms"].iloc[0].split(",")
    assert flagged["GM1_sigma_z"].iloc[0] > fleet.OUT_OF_FAMILY_THRESHOLD


def test_two_gauss_markov_terms_on_arrays_match_single_unit_api(client: Client) -> None:
    data = np.stack([_gm_unit(seed) for seed in range(3)])  # (units, n, axes)
    terms = ("N", "GM2")
    for where in (None, client):
        table = fleet.analyse(data, fs=FS, units="deg/s", terms=terms, client=where)
        assert {"GM2_sigma", "GM2_correlation_time_uncertainty"} <= set(table.columns)
        for i in range(3):
            results = allan.adev(data[i], FS, units="deg/s", axis_names=["col0", "col1"])
            _assert_gm_columns_match(table[table["source"] == f"array[{i}]"], results, terms, 2)
    # Without GM terms there are no GM columns at all.
    plain = fleet.analyse(data, fs=FS, units="deg/s")
    assert not [c for c in plain.columns if c.startswith("GM")]


def test_gauss_markov_parquet_cli_and_figure(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from matplotlib.figure import Figure

    for seed in range(5):
        np.save(tmp_path / f"gm{seed}.npy", _gm_unit(seed))
    out, png = tmp_path / "fleet.parquet", tmp_path / "fleet.png"
    args = ["fleet", str(tmp_path / "gm*.npy"), "--fs", "100", "--units", "deg/s"]
    code = main([*args, "--terms", "N,B,K,GM", "--out", str(out), "--plot", str(png)])
    assert code == 0
    printed = capsys.readouterr().out
    assert "GM1_sigma" in printed and "GM1_correlation_time" in printed
    back = pd.read_parquet(out)
    table = fleet.analyse(
        str(tmp_path / "gm*.npy"), fs=FS, units="deg/s", terms=["N", "B", "K", "GM"]
    )
    for col in ("GM1_sigma", "GM1_sigma_uncertainty", "GM1_correlation_time"):
        np.testing.assert_array_equal(back[col].to_numpy(), table[col].to_numpy())
    assert list(back["GM1_sigma_unit"]) == ["deg/s"] * 10
    assert list(back["GM1_correlation_time_unit"]) == ["s"] * 10
    assert png.read_bytes().startswith(PNG_SIGNATURE)
    titles = [ax.get_title() for ax in gyrobias.plotting.plot_fleet(table, Figure()).get_axes()]
    assert "GM1 σ" in titles and "GM1 T" in titles
    # A term list noise.fit rejects is one line naming it, before any log is read.
    assert main([*args, "--terms", "N,XYZ"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("gyrobias: error:") and "terms" in err and "XYZ" in err


def test_progress_is_reported_and_changes_nothing(logs: Path, client: Client) -> None:
    for where in (None, client):
        seen: list[float] = []
        with_progress = fleet.analyse(
            str(logs / "unit[0-4]*"), fs=FS, client=where, progress=seen.append
        )
        plain = fleet.analyse(str(logs / "unit[0-4]*"), fs=FS, client=where)
        assert seen == sorted(seen) and seen[-1] == 1.0 and len(seen) >= 5
        pd.testing.assert_frame_equal(
            with_progress.drop(columns=["adev_tau", "adev"]),
            plain.drop(columns=["adev_tau", "adev"]),
        )


def test_filled_gaps_use_the_gap_aware_estimators(tmp_path: Path) -> None:
    rate = noise.simulate(6000, FS, arw=ARW, axes=2, seed=5)
    t = np.arange(6000) / FS
    t[3000:] += 1.0  # a 1 s gap: 100 samples missing
    np.savetxt(
        tmp_path / "gap.csv",
        np.column_stack([t, rate]),
        delimiter=",",
        header="t,gx,gy",
        comments="",
        fmt="%.17g",
    )
    table = fleet.analyse(tmp_path / "gap.csv", load_options={"fill_gaps": True}, gaps="omit")
    assert table["error"].isna().all()
    assert (table["n_gaps"] == 1).all() and (table["missing_samples"] == 100).all()
    log = io.load(tmp_path / "gap.csv", fill_gaps=True)
    for (_, row), r in zip(
        table.iterrows(), allan.adev(log.data, log.fs, gaps="omit", axis_names=list(log.columns))
    ):
        np.testing.assert_array_equal(row["adev"], r.adev)
        assert row["N"] == noise.fit(r).N.value
    with_nan = fleet.analyse(tmp_path / "gap.csv", load_options={"fill_gaps": True})  # gaps="error"
    assert "NaN" in with_nan["error"].iloc[0] or "nan" in with_nan["error"].iloc[0]


def test_grouping_of_units_into_tasks_does_not_change_results() -> None:
    data = np.stack([noise.simulate(4000, FS, arw=ARW, seed=s) for s in range(7)])
    one = fleet.analyse(data, fs=FS, num_workers=1)
    many = fleet.analyse(data, fs=FS, num_workers=4)
    pd.testing.assert_frame_equal(
        one.drop(columns=["adev_tau", "adev"]), many.drop(columns=["adev_tau", "adev"])
    )


def test_parquet_round_trip(logs: Path, tmp_path: Path) -> None:
    table = fleet.analyse(str(logs / "unit[0-3]*"), fs=FS, units="deg/s")
    out = tmp_path / "fleet.parquet"
    fleet.write_table(table, out)
    back = pd.read_parquet(out)
    assert list(back.columns) == list(table.columns)
    pd.testing.assert_frame_equal(
        back.drop(columns=["adev_tau", "adev"]),
        table.drop(columns=["adev_tau", "adev"]),
        check_dtype=False,
    )
    for a, b in zip(back["adev"], table["adev"]):
        np.testing.assert_array_equal(np.asarray(a), b)
    assert [p.name for p in tmp_path.iterdir()] == ["fleet.parquet"]  # no temp file left behind


def test_bad_arguments() -> None:
    data = np.zeros((3, 100))
    with pytest.raises(ValueError, match="fs is required"):
        fleet.analyse(data)
    with pytest.raises(ValueError, match="no file matches"):
        fleet.analyse("/nonexistent/dir/*.csv", fs=FS)
    with pytest.raises(ValueError, match="sources is empty"):
        fleet.analyse([], fs=FS)
    with pytest.raises(ValueError, match="sources must be a 2-D or 3-D array"):
        fleet.analyse(np.zeros(10), fs=FS)
    with pytest.raises(TypeError, match="sources must be a glob pattern"):
        fleet.analyse([1.0, None], fs=FS)
    with pytest.raises(TypeError, match="client must be"):
        fleet.analyse(data, fs=FS, client=42)
    with pytest.raises(ValueError, match="fit='magic': method must be"):
        fleet.analyse(data, fs=FS, fit="magic")
    with pytest.raises(ValueError, match="axis_names"):
        fleet.analyse(data, fs=FS, axis_names=["a", "b"])
    with pytest.raises(ValueError, match="unit"):
        fleet.analyse(data, fs=FS, units="furlong")


@pytest.mark.parametrize("sources", ["array", "files"])
def test_bad_options_are_judged_once_by_their_owners(sources: str, tmp_path: Path) -> None:
    """The core / allan.adev / noise.fit reject bad options up front, naming the argument."""
    if sources == "array":
        src: Any = np.stack([noise.simulate(2000, FS, arw=ARW, seed=s) for s in range(3)])
    else:
        np.save(tmp_path / "u.npy", noise.simulate(2000, FS, arw=ARW, seed=1))
        src = str(tmp_path / "*.npy")
    for kwargs, error, text in (
        ({"confidence": 1.5}, ValueError, "confidence"),
        ({"confidence": 0.0}, ValueError, "confidence"),
        ({"confidence": "high"}, TypeError, "confidence"),
        ({"fs": -1.0}, ValueError, "fs"),
        ({"fs": "fast"}, TypeError, "fs"),
        ({"gaps": "fill"}, ValueError, "gaps"),
        ({"taus": "weekly"}, ValueError, "taus"),
        ({"fit": "magic"}, ValueError, "fit='magic'"),
        ({"terms": ("N", "XYZ")}, ValueError, "terms"),
        ({"terms": ("N", "GM"), "fit": "ieee"}, ValueError, "Gauss–Markov"),
    ):
        options = {"fs": FS, **kwargs}
        with pytest.raises(error, match=text):
            fleet.analyse(src, **options)


def test_every_valid_option_passes_the_option_check() -> None:
    """The fixed series of the up-front check gives a result for every valid option set."""
    for confidence in (None, 0.683, 0.95):
        for fit, term_lists in (
            ("joint", (None, ("N",), ("Q", "N", "B", "K", "R", "GM"), ("N", "GM2"), ("GM",))),
            ("ieee", (None, ("N", "B"))),
        ):
            for terms in term_lists:
                for fs in (None, 1e-3, 1e6):
                    fleet.analysis._check_options(
                        fleet.analysis._Options(
                            fs=fs,
                            fit=fit,
                            taus="octave",
                            confidence=confidence,
                            axis_names=None,
                            terms=terms,
                        )
                    )
        for taus in ("octave", "decade", "log", "all"):
            for gaps in ("error", "omit"):
                fleet.analysis._check_options(
                    fleet.analysis._Options(
                        fs=100.0,
                        fit="joint",
                        taus=taus,
                        confidence=confidence,
                        axis_names=None,
                        gaps=gaps,
                        terms=("N", "GM"),
                    )
                )


def test_missing_file_and_failed_unit_are_rows(tmp_path: Path) -> None:
    np.save(tmp_path / "ok.npy", noise.simulate(4000, FS, arw=ARW, seed=1))
    table = fleet.analyse([tmp_path / "ok.npy", tmp_path / "gone.csv"], fs=FS)
    assert table["error"].isna().tolist() == [True, False]
    assert "FileNotFoundError" in table["error"].iloc[1]
    arr = np.zeros((2, 4000))
    arr[0] = noise.simulate(4000, FS, arw=ARW, seed=2)  # unit 1 is constant: the fit must fail
    rows = fleet.analyse(arr, fs=FS)
    assert rows["error"].isna().tolist() == [True, False]
    assert rows["error"].iloc[1].startswith("noise fit: ValueError")
    assert len(rows["adev"].iloc[1]) > 0  # the Allan curve is still there
    # A NaN in one unit fails the batch call: that unit alone becomes an error row.
    arr = np.stack([noise.simulate(4000, FS, arw=ARW, seed=s) for s in range(3)])
    arr[1, 17] = np.nan
    rows = fleet.analyse(arr, fs=FS)
    assert rows["error"].isna().tolist() == [True, False, True]
    assert "NaN" in rows["error"].iloc[1] or "nan" in rows["error"].iloc[1]
    np.testing.assert_array_equal(rows["adev"].iloc[2], allan.adev(arr[2], FS).adev)


# ------------------------------------------------------------------------ statistics


def _z_reference(x: np.ndarray, u: np.ndarray) -> np.ndarray:
    """The module docstring's formula, written out with scipy's MAD."""
    m = np.median(x)
    s = stats.median_abs_deviation(x, scale="normal")
    fleet_var = max(s**2 - np.median(u**2), 0.0)
    return (x - m) / np.sqrt(fleet_var + u**2 + np.pi / 2 * s**2 / len(x))


@given(
    st.lists(st.floats(0.5, 2.0), min_size=5, max_size=40),
    st.floats(0.001, 0.5),
)
def test_robust_z_equals_formula(values: list[float], rel: float) -> None:
    x = np.asarray(values)
    u = rel * x
    np.testing.assert_allclose(
        fleet.spread._robust_z(x, u), _z_reference(x, u), rtol=1e-12, atol=1e-12
    )


def test_out_of_family_false_alarm_rate_and_z_scale_by_monte_carlo() -> None:
    """Units from one family (true spread 5 %, heterogeneous 1σ uncertainties 1–8 %).

    Under this null z is about standard normal. |z| > 3.5 would be 0.05 % for a normal; with
    the median and MAD estimated from n units the tails are wider (t-like): the module docs
    state 0.5 % per term at 40 units and 0.06 % at 400 — checked here with margin.
    """
    rng = np.random.default_rng(7)
    for n, reps, limit in ((40, 4000, 0.007), (400, 300, 0.0015)):
        z_all = []
        for _ in range(reps):
            u = rng.uniform(0.01, 0.08, n)
            x = 1.0 + rng.normal(0.0, 0.05, n) + rng.normal(0.0, u)
            z_all.append(fleet.spread._robust_z(x, u))
        z = np.concatenate(z_all)
        assert 0.9 < np.std(z) < 1.15
        assert np.mean(np.abs(z) > fleet.OUT_OF_FAMILY_THRESHOLD) < limit
    # A unit shifted by 6 family s.d. with a typical uncertainty is found nearly always.
    hits = 0
    for _ in range(500):
        u = rng.uniform(0.01, 0.08, 40)
        x = 1.0 + rng.normal(0.0, 0.05, 40) + rng.normal(0.0, u)
        u[0] = 0.03
        x[0] = 1.0 + 6 * 0.05 + rng.normal(0.0, 0.03)
        hits += fleet.spread._robust_z(x, u)[0] > fleet.OUT_OF_FAMILY_THRESHOLD
    assert hits / 500 > 0.9


@given(st.floats(0.01, 500.0), st.integers(1, 2000))
@example(0.25, 3)  # issue 19 explore run: the former Wilson–Hilferty approximation was 0.0053 off
def test_chi2_tail_against_scipy(x: float, dof: int) -> None:
    # The core's continued fraction / series for Q(ν/2, x/2): SciPy's cephes agrees to ~1e-14
    # relative; tails below 1e-300 are compared absolutely.
    assert fleet.spread._chi2_sf(x, dof) == pytest.approx(
        stats.chi2.sf(x, dof), rel=1e-10, abs=1e-300
    )


def _table(values: np.ndarray, unc: np.ndarray) -> pd.DataFrame:
    rows = [
        {
            "source": f"u{i}",
            "axis": "x",
            "error": None,
            "N": v,
            "N_uncertainty": s,
            "N_unit": "deg/√s",
        }
        for i, (v, s) in enumerate(zip(values, unc))
    ]
    return fleet.spread._finish(pd, rows, fleet.OUT_OF_FAMILY_THRESHOLD)


def test_summary_decides_whether_the_spread_is_real() -> None:
    rng = np.random.default_rng(3)
    u = np.full(30, 0.01)
    same = _table(1.0 + rng.normal(0.0, 0.01, 30), u)  # scatter = the uncertainties: not real
    real = _table(1.0 + rng.normal(0.0, 0.05, 30), u)  # five times the uncertainties: real
    s_same, s_real = fleet.summary(same), fleet.summary(real)
    assert list(s_same["term"]) == ["N"] and s_same["unit"].iloc[0] == "deg/√s"
    assert not s_same["spread_real"].iloc[0] and s_real["spread_real"].iloc[0]
    assert 0.7 < s_same["birge_ratio"].iloc[0] < 1.3 and s_real["birge_ratio"].iloc[0] > 3
    assert s_real["intrinsic_spread"].iloc[0] == pytest.approx(0.05, rel=0.35)
    assert s_same["mean_uncertainty"].iloc[0] == pytest.approx(0.01)
    # Monte Carlo: with no real spread the verdict "real" is rarer than alpha.
    false_real = 0
    for _ in range(2000):
        x = 1.0 + rng.normal(0.0, 0.01, 30)
        false_real += fleet.spread._spread(x, u, _DEFAULT_TEST)["spread_real"]
    # At n = 30 the p < 1 % condition is the binding one: the rate is alpha (binomial s.d. 0.2 %).
    assert false_real / 2000 < fleet.SPREAD_ALPHA + 0.005
    # ... and a real spread of twice the uncertainties is found nearly always.
    found = sum(
        fleet.spread._spread(
            1.0 + rng.normal(0.0, 0.02, 30) + rng.normal(0.0, 0.01, 30),
            u,
            _DEFAULT_TEST,
        )["spread_real"]
        for _ in range(500)
    )
    assert found / 500 > 0.95


def test_summary_counts_no_flag_when_no_unit_is_out_of_family() -> None:
    """A term no unit is flagged for counts 0 (pandas 3 once made this sum the string "")."""
    rng = np.random.default_rng(4)
    table = _table(1.0 + rng.normal(0.0, 0.01, 30), np.full(30, 0.01))
    assert not table["out_of_family"].any()
    # what analyse() produces under pandas 3: a string column with no value (all NaN)
    table["out_of_family_terms"] = pd.Series([np.nan] * len(table), dtype="str")
    assert fleet.summary(table)["n_out_of_family"].tolist() == [0]


# ------------------------------------------------------------------------ command line

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def test_cli_writes_parquet_summary_and_plot(
    logs: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out, png = tmp_path / "fleet.parquet", tmp_path / "fleet.png"
    code = main(
        [
            "fleet",
            str(logs / "unit*"),
            "--fs",
            "100",
            "--units",
            "deg/s",
            "--axis-names",
            "x,y,z",
            "--out",
            str(out),
            "--plot",
            str(png),
        ]
    )
    assert code == 0
    captured = capsys.readouterr()
    assert "8 unit" not in captured.out  # counts are of unit-axes
    assert "9 logs, 24 unit-axes analysed, 1 failed" in captured.out
    assert "spread real?" in captured.out
    assert f"unit{OUTLIER}.txt:x (N)" in captured.out
    assert "unit9.npy" in captured.err
    back = pd.read_parquet(out)
    assert len(back) == 25
    assert png.read_bytes().startswith(PNG_SIGNATURE)


def test_cli_scheduler_address_and_csv(
    logs: Path, tmp_path: Path, client: Client, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "fleet.csv"
    address = client.scheduler.address
    code = main(
        [
            "fleet",
            str(logs / "unit[0-2]*"),
            "--fs",
            "100",
            "--scheduler",
            address,
            "--out",
            str(out),
            "--progress",
        ]
    )
    assert code == 0
    captured = capsys.readouterr()
    assert f"(scheduler {address})" in captured.out
    assert "fleet" in captured.err  # the progress bar (tqdm, stderr)
    back = pd.read_csv(out)
    assert len(back) == 9 and "adev" not in back.columns


def test_cli_errors(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["fleet", str(tmp_path / "*.csv"), "--fs", "100"]) == 2
    assert "no file matches" in capsys.readouterr().err
    assert main(["fleet", str(tmp_path / "x.csv"), "--out", str(tmp_path / "t.xlsx")]) == 2
    assert "--out must end in" in capsys.readouterr().err


def test_plot_fleet_draws_one_adev_panel_per_axis_and_one_panel_per_term(logs: Path) -> None:
    from matplotlib.figure import Figure

    table = fleet.analyse(str(logs / "unit*"), fs=FS, units="deg/s", axis_names=["x", "y", "z"])
    fig = gyrobias.plotting.plot_fleet(table, Figure())
    titles = [ax.get_title() for ax in fig.get_axes()]
    assert titles[:3] == ["axis x (8 units)", "axis y (8 units)", "axis z (8 units)"]
    assert "N" in titles[3:] and "B" in titles[3:]
    with pytest.raises(ValueError, match="nothing to plot"):
        gyrobias.plotting.plot_fleet(table[table["error"].notna()], Figure())


def _spread_reference(x: np.ndarray, u: np.ndarray) -> dict[str, float]:
    """``summary``'s statistics written out with NumPy and SciPy (Birge 1932; chi-square tail)."""
    good = np.isfinite(u) & (u > 0)
    w = 1.0 / u[good] ** 2
    xm = np.sum(w * x[good]) / np.sum(w)
    chi2 = float(np.sum(w * (x[good] - xm) ** 2))
    dof = int(good.sum()) - 1
    return {
        "median": float(np.median(x)),
        "spread": float(stats.median_abs_deviation(x, scale="normal")),
        "mean_uncertainty": float(np.sqrt(np.mean(u[good] ** 2))),
        "chi2": chi2,
        "birge_ratio": math.sqrt(chi2 / dof),
        "p_value": float(stats.chi2.sf(chi2, dof)),
    }


@given(
    st.lists(st.tuples(st.floats(0.5, 2.0), st.floats(0.001, 0.5)), min_size=2, max_size=60),
    st.sampled_from([0.001, 0.01, 0.05]),
)
def test_spread_equals_numpy_and_scipy(units: list[tuple[float, float]], alpha: float) -> None:
    """The core's homogeneity test (``gyrocore::fleet::spread``) against NumPy/SciPy: the
    median and MAD exactly as NumPy's convention, the sums to 1e-12, the tail to SciPy's 1e-10."""
    x = np.asarray([v for v, _ in units])
    u = np.asarray([e for _, e in units])
    got = fleet.spread._spread(x, u, _core.fleet.SpreadTest(alpha, fleet.SPREAD_MIN_RATIO))
    ref = _spread_reference(x, u)
    assert got["median"] == ref["median"]
    assert got["spread"] == pytest.approx(ref["spread"], rel=1e-15, abs=1e-300)
    assert got["mean_uncertainty"] == pytest.approx(ref["mean_uncertainty"], rel=1e-12)
    # χ² is a difference of terms of size Σ w·x²: rounding noise relative to that (equal
    # values give χ² = 0 up to that noise in either implementation).
    scale = float(np.sum(x**2 / u**2))
    assert got["chi2"] == pytest.approx(ref["chi2"], rel=1e-12, abs=1e-13 * scale)
    dof = len(x) - 1
    assert got["birge_ratio"] == pytest.approx(
        ref["birge_ratio"], rel=1e-12, abs=math.sqrt(1e-13 * scale / dof)
    )
    if ref["chi2"] > 1e-9 * scale:
        assert got["p_value"] == pytest.approx(ref["p_value"], rel=1e-10, abs=1e-300)
    assert got["dof"] == len(x) - 1
    assert got["spread_real"] == (
        got["p_value"] < alpha and got["birge_ratio"] >= fleet.SPREAD_MIN_RATIO
    )


#: The summary's default levels, as the core's checked test object.
_DEFAULT_TEST = _core.fleet.SpreadTest(fleet.SPREAD_ALPHA, fleet.SPREAD_MIN_RATIO)


def test_spread_checks_are_the_core_s() -> None:
    # The levels are checked once, by the core, when the test is built; the values per call.
    x, u = np.array([1.0, 2.0, 3.0]), np.array([0.1, 0.1, 0.1])
    with pytest.raises(ValueError, match="^alpha must lie strictly between 0 and 1, got 1.5$"):
        _core.fleet.SpreadTest(1.5, 1.2)
    for bad in (0.0, -1.0, math.nan):
        with pytest.raises(ValueError, match="^min_ratio must be finite and > 0, got"):
            _core.fleet.SpreadTest(0.01, bad)
    with pytest.raises(ValueError, match="values"):
        fleet.spread._spread(np.array([1.0, np.nan]), u[:2], _DEFAULT_TEST)
    assert fleet.spread._spread(x, u, _DEFAULT_TEST)["dof"] == 2


def test_summary_refuses_bad_levels_before_any_work() -> None:
    # Also when no term has a value (so no test would run): the levels are the core's check.
    table = pd.DataFrame(
        {"axis": pd.Series([], dtype=object), "error": pd.Series([], dtype=object)}
    )
    assert fleet.summary(table).empty
    for kw, arg in (({"alpha": 1.5}, "alpha"), ({"min_ratio": 0.0}, "min_ratio")):
        with pytest.raises(ValueError, match=f"^{arg} must"):
            fleet.summary(table, **kw)

"""The explorer's state object and entry points without a browser (issue 35).

The state (:mod:`gyrobias.explore.state`) derives the results, the reproducing Python code and
the ``gyrobias`` command from one small settings object: here the code runs in a fresh
interpreter and must print the coefficients the session computed, and the command must write
the same export bytes. The browser test is tests/test_explore_browser.py.
"""

from __future__ import annotations

import os
import shlex
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("panel")

from gyrobias import allan, io, noise  # noqa: E402
from gyrobias.explore import load_sessions  # noqa: E402
from gyrobias.explore.state import Session, Settings, Source  # noqa: E402

FS = 100.0


def _log(path: Path, n: int = 40_000, *, drift: float = 0.05, spikes: bool = False) -> Path:
    cols = [
        noise.simulate(n, FS, arw=0.2 / 60, bias_instability=3 / 3600, seed=s) for s in range(2)
    ]
    rate = np.column_stack(cols) + np.linspace(0.0, drift, n)[:, None]
    if spikes:
        rate[np.arange(1000, n, 5000), 0] += 1.0
    t = np.arange(n) / FS
    np.savetxt(path, np.column_stack([t, rate]), delimiter=",", header="time,gx,gy", comments="")
    return path


@pytest.fixture(scope="module")
def csv(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return _log(tmp_path_factory.mktemp("explore") / "sim.csv", spikes=True)


def _session(csv: Path, **settings: Any) -> Session:
    log = io.load(csv, units="deg/s")
    s = Session(log, Source.from_options(csv, {"units": "deg/s"}))
    if settings:
        s.update(**settings)
    return s


def _run(argv: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    return subprocess.run(argv, cwd=cwd, capture_output=True, text=True, env=env, timeout=300)


CASES = {
    "default": {},
    "part-drift-terms-tau": {
        "start": 30.0,
        "stop": 350.0,
        "detrend": "linear",
        "terms": ("Q", "N", "B", "K"),
        "tau_range": (0.02, 30.0),
        "lines": "none",
    },
    "outliers-quadratic-ieee": {
        "outliers": 6.0,
        "detrend": "quadratic",
        "method": "ieee",
        "terms": ("N", "B", "K"),
    },
}


@pytest.mark.parametrize("case", list(CASES), ids=list(CASES))
def test_python_code_prints_the_sessions_coefficients(case: str, csv: Path, tmp_path: Path) -> None:
    s = _session(csv, **CASES[case])
    expected = "".join(c.to("ieee").summary() + "\n" for c in s.coefficients())
    script = tmp_path / "reproduce.py"
    script.write_text(s.python_code(), encoding="utf-8")
    done = _run([sys.executable, str(script)], tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stdout == expected
    assert (tmp_path / "imu.yaml").read_text(encoding="utf-8") == s.export("kalibr")


@pytest.mark.parametrize("case", list(CASES), ids=list(CASES))
def test_cli_command_writes_the_same_export(case: str, csv: Path, tmp_path: Path) -> None:
    s = _session(csv, **CASES[case])
    for fmt in ("kalibr", "json"):
        argv = shlex.split(s.cli_command(fmt, output=str(tmp_path / f"out.{fmt}")))
        assert argv[:2] == ["gyrobias", "allan"]
        done = _run([sys.executable, "-m", "gyrobias", *argv[1:], "--no-progress"], tmp_path)
        assert done.returncode == 0, done.stderr
        assert (tmp_path / f"out.{fmt}").read_text(encoding="utf-8") == s.export(fmt)


def test_gmwm_code_runs_and_the_command_says_why_not(csv: Path, tmp_path: Path) -> None:
    s = _session(csv, method="gmwm", terms=("N", "B", "K"), lines="none")
    expected = "".join(c.to("ieee").summary() + "\n" for c in s.coefficients())
    script = tmp_path / "gmwm.py"
    script.write_text(s.python_code(export=None), encoding="utf-8")
    done = _run([sys.executable, str(script)], tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stdout == expected
    with pytest.raises(ValueError, match="GMWM"):
        s.cli_command()


def test_session_matches_the_public_api_step_by_step(csv: Path) -> None:
    from gyrobias import cleaning

    s = _session(csv, start=10.0, stop=300.0, outliers=5.0, detrend="linear")
    log = io.load(csv, units="deg/s").select(start=10.0, stop=300.0)
    out = cleaning.remove_outliers(log.data, threshold=5.0, units=log.units)
    data = cleaning.detrend(out.data, FS, order=1, units=log.units).data
    np.testing.assert_array_equal(s.cleaned().data, data)
    assert sum(s.cleaned().outliers) == int(np.asarray(out.mask).sum()) > 0
    ref = allan.adev(data, FS, taus="octave", units="deg/s", axis_names=["gx", "gy"], gaps="omit")
    assert isinstance(ref, tuple)
    for got, want in zip(s.allan(), ref):
        np.testing.assert_array_equal(got.avar, want.avar)
    # the whole log is not copied: the selection is a view of the loaded data
    assert np.shares_memory(s.selection().data, s.log.data)  # type: ignore[union-attr]


def test_history_and_undo(csv: Path) -> None:
    s = _session(csv)
    first = s.settings
    assert not s.can_undo
    s.update(start=5.0)
    s.update(detrend="linear")
    s.update(detrend="linear")  # no change: no new step
    assert len(s.history) == 3 and s.settings.steps()[:2] == [
        "part 5 s – end",
        "linear drift removed",
    ]
    s.undo()
    assert s.settings.detrend is None and s.settings.start == 5.0
    s.undo()
    s.undo()  # nothing more to undo
    assert s.settings == first


@pytest.mark.parametrize(
    ("changes", "match"),
    [
        ({"start": -1.0}, "start"),
        ({"start": 10.0, "stop": 5.0}, "after start"),
        ({"outliers": 0.0}, "outlier threshold"),
        ({"detrend": "cubic"}, "detrend"),
        ({"method": "nnls"}, "method"),
        ({"terms": ()}, "at least one term"),
        ({"terms": ("N", "X")}, "unknown terms X"),
        ({"tau_range": (3.0, 1.0)}, "τ range"),
        ({"lines": "some"}, "lines"),
        ({"deviation": "xdev"}, "deviation"),
    ],
)
def test_invalid_settings_are_refused_and_keep_the_state(
    changes: dict[str, Any], match: str, csv: Path
) -> None:
    s = _session(csv)
    with pytest.raises(ValueError, match=match):
        s.update(**changes)
    assert s.settings == Settings() and not s.can_undo


def _app_messages(app: Any) -> list[str]:
    """Every message the app shows, after drawing each view."""
    out = [str(m.object) for m in app.load_errors]
    if app.sessions:
        for i in range(len(app.views)):
            app.tabs.active = i
            out += [str(m.object) for m in app.alerts]
    return out


def _bad_inputs(tmp: Path) -> dict[str, tuple[Path, str]]:
    bag = tmp / "corrupt.bag"
    bag.write_bytes(b"#ROSBAG V2.0\n" + b"\x00garbage" * 50)
    one = tmp / "one_column.csv"
    np.savetxt(one, np.arange(100) / FS, header="time", comments="")
    nan = tmp / "nan.csv"
    nan.write_text("time,gx\n" + "".join(f"{i / FS},nan\n" for i in range(200)))
    empty_dir = tmp / "empty_dir"
    empty_dir.mkdir()
    return {
        "corrupt bag": (bag, "corrupt.bag"),
        "one column": (one, "one_column.csv"),
        "all NaN": (nan, "nan.csv"),
        "directory": (empty_dir, "without logs"),
        "missing": (tmp / "missing.csv", "missing.csv"),
    }


def test_unreadable_inputs_are_messages_in_the_app(tmp_path: Path) -> None:
    from gyrobias.explore.app import ExploreApp
    from gyrobias.explore.server import configure

    configure()
    cases = _bad_inputs(tmp_path)
    sessions, errors = load_sessions([p for p, _ in cases.values()], units="deg/s")
    assert not sessions and len(errors) == len(cases)
    for (_, needle), message in zip(cases.values(), errors):
        assert needle in message and "Traceback" not in message
    app = ExploreApp(sessions, errors)
    shown = " ".join(_app_messages(app))
    assert all(needle in shown for _, needle in cases.values())


def test_ten_samples_give_messages_not_a_dead_page(tmp_path: Path) -> None:
    from gyrobias.explore.app import ExploreApp
    from gyrobias.explore.server import configure

    configure()
    path = tmp_path / "ten.csv"
    np.savetxt(
        path,
        np.column_stack([np.arange(10) / FS, np.random.default_rng(1).normal(size=10)]),
        delimiter=",",
        header="time,gx",
        comments="",
    )
    sessions, errors = load_sessions([path], units="deg/s")
    assert len(sessions) == 1 and not errors
    app = ExploreApp(sessions, errors)
    messages = _app_messages(app)
    assert any("Fit:" in m for m in messages), messages  # 10 samples cannot be fitted
    assert not any("Traceback" in m for m in messages)


def test_upload_within_the_limit_only(tmp_path: Path, csv: Path) -> None:
    from gyrobias.explore import app as app_module

    s = app_module.load_upload("../../etc/sim.csv", csv.read_bytes(), units="deg/s")
    assert s.source.path == Path("sim.csv") and s.log is not None and s.log.n_samples == 40_000
    big = b"0" * (app_module.UPLOAD_LIMIT_MB * 1_000_000 + 1)
    with pytest.raises(ValueError, match="upload limit"):
        app_module.load_upload("big.csv", big)


def test_explore_entry_accepts_paths_logs_arrays_and_allan_results(csv: Path) -> None:
    import gyrobias

    from_path = gyrobias.explore(csv, units="deg/s")
    assert from_path.sessions[0].log is not None
    log = io.load(csv, units="deg/s")
    from_log = gyrobias.explore(log)
    assert from_log.sessions[0].source.kwargs == {"units": "deg/s"}
    data = np.asarray(log.data)
    from_array = gyrobias.explore(data, fs=FS, units="deg/s")
    assert from_array.sessions[0].columns == ("col0", "col1")
    results = allan.adev(data, FS, units="deg/s")
    from_result = gyrobias.explore(results)
    assert [c.axis for c in from_result.sessions[0].coefficients()] == [r.axis for r in results]
    with pytest.raises(ValueError, match="sample rate"):
        gyrobias.explore(data)


def test_inline_display_uses_no_cdn(csv: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # Jupyter's display: Panel configured for inlined resources (pn.extension(inline=True) in
    # the notebook, the app's models rendered in 'inline' resource mode); IPython is not a test
    # dependency, so Panel's console-output capture (which imports it) is off here.
    import panel as pn

    import gyrobias

    app = gyrobias.explore(csv, units="deg/s")
    assert pn.config.inline
    monkeypatch.setattr(pn.config, "console_output", "disable")
    bundle = app._repr_mimebundle_()
    text = str(bundle)
    assert "application/vnd.holoviews_exec.v0+json" in text or "text/html" in text
    assert (
        "cdn.bokeh.org" not in text and "cdn.holoviz.org" not in text and "cdn.jsdelivr" not in text
    )


def test_import_gyrobias_explore_loads_no_framework() -> None:
    code = (
        "import sys, gyrobias.explore, gyrobias.explore.state\n"
        "print(sorted(m for m in ('panel', 'bokeh', 'playwright') if m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


def test_every_view_draws_every_setting_without_a_message(csv: Path) -> None:
    # The app over a good log: each view, each statistic, estimator and layout draws, and the
    # only messages are the refusals the settings call for (no exception reaches the page).
    from gyrobias.explore.app import ExploreApp
    from gyrobias.explore.server import configure

    configure()
    app = ExploreApp([_session(csv)])

    def shown() -> list[str]:
        return [str(m.object) for m in app.alerts]

    for i in range(len(app.views)):
        app.tabs.active = i
        assert shown() == [], (app.views[i].title, shown())
    app.tabs.active = 2
    for kind in ("mdev", "hdev", "totdev", "theo1", "wvar", "wvar-robust", "adev"):
        app.apply(deviation=kind)
        assert shown() == [], (kind, shown())
    app.views[2].layout.value = "apart"  # type: ignore[attr-defined]
    assert shown() == []
    app.tabs.active = 3
    for changes in (
        {"method": "ieee"},
        {"method": "gmwm", "terms": ("N", "B", "K")},
        {"method": "joint", "terms": ("Q", "N", "B", "K", "R", "GM")},
        {"start": 20.0, "stop": 380.0, "outliers": 5.0, "detrend": "quadratic"},
        {"tau_range": (0.05, 20.0), "lines": "none"},
    ):
        app.apply(**changes)
        assert shown() == [], (changes, shown())
    # a statistic that cannot skip the removed outliers' gaps is a message, then undo clears it
    app.tabs.active = 2
    app.apply(deviation="theo1")
    assert any("THEO1 cannot skip" in m for m in shown())
    app._on_undo(None)
    assert shown() == [] and app.session.settings.deviation == "adev"


def test_long_computations_report_progress_without_changing_results(csv: Path) -> None:
    # Théo1 of a long log takes seconds: the session hands the library's progress= to the app
    # (shown beside the busy indicator); the results are those computed without it
    plain = _session(csv, deviation="theo1").stability()
    s = _session(csv, deviation="theo1")
    seen: list[float] = []
    s.progress = seen.append
    reported = s.stability()
    assert len(seen) >= 2 and seen == sorted(seen) and seen[-1] == pytest.approx(1.0)
    for a, b in zip(plain, reported):
        np.testing.assert_array_equal(a.avar, b.avar)  # type: ignore[union-attr]


def test_progress_reaches_the_page_throttled_and_only_for_the_newest_change(
    csv: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from gyrobias.explore import app as app_module
    from gyrobias.explore.app import ExploreApp
    from gyrobias.explore.server import configure

    configure()
    app = ExploreApp([_session(csv)])

    class Doc:  # the served document's thread-safe entry (add_next_tick_callback)
        def __init__(self) -> None:
            self.callbacks: list[Any] = []

        def add_next_tick_callback(self, cb: Any) -> None:
            self.callbacks.append(cb)

    clock = [100.0]
    monkeypatch.setattr(app_module.time, "monotonic", lambda: clock[0])
    doc = Doc()
    app.busy.value = True
    report = app._progress_reporter(doc, app._generation)
    report(0.1)  # within _PROGRESS_EVERY of the start: not sent
    assert doc.callbacks == []
    clock[0] += 1.0
    report(0.42)
    assert len(doc.callbacks) == 1
    doc.callbacks.pop()()
    assert "42%" in str(app.state.object)
    clock[0] += 0.1
    report(0.5)  # throttled
    assert doc.callbacks == []
    clock[0] += 1.0
    report(0.6)
    app._generation += 1  # a newer change: the old computation's message is dropped
    doc.callbacks.pop()()
    assert "60%" not in str(app.state.object)
    clock[0] += 1.0
    report(0.7)
    assert doc.callbacks == []

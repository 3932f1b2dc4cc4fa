"""Not-static logs (issue 33): steps, motion segments and warm-up trends are found where they
are (``gyrocore::stationarity`` through ``allan.stationarity`` and ``AllanResult.stationarity``),
clean simulated logs give no warning, and the fit, the CLI and the report say so.

The independent reference is a NumPy transcription of the finest-scale statistic (block means,
consecutive differences, 1.4826·MAD, the Bonferroni threshold from SciPy's normal quantile).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from gyrobias import _core, allan, noise
from gyrobias.cli import main

FS = 100.0
HOUR = 360_000  # samples at 100 Hz


def _realistic(n: int, seed: int, **extra: float) -> np.ndarray:
    """The documentation's MEMS gyro (ADIS16405-like: N = 0.2 deg/√h, B = 3 deg/h, K)."""
    terms = {"arw": 0.2 / 60, "bias_instability": 3 / 3600, "rrw": 10 / 216_000, **extra}
    return noise.simulate(n, FS, seed=seed, **terms)  # type: ignore[arg-type]


# --------------------------------------------------------------------------- the four cases


def test_rotation_in_the_middle_is_a_segment_where_it_is() -> None:
    rate = _realistic(HOUR, 1)
    t = np.arange(HOUR) / FS
    rotation = (t >= 1800.0) & (t < 1830.0)  # 30 s at 20 deg/s with 1 s ramps
    rate[rotation] += 20.0 * np.clip(np.minimum(t[rotation] - 1800.0, 1830.0 - t[rotation]), 0, 1)
    check = allan.stationarity(rate, FS, units="deg/s")
    assert isinstance(check, allan.Stationarity)
    assert [d.kind for d in check.disturbances] == ["segment"]
    d = check.disturbances[0]
    # located to within two blocks (0.88 s each: the block before the first changed one is in
    # the span, as the difference that flags the change starts there)
    assert 1800.0 - 2 * d.block_s <= d.start_s <= 1800.0
    assert 1830.0 <= d.stop_s <= 1830.0 + 2 * d.block_s
    assert d.size == pytest.approx(20.0, rel=0.1)
    assert f"--stop {d.start_s:.6g} or select(stop={d.start_s:.6g})" in (check.advice() or "")
    assert "motion or disturbance from 1798.72 s to 1831.28 s" in check.warnings[0]


def test_step_is_found_with_its_size_and_advice() -> None:
    rate = _realistic(HOUR, 2)
    rate[123_400:] += 0.8
    check = allan.stationarity(rate, FS, units="deg/s")
    assert [d.kind for d in check.disturbances] == ["step"]
    d = check.disturbances[0]
    assert abs(d.at_s - 1234.0) <= d.block_s and d.start_s <= 1234.0 <= d.stop_s
    assert d.size == pytest.approx(0.8, rel=0.05)
    # the longer quiet side is after the step
    assert check.quiet_s[0] == pytest.approx(d.stop_s) and check.quiet_s[1] == 3600.0
    assert f"--start {d.stop_s:.6g}" in (check.advice() or "")
    assert "rate step of +0.8" in check.warnings[0]


def test_warm_up_exponential_is_a_trend_at_the_start() -> None:
    rate = _realistic(HOUR, 3)
    t = np.arange(HOUR) / FS
    rate += 0.5 * np.exp(-t / 600.0)  # a 10-minute warm-up of 0.5 deg/s
    check = allan.stationarity(rate, FS, units="deg/s")
    assert [d.kind for d in check.disturbances] == ["trend"]
    d = check.disturbances[0]
    assert d.start_s == 0.0 and 60.0 <= d.stop_s <= 1800.0
    assert 0.2 < d.size < 0.55
    assert "warm-up trend over the first" in check.warnings[0]
    assert f"--start {d.stop_s:.6g}" in (check.advice() or "")


def test_step_and_segment_together_and_the_longest_quiet_stretch() -> None:
    rate = _realistic(2 * HOUR, 4)
    rate[2000 * 100 : 2030 * 100] -= 15.0
    rate[5000 * 100 :] += 1.0
    check = allan.stationarity(rate, FS, units="deg/s")
    assert [d.kind for d in check.disturbances] == ["segment", "step"]
    a, b = check.quiet_s
    block = check.disturbances[0].block_s
    assert 2030.0 <= a <= 2030.0 + 2 * block and 5000.0 - 2 * block <= b <= 5000.0


# --------------------------------------------------------------------------- clean logs


@pytest.mark.parametrize("seed", range(12))
def test_clean_realistic_logs_give_no_warning(seed: int) -> None:
    # The docs' logs: 1 h and 2.8 h at 100 Hz with quantisation, white noise, bias instability,
    # random walk; a Gauss–Markov (AR(1)) term; a vibration line; a 31-tap FIR (sensor filter).
    logs = [
        _realistic(HOUR, seed),
        _realistic(1_008_000, 100 + seed, quantization=1e-4),
        _realistic(HOUR, 200 + seed, sinusoids=[(23.0, 0.05)]),  # type: ignore[arg-type]
        noise.simulate(
            HOUR, FS, arw=0.05 / 60, ar1=(0.999, 0.005 * np.sqrt(1 - 0.999**2)), seed=seed
        ),
    ]
    taps = np.hanning(33)[1:-1] / np.hanning(33)[1:-1].sum()
    logs.append(np.convolve(_realistic(HOUR + 30, 300 + seed), taps, mode="valid"))
    for i, rate in enumerate(logs):
        check = allan.stationarity(rate, FS, units="deg/s")
        assert check.checked and check.static, (seed, i, check.warnings)


@pytest.mark.parametrize("seed", range(8))
def test_strong_random_walk_and_bias_instability_on_long_logs_are_noise(seed: int) -> None:
    # 10 h at 20 Hz, random walk 20x the docs' gyro: the level wanders by far more than the
    # white noise, and still no warning (each scale is judged against its own spread).
    rate = noise.simulate(
        720_000, 20.0, arw=0.2 / 60, bias_instability=30 / 3600, rrw=200 / 216_000, seed=seed
    )
    check = allan.stationarity(rate, 20.0)
    assert check.checked and check.static, check.warnings


def test_short_logs_are_not_checked() -> None:
    check = allan.stationarity(np.zeros(500), FS)
    assert not check.checked and check.static
    assert "too short" in str(check)


# --------------------------------------------------------------------------- the reference


def _reference_z(rate: np.ndarray) -> tuple[np.ndarray, float]:
    """Finest scale in NumPy: |d − median(d)| / (1.4826·MAD) and the threshold t_K."""
    n = rate.shape[0]
    length = max(16, -(-n // 4096))
    k = n // length
    means = rate[: k * length].reshape(k, length).mean(axis=1)
    d = np.diff(means)
    centre = np.median(d)
    scale = 1.482602218505602 * np.median(np.abs(d - centre))
    z_k = stats.norm.isf(1e-6 / (2 * d.size))
    return np.abs(d - centre) / scale, z_k / (1 - 3 * 1.166 / np.sqrt(d.size))


def test_finest_scale_matches_numpy() -> None:
    rate = _realistic(HOUR, 5)
    rate[200_000:] += 0.3
    z, t = _reference_z(rate)
    assert _core.stationarity.block_length(HOUR) == 88
    check = allan.stationarity(rate, FS)
    (d,) = check.disturbances
    # Tolerance: the core's block means sum in another order (1e-12 relative).
    assert d.z == pytest.approx(z.max(), rel=1e-9)
    assert d.threshold == pytest.approx(t, rel=1e-9)
    assert d.at_s == pytest.approx((np.argmax(z) + 1) * 88 / FS)
    assert np.sum(z > t) >= 1


@settings(max_examples=20, deadline=None)
@given(position=st.floats(0.1, 0.9), size=st.floats(0.2, 5.0), seed=st.integers(0, 1000))
def test_any_large_step_is_located(position: float, size: float, seed: int) -> None:
    # size ≥ 0.2 deg/s is ≥ 40 times the finest scale's spread (≈ 5e-3 deg/s at 0.88 s)
    n = HOUR // 2
    rate = _realistic(n, seed)
    at = int(position * n)
    rate[at:] += size
    check = allan.stationarity(rate, FS)
    assert [d.kind for d in check.disturbances] == ["step"]
    d = check.disturbances[0]
    assert abs(d.at_s - at / FS) <= d.block_s
    assert d.size == pytest.approx(size, rel=0.1)


# --------------------------------------------------------------------------- where it shows


def test_adev_result_fit_cli_and_report_show_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    rate = _realistic(HOUR, 6)
    rate[123_400:] += 0.8
    r = allan.adev(rate, FS, units="deg/s")
    direct = allan.stationarity(rate, FS, units="deg/s")
    assert r.stationarity is not None
    # block means read off the angle series = block means of the samples (same event)
    (a,), (b,) = r.stationarity.disturbances, direct.disturbances
    assert (a.kind, a.start_s, a.stop_s, a.at_s) == (b.kind, b.start_s, b.stop_s, b.at_s)
    assert a.size == pytest.approx(b.size, rel=1e-6)
    fit = noise.fit(r)
    assert fit.diagnostics is not None
    assert fit.diagnostics.warnings[0] == r.stationarity.warnings[0]
    clean = noise.fit(allan.adev(_realistic(HOUR, 6), FS, units="deg/s"))
    assert clean.diagnostics is not None
    assert not any("not static" in w for w in clean.diagnostics.warnings)
    # CLI: a stderr warning, the JSON; with --start the times are in the log as read
    path = tmp_path / "log.csv"
    t = np.arange(HOUR) / FS
    np.savetxt(
        path, np.column_stack([t, rate]), delimiter=",", header="t,gx", comments="", fmt="%.10g"
    )
    out = tmp_path / "o.json"
    assert main(["allan", str(path), "--units", "deg/s", "--start", "600", "--json", str(out)]) == 0
    err = capsys.readouterr().err
    assert "gyrobias: warning: axis gx: the log is not static: rate step of +0.8" in err
    doc = json.loads(out.read_text())
    (event,) = doc["stationarity"][0]["disturbances"]
    assert abs(event["at_s"] - 1234.0) <= event["block_s"] + 1e-9
    # the report
    html = tmp_path / "r.html"
    assert main(["report", str(path), "--units", "deg/s", "-o", str(html)]) == 0
    page = html.read_text()
    assert "Not a static log." in page and "rate step of +0.8" in page
    # once in the channel's section, not again among the fit's warnings listed under it
    section = page[page.index('id="ch0"') : page.index('id="exports"')]
    assert section.count("rate step of +0.8") == 1 and page.count("Not a static log.") == 1

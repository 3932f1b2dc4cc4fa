"""The data's variance (issue 34, section 3): every Allan path carries it as
``AllanResult.data_variance`` (checked against ``numpy.var`` on each path), and ``noise.fit`` /
``noise.gmwm`` keep every estimated term within what it allows (``gyrocore::noise::variance_limit``).
"""

from __future__ import annotations

import dataclasses
import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from gyrobias import allan, noise

FS = 100.0


def _rate(n: int = 20_000, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return 0.3 + rng.normal(0.0, 0.05, n) + np.cumsum(rng.normal(0.0, 1e-3, n))


# ----------------------------------------------------------------------- data_variance, per path

# Tolerances: the kernel's corrected two-pass sums (block lanes, compensated block totals) and
# NumPy's pairwise two-pass variance are both accurate to a few ulp·√n relative on these data;
# 1e-12 relative leaves a factor > 100 of margin.
RTOL = 1e-12


@pytest.mark.parametrize(
    "fn", [allan.adev, allan.mdev, allan.hdev, allan.totdev, allan.theo1, allan.mtotdev]
)
def test_every_statistic_carries_the_rate_variance(fn: object) -> None:
    x = _rate(4_000)
    r = fn(x, FS)  # type: ignore[operator]
    assert r.data_variance == pytest.approx(float(np.var(x)), rel=RTOL)


def test_tdev_carries_the_rate_variance_not_the_time_variance() -> None:
    x = _rate(4_000)
    r = allan.tdev(x, FS, units="deg/s")
    assert r.unit == "deg"
    assert r.data_variance == pytest.approx(float(np.var(x)), rel=RTOL)
    assert r.to_dict()["data_variance_unit"] == "(deg/s)²"


@pytest.mark.parametrize("fn", [allan.adev, allan.theo1])
def test_angle_input_carries_the_rate_differences_variance(fn: object) -> None:
    angle = np.cumsum(_rate(5_000)) / FS + 7.0
    r = fn(angle, FS, data_type="angle", units="deg")  # type: ignore[operator]
    assert r.data_variance == pytest.approx(float(np.var(np.diff(angle) * FS)), rel=1e-10)
    assert r.unit == "deg/s"


def test_non_overlapping_and_multichannel_per_channel() -> None:
    rng = np.random.default_rng(3)
    x = rng.normal(0.0, [0.1, 1.0, 5.0], (10_001, 3))
    for r, col in zip(allan.adev(x, FS, overlapping=False), x.T):
        assert r.data_variance == pytest.approx(float(np.var(col)), rel=RTOL)


def test_batch_per_unit_and_axis() -> None:
    rng = np.random.default_rng(4)
    data = rng.normal(0.0, 1.0, (3, 5_000, 2)) * np.array([1.0, 3.0])
    out = allan.adev_batch(data, FS)
    for u in range(3):
        for a in range(2):
            assert out[u][a].data_variance == pytest.approx(float(np.var(data[u, :, a])), rel=RTOL)


@pytest.mark.parametrize("data_type", ["rate", "angle"])
def test_gaps_leave_the_missing_samples_out(data_type: str) -> None:
    x = _rate(6_000, seed=5)
    if data_type == "angle":
        x = np.cumsum(x) / FS
    x[[100, 101, 2500, 4000]] = np.nan
    r = allan.adev(x, FS, gaps="omit", data_type=data_type)
    ref = np.nanvar(x) if data_type == "rate" else np.nanvar(np.diff(x) * FS)
    assert r.data_variance == pytest.approx(float(ref), rel=1e-10)


@pytest.mark.parametrize("data_type", ["rate", "angle"])
def test_out_of_core_stream(tmp_path: Path, data_type: str) -> None:
    data = np.stack([_rate(70_001, seed=6), 2.0 * _rate(70_001, seed=7)], axis=1)
    if data_type == "angle":
        data = np.cumsum(data, axis=0) / FS
    path = tmp_path / "log.npy"
    np.save(path, data)
    streamed = allan.adev(np.load(path, mmap_mode="r"), FS, data_type=data_type)
    for r, col in zip(streamed, data.T):
        ref = np.var(col) if data_type == "rate" else np.var(np.diff(col) * FS)
        assert r.data_variance == pytest.approx(float(ref), rel=1e-10)


def test_accelerometer_offset_does_not_cancel() -> None:
    """9.81 ± 1e-4: Σv² − n·v̄² would lose every digit; the kernel's centred sums do not.
    The reference is NumPy's two-pass variance of the data with the offset removed exactly
    (9.81 is not a power of two, but subtracting it is exact to within the data's own ulps,
    1.8e-15, i.e. 2e-11 relative to the noise: hence rtol 1e-9)."""
    rng = np.random.default_rng(8)
    noise_part = rng.normal(0.0, 1e-4, 200_000)
    x = 9.81 + noise_part
    r = allan.adev(x, FS)
    assert r.data_variance == pytest.approx(float(np.var(x - 9.81)), rel=1e-9)


@pytest.mark.parametrize("scale", [2.0**-1000, 1e-300, 1e150, 2.0**900])
def test_extreme_magnitudes_scale_exactly(scale: float) -> None:
    x = _rate(3_000, seed=9)
    base = allan.adev(x, FS).data_variance
    assert base is not None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        got = allan.adev(x * scale, FS).data_variance
    want = base * scale * scale
    # The deviation is exact at every scale (computed before the scale is restored).
    dev = allan.adev(x * scale, FS).data_deviation
    assert dev == pytest.approx(math.sqrt(base) * scale, rel=1e-12)
    if math.isfinite(want) and want > 1e-300:
        assert got == pytest.approx(want, rel=1e-12)
    else:  # beyond float64, like avar of such data
        assert got == (math.inf if scale > 1 else 0.0) or got == pytest.approx(want, rel=1e-6)


def test_copies_keep_it_and_json_carries_it() -> None:
    r = allan.adev(_rate(3_000), FS, units="deg/s")
    assert r.in_log_time(12.0).data_variance == r.data_variance
    assert dataclasses.replace(r, axis="x").data_variance == r.data_variance
    d = json.loads(r.to_json())
    assert d["data_variance"] == r.data_variance and d["data_variance_unit"] == "(deg/s)²"
    stored = allan.AllanResult(
        taus=r.taus,
        avar=r.avar,
        n_terms=r.n_terms,
        fs=FS,
        data_type="rate",
        kind="adev",
        overlapping=True,
    )
    assert stored.data_variance is None  # built from stored deviations: not known
    assert json.loads(stored.to_json())["data_variance"] is None


# ----------------------------------------------------------------------- the fit respects it


def _filtered_log(seed: int, taps: int, sigma: float, amp: float, n: int = 100_000) -> np.ndarray:
    """White noise through a `taps`-sample moving average (a sensor's decimation filter) plus a
    weak 23 Hz line, at 100 Hz."""
    rng = np.random.default_rng(seed)
    w = rng.standard_normal(n + taps) * sigma
    t = np.arange(n) / FS
    return np.convolve(w, np.ones(taps) / taps, mode="valid")[:n] + amp * np.sin(
        2.0 * np.pi * 23.0 * t
    )


def test_issue_example_line_within_the_data_variance() -> None:
    """The issue's case: a line the Allan curve cannot separate from a sensor filter's
    signature (the fit's negative 1/τ² filter term and a large sinusoid cancel at short τ).
    On main 8484de3 ``noise.fit(r, lines=[(23.0, 0.5)])`` returned 0.1151 deg/s on this log,
    std 0.0573 (so at most √2·0.0573 = 0.0811), with a passing goodness-of-fit test; now
    0.08107, limited by the data's variance."""
    x = _filtered_log(5, 6, 0.14, 0.01)
    r = allan.adev(x, FS, units="deg/s")
    limit = math.sqrt(2.0 * float(np.var(x)))
    f = noise.fit(r, lines=[(23.0, 0.5)])
    amp = f.sinusoids[0].amplitude.value
    # The exact bound is Ω₀²·λ_min ≤ var (λ_min: the smallest variance over the phase of the
    # sampled unit sine at the fitted frequency, 1/2 − O(1/n)): √(2·var) to 1e-4 here.
    tt = np.arange(x.size) / FS
    freq = f.sinusoids[0].frequency.value
    pair = np.stack([np.cos(2 * np.pi * freq * tt), np.sin(2 * np.pi * freq * tt)])
    lam = np.linalg.eigvalsh(np.cov(pair, bias=True))[0]
    assert amp is not None and amp**2 * lam <= np.var(x) * (1 + 1e-9), (amp, lam)
    assert amp <= limit * (1 + 1e-4), (amp, limit)
    d = f.diagnostics
    assert d.variance_limited and d.data_variance == pytest.approx(float(np.var(x)), rel=1e-12)
    assert any("limited by the data's variance" in w for w in d.warnings)
    assert "S at 23" in " ".join(d.warnings)
    assert f.to_dict()["diagnostics"]["variance_limited"] is True


def test_realistic_fit_is_unchanged_when_the_limit_is_inactive() -> None:
    """A white + random-walk log: the limit is inactive and the fit is the unconstrained one
    bit for bit (the same code path: the result without the data's variance)."""
    x = noise.simulate(50_000, FS, arw=0.01, bias_instability=0.002, rrw=1e-4, seed=2)
    r = allan.adev(x, FS)
    f = noise.fit(r)
    g = noise.fit(dataclasses.replace(r, data_variance=None))
    assert not f.diagnostics.variance_limited
    assert f.diagnostics.variance_claimed is not None and g.diagnostics.data_variance is None
    for s in ("Q", "N", "B", "K", "R"):
        assert f[s].value == g[s].value, s


def _implied(fit: noise.NoiseCoefficients, n: int, filtered: bool) -> dict[str, float]:
    """Each fitted term's implied sample variance times its slack quantile q, recomputed here
    from the formulas of ``variance_limit`` (independently: SciPy's χ² quantile, direct sums)."""
    t0 = 1.0 / FS
    tau_lo = fit.diagnostics.tau_range[0]
    u = t0 / tau_lo
    q_white = stats.chi2.ppf(1e-3, (n - 1) * u) / ((n - 1) * u)
    out: dict[str, float] = {}
    val = {s: fit[s].value for s in ("N", "K", "R")}
    if val["N"] and not filtered:
        out["N"] = val["N"] ** 2 / tau_lo * q_white
    if val["K"]:
        out["K"] = 0.10 * val["K"] ** 2 * (t0 * (n * n - 1) / (6 * n) - tau_lo / math.pi**2)
    if val["R"]:
        out["R"] = val["R"] ** 2 * t0 * t0 * (n * n - 1) / 12.0
    for k, s in enumerate(fit.sinusoids):
        if s.amplitude.value:
            tt = np.arange(n) * t0
            # the smallest variance over the phase of n samples of a unit sine
            c = np.cos(2 * np.pi * s.frequency.value * tt)
            sn = np.sin(2 * np.pi * s.frequency.value * tt)
            lam = np.linalg.eigvalsh(np.cov(np.stack([c, sn]), bias=True))[0]
            out[f"S{k}"] = s.amplitude.value**2 * lam
    return out


@settings(max_examples=25, deadline=None, derandomize=True)
@given(
    arw=st.sampled_from([0.0, 0.002, 0.01]),
    rrw=st.sampled_from([0.0, 1e-4, 1e-3]),
    ramp=st.sampled_from([0.0, 1e-5, 1e-4]),
    line=st.sampled_from([0.0, 0.005, 0.03]),
    taps=st.sampled_from([1, 4]),
    seed=st.integers(0, 50),
)
def test_every_fitted_term_within_the_data_variance(
    arw: float, rrw: float, ramp: float, line: float, taps: int, seed: int
) -> None:
    n = 20_000
    x = noise.simulate(n, FS, arw=arw + 0.001, rrw=rrw, rate_ramp=ramp, seed=seed)
    if taps > 1:
        x = np.convolve(x, np.ones(taps) / taps, mode="same")
    x = x + line * np.sin(2 * np.pi * 17.0 * np.arange(n) / FS + 0.4)
    r = allan.adev(x, FS)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        f = noise.fit(r, lines=[(17.0, 0.5)])
    v = float(np.var(x))
    filtered = f.diagnostics.filter_correlation_time is not None or any(
        "filter" in e[2] for e in f.diagnostics.excluded
    )
    implied = _implied(f, n, filtered)
    # Each term alone, and their sum, within the data's variance (1e-6: rounding of the
    # constrained solve; the union-bound slack is in the q factors).
    for name, value in implied.items():
        assert value <= v * (1 + 1e-6), (name, value, v)
    assert sum(implied.values()) <= v * (1 + 1e-6), (implied, v)
    claimed = f.diagnostics.variance_claimed
    assert claimed is not None and claimed <= v * (1 + 1e-6)


def test_slack_coverage_on_white_noise() -> None:
    """The slack's purpose: on pure white noise (no term exceeds the data's variance) the
    limit must almost never bind. Each term's quantile is at the 0.1 % level, so with the
    default five terms at most ~0.5 % of logs; 300 logs (fixed seeds): at most 4 (Poisson mean
    1.5 at 0.5 %: P(> 4) ≈ 2 %; measured 0)."""
    bound = 0
    for seed in range(300):
        x = np.random.default_rng(1000 + seed).normal(0.0, 1.0, 4_000)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            f = noise.fit(allan.adev(x, FS))
        bound += f.diagnostics.variance_limited
    assert bound <= 4, bound


def test_random_walk_quantile_is_the_0_1_percent_level() -> None:
    """RANDOM_WALK_QUANTILE = 0.10: the fraction of random walks whose sample variance falls
    below 0.10 × its expectation t0(n²−1)/(6n) is ≈ 0.1 % (Karhunen–Loève: 0.1005 is the exact
    0.1 % quantile). 20 000 walks of 1 000 steps: expected 20 below, s.d. 4.5; ≤ 40 allowed."""
    rng = np.random.default_rng(11)
    n = 1_000
    below = 0
    for _ in range(4):
        w = np.cumsum(rng.standard_normal((5_000, n)), axis=1)
        below += int(np.sum(w.var(axis=1) < 0.10 * (n * n - 1) / (6 * n)))
    assert 5 <= below <= 40, below


def test_gmwm_respects_it_too() -> None:
    x = _filtered_log(5, 6, 0.14, 0.01, n=40_000)
    limit = math.sqrt(2.0 * float(np.var(x)))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            c = noise.gmwm(x, FS, lines=[(23.0, 0.5)], seed=0)
    except ValueError as exc:  # refused with the reason
        assert "more than the data allow" in str(exc)
        return
    for s in c.sinusoids:
        if s.amplitude.value is not None:
            assert s.amplitude.value <= limit * (1 + 1e-6)
    d = c.diagnostics
    assert d.variance_claimed is not None and d.data_variance is not None
    assert d.variance_claimed <= d.data_variance * (1 + 1e-6)

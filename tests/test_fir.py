"""Tests of gyrobias.fir: Kaiser design ([TS] eqs. 14–20, SPEC §7) and filtering vs SciPy."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.signal as ss
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_allclose

from gyrobias import fir
from tests.reference_fir import kaiser_design

PAPER = {"fs": 100.0, "fpass": 14.0, "fstop": 18.0, "apass_db": 0.0001, "astop_db": 100.0}


def paper_filter() -> fir.KaiserLowpass:
    return fir.kaiser_lowpass(100.0, 14.0, 18.0, apass_db=0.0001, astop_db=100.0)


def test_spec_check_values() -> None:
    f = paper_filter()
    # SPEC §7 gives 6 decimals.
    assert f.attenuation_db == pytest.approx(104.796886, abs=5e-7)
    assert f.alpha == pytest.approx(10.589877, abs=5e-7)
    assert f.numtaps == 171
    assert f.delay == 85
    assert f.cutoff == 16.0
    # The pass-band ripple is the binding one: A = -20 log10(δpass) > Astop.
    assert f.delta_pass < f.delta_stop == pytest.approx(1e-5)


def test_taps_equal_scipy_firwin() -> None:
    f = paper_filter()
    ref = ss.firwin(171, 16.0, window=("kaiser", f.alpha), fs=100.0, scale=False)
    # Same arithmetic as firwin except the Bessel I0 (power series vs Cephes Chebyshev):
    # the largest tap is 0.32, whose ulp is 5.6e-17; allow 2 ulp.
    assert_allclose(f.taps, ref, rtol=0, atol=1.2e-16)
    # SciPy's kaiserord gives the even length 170 (SPEC §7): we force odd N.
    n_scipy, _ = ss.kaiserord(f.attenuation_db, 4.0 / 50.0)
    assert n_scipy == 170


@given(
    fs=st.floats(10.0, 1000.0),
    lo=st.floats(0.02, 0.35),
    width=st.floats(0.02, 0.12),
    apass=st.floats(1e-4, 1.0),
    astop=st.floats(10.0, 120.0),
)
def test_design_matches_formula_reference(
    fs: float, lo: float, width: float, apass: float, astop: float
) -> None:
    fpass, fstop = lo * fs, min(lo + width, 0.5) * fs
    f = fir.kaiser_lowpass(fs, fpass, fstop, apass_db=apass, astop_db=astop)
    ref = kaiser_design(fs, fpass, fstop, apass, astop)
    assert f.numtaps == ref["N"]
    assert f.alpha == pytest.approx(ref["alpha"], rel=1e-13, abs=1e-15)
    # Taps ≤ 0.5 in magnitude; the two evaluations of sin and I0 differ by a few ulp.
    assert_allclose(f.taps, ref["taps"], rtol=0, atol=1e-14)


def test_frequency_response_meets_specification() -> None:
    f = paper_filter()
    r = f.frequency_response(n=4001)
    mag = r.magnitude
    freqs = r.frequencies
    # Kaiser designs meet the ripple δ = min(δpass, δstop) up to the window formula's slack
    # (Kaiser's empirical α, D formulas): allow 2δ.
    delta = min(f.delta_pass, f.delta_stop)
    assert np.all(np.abs(mag[freqs <= f.fpass] - 1) < 2 * delta)
    assert np.all(mag[freqs >= f.fstop] < 2 * delta)
    # −6 dB at fc for the causal filter, −12 dB for zero phase.
    at_fc = f.frequency_response([f.cutoff])
    assert at_fc.magnitude_db[0] == pytest.approx(-6.02, abs=0.01)
    assert f.frequency_response([f.cutoff], zero_phase=True).magnitude_db[0] == pytest.approx(
        -12.04, abs=0.02
    )
    # Equals scipy.signal.freqz; linear phase −2π f M / fs in the pass band.
    _, h = ss.freqz(f.taps, worN=freqs, fs=100.0)
    assert_allclose(r.response, h, atol=1e-13)
    pb = freqs < f.fpass
    assert_allclose(r.phase[pb], -2 * np.pi * freqs[pb] * f.delay / 100.0, atol=1e-9)


@pytest.mark.parametrize("padtype", ["odd", "even", "constant"])
@pytest.mark.parametrize("padlen", [None, 0, 17, 999])
def test_zero_phase_equals_filtfilt(padtype: str, padlen: int | None) -> None:
    f = paper_filter()
    rng = np.random.default_rng(3)
    x = np.cumsum(rng.normal(size=3000)) * 0.1 + rng.normal(size=3000)
    y = f.apply(x, padtype=padtype, padlen=padlen)
    ref = ss.filtfilt(f.taps, [1.0], x, padtype=padtype, padlen=padlen)
    # Same padding and initial conditions; only the summation order differs (~1e-15 rel).
    assert_allclose(y, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())


def test_padtype_none_equals_filtfilt_none() -> None:
    f = paper_filter()
    x = np.sin(np.linspace(0, 30, 2000)) + np.linspace(0, 1, 2000)
    assert_allclose(
        f.apply(x, padtype="none"), ss.filtfilt(f.taps, [1.0], x, padtype=None), rtol=0, atol=1e-12
    )


def test_causal_equals_lfilter_and_delay() -> None:
    f = paper_filter()
    rng = np.random.default_rng(4)
    x = rng.normal(size=5000)
    y = f.apply(x, zero_phase=False)
    assert_allclose(y, ss.lfilter(f.taps, [1.0], x), rtol=0, atol=1e-13)
    # A slow sinusoid in the pass band comes out delayed by M samples, unattenuated.
    n = np.arange(4000)
    s = np.sin(2 * np.pi * 1.0 * n / 100.0)
    out = f.apply(s, zero_phase=False)
    assert_allclose(out[f.numtaps :], s[f.numtaps - f.delay : -f.delay], atol=2e-5)


def test_axis_and_nd_input() -> None:
    f = paper_filter()
    rng = np.random.default_rng(5)
    x = rng.normal(size=(600, 3))
    y0 = f.apply(x, axis=0)
    for k in range(3):
        assert_allclose(y0[:, k], ss.filtfilt(f.taps, [1.0], x[:, k]), rtol=1e-12, atol=1e-13)
    x3 = rng.normal(size=(2, 600, 2))
    y3 = fir.apply(f.taps, x3, axis=1, zero_phase=False)
    assert_allclose(y3, ss.lfilter(f.taps, [1.0], x3, axis=1), atol=1e-13)
    # Non-contiguous and integer input are accepted; the caller's array is not modified.
    xi = (rng.normal(size=1200) * 100).astype(np.int64)
    keep = xi.copy()
    assert_allclose(
        f.apply(xi[::2]), ss.filtfilt(f.taps, [1.0], xi[::2].astype(float)), rtol=1e-12, atol=1e-10
    )
    assert np.array_equal(xi, keep)


def test_constant_is_preserved_exactly_enough() -> None:
    f = paper_filter()
    y = f.apply(np.full(1000, 2.5))
    # DC gain Σh = 1 within the pass-band ripple (δpass ≈ 5.8e-6), squared for zero phase.
    assert_allclose(y, 2.5, rtol=2.5e-5)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"fpass": 18.0, "fstop": 14.0}, "fpass"),
        ({"fpass": 14.0, "fstop": 14.0}, "fpass"),
        ({"fstop": 60.0}, "fstop"),
        ({"fs": 0.0}, "fs"),
        ({"fpass": -1.0}, "fpass"),
        ({"apass_db": 0.0}, "apass_db"),
        ({"astop_db": -3.0}, "astop_db"),
        ({"astop_db": float("nan")}, "astop_db"),
    ],
)
def test_bad_design(kwargs: dict[str, float], name: str) -> None:
    args = {**PAPER, **kwargs}
    with pytest.raises(ValueError, match=name):
        fir.kaiser_lowpass(
            args["fs"],
            args["fpass"],
            args["fstop"],
            apass_db=args["apass_db"],
            astop_db=args["astop_db"],
        )


def test_too_narrow_transition() -> None:
    with pytest.raises(ValueError, match="too narrow"):
        fir.kaiser_lowpass(100.0, 14.0, 14.0 + 1e-6)


def test_bad_apply_input() -> None:
    f = paper_filter()
    x = np.ones(600)
    with pytest.raises(ValueError, match="x"):
        f.apply(np.ones(100))  # shorter than filtfilt's default padlen 3N = 513
    bad = x.copy()
    bad[7] = np.nan
    with pytest.raises(ValueError, match="x .*index 7"):
        f.apply(bad)
    with pytest.raises(ValueError, match="padtype"):
        f.apply(x, padtype="wrap")
    with pytest.raises(ValueError, match="axis"):
        f.apply(x, axis=1)
    with pytest.raises(ValueError, match="padlen"):
        f.apply(x, padtype="none", padlen=4)
    with pytest.raises(TypeError, match="x"):
        f.apply(["a", "b"])
    with pytest.raises(ValueError, match="x"):
        f.apply([])
    with pytest.raises(ValueError, match="taps"):
        fir.apply([np.inf, 1.0], x)


def test_to_dict() -> None:
    d = paper_filter().to_dict()
    assert d["numtaps"] == 171 and len(d["taps"]) == 171


def test_stream_chunks_bit_identical_and_equal_lfilter() -> None:
    f = paper_filter()
    rng = np.random.default_rng(6)
    x = rng.normal(size=(3, 4000))
    whole, s_whole = fir.stream(f.taps, x)
    parts, state = [], None
    for a, b in [(0, 1), (1, 170), (170, 2500), (2500, 4000)]:
        y, state = fir.stream(f.taps, x[:, a:b], state)
        parts.append(y)
    assert np.array_equal(np.concatenate(parts, axis=1), whole)  # bit for bit
    assert state is not None and np.array_equal(state, s_whole)
    assert state.shape == (3, 170)
    assert_allclose(whole, ss.lfilter(f.taps, [1.0], x, axis=1), atol=1e-13)
    # Time along axis 0 (samples × axes, the usual log layout).
    y0, st0 = fir.stream(f.taps, x.T, axis=0)
    assert np.array_equal(y0, whole.T) and st0.shape == (3, 170)
    with pytest.raises(ValueError, match="state"):
        fir.stream(f.taps, x, np.zeros((3, 5)))
    with pytest.raises(ValueError, match="state"):
        fir.stream(f.taps, x[0], np.full(170, np.nan))
    one, st1 = fir.stream([2.0], [1.0, 2.0])  # a 1-tap filter has an empty state
    assert one.tolist() == [2.0, 4.0] and st1.shape == (0,)

"""Generated C (gyrobias.codegen): compiled with the system compiler, run, compared with Python.

- float64 C equals the float64 Python/Rust path and float32 C the ``dtype=np.float32`` path
  *bit for bit* on every vector (white noise, step, ramp, a long random walk); the NaN/overflow
  case behaves as the generated header documents. The compiled predictor's C equals
  ``predict(..., dtype=)`` (the C's summation order) bit for bit.
- clang ``-Weverything`` (minus a named list) builds the same files warning-free and gives
  gcc's bits; its default FMA contraction is held off by the source's pragma.
- Cortex-M (cross-compiled, on QEMU): ``tests/test_codegen_target.py``.
- Q31 C stays within the analytic bound of ``gyrocore::codegen`` against float64, and its RMS
  error on white noise matches the predicted quantisation noise to a factor of 3 (the remaining
  part is the deterministic coefficient rounding, ≤ 2⁻³⁰ relative).
- Same design → same bytes; bad designs, names and paths → ValueError before any file.
"""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import gyrobias
from gyrobias import codegen, fir
from gyrobias.kalman import FixedGainKalman, q_omega_from_deg_per_hour
from gyrobias.predict import FractionalKalmanPredictor
from tests._c_harness import CC, CLANG, build, numpy_type, run

pytestmark = pytest.mark.skipif(CC is None, reason="no system C compiler (cc)")
#: CI sets it (.ci/run): there clang and the Cortex-M tools must be present, not skipped.
REQUIRE = os.environ.get("GYROBIAS_REQUIRE_CORTEX_M") == "1"

KALMANS = {
    "mems1k": dict(fs=1000.0, arw=0.005, rrw=1e-4, bandwidth=20.0),
    "nr200": dict(fs=200.0, arw=0.08, rrw=7e-4, bandwidth=10.0),
    "unitdc": dict(fs=400.0, arw=0.01, rrw=0.0, bandwidth=30.0),
    "paper": dict(
        fs=200.0,
        arw=0.1667 / 60,
        rrw=1200.0 / 216000.0,
        q_omega=q_omega_from_deg_per_hour(1000.0),
        form="paper",
    ),
}
FIRS = {
    "ts100": (100.0, 14.0, 18.0, 0.0001, 100.0),
    "mems1k": (1000.0, 20.0, 60.0, 0.01, 60.0),
    "short": (1000.0, 100.0, 400.0, 0.5, 30.0),  # N < 8: only the remainder loop
}


def _vectors(n: int = 4000, seed: int = 1) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    return {
        "white": 0.3 + rng.normal(0.0, 1.0, n),
        "step": np.where(t < n // 3, -0.2, 0.7) + 0.01 * rng.normal(size=n),
        "ramp": 1e-3 * t - 1.5,
        "walk": np.cumsum(rng.normal(0.0, 0.01, 200_000)),
    }


def _kf(key: str) -> FixedGainKalman:
    d = dict(KALMANS[key])
    fs = d.pop("fs")
    return FixedGainKalman(fs, **d)


def _same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    a, b = np.ascontiguousarray(a), np.ascontiguousarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def _kalman_c(exe: Path, z: np.ndarray, t: type, tmp: Path) -> tuple[np.ndarray, ...]:
    raw = run(exe, z.astype(t), tmp)
    n, size = z.size, np.dtype(t).itemsize
    rate = np.frombuffer(raw[: n * size], dtype=t)
    bias = np.frombuffer(raw[n * size : 2 * n * size], dtype=t)
    status = np.frombuffer(raw[2 * n * size :], dtype=np.intc)
    return rate, bias, status


# --- bit for bit ------------------------------------------------------------------------------


@pytest.mark.parametrize("dtype", ["float64", "float32"])
@pytest.mark.parametrize("key", sorted(KALMANS))
def test_kalman_float_c_equals_python_bit_for_bit(key: str, dtype: str, tmp_path: Path) -> None:
    kf = _kf(key)
    gen = kf.to_c(tmp_path, name=f"kf_{key}", dtype=dtype)
    exe = build(gen, "kalman", tmp_path)
    t = numpy_type(dtype)
    for label, z in _vectors().items():
        rate, bias, status = _kalman_c(exe, z, t, tmp_path)
        ref = kf.filter(z.astype(t), dtype=t)
        assert not status.any(), label
        assert ref.rate.dtype == t
        assert _same_bits(rate, ref.rate), (key, dtype, label)
        assert _same_bits(bias, ref.bias), (key, dtype, label)


@pytest.mark.parametrize("dtype", ["float64", "float32"])
@pytest.mark.parametrize("key", sorted(FIRS))
def test_fir_float_c_equals_python_bit_for_bit(key: str, dtype: str, tmp_path: Path) -> None:
    f = fir.kaiser_lowpass(*FIRS[key][:3], apass_db=FIRS[key][3], astop_db=FIRS[key][4])
    gen = f.to_c(tmp_path, name=f"fir_{key}", dtype=dtype)
    exe = build(gen, "fir", tmp_path)
    t = numpy_type(dtype)
    for label, x in _vectors().items():
        y = np.frombuffer(run(exe, x.astype(t), tmp_path), dtype=t)
        ref, _ = fir.stream(f.taps, x.astype(t), dtype=t)
        assert ref.dtype == t
        assert _same_bits(y, ref), (key, dtype, label)


def test_float32_paths_are_float32_arithmetic() -> None:
    """The float32 paths are not float64 rounded at the end: they differ from it, by float32
    rounding only (relative ~1e-6 of the signal, here against the float64 results)."""
    z = _vectors()["white"]
    kf = _kf("mems1k")
    r32 = kf.filter(z, dtype=np.float32).rate
    r64 = kf.filter(z).rate
    assert not np.array_equal(r32, r64.astype(np.float32))
    np.testing.assert_allclose(r32, r64, atol=1e-4 * np.abs(z).max())
    f = fir.kaiser_lowpass(100.0, 14.0, 18.0)
    y32, _ = fir.stream(f.taps, z, dtype=np.float32)
    y64, _ = fir.stream(f.taps, z)
    assert not np.array_equal(y32, y64.astype(np.float32))
    np.testing.assert_allclose(y32, y64, atol=1e-5 * np.abs(z).max())


@settings(max_examples=15, deadline=None)
@given(
    cut=st.integers(1, 500),
    seed=st.integers(0, 2**32 - 1),
)
def test_float32_streaming_in_chunks_equals_one_shot(cut: int, seed: int) -> None:
    """Property: float32 filtering in two chunks (state carried) equals one call, bit for bit,
    for the Kalman filter and the FIR (what the C's per-sample state does)."""
    z = np.random.default_rng(seed).normal(size=600).astype(np.float32)
    kf = _kf("nr200")
    whole = kf.filter(z, dtype=np.float32)
    a = kf.filter(z[:cut], dtype=np.float32)
    b = kf.filter(z[cut:], dtype=np.float32, state=a.state)
    assert _same_bits(np.r_[a.rate, b.rate], whole.rate)
    taps = fir.kaiser_lowpass(100.0, 10.0, 30.0, astop_db=50.0).taps
    y, _ = fir.stream(taps, z, dtype=np.float32)
    y1, s1 = fir.stream(taps, z[:cut], dtype=np.float32)
    y2, _ = fir.stream(taps, z[cut:], s1, dtype=np.float32)
    assert _same_bits(np.r_[y1, y2], y)


# --- documented NaN / overflow behaviour ------------------------------------------------------


@pytest.mark.parametrize("dtype", ["float64", "float32"])
def test_kalman_c_skips_non_finite_and_overflowing_samples(dtype: str, tmp_path: Path) -> None:
    t = numpy_type(dtype)
    huge = float(np.finfo(t).max)
    kf = _kf("mems1k")
    gen = kf.to_c(tmp_path, name="kf_nan", dtype=dtype)
    exe = build(gen, "kalman", tmp_path)
    z = _vectors()["white"][:1000].copy()
    z[100], z[200], z[300] = np.nan, np.inf, -np.inf
    z[400] = z[401] = huge  # the second one overflows the level
    rate, bias, status = _kalman_c(exe, z, t, tmp_path)
    skipped = np.flatnonzero(status)
    assert skipped.tolist() == [100, 200, 300, 401]
    assert status[[100, 200, 300, 401]].tolist() == [1, 1, 1, 2]
    keep = np.setdiff1d(np.arange(z.size), skipped)
    ref = kf.filter(z[keep].astype(t), dtype=t)
    # A skipped sample holds the previous estimates.
    expect_rate = np.empty(z.size, dtype=t)
    expect_rate[keep] = ref.rate
    for i in skipped:
        expect_rate[i] = expect_rate[i - 1]
    assert _same_bits(rate, expect_rate)
    # Python refuses the non-finite input instead (and names the sample).
    with pytest.raises(ValueError, match="sample 100"):
        kf.filter(z.astype(t), dtype=t)


@pytest.mark.parametrize("dtype", ["float64", "float32"])
def test_fir_c_nan_poisons_exactly_one_window(dtype: str, tmp_path: Path) -> None:
    t = numpy_type(dtype)
    f = fir.kaiser_lowpass(1000.0, 20.0, 60.0, astop_db=60.0)
    n_taps = f.numtaps
    gen = f.to_c(tmp_path, name="fir_nan", dtype=dtype)
    exe = build(gen, "fir", tmp_path)
    x = _vectors()["white"][:2000].copy()
    x[500] = np.nan
    y = np.frombuffer(run(exe, x.astype(t), tmp_path), dtype=t)
    bad = ~np.isfinite(y)
    assert np.flatnonzero(bad).tolist() == list(range(500, 500 + n_taps))
    x[500] = 0.0
    ref, _ = fir.stream(f.taps, x.astype(t), dtype=t)
    assert _same_bits(y[~bad], ref[~bad])


# --- Q31 --------------------------------------------------------------------------------------


def _to_q31(x: np.ndarray) -> np.ndarray:
    return np.clip(np.round(x * 2.0**31), -(2.0**31), 2.0**31 - 1).astype(np.int32)


@pytest.mark.parametrize("key", sorted(KALMANS))
def test_kalman_q31_within_bound(key: str, tmp_path: Path) -> None:
    kf = _kf(key)
    gen = kf.to_c(tmp_path, name=f"q_{key}", dtype="q31", full_scale=8.0)
    exe = build(gen, "kalman", tmp_path)
    bound_rate, bound_bias = gen.q31["error_bound"]
    assert 0 < bound_rate < 1e-8 and 0 < bound_bias < 1e-8  # a few LSB (2**-31 = 4.7e-10)
    fs_units = 8.0
    for label, z in _vectors().items():
        zq = _to_q31(z / fs_units / (np.abs(z).max() / fs_units) * 0.9)  # within ±0.9 FS
        rate, bias, _ = _kalman_c(exe, zq, np.int32, tmp_path)
        ref = kf.filter(zq / 2.0**31)
        err_r = np.abs(rate / 2.0**31 - ref.rate).max()
        err_b = np.abs(bias / 2.0**31 - ref.bias).max()
        assert err_r <= bound_rate, (key, label, err_r, bound_rate)
        assert err_b <= bound_bias, (key, label, err_b, bound_bias)
    # The noise model: white input of 0.1 FS, RMS error near the predicted rounding noise.
    zq = _to_q31(0.1 * np.random.default_rng(5).normal(size=100_000).clip(-9, 9))
    rate, _, _ = _kalman_c(exe, zq, np.int32, tmp_path)
    ref = kf.filter(zq / 2.0**31).rate
    rms = float(np.sqrt(np.mean((rate / 2.0**31 - ref) ** 2)))
    predicted = gen.q31["noise_rms"][0]
    assert predicted / 3 < rms < 3 * predicted, (rms, predicted)


def test_kalman_q31_saturates_at_full_scale(tmp_path: Path) -> None:
    kf = _kf("unitdc")
    gen = kf.to_c(tmp_path, name="q_sat", dtype="q31")
    exe = build(gen, "kalman", tmp_path)
    n = 3000
    zq = np.where((np.arange(n) // 300) % 2 == 0, -(2**31), 2**31 - 1).astype(np.int32)
    rate, bias, _ = _kalman_c(exe, zq, np.int32, tmp_path)
    ref = kf.filter(zq / 2.0**31)
    # Saturating, never wrapping: the Q31 output is the clipped float64 output within the bound.
    top = 1.0 - 2.0**-31
    err = np.abs(rate / 2.0**31 - np.clip(ref.rate, -1.0, top)).max()
    assert err <= gen.q31["error_bound"][0]
    assert np.abs(bias / 2.0**31 - np.clip(ref.bias, -1.0, top)).max() <= gen.q31["error_bound"][1]


@pytest.mark.parametrize("key", sorted(FIRS))
def test_fir_q31_within_bound(key: str, tmp_path: Path) -> None:
    f = fir.kaiser_lowpass(*FIRS[key][:3], apass_db=FIRS[key][3], astop_db=FIRS[key][4])
    gen = f.to_c(tmp_path, name=f"qf_{key}", dtype="q31")
    exe = build(gen, "fir", tmp_path)
    bound = gen.q31["error_bound"]
    # Σ|ΔH|·FS + ½ LSB: under 100 LSB even for 171 taps whose Σ|h| > 1 forces the shift down to
    # 31 (the int64 accumulator must not overflow).
    assert bound < 100 * 2.0**-31
    top = 1.0 - 2.0**-31
    vectors = _vectors()
    vectors["square"] = np.where((np.arange(3000) // 200) % 2 == 0, -1.0, 1.0)  # saturates
    for label, x in vectors.items():
        scale = 1.0 if label == "square" else 0.9 / np.abs(x).max()
        xq = _to_q31(x * scale)
        y = np.frombuffer(run(exe, xq, tmp_path), dtype=np.int32)
        ref, _ = fir.stream(f.taps, xq / 2.0**31)
        err = np.abs(y / 2.0**31 - np.clip(ref, -1.0, top)).max()
        assert err <= bound, (key, label, err, bound)


# --- compiled predictor -----------------------------------------------------------------------


PREDICTORS = {
    "sample": dict(d=0.5, q=1e-4, r=1e-4),
    "proper": dict(d=0.3, q=1e-4, r=4e-4, mean=(0.2, 0.01)),  # w0 != 0
}


@pytest.mark.parametrize("key", sorted(PREDICTORS))
@pytest.mark.parametrize("dtype", ["float64", "float32", "q31"])
def test_predictor_c_matches_python(dtype: str, key: str, tmp_path: Path) -> None:
    """float64/float32 C equal ``predict(..., dtype=)`` (the C's summation order) bit for bit;
    Q31 is within its bound of the float64 forecast."""
    pred = FractionalKalmanPredictor(**PREDICTORS[key]).compile(40, 15)  # type: ignore[arg-type]
    gen = pred.to_c(tmp_path, name="pred", dtype=dtype)
    exe = build(gen, "predictor", tmp_path)
    rng = np.random.default_rng(3)
    windows = 0.2 + np.cumsum(rng.normal(0.0, 0.01, (30, 40)), axis=1)
    if dtype == "q31":
        yq = _to_q31(windows)
        out = np.frombuffer(run(exe, yq, tmp_path), dtype=np.int32).reshape(30, 15) / 2.0**31
        ref = pred.predict(yq / 2.0**31).bias
        assert np.abs(out - ref).max() <= gen.q31["error_bound"]
        return
    t = numpy_type(dtype)
    y = windows.astype(t)
    out = np.frombuffer(run(exe, y, tmp_path), dtype=t).reshape(30, 15)
    ref = pred.predict(y, dtype=t).bias
    assert ref.dtype == t
    assert _same_bits(out, ref)
    # The fast path (one GEMM, another summation order) differs by rounding only:
    # γ_k·Σ|W||y| + the w0 rounding, k = 40 terms (float32: also the rounding of W, y).
    fast = pred.predict(y.astype(np.float64)).bias
    eps = float(np.finfo(t).eps) / 2
    mag = np.abs(y).astype(np.float64) @ np.abs(pred.weights).T + np.abs(pred.offset)
    assert np.all(np.abs(out - fast) <= 2 * 43 * eps * mag)


def test_predict_sequential_is_the_left_to_right_sum() -> None:
    """Independent reference of ``predict(dtype=)``: the C's loop written in NumPy, one
    rounding per operation (NumPy float32 scalars: no fused multiply-add)."""
    pred = FractionalKalmanPredictor(**PREDICTORS["proper"]).compile(12, 5)  # type: ignore[arg-type]
    y = 0.2 + np.cumsum(np.random.default_rng(8).normal(0.0, 0.01, (4, 12)), axis=1)
    for t in (np.float64, np.float32):
        w, w0, yt = pred.weights.astype(t), pred.offset.astype(t), y.astype(t)
        want = np.empty((4, 5), dtype=t)
        for r in range(4):
            for j in range(5):
                acc = t(0.0)
                for i in range(12):
                    acc = t(acc + t(w[j, i] * yt[r, i]))
                want[r, j] = t(acc + w0[j])
        got = pred.predict(y, dtype=t)
        assert _same_bits(got.bias, want)
        assert got.std.shape == (4, 5)
    one = pred.predict(y[0], dtype=np.float32)
    assert _same_bits(one.bias, pred.predict(y, dtype=np.float32).bias[0])
    with pytest.raises(ValueError, match="dtype"):
        pred.predict(y, dtype=np.int32)
    with pytest.raises(ValueError, match="calibration_length"):
        pred.predict(y[:, :11], dtype=np.float32)
    bad = y.copy()
    bad[1, 3] = np.nan
    with pytest.raises(ValueError, match="batch"):
        pred.predict(bad, dtype=np.float64)
    bad[1, 3] = 1e300  # finite in float64, inf in float32
    with pytest.raises(ValueError, match="batch"):
        pred.predict(bad, dtype=np.float32)


@settings(max_examples=20, deadline=None)
@given(
    d=st.floats(0.05, 0.95),
    rows=st.integers(1, 5),
    seed=st.integers(0, 2**32 - 1),
    f32=st.booleans(),
)
def test_predict_sequential_rows_are_independent_and_close_to_the_gemm(
    d: float, rows: int, seed: int, f32: bool
) -> None:
    """Property: the C-order forecast of a batch is the forecasts of its rows (bit for bit:
    no blocking across windows), and within the k-term summation bound of the GEMM path."""
    pred = FractionalKalmanPredictor(d=d, q=1e-4, r=1e-4).compile(16, 6)
    y = 0.1 + np.cumsum(np.random.default_rng(seed).normal(0.0, 0.01, (rows, 16)), axis=1)
    t = np.float32 if f32 else np.float64
    yt = y.astype(t)
    whole = pred.predict(yt, dtype=t).bias
    for r in range(rows):
        assert _same_bits(pred.predict(yt[r], dtype=t).bias, whole[r])
    fast = pred.predict(yt.astype(np.float64)).bias
    eps = float(np.finfo(t).eps) / 2
    mag = np.abs(yt).astype(np.float64) @ np.abs(pred.weights).T + np.abs(pred.offset)
    # γ_{k+1} for both sums (k = 16), plus, in float32, the rounding of W and w0 (≤ eps each)
    assert np.all(np.abs(whole - fast) <= 2 * 19 * eps * mag)


# --- the second compiler -------------------------------------------------------------------------


@pytest.mark.skipif(CLANG is None and not REQUIRE, reason="no clang")
@pytest.mark.parametrize("dtype", ["float64", "float32", "q31"])
@pytest.mark.parametrize("kind", ["kalman", "fir", "predictor"])
def test_clang_weverything_gives_the_same_bits(kind: str, dtype: str, tmp_path: Path) -> None:
    """Every generated file compiles with clang -Weverything (minus the list in
    tests/_c_harness.CLANG_STRICT) -Werror, and its outputs equal gcc's byte for byte."""
    if kind == "kalman":
        gen = _kf("mems1k").to_c(tmp_path, name="cl_kf", dtype=dtype)
    elif kind == "fir":
        gen = fir.kaiser_lowpass(1000.0, 20.0, 60.0, astop_db=60.0).to_c(
            tmp_path, name="cl_fir", dtype=dtype
        )
    else:
        pred = FractionalKalmanPredictor(**PREDICTORS["proper"]).compile(40, 15)  # type: ignore[arg-type]
        gen = pred.to_c(tmp_path, name="cl_pred", dtype=dtype)
    exes = [build(gen, kind, tmp_path, compiler=c) for c in ("cc", "clang")]
    t = numpy_type(dtype)
    vectors = _vectors()
    for label, x in vectors.items():
        if kind == "predictor":
            x = 0.2 + x[:1200].reshape(30, 40) * 0.01
        data = _to_q31(0.9 * x / np.abs(x).max()) if dtype == "q31" else x.astype(t)
        gcc_out, clang_out = (run(e, data, tmp_path, tag=str(i)) for i, e in enumerate(exes))
        assert gcc_out == clang_out, (kind, dtype, label)


def _has_fma() -> bool:
    try:
        with open("/proc/cpuinfo") as fh:
            return " fma " in fh.read().replace("\n", " ")
    except OSError:
        return False


@pytest.mark.skipif(
    (CLANG is None and not REQUIRE) or not _has_fma(), reason="needs clang and an x86 FMA unit"
)
def test_clang_fp_contract_pragma_keeps_the_bits_on_an_fma_target(tmp_path: Path) -> None:
    """Clang contracts a*b + c into a fused multiply-add by default (-ffp-contract=on) when the
    target has one (-mfma). The generated source's #pragma STDC FP_CONTRACT OFF keeps the
    float32 Kalman filter bit-exact without any flag; the same source without the pragma is
    not (so the pragma, not luck, is what keeps the bits)."""
    kf = _kf("mems1k")
    gen = kf.to_c(tmp_path, name="fma_kf", dtype="float32")
    flags = ["-std=c99", "-O2", "-mfma", "-Werror"]
    z = _vectors()["walk"].astype(np.float32)
    ref = kf.filter(z, dtype=np.float32).rate
    rate, _, _ = _kalman_c(build(gen, "kalman", tmp_path, "clang", flags), z, np.float32, tmp_path)
    assert _same_bits(rate, ref)
    bare = tmp_path / "bare"
    bare.mkdir()
    (bare / "fma_kf.h").write_bytes(gen.header.read_bytes())
    text = gen.source.read_text()
    assert "#pragma STDC FP_CONTRACT OFF" in text
    (bare / "fma_kf.c").write_text(text.replace("#pragma STDC FP_CONTRACT OFF", ""))
    gen_bare = dataclasses.replace(gen, header=bare / "fma_kf.h", source=bare / "fma_kf.c")
    exe = build(gen_bare, "kalman", bare, "clang", flags)
    rate_bare, _, _ = _kalman_c(exe, z, np.float32, bare)
    assert not _same_bits(rate_bare, ref)


# --- determinism, errors, atomicity ------------------------------------------------------------


def test_same_design_same_bytes(tmp_path: Path) -> None:
    for dtype in ("float64", "float32", "q31"):
        a = _kf("nr200").to_c(tmp_path / "a", name="kf", dtype=dtype)
        b = _kf("nr200").to_c(tmp_path / "b", name="kf", dtype=dtype)
        assert a.header.read_bytes() == b.header.read_bytes()
        assert a.source.read_bytes() == b.source.read_bytes()
        f = fir.kaiser_lowpass(100.0, 14.0, 18.0)
        c = f.to_c(tmp_path / "a", name="f", dtype=dtype)
        d = fir.kaiser_lowpass(100.0, 14.0, 18.0).to_c(tmp_path / "b", name="f", dtype=dtype)
        assert c.source.read_bytes() == d.source.read_bytes()
    text = a.source.read_text()
    assert gyrobias.__version__ in text and "fs = 200.0 Hz" in text


def test_cmsis_arrays_are_time_reversed(tmp_path: Path) -> None:
    f = fir.kaiser_lowpass(1000.0, 100.0, 400.0, apass_db=0.5, astop_db=30.0)
    src = f.to_c(tmp_path, name="f", dtype="float32").source.read_text()
    block = src.split("f_cmsis_f32[")[1].split("};")[0].split("{")[1]
    vals = [float.fromhex(v.strip().rstrip("f")) for v in block.split(",") if v.strip()]
    assert vals == [float(np.float32(v)) for v in f.taps[::-1]]


@pytest.mark.parametrize(
    "name", ["int", "while", "2fast", "bad-name", "__x", "_Upper", "a" * 40, ""]
)
def test_bad_names_raise_before_writing(name: str, tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="name"):
        _kf("nr200").to_c(tmp_path, name=name)
    assert list(tmp_path.iterdir()) == []


def test_bad_paths_dtypes_and_designs_raise_before_writing(tmp_path: Path) -> None:
    kf = _kf("nr200")
    with pytest.raises(ValueError, match="dtype"):
        kf.to_c(tmp_path, dtype="int8")
    afile = tmp_path / "file.txt"
    afile.write_text("x")
    with pytest.raises(ValueError, match="path"):
        kf.to_c(afile)
    with pytest.raises(ValueError, match="path"):
        kf.to_c(tmp_path / "missing" / "deeper")
    if os.geteuid() != 0:  # root can write anywhere
        ro = tmp_path / "ro"
        ro.mkdir()
        ro.chmod(0o500)
        with pytest.raises(ValueError, match="path"):
            kf.to_c(ro)
    # Unstable gains and unrepresentable Q31 scalings are refused by the core.
    with pytest.raises(ValueError, match="unstable"):
        gyrobias._core.codegen.kalman_q31(1.5, -0.5, -0.4, -0.1, 1.0)
    with pytest.raises(ValueError, match="cannot be represented in Q31"):
        gyrobias._core.codegen.kalman_q31(1.0 - 1e-12, 1e-12, 1e-12, 0.0, 1.0)
    with pytest.raises(ValueError, match="cannot be represented in Q31"):
        gyrobias._core.codegen.dot_q31(np.array([[3.0e9]]), np.empty(0), 1.0)
    # A design too slow for Q31 (1 − p < 2⁻³¹) fails in to_c, before writing.
    slow = FixedGainKalman(1000.0, arw=1.0, rrw=0.0, q_omega=1e-17)
    with pytest.raises(ValueError, match="cannot be represented in Q31"):
        slow.to_c(tmp_path / "slow", dtype="q31")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file.txt"] + (
        ["ro"] if os.geteuid() != 0 else []
    )


def test_emitters_are_registered_by_the_package() -> None:
    assert codegen.emit_kalman is codegen.kalman_c.emit
    from gyrobias import _generics

    assert _generics.to_c.dispatch(FixedGainKalman) is codegen.kalman_c.emit
    with pytest.raises(TypeError, match="to_c: no method"):
        _generics.to_c(object(), ".")


# --- command line -------------------------------------------------------------------------------


def test_cli_emits_c(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from gyrobias.cli import main

    out = tmp_path / "fw"
    args = ["--fs", "1000", "--arw", "0.005", "--rrw", "1e-4", "--bandwidth", "20"]
    assert main(["kalman", "design", *args, "--emit-c", str(out), "--c-dtype", "q31"]) == 0
    assert "Q31 worst-case error" in capsys.readouterr().out
    api = _kf("mems1k").to_c(tmp_path / "api", name="gyro_kf", dtype="q31")
    assert (out / "gyro_kf.c").read_bytes() == api.source.read_bytes()
    fir_args = ["--fs", "1000", "--fpass", "20", "--fstop", "60", "--astop", "60"]
    assert main(["fir", "design", *fir_args, "--emit-c", str(out), "--c-name", "aa"]) == 0
    assert (out / "aa.h").exists() and (out / "aa.c").exists()
    log = tmp_path / "gyro.csv"
    np.savetxt(log, _vectors()["white"][:500, None], header="gx", comments="", delimiter=",")
    filt = ["filter", str(log), "--fs", "1000", "--arw", "0.005", "--bandwidth", "20"]
    assert main([*filt, "--emit-c", str(out), "--c-name", "from_log"]) == 0
    assert (out / "from_log.c").exists()
    # Errors: one line, exit 2, nothing written.
    capsys.readouterr()
    assert main(["kalman", "design", *args, "--emit-c", str(out), "--c-name", "while"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("gyrobias: error: name must not be a C keyword") and err.count("\n") == 1
    assert not (out / "while.c").exists()


# --- properties of the Q31 design (gyrocore::codegen) --------------------------------------------


@settings(max_examples=40, deadline=None)
@given(
    taps=st.lists(
        st.floats(-3.0, 3.0, allow_nan=False).filter(lambda v: abs(v) > 1e-6),
        min_size=1,
        max_size=300,
    )
)
def test_dot_q31_shift_is_the_largest_safe_one(taps: list[float]) -> None:
    """The common shift keeps every |H| ≤ 2³¹ − 1 and the int64 accumulator (Σ|H|·2³¹ plus the
    rounding constant) below 2⁶³, and one more bit would break one of the two; the stated
    coefficient error is Σ|H·2⁻ⁿ − h| exactly."""
    w = np.array([taps])
    d = gyrobias._core.codegen.dot_q31(w, np.empty(0), 1.0)
    n, q = d["shift"], np.array(d["values"], dtype=object)

    def safe(shift: int) -> bool:
        vals = [round(v * 2**shift) for v in taps]  # exact scaling; a tie is immaterial here
        return (
            max(abs(v) for v in vals) <= 2**31 - 1
            and sum(abs(v) for v in vals) * 2**31 + 2 ** (shift - 1) < 2**63
        )

    assert 1 <= n <= 62 and safe(n)
    assert n == 62 or not safe(n + 1)
    for v, h in zip(q, taps, strict=True):
        assert abs(v - h * 2**n) <= 0.5  # round to nearest
    err = sum(abs(int(v) / 2**n - h) for v, h in zip(q, taps, strict=True))
    assert d["coefficient_error"] == pytest.approx(err, rel=1e-12, abs=1e-300)


@settings(max_examples=6, deadline=None)
@given(
    fs=st.sampled_from([100.0, 400.0, 1000.0, 3200.0]),
    bw_frac=st.floats(0.002, 0.3),
    arw=st.floats(1e-4, 0.1),
    rrw=st.sampled_from([0.0, 1e-6, 1e-4, 1e-2]),
    seed=st.integers(0, 2**32 - 1),
)
def test_random_designs_compile_exact_and_within_bound(
    fs: float, bw_frac: float, arw: float, rrw: float, seed: int
) -> None:
    """Property over designs: float32 C equals Python float32 bit for bit, and Q31 C stays
    within its bound, for a random filter on a random walk plus white noise."""
    import tempfile

    try:
        kf = FixedGainKalman(fs, arw=arw, rrw=rrw, bandwidth=bw_frac * fs)
    except ValueError:  # an unreachable bandwidth for this noise: not a codegen case
        return
    rng = np.random.default_rng(seed)
    z = np.cumsum(rng.normal(0.0, 0.01, 3000)) + rng.normal(0.0, 0.3, 3000)
    with tempfile.TemporaryDirectory() as tmp:
        wd = Path(tmp)
        g32 = kf.to_c(wd, name="p32", dtype="float32")
        rate, _, _ = _kalman_c(build(g32, "kalman", wd), z, np.float32, wd)
        assert _same_bits(rate, kf.filter(z.astype(np.float32), dtype=np.float32).rate)
        gq = kf.to_c(wd, name="pq", dtype="q31")
        zq = _to_q31(0.9 * z / np.abs(z).max())
        rq, bq, _ = _kalman_c(build(gq, "kalman", wd), zq, np.int32, wd)
        ref = kf.filter(zq / 2.0**31)
        assert np.abs(rq / 2.0**31 - ref.rate).max() <= gq.q31["error_bound"][0]
        assert np.abs(bq / 2.0**31 - ref.bias).max() <= gq.q31["error_bound"][1]

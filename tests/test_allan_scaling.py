"""Allan-family results of data of extreme magnitude (issue 10: ×1e300 gave NaN, ×1e-300 zeros).

The core analyses data whose largest magnitude is beyond 2^±256 scaled by a power of two and
restores the scale at the end (``gyrocore::allan::scale_exponent``). Scaling by 2^k is exact
and commutes with every rounding of the estimators, so the reference here is the library itself
on the unscaled data: ``σ(x·2^k) = 2^k·σ(x)`` bit for bit, confidence bounds likewise, noise
identification unchanged. Data scaled by a decimal factor (1e300) are not exactly 2^k·x: each
product is rounded once (relative 2^-53), which moves σ by far less than the 1e-12 checked.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from gyrobias import allan

FS = 100.0
_RNG = np.random.default_rng(2026)
# White noise whose magnitudes lie in [0.25, 7.9]: x·2^k is exact for every k in [-1000, 1000].
_Z = _RNG.normal(size=4000)
BASE = np.sign(_Z) * np.minimum(0.25 + np.abs(_Z), 7.9)
WHITE = _RNG.normal(size=20_000)

KINDS: dict[str, Any] = {
    "adev": allan.adev,
    "avar non-overlapping": lambda x, fs, **kw: allan.avar(x, fs, overlapping=False, **kw),
    "mdev": allan.mdev,
    "hdev": allan.hdev,
    "hdev non-overlapping": lambda x, fs, **kw: allan.hdev(x, fs, overlapping=False, **kw),
    "totdev": allan.totdev,
    "tdev": allan.tdev,
    "mtotdev": allan.mtotdev,
    "htotdev": allan.htotdev,
    "theo1": allan.theo1,
    "theobr": allan.theobr,
    "theoh": allan.theoh,
}


def _one(result: Any) -> Any:
    return result[0] if isinstance(result, tuple) else result


def _assert_scaled(scaled: Any, plain: Any, k: int) -> None:
    """``scaled`` is ``plain`` of the data times 2^k, bit for bit."""
    f = np.ldexp(1.0, k) if abs(k) <= 1000 else None
    assert f is not None
    np.testing.assert_array_equal(scaled.taus, plain.taus)
    np.testing.assert_array_equal(scaled.n_terms, plain.n_terms)
    np.testing.assert_array_equal(scaled.adev, np.ldexp(plain.adev, k))
    with np.errstate(over="ignore", under="ignore"):
        np.testing.assert_array_equal(scaled.avar, np.ldexp(plain.avar, 2 * k))
    if plain.ci_low is not None:
        np.testing.assert_array_equal(scaled.alpha, plain.alpha)
        np.testing.assert_array_equal(scaled.edf, plain.edf)
        np.testing.assert_array_equal(scaled.ci_low, np.ldexp(plain.ci_low, k))
        np.testing.assert_array_equal(scaled.ci_high, np.ldexp(plain.ci_high, k))


@given(
    k=st.integers(-1000, 1000),
    kind=st.sampled_from(sorted(KINDS)),
    data_type=st.sampled_from(["rate", "angle"]),
)
@example(k=1000, kind="adev", data_type="rate")
@example(k=-1000, kind="adev", data_type="rate")
@example(k=-997, kind="theoh", data_type="angle")
def test_power_of_two_scaling_is_exact(k: int, kind: str, data_type: str) -> None:
    func = KINDS[kind]
    x = BASE if kind.startswith(("theo", "mtot", "htot")) else np.tile(BASE, 3)
    plain = _one(func(x, FS, data_type=data_type, confidence=0.683))
    scaled = _one(func(np.ldexp(x, k), FS, data_type=data_type, confidence=0.683))
    _assert_scaled(scaled, plain, k)


@pytest.mark.parametrize("factor", [1e300, 1e-300, 1e250, 1e-250])
@pytest.mark.parametrize("kind", ["adev", "mdev", "hdev", "totdev", "tdev", "theoh"])
def test_decimal_extremes_are_finite_and_scaled(factor: float, kind: str) -> None:
    """The issue's cases: adev(x·1e300) was NaN, adev(x·1e-300) zeros."""
    func = KINDS[kind]
    x = WHITE if kind != "theoh" else WHITE[:4000]
    plain = _one(func(x, FS))
    huge = _one(func(x * factor, FS))
    assert np.all(np.isfinite(huge.adev)) and np.all(huge.adev > 0)
    # One rounding per sample of x·factor (2^-53 relative): σ moves far less than 1e-12.
    np.testing.assert_allclose(huge.adev, plain.adev * factor, rtol=1e-12, atol=0)
    np.testing.assert_allclose(huge.ci_low, plain.ci_low * factor, rtol=1e-12, atol=0)
    np.testing.assert_allclose(huge.ci_high, plain.ci_high * factor, rtol=1e-12, atol=0)
    np.testing.assert_array_equal(huge.alpha, plain.alpha)
    np.testing.assert_array_equal(huge.noise_type, plain.noise_type)


def test_gaps_batch_and_stream_scale_too(tmp_path: Any) -> None:
    x = np.tile(BASE, 5)
    k = 900
    gapped = x.copy()
    gapped[1000:1010] = np.nan
    for kind in ("adev", "mdev", "hdev"):
        func = KINDS[kind]
        _assert_scaled(
            _one(func(np.ldexp(gapped, k), FS, gaps="omit")),
            _one(func(gapped, FS, gaps="omit")),
            k,
        )
    batch = np.stack([x, -x[::-1]])
    plain = allan.adev_batch(batch, FS)
    scaled = allan.adev_batch(np.ldexp(batch, -k), FS)
    for p, s in zip(plain, scaled):
        _assert_scaled(s[0], p[0], -k)
    # A memory-mapped .npy file is streamed through the core in pieces.
    path = tmp_path / "huge.npy"
    np.save(path, np.ldexp(np.tile(x, 5), k))
    streamed = _one(allan.adev(np.load(path, mmap_mode="r"), FS))
    _assert_scaled(streamed, _one(allan.adev(np.tile(x, 5), FS)), k)


def test_dynamic_variances_scale() -> None:
    x = np.tile(BASE, 2)
    k = 400  # variances ×2^800: still representable
    plain = allan.dynamic_adev(x, FS, window=2000, step=500)
    scaled = allan.dynamic_adev(np.ldexp(x, k), FS, window=2000, step=500)
    np.testing.assert_array_equal(scaled.avar, np.ldexp(plain.avar, 2 * k))

"""Spectral analysis: least-squares spectra of unequally spaced data, FFT PSD and noise density.

:func:`lssa` is the least-squares spectral analysis (LSSA) of Vaníček (1969) and Pagiatakis
(1999) used by [TS] §2.2: it works directly on unequally spaced, weighted series with gaps,
suppresses known constituents (datum bias, linear trend, sinusoids of known period) without
shifting the other peaks, and tests every spectral value for significance. :func:`psd` is the
one-sided Welch PSD of regularly sampled data and :func:`noise_density` its white-noise level.

Conventions
-----------
- Times ``t`` in seconds (any unit works: frequencies are then in cycles per that unit).
- Spectral values ``s ∈ [0, 1]`` (fraction of the residual's weighted quadratic norm explained
  by a sinusoid of that frequency); ``10 log10(s/(1 − s))`` dB ([TS] eq. 12).
- PSDs are one-sided, in unit²/Hz (integral over [0, fs/2] = variance); the noise density is
  its square root in unit/√Hz (datasheet convention); the IEEE-952 angle random walk is
  ``N = density/√2`` (SPEC §1).

References
----------
.. [TS] N. El-Diasty, A. El-Rabbany, S. Pagiatakis, "Stochastic characteristics of
   temperature-dependent MEMS-based inertial sensor error", §2.2, eqs. 5–13.
.. [V69] P. Vaníček, "Approximate spectral analysis by least-squares fit", Astrophys. Space
   Sci. 4 (1969) 387–391.
.. [P99] S. D. Pagiatakis, "Stochastic significance of peaks in the least-squares spectrum",
   J. Geodesy 73 (1999) 67–78.
.. [W67] P. D. Welch, "The use of fast Fourier transform for the estimation of power spectra",
   IEEE Trans. Audio Electroacoust. 15 (1967) 70–73.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrobias import _core
from gyrobias._validation import as_float_array, pair, real, string
from gyrobias.units import checked_units

__all__ = ["LSSAResult", "NoiseDensity", "PSDResult", "lssa", "noise_density", "psd"]


@dataclass(frozen=True)
class LSSAResult:
    """Least-squares spectrum with its significance test.

    Attributes
    ----------
    frequencies : ndarray
        Frequencies in Hz (cycles per unit of ``t``).
    spectrum : ndarray
        Spectral values ``s ∈ [0, 1]``.
    alpha : float
        Significance level of the test.
    critical_value : float
        ``s_crit = 1 − α^(2/(n − u − 2))`` (Pagiatakis 1999, unknown variance factor).
    n : int
        Number of observations.
    n_known : int
        Number of known-constituent parameters ``u`` (bias, trend, 2 per known period, user
        columns).
    trend : bool
        Whether a linear trend was fitted.
    known_periods : tuple of float
        Periods of the known sinusoids.
    known_params : ndarray
        Their least-squares estimates: bias at ``t_ref``, trend per unit time, a (cos, sin)
        amplitude pair per known period (phases relative to ``t_ref``), one per user column.
    t_ref : float
        Reference time of ``known_params`` (midpoint of the series).
    residual_norm : float
        Weighted quadratic norm ``gᵀPg`` of the series after removing the known constituents.
    """

    frequencies: NDArray[np.float64]
    spectrum: NDArray[np.float64]
    alpha: float
    critical_value: float
    n: int
    n_known: int
    trend: bool
    known_periods: tuple[float, ...]
    known_params: NDArray[np.float64]
    t_ref: float
    residual_norm: float

    @property
    def db(self) -> NDArray[np.float64]:
        """Least-squares PSD in dB, ``10 log10(s/(1 − s))`` ([TS] eq. 12)."""
        with np.errstate(divide="ignore"):
            return 10.0 * np.log10(self.spectrum / (1.0 - self.spectrum))

    @property
    def critical_db(self) -> float:
        """The critical value in dB."""
        c = self.critical_value
        return float(10.0 * np.log10(c / (1.0 - c)))

    @property
    def significant(self) -> NDArray[np.bool_]:
        """Mask of the frequencies whose spectral value exceeds the critical value."""
        return self.spectrum > self.critical_value

    @property
    def periods(self) -> NDArray[np.float64]:
        """``1/frequencies``."""
        return 1.0 / self.frequencies

    def peaks(self) -> NDArray[np.int64]:
        """Indices of the significant local maxima of the spectrum, strongest first."""
        s = self.spectrum
        left = np.concatenate(([-np.inf], s[:-1]))
        right = np.concatenate((s[1:], [-np.inf]))
        idx = np.flatnonzero((s >= left) & (s > right) & self.significant)
        return idx[np.argsort(-s[idx], kind="stable")].astype(np.int64)

    def to_dict(self) -> dict[str, Any]:
        """Plain-Python representation (arrays as lists)."""
        return {
            "frequencies": self.frequencies.tolist(),
            "spectrum": self.spectrum.tolist(),
            "alpha": self.alpha,
            "critical_value": self.critical_value,
            "n": self.n,
            "n_known": self.n_known,
            "trend": self.trend,
            "known_periods": list(self.known_periods),
            "known_params": self.known_params.tolist(),
            "t_ref": self.t_ref,
            "residual_norm": self.residual_norm,
            "significant_peaks_hz": self.frequencies[self.peaks()].tolist(),
        }


def lssa(
    t: ArrayLike,
    y: ArrayLike,
    freqs: ArrayLike | None = None,
    *,
    weights: ArrayLike | None = None,
    cov: ArrayLike | None = None,
    trend: bool = False,
    known_periods: Sequence[float] | ArrayLike = (),
    columns: ArrayLike | None = None,
    alpha: float = 0.01,
) -> LSSAResult:
    """Least-squares spectrum of an unequally spaced series with significance test.

    Parameters
    ----------
    t : array_like, 1-D
        Observation times (s), strictly increasing; gaps and irregular spacing are allowed.
    y : array_like, 1-D
        Observations, same length as ``t``.
    freqs : array_like, optional
        Frequencies (Hz) at which to evaluate the spectrum, all > 0. Default:
        ``k/(n·Δt̄)``, ``k = 1..⌊(n − 1)/2⌋`` with ``Δt̄`` the mean spacing (the Fourier
        frequencies for regular sampling, below the average Nyquist frequency). A uniform grid
        is evaluated fastest (trigonometric recurrence).
    weights : array_like, optional
        Diagonal weights ``P_ii`` (e.g. ``1/σ_i²``), all > 0.
    cov : array_like, optional
        Full ``n × n`` covariance matrix ``C_f`` (symmetric positive definite; ``P = C_f⁻¹``);
        the data are whitened once with its Cholesky factor. Costs O(n²) per frequency, so
        ``n ≤ 4000``. Not together with ``weights``.
    trend : bool
        Fit a linear trend as a known constituent (the datum bias is always fitted).
    known_periods : sequence of float
        Periods (s) of sinusoids fitted as known constituents (suppressed from the spectrum).
    columns : array_like, shape (n,) or (n, k), optional
        Further known constituents (e.g. a temperature record, a step at a known epoch),
        fitted simultaneously like the others.
    alpha : float
        Significance level, ``0 < alpha < 1`` (0.01: 99 % confidence, as [TS]).

    Returns
    -------
    LSSAResult

    Raises
    ------
    ValueError
        Unsorted or duplicate times; NaN/inf; lengths that differ; too few points for the
        fitted parameters (``n < u + 3``); non-positive frequencies, weights or periods; a
        frequency equal to ``1/P`` of a known period; both ``weights`` and ``cov``; a bad
        ``cov``; ``columns`` without one row per observation; ``alpha`` outside (0, 1).
    gyrobias.GyroLinAlgError
        ``cov`` not positive definite, dependent known constituents, or ``y`` explained exactly
        by the known constituents.

    Notes
    -----
    With the known constituents ``Φ_K`` fitted first (residual ``g``), at every frequency the
    pair ``Φ_ω = [cos ωt, sin ωt]`` is fitted simultaneously with ``Φ_K`` and

    ``s(ω) = rᵀ (N22 − N12ᵀ N11⁻¹ N12)⁻¹ r / (gᵀ P g)``, ``r = Φ_ωᵀ P g``,

    ``N11 = Φ_KᵀPΦ_K``, ``N12 = Φ_KᵀPΦ_ω``, ``N22 = Φ_ωᵀPΦ_ω``. With only the datum bias and
    no weights this equals astropy's ``LombScargle(t, y).power(f)`` (standard normalisation,
    ``fit_mean=True``); with weights it equals ``LombScargle(t, y, dy=1/√w)``. The critical
    value at level α with unknown variance factor is ``1 − α^(2/(n − u − 2))``.

    References
    ----------
    [TS] §2.2 eqs. 5–12; Vaníček (1969); Pagiatakis (1999).

    Examples
    --------
    >>> import numpy as np
    >>> from gyrobias.spectral import lssa
    >>> rng = np.random.default_rng(0)
    >>> t = np.sort(rng.uniform(0.0, 100.0, 400))            # irregular times (s)
    >>> y = np.sin(2 * np.pi * 0.2 * t) + rng.normal(0.0, 1.0, 400)
    >>> r = lssa(t, y, np.linspace(0.01, 1.0, 500))
    >>> round(float(r.frequencies[r.peaks()[0]]), 2)
    0.2
    """
    tt = as_float_array("t", t)
    yy = as_float_array("y", y)
    if tt.shape != yy.shape:
        raise ValueError(f"y has {yy.size} values but t has {tt.size}")
    alpha = real("alpha", alpha)  # 0 < alpha < 1: the core's check (critical_value)
    ff = _core.spectral.default_frequencies(tt) if freqs is None else as_float_array("freqs", freqs)
    w = None if weights is None else as_float_array("weights", weights)
    c = None
    if cov is not None:
        c = as_float_array("cov", cov, ndims=(2,))
        if c.shape != (tt.size, tt.size):
            raise ValueError(f"cov must have shape ({tt.size}, {tt.size}), got {c.shape}")
    try:
        periods = np.ascontiguousarray(np.asarray(known_periods, dtype=np.float64).reshape(-1))
    except (TypeError, ValueError) as exc:
        raise TypeError(
            f"known_periods must be a sequence of numbers, got {known_periods!r}"
        ) from exc
    user = None
    if columns is not None:
        user = as_float_array("columns", columns, ndims=(1, 2))
        user = np.ascontiguousarray(user.reshape(tt.size, -1)) if user.shape[0] == tt.size else user
        if user.ndim != 2 or user.shape[0] != tt.size:
            raise ValueError(
                f"columns must have {tt.size} rows (one per observation), got shape {user.shape}"
            )
    r = _core.spectral.lssa(tt, yy, ff, w, c, bool(trend), periods, user)
    n_known = int(r["n_known"])
    return LSSAResult(
        frequencies=ff,
        spectrum=np.asarray(r["spectrum"], dtype=np.float64),
        alpha=alpha,
        critical_value=float(_core.spectral.critical_value(tt.size, n_known, alpha)),
        n=int(tt.size),
        n_known=n_known,
        trend=bool(trend),
        known_periods=tuple(float(p) for p in periods),
        known_params=np.asarray(r["known_params"], dtype=np.float64),
        t_ref=float(r["t_ref"]),
        residual_norm=float(r["residual_norm"]),
    )


@dataclass(frozen=True)
class PSDResult:
    """One-sided power spectral density of a regularly sampled series.

    Attributes
    ----------
    frequencies : ndarray
        ``k·fs/nperseg`` in Hz, ``k = 0..nperseg/2``.
    psd : ndarray
        One-sided PSD in ``unit²/Hz``.
    fs : float
        Sample rate in Hz.
    nperseg, noverlap : int
        Welch segment length and overlap (samples).
    window : str
        Segment window.
    unit : str or None
        Unit of the input samples.
    """

    frequencies: NDArray[np.float64]
    psd: NDArray[np.float64]
    fs: float
    nperseg: int
    noverlap: int
    window: str
    unit: str | None = None

    @property
    def density(self) -> NDArray[np.float64]:
        """Amplitude spectral density ``√psd`` in ``unit/√Hz``."""
        return np.sqrt(self.psd)

    @property
    def db(self) -> NDArray[np.float64]:
        """``10 log10(psd)`` in dB re 1 unit²/Hz."""
        with np.errstate(divide="ignore"):
            return 10.0 * np.log10(self.psd)

    def to_dict(self) -> dict[str, Any]:
        """Plain-Python representation."""
        return {
            "frequencies": self.frequencies.tolist(),
            "psd": self.psd.tolist(),
            "fs": self.fs,
            "nperseg": self.nperseg,
            "noverlap": self.noverlap,
            "window": self.window,
            "unit": self.unit,
        }


def _segment(name: str, value: Any, default: int) -> int:
    if value is None:
        return default
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}")
    return int(value)


def psd(
    x: ArrayLike,
    fs: float,
    *,
    nperseg: int | None = None,
    noverlap: int | None = None,
    window: str = "hann",
    units: str | None = None,
) -> PSDResult:
    """One-sided Welch PSD of regularly sampled data (FFT in the Rust core).

    Parameters
    ----------
    x : array_like, 1-D
        Samples (e.g. gyro rate in deg/s).
    fs : float
        Sample rate in Hz.
    nperseg : int, optional
        Segment length; default ``min(n, 4096)``. ``nperseg = n`` with ``window="boxcar"`` is
        the plain periodogram.
    noverlap : int, optional
        Overlap between segments; default ``nperseg // 2``.
    window : {"hann", "boxcar"}
        Segment window (periodic Hann as SciPy's ``"hann"``).
    units : str, optional
        Unit of ``x``; the PSD is in ``units²/Hz``.

    Returns
    -------
    PSDResult

    Raises
    ------
    ValueError
        NaN/inf, ``fs ≤ 0``, ``nperseg < 2`` or longer than the series, ``noverlap ≥ nperseg``.

    Notes
    -----
    Each segment has its mean removed and is windowed; ``P(f_k) = c_k·mean|X_k|²/(fs·Σw²)`` with
    ``c_k = 2`` except at DC and Nyquist. Equals ``scipy.signal.welch(x, fs, window, nperseg,
    noverlap, detrend="constant", scaling="density")``. White noise of standard deviation σ has
    ``P = 2σ²/fs``.
    """
    arr = as_float_array("x", x)
    units = checked_units("units", units)
    fs = real("fs", fs)  # fs > 0: the core's check (spectral::welch)
    string("window", window)  # parsed by the core (Window::parse)
    # Types here; nperseg >= 2, noverlap < nperseg are the core's checks, a negative count the
    # binding's (it names the argument).
    nps = _segment("nperseg", nperseg, min(arr.size, 4096))
    nov = _segment("noverlap", noverlap, max(nps, 0) // 2)
    f, p = _core.spectral.welch(arr, fs, nps, nov, window)
    return PSDResult(f, p, fs, nps, nov, window, units)


@dataclass(frozen=True)
class NoiseDensity:
    """White-noise level of a regularly sampled series, from its one-sided PSD.

    Attributes
    ----------
    density : float
        One-sided noise density ``√(mean PSD over the band)`` in ``unit/√Hz``.
    band : tuple of float
        Frequency band (Hz) averaged.
    unit : str or None
        Unit of the input samples.
    spectrum : PSDResult
        The PSD it was read from.
    """

    density: float
    band: tuple[float, float]
    unit: str | None
    spectrum: PSDResult = field(repr=False)

    @property
    def arw(self) -> float:
        """IEEE-952 white-noise coefficient ``N = density/√2`` (unit·√s, e.g. deg/√s)."""
        return self.density / math.sqrt(2.0)

    def to_dict(self) -> dict[str, Any]:
        """Plain-Python representation (without the spectrum)."""
        return {
            "density": self.density,
            "arw": self.arw,
            "band": list(self.band),
            "unit": self.unit,
        }


def noise_density(
    x: ArrayLike,
    fs: float,
    *,
    band: tuple[float, float] | None = None,
    nperseg: int | None = None,
    units: str | None = None,
) -> NoiseDensity:
    """One-sided white-noise density of ``x`` (unit/√Hz): √ of the mean PSD over ``band``.

    Parameters
    ----------
    x : array_like, 1-D
        Regularly sampled data.
    fs : float
        Sample rate in Hz.
    band : (float, float), optional
        Band (Hz) over which the PSD is averaged; default ``(0.05·fs, 0.25·fs)``, above the
        correlated (bias-instability, random-walk) noise of typical MEMS gyros and below
        anti-alias roll-off.
    nperseg : int, optional
        Welch segment length (see :func:`psd`).
    units : str, optional
        Unit of ``x``.

    Raises
    ------
    ValueError
        As :func:`psd`; a band outside ``[0, fs/2]``, reversed, or containing no frequency bin.

    Notes
    -----
    For white noise of standard deviation σ the density is ``σ√(2/fs)`` and the IEEE-952 angle
    random walk ``N = density/√2 = σ/√fs`` (SPEC §1).
    """
    given = None if band is None else pair("band", band)  # before the work, whatever the data
    spec = psd(x, fs, nperseg=nperseg, units=units)
    lo, hi = (0.05 * spec.fs, 0.25 * spec.fs) if given is None else given
    if not (0.0 <= lo < hi <= 0.5 * spec.fs):
        raise ValueError(
            f"band must satisfy 0 <= low < high <= fs/2 = {0.5 * spec.fs}, got ({lo}, {hi})"
        )
    mask = (spec.frequencies >= lo) & (spec.frequencies <= hi)
    if not mask.any():
        raise ValueError(
            f"band ({lo}, {hi}) Hz contains no frequency bin (bin spacing {spec.fs / spec.nperseg} Hz)"
        )
    return NoiseDensity(float(np.sqrt(np.mean(spec.psd[mask]))), (lo, hi), units, spec)

"""The Haar wavelet variance (:func:`wvar`, classical and robust, with intervals) and the
generalized method of wavelet moments built on it (:func:`gmwm`)."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

from gyrobias import _core
from gyrobias._line_detection import detect_lines
from gyrobias._spectral_lines import MIN_SAMPLES, SpectralLine
from gyrobias._validation import (
    as_float_array,
    boolean,
    integer,
    names,
    real,
    sample_rate,
)
from gyrobias._validation import axis_names as check_axis_names
from gyrobias._validation import seed as seed_value
from gyrobias.allan._types import AllanResult
from gyrobias.noise._types import NoiseCoefficients, WaveletVariance
from gyrobias.noise.fitting import _line_windows
from gyrobias.units import checked_units, sensor_kind


def gmwm(
    data: Any,
    fs: float,
    *,
    terms: Iterable[str] = ("Q", "N", "B", "K"),
    units: str | None = None,
    axis_names: Sequence[str] | None = None,
    select: bool = False,
    bootstrap: int = 0,
    seed: int | None = None,
    auto_range: bool = True,
    lines: str | Sequence[float | SpectralLine | tuple[float, float]] | None = "auto",
    bound_confidence: float = 0.95,
) -> NoiseCoefficients | tuple[NoiseCoefficients, ...]:
    """Noise model by the generalized method of wavelet moments (GMWM).

    Parameters
    ----------
    data : array_like, shape (n,) or (n, axes)
        Rate samples (e.g. deg/s); one column per axis.
    fs : float
        Sample rate in Hz.
    terms : iterable of {"Q", "N", "B", "K", "R", "GM", "GM2", "S"}
        Composite model: quantisation, white noise (ARW), flicker (bias instability), random
        walk (RRW), drift (rate ramp), one or two first-order Gauss–Markov terms and ("S") a
        sinusoid per line in ``lines`` (an error when there is none).
    units : str, optional
        Rate unit of the data (``"deg/s"``, ``"rad/s"``, ``"m/s^2"``, …).
    axis_names : sequence of str, optional
        One name per column.
    select : bool
        Choose, among all sub-models of ``terms``, the one with the smallest wavelet-variance
        information criterion ``WVIC = J + 2p`` (Notes); the terms it drops are reported missing
        with the reason "dropped by the model selection" (and the chosen sub-model). Like a
        term the non-negative fit sets to zero, a dropped term is one the data do not show: it
        carries the same upper bound (:attr:`gyrobias.noise.Term.upper_bound`, at
        ``bound_confidence``).
    bootstrap : int
        Number of parametric-bootstrap replicates for the uncertainties (0: asymptotic).
    seed : int or None
        Seed of the bootstrap (``None``: fresh).
    auto_range : bool
        Select the scales as :func:`fit` selects its τ range (Notes); ``False`` uses every
        scale with half-width ``m ≤ n/8``.
    lines : "auto", sequence of float, SpectralLine or (float, float), or None
        Periodic disturbances modelled by sinusoidal terms (wavelet variance ``½`` of the
        sampled-sine Allan variance, see :func:`fit`). ``"auto"``: the lines
        :func:`detect_lines` finds in each column (false-alarm level 0.01), said in a warning;
        ``None``: none. A sequence as in :func:`fit`: a SpectralLine (held at its frequency,
        with the periodogram's uncertainty; so are the lines of ``"auto"``), a float seed (snapped to the line :func:`detect_lines` finds within ±1 % of it in the
        column, else refined within ±1 %) or a ``(frequency, half_width)`` pair
        (``half_width = 0``: held at exactly that frequency, reported without uncertainty).
    bound_confidence : float
        One-sided confidence level (in (0, 1), default 0.95) of the upper bounds of the
        requested terms the estimate does not show (as in :func:`fit`: the largest coefficient
        whose asymptote stays under the one-sided upper confidence bound of ``2ν̂²`` at every
        scale used, the other terms held at zero).

    Returns
    -------
    NoiseCoefficients or tuple of NoiseCoefficients
        ``method="gmwm"``, with diagnostics; ``allan`` holds the Allan-variance equivalent
        ``2ν̂²`` of the wavelet variance at ``τ = 2^{j−1}/fs`` (for plots).

    Raises
    ------
    ValueError
        Constant or non-finite data, too few dyadic scales for the model, unknown terms or
        units, ``bootstrap < 0``, ``bound_confidence`` outside (0, 1).

    Notes
    -----
    The Haar wavelet variance ``ν̂²_j`` at dyadic scales ``τ_j = 2^j/fs`` (MODWT; it equals half
    the overlapping Allan variance at ``τ = τ_j/2``) is matched to the composite model
    ``ν(θ)`` by ``θ̂ = argmin (ν̂ − ν(θ))ᵀ Ω⁻¹ (ν̂ − ν(θ))`` with the optimal weight matrix
    ``Ω⁻¹``, Ω the asymptotic covariance of ``ν̂`` (correlations from the spectral formula of
    Serroukh, Walden & Percival 2000, variances from SP1065's EDF) re-estimated at the current
    θ̂ three times (Guerrier et al. 2013, §3). The squared amplitudes enter linearly and are
    solved by exact non-negative generalized least squares; Gauss–Markov correlation times are
    profiled over the scale range. Uncertainties: ``(DᵀΩ⁻¹D)⁻¹``, ``D = ∂ν/∂θ``, inflated by
    ``max(1, J/(K − p))``, or the parametric bootstrap. Model selection uses
    ``WVIC = J(θ̂) + 2p`` (J Hansen's statistic, p active parameters), the GMM Akaike-type
    criterion of Andrews (1999).

    *Scales* (``auto_range``, default): every scale of :func:`wvar` (``2^j ≤ n/2``), then the
    rules of :func:`fit`: trailing scales with fewer than 3 EDF go; while the goodness-of-fit
    test rejects the model (p < 0.01) the leading scales up to the last one with standardised
    residual ``z < −2`` (failing that, the leading run of negative residuals: the generalized
    least squares spreads a misfit of the first scales over their correlated neighbours) — a
    sensor's anti-alias filter bends the first scales below the white-noise line — or the
    trailing run with ``z > 2`` (drift) is excluded and the model refitted, keeping at least
    half of the scales. ``diagnostics.excluded`` says what was dropped and why. Without
    it the scales are those with half-width ``m ≤ n/8``.

    References
    ----------
    S. Guerrier, J. Skaloud, Y. Stebler, M.-P. Victoria-Feser, "Wavelet-variance-based
    estimation for composite stochastic processes", J. Amer. Statist. Assoc. 108 (2013) 1021.
    Y. Stebler, S. Guerrier, J. Skaloud, M.-P. Victoria-Feser, "Generalized method of wavelet
    moments for inertial navigation filter design", IEEE Trans. Aerosp. Electron. Syst. 50
    (2014) 2269. D. W. K. Andrews, "Consistent moment selection procedures for generalized
    method of moments estimation", Econometrica 67 (1999) 543.

    Examples
    --------
    >>> import gyrobias
    >>> rate = gyrobias.noise.simulate(200_000, 100.0, arw=0.2 / 60, rrw=20 / 216000, seed=3)
    >>> c = gyrobias.noise.gmwm(rate, 100.0, terms=("N", "K"), units="deg/s").to("ieee")
    >>> round(c.N.value, 2), c.method
    (0.2, 'gmwm')
    """
    arr = as_float_array("data", data, ndims=(1, 2))
    fs = sample_rate(fs)  # the core checks fs before t0 = 1/fs is formed
    term_in = names("terms", terms)
    want_sine = "S" in term_in
    term_list = [t for t in term_in if t != "S"]
    # The symbols are parsed by the core (noise::parse_model_terms), whose message names terms.
    select = boolean("select", select)
    auto_range = boolean("auto_range", auto_range)
    replicates = integer("bootstrap", bootstrap)
    seed_number = seed_value("seed", seed)
    bound_confidence = real("bound_confidence", bound_confidence)  # (0, 1): the core's check
    units = checked_units("units", units)
    sensor = sensor_kind(units) if units is not None else None
    matrix = arr.reshape(-1, 1) if arr.ndim == 1 else arr
    n_axes = matrix.shape[1]
    check_axis_names(axis_names, n_axes)
    t0 = 1.0 / fs
    out = []
    for a in range(n_axes):
        column = np.ascontiguousarray(matrix[:, a], dtype=np.float64)
        found: tuple[SpectralLine, ...] | None = None
        if _needs_detection(lines) and column.shape[0] >= MIN_SAMPLES:
            found = detect_lines(column, fs, units=units)  # type: ignore[assignment]
        windows, detected, held_uncertainty = _line_windows(_Found(found), lines)
        if want_sine and not windows:
            raise ValueError(
                "terms contains 'S' but there is no line to model: pass lines=[f0, ...] (Hz) "
                "or the SpectralLine objects of gyrobias.noise.detect_lines"
            )
        raw = _core.noise.gmwm(
            column,
            t0,
            term_list,
            select,
            replicates,
            seed_number,
            4 if auto_range else 8,
            auto_range,
            windows,
            bound_confidence,
        )
        name = None if axis_names is None else str(axis_names[a])
        allan = AllanResult._from_core(
            raw["wavelet"],
            kind="adev",
            fs=fs,
            data_type="rate",
            overlapping=True,
            confidence=None,
            units=units,
            axis=name,
        )
        out.append(
            NoiseCoefficients._from_core(
                raw,
                raw["diagnostics"],
                np.asarray(allan.taus, dtype=np.float64),
                method="gmwm",
                data_unit=units,
                sensor=sensor,
                fs=fs,
                axis=name,
                edf_source="SP1065 simple approximation",
                allan=allan,
                detected=detected,
                line_uncertainties=held_uncertainty,
            )
        )
    if arr.ndim == 1:
        return out[0]
    return tuple(out)


def _needs_detection(lines: Any) -> bool:
    """Whether the column's spectral lines are needed: ``lines="auto"``, or a bare frequency
    among ``lines`` (a seed snaps to the detected line near it, see :func:`fit`)."""
    if isinstance(lines, str):
        return lines == "auto"
    if not isinstance(lines, Sequence):
        return False
    return any(not isinstance(x, (SpectralLine, Sequence, np.ndarray, str, bytes)) for x in lines)


class _Found:
    """Carries the lines detected in a column where :func:`_line_windows` expects a result."""

    def __init__(self, lines: tuple[SpectralLine, ...] | None) -> None:
        self.lines = lines


def wvar(
    data: Any,
    fs: float,
    *,
    robust: bool = False,
    efficiency: float = 0.6,
    confidence: float = 0.95,
    levels: int | None = None,
    units: str | None = None,
    axis_names: Sequence[str] | None = None,
) -> WaveletVariance | tuple[WaveletVariance, ...]:
    """Haar wavelet variance at every dyadic scale, classical or robust, with intervals.

    Parameters
    ----------
    data : array_like, shape (n,) or (n, axes)
        Rate samples; one column per axis.
    fs : float
        Sample rate (Hz).
    robust : bool
        Robust (Tukey-biweight M-) estimator instead of the mean of squares: outliers (spikes,
        glitches) barely move it (Notes).
    efficiency : float
        Gaussian efficiency of the robust estimator, in (0, 1) (0.6, as the R ``wv`` package);
        used only with ``robust=True``. Lower is more robust, higher more precise.
    confidence : float
        Confidence level of the intervals, in (0, 1).
    levels : int, optional
        Number of levels J (default: every level the record supports, ``⌊log₂ n⌋ − 1``).
    units : str, optional
        Rate unit of the data.
    axis_names : sequence of str, optional
        One name per column.

    Returns
    -------
    WaveletVariance or tuple of WaveletVariance
        With ``scales`` ``2^j/fs`` (s), ``variance``, ``ci_low``/``ci_high``, ``edf`` and
        ``.plot()``.

    Raises
    ------
    ValueError
        Non-finite data, fewer than 4 samples (16 with ``robust=True``: three scales),
        ``levels`` outside ``1 … ⌊log₂ n⌋ − 1``, ``confidence`` or ``efficiency`` outside
        (0, 1).

    Notes
    -----
    The level-j Haar MODWT coefficient is half the difference of two adjacent means of
    ``2^{j−1}`` samples; over the ``M_j = n − 2^j + 1`` coefficients free of the boundary the
    classical estimate ``ν̂²_j = (1/M_j) Σ W²_{j,t}`` equals half the overlapping Allan variance
    at ``τ = 2^{j−1}/fs`` exactly (Percival & Walden 2000, ch. 8). Intervals: chi-square with
    ``η_j = max(M_j/2^j, 1)`` degrees of freedom (Percival 1995, "η₃"),
    ``[η ν̂²/χ²_η(1 − α/2), η ν̂²/χ²_η(α/2)]``.

    The robust estimate solves ``(1/M_j) Σ ρ_c(W_{j,t}/ν) = E ρ_c(Z)`` (Z standard normal) with
    ``ρ_c(r) = r²(1 − r²/c²)⁴`` for ``|r| ≤ c`` and 0 beyond (the square of Tukey's biweight ψ,
    as in the R ``wv``/``gmwm`` packages of Guerrier, Molinari et al.), taking the root on the
    decreasing branch of the left side; ``c`` gives the requested Gaussian efficiency
    ``D²/(2Q)``, ``D = E[Z²ρ_c(Z)] − E ρ_c(Z)``, ``Q = Var ρ_c(Z)`` (c = 4.40 at 0.6). Its
    intervals use ``efficiency·η_j`` degrees of freedom (its variance is the classical one
    divided by the efficiency).

    References
    ----------
    D. B. Percival, "On estimation of the wavelet variance", Biometrika 82 (1995) 619.
    D. B. Percival, A. T. Walden, *Wavelet Methods for Time Series Analysis* (2000), ch. 8.
    S. Guerrier, R. Molinari, "Fast and robust parametric estimation for time series and
    spatial models" (2016, arXiv:1607.05858); R package ``wv`` (``wvar``).

    Examples
    --------
    >>> import numpy as np
    >>> import gyrobias
    >>> rate = np.random.default_rng(1).standard_normal(4096)
    >>> w = gyrobias.noise.wvar(rate, 100.0)
    >>> len(w.levels), round(float(w.variance[0]), 1)  # white noise: ν²_1 = σ²/2
    (11, 0.5)
    >>> spiky = rate.copy()
    >>> spiky[::500] = 50.0
    >>> r = gyrobias.noise.wvar(spiky, 100.0, robust=True)
    >>> round(float(r.variance[0]), 1)
    0.5
    """
    arr = as_float_array("data", data, ndims=(1, 2))
    fs = sample_rate(fs)
    units = checked_units("units", units)
    robust = boolean("robust", robust)
    efficiency = real("efficiency", efficiency)
    confidence = real("confidence", confidence)
    level_count = None if levels is None else integer("levels", levels)
    matrix = arr.reshape(-1, 1) if arr.ndim == 1 else arr
    check_axis_names(axis_names, matrix.shape[1])
    out = []
    for a in range(matrix.shape[1]):
        column = np.ascontiguousarray(matrix[:, a], dtype=np.float64)
        raw = _core.noise.wvar(
            column, 1.0 / fs, efficiency if robust else None, confidence, level_count
        )
        out.append(
            WaveletVariance(
                levels=np.asarray(raw["levels"]).astype(np.int64),
                scales=np.asarray(raw["scales"], dtype=np.float64),
                variance=np.asarray(raw["variance"], dtype=np.float64),
                ci_low=np.asarray(raw["ci_low"], dtype=np.float64),
                ci_high=np.asarray(raw["ci_high"], dtype=np.float64),
                edf=np.asarray(raw["edf"], dtype=np.float64),
                n_coefficients=np.asarray(raw["n_coefficients"]).astype(np.int64),
                robust=robust,
                efficiency=efficiency if robust else None,
                confidence=confidence,
                fs=fs,
                unit=units,
                axis=None if axis_names is None else str(axis_names[a]),
            )
        )
    return out[0] if arr.ndim == 1 else tuple(out)

"""Identification of the IEEE-952 coefficients from an Allan curve: the joint weighted fit and
the IEEE read-off (:func:`fit`), and the Gauss–Markov Allan variance."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING, Any, overload

import numpy as np
from numpy.typing import NDArray

from gyrobias import _core
from gyrobias._spectral_lines import SpectralLine
from gyrobias._validation import (
    as_float_array,
    asarray,
    boolean,
    choice,
    count,
    integer,
    names,
    pair,
    real,
    sample_rate,
    text,
)
from gyrobias.noise._types import (
    _GM_SYMBOLS,
    _SYMBOLS,
    NoiseCoefficients,
)
from gyrobias.units import sensor_kind

if TYPE_CHECKING:
    from gyrobias.allan import AllanResult


def gauss_markov_avar(sigma: float, correlation_time: float, taus: Any) -> NDArray[np.float64]:
    """Allan variance of a first-order Gauss–Markov rate process.

    Parameters
    ----------
    sigma : float
        Standard deviation σ of the process (rate unit u, e.g. deg/s).
    correlation_time : float
        Correlation time T in seconds (autocovariance ``σ² exp(−|t|/T)``).
    taus : array_like
        Averaging times τ in seconds.

    Returns
    -------
    ndarray
        ``σ²_A(τ) = (σ²T²/τ²)(2τ/T − 3 + 4e^{−τ/T} − e^{−2τ/T})`` in u².

    Notes
    -----
    From the angle-increment variance ``V(t) = 2σ²T(t − T(1 − e^{−t/T}))`` and
    ``σ²_A(τ) = (4V(τ) − V(2τ))/(2τ²)`` (IEEE Std 952-1997 Annex C). Limits: white noise
    ``2σ²T/τ`` for τ ≫ T, random walk ``(2σ²/T)·τ/3`` for τ ≪ T; the maximum is ≈ (0.618 σ)² at
    τ ≈ 1.89 T. Evaluated without cancellation (power series for τ < T/2).

    Examples
    --------
    >>> import gyrobias
    >>> v = gyrobias.noise.gauss_markov_avar(1.0, 10.0, [1e4])
    >>> round(float(v[0]) * 1e4 / (2 * 10.0), 4)  # 1 − 3T/(2τ) of the white noise 2σ²T/τ
    0.9985
    """
    tau = as_float_array("taus", np.atleast_1d(asarray("taus", taus)), ndims=(1,))
    return _core.noise.gauss_markov_avar(
        real("sigma", sigma), real("correlation_time", correlation_time), tau
    )


def sinusoid_avar(
    amplitude: float, frequency: float, taus: Any, *, fs: float | None = None
) -> NDArray[np.float64]:
    """Allan variance of a sinusoidal rate ``Ω₀·sin(2πf₀t + φ)`` (IEEE 952 term "S").

    Parameters
    ----------
    amplitude : float
        Ω₀ in the rate unit u (≥ 0).
    frequency : float
        f₀ in Hz (> 0; with ``fs``, at most fs/2).
    taus : array_like
        Averaging times τ in seconds (multiples of 1/fs for sampled data).
    fs : float, optional
        Sample rate of the data (Hz): the sampled form. ``None``: the continuous IEEE form.

    Returns
    -------
    ndarray
        σ²(τ) in u².

    Notes
    -----
    Continuous time (IEEE Std 952-1997 Annex C): ``σ²(τ) = Ω₀²·(sin²(πf₀τ)/(πf₀τ))²``. For data
    sampled at period ``t0 = 1/fs`` the mean of ``m`` samples has the Dirichlet gain
    ``sin(πf₀mt0)/(m·sin(πf₀t0))``, so ``σ²(m·t0) = Ω₀²·sin⁴(πf₀τ)/(m·sin(πf₀t0))²``: the
    continuous form times ``(πf₀t0/sin(πf₀t0))²`` at every τ (1.19 at f₀ = 23 Hz, fs = 100 Hz;
    2.47 at Nyquist), the difference that matters near τ ≈ 1/f₀ when f₀ is a sizeable
    fraction of fs. The sampled form is fs-periodic and even in f₀: a line above fs/2 looks
    like its alias ``|f₀ − k·fs|``, which is what must be passed.

    Raises
    ------
    ValueError
        A negative or non-finite amplitude, a frequency ≤ 0 or (with ``fs``) above fs/2.

    Examples
    --------
    >>> import gyrobias
    >>> v = gyrobias.noise.sinusoid_avar(1.0, 23.0, [0.01, 0.5], fs=100.0)
    >>> c = gyrobias.noise.sinusoid_avar(1.0, 23.0, [0.01, 0.5])
    >>> [round(float(a / b), 3) for a, b in zip(v, c)]
    [1.194, 1.194]
    """
    tau = as_float_array("taus", np.atleast_1d(asarray("taus", taus)), ndims=(1,))
    period = None if fs is None else 1.0 / sample_rate(fs)
    return _core.noise.sinusoid_avar(
        real("amplitude", amplitude), real("frequency", frequency), tau, period
    )


#: Relative half-width of the window in which a line given as a bare frequency is refined.
_SEED_WINDOW = 0.01

#: What ``lines`` accepts, for the messages.
_LINES_FORMS = (
    "'auto', None or a sequence of frequencies (Hz), SpectralLine objects or "
    "(frequency, half_width) pairs"
)


def _held(line: SpectralLine) -> tuple[tuple[float, float], SpectralLine]:
    """A detected line's window: held at the periodogram's frequency (half-width 0). The
    periodogram of the rate pins it to ``line.frequency_uncertainty`` (≈ 1e-7 Hz for a
    0.05 deg/s line in 2 h of 0.2 deg/√h noise at 100 Hz), the Allan curve only to about
    0.01 Hz: refined on the Allan curve within ±1 bin, the frequency went to the window's edge
    (1.4e-4 Hz off) with a reported uncertainty of 0.015 Hz."""
    return (line.frequency, 0.0), line


def _line_item(
    x: Any, found: tuple[SpectralLine, ...]
) -> tuple[tuple[float, float], SpectralLine | None]:
    """One element of ``lines`` as a window ``(seed Hz, half-width Hz)`` and the detected line
    behind it (if any). Only the form is checked here: the values (frequency in (0, fs/2],
    half-width finite, >= 0 and below the frequency) are the core's checks, naming ``lines``."""
    if isinstance(x, SpectralLine):
        return _held(x)
    if isinstance(x, (str, bytes)) or isinstance(x, bool):
        raise TypeError(f"lines must be {_LINES_FORMS}, got an element {x!r}")
    if isinstance(x, Sequence) or isinstance(x, np.ndarray):
        if len(x) != 2:
            raise ValueError(
                f"lines: a (frequency, half_width) pair must have 2 numbers, got {len(x)}: {x!r}"
            )
        return (real("lines", x[0]), real("lines", x[1])), None
    # finite and > 0 before it is compared with the detected lines (inf was within ±1 % of
    # every line and snapped to one): the core's check, naming lines
    f = _core.validate.positive("lines", real("lines", x))
    # A bare frequency is a seed. The periodogram of the rate (``allan.lines``) pins a line to
    # a small fraction of its resolution fs/n; the Allan curve only to about 0.01 Hz on a 2 h
    # log (its χ² hardly changes with f₀ below that): a detected line within the seed's window
    # is the better seed, and it is used as if its SpectralLine had been given.
    near = [d for d in found if abs(d.frequency - f) <= _SEED_WINDOW * abs(f)]
    if near:
        return _held(min(near, key=lambda d: abs(d.frequency - f)))
    return (f, _SEED_WINDOW * abs(f)), None


def _each(items: list[Any], work: Callable[[Any], NoiseCoefficients]) -> tuple[Any, ...]:
    """``tuple(work(x) for x in items)``, the items in threads when there are several and more
    than one CPU: each fit's heavy parts (the spectral-line search of its result, the core's
    fit) release the GIL, so a 6-axis log's fits take the time of a third of them on two
    cores. Every item is fitted alone, exactly as one by one; the first failing item (in
    order) raises, as in a loop."""
    import os

    workers = min(len(items), os.cpu_count() or 1)
    if workers <= 1:
        return tuple(work(x) for x in items)
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=workers, thread_name_prefix="gyrobias-fit") as pool:
        return tuple(pool.map(work, items))


def _line_windows(
    result: Any, lines: str | Sequence[float | SpectralLine | tuple[float, float]] | None
) -> tuple[list[tuple[float, float]], tuple[SpectralLine, ...], list[float | None]]:
    """The fit's line windows ``(seed Hz, half-width Hz)``, the detected lines behind them and,
    per window, the frequency uncertainty to report when the fit holds it (``None``: the
    fit's own, or none for a frequency the user gave exactly).

    A detected line (a :class:`SpectralLine`, or ``"auto"``) is held at its frequency, the
    periodogram maximum, with the periodogram's uncertainty; a bare frequency snaps to the
    detected line of ``result.lines`` within ±1 % of it, or else is refined within ±1 % on the
    Allan curve; a ``(frequency, half_width)`` pair is refined within
    ``frequency ± half_width``, and held at ``frequency`` when ``half_width`` is 0.
    """
    if lines is None:
        return [], (), []
    found_raw = getattr(result, "lines", None)
    found = tuple(found_raw) if found_raw else ()
    if isinstance(lines, str):
        if lines != "auto":
            raise ValueError(f"lines must be {_LINES_FORMS}, got {lines!r}")
        items: list[tuple[tuple[float, float], SpectralLine | None]] = [_held(x) for x in found]
    elif not isinstance(lines, Sequence) and not isinstance(lines, np.ndarray):
        raise TypeError(f"lines must be {_LINES_FORMS}, got {type(lines).__name__}")
    else:
        items = [_line_item(x, found) for x in lines]
    detected = tuple(dict.fromkeys(d for _, d in items if d is not None))
    given: list[float | None] = [None if d is None else d.frequency_uncertainty for _, d in items]
    return [w for w, _ in items], detected, given


def _edf_source(result: AllanResult) -> str:
    return "noise identification" if result.edf is not None else "SP1065 simple approximation"


@overload
def fit(
    allan: AllanResult,
    *,
    method: str = ...,
    terms: Iterable[str] = ...,
    tau_range: tuple[float, float] | None = ...,
    regions: Mapping[str, tuple[float, float]] | None = ...,
    slope_tolerance: float = ...,
    min_points: int = ...,
    unit: str | None = ...,
    correlation_time: tuple[float, float] | None = ...,
    auto_range: bool = ...,
    lines: str | Sequence[float | SpectralLine | tuple[float, float]] | None = ...,
    bound_confidence: float = ...,
) -> NoiseCoefficients: ...


@overload
def fit(
    allan: Sequence[AllanResult],
    *,
    method: str = ...,
    terms: Iterable[str] = ...,
    tau_range: tuple[float, float] | None = ...,
    regions: Mapping[str, tuple[float, float]] | None = ...,
    slope_tolerance: float = ...,
    min_points: int = ...,
    unit: str | None = ...,
    correlation_time: tuple[float, float] | None = ...,
    auto_range: bool = ...,
    lines: str | Sequence[float | SpectralLine | tuple[float, float]] | None = ...,
    bound_confidence: float = ...,
) -> tuple[NoiseCoefficients, ...]: ...


def fit(
    allan: AllanResult | Sequence[AllanResult],
    *,
    method: str = "joint",
    terms: Iterable[str] = _SYMBOLS,
    tau_range: tuple[float, float] | None = None,
    regions: Mapping[str, tuple[float, float]] | None = None,
    slope_tolerance: float = 0.1,
    min_points: int = 3,
    unit: str | None = None,
    correlation_time: tuple[float, float] | None = None,
    auto_range: bool = True,
    lines: str | Sequence[float | SpectralLine | tuple[float, float]] | None = "auto",
    bound_confidence: float = 0.95,
) -> NoiseCoefficients | tuple[NoiseCoefficients, ...]:
    """Identify the IEEE-952 noise coefficients from an Allan-deviation result.

    Parameters
    ----------
    allan : AllanResult or sequence of AllanResult
        Overlapping or non-overlapping Allan result(s) of rate (or angle) data
        (``gyrobias.allan.adev``). A sequence gives a tuple, one per axis.
    method : {"joint", "ieee"}
        ``"joint"``: weighted non-negative least squares of the model (the better estimator).
        ``"ieee"``: IEEE-952 read-off from fixed-slope lines on the detected slope regions and B
        from the minimum.
    terms : iterable of {"Q", "N", "B", "K", "R", "GM", "GM2", "S"}
        Terms to identify; the others are reported missing ("not requested"). ``"GM"`` adds a
        first-order Gauss–Markov term, ``"GM2"`` a second one (joint fit only). ``"S"`` asks
        for the sinusoidal term of every line in ``lines`` and is an error when there is none
        (with the default ``lines="auto"`` the terms are added anyway when the data show a line).
    tau_range : (float, float), optional
        Only use Allan points with τ in this range (seconds) for the joint fit; turns the
        automatic range selection off.
    regions : mapping, optional
        ``"ieee"`` only: explicit τ range per term (e.g. ``{"N": (0.02, 2.0)}``) overriding
        the automatic slope-region detection.
    slope_tolerance : float
        ``"ieee"``: allowed deviation of the local log-log slope from the term's slope.
    min_points : int
        ``"ieee"``: minimum number of consecutive points of a detected region.
    unit : str, optional
        Rate unit of the data when the Allan result does not carry one (``"deg/s"``, ``"rad/s"``,
        ``"m/s^2"``, ``"g"``, …).
    correlation_time : (float, float), optional
        Search range (s) of the Gauss–Markov correlation times; default: the τ range of the
        points used. It must lie inside the data's τ range.
    auto_range : bool
        Joint fit without ``tau_range``: exclude long-τ points with fewer than 3 EDF and, while
        the goodness-of-fit test rejects the model (p < 0.01), systematic departures at the
        ends of the curve (Notes). ``False`` fits every point.
    lines : "auto", sequence of float, SpectralLine or (float, float), or None
        Periodic disturbances to model with the IEEE-952 sinusoidal term "S" (joint fit).
        ``"auto"`` (default): the spectral lines :func:`gyrobias.allan.adev` found in the rate
        data (``allan.lines``, a Bonferroni test at false-alarm level 0.01, see
        :func:`gyrobias.noise.detect_lines`); when there are any, one "S" term per line is added
        and a warning says so. ``None`` fits no sinusoid. A sequence gives the lines, each one
        of (frequencies in Hz, in (0, fs/2]; a line above fs/2 is given at its alias):

        - a :class:`SpectralLine` (from :func:`gyrobias.noise.detect_lines`): held at its
          frequency, the periodogram maximum, which is reported with the periodogram's
          uncertainty (:attr:`gyrobias.noise.SpectralLine.frequency_uncertainty`, ~1e-7 Hz
          on a 2 h log); ``"auto"`` does the same with every line of ``allan.lines``;
        - a float ``f``, a seed: when ``allan.lines`` holds a line within ±1 % of ``f``, that
          line is modelled (as if its SpectralLine had been given: the periodogram of the rate
          pins a frequency far better than the Allan curve); otherwise ``f`` is refined within
          ±1 % on the Allan curve, which pins it only to about 0.01 Hz on a 2 h log;
        - a pair ``(f, half_width)``: refined within ``f ± half_width`` on the Allan curve;
          ``half_width = 0`` holds the frequency at exactly ``f`` (a frequency you know, e.g. a
          motor at 23.000 Hz): it is then not a parameter of the fit, and its
          :attr:`gyrobias.noise.SinusoidTerm.frequency` has no uncertainty (``None``: given,
          not estimated).

        A negative or NaN frequency or half-width, a frequency outside (0, fs/2] or a
        half-width not below the frequency raise ``ValueError`` naming ``lines``.
    bound_confidence : float
        One-sided confidence level (in (0, 1), default 0.95) of the upper bound given to every
        requested term the data do not show (:attr:`gyrobias.noise.Term.upper_bound`, Notes);
        it is carried as :attr:`gyrobias.noise.Term.bound_confidence` and written into the
        ``UPPER BOUND`` marks of exports and reports. A lower level gives a lower bound that
        covers the true value less often.

    Returns
    -------
    NoiseCoefficients or tuple of NoiseCoefficients
        With :attr:`NoiseCoefficients.diagnostics` (goodness of fit, excluded ranges, warnings)
        and, for ``"GM"`` terms, :attr:`NoiseCoefficients.gauss_markov`.

    Raises
    ------
    ValueError
        Not an Allan-deviation result (the model is the Allan variance's), constant data
        (σ = 0 everywhere), fewer than 3 usable points in the fit range, unknown terms, units
        or methods, a region that contains no τ, a Gauss–Markov term with ``method="ieee"``,
        a ``correlation_time`` range outside the data's τ range, a line frequency outside
        (0, fs/2], ``"S"`` in ``terms`` without any line, or ``bound_confidence`` outside
        (0, 1).

    Notes
    -----
    Model: ``σ²(τ) = 3Q²/τ² + N²/τ + (0.664282·B)² + K²τ/3 + R²τ²/2`` plus, per Gauss–Markov
    term of standard deviation σ and correlation time T,
    ``(σ²T²/τ²)(2τ/T − 3 + 4e^{−τ/T} − e^{−2τ/T})`` (IEEE Std 952-1997 Annex C; white noise
    ``N² = 2σ²T`` for τ ≫ T, random walk ``K² = 2σ²/T`` for τ ≪ T), plus, per sinusoid
    ``Ω₀·sin(2πf₀t + φ)`` of data sampled at period t0, ``Ω₀²·sin⁴(πf₀τ)/(m·sin(πf₀t0))²`` at
    ``τ = m·t0`` (IEEE Std 952-1997 Annex C gives the continuous-time form
    ``Ω₀²·(sin²(πf₀τ)/(πf₀τ))²``; sampling multiplies it by ``(πf₀t0/sin(πf₀t0))²``, 1.19 at
    f₀ = 0.23·fs, so near τ ≈ 1/f₀ only the sampled form fits a real log; a line above fs/2
    acts as its alias). Ω₀² enters linearly; f₀ is held (detected lines, zero half-widths) or
    refined within its window (``lines``) by a grid and golden-section profile of the weighted
    χ², with the sandwich uncertainty of the Allan-curve fit. The Allan curve sees a line
    only where its variance is a sizeable share of the noise's (τ ≲ 1 s for 0.05 deg/s at
    N = 0.2 deg/√h), so it pins f₀ to ~0.01 Hz on a 2 h log at 100 Hz (measured: rms error
    0.0077 Hz with reported u ≈ 0.015 Hz, an honest, conservative uncertainty), where a
    least-squares sine fit of the rate or the periodogram maximum gives ~1e-7 Hz: hence
    detected lines are held at the periodogram's frequency and seeds snap to them (refined on
    the Allan curve within ±1 bin, a detected frequency went to the window's edge, 1.4e-4 Hz
    off, reported ± 0.015 Hz). A sinusoid counts as white noise for the EDF of the weights.

    *Joint*: linear in ``c = (Q², N², B², K², R², σ_k²) ≥ 0`` for fixed correlation times, which
    are profiled out (grid and golden-section search in ln T). Weights ``w_i = edf_i/(2σ_i⁴)``
    (the variance of a chi-square estimate with ``edf_i`` degrees of freedom), with σ_i² the
    fitted model after the first pass (iteratively reweighted). Exact NNLS over all subsets of
    terms. Uncertainties from the sandwich covariance with the model correlation between Allan
    estimates at different τ, inflated by ``max(1, χ²/ν)``, and ``u(√c) = u(c)/(2√c)``. The
    EDFs are the Allan result's own (``confidence=`` given) or SP1065's simple
    approximations for the locally dominant noise type.

    *Goodness of fit* (both methods): the log-ratio residuals
    ``r_i = ln(σ̂²_i/σ²_i) − (ψ(ν_i/2) − ln(ν_i/2))`` (ψ the digamma function) are standardised by
    ``√ψ'(ν_i/2)`` (``σ̂²/σ² ~ χ²_ν/ν``), and ``χ² = zᵀR⁻¹z`` with ``R`` the model correlation of
    the estimates is referred to the chi-square law with ``points − parameters`` degrees of
    freedom. p < 0.001 is reported in ``diagnostics.warnings`` and in the printed summary.

    *Automatic τ range* (joint, default): long-τ points with EDF < 3 are excluded; then, while
    p < 0.01, the leading points up to the last one with ``z < −2`` before any ``z > 2`` (the curve bends below the −½ line at
    short τ: a sensor's anti-alias/decimation filter correlates the samples) or the trailing
    run with ``z > 2`` (drift) is excluded and the model refitted, keeping at least half of the
    points. ``diagnostics.excluded`` says what was dropped and why.

    *IEEE read-off*: local slopes by central differences in log-log; the longest run of points
    within ``slope_tolerance`` of −1, −½, +½, +1 is fitted with a line of that fixed slope and
    read at τ = √3, 1, 3, √2 s for Q, N, K, R; ``B = min σ / 0.664282`` when the minimum lies
    inside the curve. Uncertainty: the relative standard deviation ``1/√(2·edf)`` of the most
    precise point used. The read-off of B is biased high where the neighbouring asymptotes
    still contribute at the minimum (SPEC §3: 3.6 instead of 3 deg/h on an 8 h log). Its
    diagnostics test the read-off model on every point.

    *Upper bounds* (both methods): a requested term without a value gets the largest
    coefficient ``c`` whose asymptote stays under the one-sided upper confidence bound of the
    curve at every τ used, ``c²·g(τ_i) ≤ σ̂²_i·edf_i/χ²_{edf_i}(1 − bound_confidence)``, the
    other terms held at zero (``gyrocore::noise::bound``; SPEC "Third wave"). At each τ the
    true variance lies under its bound with probability ``bound_confidence``; the bound of an
    invisible term then covers the truth at least about that often (measured: 95 % → ≥ 95 %
    of simulated logs, tests/test_bounds.py).

    References
    ----------
    IEEE Std 952-1997 Annex C; NIST SP 1065 §5 (EDF); [NR] Table 1.

    Examples
    --------
    >>> import gyrobias
    >>> rate = gyrobias.noise.simulate(360_000, 100.0, arw=0.2 / 60, bias_instability=3 / 3600, seed=1)
    >>> r = gyrobias.allan.adev(rate, 100.0, confidence=None, units="deg/s")
    >>> c = gyrobias.noise.fit(r).to("ieee")
    >>> round(c.N.value, 2), c.N.unit
    (0.2, 'deg/√h')
    >>> c.diagnostics.passed
    True
    """
    if not hasattr(allan, "avar"):
        if isinstance(allan, (str, bytes)) or not isinstance(allan, Sequence):
            raise TypeError(
                f"allan must be an AllanResult or a sequence of them, got {type(allan).__name__}"
            )
        return _each(
            list(allan),
            lambda a: fit(
                a,
                method=method,
                terms=terms,
                tau_range=tau_range,
                regions=regions,
                slope_tolerance=slope_tolerance,
                min_points=min_points,
                unit=unit,
                correlation_time=correlation_time,
                auto_range=auto_range,
                lines=lines,
                bound_confidence=bound_confidence,
            ),
        )
    result: AllanResult = allan  # type: ignore[assignment]
    method = choice("method", method, ("joint", "ieee"))
    if result.kind != "adev":
        raise ValueError(
            f"allan must be an Allan-deviation result (kind 'adev'); the five-term model does not "
            f"hold for kind {result.kind!r}"
        )
    term_list_in = names("terms", terms)
    want_sine = "S" in term_list_in
    line_windows, detected, held_uncertainty = _line_windows(result, lines)
    if want_sine and not line_windows:
        raise ValueError(
            "terms contains 'S' but there is no line to model: pass lines=[f0, ...] (Hz) or "
            "the SpectralLine objects of gyrobias.noise.detect_lines"
        )
    term_list = [t for t in term_list_in if t != "S"]
    # The symbols are parsed by the core (noise::parse_model_terms), whose message names terms.
    data_unit = text("unit", unit) if unit is not None else result.unit
    sensor: str | None = None
    if data_unit is not None:
        sensor = sensor_kind(data_unit)
    if tau_range is not None:  # low < high: the core's check
        tau_range = pair("tau_range", tau_range)
    if correlation_time is not None:
        correlation_time = pair("correlation_time", correlation_time)
    # The read-off's options are refused even when the joint fit ignores them (NumPy/SciPy
    # convention): the range is the core's check, called here before either method runs.
    _core.validate.positive("slope_tolerance", real("slope_tolerance", slope_tolerance))
    min_points = count("min_points", min_points)
    auto_range = boolean("auto_range", auto_range)
    bound_confidence = real("bound_confidence", bound_confidence)  # (0, 1): the core's check
    taus = np.ascontiguousarray(result.taus, dtype=np.float64)
    variance = np.ascontiguousarray(result.avar, dtype=np.float64)
    # Integer arrays: converted by the binding, which names m / n_terms if an element is
    # negative, too large or not an integer (a cast to uint64 here would wrap -1 silently).
    m = result.m
    n_terms = result.n_terms
    edf = None if result.edf is None else np.ascontiguousarray(result.edf, dtype=np.float64)
    raw: Mapping[str, Any]
    if method == "joint":
        if regions is not None:
            raise ValueError(
                "regions applies to method='ieee' only; use tau_range for the joint fit"
            )
        raw = _core.noise.fit(
            taus,
            variance,
            m,
            n_terms,
            result.overlapping,
            edf,
            term_list,
            tau_range,
            correlation_time,
            auto_range,
            line_windows,
            bound_confidence,
            result.data_variance,
        )
        diagnostics_raw = raw["diagnostics"]
    else:
        if want_sine:
            raise ValueError(
                "the sinusoidal term 'S' needs method='joint' (or gyrobias.noise.gmwm)"
            )
        if any(t in _GM_SYMBOLS for t in term_list):
            raise ValueError(
                "Gauss–Markov terms ('GM', 'GM2') need method='joint' (or gyrobias.noise.gmwm)"
            )
        # slope_tolerance > 0 and min_points >= 1 are the core's checks.
        slope_tolerance = real("slope_tolerance", slope_tolerance)
        min_points = integer("min_points", min_points)
        region_list: list[tuple[float, float] | None] = [None] * 5
        for key, rng in (regions or {}).items():
            choice("regions key", key, _SYMBOLS)
            lo, hi = (float(v) for v in rng)
            region_list[_SYMBOLS.index(key)] = (lo, hi)
        raw = _core.noise.read_off(
            taus,
            variance,
            m,
            n_terms,
            result.overlapping,
            edf,
            term_list,
            region_list,
            slope_tolerance,
            int(min_points),
            bound_confidence,
        )
        read = [0.0 if d["value"] is None else float(d["value"]) ** 2 for d in raw["terms"]]
        diagnostics_raw = _core.noise.diagnose(
            taus,
            variance,
            m,
            n_terms,
            result.overlapping,
            edf,
            read,
            [],
            sum(v > 0.0 for v in read),
        )
    coefficients = NoiseCoefficients._from_core(
        raw,
        diagnostics_raw,
        taus,
        method=method,
        data_unit=data_unit,
        sensor=sensor,
        fs=result.fs,
        axis=result.axis,
        edf_source=_edf_source(result),
        allan=result,
        detected=detected if method == "joint" else (),
        line_uncertainties=held_uncertainty if method == "joint" else (),
    )
    return _with_stationarity(coefficients, result)


def _with_stationarity(c: NoiseCoefficients, result: AllanResult) -> NoiseCoefficients:
    """The fit with the Allan result's not-static warnings first in its diagnostics (a step,
    a motion or a warm-up makes the Allan curve describe that event, not the sensor's noise)."""
    check = result.stationarity
    if check is None or check.static or c.diagnostics is None:
        return c
    d = c.diagnostics
    return replace(c, diagnostics=replace(d, warnings=(*check.warnings, *d.warnings)))

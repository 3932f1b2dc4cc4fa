"""Conservative noise coefficients: a model that overbounds the measured Allan curve.

A filter tuned with best-fit coefficients is over-confident whenever the estimate came out low,
which is why practitioners "inflate by 10–20×". Lethander & Taylor (2023) replace the folklore
with a definite requirement: the model Allan variance must lie on or above the measured curve's
*upper confidence bound* at every τ used::

    σ²_model(τ_i) = 3Q²/τ_i² + N²/τ_i + (0.664282·B)² + K²τ_i/3 + R²τ_i²/2 ≥ U_i
    U_i = σ̂²(τ_i) · edf_i / χ²_{edf_i}(1 − p)

(one-sided level ``p``: the true variance lies below ``U_i`` with probability ``p``). Among all
such models with no term below the best fit, gyrobias takes the tightest one in the mean ratio
``(1/n) Σ σ²_model(τ_i)/U_i`` — a
linear programme solved exactly in the Rust core (``gyrocore::noise::overbound``) — and reports
each term's *inflation factor* ``√(c_j/c_best,j)`` against the best fit. An inflation of 2.3 on
N means: "to be 95 % sure of not under-stating the noise at any τ measured, multiply N by 2.3".

References
----------
.. [LT] K. A. Lethander and C. N. Taylor, "Conservative estimation of inertial sensor errors
   using Allan variance data", NAVIGATION 70(3), 2023, navi.563, doi:10.33012/navi.563.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrobias import _core, _generics
from gyrobias._validation import names, real
from gyrobias.noise._types import NoiseCoefficients, Term

__all__ = ["ConservativeCoefficients", "conservative"]

_SYMBOLS = ("Q", "N", "B", "K", "R")

#: Terms whose upper bound (:attr:`gyrobias.noise.Term.upper_bound`) a conservative set uses
#: when the fit does not identify them: the white noise and random walk every estimator file
#: needs. (Bounds of Q, B and R would add terms the files do not carry.)
_BOUNDED_TERMS = ("N", "K")


@dataclass(frozen=True)
class ConservativeCoefficients:
    """A conservative (overbounding) coefficient set and how much it inflates the best fit.

    Attributes
    ----------
    coefficients : NoiseCoefficients
        The conservative coefficients (``method="conservative"``, no uncertainties), in the
        base units of the data. Export, convert and plot them like any other set.
    best : NoiseCoefficients
        The coefficients the inflation is reported against.
    inflation : dict of str to float or None
        ``√(c_conservative / c_best)`` per term symbol (≥ 1: no term goes below the best fit);
        ``None`` where neither set has the term; ``inf`` where only the conservative set has it.
        A bounded N or K (not identified, bounded from above) is inflated against its bound.
    confidence : float
        One-sided confidence level ``p`` of the upper bound.
    taus : ndarray
        τ (s) of the points that were overbounded.
    upper_bound : ndarray
        Upper confidence bound ``U_i`` of the Allan *deviation* at ``taus`` (data unit).
    edf : ndarray
        Equivalent degrees of freedom used for each bound.
    ratio : ndarray
        ``σ²_model(τ_i) / U_i`` (variance ratio, all ≥ 1).
    """

    coefficients: NoiseCoefficients
    best: NoiseCoefficients = field(repr=False)
    inflation: dict[str, float | None]
    confidence: float
    taus: NDArray[np.float64] = field(repr=False)
    upper_bound: NDArray[np.float64] = field(repr=False)
    edf: NDArray[np.float64] = field(repr=False)
    ratio: NDArray[np.float64] = field(repr=False)

    @property
    def margin(self) -> float:
        """Smallest model/bound ratio of the Allan deviation (≥ 1: the bound holds everywhere)."""
        return float(np.sqrt(np.min(self.ratio)))

    def export(self, fmt: str, path: Any = None, **kwargs: Any) -> str:
        """Export the conservative set (see :func:`gyrobias.exports.export`)."""
        return _generics.export(self, fmt, path, **kwargs)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary: coefficients, inflation factors and the bound."""
        return {
            "confidence": self.confidence,
            "definition": (
                "model Allan variance >= one-sided upper confidence bound "
                "sigma^2 * edf / chi2_edf(1 - confidence) at every tau used (Lethander & Taylor 2023); "
                "tightest in the mean model/bound ratio"
            ),
            "inflation": {
                k: (None if v is None else (None if math.isinf(v) else v))
                for k, v in self.inflation.items()
            },
            "taus_s": self.taus.tolist(),
            "upper_bound_adev": self.upper_bound.tolist(),
            "edf": self.edf.tolist(),
            "coefficients": self.coefficients.to_dict(),
        }

    def summary(self) -> str:
        """Plain-text table: conservative value, best fit and inflation per term."""
        shown = self.coefficients.to("ieee") if self.coefficients.data_unit else self.coefficients
        best = self.best.to("ieee") if self.best.data_unit else self.best
        lines = [
            (
                f"Conservative coefficients ({100 * self.confidence:.3g} % one-sided upper bound overbounded "
                f"at {self.taus.size} τ from {self.taus[0]:.3g} to {self.taus[-1]:.3g} s; Lethander & Taylor 2023)"
            )
        ]
        for s in _SYMBOLS:
            t, b, f = shown[s], best[s], self.inflation[s]
            if t.value is None and b.value is None:
                continue
            value = "dropped" if t.value is None else f"{t.value:.4g} {t.unit or ''}"
            ref = "—" if b.value is None else f"{b.value:.4g}"
            if b.value is None and b.upper_bound is not None:
                ref = f"≤ {b.upper_bound:.4g}"
            infl = "—" if f is None else ("new term" if math.isinf(f) else f"×{f:.3g}")
            lines.append(f"  {s}  {value:<24} best fit {ref:<12} inflation {infl}")
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.summary()


def conservative(
    coefficients: NoiseCoefficients,
    confidence: float = 0.95,
    *,
    terms: Iterable[str] | None = None,
) -> ConservativeCoefficients:
    """Conservative coefficients whose model overbounds the measured curve's upper bound.

    Parameters
    ----------
    coefficients : NoiseCoefficients
        A fit of an Allan-deviation result (``noise.fit``): its curve, τ range and values.
    confidence : float
        One-sided confidence level ``p`` of the upper bound of each Allan-variance point,
        ``0 < p < 1`` (default 0.95).
    terms : iterable of {"Q", "N", "B", "K", "R"}, optional
        Terms the conservative model may use; default: the terms present in ``coefficients``.

    Returns
    -------
    ConservativeCoefficients

    Raises
    ------
    ValueError
        Coefficients without their Allan curve (e.g. from a datasheet), ``confidence``
        outside (0, 1), no usable term.

    Notes
    -----
    Upper bound of point i: ``U_i = σ̂²_i · edf_i / χ²_{edf_i}(1 − p)`` with the Allan result's
    EDF (``confidence=`` given to the analysis) or SP1065's simple approximation for the term
    dominating the best-fit model. The conservative ``c = (Q², N², B², K², R²) ≥ 0`` minimises
    ``(1/n) Σ_i σ²_model(τ_i; c)/U_i`` subject to ``σ²_model(τ_i; c) ≥ U_i`` for every point
    the fit used and ``c ≥ c_best`` (a conservative set inflates terms, it never trades one term
    for another below its estimate) — a linear programme, solved exactly by the simplex method
    in the core. A white noise N or random walk K the fit did not identify but bounds from
    above (:attr:`gyrobias.noise.Term.upper_bound`) takes the place of the best fit at its
    bound, ``c_j ≥ bound_j²``: the conservative set then carries the term (and can be exported)
    at the largest value the data allow; its inflation is reported against the bound.

    References
    ----------
    Lethander & Taylor, NAVIGATION 70(3), 2023 (doi:10.33012/navi.563); NIST SP 1065 §5.

    Examples
    --------
    >>> import gyrobias
    >>> rate = gyrobias.noise.simulate(200_000, 100.0, arw=0.2 / 60, bias_instability=3 / 3600, seed=2)
    >>> r = gyrobias.allan.adev(rate, 100.0, confidence=None, units="deg/s")
    >>> c = gyrobias.noise.fit(r).conservative(0.95)
    >>> c.margin >= 1.0, c.inflation["N"] >= 1.0
    (True, True)
    """
    if not isinstance(coefficients, NoiseCoefficients):
        raise TypeError(
            f"coefficients must be NoiseCoefficients, got {type(coefficients).__name__}"
        )
    allan = coefficients.allan
    if allan is None:
        raise ValueError(
            "coefficients: a conservative set needs the measured Allan curve; these coefficients "
            f"({coefficients.method}) carry none — fit them with gyrobias.noise.fit(allan_result)"
        )
    confidence = real("confidence", confidence)  # the range is the core's check
    reference = coefficients._squared_base()
    # A bounded N or K (a term the estimator files need that the log does not show) enters at
    # its upper bound: the conservative set assumes as much of it as the data allow.
    base = coefficients.to("base") if coefficients.data_unit is not None else coefficients
    for k, s in enumerate(_SYMBOLS):
        t = base[s]
        if s in _BOUNDED_TERMS and t.bounded and t.upper_bound is not None:
            reference[k] = max(reference[k], float(t.upper_bound) ** 2)
    if terms is None:
        allowed = [s for s, c in zip(_SYMBOLS, reference) if c > 0.0]
        if not allowed:
            raise ValueError("coefficients: no term is present to inflate (pass terms=)")
    else:
        # The symbols are parsed by the core (noise::parse_terms), whose message names terms.
        allowed = names("terms", terms)
    lo, hi = coefficients.tau_range
    tau_range = (float(lo), float(hi)) if np.isfinite(lo) and np.isfinite(hi) and hi > lo else None
    raw = _core.noise.conservative(
        np.ascontiguousarray(allan.taus, dtype=np.float64),
        np.ascontiguousarray(allan.avar, dtype=np.float64),
        allan.m,  # integer arrays: converted (and range-checked) by the binding, naming them
        allan.n_terms,
        allan.overlapping,
        None if allan.edf is None else np.ascontiguousarray(allan.edf, dtype=np.float64),
        [float(v) for v in reference],
        allowed,
        tau_range,
        float(confidence),
    )
    squared = tuple(float(v) for v in raw["squared"])
    lo_used, hi_used = (float(v) for v in raw["tau_range"])
    built: dict[str, Term] = {}
    for s, c in zip(_SYMBOLS, squared):
        t = base[s]
        built[s] = Term(
            symbol=s,
            name=t.name,
            value=math.sqrt(c) if c > 0.0 else None,
            uncertainty=None,
            unit=t.unit,
            tau_range=(lo_used, hi_used) if c > 0.0 else None,
            marker=None,
            missing=None if c > 0.0 else "not needed to overbound the curve",
        )
    cons = replace(
        coefficients,
        Q=built["Q"],
        N=built["N"],
        B=built["B"],
        K=built["K"],
        R=built["R"],
        method="conservative",
        tau_range=(lo_used, hi_used),
        chi2=None,
        dof=None,
        squared=squared,  # type: ignore[arg-type]
    )
    inflation: dict[str, float | None] = {}
    for s, f in zip(_SYMBOLS, raw["inflation"]):
        inflation[s] = None if math.isnan(f) else float(f)
    used = np.asarray(raw["used"], dtype=np.int64)
    return ConservativeCoefficients(
        coefficients=cons,
        best=coefficients,
        inflation=inflation,
        confidence=float(confidence),
        taus=np.asarray(allan.taus, dtype=np.float64)[used],
        upper_bound=np.sqrt(np.asarray(raw["bound"], dtype=np.float64)),
        edf=np.asarray(raw["edf"], dtype=np.float64),
        ratio=np.asarray(raw["ratio"], dtype=np.float64),
    )


# ``NoiseCoefficients.conservative()``: this module owns the behaviour and registers it.
_generics.conservative.register(NoiseCoefficients, conservative)

"""IEEE-952 noise coefficients of rate sensors: simulation, identification, units and exports.

The five-term model of the Allan variance of a rate signal (IEEE Std 952-1997 Annex C,
[NR] Table 1) is::

    σ²(τ) = 3Q²/τ² + N²/τ + (0.664282·B)² + K²τ/3 + R²τ²/2

with quantisation ``Q``, angle random walk ``N`` (ARW; velocity random walk VRW for an
accelerometer), bias instability ``B`` (flicker rate noise, two-sided PSD ``B²/(2πf)``; the
plateau factor is ``√(2 ln 2 / π) = 0.664282``), rate random walk ``K`` (RRW) and rate ramp ``R``.

Coefficients are stored in the base units of the data: for a rate in ``u/s`` (u = deg or rad)
``Q`` is in u, ``N`` in u/√s, ``B`` in u/s, ``K`` in u/s^1.5 and ``R`` in u/s².

References
----------
.. [IEEE952] IEEE Std 952-1997, Annex C; IEEE Std 647-2006.
.. [SP1065] W. J. Riley, "Handbook of Frequency Stability Analysis", NIST SP 1065 (2008).
.. [NR] Xue et al., "Noise reduction of MEMS gyroscope based on direct modeling for an angular
   rate signal", Micromachines 6 (2015) 266, Table 1.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, overload

import numpy as np
from numpy.typing import NDArray

from gyrobias import _core
from gyrobias._validation import (
    as_float_array,
    boolean,
    choice,
    integer,
    positive_float,
    real,
    sample_rate,
)
from gyrobias._validation import axis_names as check_axis_names
from gyrobias._validation import seed as seed_value
from gyrobias.units import CUSTOMARY, base_unit, parse_unit, sensor_kind

if TYPE_CHECKING:
    from gyrobias.allan import AllanResult
    from gyrobias.conservative import ConservativeCoefficients
    from gyrobias.exports import DiscreteNoise

__all__ = [
    "FLICKER_FACTOR",
    "TERM_NAMES",
    "FitDiagnostics",
    "GaussMarkovTerm",
    "NoiseCoefficients",
    "Term",
    "fit",
    "from_datasheet",
    "gauss_markov_avar",
    "gmwm",
    "simulate",
    "write_kalibr",
]

#: Plateau factor of flicker rate noise in the Allan deviation: √(2 ln 2 / π) = 0.664282…
#: (``gyrocore::noise::FLICKER_FACTOR``, the one definition every layer uses.)
FLICKER_FACTOR: float = _core.noise.FLICKER_FACTOR

_SYMBOLS = ("Q", "N", "B", "K", "R")
_GM_SYMBOLS = ("GM", "GM2")

#: p-value below which a fit is reported as rejected by its goodness-of-fit test.
REJECT_P: float = 0.001

#: Names of the terms for gyroscopes and accelerometers.
TERM_NAMES: dict[str, dict[str, str]] = {
    "gyro": {
        "Q": "quantization noise",
        "N": "angle random walk (ARW)",
        "B": "bias instability",
        "K": "rate random walk (RRW)",
        "R": "rate ramp",
    },
    "accel": {
        "Q": "velocity quantization",
        "N": "velocity random walk (VRW)",
        "B": "bias instability",
        "K": "acceleration random walk",
        "R": "acceleration ramp",
    },
}


def simulate(
    n: int,
    fs: float,
    *,
    quantization: float = 0.0,
    arw: float = 0.0,
    bias_instability: float = 0.0,
    rrw: float = 0.0,
    rate_ramp: float = 0.0,
    ar1: tuple[float, float] | None = None,
    bias: float = 0.0,
    axes: int = 1,
    seed: int | None = None,
) -> NDArray[np.float64]:
    """Simulate rate-sensor noise with exactly the given IEEE-952 coefficients.

    Parameters
    ----------
    n : int
        Number of samples per axis.
    fs : float
        Sample rate in Hz (``t0 = 1/fs``).
    quantization : float
        Quantisation noise ``Q`` in u (u·s for a rate unit u, e.g. deg for deg/s).
    arw : float
        Angle random walk ``N`` in u·√s (e.g. deg/√s; deg/√h = 60·deg/√s).
    bias_instability : float
        Bias instability ``B`` in u (e.g. deg/s; deg/h = 3600·deg/s).
    rrw : float
        Rate random walk ``K`` in u/√s (e.g. deg/s^1.5).
    rate_ramp : float
        Rate ramp ``R`` in u/s (e.g. deg/s²). May be negative.
    ar1 : (c, sigma) or None
        AR(1) (Gauss–Markov) drift ``b_{k+1} = c·b_k + sigma·ξ_k`` with ``|c| < 1``, started
        from its stationary distribution.
    bias : float
        Constant bias in u.
    axes : int
        Number of independent axes.
    seed : int or None
        Seed (0 ≤ seed < 2**64). The same seed gives the same samples; axis ``a`` does not
        depend on ``axes`` and each component has its own stream. ``None`` draws a fresh seed.

    Returns
    -------
    ndarray
        Shape ``(n,)`` for ``axes == 1``, else ``(n, axes)``, in the rate unit u.

    Raises
    ------
    ValueError
        Negative coefficients, ``n < 1``, ``fs <= 0``, ``|c| >= 1``.

    Notes
    -----
    Sample ``k`` is the sum of: white rate ``N/√t0·ξ_k``; quantisation as white angle noise of
    standard deviation ``Q`` differenced, ``Q(η_{k+1} − η_k)/t0``; flicker rate noise by
    spectral shaping of white noise to the two-sided PSD ``S(f) = B²/(2πf)`` (FFT of length
    ≥ 2n, first n samples kept); rate random walk ``Σ_{i≤k} K√t0·ξ_i``; ramp ``R·k·t0``;
    AR(1) drift; bias. Their Allan variances are ``3Q²/τ²``, ``N²/τ``, ``(0.664282 B)²``
    (τ ≫ t0), ``K²τ/3`` and ``R²τ²/2``.

    Examples
    --------
    >>> import gyrobias
    >>> rate = gyrobias.noise.simulate(1000, 100.0, arw=0.2 / 60, axes=3, seed=1)
    >>> rate.shape
    (1000, 3)
    """
    # Types here; every range (n, axes >= 1, fs > 0, coefficients >= 0, |c| < 1) is the core's.
    n = integer("n", n)
    axes = integer("axes", axes)
    ar: tuple[float, float] | None = None
    if ar1 is not None:
        try:
            c, s = ar1
        except (TypeError, ValueError):
            raise TypeError(f"ar1 must be a pair (c, sigma) or None, got {ar1!r}") from None
        ar = (real("ar1 coefficient", c), real("ar1 sigma", s))
    flat = _core.noise.simulate(
        n,
        real("fs", fs),
        real("quantization", quantization),
        real("arw", arw),
        real("bias_instability", bias_instability),
        real("rrw", rrw),
        real("rate_ramp", rate_ramp),
        ar,
        real("bias", bias),
        axes,
        seed_value("seed", seed),
    )
    return flat if axes == 1 else flat.reshape(n, axes)


# --- identified coefficients ---------------------------------------------------------------------


@dataclass(frozen=True)
class Term:
    """One noise coefficient with its standard uncertainty and unit, or why it is missing.

    Attributes
    ----------
    symbol : {"Q", "N", "B", "K", "R"}
        IEEE-952 symbol.
    name : str
        Long name (ARW / VRW etc. depending on the sensor).
    value : float or None
        The coefficient in ``unit``; ``None`` when the term is missing.
    uncertainty : float or None
        Standard (1σ) uncertainty in ``unit``.
    unit : str or None
        Unit of ``value`` and ``uncertainty`` (``None`` if the data unit is unknown).
    tau_range : (float, float) or None
        τ range in seconds of the Allan points that determined the term (read-off: the slope
        region used; joint fit: where the term is ≥ 10 % of the fitted variance).
    marker : (float, float) or None
        (τ [s], σ [data unit]) of the read-off point on an Allan plot: on the term's asymptote at
        τ = √3, 1, 3, √2 s for Q, N, K, R; at the minimum (σ = 0.664·B) for B.
    missing : str or None
        Why the term is missing (``value is None``).
    """

    symbol: str
    name: str
    value: float | None
    uncertainty: float | None
    unit: str | None
    tau_range: tuple[float, float] | None = None
    marker: tuple[float, float] | None = None
    missing: str | None = None

    @property
    def present(self) -> bool:
        """True when the term was identified."""
        return self.value is not None

    def to(self, unit: str) -> Term:
        """This term converted to ``unit`` (e.g. ``"deg/h"``, ``"rad/s/√Hz"``).

        Raises
        ------
        ValueError
            Unknown unit (the message lists the valid symbols and customary units), a unit of
            another dimension, or a term whose data unit is unknown.
        """
        if self.unit is None:
            raise ValueError(
                f"term {self.symbol} has no unit (the data unit was not given): pass units= to the "
                "Allan analysis or unit= to gyrobias.noise.fit"
            )
        target = parse_unit(unit)
        source = parse_unit(self.unit)
        if target.dims != source.dims:
            raise ValueError(
                f"cannot express {self.symbol} ({self.name}, in {self.unit}) in {unit!r}: different "
                f"dimensions; customary units for it: "
                + ", ".join(
                    sorted(
                        {
                            s[self.symbol]
                            for k in CUSTOMARY.values()
                            for s in k.values()
                            if self.symbol in s
                        }
                    )
                )
            )
        f = source.factor / target.factor
        return replace(
            self,
            value=None if self.value is None else self.value * f,
            uncertainty=None if self.uncertainty is None else self.uncertainty * f,
            unit=unit,
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary."""
        return {
            "symbol": self.symbol,
            "name": self.name,
            "value": self.value,
            "uncertainty": self.uncertainty,
            "unit": self.unit,
            "tau_range_s": None if self.tau_range is None else list(self.tau_range),
            "missing": self.missing,
        }

    def __str__(self) -> str:
        unit = f" {self.unit}" if self.unit else ""
        if self.value is None:
            return f"{self.symbol} ({self.name}): missing — {self.missing}"
        if self.uncertainty is None:  # datasheet values and conservative sets carry none
            return f"{self.symbol} ({self.name}) = {self.value:.4g}{unit}"
        return f"{self.symbol} ({self.name}) = {self.value:.4g} ± {self.uncertainty:.2g}{unit}"


@dataclass(frozen=True)
class GaussMarkovTerm:
    """A first-order Gauss–Markov (exponentially correlated) rate term.

    The process has autocovariance ``σ² exp(−|t|/T)`` and the Allan variance
    ``σ²(τ) = (σ²T²/τ²)(2τ/T − 3 + 4e^{−τ/T} − e^{−2τ/T})`` (IEEE Std 952-1997 Annex C).

    Attributes
    ----------
    sigma : Term
        Standard deviation σ of the process (rate unit of the data, e.g. deg/s).
    correlation_time : Term
        Correlation time T in seconds (the bias correlation time of an INS filter's
        first-order Gauss–Markov state).
    tau_range : (float, float) or None
        τ range (s) of the Allan points where the term is ≥ 10 % of the fitted variance.
    missing : str or None
        Why the term is missing.
    """

    sigma: Term
    correlation_time: Term
    tau_range: tuple[float, float] | None = None
    missing: str | None = None

    @property
    def present(self) -> bool:
        """True when the term was identified."""
        return self.sigma.value is not None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary."""
        return {
            "sigma": self.sigma.to_dict(),
            "correlation_time": self.correlation_time.to_dict(),
            "tau_range_s": None if self.tau_range is None else list(self.tau_range),
            "missing": self.missing,
        }

    def __str__(self) -> str:
        if not self.present:
            return f"{self.sigma.symbol} (Gauss–Markov): missing — {self.missing}"
        tc = self.correlation_time
        spread = f" ± {tc.uncertainty:.2g}" if tc.uncertainty is not None else ""
        return f"{self.sigma} with correlation time {tc.value:.4g}{spread} s"


@dataclass(frozen=True)
class FitDiagnostics:
    """Goodness of fit of an identification and what it left out.

    Attributes
    ----------
    chi2 : float
        Generalised chi-square ``zᵀR⁻¹z`` of the standardised log-ratio residuals ``z`` with the
        model correlation ``R`` of the Allan estimates (see :func:`fit`, Notes).
    dof : int
        Degrees of freedom (points used − fitted parameters).
    p_value : float
        Probability of a χ² at least this large if the model were right (NaN without degrees of
        freedom). Below 0.001 the fit is rejected and :attr:`warnings` says so.
    residuals : ndarray
        Standardised residual of each Allan point (about N(0, 1) if the model holds; NaN where
        the point was excluded).
    taus : ndarray
        τ (s) of each residual.
    tau_range : (float, float)
        τ range (s) of the points used.
    excluded : tuple of (float, float, str)
        Excluded τ ranges (s) with the reason.
    warnings : tuple of str
        Plain sentences about anything to know before trusting the numbers.
    """

    chi2: float
    dof: int
    p_value: float
    residuals: NDArray[np.float64] = field(repr=False, compare=False)
    taus: NDArray[np.float64] = field(repr=False, compare=False)
    tau_range: tuple[float, float]
    excluded: tuple[tuple[float, float, str], ...] = ()
    warnings: tuple[str, ...] = ()

    @property
    def passed(self) -> bool:
        """True unless the goodness-of-fit test rejects the model (p < 0.001)."""
        return not (self.p_value < REJECT_P)

    @classmethod
    def _from_raw(cls, raw: Mapping[str, Any], taus: NDArray[np.float64]) -> FitDiagnostics:
        return cls(
            chi2=float(raw["chi2"]),
            dof=int(raw["dof"]),
            p_value=float(raw["p_value"]),
            residuals=np.asarray(raw["residuals"], dtype=np.float64),
            taus=np.asarray(taus, dtype=np.float64).copy(),
            tau_range=(float(raw["tau_range"][0]), float(raw["tau_range"][1])),
            excluded=tuple((float(a), float(b), str(r)) for a, b, r in raw["excluded"]),
            warnings=tuple(str(w) for w in raw["warnings"]),
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (NaN residuals become ``None``)."""
        return {
            "chi2": self.chi2,
            "dof": self.dof,
            "p_value": None if not np.isfinite(self.p_value) else self.p_value,
            "passed": self.passed,
            "tau_range_s": list(self.tau_range),
            "residuals": [None if not np.isfinite(v) else float(v) for v in self.residuals],
            "taus_s": [float(t) for t in self.taus],
            "excluded": [
                {"tau_low_s": a, "tau_high_s": b, "reason": r} for a, b, r in self.excluded
            ],
            "warnings": list(self.warnings),
        }

    def summary(self) -> str:
        """Plain-text lines: the test, the excluded ranges and the warnings."""
        verdict = "passed" if self.passed else "REJECTED"
        lines = [
            f"  goodness of fit: χ² = {self.chi2:.4g}, ν = {self.dof}, p = {self.p_value:.3g} ({verdict})"
        ]
        for a, b, r in self.excluded:
            lines.append(f"  excluded τ {a:.3g}–{b:.3g} s: {r}")
        for w in self.warnings:
            lines.append(f"  WARNING: {w}")
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.summary()


@dataclass(frozen=True)
class NoiseCoefficients:
    """IEEE-952 noise coefficients identified from one Allan curve.

    Attributes
    ----------
    Q, N, B, K, R : Term
        Quantisation, angle (velocity) random walk, bias instability, rate (acceleration) random
        walk and rate ramp. Values in the base units of the data unless converted with
        :meth:`to`.
    method : {"joint", "ieee"}
        Identification method.
    data_unit : str or None
        Unit of the rate data (``"deg/s"``, ``"rad/s"``, ``"m/s^2"``, …).
    sensor : {"gyro", "accel"} or None
        Derived from ``data_unit``.
    fs : float
        Sample rate of the data in Hz.
    axis : str or None
        Axis name.
    tau_range : (float, float)
        τ range (s) of the Allan points the identification used.
    edf_source : str
        Where the weights' EDF came from: ``"noise identification"`` (the Allan result's EDF)
        or ``"SP1065 simple approximation"``.
    chi2, dof : float or None, int or None
        Weighted residual sum of squares and degrees of freedom of the joint fit.
    squared : tuple of float or None
        Fitted Q², N², B², K², R² in base units (joint fit), used to draw the model.
    gauss_markov : tuple of GaussMarkovTerm
        First-order Gauss–Markov terms (``terms`` containing ``"GM"``/``"GM2"``), sorted by
        correlation time.
    diagnostics : FitDiagnostics or None
        Goodness of fit, excluded τ ranges and warnings (always set by :func:`fit` and
        :func:`gmwm`; ``None`` only for coefficients that did not come from data).
    allan : AllanResult or None
        The curve the coefficients came from (for plotting).
    """

    Q: Term
    N: Term
    B: Term
    K: Term
    R: Term
    method: str
    data_unit: str | None
    sensor: str | None
    fs: float
    tau_range: tuple[float, float]
    edf_source: str
    axis: str | None = None
    chi2: float | None = None
    dof: int | None = None
    squared: tuple[float, float, float, float, float] | None = None
    gauss_markov: tuple[GaussMarkovTerm, ...] = ()
    diagnostics: FitDiagnostics | None = None
    allan: AllanResult | None = field(default=None, repr=False, compare=False)

    @property
    def terms(self) -> tuple[Term, Term, Term, Term, Term]:
        """(Q, N, B, K, R)."""
        return (self.Q, self.N, self.B, self.K, self.R)

    def __getitem__(self, symbol: str) -> Term:
        return {"Q": self.Q, "N": self.N, "B": self.B, "K": self.K, "R": self.R}[
            choice("symbol", symbol, _SYMBOLS)
        ]

    @property
    def quantization(self) -> Term:
        """Q."""
        return self.Q

    @property
    def arw(self) -> Term:
        """N (angle random walk; VRW for an accelerometer)."""
        return self.N

    @property
    def bias_instability(self) -> Term:
        """B."""
        return self.B

    @property
    def rrw(self) -> Term:
        """K (rate random walk)."""
        return self.K

    @property
    def rate_ramp(self) -> Term:
        """R."""
        return self.R

    def to(self, system: str | Mapping[str, str] = "ieee") -> NoiseCoefficients:
        """Coefficients converted to customary units.

        Parameters
        ----------
        system : {"ieee", "si", "kalibr", "base"} or mapping
            ``"ieee"``: gyro Q deg, N deg/√h, B deg/h, K deg/h^1.5, R deg/h²; accelerometer
            Q m/s, N m/s/√h, B mg, K m/s/h^1.5, R m/s/h². ``"si"`` (= ``"kalibr"``): gyro rad,
            rad/s/√Hz, rad/s, rad/s²/√Hz, rad/s²; accelerometer m/s, m/s²/√Hz, m/s², m/s³/√Hz,
            m/s³. ``"base"``: the data's base units. A mapping such as
            ``{"N": "deg/√h", "B": "deg/h"}`` converts only the terms it names.

        Raises
        ------
        ValueError
            Unknown system or unit string (listing the valid ones), unknown data unit.
        """
        if isinstance(system, str):
            choice("system", system, ("ieee", "si", "kalibr", "base"))
            if self.data_unit is None or self.sensor is None:
                raise ValueError(
                    "the data unit is unknown: pass units= to the Allan analysis (e.g. 'deg/s') "
                    "or unit= to gyrobias.noise.fit"
                )
            if system == "base":
                mapping = {s: base_unit(self.data_unit, s) for s in _SYMBOLS}
            else:
                mapping = CUSTOMARY[self.sensor][system]
        else:
            mapping = dict(system)
            for key in mapping:
                choice("system key", key, _SYMBOLS)
        conv = {s: self[s].to(mapping[s]) if s in mapping else self[s] for s in _SYMBOLS}
        gm = self.gauss_markov
        if "B" in mapping:  # σ of a Gauss–Markov term has the dimension of B (a rate)
            gm = tuple(
                replace(g, sigma=g.sigma.to(mapping["B"])) if g.sigma.unit is not None else g
                for g in gm
            )
        return replace(
            self, Q=conv["Q"], N=conv["N"], B=conv["B"], K=conv["K"], R=conv["R"], gauss_markov=gm
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary with units and conventions stated."""
        return {
            "method": self.method,
            "axis": self.axis,
            "sensor": self.sensor,
            "data_unit": self.data_unit,
            "fs_hz": self.fs,
            "tau_range_s": list(self.tau_range),
            "edf_source": self.edf_source,
            "chi2": self.chi2,
            "dof": self.dof,
            "model": "sigma^2(tau) = 3Q^2/tau^2 + N^2/tau + (0.664282 B)^2 + K^2 tau/3 + R^2 tau^2/2"
            " + sum_k sigma_k^2 T_k^2/tau^2 (2 tau/T_k - 3 + 4 exp(-tau/T_k) - exp(-2 tau/T_k))",
            "psd_convention": "two-sided (IEEE 952): white rate noise of per-sample std s at period t0 has N = s*sqrt(t0)",
            "uncertainty": "standard (1 sigma)",
            "terms": {t.symbol: t.to_dict() for t in self.terms},
            "gauss_markov": [g.to_dict() for g in self.gauss_markov],
            "diagnostics": None if self.diagnostics is None else self.diagnostics.to_dict(),
        }

    def to_json(self, path: str | os.PathLike[str] | None = None, **kwargs: Any) -> str:
        """:meth:`to_dict` as JSON; also written to ``path`` when given."""
        kwargs.setdefault("indent", 2)
        text = json.dumps(self.to_dict(), **kwargs)
        if path is not None:
            from gyrobias.exports import atomic_write

            atomic_write(path, text + "\n")
        return text

    def summary(self) -> str:
        """A plain-text table of the coefficients with uncertainties, units and τ ranges."""
        sensor = self.sensor or "sensor"
        axis = f" axis {self.axis}" if self.axis else ""
        lines = [
            f"Noise coefficients{axis} ({sensor}, {self.method} identification, "
            f"τ {self.tau_range[0]:.3g}–{self.tau_range[1]:.3g} s, EDF: {self.edf_source})"
        ]
        names = TERM_NAMES.get(self.sensor or "gyro", TERM_NAMES["gyro"])
        for t in self.terms:
            label = f"  {t.symbol}  {names[t.symbol]:<27}"
            if t.value is None:
                lines.append(f"{label} missing: {t.missing}")
                continue
            unc = f"{t.uncertainty:.2g}" if t.uncertainty is not None else "?"
            rng = f"  (τ {t.tau_range[0]:.3g}–{t.tau_range[1]:.3g} s)" if t.tau_range else ""
            if t.uncertainty is not None and t.value < 2.0 * t.uncertainty:
                rng += "  not significant (< 2σ)"
            lines.append(f"{label} {t.value:12.5g} ± {unc:<8} {t.unit or '':<12}{rng}")
        for g in self.gauss_markov:
            label = f"  {g.sigma.symbol:<3}{'Gauss–Markov σ, T':<26}"
            if not g.present:
                lines.append(f"{label} missing: {g.missing}")
                continue
            t = g.correlation_time
            lines.append(
                f"{label} {g.sigma.value:12.5g} ± {g.sigma.uncertainty or float('nan'):<8.2g} "
                f"{g.sigma.unit or '':<12}  T = {t.value:.4g} ± {t.uncertainty or float('nan'):.2g} s"
            )
        if self.diagnostics is not None:
            lines.append(self.diagnostics.summary())
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.summary()

    def to_kalibr(
        self,
        path: str | os.PathLike[str],
        *,
        update_rate: float | None = None,
        rostopic: str = "/imu0",
    ) -> str:
        """Write a Kalibr ``imu.yaml`` with this axis' coefficients (see :func:`write_kalibr`)."""
        if self.sensor == "accel":
            return write_kalibr(path, accel=[self], update_rate=update_rate, rostopic=rostopic)
        return write_kalibr(path, gyro=[self], update_rate=update_rate, rostopic=rostopic)

    # Estimator parameters (issue 13): thin delegations to gyrobias.conservative/exports.
    def conservative(
        self, confidence: float = 0.95, *, terms: Iterable[str] | None = None
    ) -> ConservativeCoefficients:
        """Coefficients whose model overbounds the curve's upper confidence bound at every τ.

        See :func:`gyrobias.conservative.conservative` (Lethander & Taylor 2023).
        """
        from gyrobias.conservative import conservative

        return conservative(self, confidence, terms=terms)

    def export(
        self,
        fmt: str,
        path: str | os.PathLike[str] | None = None,
        *,
        accel: NoiseCoefficients | Sequence[NoiseCoefficients] | None = None,
        rate: float | None = None,
        rostopic: str = "/imu0",
    ) -> str:
        """Write an estimator parameter file (kalibr, openvins, vins, orbslam3, liosam, matlab, json).

        See :func:`gyrobias.exports.export`.
        """
        from gyrobias.exports import export

        return export(self, fmt, path, accel=accel, rate=rate, rostopic=rostopic)

    def discrete(self, rate: float) -> DiscreteNoise:
        """Per-sample noise parameters at ``rate`` Hz (see :func:`gyrobias.exports.discrete`)."""
        from gyrobias.exports import discrete

        return discrete(self, rate)

    def model(self, taus: Any) -> tuple[NDArray[np.float64], dict[str, NDArray[np.float64]]]:
        """Model Allan deviation at ``taus`` and each term's asymptote (data units).

        For the read-off, the model is built from the identified coefficients (missing terms
        count as zero).
        """
        t = np.ascontiguousarray(np.asarray(taus, dtype=np.float64))
        squared = self._squared_base()
        total, parts = _core.noise.model(squared, t)
        out = {s: np.sqrt(p) for s, p in zip(_SYMBOLS, parts)}
        gm = self._gauss_markov_base()
        if gm:
            for g, v in zip(self.gauss_markov, _core.noise.gauss_markov_variance(gm, t)):
                total = total + v
                out[g.sigma.symbol] = np.sqrt(v)
        return np.sqrt(total), out

    def _gauss_markov_base(self) -> list[tuple[float, float]]:
        base = self.to("base") if self.data_unit is not None else self
        return [
            (float(g.sigma.value) ** 2, float(g.correlation_time.value))
            for g in base.gauss_markov
            if g.sigma.value is not None and g.correlation_time.value is not None
        ]

    def _squared_base(self) -> list[float]:
        if self.squared is not None:
            return list(self.squared)
        base = self.to("base") if self.data_unit is not None else self
        return [0.0 if t.value is None else float(t.value) ** 2 for t in base.terms]

    def plot(
        self, ax: Any = None, *, allan: AllanResult | None = None, show_data: bool = True
    ) -> Any:
        """Draw the fitted model, each term's asymptote and the labelled read-off points.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Axes to draw on (a new figure otherwise).
        allan : AllanResult, optional
            The Allan curve to draw beneath (defaults to the one the coefficients came from).
        show_data : bool
            Draw the Allan deviation points (set False when the caller has drawn them).

        Returns
        -------
        matplotlib Axes
            Drawn by :func:`gyrobias.plotting.plot_noise_model`.
        """
        from gyrobias.plotting import plot_noise_model

        return plot_noise_model(self, ax, allan=allan, show_data=show_data)


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
    tau = as_float_array("taus", np.atleast_1d(np.asarray(taus, dtype=np.float64)), ndims=(1,))
    return _core.noise.gauss_markov_avar(
        real("sigma", sigma), real("correlation_time", correlation_time), tau
    )


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
    terms : iterable of {"Q", "N", "B", "K", "R", "GM", "GM2"}
        Terms to identify; the others are reported missing ("not requested"). ``"GM"`` adds a
        first-order Gauss–Markov term, ``"GM2"`` a second one (joint fit only).
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
        or methods, a region that contains no τ, a Gauss–Markov term with ``method="ieee"`` or
        a ``correlation_time`` range outside the data's τ range.

    Notes
    -----
    Model: ``σ²(τ) = 3Q²/τ² + N²/τ + (0.664282·B)² + K²τ/3 + R²τ²/2`` plus, per Gauss–Markov
    term of standard deviation σ and correlation time T,
    ``(σ²T²/τ²)(2τ/T − 3 + 4e^{−τ/T} − e^{−2τ/T})`` (IEEE Std 952-1997 Annex C; white noise
    ``N² = 2σ²T`` for τ ≫ T, random walk ``K² = 2σ²/T`` for τ ≪ T).

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
    p < 0.01, the leading run of points with ``z < −2`` (the curve bends below the −½ line at
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
        return tuple(
            fit(
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
            )
            for a in allan
        )
    result: AllanResult = allan  # type: ignore[assignment]
    method = choice("method", method, ("joint", "ieee"))
    if result.kind != "adev":
        raise ValueError(
            f"allan must be an Allan-deviation result (kind 'adev'); the five-term model does not "
            f"hold for kind {result.kind!r}"
        )
    term_list = [str(t) for t in terms] if not isinstance(terms, str) else [terms]
    # The symbols are parsed by the core (noise::parse_model_terms), whose message names terms.
    data_unit = unit if unit is not None else result.unit
    sensor: str | None = None
    if data_unit is not None:
        sensor = sensor_kind(data_unit)
    if tau_range is not None:  # low < high: the core's check
        lo, hi = (real("tau_range", v) for v in tau_range)
        tau_range = (lo, hi)
    if correlation_time is not None:
        try:
            t_lo, t_hi = (float(v) for v in correlation_time)
        except (TypeError, ValueError):
            raise TypeError(
                f"correlation_time must be a pair (low, high) of seconds, got {correlation_time!r}"
            ) from None
        correlation_time = (t_lo, t_hi)
    auto_range = boolean("auto_range", auto_range)
    taus = np.ascontiguousarray(result.taus, dtype=np.float64)
    variance = np.ascontiguousarray(result.avar, dtype=np.float64)
    # Integer arrays: converted by the binding, which names m / n_terms if an element is
    # negative, too large or not an integer (a cast to uint64 here would wrap -1 silently).
    m = result.m
    n_terms = result.n_terms
    edf = None if result.edf is None else np.ascontiguousarray(result.edf, dtype=np.float64)
    gm_raw: list[_core.noise.GaussMarkovTerm] = []
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
        )
        extra: dict[str, Any] = {
            "chi2": float(raw["chi2"]),
            "dof": int(raw["dof"]),
            "squared": tuple(float(v) for v in raw["squared"]),
            "tau_range": tuple(raw["tau_range"]),
        }
        gm_raw = list(raw["gauss_markov"])
        diagnostics_raw = raw["diagnostics"]
    else:
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
        )
        extra = {"tau_range": (float(taus[0]), float(taus[-1]))}
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
    return _assemble(
        raw["terms"],
        gm_raw,
        diagnostics_raw,
        taus,
        method=method,
        data_unit=data_unit,
        sensor=sensor,
        fs=result.fs,
        axis=result.axis,
        edf_source=_edf_source(result),
        allan=result,
        extra=extra,
    )


def _assemble(
    term_dicts: Sequence[Mapping[str, Any]],
    gm_dicts: Sequence[Mapping[str, Any]],
    diagnostics_raw: Mapping[str, Any],
    taus: NDArray[np.float64],
    *,
    method: str,
    data_unit: str | None,
    sensor: str | None,
    fs: float,
    axis: str | None,
    edf_source: str,
    allan: AllanResult | None,
    extra: Mapping[str, Any],
) -> NoiseCoefficients:
    """Typed result from the core's dictionaries (shared by :func:`fit` and :func:`gmwm`)."""
    names = TERM_NAMES[sensor or "gyro"]
    built = {}
    for d in term_dicts:
        s = d["symbol"]
        built[s] = Term(
            symbol=s,
            name=names[s],
            value=d["value"],
            uncertainty=d["uncertainty"],
            unit=None if data_unit is None else base_unit(data_unit, s),
            tau_range=d["tau_range"],
            marker=d["marker"],
            missing=d["missing"],
        )
    rate_unit = None if data_unit is None else base_unit(data_unit, "B")
    gm_terms = []
    for k, g in enumerate(gm_dicts):
        symbol = "GM" if k == 0 else f"GM{k + 1}"
        rng = (
            None if g["tau_range"] is None else (float(g["tau_range"][0]), float(g["tau_range"][1]))
        )
        gm_terms.append(
            GaussMarkovTerm(
                sigma=Term(
                    symbol,
                    "Gauss–Markov σ",
                    g["sigma"],
                    g["sigma_uncertainty"],
                    rate_unit,
                    rng,
                    None,
                    g["missing"],
                ),
                correlation_time=Term(
                    symbol,
                    "Gauss–Markov correlation time",
                    g["correlation_time"],
                    g["correlation_time_uncertainty"],
                    "s",
                    rng,
                    None,
                    g["missing"],
                ),
                tau_range=rng,
                missing=g["missing"],
            )
        )
    return NoiseCoefficients(
        Q=built["Q"],
        N=built["N"],
        B=built["B"],
        K=built["K"],
        R=built["R"],
        method=method,
        data_unit=data_unit,
        sensor=sensor,
        fs=fs,
        axis=axis,
        edf_source=edf_source,
        allan=allan,
        tau_range=extra["tau_range"],
        chi2=extra.get("chi2"),
        dof=extra.get("dof"),
        squared=extra.get("squared"),
        gauss_markov=tuple(gm_terms),
        diagnostics=FitDiagnostics._from_raw(diagnostics_raw, taus),
    )


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
) -> NoiseCoefficients | tuple[NoiseCoefficients, ...]:
    """Noise model by the generalized method of wavelet moments (GMWM).

    Parameters
    ----------
    data : array_like, shape (n,) or (n, axes)
        Rate samples (e.g. deg/s); one column per axis.
    fs : float
        Sample rate in Hz.
    terms : iterable of {"Q", "N", "B", "K", "R", "GM", "GM2"}
        Composite model: quantisation, white noise (ARW), flicker (bias instability), random
        walk (RRW), drift (rate ramp) and one or two first-order Gauss–Markov terms.
    units : str, optional
        Rate unit of the data (``"deg/s"``, ``"rad/s"``, ``"m/s^2"``, …).
    axis_names : sequence of str, optional
        One name per column.
    select : bool
        Choose, among all sub-models of ``terms``, the one with the smallest wavelet-variance
        information criterion ``WVIC = J + 2p`` (Notes); the terms it drops are reported missing
        with the reason "dropped by the model selection" (and the chosen sub-model), unlike
        terms the non-negative fit sets to zero.
    bootstrap : int
        Number of parametric-bootstrap replicates for the uncertainties (0: asymptotic).
    seed : int or None
        Seed of the bootstrap (``None``: fresh).

    Returns
    -------
    NoiseCoefficients or tuple of NoiseCoefficients
        ``method="gmwm"``, with diagnostics; ``allan`` holds the Allan-variance equivalent
        ``2ν̂²`` of the wavelet variance at ``τ = 2^{j−1}/fs`` (for plots).

    Raises
    ------
    ValueError
        Constant or non-finite data, too few dyadic scales for the model, unknown terms or
        units, ``bootstrap < 0``.

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
    criterion of Andrews (1999). Scales use half-widths ``m ≤ n/8``.

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
    from gyrobias.allan import AllanResult

    arr = as_float_array("data", data, ndims=(1, 2))
    fs = sample_rate(fs)  # the core checks fs before t0 = 1/fs is formed
    term_list = [str(t) for t in terms] if not isinstance(terms, str) else [terms]
    # The symbols are parsed by the core (noise::parse_model_terms), whose message names terms.
    select = boolean("select", select)
    replicates = integer("bootstrap", bootstrap)
    seed_number = seed_value("seed", seed)
    sensor = sensor_kind(units) if units is not None else None
    matrix = arr.reshape(-1, 1) if arr.ndim == 1 else arr
    n_axes = matrix.shape[1]
    check_axis_names(axis_names, n_axes)
    t0 = 1.0 / fs
    out = []
    for a in range(n_axes):
        column = np.ascontiguousarray(matrix[:, a], dtype=np.float64)
        raw = _core.noise.gmwm(column, t0, term_list, select, replicates, seed_number, 8)
        wv = raw["wavelet"]
        m = np.asarray(wv["m"]).astype(np.int64)
        name = None if axis_names is None else str(axis_names[a])
        allan = AllanResult(
            taus=np.asarray(m * t0, dtype=np.float64),
            avar=2.0 * np.asarray(wv["variance"], dtype=np.float64),
            n_terms=np.asarray(wv["n_coefficients"]).astype(np.int64),
            fs=fs,
            data_type="rate",
            kind="adev",
            overlapping=True,
            unit=units,
            axis=name,
        )
        out.append(
            _assemble(
                raw["terms"],
                raw["gauss_markov"],
                raw["diagnostics"],
                np.asarray(allan.taus, dtype=np.float64),
                method="gmwm",
                data_unit=units,
                sensor=sensor,
                fs=fs,
                axis=name,
                edf_source="SP1065 simple approximation",
                allan=allan,
                extra={
                    "chi2": float(raw["chi2"]),
                    "dof": int(raw["dof"]),
                    "squared": tuple(float(v) for v in raw["squared"]),
                    "tau_range": tuple(raw["tau_range"]),
                },
            )
        )
    if arr.ndim == 1:
        return out[0]
    return tuple(out)


# --- Kalibr --------------------------------------------------------------------------------------


def _worst(
    coefficients: Sequence[NoiseCoefficients], symbol: str, unit: str
) -> tuple[float | None, str]:
    """Largest value over axes (the conservative choice for a filter) and a comment."""
    values = []
    missing = []
    for c in coefficients:
        t = c[symbol]
        if t.value is None:
            missing.append(f"{c.axis or '?'}: {t.missing}")
        else:
            values.append((t.to(unit).value, c.axis))
    if not values:
        return None, "; ".join(missing)
    best = max(values, key=lambda v: float(v[0] or 0.0))
    axes = ", ".join(str(c.axis) for c in coefficients if c.axis) or f"{len(coefficients)} axis(es)"
    return best[0], f"max over {axes}"


def write_kalibr(
    path: str | os.PathLike[str],
    *,
    gyro: Sequence[NoiseCoefficients] = (),
    accel: Sequence[NoiseCoefficients] = (),
    update_rate: float | None = None,
    rostopic: str = "/imu0",
) -> str:
    """Write a Kalibr ``imu.yaml`` (no YAML library needed) and return its text.

    Parameters
    ----------
    path : path-like
        Output file.
    gyro, accel : sequence of NoiseCoefficients
        Per-axis coefficients of the gyroscopes (rate unit deg/s, rad/s, …) and
        accelerometers (m/s², g, …). Each value is the largest over the axes given.
    update_rate : float, optional
        IMU rate in Hz (Kalibr discretises with it); default: the data's sample rate.
    rostopic : str
        Kalibr's ``rostopic`` entry.

    Returns
    -------
    str
        The file's text.

    Notes
    -----
    Kalibr's parameters are continuous-time densities: ``gyroscope_noise_density`` = N in
    rad/s/√Hz, ``gyroscope_random_walk`` = K in rad/s²/√Hz, ``accelerometer_noise_density`` =
    N in m/s²/√Hz, ``accelerometer_random_walk`` = K in m/s³/√Hz. Kalibr discretises them as
    ``σ_d = σ·√update_rate`` (white noise) and ``σ_bd = σ_b/√update_rate`` (bias random walk). A
    term that could not be identified is written as a comment with the reason, so that Kalibr
    refuses the file rather than using a made-up number.
    """
    gyro = list(gyro)
    accel = list(accel)
    if not gyro and not accel:
        raise ValueError("write_kalibr needs gyro and/or accel coefficients")
    for name, group, kind in (("gyro", gyro, "gyro"), ("accel", accel, "accel")):
        for c in group:
            if not isinstance(c, NoiseCoefficients):
                raise TypeError(f"{name} must contain NoiseCoefficients, got {type(c).__name__}")
            if c.data_unit is None:
                raise ValueError(
                    f"{name}: the data unit is unknown; Kalibr needs SI units (pass units=)"
                )
            if c.sensor != kind:
                raise ValueError(
                    f"{name}: coefficients of data in {c.data_unit!r} are not {kind} data"
                )
    if update_rate is None:
        update_rate = max(c.fs for c in gyro + accel)
    update_rate = positive_float("update_rate", update_rate)
    lines = [
        "# Kalibr IMU noise model written by gyrobias",
        "# Continuous-time convention (Kalibr): noise densities are the white-noise coefficient N",
        "# (IEEE-952 ARW/VRW, two-sided PSD) and random walks the coefficient K (RRW);",
        "# Kalibr discretises them with update_rate: sigma_d = sigma*sqrt(rate), sigma_bd = sigma_b/sqrt(rate).",
        "# Units: gyroscope_noise_density rad/s/sqrt(Hz), gyroscope_random_walk rad/s^2/sqrt(Hz),",
        "#        accelerometer_noise_density m/s^2/sqrt(Hz), accelerometer_random_walk m/s^3/sqrt(Hz).",
        "# Each value is the largest over the axes analysed.",
    ]
    entries = (
        ("accelerometer", accel, "m/s²/√Hz", "m/s³/√Hz"),
        ("gyroscope", gyro, "rad/s/√Hz", "rad/s²/√Hz"),
    )
    for prefix, group, n_unit, k_unit in entries:
        if not group:
            continue
        lines.append(f"#{prefix.capitalize()}s")
        for key, symbol, unit in (("noise_density", "N", n_unit), ("random_walk", "K", k_unit)):
            value, note = _worst(group, symbol, unit)
            if value is None:
                lines.append(f"# {prefix}_{key}: not identified ({note})")
            else:
                lines.append(f"{prefix}_{key}: {value:.6e}  # {unit}, {note}")
    lines.append(f"rostopic: {rostopic}")
    lines.append(f"update_rate: {update_rate:.6g}  # Hz")
    text = "\n".join(lines) + "\n"
    from gyrobias.exports import atomic_write

    atomic_write(path, text)
    return text


# Datasheet values in (issue 13); imported last: gyrobias.datasheet builds NoiseCoefficients.
from gyrobias.datasheet import Datasheet, from_datasheet  # noqa: E402

__all__ += ["Datasheet"]

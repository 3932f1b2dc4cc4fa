"""Simulation of gyro noise with given IEEE-952 coefficients (the core's generators)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from gyrobias import _core
from gyrobias._validation import (
    integer,
    real,
    sequence,
)
from gyrobias._validation import seed as seed_value


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
    sinusoids: Sequence[Sequence[float]] = (),
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
    sinusoids : sequence of (frequency, amplitude) or (frequency, amplitude, phase)
        Periodic disturbances ``Ω₀·sin(2πf₀·k·t0 + φ)`` added to every axis (Hz, rate unit u,
        radians; phase 0 by default): vibration, a fan, an aliased mechanical mode. Frequencies
        in (0, fs/2] (a line above fs/2 is its alias), amplitudes ≥ 0.

    Returns
    -------
    ndarray
        Shape ``(n,)`` for ``axes == 1``, else ``(n, axes)``, in the rate unit u.

    Raises
    ------
    ValueError
        Negative coefficients, ``n < 1``, ``fs <= 0``, ``|c| >= 1``, a sinusoid above fs/2
        or with a negative amplitude.

    Notes
    -----
    Sample ``k`` is the sum of: white rate ``N/√t0·ξ_k``; quantisation as white angle noise of
    standard deviation ``Q`` differenced, ``Q(η_{k+1} − η_k)/t0``; flicker rate noise by
    spectral shaping of white noise to the two-sided PSD ``S(f) = B²/(2πf)`` (FFT of length
    ≥ 2n, first n samples kept); rate random walk ``Σ_{i≤k} K√t0·ξ_i``; ramp ``R·k·t0``;
    AR(1) drift; bias. Their Allan variances are ``3Q²/τ²``, ``N²/τ``, ``(0.664282 B)²``
    (τ ≫ t0), ``K²τ/3`` and ``R²τ²/2``; a sinusoid's is ``Ω₀²·sin⁴(πf₀τ)/(m·sin(πf₀t0))²``
    (:func:`gyrobias.noise.sinusoid_avar`).

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
    out = flat if axes == 1 else flat.reshape(n, axes)
    lines: list[tuple[float, float, float]] = []
    for i, item in enumerate(sequence("sinusoids", sinusoids)):
        values = [real("sinusoids", v) for v in sequence(f"sinusoids[{i}]", item)]
        if len(values) not in (2, 3):
            raise TypeError(
                f"sinusoids must hold (frequency, amplitude) or (frequency, amplitude, phase), "
                f"got {item!r}"
            )
        phase = values[2] if len(values) == 3 else 0.0
        lines.append((values[0], values[1], phase))
    if not lines:
        return out
    t0 = 1.0 / real("fs", fs)
    if axes == 1:
        return _core.noise.add_lines(out, t0, lines)
    columns = [
        _core.noise.add_lines(np.ascontiguousarray(out[:, a]), t0, lines) for a in range(axes)
    ]
    return np.stack(columns, axis=1)

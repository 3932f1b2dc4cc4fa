"""The value type of a spectral line (a periodic disturbance of a rate signal).

A value-type module like ``allan._types`` and ``noise._types`` (which carry it): it imports no
algorithm. The detector is :mod:`gyrobias._line_detection`. Public name:
``gyrobias.noise.SpectralLine``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

#: Half-width (bins) of the detector's running-median window on records of ≥ 8·128 samples;
#: shorter records use ``n // 8`` bins (see :func:`gyrobias.noise.detect_lines`).
HALF_WIDTH = 128

#: Narrowest window half-width (bins): the floor is then the median of 8 bins.
MIN_HALF_WIDTH = 8

#: Smallest record the detector accepts: eight of the narrowest window half-widths.
MIN_SAMPLES = 8 * MIN_HALF_WIDTH


@dataclass(frozen=True)
class SpectralLine:
    """One spectral line: a sinusoid found in the rate above the local noise floor.

    Attributes
    ----------
    frequency : float
        Frequency (Hz), refined to the maximum of the windowed periodogram, in (0, fs/2].
    amplitude : float
        Amplitude Ω₀ of the sinusoid ``Ω₀·sin(2πf₀t + φ)`` in the rate unit.
    unit : str or None
        Rate unit of ``amplitude``.
    ratio : float
        Periodogram peak over the local noise floor.
    p_value : float
        Bonferroni-adjusted p-value ``min(1, K·exp(−ratio))`` over the K frequencies searched:
        the probability that noise alone gives a peak this high anywhere in the spectrum.
    resolution : float
        Frequency resolution ``fs/n`` of the periodogram (Hz).
    frequency_uncertainty : float
        Standard uncertainty of ``frequency`` (Hz): ``√F·(fs/n)/(π√ρ)`` with ρ the peak over
        the local floor and F = 2.34 the Hann window's variance factor over the Cramér–Rao
        bound of a sinusoid in white noise (``gyrocore::noise::sinusoid``; Rife & Boorstyn
        1974). Typically a small fraction of ``resolution``: 1e-7 Hz for a 0.05 deg/s line in
        2 h of 0.2 deg/√h noise at 100 Hz.
    """

    frequency: float
    amplitude: float
    unit: str | None
    ratio: float
    p_value: float
    resolution: float
    frequency_uncertainty: float = math.nan

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary with units."""
        return {
            "frequency_hz": self.frequency,
            "amplitude": self.amplitude,
            "unit": self.unit,
            "ratio": self.ratio,
            "p_value": self.p_value,
            "resolution_hz": self.resolution,
            "frequency_uncertainty_hz": self.frequency_uncertainty,
        }

    def __str__(self) -> str:
        unit = f" {self.unit}" if self.unit else ""
        return (
            f"line at {self.frequency:.4f} Hz, amplitude {self.amplitude:.4g}{unit} "
            f"(peak/floor {self.ratio:.3g}, p = {self.p_value:.2g})"
        )

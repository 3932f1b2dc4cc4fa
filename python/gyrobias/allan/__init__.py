"""Allan-family deviations of gyro rate or angle data (NIST SP 1065, IEEE Std 952).

The package, by task:

- **Classic deviations** (:mod:`gyrobias.allan.classic`): :func:`avar`, :func:`adev`
  (overlapping and non-overlapping), :func:`mdev`, :func:`hdev`, :func:`totdev`, and
  :func:`adev_batch` for a fleet of equal-length logs in one core call.
- **The rest of the family** (:mod:`gyrobias.allan.family`): :func:`tdev`, :func:`mtotdev`,
  :func:`htotdev`, :func:`theo1`, :func:`theobr`, :func:`theoh`.
- **Non-stationarity** (:mod:`gyrobias.allan.dynamic`): :func:`dynamic_adev`; is a log static
  (steps, motion segments, warm-up trends beyond its noise): :func:`stationarity`,
  :attr:`AllanResult.stationarity`.
- **Results** (:mod:`gyrobias.allan._types`, value types only): :class:`AllanResult`,
  :class:`DynamicAllanResult`, :class:`Stationarity`, :class:`Disturbance`, :data:`NOISE_NAMES`.

Memory-mapped inputs (``np.load(path, mmap_mode="r")``) are streamed from their file
(:mod:`gyrobias.allan.stream`) so a log larger than RAM can be analysed.
"""

from gyrobias.allan._types import KINDS as KINDS
from gyrobias.allan._types import (
    NOISE_NAMES,
    AllanResult,
    Disturbance,
    DynamicAllanResult,
    Stationarity,
)
from gyrobias.allan._types import Kind as Kind
from gyrobias.allan.classic import adev, adev_batch, avar, hdev, mdev, stationarity, totdev
from gyrobias.allan.dynamic import dynamic_adev
from gyrobias.allan.family import htotdev, mtotdev, tdev, theo1, theobr, theoh

__all__ = [
    # results
    "NOISE_NAMES",
    "AllanResult",
    "Disturbance",
    "DynamicAllanResult",
    "Stationarity",
    # classic deviations
    "adev",
    "adev_batch",
    "avar",
    "hdev",
    "mdev",
    "totdev",
    "stationarity",
    # the rest of the family
    "htotdev",
    "mtotdev",
    "tdev",
    "theo1",
    "theobr",
    "theoh",
    # non-stationarity
    "dynamic_adev",
]

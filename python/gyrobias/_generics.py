"""Generic functions behind the result objects' convenience methods.

``AllanResult.plot()``, ``NoiseCoefficients.export()``, ``.discrete()``, ``.conservative()`` and
their kin are one-line delegations to the generic functions here
(:func:`functools.singledispatch`). The module that owns a behaviour registers its method for
each value type when it is imported — :mod:`gyrobias.plotting` registers ``plot``,
:mod:`gyrobias.exports` ``export``/``export_all``/``discrete``, :mod:`gyrobias.conservative`
``conservative``, :mod:`gyrobias.exports.kalibr` ``to_kalibr``, :mod:`gyrobias.codegen` ``to_c`` — much as R packages register S3 methods when their namespace loads. The
value types thus import no behaviour module and the dependency points one way (behaviour →
types). ``import gyrobias`` (run before any ``gyrobias.*`` submodule) imports every registering
module, so the methods are always in place.

This module imports nothing from gyrobias: it is a leaf of the import graph.
"""

from __future__ import annotations

import os
from functools import singledispatch
from typing import Any

__all__ = ["conservative", "discrete", "export", "export_all", "plot", "to_c", "to_kalibr"]


def _missing(verb: str, obj: object) -> TypeError:
    return TypeError(f"{verb}: no method for {type(obj).__name__} objects")


@singledispatch
def plot(obj: object, ax: Any = None, **kwargs: Any) -> Any:
    """Draw ``obj`` (methods registered by :mod:`gyrobias.plotting`); returns the ``Axes``."""
    raise _missing("plot", obj)


@singledispatch
def export(obj: object, fmt: str, path: str | os.PathLike[str] | None = None, **kwargs: Any) -> str:
    """Write an estimator file for ``obj`` (methods registered by :mod:`gyrobias.exports`)."""
    raise _missing("export", obj)


@singledispatch
def export_all(
    obj: object, directory: str | os.PathLike[str] | None = None, **kwargs: Any
) -> dict[str, str]:
    """Every estimator file for ``obj`` (methods registered by :mod:`gyrobias.exports`)."""
    raise _missing("export_all", obj)


@singledispatch
def discrete(obj: object, rate: Any = None) -> Any:
    """Per-sample noise parameters of ``obj`` (methods registered by :mod:`gyrobias.exports`)."""
    raise _missing("discrete", obj)


@singledispatch
def conservative(obj: object, confidence: float = 0.95, **kwargs: Any) -> Any:
    """Overbounding coefficients (methods registered by :mod:`gyrobias.conservative`)."""
    raise _missing("conservative", obj)


@singledispatch
def to_kalibr(obj: object, path: str | os.PathLike[str], **kwargs: Any) -> str:
    """Write a Kalibr ``imu.yaml`` for ``obj`` (method registered by :mod:`gyrobias.exports.kalibr`)."""
    raise _missing("to_kalibr", obj)


@singledispatch
def to_c(obj: object, path: str | os.PathLike[str], **kwargs: Any) -> Any:
    """Write ``obj`` as C99 (methods registered by :mod:`gyrobias.codegen`)."""
    raise _missing("to_c", obj)

"""Generic functions behind the result objects' convenience methods.

``AllanResult.plot()``, ``NoiseCoefficients.export()``, ``.discrete()``, ``.conservative()`` and
their kin are one-line delegations to the generic functions here
(:func:`functools.singledispatch`). The module that owns a behaviour registers its method for
each value type when it is imported — :mod:`gyrobias.plotting` registers ``plot``,
:mod:`gyrobias.exports` ``export``/``export_all``/``discrete``, :mod:`gyrobias.conservative`
``conservative``, :mod:`gyrobias.exports.kalibr` ``to_kalibr``, :mod:`gyrobias.codegen` ``to_c`` — much as R packages register S3 methods when their namespace loads. The
value types thus import no behaviour module and the dependency points one way (behaviour →
types).

The package façade (``gyrobias/__init__``, which Python runs before any ``gyrobias.*``
submodule) is lazy, so that the command line's ``--help`` imports no NumPy: it hands this module
its loader with :func:`set_loader`, and the first call of a generic function that finds no
method for its argument runs that loader (which imports every registering module) and
dispatches again. So the methods are in place whatever the caller imported, and this module
still imports nothing: the façade calls in, never the other way round.

This module imports nothing from gyrobias: it is a leaf of the import graph.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from functools import singledispatch
from typing import Any, cast

__all__ = ["conservative", "discrete", "export", "export_all", "plot", "to_c", "to_kalibr"]


#: The façade's loader (imports every registering module); None once it has run.
_loader: Callable[[], None] | None = None


def set_loader(load: Callable[[], None]) -> None:
    """Called by the package façade: ``load`` imports every module that registers methods here."""
    global _loader
    _loader = load


def _fallback(generic: Any, obj: object, *args: Any, **kwargs: Any) -> Any:
    """No method of ``generic`` for ``type(obj)`` yet: run the façade's loader (once) and
    dispatch again; ``TypeError`` if there is still none."""
    global _loader
    if _loader is not None:
        _loader()
        _loader = None
        impl = generic.dispatch(type(obj))
        if impl is not generic.dispatch(object):
            return impl(obj, *args, **kwargs)
    raise TypeError(f"{generic.__name__}: no method for {type(obj).__name__} objects")


@singledispatch
def plot(obj: object, ax: Any = None, **kwargs: Any) -> Any:
    """Draw ``obj`` (methods registered by :mod:`gyrobias.plotting`); returns the ``Axes``."""
    return _fallback(plot, obj, ax, **kwargs)


@singledispatch
def export(obj: object, fmt: str, path: str | os.PathLike[str] | None = None, **kwargs: Any) -> str:
    """Write an estimator file for ``obj`` (methods registered by :mod:`gyrobias.exports`)."""
    return cast(str, _fallback(export, obj, fmt, path, **kwargs))


@singledispatch
def export_all(
    obj: object, directory: str | os.PathLike[str] | None = None, **kwargs: Any
) -> dict[str, str]:
    """Every estimator file for ``obj`` (methods registered by :mod:`gyrobias.exports`)."""
    return cast(dict[str, str], _fallback(export_all, obj, directory, **kwargs))


@singledispatch
def discrete(obj: object, rate: Any = None) -> Any:
    """Per-sample noise parameters of ``obj`` (methods registered by :mod:`gyrobias.exports`)."""
    return _fallback(discrete, obj, rate)


@singledispatch
def conservative(obj: object, confidence: float = 0.95, **kwargs: Any) -> Any:
    """Overbounding coefficients (methods registered by :mod:`gyrobias.conservative`)."""
    return _fallback(conservative, obj, confidence, **kwargs)


@singledispatch
def to_kalibr(obj: object, path: str | os.PathLike[str], **kwargs: Any) -> str:
    """Write a Kalibr ``imu.yaml`` for ``obj`` (method registered by :mod:`gyrobias.exports.kalibr`)."""
    return cast(str, _fallback(to_kalibr, obj, path, **kwargs))


@singledispatch
def to_c(obj: object, path: str | os.PathLike[str], **kwargs: Any) -> Any:
    """Write ``obj`` as C99 (methods registered by :mod:`gyrobias.codegen`)."""
    return _fallback(to_c, obj, path, **kwargs)

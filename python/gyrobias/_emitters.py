"""Late binding of the C emitters (``to_c`` methods) without an import cycle.

:mod:`gyrobias.codegen` imports the filter classes to generate C from them; the classes' ``to_c``
methods therefore cannot import it. Instead :mod:`gyrobias.codegen` registers its emitters here
when it is imported (``import gyrobias`` does that), and ``to_c`` looks them up. This module
imports nothing from gyrobias.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["emit", "register"]

_EMITTERS: dict[str, Callable[..., Any]] = {}


def register(kind: str, emitter: Callable[..., Any]) -> None:
    """Register ``emitter(obj, path, **options)`` for objects of ``kind``."""
    _EMITTERS[kind] = emitter


def emit(kind: str, obj: object, path: object, **options: Any) -> Any:
    """Run the emitter registered for ``kind``."""
    try:
        emitter = _EMITTERS[kind]
    except KeyError:
        raise RuntimeError(
            f"no C emitter for {kind!r}: import gyrobias (which loads gyrobias.codegen)"
        ) from None
    return emitter(obj, path, **options)

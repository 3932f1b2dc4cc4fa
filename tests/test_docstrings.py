"""The Examples sections of the public modules run and print what they say."""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import gyrobias

#: Every module of the package: doctest only collects the objects a module *defines*
#: (``obj.__module__``), so a package that re-exports from its submodules (``gyrobias.allan``
#: from ``gyrobias.allan.classic``, ...) must be walked module by module. ``__main__`` runs
#: the command line on import and is left out.
MODULES = sorted(
    m.name
    for m in pkgutil.walk_packages(gyrobias.__path__, "gyrobias.")
    if m.name != "gyrobias.__main__"
) + ["gyrobias"]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name: str) -> None:
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS)
    assert result.failed == 0


def test_examples_exist() -> None:
    attempted = sum(doctest.testmod(importlib.import_module(n)).attempted for n in MODULES)
    assert attempted >= 15

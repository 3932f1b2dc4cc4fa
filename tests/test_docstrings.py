"""The Examples sections of the public modules run and print what they say."""

from __future__ import annotations

import doctest
import importlib

import pytest

MODULES = [
    "gyrobias.allan",
    "gyrobias.io",
    "gyrobias.noise",
    "gyrobias.fractional",
    "gyrobias.predict",
    "gyrobias.kalman",
    "gyrobias.fir",
    "gyrobias.spectral",
    "gyrobias.thermal",
    "gyrobias.plotting",
    "gyrobias.fleet",
    "gyrobias.datasheet",
    "gyrobias.exports",
    "gyrobias.conservative",
    "gyrobias.report",
]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name: str) -> None:
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS)
    assert result.failed == 0


def test_examples_exist() -> None:
    attempted = sum(doctest.testmod(importlib.import_module(n)).attempted for n in MODULES)
    assert attempted >= 15

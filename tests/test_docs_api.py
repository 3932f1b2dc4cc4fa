"""The API reference covers every public name exactly once (docs/_ext/apiref.py).

The page is generated at build time from each public module's ``__all__``; this test renders it
the same way and checks it against an independent walk of the package: every name in every
public module's ``__all__`` (submodules aside, which are sections) appears exactly once, either
as the entry of the object or as an "also importable as" row pointing at that entry.
"""

from __future__ import annotations

import importlib
import pkgutil
import sys
import types
from collections import Counter
from pathlib import Path

import pytest

import gyrobias

DOCS = Path(__file__).resolve().parents[1] / "docs"
sys.path.insert(0, str(DOCS / "_ext"))

import apiref  # noqa: E402


def _public_names() -> set[str]:
    """Independent of apiref: every ``module.name`` of every public module's ``__all__``."""
    mods = ["gyrobias"] + [
        i.name
        for i in pkgutil.walk_packages(gyrobias.__path__, "gyrobias.")
        if not any(p.startswith("_") for p in i.name.split("."))
        and not (i.name.startswith("gyrobias.cli.") and i.name.count(".") >= 2)
    ]
    out = set()
    for name in mods:
        mod = importlib.import_module(name)
        for n in getattr(mod, "__all__", ()):
            if not isinstance(getattr(mod, n), types.ModuleType):
                out.add(f"{name}.{n}")
    return out


def test_every_public_name_appears_exactly_once() -> None:
    rst, _ = apiref.render()
    documented = apiref.documented_names(rst)
    counts = Counter(documented)
    assert [n for n, c in counts.items() if c > 1] == []
    expected = _public_names()
    assert sorted(expected - set(documented)) == []
    assert sorted(set(documented) - expected) == []


def test_each_object_has_one_entry_and_aliases_point_at_it() -> None:
    entries, _ = apiref.collect()
    objects = [id(e.obj) for e in entries if apiref._is_identity_object(e.obj)]
    assert len(objects) == len(set(objects))
    adev = next(e for e in entries if e.obj is gyrobias.allan.adev)
    assert adev.path == "gyrobias.allan.adev" and "gyrobias.adev" in adev.aliases


def test_every_entry_is_placed_in_a_task_group() -> None:
    _, unplaced = apiref.render()
    assert unplaced == []


@pytest.mark.parametrize("group", [g[0] for g in apiref.GROUPS])
def test_explicit_placements_exist(group: str) -> None:
    """A placement naming a vanished object would silently place nothing: refuse it."""
    entries, _ = apiref.collect()
    paths = {e.path for e in entries} | {e.module for e in entries}
    items = next(g[2] for g in apiref.GROUPS if g[0] == group)
    assert [i for i in items if i not in paths] == []

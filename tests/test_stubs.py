"""The binding's stubs describe exactly what it returns (issue 24 item 2).

``mypy.stubtest`` checks the signatures of ``gyrobias._core`` against its ``*.pyi`` stubs, but
not the dictionaries the functions return: those are ``TypedDict`` classes that exist only in
the stubs. Here every binding function whose stub returns a ``TypedDict`` (directly, in a
list, or nested in another one's field) is spied on while the public API runs, and each
dictionary it returns must have every required key of its ``TypedDict``, no key the stub does
not declare, and ``NotRequired`` keys only where the stub allows them. The stubs are read with
:mod:`ast`; a ``TypedDict``-returning binding that no call below reaches fails the test, so a
new binding needs its stub and a call here.
"""

from __future__ import annotations

import ast
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import gyrobias
from gyrobias import _core

# The stubs shipped with the package under test (the source tree or an installed wheel).
STUBS = Path(gyrobias.__file__).resolve().parent / "_core"


class _TypedDict:
    def __init__(self, name: str) -> None:
        self.name = name
        self.fields: dict[str, ast.expr] = {}
        self.required: set[str] = set()


def _parse_stubs() -> tuple[dict[str, _TypedDict], dict[tuple[str, str], ast.expr]]:
    """``({TypedDict name: fields}, {(module, function): return annotation})`` of every stub."""
    typed: dict[str, _TypedDict] = {}
    returns: dict[tuple[str, str], ast.expr] = {}
    for path in sorted(STUBS.glob("*.pyi")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in tree.body:
            if isinstance(node, ast.FunctionDef) and node.returns is not None:
                returns[(path.stem, node.name)] = node.returns
            if not isinstance(node, ast.ClassDef):
                continue
            bases = [b.id for b in node.bases if isinstance(b, ast.Name)]
            if not any(b == "TypedDict" or b in typed for b in bases):
                continue
            td = _TypedDict(node.name)
            for base in bases:  # inherited fields (class Gmwm(JointFit))
                if base in typed:
                    td.fields.update(typed[base].fields)
                    td.required |= typed[base].required
            for item in node.body:
                if isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
                    key, ann = item.target.id, item.annotation
                    optional = (
                        isinstance(ann, ast.Subscript)
                        and isinstance(ann.value, ast.Name)
                        and ann.value.id == "NotRequired"
                    )
                    if optional:
                        assert isinstance(ann, ast.Subscript)
                        ann = ann.slice
                    td.fields[key] = ann
                    if not optional:
                        td.required.add(key)
            assert td.fields, f"{path.name}: TypedDict {node.name} has no fields"
            typed[node.name] = td
    return typed, returns


TYPED, RETURNS = _parse_stubs()


def _mentions(ann: ast.expr) -> set[str]:
    return {n.id for n in ast.walk(ann) if isinstance(n, ast.Name) and n.id in TYPED}


#: The binding functions whose stub returns a TypedDict somewhere in the result.
DICT_RETURNING = sorted(key for key, ann in RETURNS.items() if _mentions(ann))


def _check(value: Any, ann: ast.expr, where: str, seen: set[str]) -> list[str]:
    """Mismatches between ``value`` and the stub annotation ``ann`` (TypedDicts by key)."""
    if isinstance(ann, ast.Name) and ann.id in TYPED:
        td = TYPED[ann.id]
        seen.add(td.name)
        if not isinstance(value, dict):
            return [f"{where}: {td.name} expected, got {type(value).__name__}"]
        errors = []
        missing = td.required - value.keys()
        extra = value.keys() - td.fields.keys()
        if missing:
            errors.append(f"{where}: {td.name} lacks required key(s) {sorted(missing)}")
        if extra:
            errors.append(f"{where}: {td.name} has undeclared key(s) {sorted(extra)}")
        for key in value.keys() & td.fields.keys():
            errors += _check(value[key], td.fields[key], f"{where}[{key!r}]", seen)
        return errors
    if isinstance(ann, ast.BinOp) and isinstance(ann.op, ast.BitOr):  # X | None
        if value is None:
            return []
        left = _check(value, ann.left, where, seen)
        return left if _mentions(ann.left) else _check(value, ann.right, where, seen)
    if isinstance(ann, ast.Subscript) and isinstance(ann.value, ast.Name):
        if ann.value.id == "list" and _mentions(ann.slice):
            if not isinstance(value, list):
                return [f"{where}: list expected, got {type(value).__name__}"]
            errors = []
            for i, item in enumerate(value):
                errors += _check(item, ann.slice, f"{where}[{i}]", seen)
            return errors
        if ann.value.id == "tuple" and _mentions(ann.slice):
            items = ann.slice.elts if isinstance(ann.slice, ast.Tuple) else [ann.slice]
            errors = []
            for i, (item, sub) in enumerate(zip(value, items)):
                errors += _check(item, sub, f"{where}[{i}]", seen)
            return errors
    return []


@pytest.fixture
def spied(monkeypatch: pytest.MonkeyPatch) -> Iterator[list[tuple[str, str, Any]]]:
    """Record ``(module, function, result)`` of every TypedDict-returning binding call."""
    calls: list[tuple[str, str, Any]] = []
    for module, name in DICT_RETURNING:
        real = getattr(getattr(_core, module), name)

        def spy(
            *args: Any, _real: Callable[..., Any] = real, _key=(module, name), **kw: Any
        ) -> Any:
            out = _real(*args, **kw)
            calls.append((*_key, out))
            return out

        monkeypatch.setattr(getattr(_core, module), name, spy)
    yield calls


def _public_api_calls(tmp_path: Path) -> None:
    """Calls of the public API that reach every TypedDict-returning binding."""
    rng = np.random.default_rng(24)
    rate = gyrobias.noise.simulate(20_000, 100.0, arw=0.3 / 60, rrw=3 / 216000, seed=1)
    xyz = np.column_stack([rate, rate[::-1], -rate])
    a = gyrobias.allan.adev(rate, 100.0, units="deg/s")
    gyrobias.allan.adev(xyz, 100.0, confidence=None, axis_names="xyz")
    gyrobias.allan.adev_batch(np.stack([xyz[:5000], xyz[5000:10000]]), 100.0)
    path = tmp_path / "x.npy"
    np.save(path, xyz)
    gyrobias.allan.adev(np.load(path, mmap_mode="r"), 100.0)  # streamed from the file
    gyrobias.allan.theo1(rate[:2000], 100.0)
    gyrobias.allan.tdev(rate[:2000], 100.0, confidence=None)
    gyrobias.allan.dynamic_adev(rate, 100.0, window=4000, step=4000)
    assert isinstance(a, gyrobias.AllanResult)
    joint = gyrobias.noise.fit(a, terms=("N", "K", "GM"))
    gyrobias.noise.fit(a, method="ieee")
    joint.conservative(0.95)
    gyrobias.noise.gmwm(rate, 100.0, terms=("N", "K"), units="deg/s")
    gyrobias.noise.wvar(rate, 100.0, robust=True)
    # A log with a spectral line: detect_lines, and fit/gmwm with a fitted sinusoid.
    lined = gyrobias.noise.simulate(20_000, 100.0, arw=0.3 / 60, sinusoids=[(23.0, 0.05)], seed=2)
    gyrobias.noise.fit(gyrobias.allan.adev(lined, 100.0), terms=("N",))
    design = np.abs(rng.normal(size=(6, 3))) + 0.1
    _core.noise.overbound(design, design.sum(axis=1))  # no public caller: the LP itself
    edf = np.full(a.taus.size, 5.0)  # no public caller: the bound on given points and EDF
    _core.noise.upper_bound(
        a.taus, a.avar, a.m, a.n_terms, True, np.arange(a.taus.size), edf, "K", 0.9
    )
    gyrobias.fir.kaiser_lowpass(100.0, 10.0, 20.0)
    gyrobias.fractional.elw(rng.normal(size=512))
    gyrobias.FractionalKalmanPredictor(d=0.3).predict(rng.normal(size=64), 8)
    t = np.sort(rng.uniform(0.0, 10.0, 200))
    gyrobias.lssa(t, np.sin(2.0 * np.pi * t) + rng.normal(size=200))
    gyrobias.fit_ar1(np.cumsum(rng.normal(size=500)) * 0.01 + rng.normal(size=500), 10.0)
    kf = gyrobias.FixedGainKalman(200.0, arw=0.08, rrw=7e-4, bandwidth=10.0)
    kf.to_c(tmp_path / "c", dtype="q31")  # codegen.kalman_q31
    gyrobias.FractionalKalmanPredictor().compile(8, 4).to_c(tmp_path / "c", dtype="q31")  # dot_q31


def test_binding_dicts_match_their_stubs(spied: list[tuple[str, str, Any]], tmp_path: Path) -> None:
    assert ("allan", "analyse") in DICT_RETURNING and ("noise", "gmwm") in DICT_RETURNING
    _public_api_calls(tmp_path)
    seen: set[str] = set()
    errors: list[str] = []
    for module, name, out in spied:
        errors += _check(out, RETURNS[(module, name)], f"_core.{module}.{name}()", seen)
    assert errors == [], "\n".join(errors)
    reached = {(m, n) for m, n, _ in spied}
    assert sorted(set(DICT_RETURNING) - reached) == [], "bindings not exercised here"
    assert sorted(set(TYPED) - seen) == [], "TypedDicts never checked against a real result"


def test_checker_reports_missing_extra_and_nested_keys() -> None:
    # The checker itself can fail: a missing key, an undeclared key, and a nested TypedDict
    # inside a list are each reported.
    ann = ast.parse("list[Analysis]", mode="eval").body
    good = {k: None for k in TYPED["Analysis"].required}
    assert _check([good], ann, "x", set()) == []
    missing = dict(good)
    del missing["variance"]
    assert "lacks required key(s) ['variance']" in _check([missing], ann, "x", set())[0]
    assert "undeclared key(s) ['bogus']" in _check([{**good, "bogus": 1}], ann, "x", set())[0]
    gmwm = ast.parse("Gmwm", mode="eval").body
    fake = {k: None for k in TYPED["Gmwm"].required} | {"wavelet": {"m": 1}}
    assert any("WaveletVariance lacks" in e for e in _check(fake, gmwm, "g", set()))

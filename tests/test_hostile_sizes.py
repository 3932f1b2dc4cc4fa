"""Sizes that reach an allocation (issue 34, class 2).

Every public size-like parameter gets 2**40 and 2**62, each call in its own interpreter: the
outcome must be a clean ``MemoryError``/``ValueError``/``TypeError`` naming the argument (or a
valid result, for a size that allocates nothing), and the interpreter must live on (exit code
0). Before issue 34, ``predict.Evaluation.ratio(..., resamples=2**40)`` aborted the interpreter
(``memory allocation of 8796093022208 bytes failed``, exit −6).

**Enumeration rule.** The size-like parameters are every parameter the hostile registry
(``tests/hostile_registry.py``, checked against the public signatures by
``test_hostile.test_registry_knows_every_parameter``) classifies as ``count``, except seeds
(``seed``: a generator state, not a size), plus the shape parameters of kind ``spec`` listed in
:data:`SHAPES`. A new count parameter of any public function joins this test automatically.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from tests.hostile_registry import entries

ROOT = Path(__file__).resolve().parents[1]

#: Size-like parameters that are not plain counts (a shape), with the hostile value to pass
#: for a given size ``n``.
SHAPES = {("fractional.arfima", "size"): lambda n: (n,), ("noise.simulate", "n"): None}

#: Calls that would legitimately run for a time proportional to the count rather than
#: allocate it are not in this class; none are left out today.
SKIP: dict[tuple[str, str], str] = {}


def _size_parameters() -> list[tuple[str, str]]:
    out = [
        (key, name)
        for key, name, _ in entries("count")
        if name != "seed" and not key.startswith("cli.")
    ]
    out += [k for k, v in SHAPES.items() if v is not None]
    return [k for k in out if k not in SKIP]


_SCRIPT = r"""
import sys, warnings
sys.path.insert(0, {root!r})
key, name, exponent = {key!r}, {name!r}, {exponent!r}
value = 2 ** exponent
from tests import test_hostile as th
from tests.test_hostile_sizes import SHAPES
th._TMP.insert(0, __import__("pathlib").Path({tmp!r}))
shape = SHAPES.get((key, name))
if shape is not None:
    value = shape(value)
func, kwargs = th.BASE[key]()
try:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        func(**{{**kwargs, name: value}})
except (MemoryError, ValueError, TypeError) as exc:
    print("REFUSED", type(exc).__name__, str(exc)[:300])
else:
    print("OK")
"""


@pytest.mark.parametrize(("key", "name"), _size_parameters(), ids=lambda v: str(v))
@pytest.mark.parametrize("exponent", [40, 62])
def test_huge_sizes_are_clean_errors_in_a_live_interpreter(
    key: str, name: str, exponent: int, tmp_path: Path
) -> None:
    script = _SCRIPT.format(
        root=str(ROOT), key=key, name=name, exponent=exponent, tmp=str(tmp_path)
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT / "python"), str(ROOT)])}
    proc = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=60, env=env
    )
    assert proc.returncode == 0, (
        f"{key}({name}=2**{exponent}): exit {proc.returncode}\n{proc.stderr[-1500:]}"
    )
    out = proc.stdout.strip().splitlines()[-1] if proc.stdout.strip() else ""
    assert out.startswith(("OK", "REFUSED")), proc.stdout + proc.stderr[-1500:]
    if out.startswith("REFUSED"):
        assert name in out, f"{key}({name}=2**{exponent}): the error does not name {name!r}: {out}"

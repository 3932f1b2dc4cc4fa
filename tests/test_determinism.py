"""Results never depend on progress reporting, chunking, thread count or axis order (issue 11 item 7).

Each test compares complete results (variances, term counts, noise types, EDF and interval
bounds) bit for bit.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from gyrobias import allan

FIELDS = ("taus", "avar", "n_terms", "edf", "alpha", "ci_low", "ci_high", "noise_type")
FUNCTIONS = {
    "adev": allan.adev,
    "adev_nonoverlapping": lambda d, fs, **kw: allan.adev(d, fs, overlapping=False, **kw),
    "mdev": allan.mdev,
    "hdev": allan.hdev,
    "totdev": allan.totdev,
}


def _log(n: int = 300_001, axes: int = 3, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    white = rng.normal(0.2, 1.0, (n, axes))
    walk = np.cumsum(rng.normal(0.0, 3e-3, (n, axes)), axis=0)
    return white + walk


def _same(a: allan.AllanResult, b: allan.AllanResult) -> None:
    for field in FIELDS:
        x, y = getattr(a, field), getattr(b, field)
        if isinstance(x, np.ndarray):
            np.testing.assert_array_equal(x, y, err_msg=field)
        else:
            assert x == y, field


@pytest.mark.parametrize("name", sorted(FUNCTIONS))
def test_progress_reporting_does_not_change_results(name: str) -> None:
    data = _log(120_001) if name in ("mdev", "totdev") else _log()
    seen: list[float] = []
    with_progress = FUNCTIONS[name](data, 100.0, taus="log", progress=seen.append)
    without = FUNCTIONS[name](data, 100.0, taus="log")
    for a, b in zip(with_progress, without):
        _same(a, b)
    # The callback saw the analysis from 0 to 1, in order, more than a handful of times.
    assert seen[0] == 0.0 and seen[-1] == 1.0
    assert all(x < y for x, y in zip(seen, seen[1:])) and len(seen) >= 5


def test_progress_callback_exception_stops_the_analysis() -> None:
    calls: list[float] = []

    def stop(fraction: float) -> None:
        calls.append(fraction)
        if fraction > 0.2:
            raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        allan.adev(_log(), 100.0, progress=stop)
    assert max(calls) < 0.5  # stopped at the next block, not at the end


def test_axis_order_does_not_change_results() -> None:
    data = _log()
    order = [2, 0, 1]
    a = allan.adev(data, 100.0, taus="log")
    b = allan.adev(np.ascontiguousarray(data[:, order]), 100.0, taus="log")
    for i, j in enumerate(order):
        _same(b[i], a[j])
    # and a column alone is the same column among others
    single = allan.adev(np.ascontiguousarray(data[:, 1]), 100.0, taus="log")
    assert isinstance(single, allan.AllanResult)
    _same(single, a[1])


def test_tau_chunking_does_not_change_variances() -> None:
    # The all-τ kernel groups τ by thread and chunk; a τ's variance is the same whichever other
    # τ are computed with it (the old Python-side τ chunking changed the noise identification).
    data = _log(axes=1)[:, 0]
    every = allan.adev(data, 100.0, taus="log", per_decade=20, confidence=None)
    assert isinstance(every, allan.AllanResult)
    for part in np.array_split(np.arange(len(every.taus)), 5):
        some = allan.adev(data, 100.0, taus=every.taus[part], confidence=None)
        assert isinstance(some, allan.AllanResult)
        np.testing.assert_array_equal(some.avar, every.avar[part])
        np.testing.assert_array_equal(some.n_terms, every.n_terms[part])


_DIGEST = """
import hashlib, numpy as np
from gyrobias import allan
rng = np.random.default_rng(0)
data = rng.normal(0.2, 1.0, (300_001, 2)) + np.cumsum(rng.normal(0.0, 3e-3, (300_001, 2)), axis=0)
h = hashlib.sha256()
for f in (allan.adev, allan.mdev, allan.hdev):
    for r in f(data[:120_001] if f is allan.mdev else data, 100.0, taus="log"):
        for a in (r.avar, r.n_terms, r.edf, r.alpha, r.ci_low, r.ci_high):
            h.update(np.ascontiguousarray(a).tobytes())
for unit in allan.adev_batch(data.T.reshape(2, -1, 1)[:, :200_000], 100.0):
    h.update(unit[0].avar.tobytes() + unit[0].ci_high.tobytes())
print(h.hexdigest())
"""


def test_thread_count_does_not_change_results() -> None:
    digests = set()
    for threads in ("1", "2", "5"):
        env = dict(os.environ, RAYON_NUM_THREADS=threads)
        out = subprocess.run(
            [sys.executable, "-c", _DIGEST], env=env, check=True, capture_output=True, text=True
        )
        digests.add(out.stdout.strip())
    assert len(digests) == 1

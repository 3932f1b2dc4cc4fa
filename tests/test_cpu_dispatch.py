"""Runtime CPU dispatch: the baseline kernels give the same bits as the vector ones (issue 25 item 3).

The core is compiled for the baseline of its target (no ``target-cpu=native``); its vector
kernels (``pulp``) are also compiled for x86-64-v3 (AVX2, FMA) and chosen at run time
(``gyrocore::simd``), so the wheel runs on any x86-64 CPU. ``GYROBIAS_SIMD=scalar`` forces the
baseline variant. Each kernel documents that it fixes the order of every addition in lanes and
forms no fused multiply-add, so both variants must give the same bits; this test runs the
kernels in two interpreters, one forced to the baseline, and compares digests of the results:

- the Allan difference sums (``allan/fused.rs``): the block pass and the lattices of far
  averaging factors (m >= 2**15) for the second (ADEV) and third (HDEV) differences, and the
  streamed chunk sums of a memory-mapped record (``second_chunk_sum``);
- the modified Allan sum's lockstep segments (``allan/modified.rs``: AVX lanes with an
  in-register transpose, or the same lanes in scalar code) and the total variance's interior;
- Théo1's lag-blocked structure function and edge sums (``allan/theo.rs``, ThéoBR's sweep);
- the Allan-correlation integrals of the noise fit on a dense τ grid (``noise/covariance.rs``);
- the generalized Schur recursion of the fractional predictor (``predict/schur.rs``).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from gyrobias import _core

_DIGEST = """
import hashlib, sys
import numpy as np
from gyrobias import _core, allan, noise, predict

h = hashlib.sha256()
def add(*arrays):
    for a in arrays:
        h.update(np.ascontiguousarray(a, dtype=np.float64).tobytes())

rng = np.random.default_rng(25)
n = 300_001
data = rng.normal(0.0, 1.0, n) + np.cumsum(rng.normal(0.0, 1e-3, n))
for f in (allan.adev, allan.hdev):
    r = f(data, 100.0, taus="octave")       # m up to 2**16: block pass and one lattice
    add(r.avar, r.edf, r.ci_low, r.ci_high)
path = sys.argv[1]
np.save(path, data)
for f in (allan.mdev, allan.totdev):
    r = f(data, 100.0, taus="octave", confidence=None)   # lockstep groups, lone segments
    add(r.avar)
r = allan.adev(np.load(path, mmap_mode="r"), 100.0)   # streamed in chunks from the file
add(r.avar, r.ci_low, r.ci_high)
r = allan.theobr(data[:4000], 100.0)                  # structure function + edge sums
add(r.avar)
dense = allan.adev(data[:2050], 100.0, taus="all")    # 1025 τ: the correlation integrals
c = noise.fit(dense)
add([t.value for t in (c.N, c.B, c.K)], [t.uncertainty for t in (c.N, c.B, c.K)])
p = predict.FractionalKalmanPredictor(d=0.3, q=1e-4, r=1e-2).predict(data[:3000], 200)
add(p.bias, p.std, p.std_observation)
print(_core.instruction_set(), h.hexdigest())
"""


def _run(tmp_path: Path, simd: str | None) -> tuple[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "GYROBIAS_SIMD"}
    if simd is not None:
        env["GYROBIAS_SIMD"] = simd
    out = subprocess.run(
        [sys.executable, "-c", _DIGEST, str(tmp_path / f"record-{simd}.npy")],
        env=env,
        capture_output=True,
        text=True,
        check=True,
        timeout=600,
    ).stdout.split()
    return out[0], out[1]


def test_forced_baseline_gives_the_same_bits(tmp_path: Path) -> None:
    scalar_set, scalar = _run(tmp_path, "scalar")
    assert scalar_set == "scalar"  # the variable took effect
    auto_set, auto = _run(tmp_path, None)
    if auto_set == "scalar":  # pragma: no cover - a CPU without AVX2
        pytest.skip("this CPU has no vector variant to compare with (both runs are baseline)")
    assert scalar == auto, f"{auto_set} and baseline kernels differ"


def test_misspelt_setting_fails_the_import_with_the_core_message() -> None:
    # The core reads the variable when it is imported: by the first computation (``import
    # gyrobias`` alone is lazy and loads no core, so that ``gyrobias --help`` stays light).
    env = dict(os.environ, GYROBIAS_SIMD="scaler")
    for code in (
        "import gyrobias._core",
        "import gyrobias; gyrobias.adev",
        "import gyrobias.allan",
    ):
        proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
        assert proc.returncode == 1, code
        last = proc.stderr.strip().splitlines()[-1]
        assert last == "ValueError: GYROBIAS_SIMD must be 'auto' or 'scalar', got \"scaler\"", last


def test_instruction_set_names_the_variant_in_use() -> None:
    assert _core.instruction_set() in ("x86-64-v3", "neon", "scalar")
    if os.environ.get("GYROBIAS_SIMD", "").strip().lower() == "scalar":
        assert _core.instruction_set() == "scalar"

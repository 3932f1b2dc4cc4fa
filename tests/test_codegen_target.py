"""Generated C on Cortex-M: cross-compiled with arm-none-eabi-gcc, run on QEMU's MPS2 boards.

Every emitted routine (fixed-gain Kalman, Kaiser FIR, compiled predictor; float32 and Q31) is
compiled with ``-std=c99 -mthumb`` and the host build's warnings (``-Werror``) for

- the Cortex-M4F (``-mcpu=cortex-m4 -mfpu=fpv4-sp-d16 -mfloat-abi=hard``, board mps2-an386) and
- the Cortex-M3 (``-mcpu=cortex-m3``, no FPU: float32 is libgcc's soft float; board
  mps2-an385),

at ``-O2`` and ``-Os``, linked with ``tests/cortex_m/`` (vector table, reset handler,
semihosting) and run under ``qemu-system-arm`` (see ``tests/_target_harness.py``). Checked:

- float32 equals Python's ``dtype=np.float32`` paths bit for bit on both cores, on the host
  tests' vectors (white noise, step, ramp, a 200 000-sample random walk), on subnormal input
  and around NaN/±inf/overflow as the headers document;
- Q31 stays within the designed bound and gives the same bits on every core/optimisation;
- the compiled predictor equals ``CompiledPredictor.predict(..., dtype=np.float32)`` bit for bit;
- negative controls: the same test on an image built with ``-ffp-contract=fast`` (FPv4's
  fused VFMA) or with FPSCR.FZ = 1 (flush-to-zero) does see different bits, so the bit-exact
  checks can fail and the two settings matter.

Images are built once per session, two at a time (2 cores), each running all its jobs in one
emulator run. Skipped when the cross toolchain or QEMU is missing, unless
``GYROBIAS_REQUIRE_CORTEX_M=1`` (then a missing tool is a failure; `.ci/run` instead installs
the tools and fails if it cannot, so the tests run there).
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from gyrobias import fir
from gyrobias.kalman import FixedGainKalman
from gyrobias.predict import CompiledPredictor, FractionalKalmanPredictor
from tests import _target_harness as target
from tests.test_codegen import FIRS, KALMANS, _to_q31, _vectors

REQUIRE = os.environ.get("GYROBIAS_REQUIRE_CORTEX_M") == "1"
pytestmark = pytest.mark.skipif(
    not target.AVAILABLE and not REQUIRE,
    reason="needs arm-none-eabi-gcc, arm-none-eabi-size and qemu-system-arm",
)

BUILDS = [("m4", "-O2"), ("m4", "-Os"), ("m3", "-O2"), ("m3", "-Os")]
TOP = 1.0 - 2.0**-31
#: FIR float32 on the M3 (soft float) skips the 200 000-sample walk: ~10 s of emulation each.
SLOW_ON_M3 = {"walk"}


def _kf(key: str) -> FixedGainKalman:
    d = dict(KALMANS[key])
    fs = d.pop("fs")
    return FixedGainKalman(fs, **d)


def _fir(key: str) -> Any:
    fs, fp, fst, ap, ast = FIRS[key]
    return fir.kaiser_lowpass(fs, fp, fst, apass_db=ap, astop_db=ast)


PREDICTORS = {
    "sample": dict(d=0.5, q=1e-4, r=1e-4),
    "proper": dict(d=0.3, q=1e-4, r=4e-4, mean=(0.2, 0.01)),  # w0 != 0
}


@cache
def _pred(key: str) -> CompiledPredictor:
    return FractionalKalmanPredictor(**PREDICTORS[key]).compile(40, 15)  # type: ignore[arg-type]


@cache
def float_vectors() -> dict[str, np.ndarray]:
    """The host tests' vectors in float32, plus subnormal-scale noise and the NaN case."""
    v = {k: x.astype(np.float32) for k, x in _vectors().items()}
    rng = np.random.default_rng(11)
    # |x| ~ 1e-39 < 1.18e-38 (smallest normal float32): inputs, products and outputs subnormal
    v["tiny"] = (1e-39 * rng.normal(size=3000)).astype(np.float32)
    return v


@cache
def nan_vector() -> np.ndarray:
    """The host NaN test's input: NaN, ±inf, and a finite sample that overflows the level."""
    z = _vectors()["white"][:1000].astype(np.float32)
    z[100], z[200], z[300] = np.nan, np.inf, -np.inf
    z[400] = z[401] = np.finfo(np.float32).max
    return z


@cache
def q31_vectors() -> dict[str, np.ndarray]:
    v = {k: _to_q31(0.9 * x / np.abs(x).max()) for k, x in _vectors().items()}
    # saturation: full-scale square wave (outputs clip, never wrap)
    v["square"] = np.where((np.arange(3000) // 300) % 2 == 0, -(2**31), 2**31 - 1).astype(np.int32)
    return v


@cache
def windows() -> np.ndarray:
    rng = np.random.default_rng(3)
    return 0.2 + np.cumsum(rng.normal(0.0, 0.01, (30, 40)), axis=1)


@dataclass
class Image:
    routines: list[target.Routine]
    outputs: dict[tuple[str, str], bytes]  # (routine name, vector label) -> raw output


def _routines(src: Path) -> list[target.Routine]:
    rs = []
    for key in sorted(KALMANS):
        for dt, tag in (("float32", "f"), ("q31", "q")):
            rs.append(target.Routine("kalman", _kf(key).to_c(src, name=f"k_{key}_{tag}", dtype=dt)))
    for key in sorted(FIRS):
        for dt, tag in (("float32", "f"), ("q31", "q")):
            rs.append(target.Routine("fir", _fir(key).to_c(src, name=f"f_{key}_{tag}", dtype=dt)))
    for key in sorted(PREDICTORS):
        for dt, tag in (("float32", "f"), ("q31", "q")):
            gen = _pred(key).to_c(src, name=f"p_{key}_{tag}", dtype=dt)
            rs.append(target.Routine("pred", gen, k=40, h=15))
    return rs


def _jobs(routines: list[target.Routine], core: str) -> list[tuple[int, str, np.ndarray]]:
    jobs = []
    for i, r in enumerate(routines):
        if r.kind == "pred":
            w = windows()
            data = w.astype(np.float32) if r.gen.dtype == "float32" else _to_q31(w)
            jobs.append((i, "windows", data.ravel()))
        elif r.gen.dtype == "q31":
            jobs += [(i, label, x) for label, x in q31_vectors().items()]
        else:
            for label, x in float_vectors().items():
                if not (r.kind == "fir" and core == "m3" and label in SLOW_ON_M3):
                    jobs.append((i, label, x))
            jobs.append((i, "nan", nan_vector()))
    return jobs


def _build_and_run(
    routines: list[target.Routine], core: str, opt: str, wd: Path, **flags: Any
) -> Image:
    elf = target.build_image(routines, core, opt, wd, **flags)
    jobs = _jobs(routines, core)
    raw = target.run_jobs(elf, core, routines, [(i, x) for i, _, x in jobs])
    outs = {
        (routines[i].gen.name, label): out for (i, label, _), out in zip(jobs, raw, strict=True)
    }
    return Image(routines, outs)


@pytest.fixture(scope="session")
def images(tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict[str, Image]]:
    """Every build (and the two negative controls), two at a time."""
    root = tmp_path_factory.mktemp("cortex_m")
    routines = _routines(root / "src")
    f32 = [r for r in routines if r.gen.name in ("k_mems1k_f", "f_mems1k_f")]
    tasks: dict[str, tuple[list[target.Routine], str, str, dict[str, Any]]] = {
        f"{c}{o}": (routines, c, o, {}) for c, o in BUILDS
    }
    tasks["fma"] = (f32, "m4", "-O2", {"routine_flags": ("-ffp-contract=fast",)})
    tasks["ftz"] = (f32, "m4", "-O2", {"startup_flags": ("-DGYRO_FLUSH_TO_ZERO",)})
    with ThreadPoolExecutor(max_workers=2) as pool:
        futures = {
            tag: pool.submit(_build_and_run, rs, c, o, root / tag, **fl)
            for tag, (rs, c, o, fl) in tasks.items()
        }
        yield {tag: f.result() for tag, f in futures.items()}


def _same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def _names(kind: str, dtype: str) -> list[str]:
    keys = {"k": KALMANS, "f": FIRS, "p": PREDICTORS}[kind]
    return [f"{kind}_{key}_{'f' if dtype == 'float32' else 'q'}" for key in sorted(keys)]


BUILD_IDS = [f"{c}{o}" for c, o in BUILDS]


# --- float32: bit for bit ---------------------------------------------------------------------


@pytest.mark.parametrize("build", BUILD_IDS)
def test_kalman_float32_on_target_equals_python_bit_for_bit(
    build: str, images: dict[str, Image]
) -> None:
    img = images[build]
    for name, key in zip(_names("k", "float32"), sorted(KALMANS), strict=True):
        kf = _kf(key)
        for label, z in float_vectors().items():
            rate, bias, status, skipped = target.kalman_outputs(
                img.outputs[(name, label)], np.float32
            )
            ref = kf.filter(z, dtype=np.float32)
            assert not status.any() and skipped == 0, (build, key, label)
            assert _same_bits(rate, ref.rate), (build, key, label)
            assert _same_bits(bias, ref.bias), (build, key, label)


@pytest.mark.parametrize("build", BUILD_IDS)
def test_fir_float32_on_target_equals_python_bit_for_bit(
    build: str, images: dict[str, Image]
) -> None:
    img = images[build]
    checked = 0
    for name, key in zip(_names("f", "float32"), sorted(FIRS), strict=True):
        taps = _fir(key).taps
        for label, x in float_vectors().items():
            if (name, label) not in img.outputs:  # the walk on the M3 (soft float): slow
                assert build.startswith("m3") and label in SLOW_ON_M3
                continue
            y = np.frombuffer(img.outputs[(name, label)], dtype=np.float32)
            ref, _ = fir.stream(taps, x, dtype=np.float32)
            assert _same_bits(y, ref), (build, key, label)
            checked += 1
    assert checked >= 3 * 4


def test_subnormal_vector_exercises_subnormals() -> None:
    """The "tiny" vector really computes with subnormals (else FZ could not be detected)."""
    x = float_vectors()["tiny"]
    smallest_normal = np.finfo(np.float32).smallest_normal
    rate = _kf("mems1k").filter(x, dtype=np.float32).rate
    y, _ = fir.stream(_fir("mems1k").taps, x, dtype=np.float32)
    for out in (x, rate, y):
        nz = out[out != 0]
        assert np.mean(np.abs(nz) < smallest_normal) > 0.9


@pytest.mark.parametrize("build", BUILD_IDS)
def test_float32_non_finite_input_on_target_is_handled_as_documented(
    build: str, images: dict[str, Image]
) -> None:
    """Kalman: NaN/±inf/overflowing samples skipped with status 1/2, estimates held; FIR: a NaN
    poisons exactly the N outputs whose window holds it (as the host tests)."""
    img = images[build]
    z = nan_vector()
    kf = _kf("mems1k")
    rate, bias, status, skipped = target.kalman_outputs(
        img.outputs[("k_mems1k_f", "nan")], np.float32
    )
    bad = [100, 200, 300, 401]
    keep = np.setdiff1d(np.arange(z.size), bad)
    ref = kf.filter(z[keep], dtype=np.float32)
    want_rate, want_bias = np.empty_like(z), np.empty_like(z)
    want_rate[keep], want_bias[keep] = ref.rate, ref.bias
    for i in bad:
        want_rate[i], want_bias[i] = want_rate[i - 1], want_bias[i - 1]
    assert _same_bits(rate, want_rate) and _same_bits(bias, want_bias)
    assert skipped == 4
    # statuses of the samples fed through step() (even chunks of CHUNK samples)
    by_step = (np.arange(z.size) // target.CHUNK) % 2 == 0
    want_status = np.zeros(z.size, dtype=np.int32)
    want_status[bad] = [1, 1, 1, 2]
    assert np.array_equal(status[by_step], want_status[by_step])
    assert by_step[100] and by_step[200]  # both kinds of skip are seen through step()
    f = _fir("mems1k")
    y = np.frombuffer(img.outputs[("f_mems1k_f", "nan")], dtype=np.float32)
    nonfinite = np.flatnonzero(~np.isfinite(y))
    poisoned = set()
    for i in (100, 200, 300):
        poisoned |= set(range(i, i + f.numtaps))
    assert set(nonfinite.tolist()) == poisoned
    x = z.copy()
    x[[100, 200, 300]] = 0.0
    ref_y, _ = fir.stream(f.taps, x, dtype=np.float32)
    ok = np.setdiff1d(np.arange(z.size), nonfinite)
    assert _same_bits(y[ok], ref_y[ok])


@pytest.mark.parametrize("build", BUILD_IDS)
def test_predictor_float32_on_target_equals_python_bit_for_bit(
    build: str, images: dict[str, Image]
) -> None:
    y = windows().astype(np.float32)
    for name, key in zip(_names("p", "float32"), sorted(PREDICTORS), strict=True):
        out = np.frombuffer(images[build].outputs[(name, "windows")], dtype=np.float32)
        ref = _pred(key).predict(y, dtype=np.float32).bias
        assert ref.dtype == np.float32
        assert _same_bits(out.reshape(ref.shape), ref), (build, key)


# --- negative controls: FMA contraction and flush-to-zero change the bits ----------------------


def test_fused_multiply_add_on_the_m4_changes_the_bits(images: dict[str, Image]) -> None:
    """Built with -ffp-contract=fast, GCC fuses p*u + z into FPv4's VFMA (one rounding): the
    Kalman filter no longer equals Python — which is why every build says -ffp-contract=off."""
    img = images["fma"]
    kf = _kf("mems1k")
    differs = 0
    for label, z in float_vectors().items():
        rate, _, _, _ = target.kalman_outputs(img.outputs[("k_mems1k_f", label)], np.float32)
        differs += not _same_bits(rate, kf.filter(z, dtype=np.float32).rate)
    assert differs >= 3


def test_flush_to_zero_on_the_m4_changes_the_bits(images: dict[str, Image]) -> None:
    """With FPSCR.FZ = 1 (subnormals flushed, what some start-up files set for speed) the
    subnormal vector gives other bits, the normal-range ones do not: the reset handler's
    FPSCR = 0 (FZ off, as NumPy/Rust float32 on the host) is required for bit-exactness."""
    img = images["ftz"]
    kf = _kf("mems1k")
    for label, z in float_vectors().items():
        rate, _, _, _ = target.kalman_outputs(img.outputs[("k_mems1k_f", label)], np.float32)
        same = _same_bits(rate, kf.filter(z, dtype=np.float32).rate)
        assert same == (label != "tiny"), label


# --- Q31: within the bound, same bits everywhere -----------------------------------------------


@pytest.mark.parametrize("build", BUILD_IDS)
def test_kalman_q31_on_target_within_bound(build: str, images: dict[str, Image]) -> None:
    img = images[build]
    src_dir = img.routines[0].gen.header.parent
    for name, key in zip(_names("k", "q31"), sorted(KALMANS), strict=True):
        kf = _kf(key)
        gen = next(r.gen for r in img.routines if r.gen.name == name)
        assert gen.header.parent == src_dir
        bound_rate, bound_bias = gen.q31["error_bound"]
        for label, zq in q31_vectors().items():
            rate, bias, _, _ = target.kalman_outputs(img.outputs[(name, label)], np.int32)
            ref = kf.filter(zq / 2.0**31)
            err_r = np.abs(rate / 2.0**31 - np.clip(ref.rate, -1.0, TOP)).max()
            err_b = np.abs(bias / 2.0**31 - np.clip(ref.bias, -1.0, TOP)).max()
            assert err_r <= bound_rate, (build, key, label, err_r, bound_rate)
            assert err_b <= bound_bias, (build, key, label, err_b, bound_bias)


@pytest.mark.parametrize("build", BUILD_IDS)
def test_fir_q31_on_target_within_bound(build: str, images: dict[str, Image]) -> None:
    img = images[build]
    for name, key in zip(_names("f", "q31"), sorted(FIRS), strict=True):
        gen = next(r.gen for r in img.routines if r.gen.name == name)
        taps = _fir(key).taps
        for label, xq in q31_vectors().items():
            y = np.frombuffer(img.outputs[(name, label)], dtype=np.int32)
            ref, _ = fir.stream(taps, xq / 2.0**31)
            err = np.abs(y / 2.0**31 - np.clip(ref, -1.0, TOP)).max()
            assert err <= gen.q31["error_bound"], (build, key, label, err)


@pytest.mark.parametrize("build", BUILD_IDS)
def test_predictor_q31_on_target_within_bound(build: str, images: dict[str, Image]) -> None:
    img = images[build]
    yq = _to_q31(windows())
    for name, key in zip(_names("p", "q31"), sorted(PREDICTORS), strict=True):
        gen = next(r.gen for r in img.routines if r.gen.name == name)
        out = np.frombuffer(img.outputs[(name, "windows")], dtype=np.int32) / 2.0**31
        ref = _pred(key).predict(yq / 2.0**31).bias
        assert np.abs(out.reshape(ref.shape) - ref).max() <= gen.q31["error_bound"], (build, key)


def test_q31_bits_are_the_same_on_every_core_and_optimisation(images: dict[str, Image]) -> None:
    """Integer arithmetic with stated rounding: M3/M4 at -O2/-Os give identical Q31 outputs."""
    first = images[BUILD_IDS[0]].outputs
    q31 = [key for key in first if key[0].endswith("_q")]
    assert len(q31) == 4 * 5 + 3 * 5 + 2
    for build in BUILD_IDS[1:]:
        for key in q31:
            assert images[build].outputs[key] == first[key], (build, key)

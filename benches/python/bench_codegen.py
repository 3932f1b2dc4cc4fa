"""Cost of the generated C (gyrobias.codegen): ns/sample, object size, state RAM.

Run: ``PYTHONPATH=python python benches/python/bench_codegen.py`` (needs ``cc`` and ``size``).
Every generated routine is compiled with ``cc -std=c99 -O2 -ffp-contract=off`` and timed on
1e6 samples (best of 5, in C with ``clock_gettime``), next to

- the Python/Rust path (``FixedGainKalman.filter``, ``fir.stream``, ``CompiledPredictor.predict``
  per window) on the same samples, and
- a hand-written C baseline of the same filter (the textbook form a firmware engineer would
  type: the 2-state update ``X += G (z − H X)`` in float; a modulo-indexed circular FIR in
  float; a plain double loop for the predictor).

Object size is ``size``'s text + data + bss of the generated ``.o`` (coefficients included);
state RAM is ``sizeof`` the state struct, printed by the compiled harness. The machine is
shared: read ratios, not absolute numbers.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from gyrobias import fir
from gyrobias.kalman import FixedGainKalman
from gyrobias.predict import FractionalKalmanPredictor

N = 1_000_000
CFLAGS = ["-std=c99", "-O2", "-ffp-contract=off"]
CT = {"float64": "double", "float32": "float", "q31": "int32_t"}

TIMER = """
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <stdint.h>
#include <time.h>
static double now(void) {{ struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec; }}
"""

KALMAN_MAIN = (
    TIMER
    + """
#include "{name}.h"
int main(void) {{
    long n = {n}, i; int rep; double best = 1e30; {t} *z = malloc(sizeof({t}) * n),
    *r = malloc(sizeof({t}) * n), *b = malloc(sizeof({t}) * n); {name}_state s;
    srand(1); for (i = 0; i < n; ++i) z[i] = ({t})({amp} * (rand() / (double)RAND_MAX - 0.5));
    for (rep = 0; rep < 5; ++rep) {{ double t0 = now(); {name}_init(&s, z[0], 0);
        {name}_process(&s, z, r, b, (size_t)n); t0 = now() - t0; if (t0 < best) best = t0; }}
    printf("%.3f %zu %g\\n", best / n * 1e9, sizeof({name}_state), (double)r[n - 1]);
    return 0;
}}
"""
)

FIR_MAIN = (
    TIMER
    + """
#include "{name}.h"
int main(void) {{
    long n = {n}, i; int rep; double best = 1e30; {t} *x = malloc(sizeof({t}) * n),
    *y = malloc(sizeof({t}) * n); {name}_state s;
    srand(1); for (i = 0; i < n; ++i) x[i] = ({t})({amp} * (rand() / (double)RAND_MAX - 0.5));
    for (rep = 0; rep < 5; ++rep) {{ double t0 = now(); {name}_init(&s);
        {name}_process(&s, x, y, (size_t)n); t0 = now() - t0; if (t0 < best) best = t0; }}
    printf("%.3f %zu %g\\n", best / n * 1e9, sizeof({name}_state), (double)y[n - 1]);
    return 0;
}}
"""
)

PRED_MAIN = (
    TIMER
    + """
#include "{name}.h"
int main(void) {{
    /* per calibration sample: one step; per window (every k samples): all h forecasts */
    long n = {n}, i; int rep; double best = 1e30; {t} *y = malloc(sizeof({t}) * n),
    out[{up}_HORIZON]; {name}_state s; volatile {t} sink = 0;
    srand(1); for (i = 0; i < n; ++i) y[i] = ({t})({amp} * (rand() / (double)RAND_MAX - 0.5));
    for (rep = 0; rep < 5; ++rep) {{ double t0 = now(); {name}_init(&s);
        for (i = 0; i < n; ++i) if ({name}_step(&s, y[i]) && (i + 1) % {up}_CALIBRATION_LENGTH == 0) {{
            {name}_predict(&s, out); sink += out[0]; }}
        t0 = now() - t0; if (t0 < best) best = t0; }}
    printf("%.3f %zu %g\\n", best / n * 1e9, sizeof({name}_state), (double)sink);
    return 0;
}}
"""
)

HAND_KALMAN = (
    TIMER
    + """
/* Hand-written: X = [w, b], X += G (z - (w + b)), float. */
int main(void) {{
    long n = {n}, i; int rep; double best = 1e30; float *z = malloc(sizeof(float) * n),
    *r = malloc(sizeof(float) * n), *b = malloc(sizeof(float) * n);
    const float g1 = {g1}f, g2 = {g2}f;
    srand(1); for (i = 0; i < n; ++i) z[i] = (float)(10.0 * (rand() / (double)RAND_MAX - 0.5));
    for (rep = 0; rep < 5; ++rep) {{ double t0 = now(); float w = z[0], bb = 0.0f;
        for (i = 0; i < n; ++i) {{ float e = z[i] - (w + bb); w += g1 * e; bb += g2 * e;
            r[i] = w; b[i] = bb; }}
        t0 = now() - t0; if (t0 < best) best = t0; }}
    printf("%.3f %zu %g\\n", best / n * 1e9, 2 * sizeof(float), (double)r[n - 1] + b[0]);
    return 0;
}}
"""
)

HAND_FIR = (
    TIMER
    + """
/* Hand-written: circular buffer with a modulo index, float. */
static const float h[{nt}] = {{ {taps} }};
int main(void) {{
    long n = {n}, i; int rep; double best = 1e30; float *x = malloc(sizeof(float) * n),
    *y = malloc(sizeof(float) * n); float buf[{nt}]; unsigned int pos, k;
    srand(1); for (i = 0; i < n; ++i) x[i] = (float)(10.0 * (rand() / (double)RAND_MAX - 0.5));
    for (rep = 0; rep < 5; ++rep) {{ double t0 = now(); for (k = 0; k < {nt}; ++k) buf[k] = 0.0f;
        pos = 0; for (i = 0; i < n; ++i) {{ float acc = 0.0f; buf[pos] = x[i];
            for (k = 0; k < {nt}; ++k) acc += h[k] * buf[(pos + {nt} - k) % {nt}];
            y[i] = acc; pos = (pos + 1) % {nt}; }}
        t0 = now() - t0; if (t0 < best) best = t0; }}
    printf("%.3f %zu %g\\n", best / n * 1e9, sizeof(buf) + sizeof(pos), (double)y[n - 1]);
    return 0;
}}
"""
)


def compile_run(workdir: Path, tag: str, main: str, source: Path | None) -> tuple[float, int, int]:
    """Build and run one timing program: (ns/sample, state bytes, object bytes)."""
    cc = shutil.which("cc")
    assert cc is not None, "needs a C compiler"
    m = workdir / f"main_{tag}.c"
    m.write_text(main)
    objs, size = [], 0
    if source is not None:
        obj = workdir / f"{tag}.o"
        subprocess.run([cc, *CFLAGS, "-c", str(source), "-o", str(obj)], check=True)
        out = subprocess.run(["size", str(obj)], check=True, capture_output=True, text=True)
        size = sum(int(v) for v in out.stdout.splitlines()[1].split()[:3])
        objs = [str(obj)]
    exe = workdir / f"run_{tag}"
    subprocess.run([cc, *CFLAGS, "-w", f"-I{workdir}", str(m), *objs, "-o", str(exe)], check=True)
    ns, state, _ = subprocess.run(
        [str(exe)], check=True, capture_output=True, text=True
    ).stdout.split()
    return float(ns), int(state), size


def best_ns(fn, n: int, repeats: int = 5) -> float:  # type: ignore[no-untyped-def]
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times) / n * 1e9


def main() -> int:
    if shutil.which("cc") is None or shutil.which("size") is None:
        print("needs cc and size", file=sys.stderr)
        return 1
    kf = FixedGainKalman(1000.0, arw=0.005, rrw=1e-4, bandwidth=20.0)
    f = fir.kaiser_lowpass(1000.0, 20.0, 60.0, astop_db=60.0)
    pred = FractionalKalmanPredictor(d=0.5, q=1e-4, r=1e-4).compile(100, 50)
    rows = []
    z = np.random.default_rng(1).uniform(-5.0, 5.0, N)
    with tempfile.TemporaryDirectory() as tmp:
        wd = Path(tmp)
        for dtype in ("float64", "float32", "q31"):
            t = CT[dtype]
            amp = "2147483647.0" if dtype == "q31" else "10.0"
            g = kf.to_c(wd, name=f"kf_{dtype}", dtype=dtype)
            main_c = KALMAN_MAIN.format(name=g.name, t=t, n=N, amp=amp)
            rows.append(("kalman", dtype, *compile_run(wd, g.name, main_c, g.source)))
            g = f.to_c(wd, name=f"fir_{dtype}", dtype=dtype)
            main_c = FIR_MAIN.format(name=g.name, t=t, n=N, amp=amp)
            rows.append(
                (f"fir {f.numtaps} taps", dtype, *compile_run(wd, g.name, main_c, g.source))
            )
            g = pred.to_c(wd, name=f"pr_{dtype}", dtype=dtype)
            main_c = PRED_MAIN.format(name=g.name, t=t, n=N // 10, amp=amp, up=g.name.upper())
            rows.append(("predictor k=100 h=50", dtype, *compile_run(wd, g.name, main_c, g.source)))
        g1, g2 = kf.G
        rows.append(
            (
                "kalman",
                "hand C f32",
                *compile_run(wd, "hk", HAND_KALMAN.format(n=N, g1=g1, g2=g2), None),
            )
        )
        taps = ", ".join(f"{float(np.float32(v))!r}f" for v in f.taps)
        rows.append(
            (
                f"fir {f.numtaps} taps",
                "hand C f32",
                *compile_run(wd, "hf", HAND_FIR.format(n=N, nt=f.numtaps, taps=taps), None),
            )
        )
    z32 = z.astype(np.float32)
    py = [
        ("kalman", "Python/Rust f64", best_ns(lambda: kf.filter(z), N)),
        ("kalman", "Python/Rust f32", best_ns(lambda: kf.filter(z32, dtype=np.float32), N)),
        (
            f"fir {f.numtaps} taps",
            "Python/Rust f64 stream",
            best_ns(lambda: fir.stream(f.taps, z), N),
        ),
        (
            f"fir {f.numtaps} taps",
            "Python/Rust f32 stream",
            best_ns(lambda: fir.stream(f.taps, z32, dtype=np.float32), N),
        ),
    ]
    windows = z[: 1000 * 100].reshape(1000, 100)
    # per calibration sample, as the C: one window of k = 100 samples per 100 samples
    py.append(
        (
            "predictor k=100 h=50",
            "Python/Rust f64 batch",
            best_ns(lambda: pred.predict(windows), 100_000),
        )
    )
    print(f"{'routine':<24}{'variant':<24}{'ns/sample':>10}{'state B':>9}{'.o B':>9}")
    for name, variant, ns, state, size in rows:
        print(f"{name:<24}{variant:<24}{ns:>10.2f}{state:>9}{size if size else '-':>9}")
    for name, variant, ns in py:
        print(f"{name:<24}{variant:<24}{ns:>10.2f}{'-':>9}{'-':>9}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

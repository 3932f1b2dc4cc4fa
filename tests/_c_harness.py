"""Compile generated C with the system compiler and run it on test vectors (tests and bench)."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path
from typing import Any

import numpy as np

#: The flags the generated code must compile with, warning-free (issue 28).
STRICT = [
    "-std=c99",
    "-O2",
    "-Wall",
    "-Wextra",
    "-Wpedantic",
    "-Wconversion",
    "-Werror",
    "-ffp-contract=off",
]
CC = shutil.which("cc")
#: The second compiler (issue 36): every warning clang has, as errors, minus a named list:
#: -Wdeclaration-after-statement warns about what C99 allows (mixed declarations and code; it
#: exists for C89 portability, and the generated code is C99), -Wpadded reports the alignment
#: padding the compiler adds at the end of a state struct (informational: the padding is
#: inherent to a double buffer followed by an unsigned int, and harmless).
CLANG = shutil.which("clang")
CLANG_STRICT = [
    "-std=c99",
    "-O2",
    "-Weverything",
    "-Wno-declaration-after-statement",
    "-Wno-padded",
    "-Werror",
    "-ffp-contract=off",
]

_CTYPE = {
    "float64": ("double", np.float64),
    "float32": ("float", np.float32),
    "q31": ("int32_t", np.int32),
}

_KALMAN = """
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "{name}.h"
int main(int argc, char **argv) {{
    FILE *f = fopen(argv[1], "rb"); long n; {t} *z, *r, *b, *r2, *b2; int *st; {name}_state s;
    long i, skipped = 0;
    fseek(f, 0, SEEK_END); n = ftell(f) / (long)sizeof({t}); fseek(f, 0, SEEK_SET);
    z = malloc(sizeof({t}) * (size_t)n); r = malloc(sizeof({t}) * (size_t)n);
    b = malloc(sizeof({t}) * (size_t)n); st = malloc(sizeof(int) * (size_t)n);
    r2 = malloc(sizeof({t}) * (size_t)n); b2 = malloc(sizeof({t}) * (size_t)n);
    if (fread(z, sizeof({t}), (size_t)n, f) != (size_t)n) return 1; fclose(f);
    {name}_init(&s, z[0], 0);
    for (i = 0; i < n; ++i) {{ st[i] = {step}; }}
    f = fopen(argv[2], "wb"); fwrite(r, sizeof({t}), (size_t)n, f); fwrite(b, sizeof({t}), (size_t)n, f);
    fwrite(st, sizeof(int), (size_t)n, f);
    /* the block entry point from the same start must give the same bits (returns 3 if not) */
    {name}_init(&s, z[0], 0);
    {process};
    fclose(f);
    return memcmp(r, r2, sizeof({t}) * (size_t)n) || memcmp(b, b2, sizeof({t}) * (size_t)n) ? 3 : 0;
}}
"""

_FIR = """
#include <stdio.h>
#include <stdlib.h>
#include "{name}.h"
int main(int argc, char **argv) {{
    FILE *f = fopen(argv[1], "rb"); long n; {t} *x, *y; {name}_state s; long i, half;
    fseek(f, 0, SEEK_END); n = ftell(f) / (long)sizeof({t}); fseek(f, 0, SEEK_SET);
    x = malloc(sizeof({t}) * (size_t)n); y = malloc(sizeof({t}) * (size_t)n);
    if (fread(x, sizeof({t}), (size_t)n, f) != (size_t)n) return 1; fclose(f);
    {name}_init(&s);
    half = n / 3;  /* per-sample steps, then one block: both entry points */
    for (i = 0; i < half; ++i) y[i] = {name}_step(&s, x[i]);
    {name}_process(&s, x + half, y + half, (size_t)(n - half));
    f = fopen(argv[2], "wb"); fwrite(y, sizeof({t}), (size_t)n, f); fclose(f); return 0;
}}
"""

_PRED = """
#include <stdio.h>
#include <stdlib.h>
#include "{name}.h"
int main(int argc, char **argv) {{
    /* argv[1]: windows x k samples; each window: init, push (the first half by step, the rest
       by process), predict. argv[2]: windows x h forecasts. */
    FILE *f = fopen(argv[1], "rb"); long n, w, i, k = {up}_CALIBRATION_LENGTH, h = {up}_HORIZON;
    {t} *y, *out; {name}_state s;
    fseek(f, 0, SEEK_END); n = ftell(f) / (long)sizeof({t}); fseek(f, 0, SEEK_SET);
    y = malloc(sizeof({t}) * (size_t)n); out = malloc(sizeof({t}) * (size_t)(n / k * h));
    if (fread(y, sizeof({t}), (size_t)n, f) != (size_t)n) return 1; fclose(f);
    for (w = 0; w < n / k; ++w) {{
        {name}_init(&s);
        /* a few stale samples first: the window must slide them out */
        for (i = 0; i < 3; ++i) {name}_step(&s, y[w * k]);
        for (i = 0; i < k / 2; ++i) {name}_step(&s, y[w * k + i]);
        if (!{name}_process(&s, y + w * k + k / 2, (size_t)(k - k / 2))) return 2;
        if ({name}_predict(&s, out + w * h) != 0) return 3;
    }}
    f = fopen(argv[2], "wb"); fwrite(out, sizeof({t}), (size_t)(n / k * h), f); fclose(f); return 0;
}}
"""


def build(
    gen: Any, kind: str, workdir: Path, compiler: str = "cc", flags: list[str] | None = None
) -> Path:
    """Compile ``gen`` (a GeneratedC) with :data:`STRICT` (``compiler="clang"``:
    :data:`CLANG_STRICT`; or ``flags``) and link a harness; the executable."""
    cc = CLANG if compiler == "clang" else CC
    if flags is None:
        flags = CLANG_STRICT if compiler == "clang" else STRICT
    assert cc is not None
    t = _CTYPE[gen.dtype][0]
    name = gen.name
    if kind == "kalman":
        step = (
            f"({name}_step(&s, z[i], &r[i], &b[i]), 0)"
            if gen.dtype == "q31"
            else f"{name}_step(&s, z[i], &r[i], &b[i])"
        )
        if gen.dtype == "q31":
            process = f"{name}_process(&s, z, r2, b2, (size_t)n)"
        else:
            process = (
                f"skipped = (long){name}_process(&s, z, r2, b2, (size_t)n); "
                "for (i = 0; i < n; ++i) skipped -= st[i] != 0; if (skipped) return 4"
            )
        text = _KALMAN.format(name=name, t=t, step=step, process=process)
    elif kind == "fir":
        text = _FIR.format(name=name, t=t)
    else:
        text = _PRED.format(name=name, t=t, up=name.upper())
    harness = workdir / f"main_{name}_{compiler}.c"
    harness.write_text(text)
    obj = workdir / f"{name}_{compiler}.o"
    exe = workdir / f"run_{name}_{compiler}"
    res = subprocess.run(
        [cc, *flags, "-c", str(gen.source), "-o", str(obj)], capture_output=True, text=True
    )
    assert res.returncode == 0 and not res.stderr, res.stderr  # warning-free
    subprocess.run(
        [
            cc,
            "-std=c99",
            "-O2",
            "-w",
            f"-I{gen.header.parent}",
            str(harness),
            str(obj),
            "-o",
            str(exe),
        ],
        check=True,
        capture_output=True,
        text=True,
    )
    return exe


def run(exe: Path, data: np.ndarray, workdir: Path, tag: str = "x") -> bytes:
    """Run a harness on ``data`` (raw binary) and return its raw output."""
    src = workdir / f"in_{tag}.bin"
    dst = workdir / f"out_{tag}.bin"
    np.ascontiguousarray(data).tofile(src)
    subprocess.run([str(exe), str(src), str(dst)], check=True)
    return dst.read_bytes()


def numpy_type(dtype: str) -> Any:
    """NumPy scalar type of a generated dtype."""
    return _CTYPE[dtype][1]

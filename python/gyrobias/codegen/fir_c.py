"""C for :class:`gyrobias.fir.KaiserLowpass`: a streaming causal FIR with its own state, plus
CMSIS-DSP coefficient arrays."""

from __future__ import annotations

from typing import Any

import numpy as np

from gyrobias import _core
from gyrobias.codegen._c import (
    FP_NOTE,
    Q31_HELPERS,
    Q31_NOTE,
    SOURCE_PRELUDE,
    GeneratedC,
    array_body,
    check_arguments,
    float_literal,
    int_literal,
    preamble,
    write_pair,
)
from gyrobias.fir import KaiserLowpass


def _design_lines(f: KaiserLowpass) -> list[str]:
    return [
        "Kaiser-window FIR low-pass ([TS] eqs. 14-20; gyrobias SPEC section 7), causal form",
        "y[n] = sum_k h[k] x[n-k], zero initial history, delay (N-1)/2 samples.",
        f"Design: fs = {f.fs!r} Hz, fpass = {f.fpass!r} Hz, fstop = {f.fstop!r} Hz,",
        f"  apass = {f.apass_db!r} dB, astop = {f.astop_db!r} dB -> A = {f.attenuation_db!r} dB,",
        f"  alpha = {f.alpha!r}, N = {f.numtaps} taps, cut-off {f.cutoff!r} Hz.",
        "CMSIS-DSP: <name>_cmsis_f32 / <name>_cmsis_q31 hold the taps in the time-reversed",
        "order arm_fir_init_f32 / arm_fir_init_q31 expect ({b[N-1], ..., b[0]}); their pState",
        "needs numTaps + blockSize - 1 samples. The q31 array is unscaled Q31 (saturated).",
    ]


def emit(
    f: KaiserLowpass,
    path: Any,
    *,
    name: str = "gyro_fir",
    dtype: Any = "float32",
    full_scale: float | None = None,
) -> GeneratedC:
    """Write ``<name>.h``/``<name>.c`` for ``f`` into the directory ``path``."""
    if not isinstance(f, KaiserLowpass):
        raise TypeError(f"f must be a KaiserLowpass, got {type(f).__name__}")
    name, dtype, directory, fs_units = check_arguments(name, dtype, path, full_scale)
    taps = np.asarray(f.taps, dtype=np.float64)
    n = taps.size
    if taps.ndim != 1 or n == 0:
        # a zero-length delay line would make the generated step index an empty array
        raise ValueError(
            f"taps must be a non-empty 1-D array to generate C, got shape {taps.shape}"
        )
    if not np.all(np.isfinite(taps)):
        raise ValueError("taps must be finite")
    info: dict[str, Any] = {}
    cmsis = _cmsis_arrays(name, taps)
    if dtype == "q31":
        d = _core.codegen.dot_q31(np.ascontiguousarray(taps[None, :]), np.empty(0), 1.0)
        info = {
            "shift": d["shift"],
            "taps": list(d["values"]),
            "error_bound": d["error_bound"],
            "coefficient_error": d["coefficient_error"],
            "noise_rms": d["noise_rms"],
            "noise_dbfs": 20.0 * float(np.log10(d["noise_rms"])),
        }
        if fs_units is not None:
            info["full_scale"] = fs_units
            info["error_bound_units"] = d["error_bound"] * fs_units
            info["noise_rms_units"] = d["noise_rms"] * fs_units
        t, lits, note = "int32_t", [int_literal(v) for v in d["values"]], Q31_NOTE
        extra = [
            f"Q31: taps H[k] = round(h[k] * 2^{d['shift']}), accumulated exactly in int64_t,",
            f"  y = sat(round(acc * 2^-{d['shift']})); sum |H[k] 2^-n - h[k]| = "
            f"{d['coefficient_error']:.3e}.",
            f"Error against float64 (same input): worst case {d['error_bound']:.3e} FS; RMS",
            f"  quantisation noise {d['noise_rms']:.3e} FS = {info['noise_dbfs']:.1f} dBFS.",
        ]
        if fs_units is not None:
            extra.append(
                f"With FS = {fs_units!r} u/s: bound {d['error_bound'] * fs_units:.3e} u/s, "
                f"noise {d['noise_rms'] * fs_units:.3e} u/s RMS."
            )
        elem = 4
    else:
        t = "float" if dtype == "float32" else "double"
        lits = [float_literal(float(v), dtype) for v in taps]
        ref = (
            "fir.stream(taps, x, dtype=np.float32)"
            if dtype == "float32"
            else "fir.stream(taps, x) (float64)"
        )
        note = FP_NOTE.format(ref=ref)
        extra = [
            "Sum order (the float64/float32 kernels'): acc = 0, then for k = 0, 8, 16, ... while",
            "8 taps remain acc += h[k]x[n-k] + ... + h[k+7]x[n-k-7] (left to right), then",
            "acc += h[k]x[n-k] for the rest. A NaN/inf input makes the N outputs whose window",
            "holds it NaN/inf; afterwards the output is exact again (finite memory).",
        ]
        elem = 4 if dtype == "float32" else 8
    block_init, block_body = _block(name, name.upper(), n, dtype, t, info.get("shift", 0))
    pre = preamble(f"streaming FIR low-pass, {dtype}", name, [*_design_lines(f), *extra], note)
    up = name.upper()
    guard = f"{up}_H"
    std = "#include <stdint.h>\n" if dtype == "q31" else ""
    header = f"""{pre}
#ifndef {guard}
#define {guard}

#include <stddef.h>
#include <stdint.h>

#define {up}_NUM_TAPS {n}u
#define {up}_DELAY {(n - 1) // 2}u
#define {up}_FS_HZ {float(f.fs)!r}

/* Filter state: the last N inputs, stored twice so that the window is contiguous. */
typedef struct {{
    {t} buf[2 * {n}];
    unsigned int pos;
}} {name}_state;

/* Zero history (like gyrobias' stream without a state). */
void {name}_init({name}_state *s);

/* One input sample; returns the output sample. */
{t} {name}_step({name}_state *s, {t} x);

/* n samples; y may equal x (in place). Same results as n calls of step(), four outputs at a
 * time; uses (N + 3) samples of stack ({(n + 3) * elem} bytes). */
void {name}_process({name}_state *s, const {t} *x, {t} *y, size_t n);

/* CMSIS-DSP coefficient arrays (time-reversed taps). */
extern const float {name}_cmsis_f32[{n}];
extern const int32_t {name}_cmsis_q31[{n}];

#endif /* {guard} */
"""
    if dtype == "q31":
        body = f"""    int64_t acc = 0;
    unsigned int k;
    for (k = 0; k < {up}_NUM_TAPS; ++k) {{
        acc += (int64_t){name}_taps[k] * (int64_t)w[k];
    }}
    return {name}_sat32({name}_rshift(acc, {info["shift"]}u));"""
        helpers = Q31_HELPERS.format(name=name)
        zero = "0"
    else:
        zero = "0.0f" if dtype == "float32" else "0.0"
        groups = n // 8
        terms = "\n             + ".join(f"{name}_taps[k + {j}] * w[k + {j}]" for j in range(8))
        group_loop = (
            f"""    for (; k < {8 * groups}u; k += 8u) {{
        acc += {terms};
    }}
"""
            if groups
            else ""
        )
        body = f"""    {t} acc = {zero};
    unsigned int k = 0;
{group_loop}    for (; k < {up}_NUM_TAPS; ++k) {{
        acc += {name}_taps[k] * w[k];
    }}
    return acc;"""
        helpers = SOURCE_PRELUDE
    del std
    source = f"""{pre}
#include "{name}.h"

{helpers}
static const {t} {name}_taps[{n}] = {{
{array_body(lits)}
}};

{cmsis}
void {name}_init({name}_state *s)
{{
    unsigned int i;
    for (i = 0; i < 2u * {up}_NUM_TAPS; ++i) {{
        s->buf[i] = {zero};
    }}
    s->pos = 0u;
}}

static void {name}_push({name}_state *s, {t} x)
{{
    unsigned int pos = s->pos == 0u ? {up}_NUM_TAPS - 1u : s->pos - 1u;
    s->buf[pos] = x;
    s->buf[pos + {up}_NUM_TAPS] = x;
    s->pos = pos;
}}

{t} {name}_step({name}_state *s, {t} x)
{{
    const {t} *w;
    {name}_push(s, x);
    w = &s->buf[s->pos]; /* w[k] = x[n - k] */
{body}
}}

void {name}_process({name}_state *s, const {t} *x, {t} *y, size_t n)
{{
    /* Four outputs at a time from a stack copy of the window (r: newest first; output b reads
     * r + 3 - b): four independent sums, each with exactly step()'s operations in step()'s
     * order, so the results are the same bits; the rest sample by sample. */
    {t} r[{n} - 1 + 4];
    size_t i = 0;
    unsigned int j, k;
    while (i + 4u <= n) {{
        const {t} *w = &s->buf[s->pos];
{block_init}
        for (j = 0; j < {up}_NUM_TAPS - 1u; ++j) {{
            r[4 + j] = w[j];
        }}
        r[0] = x[i + 3];
        r[1] = x[i + 2];
        r[2] = x[i + 1];
        r[3] = x[i];
        k = 0;
{block_body}
        for (j = 0; j < 4u; ++j) {{
            {name}_push(s, r[3 - j]); /* from r: y may be x */
        }}
        i += 4;
    }}
    for (; i < n; ++i) {{
        y[i] = {name}_step(s, x[i]);
    }}
}}
"""
    h, c = write_pair(directory, name, header, source)
    return GeneratedC(h, c, name, dtype, 2 * n * elem + 4, info)


def _block(name: str, up: str, n: int, dtype: str, t: str, shift: int) -> tuple[str, str]:
    """The four-output block of ``process``: accumulator declarations and the sums."""
    ind = " " * 8
    if dtype == "q31":
        init = f"{ind}int64_t a0 = 0, a1 = 0, a2 = 0, a3 = 0;"
        sums = "\n".join(
            f"{ind}    a{b} += (int64_t){name}_taps[k] * (int64_t)r[{3 - b} + k];" for b in range(4)
        )
        outs = "\n".join(
            f"{ind}y[i + {b}] = {name}_sat32({name}_rshift(a{b}, {shift}u));" for b in range(4)
        )
        body = f"""{ind}for (; k < {up}_NUM_TAPS; ++k) {{
{sums}
{ind}}}
{outs}"""
        return init, body
    zero = "0.0f" if dtype == "float32" else "0.0"
    init = f"{ind}{t} a0 = {zero}, a1 = {zero}, a2 = {zero}, a3 = {zero};"
    groups = n // 8
    parts = []
    if groups:
        group_sums = "\n".join(
            f"{ind}    a{b} += "
            + f"\n{ind}          + ".join(
                f"{name}_taps[k + {j}] * r[{3 - b} + k + {j}]" for j in range(8)
            )
            + ";"
            for b in range(4)
        )
        parts.append(f"{ind}for (; k < {8 * groups}u; k += 8u) {{\n{group_sums}\n{ind}}}")
    rest = "\n".join(f"{ind}    a{b} += {name}_taps[k] * r[{3 - b} + k];" for b in range(4))
    parts.append(f"{ind}for (; k < {up}_NUM_TAPS; ++k) {{\n{rest}\n{ind}}}")
    parts.append("\n".join(f"{ind}y[i + {b}] = a{b};" for b in range(4)))
    return init, "\n".join(parts)


def _cmsis_arrays(name: str, taps: np.ndarray) -> str:
    rev = taps[::-1]
    f32 = [float_literal(float(v), "float32") for v in rev]
    q = np.clip(np.round(rev * 2.0**31), -(2.0**31), 2.0**31 - 1).astype(np.int64)
    q31 = [int_literal(int(v)) for v in q]
    return (
        f"const float {name}_cmsis_f32[{taps.size}] = {{\n{array_body(f32)}\n}};\n\n"
        f"const int32_t {name}_cmsis_q31[{taps.size}] = {{\n{array_body(q31)}\n}};\n"
    )


__all__ = ["emit"]

"""C for :class:`gyrobias.predict.CompiledPredictor`: the linear map ``ŷ = W·y + w0`` over a
sliding calibration window."""

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
from gyrobias.predict import CompiledPredictor


def emit(
    cp: CompiledPredictor,
    path: Any,
    *,
    name: str = "gyro_pred",
    dtype: Any = "float32",
    full_scale: float | None = None,
) -> GeneratedC:
    """Write ``<name>.h``/``<name>.c`` for ``cp`` into the directory ``path``."""
    if not isinstance(cp, CompiledPredictor):
        raise TypeError(f"cp must be a CompiledPredictor, got {type(cp).__name__}")
    name, dtype, directory, fs_units = check_arguments(name, dtype, path, full_scale)
    w = np.ascontiguousarray(cp.weights, dtype=np.float64)
    w0 = np.ascontiguousarray(cp.offset, dtype=np.float64)
    h, k = w.shape
    pr = cp.predictor
    lines = [
        "Compiled fractional (1/f) Kalman bias predictor ([BP] section IV-A; gyrobias SPEC",
        "section 5): after k calibration samples y[0..k-1] (oldest first), the bias forecast",
        "for the next h samples is yhat[j] = w0[j] + sum_i W[j][i] y[i].",
        f"Design: d = {pr.d!r}, q = {pr.q!r}, r = {pr.r!r}, mean = {pr.mean!r},",
        f"  k = {k} calibration samples, h = {h} predicted samples",
        f"  (W: {h * k} constants = {h * k * (8 if dtype == 'float64' else 4)} bytes of flash).",
        "step() pushes one calibration sample into a sliding window of the last k samples;",
        "predict() / predict_one() evaluate the forecast from the current window.",
    ]
    info: dict[str, Any] = {}
    if dtype == "q31":
        d = _core.codegen.dot_q31(w, w0, 1.0)
        info = {
            "shift": d["shift"],
            "error_bound": d["error_bound"],
            "coefficient_error": d["coefficient_error"],
            "noise_rms": d["noise_rms"],
            "noise_dbfs": 20.0 * float(np.log10(d["noise_rms"])),
        }
        if fs_units is not None:
            info["full_scale"] = fs_units
            info["error_bound_units"] = d["error_bound"] * fs_units
        t, note = "int32_t", Q31_NOTE
        w_lits = [int_literal(v) for v in d["values"]]
        o_lits = [int_literal(v) for v in d["offsets"]]
        lines += [
            f"Q31: W scaled by 2^{d['shift']}, exact int64_t sums, rounded back, + w0 (Q31).",
            f"Error against float64 (|y| <= FS): worst case {d['error_bound']:.3e} FS.",
        ]
        body = f"""    int64_t acc = 0;
    unsigned int i;
    for (i = 0; i < {k}u; ++i) {{
        acc += (int64_t)row[i] * (int64_t)win[i];
    }}
    return {name}_sat32({name}_rshift(acc, {d["shift"]}u) + (int64_t){name}_w0[j]);"""
        helpers = Q31_HELPERS.format(name=name)
        zero = "0"
        elem = 4
    else:
        t = "float" if dtype == "float32" else "double"
        zero = "0.0f" if dtype == "float32" else "0.0"
        np_type = "np.float32" if dtype == "float32" else "np.float64"
        note = FP_NOTE.format(ref=f"CompiledPredictor.predict(windows, dtype={np_type})")
        w_lits = [float_literal(float(v), dtype) for v in w.ravel()]
        o_lits = [float_literal(float(v), dtype) for v in w0]
        lines += ["Sum order: acc = 0; acc += W[j][i] * y[i] for i = 0..k-1; yhat = acc + w0[j]."]
        body = f"""    {t} acc = {zero};
    unsigned int i;
    for (i = 0; i < {k}u; ++i) {{
        acc += row[i] * win[i];
    }}
    return acc + {name}_w0[j];"""
        helpers = SOURCE_PRELUDE
        elem = 4 if dtype == "float32" else 8
    pre = preamble(f"compiled bias predictor, {dtype}", name, lines, note)
    up = name.upper()
    guard = f"{up}_H"
    header = f"""{pre}
#ifndef {guard}
#define {guard}

#include <stddef.h>
#include <stdint.h>

#define {up}_CALIBRATION_LENGTH {k}u
#define {up}_HORIZON {h}u

/* Sliding window of the last k calibration samples, stored twice (contiguous window). */
typedef struct {{
    {t} buf[2 * {k}];
    unsigned int pos;   /* index of the oldest sample */
    unsigned int count; /* samples pushed, saturating at k */
}} {name}_state;

/* Empty window. */
void {name}_init({name}_state *s);

/* Push one calibration sample; returns 1 once the window holds k samples, else 0. */
int {name}_step({name}_state *s, {t} y);

/* Push n samples; returns {name}_step's value for the last one (0 if n == 0 and not full). */
int {name}_process({name}_state *s, const {t} *y, size_t n);

/* Forecast j (0 <= j < h) for the current window (meaningful once the window is full). */
{t} {name}_predict_one(const {name}_state *s, unsigned int j);

/* All h forecasts into out[0..h-1]; returns 0, or -1 (out untouched) if the window is not
 * full yet. */
int {name}_predict(const {name}_state *s, {t} *out);

#endif /* {guard} */
"""
    source = f"""{pre}
#include "{name}.h"

{helpers}
static const {t} {name}_W[{h * k}] = {{
{array_body(w_lits)}
}};

static const {t} {name}_w0[{h}] = {{
{array_body(o_lits)}
}};

void {name}_init({name}_state *s)
{{
    unsigned int i;
    for (i = 0; i < 2u * {k}u; ++i) {{
        s->buf[i] = {zero};
    }}
    s->pos = 0u;
    s->count = 0u;
}}

int {name}_step({name}_state *s, {t} y)
{{
    /* The window is buf[pos .. pos + k - 1], oldest first; the new sample replaces the
     * oldest, which then becomes the newest. */
    s->buf[s->pos] = y;
    s->buf[s->pos + {k}u] = y;
    s->pos = s->pos + 1u == {k}u ? 0u : s->pos + 1u;
    if (s->count < {k}u) {{
        ++s->count;
    }}
    return s->count == {k}u;
}}

int {name}_process({name}_state *s, const {t} *y, size_t n)
{{
    size_t i;
    int full = s->count == {k}u;
    for (i = 0; i < n; ++i) {{
        full = {name}_step(s, y[i]);
    }}
    return full;
}}

{t} {name}_predict_one(const {name}_state *s, unsigned int j)
{{
    const {t} *win = &s->buf[s->pos];
    const {t} *row = &{name}_W[j * {k}u];
{body}
}}

int {name}_predict(const {name}_state *s, {t} *out)
{{
    unsigned int j;
    if (s->count < {k}u) {{
        return -1;
    }}
    for (j = 0; j < {h}u; ++j) {{
        out[j] = {name}_predict_one(s, j);
    }}
    return 0;
}}
"""
    hp, cp_ = write_pair(directory, name, header, source)
    return GeneratedC(hp, cp_, name, dtype, 2 * k * elem + 8, info)


__all__ = ["emit"]

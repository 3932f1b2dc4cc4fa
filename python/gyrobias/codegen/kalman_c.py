"""C for :class:`gyrobias.kalman.FixedGainKalman` (one axis per state struct)."""

from __future__ import annotations

from typing import Any

from gyrobias import _core
from gyrobias.codegen._c import (
    FP_NOTE,
    Q31_HELPERS,
    Q31_NOTE,
    SOURCE_PRELUDE,
    GeneratedC,
    check_arguments,
    float_literal,
    int_literal,
    preamble,
    write_pair,
)
from gyrobias.kalman import FixedGainKalman


def _design_lines(kf: FixedGainKalman) -> list[str]:
    bw = kf.bandwidth
    g = kf.G
    return [
        "Fixed-gain [rate, bias] Kalman filter ([NR]; gyrobias SPEC section 6), one axis.",
        f"Design: fs = {kf.fs!r} Hz, ARW = {kf._arw!r} u/sqrt(s), RRW = {kf._rrw!r} u/s^1.5,",
        f"  q_omega = {kf.q_omega!r} (u/s)^2 per step, form = {kf.form!r},",
        f"  -3 dB bandwidth = {'above Nyquist' if bw is None else repr(bw) + ' Hz'},",
        f"  gain G = [{float(g[0])!r}, {float(g[1])!r}], pole p = {kf.pole!r},",
        f"  DC gain = {kf.dc_gain!r}.",
        "Recursion (scaled level u = (rate + bias)/(1 - p), constant offset c):",
        "  u <- p*u + z;  rate = g1*u + c;  bias = g2*u - c      (g2 = (1 - p) - g1)",
        "Start with init(&s, z0, 0) for gyrobias' default x0 = [z0, 0].",
    ]


def emit(
    kf: FixedGainKalman,
    path: Any,
    *,
    name: str = "gyro_kf",
    dtype: Any = "float32",
    full_scale: float | None = None,
) -> GeneratedC:
    """Write ``<name>.h``/``<name>.c`` for ``kf`` into the directory ``path``."""
    if not isinstance(kf, FixedGainKalman):
        raise TypeError(f"kf must be a FixedGainKalman, got {type(kf).__name__}")
    name, dtype, directory, fs_units = check_arguments(name, dtype, path, full_scale)
    if dtype == "q31":
        header, source, info, size = _q31(kf, name, fs_units)
    else:
        header, source, size = _float(kf, name, dtype)
        info = {}
    h, c = write_pair(directory, name, header, source)
    return GeneratedC(h, c, name, dtype, size, info)


def _coefficients(kf: FixedGainKalman) -> tuple[float, float, float, float]:
    """``(p, g1, g2, 1 - p)`` exactly as the core's kernel rounds them."""
    c = kf._core.kernel_coefficients()
    return c[0], c[1], c[2], c[3]


def _float(kf: FixedGainKalman, name: str, dtype: str) -> tuple[str, str, int]:
    t = "float" if dtype == "float32" else "double"
    zero = "0.0f" if dtype == "float32" else "0.0"
    p, g1, g2, k = _coefficients(kf)
    ref = (
        "FixedGainKalman.filter(z, dtype=np.float32)"
        if dtype == "float32"
        else "FixedGainKalman.filter(z) (float64)"
    )
    pre = preamble(
        f"fixed-gain Kalman filter, {dtype}",
        name,
        [
            *_design_lines(kf),
            "",
            "Non-finite input (NaN, +-inf) or a level that would overflow: the sample is",
            "skipped (state unchanged, outputs = the previous estimates) and step returns",
            "nonzero; gyrobias' filter raises ValueError instead and also leaves its state.",
        ],
        FP_NOTE.format(ref=ref),
    )
    guard = f"{name.upper()}_H"
    header = f"""{pre}
#ifndef {guard}
#define {guard}

#include <stddef.h>

#define {name.upper()}_FS_HZ {float(kf.fs)!r}

/* Filter state of one axis (plain data: copy it, zero it, keep it anywhere). */
typedef struct {{
    {t} level;  /* u = (rate + bias) / (1 - p) */
    {t} offset; /* c = rate - g1 * u (constant) */
    {t} rate;   /* last rate estimate */
    {t} bias;   /* last bias estimate */
}} {name}_state;

/* Start from the estimates [rate0, bias0]; gyrobias' default is [z0, 0]. */
void {name}_init({name}_state *s, {t} rate0, {t} bias0);

/* One sample z: writes the estimates to *rate and *bias (both non-NULL). Returns 0, or 1 if
 * z is not finite / 2 if the level would overflow (sample skipped, previous estimates). */
int {name}_step({name}_state *s, {t} z, {t} *rate, {t} *bias);

/* n samples; rate and bias may not alias z. Returns the number of skipped samples. */
size_t {name}_process({name}_state *s, const {t} *z, {t} *rate, {t} *bias, size_t n);

#endif /* {guard} */
"""

    def lit(x: float) -> str:
        return float_literal(x, dtype)

    source = f"""{pre}
#include "{name}.h"

{SOURCE_PRELUDE}
static const {t} {name}_p = {lit(p)};  /* pole p = {p!r} */
static const {t} {name}_g1 = {lit(g1)}; /* g1 = {g1!r} */
static const {t} {name}_g2 = {lit(g2)}; /* g2 = (1 - p) - g1 = {g2!r} */
static const {t} {name}_k = {lit(k)};  /* 1 - p = {k!r} */

void {name}_init({name}_state *s, {t} rate0, {t} bias0)
{{
    s->level = (rate0 + bias0) / {name}_k;
    s->offset = rate0 - {name}_g1 * s->level;
    s->rate = rate0;
    s->bias = bias0;
}}

int {name}_step({name}_state *s, {t} z, {t} *rate, {t} *bias)
{{
    {t} u;
    int status = 0;
    if (!(z - z == {zero})) {{
        status = 1; /* NaN or +-inf */
    }} else {{
        u = {name}_p * s->level + z;
        if (!(u - u == {zero})) {{
            status = 2; /* overflow */
        }} else {{
            s->level = u;
            s->rate = {name}_g1 * u + s->offset;
            s->bias = {name}_g2 * u - s->offset;
        }}
    }}
    *rate = s->rate;
    *bias = s->bias;
    return status;
}}

size_t {name}_process({name}_state *s, const {t} *z, {t} *rate, {t} *bias, size_t n)
{{
    /* step() on local copies of the state (registers: the outputs could alias it), the same
     * operations in the same order. */
    {t} level = s->level, r = s->rate, b = s->bias, u;
    const {t} offset = s->offset;
    size_t i, skipped = 0;
    for (i = 0; i < n; ++i) {{
        if (!(z[i] - z[i] == {zero})) {{
            ++skipped;
        }} else {{
            u = {name}_p * level + z[i];
            if (!(u - u == {zero})) {{
                ++skipped;
            }} else {{
                level = u;
                r = {name}_g1 * u + offset;
                b = {name}_g2 * u - offset;
            }}
        }}
        rate[i] = r;
        bias[i] = b;
    }}
    s->level = level;
    s->rate = r;
    s->bias = b;
    return skipped;
}}
"""
    size = 4 * (4 if dtype == "float32" else 8)
    return header, source, size


def _q31(
    kf: FixedGainKalman, name: str, fs_units: float | None
) -> tuple[str, str, dict[str, Any], int]:
    p, g1, g2, k = _coefficients(kf)
    del p
    d = _core.codegen.kalman_q31(float(kf.pole), k, g1, g2, 1.0)
    a, r, b = d["a"], d["rate_gain"], d["bias_gain"]
    bound_rate, bound_bias = d["error_bound"]
    noise_rate, noise_bias = d["noise_rms"]
    info: dict[str, Any] = {
        "a": dict(a),
        "rate_gain": dict(r),
        "bias_gain": dict(b),
        "error_bound": (bound_rate, bound_bias),
        "noise_rms": (noise_rate, noise_bias),
        "noise_dbfs": (_db(noise_rate), _db(noise_bias)),
    }
    units = []
    if fs_units is not None:
        info["full_scale"] = fs_units
        info["error_bound_units"] = (bound_rate * fs_units, bound_bias * fs_units)
        info["noise_rms_units"] = (noise_rate * fs_units, noise_bias * fs_units)
        units = [
            f"With FS = {fs_units!r} u/s: bound {bound_rate * fs_units:.3e} u/s (rate),",
            f"  RMS quantisation noise {noise_rate * fs_units:.3e} u/s (rate).",
        ]
    shift_a = a["shift"] - 31
    if shift_a == 0:
        update = f"(int64_t){name}_A * e"
    else:
        update = f"{name}_rshift((int64_t){name}_A * e, {shift_a}u)"
    pre = preamble(
        "fixed-gain Kalman filter, Q31",
        name,
        [
            *_design_lines(kf),
            "Q31 form on the observable sum s = rate + bias = (1 - p) * u, kept with 62",
            "fractional bits in an int64_t (gyrobias' gyrocore::codegen documents the analysis):",
            "  s31 = round(S * 2^-31);  e = z - s31;  S += round(A * e * 2^-(nA - 31))",
            "  rate = sat(round(D1 * s31 * 2^-n1) + c);  bias = sat(round(D2 * s31 * 2^-n2) - c)",
            f"  A  = {a['value']} * 2^-{a['shift']} (1 - p = {k!r})",
            f"  D1 = {r['value']} * 2^-{r['shift']} (g1 / (1 - p) = {g1 / k!r})",
            f"  D2 = {b['value']} * 2^-{b['shift']} (g2 / (1 - p) = {g2 / k!r})",
            "Error against the float64 filter (same input, |z| <= FS, |rate0 + bias0| <= FS):",
            f"  worst case {bound_rate:.3e} FS (rate), {bound_bias:.3e} FS (bias);",
            f"  RMS quantisation noise {noise_rate:.3e} FS = {_db(noise_rate):.1f} dBFS (rate).",
            *units,
            "Inputs beyond full scale cannot occur (int32_t); outputs saturate.",
        ],
        Q31_NOTE,
    )
    guard = f"{name.upper()}_H"
    header = f"""{pre}
#ifndef {guard}
#define {guard}

#include <stddef.h>
#include <stdint.h>

#define {name.upper()}_FS_HZ {float(kf.fs)!r}

/* Filter state of one axis (plain data). */
typedef struct {{
    int64_t s;      /* rate + bias, 62 fractional bits */
    int32_t s31;    /* s rounded to Q31 */
    int32_t offset; /* c = rate - g1 / (1 - p) * s (constant) */
    int32_t rate;   /* last rate estimate (Q31) */
    int32_t bias;   /* last bias estimate (Q31) */
}} {name}_state;

/* Start from the estimates [rate0, bias0] (Q31); gyrobias' default is [z0, 0]. */
void {name}_init({name}_state *s, int32_t rate0, int32_t bias0);

/* One Q31 sample z: writes the estimates to *rate and *bias (both non-NULL). */
void {name}_step({name}_state *s, int32_t z, int32_t *rate, int32_t *bias);

/* n samples; rate and bias may not alias z. */
void {name}_process({name}_state *s, const int32_t *z, int32_t *rate, int32_t *bias, size_t n);

#endif /* {guard} */
"""
    source = f"""{pre}
#include "{name}.h"

{Q31_HELPERS.format(name=name)}
static const int32_t {name}_A = {int_literal(a["value"])};
static const int32_t {name}_D1 = {int_literal(r["value"])};
static const int32_t {name}_D2 = {int_literal(b["value"])};
#define {name.upper()}_S_MAX (INT64_C(1) << 62)

static int64_t {name}_clamp62(int64_t v)
{{
    return v > {name.upper()}_S_MAX - 1 ? {name.upper()}_S_MAX - 1
         : (v < -{name.upper()}_S_MAX ? -{name.upper()}_S_MAX : v);
}}

void {name}_init({name}_state *s, int32_t rate0, int32_t bias0)
{{
    int64_t sum = (int64_t)rate0 + (int64_t)bias0;
    s->s = {name}_clamp62(sum * (INT64_C(1) << 31));
    s->s31 = {name}_sat32({name}_rshift(s->s, 31u));
    s->offset = {name}_sat32(
        (int64_t)rate0 - {name}_rshift((int64_t){name}_D1 * s->s31, {r["shift"]}u));
    s->rate = rate0;
    s->bias = bias0;
}}

void {name}_step({name}_state *s, int32_t z, int32_t *rate, int32_t *bias)
{{
    int64_t e = (int64_t)z - (int64_t)s->s31;
    s->s = {name}_clamp62(s->s + {update});
    s->s31 = {name}_sat32({name}_rshift(s->s, 31u));
    s->rate = {name}_sat32(
        {name}_rshift((int64_t){name}_D1 * s->s31, {r["shift"]}u) + (int64_t)s->offset);
    s->bias = {name}_sat32(
        {name}_rshift((int64_t){name}_D2 * s->s31, {b["shift"]}u) - (int64_t)s->offset);
    *rate = s->rate;
    *bias = s->bias;
}}

void {name}_process({name}_state *s, const int32_t *z, int32_t *rate, int32_t *bias, size_t n)
{{
    size_t i;
    for (i = 0; i < n; ++i) {{
        {name}_step(s, z[i], &rate[i], &bias[i]);
    }}
}}
"""
    return header, source, info, 8 + 4 * 4


def _db(x: float) -> float:
    import math

    return 20.0 * math.log10(x) if x > 0 else float("-inf")


__all__ = ["emit"]

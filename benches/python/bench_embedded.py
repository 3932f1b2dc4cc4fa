"""Cost of the generated C on Cortex-M: flash, RAM and instructions per sample, on QEMU.

Run: ``PYTHONPATH=python python benches/python/bench_embedded.py`` (needs arm-none-eabi-gcc,
arm-none-eabi-size, arm-none-eabi-nm and qemu-system-arm; Debian packages gcc-arm-none-eabi,
libnewlib-arm-none-eabi, qemu-system-arm).

For each routine (fixed-gain Kalman, a 93-tap Kaiser FIR, the compiled predictor with k = 100,
h = 50) and type (float32 on the Cortex-M4F; Q31 on the M4 and on the M3) at -O2 and -Os, the
generated C and a plain hand-written C loop of the same filter are built with the same flags as
the target tests (``tests/_target_harness.cflags``: -std=c99 -mthumb, the core's flags,
-ffp-contract=off, the host warnings with -Werror) and linked with --gc-sections into an image
for the core's MPS2 board that calls ``init`` and ``process`` (predictor: ``process`` per
calibration sample and ``predict`` per window).

- **flash**: the bytes of the routine's functions and constants *in the linked image*
  (``arm-none-eabi-nm -S``: every symbol of the routine's prefix, i.e. text + rodata that
  --gc-sections keeps; static helpers are inlined into them), so unused entry points and the
  FIR's CMSIS tap arrays do not count. ``.o`` is ``arm-none-eabi-size``'s text + data + bss of
  the whole object (everything the file defines);
- **RAM**: ``sizeof`` the state struct (printed by the image) + the peak stack of the call,
  ``stack B`` = the larger of two measurements: ``painted``, the image paints 16 KiB below the
  stack pointer with a pattern, calls the routine and finds the deepest overwritten word
  (nested calls and newlib's memcpy/memset included), and ``su B``, the largest frame GCC's
  ``-fstack-usage`` reports for the file (it includes reserved words that are never written).
  The generated files have no .data/.bss (``.o`` data + bss = 0);
- **instructions per sample**: QEMU (TCG) logs every executed translation block with
  ``-d exec,nochain`` and ``-singlestep`` makes every block one instruction, so the number of
  ``Trace`` lines is the number of instructions executed (IT instructions count as one). Each
  image runs twice, with n1 = 64 and n2 = 320 samples (predictor: 1 and 3 forecasts); the
  difference divided by n2 - n1 is the per-sample cost in steady state (start-up, stack
  painting and semihosting cancel). These are *instructions*, not cycles: QEMU does not model
  the pipeline, flash wait states or caches (on a Cortex-M4 most data-processing and FPU
  instructions take 1 cycle, loads 2 (pipelined back-to-back loads 1), taken branches 2-4,
  VDIV 14, 64-bit multiply-accumulate SMLAL 1).

The hand-written baselines are what a firmware engineer types from the textbook: the Kalman
update ``e = z - (w + b); w += g1 e; b += g2 e`` (Q31: the same with Q31 gains and int64
products), a circular-buffer FIR whose index wraps with a compare, and a circular window with
``W`` rows summed over it. They are *not* bit-exact with the Python model (the generated code
is); they show what that guarantee costs.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from gyrobias import fir  # noqa: E402
from gyrobias.kalman import FixedGainKalman  # noqa: E402
from gyrobias.predict import FractionalKalmanPredictor  # noqa: E402
from tests import _target_harness as target  # noqa: E402

N1, N2 = 64, 320
P1, P2 = 1, 3
NM = shutil.which("arm-none-eabi-nm")
VARIANTS = [("float32", "m4"), ("q31", "m4"), ("q31", "m3")]
OPTS = ["-O2", "-Os"]
T = {"float32": "float", "q31": "int32_t"}

# --- hand-written baselines ----------------------------------------------------------------------

HAND_KALMAN = {
    "float32": """
typedef struct {{ float w, b; }} hand_state;
static const float hand_g1 = {g1}, hand_g2 = {g2};
void hand_init(hand_state *s, float z0) {{ s->w = z0; s->b = 0.0f; }}
void hand_process(hand_state *s, const float *z, float *rate, float *bias, size_t n)
{{
    size_t i;
    for (i = 0; i < n; ++i) {{
        float e = z[i] - (s->w + s->b);
        s->w += hand_g1 * e;
        s->b += hand_g2 * e;
        rate[i] = s->w;
        bias[i] = s->b;
    }}
}}
""",
    "q31": """
typedef struct {{ int32_t w, b; }} hand_state;
static const int32_t hand_g1 = {g1}, hand_g2 = {g2};
static int32_t hand_sat(int64_t v) {{ return v > INT32_MAX ? INT32_MAX : (v < INT32_MIN ? INT32_MIN : (int32_t)v); }}
void hand_init(hand_state *s, int32_t z0) {{ s->w = z0; s->b = 0; }}
void hand_process(hand_state *s, const int32_t *z, int32_t *rate, int32_t *bias, size_t n)
{{
    size_t i;
    for (i = 0; i < n; ++i) {{
        int64_t e = (int64_t)z[i] - ((int64_t)s->w + (int64_t)s->b);
        s->w = hand_sat((int64_t)s->w + (((int64_t)hand_g1 * e) >> 31));
        s->b = hand_sat((int64_t)s->b + (((int64_t)hand_g2 * e) >> 31));
        rate[i] = s->w;
        bias[i] = s->b;
    }}
}}
""",
}

HAND_FIR = """
#define HAND_N {n}u
typedef struct {{ {t} buf[HAND_N]; unsigned int pos; }} hand_state;
static const {t} hand_h[HAND_N] = {{ {taps} }};
void hand_init(hand_state *s) {{ unsigned int k; for (k = 0; k < HAND_N; ++k) s->buf[k] = 0; s->pos = 0; }}
void hand_process(hand_state *s, const {t} *x, {t} *y, size_t n)
{{
    size_t i;
    for (i = 0; i < n; ++i) {{
        {acc_t} acc = 0;
        unsigned int k, idx = s->pos;
        s->buf[idx] = x[i];
        for (k = 0; k < HAND_N; ++k) {{
            acc += {term};
            idx = idx == 0u ? HAND_N - 1u : idx - 1u;
        }}
        y[i] = {out};
        s->pos = s->pos + 1u == HAND_N ? 0u : s->pos + 1u;
    }}
}}
"""

HAND_PRED = """
#define HAND_K {k}u
#define HAND_H {h}u
typedef struct {{ {t} buf[HAND_K]; unsigned int pos, count; }} hand_state;
static const {t} hand_W[HAND_H * HAND_K] = {{ {w} }};
void hand_init(hand_state *s) {{ s->pos = 0; s->count = 0; }}
void hand_process(hand_state *s, const {t} *y, size_t n)
{{
    size_t i;
    for (i = 0; i < n; ++i) {{
        s->buf[s->pos] = y[i];
        s->pos = s->pos + 1u == HAND_K ? 0u : s->pos + 1u;
        if (s->count < HAND_K) ++s->count;
    }}
}}
void hand_predict(const hand_state *s, {t} *out)
{{
    unsigned int j, i, idx;
    for (j = 0; j < HAND_H; ++j) {{
        {acc_t} acc = 0;
        idx = s->pos; /* oldest */
        for (i = 0; i < HAND_K; ++i) {{
            acc += {term};
            idx = idx + 1u == HAND_K ? 0u : idx + 1u;
        }}
        out[j] = {out};
    }}
}}
"""

# --- the measuring image -------------------------------------------------------------------------

MAIN = """/* Generated by benches/python/bench_embedded.py. in.bin: (impl, mode, n); out.bin:
 * (peak stack bytes, sizeof state). impl 0 = generated, 1 = hand-written. */
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include "semihost.h"
#include "{name}.h"
{hand_decl}
#define NMAX {nmax}u
static {t} x[NMAX], y1[NMAX], y2[NMAX];
static {name}_state gs;
static hand_state hs;

/* inlined into main: the stack measured below main's frame is the routine's alone */
static inline __attribute__((always_inline)) void run(uint32_t impl, uint32_t mode, uint32_t n)
{{
    uint32_t i;
{body}
}}

int main(void)
{{
    uint32_t cmd[3], res[2], i, seed = 12345u;
    volatile uint32_t *p, *lo;
    uint32_t *sp;
    int fin = sh_open("in.bin", 1u), fout = sh_open("out.bin", 5u);
    if (fin < 0 || fout < 0 || sh_read(fin, cmd, 12u) != 0u || cmd[2] > NMAX) {{
        return 1;
    }}
    for (i = 0; i < NMAX; ++i) {{ /* deterministic input, the same in every run */
        seed = seed * 1664525u + 1013904223u;
        x[i] = {sample};
    }}
    __asm__ volatile("mov %0, sp" : "=r"(sp)); /* main's frame (fixed size) is above */
    lo = sp - 4096;
    for (p = lo; p < sp; ++p) {{ /* paint the 16 KiB below the stack pointer */
        *p = 0xDEADBEEFu;
    }}
    run(cmd[0], cmd[1], cmd[2]);
    for (p = lo; p < sp && *p == 0xDEADBEEFu; ++p) {{ /* deepest overwritten word */
    }}
    res[0] = (uint32_t)((uintptr_t)sp - (uintptr_t)p);
    res[1] = cmd[0] == 0u ? (uint32_t)sizeof(gs) : (uint32_t)sizeof(hs);
    sh_write(fout, res, 8u);
    (void)y2;
    return 0;
}}
"""

BODY = {
    "kalman": """    if (impl == 0u) {{
        {name}_init(&gs, x[0], 0);
        {name}_process(&gs, x, y1, y2, n);
    }} else {{
        hand_init(&hs, x[0]);
        hand_process(&hs, x, y1, y2, n);
    }}
    (void)mode; (void)i;""",
    "fir": """    if (impl == 0u) {{
        {name}_init(&gs);
        {name}_process(&gs, x, y1, n);
    }} else {{
        hand_init(&hs);
        hand_process(&hs, x, y1, n);
    }}
    (void)mode; (void)i;""",
    "pred": """    if (impl == 0u) {{
        {name}_init(&gs);
        if (mode == 0u) {{
            (void){name}_process(&gs, x, n);
        }} else {{
            (void){name}_process(&gs, x, {k}u);
            for (i = 0; i < n; ++i) {{
                (void){name}_predict(&gs, y1);
            }}
        }}
    }} else {{
        hand_init(&hs);
        if (mode == 0u) {{
            hand_process(&hs, x, n);
        }} else {{
            hand_process(&hs, x, {k}u);
            for (i = 0; i < n; ++i) {{
                hand_predict(&hs, y1);
            }}
        }}
    }}""",
}


def _q31(v: float) -> int:
    return int(np.clip(np.round(v * 2.0**31), -(2.0**31), 2.0**31 - 1))


def _lit(v: float, dtype: str) -> str:
    return f"{float(np.float32(v)).hex()}f" if dtype == "float32" else f"(int32_t){_q31(v)}"


def hand_text(kind: str, dtype: str, obj: Any) -> str:
    """The hand-written baseline (declarations and definitions)."""
    t = T[dtype]
    head = ""
    if kind == "kalman":
        g1, g2 = (float(v) for v in obj.G)
        return head + HAND_KALMAN[dtype].format(g1=_lit(g1, dtype), g2=_lit(g2, dtype))
    q = dtype == "q31"
    fields = dict(
        t=t,
        acc_t="int64_t" if q else "float",
        out="(int32_t)(acc >> 31)" if q else "acc",
    )
    if kind == "fir":
        taps = ", ".join(_lit(v, dtype) for v in obj.taps)
        term = "(int64_t)hand_h[k] * s->buf[idx]" if q else "hand_h[k] * s->buf[idx]"
        return head + HAND_FIR.format(n=obj.numtaps, taps=taps, term=term, **fields)
    h, k = obj.weights.shape
    w = ", ".join(_lit(v, dtype) for v in obj.weights.ravel())
    term = (
        "(int64_t)hand_W[j * HAND_K + i] * s->buf[idx]"
        if q
        else "hand_W[j * HAND_K + i] * s->buf[idx]"
    )
    return head + HAND_PRED.format(k=k, h=h, w=w, term=term, **fields)


def hand_source(kind: str, dtype: str, obj: Any) -> str:
    """hand.c: the definitions (its #defines and typedef are in hand.h)."""
    lines = hand_text(kind, dtype, obj).splitlines()
    body = [ln for ln in lines if not ln.startswith(("#define", "typedef"))]
    return '#include "hand.h"\n' + "\n".join(body) + "\n"


def hand_header(kind: str, dtype: str, obj: Any) -> str:
    """hand.h: the #defines, the state struct and the prototypes."""
    src = hand_text(kind, dtype, obj)
    lines = [ln for ln in src.splitlines() if ln.startswith(("#define", "typedef"))]
    t = T[dtype]
    protos = {
        "kalman": [
            f"void hand_init(hand_state *s, {t} z0);",
            f"void hand_process(hand_state *s, const {t} *z, {t} *rate, {t} *bias, size_t n);",
        ],
        "fir": [
            "void hand_init(hand_state *s);",
            f"void hand_process(hand_state *s, const {t} *x, {t} *y, size_t n);",
        ],
        "pred": [
            "void hand_init(hand_state *s);",
            f"void hand_process(hand_state *s, const {t} *y, size_t n);",
            f"void hand_predict(const hand_state *s, {t} *out);",
        ],
    }[kind]
    return "#include <stddef.h>\n#include <stdint.h>\n" + "\n".join(lines + protos) + "\n"


def count(elf: Path, core: str, cmd: tuple[int, int, int]) -> tuple[int, int, int]:
    """(instructions executed, peak stack bytes, sizeof state) of one run."""
    wd = elf.parent / f"run_{cmd[0]}_{cmd[1]}_{cmd[2]}"
    wd.mkdir()
    (wd / "in.bin").write_bytes(np.array(cmd, dtype="<u4").tobytes())
    qemu = target.qemu_command(elf, core)
    args = [*qemu[:-2], "-singlestep", "-d", "exec,nochain", "-D", "/dev/stdout", *qemu[-2:]]
    res = subprocess.run(args, cwd=wd, capture_output=True, timeout=600, check=True)
    stack, state = np.frombuffer((wd / "out.bin").read_bytes(), dtype="<u4")
    return res.stdout.count(b"Trace "), int(stack), int(state)


def flash(elf: Path, prefix: str) -> int:
    """Bytes of the symbols starting with ``prefix`` in the linked image (text + rodata)."""
    assert NM is not None
    out = subprocess.run([NM, "-S", str(elf)], capture_output=True, text=True, check=True)
    spans = []
    for line in out.stdout.splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[3].startswith(prefix) and parts[2] in "tTrR":
            start = int(parts[0], 16)
            spans.append((start, start + int(parts[1], 16)))
    # the union of the symbols' address ranges: GCC may place two equal constant arrays once
    # (a linear-phase FIR's taps equal their time-reversed CMSIS copy)
    total, end = 0, -1
    for a, b in sorted(spans):
        if b > end:
            total += b - max(a, end)
            end = b
    return total


def largest_frame(su: Path) -> int:
    """The largest single stack frame in a GCC ``-fstack-usage`` file (a cross-check of the
    painted peak, which adds nested calls such as FIR ``process`` → ``step`` and memcpy)."""
    frames = [int(line.split("\t")[1]) for line in su.read_text().splitlines() if "\t" in line]
    return max(frames, default=0)


def object_size(obj: Path) -> tuple[int, int]:
    """(text, data + bss) of an object from arm-none-eabi-size (Berkeley: text has rodata)."""
    assert target.SIZE is not None
    out = subprocess.run([target.SIZE, str(obj)], capture_output=True, text=True, check=True)
    text, data, bss = (int(v) for v in out.stdout.splitlines()[1].split()[:3])
    return text, data + bss


def measure(
    kind: str, dtype: str, core: str, opt: str, obj: Any, root: Path
) -> list[dict[str, Any]]:
    wd = root / f"{kind}_{dtype}_{core}{opt}"
    wd.mkdir(parents=True)
    name = f"g_{kind}"
    gen = obj.to_c(wd, name=name, dtype=dtype)
    (wd / "hand.h").write_text(hand_header(kind, dtype, obj))
    (wd / "hand.c").write_text(hand_source(kind, dtype, obj))
    k = obj.weights.shape[1] if kind == "pred" else 0
    sample = (
        "(float)((int32_t)seed) * 0x1p-28f"
        if dtype == "float32"
        else "(int32_t)(seed >> 4) - (int32_t)(1u << 27)"
    )
    main = MAIN.format(
        name=name,
        t=T[dtype],
        nmax=max(N2, k),
        sample=sample,
        hand_decl='#include "hand.h"',
        body=BODY[kind].format(name=name, k=k),
    )
    (wd / "main.c").write_text(main)
    inc = [f"-I{target.HERE}", f"-I{wd}"]
    su = ["-fstack-usage"]
    objs = [
        target.compile_object(gen.source, core, opt, wd / "gen.o", su),
        target.compile_object(wd / "hand.c", core, opt, wd / "hand.o", [*inc, *su]),
        target.compile_object(wd / "main.c", core, opt, wd / "main.o", inc),
        target.compile_object(target.HERE / "startup.c", core, opt, wd / "startup.o", inc),
    ]
    elf = target.link(objs, core, wd / "image.elf")
    rows = []
    for impl, prefix, o in ((0, name, wd / "gen.o"), (1, "hand_", wd / "hand.o")):
        c1, stack1, state = count(elf, core, (impl, 0, N1))
        c2, stack2, _ = count(elf, core, (impl, 0, N2))
        row = {
            "routine": kind,
            "type": dtype,
            "core": core,
            "opt": opt,
            "impl": "generated" if impl == 0 else "hand C",
            "flash": flash(elf, prefix),
            "object": object_size(o),
            "state": state,
            "painted": max(stack1, stack2),
            "frame": largest_frame(o.with_suffix(".su")),
            "per_sample": (c2 - c1) / (N2 - N1),
            "per_predict": None,
        }
        if kind == "pred":
            p1, s3, _ = count(elf, core, (impl, 1, P1))
            p2, s4, _ = count(elf, core, (impl, 1, P2))
            row["per_predict"] = (p2 - p1) / (P2 - P1)
            row["painted"] = max(row["painted"], s3, s4)
        # what must be available: painting sees the words written (nested calls included),
        # -fstack-usage the frame reserved (which may hold never-written padding)
        row["stack"] = max(row["painted"], row["frame"])
        rows.append(row)
    return rows


def main() -> int:
    if not target.AVAILABLE or NM is None:
        print("needs arm-none-eabi-gcc, -size, -nm and qemu-system-arm", file=sys.stderr)
        return 1
    kf = FixedGainKalman(1000.0, arw=0.005, rrw=1e-4, bandwidth=20.0)
    f = fir.kaiser_lowpass(1000.0, 20.0, 60.0, astop_db=60.0)
    pred = FractionalKalmanPredictor(d=0.5, q=1e-4, r=1e-4).compile(100, 50)
    objs = {"kalman": kf, "fir": f, "pred": pred}
    tasks = [(kind, dtype, core, opt) for kind in objs for dtype, core in VARIANTS for opt in OPTS]
    with tempfile.TemporaryDirectory() as tmp, ThreadPoolExecutor(max_workers=2) as pool:
        root = Path(tmp)
        results = list(pool.map(lambda a: measure(a[0], a[1], a[2], a[3], objs[a[0]], root), tasks))
    labels = {
        "kalman": "Kalman",
        "fir": f"FIR {f.numtaps} taps",
        "pred": "predictor k=100 h=50",
    }
    print(
        f"{'routine':<22}{'type':<9}{'core':<6}{'opt':<5}{'impl':<11}{'flash B':>8}{'.o B':>7}"
        f"{'state B':>9}{'stack B':>9}{'painted':>8}{'su B':>6}{'insn/sample':>13}"
        f"{'insn/predict':>14}"
    )
    for rows in results:
        for r in rows:
            pp = f"{r['per_predict']:.0f}" if r["per_predict"] is not None else "-"
            print(
                f"{labels[r['routine']]:<22}{r['type']:<9}{r['core']:<6}{r['opt']:<5}"
                f"{r['impl']:<11}{r['flash']:>8}{r['object'][0]:>7}{r['state']:>9}"
                f"{r['stack']:>9}{r['painted']:>8}{r['frame']:>6}{r['per_sample']:>13.1f}{pp:>14}"
            )
            assert r["object"][1] == 0 or r["impl"] == "hand C", "generated code has no .data/.bss"
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

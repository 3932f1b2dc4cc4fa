"""Cross-compile generated C for Cortex-M and run it on QEMU's MPS2 boards (tests and bench).

An *image* links any number of generated routines (``GeneratedC`` from ``to_c``) with the
start-up code in ``tests/cortex_m/`` and a runner generated here. The runner reads *jobs* from
the host file ``in.bin`` through semihosting — each job a header ``(routine id, n)`` (two
uint32) and ``n`` 4-byte samples (float32 or Q31) — runs the routine and appends its outputs to
``out.bin``:

- Kalman filter: per sample ``(rate, bias, status)`` (status = step's return value; 0 in the
  chunks fed through ``process``), then the total number of skipped samples (int32);
- FIR: the ``n`` outputs;
- predictor: ``n / k`` windows, ``h`` forecasts each.

The samples are processed in chunks of :data:`CHUNK` (what a firmware's DMA buffer does), even
chunks sample by sample with ``step`` and odd chunks with ``process`` (FIR: in place), so both
entry points must give the Python bits. One QEMU run per image does every job.
"""

from __future__ import annotations

import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from tests._c_harness import STRICT

HERE = Path(__file__).parent / "cortex_m"
GCC = shutil.which("arm-none-eabi-gcc")
SIZE = shutil.which("arm-none-eabi-size")
QEMU = shutil.which("qemu-system-arm")
AVAILABLE = GCC is not None and SIZE is not None and QEMU is not None

#: Samples per chunk (not a multiple of 4, so FIR process() also runs its remainder loop).
CHUNK = 250

#: The host build's warning flags (tests/_c_harness.STRICT without -std and -O).
WARNINGS = [f for f in STRICT if f.startswith("-W")]

#: (core flags, QEMU machine). -mfloat-abi=hard: float arguments in s0-s15, FPv4-SP-D16
#: instructions; the M3 has no FPU, so its float32 is libgcc's IEEE soft float.
CORES: dict[str, tuple[list[str], str]] = {
    "m4": (["-mcpu=cortex-m4", "-mfpu=fpv4-sp-d16", "-mfloat-abi=hard"], "mps2-an386"),
    "m3": (["-mcpu=cortex-m3", "-mfloat-abi=soft"], "mps2-an385"),
}


def cflags(core: str, opt: str) -> list[str]:
    """The flags every target object is compiled with.

    ``-ffp-contract=off``: no fused multiply-add (FPv4 has VFMA; GCC in ISO mode does not
    contract anyway, the flag makes it explicit); the generated sources must compile
    warning-free with the host's warnings and ``-Werror``.
    """
    return [
        "-std=c99",
        "-mthumb",
        *CORES[core][0],
        opt,
        *WARNINGS,
        "-ffp-contract=off",
        "-ffunction-sections",
        "-fdata-sections",
    ]


@dataclass(frozen=True)
class Routine:
    """One generated routine in an image: ``kind`` is "kalman", "fir" or "pred"."""

    kind: str
    gen: Any  # GeneratedC
    k: int = 0  # predictor: calibration length
    h: int = 0  # predictor: horizon


_T = {"float32": "float", "q31": "int32_t"}

_KALMAN = """
static void run_{name}(uint32_t n)
{{
    static {t} z[CHUNK], r[CHUNK], b[CHUNK];
    static int32_t out[3u * CHUNK];
    {name}_state s;
    uint32_t done = 0u, m, i, chunk = 0u;
    int32_t skipped = 0, st;
    while (done < n) {{
        m = n - done < CHUNK ? n - done : CHUNK;
        get(z, m);
        if (done == 0u) {{
            {name}_init(&s, z[0], {zero});
        }}
        if (chunk % 2u == 0u) {{
            for (i = 0u; i < m; ++i) {{
                st = {step};
                skipped += st != 0;
                memcpy(&out[3u * i + 2u], &st, 4u);
            }}
        }} else {{
            skipped += (int32_t){process};
            for (i = 0u; i < m; ++i) {{
                out[3u * i + 2u] = 0;
            }}
        }}
        for (i = 0u; i < m; ++i) {{
            memcpy(&out[3u * i], &r[i], 4u);
            memcpy(&out[3u * i + 1u], &b[i], 4u);
        }}
        sh_write(fout, out, 12u * m);
        done += m;
        ++chunk;
    }}
    sh_write(fout, &skipped, 4u);
}}
"""

_FIR = """
static void run_{name}(uint32_t n)
{{
    static {t} x[CHUNK], y[CHUNK];
    {name}_state s;
    uint32_t done = 0u, m, i, chunk = 0u;
    {name}_init(&s);
    while (done < n) {{
        m = n - done < CHUNK ? n - done : CHUNK;
        get(x, m);
        if (chunk % 2u == 0u) {{
            for (i = 0u; i < m; ++i) {{
                y[i] = {name}_step(&s, x[i]);
            }}
            sh_write(fout, y, 4u * m);
        }} else {{
            {name}_process(&s, x, x, m); /* in place */
            sh_write(fout, x, 4u * m);
        }}
        done += m;
        ++chunk;
    }}
}}
"""

_PRED = """
static void run_{name}(uint32_t n)
{{
    /* n / k windows: each from an empty window with three stale samples pushed first (the
     * window must slide them out), the first half by step(), the rest by process(). */
    static {t} y[{k}], out[{h}];
    {name}_state s;
    uint32_t w, i;
    for (w = 0u; w < n / {k}u; ++w) {{
        get(y, {k}u);
        {name}_init(&s);
        for (i = 0u; i < 3u; ++i) {{
            (void){name}_step(&s, y[0]);
        }}
        for (i = 0u; i < {k}u / 2u; ++i) {{
            (void){name}_step(&s, y[i]);
        }}
        if (!{name}_process(&s, y + {k}u / 2u, {k}u - {k}u / 2u)) {{
            sh_exit(4u);
        }}
        if ({name}_predict(&s, out) != 0) {{
            sh_exit(5u);
        }}
        sh_write(fout, out, 4u * {h}u);
    }}
}}
"""

_MAIN = """/* Generated by tests/_target_harness.py: runs jobs from in.bin, writes out.bin. */
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "semihost.h"
{includes}

#define CHUNK {chunk}u

static int fin, fout;

static void get(void *buf, uint32_t count)
{{
    if (sh_read(fin, buf, 4u * count) != 0u) {{
        sh_exit(2u); /* truncated job */
    }}
}}
{runners}
int main(void)
{{
    uint32_t head[2];
    fin = sh_open("in.bin", 1u);
    fout = sh_open("out.bin", 5u);
    if (fin < 0 || fout < 0) {{
        return 1;
    }}
    while (sh_read(fin, head, 8u) == 0u) {{
        switch (head[0]) {{
{cases}
        default:
            return 6;
        }}
    }}
    return 0;
}}
"""


def runner_source(routines: list[Routine]) -> str:
    """The C runner for ``routines`` (job id = index in the list)."""
    parts, cases = [], []
    for idx, r in enumerate(routines):
        name, t = r.gen.name, _T[r.gen.dtype]
        if r.kind == "kalman":
            q31 = r.gen.dtype == "q31"
            step = (
                f"({name}_step(&s, z[i], &r[i], &b[i]), 0)"
                if q31
                else f"{name}_step(&s, z[i], &r[i], &b[i])"
            )
            process = (
                f"({name}_process(&s, z, r, b, m), 0)" if q31 else f"{name}_process(&s, z, r, b, m)"
            )
            text = _KALMAN.format(
                name=name, t=t, step=step, process=process, zero="0" if q31 else "0.0f"
            )
        elif r.kind == "fir":
            text = _FIR.format(name=name, t=t)
        else:
            text = _PRED.format(name=name, t=t, k=r.k, h=r.h)
        parts.append(text)
        cases.append(f"        case {idx}u:\n            run_{name}(head[1]);\n            break;")
    includes = "\n".join(f'#include "{r.gen.name}.h"' for r in routines)
    return _MAIN.format(
        includes=includes, chunk=CHUNK, runners="".join(parts), cases="\n".join(cases)
    )


def _cc(args: list[str], cwd: Path) -> None:
    assert GCC is not None
    res = subprocess.run([GCC, *args], capture_output=True, text=True, cwd=cwd)
    # warning-free: -Werror makes warnings errors, and nothing else may be printed
    assert res.returncode == 0 and not res.stderr, res.stderr


def compile_object(source: Path, core: str, opt: str, out: Path, extra: list[str]) -> Path:
    """Compile one C file for ``core`` at ``opt`` into ``out`` (an object file)."""
    _cc([*cflags(core, opt), *extra, "-c", str(source), "-o", str(out)], out.parent)
    return out


def link(objects: list[Path], core: str, out: Path) -> Path:
    """Link a bare-metal image for the core's MPS2 board (memcpy/memset from newlib's libc)."""
    _cc(
        [
            "-mthumb",
            *CORES[core][0],
            "-nostartfiles",
            f"-T{HERE / 'mps2.ld'}",
            "-Wl,--gc-sections",
            *map(str, objects),
            "-lc",
            "-lgcc",
            "-o",
            str(out),
        ],
        out.parent,
    )
    return out


def build_image(
    routines: list[Routine],
    core: str,
    opt: str,
    workdir: Path,
    *,
    routine_flags: tuple[str, ...] = (),
    startup_flags: tuple[str, ...] = (),
) -> Path:
    """Compile every routine's source, the start-up code and the runner; the linked ELF.

    ``routine_flags`` are appended to the generated sources' flags and ``startup_flags`` to
    the start-up code's (the tests' negative controls: ``-ffp-contract=fast``,
    ``-DGYRO_FLUSH_TO_ZERO``)."""
    workdir.mkdir(parents=True, exist_ok=True)
    inc = [f"-I{HERE}", *sorted({f"-I{r.gen.header.parent}" for r in routines})]
    objs = []
    for r in routines:
        obj = workdir / f"{r.gen.name}.o"
        objs.append(compile_object(r.gen.source, core, opt, obj, list(routine_flags)))
    main = workdir / "runner.c"
    main.write_text(runner_source(routines))
    objs.append(compile_object(main, core, opt, workdir / "runner.o", inc))
    start = workdir / "startup.o"
    objs.append(compile_object(HERE / "startup.c", core, opt, start, [*inc, *startup_flags]))
    return link(objs, core, workdir / "image.elf")


def qemu_command(elf: Path, core: str) -> list[str]:
    """The emulator command line for an image."""
    assert QEMU is not None
    return [
        QEMU,
        "-machine",
        CORES[core][1],
        "-nographic",
        "-monitor",
        "none",
        "-serial",
        "none",
        "-semihosting-config",
        "enable=on,target=native",
        "-kernel",
        str(elf),
    ]


def output_size(r: Routine, n: int) -> int:
    """Bytes a job of ``n`` samples writes."""
    if r.kind == "kalman":
        return 12 * n + 4
    if r.kind == "fir":
        return 4 * n
    return 4 * (n // r.k) * r.h


def run_jobs(
    elf: Path, core: str, routines: list[Routine], jobs: list[tuple[int, np.ndarray]]
) -> list[bytes]:
    """Run ``jobs`` (routine index, 4-byte samples) in one emulator run; their raw outputs."""
    wd = elf.parent
    with open(wd / "in.bin", "wb") as fh:
        for idx, data in jobs:
            arr = np.ascontiguousarray(data)
            assert arr.dtype.itemsize == 4
            fh.write(np.array([idx, arr.size], dtype="<u4").tobytes())
            fh.write(arr.astype(arr.dtype.newbyteorder("<")).tobytes())
    res = subprocess.run(qemu_command(elf, core), cwd=wd, capture_output=True, timeout=600)
    assert res.returncode == 0, (res.returncode, res.stdout[-2000:], res.stderr[-2000:])
    raw = (wd / "out.bin").read_bytes()
    outs, pos = [], 0
    for idx, data in jobs:
        size = output_size(routines[idx], np.asarray(data).size)
        outs.append(raw[pos : pos + size])
        pos += size
    assert pos == len(raw), (pos, len(raw))
    return outs


def kalman_outputs(raw: bytes, dtype: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """(rate, bias, status, skipped) of a Kalman job."""
    rec = np.frombuffer(raw[:-4], dtype="<i4").reshape(-1, 3)
    rate = np.ascontiguousarray(rec[:, 0]).view(dtype)
    bias = np.ascontiguousarray(rec[:, 1]).view(dtype)
    skipped = int(np.frombuffer(raw[-4:], dtype="<i4")[0])
    return rate, bias, np.ascontiguousarray(rec[:, 2]), skipped

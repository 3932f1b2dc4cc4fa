"""C99 code generation for the streaming filters and the compiled bias predictor.

``FixedGainKalman.to_c``, ``KaiserLowpass.to_c`` and ``CompiledPredictor.to_c`` write a
dependency-free C99 header/source pair (state struct, ``init``, per-sample ``step``, block
``process``; no dynamic allocation, no recursion, no global mutable state) in float64, float32
or Q31 fixed point:

- float64 C equals the float64 Python/Rust path bit for bit (same operations, same order);
- float32 C equals ``FixedGainKalman.filter(z, dtype=np.float32)`` and
  ``fir.stream(taps, x, dtype=np.float32)`` bit for bit;
- Q31 C stays within an analytic bound of float64 (designed in the Rust core,
  ``gyrocore::codegen``: shifts chosen from the design, saturating arithmetic, stated rounding).

See ``docs/guides/embedded_c.md``. This module imports the classes and registers its emitters
with :mod:`gyrobias._emitters`, which their ``to_c`` methods call (no import cycle).
"""

from __future__ import annotations

from gyrobias import _emitters
from gyrobias.codegen import fir_c, kalman_c, predict_c
from gyrobias.codegen._c import GeneratedC

__all__ = ["GeneratedC", "emit_fir", "emit_kalman", "emit_predictor"]

emit_kalman = kalman_c.emit
emit_fir = fir_c.emit
emit_predictor = predict_c.emit

_emitters.register("kalman", kalman_c.emit)
_emitters.register("fir", fir_c.emit)
_emitters.register("predictor", predict_c.emit)

"""C99 code generation for the streaming filters and the compiled bias predictor.

``FixedGainKalman.to_c``, ``KaiserLowpass.to_c`` and ``CompiledPredictor.to_c`` write a
dependency-free C99 header/source pair (state struct, ``init``, per-sample ``step``, block
``process``; no dynamic allocation, no recursion, no global mutable state) in float64, float32
or Q31 fixed point:

- float64 C equals the float64 Python/Rust path bit for bit (same operations, same order;
  for the predictor ``CompiledPredictor.predict(windows, dtype=np.float64)``);
- float32 C equals ``FixedGainKalman.filter(z, dtype=np.float32)``,
  ``fir.stream(taps, x, dtype=np.float32)`` and
  ``CompiledPredictor.predict(windows, dtype=np.float32)`` bit for bit, on the host and on a
  Cortex-M4F (``tests/test_codegen_target.py``);
- Q31 C stays within an analytic bound of float64 (designed in the Rust core,
  ``gyrocore::codegen``: shifts chosen from the design, saturating arithmetic, stated rounding).

See ``docs/guides/embedded_c.md``. This package imports the classes and registers its emitters
as methods of the generic :func:`gyrobias._generics.to_c`, to which the classes' ``to_c``
methods delegate (the dependency points one way: codegen → classes).
"""

from __future__ import annotations

from gyrobias import _generics
from gyrobias.codegen import fir_c, kalman_c, predict_c
from gyrobias.codegen._c import GeneratedC
from gyrobias.fir import KaiserLowpass
from gyrobias.kalman import FixedGainKalman
from gyrobias.predict import CompiledPredictor

__all__ = ["GeneratedC", "emit_fir", "emit_kalman", "emit_predictor"]

emit_kalman = kalman_c.emit
emit_fir = fir_c.emit
emit_predictor = predict_c.emit

_generics.to_c.register(FixedGainKalman, kalman_c.emit)
_generics.to_c.register(KaiserLowpass, fir_c.emit)
_generics.to_c.register(CompiledPredictor, predict_c.emit)

"""Type stubs of the Rust extension module ``gyrobias._core``.

One submodule per gyrocore module, with gyrocore's function names (checked by
``python -m mypy.stubtest gyrobias._core``). Array arguments may have any memory layout: the
binding borrows C-contiguous float64 arrays and copies any other layout into C order once.
"""

from gyrobias._core import allan as allan
from gyrobias._core import bags as bags
from gyrobias._core import cleaning as cleaning
from gyrobias._core import codegen as codegen
from gyrobias._core import fir as fir
from gyrobias._core import fleet as fleet
from gyrobias._core import fractional as fractional
from gyrobias._core import kalman as kalman
from gyrobias._core import noise as noise
from gyrobias._core import predict as predict
from gyrobias._core import random as random
from gyrobias._core import spectral as spectral
from gyrobias._core import stationarity as stationarity
from gyrobias._core import stats as stats
from gyrobias._core import text as text
from gyrobias._core import thermal as thermal
from gyrobias._core import timestamps as timestamps
from gyrobias._core import validate as validate

class GyroLinAlgError(ValueError): ...

#: The package version (the workspace version of Cargo.toml, also the wheel's).
__version__: str

def instruction_set() -> str:
    """The vector instruction set of the core's kernels: ``"x86-64-v3"``, ``"neon"`` or ``"scalar"``."""

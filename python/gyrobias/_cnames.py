"""Names that generated C must not take: the C standard headers and the identifiers the C
standard reserves (a leaf module without imports of gyrobias, so the command line's argument
layer can use it without loading the library)."""

from __future__ import annotations

import re

#: The C standard library headers (C99 §7.1.2, C11, C23): a generated ``<name>.h`` with one of
#: these names (in any case: case-insensitive file systems) shadows the system header for every
#: file compiled with the output directory on the include path.
C_HEADERS = frozenset(
    """assert complex ctype errno fenv float inttypes iso646 limits locale math setjmp signal
    stdalign stdarg stdatomic stdbit stdbool stdckdint stddef stdint stdio stdlib stdnoreturn
    string tgmath threads time uchar wchar wctype""".split()
)

#: Identifier prefixes reserved for the library's future use (C99 §7.26, C11 §7.31): external
#: names (the generated functions ``<name>_…``) and macros (``<NAME>_H``, ``<NAME>_FS_HZ``).
_RESERVED_FUNCTIONS = re.compile(r"(?:is|to|str|mem|wcs)[a-z]|(?:cnd|mtx|thrd|tss|atomic)_")
_RESERVED_MACROS = re.compile(r"E[0-9A-Z]|LC_[A-Z]|SIG_?[A-Z]|PRI[A-Z]|SCN[A-Z]|FE_[A-Z]|ATOMIC_")


def reserved_c_name(name: str) -> str | None:
    """Why ``name`` cannot prefix generated C (a standard header or a reserved identifier), or
    ``None`` if it can."""
    if name.lower() in C_HEADERS:
        return f"{name!r} is the name of the C standard header <{name.lower()}.h>"
    if _RESERVED_FUNCTIONS.match(name):
        return f"{name!r} starts with a prefix the C standard reserves for library functions"
    if _RESERVED_MACROS.match(name.upper()):
        return (
            f"{name!r} gives the macros {name.upper()}_H, … a prefix the C standard reserves "
            "for library macros"
        )
    return None

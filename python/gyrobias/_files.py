"""Atomic file output: every file gyrobias writes goes through a temporary file beside the
target, renamed over it (``os.replace``) only when writing succeeded.

A leaf module (it imports nothing from gyrobias), so every layer can use it.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import BinaryIO

__all__ = ["atomic_binary", "atomic_write"]


@contextlib.contextmanager
def atomic_binary(path: str | os.PathLike[str]) -> Iterator[BinaryIO]:
    """A binary file to write ``path`` with: a temporary file beside it, renamed over ``path``
    (``os.replace``) when the ``with`` block ends without an exception.

    A reader never sees a half-written file, and a failure (an exception in the block, an
    interrupted run) leaves no file at ``path`` — or the existing one untouched — and no
    temporary file. The file gets the target's mode if it exists, else the umask's.
    """
    target = Path(os.fspath(path))
    directory = target.parent if str(target.parent) else Path(".")
    try:
        mode = target.stat().st_mode & 0o777
    except FileNotFoundError:
        umask = os.umask(0)
        os.umask(umask)
        mode = 0o666 & ~umask
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=directory)
    try:
        with os.fdopen(fd, "wb") as fh:
            yield fh
        os.chmod(tmp, mode)  # mkstemp creates 0600; keep the target's (or the umask's) mode
        os.replace(tmp, target)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def atomic_write(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` through a temporary file beside it and ``os.replace``
    (:func:`atomic_binary`).

    A reader never sees a half-written file, and a failure leaves an existing file untouched.
    """
    with atomic_binary(path) as fh:
        fh.write(text.encode("utf-8"))
    return Path(os.fspath(path))

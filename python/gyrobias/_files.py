"""Atomic file output: every file gyrobias writes goes through a temporary file beside the
target, renamed over it (``os.replace``) only when writing succeeded.

A leaf module (it imports nothing from gyrobias), so every layer can use it.
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any, BinaryIO

__all__ = ["atomic_binary", "atomic_write", "checked_path"]


def _shown_path(value: str) -> str:
    return repr(value) if len(value) <= 60 else repr(value[:60]) + f"... ({len(value)} characters)"


@contextlib.contextmanager
def atomic_binary(path: str | os.PathLike[str]) -> Iterator[BinaryIO]:
    """A binary file to write ``path`` with: a temporary file beside it, renamed over ``path``
    (``os.replace``) when the ``with`` block ends without an exception.

    A reader never sees a half-written file, and a failure (an exception in the block, an
    interrupted run) leaves no file at ``path`` — or the existing one untouched — and no
    temporary file. The file gets the target's mode if it exists, else the umask's. A target
    that is a device or a FIFO (``/dev/null``) is written in place, never replaced; a directory
    is an ``IsADirectoryError`` naming it.
    """
    target = checked_path("path", path)
    directory = target.parent if str(target.parent) else Path(".")
    try:
        st_mode = target.stat().st_mode
    except (FileNotFoundError, NotADirectoryError):
        umask = os.umask(0)
        os.umask(umask)
        mode = 0o666 & ~umask
    else:
        if stat.S_ISDIR(st_mode):
            raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), str(target))
        if not stat.S_ISREG(st_mode):
            # A device or FIFO (/dev/null, /dev/stdout, a pipe): written in place. Renaming a
            # temporary file over it would replace the device node itself.
            with open(target, "wb") as fh:
                yield fh
            return
        mode = st_mode & 0o777
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=directory)
    except OSError as exc:
        raise _naming(exc, target) from None
    try:
        with os.fdopen(fd, "wb") as fh:
            yield fh
        os.chmod(tmp, mode)  # mkstemp creates 0600; keep the target's (or the umask's) mode
        try:
            os.replace(tmp, target)
        except OSError as exc:
            raise _naming(exc, target) from None
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def _naming(exc: OSError, target: Path) -> OSError:
    """``exc`` about the caller's ``target`` (not the hidden temporary file beside it)."""
    if exc.errno is None:
        return OSError(f"cannot write '{target}': {exc}")
    return type(exc)(exc.errno, exc.strerror, str(target))


def atomic_write(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` through a temporary file beside it and ``os.replace``
    (:func:`atomic_binary`).

    A reader never sees a half-written file, and a failure leaves an existing file untouched.
    """
    if not isinstance(text, str):
        raise TypeError(f"text must be a str, got {type(text).__name__}")
    try:
        data = text.encode("utf-8")  # before the temporary file exists
    except UnicodeEncodeError as exc:
        raise ValueError(
            f"text must be valid Unicode text: a lone surrogate U+{ord(text[exc.start]):04X} at "
            f"position {exc.start} cannot be written as UTF-8"
        ) from None
    with atomic_binary(path) as fh:
        fh.write(data)
    return Path(os.fspath(path))


def checked_path(name: str, value: Any, what: str = "a file path") -> Path:
    """``value`` as a :class:`~pathlib.Path` if it is a usable path, else an error naming ``name``.

    The one check of every file and directory argument, where it enters: ``TypeError`` for
    anything but a ``str`` or an ``os.PathLike`` giving one (``None``, a number, bytes);
    ``ValueError`` for an empty string, a NUL character or text the file system cannot encode
    (a lone surrogate such as ``"\\ud800"``). What the file system itself refuses (a name too
    long, a missing directory, no permission) stays its ``OSError``, which names the path.
    """
    if isinstance(value, (bytes, bytearray)) or not isinstance(value, (str, os.PathLike)):
        raise TypeError(f"{name} must be {what} (str or os.PathLike), got {type(value).__name__}")
    text_ = os.fspath(value)
    if not isinstance(text_, str):
        raise TypeError(f"{name} must be {what} (str or os.PathLike), got {type(text_).__name__}")
    if not text_:
        raise ValueError(f"{name} must be {what}, got an empty string")
    if "\x00" in text_:
        raise ValueError(f"{name} must be {what}, got {_shown_path(text_)} (a NUL character)")
    try:
        os.fsencode(text_)
    except UnicodeEncodeError as exc:
        raise ValueError(
            f"{name} must be {what} the file system can encode, got {_shown_path(text_)} "
            f"(character U+{ord(text_[exc.start]):04X} at position {exc.start})"
        ) from None
    return Path(text_)

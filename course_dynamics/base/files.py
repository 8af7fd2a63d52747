"""Opening a file someone gave us: regular files only, of a size we can take.

A device (``/dev/zero``), a named pipe (which would block), a socket or a
folder given where a file is expected is refused, with what it is, before
anything is read; :func:`read_small` also caps the size.
"""
from __future__ import annotations

import os
import stat
from pathlib import Path

from .errors import InputError
from .resources import format_bytes

KINDS_OF_FILE = ((stat.S_ISFIFO, "a named pipe"), (stat.S_ISCHR, "a character device"),
                 (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def kind_of_file(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISLNK(mode):
        return "a symbolic link"
    return next((name for test, name in KINDS_OF_FILE if test(mode)), "a special file")


def _not_regular(path, mode: int, what: str) -> InputError:
    if stat.S_ISDIR(mode) or stat.S_ISLNK(mode):
        return InputError(f"{path}: is {kind_of_file(mode)}, not a {what}")
    return InputError(f"{path}: not a regular file ({kind_of_file(mode)}), not a {what}")


def open_regular(path, what: str = "file", follow: bool = True):
    """``(binary handle, size in bytes)`` of ``path``, which must be a regular file.

    A directory, device, named pipe or socket is refused before it is opened, and the opened file
    is checked again (fstat): the open is non-blocking, so a pipe put in its place meanwhile is
    refused rather than waited on. ``follow=False`` refuses a symbolic link too.

    Raises
    ------
    InputError
        Naming the file: missing, unreadable, or not a regular file (saying what it is).
    """
    path = Path(path)
    try:
        mode = (os.stat if follow else os.lstat)(path).st_mode
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    if not stat.S_ISREG(mode):
        raise _not_regular(path, mode, what)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC | (0 if follow else os.O_NOFOLLOW))
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode):
        os.close(fd)
        raise _not_regular(path, st.st_mode, what)
    os.set_blocking(fd, True)
    return os.fdopen(fd, "rb"), st.st_size


def read_small(path, limit: int, what: str = "file", follow: bool = True) -> bytes:
    """The bytes of the regular file ``path`` (:func:`open_regular`), refused when larger than ``limit``."""
    handle, size = open_regular(path, what, follow)
    with handle:
        if size > limit:
            raise InputError(f"{path}: {format_bytes(size)} is more than a {what} may be ({format_bytes(limit)})")
        try:
            data = handle.read(limit + 1)
        except OSError as exc:
            raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    if len(data) > limit:  # it grew while being read
        raise InputError(f"{path}: more than a {what} may be ({format_bytes(limit)})")
    return data

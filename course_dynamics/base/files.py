"""Opening a file someone gave us: regular files only, of a size we can take.

A device (``/dev/zero``), a named pipe (which would block), a socket or a
folder given where a file is expected is refused, with what it is, before
anything is read; :func:`read_small` also caps the size. This is the one place
that opens a file it was given: a caller that words its refusals its own way
(the grader's "not a regular file", the viewer's "mesh file …") passes a
:class:`Refusals`.
"""
from __future__ import annotations

import os
import stat
from dataclasses import dataclass
from pathlib import Path

from .errors import CourseDynamicsError, InputError
from .resources import format_bytes

KINDS_OF_FILE = ((stat.S_ISFIFO, "a named pipe"), (stat.S_ISCHR, "a character device"),
                 (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def kind_of_file(mode: int) -> str:
    """What a file of ``mode`` is, for a message: "a directory", "a named pipe", "a character device", ….

    Parameters
    ----------
    mode : int
        The file's ``st_mode``, as ``os.stat`` or ``os.lstat`` gives it.

    Returns
    -------
    str
        Its kind with an article: "a directory", "a symbolic link", "a named pipe", "a character device",
        "a block device", "a socket", or "a special file".

    Examples
    --------
    >>> import os
    >>> kind_of_file(os.stat("/").st_mode)
    'a directory'
    """
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISLNK(mode):
        return "a symbolic link"
    return next((name for test, name in KINDS_OF_FILE if test(mode)), "a special file")


@dataclass(frozen=True)
class Refusals:
    """How :func:`open_regular` and :func:`read_small` word a refusal, and the error they raise.

    Each wording is a format string over ``path``, ``what`` (the kind of file expected), ``kind`` (what the path is
    instead: :func:`kind_of_file`), ``reason`` (the system's), ``size`` and ``limit`` (for people:
    :func:`~course_dynamics.base.resources.format_bytes`) and ``size_bytes`` and ``limit_bytes``.

    Parameters
    ----------
    error : type
        The :class:`~course_dynamics.base.errors.CourseDynamicsError` subclass raised;
        :class:`~course_dynamics.base.errors.InputError` by default.
    unreadable : str
        A file that is missing or that the system will not open or read.
    not_a_file : str
        A directory or a symbolic link.
    not_regular : str
        A device, a named pipe or a socket.
    too_large : str
        A regular file larger than the limit.
    grew : str
        A file that was larger by the time it was read than when its size was taken.
    """

    error: type[CourseDynamicsError] = InputError
    unreadable: str = "{path}: cannot read: {reason}"
    not_a_file: str = "{path}: is {kind}, not a {what}"                       # a directory or a symbolic link
    not_regular: str = "{path}: not a regular file ({kind}), not a {what}"    # a device, a pipe, a socket
    too_large: str = "{path}: {size} is more than a {what} may be ({limit})"
    grew: str = "{path}: more than a {what} may be ({limit})"                 # larger by the time it was read

    def refused(self, wording: str, path, what: str, mode: int = 0, reason: str = "", size: int = 0,
                limit: int = 0) -> CourseDynamicsError:
        """The error (not raised) of one refusal, its message ``wording`` filled in.

        Parameters
        ----------
        wording : str
            One of the format strings (``self.too_large``, …).
        path : str or pathlib.Path
            The file refused.
        what : str
            The kind of file that was expected ("table", "URDF file").
        mode : int, optional
            The file's ``st_mode``, for ``kind``; 0 when it is not known.
        reason : str, optional
            The system's reason.
        size : int, optional
            The file's size, bytes.
        limit : int, optional
            The largest size taken, bytes.

        Returns
        -------
        CourseDynamicsError
            An instance of ``self.error``, for the caller to raise.
        """
        return self.error(wording.format(path=path, what=what, kind=kind_of_file(mode) if mode else "", reason=reason,
                                         size=format_bytes(size), limit=format_bytes(limit), size_bytes=size,
                                         limit_bytes=limit))

    def not_regular_file(self, path, what: str, mode: int) -> CourseDynamicsError:
        """The error (not raised) for ``path`` being of ``mode`` rather than a regular file.

        Parameters
        ----------
        path : str or pathlib.Path
            The file refused.
        what : str
            The kind of file that was expected.
        mode : int
            Its ``st_mode``: a directory or a symbolic link is worded ``not_a_file``, anything else
            ``not_regular``.

        Returns
        -------
        CourseDynamicsError
            An instance of ``self.error``, for the caller to raise.
        """
        wording = self.not_a_file if stat.S_ISDIR(mode) or stat.S_ISLNK(mode) else self.not_regular
        return self.refused(wording, path, what, mode)

    def cannot_read(self, path, what: str, exc: Exception) -> CourseDynamicsError:
        """The error (not raised) for ``path`` that the system would not open or read.

        Parameters
        ----------
        path : str or pathlib.Path
            The file refused.
        what : str
            The kind of file that was expected.
        exc : Exception
            What the system raised; its ``strerror`` (or its message) is the reason.

        Returns
        -------
        CourseDynamicsError
            An instance of ``self.error``, for the caller to raise.
        """
        return self.refused(self.unreadable, path, what, reason=getattr(exc, "strerror", None) or str(exc))


REFUSALS = Refusals()


def open_regular(path, what: str = "file", follow: bool = True, refusals: Refusals = REFUSALS):
    """``(binary handle, size in bytes)`` of ``path``, which must be a regular file.

    A directory, device, named pipe or socket is refused before it is opened, and the opened file
    is checked again (fstat): the open is non-blocking, so a pipe put in its place meanwhile is
    refused rather than waited on. ``follow=False`` refuses a symbolic link too.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.
    what : str, optional
        The kind of file expected, for the message ("table", "URDF file").
    follow : bool, optional
        Follow a symbolic link (the default); ``False`` refuses one.
    refusals : Refusals, optional
        How a refusal is worded and what it raises.

    Returns
    -------
    tuple of (io.BufferedReader, int)
        The open binary handle (the caller closes it) and the file's size, bytes.

    Raises
    ------
    InputError
        Naming the file: missing, unreadable, or not a regular file (saying what it is); ``refusals``
        may word it otherwise and raise another error.

    Examples
    --------
    >>> handle, size = open_regular(__file__, "module")
    >>> handle.close(); size > 0
    True
    """
    path = Path(path)
    try:
        mode = (os.stat if follow else os.lstat)(path).st_mode
    except (OSError, ValueError) as exc:  # ValueError: a NUL byte in the name
        raise refusals.cannot_read(path, what, exc) from None
    if not stat.S_ISREG(mode):
        raise refusals.not_regular_file(path, what, mode)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC | (0 if follow else os.O_NOFOLLOW))
    except OSError as exc:
        raise refusals.cannot_read(path, what, exc) from None
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode):
        os.close(fd)
        raise refusals.not_regular_file(path, what, st.st_mode)
    os.set_blocking(fd, True)
    return os.fdopen(fd, "rb"), st.st_size


def read_small(path, limit: int, what: str = "file", follow: bool = True, refusals: Refusals = REFUSALS) -> bytes:
    """The bytes of the regular file ``path`` (:func:`open_regular`), refused when larger than ``limit``.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.
    limit : int
        The largest size taken, bytes.
    what : str, optional
        The kind of file expected, for the message ("table", "URDF file").
    follow : bool, optional
        Follow a symbolic link (the default); ``False`` refuses one.
    refusals : Refusals, optional
        How a refusal is worded and what it raises.

    Returns
    -------
    bytes
        The whole file.

    Raises
    ------
    InputError
        Naming the file: missing, unreadable, not a regular file, larger than ``limit`` (or larger by the time
        it was read); ``refusals`` may word it otherwise and raise another error.

    Examples
    --------
    >>> read_small("/dev/zero", 10, "table")
    Traceback (most recent call last):
    ...
    course_dynamics.base.errors.InputError: /dev/zero: not a regular file (a character device), not a table
    """
    handle, size = open_regular(path, what, follow, refusals)
    with handle:
        if size > limit:
            raise refusals.refused(refusals.too_large, path, what, size=size, limit=limit)
        try:
            data = handle.read(limit + 1)
        except OSError as exc:
            raise refusals.cannot_read(path, what, exc) from None
    if len(data) > limit:  # it grew while being read
        raise refusals.refused(refusals.grew, path, what, size=len(data), limit=limit)
    return data


__all__ = ["Refusals", "kind_of_file", "open_regular", "read_small"]

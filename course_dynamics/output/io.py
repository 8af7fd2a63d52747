"""Writing files, the one way the project does it.

:func:`output` (and :func:`write_text`, :func:`write_bytes`, :func:`write_csv`
on top of it) writes a whole file or nothing. The data goes to a temporary
file of a random name, named before it is made and made with O_EXCL and
O_NOFOLLOW (so a planted file or link is never followed), in the target's
folder, given the mode the target would have had (the replaced file's, or the
umask's), and renamed onto the target only when complete; on any exception,
Ctrl-C included, it is removed. The rename never follows a link: a symbolic
link at the target is replaced, not written through. ``-`` means standard
output, and a target that is not a regular file (a terminal, a pipe,
``/dev/stdout``) is streamed into, never replaced.
:func:`write_new` writes a file only where none exists (a student's notebook
is never replaced), and :func:`keep_backup` keeps a copy of a file before it
is replaced on request.

A temporary file's name carries its writer's process id; one left behind by a
killed writer (SIGKILL cannot be caught) is removed by the next write to the
same target. Folders of files that may already hold other things are written
by :mod:`course_dynamics.output.folders`.
"""
from __future__ import annotations

import csv
import errno
import os
import shutil
import stat
import secrets
import sys
import time
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from ..base.errors import InputError
from ..base.files import open_regular

#: The file name that means standard output.
STDOUT = "-"
STREAMED_ROOTS = ("/dev/", "/proc/")  # special files and links to them: written in place


def _is_streamed(path: Path) -> bool:
    """True for ``-`` and for targets that must be written in place rather than replaced."""
    if str(path) == STDOUT or str(path).startswith(STREAMED_ROOTS):
        return True
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return False
    except OSError as exc:
        raise InputError(f"{path}: cannot write: {exc.strerror}") from None
    if stat.S_ISDIR(mode):
        raise InputError(f"{path}: is a directory")
    if stat.S_ISLNK(mode):
        try:
            target = os.stat(path).st_mode
        except OSError:
            return False  # a dangling link: replaced like a missing file
        return not (stat.S_ISREG(target) or stat.S_ISDIR(target))
    return not stat.S_ISREG(mode)


def check_distinct(inputs, outputs) -> None:
    """InputError when an output would overwrite an input or another output (the same file by any name).

    Parameters
    ----------
    inputs : iterable of str or pathlib.Path or None
        The files (or folders, such as a ROS 2 bag) a command reads; ``None`` entries are skipped.
    outputs : iterable of str or pathlib.Path or None
        The files it writes; ``None``, ``-`` and special files (a terminal, a pipe) are skipped.

    Raises
    ------
    InputError
        If an output is an input or another output by any name (a link, a hard link, a relative path),
        lies inside an input folder or would be the folder another output is written into, or is reached
        through a loop of symbolic links.
    """
    def resolved(path) -> Path:
        try:
            return Path(path).resolve()
        except (RuntimeError, OSError):  # a loop of symbolic links
            raise InputError(f"{path}: a loop of symbolic links") from None

    def key(path):
        path = Path(path)
        try:
            st = os.stat(path)
            return ("inode", st.st_dev, st.st_ino) if stat.S_ISREG(st.st_mode) else None
        except OSError:
            return ("path", str(resolved(path)))

    folders = [resolved(p) for p in inputs if p is not None and os.path.isdir(p)]  # a ROS 2 bag is a folder
    seen = {}
    for role, paths in (("input", inputs), ("output", outputs)):
        for path in paths:
            if path is None or str(path) == STDOUT or (role == "output" and _is_streamed(Path(path))):
                continue
            inside = [f for f in folders if role == "output" and resolved(path).is_relative_to(f)]
            if inside:
                raise InputError(f"{path}: the output would be written inside the input folder {inside[0]}")
            k = key(path)
            if k is None:
                continue
            if k in seen and role == "output":
                first_role, first = seen[k]
                raise InputError(f"{path}: the output would overwrite the input {first}" if first_role == "input"
                                 else f"{path}: named for two outputs ({first} and {path} are the same file)")
            seen.setdefault(k, (role, path))
    written = [(path, resolved(path)) for path in outputs
               if path is not None and str(path) != STDOUT and not _is_streamed(Path(path))]
    for path, where in written:
        for other, there in written:
            if there != where and there.is_relative_to(where):
                raise InputError(f"{path}: named for two outputs (it is the folder {other} is written into)")


def check_writable(path) -> None:
    """Fail before long work if ``path`` cannot be written (InputError naming it).

    Parameters
    ----------
    path : str or pathlib.Path
        The file to be written; ``-`` and special files (a terminal, a pipe) always pass.

    Raises
    ------
    InputError
        If ``path`` is a directory, its directory does not exist or is not writable, or it cannot be examined.
    """
    path = Path(path)
    if _is_streamed(path):
        return
    directory = path.parent
    if not directory.is_dir():
        raise InputError(f"{path}: directory {directory} does not exist")
    if not os.access(directory, os.W_OK | os.X_OK):
        raise InputError(f"{path}: not writable (directory {directory})")


def _new_file_mode(path: Path) -> int:
    try:
        st = os.lstat(path)
        if stat.S_ISREG(st.st_mode):
            return stat.S_IMODE(st.st_mode)
    except OSError:
        pass
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


TEMP_SUFFIX = ".partial"
LINKS_UNSUPPORTED = {errno.EPERM, errno.EOPNOTSUPP, errno.ENOTSUP, errno.EMLINK, errno.ENOSYS, errno.EXDEV}


def _remove_stale_temporaries(path: Path) -> None:
    """Remove ``.NAME.PID.*.partial`` files beside ``path`` whose writer no longer runs (killed with SIGKILL)."""
    prefix = f".{path.name}."
    try:
        candidates = [p for p in path.parent.iterdir() if p.name.startswith(prefix) and p.name.endswith(TEMP_SUFFIX)]
    except OSError:
        return
    for candidate in candidates:
        pid = candidate.name[len(prefix):].split(".", 1)[0]
        if not pid.isdigit() or int(pid) == os.getpid():
            continue
        try:
            os.kill(int(pid), 0)
        except ProcessLookupError:
            try:
                if stat.S_ISREG(os.lstat(candidate).st_mode):
                    candidate.unlink()
            except OSError:
                pass
        except OSError:
            pass  # the process exists (owned by someone else): not ours to clean


class _Exists(Exception):
    """The target of a write that must not replace anything appeared (or was there)."""


def _link_new(temporary: str, path: Path) -> None:
    """Give the finished ``temporary`` the name ``path`` only if no file has it (FileExistsError otherwise).

    A hard link is made atomically and never replaces; where the file system has none, the name is
    checked and the file renamed, which leaves a moment in which another writer could slip in.
    """
    try:
        os.link(temporary, path, follow_symlinks=False)
    except FileExistsError:
        raise
    except OSError as exc:
        if exc.errno not in LINKS_UNSUPPORTED:
            raise
        if os.path.lexists(path):
            raise FileExistsError(errno.EEXIST, "File exists", str(path)) from None
        os.replace(temporary, path)
    else:
        os.unlink(temporary)


@contextmanager
def whole_file(path: Path, binary: bool, replace: bool = True, mode: int | None = None):
    """A temporary file beside ``path`` that becomes ``path`` when the block ends without an exception.

    ``replace``: renamed onto ``path`` (a link there is replaced, not followed); otherwise it takes
    the name only if nothing has it, else :class:`_Exists`. ``mode``: the new file's permission bits
    (default: the replaced file's, or the umask's).
    """
    check_writable(path)
    # The name is chosen before the file is made, so that a Ctrl-C landing just after the file exists (Python
    # acts on a signal as a C call returns, inside tempfile.mkstemp too) still finds it to remove.
    temporary = str(path.parent / f".{path.name}.{os.getpid()}.{secrets.token_hex(8)}{TEMP_SUFFIX}")
    try:
        try:
            _remove_stale_temporaries(path)
            fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC, 0o600)
        except FileExistsError:  # not ours (a name of 64 random bits taken): leave it, and say so
            temporary = None
            raise InputError(f"{path}: cannot write: a temporary name beside it is taken") from None
        except OSError as exc:
            raise InputError(f"{path}: cannot write: {exc.strerror}") from None
        os.fchmod(fd, _new_file_mode(path) if mode is None else mode)
        with os.fdopen(fd, "wb" if binary else "w",
                       **({} if binary else {"newline": "", "encoding": "utf-8"})) as handle:
            yield handle
        if replace:
            os.replace(temporary, path)
        else:
            _link_new(temporary, path)
    except BaseException as exc:
        if temporary is not None:
            Path(temporary).unlink(missing_ok=True)
        if isinstance(exc, FileExistsError) and not replace:
            raise _Exists(str(path)) from None
        if isinstance(exc, OSError):
            raise InputError(f"{path}: cannot write: {exc.strerror}") from None
        raise


@contextmanager
def output(path, binary: bool = False):
    """A handle to write ``path`` whole or not at all (module docstring); ``-`` is standard output.

    Used as ``with output(path) as handle: handle.write(text)``.

    Parameters
    ----------
    path : str or pathlib.Path
        The file to write, or ``-`` for standard output.
    binary : bool, optional
        Open for bytes rather than text (UTF-8, newlines written as given).

    Yields
    ------
    file object
        The handle to write to; the file takes the name ``path`` when the block ends without an exception.

    Raises
    ------
    InputError
        If ``path`` cannot be written (a directory, a folder that does not exist or is not writable, a full
        device).
    """
    path = Path(path) if str(path) != STDOUT else STDOUT
    if path == STDOUT:
        stream = sys.stdout.buffer if binary else sys.stdout
        yield stream
        stream.flush()
        return
    if _is_streamed(path):
        try:
            handle = open(path, "wb" if binary else "w", **({} if binary else {"newline": ""}))
        except OSError as exc:
            raise InputError(f"{path}: cannot write: {exc.strerror}") from None
        try:
            with handle:
                yield handle
        except OSError as exc:
            raise InputError(f"{path}: cannot write: {exc.strerror or exc}") from None
        return
    with whole_file(path, binary) as handle:
        yield handle


def write_text(path, text: str) -> None:
    """Write ``text`` (UTF-8) to ``path``, whole or not at all.

    Parameters
    ----------
    path : str or pathlib.Path
        The file to write, or ``-`` for standard output.
    text : str
        What to write.

    Raises
    ------
    InputError
        If ``path`` cannot be written.
    """
    with output(path) as handle:
        handle.write(text)


def write_bytes(path, data: bytes) -> None:
    """Write ``data`` to ``path``, whole or not at all.

    Parameters
    ----------
    path : str or pathlib.Path
        The file to write, or ``-`` for standard output.
    data : bytes
        What to write.

    Raises
    ------
    InputError
        If ``path`` cannot be written.
    """
    with output(path, binary=True) as handle:
        handle.write(data)


def write_new(path, data: str | bytes) -> bool:
    """Write ``data`` to ``path`` whole, only if nothing is there: True if written, False if something was.

    Nothing that exists at ``path`` (a file, a link, a folder, a pipe) is replaced or written through,
    even if it appears while the data is being written.

    Parameters
    ----------
    path : str or pathlib.Path
        The file to write.
    data : str or bytes
        What to write (text as UTF-8).

    Returns
    -------
    bool
        True if the file was written, False if something already had the name.

    Raises
    ------
    InputError
        If ``path`` cannot be written (its folder is missing or not writable).
    """
    path = Path(path)
    if os.path.lexists(path):
        return False
    try:
        with whole_file(path, binary=True, replace=False) as handle:
            handle.write(data.encode("utf-8") if isinstance(data, str) else data)
    except _Exists:
        return False
    return True


def keep_backup(path) -> Path:
    """Copy the regular file ``path`` to ``NAME.bak-YYYYmmdd-HHMMSS`` beside it (``-2``, ``-3``, … when taken).

    An existing file is never replaced: the backup takes the first free name. The copy keeps the
    file's mode and times, and is a file of its own (not a second link to the same one), so whatever
    is done to ``path`` afterwards cannot reach it.

    Parameters
    ----------
    path : str or pathlib.Path
        The regular file to back up (a symbolic link is not followed).

    Returns
    -------
    pathlib.Path
        The backup's path.

    Raises
    ------
    InputError
        If ``path`` is not a readable regular file, the backup cannot be written, or the 999 backup names of
        this second are all taken.
    """
    path = Path(path)
    stamp = time.strftime("%Y%m%d-%H%M%S")
    source, _ = open_regular(path, "file to back up", follow=False)
    with source:
        st = os.fstat(source.fileno())
        for count in range(1, 1000):
            backup = path.with_name(f"{path.name}.bak-{stamp}" + (f"-{count}" if count > 1 else ""))
            if os.path.lexists(backup):
                continue
            source.seek(0)
            try:
                with whole_file(backup, binary=True, replace=False, mode=stat.S_IMODE(st.st_mode)) as handle:
                    shutil.copyfileobj(source, handle)
                    handle.flush()
                    os.utime(handle.fileno(), ns=(st.st_atime_ns, st.st_mtime_ns))
            except _Exists:
                continue
            return backup
    raise InputError(f"{path}: more than 999 backups named {path.name}.bak-{stamp}-N: remove some")


#: Rows of a CSV file formatted at a time by :func:`write_csv`.
CSV_CHUNK = 10_000  # rows formatted at a time: memory stays bounded for long tables


def write_csv(path, header: list[str], data: np.ndarray, comments: list[str] = ()) -> None:
    """A header row and float rows (``repr``, so values read back exactly), whole or not at all.

    ``comments`` become ``# …`` lines before the header (what
    :func:`~course_dynamics.tools.tables.read_table` skips).

    Parameters
    ----------
    path : str or pathlib.Path
        The file to write, or ``-`` for standard output.
    header : list of str
        The column names.
    data : numpy.ndarray, shape (N, len(header))
        The rows, as floats.
    comments : list of str, optional
        Lines written before the header, each as one ``# …`` line.

    Raises
    ------
    InputError
        If ``path`` cannot be written.
    ValueError
        If ``data`` is not a table of ``len(header)`` columns (a caller's mistake: nothing is written).
    """
    data = np.asarray(data, dtype=float)
    if data.ndim != 2 or data.shape[1] != len(header):
        raise ValueError(f"write_csv: {len(header)} column names for data of shape {data.shape}")
    with output(path) as handle:
        for line in comments:
            handle.write("# " + " ".join(str(line).split()) + "\n")
        csv.writer(handle, lineterminator="\n").writerow(header)
        for start in range(0, len(data), CSV_CHUNK):
            rows = data[start:start + CSV_CHUNK].tolist()  # Python floats: repr gives the shortest exact form
            handle.write("".join(",".join(map(repr, row)) + "\n" for row in rows))


__all__ = ["CSV_CHUNK", "STDOUT", "check_distinct", "check_writable", "keep_backup", "output", "write_bytes",
           "write_csv", "write_new", "write_text"]

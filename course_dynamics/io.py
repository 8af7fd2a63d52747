"""Reading tables and writing files, the one way the project does both.

Writing: :func:`output` (and :func:`write_text`, :func:`write_bytes`,
:func:`write_csv` on top of it) writes a whole file or nothing. The data goes
to a temporary file made with ``mkstemp`` (O_EXCL, so a planted file or link
is never followed) in the target's folder, given the mode the target would
have had (the replaced file's, or the umask's), and renamed onto the target
only when complete; on any exception, Ctrl-C included, it is removed. The
rename never follows a link: a symbolic link at the target is replaced, not
written through. ``-`` means standard output, and a target that is not a
regular file (a terminal, a pipe, ``/dev/stdout``) is streamed into, never
replaced.

Reading: :func:`read_columns` reads a CSV file into named numeric columns and
names the file, line and column of anything it cannot use.
"""
from __future__ import annotations

import csv
import io
import os
import stat
import sys
import tempfile
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from .errors import InputError

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


def check_writable(path) -> None:
    """Fail before long work if ``path`` cannot be written (InputError naming it)."""
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


@contextmanager
def output(path, binary: bool = False):
    """A handle to write ``path`` whole or not at all (module docstring); ``-`` is standard output."""
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
        with handle:
            yield handle
        return
    check_writable(path)
    try:
        fd, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".partial", dir=path.parent)
    except OSError as exc:
        raise InputError(f"{path}: cannot write: {exc.strerror}") from None
    try:
        os.fchmod(fd, _new_file_mode(path))
        with os.fdopen(fd, "wb" if binary else "w", **({} if binary else {"newline": "", "encoding": "utf-8"})) as handle:
            yield handle
        os.replace(temporary, path)
    except BaseException as exc:
        Path(temporary).unlink(missing_ok=True)
        if isinstance(exc, OSError):
            raise InputError(f"{path}: cannot write: {exc.strerror}") from None
        raise


def write_text(path, text: str) -> None:
    """Write ``text`` (UTF-8) to ``path``, whole or not at all."""
    with output(path) as handle:
        handle.write(text)


def write_bytes(path, data: bytes) -> None:
    """Write ``data`` to ``path``, whole or not at all."""
    with output(path, binary=True) as handle:
        handle.write(data)


CSV_CHUNK = 10_000  # rows formatted at a time: memory stays bounded for long tables


def write_csv(path, header: list[str], data: np.ndarray) -> None:
    """A header row and float rows (``repr``, so values read back exactly), whole or not at all."""
    data = np.asarray(data, dtype=float)
    with output(path) as handle:
        csv.writer(handle, lineterminator="\n").writerow(header)
        for start in range(0, len(data), CSV_CHUNK):
            rows = data[start:start + CSV_CHUNK].tolist()  # Python floats: repr gives the shortest exact form
            handle.write("".join(",".join(map(repr, row)) + "\n" for row in rows))


def read_columns(path, required: list[str], optional: list[str] = ()) -> dict[str, np.ndarray]:
    """The named columns of a CSV file, checked: every required one present, no unknown one, all finite."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    rows = list(csv.reader(io.StringIO(text)))
    if not rows:
        raise InputError(f"{path}: empty file, expected a header row")
    header = [h.strip() for h in rows[0]]
    missing = [c for c in required if c not in header]
    extra = [c for c in header if c not in required and c not in optional]
    if missing:
        raise InputError(f"{path}: missing columns: {', '.join(missing)}")
    if extra:
        raise InputError(f"{path}: unexpected columns: {', '.join(extra)} (expected {', '.join(required)})")
    if len(rows) < 2:
        raise InputError(f"{path}: no data rows")
    data = np.empty((len(rows) - 1, len(header)))
    for r, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise InputError(f"{path}: line {r} has {len(row)} values, the header has {len(header)}")
        for c, value in enumerate(row):
            try:
                data[r - 2, c] = float(value)
            except ValueError:
                raise InputError(f"{path}: line {r}, column '{header[c]}': '{value}' is not a number") from None
            if not np.isfinite(data[r - 2, c]):
                raise InputError(f"{path}: line {r}, column '{header[c]}': value is {value} (must be finite)")
    return {name: data[:, header.index(name)] for name in header}


def joint_columns(kinds, joints) -> list[str]:
    """Column names ``<kind>_<joint>``, kind by kind: e.g. q_theta1, q_theta2, qd_theta1, …"""
    return [f"{kind}_{j}" for kind in kinds for j in joints]


def stack_joint_columns(columns: dict, kind: str, joints) -> np.ndarray:
    """The ``<kind>_<joint>`` columns as one array (rows, n), joints in model order."""
    return np.column_stack([columns[f"{kind}_{j}"] for j in joints])

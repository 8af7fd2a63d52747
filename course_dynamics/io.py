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

A temporary file's name carries its writer's process id; one left behind by a
killed writer (SIGKILL cannot be caught) is removed by the next write to the
same target.

Reading: :func:`read_table` reads a delimited numeric table as logs come
(comma, semicolon or tab; UTF-8 with or without BOM, UTF-16, Latin-1; CRLF;
``#`` comment lines) and names the file, line and column of anything it cannot
use; :func:`read_columns` picks and checks named columns from it.
"""
from __future__ import annotations

import codecs
import csv
import os
import stat
import sys
import tempfile
from contextlib import contextmanager
from dataclasses import dataclass
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


def check_distinct(inputs, outputs) -> None:
    """InputError when an output would overwrite an input or another output (the same file by any name)."""
    def key(path):
        path = Path(path)
        try:
            st = os.stat(path)
            return ("inode", st.st_dev, st.st_ino) if stat.S_ISREG(st.st_mode) else None
        except OSError:
            return ("path", str(path.resolve()))

    seen = {}
    for role, paths in (("input", inputs), ("output", outputs)):
        for path in paths:
            if path is None or str(path) == STDOUT or _is_streamed(Path(path)):
                continue
            k = key(path)
            if k is None:
                continue
            if k in seen and role == "output":
                first_role, first = seen[k]
                raise InputError(f"{path}: the output would overwrite the input {first}" if first_role == "input"
                                 else f"{path}: named for two outputs ({first} and {path} are the same file)")
            seen.setdefault(k, (role, path))


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


TEMP_SUFFIX = ".partial"


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
        try:
            with handle:
                yield handle
        except OSError as exc:
            raise InputError(f"{path}: cannot write: {exc.strerror or exc}") from None
        return
    check_writable(path)
    try:
        _remove_stale_temporaries(path)
        fd, temporary = tempfile.mkstemp(prefix=f".{path.name}.{os.getpid()}.", suffix=TEMP_SUFFIX, dir=path.parent)
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


def write_csv(path, header: list[str], data: np.ndarray, comments: list[str] = ()) -> None:
    """A header row and float rows (``repr``, so values read back exactly), whole or not at all.

    ``comments`` become ``# …`` lines before the header (what :func:`read_table` skips).
    """
    data = np.asarray(data, dtype=float)
    with output(path) as handle:
        for line in comments:
            handle.write("# " + " ".join(str(line).split()) + "\n")
        csv.writer(handle, lineterminator="\n").writerow(header)
        for start in range(0, len(data), CSV_CHUNK):
            rows = data[start:start + CSV_CHUNK].tolist()  # Python floats: repr gives the shortest exact form
            handle.write("".join(",".join(map(repr, row)) + "\n" for row in rows))


DELIMITERS = (",", ";", "\t")


@dataclass(frozen=True)
class Table:
    """A numeric table read from a delimited text file.

    ``header``: the column names, stripped; ``data``: float array (rows, columns);
    ``lines``: the file line number of each data row (for messages); ``path``: the file.
    """

    path: str
    header: tuple[str, ...]
    data: np.ndarray
    lines: np.ndarray

    def column(self, name: str) -> np.ndarray:
        return self.data[:, self.header.index(name)]

    def columns(self) -> dict[str, np.ndarray]:
        return {name: self.data[:, c] for c, name in enumerate(self.header)}


def _decode(path: Path, raw: bytes) -> str:
    """UTF-16 with a BOM, UTF-8 (BOM or not), else Latin-1: a log's header may come from anywhere."""
    if raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        try:
            return raw.decode("utf-16")
        except UnicodeDecodeError as exc:
            raise InputError(f"{path}: not valid UTF-16 at byte {exc.start}") from None
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        return raw.decode("latin-1")  # every byte is a Latin-1 character; numbers are ASCII in all three


def _sniff(header_line: str) -> str:
    """The delimiter: whichever of comma, semicolon and tab the header uses most (comma when none)."""
    counts = {d: header_line.count(d) for d in DELIMITERS}
    best = max(DELIMITERS, key=lambda d: counts[d])
    return best if counts[best] else ","


def _cell_error(path, line: int, name: str, cell: str) -> InputError:
    cell = cell.strip()
    if cell == "":
        return InputError(f"{path}: line {line}, column '{name}': empty cell")
    try:
        value = float(cell)
    except ValueError:
        return InputError(f"{path}: line {line}, column '{name}': '{cell[:40]}' is not a number")
    return InputError(f"{path}: line {line}, column '{name}': value is {value} (must be finite)")


def read_table(path, comment: str = "#") -> Table:
    """Read a delimited numeric table, as trajectory logs come.

    Accepted: comma, semicolon or tab as delimiter (sniffed from the header; with
    semicolons or tabs a decimal comma is read too; a separator after the last
    column is ignored), UTF-8 with or without BOM,
    UTF-16 with BOM, Latin-1, CRLF line ends, blank lines and lines starting with
    ``comment`` anywhere. Every cell must be a finite number.

    Raises
    ------
    InputError
        Naming the file, and the line and column where it can: an unreadable or empty
        file, a header naming a column twice or an empty name, a row with another
        number of cells than the header, an empty, non-numeric or non-finite cell.
    """
    path = Path(path)
    try:
        if path.is_dir():
            raise InputError(f"{path}: is a directory, not a table")
        raw = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    numbered = [(i, line) for i, line in enumerate(_decode(path, raw).splitlines(), start=1)
                if line.strip() and not line.lstrip().startswith(comment)]
    if not numbered:
        raise InputError(f"{path}: empty file, expected a header row")
    (header_line_number, header_line), rows = numbered[0], numbered[1:]
    delimiter = _sniff(header_line)
    if header_line.rstrip(" \r\n").endswith(delimiter):  # a separator after the last column, as some exports write
        def cut(line):
            line = line.rstrip(" \r\n")
            return line[:-1] if line.endswith(delimiter) else line

        header_line, rows = cut(header_line), [(n, cut(line)) for n, line in rows]
    # The header as the csv module writes it: a name holding the delimiter or a quote is quoted.
    header = tuple(name.strip() for name in next(csv.reader([header_line], delimiter=delimiter)))
    seen = set()
    for c, name in enumerate(header):
        if not name:
            raise InputError(f"{path}: line {header_line_number}: column {c + 1} has no name")
        if name in seen:
            raise InputError(f"{path}: line {header_line_number}: column '{name}' appears twice")
        seen.add(name)
    if not rows:
        raise InputError(f"{path}: no data rows")
    decimal_comma = delimiter != "," and any("," in line for _, line in rows[:10])
    try:  # numpy's C reader for the common case; the loop below finds what it could not read
        if decimal_comma:
            raise ValueError
        data = np.loadtxt([line for _, line in rows], delimiter=delimiter, ndmin=2, dtype=float, quotechar='"')
        if data.shape != (len(rows), len(header)):
            raise ValueError
    except ValueError:
        data = _parse_rows(path, header, rows, delimiter, decimal_comma)
    bad = np.argwhere(~np.isfinite(data))
    if len(bad):
        r, c = bad[0]
        raise _cell_error(path, rows[r][0], header[c], rows[r][1].split(delimiter)[c])
    return Table(path=str(path), header=header, data=data, lines=np.array([n for n, _ in rows]))


def _parse_rows(path, header, rows, delimiter: str, decimal_comma: bool) -> np.ndarray:
    """Cell by cell, naming the line and column of the first cell that is not a number."""
    data = np.empty((len(rows), len(header)))
    for r, (line_number, line) in enumerate(rows):
        cells = line.split(delimiter)
        if len(cells) != len(header):
            raise InputError(f"{path}: line {line_number} has {len(cells)} values, the header has {len(header)}")
        for c, cell in enumerate(cells):
            cell = cell.strip().strip('"')
            try:
                data[r, c] = float(cell.replace(",", ".") if decimal_comma else cell)
            except ValueError:
                raise _cell_error(path, line_number, header[c], cell) from None
    return data


def read_columns(path, required: list[str], optional: list[str] = ()) -> dict[str, np.ndarray]:
    """The named columns of a table file (:func:`read_table`), checked: every required one present and no
    column that is neither required nor optional (logs with more signals go through :mod:`course_dynamics.logs`)."""
    table = read_table(path)
    missing = [c for c in required if c not in table.header]
    if missing:
        raise InputError(f"{path}: missing columns: {', '.join(missing)}")
    unknown = [c for c in table.header if c not in required and c not in optional]
    if unknown:
        raise InputError(f"{path}: unexpected columns: {', '.join(unknown)} (expected {', '.join(required)})")
    return table.columns()


def joint_columns(kinds, joints) -> list[str]:
    """Column names ``<kind>_<joint>``, kind by kind: e.g. q_theta1, q_theta2, qd_theta1, …"""
    return [f"{kind}_{j}" for kind in kinds for j in joints]


def stack_joint_columns(columns: dict, kind: str, joints) -> np.ndarray:
    """The ``<kind>_<joint>`` columns as one array (rows, n), joints in model order."""
    return np.column_stack([columns[f"{kind}_{j}"] for j in joints])

"""Reading tables as trajectory logs come.

:func:`read_table` reads a delimited numeric table (comma, semicolon or tab;
UTF-8 with or without BOM, UTF-16, Latin-1; CRLF; ``#`` comment lines) from a
regular file of a size that fits in memory, refuses a number it could read two
ways, and names the file, line and column of anything it cannot use;
:func:`read_columns` picks and checks named columns from it.
"""
from __future__ import annotations

import csv
import io as text_io
import itertools
import os
import re
from array import array
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..base import resources
from ..base.errors import InputError
from ..base.files import open_regular
from ..base.resources import check_memory, format_bytes

STDIN = "-"  # what a user may try for standard input: logs are read from files only
DELIMITERS = (",", ";", "\t")
DELIMITER_NAMES = {",": "commas", ";": "semicolons", "\t": "tabs"}
DECIMALS = ("point", "comma")
SAMPLE_ROWS = 10               # data rows read ahead to choose the delimiter and estimate the memory needed
MAX_LINE_CHARS = 16 * 2**20    # longer is no table (a header of 10 000 joints' columns is under 1 MiB)
# Peak memory of `course-dynamics torques ur5` per value (cell) of its log, measured with /usr/bin/time -v on
# generated logs of t and six positions (7 values a row, full-precision floats, 130 bytes a row) of 20 and
# 80 MiB (1.13 and 4.52 million values): peaks of 211 and 394 MB, i.e. 55 bytes per value (2.9 per byte of
# log) beyond what the imports take; 75 bytes per value with --with-state. Before the rows were streamed
# and tau computed in blocks it was 115 bytes per value (6.2 per byte: an 80 MiB log peaked at 657 MB),
# and reading alone took 72 bytes per value where it now takes 11. Budgeted with a margin for a model
# with more joints than the log has columns.
BYTES_PER_VALUE = 100


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


# A number as written in a log: ASCII digits only (Python's float() also takes '1_000', '١٢٣', '１２３'
# and surrounding Unicode spaces; numpy's reader, which the fast path uses, takes none of them).
_POINT_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_COMMA_NUMBER = re.compile(r"[+-]?(?:[0-9]+,[0-9]*|,[0-9]+)(?:[eE][+-]?[0-9]+)?")
_GROUPED = re.compile(r"[+-]?[1-9][0-9]{0,2},[0-9]{3}")   # 1,234: 1.234, or 1234 with a thousands separator
_NON_FINITE = re.compile(r"[+-]?(?:inf|infinity|nan)", re.IGNORECASE)


class _NotUTF8(Exception):
    """The file is not UTF-8 after all: read it again as Latin-1."""


def _split(line: str, delimiter: str) -> list[str]:
    """The cells of a line; a quoted cell may hold the delimiter (as the csv module writes it)."""
    return next(csv.reader([line], delimiter=delimiter)) if '"' in line else line.split(delimiter)


def _lines(path, text, comment: str, encoding: str):
    """(line number, line without its end) of every line that is neither blank nor a comment."""
    number = 0
    while True:
        try:
            line = text.readline(MAX_LINE_CHARS + 1)
        except UnicodeDecodeError:
            if encoding == "utf-16":
                raise InputError(f"{path}: not valid UTF-16 (line {number + 1})") from None
            raise _NotUTF8 from None
        if not line:
            return
        number += 1
        if len(line) > MAX_LINE_CHARS and not line.endswith("\n"):
            raise InputError(f"{path}: line {number} is longer than {MAX_LINE_CHARS // 2**20} MiB: not a table")
        stripped = line.strip()
        if stripped and not stripped.startswith(comment):
            yield number, line.rstrip("\r\n")


def _sniff(path, line_number: int, header_line: str, sample: list[str]) -> str:
    """The delimiter: the one of comma, semicolon and tab in the header (comma when none).

    When the header holds several, the one that splits the header and the first rows alike (and leaves
    none of the others in the rows, a comma excepted, which may be a decimal comma); when that does not
    settle it, the one the header uses most. A header and rows that split alike at spaces only are refused:
    spaces do not separate columns here, since a column's name may hold them.
    """
    present = [d for d in DELIMITERS if d in header_line]
    if not present:
        names = header_line.split()
        if len(names) > 1 and sample and all(len(row.split()) == len(names) for row in sample):
            raise InputError(f"{path}: line {line_number}: the columns look separated by spaces; only a comma, a "
                             "semicolon or a tab separates columns (a column's name may hold spaces)")
        return ","
    if len(present) == 1:
        return present[0]

    def fits(d):
        width = len(_split(header_line, d))
        others = [o for o in DELIMITERS if o not in (d, ",")]
        return width > 1 and all(len(_split(row, d)) == width and not any(o in row for o in others) for row in sample)

    fitting = [d for d in present if sample and fits(d)]
    if len(fitting) > 1:
        raise InputError(f"{path}: line {line_number}: the header and the rows split into columns alike at "
                         f"{' and at '.join(DELIMITER_NAMES[d] for d in fitting)}: which separates the columns is "
                         "ambiguous")
    return fitting[0] if fitting else max(present, key=header_line.count)


def _header(path, line_number: int, header_line: str, delimiter: str) -> tuple[str, ...]:
    # The header as the csv module writes it: a name holding the delimiter or a quote is quoted.
    header = tuple(name.strip() for name in next(csv.reader([header_line], delimiter=delimiter)))
    seen = set()
    for c, name in enumerate(header):
        if not name:
            raise InputError(f"{path}: line {line_number}: column {c + 1} has no name")
        if name in seen:
            raise InputError(f"{path}: line {line_number}: column '{name}' appears twice")
        seen.add(name)
    return header


def _cell_error(path, line: int, name: str, cell: str, delimiter: str, decimal: str | None) -> InputError:
    """Why a cell (stripped, unquoted) is not read: empty, a comma where none may be, not finite, not a number."""
    where = f"{path}: line {line}, column '{name}'"
    if cell == "":
        return InputError(f"{where}: empty cell")
    if _POINT_NUMBER.fullmatch(cell):
        return InputError(f"{where}: '{cell}' has a decimal point, but the decimal separator was given as a comma "
                          "(a point as a thousands separator is not read)")
    if _COMMA_NUMBER.fullmatch(cell):
        if delimiter == ",":
            return InputError(f"{where}: '{cell}' holds a comma in a comma-separated file: a decimal comma needs "
                              "semicolons or tabs between the columns")
        return InputError(f"{where}: '{cell}' has a comma, but the decimal separator was given as a point "
                          "(thousands separators are not read)")
    if _NON_FINITE.fullmatch(cell):
        return InputError(f"{where}: value is {float(cell)} (must be finite)")
    return InputError(f"{where}: '{cell[:40]}' is not a number{_why_not_a_number(cell)}")


def _why_not_a_number(cell: str) -> str:
    if "." in cell and "," in cell:
        return " (it has both a point and a comma: one of them would be a thousands separator, which is not read)"
    if cell.count(",") > 1 or cell.count(".") > 1:
        return " (thousands separators are not read)"
    if "_" in cell:
        return " ('_' between digits is not read)"
    if any(c.isdigit() and not c.isascii() for c in cell):
        return " (only the digits 0-9 are read)"
    if cell.lower().lstrip("+-").startswith("0x"):
        return " (hexadecimal is not read)"
    if re.fullmatch(r"[+-]?[0-9.,]+(?:\s+[0-9.,]+)+", cell):
        return " (a space inside a number, as a thousands separator, is not read)"
    return ""


_INTEGER_OR_COMMA = r"{pad}[+-]?(?:[0-9]+(?:,[0-9]*)?|,[0-9]+)(?:[eE][+-]?[0-9]+)?{pad}"
_INTEGER_OR_POINT = r"{pad}[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?{pad}"
BLOCK_ROWS = 8192  # rows whose cells are all plain numbers are handed to numpy's reader this many at a time


def _parse_rows(path, header, rows, delimiter: str, decimal: str | None) -> np.ndarray:
    """Row by row: the first cell that is not a number, or could be read two ways, is an error naming it.

    With ``decimal`` None a comma is a decimal comma (outside comma-separated files), unless the
    file also has a decimal point somewhere (one file, one separator), or every comma in the file is
    followed by exactly three digits (1,234 is 1.234, or 1234 with a thousands separator). A row
    whose cells are all plain numbers of one kind is checked by one pattern and read by numpy; any
    other row is read cell by cell, which finds and names what is wrong.
    """
    width = len(header)
    values, block = array("d"), []
    point = comma = grouped = None  # (line, column, cell) of the first cell with a point, a comma, a 1,234
    commas = delimiter != "," and decimal != "point"
    separator, pad = re.escape(delimiter), "[ ]*" if delimiter == "\t" else "[ \t]*"
    comma_cell, point_cell = _INTEGER_OR_COMMA.format(pad=pad), _INTEGER_OR_POINT.format(pad=pad)
    comma_row = re.compile(f"{comma_cell}(?:{separator}{comma_cell}){{{width - 1}}}")
    point_row = re.compile(f"{point_cell}(?:{separator}{point_cell}){{{width - 1}}}")

    def flush():
        if block:
            values.extend(np.loadtxt(block, delimiter=delimiter, ndmin=2, dtype=float, comments=None).ravel())
            block.clear()

    def mixed(line, c, cell, first, kind):
        there, column, seen = first
        other = "comma" if kind == "point" else "point"
        return InputError(f"{path}: line {line}, column '{header[c]}': '{cell}' has a decimal {kind}, but line "
                          f"{there}, column '{header[column]}' has '{seen}' with a {other}: a file has one decimal "
                          "separator, so one of the two is a thousands separator, and which one is ambiguous")

    for line_number, line in rows:
        has_comma, has_point = "," in line, "." in line
        if not has_comma and not (has_point and (comma or grouped or decimal == "comma")) and point_row.fullmatch(line):
            if has_point and point is None:
                c, cell = next((c, cell.strip()) for c, cell in enumerate(line.split(delimiter)) if "." in cell)
                point = (line_number, c, cell)
            block.append(line)
        elif commas and not has_point and point is None and comma_row.fullmatch(line):
            if comma is None:  # until a comma is seen that cannot be a thousands separator
                for c, cell in enumerate(line.split(delimiter)):
                    cell = cell.strip()
                    if "," in cell and comma is None:
                        if _GROUPED.fullmatch(cell):
                            grouped = grouped or (line_number, c, cell)
                        else:
                            comma = (line_number, c, cell)
            block.append(line.replace(",", "."))
        else:  # cell by cell
            flush()
            cells = _split(line, delimiter)
            if len(cells) != width:
                raise InputError(f"{path}: line {line_number} has {len(cells)} values, the header has {width}")
            for c, raw in enumerate(cells):
                cell = raw.strip()
                if '"' in cell:
                    cell = cell.strip('"')
                if _POINT_NUMBER.fullmatch(cell) and not ("." in cell and decimal == "comma"):
                    if "." in cell:
                        if comma or grouped:
                            raise mixed(line_number, c, cell, comma or grouped, "point")
                        point = point or (line_number, c, cell)
                    values.append(float(cell))
                elif commas and _COMMA_NUMBER.fullmatch(cell):
                    if point:
                        raise mixed(line_number, c, cell, point, "comma")
                    if comma is None:
                        if _GROUPED.fullmatch(cell):
                            grouped = grouped or (line_number, c, cell)
                        else:
                            comma = (line_number, c, cell)
                    values.append(float(cell.replace(",", ".")))
                else:
                    raise _cell_error(path, line_number, header[c], cell, delimiter, decimal)
        if len(block) >= BLOCK_ROWS:
            flush()
    flush()
    if grouped and not comma and decimal != "comma":
        line, c, cell = grouped
        raise InputError(f"{path}: line {line}, column '{header[c]}': '{cell}' could be {cell.replace(',', '.')} with "
                         f"a decimal comma or {cell.replace(',', '')} with a thousands separator, and no other number "
                         "in the file settles which; say it is a decimal comma (decimal='comma'; torques: --decimal "
                         "comma), or write the log with decimal points")
    return np.frombuffer(values, dtype=float).reshape(-1, width)


@dataclass(frozen=True)
class _RowLimit:
    rows: int
    message: str


def _row_limit(path, size: int, encoding: str, width: int, sample) -> _RowLimit:
    """Refuse a log whose estimated memory need (:data:`BYTES_PER_VALUE`) exceeds the budget; the rows it may have."""
    bytes_per_row = sum(len(line) + 1 for _, line in sample) / len(sample) * (2 if encoding == "utf-16" else 1)
    rows = size / max(bytes_per_row, 2.0)
    check_memory(rows * width * BYTES_PER_VALUE,
                 f"{path}: {format_bytes(size)}, about {rows:.3g} rows of {width} values: reading and using them")
    budget = resources.memory_budget()
    limit = int(budget // (width * BYTES_PER_VALUE))
    return _RowLimit(limit, f"{path}: more than {limit} rows of {width} values: reading and using them would need more "
                            f"than {format_bytes(budget)} of memory, half of this machine's {format_bytes(2 * budget)}")


def _rows(lines, cut, numbers: array, limit: _RowLimit):
    """The data rows as (number, line) with a comment and a separator after the last column cut; records numbers."""
    for number, line in lines:
        numbers.append(number)
        if len(numbers) > limit.rows:  # the estimate from the first rows was wrong: still bounded
            raise InputError(limit.message)
        yield number, cut(line)


def read_table(path, comment: str = "#", decimal: str | None = None) -> Table:
    """Read a delimited numeric table, as trajectory logs come.

    Accepted: comma, semicolon or tab as delimiter (sniffed from the header and the first
    rows; a separator after the last column is ignored), UTF-8 with or without BOM, UTF-16
    with BOM, Latin-1, CRLF or CR line ends, blank lines, lines starting with ``comment``,
    and ``comment`` after a row's last cell. Every cell must be a finite number written with
    the digits 0-9, an optional sign, decimal separator and exponent (``-1.5e-3``).

    The decimal separator: ``decimal`` "point" or "comma", or None to read it from the file.
    A point is decimal; with semicolons or tabs a comma is too, in files that have no point:
    what could be read two ways is refused, never guessed — a file with both (is ``1.500``
    1.5 or 1500?), a cell with both (``1.234,5``), a file whose every comma is followed by
    three digits (``1,234``: 1.234 or 1234?), a comma inside a quoted cell of a comma-separated
    file. Thousands separators, ``_`` between digits, other digits than 0-9, hexadecimal and
    columns separated by spaces are refused too.

    The file must be a regular file (:func:`open_regular`: never a pipe or device, which could
    block or be endless), and the memory its rows would take in use (:data:`BYTES_PER_VALUE`
    per cell, estimated from its size before it is read, then counted while reading) must fit in
    half the machine's memory. Rows are read as a stream: the text is never held whole.

    Raises
    ------
    InputError
        Naming the file, and the line and column where it can: an unreadable, special, too large
        or empty file, a header naming a column twice or an empty name, a row with another
        number of cells than the header, an empty, non-numeric, ambiguous or non-finite cell.
    """
    if decimal not in (None, *DECIMALS):
        raise InputError(f"the decimal separator must be {' or '.join(DECIMALS)}, got '{decimal}'")
    path = Path(path)
    if str(path) == STDIN and not os.path.lexists(path):
        raise InputError("-: a table is read from a file, not from standard input")
    handle, size = open_regular(path, "table")
    with handle:
        try:
            start = handle.read(2)
        except OSError as exc:
            raise InputError(f"{path}: cannot read: {exc.strerror}") from None
        if start in (b"\xff\xfe", b"\xfe\xff"):
            return _read_table(path, handle, size, "utf-16", comment, decimal)
        try:
            return _read_table(path, handle, size, "utf-8-sig", comment, decimal)
        except _NotUTF8:  # every byte is a Latin-1 character; numbers are ASCII in all three
            return _read_table(path, handle, size, "latin-1", comment, decimal)


def _read_table(path, handle, size: int, encoding: str, comment: str, decimal: str | None) -> Table:
    readers = []

    def data_lines():
        """A fresh pass over the file's lines: the header's first, then the data rows."""
        if readers:
            readers[-1].detach()
        handle.seek(0)
        readers.append(text_io.TextIOWrapper(handle, encoding=encoding, newline=None))  # \n, \r\n and \r end lines
        return _lines(path, readers[-1], comment, encoding)

    try:
        lines = data_lines()
        first = next(lines, None)
        if first is None:
            raise InputError(f"{path}: empty file, expected a header row")
        header_number, header_line = first
        sample = list(itertools.islice(lines, SAMPLE_ROWS))
        delimiter = _sniff(path, header_number, header_line, [line for _, line in sample])
        trailing = header_line.rstrip(" \r\n").endswith(delimiter)  # a separator after the last column, as some exports write

        def cut_trailing(line):
            line = line.rstrip(" \r\n")
            return line[:-1] if trailing and line.endswith(delimiter) else line

        def cut(line):  # a data row: a comment after its last cell goes too
            return cut_trailing(line[:line.index(comment)] if comment and comment in line else line)

        header = _header(path, header_number, cut_trailing(header_line), delimiter)
        if decimal == "comma" and delimiter == ",":
            raise InputError(f"{path}: line {header_number}: the columns are separated by commas, so no comma can be a "
                             "decimal separator (decimal='comma')")
        if not sample:
            raise InputError(f"{path}: no data rows")
        limit = _row_limit(path, size, encoding, len(header), sample)
        numbers = array("q")
        data = None
        if decimal != "comma":  # numpy's C reader for the common case; the loop below finds what it could not read
            try:
                rows = (line for _, line in _rows(itertools.chain(sample, lines), cut, numbers, limit))
                data = np.loadtxt(rows, delimiter=delimiter, ndmin=2, dtype=float, quotechar='"', comments=None)
                if data.shape != (len(numbers), len(header)):
                    data = None
            except (InputError, _NotUTF8):
                raise
            except ValueError:
                data = None
        if data is None:
            lines = data_lines()
            next(lines)
            numbers = array("q")
            data = _parse_rows(path, header, _rows(lines, cut, numbers, limit), delimiter, decimal)
        finite = np.isfinite(data)
        if not finite.all():
            r, c = np.argwhere(~finite)[0]
            raise InputError(f"{path}: line {numbers[r]}, column '{header[c]}': value is {data[r, c]} (must be finite)")
        return Table(path=str(path), header=header, data=data, lines=np.array(numbers, dtype=np.int64))
    finally:
        if readers:
            readers[-1].detach()  # the handle stays open for a second pass; its owner closes it


def read_columns(path, required: list[str], optional: list[str] = (), decimal: str | None = None) -> dict[str, np.ndarray]:
    """The named columns of a table file (:func:`read_table`), checked: every required one present and no
    column that is neither required nor optional (logs with more signals go through :mod:`course_dynamics.logs`)."""
    table = read_table(path, decimal=decimal)
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

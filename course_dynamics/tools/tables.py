"""Reading tables as trajectory logs come.

:func:`read_table` reads a delimited table (comma, semicolon, tab or runs of whitespace;
UTF-8 with or without BOM, UTF-16, Latin-1; CRLF; ``#`` comment lines) from a regular file
of a size that fits in memory, refuses a number it could read two ways (by the rules of
:mod:`course_dynamics.tools.cells`), and names the file, line and column of anything it
cannot use. A column whose first cell is a word (a mode or state a controller logs) is a text
column: listed in ``Table.text``, never read as numbers. :func:`read_columns` picks and
checks named columns from it.
"""
from __future__ import annotations

import io as text_io
import itertools
import os
from array import array
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..base import resources
from ..base.errors import InputError
from ..base.files import open_regular
from ..base.resources import check_memory, format_bytes
from .cells import WHITESPACE, clean, count_error, is_word, parse_rows, split

STDIN = "-"  # what a user may try for standard input: logs are read from files only
DELIMITERS = (",", ";", "\t")
DELIMITER_NAMES = {",": "commas", ";": "semicolons", "\t": "tabs", WHITESPACE: "whitespace"}
#: The decimal separators :func:`read_table` can be told a table uses.
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
#: Bytes of memory a table's value (cell) is budgeted at, read and in use; a table must fit in the budget.
BYTES_PER_VALUE = 100


@dataclass(frozen=True)
class Table:
    """A table read from a delimited text file: numeric columns, and text columns (words) beside them.

    ``header``: the column names, stripped; ``data``: float array (rows, columns), NaN in the text
    columns; ``lines``: the file line number of each data row (for messages); ``path``: the file;
    ``text``: the names of the text columns, in header order; ``first_words``: the cell of each
    in the first data row (see :meth:`first_word`).

    Parameters
    ----------
    path : str
        The file.
    header : tuple of str
        The column names, stripped.
    data : numpy.ndarray, shape (rows, columns)
        The values, in the file's units; NaN in the text columns.
    lines : numpy.ndarray, shape (rows,)
        The file line number of each data row.
    text : tuple of str
        The names of the text columns, in header order.
    first_words : tuple of str
        Each text column's cell in the first data row.
    blanks : int
        The empty cells of numeric columns read as NaN (``read_table(..., blanks=True)``; else 0).
    """

    path: str
    header: tuple[str, ...]
    data: np.ndarray
    lines: np.ndarray
    text: tuple[str, ...] = ()
    first_words: tuple[str, ...] = ()
    blanks: int = 0

    def column(self, name: str) -> np.ndarray:
        """One column by name.

        Parameters
        ----------
        name : str
            A name of ``header``.

        Returns
        -------
        numpy.ndarray, shape (rows,)
            Its values (NaN for a text column).

        Raises
        ------
        ValueError
            If ``name`` is not in the header.
        """
        return self.data[:, self.header.index(name)]

    def columns(self) -> dict[str, np.ndarray]:
        """The numeric columns by name, in header order (the text columns are left out).

        Returns
        -------
        dict of str to numpy.ndarray
            {name: values of shape (rows,)}.
        """
        return {name: self.data[:, c] for c, name in enumerate(self.header) if name not in self.text}

    def first_word(self, name: str) -> tuple[int, str]:
        """(line number, cell) of a text column's first data row, for messages: ``(2, 'RUNNING')``.

        Parameters
        ----------
        name : str
            A text column's name.

        Returns
        -------
        tuple of (int, str)
            The line number and the cell.

        Raises
        ------
        KeyError
            If ``name`` is not a text column.
        """
        if name not in self.text:
            raise KeyError(f"{name!r} is not a text column of {self.path}")
        return int(self.lines[0]), self.first_words[self.text.index(name)]


class _NotUTF8(Exception):
    """The file is not UTF-8 after all: read it again as Latin-1."""


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


def _sniff(path, line_number: int, header_line: str, sample: list[str]) -> str | None:
    """The delimiter: the one of comma, semicolon and tab in the header, or whitespace (comma when none).

    With none of the three in the header, whitespace when the header splits into several names at runs of
    whitespace and the rows into several cells (a row with another number of cells than the header is
    then refused, naming both counts); a header whose rows have one cell each is one name holding spaces.
    With tabs only, tabs when every row has the header's number of cells at tabs, none of them empty or
    holding whitespace (a name may hold spaces); else whitespace when the header and the rows split alike
    at runs of it, as aligned output writes them (tabs and spaces, runs of tabs). When the header holds
    several of the three, the one that splits the header and the first rows alike (and leaves none of the
    others in the rows, a comma excepted, which may be a decimal comma); when that does not settle it,
    the one the header uses most.
    """
    present = [d for d in DELIMITERS if d in header_line]
    if present in ([], ["\t"]):
        names, counts = len(header_line.split()), [len(row.split()) for row in sample]
        if not present:
            return WHITESPACE if names > 1 and any(count > 1 for count in counts) else ","
        if not _splits_at_tabs(header_line, sample) and names > 1 and all(count == names for count in counts):
            return WHITESPACE
        return "\t"
    if len(present) == 1:
        return present[0]

    def fits(d):
        width = len(split(header_line, d))
        others = [o for o in DELIMITERS if o not in (d, ",")]
        return width > 1 and all(len(split(row, d)) == width and not any(o in row for o in others) for row in sample)

    fitting = [d for d in present if sample and fits(d)]
    if len(fitting) > 1:
        raise InputError(f"{path}: line {line_number}: the header and the rows split into columns alike at "
                         f"{' and at '.join(DELIMITER_NAMES[d] for d in fitting)}: which separates the columns is "
                         "ambiguous")
    return fitting[0] if fitting else max(present, key=header_line.count)


def _splits_at_tabs(header_line: str, sample: list[str]) -> bool:
    """Whether each row has the header's number of cells at tabs, each one non-empty run of non-spaces."""
    width = len(split(header_line.rstrip(" \t"), "\t"))
    cells = [split(row.rstrip(" \t"), "\t") for row in sample]
    return all(len(row) == width and all(len(cell.split()) == 1 for cell in row) for row in cells)


def _header(path, line_number: int, header_line: str, delimiter: str | None) -> tuple[str, ...]:
    # The header as the csv module writes it: a name holding the delimiter or a quote is quoted
    # (between runs of whitespace a name holds neither, and loses the quotes around it).
    header = tuple((clean if delimiter is WHITESPACE else str.strip)(name) for name in split(header_line, delimiter))
    seen = set()
    for c, name in enumerate(header):
        if not name:
            raise InputError(f"{path}: line {line_number}: column {c + 1} has no name")
        if name in seen:
            raise InputError(f"{path}: line {line_number}: column '{name}' appears twice")
        seen.add(name)
    return header


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
                            f"than {format_bytes(budget)} of memory, {resources.budget_text(budget)}")


def _rows(lines, cut, numbers: array, limit: _RowLimit):
    """The data rows as (number, ``cut(number, line)``); records the numbers."""
    for number, line in lines:
        numbers.append(number)
        if len(numbers) > limit.rows:  # the estimate from the first rows was wrong: still bounded
            raise InputError(limit.message)
        yield number, cut(number, line)


def _text_columns(path, header, first: tuple[int, str], delimiter) -> dict[int, str]:
    """{column: cell} of the columns whose cell in the first data row is a word (:func:`is_word`)."""
    number, line = first
    cells = [clean(cell) for cell in split(line, delimiter)]
    if len(cells) != len(header):
        raise count_error(path, number, len(cells), len(header), delimiter)
    text = {c: cell for c, cell in enumerate(cells) if is_word(cell)}
    if len(text) == len(header):
        raise InputError(f"{path}: line {number}: every cell is a word ('{cells[0][:40]}', …): no column holds numbers")
    return text


def _numeric_cells(path, width: int, numeric: list[int], delimiter):
    """A row's cells in the columns ``numeric``, joined again (and quoted again where they need it)."""
    join = " " if delimiter is WHITESPACE else delimiter

    def quote(cell):
        return '"' + cell.replace('"', '""') + '"' if delimiter in cell or '"' in cell else cell

    def keep(number, line):
        cells = split(line, delimiter)
        if len(cells) != width:
            raise count_error(path, number, len(cells), width, delimiter)
        if '"' in line and delimiter is not WHITESPACE:  # the csv module took the quotes off
            return join.join(quote(cells[c]) for c in numeric)
        return join.join([cells[c] for c in numeric])
    return keep


def _blank_cells(delimiter, blank: list):
    """A row's empty cells as ``0``, their (line, column) recorded in ``blank``: NaN once the row is read."""
    def fill(number, line):
        if delimiter is WHITESPACE or delimiter * 2 not in delimiter + line + delimiter:
            return line
        cells = split(line, delimiter)
        empty = [c for c, cell in enumerate(cells) if not cell.strip()]
        if '"' in line or not empty:
            return line
        blank.extend((number, c) for c in empty)
        return delimiter.join("0" if c in empty else cell for c, cell in enumerate(cells))
    return fill


def read_table(path, comment: str = "#", decimal: str | None = None, blanks: bool = False) -> Table:
    """Read a delimited table of numbers (and words), as trajectory logs come.

    Accepted: comma, semicolon or tab as delimiter, or runs of whitespace (spaces and tabs,
    as UR's RTDE recorder and aligned output write them; leading and trailing whitespace is
    no cell), sniffed from the header and the first rows (a separator after the last column
    is ignored); UTF-8 with or without BOM, UTF-16 with BOM, Latin-1; CRLF or CR line ends,
    blank lines, lines starting with ``comment``, and ``comment`` after a row's last cell.
    Every cell of a numeric column must be a finite number written with the digits 0-9, an
    optional sign, decimal separator and exponent (``-1.5e-3``).

    Text columns: a column whose cell in the first data row is a word (it starts with a letter,
    quoted or not: ``RUNNING``, ``mode = auto``; :func:`course_dynamics.tools.cells.is_word`) holds
    text, whatever its later cells; its name is in ``Table.text``, its data NaN, and
    :meth:`Table.columns` leaves it out. The first row decides, never a later one: a word in a
    numeric column is an error naming its line and column (a typo must not turn a signal to text).

    The decimal separator: ``decimal`` "point" or "comma", or None to read it from the file.
    A point is decimal; between semicolons, tabs or whitespace a comma is too, in files that
    have no point: what could be read two ways is refused, never guessed — a file with both (is
    ``1.500`` 1.5 or 1500?), a cell with both (``1.234,5``), a file whose every comma is followed
    by three digits (``1,234``: 1.234 or 1234?), a comma inside a quoted cell of a comma-separated
    file. Thousands separators, ``_`` between digits, other digits than 0-9 and hexadecimal are
    refused too.

    The file must be a regular file (:func:`~course_dynamics.base.files.open_regular`: never a pipe or
    device, which could block or be endless), and the memory its rows would take in use (:data:`BYTES_PER_VALUE`
    per cell, estimated from its size before it is read, then counted while reading) must fit in
    half the machine's memory. Rows are read as a stream: the text is never held whole.

    Parameters
    ----------
    path : str or os.PathLike
        The table's file.
    comment : str
        What starts a comment, a whole line or after a row's last cell.
    decimal : str, optional
        ``"point"`` or ``"comma"``; None reads it from the file.
    blanks : bool
        Read an empty cell of a numeric column as NaN (a recorder's "no sample here") instead of refusing it;
        ``Table.blanks`` counts them.

    Returns
    -------
    Table
        The header, the values, the line of each row and the text columns.

    Raises
    ------
    InputError
        Naming the file, and the line and column where it can: an unreadable, special, too large
        or empty file, a header naming a column twice or an empty name, a row with another
        number of cells than the header, an empty, non-numeric, ambiguous or non-finite cell
        of a numeric column, a first row of words only.
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
            return _read_table(path, handle, size, "utf-16", comment, decimal, blanks)
        try:
            return _read_table(path, handle, size, "utf-8-sig", comment, decimal, blanks)
        except _NotUTF8:  # every byte is a Latin-1 character; numbers are ASCII in all three
            return _read_table(path, handle, size, "latin-1", comment, decimal, blanks)


def _read_table(path, handle, size: int, encoding: str, comment: str, decimal: str | None, blanks: bool) -> Table:
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
        uncommented = [line[:line.index(comment)] if comment and comment in line else line for _, line in sample]
        delimiter = _sniff(path, header_number, header_line, uncommented)
        # a separator after the last column, as some exports write (trailing whitespace is no cell anyway)
        trailing = delimiter is not WHITESPACE and header_line.rstrip(" \r\n").endswith(delimiter)

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
        number, first_row = sample[0]
        text = _text_columns(path, header, (number, cut(first_row)), delimiter)
        numeric = [c for c in range(len(header)) if c not in text]
        names = tuple(header[c] for c in numeric)
        if text:  # the rows lose their text cells before any number is read
            keep = _numeric_cells(path, len(header), numeric, delimiter)

            def row(number, line):
                return keep(number, cut(line))
        else:
            def row(number, line):
                return cut(line)
        blank: list = []
        if blanks:
            fill, numeric_row = _blank_cells(delimiter, blank), row

            def row(number, line):
                return fill(number, numeric_row(number, line))
        numbers = array("q")
        data = None
        if decimal != "comma":  # numpy's C reader for the common case; the loop below finds what it could not read
            quotes = None if delimiter is WHITESPACE else '"'  # quotes in whitespace are the loop's (cells.clean)
            try:
                rows = (line for _, line in _rows(itertools.chain(sample, lines), row, numbers, limit))
                data = np.loadtxt(rows, delimiter=delimiter, ndmin=2, dtype=float, quotechar=quotes, comments=None)
                if data.shape != (len(numbers), len(names)):
                    data = None
            except (InputError, _NotUTF8):
                raise
            except ValueError:
                data = None
        if data is None:
            lines = data_lines()
            next(lines)
            numbers = array("q")
            blank.clear()
            data = parse_rows(path, names, _rows(lines, row, numbers, limit), delimiter, decimal)
        finite = np.isfinite(data)
        if not finite.all():
            r, c = np.argwhere(~finite)[0]
            raise InputError(f"{path}: line {numbers[r]}, column '{names[c]}': value is {data[r, c]} (must be finite)")
        if blank:
            at = np.array(blank)
            data[np.searchsorted(np.array(numbers), at[:, 0]), at[:, 1]] = np.nan
        if text:
            full = np.full((len(data), len(header)), np.nan)
            full[:, numeric] = data
            data = full
        return Table(path=str(path), header=header, data=data, lines=np.array(numbers, dtype=np.int64),
                     text=tuple(header[c] for c in text), first_words=tuple(text.values()), blanks=len(blank))
    finally:
        if readers:
            readers[-1].detach()  # the handle stays open for a second pass; its owner closes it


def read_columns(path, required: list[str], optional: list[str] = (),
                 decimal: str | None = None) -> dict[str, np.ndarray]:
    """The named columns of a table file (:func:`read_table`), checked: every required one present, none of them
    text, and no column that is neither required nor optional (logs with more signals go through
    :mod:`course_dynamics.tools.logs`).

    Parameters
    ----------
    path : str or os.PathLike
        The table's file.
    required : list of str
        The columns it must have.
    optional : list of str
        The columns it may have besides.
    decimal : str, optional
        ``"point"`` or ``"comma"``; None reads it from the file.

    Returns
    -------
    dict of str to numpy.ndarray
        {name: values of shape (rows,)}.

    Raises
    ------
    InputError
        Whatever :func:`read_table` refuses, a required column missing, a column of words among those asked for,
        or an unexpected column.
    """
    table = read_table(path, decimal=decimal)
    missing = [c for c in required if c not in table.header]
    if missing:
        raise InputError(f"{path}: missing columns: {', '.join(missing)}")
    words = [c for c in table.text if c in required or c in optional]
    if words:
        line, cell = table.first_word(words[0])
        raise InputError(f"{path}: line {line}, column '{words[0]}': '{cell[:40]}' is not a number (a column of words)")
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


__all__ = ["BYTES_PER_VALUE", "DECIMALS", "Table", "read_columns", "read_table"]

"""The cells of a delimited table, read as numbers one way only (for :func:`course_dynamics.tools.tables.read_table`).

A number as a log writes it: ASCII digits, an optional sign, decimal separator and exponent.
:func:`parse_rows` reads the rows of the numeric columns and refuses any cell it could read
two ways; :func:`is_word` tells a text cell (a mode or state a controller logs) from a number
or a typo of one; :func:`split` cuts a line into cells at a delimiter or at whitespace.

>>> split(' 1.5 \\t-2  RUNNING ', WHITESPACE), split('1,"a,b",2', ",")
(['1.5', '-2', 'RUNNING'], ['1', 'a,b', '2'])
"""
from __future__ import annotations

import csv
import re
from array import array

import numpy as np

from ..base.errors import InputError

# Columns separated by runs of spaces and tabs: what str.split() and numpy's reader (delimiter=None)
# split at, which is any whitespace, so that both paths of the reader cut a row alike.
#: The delimiter that means runs of spaces and tabs (None, as ``str.split`` and numpy's reader take it).
WHITESPACE = None

# A number as written in a log: ASCII digits only (Python's float() also takes '1_000', '١٢٣', '１２３'
# and surrounding Unicode spaces; numpy's reader, which the fast path uses, takes none of them).
_POINT_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_COMMA_NUMBER = re.compile(r"[+-]?(?:[0-9]+,[0-9]*|,[0-9]+)(?:[eE][+-]?[0-9]+)?")
_GROUPED = re.compile(r"[+-]?[1-9][0-9]{0,2},[0-9]{3}")   # 1,234: 1.234, or 1234 with a thousands separator
_NON_FINITE = re.compile(r"[+-]?(?:inf|infinity|nan)", re.IGNORECASE)


def split(line: str, delimiter: str | None) -> list[str]:
    """The cells of a line; a quoted cell may hold the delimiter (as the csv module writes it).

    With :data:`WHITESPACE` a cell is a run of other characters: leading and trailing whitespace
    make no cell, and a quote is part of its cell (strip it with :func:`clean`).

    Parameters
    ----------
    line : str
        A line of the table, without its end.
    delimiter : str or None
        ``,``, ``;``, a tab, or :data:`WHITESPACE`.

    Returns
    -------
    list of str
        The cells, unstripped (quotes removed where the csv module reads them).
    """
    if delimiter is WHITESPACE:
        return line.split()
    return next(csv.reader([line], delimiter=delimiter)) if '"' in line else line.split(delimiter)


def clean(cell: str) -> str:
    """A cell as it is judged: stripped of spaces and of the quotes around it.

    Parameters
    ----------
    cell : str
        A cell as :func:`split` gives it.

    Returns
    -------
    str
        The cell, stripped.
    """
    cell = cell.strip()
    return cell.strip('"') if '"' in cell else cell


def is_word(cell: str) -> bool:
    """Whether a (:func:`clean`) cell is a word: it starts with a letter and is no spelling of inf or nan.

    A cell starting with a digit, sign or point is a number or a typo of one (``1_000``, ``0x10``,
    ``١٢٣``), never a word.

    Parameters
    ----------
    cell : str
        A cleaned cell.

    Returns
    -------
    bool
        Whether it is a word.

    Examples
    --------
    >>> [is_word(cell) for cell in ("RUNNING", "mode = auto", "STATE_2", "1_000", "0x10", "nan", "-1", "")]
    [True, True, True, False, False, False, False, False]
    """
    return cell[:1].isalpha() and not _NON_FINITE.fullmatch(cell)


def count_error(path, line: int, count: int, width: int, delimiter: str | None) -> InputError:
    """A row with another number of cells than the header."""
    how = " (columns separated by whitespace)" if delimiter is WHITESPACE else ""
    return InputError(f"{path}: line {line} has {count} values, the header has {width}{how}")


def _cell_error(path, line: int, name: str, cell: str, delimiter: str | None, decimal: str | None) -> InputError:
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


def _row_patterns(width: int, delimiter: str | None) -> tuple[re.Pattern, re.Pattern]:
    """Whole rows of plain numbers with a decimal comma (or none), and with a decimal point (or none)."""
    if delimiter is WHITESPACE:  # numbers hold no space: the runs between them are unambiguous, no backtracking
        separator, pad, ends = "[ \t]+", "", "[ \t]*"
    else:
        separator, pad, ends = re.escape(delimiter), "[ ]*" if delimiter == "\t" else "[ \t]*", ""
    comma_cell, point_cell = _INTEGER_OR_COMMA.format(pad=pad), _INTEGER_OR_POINT.format(pad=pad)
    return (re.compile(f"{ends}{comma_cell}(?:{separator}{comma_cell}){{{width - 1}}}{ends}"),
            re.compile(f"{ends}{point_cell}(?:{separator}{point_cell}){{{width - 1}}}{ends}"))


def parse_rows(path, header, rows, delimiter: str | None, decimal: str | None) -> np.ndarray:
    """Row by row: the first cell that is not a number, or could be read two ways, is an error naming it.

    ``rows`` are (line number, line) holding the cells of the columns ``header`` names. With
    ``decimal`` None a comma is a decimal comma (outside comma-separated files), unless the
    file also has a decimal point somewhere (one file, one separator), or every comma in the file is
    followed by exactly three digits (1,234 is 1.234, or 1234 with a thousands separator). A row
    whose cells are all plain numbers of one kind is checked by one pattern and read by numpy; any
    other row is read cell by cell, which finds and names what is wrong.

    Parameters
    ----------
    path : str or os.PathLike
        The file, for messages.
    header : sequence of str
        The numeric columns' names.
    rows : iterable of (int, str)
        (line number, line) of each data row, holding only the numeric columns' cells.
    delimiter : str or None
        ``,``, ``;``, a tab, or :data:`WHITESPACE`.
    decimal : str or None
        ``"point"`` or ``"comma"``; None reads it from the rows.

    Returns
    -------
    numpy.ndarray, shape (rows, len(header))
        The values.

    Raises
    ------
    InputError
        Naming the line and column of the first cell that is not a number, could be read two ways, or of a row
        with another number of cells than the header.
    """
    width = len(header)
    values, block = array("d"), []
    point = comma = grouped = None  # (line, column, cell) of the first cell with a point, a comma, a 1,234
    commas = delimiter != "," and decimal != "point"
    comma_row, point_row = _row_patterns(width, delimiter)

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
            cells = split(line, delimiter)
            if len(cells) != width:
                raise count_error(path, line_number, len(cells), width, delimiter)
            for c, raw in enumerate(cells):
                cell = clean(raw)
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


__all__ = ["WHITESPACE", "clean", "is_word", "parse_rows", "split"]

"""What a student hands in and who they are: a Python file or a notebook's code cells, and the id on the roster.

A Jupyter notebook (``.ipynb``) is graded from its code cells, joined in order into one Python
file, each cell after a ``# In[k]:`` line (the line numbers of its feedback count in that
file). The notebook is read as hostile JSON: at most :data:`MAX_NOTEBOOK_BYTES`, integers of
at most 18 digits, every cell checked; anything else is a ``not python`` status
saying what is wrong and how to export one ``.py`` instead. A line of IPython's own (a magic
``%timeit …`` or ``%%time``, a shell ``!pip …``) is no Python: it becomes ``pass`` with a note.

A roster (the assignment's ``roster``) is matched as :func:`roster_match` says: exactly, else
ignoring case, else ignoring case and a ``+tag`` (``ada+hw1`` is ``ada``), each only when it
names one student.
"""
from __future__ import annotations

import ast
import json
import re
import threading

from ..base.errors import InputError
from ..base.files import read_small

#: The largest notebook read, bytes (its outputs, plots included, count).
MAX_NOTEBOOK_BYTES = 20 * 2**20
MAX_DIGITS = 18  # an integer in a notebook's JSON (execution counts) has at most this many digits
MAX_CELLS = 10_000
# CPython before 3.11.8 and 3.12.1 counts the depth of an AST's conversion per interpreter, not per thread:
# two threads parsing at once fail with "AST constructor recursion depth mismatch". A class is graded in a pool
# of threads, so every parse of ours takes this lock.
_PARSING = threading.Lock()
EXPORT = ("export the notebook as one Python file (Jupyter: File > Save and Export Notebook As > Executable Script; "
          "or jupyter nbconvert --to script NOTEBOOK.ipynb) and submit that")
IPYTHON_LINE = re.compile(r"\s*(%|!)")


class NotANotebook(InputError):
    """A file that is no notebook whose code cells can be read (the message says what is wrong)."""


def _integer(text: str) -> int:
    if len(text.lstrip("-")) > MAX_DIGITS:
        raise NotANotebook(f"an integer of {len(text)} digits")
    return int(text)


def _cells(data: bytes) -> list:
    try:
        document = json.loads(data.decode("utf-8"), parse_int=_integer, parse_constant=lambda name: None)
    except UnicodeDecodeError:
        raise NotANotebook("the notebook is not UTF-8 text") from None
    except (ValueError, RecursionError) as exc:
        raise NotANotebook(f"the notebook is not valid JSON ({type(exc).__name__})") from None
    cells = document.get("cells") if isinstance(document, dict) else None
    if not isinstance(cells, list):
        raise NotANotebook("the notebook has no list of cells (a Jupyter notebook of format 4 has one)")
    if len(cells) > MAX_CELLS:
        raise NotANotebook(f"the notebook has {len(cells)} cells, more than {MAX_CELLS}")
    return cells


def notebook_code(data: bytes) -> tuple[str, list[str]]:
    """The code cells of a notebook's bytes as one Python source, and the notes of what was changed.

    Parameters
    ----------
    data : bytes
        The ``.ipynb`` file's bytes.

    Returns
    -------
    tuple of (str, list of str)
        The source (each cell after a ``# In[k]:`` line) and notes (IPython lines made ``pass``).

    Raises
    ------
    NotANotebook
        If the bytes are not a notebook's JSON, or a cell is not what a notebook's cell is.
    """
    lines, notes, magics = [], [], []
    for number, cell in enumerate(_cells(data), start=1):
        if not isinstance(cell, dict) or not isinstance(cell.get("cell_type"), str):
            raise NotANotebook(f"cell {number} is not a notebook cell")
        if cell["cell_type"] != "code":
            continue
        source = cell.get("source", "")
        if isinstance(source, list) and all(isinstance(part, str) for part in source):
            source = "".join(source)
        if not isinstance(source, str):
            raise NotANotebook(f"cell {number}'s source is not text")
        lines.append(f"# In[{number}]:")
        for line in source.splitlines():
            if IPYTHON_LINE.match(line):
                magics.append(f"cell {number}: {line.strip()[:60]}")
                line = line[:len(line) - len(line.lstrip())] + "pass  # an IPython line, not Python: " \
                    + repr(line.strip()[:60])
            lines.append(line)
        lines.append("")
    if magics:
        notes.append(f"IPython lines are not Python and were not run ({'; '.join(magics[:5])}"
                     f"{f' and {len(magics) - 5} more' if len(magics) > 5 else ''})")
    return "\n".join(lines) + "\n", notes


def read_notebook(path) -> tuple[str | None, str, list[str]]:
    """A notebook file's code (:func:`notebook_code`): (source, "", notes), or (None, why not, []).

    Parameters
    ----------
    path : str or os.PathLike
        The ``.ipynb`` file.

    Returns
    -------
    tuple of (str or None, str, list of str)
        The source, an empty reason and the notes; or None, why it cannot be graded (with how to export a ``.py``),
        and no notes.
    """
    try:
        source, notes = notebook_code(read_small(path, MAX_NOTEBOOK_BYTES, "notebook"))
    except InputError as exc:
        return None, f"{exc}; {EXPORT}", []
    return source, "", [f"graded from the notebook's code cells, joined in order (each after a '# In[k]:' line; "
                        "line numbers count in that file)", *notes]


def roster_match(student: str, roster) -> tuple[str | None, str]:
    """The roster's id for ``student``: exactly, else ignoring case, else ignoring case and a ``+tag``, each only when
    it names one student; (None, why) otherwise.

    Parameters
    ----------
    student : str
        The id given (a file's name, the local part of Gradescope's e-mail).
    roster : iterable of str
        The roster's ids.

    Returns
    -------
    tuple of (str or None, str)
        The roster's id and ``""``, or None and the sentence for the student's feedback.

    Examples
    --------
    >>> roster_match("Ada+hw1", ["ada", "grace"])
    ('ada', '')
    """
    roster = list(roster)
    if student in roster:
        return student, ""

    def untagged(name: str) -> str:
        return name.split("+", 1)[0].casefold()

    for key in (str.casefold, untagged):
        found = [r for r in roster if key(r) == key(student)]
        if len(found) == 1:
            return found[0], ""
        if len(found) > 1:
            return None, (f"not on the roster: '{student}' could be any of {', '.join(found[:5])}; ask your "
                          "instructor which is yours")
    return None, f"not on the roster: no student '{student}' is on this assignment's roster; ask your instructor"


def parse_python(source: str, filename: str) -> ast.Module:
    """``ast.parse`` of a submission's source, one parse at a time in this process (threads grade a class).

    Parameters
    ----------
    source : str
        The Python source.
    filename : str
        The name its syntax errors give.

    Returns
    -------
    ast.Module
        The syntax tree.

    Raises
    ------
    SyntaxError
        If the source is not Python (``ValueError`` for a NUL byte, ``RecursionError`` for nesting too deep, as
        ``ast.parse`` raises them).

    Examples
    --------
    >>> type(parse_python("x = 1", "a.py").body[0]).__name__
    'Assign'
    """
    with _PARSING:
        return ast.parse(source, filename=filename)


__all__ = ["MAX_NOTEBOOK_BYTES", "NotANotebook", "notebook_code", "parse_python", "read_notebook", "roster_match"]

"""The notebook course: reading its notebooks, making student versions, running them, publishing them.

The course's notebooks are stored as Python files in jupytext's *percent*
format (``notebooks/NN_topic.py``: ``# %%`` starts a code cell,
``# %% [markdown]`` a text cell): they are the source of truth, readable in
review, and every tool here turns them into ``.ipynb`` notebooks.

An exercise's solution sits between ``### BEGIN SOLUTION`` and
``### END SOLUTION`` in a code cell (nbgrader's convention), and the next cell
calls :func:`course_dynamics.teaching.exercises.check`. :func:`student_version`
replaces every solution region by ``pass  # YOUR CODE HERE`` at the same
indentation, so the notebook still runs and the check reports "not done yet",
and leaves out the cells marked :data:`SOLUTIONS_ONLY` (the library showing an
exercise's answer, which the version with solutions keeps);
both versions carry nbgrader's cell metadata (solution cells, and check cells
read-only and worth no points), so an instructor can also use nbgrader. A check
runs in the student's own kernel, where it can be made to pass: marks come from
``course-dynamics grade``, which runs each submission in a sandbox.
"""
from __future__ import annotations

import base64
import copy
import os
import re
import stat
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from markupsafe import Markup

from ..base.errors import InputError
from ..output import io, page
from ..output.folders import check_folder, write_folder
from ..tools.variants import check_student_id

BEGIN, END = "### BEGIN SOLUTION", "### END SOLUTION"
#: The first line (alone, or as a comment) of a cell that only the version with solutions keeps.
SOLUTIONS_ONLY = "(with the solutions only)"  # a cell whose first line is this (or "# " and this) shows an answer
PLACEHOLDER = "pass  # YOUR CODE HERE"  # a function with it returns None: "not done yet"; nothing is displayed
#: How long one cell may run, s, before :func:`execute` fails.
CELL_TIMEOUT = 300  # s
PUBLISH_OWNER = "publish-notebooks"  # the command named in an output folder's manifest
# What a published page shows of an output, best first (JupyterLab's order, less what a static page cannot run).
OUTPUT_KINDS = ("text/html", "text/markdown", "text/latex", "image/svg+xml", "image/png", "image/jpeg", "text/plain")
ANSI = re.compile(r"\x1b\[[0-9;]*[A-Za-z]")  # colours in a traceback


def notebooks_folder() -> Path:
    """Where the course's notebooks are: the installed package data, else the repository's ``notebooks/``.

    Returns
    -------
    pathlib.Path
        The folder of the percent-format sources.
    """
    try:
        folder = resources.files("course_dynamics_notebooks")
        if folder.is_dir():
            return Path(str(folder))
    except ModuleNotFoundError:
        pass
    return Path(__file__).resolve().parents[2] / "notebooks"  # course_dynamics/teaching/ -> the checkout


def notebook_paths(only=None) -> list[Path]:
    """The course's notebooks, in reading order (their numbers); ``only`` keeps those numbered e.g. ("01", "03").

    Parameters
    ----------
    only : iterable of str, optional
        The two-digit numbers of the notebooks to keep; all by default.

    Returns
    -------
    list of pathlib.Path
        The sources, ``NN_topic.py``.

    Raises
    ------
    InputError
        If no notebook is found, or a number of ``only`` is not one of the course's.
    """
    paths = sorted(p for p in notebooks_folder().glob("[0-9][0-9]_*.py"))
    if not paths:
        raise InputError(f"{notebooks_folder()}: no course notebooks found")
    if only is not None:
        unknown = sorted(set(only) - {p.name[:2] for p in paths})
        if unknown:
            raise InputError(f"no notebook numbered {', '.join(unknown)} "
                             f"(the course has {', '.join(p.name[:2] for p in paths)})")
        paths = [p for p in paths if p.name[:2] in only]
    return paths


def read_notebook(path):
    """A notebook (nbformat) from a percent-format source file.

    Parameters
    ----------
    path : str or pathlib.Path
        The source, ``NN_topic.py``.

    Returns
    -------
    nbformat.NotebookNode
        The notebook, without outputs.
    """
    import jupytext

    return jupytext.read(str(path), fmt="py:percent")


def solution_regions(source: str) -> list[tuple[int, int]]:
    """(first, last) line numbers of every ``### BEGIN SOLUTION`` … ``### END SOLUTION`` region, markers included.

    Parameters
    ----------
    source : str
        A cell's source.

    Returns
    -------
    list of tuple of (int, int)
        The regions' first and last lines, numbered from 0.

    Examples
    --------
    >>> solution_regions("x = 1\\n### BEGIN SOLUTION\\ny = 2\\n### END SOLUTION")
    [(1, 3)]
    """
    regions, start = [], None
    for number, line in enumerate(source.splitlines()):
        if line.strip() == BEGIN:
            start = number
        elif line.strip() == END and start is not None:
            regions.append((start, number))
            start = None
    return regions


def strip_solutions(source: str) -> str:
    """The cell's source with every solution region replaced by a placeholder at its indentation.

    Parameters
    ----------
    source : str
        A cell's source.

    Returns
    -------
    str
        The source, each region replaced by ``pass  # YOUR CODE HERE``.

    Examples
    --------
    >>> print(strip_solutions("def f():\\n    ### BEGIN SOLUTION\\n    return 1\\n    ### END SOLUTION"))
    def f():
        pass  # YOUR CODE HERE
    """
    lines = source.splitlines()
    for first, last in reversed(solution_regions(source)):
        indent = re.match(r"\s*", lines[first]).group(0)
        lines[first:last + 1] = [indent + PLACEHOLDER]
    return "\n".join(lines)


def _nbgrader(notebook, stem: str) -> None:
    """nbgrader metadata: cells with a solution are solution cells; the check cell after each is read-only, with
    no points (it runs in the student's kernel, where it can be made to pass: marks come from ``grade``)."""
    exercise = 0
    for cell in notebook.cells:
        if cell.cell_type != "code":
            continue
        if solution_regions(cell.source):
            exercise += 1
            cell.metadata["nbgrader"] = {"grade": False, "grade_id": f"{stem}-exercise-{exercise}", "locked": False,
                                         "schema_version": 3, "solution": True, "task": False}
        elif "check(" in cell.source and exercise:
            cell.metadata["nbgrader"] = {"grade": False, "grade_id": f"{stem}-check-{exercise}", "locked": True,
                                         "schema_version": 3, "solution": False, "task": False}


def _for_student(notebook, student: str | None) -> None:
    """A first code cell naming the student, so that every check runs on their own robot and numbers."""
    if student is None:
        return
    import nbformat

    cell = nbformat.v4.new_code_cell(
        "# Your exercises use your own robot and numbers, derived from your id: keep this line as it is.\n"
        f"from course_dynamics.teaching.exercises import use_student\nuse_student({check_student_id(student)!r})",
        metadata={"editable": False, "deletable": False, "tags": ["student-id"]})
    first_code = next((k for k, c in enumerate(notebook.cells) if c.cell_type == "code"), len(notebook.cells))
    notebook.cells.insert(first_code, cell)


def student_version(notebook, stem: str = "notebook", student: str | None = None):
    """A copy without solutions (placeholders instead) and without outputs, with nbgrader metadata; with
    ``student``, its checks run on that student's robot and numbers.

    Parameters
    ----------
    notebook : nbformat.NotebookNode
        The notebook with solutions (it is not changed).
    stem : str, optional
        The notebook's name, for nbgrader's cell ids.
    student : str, optional
        The student's id: a first code cell calls :func:`~course_dynamics.teaching.catalogue.use_student`.

    Returns
    -------
    nbformat.NotebookNode
        The student version.

    Raises
    ------
    InputError
        If ``student`` is not an id a course uses.
    """
    notebook = copy.deepcopy(notebook)
    notebook.cells = [cell for cell in notebook.cells if not solutions_only(cell)]
    _nbgrader(notebook, stem)
    for cell in notebook.cells:
        if cell.cell_type == "code":
            cell.source = strip_solutions(cell.source)
            cell.outputs, cell.execution_count = [], None
    _for_student(notebook, student)
    return notebook


def solutions_only(cell) -> bool:
    """Whether a cell shows an exercise's answer (the library's closed form of what the student derives), and so
    stays out of the student version: its first line is :data:`SOLUTIONS_ONLY`.

    Parameters
    ----------
    cell : nbformat.NotebookNode
        A cell of a notebook.

    Returns
    -------
    bool
        True for a cell only the version with solutions keeps.
    """
    first = (cell.source.strip().splitlines() or [""])[0].strip()
    return first in (SOLUTIONS_ONLY, "# " + SOLUTIONS_ONLY)


def solution_version(notebook, stem: str = "notebook", student: str | None = None):
    """A copy with the solutions, with nbgrader metadata (for ``student``'s robot, if given).

    Parameters
    ----------
    notebook : nbformat.NotebookNode
        The notebook (it is not changed).
    stem : str, optional
        The notebook's name, for nbgrader's cell ids.
    student : str, optional
        The student's id: a first code cell calls :func:`~course_dynamics.teaching.catalogue.use_student`.

    Returns
    -------
    nbformat.NotebookNode
        The version with solutions.

    Raises
    ------
    InputError
        If ``student`` is not an id a course uses.
    """
    notebook = copy.deepcopy(notebook)
    _nbgrader(notebook, stem)
    _for_student(notebook, student)
    return notebook


@dataclass(frozen=True)
class NotebooksWritten:
    """What :func:`write_notebooks` did.

    ``written``: the notebooks written; ``kept``: (path, why) for each left as it was — ``"exists"``
    for a file (a student's work, perhaps), or what else is there (``"is a symbolic link"``, …);
    ``backups``: the copies kept of the notebooks replaced with ``force``.

    Parameters
    ----------
    written : tuple of pathlib.Path
        The notebooks written.
    kept : tuple of tuple of (pathlib.Path, str)
        Each notebook left as it was, and why.
    backups : tuple of pathlib.Path
        The copies kept of the notebooks replaced.
    """

    written: tuple[Path, ...]
    kept: tuple[tuple[Path, str], ...]
    backups: tuple[Path, ...]


def write_notebooks(out: Path, solutions: bool = False, force: bool = False, student: str | None = None,
                    only=None) -> NotebooksWritten:
    """Every notebook of the course (or those numbered ``only``) as ``.ipynb`` in ``out`` (made if missing): student
    versions, or with solutions; with ``student``, for that student's own robot and numbers.

    A notebook that is already there is kept as it is — a student's answers live in it — so a second
    run adds only the notebooks that are missing. With ``force`` it is replaced, after a copy is kept
    beside it (``NN_topic.ipynb.bak-YYYYmmdd-HHMMSS``, :func:`course_dynamics.output.io.keep_backup`). What
    is not a regular file at a notebook's name (a symbolic link, a folder, a pipe) is left alone even
    with ``force``: nothing is written through it or put in its place. Every notebook is rendered
    before the first is written.

    Parameters
    ----------
    out : str or pathlib.Path
        The folder.
    solutions : bool, optional
        Write the versions with solutions.
    force : bool, optional
        Replace a notebook that is there (after keeping a copy).
    student : str, optional
        The student's id, for their own robot and numbers.
    only : iterable of str, optional
        The two-digit numbers of the notebooks to write; all by default.

    Returns
    -------
    NotebooksWritten
        What was written, kept and backed up.

    Raises
    ------
    InputError
        If ``out`` is not a folder, ``student`` or a number of ``only`` is not valid, or a notebook cannot be
        written.
    """
    import nbformat


    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: exists and is not a directory")
    documents = {}
    for path in notebook_paths(only):
        notebook = read_notebook(path)
        made = (solution_version if solutions else student_version)(notebook, path.stem, student)
        documents[out / f"{path.stem}.ipynb"] = nbformat.writes(made)
    out.mkdir(parents=True, exist_ok=True)
    written, kept, backups = [], [], []
    for target, text in documents.items():
        try:
            mode = os.lstat(target).st_mode
        except FileNotFoundError:
            if io.write_new(target, text):
                written.append(target)
            else:  # it appeared meanwhile
                kept.append((target, "exists"))
            continue
        if not stat.S_ISREG(mode):
            kept.append((target, "is a symbolic link" if stat.S_ISLNK(mode) else "is not a regular file"))
        elif not force:
            kept.append((target, "exists"))
        else:
            backups.append(io.keep_backup(target))
            io.write_text(target, text)
            written.append(target)
    return NotebooksWritten(written=tuple(written), kept=tuple(kept), backups=tuple(backups))


NOTEBOOK_STACK = ("nbclient", "nbconvert", "ipykernel")  # the `notebooks` extra: running and rendering notebooks


def check_notebook_stack() -> None:
    """An InputError saying what to install when the notebook execution stack is missing (the base install
    leaves it out: an engineer computing torques never runs a notebook).

    Raises
    ------
    InputError
        If nbclient, nbconvert or ipykernel cannot be imported.
    """
    import importlib

    missing = []
    for name in NOTEBOOK_STACK:
        try:
            importlib.import_module(name)
        except ImportError:
            missing.append(name)
    if missing:
        raise InputError(f"running the notebooks needs {', '.join(missing)}, which the base install leaves out: "
                         "pip install 'course-dynamics[notebooks]' (from a checkout: pip install -e '.[notebooks]')")


def execute(notebook, folder: Path, timeout: int = CELL_TIMEOUT):
    """Run every cell in a fresh kernel with ``folder`` as working directory; a failing cell raises.

    Parameters
    ----------
    notebook : nbformat.NotebookNode
        The notebook, run in place (its outputs filled in).
    folder : str or pathlib.Path
        The kernel's working directory.
    timeout : int, optional
        How long one cell may run, s.

    Returns
    -------
    nbformat.NotebookNode
        ``notebook``, run.

    Raises
    ------
    KeyboardInterrupt
        When the run was interrupted (SIGINT or SIGTERM), whatever nbclient made of it.
    nbclient.exceptions.CellExecutionError
        If a cell raises (nbclient's errors: a cell's timeout too).
    """
    import subprocess

    from nbclient import NotebookClient

    client = NotebookClient(notebook, timeout=timeout, kernel_name="python3",
                            resources={"metadata": {"path": str(folder)}})
    try:
        # The kernel gets its own session (Ctrl-C on the terminal is ours to handle) and no stderr (its
        # start-up notices and, when it is stopped, its tracebacks are not the user's business).
        client.execute(stderr=subprocess.DEVNULL, start_new_session=True)
    except BaseException:
        # nbclient answers SIGINT/SIGTERM itself (it shuts the kernel down and leaves this future behind),
        # then fails in its own ways: report that as the interruption it was.
        if getattr(client, "_async_cleanup_kernel_future", None) is not None:
            raise KeyboardInterrupt from None
        raise
    if getattr(client, "_async_cleanup_kernel_future", None) is not None:
        # nbclient sets this future only when it caught SIGINT/SIGTERM; a signal that lands while the kernel
        # starts is answered by a shutdown and then a normal return: still the user's Ctrl-C
        raise KeyboardInterrupt
    return notebook


def first_heading(notebook) -> str:
    """The text of the first Markdown heading of a notebook (its title), or ``""``.

    Parameters
    ----------
    notebook : nbformat.NotebookNode
        The notebook.

    Returns
    -------
    str
        The heading without its ``#`` marks.
    """
    for cell in notebook.cells:
        if cell.cell_type == "markdown":
            for line in cell.source.splitlines():
                if line.startswith("#"):
                    return line.lstrip("#").strip()
    return ""


def output_html(output):
    """One cell output as HTML: printed text and tracebacks escaped, figures inline, Markdown and LaTeX with MathML.

    HTML outputs are kept as they are: in the course they come from the library itself (the
    animation of :func:`~course_dynamics.output.viewer.live.show`, an ``srcdoc`` iframe that plays offline).

    Parameters
    ----------
    output : dict
        One output of a code cell (nbformat): a stream, an error, or display data.

    Returns
    -------
    markupsafe.Markup or None
        A ``<pre>`` for a stream or an error, a ``<div class="output">`` for data; None for data of no kind a
        page shows.
    """
    kind = output.get("output_type")
    if kind == "stream":
        return page.pre(output.get("text", ""), css="stderr" if output.get("name") == "stderr" else "stdout")
    if kind == "error":
        return page.pre(ANSI.sub("", "\n".join(output.get("traceback", []))), css="error")
    data = output.get("data", {})
    mime = next((m for m in OUTPUT_KINDS if m in data), None)
    if mime is None:
        return None
    value = data[mime] if isinstance(data[mime], str) else "".join(data[mime])
    if mime == "text/html":
        shown = Markup(value)  # the course's own output (see above)
    elif mime == "image/svg+xml":
        shown = page.svg(value)
    elif mime in ("image/png", "image/jpeg"):
        shown = page.image(base64.b64decode(value), mime)
    elif mime in ("text/markdown", "text/latex"):
        shown = page.markdown(value)
    else:
        shown = page.pre(value)
    return page.element("div", shown, class_="output")


def notebook_page(notebook, title: str = "") -> str:
    """A notebook (run or not) as one page: its Markdown with the formulas as MathML, its code and outputs.

    Parameters
    ----------
    notebook : nbformat.NotebookNode
        The notebook.
    title : str, optional
        The page's title; by default the notebook's first heading.

    Returns
    -------
    str
        The HTML page (:func:`~course_dynamics.output.page.page`).
    """
    body = []
    for cell in notebook.cells:
        if cell.cell_type == "markdown":
            body.append(page.markdown(cell.source))
        elif cell.cell_type == "code":
            body.append(page.pre(cell.source, css="input"))
            body += [output_html(output) for output in cell.get("outputs", [])]
    return page.page(title or first_heading(notebook) or "notebook", body)


def index_page(entries, solutions: bool = False) -> str:
    """The course's front page: a link to each ``(stem, title)`` in ``entries``, in order.

    Parameters
    ----------
    entries : iterable of tuple of (str, str)
        Each notebook's name (its page is ``stem.html``) and title (the name when empty).
    solutions : bool, optional
        The pages are the versions with solutions (the heading says which).

    Returns
    -------
    str
        The HTML page.
    """
    kind = "with solutions" if solutions else "student version"
    links = [page.link(f"{stem}.html", title or stem) for stem, title in entries]
    return page.page("Manipulator dynamics: the course",
                     [page.heading(f"Manipulator dynamics (Craig, chapter 6): the course ({kind})"),
                      page.bullet_list(links, ordered=True)])


def publish(out: Path, solutions: bool = False, only=None, progress=None) -> list[Path]:
    """Run every notebook and render it to a static HTML page in ``out``, with ``index.html`` listing them.

    Pages are built by :mod:`course_dynamics.output.page` (:func:`notebook_page`): the formulas are
    MathML, the figures and the animations are embedded, and a page loads nothing from the network:
    it opens, and the animations play, offline. ``out`` may hold other files: it is written by
    :func:`course_dynamics.output.folders.write_folder`, which replaces only pages an earlier run of
    this command wrote and nobody changed since, and refuses (before any notebook runs) when another
    file is in the way.

    Parameters
    ----------
    out : str or pathlib.Path
        The folder of the pages.
    solutions : bool, optional
        Publish the versions with solutions.
    only : iterable of str, optional
        The two-digit numbers of the notebooks to publish; all by default.
    progress : callable, optional
        Called with 1 after each notebook.

    Returns
    -------
    list of pathlib.Path
        The pages written, ``index.html`` last.

    Raises
    ------
    InputError
        If the notebook execution stack is missing, a number of ``only`` is not one of the course's, or a
        file in the way was not written by ``publish-notebooks`` (before any notebook runs).
    """
    import tempfile

    check_notebook_stack()
    out = Path(out)
    paths = notebook_paths(only)
    check_folder(out, [f"{path.stem}.html" for path in paths] + ["index.html"], PUBLISH_OWNER)  # before minutes of work
    pages, entries = {}, []
    with tempfile.TemporaryDirectory(prefix="course-dynamics-publish-") as folder:
        for path in paths:
            source = read_notebook(path)
            notebook = solution_version(source, path.stem) if solutions else student_version(source, path.stem)
            execute(notebook, Path(folder))
            pages[f"{path.stem}.html"] = notebook_page(notebook)
            entries.append((path.stem, first_heading(notebook)))
            if progress is not None:
                progress(1)
    pages["index.html"] = index_page(entries, solutions)
    return write_folder(out, pages, PUBLISH_OWNER)


__all__ = ["CELL_TIMEOUT", "SOLUTIONS_ONLY", "NotebooksWritten", "check_notebook_stack", "execute", "first_heading",
           "index_page", "notebook_page", "notebook_paths", "notebooks_folder", "output_html", "publish",
           "read_notebook", "solution_regions", "solution_version", "solutions_only", "strip_solutions",
           "student_version", "write_notebooks"]

"""The notebook course: reading its notebooks, making student versions, running them, publishing them.

The course's notebooks are stored as Python files in jupytext's *percent*
format (``notebooks/NN_topic.py``: ``# %%`` starts a code cell,
``# %% [markdown]`` a text cell): they are the source of truth, readable in
review, and every tool here turns them into ``.ipynb`` notebooks.

An exercise's solution sits between ``### BEGIN SOLUTION`` and
``### END SOLUTION`` in a code cell (nbgrader's convention), and the next cell
calls :func:`course_dynamics.teaching.exercises.check`. :func:`student_version`
replaces every solution region by ``...  # YOUR CODE HERE`` at the same
indentation, so the notebook still runs and the check reports "not done yet";
both versions carry nbgrader's cell metadata (solution cells, graded check
cells), so an instructor can also use nbgrader.
"""
from __future__ import annotations

import copy
import html
import os
import re
import stat
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from ..base.errors import InputError
from ..output import io
from ..output.folders import check_folder, write_folder

BEGIN, END = "### BEGIN SOLUTION", "### END SOLUTION"
PLACEHOLDER = "...  # YOUR CODE HERE"
CELL_TIMEOUT = 300  # s
PUBLISH_OWNER = "publish-notebooks"  # the command named in an output folder's manifest


def notebooks_folder() -> Path:
    """Where the course's notebooks are: the installed package data, else the repository's ``notebooks/``."""
    try:
        folder = resources.files("course_dynamics_notebooks")
        if folder.is_dir():
            return Path(str(folder))
    except ModuleNotFoundError:
        pass
    return Path(__file__).resolve().parents[2] / "notebooks"  # course_dynamics/teaching/ -> the checkout


def notebook_paths(only=None) -> list[Path]:
    """The course's notebooks, in reading order (their numbers); ``only`` keeps those numbered e.g. ("01", "03")."""
    paths = sorted(p for p in notebooks_folder().glob("[0-9][0-9]_*.py"))
    if not paths:
        raise InputError(f"{notebooks_folder()}: no course notebooks found")
    if only is not None:
        unknown = sorted(set(only) - {p.name[:2] for p in paths})
        if unknown:
            raise InputError(f"no notebook numbered {', '.join(unknown)} (the course has {', '.join(p.name[:2] for p in paths)})")
        paths = [p for p in paths if p.name[:2] in only]
    return paths


def read_notebook(path):
    """A notebook (nbformat) from a percent-format source file."""
    import jupytext

    return jupytext.read(str(path), fmt="py:percent")


def solution_regions(source: str) -> list[tuple[int, int]]:
    """(first, last) line numbers of every ``### BEGIN SOLUTION`` … ``### END SOLUTION`` region, markers included."""
    regions, start = [], None
    for number, line in enumerate(source.splitlines()):
        if line.strip() == BEGIN:
            start = number
        elif line.strip() == END and start is not None:
            regions.append((start, number))
            start = None
    return regions


def strip_solutions(source: str) -> str:
    """The cell's source with every solution region replaced by a placeholder at its indentation."""
    lines = source.splitlines()
    for first, last in reversed(solution_regions(source)):
        indent = re.match(r"\s*", lines[first]).group(0)
        lines[first:last + 1] = [indent + PLACEHOLDER]
    return "\n".join(lines)


def _nbgrader(notebook, stem: str) -> None:
    """nbgrader metadata: cells with a solution are solution cells, the check cell after each is graded."""
    exercise = 0
    for cell in notebook.cells:
        if cell.cell_type != "code":
            continue
        if solution_regions(cell.source):
            exercise += 1
            cell.metadata["nbgrader"] = {"grade": False, "grade_id": f"{stem}-exercise-{exercise}", "locked": False,
                                         "schema_version": 3, "solution": True, "task": False}
        elif "check(" in cell.source and exercise:
            cell.metadata["nbgrader"] = {"grade": True, "grade_id": f"{stem}-check-{exercise}", "locked": True,
                                         "points": 1, "schema_version": 3, "solution": False, "task": False}


def student_version(notebook, stem: str = "notebook"):
    """A copy without solutions (placeholders instead) and without outputs, with nbgrader metadata."""
    notebook = copy.deepcopy(notebook)
    _nbgrader(notebook, stem)
    for cell in notebook.cells:
        if cell.cell_type == "code":
            cell.source = strip_solutions(cell.source)
            cell.outputs, cell.execution_count = [], None
    return notebook


def solution_version(notebook, stem: str = "notebook"):
    """A copy with the solutions, with nbgrader metadata."""
    notebook = copy.deepcopy(notebook)
    _nbgrader(notebook, stem)
    return notebook


@dataclass(frozen=True)
class NotebooksWritten:
    """What :func:`write_notebooks` did.

    ``written``: the notebooks written; ``kept``: (path, why) for each left as it was — ``"exists"``
    for a file (a student's work, perhaps), or what else is there (``"is a symbolic link"``, …);
    ``backups``: the copies kept of the notebooks replaced with ``force``.
    """

    written: tuple[Path, ...]
    kept: tuple[tuple[Path, str], ...]
    backups: tuple[Path, ...]


def write_notebooks(out: Path, solutions: bool = False, force: bool = False) -> NotebooksWritten:
    """Every notebook of the course as ``.ipynb`` in ``out`` (made if missing): student versions, or with solutions.

    A notebook that is already there is kept as it is — a student's answers live in it — so a second
    run adds only the notebooks that are missing. With ``force`` it is replaced, after a copy is kept
    beside it (``NN_topic.ipynb.bak-YYYYmmdd-HHMMSS``, :func:`course_dynamics.output.io.keep_backup`). What
    is not a regular file at a notebook's name (a symbolic link, a folder, a pipe) is left alone even
    with ``force``: nothing is written through it or put in its place. Every notebook is rendered
    before the first is written.
    """
    import nbformat


    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: exists and is not a directory")
    documents = {}
    for path in notebook_paths():
        notebook = read_notebook(path)
        made = solution_version(notebook, path.stem) if solutions else student_version(notebook, path.stem)
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


def execute(notebook, folder: Path, timeout: int = CELL_TIMEOUT):
    """Run every cell in a fresh kernel with ``folder`` as working directory; a failing cell raises."""
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
    return notebook


def first_heading(notebook) -> str:
    for cell in notebook.cells:
        if cell.cell_type == "markdown":
            for line in cell.source.splitlines():
                if line.startswith("#"):
                    return line.lstrip("#").strip()
    return ""


def publish(out: Path, solutions: bool = False, only=None, progress=None) -> list[Path]:
    """Run every notebook and render it to a static HTML page in ``out``, with ``index.html`` listing them.

    Pages are nbconvert's HTML; the animations are embedded in the page and play offline. ``out``
    may hold other files: it is written by :func:`course_dynamics.output.folders.write_folder`, which replaces
    only pages an earlier run of this command wrote and nobody changed since, and refuses (before
    any notebook runs) when another file is in the way.
    """
    import tempfile

    from nbconvert import HTMLExporter


    out = Path(out)
    paths = notebook_paths(only)
    check_folder(out, [f"{path.stem}.html" for path in paths] + ["index.html"], PUBLISH_OWNER)  # before minutes of work
    exporter = HTMLExporter(template_name="lab")
    pages, entries = {}, []
    with tempfile.TemporaryDirectory(prefix="course-dynamics-publish-") as folder:
        for path in paths:
            source = read_notebook(path)
            notebook = solution_version(source, path.stem) if solutions else student_version(source, path.stem)
            execute(notebook, Path(folder))
            body, _ = exporter.from_notebook_node(notebook)
            pages[f"{path.stem}.html"] = body
            entries.append((path.stem, first_heading(notebook)))
            if progress is not None:
                progress(1)
    kind = "with solutions" if solutions else "student version"
    items = "".join(f'<li><a href="{html.escape(stem)}.html">{html.escape(title or stem)}</a></li>' for stem, title in entries)
    pages["index.html"] = (f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8"><title>Manipulator dynamics: '
                           f"the course</title></head><body><h1>Manipulator dynamics (Craig, chapter 6): the course "
                           f"({kind})</h1><ol>{items}</ol></body></html>\n")
    return write_folder(out, pages, PUBLISH_OWNER)

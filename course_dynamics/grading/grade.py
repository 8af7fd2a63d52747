"""Grading a class: read each submission without running it, run it in the sandbox, score and explain every term.

:func:`grade_class` is the whole job behind ``course-dynamics grade``; it
returns one :class:`SubmissionGrade` per file. Nothing here executes student
code: the grader only parses it (``ast``), and everything else happens in the
child process of :mod:`course_dynamics.grading.sandbox`. What comes back is
scored by :func:`~course_dynamics.grading.score.score_outcome`, the scorer the
notebooks' exercise checks use too.

Statuses (``SubmissionGrade.status``; anything but ``ok`` scores zero):

====================  =========================================================
status                meaning
====================  =========================================================
``ok``                graded term by term
``not python``        not a readable UTF-8 text file of at most 1 MB
``syntax error``      Python cannot parse it (the message gives the line)
``forbidden import``  it imports a module the assignment forbids
``no functions``      it defines none of tau, M, V, G, C
``exited``            it called exit() while being imported
``crashed``           an exception at import, or the process died
``file access``       it tried to write or read where it may not
``timeout``           it used more than the CPU or wall-clock time allowed
``memory``            it ran out of its memory allowance
``output limit``      it printed more than the assignment's output_limit
``invalid result``    what came back is not what the harness writes (a
                      submission that wrote on the results channel itself)
``not on roster``     the assignment names a roster, and the student's id
                      matches no one on it (:func:`~.uploads.roster_match`)
====================  =========================================================

With the assignment's ``interface = "robot"``, a submission runs twice: on the practice robot (what it prints is
its feedback's) and on the hidden robots of :mod:`~course_dynamics.grading.robots` (what it prints there is only
counted); each term scores the states of all of them, and its feedback shows the practice robot's alone.

Everything a submission's process sends back is read as hostile
(:mod:`~course_dynamics.grading.results`): one bad submission affects only its
own grade.
"""
from __future__ import annotations

import ast
import os
import re
import signal
import tempfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ..base.errors import InputError
from ..base.files import Refusals, read_small
from .assignment import TERMS, Assignment
from .diagnosis import Diagnosis
from .environment import submission_environment
from .harness import FLAGS
from .plan import Expected, Plan, expected_terms, make_plan
from .robots import combined, hidden_assignments, robot_record
from .sandbox import Limits, check_sandbox, run_submission
from .score import score_outcome
from .similarity import GENERATED, Comparison, fingerprints, generated_pairs, read_starter, similar_pairs
from .uploads import parse_python, read_notebook, roster_match

MAX_SOURCE_BYTES = 1_000_000
FEEDBACK_OUTPUT = 20_000  # characters of a submission's printed output kept in its feedback


@dataclass
class SubmissionGrade:
    """One student's grade: per-term diagnoses, or the status that gave zero.

    Parameters
    ----------
    student : str
        The student's name (the file's stem by default).
    path : pathlib.Path
        The submission file.
    status : str
        ``ok``, or why it scored zero (the module docstring's table).
    message : str
        What the status means for this file.
    diagnoses : list of Diagnosis
        Per graded term, its score and feedback (with status ``ok``).
    max_total : float
        The points the assignment is worth.
    stdout : str
        What the submission printed (standard output, then error), cut to the first 20000 characters.
    sandbox : str
        How it was isolated: ``bubblewrap``, ``unprivileged-user`` or ``none``.
    notes : list of str
        Notes of the run, shown in the feedback.
    flags : list of tuple of (str, str)
        Integrity flags (code, detail): leads for the instructor, never a score.
    ran : bool
        False when it was refused from its source alone (not run, so not watched for flags either).
    variant : str
        The roster's id whose robot it was graded on (the name as the roster spells it), ``""`` when it was not
        graded on any.
    """

    student: str
    path: Path
    status: str
    message: str = ""
    diagnoses: list[Diagnosis] = field(default_factory=list)
    max_total: float = 0.0
    stdout: str = ""
    sandbox: str = ""
    notes: list[str] = field(default_factory=list)
    flags: list[tuple[str, str]] = field(default_factory=list)  # integrity flags (code, detail): leads, not a score
    ran: bool = True  # False: refused from its source alone (not run, so not watched for flags either)
    variant: str = ""

    @property
    def flag_codes(self) -> list[str]:
        """The distinct flag codes, in the order of harness.FLAGS."""
        return [code for code in FLAGS if any(c == code for c, _ in self.flags)]

    @property
    def total(self) -> float:
        """The points given, 0 unless the status is ``ok``."""
        return round(sum(d.points for d in self.diagnoses), 2) if self.status == "ok" else 0.0

    def points(self, term: str) -> float:
        """The points given for ``term``.

        Parameters
        ----------
        term : str
            A term: ``tau``, ``M``, ``V``, ``G`` or ``C``.

        Returns
        -------
        float
            Its points; 0 when it is not graded or the status is not ``ok``.
        """
        if self.status != "ok":
            return 0.0
        return next((d.points for d in self.diagnoses if d.term == term), 0.0)


def _forbidden_in_source(tree: ast.AST, forbidden) -> tuple[str, int] | None:
    """The first forbidden module the source imports, statically: import statements and literal names given to
    ``__import__`` or ``importlib.import_module``."""
    forbidden = set(forbidden)
    for node in ast.walk(tree):
        names = []
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module]
        elif isinstance(node, ast.Call) and node.args and isinstance(node.args[0], ast.Constant) \
                and isinstance(node.args[0].value, str):
            function = node.func
            called = (function.id if isinstance(function, ast.Name)
                      else function.attr if isinstance(function, ast.Attribute) else "")
            if called in ("__import__", "import_module"):
                names = [node.args[0].value]
        for name in names:
            if name.split(".")[0] in forbidden:
                return name, node.lineno
    return None


# What a submission's feedback says of a file it cannot be (the file is named elsewhere in the feedback).
SOURCE_REFUSALS = Refusals(unreadable="cannot read the file: {reason}", not_a_file="not a regular file",
                           not_regular="not a regular file",
                           too_large="the file has {size_bytes} bytes; a submission may have at most {limit_bytes}",
                           grew="the file has more than {limit_bytes} bytes; a submission may have at most that")


def read_source(path: Path) -> tuple[str | None, str]:
    """(source, "") for a readable UTF-8 file of at most MAX_SOURCE_BYTES, read without blocking on a FIFO
    (:func:`~course_dynamics.base.files.read_small`), or a notebook's code cells (:func:`~.uploads.read_notebook`);
    (None, why not) otherwise.

    Parameters
    ----------
    path : pathlib.Path
        The submission file.

    Returns
    -------
    tuple of (str or None, str)
        The source and an empty reason, or None and why it cannot be read.
    """
    if path.suffix == ".ipynb":
        return read_notebook(path)[:2]
    try:
        data = read_small(path, MAX_SOURCE_BYTES, "submission", refusals=SOURCE_REFUSALS)
    except InputError as exc:
        return None, str(exc)
    try:
        return data.decode("utf-8"), ""
    except UnicodeDecodeError:
        return None, "the file is not UTF-8 text"


def inspect_source(path: Path, assignment: Assignment) -> tuple[str, str] | None:
    """(status, message) when the file cannot be graded at all, read without running it; None otherwise.

    Parameters
    ----------
    path : pathlib.Path
        The submission file.
    assignment : Assignment
        The assignment: its forbidden imports.

    Returns
    -------
    tuple of (str, str) or None
        The status (``not python``, ``syntax error`` or ``forbidden import``) and its message, or None.
    """
    return check_source(*read_source(path), path.name, assignment)


def check_source(source: str | None, problem: str, name: str, assignment: Assignment) -> tuple[str, str] | None:
    """:func:`inspect_source` on what :func:`read_source` read: (status, message), or None."""
    if source is None:
        return "not python", problem
    try:
        tree = parse_python(source, name)
    except SyntaxError as exc:
        return "syntax error", f"{exc.msg} (line {exc.lineno})"
    except (ValueError, RecursionError, MemoryError) as exc:
        return "syntax error", f"Python cannot parse the file ({type(exc).__name__})"
    found = _forbidden_in_source(tree, assignment.forbidden_imports)
    if found is not None:
        name, line = found
        return "forbidden import", f"imports '{name}' (line {line}), which this assignment does not allow"
    return None


def _ended(run, assignment: Assignment) -> tuple[str, str] | None:
    """(status, message) for a run that did not produce usable results, or that broke a limit."""
    if run.timed_out:
        return "timeout", f"still running after {Limits(assignment.time_limit).wall_seconds:g} s of wall-clock time"
    if run.output_bytes > assignment.output_limit:  # before the results: a print in a loop is the likely cause
        return "output limit", (f"printed {run.output_bytes} bytes; the limit is {assignment.output_limit}: remove the "
                                "print calls (or print less) and submit again")
    if run.invalid:
        return "invalid result", f"the results that came back cannot be used: {run.invalid}"
    if run.results is not None:
        status = run.results.get("status", "crashed")
        if status != "ok":
            return status, str(run.results.get("message", ""))
        if not run.results.get("defined"):
            return "no functions", f"defines none of {', '.join(TERMS)} (see the assignment for their signatures)"
        return None
    code = run.returncode
    signals = {code, -(code or 0), (code or 0) - 128}
    if signal.SIGXCPU in signals:
        return "timeout", f"used more than {assignment.time_limit:g} s of CPU time"
    if run.out_of_memory or (signal.SIGKILL in signals and "MemoryError" in run.stderr):
        return "memory", f"ran out of its {assignment.memory_limit} MiB of memory"
    if signal.SIGXFSZ in signals:
        return "file access", "wrote a file larger than allowed"
    tail = run.stderr.strip().splitlines()[-1] if run.stderr.strip() else f"exit status {code}"
    if "MemoryError" in tail:
        return "memory", f"ran out of its {assignment.memory_limit} MiB of memory"
    return "crashed", f"the process ended without results: {tail[:300]}"


def grade_submission(assignment: Assignment, plan: Plan, expected: Expected, path: Path, bwrap: str | None,
                     environment=None, user: tuple[int, int] | None = None, student: str | None = None,
                     read: tuple[str | None, str] | None = None, others: list | None = None) -> SubmissionGrade:
    """Grade one file (as ``student``, default its stem): inspect, run in the sandbox, score every term.

    Without ``bwrap``, a ``user`` (uid, gid) is the unprivileged user the submission runs as (sandbox.run_submission).
    ``read`` is what :func:`read_source` already read of the file, if the caller read it.

    Parameters
    ----------
    assignment : Assignment
        The assignment, as this submission is graded on it.
    plan : Plan
        The calls asked (:func:`~course_dynamics.grading.plan.make_plan`).
    expected : Expected
        Our answers (:func:`~course_dynamics.grading.plan.expected_terms`).
    path : pathlib.Path
        The submission file.
    bwrap : str or None
        The bubblewrap executable (:func:`~course_dynamics.grading.sandbox.check_sandbox`), None for no sandbox.
    environment : Environment or None
        The Python the submission runs in; numpy and the allowed packages of this installation when None.
    user : tuple of (int, int) or None
        Without ``bwrap``, the (uid, gid) the submission runs as.
    student : str or None
        The student's name; the file's stem when None.
    read : tuple of (str or None, str) or None
        What :func:`read_source` read of the file; read here when None.
    others : list of tuple or None
        With ``interface = "robot"``, (assignment, plan, expected) on each hidden robot
        (:func:`~course_dynamics.grading.robots.hidden_assignments`).

    Returns
    -------
    SubmissionGrade
        The grade: diagnoses per term, or the status that gave zero.
    """
    isolation = "bubblewrap" if bwrap else "unprivileged-user" if user is not None else "none"
    grade = SubmissionGrade(student=student or path.stem, path=path, status="ok", max_total=assignment.total_points,
                            sandbox=isolation, variant=student or path.stem)
    problem = check_source(*(read or read_source(path)), path.name, assignment)
    if problem is not None:
        grade.status, grade.message = problem
        grade.ran = False
        return grade
    limits = Limits(time_limit=assignment.time_limit, memory_limit=assignment.memory_limit,
                    output_limit=assignment.output_limit)
    harness_plan = {"module": str(path), "forbidden": list(assignment.forbidden_imports),
                    "available": ["numpy", *assignment.allowed_imports], "time_limit": assignment.time_limit,
                    "wall_seconds": limits.wall_seconds}
    on_robots = assignment.interface == "robot"
    graded = [(assignment, plan, expected)]
    run = run_submission(path, _calls(harness_plan, graded, on_robots), limits, bwrap, environment, user)
    grade.stdout = (run.stdout + run.stderr)[:FEEDBACK_OUTPUT]
    grade.notes += run.notes
    grade.flags = run.flags
    ended = _ended(run, assignment)
    if ended is not None:
        grade.status, grade.message = ended
        return grade
    grade.diagnoses = score_outcome(run.results, assignment, plan, expected)
    if on_robots and others:  # what it prints on the hidden robots is counted, never shown: their numbers stay ours
        hidden = run_submission(path, _calls(harness_plan, others, True), limits, bwrap, environment, user)
        grade.flags += [flag for flag in hidden.flags if flag not in grade.flags]
        ended = _ended(hidden, assignment)
        if ended is not None:
            grade.status = ended[0]
            grade.message = ("on the hidden robots of the assignment's shape, which your code is graded on too: "
                             + (ended[1] if ended[0] in OUR_MESSAGES else ended[0]))
            return grade
        per_robot = [score_outcome(outcome, *other) for outcome, other in zip(_split(hidden.results, others), others)]
        grade.diagnoses = [combined(d, [scored[i] for scored in per_robot], assignment.partial_credit)
                           for i, d in enumerate(grade.diagnoses)]
    return grade


OUR_MESSAGES = ("timeout", "memory", "output limit", "forbidden import")  # statuses whose message holds no answer


def _calls(harness_plan: dict, graded: list, on_robots: bool) -> dict:
    """The harness's plan for the plans of ``graded`` (assignment, plan, expected), one after the other; with
    ``on_robots``, each call's robot."""
    functions, robot_of = {}, {}
    for index, (_, plan, _) in enumerate(graded):
        for name, calls in plan.harness_functions().items():
            functions.setdefault(name, []).extend(calls)
            robot_of.setdefault(name, []).extend([index] * len(calls))
    if not on_robots:
        return dict(harness_plan, functions=functions)
    return dict(harness_plan, functions=functions, robot_of=robot_of,
                robots=[robot_record(assignment.robot) for assignment, _, _ in graded])


def _split(results: dict, graded: list) -> list[dict]:
    """The harness's outcome for the plans of ``graded`` one after the other, split into one outcome per plan."""
    taken: dict[str, int] = {}
    outcomes = []
    for _, plan, _ in graded:
        answered = {}
        for name in plan.harness_functions():
            records = results.get("results", {}).get(name, [])
            count, start = len(plan.calls_of(name)), taken.get(name, 0)
            answered[name], taken[name] = records[start:start + count], start + count
        outcomes.append(dict(results, results=answered))
    return outcomes


RESERVED_NAMES = ("summary", "gradebook")  # the class's own files in the output folder
RESERVED_PATTERN = re.compile(r"similar-[0-9]+")  # the similarity pages


MAX_NAME_BYTES = 200  # a student's name plus ".html" must fit a file name (255 bytes on Linux)


def _surrogates(text: str) -> bool:
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return True
    return False


def _unusable_name(name: str) -> str:
    """Why a file stem cannot be a student's name in the outputs, or ''."""
    if _surrogates(name):
        return "the file name is not UTF-8"
    if not name.isprintable():
        return "the file name holds a control character (a line break, a tab, a direction mark...)"
    if len(name.encode("utf-8")) > MAX_NAME_BYTES:
        return f"the file name is longer than {MAX_NAME_BYTES} bytes"
    return ""


def student_names(paths) -> list[str]:
    """The file stems, which name the students; InputError for a missing file or two files with one name (or names
    that differ only in case).

    Parameters
    ----------
    paths : iterable of str or os.PathLike
        The submission files.

    Returns
    -------
    list of str
        The students' names, in the order of the files.

    Raises
    ------
    InputError
        If a file is missing, two files have one name (or names that differ only in case), a name is not printable
        UTF-8 of at most 200 bytes, or it is one of the class's own files (``summary``, ``gradebook``,
        ``similar-N``).
    """
    names, folded = {}, {}
    for path in paths:
        path = Path(path)
        if not path.is_file():
            raise InputError(f"{path}: no such submission file")
        problem = _unusable_name(path.stem)
        if problem:
            raise InputError(f"{path}: {problem}, so it cannot name a student's files and rows; rename it")
        if path.stem.casefold() in folded:
            other = folded[path.stem.casefold()]
            raise InputError(f"{path} and {other}: two submissions named '{path.stem}'" if other.stem == path.stem else
                             f"{path} and {other}: names that differ only in case (a student is a file name, and "
                             "some file systems do not tell case apart)")
        if path.stem in RESERVED_NAMES or RESERVED_PATTERN.fullmatch(path.stem):
            raise InputError(f"{path}: a submission named '{path.stem}' would overwrite the class's {path.stem} file; "
                             "rename it")
        names[path.stem] = folded[path.stem.casefold()] = path
    return list(names)


def similar_submissions(paths, threshold: float, starter=None, assignment: Assignment | None = None) -> Comparison:
    """Near-identical pairs among the submission files (similarity.similar_pairs), read without running them;
    ``starter`` is the path of the starter code given to everyone, or None. With an ``assignment`` of the default
    interface, each file is also compared with the code the package generates for its student's robot
    (similarity.generated_pairs): those pairs come after the others.

    Parameters
    ----------
    paths : iterable of str or os.PathLike
        The submission files; an unreadable one is left out.
    threshold : float
        The similarity from which a pair is listed, 0 to 1.
    starter : str or os.PathLike or None
        The starter code, whose text does not count as shared.
    assignment : Assignment or None
        The assignment, whose robot (or each student's) the generated code is written for; None compares the
        submissions with each other only.

    Returns
    -------
    Comparison
        The pairs found, the threshold and the starter's file name.

    Raises
    ------
    InputError
        If the starter code cannot be read.
    """
    given = read_starter(starter) if starter is not None else None
    found = []
    for path in map(Path, paths):
        source, _ = read_source(path)
        if source is not None:
            found.append(fingerprints(path.stem, source, given))
    pairs = similar_pairs(found, threshold)
    if assignment is not None and assignment.interface == "functions":
        robots = {}
        for submission in found:
            student = roster_match(submission.student, assignment.roster)[0] if assignment.roster is not None \
                else submission.student
            if student is not None:
                robots[submission.student] = assignment.for_student(student).robot
        pairs += generated_pairs([s for s in found if s.student in robots], robots, threshold)
    return Comparison(tuple(pairs), threshold, Path(starter).name if starter else None)


def generated_flags(grades: list[SubmissionGrade], comparison: Comparison | None) -> None:
    """Add the ``generated-code`` flag to every grade whose submission is a pair with generated code (a flag, never a
    score).

    Parameters
    ----------
    grades : list of SubmissionGrade
        The class's grades, changed in place.
    comparison : Comparison or None
        The similarity's pairs (:func:`similar_submissions`), None when it was not asked for.
    """
    for pair in comparison.pairs if comparison is not None else ():
        if pair.second.student.startswith(GENERATED):
            for grade in grades:
                if grade.student == pair.first.student:
                    grade.flags.append(("generated-code", f"{pair.second.student.removeprefix(GENERATED).strip()}, "
                                                          f"{pair.score:.2f} of its code"))


def _planned(assignment: Assignment):
    plan = make_plan(assignment)
    return assignment, plan, expected_terms(assignment, plan)


def grade_class(assignment: Assignment, paths, sandbox: bool = True, jobs: int | None = None,
                progress=None, students=None, user: tuple[int, int] | None = None,
                environment=None) -> list[SubmissionGrade]:
    """Grade every submission (in parallel, ``jobs`` at a time); ``progress`` is called once per submission.

    With ``sandbox`` (the default) a machine where bubblewrap cannot start is a
    :class:`~course_dynamics.grading.sandbox.SandboxError`, never a silent downgrade. ``students`` name the
    submissions (default: their file stems); ``user`` and ``environment`` are as in :func:`grade_submission`
    (default environment: numpy and the assignment's allowed packages from this installation). Each file is
    graded on states of its own (:meth:`~course_dynamics.grading.assignment.Assignment.for_submission`), with
    ``interface = "robot"`` on hidden robots of its own too; a notebook from its code cells; with a ``roster``, as
    the roster's id its name matches (:func:`~course_dynamics.grading.uploads.roster_match`), and one that matches
    none is ``not on roster`` without running.

    Parameters
    ----------
    assignment : Assignment
        The assignment.
    paths : iterable of str or os.PathLike
        The submission files, one per student.
    sandbox : bool
        Run each submission in bubblewrap.
    jobs : int or None
        How many submissions run at a time; as many as there are CPUs (and files) when None.
    progress : callable or None
        Called with 1 once per submission graded.
    students : iterable of str or None
        The students' names, one per file; the file stems when None.
    user : tuple of (int, int) or None
        Without the sandbox, the (uid, gid) submissions run as.
    environment : Environment or None
        The Python submissions run in; numpy and the allowed packages of this installation when None.

    Returns
    -------
    list of SubmissionGrade
        One grade per file, in the order of ``paths``.

    Raises
    ------
    SandboxError
        If ``sandbox`` is set and bubblewrap cannot start on this machine.
    InputError
        If the files cannot name the students (:func:`student_names`), or with ``variant = "per-student"`` a name
        is not a valid student id.
    """
    paths = [Path(p) for p in paths]
    names = list(students) if students is not None else student_names(paths)
    bwrap = check_sandbox() if sandbox else None
    environment = environment or submission_environment(assignment.allowed_imports)
    on_roster = {name: roster_match(name, assignment.roster) if assignment.roster is not None else (name, "")
                 for name in names}
    for path, name in zip(paths, names):
        if on_roster[name][0] is not None:  # a per-student assignment refuses an unusable id before any runs
            assignment.for_student(on_roster[name][0], str(path))
    jobs = jobs or max(1, min(len(paths), os.cpu_count() or 1))

    def one(path_and_name):
        path, name = path_and_name
        student, unknown = on_roster[name]
        if student is None:  # never a silent random variant
            grade = SubmissionGrade(student=name, path=path, status="not on roster", message=unknown,
                                    max_total=assignment.total_points, ran=False)
        else:
            with tempfile.TemporaryDirectory(prefix="course-dynamics-upload-") as folder:
                grade = _one(path, name, student, Path(folder))
        if progress is not None:
            progress(1)
        return grade

    def _one(path: Path, name: str, student: str, folder: Path) -> SubmissionGrade:
        source, problem, notes = read_notebook(path) if path.suffix == ".ipynb" else (*read_source(path), [])
        run_path = path.resolve()
        if path.suffix == ".ipynb" and source is not None:  # its code cells, as the one file the sandbox runs
            run_path = folder / f"{path.stem}.py"
            run_path.write_text(source, encoding="utf-8")
        # unreadable: check_source gives its status, on the assignment's own states
        graded = assignment.for_submission(student, source.encode(), str(path)) if source is not None else assignment
        graded, plan, expected = _planned(graded)
        others = [_planned(a) for a in hidden_assignments(graded)] if graded.interface == "robot" else None
        # A student's 1e308 overflows in the comparison: inf, which the diagnosis reports (numpy's error
        # state is per thread, so the command line's does not reach the pool's threads).
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            grade = grade_submission(graded, plan, expected, run_path, bwrap, environment, user, name,
                                     (source, problem), others)
        grade.path, grade.variant = path, student
        grade.notes[:0] = notes
        return grade

    with ThreadPoolExecutor(max_workers=jobs) as pool:
        return list(pool.map(one, zip(paths, names)))


__all__ = ["SubmissionGrade", "generated_flags", "grade_class", "grade_submission", "inspect_source", "read_source",
           "similar_submissions", "student_names"]

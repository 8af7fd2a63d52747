"""What the grader writes: the gradebook, each student's feedback (Markdown, HTML, Gradescope JSON), a class summary.

=====================  ======================================================
file                   content
=====================  ======================================================
``gradebook.csv``      ``student,<term>…,total,status,sandbox,flags``: points
                       per graded term, their sum, the status (``ok`` or why
                       it got nothing), whether a sandbox was used, and the
                       integrity flags (codes of ``harness.FLAGS`` joined by
                       ``;``, empty when clean)
``<student>.md``       the feedback: per term the points, the findings and
                       the worst state; the submission's printed output
``<student>.html``     the same as a page
``<student>.json``     Gradescope's ``results.json``: ``score``, ``output``,
                       ``tests`` (``name``, ``score``, ``max_score``,
                       ``output``, ``visibility``); the integrity flags as a
                       hidden test of no points (instructors only)
``summary.html``       score histogram, per-term pass rates, the most common
                       mistakes and statuses, the integrity flags and (with
                       ``--similarity``) the near-identical pairs, for the
                       instructor
``similar-<k>.html``   the k-th near-identical pair side by side, the shared
                       lines marked (:mod:`~course_dynamics.grading.similarity`)
=====================  ======================================================

Flags never change a score, and a student's own feedback mentions them only
with the assignment's ``flags_in_feedback = true``.

Every text that came from a student (file names, exception messages, printed
output) is escaped for Markdown and HTML. Each feedback file stays under
:data:`MAX_FEEDBACK_BYTES`. All files are built in memory first and then
written one by one, each whole or not at all.
"""
from __future__ import annotations

import csv
import io as text_io
from collections import Counter
from pathlib import Path
from urllib.parse import quote

from markupsafe import Markup

from ..output import page, plotting, render
from ..output.folders import write_folder, written_by
from .assignment import Assignment
from .grade import SubmissionGrade
from .harness import FLAGS
from .robots import HIDDEN_ROBOTS
from .similarity import GENERATED, Comparison, Pair

#: The most bytes a feedback file (Markdown or HTML) has; a longer one is cut.
MAX_FEEDBACK_BYTES = 1_000_000
FEEDBACK_PRINTED = 10_000  # characters of a submission's printed output in Gradescope's results


def gradebook_csv(grades: list[SubmissionGrade], assignment: Assignment) -> str:
    """The gradebook: one row per student, the points per graded term, the total, status, sandbox and flags.

    Parameters
    ----------
    grades : list of SubmissionGrade
        The class's grades.
    assignment : Assignment
        The assignment: its graded terms.

    Returns
    -------
    str
        The CSV text; every text a student gave (a name, a status) is made safe for a spreadsheet.
    """
    out = text_io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["student", *assignment.terms, "total", "status", "sandbox", "flags"])
    for g in grades:
        writer.writerow([spreadsheet_text(g.student), *(f"{g.points(t):g}" for t in assignment.terms), f"{g.total:g}",
                         spreadsheet_text(g.status), g.sandbox, ";".join(g.flag_codes)])
    return out.getvalue()


FORMULA_STARTS = ("=", "+", "-", "@", "\t", "\r", "\n", "|", "%")


def spreadsheet_text(text: str) -> str:
    """A cell a spreadsheet shows as text, never runs as a formula (a leading quote, as OWASP's CSV advice).

    Parameters
    ----------
    text : str
        The cell's text.

    Returns
    -------
    str
        The text, with a leading ``'`` when it (or its first non-blank character) could start a formula.
    """
    return "'" + text if text[:1] in FORMULA_STARTS or text.lstrip()[:1] in FORMULA_STARTS else text


def flag_lines(grade: SubmissionGrade) -> list[str]:
    """One line per flag code: what it means and the first few things the submission tried."""
    lines = []
    for code in grade.flag_codes:
        details = [d for c, d in grade.flags if c == code and d]
        shown = "; ".join(details[:3]) + (f"; and {len(details) - 3} more" if len(details) > 3 else "")
        lines.append(f"[{code}] {FLAGS[code]}" + (f": {shown}" if shown else ""))
    return lines


def results_json(grade: SubmissionGrade, assignment: Assignment) -> dict:
    """Gradescope's autograder ``results.json`` for one student (its documented schema: score, output, tests).

    Parameters
    ----------
    grade : SubmissionGrade
        The student's grade.
    assignment : Assignment
        The assignment.

    Returns
    -------
    dict
        The document: ``score``, ``output``, ``visibility`` and ``tests`` (one per graded term, and the integrity
        flags as a hidden test of no points).
    """
    tests = []
    for term in assignment.terms:
        d = next((d for d in grade.diagnoses if d.term == term), None)
        output = d.text() if d is not None and grade.status == "ok" else f"not graded ({grade.status}: see above)"
        tests.append({"name": term, "score": grade.points(term), "max_score": assignment.points[term],
                      "output": output[:20_000], "visibility": "visible"})
    tests.append({"name": "integrity flags (instructors only)", "score": 0.0, "max_score": 0.0,
                  "output": "\n".join(flag_lines(grade)) or "none", "visibility": "hidden"})
    summary = "\n".join(_header(grade, assignment))
    if grade.stdout:
        summary += "\n\nWhat your file printed:\n" + grade.stdout[:FEEDBACK_PRINTED]
    return {"score": grade.total, "output": summary[:20_000], "visibility": "visible", "tests": tests}


def _header(grade: SubmissionGrade, assignment: Assignment) -> list[str]:
    ran = "ran, and each term is graded below" if grade.status == "ok" else f"status {grade.status}"
    lines = [f"total {grade.total:g} / {assignment.total_points:g} points; {ran}"
             + (f": {grade.message}" if grade.message else "")]
    if grade.variant:  # graded on a robot: which one (a file on no roster was graded on none)
        own = f", your own variant for {grade.variant}" if assignment.variant == "per-student" else ""
        hidden = (f", and {HIDDEN_ROBOTS} hidden robots of its shape with as many states each (interface = "
                  "\"robot\": your functions take the robot)" if assignment.interface == "robot" else "")
        lines.append(f"robot {assignment.robot.name}{own} (joints {', '.join(assignment.robot.joint_names)}), "
                     f"{assignment.samples} random states of this file's own{hidden}, relative tolerance "
                     f"{assignment.tolerance:g}")
    if grade.sandbox == "none":
        lines.append("graded without a sandbox")
    lines += grade.notes
    if assignment.flags_in_feedback:
        lines += [f"integrity flag {line}" for line in flag_lines(grade)]
    return lines


def feedback_markdown(grade: SubmissionGrade, assignment: Assignment) -> str:
    """A student's feedback as Markdown: the total, per term the points, the findings and the worst state, and what
    the file printed.

    Parameters
    ----------
    grade : SubmissionGrade
        The student's grade.
    assignment : Assignment
        The assignment.

    Returns
    -------
    str
        The Markdown, every text from the student escaped, at most :data:`MAX_FEEDBACK_BYTES`.
    """
    e = render.markdown_escape
    parts = [f"# Feedback for {e(grade.student)}", ""]
    parts += [f"{e(line)}  " for line in _header(grade, assignment)] + [""]
    for d in grade.diagnoses:
        first, *rest = d.text().splitlines()
        parts += [f"## {e(first)}", ""] + [f"- {e(line[2:])}" for line in rest] + [""]
    if grade.stdout:
        parts += ["## What your file printed", "", render.code_block(grade.stdout), ""]
    return _bounded("\n".join(parts))


def feedback_html(grade: SubmissionGrade, assignment: Assignment) -> str:
    """A student's feedback as an HTML page, the same as :func:`feedback_markdown`.

    Parameters
    ----------
    grade : SubmissionGrade
        The student's grade.
    assignment : Assignment
        The assignment.

    Returns
    -------
    str
        The page, every text from the student escaped, at most :data:`MAX_FEEDBACK_BYTES`.
    """
    body = ([page.heading(f"Feedback for {grade.student}")]
            + [page.paragraph(line) for line in _header(grade, assignment)])
    for d in grade.diagnoses:
        first, *rest = d.text().splitlines()
        body.append(page.heading(first, 2, css="ok" if d.correct else "bad"))
        if rest:
            body.append(page.bullet_list(line[2:] for line in rest))
    if grade.stdout:
        body += [page.heading("What your file printed", 2), page.pre(grade.stdout)]
    return _bounded(page.page(f"Feedback for {grade.student}", body))


def _bounded(text: str) -> str:
    if len(text.encode()) <= MAX_FEEDBACK_BYTES:
        return text
    return text.encode()[: MAX_FEEDBACK_BYTES - 100].decode("utf-8", "ignore") + "\n\n(feedback cut at 1 MB)\n"


def _histogram_svg(totals: list[float], maximum: float) -> str:
    import matplotlib.ticker

    figure, axis = plotting.pyplot().subplots(figsize=(6.4, 3.2), constrained_layout=True)
    axis.hist(totals, bins=min(20, max(5, len(totals))), range=(0, maximum or 1), color="#4a6fa5", edgecolor="white")
    axis.set_xlabel("total points")
    axis.set_ylabel("students")
    axis.yaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))  # students come whole
    return plotting.figure_bytes(figure, "svg").decode("utf-8")


def similar_name(index: int) -> str:
    """The file name of the page of a similar pair.

    Parameters
    ----------
    index : int
        The pair's index in the comparison, from 0.

    Returns
    -------
    str
        ``similar-<index + 1>.html``.
    """
    return f"similar-{index + 1}.html"


def _marked_source(pair: Pair, which) -> Markup:
    """The source of one side with the lines the pair shares in ``<mark>``, each line numbered."""
    shared, lines = pair.lines(which), which.source.splitlines()
    width = len(str(len(lines)))
    parts = []
    for number, line in enumerate(lines, start=1):
        text = f"{number:>{width}}  {line}\n"
        parts.append(page.element("mark", text, inline=True) if number in shared else text)
    return page.element("pre", *parts, inline=True)


def _compared(comparison: Comparison) -> str:
    starter = f"the starter code ({comparison.starter}) removed" if comparison.starter else "no starter code given"
    return f"compared on the syntax tree, names, comments and formatting set aside, {starter}"


def similar_html(pair: Pair, assignment: Assignment, comparison: Comparison) -> str:
    """One pair side by side: a lead for the instructor to read, not a verdict.

    Parameters
    ----------
    pair : Pair
        The pair.
    assignment : Assignment
        The assignment.
    comparison : Comparison
        The class's comparison (its starter code).

    Returns
    -------
    str
        The page: both sources, their lines numbered, the shared lines marked.
    """
    generated = pair.second.student.startswith(GENERATED)
    title = (f"{pair.first.student} and the code course-dynamics generates for their robot "
             f"({pair.second.student.removeprefix(GENERATED).strip()}): {pair.score:.0%} of the submission shared"
             if generated else
             f"{pair.first.student} and {pair.second.student}: {pair.score:.0%} of the smaller submission shared")
    lead = ("The package writes this code for the student's robot (course-dynamics derive, a compiled model): "
            "pasted in, it answers for the student; a lead, not a verdict; read both." if generated else
            "Two students who worked from the same lecture can be alike: a lead, not a verdict; read both.")
    body = [page.heading(title),
            page.paragraph(f"{assignment.source.name}; {_compared(comparison)}; marked lines hold shared runs. {lead}"),
            page.table([(_marked_source(pair, pair.first), _marked_source(pair, pair.second))],
                       header=(pair.first.student, pair.second.student), css="side-by-side")]
    return page.page(title, body)


def _similar_section(comparison: Comparison | None) -> list:
    if comparison is None:
        return []
    rows = [(page.link(f"{quote(p.first.student)}.html", p.first.student),
             p.second.student if p.second.student.startswith(GENERATED) else
             page.link(f"{quote(p.second.student)}.html", p.second.student), f"{p.score:.0%}",
             page.link(similar_name(k), "side by side")) for k, p in enumerate(comparison.pairs)]
    return [page.heading("Similar submissions", 2),
            page.paragraph(f"Pairs whose code is near-identical, {_compared(comparison)}: listed from a score of "
                           f"{comparison.threshold:g}, the share of the smaller submission the other holds too; "
                           "a submission beside \"generated: …\" holds that share of the code course-dynamics "
                           "writes for its robot (flag generated-code). Leads to read, not verdicts."),
            page.table(rows, header=("student", "student", "shared", "compare")) if rows
            else page.paragraph(f"None at a score of {comparison.threshold:g} or more.")]


def _flags_section(grades: list[SubmissionGrade]) -> list:
    unwatched = [g.student for g in grades if not g.ran]
    rows = [(page.link(f"{quote(g.student)}.html", g.student), "; ".join(flag_lines(g))) for g in grades if g.flags]
    parts = [page.heading("Integrity flags", 2),
             page.paragraph("What a submission tried that a dynamics answer never needs, recorded by an audit hook in "
                            "its process. Leads for a conversation, not proof, and no change to any score: the sandbox "
                            "is what contains a submission. Students do not see their flags unless the assignment sets "
                            "flags_in_feedback = true (on Gradescope they are a hidden test). Codes: "
                            + "; ".join(f"{c}: {w}" for c, w in FLAGS.items()) + "."),
             page.table(rows, header=("student", "flags")) if rows
             else page.paragraph("None: no submission that ran tried any of these.")]
    if unwatched:
        parts.append(page.paragraph(f"Not run, so not watched: {', '.join(unwatched)} (refused from the source alone; "
                                    "see their statuses)."))
    return parts


def summary_html(grades: list[SubmissionGrade], assignment: Assignment, comparison=None) -> str:
    """The class summary for the instructor: score histogram, per-term pass rates, the most common mistakes and
    statuses, the integrity flags, the similar pairs (with a comparison), and every student.

    Parameters
    ----------
    grades : list of SubmissionGrade
        The class's grades.
    assignment : Assignment
        The assignment.
    comparison : Comparison or None
        The similar pairs, None when they were not asked for.

    Returns
    -------
    str
        The page.
    """
    totals = [g.total for g in grades]
    rows = []
    for term in assignment.terms:
        correct = sum(1 for g in grades for d in g.diagnoses if d.term == term and d.correct)
        mean = sum(g.points(term) for g in grades) / max(len(grades), 1)
        rows.append((term, f"{correct} of {len(grades)}", f"{mean:.3g} / {assignment.points[term]:g}"))
    # Each student counts once per mistake, whichever terms show it (one slip in τ shows in M, V, G too). Every
    # mistake is listed (their codes are a short catalogue), most common first and ties by name, never in a set's order.
    mistakes = Counter(tag for g in grades for tag in {tag for d in g.diagnoses for tag in d.tags})
    statuses = Counter(g.status for g in grades)
    body = [
        page.heading(f"{assignment.source.name}: class summary"),
        page.paragraph(f"{len(grades)} submissions; robot {assignment.robot.name}; mean "
                       f"{sum(totals) / max(len(totals), 1):.3g} of {assignment.total_points:g} points."),
        page.figure(page.svg(_histogram_svg(totals, assignment.total_points)), "Score distribution"),
        page.heading("Per term", 2), page.table(rows, header=("term", "fully correct", "mean points")),
        page.heading("Most common mistakes", 2),
        page.table(sorted(mistakes.items(), key=lambda item: (-item[1], item[0])), header=("mistake", "students"))
        if mistakes
        else page.paragraph("None: every graded term was right."),
        page.heading("Statuses", 2),
        page.table(sorted(statuses.items(), key=lambda item: (-item[1], item[0])), header=("status", "students")),
        *_flags_section(grades),
        *_similar_section(comparison),
        page.heading("Students", 2),
        page.table([(page.link(f"{quote(g.student)}.html", g.student), f"{g.total:g}", g.status) for g in grades],
                   header=("student", "total", "status")),
    ]
    return page.page(f"{assignment.source.name}: class summary", body)


#: The command named in the output folder's manifest as the writer of the files.
OWNER = "grade"  # the command named in the output folder's manifest


def output_names(students, comparison: Comparison | None = None) -> list[str]:
    """The files :func:`write_outputs` writes for these students (what ``grade`` checks before grading).

    Parameters
    ----------
    students : iterable of str
        The students' names.
    comparison : Comparison or None
        The similar pairs, whose pages are written too.

    Returns
    -------
    list of str
        The file names, relative to the output folder.
    """
    pairs = comparison.pairs if comparison is not None else ()
    return (["gradebook.csv", "summary.html"]
            + [f"{s}{suffix}" for s in students for suffix in (".md", ".html", ".json")]
            + [similar_name(k) for k in range(len(pairs))])


def other_students(out: Path, students) -> list[str]:
    """Students whose feedback an earlier ``grade`` wrote in ``out`` and who are not among ``students``.

    Parameters
    ----------
    out : pathlib.Path
        The output folder.
    students : iterable of str
        The students graded now.

    Returns
    -------
    list of str
        Their names, sorted.
    """
    now = set(students)
    return sorted({name[:-3] for name in written_by(out, OWNER) if name.endswith(".md")} - now)


def write_outputs(out: Path, grades: list[SubmissionGrade], assignment: Assignment,
                  comparison: Comparison | None = None) -> list[Path]:
    """Every output file in ``out`` (made if missing), through the folder's manifest
    (:func:`~course_dynamics.output.folders.write_folder`): only files an earlier ``grade`` wrote there are
    replaced, and nothing else in the folder is touched.
    ``comparison`` (similarity's, or None when not asked for) adds the summary's table and one page per pair.

    Parameters
    ----------
    out : pathlib.Path
        The output folder, made if missing.
    grades : list of SubmissionGrade
        The class's grades.
    assignment : Assignment
        The assignment.
    comparison : Comparison or None
        The similar pairs.

    Returns
    -------
    list of pathlib.Path
        The files written.

    Raises
    ------
    InputError
        If a file is in the way that an earlier ``grade`` did not write there, or a file cannot be written
        (raised before anything is written).
    """
    documents = {"gradebook.csv": gradebook_csv(grades, assignment),
                 "summary.html": summary_html(grades, assignment, comparison)}
    for k, pair in enumerate(comparison.pairs if comparison is not None else ()):
        documents[similar_name(k)] = similar_html(pair, assignment, comparison)
    for g in grades:
        documents[f"{g.student}.md"] = feedback_markdown(g, assignment)
        documents[f"{g.student}.html"] = feedback_html(g, assignment)
        documents[f"{g.student}.json"] = render.json_text(results_json(g, assignment)) + "\n"
    return write_folder(out, documents, OWNER)


__all__ = ["MAX_FEEDBACK_BYTES", "OWNER", "feedback_html", "feedback_markdown", "gradebook_csv", "other_students",
           "output_names", "results_json", "similar_html", "similar_name", "spreadsheet_text", "summary_html",
           "write_outputs"]

"""What the grader writes: the gradebook, each student's feedback (Markdown, HTML, Gradescope JSON), a class summary.

=====================  ======================================================
file                   content
=====================  ======================================================
``gradebook.csv``      ``student,<term>…,total,status,sandbox``: points per
                       graded term, their sum, the status (``ok`` or why it
                       got nothing) and whether a sandbox was used
``<student>.md``       the feedback: per term the points, the findings and
                       the worst state; the submission's printed output
``<student>.html``     the same as a page
``<student>.json``     Gradescope's ``results.json``: ``score``, ``tests``
                       (``name``, ``score``, ``max_score``, ``output``)
``summary.html``       score histogram, per-term pass rates, the most common
                       mistakes and statuses, for the instructor
=====================  ======================================================

Every text that came from a student (file names, exception messages, printed
output) is escaped for Markdown and HTML. Each feedback file stays under
:data:`MAX_FEEDBACK_BYTES`. All files are built in memory first and then
written one by one, each whole or not at all.
"""
from __future__ import annotations

import csv
import html
import io as text_io
from collections import Counter
from pathlib import Path
from urllib.parse import quote

from ..output import render
from ..output.folders import write_folder
from .assignment import Assignment
from .grade import SubmissionGrade

MAX_FEEDBACK_BYTES = 1_000_000
STYLE = ("body{font-family:system-ui,sans-serif;max-width:60rem;margin:2rem auto;padding:0 1rem;line-height:1.45}"
         "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:.25rem .6rem;text-align:left}"
         "pre{background:#f4f4f4;padding:.6rem;overflow:auto;white-space:pre-wrap}.ok{color:#1a7f37}.bad{color:#b3261e}")


def gradebook_csv(grades: list[SubmissionGrade], assignment: Assignment) -> str:
    out = text_io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["student", *assignment.terms, "total", "status", "sandbox"])
    for g in grades:
        writer.writerow([spreadsheet_text(g.student), *(f"{g.points(t):g}" for t in assignment.terms), f"{g.total:g}",
                         spreadsheet_text(g.status), g.sandbox])
    return out.getvalue()


FORMULA_STARTS = ("=", "+", "-", "@", "\t", "\r", "\n", "|", "%")


def spreadsheet_text(text: str) -> str:
    """A cell a spreadsheet shows as text, never runs as a formula (a leading quote, as OWASP's CSV advice)."""
    return "'" + text if text[:1] in FORMULA_STARTS or text.lstrip()[:1] in FORMULA_STARTS else text


def results_json(grade: SubmissionGrade, assignment: Assignment) -> dict:
    """Gradescope's autograder ``results.json`` for one student."""
    tests = []
    for term in assignment.terms:
        d = next((d for d in grade.diagnoses if d.term == term), None)
        output = d.text() if d is not None and grade.status == "ok" else f"{grade.status}: {grade.message}"
        tests.append({"name": term, "score": grade.points(term), "max_score": assignment.points[term],
                      "output": output[:20_000]})
    summary = f"status: {grade.status}" + (f" ({grade.message})" if grade.message else "")
    return {"score": grade.total, "output": summary, "tests": tests}


def _header(grade: SubmissionGrade, assignment: Assignment) -> list[str]:
    lines = [f"total {grade.total:g} / {assignment.total_points:g} points; status {grade.status}"
             + (f": {grade.message}" if grade.message else "")]
    lines.append(f"robot {assignment.robot.name} (joints {', '.join(assignment.robot.joint_names)}), "
                 f"{assignment.samples} states (seed {assignment.seed}), relative tolerance {assignment.tolerance:g}")
    if grade.sandbox == "none":
        lines.append("graded without a sandbox")
    lines += grade.notes
    return lines


def feedback_markdown(grade: SubmissionGrade, assignment: Assignment) -> str:
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
    e = html.escape
    body = [f"<h1>Feedback for {e(grade.student)}</h1>"] + [f"<p>{e(line)}</p>" for line in _header(grade, assignment)]
    for d in grade.diagnoses:
        first, *rest = d.text().splitlines()
        css = "ok" if d.correct else "bad"
        body.append(f'<h2 class="{css}">{e(first)}</h2>')
        if rest:
            body.append("<ul>" + "".join(f"<li>{e(line[2:])}</li>" for line in rest) + "</ul>")
    if grade.stdout:
        body += ["<h2>What your file printed</h2>", f"<pre>{e(grade.stdout)}</pre>"]
    return _bounded(_page(f"Feedback for {grade.student}", "\n".join(body)))


def _page(title: str, body: str) -> str:
    return (f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8"><title>{html.escape(title)}</title>'
            f"<style>{STYLE}</style></head>\n<body>\n{body}\n</body></html>\n")


def _bounded(text: str) -> str:
    if len(text.encode()) <= MAX_FEEDBACK_BYTES:
        return text
    return text.encode()[: MAX_FEEDBACK_BYTES - 100].decode("utf-8", "ignore") + "\n\n(feedback cut at 1 MB)\n"


def _histogram_svg(totals: list[float], maximum: float) -> str:
    import matplotlib

    matplotlib.use("Agg")
    matplotlib.rcParams["text.parse_math"] = False  # students' names are text, not TeX
    import matplotlib.pyplot as plt

    figure, axis = plt.subplots(figsize=(6.4, 3.2), constrained_layout=True)
    axis.hist(totals, bins=min(20, max(5, len(totals))), range=(0, maximum or 1), color="#4a6fa5", edgecolor="white")
    axis.set_xlabel("total points")
    axis.set_ylabel("students")
    axis.set_title("Score distribution")
    buffer = text_io.StringIO()
    figure.savefig(buffer, format="svg")
    plt.close(figure)
    svg = buffer.getvalue()
    return svg[svg.index("<svg"):]


def summary_html(grades: list[SubmissionGrade], assignment: Assignment) -> str:
    e = html.escape
    totals = [g.total for g in grades]
    rows = []
    for term in assignment.terms:
        correct = sum(1 for g in grades for d in g.diagnoses if d.term == term and d.correct)
        mean = sum(g.points(term) for g in grades) / max(len(grades), 1)
        rows.append(f"<tr><td>{e(term)}</td><td>{correct} of {len(grades)}</td>"
                    f"<td>{mean:.3g} / {assignment.points[term]:g}</td></tr>")
    mistakes = Counter(f"{d.term}: {tag}" for g in grades for d in g.diagnoses for tag in d.tags)
    statuses = Counter(g.status for g in grades)
    body = [
        f"<h1>{e(assignment.source.name)}: class summary</h1>",
        f"<p>{len(grades)} submissions; robot {e(assignment.robot.name)}; mean {sum(totals) / max(len(totals), 1):.3g} "
        f"of {assignment.total_points:g} points.</p>",
        _histogram_svg(totals, assignment.total_points),
        "<h2>Per term</h2><table><tr><th>term</th><th>fully correct</th><th>mean points</th></tr>" + "".join(rows)
        + "</table>",
        "<h2>Most common mistakes</h2>",
        "<table><tr><th>mistake</th><th>students</th></tr>"
        + "".join(f"<tr><td>{e(k)}</td><td>{v}</td></tr>" for k, v in mistakes.most_common(15)) + "</table>"
        if mistakes else "<p>None: every graded term was right.</p>",
        "<h2>Statuses</h2><table><tr><th>status</th><th>students</th></tr>"
        + "".join(f"<tr><td>{e(k)}</td><td>{v}</td></tr>" for k, v in statuses.most_common()) + "</table>",
        "<h2>Students</h2><table><tr><th>student</th><th>total</th><th>status</th></tr>"
        + "".join(f'<tr><td><a href="{e(quote(g.student))}.html">{e(g.student)}</a></td><td>{g.total:g}</td>'
                  f"<td>{e(g.status)}</td></tr>" for g in grades) + "</table>",
    ]
    return _page(f"{assignment.source.name}: class summary", "\n".join(body))


OWNER = "grade"  # the command named in the output folder's manifest


def output_names(students) -> list[str]:
    """The files :func:`write_outputs` writes for these students (what ``grade`` checks before grading)."""
    return ["gradebook.csv", "summary.html"] + [f"{s}{suffix}" for s in students for suffix in (".md", ".html", ".json")]


def write_outputs(out: Path, grades: list[SubmissionGrade], assignment: Assignment) -> list[Path]:
    """Every output file in ``out`` (made if missing), through the folder's manifest (:func:`write_folder`):
    only files an earlier ``grade`` wrote there are replaced, and nothing else in the folder is touched."""
    import json

    documents = {"gradebook.csv": gradebook_csv(grades, assignment), "summary.html": summary_html(grades, assignment)}
    for g in grades:
        documents[f"{g.student}.md"] = feedback_markdown(g, assignment)
        documents[f"{g.student}.html"] = feedback_html(g, assignment)
        documents[f"{g.student}.json"] = json.dumps(results_json(g, assignment), indent=2, allow_nan=False) + "\n"
    return write_folder(out, documents, OWNER)

"""``course-dynamics student-notebooks``: the course's notebooks as .ipynb, without solutions (or with them)."""
from __future__ import annotations

import sys

from ..options import UsageError, add, add_all, notebook_numbers, print_json, progress_bar
from . import COMMANDS

HELP = COMMANDS["student_notebooks"]
DESCRIPTION = ("Write the ten notebooks of the course (one per section of Craig's chapter 6, and identification) to "
               "OUTDIR as .ipynb. Student versions have every solution replaced by a placeholder and no outputs; "
               "they run top to bottom, and each exercise's check says 'not done yet' until it is answered. Both "
               "versions carry nbgrader metadata. A notebook already in OUTDIR is kept as it is (it may hold a "
               "student's work), so running again adds only what is missing; --force replaces it, keeping a copy "
               "beside it. With --student ID the exercises use that student's own robot and numbers (derived from "
               "the id); with --roster FILE (a CSV with an 'id' column) each student gets a subfolder OUTDIR/ID. The "
               "grader uses the same robots (an assignment with variant = \"per-student\"). --json: out, "
               "solutions, and student, written, kept (path, why), backups; with --roster, students: id -> written, "
               "kept, backups.")


def add_arguments(parser) -> None:
    parser.add_argument("out", metavar="OUTDIR", help="folder for the notebooks (made if missing)")
    add(parser, "--solutions")
    who = parser.add_mutually_exclusive_group()
    add_all(who, "--student", "--roster")
    add_all(parser, "--only", "--force", "--json", "--quiet")


def run(args) -> int:
    from pathlib import Path

    from ...teaching.course import write_notebooks
    from ...tools.variants import check_student_id, read_roster

    only = notebook_numbers(args)

    if args.roster:
        students = read_roster(args.roster)  # every id checked before anything is written
        for student in students:  # and every folder: a roster is written whole or not at all
            folder = Path(args.out) / student
            if folder.exists() and not folder.is_dir() or folder.is_symlink():
                raise UsageError(f"{folder}: exists and is not a folder; nothing was written")
        results = {}
        bar = progress_bar(args, total=len(students), unit="student")
        try:
            for student in students:
                results[student] = write_notebooks(Path(args.out) / student, args.solutions, args.force, student, only)
                bar.update(1)
        finally:
            bar.close()
        for student, result in results.items():
            _report(result, args, Path(args.out) / student, f" for {student}")
        if args.json:
            print_json(dict(out=str(args.out), solutions=args.solutions,
                            students={s: _record(r) for s, r in results.items()}))
        print(f"wrote the notebooks of {len(students)} students to {args.out}/<id>/", file=sys.stderr)
        return 0
    student = check_student_id(args.student) if args.student else None
    result = write_notebooks(args.out, args.solutions, args.force, student, only)
    _report(result, args, args.out, f" for {student}" if student else "")
    if args.json:
        print_json(dict(out=str(args.out), solutions=args.solutions, student=student, **_record(result)))
    return 0


def _record(result) -> dict:
    return dict(written=[str(p) for p in result.written], kept=[dict(path=str(p), why=why) for p, why in result.kept],
                backups=[str(p) for p in result.backups])


def _report(result, args, out, whose: str) -> None:
    for path, why in result.kept:
        if why == "exists":
            print(f"note: {path} exists, kept (student-notebooks --force replaces it, keeping a backup)",
                  file=sys.stderr)
        else:
            print(f"note: {path} {why}, left alone (nothing is written through it, even with --force)", file=sys.stderr)
    for backup in result.backups:
        print(f"note: kept the notebook it replaces as {backup}", file=sys.stderr)
    kind = "with solutions" if args.solutions else "student versions"
    kept = f", kept {len(result.kept)} already there" if result.kept else ""
    print(f"wrote {len(result.written)} notebooks ({kind}{whose}) to {out}{kept}; open them with: jupyter lab {out}",
          file=sys.stderr)

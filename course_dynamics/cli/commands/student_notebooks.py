"""``course-dynamics student-notebooks``: the course's notebooks as .ipynb, without solutions (or with them)."""
from __future__ import annotations

import sys

from ..options import UsageError

HELP = "write the notebook course as .ipynb for students (solutions removed) or instructors (--solutions)"
DESCRIPTION = ("Write the ten notebooks of the course (one per section of Craig's chapter 6, and identification) to OUTDIR as .ipynb. "
               "Student versions have every solution replaced by a placeholder and no outputs; they run top to "
               "bottom, and each exercise's check says 'not done yet' until it is answered. Both versions carry "
               "nbgrader metadata. A notebook already in OUTDIR is kept as it is (it may hold a student's work), so "
               "running again adds only what is missing; --force replaces it, keeping a copy beside it. "
               "With --student ID the exercises use that student's own robot and numbers (derived from the id); "
               "with --roster FILE (a CSV with an 'id' column) each student gets a subfolder OUTDIR/ID. The grader "
               "uses the same robots (an assignment with variant = \"per-student\").")


def add_arguments(parser) -> None:
    parser.add_argument("out", metavar="OUTDIR", help="folder for the notebooks (made if missing)")
    parser.add_argument("--solutions", action="store_true", help="keep the solutions (the instructor's copy)")
    who = parser.add_mutually_exclusive_group()
    who.add_argument("--student", metavar="ID", help="a student's id (a login or an e-mail's local part): the "
                     "exercises use their own robot and numbers")
    who.add_argument("--roster", metavar="FILE", help="a CSV file with an 'id' column: one subfolder per student")
    parser.add_argument("--only", metavar="NN", action="append", help="only the notebook numbered NN (repeatable)")
    parser.add_argument("--force", action="store_true",
                        help="replace notebooks already in OUTDIR, keeping each as NN_topic.ipynb.bak-YYYYmmdd-HHMMSS")


def run(args) -> int:
    from pathlib import Path

    from ...teaching.course import write_notebooks
    from ...tools.variants import check_student_id, read_roster

    if args.roster:
        students = read_roster(args.roster)  # every id checked before anything is written
        for student in students:  # and every folder: a roster is written whole or not at all
            folder = Path(args.out) / student
            if folder.exists() and not folder.is_dir() or folder.is_symlink():
                raise UsageError(f"{folder}: exists and is not a folder; nothing was written")
        for student in students:
            _report(write_notebooks(Path(args.out) / student, args.solutions, args.force, student, args.only),
                    args, Path(args.out) / student, f" for {student}")
        print(f"wrote the notebooks of {len(students)} students to {args.out}/<id>/", file=sys.stderr)
        return 0
    student = check_student_id(args.student) if args.student else None
    _report(write_notebooks(args.out, args.solutions, args.force, student, args.only), args, args.out,
            f" for {student}" if student else "")
    return 0


def _report(result, args, out, whose: str) -> None:
    for path, why in result.kept:
        if why == "exists":
            print(f"note: {path} exists, kept (student-notebooks --force replaces it, keeping a backup)", file=sys.stderr)
        else:
            print(f"note: {path} {why}, left alone (nothing is written through it, even with --force)", file=sys.stderr)
    for backup in result.backups:
        print(f"note: kept the notebook it replaces as {backup}", file=sys.stderr)
    kind = "with solutions" if args.solutions else "student versions"
    kept = f", kept {len(result.kept)} already there" if result.kept else ""
    print(f"wrote {len(result.written)} notebooks ({kind}{whose}) to {out}{kept}; open them with: jupyter lab {out}",
          file=sys.stderr)

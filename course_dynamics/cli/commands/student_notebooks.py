"""``course-dynamics student-notebooks``: the course's notebooks as .ipynb, without solutions (or with them)."""
from __future__ import annotations

import sys

HELP = "write the notebook course as .ipynb for students (solutions removed) or instructors (--solutions)"
DESCRIPTION = ("Write the ten notebooks of the course (one per section of Craig's chapter 6, and identification) to OUTDIR as .ipynb. "
               "Student versions have every solution replaced by a placeholder and no outputs; they run top to "
               "bottom, and each exercise's check says 'not done yet' until it is answered. Both versions carry "
               "nbgrader metadata. A notebook already in OUTDIR is kept as it is (it may hold a student's work), so "
               "running again adds only what is missing; --force replaces it, keeping a copy beside it.")


def add_arguments(parser) -> None:
    parser.add_argument("out", metavar="OUTDIR", help="folder for the notebooks (made if missing)")
    parser.add_argument("--solutions", action="store_true", help="keep the solutions (the instructor's copy)")
    parser.add_argument("--force", action="store_true",
                        help="replace notebooks already in OUTDIR, keeping each as NN_topic.ipynb.bak-YYYYmmdd-HHMMSS")


def run(args) -> int:
    from ...teaching.course import write_notebooks

    result = write_notebooks(args.out, solutions=args.solutions, force=args.force)
    for path, why in result.kept:
        if why == "exists":
            print(f"note: {path} exists, kept (student-notebooks --force replaces it, keeping a backup)", file=sys.stderr)
        else:
            print(f"note: {path} {why}, left alone (nothing is written through it, even with --force)", file=sys.stderr)
    for backup in result.backups:
        print(f"note: kept the notebook it replaces as {backup}", file=sys.stderr)
    kind = "with solutions" if args.solutions else "student versions"
    kept = f", kept {len(result.kept)} already there" if result.kept else ""
    print(f"wrote {len(result.written)} notebooks ({kind}) to {args.out}{kept}; open them with: jupyter lab {args.out}",
          file=sys.stderr)
    return 0

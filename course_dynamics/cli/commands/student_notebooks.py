"""``course-dynamics student-notebooks``: the course's notebooks as .ipynb, without solutions (or with them)."""
from __future__ import annotations

import sys

HELP = "write the notebook course as .ipynb for students (solutions removed) or instructors (--solutions)"
DESCRIPTION = ("Write the nine notebooks of the course (one per section of Craig's chapter 6) to OUTDIR as .ipynb. "
               "Student versions have every solution replaced by a placeholder and no outputs; they run top to "
               "bottom, and each exercise's check says 'not done yet' until it is answered. Both versions carry "
               "nbgrader metadata.")


def add_arguments(parser) -> None:
    parser.add_argument("out", metavar="OUTDIR", help="folder for the notebooks (made if missing)")
    parser.add_argument("--solutions", action="store_true", help="keep the solutions (the instructor's copy)")


def run(args) -> int:
    from ...course import write_notebooks

    written = write_notebooks(args.out, solutions=args.solutions)
    kind = "with solutions" if args.solutions else "student versions"
    print(f"wrote {len(written)} notebooks ({kind}) to {args.out}; open them with: jupyter lab {args.out}",
          file=sys.stderr)
    return 0

"""``course-dynamics report``: a comparison report (HTML, Markdown, JSON) of our dynamics against Pinocchio."""
from __future__ import annotations

import sys
from pathlib import Path

from course_dynamics_reference import TOLERANCE

from ..options import (
    UsageError,
    add,
    add_all,
    add_robot_argument,
    add_sampling_arguments,
    check_sampling,
    gravity,
    load_robot_argument,
    print_json,
    progress_bar,
)
from . import COMMANDS

HELP = COMMANDS["report"]
DESCRIPTION = ("For each ROBOT: the largest and median error of tau, M, C, V, G against Pinocchio on seeded random "
               "states, their distribution, tau along a smooth trajectory by both libraries, the textbook's closed "
               "forms for the course robots, the errata count and the environment. Writes DIR/index.html (one "
               "self-contained page), DIR/report.md with DIR/figures/, and DIR/report.json. DIR may hold other "
               "files: only the files an earlier report wrote there and nobody changed since are replaced (listed in "
               "DIR/.course-dynamics-files.json); any other file in the way is an error before any work. --json prints "
               "out, robots, agree and the files written. Exit 1 when a term disagrees.")


def add_arguments(parser) -> None:
    add_robot_argument(parser, nargs="+", help="URDF files or shipped robot names")
    add(parser, "--out", required=True)
    add_sampling_arguments(parser, TOLERANCE)
    add_all(parser, "--json", "--quiet")


def run(args) -> int:
    from ...output import io
    from ...output.folders import check_folder

    check_sampling(args)
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise UsageError(f"{out}: exists and is not a directory")
    io.check_writable(out / "index.html") if out.is_dir() else io.check_writable(out)
    from course_dynamics_reference.validate import check_comparison_memory

    for target in args.urdf:  # bad input fails before any long work: the robot's joints and the states asked
        check_comparison_memory(load_robot_argument(args, target), args.samples)
    # The oracle is imported by this command only, so the library itself never loads Pinocchio.
    from course_dynamics_reference.report import (
        OWNER,
        build_report,
        report_files,
        write_report,
    )

    check_folder(out, report_files(len(args.urdf)), OWNER)  # a file in the way fails before minutes of work

    progress = progress_bar(args, total=len(args.urdf) * args.samples, unit="state", delay=0.0)
    report = build_report(args.urdf, samples=args.samples, seed=args.seed, tolerance=args.tolerance,
                          progress=progress.update, gravity=gravity(args),
                          allow_nonphysical_inertia=args.allow_nonphysical_inertia)
    progress.close()
    write_report(out, report)
    agree = all(t["agrees"] for r in report.robots for t in r.terms.values())
    if args.json:
        print_json(dict(out=str(out), robots=[r.name for r in report.robots], agree=agree,
                        files=[str(out / name) for name in ("index.html", "report.md", "report.json")]))
        return 0 if agree else 1
    print(f"wrote {out / 'index.html'}, {out / 'report.md'} and {out / 'report.json'} for {len(report.robots)} robots; "
          + ("every term agrees" if agree else "DISAGREEMENT: see the rows marked NO"))
    return 0 if agree else 1

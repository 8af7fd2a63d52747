"""``course-dynamics grade``: grade students' dynamics code in a sandbox and write feedback that teaches."""
from __future__ import annotations

import sys
import warnings
from pathlib import Path

from ...base.errors import CourseDynamicsWarning
from ..options import UsageError, add_all, print_json, progress_bar
from . import COMMANDS

HELP = COMMANDS["grade"]
DESCRIPTION = ("Run each SUBMISSION.py in its own sandboxed process (bubblewrap: no network, read-only system, "
               "CPU/memory/process/output limits), call its tau, M, V, G or C on the assignment's seeded states, "
               "score every term against course_dynamics and explain each mistake. Writes gradebook.csv, "
               "<student>.md/.html/.json (Gradescope results.json) and summary.html to --out. An existing --out folder "
               "keeps a manifest (.course-dynamics-files.json): only files an earlier grade wrote there are "
               "replaced; any other file in the way is an error before anything runs. --json prints a summary (per "
               "student: total, status, flags, terms).")


def add_arguments(parser) -> None:
    parser.add_argument("assignment", nargs="?", help="assignment TOML file (see --example-assignment)")
    parser.add_argument("submissions", nargs="*", help="student files, one Python file per student")
    add_all(parser, "--out", "--example-assignment", "--gradescope", "--handout", "--similarity",
            "--similarity-threshold", "--starter", "--no-sandbox", "--jobs", "--json", "--quiet")


def run(args) -> int:
    from ...grading import (
        EXAMPLE,
        check_sandbox,
        grade_class,
        load_assignment,
        write_outputs,
    )
    from ...grading.feedback import OWNER, other_students, output_names, similar_name
    from ...grading.similarity import THRESHOLD
    from ...grading.grade import generated_flags, similar_submissions, student_names
    from ...output import io
    from ...output.folders import check_folder

    if args.example_assignment:
        sys.stdout.write(EXAMPLE)
        return 0
    if args.handout is not None:
        return _handout(args, load_assignment)
    if args.gradescope is not None:
        return _gradescope(args, load_assignment)
    if args.assignment is None or not args.submissions or args.out is None:
        raise UsageError("grade needs ASSIGNMENT.toml, at least one SUBMISSION.py and --out DIR "
                         "(or --example-assignment)")
    if args.jobs is not None and args.jobs < 1:
        raise UsageError("--jobs must be at least 1")
    threshold = args.similarity_threshold if args.similarity_threshold is not None else THRESHOLD
    if not 0 < threshold <= 1:
        raise UsageError("--similarity-threshold takes a score from 0 (exclusive) to 1")
    compare = args.similarity or args.starter is not None or args.similarity_threshold is not None
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise UsageError(f"{out}: exists and is not a directory")
    io.check_writable(out / "gradebook.csv") if out.is_dir() else io.check_writable(out)
    assignment = load_assignment(args.assignment)
    comparison = similar_submissions(args.submissions, threshold, args.starter, assignment) if compare else None
    check_folder(out, output_names(student_names(args.submissions), comparison), OWNER)  # before any student code runs
    if not args.no_sandbox:
        check_sandbox()  # before any output: no sandbox is an error, not a quiet downgrade
    progress = progress_bar(args, total=len(args.submissions), unit="submission", delay=0.0)
    grades = grade_class(assignment, args.submissions, sandbox=not args.no_sandbox, jobs=args.jobs,
                         progress=progress.update)
    progress.close()
    generated_flags(grades, comparison)
    earlier = other_students(out, student_names(args.submissions))
    write_outputs(out, grades, assignment, comparison)
    if args.json:
        similar = None if comparison is None else [
            dict(students=[p.first.student, p.second.student], score=round(p.score, 3), page=similar_name(k))
            for k, p in enumerate(comparison.pairs)]
        print_json(dict(assignment=str(args.assignment), out=str(out), max_total=assignment.total_points,
                        similar=similar,
                        students=[dict(student=g.student, total=g.total, status=g.status, flags=g.flag_codes,
                                       terms={t: g.points(t) for t in assignment.terms}) for g in grades]))
    else:
        mean = sum(g.total for g in grades) / len(grades)
        print(f"graded {len(grades)} submission{'s' if len(grades) != 1 else ''} against {assignment.robot.name}: "
              f"mean {mean:.3g} of {assignment.total_points:g} points; "
              f"wrote {out / 'gradebook.csv'}, feedback and {out / 'summary.html'}")
        flagged = sum(1 for g in grades if g.flags)
        if flagged:
            print(f"{flagged} submission{'s' if flagged != 1 else ''} with integrity flags (leads, not proof): see the "
                  "gradebook's flags column and the summary")
        if comparison is not None and comparison.pairs:
            count = len(comparison.pairs)
            print(f"{count} near-identical pair{'s' if count != 1 else ''} of submissions: see the summary")
        if args.no_sandbox:
            warnings.warn("graded without a sandbox (--no-sandbox)", CourseDynamicsWarning)
    if earlier:
        shown = ", ".join(earlier[:5]) + (f" and {len(earlier) - 5} more" if len(earlier) > 5 else "")
        print(f"note: {out} still holds the feedback an earlier grade wrote for {len(earlier)} student"
              f"{'s' if len(earlier) != 1 else ''} not graded now ({shown}); the gradebook and the summary list this "
              "run's submissions only", file=sys.stderr)
    return 0


def _gradescope(args, load_assignment) -> int:
    """The autograder bundle: everything Gradescope needs to grade this assignment on its own workers."""
    from ...grading.autograder import write_bundle

    if args.assignment is None or args.submissions or args.out is not None:
        raise UsageError("grade --gradescope ZIP takes the assignment only: "
                         "grade ASSIGNMENT.toml --gradescope autograder.zip")
    target = write_bundle(load_assignment(args.assignment), args.gradescope)
    if args.json:
        print_json(dict(assignment=str(args.assignment), bundle=str(target)))
    else:
        print(f"wrote {target}: upload it in Gradescope as the assignment's autograder (Configure Autograder, "
              "Ubuntu 24.04 base image); students submit one Python file")
    return 0


def _handout(args, load_assignment) -> int:
    """A student's own robot, as the per-student assignment grades them: its numbers, and its URDF in --out."""
    from ...output import io
    from ...output.urdf_writer import model_urdf
    from ...tools.variants import check_student_id, robot_variant

    if args.assignment is None or args.submissions:
        raise UsageError("grade --handout ID takes the assignment and no submissions: "
                         "grade ASSIGNMENT.toml --handout ID")
    from ...grading.robots import INTERFACE

    student = check_student_id(args.handout)
    assignment = load_assignment(args.assignment)
    interface = INTERFACE if assignment.interface == "robot" else None
    if assignment.variant != "per-student" and interface is not None:  # the interface is the handout
        if args.out is not None:
            raise UsageError(f"{args.assignment}: every student has the same robot ({assignment.robot_argument}); "
                             "--out writes a student's own URDF and needs variant = \"per-student\"")
        print_json(dict(student=student, robot=assignment.robot_argument, interface=interface)) if args.json \
            else print(interface)
        return 0
    if assignment.variant != "per-student":
        raise UsageError(f"{args.assignment}: every student has the same robot ({assignment.robot_argument}); "
                         "--handout needs variant = \"per-student\"")
    variant = robot_variant(assignment.robot_argument, student)
    urdf = None
    if args.out is not None:
        out = Path(args.out)
        if out.exists() and not out.is_dir():
            raise UsageError(f"{out}: exists and is not a directory")
        out.mkdir(parents=True, exist_ok=True)
        urdf = out / f"{assignment.robot_argument}_{student}.urdf"
        text = model_urdf(assignment.for_student(student).robot, f"{assignment.robot_argument} for student {student}: "
                          "the robot course-dynamics grade grades this student on")
        if not io.write_new(urdf, text):
            raise UsageError(f"{urdf}: exists; kept as it is (remove it to write it again)")
    if args.json:
        print_json(dict(student=student, robot=assignment.robot_argument, parameters=variant.parameters,
                        urdf=str(urdf) if urdf else None, interface=interface))
    else:
        if interface is not None:
            print(interface)
        print(variant.describe())
        print("parameters: " + ", ".join(f"{k} = {v:g}" for k, v in variant.parameters.items()))
        if urdf:
            print(f"wrote {urdf}", file=sys.stderr)
    return 0

"""``course-dynamics crosscheck``: one URDF through course_dynamics, Pinocchio, MuJoCo and PyBullet."""
from __future__ import annotations

import sys

from course_dynamics_reference import TOLERANCE

from ..options import (
    UsageError,
    add,
    add_all,
    add_robot_argument,
    check_output_names,
    check_sampling,
    drives_argument,
    gravity,
    load_robot_argument,
    print_json,
)
from . import COMMANDS

HELP = COMMANDS["crosscheck"]
DESCRIPTION = ("Evaluate tau, M, G, the bias forces C(q, qd) qd + G and the forward dynamics with course_dynamics and "
               "with each engine through its own API (Pinocchio; MuJoCo and PyBullet from the engines extra) at "
               "seeded random states. Every difference is within the tolerance (relative; qdd compared as the torque "
               "M qdd it stands for) or explained by a named convention shown with its size (fixed joints merged, "
               "joint order, continuous joints as cos/sin, gravity, MuJoCo's damping, friction loss, armature and "
               "constraints, PyBullet's massless links and approximated principal axes, an inertia refused, an "
               "engine limit, a subnormal number); an engine that cannot be imported is skipped with a note. --json "
               "prints the report (robot, ok, conventions, engines); --out writes it as an offline HTML page. Exit 0 "
               "when every difference is explained, 1 when one is not (the report names the first link where the "
               "engines part) or no engine was compared, 2 on bad input. --drives FILE sets the file's rotor inertias "
               "on Pinocchio's armature and MuJoCo's dof_armature and compares them with course_dynamics's own drives "
               "(tau + I_a qdd, M + diag(I_a), forward dynamics through both); PyBullet, which has no rotor inertia, "
               "is compared without them, and the offsets, which no engine has, are not compared (a note says "
               "each).")


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    add(parser, "--samples", default=3)
    add(parser, "--seed")
    add(parser, "--tolerance", default=TOLERANCE)
    add_all(parser, "--drives", "--json", "--out")


def run(args) -> int:
    from ...output import io

    check_sampling(args)
    check_output_names(args)
    if args.out == "-" and args.json:
        raise UsageError("--out - and --json would both print to standard output; give --out a file")
    model = load_robot_argument(args)  # bad input fails before an engine is loaded
    joint_drives = drives_argument(args, model)
    if args.out is not None:
        io.check_writable(args.out)
    # The engines are imported by this command only, through the oracle package.
    from course_dynamics_reference.crosscheck import crosscheck
    from course_dynamics_reference.crosscheck_report import crosscheck_document, crosscheck_html, crosscheck_text

    check = crosscheck(args.urdf, samples=args.samples, seed=args.seed, tolerance=args.tolerance,
                       gravity=gravity(args), allow_nonphysical_inertia=args.allow_nonphysical_inertia,
                       drives=joint_drives)
    if args.out is not None:
        io.write_text(args.out, crosscheck_html(check))
    if args.json:
        print_json(crosscheck_document(check) | ({} if args.out is None else {"out": str(args.out)}))
    elif args.out != "-":  # the page itself is the output on standard output
        sys.stdout.write(crosscheck_text(check))
        if args.out is not None:
            print(f"wrote {args.out}")
    return 0 if check.ok else 1

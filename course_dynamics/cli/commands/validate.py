"""``course-dynamics validate``: every term against Pinocchio on seeded random states."""
from __future__ import annotations

import sys

from course_dynamics_reference import TERMS, TOLERANCE

from ..options import (
    add_all,
    add_robot_argument,
    add_sampling_arguments,
    check_sampling,
    gravity,
    load_robot_argument,
    print_json,
    progress_bar,
    warn_if_gravity_free,
)
from . import COMMANDS

HELP = COMMANDS["validate"]
DESCRIPTION = ("Evaluate tau, M, C, V, G with course_dynamics and with Pinocchio on seeded random states within joint "
               "limits. --json prints the report (ok, tolerance, robots, massless: the robots with no mass where a "
               "joint moves, each also a warning line). Exit 0 when every term agrees to the "
               "tolerance (relative), 1 when one does not, 2 on bad input.")


def add_arguments(parser) -> None:
    add_robot_argument(parser, nargs="*", help="URDF files or robot names (default: every shipped robot)")
    add_sampling_arguments(parser, TOLERANCE)
    add_all(parser, "--json", "--quiet")


def run(args) -> int:
    check_sampling(args)
    # The oracle is imported by this command only, so the library itself never loads Pinocchio.
    from course_dynamics_reference.validate import (
        bundled_targets,
        check_comparison_memory,
        display_name,
        validate,
    )

    from ...tools.lint import warn_if_massless

    targets = args.urdf or bundled_targets()
    massless = []  # robots whose agreement is partly on zeros: no mass where a joint moves
    for target in targets:  # fail on bad input before any long work
        model = load_robot_argument(args, target)
        check_comparison_memory(model, args.samples)  # the robot's joints and the states asked
        warn_if_gravity_free(model)
        massless += [target] if warn_if_massless(model) else []
    progress = progress_bar(args, total=len(targets) * args.samples, unit="state", delay=0.0)
    reports = [validate(target, samples=args.samples, seed=args.seed, tolerance=args.tolerance,
                        progress=progress.update, gravity=gravity(args),
                        allow_nonphysical_inertia=args.allow_nonphysical_inertia)
               for target in targets]
    progress.close()
    ok = all(r.ok for r in reports)
    if args.json:
        print_json(dict(ok=ok, tolerance=args.tolerance, robots=[r.as_dict() for r in reports],
                        massless=[display_name(t) for t in massless]))
        return 0 if ok else 1
    print(f"course_dynamics vs Pinocchio: max relative error over {args.samples} random states (seed {args.seed}), "
          f"tolerance {args.tolerance:g}")
    width = max(30, *(len(display_name(target)) for target in targets))  # a long file name keeps the columns
    print(f"{'robot':<{width}} {'n':>2} " + " ".join(f"{t:>9}" for t in TERMS) + "  agree")
    for target, r in zip(targets, reports):
        errors = " ".join(f"{r.terms[t].max_rel:>9.1e}" for t in TERMS)
        print(f"{display_name(target):<{width}} {len(r.joints):>2} {errors}  {'yes' if r.ok else 'NO'}")
    if ok and massless:
        print(f"all robots agree, but {', '.join(map(display_name, massless))}: no mass where a joint moves, so "
              "they agree on zeros there (see the warnings; course-dynamics lint names each link)")
    else:
        print("all robots agree" if ok else "DISAGREEMENT: see the rows marked NO")
    return 0 if ok else 1

"""``course-dynamics excite``: an excitation trajectory for identification, written as CSV."""
from __future__ import annotations

import sys
import time

from ...output import io
from ...output.render import one_line
from ..options import UsageError, add_robot_argument, load_robot_argument, print_json, progress_bar

HELP = "an excitation trajectory for identification (periodic Fourier motion, well-conditioned regressor)"
DESCRIPTION = (
    "Make a trajectory that identification can learn the inertial parameters from: each joint follows a finite "
    "Fourier series q_j(t) = q0_j + sum_k a_jk/(w k) sin(w k t) - b_jk/(w k) cos(w k t), w = 2 pi / duration, "
    "periodic over the duration and at rest in the middle of the joint ranges at both ends (so it can be "
    "repeated). The coefficients are optimised (SciPy's SLSQP, from a seeded random start) to minimise the "
    "condition number of the base regressor stacked over the motion, columns scaled to unit norm (below 100 is "
    "good), within the URDF's position limits (less the margin), velocity limits and effort limits (torques by "
    "our inverse dynamics, without friction); the result is checked on a fine time grid and refused if it "
    "exceeds a limit. A joint without position limits is bounded by its velocity limit alone; a joint with "
    "neither is refused. Writes t, q_<joint>, qd_<joint>, qdd_<joint> and tau_<joint> (the torques the "
    "motion needs), which 'torques' reads as a log and 'simulate --torque-csv' as applied torques. Prints the "
    "condition number, the largest share of each limit used and the run time.")


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    parser.add_argument("--duration", type=float, required=True,
                        help="the period of the motion, s (one period is written)")
    parser.add_argument("--out", required=True,
                        help="output CSV, or - for standard output (written whole or not at all)")
    parser.add_argument("--dt", type=float, default=0.01, help="time between written samples, s (default 0.01)")
    parser.add_argument("--harmonics", type=int, default=5, help="harmonics per joint, at least 2 (default 5)")
    parser.add_argument("--samples", type=int, default=40,
                        help="instants of the period the condition number is optimised on (default 40)")
    parser.add_argument("--max-iterations", type=int, default=100,
                        help="of the optimisation (default 100: under a minute for a UR5; 0 keeps the random start)")
    parser.add_argument("--margin", type=float, default=0.05,
                        help="share of every limit the optimisation keeps clear of (default 0.05)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random start (default 0)")
    parser.add_argument("--json", action="store_true", help="print a JSON summary")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def run(args) -> int:
    from ...tools.excitation import KINDS, excitation

    if args.seed < 0:
        raise UsageError(f"--seed must be a non-negative integer, got {args.seed}")
    if args.out == io.STDOUT and args.json:
        raise UsageError("--out - and --json both want standard output; write the CSV to a file")
    model = load_robot_argument(args)
    io.check_writable(args.out)
    started = time.monotonic()
    bar = progress_bar(total=args.max_iterations, enabled=not args.quiet, delay=1.0, unit="iteration")

    def progress(done, total):
        bar.update(done - bar.n)

    try:
        found = excitation(model, args.duration, harmonics=args.harmonics, samples=args.samples, seed=args.seed,
                           max_iterations=args.max_iterations, margin=args.margin, dt=args.dt, progress=progress)
    finally:
        bar.close()
    seconds = time.monotonic() - started
    header, data = found.table()
    io.write_csv(args.out, header, data)
    report = sys.stderr if args.out == io.STDOUT else sys.stdout
    for note in found.notes:
        print(f"warning: {one_line(note)}", file=sys.stderr)
    if args.json:
        print_json(dict(robot=model.name, out=str(args.out), seconds=round(seconds, 3), seed=args.seed,
                        samples=args.samples, margin=args.margin, **found.record()))
        return 0
    print(f"excitation of {one_line(model.name)}: {args.duration:g} s, {found.coefficients.harmonics} harmonics, "
          f"{found.iterations} iterations in {seconds:.1f} s (optimisation {found.ended})", file=report)
    print(f"condition number {found.condition:.4g} (random start {found.condition_start:.4g}; base regressor, "
          "columns of unit norm)", file=report)
    for kind in KINDS:
        share, joint = found.limits.largest(kind)
        used = "no limit given" if joint is None else f"{100 * share:.1f}% (joint {one_line(joint)})"
        print(f"largest share of the {kind} limits: {used}", file=report)
    print(f"wrote {len(found.t)} samples to {args.out}", file=report)
    return 0

"""``course-dynamics excite``: an excitation trajectory for identification, written as CSV."""
from __future__ import annotations

import csv
import math
import sys
import time
import warnings

from ...base.errors import CourseDynamicsWarning
from ...base.text import one_line
from ...output import io
from ..options import (
    UsageError,
    add,
    add_all,
    add_renamed,
    add_robot_argument,
    load_robot_argument,
    print_json,
    progress_bar,
    progress_callback,
)
from . import COMMANDS

HELP = COMMANDS["excite"]
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
    "motion needs), which 'torques --log' reads as a log, 'simulate --torque-log' as applied torques and "
    "'animate --log' as a motion. --instants are the instants of the period the condition number is optimised "
    "on. Prints the condition number, the largest share of each limit used and the run time; --json prints them "
    "as one document (condition, limits, iterations, seconds, ...). --scope payload makes a short motion for "
    "'identify --scope payload': only the last three joints of the flange's chain move (the wrist; the others "
    "rest in the middle of their ranges), and the condition number is that of the payload's ten columns of the "
    "regressor on the moving joints' rows (the flange: --flange); fewer harmonics, instants and iterations by "
    "default, so it takes seconds.")

DEFAULTS = {"robot": dict(harmonics=5, instants=40, max_iterations=100),   # as tools.excitation's
            "payload": dict(harmonics=4, instants=20, max_iterations=40)}  # ten columns: seconds, not a minute


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    add(parser, "--duration", required=True)
    add(parser, "--out", required=True)
    add(parser, "--dt", default=0.01)
    add_all(parser, "--harmonics", "--instants", "--max-iterations", "--margin", "--seed", "--scope", "--flange",
            "--json", "--quiet")
    add_renamed(parser, "--samples", "--instants")


def _scope(args, model):
    """(the regressor's columns that count, the joints that move): (None, None) for the robot's base parameters."""
    if args.scope == "robot":
        if args.flange is not None:
            raise UsageError("--flange names the link a payload is fixed to: give --scope payload with it")
        return None, None
    from ...tools.payloads import flange, wrist

    moving = wrist(model, args.flange)
    return flange(model, args.flange, rows=moving), moving


def _say_if_long(model, args) -> None:
    """Refuse (one line) what would exceed the memory budget, and warn before a run estimated to be long."""
    from ...tools import excitation as excitation_module
    from ...tools import excitationcost

    excitationcost.check_options(args.duration, args.harmonics, args.instants, args.max_iterations, args.margin)
    if not (math.isfinite(args.dt) and 0 < args.dt <= args.duration):
        return  # excitation() says why
    samples = math.ceil(args.duration / args.dt - 1e-9) + 1
    if samples < excitation_module.SAMPLES_PER_HARMONIC * args.harmonics + 1:
        return  # too few samples to show the harmonics: excitation() says so, and no estimate is worth giving
    cost = excitationcost.cost(model, args.harmonics, args.instants, samples, args.max_iterations,
                               excitation_module.CONSTRAINT_POINTS, excitation_module.FINE_POINTS)
    if cost.seconds > excitationcost.LONG:
        warnings.warn(f"this excitation is estimated to take {cost.describe()}; fewer --max-iterations, "
                      "--harmonics or --instants make it shorter", CourseDynamicsWarning)


def _write(args, found) -> None:
    """The CSV as io.write_csv writes it (whole or not at all), a chunk of rows at a time (the table is not copied
    whole), with a bar on a terminal for a long one."""
    bar = progress_bar(args, total=len(found.t), unit="sample")
    try:
        with io.output(args.out) as handle:
            csv.writer(handle, lineterminator="\n").writerow(found.table(slice(0))[0])
            for start in range(0, len(found.t), io.CSV_CHUNK):
                rows = found.table(slice(start, start + io.CSV_CHUNK))[1].tolist()  # repr: shortest exact form
                handle.write("".join(",".join(map(repr, row)) + "\n" for row in rows))
                bar.update(len(rows))
    finally:
        bar.close()


def run(args) -> int:
    from ...tools.excitation import KINDS, excitation

    if args.seed < 0:
        raise UsageError(f"--seed must be a non-negative integer, got {args.seed}")
    if args.out == io.STDOUT and args.json:
        raise UsageError("--out - and --json both want standard output; write the CSV to a file")
    model = load_robot_argument(args)
    for name, value in DEFAULTS[args.scope].items():
        setattr(args, name, value if getattr(args, name) is None else getattr(args, name))
    columns, moving = _scope(args, model)
    io.check_writable(args.out)
    _say_if_long(model, args)
    started = time.monotonic()
    bar = progress_bar(args, total=args.max_iterations, unit="iteration")
    try:
        found = excitation(model, args.duration, harmonics=args.harmonics, samples=args.instants, seed=args.seed,
                           max_iterations=args.max_iterations, margin=args.margin, dt=args.dt,
                           progress=progress_callback(bar), columns=columns, moving=moving)
    finally:
        bar.close()
    seconds = time.monotonic() - started
    _write(args, found)
    report = sys.stderr if args.out == io.STDOUT else sys.stdout
    for note in found.notes:
        warnings.warn(note, CourseDynamicsWarning)
    if args.json:
        print_json(dict(robot=model.name, out=str(args.out), seconds=round(seconds, 3), seed=args.seed,
                        instants=args.instants, margin=args.margin, scope=args.scope,
                        flange=None if columns is None else columns.link, **found.record()))
        return 0
    print(f"excitation of {one_line(model.name)}: {args.duration:g} s, {found.coefficients.harmonics} harmonics, "
          f"{found.iterations} iterations in {seconds:.1f} s (optimisation {found.ended})", file=report)
    which = "base regressor" if columns is None else f"the payload's columns on {columns.link}"
    print(f"condition number {found.condition:.4g} (random start {found.condition_start:.4g}; {which}, "
          "columns of unit norm)", file=report)
    for kind in KINDS:
        share, joint = found.limits.largest(kind)
        used = "no limit given" if joint is None else f"{100 * share:.1f}% (joint {one_line(joint)})"
        print(f"largest share of the {kind} limits: {used}", file=report)
    print(f"wrote {len(found.t)} samples to {args.out}", file=report)
    return 0

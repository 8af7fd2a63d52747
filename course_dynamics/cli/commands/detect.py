"""``course-dynamics detect``: collisions and external torques in a log, by the generalized-momentum observer."""
from __future__ import annotations

import sys

from ...base.text import one_line
from ...output import io, render
from ..options import (
    UsageError, add_all, add_differentiation_arguments, add_friction_arguments, add_log_arguments, add_robot_argument,
    check_log_outputs, column_map, constants, friction, joint_values, load_robot_argument, numbers, open_log_argument,
    progress_bar,
)
from . import COMMANDS

HELP = COMMANDS["detect"]
DESCRIPTION = (
    "Read a log with measured joint torques (tau_meas_<joint>, a bag's effort, or currents with --torque-constant; "
    "any format torques --log reads) and run the generalized-momentum observer on it: r = K (p - p(0) - integral "
    "of (tau_meas - F + C^T qd - G + r)), p = M qd, which needs no accelerations and follows tau_ext, the torque "
    "the surroundings apply to each joint, with time constant 1/K. Friction (--friction, --viscous, --coulomb) is "
    "subtracted from the measured torques. A contact is where a joint's r exceeds its threshold in size (--threshold, "
    "or 6 sigma of the residual's own noise above its median, over --noise-window or the whole log; with friction, "
    "plus what the friction model may be off by where the rate is within 6 sigma of its noise of a change, filtered "
    "as r is) and lasts until every joint is under half of it, for at least --min-duration. The log's stamps are "
    "taken as they are (nothing is differentiated when it has rates), and times are from its start. Prints each "
    "event (start, end, the joints, the peak external torque per joint) and, with --link, the wrench the "
    "surroundings exert on that link while the contact lasts: tau_ext = J^T F by least squares, J^T passed through "
    "the observer's own update so that the fit has no lag, for short contacts and long; the whole wrench where the "
    "measured joints' J^T has rank 6, otherwise the force at the link's origin in the directions they see, the "
    "others named. "
    "--out writes r(t) as CSV (t, r_<joint>), --plot draws it with the thresholds and the events shaded, --json "
    "prints rows, gain, threshold, sigma, link, events and notes. Exit 0 when no contact is found, 1 when one is, "
    "2 on bad input.")


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    add_log_arguments(parser)
    add_differentiation_arguments(parser)
    add_all(parser, "--gain", "--threshold", "--noise-window", "--min-duration", "--link")
    add_friction_arguments(parser)
    add_all(parser, "--out", "--plot", "--json", "--quiet", "--no-compile")


def run(args) -> int:
    from ...tools.collisions import DEFAULT_GAIN, detect

    model = load_robot_argument(args)
    if not args.min_duration >= 0 or args.min_duration == float("inf"):
        raise UsageError(f"--min-duration must be a non-negative number of seconds, got '{args.min_duration:g}'")
    joint_friction = friction(args, model)
    gain = DEFAULT_GAIN if args.gain is None else _per_joint(args.gain, "--gain", model)
    threshold = None if args.threshold is None else _per_joint(args.threshold, "--threshold", model)
    if args.link is not None:
        model.frame(args.link)
    check_log_outputs(args, model)  # fail before reading a long log
    constants_k = (None if args.torque_constant is None
                   else joint_values(args.torque_constant, "--torque-constant", model))
    bar = progress_bar(args, total=None, unit="step")
    try:
        bar.set_description("reading the log")
        source = open_log_argument(args, model, args.log)
        bar.set_description("observer")
        found = detect(model, source, gain=gain, threshold=threshold, window=args.noise_window,
                       min_duration=args.min_duration, link=args.link, friction=joint_friction, dt=args.log_dt,
                       columns=column_map(args), constants=constants(args), time_unit=args.time_unit,
                       resample=args.resample, split_gaps=args.split_gaps, repair=args.repair, smooth=args.smooth,
                       torque_constants=constants_k, compiled=False if args.no_compile else None)
    finally:
        bar.close()
    document = render.json_text(dict(robot=model.name, log=str(args.log), out=args.out, plot=args.plot,
                                     **found.record()))
    if args.out == io.STDOUT and not args.json:
        _print_report(found, model, sys.stderr)
    if args.plot:
        from ...output.plotting import plot_residuals

        plot_residuals(found, args.plot, title=f"{model.name}: momentum observer on {args.log}")
    if args.out:
        header, data = found.table()
        comments = [f"course-dynamics detect {model.name} from {args.log}: r in N m (N), r -> tau_ext",
                    "thresholds: " + ", ".join(f"{j} {found.threshold[found.joints.index(j)]:.6g}"
                                               for j in found.measured)]
        io.write_csv(args.out, header, data, comments=comments + [one_line(n) for n in found.notes])
    if args.json:
        sys.stdout.write(document + "\n")
    elif args.out != io.STDOUT:
        _print_report(found, model, sys.stdout)
    if args.out and args.out != io.STDOUT:
        print(f"wrote {len(found.t)} rows of r(t) to {args.out}", file=sys.stderr)
    return 1 if found.events else 0


def _per_joint(text, option, model):
    """One positive number for every joint, or one per joint."""
    values = numbers(text, option)
    values = values.repeat(model.n) if len(values) == 1 else values
    if values.shape != (model.n,):
        raise UsageError(f"{option} takes one value or one per joint: {len(values)} given, robot '{model.name}' has "
                         f"{model.n} joints ({', '.join(model.joint_names)})")
    if not (values > 0).all() or not (values < float("inf")).all():
        raise UsageError(f"{option} must be positive and finite, got '{text}'")
    return values


def _print_report(found, model, stream) -> None:
    from ...tools.collisions import unseen_words

    for note in found.notes:
        print(f"note: {one_line(note)}", file=stream)
    print(f"robot {model.name}: {len(found.t)} samples over {found.t[-1] - found.t[0]:.6g} s; momentum observer "
          f"(r -> tau_ext, the torque the surroundings apply to each joint, N m or N)", file=stream)
    rows = [["joint", "gain K (1/s)", "sigma", "threshold"]]
    for j in found.measured:
        i = found.joints.index(j)
        sigma = found.sigma[i]
        rows.append([j, f"{found.gain[i]:.4g}", "-" if sigma != sigma else f"{sigma:.3g}", f"{found.threshold[i]:.3g}"])
    print(render.text_table(rows, align="<>>>"), file=stream)
    if not found.events:
        print("no contact found", file=stream)
        return
    wrench = found.link is not None
    header = ["event", "start (s)", "end (s)", "detected", "peak tau_ext, joint by joint (- under its threshold)"]
    rows = [header + (["force (N)", "moment (N m)", "cond"] if wrench else [])]
    for number, e in enumerate(found.events, 1):
        peak = dict(zip(e.joints, e.peak))
        peaks = " ".join(f"{peak[j]:+.3g}" if j in peak else "-" for j in found.measured)
        row = [str(number), f"{e.start:.4f}", f"{e.end:.4f}", f"{e.detected:.4f}", peaks]
        if wrench:
            row += [" ".join(f"{x:+.3g}" for x in e.force),
                    "-" if e.moment is None else " ".join(f"{x:+.3g}" for x in e.moment), f"{e.condition:.3g}"]
        rows.append(row)
    print(render.text_table(rows, align="<>>><" + ("<<>" if wrench else "")), file=stream)
    for number, e in enumerate(found.events, 1):
        if wrench and e.unseen:
            print(f"event {number}: no measured joint sees the force along {unseen_words(model, e.unseen)}; the force "
                  "shown is its component across", file=stream)
    where = (f"; the wrench is what the surroundings exert on {found.link}, base coordinates (moment about its "
             "origin; cond: the fit's condition number)") if wrench else ""
    print(f"{len(found.events)} contact event{'s' if len(found.events) > 1 else ''} found{where}", file=stream)

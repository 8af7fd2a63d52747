"""``course-dynamics identify``: the inertial and friction parameters a robot's log shows, as a URDF and a report."""
from __future__ import annotations

import sys

from .. import options
from ..options import UsageError, add_robot_argument, joint_values, load_robot_argument, print_json
from . import torques

HELP = "identify the inertial and friction parameters from a log with measured torques; write them as a URDF"
DESCRIPTION = (
    "Read a log of the robot moving (as 'torques' reads it: a table, a UR RTDE recording or a ROS bag) that holds "
    "what the robot measured - tau_meas_<joint> columns, a bag's effort, Franka's tau_J, or current_<joint> with "
    "--torque-constant - and find the masses, centres of mass, inertias and joint friction (viscous, Coulomb) that "
    "explain it: weighted least squares on the base parameters (the combinations the torques can tell apart), then "
    "a physically consistent estimate (every body's pseudo-inertia positive semi-definite, masses positive, friction "
    "non-negative; cvxpy with Clarabel) that keeps what the log does not excite at the URDF's values. The last "
    "--holdout share of the log is kept out of the fit and predicted by both models. Writes --out, the input URDF "
    "with each moving link's <inertial> and each joint's <dynamics damping friction> identified (links merged into a "
    "moving body by fixed joints lose their <inertial>; everything else is kept as it was; the text is read back before "
    "it is written, and one that would read back otherwise than identified is refused), and with --report DIR "
    "report.html, report.md, report.json and held_out.svg. Needs course-dynamics[identify]. Exit 0, 2 on bad input.")

SHOWN = 5  # hardly excited combinations printed; the report and --json list all
FRICTION_MODELS = ("both", "viscous", "coulomb", "none")  # as tools.identification (not imported at start-up)


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    torques.add_log_arguments(parser, "the robot's log with its measured torques (tau_meas_<joint>, a bag's effort, "
                                      "Franka's tau_J, or current_<joint> with --torque-constant)")
    parser.add_argument("--out", required=True, metavar="URDF",
                        help="the identified URDF to write (whole or not at all), or - for standard output")
    parser.add_argument("--report", metavar="DIR",
                        help="also write DIR/report.html, report.md, report.json and held_out.svg (DIR may hold "
                             "other files; only files an earlier 'identify' wrote there are replaced)")
    parser.add_argument("--friction", choices=FRICTION_MODELS, default="both",
                        help="which joint friction to identify: viscous F_v qd, Coulomb F_c sgn(qd), both (default) "
                             "or none; what is not identified stays as the URDF's <dynamics>")
    parser.add_argument("--holdout", type=float, default=0.2, metavar="FRACTION",
                        help="the share of the log's time, at its end, kept out of the fit to judge it (default 0.2; "
                             "0 fits everything)")
    parser.add_argument("--prior-weight", type=float, metavar="LAMBDA",
                        help="the weight of the URDF's values against the log's, as a share of what the log says "
                             "(default 1e-6): larger keeps poorly excited parameters nearer the URDF")
    parser.add_argument("--json", action="store_true", help="print the identification as one JSON document")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def run(args) -> int:
    from ...output import io
    from ...output.identification_report import REPORT_FILES, check_report_folder
    from ...tools.logs import joint_log
    from ...tools.sources import open_log

    model = load_robot_argument(args)
    mapping, fixed = torques.column_map(args), torques.constants(args)
    if not 0 <= args.holdout < 1:
        raise UsageError(f"--holdout must be at least 0 and less than 1, got {args.holdout:g}")
    if args.out == io.STDOUT and args.json:
        raise UsageError("--out - and --json both want standard output; write the URDF to a file")
    reports = [] if args.report is None else [f"{args.report}/{name}" for name in REPORT_FILES]
    io.check_distinct([model.source, args.trajectory], [args.out] + reports)
    io.check_writable(args.out)
    if args.report is not None:
        if not str(args.report).strip():
            raise UsageError("--report names an empty folder; name one")
        check_report_folder(args.report)  # a file in the way fails before the work
    constants_k = None if args.torque_constant is None else joint_values(args.torque_constant, "--torque-constant", model)
    source = open_log(args.trajectory, model, format=args.format, topic=args.topic, decimal=args.decimal)
    log = joint_log(model, source, dt=args.dt, columns=mapping, window=args.smooth, constants=fixed,
                    time_unit=args.time_unit, resample=args.resample, split_gaps=args.split_gaps,
                    torque_constants=constants_k)
    result = _identify(args, model, log, source.where)

    from ...output.urdf_writer import write_identified_urdf

    write_identified_urdf(args.out, result.model, None if args.friction == "none" else result.friction, model.source)
    if args.report is not None:
        from ...output.identification_report import write_report

        write_report(args.report, result, str(args.urdf), str(args.trajectory))
    if args.json:
        print_json(dict(urdf=str(args.urdf), log=str(args.trajectory), out=args.out, report=args.report,
                        log_notes=list(log.notes), **result.record()))
        return 0
    _print_summary(result, log, sys.stderr if args.out == io.STDOUT else sys.stdout)
    if args.out != io.STDOUT:
        print(f"wrote the identified URDF to {args.out}", file=sys.stderr)
    if args.report is not None:
        print(f"wrote {args.report}/report.html, report.md, report.json and held_out.svg", file=sys.stderr)
    return 0


def _identify(args, model, log, where):
    from ...tools.identification import PRIOR_WEIGHT, identify

    prior = PRIOR_WEIGHT if args.prior_weight is None else args.prior_weight
    bar = options.progress_bar(total=int(len(log.t) * (1 - args.holdout)) + 1, enabled=not args.quiet
                               and sys.stderr.isatty(), delay=1.0, unit="sample")
    try:
        return identify(model, log, friction=args.friction, holdout=args.holdout, prior_weight=prior, where=where,
                        progress=lambda done, total: bar.update(done - bar.n))
    finally:
        bar.close()


def _print_summary(result, log, stream) -> None:
    from ...output import render
    from ...output.identification_report import RESIDUAL_HEADER, residual_rows

    for note in list(log.notes) + list(result.notes):
        print(f"note: {note}", file=stream)
    fitted, held = result.samples
    condition = f"{result.condition_number:.3g}"
    print(f"robot {result.model.name}: identified from {fitted} samples (friction: {result.friction_model}), "
          f"{held} held out from t = {result.split_t:.6g} s; condition number {condition}; solver {result.solver}",
          file=stream)
    rows = residual_rows(result)
    if held:
        print(render.text_table([list(RESIDUAL_HEADER)] + rows, align="<>>>>"), file=stream)
    for share, combination in result.unexcited[:SHOWN]:
        print(f"warning: hardly excited by the log (singular value {share:.2g} of the largest): {combination}; "
              "it stays near the URDF's values", file=stream)
    if len(result.unexcited) > SHOWN:
        print(f"warning: and {len(result.unexcited) - SHOWN} more combinations hardly excited (--report or --json "
              "lists them)", file=stream)
    worse = [j for j, b, a in zip(result.model.joint_names, result.rms_before, result.rms_after) if a > b]
    if worse:
        print(f"warning: on the held-out part the identified model does worse than the URDF for {', '.join(worse)}: "
              "the log may be too short or too little varied for the parameters (a longer, richer motion helps)",
              file=stream)

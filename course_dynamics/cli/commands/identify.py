"""``course-dynamics identify``: the inertial and friction parameters a robot's log shows, as a URDF and a report."""
from __future__ import annotations

import sys
from pathlib import Path

from ..options import (
    UsageError,
    add,
    add_all,
    add_differentiation_arguments,
    add_log_arguments,
    add_renamed,
    add_robot_argument,
    column_map,
    constants,
    joint_values,
    load_robot_argument,
    open_log_argument,
    print_json,
    progress_bar,
    progress_callback,
)

HELP = "identify the inertial and friction parameters from a log with measured torques; write them as a URDF"
DESCRIPTION = (
    "Read a log of the robot moving (--log, as 'torques' reads it: a table, a UR RTDE recording or a ROS bag) that "
    "holds what the robot measured - tau_meas_<joint> columns, a bag's effort, Franka's tau_J, or current_<joint> "
    "with --torque-constant - and find the masses, centres of mass, inertias and joint friction (viscous, Coulomb; "
    "--friction-fit) that explain it: weighted least squares on the base parameters (the combinations the torques "
    "can tell apart), then a physically consistent estimate (every body's pseudo-inertia positive semi-definite, "
    "masses positive, friction non-negative; cvxpy with Clarabel) regularised by each body's log-determinant "
    "divergence from the URDF's pseudo-inertia (--prior-weight); the directions the log does not see (singular "
    "values below 1e-4 of the largest, each parameter in its body's scale) stay at the URDF's values, and so do the "
    "bodies of joints held still (--set). Friction has no prior: the log finds it."
    " The last --holdout share of the log is kept out of the fit and predicted by both models. The "
    "identified URDF is the input URDF with each moving link's <inertial> and each joint's <dynamics damping "
    "friction> identified (links merged into a moving body by fixed joints lose their <inertial>; everything else "
    "is kept as it was; the text is read back before it is written, and one that would read back otherwise than "
    "identified is refused). --out FILE.urdf (or -, or a file that exists) writes it alone; --out DIR writes "
    "DIR/identified.urdf with the report: report.html, report.md, report.json and held_out.svg. --json prints "
    "the identification (parameters, held_out_rms, samples, friction_model, ...). Needs course-dynamics[identify]. "
    "Exit 0, 2 on bad input.")

SHOWN = 5  # hardly excited combinations printed; the report and --json list all
URDF_SUFFIXES = (".urdf", ".xml")   # an --out with one of these (or a file already) is the URDF alone; else a folder
IDENTIFIED = "identified.urdf"      # the URDF's name in an --out folder


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    add_log_arguments(parser)
    add_differentiation_arguments(parser)
    add(parser, "--out", required=True)
    add_all(parser, "--friction-fit", "--holdout", "--prior-weight", "--json", "--quiet")
    add_renamed(parser, "--friction", "--friction-fit")
    add_renamed(parser, "--report", "--out DIR (the folder then holds the identified URDF too)",
                dest="report_folder", metavar="DIR")


def outputs(args) -> tuple[str, str | None]:
    """Where the URDF goes and which folder the report goes to (None: no report)."""
    from ...output import io

    old = getattr(args, "report_folder", None)
    out = Path(args.out)
    if args.out == io.STDOUT or str(args.out).lower().endswith(URDF_SUFFIXES) or (out.exists() and not out.is_dir()):
        if old is not None and not str(old).strip():
            raise UsageError("--report names an empty folder; name one")
        return args.out, old
    if old is not None:
        raise UsageError(f"--out {args.out} is a folder (its name does not end in .urdf): it holds the report, so "
                         "--report is not needed")
    return f"{args.out}/{IDENTIFIED}", args.out


def run(args) -> int:
    from ...output import io
    from ...output.identification_report import REPORT_FILES, check_report_folder
    from ...tools.logs import joint_log

    model = load_robot_argument(args)
    mapping, fixed = column_map(args), constants(args)
    if not 0 <= args.holdout < 1:
        raise UsageError(f"--holdout must be at least 0 and less than 1, got {args.holdout:g}")
    if args.out == io.STDOUT and args.json:
        raise UsageError("--out - and --json both want standard output; write the URDF to a file")
    urdf_out, folder = outputs(args)
    in_folder = folder is not None and urdf_out == f"{folder}/{IDENTIFIED}"
    reports = [] if folder is None else [f"{folder}/{name}" for name in REPORT_FILES]
    io.check_distinct([model.source, args.log], [urdf_out] + reports)
    if folder is not None:
        check_report_folder(folder, (IDENTIFIED,) if in_folder else ())  # a file in the way fails before the work
    if not in_folder:
        io.check_writable(urdf_out)
    constants_k = (None if args.torque_constant is None
                   else joint_values(args.torque_constant, "--torque-constant", model))
    source = open_log_argument(args, model, args.log)
    log = joint_log(model, source, dt=args.log_dt, columns=mapping, window=args.smooth, constants=fixed,
                    time_unit=args.time_unit, resample=args.resample, split_gaps=args.split_gaps,
                    torque_constants=constants_k)
    result = _identify(args, model, log, source.where)

    from ...output.urdf_writer import checked_identified_urdf, write_identified_urdf

    friction = None if args.friction_fit == "none" else result.friction
    if in_folder:
        from ...output.identification_report import write_report

        text = checked_identified_urdf(result.model, friction, model.source, urdf_out)
        write_report(folder, result, str(args.urdf), str(args.log), also={IDENTIFIED: text})
    else:
        write_identified_urdf(urdf_out, result.model, friction, model.source)
        if folder is not None:
            from ...output.identification_report import write_report

            write_report(folder, result, str(args.urdf), str(args.log))
    if args.json:
        print_json(dict(urdf=str(args.urdf), log=str(args.log), out=urdf_out, report=folder,
                        log_notes=list(log.notes), **result.record()))
        return 0
    _print_summary(result, log, sys.stderr if args.out == io.STDOUT else sys.stdout)
    if urdf_out != io.STDOUT:
        print(f"wrote the identified URDF to {urdf_out}", file=sys.stderr)
    if folder is not None:
        print(f"wrote {folder}/report.html, report.md, report.json and held_out.svg", file=sys.stderr)
    return 0


def _identify(args, model, log, where):
    from ...tools.identification import PRIOR_WEIGHT, identify

    prior = PRIOR_WEIGHT if args.prior_weight is None else args.prior_weight
    bar = progress_bar(args, total=int(len(log.t) * (1 - args.holdout)) + 1, unit="sample")
    try:
        return identify(model, log, friction=args.friction_fit, holdout=args.holdout, prior_weight=prior, where=where,
                        progress=progress_callback(bar))
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
    for body in result.bodies:
        if body["kept"] or body["in_combination"]:
            print(f"body {body['body']}: determined by the log {', '.join(body['determined']) or 'nothing alone'}; "
                  f"seen only in combination {', '.join(body['in_combination']) or 'none'}; "
                  f"kept at the URDF's {', '.join(body['kept']) or 'none'}", file=stream)
    for line in result.active:
        print(f"note: a physical constraint is active: {line}", file=stream)
    for line in result.far:
        print(f"warning: moved far from the URDF: {line}", file=stream)
    for share, combination in result.unexcited[:SHOWN]:
        print(f"warning: hardly excited by the log (singular value {share:.2g} of the largest): {combination}; "
              "it stays near the URDF's values", file=stream)
    if len(result.unexcited) > SHOWN:
        print(f"warning: and {len(result.unexcited) - SHOWN} more combinations hardly excited (the report in an "
              "--out folder, or --json, lists them)", file=stream)
    worse = [j for j, b, a in zip(result.model.joint_names, result.rms_before, result.rms_after) if a > b]
    if worse:
        print(f"warning: on the held-out part the identified model does worse than the URDF for {', '.join(worse)}: "
              "the log may be too short or too little varied for the parameters (a longer, richer motion helps)",
              file=stream)

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
    drives_argument,
    joint_values,
    load_robot_argument,
    open_log_argument,
    print_json,
    progress_bar,
    progress_callback,
)
from . import COMMANDS

HELP = COMMANDS["identify"]
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
    "the identification (parameters, held_out_rms, samples, friction_model, drives, ...). Drives: --armature and "
    "--offset add each moving measured joint's rotor inertia and torque offset to the fit (no prior, standard errors "
    "in the report; an armature held >= 0), which a URDF cannot hold: --drives-out FILE writes them as TOML for "
    "--drives. --drives FILE gives known drives: subtracted from the measured torques where not fitted, the start "
    "(kept where the log does not see them) where fitted. Needs course-dynamics[identify]. Exit 0, 2 on bad input.")

DESCRIPTION += (
    " --scope payload identifies only a payload fixed to the flange (--flange; default the last link of the last "
    "moving body every tip is carried by): its mass, centre of mass and inertia about it with standard errors, the "
    "arm's own parameters as the URDF gives them (an earlier identification's URDF works too), the URDF's friction "
    "subtracted unless --friction-fit says otherwise; the consistent estimate (J >= 0, m >= 0) where the least "
    "squares is not physical, and what the log does not determine printed as such. It writes the URDF with a link "
    "'payload' fixed to the flange (--out DIR: DIR/identified.urdf, report.html, report.md and report.json), and "
    "prints UR's set_payload (in tool0) and Franka's load (in panda_link8). Exit 0 when the payload is written, 1 "
    "when none is detected (a mass within 3 standard errors of 0) or the log does not determine its mass or "
    "centre of mass: nothing is written then.")
SHOWN = 5  # hardly excited combinations printed; the report and --json list all
URDF_SUFFIXES = (".urdf", ".xml")   # an --out with one of these (or a file already) is the URDF alone; else a folder
IDENTIFIED = "identified.urdf"      # the URDF's name in an --out folder


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    add_log_arguments(parser)
    add_differentiation_arguments(parser)
    add(parser, "--out", required=True)
    add_all(parser, "--friction-fit", "--holdout", "--prior-weight", "--armature", "--offset", "--drives",
            "--drives-out", "--json", "--quiet")
    add_all(parser, "--scope", "--flange")
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

    model = load_robot_argument(args)
    mapping, fixed = column_map(args), constants(args)
    if not 0 <= args.holdout < 1:
        raise UsageError(f"--holdout must be at least 0 and less than 1, got {args.holdout:g}")
    if args.out == io.STDOUT and args.json:
        raise UsageError("--out - and --json both want standard output; write the URDF to a file")
    if args.scope == "payload":
        return _run_payload(args, model, mapping, fixed)
    if args.flange is not None:
        raise UsageError("--flange names the link a payload is fixed to: give --scope payload with it")
    args.friction_fit = args.friction_fit or "both"
    urdf_out, folder = outputs(args)
    in_folder = folder is not None and urdf_out == f"{folder}/{IDENTIFIED}"
    reports = [] if folder is None else [f"{folder}/{name}" for name in REPORT_FILES]
    known = drives_argument(args, model)
    drives_out = args.drives_out
    if drives_out is not None and (drives_out == io.STDOUT or not str(drives_out).strip()):
        raise UsageError("--drives-out needs a file name (the URDF or the report may take standard output)")
    if drives_out is not None and not (args.armature or args.offset or args.drives):
        raise UsageError("--drives-out writes the drives --armature and --offset identify (or --drives gives): "
                         "give one of them")
    io.check_distinct([model.source, args.log, args.drives], [urdf_out] + reports + [drives_out])
    if drives_out is not None:
        io.check_writable(drives_out)
    if folder is not None:
        check_report_folder(folder, (IDENTIFIED,) if in_folder else ())  # a file in the way fails before the work
    if not in_folder:
        io.check_writable(urdf_out)
    source, log = _read_log(args, model, mapping, fixed)
    result = _identify(args, model, log, source.where, known)

    from ...output.urdf_writer import checked_identified_urdf, write_identified_urdf

    friction = None if args.friction_fit == "none" else result.friction
    if in_folder:
        from ...output.identification_report import write_report

        text = checked_identified_urdf(result.model, friction, model.source, urdf_out)
        write_report(folder, result, str(args.urdf), str(args.log), also={IDENTIFIED: text}, log_notes=log.notes)
    else:
        write_identified_urdf(urdf_out, result.model, friction, model.source)
        if folder is not None:
            from ...output.identification_report import write_report

            write_report(folder, result, str(args.urdf), str(args.log), log_notes=log.notes)
    if drives_out is not None:
        _write_drives(drives_out, result, args)
    if args.json:
        print_json(dict(urdf=str(args.urdf), log=str(args.log), out=urdf_out, report=folder, drives_out=drives_out,
                        log_notes=list(log.notes), **result.record()))
        return 0
    _print_summary(result, log, sys.stderr if args.out == io.STDOUT else sys.stdout)
    if urdf_out != io.STDOUT:
        print(f"wrote the identified URDF to {urdf_out}", file=sys.stderr)
    if folder is not None:
        print(f"wrote {folder}/report.html, report.md, report.json and held_out.svg", file=sys.stderr)
    if drives_out is not None:
        print(f"wrote the drives to {drives_out}", file=sys.stderr)
    return 0


def _write_drives(path, result, args) -> None:
    """The drives file: the identified drives (the given ones, or none, where not fitted), with standard errors."""
    from ...core.drives import Drives, drives_text
    from ...output import io

    drives = result.drives or Drives.none(result.model)
    errors = result.drive_error if result.drive_error is not None else None
    header = f"drives of {result.model.name}: identified by course-dynamics from {args.log}"
    io.write_text(path, drives_text(drives, result.model, header, errors))


def _read_log(args, model, mapping, fixed):
    """The log as both scopes read it: (the opened source, its :class:`~course_dynamics.tools.logs.JointLog`)."""
    from ...tools.logs import joint_log

    constants_k = (None if args.torque_constant is None
                   else joint_values(args.torque_constant, "--torque-constant", model))
    source = open_log_argument(args, model, args.log)
    return source, joint_log(model, source, dt=args.log_dt, columns=mapping, window=args.smooth, constants=fixed,
                             time_unit=args.time_unit, resample=args.resample, split_gaps=args.split_gaps,
                             repair=args.repair, torque_constants=constants_k)


def _identify(args, model, log, where, known):
    from ...tools.identification import PRIOR_WEIGHT, identify

    prior = PRIOR_WEIGHT if args.prior_weight is None else args.prior_weight
    bar = progress_bar(args, total=int(len(log.t) * (1 - args.holdout)) + 1, unit="sample")
    try:
        fit = tuple(part for part in ("armature", "offset") if getattr(args, part))
        return identify(model, log, friction=args.friction_fit, holdout=args.holdout, prior_weight=prior, where=where,
                        progress=progress_callback(bar), drives=known, fit_drives=fit)
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
    if result.drives is not None:
        from ...output.identification_report import DRIVES_HEADER, drive_rows

        print(render.text_table([list(DRIVES_HEADER)] + drive_rows(result), align="<>>"), file=stream)
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


def _run_payload(args, model, mapping, fixed) -> int:
    """--scope payload: the payload on the flange, as a URDF with a payload link, a summary and a report."""
    from ...output import folders, io
    from ...output.identification_report import OWNER, PAYLOAD_REPORT_FILES, payload_report_files
    from ...output.urdf_writer import checked_payload_urdf
    from ...tools.payloads import PAYLOAD_LINK, flange, identify_payload

    robot_only = ("--prior-weight", "--armature", "--offset", "--drives", "--drives-out")
    given = [flag for flag in robot_only if getattr(args, flag[2:].replace("-", "_"), None)]
    if given:
        raise UsageError(f"{given[0]} is for --scope robot: a payload's identification has no prior and no drives")
    link = flange(model, args.flange).link          # a link that is not one, or is fixed to the base: refused now
    if any(frame.name == PAYLOAD_LINK for frame in model.frames):
        raise UsageError(f"{args.urdf} has a link '{PAYLOAD_LINK}' already (a payload written before?): identify a "
                         "payload from the URDF without it")
    urdf_out, folder = outputs(args)
    in_folder = folder is not None and urdf_out == f"{folder}/{IDENTIFIED}"
    reports = [] if folder is None else [f"{folder}/{name}" for name in PAYLOAD_REPORT_FILES]
    io.check_distinct([model.source, args.log], [urdf_out] + reports)
    if folder is not None:
        folders.check_folder(folder, PAYLOAD_REPORT_FILES + ((IDENTIFIED,) if in_folder else ()), OWNER)
    if not in_folder:
        io.check_writable(urdf_out)
    source, log = _read_log(args, model, mapping, fixed)
    bar = progress_bar(args, total=int(len(log.t) * (1 - args.holdout)) + 1, unit="sample")
    try:
        result = identify_payload(model, log, link, friction=args.friction_fit or "none", holdout=args.holdout,
                                  where=source.where, progress=progress_callback(bar))
    finally:
        bar.close()
    written = result.detected and result.determined["com"]
    files = {}
    if written:
        target = "standard output" if urdf_out == io.STDOUT else urdf_out
        files[urdf_out] = checked_payload_urdf(model, link, result.pi, model.source, target, PAYLOAD_LINK)
    if folder is not None and written:  # no payload, nothing written (an earlier run's folder is left as it was)
        pages = payload_report_files(result, model, str(args.urdf), str(args.log))
        folders.write_folder(folder, {**({IDENTIFIED: files.pop(urdf_out)} if in_folder and files else {}), **pages},
                             OWNER)
    for path, text in files.items():
        io.write_bytes(path, text)
    if args.json:
        print_json(dict(urdf=str(args.urdf), log=str(args.log), out=urdf_out if written else None,
                        report=folder if written else None, scope="payload", log_notes=list(log.notes),
                        **result.record(model)))
        return 0 if written else 1
    _print_payload(result, model, log, sys.stderr if args.out == io.STDOUT else sys.stdout)
    if written and urdf_out != io.STDOUT:
        print(f"wrote the URDF with the payload (link '{PAYLOAD_LINK}' fixed to '{link}') to {urdf_out}",
              file=sys.stderr)
    if not written:
        why = ("the log does not determine the payload's mass" if not result.determined["mass"] else
               "no payload is detected" if not result.detected else "the log does not determine its centre of mass")
        import warnings

        from ...base.errors import CourseDynamicsWarning

        warnings.warn(f"{why}: no URDF written", CourseDynamicsWarning)
    if folder is not None and written:
        print(f"wrote {folder}/{', '.join(PAYLOAD_REPORT_FILES)}", file=sys.stderr)
    return 0 if written else 1


def _print_payload(result, model, log, stream) -> None:
    from ...output import render
    from ...output.identification_report import PAYLOAD_HEADER, payload_forms, payload_rows

    for note in list(log.notes) + list(result.notes):
        print(f"note: {note}", file=stream)
    fitted, held = result.samples
    print(f"payload on {model.name}'s {result.link}: identified from {fitted} samples (friction: "
          f"{result.friction_model}), {held} held out; {result.solver}", file=stream)
    print(render.text_table([list(PAYLOAD_HEADER)] + payload_rows(result, model), align="<<<<"), file=stream)
    for line in payload_forms(result, model):
        print(line, file=stream)
    if held:
        joints = [j for j, b in zip(model.joint_names, result.rms_before) if b == b]
        before = ", ".join(f"{b:.3g}" for b in result.rms_before if b == b)
        after = ", ".join(f"{a:.3g}" for a in result.rms_after if a == a)
        print(f"held-out RMS residual ({', '.join(joints)}), N m: without the payload {before}; with it {after}",
              file=stream)

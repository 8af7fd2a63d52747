"""``course-dynamics torques``: the joint torques a logged trajectory needs, and a limits report."""
from __future__ import annotations

import sys

import numpy as np

from ...base.text import one_line
from ...output import io, render
from ...tools.limits import seconds
from ...tools.loads import Payload, Wrench, payload_link
from ...tools.columns import merged_map, plan_columns
from ...tools.logs import torques_from_log
from ...tools.retiming import retime, retimed_log
from ..flags import FLAGS
from ..options import (
    UsageError, add, add_all, add_differentiation_arguments, add_friction_arguments, add_log_arguments,
    add_robot_argument, check_log_outputs, column_map, constants, drives_argument, friction, joint_values,
    load_robot_argument, numbers,
    open_log_argument, progress_bar, progress_callback,
)
from . import COMMANDS

HELP = COMMANDS["torques"]
DESCRIPTION = (
    "Read a trajectory log - a table (comma, semicolon, tab or whitespace separated; columns t, q_<joint> and "
    "optionally qd_<joint>, qdd_<joint>, tau_meas_<joint>, current_<joint>; other columns, numbers or words, are "
    "ignored), a UR RTDE recording, or a ROS 1/ROS 2 bag or MCAP file (sensor_msgs/JointState by joint name, or "
    "Franka's FrankaState) - and write t, tau_<joint>: tau = M qdd + V + G (+ friction, payload, wrench, and the "
    "rotor inertias and offsets of --drives: I_a qdd + tau_0). Missing "
    "rates are differentiated from q (Savitzky-Golay); dropped samples are filled and the fill is reported. Prints "
    "each joint's peak and RMS torque, peak rate and the share of the URDF's effort and velocity limits used, and, "
    "when the log holds measured torques (or currents and --torque-constant), the residual of our model against "
    "them. --out writes the torques as CSV (- for standard output), which animate --log and simulate --torque-log "
    "read; --plot draws them; --json prints the report (exceeded, joints, violations, uncertain, notes, "
    "residuals). --retime finds the smallest k such that the motion played k times slower is within every limit "
    "less --margin, prints it with the new duration (or the joint whose gravity and Coulomb friction alone exceed "
    "a limit, which no k lowers) and makes --out the retimed log. Exit 0 within the limits, 1 when a limit is "
    "exceeded (by the motion as logged), 2 on bad input.")


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    add_log_arguments(parser)
    add_differentiation_arguments(parser)
    add_all(parser, "--out", "--columns", "--with-state", "--retime")
    add(parser, "--margin", default=None)  # given or not: only --retime uses it
    add_friction_arguments(parser)
    add(parser, "--drives")
    add_all(parser, "--payload", "--payload-size", "--wrench", "--plot", "--json", "--quiet", "--no-compile")


def payload_arguments(args) -> list[Payload]:
    if not args.payload:
        if args.payload_size is not None:
            raise UsageError("--payload-size needs --payload")
        return []
    if args.payload_size is not None and len(args.payload) > 1:
        raise UsageError("--payload-size describes one payload; with several --payload, each is a point mass")
    return [_payload(text, args.payload_size) for text in args.payload]


def _payload(text: str, size_text) -> Payload:
    head, *rest = text.split(",")
    mass_text, _, link = head.partition("@")
    try:
        mass = float(mass_text)
    except ValueError:
        raise UsageError(f"--payload must be MASS[@LINK][,CX,CY,CZ], got '{text}'") from None
    com = numbers(",".join(rest), "--payload") if rest else (0.0, 0.0, 0.0)
    if len(com) != 3:
        raise UsageError(f"--payload: the centre of mass needs three numbers CX,CY,CZ, got '{','.join(rest)}'")
    size = None if size_text is None else numbers(size_text, "--payload-size")
    return Payload(mass=mass, link=link.strip() or None, com=tuple(com), size=None if size is None else tuple(size))


def wrench_arguments(args) -> list[Wrench]:
    wrenches = []
    for text in args.wrench or ():
        link, sep, values = text.partition(":")
        F = numbers(values, "--wrench") if sep else ()
        if not link.strip() or len(F) not in (3, 6):
            raise UsageError(f"--wrench must be LINK:FX,FY,FZ[,NX,NY,NZ], got '{text}'")
        wrenches.append(Wrench(link=link.strip(), force=tuple(F[:3]),
                               moment=tuple(F[3:]) if len(F) == 6 else (0.0, 0.0, 0.0)))
    return wrenches


def drives_note(args, joint_drives) -> list[str]:
    """The note saying which drives file was applied and what it holds (none without --drives)."""
    if joint_drives is None:
        return []
    return [f"drives from {args.drives}: rotor inertias I_a {joint_drives.armature.tolist()} kg m^2 (kg), offsets "
            f"tau_0 {joint_drives.offset.tolist()} N m (N), added as I_a qdd + tau_0"]


def settings(args, model, payloads, wrenches, joint_friction) -> list[str]:
    """The options that change the torques, for the output file's header."""
    lines = []
    if args.gravity is not None:
        lines.append(f"gravity {model.gravity.tolist()} m/s^2")
    if args.torque_constant is not None:
        lines.append(f"measured torques: currents times the torque constants {args.torque_constant} N m/A")
    if joint_friction is not None:
        lines.append(f"friction: viscous {joint_friction.viscous.tolist()}, Coulomb {joint_friction.coulomb.tolist()}")
    for p in payloads:
        lines.append(f"payload {p.mass:g} kg at {payload_link(model, p)}, centre {list(p.com)} m"
                     + (f", box {list(p.size)} m" if p.size else ", point mass"))
    for w in wrenches:
        lines.append(f"wrench at {w.link}: force {list(w.force)} N, moment {list(w.moment)} N m (base coordinates)")
    return lines


def _list_columns(source, model, mapping, fixed) -> int:
    """What ``--columns`` prints: the column plan that reading the log would follow, before any number is used."""
    plan = plan_columns(model, list(source.columns) + list(source.text), columns=merged_map(source.implied, mapping),
                        constants=fixed,
                        where=source.where)
    used = plan.used_as
    rows = [["log column", "used as"]] + [[one_line(c), used.get(c, "(words: ignored)" if c in source.text
                                                                         else "(ignored)")] for c in plan.theirs]
    length = len(next(iter(source.columns.values()))) if source.columns else 0
    print(f"{source.where}: {length} rows, {len(plan.theirs)} columns" + (f" ({source.format})" if source.format !=
                                                                            "table" else ""))
    print(render.text_table(rows, align="<<"))
    for name, value in plan.constants.items():
        print(f"{name} = {value:g} throughout (--set)")
    if not plan.has_time:
        print("t: not found (map it, or give --log-dt)")
    if plan.missing_positions:
        print(f"missing (map them, or --set a constant): {', '.join(plan.missing_positions)}")
    derived = [d.name for d in plan.derived]
    if len(derived) == 2 * model.n:
        print("qd, qdd: differentiated from q for every joint")
    elif derived:
        print(f"differentiated: {', '.join(derived)}")
    return 0


def run(args) -> int:
    model = load_robot_argument(args)
    mapping, fixed = column_map(args), constants(args)
    joint_friction, payloads, wrenches = friction(args, model), payload_arguments(args), wrench_arguments(args)
    for w in wrenches:
        model.frame(w.link)
    joint_drives = drives_argument(args, model)
    if joint_drives is not None and args.retime:
        raise UsageError("--retime scales the motion's rates, not the drives' offsets and rotor torques: run it "
                         "without --drives")
    if args.margin is not None and not args.retime:
        raise UsageError("--margin is the share of the limits --retime keeps clear of: give --retime")
    margin = FLAGS["--margin"]["default"] if args.margin is None else args.margin
    check_log_outputs(args, model)  # fail before reading a long log
    constants_k = (None if args.torque_constant is None
                   else joint_values(args.torque_constant, "--torque-constant", model))
    bar = progress_bar(args, total=None, unit="step")
    try:
        bar.set_description("reading the log")
        source = open_log_argument(args, model, args.log)
        if args.columns:
            return _list_columns(source, model, mapping, fixed)
        bar.set_description("differentiating")
        rows = progress_callback(bar)

        def progress(done, total):
            bar.total = total
            bar.set_description("joint torques" if done >= total // 3 else "differentiating")
            rows(done, total)

        result = torques_from_log(model, source, dt=args.log_dt, columns=mapping, window=args.smooth, constants=fixed,
                                  time_unit=args.time_unit, friction=joint_friction, payload=payloads, wrench=wrenches,
                                  compiled=False if args.no_compile else None, resample=args.resample,
                                  split_gaps=args.split_gaps, repair=args.repair, torque_constants=constants_k,
                                  progress=progress, drives=joint_drives)
    finally:
        bar.close()
    header, data = result.table(with_state=args.with_state)
    # What was derived and which options changed the torques are said at the top of the file
    # ('#' lines, which read_table and pandas' comment='#' skip); a plain run writes a plain CSV.
    notes = list(result.notes) + drives_note(args, joint_drives)
    extra = [one_line(line) for line in notes + settings(args, result.model, payloads, wrenches, joint_friction)]
    comments = [f"course-dynamics torques {model.name} from {args.log}"] + extra if extra else []
    report = result.report
    timing = retime(result, joint_friction, margin) if args.retime else None
    if timing is not None and timing.k is not None:
        retimed = retimed_log(result, timing.k, joint_friction, wrenches)
        header, data = retimed.table(with_state=True)
        comments = [f"course-dynamics torques {model.name} from {args.log}, retimed", one_line(timing.describe())]
        comments += extra
    # strict JSON of every figure: a result beyond floating-point range is an error before any file is written
    document = render.json_text(dict(robot=model.name, log=str(args.log), rows=len(result.t), out=args.out,
                                     plot=args.plot, notes=notes, **report.record(),
                                     residuals=None if result.residuals is None else result.residuals.record(),
                                     **({} if timing is None else dict(retiming=timing.record()))))
    if args.out == io.STDOUT and not args.json:
        # before the CSV: a reader that stops early (| head) still sees it
        _print_report(result, sys.stderr, timing, notes)
    if args.plot:
        from ...output.plotting import plot_torques

        plot_torques(result, args.plot)
    if args.out and not (timing is not None and timing.k is None):   # no k: no retimed log to write
        io.write_csv(args.out, header, data, comments=comments)
    if args.json:
        sys.stdout.write(document + "\n")
        return 1 if report.exceeded else 0
    if args.out != io.STDOUT:
        _print_report(result, sys.stdout, timing, notes)
    if args.out and args.out != io.STDOUT and not (timing is not None and timing.k is None):
        what = "the retimed log" if timing is not None else "joint torques"
        print(f"wrote {len(result.t)} rows of {what} to {args.out}", file=sys.stderr)
    return 1 if report.exceeded else 0


def _print_report(result, stream, timing, notes) -> None:
    report, model = result.report, result.model
    for note in notes:
        print(f"note: {one_line(note)}", file=stream)
    rows = [["joint", "peak |tau|", "rms tau", "effort limit", "used", "peak |qd|", "velocity limit", "used"]]
    for r in report.rows():
        band = "" if not r["peak_tau_band"] else f" ±{r['peak_tau_band']:.2g}"
        rows.append([r["joint"], f"{r['peak_tau']:.4g}{band}", f"{r['rms_tau']:.4g}", _limit(r["effort_limit"]),
                     _share(r["effort_used"]), f"{r['peak_qd']:.4g}", _limit(r["velocity_limit"]),
                     _share(r["velocity_used"])])
    print(f"robot {model.name}: {len(result.t)} samples over {result.t[-1] - result.t[0]:.6g} s "
          "(tau in N m or N; rates in rad/s or m/s)", file=stream)
    print(render.text_table(rows, align="<>>>>>>>"), file=stream)
    for v in report.violations:
        print(f"LIMIT EXCEEDED: {v.describe()}", file=stream)
    for v in report.uncertain:
        print(f"warning: {v.describe()}", file=stream)
    if result.residuals is not None:
        rows = [["joint", "rms tau_meas", "rms residual", "peak residual", "at t", "R^2"]]
        for r in result.residuals.joints:
            rows.append([r.joint, f"{r.rms_measured:.4g}", f"{r.rms:.4g}", f"{r.peak:.4g}", seconds(r.peak_t),
                         "-" if r.r2 is None else f"{max(r.r2, -1e6):.4g}" if r.r2 < -1 else f"{r.r2:.4f}"])
        print(f"model against the robot (residual = measured - ours; measured: {result.residuals.source}):",
              file=stream)
        print(render.text_table(rows, align="<>>>>>"), file=stream)
    if report.peak_band is not None and np.any(report.peak_band):
        print("(± is 2 sigma of the torque at the peak: what differentiating the rates may have got wrong)",
              file=stream)
    if report.exceeded:
        print("a limit is exceeded", file=stream)
    elif report.uncertain:
        print("every joint stays within its limits, but not beyond the uncertainty of the rates (see the warnings)",
              file=stream)
    else:
        print("every joint stays within its limits", file=stream)
    if timing is not None:
        print(timing.describe() if timing.k is not None else f"cannot retime: {timing.describe()}", file=stream)


def _limit(value) -> str:
    return "-" if value is None else f"{value:.4g}"


def _share(value) -> str:
    return "-" if value is None else (f"{100 * value:.0f}%" if value < 1e6 else f"{100 * value:.3g}%")

"""``course-dynamics torques``: the joint torques a logged trajectory needs, and a limits report."""
from __future__ import annotations

import sys

import numpy as np

from ...output import io, render
from ...tools.limits import seconds
from ...tools.loads import Payload, Wrench, payload_link
from ...tools.columns import merged_map, parse_column_map, plan_columns
from ...tools.logs import TIME_UNITS, torques_from_log
from ...tools.sources import FORMATS, open_log
from ...tools.tables import DECIMALS
from ..options import (
    UsageError,
    add_friction_arguments,
    add_robot_argument,
    friction,
    joint_values,
    load_robot_argument,
    numbers,
)

HELP = "joint torques along a trajectory log, and a limits report"
SLOW_SAMPLES = 0.5  # s between samples: more suggests a t column in ms read as seconds
DESCRIPTION = (
    "Read a trajectory log - a table (comma, semicolon, tab or whitespace separated; columns t, q_<joint> and "
    "optionally qd_<joint>, qdd_<joint>, tau_meas_<joint>, current_<joint>; other columns, numbers or words, are "
    "ignored), a UR RTDE recording, or a ROS 1/ROS 2 bag or MCAP file (sensor_msgs/JointState by joint name, or "
    "Franka's FrankaState) - and write t, tau_<joint>: tau = M qdd + V + G (+ friction, payload, wrench). Missing "
    "rates are differentiated from q (Savitzky-Golay); dropped samples are filled and the fill is reported. Prints "
    "each joint's peak and RMS torque, peak rate and the share of the URDF's effort and velocity limits used, and, "
    "when the log holds measured torques (or currents and --torque-constant), the residual of our model against "
    "them. Exit 0 within the limits, 1 when a limit is exceeded, 2 on bad input.")


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    add_log_arguments(parser, "the trajectory log (a CSV as 'simulate' writes, or a robot's own log)")
    parser.add_argument("--out", help="output CSV, or - for standard output (written whole or not at all)")
    parser.add_argument("--columns", action="store_true",
                        help="list the log's columns and which of them would be used, then stop")
    parser.add_argument("--with-state", action="store_true", help="also write q_, qd_, qdd_ columns (as used)")
    add_friction_arguments(parser)
    parser.add_argument("--payload", metavar="MASS[@LINK][,CX,CY,CZ]", action="append",
                        help="a payload of MASS kg fixed to LINK (default: the tip, the last link on the last moving "
                             "body, e.g. ur5's tool0), its centre of mass at CX,CY,CZ m in the link's frame "
                             "(may be repeated)")
    parser.add_argument("--payload-size", metavar="A,B,C",
                        help="make the (single) payload a uniform box with these edges (m) along the link's axes "
                             "(default: a point mass)")
    parser.add_argument("--wrench", metavar="LINK:FX,FY,FZ[,NX,NY,NZ]", action="append",
                        help="force (N) and moment (N m, about the link's origin) the robot exerts on its "
                             "surroundings at LINK, in base coordinates; adds J^T F, the static-force relation of chapter 5 (may be repeated)")
    parser.add_argument("--plot", metavar="FILE", help="draw tau(t) per joint with the effort limits: .png, .svg or .html")
    parser.add_argument("--json", action="store_true", help="print the limits report as JSON")
    parser.add_argument("--no-compile", action="store_true",
                        help="use the interpreted recursion even for a log long enough to compile the model for "
                             "(about 20 000 rows)")


def add_log_arguments(parser, log_help: str) -> None:
    """The options that say how to read a log: shared by every command that reads one (torques, identify)."""
    parser.add_argument("--trajectory", "--log", dest="trajectory", required=True, metavar="LOG", help=log_help)
    parser.add_argument("--format", choices=FORMATS, default="auto",
                        help="how to read the log: a table, a UR RTDE recording (timestamp, actual_q_i, actual_qd_i, "
                             "actual_current_i; joint i is the URDF's i-th), a ROS bag/MCAP; default auto: a bag by "
                             "its file, an RTDE recording by its header, else a table")
    parser.add_argument("--topic", help="a bag's topic (default /joint_states, else its one joint-state topic)")
    parser.add_argument("--resample", type=float, metavar="HZ",
                        help="put the log on an even clock at HZ (cubic splines) before differentiating")
    parser.add_argument("--split-gaps", action="store_true",
                        help="treat the pieces between gaps longer than 5 sample periods as separate segments "
                             "(each differentiated on its own) instead of refusing the log")
    parser.add_argument("--torque-constant", metavar="K1,K2,...",
                        help="motor torque constants, N m/A, one per joint: logged currents times these are the "
                             "measured torques")
    parser.add_argument("--map", metavar="OURS=THEIRS,...|FILE.toml", action="append",
                        help="our column names for the log's, e.g. q_shoulder_pan_joint=joint1_pos, or a TOML file "
                             "of such lines (may be repeated)")
    parser.add_argument("--set", metavar="OURS=VALUE,...", action="append",
                        help="a constant for a signal the log lacks, e.g. q_panda_finger_joint1=0.04 (a constant q "
                             "has zero rates; may be repeated)")
    parser.add_argument("--decimal", choices=DECIMALS,
                        help="the log's decimal separator, when it cannot tell (default: read from the log; a log "
                             "that could be read two ways is refused)")
    parser.add_argument("--dt", type=float, help="sample step, s, for a log without a t column")
    parser.add_argument("--time-unit", choices=tuple(TIME_UNITS), default="s",
                        help="the unit of the log's t column (default s)")
    parser.add_argument("--smooth", type=int, metavar="W",
                        help="one Savitzky-Golay window in samples (odd, >= 5) for differentiated rates (default: "
                             "chosen per joint from the log's own noise)")


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


def column_map(args) -> dict[str, str]:
    mapping = {}
    for text in args.map or ():
        for ours, theirs in parse_column_map(text).items():
            if ours in mapping:
                raise UsageError(f"--map: '{ours}' is mapped twice")
            mapping[ours] = theirs
    return mapping


def constants(args) -> dict[str, float]:
    values = {}
    for text in args.set or ():
        for item in filter(None, (part.strip() for part in text.split(","))):
            name, sep, value = item.partition("=")
            try:
                number = float(value)
            except ValueError:
                number = None
            if not sep or number is None:
                raise UsageError(f"--set entries must be OURS=VALUE, e.g. q_panda_finger_joint1=0.04; got '{item}'")
            if name.strip() in values:
                raise UsageError(f"--set: '{name.strip()}' is set twice")
            values[name.strip()] = number
    return values


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
    rows = [["log column", "used as"]] + [[render.one_line(c), used.get(c, "(words: ignored)" if c in source.text
                                                                         else "(ignored)")] for c in plan.theirs]
    length = len(next(iter(source.columns.values()))) if source.columns else 0
    print(f"{source.where}: {length} rows, {len(plan.theirs)} columns" + (f" ({source.format})" if source.format !=
                                                                            "table" else ""))
    print(render.text_table(rows, align="<<"))
    for name, value in plan.constants.items():
        print(f"{name} = {value:g} throughout (--set)")
    if not plan.has_time:
        print("t: not found (map it, or give --dt)")
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
    if args.out == io.STDOUT and args.json:
        raise UsageError("--out - and --json both want standard output; write the CSV to a file")
    if args.plot:
        from ...output.plotting import PLOT_FORMATS, plot_format

        plot_format(args.plot, PLOT_FORMATS + ("html",))
    maps = [text for text in args.map or () if "=" not in text]  # map files are inputs too
    io.check_distinct([args.trajectory, model.source or None, *maps], [args.out, args.plot])
    for target in (args.out, args.plot):  # fail before reading a long log
        if target:
            io.check_writable(target)
    constants_k = None if args.torque_constant is None else joint_values(args.torque_constant, "--torque-constant", model)
    source = open_log(args.trajectory, model, format=args.format, topic=args.topic, decimal=args.decimal)
    if args.columns:
        return _list_columns(source, model, mapping, fixed)
    result = torques_from_log(model, source, dt=args.dt, columns=mapping, window=args.smooth, constants=fixed,
                              time_unit=args.time_unit, friction=joint_friction, payload=payloads, wrench=wrenches,
                              compiled=False if args.no_compile else None, resample=args.resample,
                              split_gaps=args.split_gaps, torque_constants=constants_k)
    header, data = result.table(with_state=args.with_state)
    # What was derived and which options changed the torques are said at the top of the file
    # ('#' lines, which read_table and pandas' comment='#' skip); a plain run writes a plain CSV.
    extra = [render.one_line(line) for line in list(result.notes) + settings(args, result.model, payloads, wrenches,
                                                                            joint_friction)]
    comments = [f"course-dynamics torques {model.name} from {args.trajectory}"] + extra if extra else []
    report = result.report
    # strict JSON of every figure: a result beyond floating-point range is an error before any file is written
    document = render.json_text(dict(robot=model.name, log=str(args.trajectory), rows=len(result.t), out=args.out,
                                     plot=args.plot, notes=list(result.notes), **report.record(),
                                     residuals=None if result.residuals is None else result.residuals.record()))
    step = float(np.median(np.diff(result.t))) if len(result.t) > 1 else 0.0
    if step > SLOW_SAMPLES:
        print(f"warning: the samples are {step:g} s apart; if t is not in seconds, give --time-unit", file=sys.stderr)
    if args.out == io.STDOUT and not args.json:
        _print_report(result, sys.stderr)  # before the CSV: a reader that stops early (| head) still sees it
    if args.plot:
        from ...output.plotting import plot_torques

        plot_torques(result, args.plot)
    if args.out:
        io.write_csv(args.out, header, data, comments=comments)
    if args.json:
        sys.stdout.write(document + "\n")
        return 1 if report.exceeded else 0
    if args.out != io.STDOUT:
        _print_report(result, sys.stdout)
    if args.out and args.out != io.STDOUT:
        print(f"wrote {len(result.t)} rows of joint torques to {args.out}", file=sys.stderr)
    return 1 if report.exceeded else 0


def _print_report(result, stream) -> None:
    report, model = result.report, result.model
    for note in result.notes:
        print(f"note: {render.one_line(note)}", file=stream)
    rows = [["joint", "peak |tau|", "rms tau", "effort limit", "used", "peak |qd|", "velocity limit", "used"]]
    for r in report.rows():
        band = "" if not r["peak_tau_band"] else f" ±{r['peak_tau_band']:.2g}"
        rows.append([r["joint"], f"{r['peak_tau']:.4g}{band}", f"{r['rms_tau']:.4g}", _limit(r["effort_limit"]),
                     _share(r["effort_used"]), f"{r['peak_qd']:.4g}", _limit(r["velocity_limit"]), _share(r["velocity_used"])])
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
        print("(± is 2 sigma of the torque at the peak: what differentiating the rates may have got wrong)", file=stream)
    if report.exceeded:
        print("a limit is exceeded", file=stream)
    elif report.uncertain:
        print("every joint stays within its limits, but not beyond the uncertainty of the rates (see the warnings)",
              file=stream)
    else:
        print("every joint stays within its limits", file=stream)


def _limit(value) -> str:
    return "-" if value is None else f"{value:.4g}"


def _share(value) -> str:
    return "-" if value is None else (f"{100 * value:.0f}%" if value < 1e6 else f"{100 * value:.3g}%")

"""``course-dynamics torques``: the joint torques a logged trajectory needs, and a limits report."""
from __future__ import annotations

import sys

from ... import io, render
from ...loads import Payload, Wrench
from ...logs import (
    COMPILE_FROM_ROWS,
    KINDS,
    as_columns,
    parse_column_map,
    torques_from_log,
)
from ..options import (
    UsageError,
    add_friction_arguments,
    add_robot_argument,
    friction,
    load_robot_argument,
    numbers,
    print_json,
)

HELP = "joint torques along a trajectory log, and a limits report"
DESCRIPTION = (
    "Read a trajectory log (comma, semicolon or tab separated; columns t, q_<joint> and optionally qd_<joint>, "
    "qdd_<joint>; other columns are ignored) and write t, tau_<joint>: tau = M qdd + V + G (+ friction, payload, "
    "wrench). Missing rates are differentiated from q (Savitzky-Golay). Prints each joint's peak and RMS torque, "
    "peak rate and the share of the URDF's effort and velocity limits used. Exit 0 within the limits, 1 when a "
    "limit is exceeded, 2 on bad input.")


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    parser.add_argument("--trajectory", "--log", dest="trajectory", required=True, metavar="LOG",
                        help="the trajectory log (a CSV as 'simulate' writes, or a robot's own log)")
    parser.add_argument("--out", help="output CSV, or - for standard output (written whole or not at all)")
    parser.add_argument("--columns", action="store_true",
                        help="list the log's columns and which of them would be used, then stop")
    parser.add_argument("--map", metavar="OURS=THEIRS,...|FILE.toml",
                        help="our column names for the log's, e.g. q_shoulder_pan_joint=joint1_pos, or a TOML file "
                             "of such lines")
    parser.add_argument("--dt", type=float, help="sample step, s, for a log without a t column")
    parser.add_argument("--smooth", type=int, metavar="W",
                        help="Savitzky-Golay window in samples (odd, >= 5) for differentiated rates "
                             "(default: about 20 ms of samples, at least 7)")
    parser.add_argument("--with-state", action="store_true", help="also write q_, qd_, qdd_ columns (as used)")
    add_friction_arguments(parser)
    parser.add_argument("--payload", metavar="MASS[@LINK][,CX,CY,CZ]",
                        help="a payload of MASS kg fixed to LINK (default: the last joint's link), its centre of mass "
                             "at CX,CY,CZ m in the link's frame")
    parser.add_argument("--payload-size", metavar="A,B,C",
                        help="make the payload a uniform box with these edges (m) along the link's axes "
                             "(default: a point mass)")
    parser.add_argument("--wrench", metavar="LINK:FX,FY,FZ[,NX,NY,NZ]",
                        help="force (N) and moment (N m, about the link's origin) the robot exerts on its "
                             "surroundings at LINK, in base coordinates; adds J^T F (6.105)")
    parser.add_argument("--plot", metavar="FILE", help="draw tau(t) per joint with the effort limits: .png, .svg or .html")
    parser.add_argument("--json", action="store_true", help="print the limits report as JSON")
    parser.add_argument("--no-compile", action="store_true",
                        help=f"use the interpreted recursion even for logs of {COMPILE_FROM_ROWS} rows or more")


def payload_argument(args) -> Payload | None:
    if args.payload is None:
        if args.payload_size is not None:
            raise UsageError("--payload-size needs --payload")
        return None
    head, *rest = args.payload.split(",")
    mass_text, _, link = head.partition("@")
    try:
        mass = float(mass_text)
    except ValueError:
        raise UsageError(f"--payload must be MASS[@LINK][,CX,CY,CZ], got '{args.payload}'") from None
    com = numbers(",".join(rest), "--payload") if rest else (0.0, 0.0, 0.0)
    if len(com) != 3:
        raise UsageError(f"--payload: the centre of mass needs three numbers CX,CY,CZ, got '{','.join(rest)}'")
    size = None if args.payload_size is None else numbers(args.payload_size, "--payload-size")
    return Payload(mass=mass, link=link.strip() or None, com=tuple(com), size=None if size is None else tuple(size))


def wrench_argument(args) -> Wrench | None:
    if args.wrench is None:
        return None
    link, sep, values = args.wrench.partition(":")
    F = numbers(values, "--wrench") if sep else ()
    if not link.strip() or len(F) not in (3, 6):
        raise UsageError(f"--wrench must be LINK:FX,FY,FZ[,NX,NY,NZ], got '{args.wrench}'")
    return Wrench(link=link.strip(), force=tuple(F[:3]), moment=tuple(F[3:]) if len(F) == 6 else (0.0, 0.0, 0.0))


def _list_columns(table, model, mapping) -> int:
    columns, _ = as_columns(table)
    used = {mapping.get(name, name): name for name in ["t"] + io.joint_columns(KINDS, model.joint_names)}
    rows = [["log column", "used as"]] + [[c, used.get(c, "(ignored)")] for c in columns]
    print(f"{table.path}: {len(table.data)} rows, {len(columns)} columns")
    print(render.text_table(rows, align="<<"))
    return 0


def run(args) -> int:
    model = load_robot_argument(args)
    mapping = parse_column_map(args.map) if args.map else {}
    joint_friction, payload, wrench = friction(args, model), payload_argument(args), wrench_argument(args)
    if wrench is not None:
        model.frame(wrench.link)
    if args.out == io.STDOUT and args.json:
        raise UsageError("--out - and --json both want standard output; write the CSV to a file")
    if args.plot:
        from ...plotting import PLOT_FORMATS, plot_format

        plot_format(args.plot, PLOT_FORMATS + ("html",))
    for target in (args.out, args.plot):  # fail before reading a long log
        if target:
            io.check_writable(target)
    table = io.read_table(args.trajectory)
    if args.columns:
        return _list_columns(table, model, mapping)
    result = torques_from_log(model, table, dt=args.dt, columns=mapping, window=args.smooth, friction=joint_friction,
                              payload=payload, wrench=wrench, compiled=False if args.no_compile else None)
    header, data = result.table(with_state=args.with_state)
    # Derived signals are said at the top of the file (a '#' line, which read_table and pandas' comment='#' skip).
    comments = [f"course-dynamics torques {model.name} from {args.trajectory}"] + list(result.notes) if result.notes else []
    # Every output is computed before any is written: the plot first (it can fail), then the CSV.
    if args.plot:
        from ...plotting import plot_torques

        plot_torques(result, args.plot)
    if args.out:
        io.write_csv(args.out, header, data, comments=comments)
    report = result.report
    if args.json:
        print_json(dict(robot=model.name, log=str(args.trajectory), rows=len(result.t), out=args.out, plot=args.plot,
                        notes=list(result.notes), **report.record()))
        return 1 if report.exceeded else 0
    stream = sys.stderr if args.out == io.STDOUT else sys.stdout
    for note in result.notes:
        print(f"note: {note}", file=stream)
    rows = [["joint", "peak |tau|", "rms tau", "effort limit", "used", "peak |qd|", "velocity limit", "used"]]
    for r in report.rows():
        rows.append([r["joint"], f"{r['peak_tau']:.4g}", f"{r['rms_tau']:.4g}", _limit(r["effort_limit"]),
                     _share(r["effort_used"]), f"{r['peak_qd']:.4g}", _limit(r["velocity_limit"]), _share(r["velocity_used"])])
    print(f"robot {model.name}: {len(result.t)} samples over {result.t[-1] - result.t[0]:.6g} s "
          "(tau in N m or N; rates in rad/s or m/s)", file=stream)
    print(render.text_table(rows, align="<>>>>>>>"), file=stream)
    for v in report.violations:
        print(f"LIMIT EXCEEDED: {v.describe()}", file=stream)
    print("a limit is exceeded" if report.exceeded else "every joint stays within its limits", file=stream)
    if args.out and args.out != io.STDOUT:
        print(f"wrote {len(result.t)} rows of joint torques to {args.out}", file=sys.stderr)
    return 1 if report.exceeded else 0


def _limit(value) -> str:
    return "-" if value is None else f"{value:.4g}"


def _share(value) -> str:
    return "-" if value is None else f"{100 * value:.0f}%"

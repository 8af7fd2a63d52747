"""``course-dynamics trace``: the Newton–Euler iterations link by link, numeric or symbolic."""
from __future__ import annotations

from ...output import render
from ..options import (
    UsageError,
    add_robot_argument,
    check_finite,
    joint_values,
    load_robot_argument,
    print_json,
    symbol_names,
)

HELP = "the Newton-Euler iterations link by link (numeric or symbolic)"
DESCRIPTION = ("Show omega, omega_dot, v_dot, v_dot_C, F, N (outward, 6.45-6.50) and f, n, tau (inward, 6.51-6.53) "
               "for every link, each in its own frame, as the notes' worked example lays them out.")


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    parser.add_argument("--q", help="joint positions (numeric trace)")
    parser.add_argument("--qd", help="joint velocities (default 0)")
    parser.add_argument("--qdd", help="joint accelerations (default 0)")
    parser.add_argument("--symbolic", action="store_true", help="symbolic trace in q_<joint>, qd_<joint>, qdd_<joint>")
    parser.add_argument("--symbols", help="with --symbolic: parameters kept as symbols, e.g. m1,m2,l1,l2,g")
    parser.add_argument("--decimal", type=int, metavar="N",
                        help="with --symbolic: the URDF's numbers as N-digit decimals instead of exact fractions")
    parser.add_argument("--format", choices=render.TRACE_FORMATS, default="table", help="output format (default table)")


def run(args) -> int:
    from ...tools.trace import trace

    model = load_robot_argument(args)
    if args.symbolic:
        result = trace(model, None, None, None, symbols=symbol_names(args.symbols), decimals=args.decimal)
    else:
        if args.q is None:
            raise UsageError("--q is required unless --symbolic is given")
        result = trace(model, joint_values(args.q, "--q", model), joint_values(args.qd, "--qd", model),
                       joint_values(args.qdd, "--qdd", model))
        check_finite("the result", result.tau)
    if args.format == "json":
        print_json(render.trace_record(result))
    else:
        print(render.trace_latex(result) if args.format == "latex" else render.trace_table(result))
    return 0

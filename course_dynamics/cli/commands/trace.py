"""``course-dynamics trace``: the Newton–Euler iterations link by link, numeric or symbolic."""
from __future__ import annotations

from ...output import render
from ..flags import output_format
from ..options import (
    UsageError,
    add_all,
    add_renamed,
    add_robot_argument,
    check_finite,
    joint_values,
    load_robot_argument,
    print_json,
    symbol_names,
)
from . import COMMANDS

HELP = COMMANDS["trace"]
DESCRIPTION = ("Show omega, omega_dot, v_dot, v_dot_C, F, N (outward, 6.45-6.50) and f, n, tau (inward, 6.51-6.53) "
               "for every link, each in its own frame, as the notes' worked example lays them out: numeric at --q, "
               "--qd, --qdd, or symbolic (--symbolic, with --symbols kept as symbols and --digits for the URDF's "
               "numbers). A table, --latex, or --json (robot, joints, symbolic, links: each link's quantities).")


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    add_all(parser, "--q", "--qd", "--qdd", "--symbolic", "--symbols", "--digits")
    output = parser.add_mutually_exclusive_group()
    add_all(output, "--latex", "--json")
    add_renamed(parser, "--decimal", "--digits")
    add_renamed(parser, "--format", "--json or --latex", **output_format(render.TRACE_FORMATS))


def run(args) -> int:
    from ...tools.trace import trace

    model = load_robot_argument(args)
    if args.symbolic:
        result = trace(model, None, None, None, symbols=symbol_names(args.symbols), decimals=args.digits)
    else:
        if args.q is None:
            raise UsageError("--q is required unless --symbolic is given")
        result = trace(model, joint_values(args.q, "--q", model), joint_values(args.qd, "--qd", model),
                       joint_values(args.qdd, "--qdd", model))
        check_finite("the result", result.tau)
    if args.json:
        print_json(render.trace_record(result))
    else:
        print(render.trace_latex(result) if args.latex else render.trace_table(result))
    return 0

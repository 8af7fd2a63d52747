"""``course-dynamics derive``: closed-form τ, M, V, G and Craig's B, C (symbolic)."""
from __future__ import annotations

from ...core.parameters import MAX_SYMBOLIC_JOINTS
from ...output import render
from ..flags import output_format
from ..options import add_all, add_renamed, add_robot_argument, load_robot_argument, print_json, symbol_names
from . import COMMANDS

HELP = COMMANDS["derive"]
DESCRIPTION = ("Derive the equations of motion symbolically by Newton-Euler or by Lagrange: "
               "tau = M(q) qdd + B(q)[qd qd] + C(q)[qd^2] + G(q) (6.63). Joint variables are q_<joint>, qd_<joint>, "
               "qdd_<joint>; parameters not named in --symbols are the URDF's numbers, made exact "
               "(or, with --digits N, N-digit decimals). Markdown with LaTeX math, --latex, or --json: keys joints, "
               "tau, M, V, G, B, C, each entry an expression string in q_<joint>, qd_<joint>, qdd_<joint> and the "
               "parameters.")


def add_arguments(parser) -> None:
    add_robot_argument(parser, help=f"URDF file or shipped robot name (at most {MAX_SYMBOLIC_JOINTS} joints)")
    add_all(parser, "--symbols", "--method", "--digits")
    output = parser.add_mutually_exclusive_group()
    add_all(output, "--latex", "--json")
    add_renamed(parser, "--decimal", "--digits")
    add_renamed(parser, "--format", "--json or --latex", **output_format(render.DERIVATION_FORMATS))


def run(args) -> int:
    from ...core.symbolic import derive

    model = load_robot_argument(args)
    derivation = derive(model, symbol_names(args.symbols), method=args.method, decimals=args.digits)
    if args.json:
        print_json(render.derivation_record(derivation))
    else:
        print(render.derivation_text(derivation, "latex" if args.latex else "markdown"))
    return 0

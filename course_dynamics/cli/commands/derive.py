"""``course-dynamics derive``: closed-form τ, M, V, G and Craig's B, C (symbolic)."""
from __future__ import annotations

from ...core.parameters import MAX_SYMBOLIC_JOINTS
from ...core.symbolic import METHODS
from ...output import render
from ..options import add_robot_argument, load_robot_argument, print_json, symbol_names

HELP = "closed-form tau, M, V, G and Craig's B, C (symbolic)"
DESCRIPTION = ("Derive the equations of motion symbolically by Newton-Euler or by Lagrange: "
               "tau = M(q) qdd + B(q)[qd qd] + C(q)[qd^2] + G(q) (6.63). Joint variables are q_<joint>, qd_<joint>, "
               "qdd_<joint>; parameters not named in --symbols are the URDF's numbers, made exact.")


def add_arguments(parser) -> None:
    add_robot_argument(parser, help=f"URDF file or shipped robot name (at most {MAX_SYMBOLIC_JOINTS} joints)")
    parser.add_argument("--symbols", help="parameters kept symbolic: m<i>, l<i> (link length), lc<i> (distance to "
                                          "the link's centre of mass), I<xx|yy|zz|xy|xz|yz><i>, g (a one-joint robot "
                                          "also takes m, l, lc)")
    parser.add_argument("--method", choices=METHODS, default="newton-euler")
    parser.add_argument("--decimal", type=int, metavar="N",
                        help="write the URDF's numbers as N-digit decimals instead of exact fractions (real robots)")
    parser.add_argument("--format", choices=render.DERIVATION_FORMATS, default="markdown",
                        help="json has keys joints, tau, M, V, G, B, C; each entry an expression string in q_<joint>, qd_<joint>, "
                             "qdd_<joint> and the parameters")


def run(args) -> int:
    from ...core.symbolic import derive

    model = load_robot_argument(args)
    derivation = derive(model, symbol_names(args.symbols), method=args.method, decimals=args.decimal)
    if args.format == "json":
        print_json(render.derivation_record(derivation))
    else:
        print(render.derivation_text(derivation, args.format))
    return 0

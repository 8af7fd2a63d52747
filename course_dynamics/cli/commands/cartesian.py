"""``course-dynamics cartesian``: operational-space dynamics Mx, Vx, Gx (6.99) of a frame."""
from __future__ import annotations

import numpy as np

from ...core.cartesian import EXPRESSED_IN, MAX_CONDITION, ROW_NAMES, cartesian_dynamics
from ...output import render
from ..options import (
    UsageError,
    add_robot_argument,
    check_finite,
    joint_values,
    load_robot_argument,
    print_json,
)

HELP = "Cartesian-space dynamics Mx, Vx, Gx (6.99) of a frame"
DESCRIPTION = ("Jacobian J, its time derivative, and F = Mx Xdd + Vx + Gx (6.91) for a URDF link or frame. "
               "The selected task rows must make J square (as many rows as joints).")


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    parser.add_argument("--frame", required=True, help="URDF link name of the task frame")
    parser.add_argument("--q", required=True, help="joint positions")
    parser.add_argument("--qd", help="joint velocities (default 0)")
    parser.add_argument("--rows", help=f"task rows among {','.join(ROW_NAMES)} (default all six)")
    parser.add_argument("--expressed-in", choices=EXPRESSED_IN, default="base",
                        help="coordinates of J and the task: the base frame, or the task frame itself as Craig's 3J "
                             "(default base)")
    parser.add_argument("--max-condition", type=float, default=MAX_CONDITION,
                        help=f"cond(J) above which J counts as singular (default {MAX_CONDITION:g})")
    parser.add_argument("--json", action="store_true",
                        help="print JSON with keys joints, frame, rows, J, J_dot, Mx, Vx, Gx, condition")


def run(args) -> int:
    if not (np.isfinite(args.max_condition) and args.max_condition >= 1):
        raise UsageError(f"--max-condition must be a finite number of at least 1, got {args.max_condition}")
    model = load_robot_argument(args)
    q = joint_values(args.q, "--q", model)
    qd = joint_values(args.qd, "--qd", model)
    rows = args.rows.split(",") if args.rows else None
    terms = cartesian_dynamics(model, q, qd, args.frame, expressed_in=args.expressed_in, rows=rows,
                               max_condition=args.max_condition)
    check_finite("the result", terms.J, terms.J_dot, terms.Mx, terms.Vx, terms.Gx)
    document = dict(joints=list(model.joint_names), frame=terms.frame, rows=list(terms.rows), J=terms.J.tolist(),
                    J_dot=terms.J_dot.tolist(), Mx=terms.Mx.tolist(), Vx=terms.Vx.tolist(), Gx=terms.Gx.tolist(),
                    condition=terms.condition)
    if args.json:
        print_json(document)
        return 0
    print(f"robot {model.name}, frame '{terms.frame}' ({args.expressed_in} coordinates), task rows "
          f"{', '.join(terms.rows)}; cond(J) = {terms.condition:.4g}")
    for label in ("J", "J_dot", "Mx"):
        print(f"\n{label}:")
        print("\n".join(render.matrix_lines([f"{r:<3}" for r in terms.rows], document[label])))
    print("\nVx: " + " ".join(f"{x:.6g}" for x in terms.Vx))
    print("Gx: " + " ".join(f"{x:.6g}" for x in terms.Gx))
    return 0

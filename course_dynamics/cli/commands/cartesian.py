"""``course-dynamics cartesian``: operational-space dynamics Mx, Vx, Gx (6.99) of a frame."""
from __future__ import annotations

import numpy as np

from ...core.cartesian import cartesian_dynamics
from ...output import render
from ..options import (
    UsageError,
    add,
    add_all,
    add_robot_argument,
    check_finite,
    joint_values,
    load_robot_argument,
    print_json,
)
from . import COMMANDS

HELP = COMMANDS["cartesian"]
DESCRIPTION = ("Jacobian J, its time derivative, and F = Mx Xdd + Vx + Gx (6.91) for a URDF link or frame. "
               "The selected task rows must make J square (as many rows as joints). --json prints keys joints, frame, "
               "rows, J, J_dot, Mx, Vx, Gx, condition.")


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    add(parser, "--frame", required=True)
    add(parser, "--q", required=True)
    add_all(parser, "--qd", "--rows", "--expressed-in", "--max-condition", "--json")


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

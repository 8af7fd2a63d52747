"""``course-dynamics torques``: inverse dynamics along a trajectory CSV."""
from __future__ import annotations

import sys

import numpy as np

from ... import io
from ...newton_euler import inverse_dynamics
from ..options import add_robot_argument, load_robot_argument

HELP = "inverse dynamics along a trajectory CSV"
COMPILE_FROM_ROWS = 5000  # from here on a compiled model (cached after the first run) pays off
DESCRIPTION = "Read columns t, q_<joint>, qd_<joint>, qdd_<joint>; write t, tau_<joint>."


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    parser.add_argument("--trajectory", required=True, help="input CSV")
    parser.add_argument("--out", required=True, help="output CSV (written whole or not at all)")
    parser.add_argument("--no-compile", action="store_true",
                        help=f"use the interpreted recursion even for logs of {COMPILE_FROM_ROWS} rows or more")


def read_trajectory(path, joints) -> dict[str, np.ndarray]:
    """Columns t, q_<joint>, qd_<joint>, qdd_<joint>; a simulate output's tau_<joint> and energy are allowed."""
    return io.read_columns(path, ["t"] + io.joint_columns(("q", "qd", "qdd"), joints),
                           io.joint_columns(("tau",), joints) + ["energy"])


def run(args) -> int:
    model = load_robot_argument(args.urdf)
    io.check_writable(args.out)
    columns = read_trajectory(args.trajectory, model.joint_names)
    q, qd, qdd = (io.stack_joint_columns(columns, kind, model.joint_names) for kind in ("q", "qd", "qdd"))
    if len(q) >= COMPILE_FROM_ROWS and not args.no_compile:
        from ...compiled import compile_model

        tau = compile_model(model).inverse_dynamics(q, qd, qdd)
    else:
        tau = inverse_dynamics(model, q, qd, qdd)
    header = ["t"] + [f"tau_{j}" for j in model.joint_names]
    io.write_csv(args.out, header, np.column_stack([columns["t"], tau]))
    print(f"wrote {len(tau)} rows of joint torques to {args.out}", file=sys.stderr)
    return 0

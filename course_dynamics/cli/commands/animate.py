"""``course-dynamics animate``: a trajectory CSV as a self-contained HTML animation (meshcat)."""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from ...core.evaluator import inverse_dynamics
from ...core.robots import resolve
from ...output import io
from ...tools.tables import joint_columns, read_columns, stack_joint_columns
from ..animation import add_animation_options, export_animation
from ..options import UsageError, add_robot_argument, load_robot_argument

HELP = "animate a trajectory CSV as a self-contained HTML file (meshcat)"
DESCRIPTION = ("Draw the robot (URDF meshes or a stick model) and animate a trajectory with columns t and q_<joint> "
               "(a simulate output works) as meshcat keyframes, in one HTML file that opens offline in any browser.")


def add_arguments(parser) -> None:
    add_robot_argument(parser, gravity=False)
    parser.add_argument("--trajectory", required=True, help="CSV with t, q_<joint> (qd_, qdd_, tau_, energy allowed)")
    add_animation_options(parser, html_required=True)


def run(args) -> int:
    model = load_robot_argument(args)
    joints = model.joint_names
    io.check_distinct([args.trajectory], [args.html])
    io.check_writable(args.html)
    columns = read_columns(args.trajectory, ["t"] + joint_columns(("q",), joints),
                              joint_columns(("qd", "qdd", "tau"), joints) + ["energy"])
    q = stack_joint_columns(columns, "q", joints)
    tau = None
    if args.torques:
        if all(f"tau_{j}" in columns for j in joints):
            tau = stack_joint_columns(columns, "tau", joints)
        elif all(f"{k}_{j}" in columns for k in ("qd", "qdd") for j in joints):
            tau = inverse_dynamics(model, q, stack_joint_columns(columns, "qd", joints),
                                   stack_joint_columns(columns, "qdd", joints))
        else:
            raise UsageError(f"{args.trajectory}: --torques needs tau_<joint> columns, or qd_<joint> and qdd_<joint> "
                             "to compute them")
    if np.any(np.diff(columns["t"]) <= 0):
        raise UsageError(f"{args.trajectory}: times in column 't' must increase")
    export_animation(args.html, model, resolve(args.urdf), columns["t"], q, tau, args)
    size = Path(args.html).stat().st_size / 1e6
    print(f"wrote {args.html} ({size:.2f} MB, {len(q)} samples); open it in any browser, offline", file=sys.stderr)
    return 0

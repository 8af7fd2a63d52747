"""``course-dynamics info``: the joints (order, type, axis, limits, parent) and moving bodies of a robot."""
from __future__ import annotations

import numpy as np

from ...output import render
from ..options import add, add_robot_argument, load_robot_argument, print_json

HELP = "joints (order, type, axis, limits, parent) and moving bodies (mass, COM)"
DESCRIPTION = (HELP + "; --json prints them as one document (robot, urdf, base_link, n, gravity, joints, bodies).")


def add_arguments(parser) -> None:
    add_robot_argument(parser, gravity=False)
    add(parser, "--json")


def run(args) -> int:
    model = load_robot_argument(args)
    joints = [
        dict(index=j, name=b.joint, type=b.joint_type, axis=b.axis.tolist(),
             lower=None if not np.isfinite(b.lower) else b.lower, upper=None if not np.isfinite(b.upper) else b.upper,
             effort=None if not np.isfinite(b.effort) else b.effort,
             velocity=None if not np.isfinite(b.velocity) else b.velocity,
             parent_link=b.parent_link, damping=b.damping, friction=b.friction)
        for j, b in enumerate(model.bodies)
    ]
    bodies = [dict(link=b.name, joint=b.joint, mass=float(b.mass), com=b.p_com.tolist()) for b in model.bodies]
    if args.json:
        print_json(dict(robot=model.name, urdf=model.source, base_link=model.base_link, n=model.n,
                        gravity=model.gravity.tolist(), joints=joints, bodies=bodies))
        return 0
    print(f"robot {model.name} ({model.source}): {model.n} joints, base link '{model.base_link}', "
          f"gravity {model.gravity.tolist()} m/s²")
    rows = [["#", "joint", "type", "axis", "limits", "effort", "velocity", "parent link"]]
    for j in joints:
        limits = "-" if j["lower"] is None else f"[{j['lower']:g}, {j['upper']:g}]"
        axis = "(" + ", ".join(f"{a:.4g}" for a in j["axis"]) + ")"
        effort, velocity = ("-" if j[k] is None else f"{j[k]:g}" for k in ("effort", "velocity"))
        rows.append([str(j["index"]), j["name"], j["type"], axis, limits, effort, velocity, j["parent_link"]])
    print(render.text_table(rows, align="><<<<>><"))
    rows = [["moving body", "mass (kg)", "COM in body frame (m)"]]
    rows += [[b["link"], f"{b['mass']:.4g}", "(" + ", ".join(f"{c:.4g}" for c in b["com"]) + ")"] for b in bodies]
    print()
    print(render.text_table(rows, align="<><"))
    return 0

"""``course-dynamics info``: the joints (order, type, axis, limits, parent) and moving bodies of a robot."""
from __future__ import annotations

import numpy as np

from ...output import render
from ..options import add, add_robot_argument, load_robot_argument, print_json
from . import COMMANDS

HELP = COMMANDS["info"]
DESCRIPTION = (HELP + "; a joint that <mimic>s another is listed after the joints, with no coordinate of its own; "
               "--json prints them as one document (robot, urdf, base_link, n, gravity, joints, mimic_joints, "
               "bodies).")


def add_arguments(parser) -> None:
    add_robot_argument(parser, gravity=False)
    add(parser, "--json")


def run(args) -> int:
    model = load_robot_argument(args)
    def limit(value):
        return None if not np.isfinite(value) else float(value)

    # the coordinates: their limits are the model's (a coordinate with mimics: where every joint it drives can be)
    joints = [
        dict(index=j, name=b.joint, type=b.joint_type, axis=b.axis.tolist(), lower=limit(model.lower[j]),
             upper=limit(model.upper[j]), effort=limit(model.effort[j]), velocity=limit(model.velocity[j]),
             parent_link=b.parent_link, damping=b.damping, friction=b.friction)
        for j, b in enumerate(model.coordinate_bodies)
    ]
    mimics = [dict(name=b.joint, type=b.joint_type, mimics=b.mimic, multiplier=b.multiplier, offset=b.offset,
                   follows=model.joint_names[j], scale=a, shift=c, lower=limit(b.lower), upper=limit(b.upper),
                   parent_link=b.parent_link, damping=b.damping, friction=b.friction)
              for b, (j, a, c) in zip(model.bodies, model.coupling) if b.mimic]
    bodies = [dict(link=b.name, joint=b.joint, mass=float(b.mass), com=b.p_com.tolist()) for b in model.bodies]
    if args.json:
        print_json(dict(robot=model.name, urdf=model.source, base_link=model.base_link, n=model.n,
                        gravity=model.gravity.tolist(), joints=joints, mimic_joints=mimics, bodies=bodies))
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
    for m in mimics:
        print(f"joint '{m['name']}' mimics '{m['mimics']}' (multiplier {m['multiplier']:g}, offset {m['offset']:g}): "
              f"θ = {m['scale']:g}·θ_{m['follows']} {'-' if m['shift'] < 0 else '+'} {abs(m['shift']):g}, no "
              "coordinate of its own")
    rows = [["moving body", "mass (kg)", "COM in body frame (m)"]]
    rows += [[b["link"], f"{b['mass']:.4g}", "(" + ", ".join(f"{c:.4g}" for c in b["com"]) + ")"] for b in bodies]
    print()
    print(render.text_table(rows, align="<><"))
    return 0

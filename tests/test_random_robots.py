"""Property test: randomly generated URDF trees agree with Pinocchio term by term.

Hypothesis writes robots with random joint types (revolute, continuous,
prismatic, fixed), random non-unit axes, random origins and inertial frames, and
random physical inertias (principal moments obeying the triangle inequality,
rotated), attached to random earlier links so that branches occur.
"""
from __future__ import annotations

import numpy as np
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from course_dynamics_reference.validate import random_states
from helpers import assert_agrees
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from course_dynamics import coriolis_matrix, inverse_dynamics, load_urdf, mass_matrix

real = st.floats(-1.0, 1.0, allow_nan=False)
triple = st.tuples(real, real, real)


@st.composite
def link_specs(draw):
    axis = draw(triple.filter(lambda a: np.linalg.norm(a) > 0.2))
    moments = draw(st.tuples(st.floats(0.01, 1.0), st.floats(0.01, 1.0)))
    a, b = moments
    c = draw(st.floats(abs(a - b) + 1e-3, a + b))  # triangle inequality with margin
    return dict(
        type=draw(st.sampled_from(["revolute", "continuous", "prismatic", "fixed"])),
        parent=draw(st.floats(0, 1)), axis=axis, xyz=draw(triple), rpy=draw(triple),
        com=draw(triple), com_rpy=draw(triple), mass=draw(st.floats(0.1, 5.0)), moments=(a, b, c),
    )


def write_urdf(path, specs) -> None:
    parts = ['<robot name="random"><link name="link0"/>']
    for k, spec in enumerate(specs, start=1):
        a, b, c = spec["moments"]
        parts.append(
            f'<link name="link{k}"><inertial><origin xyz="{" ".join(map(str, spec["com"]))}" '
            f'rpy="{" ".join(map(str, spec["com_rpy"]))}"/><mass value="{spec["mass"]}"/>'
            f'<inertia ixx="{a}" iyy="{b}" izz="{c}" ixy="0" ixz="0" iyz="0"/></inertial></link>'
        )
        parent = min(int(spec["parent"] * k), k - 1)  # any earlier link: chains and branches
        limit = '<limit lower="-2" upper="2" effort="1" velocity="1"/>' if spec["type"] in ("revolute", "prismatic") else ""
        parts.append(
            f'<joint name="j{k}" type="{spec["type"]}"><parent link="link{parent}"/><child link="link{k}"/>'
            f'<origin xyz="{" ".join(map(str, spec["xyz"]))}" rpy="{" ".join(map(str, spec["rpy"]))}"/>'
            f'<axis xyz="{" ".join(map(str, spec["axis"]))}"/>{limit}</joint>'
        )
    parts.append("</robot>")
    path.write_text("".join(parts))


@settings(max_examples=40, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(specs=st.lists(link_specs(), min_size=1, max_size=5).filter(lambda s: any(x["type"] != "fixed" for x in s)))
def test_random_tree_agrees_with_pinocchio(tmp_path, specs):
    path = tmp_path / "random.urdf"
    write_urdf(path, specs)
    model = load_urdf(path)
    oracle = PinocchioOracle(path, model.joint_names, model.gravity)
    q, qd, qdd = random_states(model, 5, seed=0)
    tau, M, C = inverse_dynamics(model, q, qd, qdd), mass_matrix(model, q), coriolis_matrix(model, q, qd)
    for k in range(len(q)):
        M_ref = oracle.M(q[k])
        scale = np.abs(M_ref).max()
        assert_agrees(M[k], M_ref, what="M")
        assert_agrees(tau[k], oracle.tau(q[k], qd[k], qdd[k]), scale * (1 + np.abs(qd[k]).max() ** 2), what="tau")
        assert_agrees(C[k], oracle.C(q[k], qd[k]), scale * np.abs(qd[k]).max(), what="C")

"""Mimic joints (course_dynamics/core/model.py's coupling, read by core/urdf.py) against Pinocchio.

Where Pinocchio's ``mimic=True`` builds the URDF (Panda; tests/data/mimic.urdf: a revolute mimic with
multiplier ≠ 1 and offset ≠ 0 between merged fixed joints, a prismatic mimic, a revolute mimic about another
axis) its mimic model is the reference for τ, M, G and V. For a leader later in the tree and a mimic of a
mimic (tests/data/mimic_order.urdf), which Pinocchio refuses, the reference is Pinocchio's model without
mimic through the chain rule, S and b written here from the URDF's declarations, not taken from our model.
"""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from helpers import DATA, assert_agrees

from course_dynamics import load_robot, load_urdf
from course_dynamics.base.errors import ModelError
from course_dynamics.core import coriolis, crba, dynamics, forward_dynamics, lagrange, newton_euler, regressor
from course_dynamics.core.cartesian import jacobian
from course_dynamics.core.compiled import compile_model
from course_dynamics.core.friction import Friction
from course_dynamics.core.robots import robot_path
from course_dynamics.core.sampling import random_states
from reference.pinocchio_oracle import PinocchioOracle

SAMPLES = 20


@pytest.fixture(scope="module", params=["panda", "mimic"])
def robot(request):
    path = robot_path("panda") if request.param == "panda" else DATA / "mimic.urdf"
    model = load_urdf(path)
    return request.param, model, PinocchioOracle(path, model.joint_names, model.gravity), random_states(model, SAMPLES, 7)


def test_coordinates_are_the_independent_joints():
    panda = load_robot("panda")
    assert (panda.n, panda.n_bodies) == (8, 9)
    assert panda.joint_names[-1] == "panda_finger_joint1" and "panda_finger_joint2" not in panda.joint_names
    mimics = load_urdf(DATA / "mimic.urdf")
    assert mimics.joint_names == ("j1", "j4", "j5")
    np.testing.assert_array_equal(mimics.S[:, 0], [1, -1.5, 0, 0, 0, 0])
    assert mimics.b.tolist() == [0, 0.3, 0, 0, -0.05, 0.1]
    # j1's interval is where j2 = −1.5 θ₁ + 0.3 stays within its own ±2 as well
    assert mimics.lower[0] == pytest.approx((2 - 0.3) / -1.5) and mimics.upper[0] == pytest.approx((-2 - 0.3) / -1.5)


def test_dynamics_agree_with_pinocchios_mimic_model(robot):
    name, model, oracle, (q, qd, qdd) = robot
    tau, M, C = newton_euler.inverse_dynamics(model, q, qd, qdd), crba.mass_matrix(model, q), \
        coriolis.coriolis_matrix(model, q, qd)
    G, V = dynamics.gravity_torques(model, q), dynamics.velocity_torques(model, q, qd)
    for k in range(SAMPLES):
        M_ref = oracle.M(q[k])
        scale = np.abs(M_ref).max() * (1 + np.abs(qd[k]).max() ** 2 + np.abs(qdd[k]).max())
        assert_agrees(tau[k], oracle.tau(q[k], qd[k], qdd[k]), scale, what=f"{name} tau {k}")
        assert_agrees(M[k], M_ref, what=f"{name} M {k}")
        assert_agrees(G[k], oracle.G(q[k]), what=f"{name} G {k}")
        assert_agrees(V[k], oracle.V(q[k], qd[k]), scale, what=f"{name} V {k}")
        assert_agrees(C[k], oracle.C(q[k], qd[k]), scale, what=f"{name} C {k}")
        assert_agrees(C[k] @ qd[k], V[k], scale, what=f"{name} C Θ̇ = V {k}")
        qdd_ours = forward_dynamics.forward_dynamics(model, q[k], qd[k], tau[k])
        assert_agrees(qdd_ours, oracle.aba(q[k], qd[k], tau[k]), what=f"{name} forward dynamics {k}")
        assert_agrees(qdd_ours, qdd[k], what=f"{name} forward dynamics inverts τ {k}")


def test_pinocchios_own_coriolis_matrix_does_not_honour_mimic():
    """Why the oracle's C goes through the model without mimic: Pinocchio 4.1's C Θ̇ misses V on Panda."""
    model = load_robot("panda")
    pm = pin.buildModelFromUrdf(str(robot_path("panda")), mimic=True)
    q, qd, _ = random_states(model, 1, 3)
    C = pin.computeCoriolisMatrix(pm, pm.createData(), q[0], qd[0])
    V = dynamics.velocity_torques(model, q[0], qd[0])
    assert np.abs(C @ qd[0] - V).max() > 1e-6 * np.abs(V).max()
    assert_agrees(coriolis.coriolis_matrix(model, q[0], qd[0]) @ qd[0], V, np.abs(V).max())


def test_every_path_agrees(robot):
    """Lagrange, the Christoffel C, the regressor, Jacobians, energies and compiled programs on the mimic robot."""
    name, model, oracle, (q, qd, qdd) = robot
    tau = newton_euler.inverse_dynamics(model, q, qd, qdd)
    M, C = crba.mass_matrix(model, q), coriolis.coriolis_matrix(model, q, qd)
    scale = np.abs(M).max() * (1 + np.abs(qd).max() ** 2 + np.abs(qdd).max())
    assert_agrees(lagrange.mass_matrix(model, q), M, what=f"{name} Lagrange M")
    assert_agrees(lagrange.coriolis_matrix(model, q[:3], qd[:3]), C[:3], scale, what=f"{name} Lagrange C")
    assert_agrees(dynamics.coriolis_matrix_christoffel(model, q[0], qd[0]), C[0], scale, what=f"{name} Christoffel C")
    assert_agrees(dynamics.mass_matrix_by_unit_accelerations(model, q), M, what=f"{name} M by unit accelerations")
    Y = regressor.regressor(model, q, qd, qdd)
    assert Y.shape == (SAMPLES, model.n, 10 * model.n_bodies)
    assert_agrees(Y @ regressor.parameters(model), tau, scale, what=f"{name} Y π = τ")
    frame = model.bodies[-1].name
    for k in range(3):
        assert_agrees(Y[k] @ regressor.parameters(model), oracle.regressor(q[k], qd[k], qdd[k]) @
                      _pinocchio_parameters(oracle), scale, what=f"{name} regressor {k}")
        assert_agrees(jacobian(model, q[k], frame), oracle.frame_jacobian(q[k], frame), 1.0,
                      what=f"{name} J {k}")
        assert dynamics.kinetic_energy(model, q[k], qd[k]) == pytest.approx(oracle.kinetic_energy(q[k], qd[k]),
                                                                                rel=1e-9, abs=1e-12)
    for native_code in (False, True):
        fast = compile_model(model, cache=False, native_code=native_code)
        assert_agrees(fast.inverse_dynamics(q, qd, qdd), tau, scale, what=f"{name} compiled tau")
        assert_agrees(fast.mass_matrix(q), M, what=f"{name} compiled M")
        assert_agrees(fast.coriolis_matrix(q, qd), C, scale, what=f"{name} compiled C")
        assert_agrees(fast.forward_dynamics(q, qd, tau), qdd, what=f"{name} compiled forward dynamics")


def test_the_evaluator_compiled_or_not_agrees(robot):
    """``implementation(model, compiled=True)`` and ``compiled=False`` on a mimic robot, with friction."""
    from course_dynamics.core.evaluator import implementation

    name, model, _, (q, qd, qdd) = robot
    runs = [implementation(model, compiled=flag) for flag in (False, True)]
    friction = Friction.from_urdf(model)
    tau = runs[0].inverse_dynamics(q, qd, qdd)
    scale = np.abs(runs[0].mass_matrix(q)).max() * (1 + np.abs(qd).max() ** 2 + np.abs(qdd).max())
    assert_agrees(runs[1].inverse_dynamics(q, qd, qdd), tau, scale, what=f"{name} tau")
    assert_agrees(runs[1].mass_matrix(q), runs[0].mass_matrix(q), what=f"{name} M")
    assert_agrees(runs[1].coriolis_matrix(q, qd), runs[0].coriolis_matrix(q, qd), scale, what=f"{name} C")
    assert_agrees(runs[1].bias(q, qd), runs[0].bias(q, qd), scale, what=f"{name} bias")
    for run in runs:
        assert_agrees(run.forward_dynamics(q, qd, tau + friction.torques(qd), friction), qdd,
                      what=f"{name} forward dynamics with friction")


def _pinocchio_parameters(oracle) -> np.ndarray:
    return np.concatenate([oracle.plain.inertias[j].toDynamicParameters() for j in range(1, oracle.plain.njoints)])


def test_friction_of_a_mimic_acts_through_its_leader():
    model = load_urdf(DATA / "mimic.urdf")
    oracle = PinocchioOracle(DATA / "mimic.urdf", model.joint_names, model.gravity)
    friction = Friction.from_urdf(model)
    # j1 carries j2 (a = −1.5): 0.1 + 2.25 · 0.1 viscous, 0.2 + 1.5 · 0.2 Coulomb
    assert friction.viscous[0] == pytest.approx(0.325) and friction.coulomb[0] == pytest.approx(0.5)
    np.testing.assert_allclose(friction.viscous, oracle.damping, rtol=1e-12)
    np.testing.assert_allclose(friction.coulomb, oracle.friction, rtol=1e-12)
    qd = np.array([0.7, -1.1, 0.4])
    body_rates = model.S @ qd
    by_bodies = model.S.T @ (np.array([b.damping for b in model.bodies]) * body_rates
                             + np.array([b.friction for b in model.bodies]) * np.sign(body_rates))
    np.testing.assert_allclose(friction.torques(qd), by_bodies, rtol=1e-12)


def _order_reference():
    """S and b of tests/data/mimic_order.urdf, composed here from its <mimic> lines, in Pinocchio's joint order."""
    plain = pin.buildModelFromUrdf(str(DATA / "mimic_order.urdf"))
    declared = {"j2": ("j1", -1.5, 0.3), "j6": ("j4", 0.5, 0.1), "j3": ("j2", 2.0, -0.05)}
    coordinates = ("j1", "j4")
    S, b = np.zeros((plain.nv, 2)), np.zeros(plain.nv)
    for jid in range(1, plain.njoints):
        name, a, offset = plain.names[jid], 1.0, 0.0
        while name in declared:
            name, m, o = declared[name]
            a, offset = a * m, a * o + offset
        S[plain.joints[jid].idx_v, coordinates.index(name)] = a
        b[plain.joints[jid].idx_v] = offset
    return plain, S, b


def test_a_leader_later_in_the_tree_and_a_mimic_of_a_mimic():
    model = load_urdf(DATA / "mimic_order.urdf")
    assert model.joint_names == ("j1", "j4") and [b.joint for b in model.bodies][2] == "j6"
    plain, S, b = _order_reference()
    data = plain.createData()
    q, qd, qdd = random_states(model, SAMPLES, 11)
    tau, M = newton_euler.inverse_dynamics(model, q, qd, qdd), crba.mass_matrix(model, q)
    C, G = coriolis.coriolis_matrix(model, q, qd), dynamics.gravity_torques(model, q)
    for k in range(SAMPLES):
        x, v, a = S @ q[k] + b, S @ qd[k], S @ qdd[k]
        M_ref = S.T @ (np.triu(M_b := pin.crba(plain, data, x)) + np.triu(M_b, 1).T) @ S
        scale = np.abs(M_ref).max() * (1 + np.abs(qd[k]).max() ** 2 + np.abs(qdd[k]).max())
        assert_agrees(tau[k], S.T @ pin.rnea(plain, data, x, v, a), scale, what=f"tau {k}")
        assert_agrees(M[k], M_ref, what=f"M {k}")
        assert_agrees(C[k], S.T @ pin.computeCoriolisMatrix(plain, data, x, v) @ S, scale, what=f"C {k}")
        assert_agrees(G[k], S.T @ pin.computeGeneralizedGravity(plain, data, x), what=f"G {k}")
        assert_agrees(forward_dynamics.forward_dynamics(model, q[k], qd[k], tau[k]), qdd[k], what=f"Θ̈ {k}")
    fast = compile_model(model, cache=False, native_code=False)
    assert_agrees(fast.inverse_dynamics(q, qd, qdd), tau, np.abs(tau).max(), what="compiled tau")


def _urdf(tmp_path, body: str) -> str:
    path = tmp_path / "hostile.urdf"
    path.write_text('<robot name="r"><link name="base"/><link name="a"><inertial><mass value="1"/>'
                    '<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>'
                    '<link name="b"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" '
                    'izz="0.1"/></inertial></link>'
                    '<joint name="j1" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/>'
                    '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>' + body + '</robot>')
    return str(path)


def _joint(name, parent, child, mimic, kind="revolute", extra=""):
    return (f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/><axis xyz="0 1 0"/>'
            f'<limit lower="-1" upper="1" effort="1" velocity="1"/><mimic joint="{mimic}" {extra}/></joint>')


@pytest.mark.parametrize("body, fragments", [
    (_joint("j2", "a", "b", "nowhere"), ("joint 'j2' mimics joint 'nowhere'", "does not define")),
    ('<link name="c"/><joint name="fx" type="fixed"><parent link="b"/><child link="c"/></joint>' +
     _joint("j2", "a", "b", "fx"),
     ("joint 'j2' mimics joint 'fx', a fixed joint",)),
    (_joint("j2", "a", "b", "j3") + '<link name="c"/>' + _joint("j3", "b", "c", "j2"), ("joint 'j2': its mimics form a cycle",
                                                                  "j2 -> j3 -> j2")),
    (_joint("j2", "a", "b", "j2"), ("joint 'j2' mimics itself",)),
    (_joint("j2", "a", "b", "j1", extra='multiplier="nan"'), ("joint 'j2'", "multiplier", "must be finite")),
    (_joint("j2", "a", "b", "j1", extra='offset="inf"'), ("joint 'j2'", "offset", "must be finite")),
    (_joint("j2", "a", "b", "j1", extra='multiplier="1" offset="5"'), ("joint 'j1'", "joint 'j2' that mimics",
                                                                       "leave no position")),
    (_joint("j2", "a", "b", "j1", extra='multiplier="1e200"') + '<link name="c"/>' +
     _joint("j3", "b", "c", "j2", extra='multiplier="1e200"'), ("joint 'j2'", "multiplier of 1e+200")),
    (_joint("j2", "a", "b", "j1", extra='multiplier="1e308"'), ("joint 'j2'", "multiplier of 1e+308",
                                                                "1e-06 <= |multiplier| <= 1e+06")),
    (_joint("j2", "a", "b", "j1", extra='multiplier="1e-9"'), ("joint 'j2'", "multiplier of 1e-09")),
    (_joint("j2", "a", "b", "j1", extra='multiplier="1e4"') + '<link name="c"/>' +
     _joint("j3", "b", "c", "j2", extra='multiplier="1e4"'), ("joint 'j3'", "chain of mimics (j3 -> j2 -> j1)",
                                                              "multiplier of 1e+08")),
    (_joint("j2", "a", "b", "j1", extra='offset="1e4"') + '<link name="c"/>' +
     _joint("j3", "b", "c", "j2", extra='multiplier="1e3"'), ("joint 'j3'", "offset of 1e+07")),
    (_joint("j2", "a", "b", "j1", extra='multiplier="2"/><mimic joint="j1" multiplier="3"'),
     ("joint 'j2'", "2 <mimic> elements")),
    (_joint("j2", "a", "b", "j1", extra='multiplier=""'), ("joint 'j2'", '<mimic multiplier="">', "empty")),
])
def test_mimics_that_cannot_be_honoured_are_refused_in_one_line(tmp_path, body, fragments):
    path = _urdf(tmp_path, body)
    with pytest.raises(ModelError) as caught:
        load_urdf(path)
    message = str(caught.value)
    assert "\n" not in message and message.startswith(path), message
    for fragment in fragments:
        assert fragment in message, message


def test_a_mimic_on_a_fixed_joint_is_ignored_whatever_its_values(tmp_path):
    path = _urdf(tmp_path, '<joint name="fx" type="fixed"><parent link="a"/><child link="b"/>'
                           '<mimic joint="j1" multiplier="nan" offset="inf"/></joint>')
    model = load_urdf(path)
    assert model.joint_names == ("j1",) and not model.has_mimic and model.bodies[0].mass == 2


def test_the_forms_pinocchio_cannot_build_are_named():
    model = load_urdf(DATA / "mimic_order.urdf")
    assert model.mimic_forms == (("j6", "its leader 'j4' comes later in the tree"),
                                 ("j3", "its leader 'j2' is itself a mimic"))
    assert load_robot("panda").mimic_forms == () and load_urdf(DATA / "mimic.urdf").mimic_forms == ()


def _cross_branch(tmp_path, continuous: bool = False) -> str:
    """j1 carries b (joint jl) and c (joint jr, a mimic of jl: another branch); jr2 beyond c; or, with
    ``continuous``, j1 continuous and jl a revolute mimic of it."""
    links = "".join(f'<link name="{name}"><inertial><origin xyz="0.01 0.005 0.02" rpy="0.1 0.2 0.3"/><mass value='
                    f'"{mass}"/><inertia ixx="0.0004" ixy="0.00001" ixz="0" iyy="0.0005" iyz="0.00002" izz="0.0003"/>'
                    '</inertial></link>' for name, mass in (("a", 1.0), ("b", 0.8), ("c", 0.5), ("d", 0.5))
                    if continuous is False or name in "ab")

    def joint(name, parent, child, xyz, axis, kind="revolute", mimic=""):
        limit = '<limit effort="50" velocity="3"/>' if kind == "continuous" else \
            '<limit lower="-2" upper="2" effort="50" velocity="3"/>'
        return (f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/><origin '
                f'xyz="{xyz}" rpy="0.1 0 0.2"/><axis xyz="{axis}"/>{limit}{mimic}</joint>')
    if continuous:
        body = (joint("j1", "base", "a", "0 0 0.1", "0 0 1", "continuous") +
                joint("jl", "a", "b", "0.3 0 0", "0 1 0", mimic='<mimic joint="j1"/>'))
    else:
        body = (joint("j1", "base", "a", "0 0 0.1", "0 0 1") + joint("jl", "a", "b", "0.3 0 0", "0 1 0") +
                joint("jr", "a", "c", "-0.3 0 0", "0 1 0", mimic='<mimic joint="jl" multiplier="-1" offset="0.1"/>')
                + joint("jr2", "c", "d", "-0.3 0 0", "1 0 0"))
    path = tmp_path / ("cont_vs_rev.urdf" if continuous else "cross_branch.urdf")
    path.write_text(f'<robot name="r"><link name="base"/>{links}{body}</robot>')
    return str(path)


def test_pinocchios_crba_leaves_its_data_stale_on_a_mimic_in_another_branch(tmp_path):
    """Pinocchio 4.1: crba on a Data used before at another q gives a wrong M (rnea does not); when this fails,
    Pinocchio is fixed and the oracle's fresh Data per crba call can go."""
    pm = pin.buildModelFromUrdf(_cross_branch(tmp_path), mimic=True)
    data = pm.createData()
    q1, q2 = np.array([0.3, -0.4, 0.7]), np.array([1.0, 0.5, -1.2])
    first = pin.crba(pm, data, q1).copy()
    pin.crba(pm, data, q2)
    again, fresh = pin.crba(pm, data, q1).copy(), pin.crba(pm, pm.createData(), q1).copy()
    assert np.array_equal(first, fresh) and np.abs(again - fresh).max() > 1e-3


def test_a_mimic_in_another_branch_validates_and_crosschecks(tmp_path, capsys):
    from helpers import run

    path = _cross_branch(tmp_path)
    code, out, err = run(capsys, "validate", path, "--samples", "20")
    assert code == 0 and "all robots agree" in out, (out, err)
    code, out, err = run(capsys, "crosscheck", path, "--samples", "3")
    assert code == 0 and "UNEXPLAINED" not in out, (out, err)


def test_a_form_pinocchio_cannot_build_is_a_named_convention_and_one_line_in_validate(tmp_path, capsys):
    from helpers import run

    path = _cross_branch(tmp_path, continuous=True)
    code, out, err = run(capsys, "crosscheck", path, "--samples", "3")
    assert code == 0 and "refused (explained)" in out and "mimic form refused: Pinocchio" in out, (out, err)
    assert "UNEXPLAINED" not in out and "more lenient" not in out
    code, out, err = run(capsys, "validate", path, "--samples", "3")
    assert code == 2 and err.count("\n") == 1 and "cannot build mimic joint 'jl' (it is revolute and its leader " \
        "'j1' continuous: configurations of different sizes)" in err, err


def test_a_mimic_joints_column_names_its_leader(capsys, tmp_path):
    from helpers import run

    joints = load_robot("panda").joint_names
    (tmp_path / "log.csv").write_text(",".join(["t"] + [f"q_{j}" for j in joints]) + "\n" + "".join(
        ",".join([str(0.01 * k)] + ["0.01"] * len(joints)) + "\n" for k in range(5)))
    code, _, err = run(capsys, "torques", "panda", "--log", str(tmp_path / "log.csv"), "--set",
                       "q_panda_finger_joint2=0.01")
    assert code == 2 and "'q_panda_finger_joint2': joint 'panda_finger_joint2' is a mimic of joint " \
        "'panda_finger_joint1'" in err and "set or map q_panda_finger_joint1" in err, err


def test_a_redundant_robot_has_no_cartesian_mass_matrix(capsys):
    from helpers import run

    code, _, err = run(capsys, "cartesian", "panda", "--q", "0,0,0,-1,0,1,0,0.01", "--frame", "panda_hand")
    assert code == 2 and "8 joints, more than the 6 task rows: a redundant robot has no Cartesian mass matrix" in err

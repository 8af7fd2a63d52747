"""course_dynamics/tools/trace.py: every entry of the step-by-step iterations against Pinocchio's own per-joint data."""
from __future__ import annotations

import numpy as np
import sympy
from helpers import assert_agrees

from course_dynamics import load_robot
from course_dynamics.tools.trace import trace

QUANTITIES = ("omega", "omega_dot", "v_dot", "v_dot_c", "F", "N", "f", "n")


def test_every_entry_agrees_with_pinocchio(robot):
    name, model, oracle, (q, qd, qdd) = robot
    for k in range(0, len(q), 10):
        ours = trace(model, q[k], qd[k], qdd[k])
        ref = oracle.link_quantities(q[k], qd[k], qdd[k])
        scale = 1 + np.abs(qd[k]).max() ** 2 + np.abs(qdd[k]).max() + 9.81  # m/s² and rad/s² entries
        masses = np.array([b.mass for b in model.bodies])
        for key in QUANTITIES:
            load_scale = scale * max(masses.max(), 1e-3) if key in ("F", "N", "f", "n") else scale
            assert_agrees(np.array(ours.values[key]), ref[key], load_scale, what=f"{name} {key}, state {k}")
        # each joint's own τᵢ; a mimic joint's maps onto its leader: τ = Sᵀ τ_bodies
        assert_agrees(model.S.T @ np.array(ours.tau), oracle.tau(q[k], qd[k], qdd[k]), scale * masses.max(),
                      what=f"{name} tau")


def test_symbolic_trace_is_the_notes_worked_example():
    """Craig §6.7 with symbols: the quantities the notes derive by hand (corrected where misprinted)."""
    t = trace(load_robot("two_link"), None, None, None, symbols=("m1", "m2", "l1", "l2", "g"))
    q1, q2, qd1, qd2, qdd1, qdd2, m1, l1, g = sympy.symbols("q_theta1 q_theta2 qd_theta1 qd_theta2 qdd_theta1 qdd_theta2 m1 l1 g")
    subs = {s: sympy.Symbol(s.name, real=True) for s in (q1, q2, qd1, qd2, qdd1, qdd2)}
    subs.update({s: sympy.Symbol(s.name, positive=True) for s in (m1, l1, g)})

    def same(ours, expected):
        return sympy.simplify(ours - sympy.sympify(expected).xreplace(subs)) == 0

    v_dot_1 = t.values["v_dot"][0]
    assert same(v_dot_1[0], g * sympy.sin(q1)) and same(v_dot_1[1], g * sympy.cos(q1))  # ¹v̇₁ = (g s1, g c1, 0)
    v_dot_c1 = t.values["v_dot_c"][0]
    assert same(v_dot_c1[0], -l1 * qd1**2 + g * sympy.sin(q1))
    assert same(v_dot_c1[1], l1 * qdd1 + g * sympy.cos(q1))
    assert same(t.values["omega_dot"][1][2], qdd1 + qdd2)
    assert all(same(x, 0) for x in t.values["N"][0] + t.values["N"][1])

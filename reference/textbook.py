"""The textbook's closed forms for the course robots, as plain functions.

Each function returns (M, V, G) at one state, from Craig's printed results:

* :func:`two_link` — section 6.7, (6.60)–(6.62): point masses at the distal
  ends, gravity along −Y0.
* :func:`rp_arm` — example 6.5: θ1 from the horizontal, d2 along link 1.
* :func:`pendulum` — the notes' Lagrangian example: m l² θ̈ + m g l sin θ = τ.
* :func:`two_link_cartesian` — example 6.6, (6.101)–(6.103): J, M_x, V_x, G_x
  of the two-link arm in its tool frame {3}.

The parameter values of the shipped URDFs (``robots/README.md``) are in
:data:`COURSE_PARAMETERS`; the tests check the URDFs against them too.
"""
from __future__ import annotations

import numpy as np

G0 = 9.81  # m/s², the gravity the URDFs are used with

COURSE_PARAMETERS = {
    "two_link": dict(m1=2.0, m2=1.0, l1=0.5, l2=0.4, g=G0),
    "rp_arm": dict(m1=2.0, m2=1.5, l1=0.3, Izz1=0.05, Izz2=0.02, g=G0),
    "pendulum": dict(m=1.0, l=1.0, g=G0),
}


def two_link(q, qd, m1, m2, l1, l2, g):
    """Craig (6.60)–(6.62): M(Θ), V(Θ, Θ̇), G(Θ) of the planar RR arm."""
    c1, c2, s2 = np.cos(q[0]), np.cos(q[1]), np.sin(q[1])
    c12 = np.cos(q[0] + q[1])
    M = np.array([
        [l2**2 * m2 + 2 * l1 * l2 * m2 * c2 + l1**2 * (m1 + m2), l2**2 * m2 + l1 * l2 * m2 * c2],
        [l2**2 * m2 + l1 * l2 * m2 * c2, l2**2 * m2],
    ])
    V = np.array([
        -m2 * l1 * l2 * s2 * qd[1] ** 2 - 2 * m2 * l1 * l2 * s2 * qd[0] * qd[1],
        m2 * l1 * l2 * s2 * qd[0] ** 2,
    ])
    G = np.array([m2 * l2 * g * c12 + (m1 + m2) * l1 * g * c1, m2 * l2 * g * c12])
    return M, V, G


def rp_arm(q, qd, m1, m2, l1, Izz1, Izz2, g):
    """Craig example 6.5: M, V, G of the RP arm (Θ = (θ1, d2))."""
    theta1, d2 = q
    M = np.array([[m1 * l1**2 + Izz1 + Izz2 + m2 * d2**2, 0.0], [0.0, m2]])
    V = np.array([2 * m2 * d2 * qd[0] * qd[1], -m2 * d2 * qd[0] ** 2])
    G = np.array([(m1 * l1 + m2 * d2) * g * np.cos(theta1), m2 * g * np.sin(theta1)])
    return M, V, G


def pendulum(q, qd, m, l, g):
    """The pendulum: M = m l², V = 0, G = m g l sin θ."""
    return np.array([[m * l**2]]), np.array([0.0]), np.array([m * g * l * np.sin(q[0])])


def two_link_cartesian(q, qd, m1, m2, l1, l2, g):
    """Craig example 6.6: ³J (5.66) and M_x, V_x, G_x (6.101)–(6.103) of the two-link arm in frame {3}."""
    c1, s2, c2 = np.cos(q[0]), np.sin(q[1]), np.cos(q[1])
    s12, c12 = np.sin(q[0] + q[1]), np.cos(q[0] + q[1])
    td1, td2 = qd
    J = np.array([[l1 * s2, 0.0], [l1 * c2 + l2, l2]])
    Mx = np.array([[m2 + m1 / s2**2, 0.0], [0.0, m2]])
    Vx = np.array([
        -(m2 * l1 * c2 + m2 * l2) * td1**2 - m2 * l2 * td2**2
        - (2 * m2 * l2 + m2 * l1 * c2 + m1 * l1 * c2 / s2**2) * td1 * td2,
        m2 * l1 * s2 * td1**2 + l1 * m2 * s2 * td1 * td2,
    ])
    Gx = np.array([m1 * g * c1 / s2 + m2 * g * s12, m2 * g * c12])
    return J, Mx, Vx, Gx

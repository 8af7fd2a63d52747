"""Bob: closed forms, with gravity pointing the wrong way."""
import numpy as np

m1, m2, l1, l2, g = 2.0, 1.0, 0.5, 0.4, 9.81


def M(q):
    c2 = np.cos(q[1])
    a = l2**2 * m2 + l1 * l2 * m2 * c2
    return np.array([[l2**2 * m2 + 2 * l1 * l2 * m2 * c2 + l1**2 * (m1 + m2), a], [a, l2**2 * m2]])


def V(q, qd):
    h = m2 * l1 * l2 * np.sin(q[1])
    return np.array([-h * qd[1] ** 2 - 2 * h * qd[0] * qd[1], h * qd[0] ** 2])


def G(q):
    c1, c12 = np.cos(q[0]), np.cos(q[0] + q[1])
    return np.array([m2 * l2 * g * c12 + (m1 + m2) * l1 * g * c1, m2 * l2 * g * c12])


def C(q, qd):
    h = m2 * l1 * l2 * np.sin(q[1])
    return np.array([[-h * qd[1], -h * (qd[0] + qd[1])], [h * qd[0], 0.0]])


def tau(q, qd, qdd):
    return M(q) @ qdd + V(q, qd) + G(q)

g = -9.81

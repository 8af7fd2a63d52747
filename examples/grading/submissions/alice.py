"""Alice: Newton-Euler for the two-link arm, by hand (all correct)."""
import numpy as np

m1, m2, l1, l2, g = 2.0, 1.0, 0.5, 0.4, 9.81


def rot_z(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def tau(q, qd, qdd):
    """Craig's outward and inward iterations, written out for the two-link arm."""
    z = np.array([0.0, 0.0, 1.0])
    R = [rot_z(q[0]), rot_z(q[1])]
    P = [np.zeros(3), np.array([l1, 0.0, 0.0])]
    Pc = [np.array([l1, 0.0, 0.0]), np.array([l2, 0.0, 0.0])]
    m = [m1, m2]
    w, wd, vd = np.zeros(3), np.zeros(3), np.array([0.0, g, 0.0])
    F = []
    for i in range(2):
        Rt = R[i].T
        vd = Rt @ (np.cross(wd, P[i]) + np.cross(w, np.cross(w, P[i])) + vd)
        wd = Rt @ wd + np.cross(Rt @ w, qd[i] * z) + qdd[i] * z
        w = Rt @ w + qd[i] * z
        F.append(m[i] * (np.cross(wd, Pc[i]) + np.cross(w, np.cross(w, Pc[i])) + vd))
    f, n, out = np.zeros(3), np.zeros(3), np.zeros(2)
    for i in (1, 0):
        R_next = R[i + 1] if i == 0 else np.eye(3)
        P_next = P[i + 1] if i == 0 else np.zeros(3)
        n = R_next @ n + np.cross(Pc[i], F[i]) + np.cross(P_next, R_next @ f)
        f = R_next @ f + F[i]
        out[i] = n @ z
    return out

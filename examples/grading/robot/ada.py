"""Ada's dynamics for interface = "robot": Newton-Euler over whatever robot it is given."""
import numpy as np


def rotation(axis, angle):
    """Rodrigues: the rotation by angle about the unit axis."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * (k @ k)


def tau(robot, q, qd, qdd):
    """Craig's outward and inward iterations over the robot's tree, from its data alone."""
    joints, links, n = robot["joints"], robot["links"], len(robot["joints"])
    zero = np.zeros(3)
    R, P, w, wd, vd, F, N = [], [], [], [], [], [], []
    for i, joint in enumerate(joints):
        z, origin = joint["axis"], joint["origin"]
        revolute = joint["type"] == "revolute"
        R.append(origin[:3, :3] @ rotation(z, q[i]) if revolute else origin[:3, :3])
        P.append(origin[:3, 3] if revolute else origin[:3, 3] + origin[:3, :3] @ z * q[i])
        p = joint["parent"]
        wp, wdp, vdp = (zero, zero, -robot["gravity"]) if p < 0 else (w[p], wd[p], vd[p])
        Rt = R[i].T
        v = Rt @ (np.cross(wdp, P[i]) + np.cross(wp, np.cross(wp, P[i])) + vdp)
        if revolute:
            w.append(Rt @ wp + qd[i] * z)
            wd.append(Rt @ wdp + np.cross(Rt @ wp, qd[i] * z) + qdd[i] * z)
            vd.append(v)
        else:
            w.append(Rt @ wp)
            wd.append(Rt @ wdp)
            vd.append(v + 2 * np.cross(w[i], qd[i] * z) + qdd[i] * z)
        c, m, I = links[i]["com"], links[i]["mass"], links[i]["inertia"]
        F.append(m * (np.cross(wd[i], c) + np.cross(w[i], np.cross(w[i], c)) + vd[i]))
        N.append(I @ wd[i] + np.cross(w[i], I @ w[i]))
    f, nn, out = [zero] * n, [zero] * n, np.zeros(n)
    for i in reversed(range(n)):
        fi = F[i] + f[i]
        ni = N[i] + nn[i] + np.cross(links[i]["com"], F[i])
        out[i] = (ni if joints[i]["type"] == "revolute" else fi) @ joints[i]["axis"]
        p = joints[i]["parent"]
        if p >= 0:
            f[p] = f[p] + R[i] @ fi
            nn[p] = nn[p] + R[i] @ ni + np.cross(P[i], R[i] @ fi)
    return out

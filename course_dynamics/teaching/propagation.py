"""The notes' homework as functions of their inputs: the propagation rules a student derives, with their slips.

Each rule is written once, here, with a keyword that makes the slip a student makes (a factor, a term left out);
the exercises of :mod:`~course_dynamics.teaching.catalogue` check a student's function against the rule, and
name the slip whose version agrees.

=====================  ====================================================  ============
function               rule                                                  equation
=====================  ====================================================  ============
``omega_dot_next``     ⁱ⁺¹ω̇ᵢ₊₁ = ⁱ⁺¹ᵢR ⁱω̇ᵢ + ⁱ⁺¹ᵢR ⁱωᵢ × θ̇Ẑ + θ̈Ẑ              (6.32)
``v_dot_next``         ⁱ⁺¹v̇ᵢ₊₁ = ⁱ⁺¹ᵢR (ⁱω̇ᵢ × ⁱPᵢ₊₁ + ⁱωᵢ × (ⁱωᵢ × ⁱPᵢ₊₁) + ⁱv̇ᵢ)  (6.34)
``inward_moment``      ⁱnᵢ = ⁱNᵢ + ⁱᵢ₊₁R ⁱ⁺¹nᵢ₊₁ + ⁱP_Cᵢ × ⁱFᵢ + ⁱPᵢ₊₁ × ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁  (6.42)
``prismatic``          (6.34) + 2 ⁱ⁺¹ωᵢ₊₁ × ḋẐ + d̈Ẑ, and τ = fᵀẐ                (6.35), (6.44)
``moving_point``       ᴬV̇_Q of a point moving in a moving frame                  (6.10)
=====================  ====================================================  ============

>>> import numpy as np
>>> omega_dot_next(np.eye(3), np.zeros(3), np.zeros(3), 0.0, 2.0).tolist()   # θ̈ Ẑ alone
[0.0, 0.0, 2.0]
"""
from __future__ import annotations

import numpy as np

Z = np.array([0.0, 0.0, 1.0])


def random_rotation(rng) -> np.ndarray:
    """A random rotation matrix (proper: determinant +1)."""
    from scipy.spatial.transform import Rotation

    return Rotation.from_rotvec(rng.uniform(-1.5, 1.5, 3)).as_matrix()


def omega_dot_next(R, w, wd, qd, qdd, cross=np.cross):  # (6.32): ⁱ⁺¹ᵢR ⁱω̇ᵢ + ⁱ⁺¹ᵢR ⁱωᵢ × θ̇ Ẑ + θ̈ Ẑ
    return R @ wd + cross(R @ w, qd * Z) + qdd * Z


def v_dot_next(R, w, wd, vd, P, centripetal=1.0):  # (6.34): ⁱ⁺¹ᵢR (ⁱω̇ᵢ × ⁱPᵢ₊₁ + ⁱωᵢ × (ⁱωᵢ × ⁱPᵢ₊₁) + ⁱv̇ᵢ)
    return R @ (np.cross(wd, P) + centripetal * np.cross(w, np.cross(w, P)) + vd)


def inward_moment(R, N, n_next, P_c, F, P_next, f_next, arm=1.0):  # (6.42)
    return N + R @ n_next + np.cross(P_c, F) + arm * np.cross(P_next, R @ f_next)


def prismatic(R, w, wd, vd, P, d_dot, d_ddot, f, coriolis=2.0):  # (6.35) and (6.44)
    return v_dot_next(R, w, wd, vd, P) + coriolis * np.cross(R @ w, d_dot * Z) + d_ddot * Z, float(f @ Z)


def moving_point(Vd_org, R, Omega, Omega_dot, Q, V_Q, Vd_Q, coriolis=2.0):  # (6.10) corrected
    return (Vd_org + R @ Vd_Q + coriolis * np.cross(Omega, R @ V_Q) + np.cross(Omega_dot, R @ Q)
            + np.cross(Omega, np.cross(Omega, R @ Q)))


def random_inputs(*kinds):
    """Random inputs: "R" a rotation, "v" a 3-vector, "s" a number."""
    def draw(rng):
        return [random_rotation(rng) if k == "R" else rng.standard_normal(3) if k == "v"
                else float(rng.standard_normal())
                for k in kinds]

    return draw

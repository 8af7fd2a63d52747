"""The notes' homework as functions of their inputs: the propagation rules a student derives, with their slips.

Each rule is written once, here, with a keyword that makes the slip a student makes (a factor, a term left out);
the exercises of :mod:`~course_dynamics.teaching.catalogue` check a student's function against the rule, and
name the slip whose version agrees.

=====================  ===============================================================  ==============
function               rule                                                             equation
=====================  ===============================================================  ==============
``omega_dot_next``     ⁱ⁺¹ω̇ᵢ₊₁ = ⁱ⁺¹ᵢR ⁱω̇ᵢ + ⁱ⁺¹ᵢR ⁱωᵢ × θ̇Ẑ + θ̈Ẑ                        (6.32)
``v_dot_next``         ⁱ⁺¹v̇ᵢ₊₁ = ⁱ⁺¹ᵢR (ⁱω̇ᵢ × ⁱPᵢ₊₁ + ⁱωᵢ × (ⁱωᵢ × ⁱPᵢ₊₁) + ⁱv̇ᵢ)        (6.34)
``inward_moment``      ⁱnᵢ = ⁱNᵢ + ⁱᵢ₊₁R ⁱ⁺¹nᵢ₊₁ + ⁱP_Cᵢ × ⁱFᵢ + ⁱPᵢ₊₁ × ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁  (6.42)
``prismatic``          (6.34) + 2 ⁱ⁺¹ωᵢ₊₁ × ḋẐ + d̈Ẑ, and τ = fᵀẐ                        (6.35), (6.44)
``moving_point``       ᴬV̇_Q of a point moving in a moving frame                         (6.10)
=====================  ===============================================================  ==============

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
    """The angular acceleration of link i + 1 across a revolute joint, (6.32).

    Parameters
    ----------
    R : numpy.ndarray, shape (3, 3)
        ⁱ⁺¹ᵢR, the rotation from frame i to frame i + 1.
    w : numpy.ndarray, shape (3,)
        ⁱωᵢ, rad/s.
    wd : numpy.ndarray, shape (3,)
        ⁱω̇ᵢ, rad/s².
    qd : float
        θ̇ᵢ₊₁, rad/s.
    qdd : float
        θ̈ᵢ₊₁, rad/s².
    cross : callable, optional
        The cross product (``numpy.cross``); the slip ``cross-reversed`` passes one with its factors swapped.

    Returns
    -------
    numpy.ndarray, shape (3,)
        ⁱ⁺¹ω̇ᵢ₊₁, rad/s².

    Examples
    --------
    >>> omega_dot_next(np.eye(3), np.array([1.0, 0, 0]), np.zeros(3), 1.0, 0.0).tolist()
    [0.0, -1.0, 0.0]
    """
    return R @ wd + cross(R @ w, qd * Z) + qdd * Z


def v_dot_next(R, w, wd, vd, P, centripetal=1.0):  # (6.34): ⁱ⁺¹ᵢR (ⁱω̇ᵢ × ⁱPᵢ₊₁ + ⁱωᵢ × (ⁱωᵢ × ⁱPᵢ₊₁) + ⁱv̇ᵢ)
    """The linear acceleration of the origin of frame i + 1 across a revolute joint, (6.34).

    With ``R`` the identity and ``P`` = ⁱP_Cᵢ it is (6.36), the acceleration of link i's centre of mass.

    Parameters
    ----------
    R : numpy.ndarray, shape (3, 3)
        ⁱ⁺¹ᵢR, the rotation from frame i to frame i + 1.
    w : numpy.ndarray, shape (3,)
        ⁱωᵢ, rad/s.
    wd : numpy.ndarray, shape (3,)
        ⁱω̇ᵢ, rad/s².
    vd : numpy.ndarray, shape (3,)
        ⁱv̇ᵢ, m/s².
    P : numpy.ndarray, shape (3,)
        ⁱPᵢ₊₁, the origin of frame i + 1 in frame i, m.
    centripetal : float, optional
        The factor of ω × (ω × P): 1, or 0 for the slip ``centripetal-missing``.

    Returns
    -------
    numpy.ndarray, shape (3,)
        ⁱ⁺¹v̇ᵢ₊₁, m/s².
    """
    return R @ (np.cross(wd, P) + centripetal * np.cross(w, np.cross(w, P)) + vd)


def inward_moment(R, N, n_next, P_c, F, P_next, f_next, arm=1.0):  # (6.42)
    """The moment exerted on link i by link i − 1, (6.42).

    Parameters
    ----------
    R : numpy.ndarray, shape (3, 3)
        ⁱᵢ₊₁R, the rotation from frame i + 1 to frame i.
    N : numpy.ndarray, shape (3,)
        ⁱNᵢ, the inertial moment of link i, N·m.
    n_next : numpy.ndarray, shape (3,)
        ⁱ⁺¹nᵢ₊₁, N·m.
    P_c : numpy.ndarray, shape (3,)
        ⁱP_Cᵢ, link i's centre of mass in frame i, m.
    F : numpy.ndarray, shape (3,)
        ⁱFᵢ, the inertial force of link i, N.
    P_next : numpy.ndarray, shape (3,)
        ⁱPᵢ₊₁, the origin of frame i + 1 in frame i, m.
    f_next : numpy.ndarray, shape (3,)
        ⁱ⁺¹fᵢ₊₁, N.
    arm : float, optional
        The factor of ⁱPᵢ₊₁ × ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁: 1, or 0 for the slip ``moment-arm-missing``.

    Returns
    -------
    numpy.ndarray, shape (3,)
        ⁱnᵢ, N·m.
    """
    return N + R @ n_next + np.cross(P_c, F) + arm * np.cross(P_next, R @ f_next)


def prismatic(R, w, wd, vd, P, d_dot, d_ddot, f, coriolis=2.0):  # (6.35) and (6.44)
    """Across a prismatic joint: the linear acceleration of frame i + 1, (6.35), and the joint's force, (6.44).

    Parameters
    ----------
    R : numpy.ndarray, shape (3, 3)
        ⁱ⁺¹ᵢR, the rotation from frame i to frame i + 1.
    w : numpy.ndarray, shape (3,)
        ⁱωᵢ, rad/s.
    wd : numpy.ndarray, shape (3,)
        ⁱω̇ᵢ, rad/s².
    vd : numpy.ndarray, shape (3,)
        ⁱv̇ᵢ, m/s².
    P : numpy.ndarray, shape (3,)
        ⁱPᵢ₊₁, m.
    d_dot : float
        ḋᵢ₊₁, m/s.
    d_ddot : float
        d̈ᵢ₊₁, m/s².
    f : numpy.ndarray, shape (3,)
        ⁱ⁺¹fᵢ₊₁, the force on link i + 1, N.
    coriolis : float, optional
        The factor of ⁱ⁺¹ωᵢ₊₁ × ḋẐ: 2, or 1 for the slip ``coriolis-half``.

    Returns
    -------
    tuple of (numpy.ndarray, float)
        ⁱ⁺¹v̇ᵢ₊₁ (shape (3,), m/s²) and τᵢ₊₁ = fᵀẐ, N.
    """
    return v_dot_next(R, w, wd, vd, P) + coriolis * np.cross(R @ w, d_dot * Z) + d_ddot * Z, float(f @ Z)


def moving_point(Vd_org, R, Omega, Omega_dot, Q, V_Q, Vd_Q, coriolis=2.0):  # (6.10) corrected
    """ᴬV̇_Q, the acceleration in frame {A} of a point Q moving in a moving frame {B}, (6.10).

    Parameters
    ----------
    Vd_org : numpy.ndarray, shape (3,)
        ᴬV̇_BORG, the acceleration of {B}'s origin, m/s².
    R : numpy.ndarray, shape (3, 3)
        ᴬ_BR, the orientation of {B} in {A}.
    Omega : numpy.ndarray, shape (3,)
        ᴬΩ_B, the angular velocity of {B}, rad/s.
    Omega_dot : numpy.ndarray, shape (3,)
        ᴬΩ̇_B, rad/s².
    Q : numpy.ndarray, shape (3,)
        ᴮQ, the point in {B}, m.
    V_Q : numpy.ndarray, shape (3,)
        ᴮV_Q, its velocity in {B}, m/s.
    Vd_Q : numpy.ndarray, shape (3,)
        ᴮV̇_Q, its acceleration in {B}, m/s².
    coriolis : float, optional
        The factor of the Coriolis term ᴬΩ_B × ᴬ_BR ᴮV_Q: 2 (1 and 3 are the slips ``coriolis-half`` and
        ``coriolis-doubled``).

    Returns
    -------
    numpy.ndarray, shape (3,)
        ᴬV̇_Q, m/s².
    """
    return (Vd_org + R @ Vd_Q + coriolis * np.cross(Omega, R @ V_Q) + np.cross(Omega_dot, R @ Q)
            + np.cross(Omega, np.cross(Omega, R @ Q)))


def random_inputs(*kinds):
    """Random inputs: "R" a rotation, "v" a 3-vector, "s" a number."""
    def draw(rng):
        return [random_rotation(rng) if k == "R" else rng.standard_normal(3) if k == "v"
                else float(rng.standard_normal())
                for k in kinds]

    return draw


__all__ = ["inward_moment", "moving_point", "omega_dot_next", "prismatic", "v_dot_next"]

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
``chain_quantities``   a robot's own inputs for them: both iterations, link by link     (6.45)–(6.53)
=====================  ===============================================================  ==============

>>> import numpy as np
>>> omega_dot_next(np.eye(3), np.zeros(3), np.zeros(3), 0.0, 2.0).tolist()   # θ̈ Ẑ alone
[0.0, 0.0, 2.0]
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.errors import InputError
from ..core.kinematics import joint_transforms
from ..core.model import Model
from ..core.newton_euler import newton_euler_links

Z = np.array([0.0, 0.0, 1.0])


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


@dataclass(frozen=True)
class ChainQuantities:
    """Both iterations of a serial chain at one state, per link (index i is link i + 1), each in its own frame.

    Parameters
    ----------
    R_up, R_base : numpy.ndarray, shape (n, 3, 3)
        ᵖᵢR, the orientation of frame i in its parent, and ⁰ᵢR, in the base.
    P_up, p_com : numpy.ndarray, shape (n, 3)
        ᵖPᵢ, the origin of frame i in its parent, and ⁱP_Cᵢ, link i's centre of mass, m.
    omega, omega_dot, v_dot, v_dot_c : numpy.ndarray, shape (n, 3)
        ⁱωᵢ (rad/s), ⁱω̇ᵢ (rad/s²), ⁱv̇ᵢ and ⁱv̇_Cᵢ (m/s², with the −g base lift).
    F, N, f, n : numpy.ndarray, shape (n, 3)
        ⁱFᵢ (N), ⁱNᵢ (N·m), ⁱfᵢ (N), ⁱnᵢ (N·m).
    qd, qdd : numpy.ndarray, shape (n,)
        Θ̇ (rad/s) and Θ̈ (rad/s²) of the state.
    """

    R_up: np.ndarray
    R_base: np.ndarray
    P_up: np.ndarray
    p_com: np.ndarray
    omega: np.ndarray
    omega_dot: np.ndarray
    v_dot: np.ndarray
    v_dot_c: np.ndarray
    F: np.ndarray
    N: np.ndarray
    f: np.ndarray
    n: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray


def chain_quantities(model: Model, q, qd, qdd) -> ChainQuantities:
    """The inputs the homework's functions take, from a robot's own links: both iterations at one state.

    Parameters
    ----------
    model : Model
        A serial chain (each body the child of the one before).
    q, qd, qdd : array_like, shape (n,)
        Θ (rad), Θ̇ (rad/s), Θ̈ (rad/s²); m, m/s, m/s² for a prismatic joint.

    Returns
    -------
    ChainQuantities
        The rotations, offsets and every quantity of (6.45)–(6.53), link by link.

    Raises
    ------
    InputError
        If the robot is not a serial chain.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> chain = chain_quantities(load_robot("two_link"), [0.0, 0.0], [1.0, 0.0], [0.0, 0.0])
    >>> chain.omega[1].tolist(), chain.P_up[1].tolist()   # link 2 turns with link 1; joint 2 at l₁ along X₁
    ([0.0, 0.0, 1.0], [0.5, 0.0, 0.0])
    """
    if [body.parent for body in model.bodies] != list(range(-1, len(model.bodies) - 1)):
        raise InputError(f"robot '{model.name}' is not a serial chain: its links' quantities have no single order")
    links = newton_euler_links(model, q, qd, qdd)
    X = joint_transforms(model, [float(x) for x in np.asarray(q, dtype=float)])
    R_up = np.array([np.array(R.rows, dtype=float) for R in X.R])
    R_base = [R_up[0]]
    for R in R_up[1:]:
        R_base.append(R_base[-1] @ R)  # ⁰ᵢR = ⁰ₚR ᵖᵢR
    return ChainQuantities(R_up=R_up, R_base=np.array(R_base), P_up=np.array([tuple(P) for P in X.P], dtype=float),
                           p_com=np.array([b.p_com for b in model.bodies]), omega=links.omega,
                           omega_dot=links.omega_dot, v_dot=links.v_dot, v_dot_c=links.v_dot_c, F=links.F, N=links.N,
                           f=links.f, n=links.n, qd=np.asarray(qd, dtype=float), qdd=np.asarray(qdd, dtype=float))


__all__ = ["ChainQuantities", "chain_quantities", "inward_moment", "moving_point", "omega_dot_next", "prismatic",
           "v_dot_next"]

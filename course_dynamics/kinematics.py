"""Forward kinematics and potential energy.

=============  =========  ==============================================
code           Craig      meaning (shape, unit)
=============  =========  ==============================================
``R[i]``       ⁰ᵢR        orientation of frame i in the base (3, 3)
``P[i]``       ⁰Pᵢ        origin of frame i in the base (3,), m
``P_com[i]``   ⁰P_Cᵢ      centre of mass of body i in the base (3,), m
``u``          u          potential energy (6.73), J, with u_ref = 0
=============  =========  ==============================================
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .algebra import Vec3, cross, dot
from .model import Model
from .newton_euler import joint_transforms
from .state import as_state, columns, layout_of


@dataclass(frozen=True)
class Placements:
    """Base-frame placements of every body: R (n, 3, 3), P and P_com (n, 3); batch axes lead."""

    R: np.ndarray
    P: np.ndarray
    P_com: np.ndarray


def _placements(model: Model, theta: list):
    """⁰ᵢR, ⁰Pᵢ, ⁰P_Cᵢ as Mat3/Vec3 of per-joint scalars."""
    X = joint_transforms(model, theta)
    R, P, P_com = [], [], []
    for i, body in enumerate(model.bodies):
        if body.parent < 0:
            R_i, P_i = X.R[i], X.P[i]
        else:
            R_p, P_p = R[body.parent], P[body.parent]
            R_i, P_i = R_p @ X.R[i], P_p + R_p @ X.P[i]
        R.append(R_i)
        P.append(P_i)
        P_com.append(P_i + R_i @ body.p_com_v)
    return R, P, P_com


def point_jacobian_columns(model: Model, R: list, P: list, body: int, point: Vec3) -> list:
    """Columns (J_v[:, j], J_ω[:, j]) of a point fixed to ``body``, base coordinates.

    ``R``, ``P`` are the base-frame placements ⁰ᵢR, ⁰Pᵢ of every body and ``point``
    is ⁰P of the point. Joint j moves the point when body j is ``body`` or one of
    its ancestors: a revolute joint adds ⁰Ẑⱼ × (⁰P − ⁰Pⱼ) to its velocity and ⁰Ẑⱼ
    to the angular velocity, a prismatic joint adds ⁰Ẑⱼ and no rotation.
    Other columns are zero.
    """
    zero = Vec3(0, 0, 0)
    cols = [(zero, zero)] * model.n
    j = body
    while j >= 0:
        joint = model.bodies[j]
        z = R[j] @ joint.axis_v  # ⁰Ẑⱼ
        cols[j] = (z, zero) if joint.is_prismatic else (cross(z, point - P[j]), z)
        j = joint.parent
    return cols


def forward_kinematics(model: Model, q) -> Placements:
    """Where every body is at Θ (shape (n,) or (N, n))."""
    q = as_state(model, q, "q")
    layout = layout_of(q)
    R, P, P_com = _placements(model, columns(q))
    n = model.n
    return Placements(
        R=layout.assemble([tuple(tuple(row) for row in r.rows) for r in R], (n, 3, 3)),
        P=layout.assemble([tuple(p) for p in P], (n, 3)),
        P_com=layout.assemble([tuple(p) for p in P_com], (n, 3)),
    )


def potential_energy_from_columns(model: Model, theta: list):
    """u = Σᵢ −mᵢ ⁰gᵀ ⁰P_Cᵢ (6.73) from per-joint scalars (u_ref = 0)."""
    g = Vec3.of(model.gravity)
    _, _, P_com = _placements(model, theta)
    u = 0
    for body, p in zip(model.bodies, P_com):
        u = u - body.mass_s * dot(g, p)  # (6.73)
    return u


def potential_energy(model: Model, q) -> np.ndarray:
    """u(Θ), J: shape () for one state, (N,) for a batch."""
    q = as_state(model, q, "q")
    return layout_of(q).assemble(potential_energy_from_columns(model, columns(q)), ())

"""The mass matrix by the composite-rigid-body algorithm (Walker and Orin): O(n²), one pass, no Θ̈.

Craig (section 6.8) reads column j of M(Θ) off the Newton–Euler recursion with
Θ̈ = eⱼ and no velocity or gravity: n passes. The composite-rigid-body algorithm
gets the same matrix in one: if joint i alone accelerates at a unit rate, body
i and everything beyond it move as one rigid *composite* body, and the force
joint k must transmit for that motion is Mₖᵢ.

====================  ============================================================
code                  meaning (base frame, about its origin; :mod:`~course_dynamics.core.spatial`)
====================  ============================================================
``s[i]``              joint i's unit motion
``body[i]``           body i's spatial inertia (m, h = m ⁰P_Cᵢ, Ī about the origin)
``composite[i]``      Iᶜᵢ = body i plus every body beyond it: sums, since one frame
``F[i]``              Fᵢ = Iᶜᵢ s[i]: the force moving that composite at a unit rate
``M[k][i]``           Mₖᵢ = s[k]ᵀ Fᵢ for k = i and every ancestor k of i; 0 for
                      joints on other branches (M is symmetric)
====================  ============================================================

>>> from course_dynamics import load_robot
>>> mass_matrix(load_robot("pendulum"), [0.4])   # m l² = 1 kg · (1 m)²
array([[1.]])
"""
from __future__ import annotations

import numpy as np

from .kinematics import placement_entries
from .model import Model
from .spatial import body_inertias, motion_axes, power
from .state import as_state, entries, layout_of


def composite_inertias(model: Model, bodies: list) -> list:
    """Iᶜᵢ: body i's inertia plus its children's composites, tips to base.

    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.spatial import body_inertias
    >>> arm = load_robot("two_link")
    >>> [c.m for c in composite_inertias(arm, body_inertias(arm, placement_entries(arm, [0.0, 0.0])))]   # kg
    [3.0, 1.0]
    """
    composite = list(bodies)
    for i in reversed(range(model.n_bodies)):
        for c in model.children[i]:
            composite[i] = composite[i] + composite[c]
    return composite


def mass_matrix_entries(model: Model, theta: list) -> list:
    """M[k][i] as nested scalars from per-joint scalars Θ (module docstring).

    >>> from course_dynamics import load_robot
    >>> np.round(mass_matrix_entries(load_robot("two_link"), [0.0, 0.0]), 3)
    array([[1.31, 0.36],
           [0.36, 0.16]])
    """
    placements = placement_entries(model, theta)
    s = motion_axes(model, placements)
    composite = composite_inertias(model, body_inertias(model, placements))
    n = model.n_bodies
    M = [[0] * n for _ in range(n)]
    for i in range(n):
        F = composite[i].times(s[i])  # Fᵢ = Iᶜᵢ sᵢ
        k = i
        while k >= 0:
            M[k][i] = M[i][k] = power(s[k], F)  # Mₖᵢ = sₖᵀ Fᵢ
            k = model.bodies[k].parent
    return model.coordinate_matrix(M)  # M = Sᵀ M_bodies S (mimic joints)


def mass_matrix(model: Model, q) -> np.ndarray:
    """M(Θ), shape (n, n) or (N, n, n), kg·m² (kg for prismatic joints) by the composite-rigid-body algorithm.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.

    Returns
    -------
    numpy.ndarray, shape (n, n) or (N, n, n)
        The mass matrix M(Θ), symmetric: kg·m² between revolute joints, kg between prismatic ones, kg·m
        between the two.

    Raises
    ------
    StateError
        If ``q`` is not numeric or not finite, or its last axis is not the model's n joints.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> mass_matrix(load_robot("two_link"), [0.0, 0.0]).round(3)   # Craig (6.60) at θ₂ = 0, kg·m²
    array([[1.31, 0.36],
           [0.36, 0.16]])
    """
    q = as_state(model, q, "q")
    return layout_of(q).assemble(mass_matrix_entries(model, entries(q)), (model.n, model.n))


__all__ = ["mass_matrix"]

"""The Coriolis matrix in O(n²): C(Θ, Θ̇) with C Θ̇ = V and Ṁ − 2C skew-symmetric, without derivatives.

The teaching definition is Cᵢⱼ = Σₖ Γᵢⱼₖ θ̇ₖ, from the Christoffel symbols of
M (:mod:`course_dynamics.core.lagrange`, and :func:`course_dynamics.core.dynamics.coriolis_matrix_christoffel`,
which differentiates exactly with dual numbers). This module gets the same
matrix from velocities and composite inertias alone, by the factorization of
Echeandia and Wensing (2021), which Pinocchio's ``computeCoriolisMatrix`` also
uses. Each body k contributes the matrix Bₖ(vₖ), with
Bₖ(v) s = ½ [v ×* (Iₖ s) + s ×* (Iₖ v) − Iₖ (v × s)], so that
C = Σₖ Jₖᵀ (Iₖ J̇ₖ + Bₖ Jₖ); summing over the bodies beyond each joint:

====================  ============================================================
code                  meaning (base frame, about its origin; :mod:`~course_dynamics.core.spatial`)
====================  ============================================================
``s[j]``              joint j's unit motion; ``s_dot[j]`` = vⱼ × s[j], its rate
``v[k]``              body k's velocity, Σ s[j] θ̇ⱼ over j = k and its ancestors
``h[k]``              body k's momentum Iₖ vₖ
``f[d]``              for one joint j: fᵈ = Σ over bodies k at or beyond d of
                      Iₖ ṡⱼ + Bₖ(vₖ) sⱼ (the force that joint j's rate costs them)
``C[i][j]``           s[i]ᵀ f at the deeper of i and j: s[i]ᵀ fⁱ if j is i or an
                      ancestor of i, s[i]ᵀ fʲ if i is an ancestor of j, else 0
====================  ============================================================

It serves one state, a batch and sympy symbols, like the rest of the library.
"""
from __future__ import annotations

import numpy as np

from .kinematics import placement_entries
from .model import Model
from .spatial import add, body_inertias, cross_force, cross_motion, motion_axes, power
from .state import as_state, entries, layout_of


def _half(force):
    n, f = force
    return n / 2, f / 2


def coriolis_matrix_entries(model: Model, theta: list, theta_dot: list) -> list:
    """C[i][j] as nested scalars from per-joint scalars Θ, Θ̇ (module docstring).

    >>> from course_dynamics import load_robot
    >>> np.round(coriolis_matrix_entries(load_robot("two_link"), [0.0, np.pi / 2], [1.0, 0.0]), 3)
    array([[ 0. , -0.2],
           [ 0.2,  0. ]])
    """
    placements = placement_entries(model, theta)
    s = motion_axes(model, placements)
    inertia = body_inertias(model, placements)
    n = model.n_bodies
    theta_dot = model.body_entries(theta_dot, False)  # S Θ̇ (mimic joints)
    v = []
    for k, body in enumerate(model.bodies):
        own = (theta_dot[k] * s[k][0], theta_dot[k] * s[k][1])
        v.append(own if body.parent < 0 else add(v[body.parent], own))
    h = [inertia[k].times(v[k]) for k in range(n)]  # momenta Iₖ vₖ
    s_dot = [cross_motion(v[j], s[j]) for j in range(n)]
    C = [[0] * n for _ in range(n)]
    subtree = [[j] for j in range(n)]
    for j in reversed(range(n)):
        for c in model.children[j]:
            subtree[j] += subtree[c]
    for j in range(n):
        f = {}
        for d in sorted(subtree[j], reverse=True):  # bodies beyond j, tips first (children after parents)
            I = inertia[d]
            B_s = _half(add(add(cross_force(v[d], I.times(s[j])), cross_force(s[j], h[d])),
                            _neg(I.times(cross_motion(v[d], s[j])))))  # Bᵈ(vᵈ) sⱼ
            f_d = add(I.times(s_dot[j]), B_s)
            for c in model.children[d]:
                f_d = add(f_d, f[c])
            f[d] = f_d
            C[d][j] = power(s[d], f_d)  # j is d or an ancestor of d
        k = model.bodies[j].parent
        while k >= 0:
            C[k][j] = power(s[k], f[j])  # k an ancestor of j
            k = model.bodies[k].parent
    return model.coordinate_matrix(C)  # C = Sᵀ C_bodies S (mimic joints)


def _neg(force):
    return -force[0], -force[1]


def coriolis_matrix(model: Model, q, qd) -> np.ndarray:
    """C(Θ, Θ̇), shape (n, n) or (N, n, n), in O(n²) (module docstring); equals the Christoffel form.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.
    qd : array_like, shape (n,) or (N, n)
        Joint velocities Θ̇, rad/s (m/s for a prismatic joint).

    Returns
    -------
    numpy.ndarray, shape (n, n) or (N, n, n)
        The Coriolis matrix C(Θ, Θ̇), with C(Θ, Θ̇) Θ̇ = V(Θ, Θ̇) and Ṁ − 2C skew-symmetric; kg·m²/s
        between revolute joints.

    Raises
    ------
    StateError
        If ``q`` or ``qd`` is not numeric or not finite, its last axis is not the model's n joints, or their
        batches differ in length.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> coriolis_matrix(load_robot("two_link"), [0.0, np.pi / 2], [1.0, 0.0]).round(3)   # ∓m₂l₁l₂s₂θ̇₁ off the diagonal
    array([[ 0. , -0.2],
           [ 0.2,  0. ]])
    """
    q, qd = as_state(model, q, "q"), as_state(model, qd, "qd")
    return layout_of(q, qd).assemble(coriolis_matrix_entries(model, entries(q), entries(qd)), (model.n, model.n))


__all__ = ["coriolis_matrix"]

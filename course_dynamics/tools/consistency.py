"""The physically consistent fit of an identification (step 3 of :mod:`course_dynamics.tools.identification`).

The estimate minimises ‖W (Y θ − τ_meas)‖² + λ c² Σ ((θₖ − θₖ,URDF) / sₖ)² subject to
J(πᵢ) ⪰ 0 and mᵢ ≥ m_min for every body and F_v, F_c ≥ 0, with cvxpy (Clarabel, SCS if that
fails). What the solvers warn (an inaccurate solution) comes out as a
:class:`~course_dynamics.base.errors.CourseDynamicsWarning`: one ``warning:`` line on the command line.
"""
from __future__ import annotations

import warnings

import numpy as np

from ..base.errors import CourseDynamicsWarning, InputError
from ..core.regressor import TENSOR


def consistent_fit(model, R, sigma, theta_urdf, kinds, sizes, prior_weight, min_mass):
    """The physically consistent θ (module docstring, step 3): (θ, solver).

    Parameters
    ----------
    model : Model
        The robot whose bodies the first 10 n entries of θ describe.
    R : numpy.ndarray, shape (m, r, P + 1)
        Per measured joint, the triangular factor of [Yⱼ | τⱼ] (the fit's data, P parameters).
    sigma : numpy.ndarray, shape (m,)
        Each measured joint's torque noise σⱼ, N·m (N for a prismatic joint): the weights are 1/σⱼ.
    theta_urdf : numpy.ndarray, shape (P,)
        The URDF's θ: the prior and the starting point.
    kinds : sequence of str
        The kind of each entry of θ: ``"m"``, ``"h"``, ``"I"``, ``"viscous"`` or ``"coulomb"``.
    sizes : dict
        {kind: the values a parameter of that kind typically has}, the scale sₖ of its changes.
    prior_weight : float
        λ ≥ 0, the weight of the URDF's values as a share of what the data say.
    min_mass : numpy.ndarray, shape (n,)
        The least mass of each body, kg.

    Returns
    -------
    theta : numpy.ndarray, shape (P,)
        The consistent estimate: J(πᵢ) ⪰ 0, mᵢ ≥ m_min and friction coefficients ≥ 0.
    solver : str
        The solver that found it, ``"clarabel"`` or ``"scs"`` (``"scs (inaccurate)"`` if it said so).

    Raises
    ------
    InputError
        If cvxpy is not installed, or neither solver finds a solution.

    Warns
    -----
    CourseDynamicsWarning
        What the solvers warn, one line each.
    """
    try:
        import cvxpy as cp
    except ImportError:
        raise InputError("identification needs cvxpy and clarabel: install course-dynamics[identify] "
                         "(pip install 'course-dynamics[identify]')") from None
    P, n_rigid = len(theta_urdf), 10 * model.n_bodies
    weighted = (R / sigma[:, None, None]).reshape(-1, P + 1)
    Rw = np.linalg.qr(weighted, mode="r")                  # ‖W (Y θ − τ)‖ = ‖Rw[:, :P] θ − Rw[:, P]‖
    A, z = Rw[:P, :P], Rw[:P, P]
    norms = np.sum(A**2, axis=0)
    scale = np.ones(P)       # θ = θ_URDF + scale d: d is a change of the size a parameter of its kind has
    for kind in set(kinds):
        typical = np.sqrt(np.mean(np.asarray(sizes[kind]) ** 2))
        scale[[k for k in range(P) if kinds[k] == kind]] = typical if typical > 0 else 1.0
    prior = prior_weight * float(np.mean(norms * scale**2))   # what such a change typically does to the fit
    residual = z - A @ theta_urdf
    size = max(float(np.linalg.norm(residual)), 1e-300)  # the URDF's misfit: the objective starts at 1
    d = cp.Variable(P)
    theta = theta_urdf + cp.multiply(scale, d)
    constraints = []
    for i in range(model.n_bodies):
        p = theta[10 * i:10 * i + 10]
        J = cp.Variable((4, 4), PSD=True)
        trace = p[4] + p[6] + p[9]
        constraints += [J[a, b] == (0.5 * trace if a == b else 0) - p[TENSOR[a][b]]
                        for a in range(3) for b in range(a, 3)]
        constraints += [J[a, 3] == p[1 + a] for a in range(3)] + [J[3, 3] == p[0], p[0] >= min_mass[i]]
    if P > n_rigid:
        constraints.append(theta[n_rigid:] >= 0)
    objective = cp.sum_squares((A * scale / size) @ d - residual / size) + prior / size**2 * cp.sum_squares(d)
    problem = cp.Problem(cp.Minimize(objective), constraints)
    for solver, options in (("CLARABEL", {}), ("SCS", {"eps": 1e-9, "max_iters": 200_000})):
        try:
            with warnings.catch_warnings(record=True) as said:  # cvxpy's warnings, as ours: one line each
                warnings.simplefilter("always")
                problem.solve(solver=solver, **options)
        except (cp.error.SolverError, ValueError):
            continue
        finally:
            for warning in said:
                warnings.warn(f"robot '{model.name}', the physically consistent fit ({solver.lower()}): "
                              f"{warning.message}", CourseDynamicsWarning)
        if problem.status in ("optimal", "optimal_inaccurate") and d.value is not None:
            accuracy = "" if problem.status == "optimal" else " (inaccurate)"
            return theta_urdf + scale * d.value, solver.lower() + accuracy
    raise InputError(f"robot '{model.name}': the physically consistent fit found no solution (Clarabel and SCS: "
                     f"{problem.status}); the log may not move the joints enough")


__all__ = ["consistent_fit"]

"""The physically consistent fit of an identification (step 3 of :mod:`course_dynamics.tools.identification`).

==================  =============  ====================================================================
code                symbol         meaning (shape, unit)
==================  =============  ====================================================================
``A``, ``z``        A, z           the weighted data: ‖W (Y θ − τ_meas)‖ = ‖A θ − z‖ (P, P), (P,)
``scale``           S              the size a change of each parameter of θ is measured in (P,):
                                   mᵢ, mᵢ ℓᵢ, mᵢ ℓᵢ² for body i (ℓᵢ its link's extent), the first
                                   fit's friction coefficients
``V_E``, ``V_N``    V_E, V_N       the right singular vectors of A S whose singular values are at least
                                   (below) ``threshold`` of the largest: what the log sees (does not)
``J``, ``J0``       Jᵢ, Jᵢ₀        body i's pseudo-inertia, identified and the URDF's (4, 4)
==================  =============  ====================================================================

The estimate is θ = θ_URDF + S (V_E a + V_N b), and (a, b) minimise

    ‖A θ − z‖² / N + λ Σᵢ d(Jᵢ ‖ Jᵢ₀) + ρ ‖b‖²,   d(J ‖ J₀) = −log det(J₀⁻¹ J) + tr(J₀⁻¹ J) − 4

with Jᵢ ⪰ 0, mᵢ ≥ m_min,i, the friction coefficients and rotor inertias ≥ 0 and the torque offsets
free (``at_least_zero`` says which entries are held ≥ 0; N: the weighted torques fitted, so
the data term is the mean squared residual in units of each joint's noise). d is the log-determinant
(Bregman) divergence of Lee, Wensing and Park (IEEE T-RO 2020): zero at J₀, infinite as J
becomes singular, and the same for a body whatever its frame or units. It acts on the bodies only:
friction and drives have no prior. The data term sees a alone (what the log does not see cannot fit its noise);
b is nearly free (ρ = :data:`HOLD`), so the constraints never bend a. Then b is dropped: θ =
θ_URDF + S V_E a, what the log does not see exactly the URDF's. If a body is then not physical,
b is the least ‖b‖ that makes every body physical again (a second, small problem), and those
bodies are named. A URDF body with a singular J₀ (a point mass, a rod) is held toward
J₀ + ε mᵢ diag(ℓᵢ², ℓᵢ², ℓᵢ², 1), ε = :data:`SINGULAR_EPSILON`.

cvxpy solves it (Clarabel, SCS if that fails); what the solvers warn (an inaccurate solution) comes
out as a :class:`~course_dynamics.base.errors.CourseDynamicsWarning`: one ``warning:`` line on the
command line.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..base.errors import CourseDynamicsWarning, InputError
from ..core.regressor import TENSOR

#: The weight ρ of ‖b‖², per squared unit of scale, against a data term near 1 (small, so b is nearly free).
HOLD = 1e-6
#: The ε of a URDF body's singular pseudo-inertia, held toward J₀ + ε mᵢ diag(ℓᵢ², ℓᵢ², ℓᵢ², 1).
SINGULAR_EPSILON = 1e-3
PHYSICAL_TOLERANCE = 1e-10   # an eigenvalue of J above −this share of its largest counts as ≥ 0


@dataclass(frozen=True)
class ConsistentFit:
    """What :func:`consistent_fit` found.

    Parameters
    ----------
    theta : numpy.ndarray, shape (P,)
        The consistent estimate θ.
    solver : str
        ``"clarabel"`` or ``"scs"`` (with `` (inaccurate)`` if the solver said so).
    shares : numpy.ndarray, shape (F,)
        The singular values of A S on the free parameters, as shares of the largest (0 for the null space).
    seen : numpy.ndarray, shape (P,)
        Per parameter, the share of its unit change (in scale units) that lies in what the log sees, 0 to 1
        (0 for a parameter that is not free).
    active : tuple of str
        The physical constraints the estimate rests on, by name (a body held physical by moving what the log
        does not see, a mass at its least, a friction coefficient at 0).
    moved : float
        How far what the log does not see moved, in scale units (0 when it stayed at the URDF's).
    divergence : numpy.ndarray, shape (n_bodies,)
        d(Jᵢ ‖ Jᵢ₀) of each body (0 for a body that is not free).
    """

    theta: np.ndarray
    solver: str
    shares: np.ndarray
    seen: np.ndarray
    active: tuple[str, ...]
    moved: float
    divergence: np.ndarray


def pseudo_inertia(p) -> np.ndarray:
    """J of one body's ten parameters (m, h, I about the origin, as
    :data:`~course_dynamics.core.regressor.PARAMETER_NAMES` orders them).

    J = [[Σ, h], [hᵀ, m]] with Σ = ∫ r rᵀ dm = ½ tr(I) 1 − I. J ⪰ 0 holds exactly for real bodies:
    it implies m ≥ 0, an inertia about the centre of mass that is positive semi-definite and
    obeys the triangle inequality.

    Parameters
    ----------
    p : array_like, shape (10,)
        m (kg), h = m c (kg·m), then Ixx, Ixy, Iyy, Ixz, Iyz, Izz about the body's frame origin (kg·m²).

    Returns
    -------
    numpy.ndarray, shape (4, 4)
        The pseudo-inertia J, kg·m² (Σ), kg·m (h) and kg (m).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.regressor import parameters
    >>> J = pseudo_inertia(parameters(load_robot("two_link"))[10:20])   # a point mass, 1 kg at (0.4, 0, 0)
    >>> J.round(3).tolist()
    [[0.16, 0.0, 0.0, 0.4], [0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0], [0.4, 0.0, 0.0, 1.0]]
    """
    p = np.asarray(p, dtype=float)
    inertia = p[np.array(TENSOR)]
    J = np.empty((4, 4))
    J[:3, :3] = 0.5 * np.trace(inertia) * np.eye(3) - inertia
    J[:3, 3] = J[3, :3] = p[1:4]
    J[3, 3] = p[0]
    return J


def divergence(J, J0) -> float:
    """d(J ‖ J₀) = −log det(J₀⁻¹ J) + tr(J₀⁻¹ J) − 4 (module docstring); ∞ unless J ≻ 0.

    Parameters
    ----------
    J, J0 : array_like, shape (4, 4)
        Two pseudo-inertias, J₀ positive definite.

    Returns
    -------
    float
        The divergence, ≥ 0, 0 only at J = J₀.

    Examples
    --------
    >>> import numpy as np
    >>> J0 = np.diag([0.01, 0.01, 0.01, 1.0])
    >>> divergence(J0, J0), round(divergence(2 * J0, J0), 4)   # doubling a body costs 4 (1 − log 2)
    (0.0, 1.2274)
    """
    M = np.linalg.solve(np.asarray(J0, float), np.asarray(J, float))
    sign, logdet = np.linalg.slogdet(M)
    return float(np.inf) if sign <= 0 else max(float(-logdet + np.trace(M) - 4.0), 0.0)


def _basis() -> np.ndarray:
    """B (10, 4, 4) with J(p) = Σₖ pₖ Bₖ."""
    return np.stack([pseudo_inertia(e) for e in np.eye(10)])


def prior_pseudo_inertia(p, mass_scale: float, length: float) -> np.ndarray:
    """Jᵢ₀ the divergence is taken from: the URDF's, plus ε m diag(ℓ², ℓ², ℓ², 1) where it is (nearly) singular.

    Parameters
    ----------
    p : array_like, shape (10,)
        The body's URDF parameters (:func:`pseudo_inertia`).
    mass_scale : float
        m, the body's mass scale, kg.
    length : float
        ℓ, its link's extent, m.

    Returns
    -------
    numpy.ndarray, shape (4, 4)
        J₀, positive definite.
    """
    J0 = pseudo_inertia(p)
    lowest = np.linalg.eigvalsh(J0).min()
    floor = SINGULAR_EPSILON * mass_scale * min(length**2, 1.0)
    if lowest >= floor:
        return J0
    return J0 + SINGULAR_EPSILON * mass_scale * np.diag([length**2, length**2, length**2, 1.0])


def _is_physical(p, min_mass) -> bool:
    values = np.linalg.eigvalsh(pseudo_inertia(p))
    return values.min() >= -PHYSICAL_TOLERANCE * max(values.max(), 1e-300) and p[0] >= min_mass * (1 - 1e-9)


def consistent_fit(model, R, sigma, count, theta_urdf, free, scale, lengths, names, prior_weight, threshold,
                   min_mass, at_least_zero=None) -> ConsistentFit:
    """The physically consistent θ (module docstring).

    Parameters
    ----------
    model : Model
        The robot whose bodies the first 10 n_bodies entries of θ describe.
    R : numpy.ndarray, shape (m, r, P + 1)
        Per measured joint, the triangular factor of [Yⱼ | τⱼ] (the fit's data, P parameters).
    sigma : numpy.ndarray, shape (m,)
        Each measured joint's torque noise σⱼ, N·m (N for a prismatic joint): the weights are 1/σⱼ.
    count : int
        N, the number of weighted torques R stands for (samples times measured joints).
    theta_urdf : numpy.ndarray, shape (P,)
        The URDF's θ: the prior, and the value of what the log does not see.
    free : numpy.ndarray of bool, shape (P,)
        The entries that may change (a held joint's body and friction are not free).
    scale : numpy.ndarray, shape (P,)
        S, the size a change of each entry is measured in (positive).
    lengths : numpy.ndarray, shape (n_bodies,)
        ℓᵢ, each link's extent, m.
    names : sequence of str
        The names of θ's entries, for the constraints named.
    prior_weight : float
        λ ≥ 0, the weight of the divergence against the mean squared weighted residual.
    threshold : float
        The share of the largest singular value of A S below which a direction counts as not seen.
    min_mass : numpy.ndarray, shape (n_bodies,)
        The least mass of each body, kg.
    at_least_zero : dict of str to list of int, optional
        The entries after the bodies' held ≥ 0, by what they are (``{"friction": [...], "armature": [...]}``);
        default every one, as friction; an entry in none (a torque offset) has no bound.

    Returns
    -------
    ConsistentFit
        The estimate, the solver, what the log sees and the constraints the estimate rests on.

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
    count = max(float(count), 1.0)
    Rw = np.linalg.qr(weighted, mode="r")                  # ‖W (Y θ − τ)‖ = ‖Rw[:, :P] θ − Rw[:, P]‖
    A, z = Rw[:, :P], Rw[:, P]
    F = np.flatnonzero(free)
    As = A[:, F] * scale[F]
    _, s, Vt = np.linalg.svd(As, full_matrices=True)
    shares = np.zeros(len(F))
    shares[:len(s)] = s / s[0] if len(s) and s[0] > 0 else 0.0
    seen_rows = shares >= threshold
    VE = Vt[seen_rows].T
    seen = np.zeros(P)
    seen[F] = np.sum(VE**2, axis=1)
    residual = z - A @ theta_urdf
    embed = np.zeros((P, len(F)))
    embed[F, np.arange(len(F))] = scale[F]
    k = VE.shape[1]
    y = cp.Variable(len(F))                                # θ = θ_urdf + E V y: y[:k] seen, y[k:] not
    basis = _basis().reshape(10, 16).T                     # vec Jᵢ = B pᵢ (J symmetric: either order)
    bodies = [i for i in range(model.n_bodies) if free[10 * i:10 * i + 10].any()]
    priors = {i: prior_pseudo_inertia(theta_urdf[10 * i:10 * i + 10], scale[10 * i], lengths[i]) for i in bodies}
    groups = {"friction": [k for k in range(n_rigid, P)]} if at_least_zero is None else at_least_zero
    groups = {label: [k for k in F if k in set(ks)] for label, ks in groups.items()}
    friction = sorted(k for ks in groups.values() for k in ks)

    def physical(t, T, v, logdet):
        """The constraints on θ = t + T v (constants t and T, the variable v), and Σ d(Jᵢ ‖ Jᵢ₀) less its
        constants when ``logdet``; each a product of constant matrices and v, so cvxpy's trees stay small."""
        constraints, penalty = [], 0
        for i in bodies:
            rows = slice(10 * i, 10 * i + 10)
            J = cp.Variable((4, 4), PSD=True)
            constraints.append(cp.vec(J, order="F") == basis @ t[rows] + (basis @ T[rows]) @ v)
            if logdet:  # trace(Jᵢ₀⁻¹ Jᵢ) = vec(Jᵢ₀⁻¹) · vec(Jᵢ)
                penalty = penalty - cp.log_det(J) + np.linalg.inv(priors[i]).ravel() @ cp.vec(J, order="F")
        masses = [10 * i for i in bodies]
        if masses:
            constraints.append(T[masses] @ v >= min_mass[bodies] - t[masses])
        if friction:
            constraints.append(T[friction] @ v >= -t[friction])
        return constraints, penalty

    embedded = embed @ Vt.T                                # θ's change for each entry of y
    constraints, penalty = physical(theta_urdf, embedded, y, prior_weight > 0)
    objective = cp.sum_squares((A @ embedded[:, :k]) @ y[:k] - residual) / count if k else 0
    if bodies and prior_weight > 0:
        objective = objective + prior_weight * penalty
    if k < len(F):
        objective = objective + HOLD * cp.sum_squares(y[k:])
    solver = _solve(cp.Problem(cp.Minimize(objective), constraints), model.name)
    a_value = y.value[:k]
    kept = theta_urdf + embedded[:, :k] @ a_value
    unphysical = [i for i in bodies if not _is_physical(kept[10 * i:10 * i + 10], min_mass[i])]
    active, moved = [], 0.0
    if unphysical and k < len(F):   # the least move of what the log does not see that makes every body physical
        b = cp.Variable(len(F) - k)
        constraints, _ = physical(kept, embedded[:, k:], b, False)
        _solve(cp.Problem(cp.Minimize(cp.sum_squares(b)), constraints), model.name)
        moved = float(np.linalg.norm(b.value))
        change = embedded[:, k:] @ b.value / scale
        kept = kept + embedded[:, k:] @ b.value
        active = [f"body '{model.bodies[i].name}': physical only with what the log does not see moved by "
                  f"{float(np.linalg.norm(change[10 * i:10 * i + 10])):.3g} (in its scale)" for i in unphysical]
    for i in bodies:
        if free[10 * i] and kept[10 * i] <= min_mass[i] * (1 + 1e-6):
            active.append(f"body '{model.bodies[i].name}': mass at its least, {min_mass[i]:.4g} kg")
    for label, ks in groups.items():
        at_zero = [names[k] for k in ks if kept[k] <= 1e-9 * scale[k]]
        active += [f"{label} at 0: {', '.join(at_zero)}"] if at_zero else []
    spent = np.zeros(model.n_bodies)
    for i in bodies:
        spent[i] = divergence(pseudo_inertia(kept[10 * i:10 * i + 10]), priors[i])
    return ConsistentFit(theta=kept, solver=solver, shares=shares, seen=seen, active=tuple(active), moved=moved,
                         divergence=spent)


def _solve(problem, robot: str) -> str:
    import cvxpy as cp

    for solver, options in (("CLARABEL", {}), ("SCS", {"eps": 1e-9, "max_iters": 200_000})):
        try:
            with warnings.catch_warnings(record=True) as said:  # cvxpy's warnings, as ours: one line each
                warnings.simplefilter("always")
                problem.solve(solver=solver, **options)
        except (cp.error.SolverError, ValueError):
            continue
        finally:
            for warning in said:
                warnings.warn(f"robot '{robot}', the physically consistent fit ({solver.lower()}): "
                              f"{warning.message}", CourseDynamicsWarning)
        if problem.status in ("optimal", "optimal_inaccurate") and problem.value is not None:
            return solver.lower() + ("" if problem.status == "optimal" else " (inaccurate)")
    raise InputError(f"robot '{robot}': the physically consistent fit found no solution (Clarabel and SCS: "
                     f"{problem.status}); the log may not move the joints enough")


__all__ = ["HOLD", "SINGULAR_EPSILON", "ConsistentFit", "consistent_fit", "divergence", "prior_pseudo_inertia",
           "pseudo_inertia"]

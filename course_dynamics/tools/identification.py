"""Identification: from a robot's log to the inertial and friction parameters it really has, physically consistent.

==================  =============  ====================================================================
code                symbol         meaning (shape, unit)
==================  =============  ====================================================================
``pi``              π              inertial parameters, 10 per moving body (:mod:`~course_dynamics.core.regressor`)
``Y``               Y(Θ, Θ̇, Θ̈)     the regressor: τ = Y π (K, n, 10 n)
``friction``        F_v, F_c       viscous and Coulomb coefficients per joint: τ_F = F_v θ̇ + F_c sgn θ̇ (6.112)
``drives``          Iₐ, τ₀         each joint's rotor inertia and torque offset (:mod:`~course_dynamics.core.drives`):
                                   τ gains Iₐ θ̈ + τ₀
``theta``           θ              π and the friction coefficients identified, one vector
``base``            π_b = β π      the base parameters: the combinations of π the torques can tell apart
``sigma``           σⱼ             the noise of joint j's measured torque, from a first unweighted fit
``W``               W              row weights 1/σⱼ
``J``               J(π)           the pseudo-inertia of a body, [[½ tr(I) 1 − I, h], [hᵀ, m]] (4, 4),
                                   I about the frame origin; J ⪰ 0 is what a real body has
==================  =============  ====================================================================

The steps, on the samples of a :class:`~course_dynamics.tools.logs.JointLog` (Θ, Θ̇, Θ̈ as
:func:`~course_dynamics.tools.logs.joint_log` read or differentiated them; τ_meas as the robot measured):

1. the last ``holdout`` share of the log's time is held out; the rest is fitted;
2. ordinary least squares on the base parameters (and friction) gives each joint's residual σⱼ;
   weighted least squares with weights 1/σⱼ gives the estimate, its standard errors
   (the diagonal of s² (Yᵀ W² Y)⁻¹) and the condition number of W Y_b with unit-norm columns;
3. the physically consistent estimate (:mod:`~course_dynamics.tools.consistency`: cvxpy, Clarabel,
   SCS if that fails) minimises the mean squared weighted residual plus λ Σᵢ d(Jᵢ ‖ Jᵢ₀), the
   log-determinant divergence of each body's pseudo-inertia from the URDF's (λ = ``prior_weight``),
   subject to J(πᵢ) ⪰ 0, mᵢ ≥ m_min and F_v, F_c ≥ 0; only the directions the log sees move (a
   singular value of the weighted regressor, each parameter in its body's scale, at least
   ``threshold`` of the largest): the rest stays at the URDF's values unless a body would then not be
   physical (``active`` names it). Friction has no prior. A joint held still in the log (its
   position spanning at most ``HELD`` = 1e-4 rad or m) is a fixed joint: its body keeps the URDF's parameters,
   its rows and friction are left out, and the base parameters are those of the robot with it fixed;
4. the held-out part is predicted by the URDF and by the identified model (their RMS residuals).

Friction that is not identified (``friction="viscous"``: the Coulomb part) is the URDF's
``<dynamics>``, subtracted from τ_meas before fitting. Θ̇ is the log's, as for the torques: the
sign of a Coulomb term follows the measured rate.

Drives (``fit_drives``): an armature adds the column θ̈ⱼ to joint j's rows, an offset the column 1; like
friction they have no prior, are fitted with the base parameters (standard errors included) and an armature
is held ≥ 0. What is not fitted is ``drives``' value (zero without), subtracted from τ_meas as known; what is
fitted starts there, and stays there where the log does not see it. A drive column that the rigid base
parameters already span at every state (to ``SPANNED`` = 1e-6) cannot be told apart from them: the armature of a
first joint moves with its body's inertia about the axis (both multiply θ̈₁ alone), the offset of a vertical
first prismatic joint with the weight it lifts. Such a column is not fitted (it keeps ``drives``' value) and
a note names the base parameters that absorb it: those combinations are then reported as such.

>>> import numpy as np
>>> from dataclasses import replace
>>> from course_dynamics import load_robot, inverse_dynamics
>>> from course_dynamics.tools.logs import joint_log
>>> arm = load_robot("two_link")
>>> true = replace(arm, bodies=(arm.bodies[0], replace(arm.bodies[1], mass=1.3)))
>>> t = np.arange(0, 6, 0.01)
>>> q = np.column_stack([np.sin(1.3 * t), np.cos(0.7 * t) + 0.2 * np.sin(2.9 * t)])
>>> qd = np.gradient(q, t, axis=0); qdd = np.gradient(qd, t, axis=0)
>>> tau = inverse_dynamics(true, q, qd, qdd)
>>> columns = {"t": t, "q_theta1": q[:, 0], "q_theta2": q[:, 1], "qd_theta1": qd[:, 0], "qd_theta2": qd[:, 1],
...            "qdd_theta1": qdd[:, 0], "qdd_theta2": qdd[:, 1],
...            "tau_meas_theta1": tau[:, 0], "tau_meas_theta2": tau[:, 1]}
>>> found = identify(arm, joint_log(arm, columns), friction="none")
>>> bool(found.rms_after.max() < 1e-3 * found.rms_before.max())       # on the held-out last 20 %
True
>>> found.base.describe().splitlines()[3], round(float(found.base_consistent[3]), 4)   # m₂ c₂: 1.3 kg at 0.4 m
('π_b4 = mcx_2', 0.52)
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.errors import InputError
from ..base.resources import check_memory
from ..core.evaluator import inverse_dynamics, regressor  # the evaluator chooses the implementation of each call
from ..core.drives import Drives
from ..core.friction import Friction
from ..core.inertia import physical_problems
from ..core.model import Model
from ..core.regressor import TENSOR, BaseParameters, base_parameters, parameter_names, parameters, with_parameters
from ..core.sampling import random_states
from .consistency import consistent_fit, pseudo_inertia
from .logs import JointLog
from .plausibility import far_moves, link_extents

#: Which friction :func:`identify` can identify (both parts, the viscous or the Coulomb part only, or none).
FRICTION_MODELS = ("both", "viscous", "coulomb", "none")
SYMBOLS = {"viscous": "Fv", "coulomb": "Fc", "armature": "Ia", "offset": "tau0"}   # Fv_<joint>, Ia_<joint>, …
#: What a drive can add to the fit (its column in joint j's rows: θ̈ⱼ, 1).
DRIVE_PARTS = ("armature", "offset")
#: A drive column whose sine of angle to the rigid base regressor's span, over random states, is below this is spanned.
SPANNED = 1e-6
ROWS_AT_A_TIME = 2048         # samples per regressor block: (2048, n, 10 n) floats, 6 MB for a UR5
#: The default λ of step 3, the weight of the bodies' divergence from the URDF against the mean squared residual.
PRIOR_WEIGHT = 1e-5
#: A direction whose singular value (in scale units) is below this share of the largest is not seen by the log.
UNSEEN = 1e-4
#: A joint whose position spans at most this (rad or m) in the log is held, a fixed joint for the fit.
HELD = 1e-4
SEEN_SPLIT = 0.01             # a parameter is determined when ≥ 99 % of it is seen, kept when ≤ 1 %
#: m_min by default, as this share of the URDF's mass of each body (at least :data:`MIN_MASS`).
MIN_MASS_SHARE = 0.01         # m_min: 1 % of the URDF's mass of the body (MIN_MASS for a massless one)
#: The least m_min of a body, kg.
MIN_MASS = 1e-6               # kg
UNEXCITED = 1e-3              # a direction whose singular value is below this share of the largest
NOISE_FLOOR = 1e-9            # σⱼ at least this share of the RMS measured torque (noise-free data)


@dataclass(frozen=True)
class Identification:
    """What :func:`identify` found (module docstring). Arrays per joint are NaN for joints not measured.

    ``model`` and ``friction``: the identified robot; ``original``, ``original_friction``: the URDF's.
    ``names``/``pi_urdf``/``pi``: every parameter (π, then the identified friction coefficients).
    ``base``: the base parameters; ``base_urdf``, ``base_wls``, ``base_error``, ``base_consistent``:
    their values (friction after the rigid ones, as ``base_names``) before, by weighted least squares
    with its standard errors, and in the consistent estimate. ``unexcited``: the directions the log
    hardly excites, as (share of the largest singular value, combination); ``never_act``: parameters
    no motion can reveal. ``held_out``: (t, τ_meas, τ_URDF, τ_identified) on the held-out samples.

    Parameters
    ----------
    model : Model
        The identified robot.
    friction : Friction
        The identified friction (the URDF's where a part was not identified).
    original : Model
        The URDF's robot.
    original_friction : Friction
        The URDF's friction.
    friction_model : str
        What friction was identified, one of :data:`FRICTION_MODELS`.
    names : tuple of str
        The names of every parameter: π, then the identified friction coefficients.
    pi_urdf : numpy.ndarray, shape (P,)
        The URDF's values of ``names`` (SI: kg, kg·m, kg·m², N·m·s/rad, N·m).
    pi : numpy.ndarray, shape (P,)
        The identified values of ``names``.
    base : BaseParameters
        The base parameters π_b = β π.
    base_names : tuple of str
        The base parameters' names, then the friction coefficients'.
    base_urdf : numpy.ndarray, shape (B,)
        The URDF's values of ``base_names``.
    base_wls : numpy.ndarray, shape (B,)
        The weighted least-squares values of ``base_names``.
    base_error : numpy.ndarray, shape (B,)
        Their standard errors.
    base_consistent : numpy.ndarray, shape (B,)
        The physically consistent values of ``base_names``.
    condition_number : float
        The condition number of W Y_b with unit-norm columns.
    unexcited : tuple of (float, str)
        The directions the log hardly excites: (share of the largest singular value, combination).
    never_act : tuple of str
        The parameters no motion can reveal.
    sigma : numpy.ndarray, shape (n,)
        Each joint's torque noise σⱼ, N·m (N for a prismatic joint); NaN where not measured.
    split_t : float
        Where the held-out part starts, s.
    samples : tuple of (int, int)
        The samples fitted and held out.
    held_out : tuple of numpy.ndarray
        (t (H,) s, τ_meas, τ_URDF, τ_identified (H, n) N·m) on the held-out samples.
    rms_before : numpy.ndarray, shape (n,)
        The URDF's RMS residual on the held-out part, per joint, N·m.
    rms_after : numpy.ndarray, shape (n,)
        The identified model's RMS residual on the held-out part, per joint, N·m.
    solver : str
        The solver of the consistent fit, as
        :func:`~course_dynamics.tools.consistency.consistent_fit` names it.
    notes : tuple of str
        What the reader should know (joints left out, joints held).
    held : tuple of str
        The joints held still in the log (a fixed joint for the fit; their bodies are the URDF's).
    scale : numpy.ndarray, shape (P,)
        The size a change of each parameter is measured in (:mod:`~course_dynamics.tools.consistency`).
    threshold : float
        The share of the largest singular value below which a direction counts as not seen.
    shares : numpy.ndarray
        The singular values of the weighted regressor in scale units (free parameters), shares of the largest.
    seen : numpy.ndarray, shape (P,)
        Per parameter, the share of it the log sees, 0 (kept at the URDF's) to 1 (determined by the log).
    active : tuple of str
        The physical constraints the estimate rests on, by name.
    moved : float
        How far what the log does not see moved to keep the bodies physical, scale units (0: it did not).
    far : tuple of str
        Bodies that moved far: a mass more than doubled or halved, a centre of mass outside its link.
    bodies : tuple of dict
        Per body: the parameters ``determined``, seen ``in_combination``, ``kept`` at the URDF's, its
        ``divergence`` from the URDF's and its ``warnings``.
    drives : Drives, optional
        The identified drives (the given ones where a part was not fitted); None: none given or fitted.
    original_drives : Drives, optional
        The drives given (a file's), or none.
    drive_error : numpy.ndarray, shape (2, n), optional
        The weighted fit's standard errors of the armatures and the offsets, NaN where not fitted.
    """

    model: Model
    friction: Friction
    original: Model
    original_friction: Friction
    friction_model: str
    names: tuple[str, ...]
    pi_urdf: np.ndarray
    pi: np.ndarray
    base: BaseParameters
    base_names: tuple[str, ...]
    base_urdf: np.ndarray
    base_wls: np.ndarray
    base_error: np.ndarray
    base_consistent: np.ndarray
    condition_number: float
    unexcited: tuple[tuple[float, str], ...]
    never_act: tuple[str, ...]
    sigma: np.ndarray
    split_t: float
    samples: tuple[int, int]
    held_out: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
    rms_before: np.ndarray
    rms_after: np.ndarray
    solver: str
    notes: tuple[str, ...] = ()
    held: tuple[str, ...] = ()
    scale: np.ndarray | None = None
    threshold: float = 0.0
    shares: np.ndarray | None = None
    seen: np.ndarray | None = None
    active: tuple[str, ...] = ()
    moved: float = 0.0
    far: tuple[str, ...] = ()
    bodies: tuple[dict, ...] = ()
    drives: Drives | None = None
    original_drives: Drives | None = None
    drive_error: np.ndarray | None = None

    def record(self) -> dict:
        """A JSON-ready summary (no arrays of samples).

        Returns
        -------
        dict
            The robot, options, σ, held-out RMS residuals, every parameter and base parameter (URDF, fitted,
            identified), and the notes; non-finite numbers as None.
        """
        def listed(a):
            return [None if not np.isfinite(x) else float(x) for x in np.asarray(a, dtype=float)]
        joints = self.model.joint_names
        return {
            "robot": self.model.name, "friction_model": self.friction_model, "solver": self.solver,
            "samples": {"fitted": self.samples[0], "held_out": self.samples[1]}, "split_t": self.split_t,
            "condition_number": None if not np.isfinite(self.condition_number) else self.condition_number,
            "sigma": dict(zip(joints, listed(self.sigma))),
            "held_out_rms": {"urdf": dict(zip(joints, listed(self.rms_before))),
                             "identified": dict(zip(joints, listed(self.rms_after)))},
            "parameters": [{"name": n, "urdf": a, "identified": b}
                           for n, a, b in zip(self.names, listed(self.pi_urdf), listed(self.pi))],
            "base_parameters": [{"name": n, "urdf": a, "wls": b, "standard_error": e, "identified": c}
                                for n, a, b, e, c in zip(self.base_names, listed(self.base_urdf),
                                                         listed(self.base_wls), listed(self.base_error),
                                                         listed(self.base_consistent))],
            "base_definitions": self.base.describe().splitlines(),
            "unexcited": [{"singular_value_share": s, "combination": c} for s, c in self.unexcited],
            "never_act": list(self.never_act), "notes": list(self.notes),
            "held": list(self.held), "unseen_threshold": self.threshold, "active_constraints": list(self.active),
            "unseen_moved": self.moved, "far": list(self.far), "bodies": [dict(b) for b in self.bodies],
            **({} if self.drives is None else {"drives": {joint: {
                "armature": float(self.drives.armature[j]), "armature_error": listed(self.drive_error[0])[j],
                "offset": float(self.drives.offset[j]), "offset_error": listed(self.drive_error[1])[j]}
                for j, joint in enumerate(joints)}}),
        }


def _friction_columns(friction: str, measured) -> list[tuple[str, int]]:
    """(kind, joint) of each identified friction coefficient, in θ's order after π: the measured joints' only
    (a joint's friction acts on its own torque alone)."""
    kinds = [k for k in ("viscous", "coulomb") if friction in (k, "both")]
    return [(kind, j) for j in measured for kind in kinds]


def _design(model: Model, log: JointLog, rows, columns) -> np.ndarray:
    """[Y | friction columns] for ``rows``: (K, n, P)."""
    Y = regressor(model, log.q[rows], log.qd[rows], log.qdd[rows])
    F = np.zeros(Y.shape[:2] + (len(columns),))
    for k, (kind, j) in enumerate(columns):
        F[:, j, k] = (log.qd[rows, j] if kind == "viscous" else np.sign(log.qd[rows, j]) if kind == "coulomb"
                      else log.qdd[rows, j] if kind == "armature" else 1.0)   # τ gains Iₐ θ̈ + τ₀
    return np.concatenate([Y, F], axis=2)


def _factors(model, log, rows, columns, target, measured, progress, design=None) -> np.ndarray:
    """Per measured joint j, the triangular R_j (r, P + 1) with R_jᵀ R_j = [Yⱼ | τⱼ]ᵀ [Yⱼ | τⱼ], r ≤ P + 1.

    Built a block of samples at a time (a QR of the factor so far stacked on the block), so any
    least-squares problem in Yⱼ and τⱼ keeps its size and its conditioning (no normal equations):
    ‖Yⱼ θ − τⱼ‖ = ‖R_j[:, :P] θ − R_j[:, P]‖. R_j has as many rows as the samples so far, at most
    P + 1: a short log costs what its samples do. ``progress`` moves after each joint's QR. ``design(block)``
    gives the (K, n, P) design of samples ``block`` (default :func:`_design`'s [Y | friction columns]).
    """
    if design is None:
        def design(block):
            return _design(model, log, block, columns)
    P = design(rows[:1]).shape[2]
    R = np.zeros((len(measured), 0, P + 1))
    for start in range(0, len(rows), ROWS_AT_A_TIME):
        block = rows[start:start + ROWS_AT_A_TIME]
        A = design(block)[:, measured, :]     # (K, m, P)
        b = target[block][:, measured]
        old, grown = R, min(R.shape[1] + len(block), P + 1)
        if grown != R.shape[1]:
            R = np.empty((len(measured), grown, P + 1))
        for j in range(len(measured)):
            R[j] = np.linalg.qr(np.vstack([old[j], np.column_stack([A[:, j], b[:, j]])]), mode="r")
            if progress is not None:
                progress(start + len(block) * (j + 1) // len(measured), len(rows))
    return R


def memory_needed(n: int, parameters: int, samples: int, measured: int) -> float:
    """Bytes an identification of ``parameters`` from ``samples`` of ``measured`` joints of an n-joint robot keeps
    at its peak: a few copies of the factors R (m, r, P + 1) (their QRs, the weighted fits), a block's regressor,
    and the consistent fit's problem (cvxpy's, measured near 400 (P + 1)² bytes: 0.99 GB in all at n = 100, 3.4 GB
    at 200)."""
    factors = 8.0 * measured * min(samples, parameters + 1) * (parameters + 1)
    return 6 * factors + 4 * 8.0 * min(samples, ROWS_AT_A_TIME) * n * parameters + 400.0 * (parameters + 1) ** 2


def _solve(M: np.ndarray, r: np.ndarray) -> np.ndarray:
    """The least-squares θ of M θ ≈ r, on unit-norm columns (directions below 1e-10 of the largest dropped)."""
    d = np.linalg.norm(M, axis=0)
    d[d == 0] = 1.0
    return np.linalg.lstsq(M / d, r, rcond=1e-10)[0] / d


def _weighted_fit(R, counts, where, full: bool = False):
    """Unweighted, then weighted least squares on the columns ``where`` (step 2).

    Returns σⱼ, θ, its standard errors (with ``full``, their covariance s² (Yᵀ W² Y)⁻¹), and the singular values
    (shares of the largest) and right singular vectors of W Y_b with unit-norm columns.
    """
    X, y = R[:, :, where], R[:, :, -1]
    theta0 = _solve(X.reshape(-1, len(where)), y.reshape(-1))
    dof = np.maximum(counts - len(where) / len(counts), 1.0)
    sigma = np.sqrt(np.sum((X @ theta0 - y) ** 2, axis=1) / dof)
    sigma = np.maximum(sigma, NOISE_FLOOR * np.sqrt(np.sum(y**2, axis=1) / counts) + 1e-300)
    Xw, yw = (X / sigma[:, None, None]).reshape(-1, len(where)), (y / sigma[:, None]).reshape(-1)
    theta = _solve(Xw, yw)
    s2 = float(np.sum((Xw @ theta - yw) ** 2)) / max(counts.sum() - len(where), 1.0)
    d = np.linalg.norm(Xw, axis=0)
    d[d == 0] = 1.0
    _, S, Vt = np.linalg.svd(Xw / d, full_matrices=False)
    kept = S > 1e-10 * S[0]
    covariance = (Vt[kept].T / S[kept] ** 2) @ Vt[kept] / np.outer(d, d) * s2
    error = covariance if full else np.sqrt(np.maximum(np.diag(covariance), 0.0))
    return sigma, theta, error, S / S[0], Vt


def _scales(model, lengths, theta_wls, columns, where, urdf_values) -> np.ndarray:
    """S: body i's mᵢ, mᵢ ℓᵢ, mᵢ ℓᵢ² (the URDF's mass, or the bodies' RMS mass for a massless one), and each friction
    kind's RMS coefficient in the weighted fit or in the URDF (``urdf_values``, in ``columns``' order), the larger
    (1 without either). A log without friction fits coefficients of round-off size: as a scale alone they would
    count friction as unseen and hold it at the URDF's, which the log contradicts by far more than its noise."""
    masses = np.array([float(b.mass) for b in model.bodies])
    typical = np.sqrt(np.mean(masses[masses > 0] ** 2)) if np.any(masses > 0) else 1.0
    masses = np.where(masses > 0, masses, typical)
    scale = np.concatenate([m * np.array([1.0, *[l] * 3, *[l * l] * 6]) for m, l in zip(masses, lengths)])
    estimate = dict(zip(where, theta_wls))
    n_rigid = 10 * model.n_bodies
    friction = np.ones(len(columns))
    for kind in ("viscous", "coulomb", *DRIVE_PARTS):
        ks = [k for k, (c, _) in enumerate(columns) if c == kind]
        values = np.array([abs(estimate.get(n_rigid + k, 0.0)) for k in ks])
        urdf = np.abs(np.asarray(urdf_values, dtype=float)[ks])
        size = max(np.sqrt(np.mean(values**2)), np.sqrt(np.mean(urdf**2))) if len(values) else 0.0
        friction[ks] = size if size > 0 else 1.0
    return np.concatenate([scale, friction])


def _physical(pi: np.ndarray, model: Model, min_mass, bodies) -> np.ndarray:
    """π with every body of ``bodies`` J ⪰ 0 exactly (the solver's round-off clipped), so that loaders accept it."""
    pi = pi.copy()
    for i in bodies:
        body = model.bodies[i]
        J = pseudo_inertia(pi[10 * i:10 * i + 10])
        values, vectors = np.linalg.eigh(J)
        if values.min() < 1e-12 * max(values.max(), 0.0):
            J = (vectors * np.maximum(values, 1e-12 * max(values.max(), 0.0))) @ vectors.T
        mass = max(J[3, 3], min_mass[i] * (1 - 1e-9))
        inertia = np.trace(J[:3, :3]) * np.eye(3) - J[:3, :3]
        upper = ((0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2))   # Ixx, Ixy, Iyy, Ixz, Iyz, Izz
        pi[10 * i:10 * i + 10] = [mass, *J[:3, 3]] + [inertia[a, b] for a, b in upper]
        problems = physical_problems(with_parameters(model, pi).bodies[i].I_com)
        if problems:
            raise InputError(f"body '{body.name}': the identified inertia {problems[0]} (a solver failure)")
    return pi


def _body_summary(model, names, seen, fit, far) -> list[dict]:
    """Per body: the parameters the log determined (alone), saw only in combination, and left at the URDF's."""
    rows = []
    for i, body in enumerate(model.bodies):
        block = range(10 * i, 10 * i + 10)
        rows.append({"body": body.name,
                     "determined": [names[k] for k in block if seen[k] >= 1 - SEEN_SPLIT],
                     "in_combination": [names[k] for k in block if SEEN_SPLIT < seen[k] < 1 - SEEN_SPLIT],
                     "kept": [names[k] for k in block if seen[k] <= SEEN_SPLIT],
                     "divergence": float(fit.divergence[i]) if np.isfinite(fit.divergence[i]) else None,
                     "warnings": [line for line in far if line.startswith(f"body '{body.name}':")]})
    return rows


def _spanned(model: Model, base: BaseParameters, held: dict, columns) -> dict[int, list[int]]:
    """Per drive column (its index in ``columns``) that the rigid base regressor spans at the base parameters'
    random states: the base parameters that absorb it (module docstring)."""
    q, qd, qdd = random_states(model, base.samples, base.seed)
    for j, value in held.items():
        q[:, j], qd[:, j], qdd[:, j] = value, 0.0, 0.0
    rows = [j for j in range(model.n) if j not in held]
    Yb = regressor(model, q, qd, qdd)[:, rows][:, :, list(base.independent)].reshape(-1, base.rank)
    unit = Yb / np.maximum(np.linalg.norm(Yb, axis=0), 1e-300)
    out = {}
    for k, (kind, j) in enumerate(columns):
        if kind not in DRIVE_PARTS:
            continue
        column = np.zeros((len(q), len(rows)))
        column[:, rows.index(j)] = qdd[:, j] if kind == "armature" else 1.0
        column = column.reshape(-1) / np.linalg.norm(column)
        K = np.linalg.lstsq(unit, column, rcond=None)[0]
        if np.linalg.norm(unit @ K - column) < SPANNED:
            out[k] = [int(b) for b in np.flatnonzero(np.abs(K) > SPANNED ** 0.5 * np.abs(K).max())]
    return out


def _kind(k: int, n_rigid: int, columns) -> str:
    """What θ's entry k is: a mass (m), a first moment (h), an inertia (I), or a friction kind."""
    if k >= n_rigid:
        return columns[k - n_rigid][0]
    return "m" if k % 10 == 0 else "h" if k % 10 < 4 else "I"


def _combination(vector, names) -> str:
    big = np.flatnonzero(np.abs(vector) >= 0.3 * np.abs(vector).max())
    lead = vector[big[np.argmax(np.abs(vector[big]))]]
    terms = [(vector[k] / lead, names[k]) for k in big]
    text = " ".join(f"{'-' if c < 0 else '+'} {'' if abs(c) == 1 else f'{abs(c):.3g} '}{name}" for c, name in terms)
    return text.removeprefix("+ ") if text.startswith("+") else "-" + text[2:]


def identify(model: Model, log: JointLog, friction: str = "both", holdout: float = 0.2,
             prior_weight: float = PRIOR_WEIGHT, min_mass=None, progress=None,
             where: str = "the log", threshold: float = UNSEEN, drives: Drives | None = None,
             fit_drives=()) -> Identification:
    """The parameters ``log`` shows ``model`` really has (module docstring).

    Parameters
    ----------
    model : Model
        The URDF's robot: its parameters are the prior and the starting point.
    log : JointLog
        A :class:`~course_dynamics.tools.logs.JointLog` with measured torques (``log.measured``).
    friction : str
        Which friction to identify: ``both``, ``viscous``, ``coulomb`` or ``none``.
    holdout : float
        The share of the log's time, at its end, kept out of the fit to judge it (0 ≤ holdout < 1).
    prior_weight : float
        λ ≥ 0, the weight of the URDF's values (step 3).
    min_mass : numpy.ndarray, shape (n,), optional
        The least mass of each body, kg; default 1 % of the URDF's (at least 1e-6 kg).
    progress : callable, optional
        Called as ``progress(done, total)`` (samples) while the regressor is computed.
    where : str
        How messages name the log (its file).
    threshold : float
        The share of the largest singular value (scale units) below which a direction counts as not seen by the
        log: it stays at the URDF's value.
    drives : Drives, optional
        The drives known (a file's): subtracted from τ_meas where not fitted, the start where fitted; default none.
    fit_drives : sequence of str
        Which drive parts to identify on every measured moving joint: ``"armature"``, ``"offset"`` (module
        docstring).

    Returns
    -------
    Identification
        The identified robot and friction, the fits' values and errors, and the held-out comparison.

    Raises
    ------
    InputError
        No measured torques, a bad option, a fitted part too short for the parameters, or no
        consistent solution; cvxpy missing (install ``course-dynamics[identify]``).

    Warns
    -----
    CourseDynamicsWarning
        What the consistent fit's solvers warn (an inaccurate solution).
    """
    if friction not in FRICTION_MODELS:
        raise InputError(f"unknown friction model '{friction}' (choose from {', '.join(FRICTION_MODELS)})")
    if not 0 <= holdout < 1:
        raise InputError(f"the held-out share must be at least 0 and less than 1, got {holdout}")
    if not (np.isfinite(prior_weight) and prior_weight >= 0):
        raise InputError(f"the prior weight must be a non-negative number, got {prior_weight}")
    if set(fit_drives) - set(DRIVE_PARTS):
        raise InputError(f"unknown drive parts {sorted(set(fit_drives) - set(DRIVE_PARTS))} (choose from "
                         f"{', '.join(DRIVE_PARTS)})")
    has_torque = [] if log.measured is None else [j for j in range(model.n)
                                                   if np.all(np.isfinite(log.measured[:, j]))]
    if not has_torque:
        raise InputError(f"{where} holds no measured torques: identification needs them, as tau_meas_<joint> columns "
                         f"(tau_meas_{model.joint_names[0]}, …), a bag's effort, Franka's tau_J, or current_<joint> "
                         "columns with torque constants")
    held = {j: float(log.q[0, j]) for j in range(model.n) if np.ptp(log.q[:, j]) <= HELD}
    measured = [j for j in has_torque if j not in held]
    if not measured:
        raise InputError(f"{where}: no joint with a measured torque moves in the log (each spans at most {HELD:g}): "
                         "there is nothing to identify")
    held_bodies = [k for k, (j, _, _) in enumerate(model.coupling) if j in held]
    columns = _friction_columns(friction, measured) + [(k, j) for j in measured for k in DRIVE_PARTS if k in fit_drives]
    base = base_parameters(model, held=held) if held else base_parameters(model)
    given = Drives.none(model) if drives is None else drives
    spanned = _spanned(model, base, held, columns)
    drive_notes = tuple(f"the {columns[k][0]} of joint '{model.joint_names[columns[k][1]]}' cannot be told apart "
                        f"from {', '.join(f'π_b{b + 1}' for b in bs)} (it multiplies what they multiply at every "
                        f"state): it is not fitted but kept at {getattr(given, columns[k][0])[columns[k][1]]:g}, "
                        f"and what the log shows of it is in those base parameters" for k, bs in spanned.items())
    columns = [c for k, c in enumerate(columns) if k not in spanned]
    identified = {(kind, j) for kind, j in columns}
    urdf_friction = Friction.from_urdf(model)
    fixed = Friction(viscous=[0.0 if ("viscous", j) in identified else v for j, v in enumerate(urdf_friction.viscous)],
                     coulomb=[0.0 if ("coulomb", j) in identified else c for j, c in enumerate(urdf_friction.coulomb)])
    known = Drives(*(np.where([(k, j) in identified for j in range(model.n)], 0.0, getattr(given, k))
                     for k in DRIVE_PARTS))
    target = np.where(np.isfinite(log.measured), log.measured, 0.0) - fixed.torques(log.qd) - known.torques(log.qdd)
    t = log.t
    split = t[0] + (1 - holdout) * (t[-1] - t[0])
    train = np.flatnonzero(t < split) if holdout > 0 else np.arange(len(t))
    test = np.flatnonzero(t >= split) if holdout > 0 else np.arange(0)
    n_rigid = 10 * model.n_bodies
    check_memory(memory_needed(model.n, n_rigid + len(columns), len(train), len(measured)),
                 f"{where}: identifying robot '{model.name}' ({model.n} joints, {n_rigid + len(columns)} parameters) "
                 f"from {len(train)} samples of {len(measured)} measured joints",
                 ": take a robot with fewer joints, or identify less friction (--friction-fit)")
    fitted = list(base.independent) + [n_rigid + k for k in range(len(columns))]
    if len(train) * len(measured) < 2 * len(fitted):
        raise InputError(f"{where}: the fitted part has {len(train)} samples of {len(measured)} measured joints, too "
                         f"few for {len(fitted)} base parameters (at least twice as many values are needed)")
    R = _factors(model, log, train, columns, target, measured, progress)
    counts = np.full(len(measured), float(len(train)))
    sigma, theta_wls, error, shares, directions = _weighted_fit(R, counts, fitted)
    theta_urdf = np.concatenate([parameters(model), [getattr(given if kind in DRIVE_PARTS else urdf_friction, kind)[j]
                                                     for kind, j in columns]])
    masses = np.array([b.mass for b in model.bodies], dtype=float)
    min_mass = np.maximum(MIN_MASS_SHARE * masses, MIN_MASS) if min_mass is None else np.asarray(min_mass, float)
    names = tuple(parameter_names(model)) + tuple(f"{SYMBOLS[kind]}_{model.joint_names[j]}" for kind, j in columns)
    lengths = link_extents(model)
    scale = _scales(model, lengths, theta_wls, columns, fitted, theta_urdf[n_rigid:])
    free = np.ones(len(theta_urdf), dtype=bool)
    for k in held_bodies:
        free[10 * k:10 * k + 10] = False
    groups = {label: [n_rigid + k for k, (kind, _) in enumerate(columns) if kind in kinds]
              for label, kinds in (("friction", ("viscous", "coulomb")), ("armature", ("armature",)))}
    fit = consistent_fit(model, R, sigma, len(train) * len(measured), theta_urdf, free, scale, lengths, names,
                         prior_weight, threshold, min_mass, groups)
    moving = [i for i in range(model.n_bodies) if i not in held_bodies]
    pi = _physical(fit.theta[:n_rigid], model, min_mass, moving)
    signed = np.array([kind == "offset" for kind, _ in columns], dtype=bool)
    theta = np.concatenate([pi, np.where(signed, fit.theta[n_rigid:], np.maximum(fit.theta[n_rigid:], 0.0))])
    solver = fit.solver
    found = with_parameters(model, pi)
    viscous, coulomb = fixed.viscous.copy(), fixed.coulomb.copy()
    armature, offset = given.armature.copy(), given.offset.copy()
    for (kind, j), value in zip(columns, theta[n_rigid:]):
        {"viscous": viscous, "coulomb": coulomb, "armature": armature, "offset": offset}[kind][j] = value
    found_friction, found_drives = Friction(viscous=viscous, coulomb=coulomb), Drives(armature, offset)

    base_names = tuple(f"π_b{k + 1}" for k in range(base.rank)) + names[n_rigid:]

    def base_values(th):
        return np.concatenate([base.values(th[:n_rigid]), th[n_rigid:]])
    unexcited = tuple((float(share), _combination(direction, base_names))
                      for share, direction in zip(shares, directions) if share < UNEXCITED)
    condition = float(1.0 / shares[-1]) if shares[-1] > 0 else float("inf")
    never_act = tuple(names[k] for k in range(n_rigid) if not base.beta[:, k].any())

    before = _predict(model, urdf_friction, log, test, given)
    after = _predict(found, found_friction, log, test, found_drives)
    rms_before, rms_after = (_per_joint(model, measured, np.sqrt(np.mean((log.measured[test] - tau) ** 2, axis=0))
                                        if len(test) else None) for tau in (before, after))
    notes = tuple(f"joint '{model.joint_names[j]}' has no measured torque: its rows are left out"
                  for j in range(model.n) if j not in has_torque)
    notes += tuple(f"joint '{model.joint_names[j]}' is held at {value:.6g} in the log: a fixed joint for the fit, "
                   f"its body left as the URDF has it" for j, value in held.items()) + drive_notes
    far = tuple(far_moves(model, found, lengths))
    return Identification(
        model=found, friction=found_friction, original=model, original_friction=urdf_friction, friction_model=friction,
        names=names, pi_urdf=theta_urdf, pi=theta, base=base, base_names=base_names, base_urdf=base_values(theta_urdf),
        base_wls=theta_wls, base_error=error, base_consistent=base_values(theta), condition_number=condition,
        unexcited=unexcited, never_act=never_act, sigma=_per_joint(model, measured, sigma, packed=True),
        split_t=float(split),
        samples=(len(train), len(test)), held_out=(t[test], log.measured[test], before, after),
        rms_before=rms_before, rms_after=rms_after, solver=solver, notes=notes,
        held=tuple(model.joint_names[j] for j in held), scale=scale, threshold=threshold, shares=fit.shares,
        seen=fit.seen, active=fit.active, moved=fit.moved, far=far,
        bodies=tuple(_body_summary(model, names, fit.seen, fit, far)),
        drives=found_drives if drives is not None or fit_drives else None, original_drives=given,
        drive_error=_drive_errors(model, columns, error[len(base.independent):]))


def fit_transformed(model: Model, log: JointLog, rows, measured, target, friction: str, transform, progress=None):
    """Step 2 on the regressor's columns transformed: Y (K, n, 10 n_bodies) becomes ``transform(Y)`` (K, n, p), the
    friction columns of ``friction`` after it; the factors of each measured joint, then the weighted least squares
    on every column (a payload's fit, :mod:`~course_dynamics.tools.payloads`: its ten columns of one body).

    Parameters
    ----------
    model : Model
        The robot.
    log : JointLog
        The log.
    rows : numpy.ndarray of int, shape (K,)
        The samples fitted.
    measured : list of int
        The joints whose rows are fitted.
    target : numpy.ndarray, shape (samples, n)
        What the columns are to explain, N·m (N).
    friction : str
        Which friction is fitted with them (:data:`FRICTION_MODELS`).
    transform : callable
        Y (K, n, 10 n_bodies) → (K, n, p).
    progress : callable, optional
        Called as ``progress(done, total)`` (samples).

    Returns
    -------
    columns : list of (str, int)
        The friction columns (kind, joint), after the p transformed ones.
    R : numpy.ndarray, shape (m, r, p + F + 1)
        The factors of [columns | target], per measured joint.
    sigma : numpy.ndarray, shape (m,)
        Each measured joint's noise σⱼ, N·m.
    theta : numpy.ndarray, shape (p + F,)
        The weighted least-squares estimate.
    covariance : numpy.ndarray, shape (p + F, p + F)
        Its covariance s² (Yᵀ W² Y)⁻¹.
    """
    columns = _friction_columns(friction, measured)
    n_rigid = 10 * model.n_bodies

    def design(block):
        D = _design(model, log, block, columns)
        return np.concatenate([transform(D[..., :n_rigid]), D[..., n_rigid:]], axis=2)
    R = _factors(model, log, rows, columns, target, measured, progress, design=design)
    counts = np.full(len(measured), float(len(rows)))
    sigma, theta, covariance, _, _ = _weighted_fit(R, counts, list(range(R.shape[2] - 1)), full=True)
    return columns, R, sigma, theta, covariance


def _per_joint(model: Model, measured, values, packed: bool = False) -> np.ndarray:
    """(n,) with ``values`` at the measured joints (given for every joint, or with ``packed`` for those only), NaN
    elsewhere."""
    out = np.full(model.n, np.nan)
    if values is not None:
        out[measured] = values if packed else np.asarray(values)[measured]
    return out


def _drive_errors(model: Model, columns, errors) -> np.ndarray:
    """(2, n): the standard errors of the armatures and offsets fitted, NaN for those not fitted."""
    out = np.full((len(DRIVE_PARTS), model.n), np.nan)
    for (kind, j), e in zip(columns, errors):
        if kind in DRIVE_PARTS:
            out[DRIVE_PARTS.index(kind), j] = e
    return out


def _predict(model: Model, friction: Friction, log: JointLog, rows, drives: Drives) -> np.ndarray:
    """τ = M Θ̈ + V + G + F(Θ̇) + Iₐ Θ̈ + τ₀ of ``model`` on the samples ``rows`` (K, n)."""
    tau = np.empty((len(rows), model.n))
    for start in range(0, len(rows), ROWS_AT_A_TIME):
        block = rows[start:start + ROWS_AT_A_TIME]
        rigid = inverse_dynamics(model, log.q[block], log.qd[block], log.qdd[block])
        tau[start:start + len(block)] = rigid + friction.torques(log.qd[block]) + drives.torques(log.qdd[block])
    return tau


__all__ = ["FRICTION_MODELS", "MIN_MASS", "MIN_MASS_SHARE", "PRIOR_WEIGHT", "Identification", "fit_transformed",
           "identify", "pseudo_inertia"]

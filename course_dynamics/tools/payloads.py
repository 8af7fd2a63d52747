"""Payload identification: the mass, centre of mass and inertia of what an arm carries, from a short log.

==================  =============  ====================================================================
code                symbol         meaning (shape, unit)
==================  =============  ====================================================================
``link``            F              the flange: the URDF link the payload is fixed to (frame F)
``body``            B              the moving body F belongs to (F is fixed to B's link, or is it)
``R``, ``P``        ᴮR_F, ᴮP_F     F's axes and origin in frame B (3, 3), (3,) m
``T``               T              [[ᴮR_F, ᴮP_F], [0, 1]] (4, 4): a point of F in frame B
``pi``              π_P            the payload's ten parameters in F: m, m ᶠc, ᶠI about F's origin, in
                                   :data:`~course_dynamics.core.regressor.PARAMETER_NAMES` order (10,)
``A``               A              π_B = A π_P: the same body's parameters in frame B (10, 10)
``Y_F``             Y_F            Y_F = Y_B A, τ_P = Y_F π_P (K, n, 10): Y_B the regressor's columns
                                   of body B (:mod:`~course_dynamics.core.regressor`)
``mass``, ``com``   m, ᶠc          the payload's mass, kg, and centre of mass in F (3,), m
``inertia``         ᶜI             its inertia about its centre of mass, F's axes (3, 3), kg·m²
==================  =============  ====================================================================

A payload fixed to F is part of body B: its parameters add to B's, and the torques it costs are
linear in them. Moved rigidly from F to B, a body's pseudo-inertia J = [[∫ r rᵀ dm, h], [hᵀ, m]]
(:func:`~course_dynamics.tools.consistency.pseudo_inertia`) becomes T J Tᵀ — the parallel-axis theorem
(6.25) and the rotation of the inertia together, linear in π_P: that is A. So with the arm known (the URDF,
or an earlier identification's), what the log shows beyond it is::

    τ_meas − τ_arm(Θ, Θ̇, Θ̈) − F(Θ̇) = Y_F(Θ, Θ̇, Θ̈) π_P                 (τ_arm by (6.45)–(6.53), F (6.112))

solved as :func:`~course_dynamics.tools.identification.identify` solves its own (its factors, its
weighted least squares with weights 1/σⱼ and standard errors from s² (Yᵀ W² Y)⁻¹, the same held-out
share and held joints), then made physically consistent
(:func:`~course_dynamics.tools.consistency.consistent_fit`: J ⪰ 0, m ≥ 0; no prior, λ = 0) when the least
squares is not physical or the log does not see all ten: a direction whose singular value (each
parameter in the scale m, m ℓ, m ℓ², ℓ = :data:`LENGTH`) is below ``threshold`` of the largest stays at 0,
then moves the least that makes the body physical (toward a point mass). A parameter is *determined*
when at least 99 % of it is seen. The mass, centre of mass and inertia about it, with their standard
errors (linearised from the covariance), follow from π_P; none is reported as known that the log did not
determine. A mass within :data:`NO_PAYLOAD` standard errors of 0 is no payload detected.

>>> import numpy as np
>>> from course_dynamics import load_robot, inverse_dynamics
>>> from course_dynamics.tools.loads import Payload, with_payload
>>> from course_dynamics.tools.logs import joint_log
>>> arm = load_robot("ur5")
>>> carried = with_payload(arm, Payload(1.7, link="tool0", com=(0.01, -0.02, 0.06), size=(0.1, 0.08, 0.12)))
>>> t = np.arange(0, 6, 0.01)
>>> q = np.column_stack([0.3 * np.sin((0.5 + 0.2 * j) * t + j) for j in range(6)])
>>> qd, qdd = np.gradient(q, t, axis=0), np.gradient(np.gradient(q, t, axis=0), t, axis=0)
>>> tau = inverse_dynamics(carried, q, qd, qdd)
>>> columns = {"t": t, **{f"{k}_{j}": v[:, i] for k, v in (("q", q), ("qd", qd), ("qdd", qdd), ("tau_meas", tau))
...                       for i, j in enumerate(arm.joint_names)}}
>>> found = identify_payload(arm, joint_log(arm, columns))
>>> round(found.mass, 6), found.com.round(6).tolist()
(1.7, [0.01, -0.02, 0.06])
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.errors import InputError
from ..core.evaluator import inverse_dynamics, regressor  # the evaluator chooses the implementation of each call
from ..core.friction import Friction
from ..core.model import Model
from ..core.regressor import PARAMETER_NAMES, TENSOR
from .consistency import consistent_fit, pseudo_inertia
from .identification import FRICTION_MODELS, HELD, ROWS_AT_A_TIME, SEEN_SPLIT, SYMBOLS, UNSEEN, fit_transformed
from .logs import JointLog

#: The length ℓ (m) a payload's first moments and inertias are measured in when judging what is seen (a tool's size).
LENGTH = 0.1
#: A mass within this many standard errors of 0 is no payload detected.
NO_PAYLOAD = 3.0
#: Nor is a mass below this share of the arm's own mass (a bias of the differentiated Θ̈ that a long, quiet log
#: makes significant: no tool weighs a thousandth of its arm).
SMALLEST_PAYLOAD = 1e-3
#: How many joints an excitation for a payload moves by default, the last of the flange's chain (the wrist).
WRIST = 3
#: The name of the link the identified payload is written as.
PAYLOAD_LINK = "payload"
#: UR's tool flange frame as ur_description names it, the frame of the controller's payload centre of gravity.
UR_FLANGE = "tool0"
#: Franka's flange frame F as franka_description names it, the frame of the load's F_x_Cload and inertia.
FRANKA_FLANGE = "panda_link8"
UPPER = ((0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2))    # Ixx, Ixy, Iyy, Ixz, Iyz, Izz


def parameters_of(J) -> np.ndarray:
    """π of a pseudo-inertia J, the inverse of :func:`~course_dynamics.tools.consistency.pseudo_inertia`.

    Parameters
    ----------
    J : array_like, shape (4, 4)
        [[Σ, h], [hᵀ, m]], Σ = ∫ r rᵀ dm: kg·m², kg·m, kg.

    Returns
    -------
    numpy.ndarray, shape (10,)
        m, h, then Ixx, Ixy, Iyy, Ixz, Iyz, Izz of I = tr(Σ) 1 − Σ about the frame's origin.
    """
    J = np.asarray(J, dtype=float)
    inertia = np.trace(J[:3, :3]) * np.eye(3) - J[:3, :3]
    return np.array([J[3, 3], *J[:3, 3]] + [inertia[a, b] for a, b in UPPER])


def offset_map(R, P) -> np.ndarray:
    """A with π_B = A π_P: a body's ten parameters in frame F, expressed in frame B (module docstring).

    Parameters
    ----------
    R : array_like, shape (3, 3)
        ᴮR_F, F's axes in frame B.
    P : array_like, shape (3,)
        ᴮP_F, F's origin in frame B, m.

    Returns
    -------
    numpy.ndarray, shape (10, 10)
        A: column k is π_B of the unit π_P = e_k, by J_B = T J_F Tᵀ.

    Examples
    --------
    >>> A = offset_map(np.eye(3), [0.0, 0.0, 0.5])          # a point mass of 2 kg at F's origin, 0.5 m up B's z
    >>> pi_B = A @ payload_parameters(2.0, [0.0, 0.0, 0.0])
    >>> pi_B[:4].tolist(), float(pi_B[4]), float(pi_B[9])     # h = m P; Ixx = m z², Izz = 0 (6.25)
    ([2.0, 0.0, 0.0, 1.0], 0.5, 0.0)
    """
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = np.asarray(R, dtype=float), np.asarray(P, dtype=float)
    return np.column_stack([parameters_of(T @ pseudo_inertia(e) @ T.T) for e in np.eye(10)])


def payload_parameters(mass: float, com, inertia=None) -> np.ndarray:
    """π_P of a payload of ``mass`` at ``com`` with ``inertia`` about it (F's axes): m, m c, I about F's origin (6.25).

    Parameters
    ----------
    mass : float
        m, kg.
    com : array_like, shape (3,)
        ᶠc, m.
    inertia : array_like, shape (3, 3), optional
        ᶜI about the centre of mass, F's axes, kg·m²; a point mass without it.

    Returns
    -------
    numpy.ndarray, shape (10,)
        π_P.
    """
    c = np.asarray(com, dtype=float)
    I = (np.zeros((3, 3)) if inertia is None else np.asarray(inertia, dtype=float)) \
        + mass * (c @ c * np.eye(3) - np.outer(c, c))                                   # (6.25)
    return np.array([mass, *(mass * c)] + [I[a, b] for a, b in UPPER])


def flange_link(model: Model) -> str:
    """The default flange: the last URDF link of the last moving body every tip is carried by (the arm's last
    body before a gripper's fingers branch off: ur5's tool0, panda's panda_hand_tcp).

    Parameters
    ----------
    model : Model
        The robot.

    Returns
    -------
    str
        The link's name.
    """
    parents = [b.parent for b in model.bodies]
    leaves = [i for i in range(model.n_bodies) if i not in parents]

    def chain(i):
        return [i] + chain(parents[i]) if i >= 0 else []
    shared = set(chain(leaves[0])).intersection(*(chain(i) for i in leaves[1:]))
    body = max(shared) if shared else leaves[-1]
    return [f.name for f in model.frames if f.body == body][-1]


@dataclass(frozen=True)
class Flange:
    """The payload's columns of the regressor: Y_F = Y_B A on the joints ``rows`` (the others' rows 0).

    Used wherever the base regressor is (``rank`` and ``regressor``: :mod:`~course_dynamics.tools.excitation`
    optimises its condition number).

    Parameters
    ----------
    link : str
        F, the flange link.
    body : int
        B, the moving body it belongs to (from 0).
    A : numpy.ndarray, shape (10, 10)
        :func:`offset_map` of F in B.
    rows : numpy.ndarray of bool, shape (n,)
        The joints whose torques count.
    rank : int
        The columns: 10.
    """

    link: str
    body: int
    A: np.ndarray
    rows: np.ndarray
    rank: int = 10

    def regressor(self, Y) -> np.ndarray:
        """Y_F of the regressor ``Y`` (..., n, 10 n_bodies).

        Parameters
        ----------
        Y : numpy.ndarray, shape (..., n, 10 n_bodies)
            :func:`~course_dynamics.core.regressor.regressor`'s Y.

        Returns
        -------
        numpy.ndarray, shape (..., n, 10)
            Y_F, N·m (N) per unit of each of π_P.
        """
        return Y[..., 10 * self.body:10 * self.body + 10] @ self.A * self.rows[:, None]


def flange(model: Model, link: str | None = None, rows=None) -> Flange:
    """The flange ``link`` (default :func:`flange_link`) of ``model``, its columns on the joints ``rows`` (default all).

    Parameters
    ----------
    model : Model
        The robot.
    link : str, optional
        The URDF link the payload is fixed to.
    rows : array_like of bool, shape (n,), optional
        The joints whose torques count.

    Returns
    -------
    Flange
        F, its body and its A.

    Raises
    ------
    ModelError
        If ``link`` is not a link of the robot (the message lists them).
    InputError
        If it is fixed to the base, where a payload costs no torque.
    """
    link = flange_link(model) if link is None else link
    frame = model.frame(link)
    if frame.body < 0:
        raise InputError(f"link '{link}' is fixed to the base of robot '{model.name}': a payload there costs no "
                         f"torque, so no log can identify it; name the arm's flange ({model.name}'s is "
                         f"{flange_link(model)})")
    rows = np.ones(model.n, dtype=bool) if rows is None else np.asarray(rows, dtype=bool)
    return Flange(link, frame.body, offset_map(frame.R, frame.P), rows)


def wrist(model: Model, link: str | None = None, count: int = WRIST) -> np.ndarray:
    """Which joints move for a payload's excitation: the last ``count`` coordinates of the flange's chain.

    Parameters
    ----------
    model : Model
        The robot.
    link : str, optional
        The flange (default :func:`flange_link`).
    count : int
        How many of the chain's last joints.

    Returns
    -------
    numpy.ndarray of bool, shape (n,)
        True for the joints that move.
    """
    body, chain = flange(model, link).body, []
    while body >= 0:
        j = model.coupling[body][0]
        chain += [] if j in chain else [j]
        body = model.bodies[body].parent
    moving = np.zeros(model.n, dtype=bool)
    moving[chain[:count]] = True
    return moving


@dataclass(frozen=True)
class PayloadIdentification:
    """What :func:`identify_payload` found (module docstring); NaN where the log did not determine a value.

    Parameters
    ----------
    link : str
        F, the flange.
    pi : numpy.ndarray, shape (10,)
        π_P identified (physically consistent), in F.
    pi_wls : numpy.ndarray, shape (10,)
        π_P by weighted least squares.
    covariance : numpy.ndarray, shape (10, 10)
        Its covariance s² (Yᵀ W² Y)⁻¹.
    mass, mass_sigma : float
        m and its standard error, kg.
    com, com_sigma : numpy.ndarray, shape (3,)
        ᶠc and its standard errors, m.
    inertia : numpy.ndarray, shape (3, 3)
        ᶜI about the centre of mass, F's axes, kg·m².
    inertia_sigma : numpy.ndarray, shape (6,)
        The standard errors of its Ixx, Ixy, Iyy, Ixz, Iyz, Izz, kg·m².
    seen : numpy.ndarray, shape (10,)
        The share of each of π_P the log sees, 0 to 1.
    detected : bool
        Whether the mass is determined and more than :data:`NO_PAYLOAD` standard errors above 0.
    friction : Friction
        The friction used (the URDF's, with what was identified).
    friction_model : str
        What friction was identified.
    sigma : numpy.ndarray, shape (n,)
        Each joint's torque noise σⱼ, N·m; NaN where not fitted.
    samples : tuple of (int, int)
        The samples fitted and held out.
    rms_before, rms_after : numpy.ndarray, shape (n,)
        The held-out RMS residual without and with the payload, N·m; NaN where not fitted.
    solver : str
        The consistent fit's solver, or ``"least squares"`` where it was physical and fully seen.
    notes : tuple of str
        What the reader should know.
    """

    link: str
    pi: np.ndarray
    pi_wls: np.ndarray
    covariance: np.ndarray
    mass: float
    mass_sigma: float
    com: np.ndarray
    com_sigma: np.ndarray
    inertia: np.ndarray
    inertia_sigma: np.ndarray
    seen: np.ndarray
    detected: bool
    friction: Friction
    friction_model: str
    sigma: np.ndarray
    samples: tuple[int, int]
    rms_before: np.ndarray
    rms_after: np.ndarray
    solver: str
    notes: tuple[str, ...] = ()

    @property
    def determined(self) -> dict[str, bool]:
        """Whether the log determined the mass, the centre of mass and the inertia (each wholly).

        Returns
        -------
        dict of str to bool
            ``mass``, ``com``, ``inertia``.
        """
        seen = self.seen >= 1 - SEEN_SPLIT
        return {"mass": bool(seen[0]), "com": bool(seen[:4].all() and self.detected),
                "inertia": bool(seen.all() and self.detected)}

    def in_frame(self, model: Model, link: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(ᴸc, its standard errors, ᶜI in L's axes) in another frame L of the flange's body.

        Parameters
        ----------
        model : Model
            The robot identified on.
        link : str
            L, a URDF link fixed to the same body as F.

        Returns
        -------
        com : numpy.ndarray, shape (3,)
            The centre of mass in L, m.
        com_sigma : numpy.ndarray, shape (3,)
            Its standard errors (of each coordinate, rotated by absolute values: a bound), m.
        inertia : numpy.ndarray, shape (3, 3)
            ᶜI in L's axes, kg·m².
        """
        F, L = model.frame(self.link), model.frame(link)
        R = L.R.T @ F.R                                          # F's axes in L
        com = R @ self.com + L.R.T @ (F.P - L.P)
        return com, np.sqrt((R**2) @ self.com_sigma**2), R @ self.inertia @ R.T

    def robot_forms(self, model: Model) -> dict:
        """The payload as UR's and Franka's controllers take it: each robot's form where the model has its flange
        link, both in F where it has neither.

        UR: ``set_payload(m, [cx, cy, cz])``, the centre of gravity in the tool flange frame, which is
        ur_description's ``tool0`` (z out of the flange; ``wrist_3_link`` and ``flange`` are rotated from it).
        Franka: ``mass``, ``F_x_Cload`` and ``load_inertia`` (9 values, column-major, about the centre of
        mass) in the flange frame F, franka_description's ``panda_link8``.

        Parameters
        ----------
        model : Model
            The robot identified on.

        Returns
        -------
        dict
            ``ur`` and/or ``franka``: ``frame``, ``mass``, ``com``, (Franka) ``inertia`` and the ``call`` as text.
        """
        names = {f.name for f in model.frames if f.body == model.frame(self.link).body}
        frames = {key: frame for key, frame in (("ur", UR_FLANGE), ("franka", FRANKA_FLANGE)) if frame in names}
        forms = {}
        for key, frame in (frames or {"ur": self.link, "franka": self.link}).items():
            c, _, I = self.in_frame(model, frame)
            forms[key] = dict(frame=frame, mass=self.mass, com=c.tolist())
            if key == "ur":
                forms[key]["call"] = f"set_payload({_g(self.mass)}, [{', '.join(_g(x) for x in c)}])"
            else:
                forms[key]["inertia"] = I.T.ravel().tolist()
                forms[key]["call"] = (f"mass = {_g(self.mass)}; F_x_Cload = [{', '.join(_g(x) for x in c)}]; "
                                      f"load_inertia = [{', '.join(_g(x) for x in I.T.ravel())}]")
        return forms

    def record(self, model: Model) -> dict:
        """A JSON-ready summary.

        Parameters
        ----------
        model : Model
            The robot identified on.

        Returns
        -------
        dict
            The flange, what was determined, mass, centre of mass and inertia with standard errors, the robot
            forms, π_P, σ, held-out RMS and notes; non-finite numbers as None.
        """
        def listed(a):
            return [None if not np.isfinite(x) else float(x) for x in np.ravel(np.asarray(a, dtype=float))]
        joints = model.joint_names
        return {
            "link": self.link, "detected": self.detected, "determined": self.determined,
            "mass": listed([self.mass])[0], "mass_sigma": listed([self.mass_sigma])[0],
            "com": listed(self.com), "com_sigma": listed(self.com_sigma),
            "inertia": listed(self.inertia), "inertia_sigma": listed(self.inertia_sigma),
            "robot_forms": self.robot_forms(model) if self.detected and self.determined["com"] else None,
            "parameters": [{"name": n, "wls": a, "standard_error": e, "identified": b, "seen": s}
                           for n, a, e, b, s in zip(PARAMETER_NAMES, listed(self.pi_wls),
                                                    listed(np.sqrt(np.diag(self.covariance))), listed(self.pi),
                                                    listed(self.seen))],
            "friction_model": self.friction_model, "solver": self.solver,
            "friction": {kind: dict(zip(joints, listed(getattr(self.friction, kind))))
                         for kind in ("viscous", "coulomb")},
            "samples": {"fitted": self.samples[0], "held_out": self.samples[1]},
            "sigma": dict(zip(joints, listed(self.sigma))),
            "held_out_rms": {"without": dict(zip(joints, listed(self.rms_before))),
                             "with_payload": dict(zip(joints, listed(self.rms_after)))},
            "notes": list(self.notes)}


def _g(x) -> str:
    return f"{float(x):.4g}"


def _derived(pi, covariance):
    """(m, c, ᶜI) of π_P and their standard errors, linearised: ∂ of (m, h/m, I − (hᵀh 1 − h hᵀ)/m) (6.25)."""
    m, h = pi[0], pi[1:4]
    c = h / m
    I = pi[np.array(TENSOR)] - m * (c @ c * np.eye(3) - np.outer(c, c))
    G = np.zeros((10, 10))                          # rows: m, c (3), ᶜI (6, UPPER order)
    G[0, 0] = 1.0
    G[1:4, 0], G[1:4, 1:4] = -h / m**2, np.eye(3) / m
    for row, (a, b) in enumerate(UPPER):
        G[4 + row, 4 + row] = 1.0
        shift = (h @ h * (a == b) - h[a] * h[b])
        G[4 + row, 0] = shift / m**2
        G[4 + row, 1:4] = -(2 * h * (a == b) - np.eye(3)[a] * h[b] - h[a] * np.eye(3)[b]) / m
    error = np.sqrt(np.maximum(np.diag(G @ covariance @ G.T), 0.0))
    return float(m), c, I, float(error[0]), error[1:4], error[4:]


def identify_payload(model: Model, log: JointLog, link: str | None = None, friction: str = "none",
                     holdout: float = 0.2, where: str = "the log", threshold: float = UNSEEN,
                     progress=None) -> PayloadIdentification:
    """The payload ``log`` shows fixed to ``link`` of ``model`` (module docstring).

    Parameters
    ----------
    model : Model
        The arm without the payload: the URDF's, or an earlier identification's.
    log : JointLog
        A :class:`~course_dynamics.tools.logs.JointLog` with measured torques.
    link : str, optional
        F, the flange the payload is fixed to (default :func:`flange_link`).
    friction : str
        Which friction to identify with it, as :func:`~course_dynamics.tools.identification.identify` (default
        ``none``: the URDF's ``<dynamics>``).
    holdout : float
        The share of the log's time, at its end, kept out of the fit (0 ≤ holdout < 1).
    where : str
        How messages name the log.
    threshold : float
        The share of the largest singular value below which a direction counts as not seen.
    progress : callable, optional
        Called as ``progress(done, total)`` (samples) while the regressor is computed.

    Returns
    -------
    PayloadIdentification
        π_P, the mass, centre of mass and inertia with standard errors, and what the log determined.

    Raises
    ------
    InputError
        No measured torques, no measured joint that moves, a flange fixed to the base, a bad option, too few
        samples; cvxpy missing.
    ModelError
        If ``link`` is not a link of the robot.
    """
    if friction not in FRICTION_MODELS:
        raise InputError(f"unknown friction model '{friction}' (choose from {', '.join(FRICTION_MODELS)})")
    if not 0 <= holdout < 1:
        raise InputError(f"the held-out share must be at least 0 and less than 1, got {holdout}")
    F = flange(model, link)
    has_torque = [] if log.measured is None else [j for j in range(model.n) if np.all(np.isfinite(log.measured[:, j]))]
    if not has_torque:
        raise InputError(f"{where} holds no measured torques: a payload is identified from them, as "
                         f"tau_meas_<joint> columns (tau_meas_{model.joint_names[0]}, …), a bag's effort, Franka's "
                         "tau_J, or current_<joint> columns with torque constants")
    held = [j for j in range(model.n) if np.ptp(log.q[:, j]) <= HELD]
    measured = [j for j in has_torque if j not in held]
    if not measured:
        raise InputError(f"{where}: no joint with a measured torque moves in the log (each spans at most {HELD:g}): "
                         "nothing shows the payload")
    kinds = [k for k in ("viscous", "coulomb") if friction in (k, "both")]
    identified = {(kind, j) for j in measured for kind in kinds}
    urdf_friction = Friction.from_urdf(model)
    fixed = Friction(viscous=[0.0 if ("viscous", j) in identified else v for j, v in enumerate(urdf_friction.viscous)],
                     coulomb=[0.0 if ("coulomb", j) in identified else c for j, c in enumerate(urdf_friction.coulomb)])
    t = log.t
    split = t[0] + (1 - holdout) * (t[-1] - t[0])
    train = np.flatnonzero(t < split) if holdout > 0 else np.arange(len(t))
    test = np.flatnonzero(t >= split) if holdout > 0 else np.arange(0)
    P = 10 + len(identified)
    if len(train) * len(measured) < 2 * P:
        raise InputError(f"{where}: the fitted part has {len(train)} samples of {len(measured)} measured joints, too "
                         f"few for the payload's {P} parameters (at least twice as many values are needed)")
    arm = np.zeros_like(log.q)      # τ_arm + F(Θ̇), what the arm alone costs
    for start in range(0, len(t), ROWS_AT_A_TIME):
        block = slice(start, start + ROWS_AT_A_TIME)
        arm[block] = inverse_dynamics(model, log.q[block], log.qd[block], log.qdd[block]) + fixed.torques(log.qd[block])
    target = np.where(np.isfinite(log.measured), log.measured, 0.0) - arm
    columns, R, sigma, theta_wls, covariance = fit_transformed(model, log, train, measured, target, friction,
                                                               F.regressor, progress)
    urdf = np.array([getattr(urdf_friction, kind)[j] for kind, j in columns])
    mass_scale = max(abs(theta_wls[0]), np.sqrt(covariance[0, 0]), 1e-6)
    friction_scale = [max(np.sqrt(np.mean([theta_wls[10 + i] ** 2 for i, c in enumerate(columns) if c[0] == kind])),
                          np.sqrt(np.mean(urdf[[c[0] == kind for c in columns]] ** 2)), 1e-6) for kind, _ in columns]
    scale = np.concatenate([mass_scale * np.array([1.0] + [LENGTH] * 3 + [LENGTH**2] * 6), friction_scale])
    names = [f"{p}_payload" for p in PARAMETER_NAMES] + [f"{SYMBOLS[kind]}_{model.joint_names[j]}"
                                                         for kind, j in columns]
    bodies = _Payload(model.name)
    fit = consistent_fit(bodies, R, sigma, len(train) * len(measured), np.concatenate([np.zeros(10), urdf]),
                         np.ones(P, dtype=bool), scale, np.array([LENGTH]), names, 0.0, threshold, np.zeros(1))
    values = np.linalg.eigvalsh(pseudo_inertia(theta_wls[:10]))
    physical = theta_wls[0] > 0 and values.min() >= -1e-10 * values.max() and np.all(theta_wls[10:] >= 0)
    notes = [f"joint '{model.joint_names[j]}' has no measured torque: its rows are left out"
             for j in range(model.n) if j not in has_torque]
    notes += [f"joint '{model.joint_names[j]}' is held in the log: its rows are left out (its friction at rest is "
              "unknown)" for j in held if j in has_torque]
    mass_sigma = float(np.sqrt(covariance[0, 0]))
    arm_mass = sum(body.mass for body in model.bodies)
    smallest = max(NO_PAYLOAD * mass_sigma, SMALLEST_PAYLOAD * arm_mass)
    mass_seen = fit.seen[0] >= 1 - SEEN_SPLIT
    detected = bool(mass_seen and theta_wls[0] > smallest)
    if physical and fit.seen.min() >= 1 - SEEN_SPLIT:
        theta, solver = theta_wls, "least squares"
    else:
        theta, solver = fit.theta.copy(), fit.solver
        theta[10:] = np.maximum(theta[10:], 0.0)  # the solver's round-off below a bound of 0 (−1e-8) is the bound
        if mass_seen and not detected:  # nothing is written: the payload is given as the estimate tested
            theta[:10], solver = theta_wls[:10], "least squares"
        else:
            why = "is not physical" if not physical else "is not fully seen by the log"
            notes += [f"the least-squares payload {why}: the physically consistent estimate ({fit.solver}) is given"
                      + (f"; {'; '.join(fit.active)}" if fit.active else "")]
    unseen = [PARAMETER_NAMES[k] for k in range(10) if fit.seen[k] < 1 - SEEN_SPLIT]
    if unseen:
        notes.append(f"not determined by the log (a motion of the joints that carry {F.link} shows them: excite "
                     f"--scope payload --flange {F.link}): {', '.join(unseen)}")
    viscous, coulomb = fixed.viscous.copy(), fixed.coulomb.copy()
    for (kind, j), value in zip(columns, theta[10:]):
        (viscous if kind == "viscous" else coulomb)[j] = value
    used = Friction(viscous=viscous, coulomb=coulomb)
    seen = fit.seen[:10]
    mass = float(theta[0])
    com, inertia, com_sigma, inertia_sigma = np.full(3, np.nan), np.full((3, 3), np.nan), np.full(3, np.nan), \
        np.full(6, np.nan)
    if mass > 0 and seen[0] >= 1 - SEEN_SPLIT:
        _, com, inertia, _, com_sigma, inertia_sigma = _derived(theta[:10], covariance[:10, :10])
        unseen_h = seen[1:4] < 1 - SEEN_SPLIT              # a coordinate of c is known where its first moment is
        com[unseen_h], com_sigma[unseen_h] = np.nan, np.nan
    if seen.min() < 1 - SEEN_SPLIT:
        inertia, inertia_sigma = np.full((3, 3), np.nan), np.full(6, np.nan)
    if mass_seen and not detected:
        why = (f"within {NO_PAYLOAD:g} standard errors of 0" if smallest > SMALLEST_PAYLOAD * arm_mass else
               f"less than {SMALLEST_PAYLOAD:.1%} of the arm's own {arm_mass:.3g} kg")
        notes.append(f"no payload detected: the least-squares mass {theta_wls[0]:.3g} ± {mass_sigma:.2g} kg is {why} "
                     "(so no centre of mass or inertia either)")
    if not detected:        # h / m of a mass that is noise is noise: not given
        com, com_sigma, inertia, inertia_sigma = (np.full_like(v, np.nan) for v in (com, com_sigma, inertia,
                                                                                   inertia_sigma))
    rms = [np.full(model.n, np.nan), np.full(model.n, np.nan)]
    if len(test):
        Y_F = F.regressor(regressor(model, log.q[test], log.qd[test], log.qdd[test]))
        found = target[test] - Y_F @ theta[:10] - used.torques(log.qd[test]) + fixed.torques(log.qd[test])
        for out, residual in zip(rms, (target[test], found)):
            out[measured] = np.sqrt(np.mean(residual[:, measured] ** 2, axis=0))
    noise = np.full(model.n, np.nan)
    noise[measured] = sigma
    return PayloadIdentification(
        link=F.link, pi=theta[:10], pi_wls=theta_wls[:10], covariance=covariance[:10, :10],
        mass=mass if seen[0] >= 1 - SEEN_SPLIT else float("nan"), mass_sigma=mass_sigma, com=com,
        com_sigma=com_sigma, inertia=inertia, inertia_sigma=inertia_sigma, seen=seen, detected=detected,
        friction=used, friction_model=friction, sigma=noise, samples=(len(train), len(test)),
        rms_before=rms[0], rms_after=rms[1], solver=solver, notes=tuple(notes))


@dataclass(frozen=True)
class _Body:
    name: str


class _Payload:
    """The one body the consistent fit sees: the payload (what it reads of a model: name, bodies)."""

    def __init__(self, robot: str):
        self.name, self.n_bodies, self.bodies = robot, 1, (_Body(PAYLOAD_LINK),)


__all__ = ["FRANKA_FLANGE", "LENGTH", "NO_PAYLOAD", "PAYLOAD_LINK", "UR_FLANGE", "WRIST", "Flange",
           "PayloadIdentification", "flange", "flange_link", "identify_payload", "offset_map", "parameters_of",
           "payload_parameters", "wrist"]

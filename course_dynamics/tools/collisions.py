"""Collisions and external torques from a log: the generalized-momentum observer.

==================  =============  ===================================================
code                symbol         meaning (shape, unit)
==================  =============  ===================================================
``t``               t              sample times as logged (K,), s (they may jitter)
``q``, ``qd``       Θ, Θ̇           joint positions and rates (K, n)
``tau``             τ_m            the measured joint torques (K, n), N·m or N
``friction``        F(Θ̇)           joint friction (6.112), subtracted from τ_m
``p``               p              p = M(Θ) Θ̇, the generalized momentum (K, n)
``beta``            β              β = τ_m − F + Cᵀ(Θ,Θ̇) Θ̇ − G(Θ) (K, n)
``gain``            K              the observer's gain per joint (n,), 1/s
``r``               r              the residual (K, n), N·m: r → τ_ext
``threshold``       θ              per joint: ``|r|`` above it is a contact (n,), N·m
``band``            θ_F(t)         what the friction model may be off by, filtered like r (K, n), N·m
``unseen``                         force directions no measured joint sees at a link (m, 3), base
==================  =============  ===================================================

The robot moves by M Θ̈ + C Θ̇ + G + F = τ_m + τ_ext, where τ_ext is what the surroundings
apply to the joints: a contact force F_c (on the robot) at a link gives τ_ext = Jᵀ F_c. Since
Ṁ = C + Cᵀ (C as :func:`~course_dynamics.core.evaluator.coriolis_matrix` defines it, with
Ṁ − 2C skew-symmetric), the momentum obeys ṗ = τ_m − F + Cᵀ Θ̇ − G + τ_ext = β + τ_ext, which
needs no Θ̈. The observer (De Luca and Mattone; Haddadin, De Luca and Albu-Schäffer, "Robot
Collisions: A Survey on Detection, Isolation, and Identification", IEEE T-RO 2017) is

    r(t) = K (p(t) − p(0) − ∫₀ᵗ (β + r) ds)                                 (observer)

so that ṙ = K (τ_ext − r): r follows τ_ext through a first-order lag of time constant 1/K, joint
by joint. A larger K follows a collision sooner (63 % of a step after 1/K) but passes more
noise: K p carries the rates' noise into r unfiltered, K M σ_Θ̇, and the measured torques' noise
gets through a band of K rad/s. :data:`DEFAULT_GAIN` (100 1/s, 10 ms) sees a 20 ms pulse.

On the log's own samples the integral is a sum over each step [t_{k−1}, t_k], Δt_k = t_k − t_{k−1}:
p's derivative integrates to Δp exactly, β by the trapezoid rule, and r's own term exactly
(ṗ − β held over the step), which is stable for every K Δt:

    d_k = (p_k − p_{k−1}) / Δt_k − (β_{k−1} + β_k) / 2                       (step)
    r_k = e^{−K Δt_k} r_{k−1} + (1 − e^{−K Δt_k}) d_k,   r_0 = 0              (update)

A contact is where some joint's ``|r|`` exceeds its threshold θ: given (:func:`detect`'s ``threshold``),
or k σ above the residual's own level, θ = ``|median r|`` + k σ with σ = 1.4826 × the median absolute
deviation (:func:`residual_noise`; k = :data:`SIGMAS`), robust to the contacts themselves, over a
quiet stretch after the observer has settled (5/K) or over the whole log. With friction, F(Θ̇) is evaluated at
the measured rate, whose noise σ_Θ̇ (estimated from the log, :func:`~course_dynamics.tools.differentiation.noise_level`)
makes the model wrong by up to δ_k = max ``|F(v) − F(Θ̇_k)|`` over ``|v − Θ̇_k|`` ≤ k σ_Θ̇: near a reversal, where
the Coulomb term may be anything between ±F_c, a burst the noise σ of r does not hold. δ enters β, so r carries it
through the same filter, and the threshold at each sample is θ + θ_F(t) (:func:`friction_band`):

    θ_F = observer_update(t, δ, K)                                          (band)

An event lasts until every joint is back under half its threshold (hysteresis) and counts once it has lasted
:data:`MIN_DURATION`.

With ``link``, the wrench the surroundings exert on that link (:func:`contact_wrench`) is fitted in what the
measured joints can see: the whole wrench where their Jᵀ has rank 6 at every state of the event; otherwise the
force alone, a contact at the link's origin, in the directions its J_vᵀ sees (its rank at the state that sees
least, singular values within :data:`RANK_TOLERANCE` of the largest), the others named as not seen. The fit has no
lag for a contact of any length: from the event's start s, r_k − e^{−K (t_k − t_s)} r_s is Jᵀ F passed through the
observer's own update from zero, over the rows while the contact lasts (up to its peak, and to the event's end
less the time r takes to decay from its peak to half the threshold), each joint's rows weighted by one over its
threshold.

>>> import numpy as np
>>> from course_dynamics import load_robot
>>> arm = load_robot("two_link")
>>> t = np.arange(0, 1, 2e-3)
>>> q, qd = np.column_stack([np.sin(t), t]), np.column_stack([np.cos(t), np.ones_like(t)])
>>> from course_dynamics.core.evaluator import inverse_dynamics
>>> tau = inverse_dynamics(arm, q, qd, np.column_stack([-np.sin(t), 0 * t]))
>>> push = np.where((t > 0.5) & (t < 0.7), 3.0, 0.0)[:, None] * [1.0, 0.0]   # 3 N m on joint 1
>>> r = momentum_residual(arm, t, q, qd, tau - push, gain=100.0)           # measured: τ_m = τ − τ_ext
>>> round(float(r[340, 0]), 2), round(float(np.abs(r[:250]).max()), 3)
(3.0, 0.0)
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..base.errors import InputError
from ..core.cartesian import jacobian
from ..core.evaluator import implementation
from ..core.friction import Friction
from ..core.model import Model
from .differentiation import noise_level
from .logs import ROWS_AT_A_TIME, joint_log
from .sources import as_source

#: The observer's gain K by default, 1/s (a time constant of 10 ms).
DEFAULT_GAIN = 100.0
#: k of the threshold θ = ``|median r|`` + k σ (Gaussian noise crosses 6 σ once in about 5e8 samples).
SIGMAS = 6.0
#: The shortest event in seconds (a shorter crossing is noise).
MIN_DURATION = 0.005
#: An event ends when every joint's ``|r|`` is under this share of its threshold.
RELEASE = 0.5
#: A direction of a link's wrench is seen when its singular value is at least this share of the largest.
RANK_TOLERANCE = 1e-6
#: The smallest threshold, as a share of the joint's largest measured torque (a noise-free log has σ = 0).
THRESHOLD_FLOOR = 1e-3
MAD_TO_SIGMA = 1.4826   # σ of Gaussian noise from its median absolute deviation
SETTLING = 5.0          # the observer has settled after SETTLING / K seconds
_EXPONENT = 40.0        # K (t − t_s) within one block of the update's closed form: e^40 stays far from overflow


@dataclass(frozen=True)
class ContactEvent:
    """One contact: when it started, ended and counted, which joints felt it and how hard.

    Parameters
    ----------
    start : float
        The first sample over a threshold, s.
    end : float
        The last sample before every joint was back under half its threshold, s.
    detected : float
        When the event had lasted :data:`MIN_DURATION` (the earliest a detector could say so), s.
    joints : tuple of str
        The joints whose ``|r|`` exceeded their threshold.
    peak : tuple of float
        Per joint of ``joints``, r at its largest ``|r|`` in the event (the external torque), N·m (N).
    peak_t : float
        When r was largest against the thresholds, s.
    force : tuple of float, optional
        With a link: the force the surroundings exert on it, base coordinates (3,), N: one least-squares fit over
        the event (:func:`contact_wrench`); no component along ``unseen``.
    moment : tuple of float, optional
        With a link whose Jacobian resolves it: the moment about the link's origin (3,), N·m; None otherwise.
    condition : float, optional
        With a link: the condition number of the wrench's least-squares fit, on the directions it resolves.
    unseen : tuple of tuple of float
        With a link: unit force directions, base coordinates, that no measured joint sees (their component is not
        in ``force``).
    """

    start: float
    end: float
    detected: float
    joints: tuple[str, ...]
    peak: tuple[float, ...]
    peak_t: float
    force: tuple[float, ...] | None = None
    moment: tuple[float, ...] | None = None
    condition: float | None = None
    unseen: tuple[tuple[float, ...], ...] = ()

    def record(self) -> dict:
        """The event, JSON-ready.

        Returns
        -------
        dict
            start, end, detected, peak_t (s), peak (joint → N·m), force (N) and moment (N·m) or None, condition,
            unseen (unit directions).
        """
        return {"start": self.start, "end": self.end, "detected": self.detected, "peak_t": self.peak_t,
                "peak": dict(zip(self.joints, self.peak)), "force": None if self.force is None else list(self.force),
                "moment": None if self.moment is None else list(self.moment), "condition": self.condition,
                "unseen": [list(u) for u in self.unseen]}


@dataclass(frozen=True)
class Detection:
    """What :func:`detect` found in a log: r(t), the thresholds and the events.

    Parameters
    ----------
    t : numpy.ndarray, shape (K,)
        Sample times, s.
    r : numpy.ndarray, shape (K, n)
        The residual, N·m (N); NaN for joints the log did not measure.
    joints : tuple of str
        The model's joints, in the columns' order.
    measured : tuple of str
        The joints with measured torques (the others have no residual).
    gain : numpy.ndarray, shape (n,)
        K per joint, 1/s.
    threshold : numpy.ndarray, shape (n,)
        θ per joint, N·m (N); NaN where not measured.
    sigma : numpy.ndarray, shape (n,)
        The residual's noise σ where the threshold came from it, else NaN, N·m (N).
    events : tuple of ContactEvent
        The contacts, in time order.
    link : str, optional
        The link the events' wrenches are at.
    notes : tuple of str
        What was derived or assumed, in words.
    band : numpy.ndarray, shape (K, n), optional
        θ_F(t), added to ``threshold`` at each sample (friction the rates' noise leaves unknown), N·m (N).
    """

    t: np.ndarray
    r: np.ndarray
    joints: tuple[str, ...]
    measured: tuple[str, ...]
    gain: np.ndarray
    threshold: np.ndarray
    sigma: np.ndarray
    events: tuple[ContactEvent, ...]
    link: str | None = None
    notes: tuple[str, ...] = ()
    band: np.ndarray | None = None

    def table(self) -> tuple[list[str], np.ndarray]:
        """Header and rows of r(t): ``t`` and ``r_<joint>`` for each measured joint.

        Returns
        -------
        header : list of str
            The column names.
        rows : numpy.ndarray, shape (K, 1 + measured joints)
            t in s, r in N·m (N).
        """
        columns = [self.joints.index(j) for j in self.measured]
        return ["t"] + [f"r_{j}" for j in self.measured], np.column_stack([self.t, self.r[:, columns]])

    def record(self) -> dict:
        """The detection, JSON-ready (r(t) itself is left to :meth:`table`).

        Returns
        -------
        dict
            rows, gain, threshold and sigma by joint, link, events, notes.
        """
        def by_joint(values):
            return {j: None if not np.isfinite(values[i]) else float(values[i]) for i, j in enumerate(self.joints)
                    if j in self.measured}

        return {"rows": len(self.t), "gain": by_joint(self.gain), "threshold": by_joint(self.threshold),
                "sigma": by_joint(self.sigma), "link": self.link, "events": [e.record() for e in self.events],
                "notes": list(self.notes)}


def _positive(values, n: int, what: str, joints) -> np.ndarray:
    """One value for every joint, or one per joint; finite and positive."""
    array = np.broadcast_to(np.asarray(values, dtype=float).reshape(-1), (n,)) if np.size(values) in (1, n) else None
    if array is None or not np.all(np.isfinite(array)) or np.any(array <= 0):
        raise InputError(f"{what}: one positive number, or one per joint ({', '.join(joints)}), is needed; got "
                         f"{np.asarray(values).reshape(-1).tolist()}")
    return np.array(array)


def momentum_terms(model: Model, q, qd, tau, friction: Friction | None = None, compiled: bool | None = None):
    """p = M Θ̇ and β = τ_m − F + Cᵀ Θ̇ − G along a log, in blocks through the evaluator.

    Cᵀ Θ̇ is formed here from :func:`~course_dynamics.core.evaluator.coriolis_matrix` (the core computes
    C Θ̇ = V, not its transpose's product).

    Parameters
    ----------
    model : Model
        The robot.
    q, qd : numpy.ndarray, shape (K, n)
        Joint positions Θ (rad, m) and rates Θ̇ (rad/s, m/s).
    tau : numpy.ndarray, shape (K, n)
        The measured joint torques τ_m, N·m (N).
    friction : Friction, optional
        F(Θ̇), subtracted from τ_m.
    compiled : bool, optional
        Whether to use the compiled model; None lets the evaluator choose once for the log.

    Returns
    -------
    p : numpy.ndarray, shape (K, n)
        The generalized momentum, N·m·s (N·s).
    beta : numpy.ndarray, shape (K, n)
        β, N·m (N).
    """
    q, qd, tau = (np.asarray(x, dtype=float) for x in (q, qd, tau))
    run = implementation(model, calls=3 * -(-len(q) // ROWS_AT_A_TIME), states=min(len(q), ROWS_AT_A_TIME),
                         compiled=compiled)
    p, beta = np.empty_like(q), np.empty_like(q)
    for start in range(0, len(q), ROWS_AT_A_TIME):
        rows = slice(start, start + ROWS_AT_A_TIME)
        C = run.coriolis_matrix(q[rows], qd[rows])
        p[rows] = np.einsum("kij,kj->ki", run.mass_matrix(q[rows]), qd[rows])            # p = M Θ̇
        applied = tau[rows] if friction is None else tau[rows] - friction.torques(qd[rows])
        beta[rows] = applied + np.einsum("kji,kj->ki", C, qd[rows]) - run.gravity_torques(q[rows])  # ṗ − τ_ext
    return p, beta


def observer_update(t, d, gain) -> np.ndarray:
    """The update r_k = e^{−K Δt_k} r_{k−1} + (1 − e^{−K Δt_k}) d_k, r_0 = 0, for all samples at once.

    The product of the e^{−K Δt} from sample s to k is e^{−K (t_k − t_s)}, so within a block that starts at s,
    r_k = e^{−K (t_k − t_s)} (r_s + Σ e^{K (t_i − t_s)} (1 − e^{−K Δt_i}) d_i): a cumulative sum; the blocks are
    short enough that K (t_k − t_s) stays under 40.

    Parameters
    ----------
    t : numpy.ndarray, shape (K,)
        Sample times, increasing, s.
    d : numpy.ndarray, shape (K, n)
        d_k of the step equation (row 0 unused), N·m (N).
    gain : numpy.ndarray, shape (n,)
        K per joint, 1/s.

    Returns
    -------
    numpy.ndarray, shape (K, n)
        r, N·m (N).
    """
    t, d, gain = np.asarray(t, dtype=float), np.asarray(d, dtype=float), np.asarray(gain, dtype=float)
    r = np.zeros_like(d)
    if len(t) < 2:
        return r
    b = -np.expm1(-gain * np.diff(t)[:, None]) * d[1:]               # (1 − e^{−K Δt_k}) d_k, rows 1…K−1
    span, start, last = _EXPONENT / float(gain.max()), 0, np.zeros(d.shape[1])
    while start < len(t) - 1:
        stop = max(int(np.searchsorted(t, t[start] + span, side="right")), start + 2)
        stop = min(stop, len(t))
        x = gain * (t[start + 1:stop] - t[start])[:, None]
        if x[-1].max() > 2 * _EXPONENT:                               # one long step: its own block
            stop = start + 2
            r[start + 1] = np.exp(-gain * (t[start + 1] - t[start])) * last + b[start]   # (update)
        else:
            r[start + 1:stop] = np.exp(-x) * (last + np.cumsum(np.exp(x) * b[start:stop - 1], axis=0))
        start, last = stop - 1, r[stop - 1]
    return r


def momentum_residual(model: Model, t, q, qd, tau, gain=DEFAULT_GAIN, friction: Friction | None = None,
                      compiled: bool | None = None) -> np.ndarray:
    """The observer's residual r(t) (module docstring): the external joint torques τ_ext, filtered by K.

    Parameters
    ----------
    model : Model
        The robot.
    t : array_like, shape (K,)
        Sample times, increasing, s (an uneven clock is fine).
    q, qd : array_like, shape (K, n)
        Joint positions Θ (rad, m) and rates Θ̇ (rad/s, m/s).
    tau : array_like, shape (K, n)
        The measured joint torques τ_m, N·m (N); a column of NaN gives a column of NaN.
    gain : float or array_like, shape (n,)
        K, 1/s.
    friction : Friction, optional
        F(Θ̇), subtracted from τ_m.
    compiled : bool, optional
        Whether to use the compiled model; None lets the evaluator choose.

    Returns
    -------
    numpy.ndarray, shape (K, n)
        r, N·m (N): the torques the surroundings apply to the joints, once the observer has followed them.

    Raises
    ------
    InputError
        A gain that is not positive, or times that do not increase.
    """
    t = np.asarray(t, dtype=float)
    K = _positive(gain, model.n, "gain", model.joint_names)
    if len(t) > 1 and not np.all(np.diff(t) > 0):
        raise InputError(f"the sample times must increase; row {int(np.argmin(np.diff(t) > 0)) + 2} does not")
    p, beta = momentum_terms(model, q, qd, tau, friction, compiled)
    d = np.zeros_like(p)
    if len(t) > 1:
        d[1:] = np.diff(p, axis=0) / np.diff(t)[:, None] - (beta[1:] + beta[:-1]) / 2   # (step)
    return observer_update(t, d, K)


def residual_noise(t, r, gain, window: float | None = None, where: str = "the log") -> tuple[np.ndarray, np.ndarray]:
    """The residual's level and noise per joint, robustly: its median and σ = 1.4826 MAD.

    Over ``window`` seconds after the observer has settled (5/K from the start), or over the whole log after
    it: the median absolute deviation ignores contacts that take less than half of that stretch.

    Parameters
    ----------
    t : numpy.ndarray, shape (K,)
        Sample times, s.
    r : numpy.ndarray, shape (K, n)
        The residual, N·m (N).
    gain : numpy.ndarray, shape (n,)
        K per joint, 1/s.
    window : float, optional
        The quiet stretch's length, s; None for the whole log.
    where : str
        The log's name in messages.

    Returns
    -------
    level : numpy.ndarray, shape (n,)
        The median of r, N·m (N).
    sigma : numpy.ndarray, shape (n,)
        σ, N·m (N).

    Raises
    ------
    InputError
        A window that holds fewer than 10 samples.
    """
    begin = t[0] + SETTLING / float(np.min(gain))
    quiet = (t >= begin) & (t <= begin + window) if window is not None else t >= begin
    if np.count_nonzero(quiet) < 10:
        raise InputError(f"{where}: the quiet stretch from {begin - t[0]:.3g} s (the observer's settling, 5/K) "
                         + (f"for {window:g} s " if window is not None else "to the log's end ")
                         + f"holds {np.count_nonzero(quiet)} of the log's {len(t)} samples: at least 10 are needed; "
                         + ("a longer window (--noise-window), " if window is not None else "")
                         + "a larger gain (--gain, 1/s) settles sooner, or give a longer log")
    level = np.median(r[quiet], axis=0)
    return level, MAD_TO_SIGMA * np.median(np.abs(r[quiet] - level), axis=0)


def contact_events(t, r, threshold, joints, min_duration: float = MIN_DURATION) -> tuple[ContactEvent, ...]:
    """The contacts in r(t): from a joint's ``|r|`` over its threshold until every joint is under half of it.

    Parameters
    ----------
    t : numpy.ndarray, shape (K,)
        Sample times, s.
    r : numpy.ndarray, shape (K, n)
        The residual, N·m (N); NaN columns are ignored.
    threshold : numpy.ndarray, shape (n,) or (K, n)
        θ per joint, or per sample and joint, N·m (N).
    joints : sequence of str
        The joints' names.
    min_duration : float
        The shortest event, s.

    Returns
    -------
    tuple of ContactEvent
        In time order, without wrenches.
    """
    with np.errstate(invalid="ignore"):
        ratio = np.where(np.isfinite(r), np.abs(r) / threshold, 0.0)
    marker = np.where(ratio.max(axis=1) > 1, 1, np.where(ratio.max(axis=1) < RELEASE, -1, 0))
    last = np.maximum.accumulate(np.where(marker != 0, np.arange(len(t)), 0))   # the latest sample that decided
    inside = np.concatenate([[False], marker[last] == 1, [False]])               # hysteresis: on until released
    edges = np.flatnonzero(np.diff(inside.astype(int)))
    events = []
    for start, stop in zip(edges[::2], edges[1::2]):
        if t[stop - 1] - t[start] < min_duration:
            continue
        rows = slice(start, stop)
        over = [i for i in range(len(joints)) if ratio[rows, i].max() > 1]
        worst = [start + int(np.argmax(np.abs(np.nan_to_num(r[rows, i])))) for i in over]
        peak_row = start + int(np.argmax(ratio[rows].max(axis=1)))
        detected = t[min(int(np.searchsorted(t, t[start] + min_duration - 1e-12)), stop - 1)]
        events.append(ContactEvent(float(t[start]), float(t[stop - 1]), float(detected),
                                   tuple(joints[i] for i in over), tuple(float(r[k, i]) for k, i in zip(worst, over)),
                                   float(t[peak_row])))
    return tuple(events)


def friction_band(t, qd, friction: Friction, gain, sigmas: float = SIGMAS) -> np.ndarray:
    """θ_F(t): what evaluating F at the measured, noisy Θ̇ may have got wrong, through the observer's filter (band).

    δ_k = max ``|F(v) − F(Θ̇_k)|`` over ``|v − Θ̇_k|`` ≤ k σ_Θ̇ (F is monotone in each rate, so the ends of that
    interval bound it), σ_Θ̇ each joint's rate noise estimated from the log.

    Parameters
    ----------
    t : numpy.ndarray, shape (K,)
        Sample times, s.
    qd : numpy.ndarray, shape (K, n)
        The measured rates Θ̇, rad/s (m/s).
    friction : Friction
        The friction model subtracted from the measured torques.
    gain : numpy.ndarray, shape (n,)
        K per joint, 1/s.
    sigmas : float
        k: how many σ_Θ̇ the true rate may be from the measured one.

    Returns
    -------
    numpy.ndarray, shape (K, n)
        θ_F, N·m (N), non-negative.
    """
    qd = np.asarray(qd, dtype=float)
    spread = sigmas * (noise_level(qd) if len(qd) >= 5 else np.zeros(qd.shape[1]))
    model_at = friction.torques(qd)
    delta = np.maximum(np.abs(friction.torques(qd + spread) - model_at),
                       np.abs(friction.torques(qd - spread) - model_at))
    return observer_update(t, delta, gain)


def _ranks(A: np.ndarray) -> np.ndarray:
    """The rank of each (m, c) matrix of a stack (N, m, c): singular values within RANK_TOLERANCE of the largest."""
    if A.shape[1] == 0:
        return np.zeros(len(A), dtype=int)
    s = np.linalg.svd(A, compute_uv=False)
    return np.count_nonzero(s > RANK_TOLERANCE * np.maximum(s[:, :1], np.finfo(float).tiny), axis=1)


def _transposed(model: Model, q, link: str, measured) -> np.ndarray:
    """The measured joints' rows of Jᵀ at ``link``, (N, m, 6): force columns, then moment columns."""
    rows = [model.joint_names.index(j) for j in measured]
    J = np.asarray(jacobian(model, q, link)).reshape(-1, 6, model.n)
    return np.swapaxes(J, 1, 2)[:, rows]


def wrench_components(model: Model, link: str, measured, q=None) -> int:
    """How much of a wrench at ``link`` the torques of the ``measured`` joints resolve at every state of ``q``.

    Parameters
    ----------
    model : Model
        The robot.
    link : str
        A URDF link.
    measured : sequence of str
        The joints with measured torques.
    q : array_like, shape (n,) or (N, n), optional
        The states; the zero position by default.

    Returns
    -------
    int
        6 when Jᵀ has rank 6 at every state (force and moment); otherwise the rank of J_vᵀ at the state that sees
        least (1 to 3): the components of a force at the link's origin that can be resolved.

    Raises
    ------
    ModelError
        If the robot has no link ``link``.
    InputError
        If no measured joint moves the link's origin at some state.
    """
    Jt = _transposed(model, np.zeros(model.n) if q is None else q, link, measured)
    scaled = Jt / np.maximum(np.linalg.norm(Jt, axis=1, keepdims=True), np.finfo(float).tiny)   # units apart
    if np.all(_ranks(scaled) == 6):
        return 6
    seen = int(_ranks(Jt[:, :, :3]).min())
    if seen == 0:
        moving = [j for j, column in zip(measured, np.abs(Jt[:, :, :3]).max(axis=(0, 2))) if column > 0]
        raise InputError(f"link '{link}': no joint with a measured torque moves its origin "
                         f"({', '.join(moving) + ' only turn it' if moving else 'none moves it'}): their torques "
                         "resolve no component of a force there")
    return seen


@dataclass(frozen=True)
class Wrench:
    """A wrench fitted at a link (:func:`contact_wrench`).

    Parameters
    ----------
    force : numpy.ndarray, shape (3,)
        On the robot, base coordinates, N: no component along ``unseen``.
    moment : numpy.ndarray, shape (3,), optional
        About the link's origin, base coordinates, N·m; None when only the force is resolved.
    condition : float
        The condition number of the (weighted) least-squares fit on the directions it resolves.
    unseen : numpy.ndarray, shape (m, 3)
        Unit force directions, base coordinates, that no measured joint sees (m = 0 to 2).
    """

    force: np.ndarray
    moment: np.ndarray | None
    condition: float
    unseen: np.ndarray


def contact_wrench(model: Model, q, tau_ext, link: str, measured, weights=None, t=None, gain=None) -> Wrench:
    """The one wrench at ``link`` whose Jᵀ F best gives ``tau_ext`` at every state, by least squares on the
    measured joints' rows stacked over the states (a contact's wrench held over them), in what they can see.

    The components are :func:`wrench_components`' at these states: the whole wrench, or a force at the link's
    origin in the directions J_vᵀ sees, fitted on the stacked matrix's leading singular directions. Stacking the
    states keeps the estimate sound where one state's Jᵀ is near-singular (a wrist singularity). With ``t`` and
    ``gain``, ``tau_ext`` is the observer's r over a contact that lasts from the first state on: r − e^{−K (t −
    t₀)} r₀ is fitted by each column of Jᵀ passed through the same update from zero, which has no lag.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m).
    tau_ext : array_like, shape (n,) or (N, n)
        External joint torques (or the residual r), N·m (N).
    link : str
        A URDF link.
    measured : sequence of str
        The joints whose rows are used.
    weights : array_like, shape (n,), optional
        Each joint's row weight (one over its noise); equal by default.
    t : array_like, shape (N,), optional
        The states' times, s: with ``gain``, fit r through the observer's update.
    gain : array_like, shape (n,), optional
        K per joint, 1/s.

    Returns
    -------
    Wrench
        The force, the moment (or None), the fit's condition number and the directions not seen.

    Raises
    ------
    InputError
        If no measured joint moves the link's origin at some state.
    """
    rows = [model.joint_names.index(j) for j in measured]
    components = wrench_components(model, link, measured, q)
    c = 6 if components == 6 else 3
    Jt = _transposed(model, q, link, measured)[:, :, :c]                                  # (N, m, c)
    b = np.asarray(tau_ext, dtype=float).reshape(-1, model.n)[:, rows]
    if t is not None:
        t, K = np.asarray(t, dtype=float), np.asarray(gain, dtype=float)[rows]
        Jt = np.stack([observer_update(t, Jt[:, :, i], K) for i in range(c)], axis=2)     # Jᵀ through (update)
        b = b - np.exp(-K * (t - t[0])[:, None]) * b[0]                                   # r less its start's decay
    w = np.ones(len(rows)) if weights is None else np.asarray(weights, dtype=float)[rows]
    A = (Jt * w[:, None]).reshape(-1, c)                                                  # τ_ext = Jᵀ F, stacked
    scale = np.maximum(np.linalg.norm(A, axis=0), np.finfo(float).tiny) if c == 6 else np.ones(c)
    U, s, Vt = np.linalg.svd(A / scale, full_matrices=False)
    k = components if c == 3 else 6
    x = Vt[:k].T @ ((U[:, :k].T @ (b * w).reshape(-1)) / s[:k]) / scale                   # in the seen directions
    return Wrench(x[:3], x[3:] if c == 6 else None, float(s[0] / s[k - 1]), Vt[k:c, :3].copy())


def _contact_rows(log, r, event, theta, gain) -> np.ndarray:
    """The rows of an event while the contact lasts: from its start to its peak and to its end less the time
    r takes to decay from each joint's largest ``|r|`` to half its threshold, e^{−K τ} = RELEASE θ / ``|r|``."""
    inside = np.flatnonzero((log.t >= event.start) & (log.t <= event.end))
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.nan_to_num(np.abs(r[inside]) / theta).max(axis=0)
        decay = np.where(ratio > RELEASE, np.log(ratio / RELEASE) / gain, 0.0).max()
    last = max(int(np.flatnonzero(log.t == event.peak_t)[0]), int(np.searchsorted(log.t, event.end - decay,
                                                                                    side="right")) - 1)
    return np.arange(inside[0], min(max(last, inside[0] + 1), len(log.t) - 1) + 1)


def _with_wrench(model, log, r, event, link, measured, gain, theta) -> ContactEvent:
    """The event with its wrench, fitted through the observer's update over the rows of the contact."""
    rows = _contact_rows(log, r, event, theta, gain)
    fit = contact_wrench(model, log.q[rows], r[rows], link, measured, 1 / np.nan_to_num(theta, nan=1.0),
                         log.t[rows], gain)
    return ContactEvent(event.start, event.end, event.detected, event.joints, event.peak, event.peak_t,
                        tuple(map(float, fit.force)), None if fit.moment is None else tuple(map(float, fit.moment)),
                        fit.condition, tuple(tuple(map(float, u)) for u in fit.unseen))


def unseen_words(model: Model, unseen) -> str:
    """Directions not seen, in words: ``z of base_link`` for a base axis, else the unit vector in base coordinates.

    Parameters
    ----------
    model : Model
        The robot (its base link names the frame).
    unseen : array_like, shape (m, 3)
        Unit directions, base coordinates.

    Returns
    -------
    str
        The directions joined by ``and``; empty for none.
    """
    words = []
    for u in np.asarray(unseen, dtype=float).reshape(-1, 3):
        axis = int(np.argmax(np.abs(u)))
        words.append(f"{'xyz'[axis]} of {model.base_link}" if abs(u[axis]) > 1 - 1e-6 else
                     "(" + ", ".join(f"{x:+.3f}" for x in u * np.sign(u[axis])) + f") in {model.base_link}")
    return " and ".join(words)


def detect(model: Model, table, *, gain=DEFAULT_GAIN, threshold=None, window: float | None = None,
           sigmas: float = SIGMAS, min_duration: float = MIN_DURATION, link: str | None = None,
           friction: Friction | None = None, dt: float | None = None, columns: Mapping[str, str] | None = None,
           constants: Mapping[str, float] | None = None, time_unit: str = "s", resample: float | None = None,
           split_gaps: bool = False, repair: bool = False, smooth: int | None = None, torque_constants=None,
           compiled: bool | None = None) -> Detection:
    """Contacts in a log with measured torques: the observer's residual, its thresholds and events.

    Parameters
    ----------
    model : Model
        The robot.
    table : LogSource or table
        A log, as :func:`~course_dynamics.tools.logs.joint_log` reads one; it must hold measured torques.
    gain : float or array_like, shape (n,)
        K, 1/s.
    threshold : float or array_like, shape (n,), optional
        θ, N·m (N); by default ``sigmas`` σ above the residual's level (:func:`residual_noise`).
    window : float, optional
        The quiet stretch σ is measured on, s; None for the whole log.
    sigmas : float
        k of θ = ``|level|`` + k σ.
    min_duration : float
        The shortest event, s.
    link : str, optional
        A URDF link: each event's wrench there.
    friction : Friction, optional
        F(Θ̇), subtracted from the measured torques.
    dt : float, optional
        The sample step of a log without a ``t`` column, s.
    columns : mapping of str to str, optional
        Our column name → the log's.
    constants : mapping of str to float, optional
        Our column name → a value for every row, for signals the log lacks.
    time_unit : str
        The unit of the log's ``t`` column: s, ms, us or ns.
    resample : float, optional
        Put the log on an even clock at this rate first, Hz.
    split_gaps : bool
        Differentiate the pieces between long gaps apart instead of refusing them.
    repair : bool
        Mend the clock where rates are differentiated (:func:`~course_dynamics.tools.logs.joint_log`); a log with
        rates is taken on its own stamps, with or without it.
    smooth : int, optional
        The Savitzky–Golay window for rates the log lacks, samples (:func:`~course_dynamics.tools.logs.joint_log`'s
        ``window``).
    torque_constants : array_like, shape (n,), optional
        Turn logged motor currents into measured torques, N·m/A.
    compiled : bool, optional
        Whether to use the compiled model; None lets the evaluator choose.

    Returns
    -------
    Detection
        r(t), the thresholds, the events.

    Raises
    ------
    InputError
        What the log reader refuses, a log without measured torques, a bad gain, threshold, window or duration,
        a link too few measured joints move.
    ModelError
        A link the robot does not have.
    """
    source = as_source(table)
    K = _positive(gain, model.n, "gain", model.joint_names)
    if not (np.isfinite(sigmas) and sigmas > 0):
        raise InputError(f"sigmas: the threshold's multiple of the noise must be a positive number, got {sigmas:g}")
    if not (np.isfinite(min_duration) and min_duration >= 0):
        raise InputError(f"min_duration: the shortest event must be a non-negative number of seconds, got "
                         f"{min_duration:g}")
    if window is not None and not (np.isfinite(window) and window > 0):
        raise InputError(f"the quiet window must be a positive number of seconds, got {window:g}")
    if link is not None:
        model.frame(link)
    log = joint_log(model, source, dt=dt, columns=columns, window=smooth, constants=constants, time_unit=time_unit,
                    resample=resample, split_gaps=split_gaps, repair=repair, torque_constants=torque_constants,
                    needs="qd")
    if log.measured is None:
        raise InputError(f"{source.where}: no measured torques: the observer needs tau_meas_<joint> columns (a bag's "
                         "effort), or motor currents with their torque constants")
    measured = tuple(j for i, j in enumerate(model.joint_names) if np.all(np.isfinite(log.measured[:, i])))
    if link is not None:
        wrench_components(model, link, measured, log.q[::max(1, len(log.t) // 200)])   # refused if nothing is seen
    r = momentum_residual(model, log.t, log.q, log.qd, log.measured, K, friction, compiled)
    notes = [n for n in log.notes if not n.startswith("qdd:")]          # Θ̈ is never used here
    if not any(n.startswith("qd:") for n in notes):                         # nor how its edges were fitted
        notes = [n for n in notes if not n.startswith("edges:")]
    if len(log.t) > 1 and float(K.max()) * float(np.median(np.diff(log.t))) > 1:
        notes.append(f"gain K = {float(K.max()):g} 1/s is more than one over the sample step "
                     f"({float(np.median(np.diff(log.t))):.3g} s): r follows each step's momentum change unfiltered")
    sigma = np.full(model.n, np.nan)
    if threshold is None:
        level, noise = residual_noise(log.t, r, K, window, source.where)
        theta = np.abs(level) + sigmas * noise
        floor = THRESHOLD_FLOOR * np.nan_to_num(np.abs(log.measured).max(axis=0)) if len(log.t) else 0.0
        theta = np.maximum(theta, np.maximum(floor, np.finfo(float).tiny))
        sigma = noise
        settled = log.t[-1] - log.t[0] - SETTLING / float(np.min(K))
        long_window = window is not None and window > settled
        notes.append(f"thresholds: |median r| + {sigmas:g} sigma of r "
                     + (f"over {window:g} s" if window is not None and not long_window else "over the whole log")
                     + f" after the observer settled ({SETTLING:g}/K)"
                     + (f" (the quiet window, {window:g} s, is longer than the {settled:.3g} s left)"
                        if long_window else ""))
    else:
        theta = _positive(threshold, model.n, "threshold", model.joint_names)
    theta = np.where([j in measured for j in model.joint_names], theta, np.nan)
    band = None
    if friction is not None:
        band = friction_band(log.t, log.qd, friction, K, sigmas)
        notes.append(f"friction: each threshold grows by what F may be off by where the rate is within {sigmas:g} "
                     "sigma of the rate noise of a change in F (Coulomb's sign near a reversal), filtered as r is")
    events = contact_events(log.t, r, theta if band is None else theta + band, model.joint_names, min_duration)
    if link is not None:
        events = tuple(_with_wrench(model, log, r, e, link, measured, K, theta) for e in events)
        if wrench_components(model, link, measured, log.q[::max(1, len(log.t) // 200)]) < 6:
            notes.append(f"link '{link}': the measured joints cannot resolve a moment there, so the wrench is a "
                         "force at its origin, in the directions they see")
    return Detection(t=log.t, r=r, joints=model.joint_names, measured=measured, gain=K, threshold=theta, sigma=sigma,
                     events=tuple(events), link=link, notes=tuple(notes), band=band)


__all__ = ["DEFAULT_GAIN", "MIN_DURATION", "RANK_TOLERANCE", "RELEASE", "SIGMAS", "THRESHOLD_FLOOR", "ContactEvent",
           "Detection", "Wrench", "contact_events", "contact_wrench", "detect", "friction_band", "momentum_residual",
           "momentum_terms", "observer_update", "residual_noise", "unseen_words", "wrench_components"]

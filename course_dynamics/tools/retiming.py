"""A motion played slower, uniformly, until every joint is within its effort and velocity limits.

==========  ===========================================================================================
symbol      meaning (shape, unit)
==========  ===========================================================================================
``k``       the time scaling: the motion played k times slower, t ↦ t₀ + k (t − t₀) (scalar, 1)
``x``       1/k (scalar, 1)
``m``       the margin: the share of every limit kept clear of (scalar, 1)
``L``       a joint's effort limit (n,), N·m or N; ``L' = (1 − m) L``
``W``       a joint's velocity limit (n,), rad/s or m/s
``a``       what slowing down cannot lower: G(Θ) + Coulomb F_c sgn(Θ̇) + Jᵀ F (K, n), N·m or N
``b``       M(Θ) Θ̈ + V(Θ, Θ̇), which scales as 1/k² (K, n), N·m or N
``c``       viscous friction F_v Θ̇, which scales as 1/k (K, n), N·m or N
==========  ===========================================================================================

Played k times slower along the same path, Θ̇ becomes Θ̇/k and Θ̈ becomes Θ̈/k², so each joint's torque at
each sample is τ(x) = a + c x + b x² with x = 1/k. Every slower playing stays within ``|τ| ≤ L'`` up to the
first positive root of ``b x² + c x + a = ±L'``: a closed form per joint and sample; the smallest k is the
largest of their reciprocals, and of ``|Θ̇| / ((1 − m) W)`` for the velocity limits. When ``|a|`` alone exceeds
``L'`` no k helps: :class:`Retiming` says where (``static``). Smoothed Coulomb friction (tanh) is taken as its sign.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.errors import InputError
from ..core.evaluator import implementation
from ..core.friction import Friction
from .limits import seconds
from .logs import ROWS_AT_A_TIME, TorqueLog, torques_from_log
from .tables import joint_columns


@dataclass(frozen=True)
class Retiming:
    """The smallest uniform time scaling that brings a motion within its limits, or why there is none.

    Parameters
    ----------
    k : float or None
        The time scaling (the motion played k times slower); None when gravity, Coulomb friction and wrenches
        alone exceed a limit.
    duration : float
        The motion's duration as logged, s.
    margin : float
        The share of every limit kept clear of.
    joint : str
        The joint whose limit sets k (or that no k can bring within).
    kind : str
        ``"effort"`` or ``"velocity"``: the limit that sets k; ``"static"`` when no k can.
    at : float
        The time of the sample that sets k (or of the worst static torque), s.
    limit : float
        That joint's limit (N·m or N, rad/s or m/s).
    static : float or None
        With ``kind == "static"``: the torque that does not scale, ``a`` at that sample, N·m or N.
    """

    k: float | None
    duration: float
    margin: float
    joint: str
    kind: str
    at: float
    limit: float
    static: float | None = None

    @property
    def new_duration(self) -> float | None:
        """``k`` times the duration, s; None without a k."""
        return None if self.k is None else self.k * self.duration

    def describe(self) -> str:
        """The result in one line, for a report.

        Returns
        -------
        str
            k and the new duration, or the joint and the static torque that no k can lower.
        """
        share = f"{100 * (1 - self.margin):.4g}% of"
        if self.k is None:
            return (f"joint '{self.joint}': gravity and Coulomb friction alone need {self.static:.4g} N m or N at "
                    f"t = {seconds(self.at)} s against {share} the effort limit {self.limit:.4g}: "
                    "no slower playing lowers them")
        return (f"retimed: k = {self.k:.6g}, {seconds(self.duration)} s -> {seconds(self.new_duration)} s; set by "
                f"joint '{self.joint}' ({self.kind}, {share} the limit {self.limit:.4g}) at t = {seconds(self.at)} s")

    def record(self) -> dict:
        """The result, JSON-ready.

        Returns
        -------
        dict
            The fields and ``new_duration``.
        """
        return dict(k=self.k, duration=self.duration, new_duration=self.new_duration, margin=self.margin,
                    joint=self.joint, kind=self.kind, at=self.at, limit=self.limit, static=self.static)


def terms(result: TorqueLog, friction: Friction | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The torques of a log split by how they scale: τ(k) = a + c/k + b/k² (the module's table).

    Parameters
    ----------
    result : TorqueLog
        The torques of the log, from :func:`~course_dynamics.tools.logs.torques_from_log`.
    friction : Friction, optional
        The joint friction those torques included.

    Returns
    -------
    a, b, c : numpy.ndarray, shape (K, n)
        What does not scale, what scales as 1/k², what scales as 1/k; N·m or N.
    """
    log, model = result.log, result.model
    run = implementation(model, calls=-(-len(log.t) // ROWS_AT_A_TIME), states=min(len(log.t), ROWS_AT_A_TIME))
    b = np.empty_like(log.q)
    for start in range(0, len(log.t), ROWS_AT_A_TIME):
        rows = slice(start, start + ROWS_AT_A_TIME)
        b[rows] = run.inverse_dynamics(log.q[rows], log.qd[rows], log.qdd[rows]) - run.gravity_torques(log.q[rows])
    c = np.zeros_like(b) if friction is None else friction.viscous * log.qd
    return result.tau - b - c, b, c


def _first_exit(a: np.ndarray, b: np.ndarray, c: np.ndarray, bound: np.ndarray) -> np.ndarray:
    """The first x > 0 where ``|a + c x + b x²|`` reaches ``bound`` (inf where it never does), elementwise."""
    exit_ = np.full(a.shape, np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):
        for side in (1.0, -1.0):
            constant = a - side * bound
            quadratic = np.abs(b) > 1e-300
            disc = c * c - 4.0 * b * constant
            root = np.sqrt(np.where(disc >= 0, disc, np.nan))
            q = -0.5 * (c + np.where(c >= 0, 1.0, -1.0) * root)      # the stable pair q/b, constant/q
            for x in (q / b, constant / q):
                exit_ = np.where(quadratic & (disc >= 0) & (x > 0), np.fmin(exit_, x), exit_)
            linear = ~quadratic & (np.abs(c) > 1e-300)
            x = -constant / c
            exit_ = np.where(linear & (x > 0), np.fmin(exit_, x), exit_)
    return exit_


def retime(result: TorqueLog, friction: Friction | None = None, margin: float = 0.05) -> Retiming:
    """The smallest k such that the motion played k times slower (or any slower) is within its limits.

    Parameters
    ----------
    result : TorqueLog
        The torques of the log, from :func:`~course_dynamics.tools.logs.torques_from_log`.
    friction : Friction, optional
        The joint friction those torques included.
    margin : float, optional
        The share of every limit kept clear of, in [0, 1).

    Returns
    -------
    Retiming
        k, the durations and the joint that sets k; or, with ``k`` None, the joint whose static torque no k lowers.

    Raises
    ------
    InputError
        A margin outside [0, 1), and a motion that no limit bounds (nothing moves, or no joint has a limit).
    """
    if not 0 <= margin < 1:
        raise InputError(f"--margin must be in [0, 1), got {margin:g}")
    model, t = result.model, result.t
    names, keep = model.joint_names, 1.0 - margin
    duration = float(t[-1] - t[0])
    effort, velocity = model.effort, model.velocity
    a, b, c = terms(result, friction)
    bound = np.where(np.isfinite(effort), keep * effort, np.inf)
    over = np.where(np.isfinite(bound), np.abs(a) - bound, -np.inf)
    if np.any(over >= 0):
        row, i = np.unravel_index(int(np.argmax(np.where(over >= 0, np.abs(a) / effort, -np.inf))), a.shape)
        return Retiming(k=None, duration=duration, margin=margin, joint=names[i], kind="static", at=float(t[row]),
                        limit=float(effort[i]), static=float(abs(a[row, i])))
    x = np.where(np.isfinite(bound), _first_exit(a, b, c, bound), np.inf)
    k_effort = np.where(np.isfinite(x), 1.0 / x, 0.0)
    k_velocity = np.where(np.isfinite(velocity), np.abs(result.log.qd) / (keep * velocity), 0.0)
    k_effort, k_velocity = np.nan_to_num(k_effort), np.nan_to_num(k_velocity)
    kind, ks, limits = max((("effort", k_effort, effort), ("velocity", k_velocity, velocity)),
                           key=lambda entry: entry[1].max())
    row, i = np.unravel_index(int(np.argmax(ks)), ks.shape)
    if not ks[row, i] > 0:
        raise InputError("no limit bounds the motion's speed: nothing moves, or no moving joint has a limit")
    return Retiming(k=float(ks[row, i]), duration=duration, margin=margin, joint=names[i], kind=kind,
                    at=float(t[row]), limit=float(limits[i]))


def retimed_log(result: TorqueLog, k: float, friction: Friction | None = None, wrench=None) -> TorqueLog:
    """The motion played k times slower: t₀ + k (t − t₀), Θ, Θ̇/k, Θ̈/k², and its torques and limits report.

    Parameters
    ----------
    result : TorqueLog
        The torques of the log, from :func:`~course_dynamics.tools.logs.torques_from_log`.
    k : float
        The time scaling, > 0.
    friction : Friction, optional
        The joint friction, as for the log.
    wrench : Wrench or list of Wrench, optional
        The external wrenches, as for the log (payloads are in ``result.model`` already).

    Returns
    -------
    TorqueLog
        The retimed state, its torques (through :func:`~course_dynamics.tools.logs.torques_from_log`) and report.

    Raises
    ------
    InputError
        A k that is not a positive number.
    """
    if not (np.isfinite(k) and k > 0):
        raise InputError(f"a time scaling must be a positive number, got {k}")
    log, names = result.log, result.model.joint_names
    table = {"t": log.t[0] + k * (log.t - log.t[0])}
    for kind, values in (("q", log.q), ("qd", log.qd / k), ("qdd", log.qdd / k**2)):
        table.update(zip(joint_columns((kind,), names), values.T))
    return torques_from_log(result.model, table, friction=friction, wrench=wrench)


__all__ = ["Retiming", "retime", "retimed_log", "terms"]

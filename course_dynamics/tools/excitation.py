"""Excitation trajectories for identification: periodic motions that make the base regressor well conditioned.

===============  ===========  ==========================================================================
code             symbol       meaning (shape, unit)
===============  ===========  ==========================================================================
``period``       T            the duration, one period of the motion (s)
``w``            ω_f k        the harmonics' frequencies, k = 1 … H, ω_f = 2π/T (H,), rad/s
``q0``           q0_j         each joint's offset (n,), rad or m
``a``, ``b``     a_jk, b_jk   the Fourier coefficients (n, H), rad/s or m/s: amplitudes of q̇
``x``                         the free coefficients, divided by each joint's velocity scale (2 n (H − 1),)
``Y_b``          Y_b          the base regressor (:mod:`~course_dynamics.core.regressor`) (K, n, r)
``kappa``        κ            condition number of Y_b stacked over K instants, columns scaled to unit norm
===============  ===========  ==========================================================================

Each joint moves along a finite Fourier series (Swevers' form), periodic over T by construction::

    q_j(t) = q0_j + Σ_{k=1..H} a_jk/(ω_f k) sin(ω_f k t) − b_jk/(ω_f k) cos(ω_f k t)
    q̇_j(t) = Σ_k a_jk cos(ω_f k t) + b_jk sin(ω_f k t)
    q̈_j(t) = Σ_k ω_f k (b_jk cos(ω_f k t) − a_jk sin(ω_f k t))

It starts, and so ends, at rest in the middle of the joint's range (0 for a joint without one):
q(0) = q_mid, q̇(0) = 0 and q̈(0) = 0 fix q0_j = q_mid + Σ_k b_jk/(ω_f k), a_j1 = −Σ_{k≥2} a_jk and
b_j1 = −Σ_{k≥2} k b_jk, which leaves 2 (H − 1) free coefficients per joint. Then q − q_mid, q̇ and q̈
are linear in them.

Why κ: identification solves τ = Y_b π_b by least squares, and the relative error of π_b is up
to κ times that of the torques. Unit-norm columns make κ independent of the parameters' units,
as in :func:`~course_dynamics.tools.identification.identify`; repeating the period keeps κ.

SLSQP (SciPy), from seeded random coefficients, minimises log κ on ``samples`` instants of the period,
keeping ``|q − q_mid|``, ``|q̇|`` and ``|τ|`` (our inverse dynamics, rigid bodies) within (1 − margin) of half the
range, the velocity and the effort limit on ``CONSTRAINT_POINTS`` instants per period of the highest harmonic. q and
q̇ are linear in x (exact Jacobians); the other gradients are forward differences, one batched call each. The
best feasible iterate is kept, and checked against the limits themselves on ``FINE_POINTS`` instants per
period of the highest harmonic and on the written samples.

Which columns of the regressor κ is taken over is a parameter (``columns``: the base parameters by default; a
payload's ten, :class:`~course_dynamics.tools.payloads.Flange`, for ``excite --scope payload``), and so is which
joints move (``moving``: the others' coefficients are left out of x, so they rest in the middle of their ranges).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..core.evaluator import inverse_dynamics  # the evaluator chooses the implementation of each call
from ..core.model import Model
from ..core.regressor import BaseParameters, base_parameters
from . import excitationcost as batches  # the cost estimated up front, evaluations in bounded batches
from .excitationcost import ExcitationError
from .simulation import time_grid

#: H by default.
HARMONICS = 5           # H
#: Instants of the period on which κ is optimised, by default.
SAMPLES = 40            # instants of the period on which κ is optimised
#: SLSQP's iterations at most, by default.
MAX_ITERATIONS = 100    # of SLSQP
#: The share of each limit the optimisation keeps clear of, by default.
MARGIN = 0.05           # the share of each limit the optimisation keeps clear of
#: Seconds between written samples, by default.
DT = 0.01               # s between written samples
#: The fewest written samples a period of the highest harmonic may have (the file must show the motion).
SAMPLES_PER_HARMONIC = 4
#: Instants per period of the highest harmonic where the limits are imposed.
CONSTRAINT_POINTS = 24  # instants per period of the highest harmonic where the limits are imposed
#: Instants per period of the highest harmonic where the result is checked.
FINE_POINTS = 200       # instants per period of the highest harmonic where the result is checked
STEP = 1e-6             # forward-difference step in x
START_SHARE = 0.5       # the random start uses half of the tightest position or velocity limit
FEASIBLE = 1e-6         # slack (a share of a limit) within which an iterate counts as feasible
#: The kinds of limit an excitation keeps within, as :class:`LimitShares` names them.
KINDS = ("position", "velocity", "effort")
SMALLEST = 1e-6         # rad, m, rad/s or m/s: a joint whose half range or velocity limit is below it cannot move


def _number(x) -> float | None:
    return float(x) if np.isfinite(x) else None


@dataclass(frozen=True)
class Fourier:
    """The coefficients of the motion (module docstring); calling it gives (q, q̇, q̈) at times t.

    >>> f = Fourier(period=2.0, q0=[0.1], a=[[1.0, -1.0]], b=[[0.0, 0.0]])
    >>> q, qd, qdd = f([0.0, 0.5])
    >>> q.round(4).tolist(), qd.round(4).tolist()
    ([[0.1], [0.4183]], [[0.0], [1.0]])

    Parameters
    ----------
    period : float
        T, the motion's period, s.
    q0 : numpy.ndarray, shape (n,)
        Each joint's offset q0_j, rad (m for a prismatic joint).
    a : numpy.ndarray, shape (n, H)
        The cosine coefficients a_jk of q̇, rad/s (m/s).
    b : numpy.ndarray, shape (n, H)
        The sine coefficients b_jk of q̇, rad/s (m/s).
    """

    period: float
    q0: np.ndarray
    a: np.ndarray
    b: np.ndarray

    def __post_init__(self):
        for name in ("q0", "a", "b"):
            array = np.array(getattr(self, name), dtype=float)
            array.setflags(write=False)
            object.__setattr__(self, name, array)

    @property
    def harmonics(self) -> int:
        """H, the number of harmonics."""
        return self.a.shape[1]

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        w = 2 * np.pi / self.period * np.arange(1, self.harmonics + 1)  # ω_f k
        sin, cos = np.sin(t[:, None] * w), np.cos(t[:, None] * w)  # (K, H)
        q = self.q0 + sin @ (self.a / w).T - cos @ (self.b / w).T
        qd = cos @ self.a.T + sin @ self.b.T
        qdd = cos @ (self.b * w).T - sin @ (self.a * w).T
        return q, qd, qdd


@dataclass(frozen=True)
class LimitShares:
    """The largest share of each limit a motion uses, per joint (n,): 1 is at the limit, NaN where none is given.

    Position: max ``|q − q_mid|`` over half the range; velocity: max ``|q̇|`` over the limit; effort: max ``|τ|``
    over it.

    Parameters
    ----------
    joints : tuple of str
        The joints' names, in the model's order.
    position : numpy.ndarray, shape (n,)
        The share of half the range used.
    velocity : numpy.ndarray, shape (n,)
        The share of the velocity limit used.
    effort : numpy.ndarray, shape (n,)
        The share of the effort limit used.
    """

    joints: tuple[str, ...]
    position: np.ndarray
    velocity: np.ndarray
    effort: np.ndarray

    def largest(self, kind: str) -> tuple[float, str | None]:
        """(share, joint) of the joint that uses most of ``kind``'s limit; (NaN, None) if no joint has one.

        Parameters
        ----------
        kind : str
            One of :data:`KINDS`.

        Returns
        -------
        share : float
            The largest share.
        joint : str or None
            The joint that uses it.
        """
        shares = getattr(self, kind)
        if not np.isfinite(shares).any():
            return float("nan"), None
        j = int(np.nanargmax(shares))
        return float(shares[j]), self.joints[j]

    def record(self) -> dict:
        """The shares, JSON-ready.

        Returns
        -------
        dict
            {kind: {joint: share or None}}.
        """
        return {kind: {j: _number(s) for j, s in zip(self.joints, getattr(self, kind))} for kind in KINDS}


@dataclass(frozen=True)
class Excitation:
    """What :func:`excitation` made. ``t`` (K,), ``q``, ``qd``, ``qdd``, ``tau`` (K, n): the samples to write (τ by
    our inverse dynamics, rigid bodies); ``condition``: κ on the fine grid, ``condition_start``: the random start's,
    ``condition_samples``: κ on the optimisation's instants; ``limits``: the shares used (fine grid and samples);
    ``notes``: the limits the URDF lacks; ``ended``: how the optimisation ended.

    Parameters
    ----------
    joints : tuple of str
        The joints' names, in the model's order.
    t : numpy.ndarray, shape (K,)
        The written samples' times, s.
    q : numpy.ndarray, shape (K, n)
        Joint positions Θ, rad (m for a prismatic joint).
    qd : numpy.ndarray, shape (K, n)
        Joint velocities Θ̇, rad/s (m/s).
    qdd : numpy.ndarray, shape (K, n)
        Joint accelerations Θ̈, rad/s² (m/s²).
    tau : numpy.ndarray, shape (K, n)
        Joint torques τ by our inverse dynamics, rigid bodies, N·m (N).
    coefficients : Fourier
        The motion.
    condition : float
        κ on the fine grid.
    condition_start : float
        κ of the random start.
    condition_samples : float
        κ on the optimisation's instants.
    limits : LimitShares
        The shares of the limits used, on the fine grid and the samples.
    iterations : int
        SLSQP's iterations.
    notes : tuple of str
        The limits the URDF lacks.
    ended : str
        How the optimisation ended.
    """

    joints: tuple[str, ...]
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    tau: np.ndarray
    coefficients: Fourier
    condition: float
    condition_start: float
    condition_samples: float
    limits: LimitShares
    iterations: int
    notes: tuple[str, ...] = ()
    ended: str = ""

    def table(self, rows: slice = slice(None)) -> tuple[list[str], np.ndarray]:
        """(header, data) of samples ``rows``: t, ``q_<joint>``, ``qd_<joint>``, ``qdd_<joint>``, ``tau_<joint>``, as
        ``torques`` and ``simulate`` read.

        Parameters
        ----------
        rows : slice
            The samples.

        Returns
        -------
        header : list of str
            The column names.
        data : numpy.ndarray, shape (rows, 4 n + 1)
            One row per sample, SI units.
        """
        header = ["t"] + [f"{kind}_{j}" for kind in ("q", "qd", "qdd", "tau") for j in self.joints]
        return header, np.column_stack([v[rows] for v in (self.t, self.q, self.qd, self.qdd, self.tau)])

    def record(self) -> dict:
        """A JSON-ready summary (no samples).

        Returns
        -------
        dict
            κ, the largest shares, the shares per joint, the coefficients, the notes and how it ended.
        """
        largest = {kind: dict(share=_number(share), joint=joint)
                   for kind, (share, joint) in ((k, self.limits.largest(k)) for k in KINDS)}
        return dict(joints=list(self.joints), duration=float(self.coefficients.period),
                    harmonics=self.coefficients.harmonics, iterations=self.iterations,
                    condition=_number(self.condition),
                    condition_start=_number(self.condition_start), condition_samples=_number(self.condition_samples),
                    largest_share=largest, limits_used=self.limits.record(), written_samples=len(self.t),
                    coefficients=dict(q0=self.coefficients.q0.tolist(), a=self.coefficients.a.tolist(),
                                      b=self.coefficients.b.tolist()), notes=list(self.notes), ended=self.ended)


def condition_number(model: Model, q, qd, qdd, base: BaseParameters | None = None) -> float:
    """κ: the condition number of the base regressor stacked over the samples (K, n), columns of unit norm.

    Parameters
    ----------
    model : Model
        The robot.
    q : numpy.ndarray, shape (K, n)
        Joint positions Θ, rad (m for a prismatic joint).
    qd : numpy.ndarray, shape (K, n)
        Joint velocities Θ̇, rad/s (m/s).
    qdd : numpy.ndarray, shape (K, n)
        Joint accelerations Θ̈, rad/s² (m/s²).
    base : BaseParameters, optional
        The model's base parameters, if already computed.

    Returns
    -------
    float
        κ; inf where a column of the regressor vanishes.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> t = np.linspace(0, 2 * np.pi, 50)[:, None]             # both joints in phase: a poor excitation
    >>> q, qd, qdd = np.sin(t) * [1.0, 0.5], np.cos(t) * [1.0, 0.5], -np.sin(t) * [1.0, 0.5]
    >>> round(condition_number(load_robot("two_link"), q, qd, qdd), 1)
    79.3
    """
    base = base_parameters(model) if base is None else base
    states = [np.asarray(v, dtype=float).reshape(1, -1, model.n) for v in (q, qd, qdd)]
    return float(batches.kappa_of_gram(batches.gram(model, base, *states))[0])  # in batches: bounded memory


class _Bounds(NamedTuple):
    """Per joint (n,): q_mid, half the range, velocity and effort limits (inf: none), velocity scale; notes."""

    mid: np.ndarray
    half: np.ndarray
    velocity: np.ndarray
    effort: np.ndarray
    scale: np.ndarray
    notes: tuple[str, ...]


def _ranges(model: Model):
    """(has a range, q_mid, half the range) per joint: 0 and inf without one.

    Halved before they are added, so that limits at the largest floats (±1.8e308) give a finite middle and half.
    """
    ranged = np.isfinite(model.lower) & np.isfinite(model.upper)
    lower, upper = np.where(ranged, model.lower, 0.0), np.where(ranged, model.upper, 0.0)
    return ranged, lower / 2 + upper / 2, np.where(ranged, upper / 2 - lower / 2, np.inf)


def _bounds(model: Model, omega: float) -> _Bounds:
    """The URDF's limits, the missing ones in notes; ExcitationError for a joint that nothing bounds or cannot move."""
    ranged, mid, half = _ranges(model)
    velocity, effort = model.velocity, model.effort
    notes = []
    for j, name in enumerate(model.joint_names):
        if ranged[j] and half[j] <= 0:
            raise ExcitationError(f"joint '{name}' of robot '{model.name}' cannot move: its limits are lower = upper = "
                                  f"{model.lower[j]:g} (exporters often write 0 for 'no limit': give it real ones)")
        for what, value in (("half its range", half[j]), ("its velocity limit", velocity[j])):
            if value < SMALLEST:  # its motion would vanish in rounding, and κ with it (inf)
                raise ExcitationError(f"joint '{name}' of robot '{model.name}' can hardly move: {what} is {value:.3g}, "
                                      f"below {SMALLEST:g} (rad, m or per s), so no motion within it excites its "
                                      "parameters: give it real limits")
        if not ranged[j] and not np.isfinite(velocity[j]):
            raise ExcitationError(f"joint '{name}' of robot '{model.name}' has neither position limits nor a velocity "
                                  "limit in the URDF, so nothing bounds how far or fast it may move: give it "
                                  "<limit lower=... upper=... velocity=...>")
        if not ranged[j]:
            notes.append(f"joint '{name}' has no position limits: it starts at 0 and only its velocity is bounded")
        if not np.isfinite(effort[j]):
            notes.append(f"joint '{name}' has no effort limit: its torque is not bounded")
    return _Bounds(mid, half, velocity, effort, np.where(np.isfinite(velocity), velocity, half * omega), tuple(notes))


def _coefficients(x: np.ndarray, bounds: _Bounds, period: float, harmonics: int) -> Fourier:
    """The motion of free coefficients x, the first harmonic and q0 chosen to start at rest (module docstring)."""
    free = np.asarray(x, dtype=float).reshape(2, len(bounds.mid), harmonics - 1) * bounds.scale[None, :, None]
    k = np.arange(2, harmonics + 1)
    a = np.column_stack([-free[0].sum(axis=1), free[0]])
    b = np.column_stack([-(free[1] * k).sum(axis=1), free[1]])
    w = 2 * np.pi / period * np.arange(1, harmonics + 1)
    return Fourier(period, bounds.mid + (b / w).sum(axis=1), a, b)


def _linear_maps(bounds: _Bounds, period: float, harmonics: int, t: np.ndarray) -> np.ndarray:
    """L (3, K, n, P): (q − q_mid, q̇, q̈) at times t is L @ x, the motion being linear in x."""
    n, k = len(bounds.mid), np.arange(2, harmonics + 1)
    w1 = 2 * np.pi / period
    wt = w1 * np.asarray(t, dtype=float)[:, None]                                 # ω_f t, (K, 1)
    sin_k, cos_k, sin_1, cos_1 = np.sin(wt * k), np.cos(wt * k), np.sin(wt), np.cos(wt)
    # per unit of a_jk (a_j1 = −a_jk) and of b_jk (b_j1 = −k b_jk, q0_j += b_jk (1/k − k)/ω_f), (3, 2, K, H−1)
    unit = np.array([[sin_k / (k * w1) - sin_1 / w1, (1 / k - k) / w1 - cos_k / (k * w1) + k * cos_1 / w1],
                     [cos_k - cos_1, sin_k - k * sin_1],
                     [-k * w1 * sin_k + w1 * sin_1, k * w1 * cos_k - k * w1 * cos_1]])
    maps = np.zeros((3, len(wt), n, 2, n, harmonics - 1))
    for j in range(n):   # coefficient (s, j, k) moves joint j only
        maps[:, :, j, :, j, :] = bounds.scale[j] * np.moveaxis(unit, 1, 2)
    return maps.reshape(3, len(wt), n, -1)


def _states(L: np.ndarray, X: np.ndarray, mid: np.ndarray):
    """(q, q̇, q̈) of free coefficients X (m, P), each (m, K, n)."""
    q, qd, qdd = (np.einsum("knp,mp->mkn", L[i], X) for i in range(3))
    return q + mid, qd, qdd


class _Problem:
    """log κ on the instants ``t_kappa`` and the limits' slack on ``t_limits``, as functions of x: the coefficients
    of the joints ``moving`` (the others rest in the middle of their ranges)."""

    def __init__(self, model, base, bounds, period, harmonics, t_kappa, t_limits, margin, moving):
        self.model, self.base, self.bounds, self.margin = model, base, bounds, margin
        joint = np.tile(np.repeat(np.arange(model.n), harmonics - 1), 2)        # the joint of each of x's entries
        self.free, self.P_all = np.flatnonzero(np.asarray(moving, dtype=bool)[joint]), len(joint)
        self.K = _linear_maps(bounds, period, harmonics, t_kappa)[..., self.free]
        self.C = _linear_maps(bounds, period, harmonics, t_limits)[..., self.free]
        self.P = self.K.shape[-1]
        self.values: dict[bytes, float] = {}
        ranged, fast = np.isfinite(bounds.half), np.isfinite(bounds.velocity)
        rows = [self.C[0][:, ranged] / bounds.half[ranged, None], self.C[1][:, fast] / bounds.velocity[fast, None]]
        A = np.concatenate([r.reshape(-1, self.P) for r in rows])     # shares of position and velocity, A x
        self.A = np.vstack([A, -A])
        self.strong = np.isfinite(bounds.effort)
        self.tick = None  # called with the number of states just evaluated (progress within an iteration)

    def full(self, x: np.ndarray) -> np.ndarray:
        """Every joint's free coefficients (2 n (H − 1),) of x, 0 for the joints that rest."""
        out = np.zeros(self.P_all)
        out[self.free] = x
        return out

    def kappas(self, X: np.ndarray) -> np.ndarray:
        """κ of each row of X, a few rows at a time (the states of X are not all kept), regressor calls in batches."""
        rows = max(1, 4096 // self.K.shape[1])
        states = (_states(self.K, X[k:k + rows], self.bounds.mid) for k in range(0, len(X), rows))
        return np.concatenate([batches.kappa_of_gram(batches.gram(self.model, self.base, *s, self.tick))
                               for s in states])

    def objective(self, x: np.ndarray) -> float:
        """log κ at x (remembered: SLSQP and the callback ask for the same x again)."""
        key = x.tobytes()
        if key not in self.values:  # a few hundred x in all: kept
            self.values[key] = float(np.log(min(self.kappas(x[None])[0], 1e300)))
        return self.values[key]

    def gradient(self, x: np.ndarray) -> np.ndarray:
        """∂ log κ/∂x by forward differences: one regressor call for the P perturbations of x."""
        values = np.log(np.minimum(self.kappas(x + STEP * np.eye(self.P)), 1e300))
        return (values - self.objective(x)) / STEP

    def torque_shares(self, X: np.ndarray) -> np.ndarray:
        """τ / effort limit at the limit instants, for the joints that have one: (m, K, n_limited)."""
        rows = max(1, 4096 // self.C.shape[1])
        shares = []
        for k in range(0, len(X), rows):
            tau = batches.torques(self.model, *_states(self.C, X[k:k + rows], self.bounds.mid), self.tick)
            shares.append(tau[..., self.strong] / self.bounds.effort[self.strong])
        return np.concatenate(shares)

    def slack(self, x: np.ndarray) -> np.ndarray:
        """1 − margin − share for every constraint row: ≥ 0 is within the limits with the margin."""
        shares = [self.A @ x]
        if self.strong.any():
            tau = self.torque_shares(x[None])[0].ravel()
            shares += [tau, -tau]
        return 1 - self.margin - np.concatenate(shares)

    def slack_jacobian(self, x: np.ndarray) -> np.ndarray:
        """∂ slack/∂x: exact for positions and velocities, forward differences for the torques."""
        rows = [self.A]
        if self.strong.any():
            tau = self.torque_shares(np.vstack([x, x + STEP * np.eye(self.P)]))
            d = ((tau[1:] - tau[0]) / STEP).reshape(self.P, -1).T
            rows += [d, -d]
        return -np.vstack(rows)


def _start(problem: _Problem, rng) -> np.ndarray:
    """Seeded random free coefficients, scaled to START_SHARE of the tightest position or velocity limit, then
    halved until the torques are within the limits too; ExcitationError when even rest in the middle is not."""
    x = rng.standard_normal(problem.P)
    x *= START_SHARE / max(np.abs(problem.A @ x).max(), 1e-300)
    for _ in range(40):
        if problem.slack(x).min() >= 0:
            return x
        x = x / 2
    model, (mid, effort) = problem.model, (problem.bounds.mid, problem.bounds.effort)
    tau = np.abs(inverse_dynamics(model, mid, 0 * mid, 0 * mid))
    j = int(np.argmax(np.where(problem.strong, tau / effort, 0.0)))
    raise ExcitationError(f"robot '{model.name}' cannot even rest in the middle of its joint ranges within its effort "
                          f"limits less the margin: joint '{model.joint_names[j]}' needs {tau[j]:.4g} of its limit "
                          f"{effort[j]:.4g} (N m or N)")


def limit_shares(model: Model, q, qd, tau) -> LimitShares:
    """The shares of the URDF's limits a motion (K, n) uses, position measured from the middle of the range.

    Parameters
    ----------
    model : Model
        The robot.
    q : numpy.ndarray, shape (K, n)
        Joint positions Θ, rad (m for a prismatic joint).
    qd : numpy.ndarray, shape (K, n)
        Joint velocities Θ̇, rad/s (m/s).
    tau : numpy.ndarray, shape (K, n)
        Joint torques τ, N·m (N).

    Returns
    -------
    LimitShares
        Per joint, the largest share of each limit; NaN where none is given.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> arm = load_robot("rp_arm")                   # d2 between 0.1 and 0.8 m, at most 1 m/s
    >>> shares = limit_shares(arm, [[0.0, 0.8]], [[0.0, 0.5]], [[50.0, 0.0]])
    >>> shares.position.round(3).tolist(), shares.velocity.tolist(), shares.effort.tolist()
    ([0.0, 1.0], [0.0, 0.5], [0.5, 0.0])
    """
    q, qd, tau = (np.atleast_2d(np.asarray(v, dtype=float)) for v in (q, qd, tau))
    ranged, mid, half = _ranges(model)

    def share(values, limit, where):
        return np.where(where, np.abs(values).max(axis=0) / np.where(where, limit, 1.0), np.nan)

    return LimitShares(model.joint_names, share(q - mid, half, ranged & (half > 0)),
                       share(qd, model.velocity, np.isfinite(model.velocity)),
                       share(tau, model.effort, np.isfinite(model.effort)))


def excitation(model: Model, duration: float, harmonics: int = HARMONICS, samples: int = SAMPLES, seed: int = 0,
               max_iterations: int = MAX_ITERATIONS, margin: float = MARGIN, dt: float = DT,
               progress=None, columns=None, moving=None) -> Excitation:
    """A periodic excitation of ``duration`` seconds with a small κ, within the URDF's limits (module docstring).

    Parameters
    ----------
    model : Model
        The robot; its position, velocity and effort limits bound the motion.
    duration : float
        T, one period, s.
    harmonics : int
        H ≥ 2.
    samples : int
        The instants of the period κ is optimised on.
    seed : int
        The seed of the random start.
    max_iterations : int
        SLSQP's iterations at most.
    margin : float
        The share of each limit kept clear of, 0 ≤ margin < 1.
    dt : float
        Seconds between the written samples (t = 0 … T, both ends: the motion is at rest in the middle at both).
    progress : callable, optional
        Called as ``progress(iteration, max_iterations)``.
    columns : BaseParameters or Flange, optional
        The regressor's columns whose κ counts (``rank`` and ``regressor(Y)``): the base parameters by default; a
        payload's (:class:`~course_dynamics.tools.payloads.Flange`) for an excitation of the payload alone.
    moving : array_like of bool, shape (n,), optional
        The joints that move (default all); the others rest in the middle of their ranges.

    Returns
    -------
    Excitation
        The samples, the coefficients, κ and the shares of the limits used.

    Raises
    ------
    ExcitationError
        A bad option (a time grid of fewer than :data:`SAMPLES_PER_HARMONIC` samples a harmonic among them), a
        joint without position and velocity limits or that cannot move, a robot that
        cannot rest in the middle within its effort limits, or a result beyond a limit on the fine grid.
    SimulationError
        A ``duration`` or ``dt`` that gives no time grid (not positive, ``dt`` longer than ``duration``, too many
        samples for the memory budget).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> found = excitation(load_robot("two_link"), 4.0, harmonics=3, samples=12, max_iterations=15)
    >>> bool(found.condition < found.condition_start), bool(np.nanmax(found.limits.velocity) <= 1)
    (True, True)
    """
    import scipy.optimize  # lazily: slow to import, and nothing else here needs it

    batches.check_options(duration, harmonics, samples, max_iterations, margin)
    t = time_grid(duration, dt, values_per_sample=batches.SAMPLE_VALUES * model.n + 1)
    if len(t) < SAMPLES_PER_HARMONIC * harmonics + 1:  # the file would not show the motion that was optimised
        raise ExcitationError(f"{len(t)} samples ({duration:g} s every {dt:g} s) cannot show {harmonics} harmonics: "
                              f"at least {SAMPLES_PER_HARMONIC * harmonics + 1} are needed (a longer duration, a "
                              "shorter dt, or fewer harmonics)")
    bounds = _bounds(model, 2 * np.pi / duration)
    batches.cost(model, harmonics, samples, len(t), max_iterations, CONSTRAINT_POINTS, FINE_POINTS)  # or refused
    base = base_parameters(model) if columns is None else columns
    moving = np.ones(model.n, dtype=bool) if moving is None else np.asarray(moving, dtype=bool)
    if not moving.any():
        raise ExcitationError(f"robot '{model.name}': no joint is to move, so nothing is excited")
    if not samples * model.n >= base.rank:
        raise ExcitationError(f"the instants the condition is optimised at must be a whole number from "
                              f"{-(-base.rank // model.n)} (instants × {model.n} joints ≥ the {base.rank} base "
                              f"parameters) to {batches.INSTANTS_MAX}, got {samples}")
    problem = _Problem(model, base, bounds, duration, harmonics, np.arange(samples) * duration / samples,
                       np.linspace(0, duration, CONSTRAINT_POINTS * harmonics, endpoint=False), margin, moving)
    start = _start(problem, np.random.default_rng(seed))
    best, iterations, ended = [problem.objective(start), start], 0, "skipped (0 iterations)"
    work = [0, (problem.P + 1) * (samples + CONSTRAINT_POINTS * harmonics * problem.strong.any())]  # an iteration's

    def tick(states):  # the bar moves within an iteration, up to just short of its end
        work[0] += states
        if progress is not None and iterations < max_iterations:
            progress(min(iterations + work[0] / work[1], iterations + 0.99), max_iterations)

    problem.tick = tick

    def keep_best(x, count=True):
        nonlocal iterations
        iterations += count
        work[0] = 0
        if progress is not None and count:
            progress(iterations, max_iterations)
        value = problem.objective(x)
        if value < best[0] and problem.slack(x).min() >= -FEASIBLE:
            best[:] = value, x.copy()

    if max_iterations > 0:
        result = scipy.optimize.minimize(
            problem.objective, start, jac=problem.gradient, method="SLSQP", callback=keep_best,
            constraints=[dict(type="ineq", fun=problem.slack, jac=problem.slack_jacobian)],
            options=dict(maxiter=max_iterations, ftol=1e-6))
        keep_best(result.x, count=False)
        ended = "converged" if result.success else f"stopped: {result.message}"
    coefficients = _coefficients(problem.full(best[1]), bounds, duration, harmonics)
    fine = np.linspace(0, duration, FINE_POINTS * harmonics, endpoint=False)
    q_fine, qd_fine, qdd_fine = coefficients(fine)
    q, qd, qdd, tau = batches.motion_samples(model, coefficients, t)
    shares = limit_shares(model, q_fine, qd_fine, batches.torques(model, q_fine, qd_fine, qdd_fine))
    written = limit_shares(model, q, qd, tau)  # separately: the samples are not copied
    shares = LimitShares(model.joint_names, *(np.fmax(getattr(shares, k), getattr(written, k)) for k in KINDS))
    for kind in KINDS:
        share, joint = shares.largest(kind)
        if share > 1:
            raise ExcitationError(f"robot '{model.name}': the optimised motion uses {share:.3g} of the {kind} limit of "
                                  f"joint '{joint}' on the fine grid; try a larger margin")
    condition_start = condition_number(model, *_coefficients(problem.full(start), bounds, duration, harmonics)(fine),
                                       base=base)
    condition = condition_number(model, q_fine, qd_fine, qdd_fine, base=base)
    if not np.isfinite(condition):
        raise ExcitationError(f"robot '{model.name}': the motion does not excite every base parameter within its "
                              "limits (condition number inf); check that every joint's limits let it move")
    return Excitation(
        joints=model.joint_names, t=t, q=q, qd=qd, qdd=qdd, tau=tau, coefficients=coefficients,
        condition=condition, condition_start=condition_start,
        condition_samples=float(np.exp(best[0])), limits=shares, iterations=iterations, notes=bounds.notes, ended=ended)


__all__ = ["CONSTRAINT_POINTS", "DT", "FINE_POINTS", "HARMONICS", "KINDS", "MARGIN", "MAX_ITERATIONS", "SAMPLES",
           "SAMPLES_PER_HARMONIC",
           "Excitation", "ExcitationError", "Fourier", "LimitShares", "condition_number", "excitation",
           "limit_shares"]

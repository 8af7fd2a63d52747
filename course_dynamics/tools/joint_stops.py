"""Joint stops: a joint at its limit as a unilateral constraint, for ``simulate(..., limits="stop")``.

A joint i that reaches a limit is stopped by an impulse P acting through M, and then held there by a reaction
torque λ while the motion pushes into the limit; it is released when λ would have to pull. The other joints keep
their momentum consistently, and no stop adds energy: the impulse is the M-orthogonal projection of Θ̇ onto the
motions that leave the stopped joints still, so the kinetic energy never grows at a stop, and a held joint does no
work (λᵢ Θ̇ᵢ = 0).

==============  ===================================================================================================
symbol          meaning
==============  ===================================================================================================
M, b            the mass matrix M(Θ) and the bias b = V(Θ, Θ̇) + G(Θ), from the library's evaluator
E               the columns eᵢ of the stopped (or held) joints i
dᵢ              +1 at an upper limit, −1 at a lower one: the direction into the limit
P               the impulse of a stop, N·m·s: Θ̇⁺ = Θ̇⁻ + M⁻¹E P with Eᵀ Θ̇⁺ = 0, so
                P = −(Eᵀ M⁻¹ E)⁻¹ Eᵀ Θ̇⁻; for one joint Δ Θ̇ = −M⁻¹eᵢ (eᵢᵀ Θ̇⁻) / (M⁻¹)ᵢᵢ
λ               the held joints' reaction, N·m: M Θ̈ + b = τ + E λ with Eᵀ Θ̈ = 0 (the constrained dynamics,
                whose Lagrange multiplier λ is)
==============  ===================================================================================================

A limit can only push: a stop keeps a joint only if dᵢ Pᵢ ≤ 0, a hold only if dᵢ λᵢ ≤ 0. When several joints are
stopped or held at once, the small complementarity problem is solved exactly (every stopped or held joint
pushed, every other joint at its limit leaving it) by principal pivoting.

>>> import numpy as np
>>> M = np.array([[2.0, 1.0], [1.0, 1.0]])
>>> qd, side = np.array([0.0, 1.0]), np.array([0, 1])              # joint 2 runs into its upper limit
>>> after, stopped, impulse = stop_impulse(M, qd, np.array([False, True]), side)
>>> after, stopped, np.round(impulse, 6)                            # joint 1 keeps its momentum
(array([0.5, 0. ]), array([False,  True]), array([ 0. , -0.5]))
>>> (M @ qd)[0], (M @ after)[0]                                      # joint 1's momentum is kept
(np.float64(1.0), np.float64(1.0))
>>> 0.5 * qd @ M @ qd, 0.5 * after @ M @ after                      # and the stop took kinetic energy
(np.float64(0.5), np.float64(0.25))
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.compiled.impulses import MAXIMUM_PIVOTS
from ..core.compiled.stopping import MAXIMUM_CONTACTS_PER_STEP, POSITION_TOLERANCE
from ..core.model import Model


@dataclass(frozen=True)
class Stop:
    """One stop: the joints a contact stopped at one instant, and the kinetic energy the impulse took.

    Parameters
    ----------
    t : float
        When the joints reached their limits, s.
    member : int or None
        The ensemble member, or None for a single run.
    joints : tuple of str
        The joints stopped.
    sides : tuple of str
        ``"lower"`` or ``"upper"``, one per joint.
    limits : tuple of float
        The limits reached, rad (m for a prismatic joint), one per joint.
    kinetic_before : float
        The kinetic energy just before the impulse, J.
    kinetic_after : float
        The kinetic energy just after it, J.
    """

    t: float
    member: int | None
    joints: tuple[str, ...]
    sides: tuple[str, ...]
    limits: tuple[float, ...]
    kinetic_before: float
    kinetic_after: float

    @property
    def energy(self) -> float:
        """The kinetic energy the stop changed (``kinetic_after − kinetic_before``, J), never positive.

        Returns
        -------
        float
            The change, J.
        """
        return self.kinetic_after - self.kinetic_before

    def sentence(self) -> str:
        """The stop in words, as ``Trajectory.events`` holds it.

        Returns
        -------
        str
            ``t = … s: joint '…' stopped at its upper limit … (kinetic energy … J -> … J)``.
        """
        member = f"member {self.member}: " if self.member is not None else ""
        where = " and ".join(f"joint '{j}' stopped at its {s} limit {b:g}"
                             for j, s, b in zip(self.joints, self.sides, self.limits))
        return (f"t = {self.t:.6g} s: {member}{where} (kinetic energy {self.kinetic_before:.6g} J -> "
                f"{self.kinetic_after:.6g} J)")

    def record(self) -> dict:
        """The stop as plain data, for ``--json``.

        Returns
        -------
        dict
            t, member, joints, sides, limits, kinetic_before, kinetic_after and energy.
        """
        return dict(t=self.t, member=self.member, joints=list(self.joints), sides=list(self.sides),
                    limits=list(self.limits), kinetic_before=self.kinetic_before, kinetic_after=self.kinetic_after,
                    energy=self.energy)


def stops_recorded(model: Model, rows: np.ndarray, ensemble: bool) -> tuple[Stop, ...]:
    """The stops a native run recorded, as :class:`Stop` records.

    Parameters
    ----------
    model : Model
        The robot.
    rows : numpy.ndarray, shape (S, 4 + 2n)
        One row per stop (:data:`~course_dynamics.core.compiled.impulses.STOP_RECORD`).
    ensemble : bool
        Whether the run was an ensemble's (a single run's stops name no member).

    Returns
    -------
    tuple of Stop
        In the rows' order.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> row = np.array([[0.25, 0.0, 2.0, 0.5, 0.0, 1.0, 0.0, 1.5]])    # joint 2 stopped at its upper limit
    >>> stops_recorded(load_robot("double_pendulum"), row, ensemble=False)[0].sentence()
    "t = 0.25 s: joint 'joint2' stopped at its upper limit 1.5 (kinetic energy 2 J -> 0.5 J)"
    """
    n, found = model.n, []
    for row in rows:
        stopped = np.flatnonzero(row[4:4 + n])
        found.append(Stop(t=float(row[0]), member=int(row[1]) if ensemble else None,
                          joints=tuple(model.joint_names[j] for j in stopped),
                          sides=tuple("upper" if row[4 + j] > 0 else "lower" for j in stopped),
                          limits=tuple(float(row[4 + n + j]) for j in stopped),
                          kinetic_before=float(row[2]), kinetic_after=float(row[3])))
    return tuple(found)


def limit_bounds(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """The limits a stop holds: the URDF's where they form a non-empty interval, ∓inf elsewhere.

    Parameters
    ----------
    model : Model
        The robot.

    Returns
    -------
    lower, upper : numpy.ndarray, shape (n,)
        The lower and upper limits, rad (m for a prismatic joint).
    """
    limited = np.isfinite(model.lower) & np.isfinite(model.upper) & (model.lower < model.upper)
    return np.where(limited, model.lower, -np.inf), np.where(limited, model.upper, np.inf)


def _masked_system(A: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """A's rows and columns of the masked joints, the identity elsewhere: a system in the masked joints only."""
    both = mask[..., :, None] & mask[..., None, :]
    return np.where(both, A, 0.0) + np.eye(A.shape[-1]) * ~mask[..., None, :]


def _solve(A: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    return np.linalg.solve(A, rhs[..., None])[..., 0]


def held_accelerations(M: np.ndarray, bias: np.ndarray, tau: np.ndarray, held: np.ndarray):
    """The constrained forward dynamics: Θ̈ with Θ̈ᵢ = 0 for the held joints, and their reaction λ.

    M Θ̈ + b = τ + E λ and Eᵀ Θ̈ = 0: the free joints' rows of M Θ̈ = τ − b are solved with the held joints' Θ̈
    zero, and λ is what the held joints' rows then lack.

    Parameters
    ----------
    M : numpy.ndarray, shape (n, n) or (K, n, n)
        The mass matrix M(Θ), kg·m² (kg).
    bias : numpy.ndarray, shape (n,) or (K, n)
        V(Θ, Θ̇) + G(Θ), N·m (N).
    tau : numpy.ndarray, shape (n,) or (K, n)
        The driving torques τ (friction taken off), N·m (N).
    held : numpy.ndarray of bool, shape (n,) or (K, n)
        Which joints are held.

    Returns
    -------
    qdd : numpy.ndarray, shape (n,) or (K, n)
        Joint accelerations Θ̈, rad/s² (m/s²), zero for the held joints.
    reaction : numpy.ndarray, shape (n,) or (K, n)
        λ, N·m (N): the held joints' reaction torques, zero for the others.

    Examples
    --------

    >>> M, b = np.array([[2.0, 1.0], [1.0, 1.0]]), np.array([0.0, -1.0])   # something pushes joint 2 forward
    >>> qdd, reaction = held_accelerations(M, b, np.zeros(2), np.array([False, True]))
    >>> qdd, reaction
    (array([0., 0.]), array([ 0., -1.]))
    """
    held = np.asarray(held, dtype=bool)
    rhs = tau - bias
    qdd = np.where(held, 0.0, _solve(_masked_system(M, ~held), np.where(held, 0.0, rhs)))
    reaction = np.where(held, (M @ qdd[..., None])[..., 0] - rhs, 0.0)
    return qdd, reaction


def _pivot(candidates: np.ndarray, solve, wrong):
    """Murty's least-index principal pivoting on the small complementarity problem of a stop or a hold: start
    with every candidate active; while some joint breaks complementarity (active and pulling, or inactive and
    moving into its limit), flip the first such joint of each state. For these problems (the matrices Eᵀ M⁻¹ E
    are positive definite) it ends at the one solution."""
    active = np.asarray(candidates, dtype=bool).copy()
    for _ in range(MAXIMUM_PIVOTS):
        result = solve(active)
        bad = wrong(active, *result)
        if not bad.any():
            break
        flat, rows = active.reshape(-1, active.shape[-1]), bad.reshape(-1, bad.shape[-1])
        broken = np.flatnonzero(rows.any(axis=1))
        first = np.argmax(rows[broken], axis=1)
        flat[broken, first] = ~flat[broken, first]
        active = flat.reshape(active.shape)
    return active, result


def _round_off(x: np.ndarray) -> np.ndarray:
    """What counts as zero beside the values of x, state by state: 1e-12 of the largest."""
    return 1e-12 * (1e-300 + np.abs(x).max(axis=-1, keepdims=True))


def hold(M: np.ndarray, bias: np.ndarray, tau: np.ndarray, held: np.ndarray, side: np.ndarray):
    """The joints held, their reaction and the accelerations: every held joint pushed by its reaction (dᵢ λᵢ ≤ 0),
    every other candidate accelerating away from its limit (dᵢ Θ̈ᵢ ≤ 0).

    Parameters
    ----------
    M : numpy.ndarray, shape (n, n) or (K, n, n)
        The mass matrix M(Θ), kg·m² (kg).
    bias : numpy.ndarray, shape (n,) or (K, n)
        V(Θ, Θ̇) + G(Θ), N·m (N).
    tau : numpy.ndarray, shape (n,) or (K, n)
        The driving torques τ (friction taken off), N·m (N).
    held : numpy.ndarray of bool, shape (n,) or (K, n)
        The joints that may be held (each at a limit, still).
    side : numpy.ndarray, shape (n,) or (K, n)
        dᵢ: +1 at an upper limit, −1 at a lower one (0 elsewhere).

    Returns
    -------
    held : numpy.ndarray of bool, shape (n,) or (K, n)
        The joints held.
    qdd : numpy.ndarray, shape (n,) or (K, n)
        Joint accelerations Θ̈, rad/s² (m/s²).
    reaction : numpy.ndarray, shape (n,) or (K, n)
        λ, N·m (N), zero for the joints not held.

    Examples
    --------

    >>> M = np.array([[2.0, 1.0], [1.0, 1.0]])
    >>> held, qdd, reaction = hold(M, np.array([0.0, 1.0]), np.zeros(2), np.array([False, True]), np.array([0, 1]))
    >>> held, qdd                                                     # pulled away from its upper limit: let go
    (array([False, False]), array([ 1., -2.]))
    """
    candidates = np.asarray(held, dtype=bool)
    scale = _round_off(tau - bias)

    def wrong(active, qdd, reaction):
        return ((active & (side * reaction > scale)) |
                (candidates & ~active & (side * qdd > _round_off(qdd))))

    held, (qdd, reaction) = _pivot(candidates, lambda active: held_accelerations(M, bias, tau, active), wrong)
    return held, qdd, reaction


def stop_impulse(M: np.ndarray, qd: np.ndarray, stopping: np.ndarray, side: np.ndarray, resting=0.0):
    """Θ̇ just after the impulse that stops joints at their limits, acting through M.

    P = −(Eᵀ M⁻¹ E)⁻¹ Eᵀ Θ̇⁻ and Θ̇⁺ = Θ̇⁻ + M⁻¹ E P (the stopped joints' rates exactly zero), for the set of
    candidates in which every stopped joint's impulse pushes (dᵢ Pᵢ ≤ 0) and every other candidate leaves its
    limit (dᵢ Θ̇⁺ᵢ ≤ 0). A joint leaving more slowly than ``resting`` counts as resting on its limit: it is stopped
    too (by an impulse of at most that rate's size, whichever its sign).

    Parameters
    ----------
    M : numpy.ndarray, shape (n, n) or (K, n, n)
        The mass matrix M(Θ), kg·m² (kg).
    qd : numpy.ndarray, shape (n,) or (K, n)
        Θ̇⁻, rad/s (m/s).
    stopping : numpy.ndarray of bool, shape (n,) or (K, n)
        The joints at a limit, which may be stopped.
    side : numpy.ndarray, shape (n,) or (K, n)
        dᵢ: +1 at an upper limit, −1 at a lower one (0 elsewhere).
    resting : float or numpy.ndarray, shape (n,) or (K, n)
        The rate below which a joint leaving its limit rests on it, rad/s (m/s); default 0.

    Returns
    -------
    qd : numpy.ndarray, shape (n,) or (K, n)
        Θ̇⁺, rad/s (m/s).
    stopped : numpy.ndarray of bool, shape (n,) or (K, n)
        The joints stopped.
    impulse : numpy.ndarray, shape (n,) or (K, n)
        P, N·m·s (N·s), zero for the joints not stopped.
    """
    candidates = np.asarray(stopping, dtype=bool)
    inverse = np.linalg.inv(M)
    resting = np.broadcast_to(resting, qd.shape)
    leaving = np.where(resting > 0, -resting, _round_off(qd))  # a candidate not stopped leaves faster than this
    # the impulse that stops a rate v alone is v / (M⁻¹)ᵢᵢ: a resting joint's may pull that much
    allowed = (_round_off(qd) + resting) / np.diagonal(inverse, axis1=-2, axis2=-1)

    def solve(active):
        impulse = np.where(active, _solve(_masked_system(inverse, active), np.where(active, -qd, 0.0)), 0.0)
        return np.where(active, 0.0, qd + (inverse @ impulse[..., None])[..., 0]), impulse

    def wrong(active, after, impulse):
        return ((active & (side * impulse > allowed)) | (candidates & ~active & (side * after > leaving)))

    stopped, (after, impulse) = _pivot(candidates, solve, wrong)
    return after, stopped, impulse


class StopRun:
    """A fixed-step integration with joint stops: each step taken with the held joints held, each crossing of a
    limit found within its step (to :data:`~course_dynamics.core.compiled.stopping.POSITION_TOLERANCE`), the
    step taken up to it, the joints stopped there, and the rest of the step taken from the new state. The native
    run (:mod:`~course_dynamics.core.compiled.stopping`) takes these steps in C.

    Parameters
    ----------
    model : Model
        The robot.
    run : object
        What gives ``mass_matrix(q)`` and ``bias(q, qd)`` (the evaluator's implementation).
    step : callable
        One integrator step ``step(f, t, q, qd, h) -> (q, qd)`` with ``f(t, q, qd) -> (qdd, …)``.
    free : callable
        ``free(t, q, qd) -> (qdd, tau)``: the unconstrained accelerations, rad/s², and applied torques, N·m.
    driving : callable
        ``driving(t, q, qd) -> tau``: the torques the dynamics is driven by (friction taken off), N·m.
    dt : float
        The run's step, s: a joint leaving its limit at less than its acceleration into it times dt rests on it.
    """

    def __init__(self, model: Model, run, step, free, driving, dt: float):
        self.model, self.run, self.step, self.free, self.driving, self.dt = model, run, step, free, driving, dt
        self.lower, self.upper = limit_bounds(model)
        self.stops: list[Stop] = []

    def side(self, q: np.ndarray) -> np.ndarray:
        """dᵢ for the joints at a limit (+1 upper, −1 lower), 0 for the others.

        Parameters
        ----------
        q : numpy.ndarray, shape (n,) or (K, n)
            Joint positions Θ, rad (m).

        Returns
        -------
        numpy.ndarray, shape (n,) or (K, n)
            +1, −1 or 0.
        """
        return np.where(q >= self.upper, 1, np.where(q <= self.lower, -1, 0))

    def accelerations(self, t, q, qd, held):
        """Θ̈ with the ``held`` joints held, and the applied torques: ``free`` where nothing is held.

        Parameters
        ----------
        t : float
            Time, s.
        q, qd : numpy.ndarray, shape (n,) or (K, n)
            Joint positions, rad (m), and velocities, rad/s (m/s).
        held : numpy.ndarray of bool, shape (n,) or (K, n)
            The joints held.

        Returns
        -------
        qdd : numpy.ndarray, shape (n,) or (K, n)
            Θ̈, rad/s² (m/s²).
        tau : numpy.ndarray, shape (n,) or (K, n)
            The applied torques, N·m (N).
        """
        qdd, tau = self.free(t, q, qd)
        if not held.any():
            return qdd, tau
        constrained = held_accelerations(self.run.mass_matrix(q), self.run.bias(q, qd), self.driving(t, q, qd), held)[0]
        rows = held.any(axis=-1)
        return (np.where(rows[..., None], constrained, qdd) if q.ndim == 2 else constrained), tau

    def release(self, t, q, qd, held):
        """The joints held from (t, Θ, Θ̇) on: of those held until now and those still at a limit, the ones the
        motion pushes into it (:func:`hold`).

        Parameters
        ----------
        t : float
            Time, s.
        q, qd : numpy.ndarray, shape (n,) or (K, n)
            Joint positions, rad (m), and velocities, rad/s (m/s).
        held : numpy.ndarray of bool, shape (n,) or (K, n)
            The joints held until now.

        Returns
        -------
        numpy.ndarray of bool, shape (n,) or (K, n)
            The joints held from now.
        """
        if not (held.any() or (self.side(q) != 0).any()):
            return held
        return self.holding(q, qd, self.driving(t, q, qd), held)[0]

    def holding(self, q, qd, tau, held):
        """:func:`hold` for the joints held until now and those still at a limit (not leaving it).

        Parameters
        ----------
        q, qd : numpy.ndarray, shape (n,) or (K, n)
            Joint positions, rad (m), and velocities, rad/s (m/s).
        tau : numpy.ndarray, shape (n,) or (K, n)
            The driving torques (friction taken off), N·m (N).
        held : numpy.ndarray of bool, shape (n,) or (K, n)
            The joints held until now.

        Returns
        -------
        held : numpy.ndarray of bool, shape (n,) or (K, n)
            The joints held from now.
        qdd : numpy.ndarray, shape (n,) or (K, n)
            Θ̈, rad/s² (m/s²).
        reaction : numpy.ndarray, shape (n,) or (K, n)
            λ, N·m (N).
        """
        side = self.side(q)
        candidates = held | ((side != 0) & (side * qd >= -_round_off(qd)))
        return hold(self.run.mass_matrix(q), self.run.bias(q, qd), tau, candidates, side)

    def contact(self, t, q, qd, held, member):
        """Stop the joints at a limit that run into it (one impulse, :func:`stop_impulse`), hold those pushed into
        it (:func:`hold`), and record the stop.

        Parameters
        ----------
        t : float
            Time, s.
        q, qd : numpy.ndarray, shape (n,)
            One state: joint positions, rad (m), at or beyond the limits they reached, and velocities, rad/s (m/s).
        held : numpy.ndarray of bool, shape (n,)
            The joints held until now.
        member : int or None
            The ensemble member, named in the record.

        Returns
        -------
        q, qd : numpy.ndarray, shape (n,)
            The state after the stop (positions put on the limits).
        held : numpy.ndarray of bool, shape (n,)
            The joints held from now.
        """
        q = np.clip(q, self.lower, self.upper)
        side = self.side(q)
        M, tau = self.run.mass_matrix(q), self.driving(t, q, qd)
        # leaving its limit more slowly than its acceleration into it would bring it back within a step: resting
        resting = self.dt * np.maximum(side * np.linalg.solve(M, tau - self.run.bias(q, qd)), 0.0)
        after, stopped, _ = stop_impulse(M, qd, side != 0, side, resting)
        new = stopped & ~held
        if new.any():
            names = tuple(self.model.joint_names[j] for j in np.flatnonzero(new))
            sides = tuple("upper" if side[j] > 0 else "lower" for j in np.flatnonzero(new))
            self.stops.append(Stop(t=float(t), member=member, joints=names, sides=sides,
                                   limits=tuple(float(q[j]) for j in np.flatnonzero(new)),
                                   kinetic_before=float(0.5 * qd @ M @ qd),
                                   kinetic_after=float(0.5 * after @ M @ after)))
        candidates = (side != 0) & (side * after >= -_round_off(qd))  # not leaving its limit: held if pushed into it
        held = hold(M, self.run.bias(q, after), tau, candidates, side)[0]
        return q, np.where(held, 0.0, after), held

    def beyond(self, q: np.ndarray, watched: np.ndarray) -> np.ndarray:
        """How far each watched joint is beyond its limits (negative inside), rad (m); −inf for the others.

        Parameters
        ----------
        q : numpy.ndarray, shape (n,) or (K, n)
            Joint positions Θ, rad (m).
        watched : numpy.ndarray of bool, shape (n,) or (K, n)
            The joints to measure.

        Returns
        -------
        numpy.ndarray, shape (n,) or (K, n)
            max(Θ − upper, lower − Θ), or −inf.
        """
        return np.where(watched, np.maximum(q - self.upper, self.lower - q), -np.inf)

    def substeps(self, t, q, qd, h, held, member):
        """One step of length h for one state, stopping joints at the limits they reach within it.

        Parameters
        ----------
        t : float
            The step's start, s.
        q, qd : numpy.ndarray, shape (n,)
            The state at its start: joint positions, rad (m), and velocities, rad/s (m/s).
        h : float
            The step, s.
        held : numpy.ndarray of bool, shape (n,)
            The joints held at its start.
        member : int or None
            The ensemble member, named in the records.

        Returns
        -------
        q, qd : numpy.ndarray, shape (n,)
            The state at t + h.
        held : numpy.ndarray of bool, shape (n,)
            The joints held then.
        """
        end = t + h
        for _ in range(MAXIMUM_CONTACTS_PER_STEP):
            def f(time, a, b, held=held):
                return self.accelerations(time, a, b, held)

            q_end, qd_end = self.step(f, t, q, qd, end - t)
            if self.beyond(q_end, ~held).max() <= 0:
                return q_end, qd_end, held
            s, q, qd = self.crossing(f, t, q, qd, end - t, ~held, q_end, qd_end)
            t = t + s
            q, qd, held = self.contact(t, q, qd, held, member)
            if t >= end:
                return q, qd, held
            held = self.release(t, q, qd, held)
        q_end, qd_end = self.step(lambda time, a, b: self.accelerations(time, a, b, held), t, q, qd,
                                  end - t)  # pragma: no cover - more contacts than a step can hold
        return self.contact(end, q_end, qd_end, held, member)  # pragma: no cover

    def crossing(self, f, t, q, qd, h, watched, q_end, qd_end):
        """The first time within (0, h] at which a watched joint reaches its limit, and the state then.

        Found by the Illinois variant of regula falsi on the joints' distance beyond their limits, each
        evaluation one step of the integrator from the step's start; the state returned is at or just beyond the
        limit, by at most :data:`~course_dynamics.core.compiled.stopping.POSITION_TOLERANCE`. A joint that starts
        on its limit and leaves it is bracketed from the first of h/2, h/4, … at which every watched joint is
        inside; one that cannot leave it is a contact at once (s = 0).

        Parameters
        ----------
        f : callable
            The accelerations during the step.
        t : float
            The step's start, s.
        q, qd : numpy.ndarray, shape (n,)
            The state at its start.
        h : float
            The step, s.
        watched : numpy.ndarray of bool, shape (n,)
            The joints not held at the start (inside their limits or on them).
        q_end, qd_end : numpy.ndarray, shape (n,)
            The state after the whole step (some watched joint beyond its limit).

        Returns
        -------
        s : float
            The time after ``t`` of the crossing, s.
        q, qd : numpy.ndarray, shape (n,)
            The state then.
        """
        a, f_a = 0.0, float(self.beyond(q, watched).max())
        for k in range(1, 30 if f_a >= 0 else 0):  # a joint starting on its limit: find where it is inside
            q_a = self.step(f, t, q, qd, h * 0.5 ** k)[0]
            if self.beyond(q_a, watched).max() < 0:
                a, f_a = h * 0.5 ** k, float(self.beyond(q_a, watched).max())
                break
        if f_a >= 0:
            return 0.0, q, qd
        b, f_b, state = h, float(self.beyond(q_end, watched).max()), (q_end, qd_end)
        beyond_b, last = f_b, 0
        for _ in range(200):
            if beyond_b <= POSITION_TOLERANCE or b - a <= 1e-15 * h:
                break
            c = (a * f_b - b * f_a) / (f_b - f_a)
            if not a < c < b:
                c = 0.5 * (a + b)
            q_c, qd_c = self.step(f, t, q, qd, c)
            g_c = float(self.beyond(q_c, watched).max())
            if g_c > 0:
                b, f_b, beyond_b, state = c, g_c, g_c, (q_c, qd_c)
                f_a, last = (0.5 * f_a if last > 0 else f_a), 1
            else:
                a, f_a = c, g_c
                f_b, last = (0.5 * f_b if last < 0 else f_b), -1
        return b, state[0], state[1]



__all__ = ["MAXIMUM_CONTACTS_PER_STEP", "MAXIMUM_PIVOTS", "POSITION_TOLERANCE", "Stop", "StopRun",
           "held_accelerations", "hold", "limit_bounds", "stop_impulse", "stops_recorded"]

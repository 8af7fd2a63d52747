"""Dynamic simulation: integrate Θ̈ = M⁻¹[τ − V − G − F] (6.115) in time.

==================  ==========================================================
integrator          one step of size Δt from (Θ, Θ̇), with Θ̈ = f(t, Θ, Θ̇)
==================  ==========================================================
``euler``           the notes' scheme, exactly (6.116)–(6.117):
                    Θ̇(t+Δt) = Θ̇ + Θ̈ Δt,  Θ(t+Δt) = Θ + Θ̇ Δt + ½ Θ̈ Δt²
``semi-implicit``   Θ̇(t+Δt) = Θ̇ + Θ̈ Δt,  Θ(t+Δt) = Θ + Θ̇(t+Δt) Δt (symplectic)
``rk4``             classical fourth-order Runge–Kutta on (Θ, Θ̇)
``adaptive``        SciPy ``solve_ivp`` (DOP853, rtol = atol = 1e-10), reported
                    on the same time grid
==================  ==========================================================

Dynamics: ``dynamics=None`` uses our forward dynamics, M by composite rigid
bodies and V + G by Newton–Euler, compiled into straight-line code
(:mod:`course_dynamics.core.compiled`) where the cache holds it or the run is long enough
for that to pay off, as the evaluator (:mod:`course_dynamics.core.evaluator`) decides once,
at the start, from the whole run's calls (:data:`CALLS_PER_STEP` a step) and ensemble size —
about 100 Euler steps or 25 RK4 steps of one robot; ``compiled=True``/``False`` forces the choice.
Any :data:`~course_dynamics.core.forward_dynamics.AccelerationFunction` (q, qd, τ) → Θ̈ can take its
place — Pinocchio's ``aba`` in a benchmark. With our dynamics, ``limits="report"``, a fixed-step integrator
and a torque that is zero, constant or a :class:`TorqueTable`, the whole run is native code
(:mod:`course_dynamics.core.compiled.rollout`: the same steps, operation for operation, with the torque,
friction, drives and recording), called once per chunk of steps; the energy and the limit report are
computed from the recorded samples afterwards. Anything else (a torque that is a function of the state,
joint stops, ``adaptive``, a dynamics of one's own, no native library) takes the steps in Python.
Friction, if given, is subtracted from τ before the call (6.114); a fixed step too long for its slope
(:meth:`~course_dynamics.core.friction.Friction.slope`: dt times the largest eigenvalue of M⁻¹ diag(slope) at
the start past :data:`~course_dynamics.tools.simulation.STABLE_STEP`) is warned of, as the velocity would then
oscillate about zero. Drives, if given (:class:`~course_dynamics.core.drives.Drives`), put each rotor's
inertia on M's diagonal and take each torque offset off τ, for the motion, the joint stops and the energy
alike: the energy then holds the rotors' ½ Θ̇ᵀ diag(Iₐ) Θ̇, and an offset does work as an applied torque does
(−τ₀ per radian or metre).

Ensembles: with ``q0`` (and ``qd0``) of shape (K, n), K systems are integrated
at once, each step one batched call; the trajectory's arrays then have shape
(T, K, n) (energy (T, K)). The fixed-step integrators step every member alike;
``adaptive`` integrates the stacked system with one shared step, chosen for
the member that needs the smallest. Under ``limits="stop"`` a member whose
joint reaches a limit within a step takes that step alone (a callable torque
is then called with that member's state, shape (n,)).

Torque input: ``None`` (zero), a constant array (n,), a callable
``tau(t, q, qd) -> (n,)``, or a :class:`TorqueTable` (linear interpolation in
time, held at its first/last row outside its range).

Joint limits (joints whose URDF limits form a non-empty interval):
``limits="report"`` lets the motion continue and records, once per joint, when
it left its limits (in ``Trajectory.events``). ``limits="stop"`` makes each
limit a unilateral constraint (:mod:`course_dynamics.tools.joint_stops`): the
crossing is found within its step, an impulse through M stops the joint there
(the other joints keep their momentum), the joint is held by its reaction
torque while the motion pushes into the limit and let go when the reaction
would pull. Each stop takes kinetic energy and never adds any; it is recorded
with its time, joints and energy (``Trajectory.stops``, and a sentence in
``Trajectory.events``), and the reaction at every sample is
``Trajectory.reaction``. Nothing passes a limit silently.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..base.errors import CourseDynamicsError, CourseDynamicsWarning, StateError
from ..base.resources import check_memory
from ..core.compiled.looped import rollout
from ..core.evaluator import implementation, mass_matrix
from ..core.drives import Driven, Drives
from ..core.dynamics import kinetic_energy
from ..core.forward_dynamics import AccelerationFunction
from ..core.friction import Friction
from ..core.kinematics import potential_energy
from ..core.model import Model
from ..core.state import as_state
from .joint_stops import Stop, StopRun, limit_bounds, stops_recorded

#: The integrators :func:`simulate` offers, by name (the table above).
INTEGRATORS = ("euler", "semi-implicit", "rk4", "adaptive")
ADAPTIVE_CALLS_PER_STEP = 1000  # right-hand-side evaluations per output sample before the adaptive integrator gives up
#: What :func:`simulate` does at a joint limit (``"report"`` it, or ``"stop"`` the joint there).
LIMIT_MODES = ("report", "stop")
#: Samples whose mass matrices :func:`total_energy` holds at once (the memory of M for a long run).
ENERGY_BLOCK = 65536
#: The largest dt · λ at which each fixed-step integrator follows a decay Θ̇' = −λ Θ̇ without growing (the real
#: axis of its stability region: Euler's and the semi-implicit velocity step 2, RK4 about 2.785).
STABLE_STEP = {"euler": 2.0, "semi-implicit": 2.0, "rk4": 2.785}
#: Forward-dynamics calls per step of each integrator (DOP853 takes 12 stages a step, and several steps a sample).
CALLS_PER_STEP = {"euler": 1, "semi-implicit": 1, "rk4": 4, "adaptive": 12}


class SimulationError(CourseDynamicsError):
    """Bad simulation input, or a simulation that cannot go on (non-finite torque or state).

    A :class:`~course_dynamics.base.errors.CourseDynamicsError`, so a ``ValueError`` too.
    """


@dataclass(frozen=True)
class TorqueTable:
    """Applied torques sampled in time: ``t`` (K,), increasing; ``tau`` (K, n).

    Called as ``table(t, q, qd)`` it gives τ at time ``t``, interpolated linearly in time and held at its first or
    last row outside its range (``q`` and ``qd`` are ignored).

    Parameters
    ----------
    t : numpy.ndarray, shape (K,)
        Sample times, s, strictly increasing.
    tau : numpy.ndarray, shape (K, n)
        Applied joint torques τ at those times, N·m (N for a prismatic joint).

    Raises
    ------
    SimulationError
        If the shapes do not match, the times do not increase, or a value is not finite.
    """

    t: np.ndarray
    tau: np.ndarray

    def __post_init__(self):
        t, tau = np.asarray(self.t, dtype=float), np.asarray(self.tau, dtype=float)
        if t.ndim != 1 or tau.ndim != 2 or len(t) != len(tau) or len(t) == 0:
            raise SimulationError(f"a torque table needs t of shape (K,) and tau of shape (K, n), "
                                  f"got {t.shape} and {tau.shape}")
        if np.any(np.diff(t) <= 0):
            raise SimulationError("torque table times must be strictly increasing")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(tau))):
            raise SimulationError("torque table has non-finite values")
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "tau", tau)

    def __call__(self, t: float, q=None, qd=None) -> np.ndarray:
        return np.array([np.interp(t, self.t, column) for column in self.tau.T])


@dataclass(frozen=True)
class Trajectory:
    """A simulated motion, one row per time sample.

    t (T,) s; q, qd, qdd, tau (T, n) in model joint order — (T, K, n) for an
    ensemble of K; energy (T,) or (T, K), J, kinetic (6.71) plus potential
    (6.73); events: limit crossings, in time order.

    Parameters
    ----------
    joints : tuple of str
        The joints' names, in the model's order.
    t : numpy.ndarray, shape (T,)
        Sample times, s.
    q : numpy.ndarray, shape (T, n) or (T, K, n)
        Joint positions Θ, rad (m for a prismatic joint).
    qd : numpy.ndarray, shape (T, n) or (T, K, n)
        Joint velocities Θ̇, rad/s (m/s).
    qdd : numpy.ndarray, shape (T, n) or (T, K, n)
        Joint accelerations Θ̈, rad/s² (m/s²).
    tau : numpy.ndarray, shape (T, n) or (T, K, n)
        Applied joint torques τ, N·m (N for a prismatic joint).
    energy : numpy.ndarray, shape (T,) or (T, K)
        Total energy, kinetic (6.71) plus potential (6.73), J.
    events : tuple of str
        The joint-limit crossings and stops, in time order, as sentences.
    stops : tuple of Stop
        Under ``limits="stop"``: each stop, in time order (when, which joints, the kinetic energy it took).
    reaction : numpy.ndarray, shape (T, n) or (T, K, n), optional
        Under ``limits="stop"``: the held joints' reaction torques λ, N·m (N), zero where a joint is not held.
    """

    joints: tuple[str, ...]
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    tau: np.ndarray
    energy: np.ndarray
    events: tuple[str, ...] = ()
    stops: tuple[Stop, ...] = ()
    reaction: np.ndarray | None = None

    @property
    def members(self) -> int | None:
        """K for an ensemble, None for a single run.

        Returns
        -------
        int or None
            The number of members K, or None.
        """
        return self.q.shape[1] if self.q.ndim == 3 else None

    def table(self) -> tuple[list[str], np.ndarray]:
        """CSV header and rows: t, ``q_<j>``, ``qd_<j>``, ``qdd_<j>``, ``tau_<j>``, energy (and ``member`` after t for
        an ensemble).

        Returns
        -------
        header : list of str
            The column names.
        rows : numpy.ndarray, shape (T, 4 n + 2) or (T K, 4 n + 3)
            One row per sample (per sample and member for an ensemble), in SI units.
        """
        columns = [f"{kind}_{j}" for kind in ("q", "qd", "qdd", "tau") for j in self.joints] + ["energy"]
        if self.members is None:
            return ["t"] + columns, np.column_stack([self.t, self.q, self.qd, self.qdd, self.tau, self.energy])
        T, K = len(self.t), self.members
        flat = [a.reshape(T * K, -1) for a in (self.q, self.qd, self.qdd, self.tau)]
        return ["t", "member"] + columns, np.column_stack([np.repeat(self.t, K), np.tile(np.arange(K), T), *flat,
                                                           self.energy.reshape(-1)])


def total_energy(model: Model, q, qd, drives: Drives | None = None, run=None) -> np.ndarray:
    """k + u (6.71), (6.73), J, and the rotors' kinetic energy with ``drives``; shape () or (N,).

    Parameters
    ----------
    model : Model
        The robot.
    q : numpy.ndarray, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint).
    qd : numpy.ndarray, shape (n,) or (N, n)
        Joint velocities Θ̇, rad/s (m/s).
    drives : Drives, optional
        Adds ½ Θ̇ᵀ diag(Iₐ) Θ̇, the rotors' kinetic energy.
    run : object, optional
        What gives M for k = ½ Θ̇ᵀ M Θ̇ (an implementation from
        :func:`~course_dynamics.core.evaluator.implementation`, as a simulation's own); by default the
        evaluator's choice for these states.

    Returns
    -------
    float or numpy.ndarray, shape (N,)
        Kinetic plus potential energy, J. A sympy expression for a symbolic state.

    Raises
    ------
    StateError
        If ``q`` or ``qd`` is not a finite array of shape (n,) or (N, n).
    """
    rotors = 0.0 if drives is None else drives.kinetic_energy(qd)
    q, qd = as_state(model, q, "q"), as_state(model, qd, "qd")
    if q.dtype == object or qd.dtype == object:
        kinetic = kinetic_energy(model, q, qd)
    else:  # (6.71) with M as the evaluator gives it (natively for a simulation's samples), a block at a time
        q_all, qd_all = np.broadcast_arrays(q, qd)
        flat_q, flat_qd = q_all.reshape(-1, model.n), qd_all.reshape(-1, model.n)
        kinetic = np.empty(len(flat_q))
        for s in range(0, len(flat_q), ENERGY_BLOCK):
            part = slice(s, s + ENERGY_BLOCK)
            M = mass_matrix(model, flat_q[part]) if run is None else run.mass_matrix(flat_q[part])
            kinetic[part] = 0.5 * np.einsum("ki,kij,kj->k", flat_qd[part], M, flat_qd[part])
        kinetic = kinetic.reshape(q_all.shape[:-1])
    return kinetic + potential_energy(model, q) + rotors


def torque_function(model: Model, torque) -> Callable:
    """τ(t, q, qd) from any accepted torque input (see module docstring)."""
    if torque is None:
        zero = np.zeros(model.n)
        return lambda t, q, qd: zero
    if callable(torque):
        return torque
    constant = as_state(model, torque, "torque")
    if constant.ndim != 1:
        raise SimulationError(f"a constant torque must have shape ({model.n},), got {constant.shape}")
    return lambda t, q, qd: constant


def time_grid(duration: float, dt: float, values_per_sample: int = 1,
              advice: str = ": take a larger dt or a shorter duration") -> np.ndarray:
    """t = 0, dt, 2 dt, …, duration (s): the samples of a run; the last step is shortened to end at ``duration``.

    Raises SimulationError for a dt or duration that is not a positive finite number, and for a
    grid whose samples (``values_per_sample`` floats each) would not fit in
    :func:`~course_dynamics.base.resources.memory_budget`
    (the message ends with ``advice``: an ensemble's caller names its size too).

    Parameters
    ----------
    duration : float
        The run's length, s.
    dt : float
        The sample step, s.
    values_per_sample : int
        How many floats each sample will hold, for the memory check.
    advice : str
        What the memory refusal ends with.

    Returns
    -------
    numpy.ndarray, shape (T,)
        The sample times, s, from 0 to ``duration``.

    Raises
    ------
    SimulationError
        If ``dt`` or ``duration`` is not a positive finite number, ``dt`` exceeds ``duration``, or the samples
        would not fit in the memory budget.
    """
    for name, value in (("dt", dt), ("duration", duration)):
        if not (np.isfinite(value) and value > 0):
            raise SimulationError(f"{name} must be a positive number of seconds, got {value}")
    if dt > duration:
        raise SimulationError(f"dt = {dt:g} s is longer than the duration {duration:g} s")
    steps = duration / dt
    check_memory((steps + 1) * 8.0 * max(values_per_sample, 1),
                 f"{duration:g} s in steps of {dt:g} s is {steps:.3g} steps; keeping them",
                 advice, SimulationError)
    times = np.arange(int(np.ceil(steps - 1e-9)) + 1) * dt
    times[-1] = duration
    return times


def simulate(model: Model, q0, qd0, duration: float, dt: float, integrator: str = "rk4", torque=None,
             friction: Friction | None = None, limits: str = "report", progress: Callable[[int], None] | None = None,
             dynamics: AccelerationFunction | None = None, compiled: bool | None = None,
             drives: Drives | None = None) -> Trajectory:
    """Integrate the robot's motion from (Θ₀, Θ̇₀) for ``duration`` seconds in steps of ``dt``.

    ``q0``, ``qd0``: shape (n,), or (K, n) for an ensemble (``qd0`` of shape (n,) is shared).
    Returns the :class:`Trajectory` at the samples of :func:`time_grid`.
    ``progress``, if given, is called with the number of steps just completed.
    ``dynamics`` replaces our forward dynamics; ``compiled`` chooses whether ours is compiled
    (default: as the evaluator chooses for the whole run; module docstring).

    Parameters
    ----------
    model : Model
        The robot.
    q0 : numpy.ndarray, shape (n,) or (K, n)
        Initial joint positions Θ₀, rad (m for a prismatic joint); (K, n) for an ensemble of K.
    qd0 : numpy.ndarray, shape (n,) or (K, n)
        Initial joint velocities Θ̇₀, rad/s (m/s); shape (n,) is shared by every member.
    duration : float
        How long to simulate, s.
    dt : float
        The step, s (also the sample step of the result).
    integrator : str
        One of :data:`INTEGRATORS`.
    torque : None, array_like of shape (n,), callable or TorqueTable
        The applied torques τ, N·m (N for a prismatic joint): zero, constant, ``tau(t, q, qd)``, or sampled.
    friction : Friction, optional
        Joint friction, subtracted from τ before the dynamics (6.114).
    limits : str
        One of :data:`LIMIT_MODES`.
    progress : callable, optional
        Called with the number of steps just completed.
    dynamics : callable, optional
        An acceleration function (q, qd, τ) → Θ̈ to use instead of ours.
    compiled : bool, optional
        Whether our forward dynamics is compiled; None lets the evaluator choose.
    drives : Drives, optional
        Rotor inertias on M's diagonal and torque offsets taken off τ (module docstring).

    Returns
    -------
    Trajectory
        The motion at the samples of :func:`time_grid`.

    Raises
    ------
    SimulationError
        If an input is not accepted (shapes, integrator, limits mode, time grid, torque), or the motion cannot go
        on (a non-finite torque or state, the adaptive integrator failing).
    StateError
        If ``q0`` or ``qd0`` is not a finite array of the model's joint count.
    """
    q0, qd0 = as_state(model, q0, "q0"), as_state(model, qd0, "qd0")
    if q0.ndim > 2 or qd0.ndim > 2 or (qd0.ndim == 2 and qd0.shape != q0.shape):
        raise SimulationError(f"q0 and qd0 must have shape (n,) or (K, n) alike, got {q0.shape} and {qd0.shape}")
    q0, qd0 = np.broadcast_arrays(q0, qd0)
    q0, qd0 = q0.copy(), qd0.copy()
    members = q0.shape[0] if q0.ndim == 2 else 1
    times = time_grid(duration, dt, values_per_sample=members * (4 * model.n + 1) + 1)  # t; q, qd, qdd, tau, energy
    if integrator not in INTEGRATORS:
        raise SimulationError(f"unknown integrator '{integrator}' (choose from {', '.join(INTEGRATORS)})")
    if limits not in LIMIT_MODES:
        raise SimulationError(f"unknown limits mode '{limits}' (choose from {', '.join(LIMIT_MODES)})")
    if integrator == "adaptive" and limits == "stop":
        raise SimulationError("limits='stop' needs a fixed-step integrator (euler, semi-implicit or rk4)")
    if limits == "stop":
        _check_within_limits(model, q0)
        if dynamics is not None:
            raise SimulationError("limits='stop' holds joints through our mass matrix and bias: it cannot be "
                                  "combined with a dynamics function of your own (use limits='report')")
    if drives is not None and dynamics is not None:
        raise SimulationError("drives are added to our mass matrix and bias: they cannot be combined with a "
                              "dynamics function of your own (add them in it)")
    tau_of = torque_function(model, torque)
    run = base = None
    if dynamics is None:
        base = implementation(model, calls=(len(times) - 1) * CALLS_PER_STEP[integrator], states=members,
                              compiled=compiled)
        run = base if drives is None else Driven(base, drives)
        dynamics = run.accelerations
    solve_accelerations = dynamics

    if friction is not None and integrator in STABLE_STEP:
        _warn_if_too_steep(model, run, friction, q0, dt, integrator)
    constant = None if callable(torque) else tau_of(0.0, q0, qd0)  # checked once: None or an array (n,)

    def applied(t, q, qd):
        if constant is not None:
            return constant if q.ndim == 1 else np.broadcast_to(constant, q.shape)
        tau = np.asarray(tau_of(t, q, qd), dtype=float)
        if tau.shape not in ((model.n,), q.shape) or not np.all(np.isfinite(tau)):
            raise _torque_refused(t, tau, model.n, q.shape)
        return np.broadcast_to(tau, q.shape)

    def driving_torques(t, q, qd):
        tau = applied(t, q, qd)
        return tau if friction is None else tau - friction.torques(qd)  # (6.114)

    def accelerations(t, q, qd):
        if not (_finite(q) and _finite(qd)):
            raise _non_finite(t)
        tau = applied(t, q, qd)
        driving = tau if friction is None else tau - friction.torques(qd)  # (6.114)
        try:
            qdd = solve_accelerations(q, qd, driving)
        except StateError:  # our terms overflowed at a finite state
            qdd = np.full(q.shape, np.nan)
        if not _finite(qdd):  # the next state would not be
            raise _non_finite(t)
        return qdd, tau

    native = None
    if base is not None and integrator in _STEPS and (table := _table(model, torque, constant)) is not None:
        bounds = (*limit_bounds(model), dt) if limits == "stop" else None
        native = _native_run(base, run, times, q0, qd0, integrator, table, friction, drives, progress, bounds)
    if native is not None:  # the whole run in native code: Θ̈ and τ (and λ) recorded at every sample
        q, qd, qdd, tau = native.q, native.qd, native.qdd, native.tau
        energy = total_energy(model, q, qd, drives, base)
        if limits == "report":
            return Trajectory(joints=model.joint_names, t=times, q=q, qd=qd, qdd=qdd, tau=tau, energy=energy,
                              events=_limit_events(model, times, q))
        found = stops_recorded(model, native.stops, ensemble=q0.ndim == 2)
        return Trajectory(joints=model.joint_names, t=times, q=q, qd=qd, qdd=qdd, tau=tau, energy=energy,
                          events=tuple(stop.sentence() for stop in found), stops=found, reaction=native.reaction)
    if limits == "stop":
        stops = StopRun(model, run, _STEPS[integrator], accelerations, driving_torques, dt)
        q, qd, held = _integrate_with_stops(stops, times, q0, qd0, progress)
    elif integrator == "adaptive":
        q, qd = _integrate_adaptive(model, accelerations, times, q0, qd0, progress)
    else:
        q, qd = _integrate_fixed(_STEPS[integrator], accelerations, times, q0, qd0, progress)
    # Θ̈ and τ at every sample: the torques one by one (they may depend on t), the dynamics in one batched call.
    if not (np.all(np.isfinite(q)) and np.all(np.isfinite(qd))):
        k = int(np.argmax(~np.all(np.isfinite(np.concatenate([q, qd], axis=-1)).reshape(len(times), -1), axis=1)))
        raise _non_finite(times[k])
    tau = np.array([applied(t, q[k], qd[k]) for k, t in enumerate(times)])
    driving = tau if friction is None else tau - friction.torques(qd)  # (6.114)
    qdd = solve_accelerations(q, qd, driving)
    if limits != "stop":
        return Trajectory(joints=model.joint_names, t=times, q=q, qd=qd, qdd=qdd, tau=tau,
                          energy=total_energy(model, q, qd, drives, base), events=_limit_events(model, times, q))
    reaction = np.zeros_like(qdd)
    rows = (held | (stops.side(q) != 0)).any(axis=-1)
    if rows.any():  # the held joints' accelerations and reactions, as each step began
        _, qdd[rows], reaction[rows] = stops.holding(q[rows], qd[rows], driving[rows], held[rows])
    found = tuple(sorted(stops.stops, key=lambda stop: (stop.t, stop.member or 0)))
    return Trajectory(joints=model.joint_names, t=times, q=q, qd=qd, qdd=qdd, tau=tau,
                      energy=total_energy(model, q, qd, drives, base), events=tuple(stop.sentence() for stop in found),
                      stops=found, reaction=reaction)


def _warn_if_too_steep(model: Model, run, friction: Friction, q0: np.ndarray, dt: float, integrator: str) -> None:
    """Warn where the friction's slope is too steep for the step at the start: the largest λ of M⁻¹ diag(slope)
    (the friction linearised about Θ̇ = 0) times dt past :data:`STABLE_STEP`, where the velocity would
    oscillate about zero from step to step and the motion depend on round-off."""
    slope = friction.slope()
    if not np.any(slope > 0):
        return
    M = run.mass_matrix(q0) if run is not None else mass_matrix(model, q0)
    root = np.sqrt(slope)
    try:
        inverse = np.linalg.inv(M).reshape(-1, model.n, model.n)
        decays = np.linalg.eigvalsh(root[:, None] * inverse * root).max(axis=-1)  # D^½ M⁻¹ D^½, as M⁻¹ D
    except np.linalg.LinAlgError:
        return  # a singular M is the run's own error to report
    member = int(np.argmax(decays))
    if not dt * decays[member] > STABLE_STEP[integrator]:
        return
    j = int(np.argmax(slope * inverse[member].diagonal()))
    limit = STABLE_STEP[integrator] / decays[member]
    unit = 10.0 ** (math.floor(math.log10(limit)) - 1)
    shown = math.floor(limit / unit) * unit  # two digits, rounded down: a step below it is below the limit
    where = f"member {member}'s joint" if q0.ndim == 2 else "joint"
    warnings.warn(f"simulate: the friction is too steep for dt = {dt:g} s with integrator '{integrator}': {where} "
                  f"'{model.joint_names[j]}' (v + c / smoothing = {slope[j]:.3g}) needs dt below {shown:.2g} s, "
                  "or its velocity oscillates about zero from step to step and the motion depends on round-off; "
                  "take a smaller dt, a larger smoothing (the CLI's --friction-width) or the adaptive integrator",
                  CourseDynamicsWarning, stacklevel=3)


def _table(model: Model, torque, constant) -> tuple[np.ndarray, np.ndarray] | None:
    """The applied torque as rows of a table in time, (t (R,), τ (R, n)), for a native run: zero, a constant
    and a :class:`TorqueTable` are; a function of the state is not (None), nor a table of another width (the
    checked path names it)."""
    if constant is not None:
        return np.zeros(1), np.asarray(constant, dtype=float)[None, :]
    if isinstance(torque, TorqueTable) and torque.tau.shape[1] == model.n:
        return torque.t, torque.tau
    return None


def _native_run(base, run, times, q0, qd0, integrator, table, friction, drives, progress, bounds):
    """The run in native code (:func:`~course_dynamics.core.compiled.looped.rollout`; with joint stops where
    ``bounds`` gives their limits and dt), or None where it cannot be (then the steps run in Python). A state that
    became non-finite, or a torque, is refused as the Python steps refuse it; a singular mass matrix is named by
    the checked solve, which raises."""
    done = rollout(base, times, q0, qd0, integrator, *table, friction, drives, progress, bounds)
    if done is None or not done.failure:
        return done
    if done.failure == "not finite":
        raise _non_finite(done.t)
    if done.failure == "torque not finite":
        raise _torque_refused(done.t, done.state[2], run.model.n, q0.shape)
    run.accelerations(*done.state)  # raises SingularMassMatrixError, naming the joint
    return None  # the checked solve accepts what the native pivots did not: the Python steps decide


def _non_finite(t: float) -> SimulationError:
    """The error for a state, or the accelerations from it, that stopped being finite near time t."""
    return SimulationError(f"the state became non-finite near t = {t:.6g} s (try a smaller dt)")


def _torque_refused(t: float, tau: np.ndarray, n: int, shape: tuple) -> SimulationError:
    """The error for an applied torque at time t that is not n finite values (nor one per member, shape (K, n))."""
    shown = tau.tolist() if tau.size <= 3 * n else f"an array of shape {tau.shape}"
    return SimulationError(f"the torque at t = {t:.6g} s is {shown}: expected {n} finite values"
                           + (f" (or shape {shape})" if len(shape) == 2 else ""))


def _check_within_limits(model: Model, q0: np.ndarray) -> None:
    """Under limits='stop' a motion starts within the limits (a start beyond one would be moved, silently)."""
    lower, upper = limit_bounds(model)
    outside = np.argwhere((q0 < lower) | (q0 > upper))
    if len(outside):
        index = tuple(outside[0])
        j = index[-1]
        member = f" (member {index[0]})" if q0.ndim == 2 else ""
        side, bound = ("lower", lower[j]) if q0[index] < lower[j] else ("upper", upper[j])
        digits = next(d for d in range(6, 18) if f"{q0[index]:.{d}g}" != f"{bound:.{d}g}")  # as many as differ
        raise SimulationError(f"q0 for joint '{model.joint_names[j]}' is {q0[index]:.{digits}g}{member}, beyond its "
                              f"{side} limit {bound:.{digits}g}: with limits='stop' the motion must start within "
                              "the limits")


def _integrate_with_stops(stops: StopRun, times, q0, qd0, progress):
    """The fixed-step integration with joint stops: every member stepped alike with its held joints held, and a
    member with a joint crossing a limit within the step stepped alone to the crossing and on (joint_stops)."""
    q, qd = np.empty((len(times),) + q0.shape), np.empty((len(times),) + q0.shape)
    held = np.zeros((len(times),) + q0.shape, dtype=bool)
    q[0], qd[0] = q0, qd0
    for m in [None] if q0.ndim == 1 else range(len(q0)):  # a start on a limit is a contact at t = 0
        at = ... if m is None else m
        if (stops.side(q0[at]) != 0).any():
            q[0][at], qd[0][at], held[0][at] = stops.contact(times[0], q0[at], qd0[at], held[0][at], m)
    for k in range(len(times) - 1):
        t, h = times[k], times[k + 1] - times[k]
        now = stops.release(t, q[k], qd[k], held[k])
        q_next, qd_next = stops.step(lambda time, a, b: stops.accelerations(time, a, b, now), t, q[k], qd[k], h)
        crossed = (stops.beyond(q_next, ~now) > 0).any(axis=-1)
        held[k + 1] = now
        if q0.ndim == 1 and crossed:
            q_next, qd_next, held[k + 1] = stops.substeps(t, q[k], qd[k], h, now, None)
        elif q0.ndim == 2:
            for m in np.flatnonzero(crossed):
                q_next[m], qd_next[m], held[k + 1, m] = stops.substeps(t, q[k, m], qd[k, m], h, now[m], int(m))
        q[k + 1], qd[k + 1] = q_next, qd_next
        if progress is not None:
            progress(1)
    return q, qd, held


def _finite(a: np.ndarray) -> bool:
    """Whether every value is finite; for one state by a sum of Python floats, which is quicker than numpy's check
    (a NaN or an inf makes the sum so, and a sum that merely overflows is checked value by value)."""
    if a.ndim == 1 and math.isfinite(sum(a.tolist())):
        return True
    return bool(np.all(np.isfinite(a)))


def _euler_step(f, t, q, qd, dt):
    qdd = f(t, q, qd)[0]
    qd_next = qd + qdd * dt  # (6.116)
    q_next = q + qd * dt + 0.5 * qdd * dt**2  # (6.117)
    return q_next, qd_next


def _semi_implicit_step(f, t, q, qd, dt):
    qdd = f(t, q, qd)[0]
    qd_next = qd + qdd * dt
    return q + qd_next * dt, qd_next


def _rk4_step(f, t, q, qd, dt):
    a1 = f(t, q, qd)[0]
    q2, qd2 = q + 0.5 * dt * qd, qd + 0.5 * dt * a1
    a2 = f(t + 0.5 * dt, q2, qd2)[0]
    q3, qd3 = q + 0.5 * dt * qd2, qd + 0.5 * dt * a2
    a3 = f(t + 0.5 * dt, q3, qd3)[0]
    q4, qd4 = q + dt * qd3, qd + dt * a3
    a4 = f(t + dt, q4, qd4)[0]
    return q + dt / 6 * (qd + 2 * qd2 + 2 * qd3 + qd4), qd + dt / 6 * (a1 + 2 * a2 + 2 * a3 + a4)


_STEPS = {"euler": _euler_step, "semi-implicit": _semi_implicit_step, "rk4": _rk4_step}


def _integrate_fixed(step, f, times, q0, qd0, progress):
    q, qd = np.empty((len(times),) + q0.shape), np.empty((len(times),) + q0.shape)
    q[0], qd[0] = q0, qd0
    for k in range(len(times) - 1):
        q[k + 1], qd[k + 1] = step(f, times[k], q[k], qd[k], times[k + 1] - times[k])
        if progress is not None:
            progress(1)
    return q, qd


def _integrate_adaptive(model, f, times, q0, qd0, progress):
    from scipy.integrate import (
        solve_ivp,  # SciPy: a well-tested adaptive integrator with error control
    )

    shape, size = q0.shape, q0.size  # an ensemble is one stacked system with a shared step
    reached, calls = [0], [0]
    budget = ADAPTIVE_CALLS_PER_STEP * len(times) + 100_000

    def rhs(t, y):
        calls[0] += 1
        if calls[0] > budget:
            raise SimulationError(f"the adaptive integrator needed more than {budget} evaluations and had reached only "
                                  f"t = {t:.6g} s: the motion is too fast or too stiff for it here; use rk4 with a "
                                  "small dt")
        if progress is not None:
            k = int(np.searchsorted(times, t, side="right")) - 1
            if k > reached[0]:
                progress(k - reached[0])
                reached[0] = k
        q, qd = y[:size].reshape(shape), y[size:].reshape(shape)
        return np.concatenate([y[size:], f(t, q, qd)[0].reshape(-1)])

    solution = solve_ivp(rhs, (times[0], times[-1]), np.concatenate([q0.reshape(-1), qd0.reshape(-1)]),
                         method="DOP853", t_eval=times, rtol=1e-10, atol=1e-10)
    if not solution.success:
        raise SimulationError(f"the adaptive integrator failed: {solution.message}")
    if progress is not None and len(times) - 1 > reached[0]:
        progress(len(times) - 1 - reached[0])
    T = len(times)
    return solution.y[:size].T.reshape((T,) + shape).copy(), solution.y[size:].T.reshape((T,) + shape).copy()


def _limit_events(model: Model, times: np.ndarray, q: np.ndarray) -> tuple[str, ...]:
    """Under limits='report', from the recorded samples: when each joint (of each member) first left its limits,
    in time order (a joint whose limits bound nothing is never reported)."""
    lower, upper = limit_bounds(model)
    outside = (q < lower) | (q > upper)
    if not outside.any():
        return ()
    first = np.argmax(outside, axis=0)  # the first sample outside, per (member,) joint
    found = sorted((int(first[tuple(index)]),) + tuple(index) for index in np.argwhere(outside.any(axis=0)))
    events = []
    for k, *index in found:
        index = tuple(index)
        j, value = index[-1], q[(k,) + index]
        member = f"member {index[0]}: " if q.ndim == 3 else ""
        side, bound = ("lower", lower[j]) if value < lower[j] else ("upper", upper[j])
        events.append(f"t = {times[k]:.6g} s: {member}joint '{model.joint_names[j]}' passed its {side} limit "
                      f"{bound:g} (q = {value:.6g})")
    return tuple(events)


__all__ = ["CALLS_PER_STEP", "ENERGY_BLOCK", "INTEGRATORS", "LIMIT_MODES", "STABLE_STEP", "SimulationError",
           "StateError", "TorqueTable", "Trajectory", "simulate", "time_grid", "total_energy"]

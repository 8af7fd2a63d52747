"""What an excitation costs, estimated before it starts, and its evaluations in batches of bounded memory.

:func:`~course_dynamics.tools.excitation.excitation` asks :func:`cost` before it builds anything: memory beyond
:func:`~course_dynamics.base.resources.memory_budget` is refused in one line (ExcitationError), and the time is
estimated so that the command can say so before a long run. The estimates are the sizes below times costs
measured on the course's robots (2-core machine, NumPy; the per-state costs hold from 2 to 30 joints):

====================  =====================================================================================
quantity              size
====================  =====================================================================================
P                     2 n (H − 1) free coefficients
K_c                   ``CONSTRAINT_POINTS`` H instants where the limits are imposed
                      (:mod:`~course_dynamics.tools.excitation`)
m                     2 K_c (joints with a range + with a velocity limit + with an effort limit) rows of
                      the constraints' Jacobian (m, P), which SLSQP copies into its own work arrays
linear maps           3 (instants + K_c) n P floats: the motion as a linear function of the coefficients
one iteration         a gradient: (P + 1) × instants regressor states; the constraints' Jacobian: (P + 1) K_c
                      inverse-dynamics states; SLSQP's least-squares subproblem, about m P² operations
written samples       4 n + 1 floats each (t, q, q̇, q̈, τ), computed in blocks; about 1 µs a value to write
====================  =====================================================================================

The regressor's dual numbers carry 10 n entries per joint and per state, with work arrays measured at
17–22 times Y's n × 10 n floats (``REGRESSOR_WORK``); a regressor call gets at most ``BATCH_BYTES`` of them,
so the states per call fall as 1/n² (about 2900 at n = 2, 40 at n = 30) and memory stays bounded whatever n.
Inverse dynamics measured 240–270 bytes per state and joint (``INVERSE_DYNAMICS_BYTES``).

Why the harmonics stop at ``HARMONICS_MAX`` = 50: identification excitations use 3–10 harmonics (Swevers et al.
1997 use 5); the optimisation's cost grows with n³ H³ (m P²), a minute an iteration for two joints near 50 and
hours for six, and higher harmonics only add motion at frequencies the joint's limits must already bound.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..base.resources import check_memory, format_bytes
from ..core.evaluator import inverse_dynamics, regressor
from ..base.errors import InputError

#: The most harmonics an excitation may have (the module docstring says why).
HARMONICS_MAX = 50           # see the module docstring
#: The most instants κ is optimised on.
INSTANTS_MAX = 10_000        # instants κ is optimised on
BATCH_BYTES = 64 * 2**20     # work arrays of one regressor or inverse-dynamics call
REGRESSOR_WORK = 24          # the regressor's work per state, in floats per entry of Y (n × 10 n); measured 17-22
INVERSE_DYNAMICS_BYTES = 300  # per state and joint; measured 240-270
JACOBIAN_COPIES = 6          # (m, P) arrays alive at once: A, the torque rows, their stack, SLSQP's copies
REGRESSOR_SECONDS = 1e-5     # per gradient state and n², an iteration's: measured 0.75e-5 to 1.1e-5 (a call 3e-6)
INVERSE_DYNAMICS_SECONDS = 3e-6  # per Jacobian state and joint, an iteration's; a call measured 0.9e-6 to 1.2e-6
SUBPROBLEM_SECONDS = 1.6e-8  # SLSQP, per iteration and m P²; measured 1.1e-8 to 1.6e-8 end to end
WRITE_SECONDS = 2e-6         # per value written as CSV: measured 1e-6 alone, 3.5e-6 with both cores busy
SAMPLE_VALUES = 6            # floats per written sample and joint: q, q̇, q̈, τ kept, two temporaries of the checks
#: A run estimated to take longer than this many seconds is said before it starts.
LONG = 60.0                  # s: a run estimated to take longer is said before it starts


class ExcitationError(InputError):
    """An excitation that cannot be made or does not stay within the limits (the message says which).

    An :class:`~course_dynamics.base.errors.InputError`: one line on the command line.
    """


class Cost(NamedTuple):
    """An excitation's estimated memory (bytes) and seconds: to set up, per iteration, for the samples.

    Parameters
    ----------
    memory : float
        The peak memory, bytes.
    setup : float
        The time to set up, s.
    iteration : float
        The time of one iteration, s.
    samples : float
        The time to compute and write the samples, s.
    iterations : int
        The most iterations the run may take.
    """

    memory: float
    setup: float
    iteration: float
    samples: float
    iterations: int

    @property
    def seconds(self) -> float:
        """The whole run's estimated time, s, at the most iterations."""
        return self.setup + (self.iterations + 1) * self.iteration + self.samples  # + SLSQP's last evaluations

    def describe(self) -> str:
        """'about 25 min (15 s an iteration × 100, 3 s for the samples), 1.2 GiB' for a warning.

        Returns
        -------
        str
            The time and the memory, in words.
        """
        return (f"about {_duration(self.seconds)} ({_duration(self.iteration)} an iteration × {self.iterations}, "
                f"{_duration(self.setup + self.samples)} to set up and write the samples), {format_bytes(self.memory)}")


def _duration(seconds: float) -> str:
    if seconds >= 3600:
        return f"{seconds / 3600:.3g} h"
    return f"{seconds / 60:.3g} min" if seconds >= 60 else f"{seconds:.2g} s"


def states_per_call(n: int, regressor_call: bool = True) -> int:
    """States per regressor (or inverse-dynamics) call so its work arrays stay within ``BATCH_BYTES``."""
    per_state = REGRESSOR_WORK * 8 * n * 10 * n if regressor_call else INVERSE_DYNAMICS_BYTES * n
    return max(1, int(BATCH_BYTES // per_state))


def cost(model, harmonics: int, instants: int, samples: int, max_iterations: int, constraint_points: int,
         fine_points: int) -> Cost:
    """The estimate of the module docstring for ``model``; ExcitationError (one line) beyond the memory budget.

    Parameters
    ----------
    model : Model
        The robot.
    harmonics : int
        H, the harmonics of the Fourier series.
    instants : int
        The instants κ is optimised on.
    samples : int
        The samples to be written.
    max_iterations : int
        The most iterations of the optimisation.
    constraint_points : int
        Instants per harmonic where the limits are imposed.
    fine_points : int
        Instants per harmonic where the result is checked.

    Returns
    -------
    Cost
        The estimated memory and times.

    Raises
    ------
    ExcitationError
        If the memory needed is beyond the budget.
    """
    n = model.n
    P, Kc = 2 * n * (harmonics - 1), constraint_points * harmonics
    ranged = np.isfinite(model.lower) & np.isfinite(model.upper)
    limited = int(ranged.sum() + np.isfinite(model.velocity).sum() + np.isfinite(model.effort).sum())
    m = 2 * Kc * limited
    fine = fine_points * harmonics
    kept = 3 * (instants + Kc) * n * P + JACOBIAN_COPIES * m * P + (SAMPLE_VALUES * n + 1) * samples  # floats
    memory = 8.0 * kept + 2 * BATCH_BYTES
    regressor_state, dynamics_state = REGRESSOR_SECONDS * n * n, INVERSE_DYNAMICS_SECONDS * n
    iteration = (P + 1) * (instants * regressor_state + Kc * dynamics_state) + SUBPROBLEM_SECONDS * m * P * P
    setup = 40 * Kc * dynamics_state + 2 * fine * regressor_state
    written = samples * (INVERSE_DYNAMICS_SECONDS * n / 3 + WRITE_SECONDS * (4 * n + 1))
    estimate = Cost(memory, setup, iteration, written, max_iterations)
    check_memory(memory, f"an excitation of robot '{model.name}' ({n} joints, {harmonics} harmonics, {instants} "
                 f"instants, {samples} written samples)", ": take fewer harmonics or instants, or a larger dt",
                 ExcitationError)
    return estimate


def _is_integer(value) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


def check_options(duration, harmonics, instants, max_iterations, margin) -> None:
    """ExcitationError (one line) for an option no excitation can have, before anything is computed.

    Parameters
    ----------
    duration : float
        The excitation's period, s; positive.
    harmonics : int
        From 2 to :data:`HARMONICS_MAX`.
    instants : int
        From 1 to :data:`INSTANTS_MAX`.
    max_iterations : int
        At least 0.
    margin : float
        The share of each limit kept free, 0 ≤ margin < 1.

    Raises
    ------
    ExcitationError
        If an option is out of its range.
    """
    if not (np.isfinite(duration) and duration > 0):
        raise ExcitationError(f"the duration must be a positive number of seconds, got {duration}")
    if not (_is_integer(harmonics) and 2 <= harmonics <= HARMONICS_MAX):
        raise ExcitationError(f"the harmonics must be a whole number of at least 2 (starting at rest fixes the first) "
                              f"and at most {HARMONICS_MAX} (identification uses 3-10; the cost grows as n³ H³), "
                              f"got {harmonics}")
    if not (_is_integer(instants) and 1 <= instants <= INSTANTS_MAX):
        raise ExcitationError(f"the instants the condition is optimised at must be a whole number up to "
                              f"{INSTANTS_MAX}, got {instants}")
    if not (_is_integer(max_iterations) and max_iterations >= 0):
        raise ExcitationError(f"the iterations must be a non-negative integer, got {max_iterations}")
    if not (np.isfinite(margin) and 0 <= margin < 1):
        raise ExcitationError(f"the margin must be at least 0 and less than 1, got {margin}")


def motion_samples(model, motion, t: np.ndarray):
    """(q, q̇, q̈, τ) of ``motion`` (a Fourier) at times t, (K, n) each, a block of samples at a time: only the
    results are kept whole, not the sines, cosines and the recursion's work arrays of every sample."""
    q, qd, qdd, tau = (np.empty((len(t), model.n)) for _ in range(4))
    step = states_per_call(model.n, regressor_call=False)
    for start in range(0, len(t), step):
        block = slice(start, start + step)
        q[block], qd[block], qdd[block] = motion(t[block])
        tau[block] = torques(model, q[block], qd[block], qdd[block])
    return q, qd, qdd, tau


def gram(model, base, q, qd, qdd, tick=None) -> np.ndarray:
    """Y_bᵀ Y_b of each motion (m, K, n) → (m, r, r), at most :func:`states_per_call` states per regressor call."""
    count, K, n = q.shape
    step = states_per_call(n)
    G = np.zeros((count, base.rank, base.rank))
    rows = max(1, step // K)
    for first in range(0, count, rows):
        chunk = slice(first, first + rows)
        for start in range(0, K, step):
            part = [v[chunk, start:start + step] for v in (q, qd, qdd)]
            Y = base.regressor(regressor(model, *(v.reshape(-1, n) for v in part)))
            Y = Y.reshape(len(part[0]), -1, base.rank)
            G[chunk] += np.swapaxes(Y, 1, 2) @ Y
            if tick is not None:
                tick(part[0].shape[0] * part[0].shape[1])
    return G


def kappa_of_gram(G: np.ndarray) -> np.ndarray:
    """κ of each stacked regressor from its Gram matrix (m, r, r), columns scaled to unit norm; inf where a
    column vanishes. κ² = λ_max/λ_min, good to 1e-16 κ² (relative)."""
    norms = np.sqrt(np.maximum(np.diagonal(G, axis1=1, axis2=2), 0.0))
    scale = np.where(norms > 0, norms, 1.0)
    unit = G / scale[:, :, None] / scale[:, None, :]
    eigenvalues = np.linalg.eigvalsh(unit)
    with np.errstate(divide="ignore", invalid="ignore"):
        kappa = np.sqrt(eigenvalues[:, -1] / np.where(eigenvalues[:, 0] > 0, eigenvalues[:, 0], 0.0))
    return np.where((norms.min(axis=1) > 0) & np.isfinite(kappa), kappa, np.inf)


def torques(model, q, qd, qdd, tick=None) -> np.ndarray:
    """Our inverse dynamics of states (..., n), at most :func:`states_per_call` states per call."""
    shape = q.shape
    q, qd, qdd = (v.reshape(-1, shape[-1]) for v in (q, qd, qdd))
    tau = np.empty_like(q)
    step = states_per_call(shape[-1], regressor_call=False)
    for start in range(0, len(q), step):
        tau[start:start + step] = inverse_dynamics(model, q[start:start + step], qd[start:start + step],
                                                   qdd[start:start + step])
        if tick is not None:
            tick(len(tau[start:start + step]))
    return tau.reshape(shape)


__all__ = ["HARMONICS_MAX", "INSTANTS_MAX", "LONG", "Cost", "ExcitationError", "check_options", "cost"]

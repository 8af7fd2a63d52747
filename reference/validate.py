"""Ours against Pinocchio on seeded random states: the agreement report.

States and the error measure are the library's own (:mod:`course_dynamics.core.sampling`):
‖ours − Pinocchio‖∞ / max(‖Pinocchio‖∞, s), with s the scale each term is built
at. The report keeps, per term, the largest absolute and relative error over
the samples; a robot agrees when every relative error is at most the tolerance.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from course_dynamics import (
    coriolis_matrix,
    gravity_torques,
    inverse_dynamics,
    load_urdf,
    mass_matrix,
    velocity_torques,
)
from course_dynamics.core.robots import resolve
from course_dynamics.core.sampling import (
    random_states,
    relative_error,
    sampling_bounds,
    term_scales,
)

from . import TERMS, TOLERANCE
from .pinocchio_oracle import PinocchioOracle


def ours_batch(model, q, qd, qdd) -> dict[str, np.ndarray]:
    """Every term for a batch of states, from course_dynamics (vectorised)."""
    return dict(
        tau=inverse_dynamics(model, q, qd, qdd), M=mass_matrix(model, q), C=coriolis_matrix(model, q, qd),
        V=velocity_torques(model, q, qd), G=gravity_torques(model, q),
    )


@dataclass
class TermAgreement:
    max_abs: float = 0.0
    max_rel: float = 0.0


@dataclass
class RobotReport:
    """Agreement of one robot: per-term worst errors over the samples."""

    robot: str
    urdf: str
    joints: list[str]
    samples: int
    seed: int
    tolerance: float
    terms: dict[str, TermAgreement] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return all(t.max_rel <= self.tolerance for t in self.terms.values())

    def as_dict(self) -> dict:
        return dict(asdict(self), ok=self.ok)


def term_errors(model, oracle: PinocchioOracle, q, qd, qdd, progress=None) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Per term, the absolute and the relative error of every state (arrays of shape (N,)), ours against Pinocchio.

    Ours are computed a block of :func:`block_states` states at a time, so the n × n terms held at once are the
    block's, whatever N is; each state's figures are the same as in one batch. ``progress``, if given, is called with
    the number of states just finished.
    """
    absolute = {t: np.empty(len(q)) for t in TERMS}
    relative = {t: np.empty(len(q)) for t in TERMS}
    step = block_states(model.n)
    for start in range(0, len(q), step):
        ours = ours_batch(model, q[start:start + step], qd[start:start + step], qdd[start:start + step])
        for i in range(len(ours["tau"])):
            k = start + i
            ref = oracle.terms(q[k], qd[k], qdd[k])
            scales = term_scales(ref["M"], ref["G"], qd[k], qdd[k], model.gravity)
            for term in TERMS:
                absolute[term][k] = float(np.abs(ours[term][i] - ref[term]).max())
                relative[term][k] = relative_error(ours[term][i], ref[term], scales[term])
            if progress is not None:
                progress(1)
    return {t: (absolute[t], relative[t]) for t in TERMS}


def validate(name_or_path: str, samples: int = 200, seed: int = 0, tolerance: float = TOLERANCE, progress=None,
             gravity=None, allow_nonphysical_inertia: bool = False) -> RobotReport:
    """Compare τ, M, C, V, G of course_dynamics and Pinocchio on seeded random states.

    ``progress``, if given, is called with the number of samples just finished; ``gravity``
    (3,) m/s² replaces the standard one on both sides.
    """
    urdf = resolve(name_or_path)
    model = load_urdf(urdf, allow_nonphysical_inertia=allow_nonphysical_inertia,
                      **({} if gravity is None else {"gravity": gravity}))
    oracle = PinocchioOracle(urdf, model.joint_names, model.gravity)
    errors = term_errors(model, oracle, *random_states(model, samples, seed), progress=progress)
    return RobotReport(
        robot=model.name, urdf=str(urdf), joints=list(model.joint_names), samples=samples, seed=seed,
        tolerance=tolerance,
        terms={t: TermAgreement(float(a.max()), float(r.max())) for t, (a, r) in errors.items()},
    )


BYTES_PER_CUBED_JOINT = 70  # measured: a validate of an n-joint chain peaks near 70 n³ bytes (4.3 GB at n = 400)
BYTES_PER_STATE_SQUARE = 32  # measured: ours for a batch of states peaks near 31 n² bytes a state (M, C, their work)
BLOCK_BYTES = 128 * 2**20    # ours are computed for at most this much at a time
BYTES_PER_STATE = 48         # a state's Θ, Θ̇, Θ̈ (8 n bytes each, times two while drawn) per joint, and
BYTES_PER_STATE_ERRORS = 160  # its absolute and relative errors of the five terms


def block_states(n: int) -> int:
    """States whose terms (ours) are computed at once for an n-joint robot: :data:`BLOCK_BYTES` worth, at least one."""
    return max(1, BLOCK_BYTES // (BYTES_PER_STATE_SQUARE * n * n))


def memory_estimate(n: int, samples: int = 0) -> float:
    """Bytes a comparison of an n-joint robot on ``samples`` states needs at its peak (Pinocchio's data and ours, a
    measured fit; the states and their errors; one block of ours)."""
    states = float(samples) * (BYTES_PER_STATE * n + BYTES_PER_STATE_ERRORS)
    block = min(samples, block_states(n)) * BYTES_PER_STATE_SQUARE * float(n) ** 2
    return 0.3 * 2**30 + BYTES_PER_CUBED_JOINT * float(n) ** 3 + states + block


def check_comparison_memory(model, samples: int) -> None:
    """InputError in one line, before any work, when comparing ``model`` on ``samples`` states would not fit in
    memory: naming ``--samples`` and how many fit when the states are what is too many."""
    from course_dynamics.base.resources import check_memory, memory_budget

    what = f"robot '{model.name}' has {model.n} joints: comparing it with Pinocchio on --samples {samples} states"
    spare = memory_budget() - memory_estimate(model.n, 1)
    if spare >= 0:
        fit = 1 + int(spare // (BYTES_PER_STATE * model.n + BYTES_PER_STATE_ERRORS))
        check_memory(memory_estimate(model.n, samples), what, f": take fewer --samples (about {fit} fit)")
    check_memory(memory_estimate(model.n, samples), what, " ('terms' computes one state of it with our library alone)")


def bundled_targets() -> list[str]:
    """Every shipped robot, by name (see :mod:`course_dynamics.core.robots`)."""
    from course_dynamics.core.robots import robot_names

    return list(robot_names())


def display_name(name_or_path: str) -> str:
    return name_or_path if not Path(name_or_path).suffix else Path(name_or_path).name


__all__ = ["RobotReport", "TermAgreement", "block_states", "bundled_targets", "check_comparison_memory", "display_name",
           "ours_batch", "random_states", "memory_estimate", "sampling_bounds", "term_errors", "validate"]

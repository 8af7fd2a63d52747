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

    ``progress``, if given, is called with the number of states just finished.
    """
    ours = ours_batch(model, q, qd, qdd)
    absolute = {t: np.empty(len(q)) for t in TERMS}
    relative = {t: np.empty(len(q)) for t in TERMS}
    for k in range(len(q)):
        ref = oracle.terms(q[k], qd[k], qdd[k])
        scales = term_scales(ref["M"], ref["G"], qd[k], qdd[k], model.gravity)
        for term in TERMS:
            absolute[term][k] = float(np.abs(ours[term][k] - ref[term]).max())
            relative[term][k] = relative_error(ours[term][k], ref[term], scales[term])
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


def memory_estimate(n: int) -> float:
    """Bytes a comparison of an n-joint robot needs at its peak (Pinocchio's data and ours), a measured fit."""
    return 0.3 * 2**30 + BYTES_PER_CUBED_JOINT * float(n) ** 3


def bundled_targets() -> list[str]:
    """Every shipped robot, by name (see :mod:`course_dynamics.core.robots`)."""
    from course_dynamics.core.robots import robot_names

    return list(robot_names())


def display_name(name_or_path: str) -> str:
    return name_or_path if not Path(name_or_path).suffix else Path(name_or_path).name


__all__ = ["RobotReport", "TermAgreement", "bundled_targets", "display_name", "ours_batch", "random_states",
           "memory_estimate", "sampling_bounds", "term_errors", "validate"]

"""Robot logs with collisions in them, generated from a known motion and a known external wrench.

The motion is the multi-sine of ``logmakers`` evaluated on a jittering clock (each stamp up to ±0.2 ms off
its 250 Hz tick, as a controller's clock is); the robot has joint friction (:data:`FRICTION`); a contact
pushes with force :data:`PUSH` N (on the robot, base coordinates) at ``tool0`` for each (start, length) of
``pulses``, so τ_ext = Jᵀ F and the measured torques are τ_m = M Θ̈ + V + G + F(Θ̇) − τ_ext. The recorder
adds white noise of the stated σ to Θ, Θ̇ and τ_m.

:func:`reversal_log` is a second recorder's: one sine per joint, so that every joint reverses about twice a second,
at 500 Hz, with Coulomb friction and noise in proportion to each joint's torque (little on the wrist), as an
independent generator built on Pinocchio wrote it; with the friction known it has no contact to find.

``python tests/collisionlogs.py`` writes ``examples/ur5_collision.csv`` again (``tests/test_collisions.py`` checks
the committed file is what :func:`write_example` writes today).
"""
from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from logmakers import BASE_HZ, HARMONICS, noisy, write_csv  # noqa: E402

from course_dynamics import load_robot  # noqa: E402
from course_dynamics.core.cartesian import jacobian  # noqa: E402
from course_dynamics.core.friction import Friction  # noqa: E402
from course_dynamics.core.newton_euler import inverse_dynamics  # noqa: E402
from course_dynamics.core.sampling import sampling_bounds  # noqa: E402

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "ur5_collision.csv"
RATE = 250.0                                                   # Hz, as UR's RTDE
JITTER = 2e-4                                                  # s: the clock's stamps off their ticks, at most
PUSH = (30.0, -20.0, 40.0)                                     # N on the robot at tool0, base coordinates
LINK = "tool0"
FRICTION = Friction(viscous=[2.0, 2.0, 1.0, 0.5, 0.5, 0.5], coulomb=[3.0, 3.0, 2.0, 1.0, 1.0, 1.0], smoothing=0.01)
SIGMA_Q, SIGMA_QD, SIGMA_TAU = 2e-5, 2e-3, 0.2                # rad, rad/s, N m: the recorder's noise


@dataclass(frozen=True)
class CollisionLog:
    """A log's samples: ``t`` (K,), the recorded ``q``, ``qd``, ``tau`` (τ_m) and the true ``tau_ext`` (K, n)."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    tau: np.ndarray
    tau_ext: np.ndarray
    exact_q: np.ndarray
    exact_qd: np.ndarray


def motion_at(model, t, seed=0):
    """Θ, Θ̇, Θ̈ of ``logmakers.multisine``'s motion at any times ``t`` (K,)."""
    rng = np.random.default_rng(seed)
    lower, upper = sampling_bounds(model)
    centre, half = (lower + upper) / 2, (upper - lower) / 2
    q, qd, qdd = (np.zeros((len(t), model.n)) for _ in range(3))
    for k in HARMONICS:
        w, a = 2 * np.pi * BASE_HZ * k, 0.1 * half / k
        angle = np.outer(t, np.full(model.n, w)) + rng.uniform(0, 2 * np.pi, model.n)
        q, qd, qdd = q + a * np.sin(angle), qd + a * w * np.cos(angle), qdd - a * w**2 * np.sin(angle)
    return centre + q, qd, qdd


def collision_log(duration=4.0, pulses=((2.0, 0.3),), seed=0, noise=True, friction=FRICTION, force=PUSH,
                  jitter=JITTER, model=None, link=LINK, rate=RATE) -> CollisionLog:
    """A UR5 (or ``model``) log of ``duration`` s at ``rate`` with the contacts ``pulses`` at ``link`` (module
    docstring)."""
    model = load_robot("ur5") if model is None else model
    rng = np.random.default_rng(seed + 100)
    ticks = np.arange(int(round(duration * rate)) + 1) / rate
    t = ticks + (rng.uniform(-jitter, jitter, len(ticks)) if jitter else 0.0)
    t[0] = 0.0
    q, qd, qdd = motion_at(model, t, seed)
    F = np.zeros((len(t), 6))
    for start, length in pulses:
        F[(t >= start) & (t < start + length), :3] = force
    tau_ext = np.einsum("kji,kj->ki", jacobian(model, q, link), F)                  # τ_ext = Jᵀ F
    tau = inverse_dynamics(model, q, qd, qdd) - tau_ext
    if friction is not None:
        tau = tau + friction.torques(qd)
    if not noise:
        return CollisionLog(t, q, qd, tau, tau_ext, q, qd)
    return CollisionLog(t, noisy(q, SIGMA_Q, seed + 1), noisy(qd, SIGMA_QD, seed + 2), noisy(tau, SIGMA_TAU, seed + 3),
                        tau_ext, q, qd)


def reversal_log(duration=20.0, seed=7, pulses=(), jitter=8e-5) -> CollisionLog:
    """The UR5 at 500 Hz (stamps ``jitter`` s off their ticks at most) on q = q₀ + 0.4 sin(ω t + φ), ω/2π = 0.3 …
    1.1 Hz per joint, with :data:`FRICTION`, a push of :data:`PUSH` at :data:`LINK` for each (start, length) of
    ``pulses``, and noise of 1e-5 rad, 1e-3 rad/s and 1 % of each joint's RMS torque (at least 0.01 N m)."""
    model = load_robot("ur5")
    rng = np.random.default_rng(seed)
    ticks = np.arange(int(round(duration * 500.0)) + 1) / 500.0
    t = ticks + rng.uniform(-jitter, jitter, len(ticks))
    t[0] = 0.0
    w = 2 * np.pi * np.array([0.3, 0.45, 0.5, 0.7, 0.8, 1.1])
    angle = np.outer(t, w) + rng.uniform(0, 2 * np.pi, 6)
    q0 = np.array([0.3, -1.2, 1.3, -1.5, -1.5, 0.2])
    q, qd, qdd = q0 + 0.4 * np.sin(angle), 0.4 * w * np.cos(angle), -0.4 * w**2 * np.sin(angle)
    F = np.zeros((len(t), 6))
    for start, length in pulses:
        F[(t >= start) & (t < start + length), :3] = PUSH
    tau_ext = np.einsum("kji,kj->ki", jacobian(model, q, LINK), F)                  # τ_ext = Jᵀ F
    tau = inverse_dynamics(model, q, qd, qdd) + FRICTION.torques(qd) - tau_ext
    sigma_tau = 0.01 * np.maximum(np.sqrt(np.mean(tau**2, axis=0)), 1.0)
    return CollisionLog(t, q + rng.normal(0, 1e-5, q.shape), qd + rng.normal(0, 1e-3, qd.shape),
                        tau + rng.normal(0, 1, tau.shape) * sigma_tau, tau_ext, q, qd)


def write_log(path, log: CollisionLog, joints, measured=True) -> Path:
    """The log as a table: t, q_<joint>, qd_<joint> and (``measured``) tau_meas_<joint>."""
    header, columns = ["t"], [log.t]
    for kind, values in (("q", log.q), ("qd", log.qd)) + ((("tau_meas", log.tau),) if measured else ()):
        header += [f"{kind}_{j}" for j in joints]
        columns += list(values.T)
    write_csv(Path(path), header, columns)
    return Path(path)


def write_example(path: Path = EXAMPLE) -> Path:
    """``examples/ur5_collision.csv``: 4 s of the UR5 with one 0.3 s push at tool0 from t = 2 s."""
    return write_log(path, collision_log(), load_robot("ur5").joint_names)


if __name__ == "__main__":
    print(f"wrote {write_example()}")

"""Robot logs as robots' own recorders write them, generated from a known motion.

The motion is exact (Θ, Θ̇, Θ̈ in closed form), so a test knows the torques a log should give;
what a recorder adds (its file layout, noise, dropped samples) is added here on purpose, with the
amounts stated. Bags are written by ``tests/bagmakers.py`` from the same motions.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from course_dynamics.core.sampling import sampling_bounds

# A multi-sine per joint: three harmonics of a 0.25 Hz base (0.25, 0.75, 1.25 Hz) with amplitudes
# falling as 1, 1/3, 1/5 of a tenth of the joint's half-range, phases seeded: smooth, periodic, rich.
BASE_HZ = 0.25
HARMONICS = (1, 3, 5)


@dataclass(frozen=True)
class Motion:
    """An exact motion on the samples ``t`` (K,), s: Θ, Θ̇, Θ̈ (K, n)."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray


def multisine(model, duration: float = 4.0, rate: float = 500.0, seed: int = 0, start: float = 0.0) -> Motion:
    """The multi-sine motion (module constants) of ``model`` sampled at ``rate`` Hz for ``duration`` s."""
    rng = np.random.default_rng(seed)
    lower, upper = sampling_bounds(model)
    centre, half = (lower + upper) / 2, (upper - lower) / 2
    t = start + np.arange(int(round(duration * rate)) + 1) / rate
    q, qd, qdd = (np.zeros((len(t), model.n)) for _ in range(3))
    for k in HARMONICS:
        w = 2 * np.pi * BASE_HZ * k
        a = 0.1 * half / k
        phase = rng.uniform(0, 2 * np.pi, model.n)
        angle = np.outer(t, np.full(model.n, w)) + phase
        q += a * np.sin(angle)
        qd += a * w * np.cos(angle)
        qdd += -a * w**2 * np.sin(angle)
    return Motion(t, centre + q, qd, qdd)


def sampled_at(model, t, seed: int = 0) -> Motion:
    """The motion ``multisine(model, seed=seed)`` at the times ``t`` (K,), s, however uneven they are."""
    parts = [multisine(model, duration=0.0, seed=seed, start=float(x)) for x in t]
    return Motion(np.asarray(t, dtype=float), *(np.vstack([getattr(p, k) for p in parts]) for k in ("q", "qd", "qdd")))


def real_clock(rate: float, duration: float, seed: int = 0, gap: int = 40, lone: int = 20) -> np.ndarray:
    """Stamps as a real recorder writes them at about ``rate`` Hz for ``duration`` s: each stamp off its slot by up to
    a tenth of a period (every step within ±20 % of the period), a gap of ``gap`` periods at 30 % of the log, a lone
    sample between two gaps of ``lone`` periods at 60 %, and two single rows dropped (at 15 % and 80 %)."""
    slots = np.arange(int(round(duration * rate)) + 1)
    t = (slots + np.random.default_rng(seed).uniform(-0.1, 0.1, len(slots))) / rate
    at = [int(share * len(slots)) for share in (0.15, 0.3, 0.6, 0.8)]
    lost = [at[0], *range(at[1] + 1, at[1] + gap), *range(at[2] + 1, at[2] + lone),
            *range(at[2] + lone + 1, at[2] + 2 * lone), at[3]]
    return np.delete(t, lost)


def noisy(values: np.ndarray, sigma: float, seed: int) -> np.ndarray:
    """``values`` plus white Gaussian noise of standard deviation ``sigma``."""
    return values + np.random.default_rng(seed).normal(0.0, sigma, values.shape)


def dropped(motion: Motion, rows) -> Motion:
    """The motion without the samples ``rows`` (as a recorder that dropped those packets)."""
    keep = np.setdiff1d(np.arange(len(motion.t)), np.asarray(rows, dtype=int))
    return Motion(motion.t[keep], motion.q[keep], motion.qd[keep], motion.qdd[keep])


def write_csv(path, header, columns, delimiter=",", fmt="{:.10g}") -> None:
    """A plain delimited table: ``header`` names, ``columns`` equal-length 1-D arrays (or lists of strings)."""
    rows = [delimiter.join(header)]
    for i in range(len(columns[0])):
        rows.append(delimiter.join(c[i] if isinstance(c[i], str) else fmt.format(c[i]) for c in columns))
    path.write_text("\n".join(rows) + "\n")


def write_ur_rtde(path, t, q, qd, current=None, target_q=None, mode_words=False) -> None:
    """A log as UR's RTDE recorder (``record.py``) writes it: space separated, ``timestamp``, ``actual_q_i``,
    ``actual_qd_i`` (i from 0), optionally ``actual_current_i`` and ``target_q_i``; ``mode_words`` adds a text
    column as a controller logs one (its values are words)."""
    header, columns = ["timestamp"], [t]
    blocks = [("actual_q", q), ("actual_qd", qd), ("actual_current", current), ("target_q", target_q)]
    for name, block in blocks:
        if block is not None:
            header += [f"{name}_{i}" for i in range(block.shape[1])]
            columns += [block[:, i] for i in range(block.shape[1])]
    if mode_words:
        header.append("robot_mode_word")
        columns.append(["RUNNING" if i % 7 else "running" for i in range(len(t))])
    write_csv(path, header, columns, delimiter=" ", fmt="{:.12g}")

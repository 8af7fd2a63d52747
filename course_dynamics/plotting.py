"""Pictures of a simulated motion (matplotlib, drawn off-screen to a PNG file).

:func:`plot_trajectory` draws one run (Θ(t), Θ̇(t), E(t)); :func:`plot_ensemble`
draws how far the members of an ensemble drift from the first one.
"""
from __future__ import annotations

from pathlib import Path

from .simulation import Trajectory


def plot_trajectory(trajectory: Trajectory, path, title: str = "") -> None:
    """Joint positions Θ(t), velocities Θ̇(t) and total energy E(t), stacked, saved as ``path`` (PNG)."""
    import matplotlib

    matplotlib.use("Agg")  # no screen needed
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(3, 1, sharex=True, figsize=(8, 7.5), constrained_layout=True)
    for j, name in enumerate(trajectory.joints):
        axes[0].plot(trajectory.t, trajectory.q[:, j], label=name)
        axes[1].plot(trajectory.t, trajectory.qd[:, j], label=name)
    axes[2].plot(trajectory.t, trajectory.energy, color="black")
    axes[0].set_ylabel("Θ (rad or m)")
    axes[1].set_ylabel("dΘ/dt (rad/s or m/s)")  # the combining dot of Θ̇ is lost in most fonts
    axes[2].set_ylabel("E = k + u (J)")
    axes[2].set_xlabel("t (s)")
    axes[0].legend(loc="upper right", fontsize="small", ncol=min(len(trajectory.joints), 4))
    if title:
        axes[0].set_title(title)
    for axis in axes:
        axis.grid(alpha=0.3)
    figure.savefig(Path(path), dpi=110)
    plt.close(figure)


def plot_ensemble(trajectory: Trajectory, path, title: str = "") -> None:
    """Divergence of an ensemble from member 0: max over joints of |Θₖ(t) − Θ₀(t)|, log scale, and Θ of every member."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    q, t = trajectory.q, trajectory.t
    distance = np.abs(q[:, 1:, :] - q[:, :1, :]).max(axis=-1)  # (T, K − 1)
    figure, axes = plt.subplots(2, 1, sharex=True, figsize=(8, 7), constrained_layout=True)
    axes[0].semilogy(t, np.maximum(distance, 1e-17), color="tab:blue", alpha=max(0.05, min(0.5, 20 / distance.shape[1])),
                     linewidth=0.8)
    axes[0].semilogy(t, np.maximum(np.median(distance, axis=1), 1e-17), color="black", linewidth=2, label="median")
    axes[0].set_ylabel("max_j |θ_j(t) − θ_j of member 0| (rad or m)")
    axes[0].legend(loc="lower right")
    for j, name in enumerate(trajectory.joints):
        axes[1].plot(t, q[:, :, j], linewidth=0.6, alpha=max(0.05, min(0.6, 20 / q.shape[1])), color=f"C{j}")
        axes[1].plot([], [], color=f"C{j}", label=name)
    axes[1].set_ylabel("Θ (rad or m), every member")
    axes[1].set_xlabel("t (s)")
    axes[1].legend(loc="upper right", fontsize="small")
    axes[0].set_title(title or f"{q.shape[1]} members: divergence from member 0")
    for axis in axes:
        axis.grid(alpha=0.3)
    figure.savefig(Path(path), dpi=110)
    plt.close(figure)

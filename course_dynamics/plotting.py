"""Pictures of a simulated motion (matplotlib, drawn off-screen to a PNG file)."""
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

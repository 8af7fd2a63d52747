"""Draw docs/energy_drift.png: energy error of each integrator on the double pendulum.

Run:  python docs/energy_drift.py

10 s from Θ = (2.0, 0.0) rad at rest, no torque, no friction, dt = 1 ms: the
exact motion conserves energy, so |E(t) − E(0)| / |E(0)| is the integrator's error.
"""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from course_dynamics import load_robot
from course_dynamics.tools.simulation import INTEGRATORS, simulate


def main() -> None:
    model = load_robot("double_pendulum_continuous")
    figure, axis = plt.subplots(figsize=(8, 4.5), constrained_layout=True)
    for integrator in INTEGRATORS:
        trajectory = simulate(model, [2.0, 0.0], [0.0, 0.0], duration=10.0, dt=1e-3, integrator=integrator)
        error = np.abs(trajectory.energy - trajectory.energy[0]) / abs(trajectory.energy[0])
        label = "euler (the notes' 6.116-6.117)" if integrator == "euler" else integrator
        axis.semilogy(trajectory.t[1:], np.maximum(error[1:], 1e-16), label=label)
        print(f"{integrator:<14} max relative energy error over 10 s: {error.max():.2e}")
    axis.set_xlabel("t (s)")
    axis.set_ylabel("|E(t) − E(0)| / |E(0)|")
    axis.set_title("Double pendulum, dt = 1 ms: energy error by integrator")
    axis.grid(alpha=0.3, which="both")
    axis.legend()
    out = Path(__file__).with_name("energy_drift.png")
    figure.savefig(out, dpi=100)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()

"""The figures: what their labels say, with TeX parsing off (a '$' in a joint name is a dollar sign)."""
from __future__ import annotations

import numpy as np

from course_dynamics import load_robot, simulate
from course_dynamics.output import plotting


def test_the_ensemble_figure_labels_its_log_axis_in_plain_numbers():
    """Matplotlib's default log labels are TeX ($\\mathdefault{10^{-5}}$): with parsing off they would show raw."""
    arm = load_robot("double_pendulum")
    q0 = np.array([1.5, 0.0]) + 1e-6 * np.random.default_rng(0).standard_normal((3, 2))
    trajectory = simulate(arm, q0, np.zeros((3, 2)), duration=0.5, dt=1e-3)
    figure = plotting.ensemble_figure(trajectory)
    figure.canvas.draw()
    labels = [label.get_text() for label in figure.axes[0].get_yticklabels() if label.get_text()]
    plotting.pyplot().close(figure)
    assert labels and not any("$" in label or "mathdefault" in label for label in labels), labels
    assert all(float(label.replace("−", "-")) > 0 for label in labels), labels

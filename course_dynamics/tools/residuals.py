"""The model against the robot: predicted torques next to the ones the robot measured.

==================  =============  ===================================================
code                symbol         meaning (shape, unit)
==================  =============  ===================================================
``predicted``       τ              our τ along the log (K, n), N·m or N
``measured``        τ_meas         what the robot measured (K, n): joint torques, or motor
                                   currents i times torque constants k, τ_meas = k i
``residual``        e              e = τ_meas − τ (K, n)
``rms``             —              √(mean e²) per joint
``peak``            —              max ``|e|`` per joint, and the time it happens
``r2``              R²             1 − Σ e² / Σ (τ_meas − mean τ_meas)²: the share of the
                                   measured torque's variation the model explains
==================  =============  ===================================================

A joint the log did not measure has no row. R² is undefined (None) for a measured torque
that does not vary. This is the baseline identification improves on: a URDF whose masses
are right leaves residuals of the size of friction and sensor noise.

>>> import numpy as np
>>> t = np.linspace(0, 1, 5)
>>> tau = np.column_stack([np.sin(t), t])
>>> report = residual_report(("a", "b"), t, tau, tau + [[0.1, np.nan]], source="tau_meas")
>>> [(r.joint, round(r.rms, 3), r.r2 is not None) for r in report.joints]
[('a', 0.1, True)]
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class JointResidual:
    """One joint's residual: RMS and peak of e = τ_meas − τ, when the peak happens, and R².

    Parameters
    ----------
    joint : str
        The joint's name.
    rms : float
        √(mean e²), N·m (N for a prismatic joint).
    peak : float
        max ``|e|``, N·m (N).
    peak_t : float
        When the peak happens, s.
    r2 : float or None
        R², the share of the measured torque's variation the model explains; None if it does not vary.
    rms_measured : float
        √(mean τ_meas²), N·m (N): the size the residual is compared with.
    """

    joint: str
    rms: float
    peak: float
    peak_t: float
    r2: float | None
    rms_measured: float

    def record(self) -> dict:
        """The residual, JSON-ready.

        Returns
        -------
        dict
            The fields by name.
        """
        return {"joint": self.joint, "rms": self.rms, "peak": self.peak, "peak_t": self.peak_t, "r2": self.r2,
                "rms_measured": self.rms_measured}


@dataclass(frozen=True)
class ResidualReport:
    """Every measured joint's residual, and what the measurement was (``tau_meas``, or currents × constants).

    Parameters
    ----------
    joints : tuple of JointResidual
        One per measured joint, in the model's order.
    source : str
        What the measurement was.
    """

    joints: tuple[JointResidual, ...]
    source: str

    def record(self) -> dict:
        """The report, JSON-ready.

        Returns
        -------
        dict
            ``source`` and each joint's record.
        """
        return {"source": self.source, "joints": [j.record() for j in self.joints]}


def residual_report(joints, t, predicted, measured, source: str) -> ResidualReport:
    """Per joint, ``measured`` (K, n; NaN columns for joints not measured) against ``predicted`` (K, n)
    (module docstring).

    Parameters
    ----------
    joints : sequence of str
        The joints' names, in the columns' order.
    t : numpy.ndarray, shape (K,)
        Sample times, s.
    predicted : numpy.ndarray, shape (K, n)
        Our torques τ, N·m (N for a prismatic joint).
    measured : numpy.ndarray, shape (K, n)
        The measured torques τ_meas, N·m (N); a column with a NaN is a joint not measured.
    source : str
        What the measurement was (``tau_meas``, or currents times torque constants).

    Returns
    -------
    ResidualReport
        A row per measured joint.
    """
    rows = []
    for i, joint in enumerate(joints):
        tau_meas = measured[:, i]
        if not np.all(np.isfinite(tau_meas)):
            continue
        scale = max(float(np.abs(tau_meas).max()), float(np.abs(predicted[:, i]).max()), np.finfo(float).tiny)
        e, measured_s = (tau_meas - predicted[:, i]) / scale, tau_meas / scale   # scaled: no overflow in squares
        spread = float(np.sum((measured_s - measured_s.mean()) ** 2))
        worst = int(np.argmax(np.abs(e)))
        rows.append(JointResidual(joint, scale * float(np.sqrt(np.mean(e**2))), scale * float(abs(e[worst])),
                                  float(t[worst]), 1.0 - float(np.sum(e**2)) / spread if spread > 0 else None,
                                  scale * float(np.sqrt(np.mean(measured_s**2)))))
    return ResidualReport(tuple(rows), source)


__all__ = ["JointResidual", "ResidualReport", "residual_report"]

"""Does a motion stay within the motors' limits? Peaks, RMS and violations per joint.

==================  =====================================================================
field               meaning (shape, unit)
==================  =====================================================================
``peak_tau``        max ``|τᵢ(t)|`` over the motion (n,), N·m or N
``rms_tau``         √(mean τᵢ²) (n,): what heats a motor, N·m or N
``peak_qd``         max ``|θ̇ᵢ(t)|`` (n,), rad/s or m/s
``effort``          the URDF's effort limit (n,), inf where none is given
``velocity``        the URDF's velocity limit (n,), inf where none is given
``effort_used``     peak_tau / effort (n,): 1 means at the limit, 0 where there is none
``velocity_used``   peak_qd / velocity (n,)
``violations``      every stretch of time a joint spends beyond a limit
``peak_band``       the uncertainty of τ at each joint's peak, ± UNCERTAINTY_SIGMAS σ_τ (n,), N·m or N
``uncertain``       every stretch where ``|τ|`` is within that band of the effort limit, on either side
==================  =====================================================================

When τ comes from differentiated rates, σ_τ (K, n) says what their noise leaves in it. A row then
counts as beyond the effort limit only when ``|τ|`` − 2σ_τ is; a row whose ``|τ|`` ± 2σ_τ straddles the limit
is *uncertain*: reported apart ("within the uncertainty of the rates"), never silently passed or failed.

RMS is over samples, which is the time average for evenly spaced logs. A
signal hovering at a limit crosses it back and forth; stretches beyond it fewer
than :data:`MERGE_GAP` samples apart are reported as one violation.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.model import Model

#: Stretches beyond a limit fewer than this many samples apart are one violation.
MERGE_GAP = 10  # samples


def seconds(t: float) -> str:
    """A time for reading: 6 digits, or milliseconds in full for clock times (a bag's 1.7e9 s since 1970).

    Parameters
    ----------
    t : float
        A time, s.

    Returns
    -------
    str
        The number, without its unit.

    Examples
    --------
    >>> seconds(1.25), seconds(1700000000.0143)
    ('1.25', '1700000000.014')
    """
    return f"{t:.6g}" if abs(t) < 1e5 else f"{t:.3f}"
#: The band of a verdict in σ_τ (± 2σ, about 95 % for Gaussian noise).
UNCERTAINTY_SIGMAS = 2.0  # the band of a verdict: ± 2σ, about 95 % for Gaussian noise


@dataclass(frozen=True)
class Violation:
    """Joint ``joint`` beyond its ``kind`` limit ("effort" or "velocity") from ``start`` to ``end`` (s).

    Parameters
    ----------
    joint : str
        The joint's name.
    kind : str
        ``"effort"`` or ``"velocity"``.
    start : float
        When the stretch starts, s.
    end : float
        When it ends, s.
    peak : float
        The largest ``|τ|`` (N·m or N) or ``|θ̇|`` (rad/s or m/s) in it.
    limit : float
        The URDF's limit, in the same unit.
    band : float
        ± :data:`UNCERTAINTY_SIGMAS` σ_τ at the peak, for an uncertain stretch; 0 for a violation.
    """

    joint: str
    kind: str
    start: float
    end: float
    peak: float
    limit: float

    band: float = 0.0  # ± UNCERTAINTY_SIGMAS σ_τ at the peak, for an uncertain stretch

    def describe(self) -> str:
        """The stretch in one sentence, for a report.

        Returns
        -------
        str
            Joint, kind, peak (± band), limit and the stretch's times.
        """
        unit = "N m or N" if self.kind == "effort" else "rad/s or m/s"
        if self.band:
            return (f"joint '{self.joint}': {self.kind} {self.peak:.4g} ± {self.band:.2g} is within the uncertainty of "
                    f"the rates of the limit {self.limit:.4g} ({unit}) from t = {seconds(self.start)} s to "
                    f"t = {seconds(self.end)} s")
        return (f"joint '{self.joint}': {self.kind} {self.peak:.4g} exceeds the limit {self.limit:.4g} ({unit}) "
                f"from t = {seconds(self.start)} s to t = {seconds(self.end)} s")


@dataclass(frozen=True)
class LimitsReport:
    """A motion's peaks, RMS and limit violations per joint (the module's table).

    Parameters
    ----------
    joints : tuple of str
        The joints' names, in the model's order.
    peak_tau : numpy.ndarray, shape (n,)
        max ``|τᵢ(t)|``, N·m (N for a prismatic joint).
    rms_tau : numpy.ndarray, shape (n,)
        √(mean τᵢ²), N·m (N).
    peak_qd : numpy.ndarray, shape (n,)
        max ``|θ̇ᵢ(t)|``, rad/s (m/s).
    effort : numpy.ndarray, shape (n,)
        The URDF's effort limits, N·m (N); inf where none is given.
    velocity : numpy.ndarray, shape (n,)
        The URDF's velocity limits, rad/s (m/s); inf where none is given.
    violations : tuple of Violation
        Every stretch of time a joint spends beyond a limit, in time order.
    peak_band : numpy.ndarray, shape (n,), optional
        The uncertainty of τ at each joint's peak, ± :data:`UNCERTAINTY_SIGMAS` σ_τ, N·m (N); None without σ_τ.
    uncertain : tuple of Violation
        Every stretch where ``|τ|`` is within that band of the effort limit, on either side.
    """

    joints: tuple[str, ...]
    peak_tau: np.ndarray
    rms_tau: np.ndarray
    peak_qd: np.ndarray
    effort: np.ndarray
    velocity: np.ndarray
    violations: tuple[Violation, ...]
    peak_band: np.ndarray | None = None
    uncertain: tuple[Violation, ...] = ()

    @property
    def effort_used(self) -> np.ndarray:
        """``peak_tau / effort`` (n,), 1 at the limit, 0 where there is none."""
        return np.where(np.isfinite(self.effort), self.peak_tau / np.where(self.effort > 0, self.effort, np.inf), 0.0)

    @property
    def velocity_used(self) -> np.ndarray:
        """``peak_qd / velocity`` (n,), 1 at the limit, 0 where there is none."""
        return np.where(np.isfinite(self.velocity),
                        self.peak_qd / np.where(self.velocity > 0, self.velocity, np.inf), 0.0)

    @property
    def exceeded(self) -> bool:
        """Whether any joint went beyond a limit (uncertain stretches do not count)."""
        return bool(self.violations)

    def rows(self) -> list[dict]:
        """One record per joint (for tables and JSON); a missing limit is None.

        Returns
        -------
        list of dict
            Per joint: peaks, RMS, limits and the shares of them used.
        """
        def limit(x):
            return float(x) if np.isfinite(x) else None

        return [dict(joint=j, peak_tau=float(self.peak_tau[i]), rms_tau=float(self.rms_tau[i]),
                     effort_limit=limit(self.effort[i]),
                     effort_used=float(self.effort_used[i]) if np.isfinite(self.effort[i]) else None,
                     peak_qd=float(self.peak_qd[i]), velocity_limit=limit(self.velocity[i]),
                     velocity_used=float(self.velocity_used[i]) if np.isfinite(self.velocity[i]) else None,
                     peak_tau_band=None if self.peak_band is None else float(self.peak_band[i]))
                for i, j in enumerate(self.joints)]

    def record(self) -> dict:
        """The whole report, JSON-ready.

        Returns
        -------
        dict
            ``exceeded``, the joints' :meth:`rows`, the violations and the uncertain stretches.
        """
        def stretch(v):
            return dict(joint=v.joint, kind=v.kind, start=v.start, end=v.end, peak=v.peak, limit=v.limit)

        return dict(exceeded=self.exceeded, joints=self.rows(), violations=[stretch(v) for v in self.violations],
                    uncertain=[dict(stretch(v), band=v.band) for v in self.uncertain])


def _intervals(t: np.ndarray, over: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) sample indices of each run of True in ``over``."""
    edges = np.diff(np.concatenate([[0], over.astype(np.int8), [0]]))
    runs = []
    for first, last in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1):
        if runs and first - runs[-1][1] <= MERGE_GAP:
            runs[-1] = (runs[-1][0], last)
        else:
            runs.append((first, last))
    return runs


def limits_report(model: Model, t, qd, tau, tau_sigma=None) -> LimitsReport:
    """Peaks, RMS and limit violations of a motion.

    Parameters
    ----------
    model : Model
        The robot, whose URDF limits are checked.
    t : numpy.ndarray, shape (N,)
        Sample times, s.
    qd : numpy.ndarray, shape (N, n)
        Joint velocities Θ̇, rad/s (m/s for a prismatic joint).
    tau : numpy.ndarray, shape (N, n)
        Joint torques τ, N·m (N for a prismatic joint).
    tau_sigma : numpy.ndarray, shape (N, n), optional
        σ_τ, the standard deviation the rates' noise leaves in τ (module docstring), N·m (N).

    Returns
    -------
    LimitsReport
        Peaks, RMS, violations and uncertain stretches per joint.
    """
    t, qd, tau = np.asarray(t, dtype=float), np.asarray(qd, dtype=float), np.asarray(tau, dtype=float)
    band = np.zeros_like(tau) if tau_sigma is None else UNCERTAINTY_SIGMAS * np.asarray(tau_sigma, dtype=float)
    effort, velocity = model.effort, model.velocity
    violations, uncertain = [], []
    for kind, values, limits in (("effort", np.abs(tau), effort), ("velocity", np.abs(qd), velocity)):
        margin = band if kind == "effort" else np.zeros_like(values)
        for i, joint in enumerate(model.joint_names):
            if not np.isfinite(limits[i]):
                continue
            for first, last in _intervals(t, values[:, i] - margin[:, i] > limits[i]):
                violations.append(Violation(joint=joint, kind=kind, start=float(t[first]), end=float(t[last]),
                                            peak=float(values[first:last + 1, i].max()), limit=float(limits[i])))
            beyond = values[:, i] - margin[:, i] > limits[i]
            near = values[:, i] + margin[:, i] > limits[i]          # beyond, or within the band of the limit
            for first, last in _intervals(t, near) if kind == "effort" and tau_sigma is not None else ():
                if beyond[first:last + 1].any():                     # the edge of a violation: part of it
                    continue
                worst = first + int(np.argmax(values[first:last + 1, i]))
                uncertain.append(Violation(joint=joint, kind=kind, start=float(t[first]), end=float(t[last]),
                                           peak=float(values[worst, i]), limit=float(limits[i]),
                                           band=float(margin[worst, i])))
    violations.sort(key=lambda v: (v.start, v.joint, v.kind))
    uncertain.sort(key=lambda v: (v.start, v.joint, v.kind))
    peak = np.abs(tau).max(axis=0)
    scale = np.where(peak > 0, peak, 1.0)
    rms = scale * np.sqrt(np.mean((tau / scale) ** 2, axis=0))  # scaled: no overflow for large torques
    at_peak = np.abs(tau).argmax(axis=0)
    peak_band = None if tau_sigma is None else band[at_peak, np.arange(tau.shape[1])]
    return LimitsReport(joints=model.joint_names, peak_tau=peak, rms_tau=rms,
                        peak_qd=np.abs(qd).max(axis=0), effort=effort, velocity=velocity, violations=tuple(violations),
                        peak_band=peak_band, uncertain=tuple(uncertain))


__all__ = ["MERGE_GAP", "UNCERTAINTY_SIGMAS", "LimitsReport", "Violation", "limits_report", "seconds"]

"""From a recorded trajectory log to joint torques and a limits report.

==================  =============  ===================================================
code                Craig          meaning (shape, unit)
==================  =============  ===================================================
``t``               t              sample times (N,), s
``q``               Θ              joint positions (N, n), rad or m
``qd``              Θ̇              joint rates (N, n): read, or differentiated from Θ
``qdd``             Θ̈              joint accelerations (N, n): read, or differentiated
``tau``             τ              τ = M(Θ)Θ̈ + V(Θ,Θ̇) + G(Θ) + F(Θ̇) + Jᵀ F_ext (6.59),
                                   (6.114), τ = JᵀF, (N, n), N·m or N
==================  =============  ===================================================

A log is any table of numbers with named columns: what :func:`~course_dynamics.tools.sources.open_log`
reads (a delimited table, a UR RTDE recording, a ROS bag), a pandas DataFrame, a dict of arrays
or a numpy structured array. Our names are ``t``, ``q_<joint>``, ``qd_<joint>``, ``qdd_<joint>``,
and for what the robot measured ``tau_meas_<joint>`` and ``current_<joint>``; ``columns`` maps
ours to the log's (``{"q_shoulder_pan_joint": "joint1_pos"}``), and every other column of the log,
numbers or words, is ignored (:mod:`~course_dynamics.tools.columns`).

Positions only: when a log has no ``qd_`` (or no ``qdd_``) columns, they are
differentiated from Θ(t) by a Savitzky–Golay filter (scipy): a cubic fitted by
least squares to a window of samples around each one, differentiated exactly.
It smooths as it differentiates, which plain finite differences of a measured
signal do not (they amplify its noise by 1/Δt, and Θ̈ by 1/Δt²). The window
(odd, in samples) is ``window``; by default the odd count nearest to 20 ms of
samples, and at least 7. What is differentiated must be on an even clock; dropped samples
are filled, a log can be resampled and long gaps split (:mod:`~course_dynamics.tools.resampling`).
The caller states what it needs (``needs``): Θ̈ (the torques), or Θ̇ alone (the momentum observer); a log that
holds what is needed is taken on its own stamps, however uneven, and nothing is filled.
What was differentiated, filled or resampled is said in :attr:`TorqueLog.notes`, and
the CLI writes it at the top of its output. When the log holds measured torques (or
currents and their torque constants), the ``residuals`` of a :class:`TorqueLog` compare them with ours
(:mod:`~course_dynamics.tools.residuals`).

>>> import numpy as np
>>> from course_dynamics import load_robot
>>> from course_dynamics.tools.logs import torques_from_log
>>> t = np.arange(0, 1, 1e-3)
>>> log = {"t": t, "q_theta1": np.sin(t), "q_theta2": 0.5 * t}          # positions only
>>> result = torques_from_log(load_robot("two_link"), log)
>>> result.tau.shape, result.notes[0].split(":")[0]
((1000, 2), 'qd')
>>> result.report.exceeded                                              # two_link has no limits
False
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..base.errors import InputError
from ..core.drives import Driven, Drives
from ..core.evaluator import implementation
from ..core.friction import Friction
from ..core.model import Model
from .columns import KINDS
from .differentiation import POLYORDER, derivatives
from .limits import LimitsReport, limits_report
from .loads import with_payload, wrench_torques
from .motion import TIME_UNITS, check_clock, check_time_unit, check_values, log_times, planned_columns
from .resampling import MIN_SEGMENT_ROWS, even_clock
from .residuals import ResidualReport, residual_report
from .sources import as_source
from .tables import joint_columns, stack_joint_columns

#: τ is computed this many rows at a time, so that the recursion's temporaries (for the UR5 about 1.6 kB a row
#: interpreted, 0.5 kB compiled, measured with tracemalloc) stay under 60 MB however long the log.
ROWS_AT_A_TIME = 2**15
MAX_MEASURED = 1e7          # N m: the largest industrial joints take about 1e5
RATE_UNITS_RATIO = 3.0      # a logged Θ̇ this many times larger or smaller than dΘ/dt is in other units
RATE_CHECK_SPAN = 0.05      # s: dΘ/dt for that check is a difference over at most this time


@dataclass(frozen=True)
class JointLog:
    """Θ, Θ̇, Θ̈ on the samples of a log; ``notes`` says what was computed rather than read.

    ``measured``: τ_meas (K, n), NaN for joints not measured, or None; ``measured_from`` says what it was
    (``tau_meas``, or currents times torque constants); ``segments``: (start, stop) rows differentiated apart.

    Parameters
    ----------
    t : numpy.ndarray, shape (K,)
        Sample times, s.
    q : numpy.ndarray, shape (K, n)
        Joint positions Θ, rad (m for a prismatic joint).
    qd : numpy.ndarray, shape (K, n)
        Joint velocities Θ̇, rad/s (m/s).
    qdd : numpy.ndarray, shape (K, n)
        Joint accelerations Θ̈, rad/s² (m/s²).
    notes : tuple of str
        What was computed (differentiated, filled, resampled) rather than read.
    measured : numpy.ndarray, shape (K, n), optional
        The measured torques τ_meas, N·m (N for a prismatic joint), NaN for joints not measured; None if none.
    measured_from : str
        What ``measured`` was made from.
    segments : tuple of (int, int)
        The (start, stop) rows differentiated apart.
    sigma_qdd : numpy.ndarray, shape (K, n), optional
        What the position or rate noise leaves in Θ̈, rad/s² (0 where Θ̈ was read).
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    notes: tuple[str, ...] = ()
    measured: np.ndarray | None = None
    measured_from: str = ""
    segments: tuple[tuple[int, int], ...] = ()
    sigma_qdd: np.ndarray | None = None     # (K, n) rad/s²: what the position or rate noise leaves in Θ̈


@dataclass(frozen=True)
class TorqueLog:
    """The torques a log needs, the state they were computed from, the limits report and, when the robot
    measured its torques, the residuals.

    Parameters
    ----------
    log : JointLog
        The state the torques were computed from.
    tau : numpy.ndarray, shape (K, n)
        Joint torques τ, N·m (N for a prismatic joint).
    report : LimitsReport
        The torques and rates against the URDF's limits.
    model : Model
        The robot the torques are of (payloads lumped in).
    residuals : ResidualReport, optional
        The measured torques against ours; None when the log measured none.
    tau_sigma : numpy.ndarray, shape (K, n), optional
        σ_τ from the noise of differentiated rates, N·m; None when nothing was differentiated.
    """

    log: JointLog
    tau: np.ndarray
    report: LimitsReport
    model: Model
    residuals: ResidualReport | None = None
    tau_sigma: np.ndarray | None = None   # (K, n): σ_τ from the noise of differentiated rates, or None

    @property
    def t(self) -> np.ndarray:
        """The sample times (K,), s."""
        return self.log.t

    @property
    def notes(self) -> tuple[str, ...]:
        """What was computed (differentiated, filled, resampled) rather than read."""
        return self.log.notes

    def table(self, with_state: bool = False) -> tuple[list[str], np.ndarray]:
        """Header and rows: t, ``tau_<joint>`` (and ``q_``, ``qd_``, ``qdd_`` with ``with_state``; ``tau_meas_`` when
        measured).

        Parameters
        ----------
        with_state : bool
            Whether the state's columns come before the torques.

        Returns
        -------
        header : list of str
            The column names.
        rows : numpy.ndarray, shape (K, columns)
            One row per sample, in SI units.
        """
        kinds = (KINDS if with_state else ()) + ("tau",)
        header = ["t"] + joint_columns(kinds, self.model.joint_names)
        blocks = [getattr(self.log, k) for k in kinds[:-1]] + [self.tau]
        if self.residuals is not None:
            measured = [r.joint for r in self.residuals.joints]
            header += [f"tau_meas_{j}" for j in measured]
            blocks += [self.log.measured[:, [self.model.joint_names.index(j) for j in measured]]]
        return header, np.column_stack([self.t] + blocks)


def _measured(model: Model, plan, renamed: dict, samples: int, torque_constants, where: str):
    """τ_meas (K, n) with NaN columns for joints not measured, and what it is; or (None, "", notes)."""
    with_tau, with_current = plan.measured("tau_meas"), plan.measured("current")
    notes = []
    if torque_constants is not None:
        k = np.asarray(torque_constants, dtype=float).reshape(-1)
        if k.shape != (model.n,) or not np.all(np.isfinite(k)) or np.any(k == 0):
            raise InputError(f"torque constants: {model.n} finite numbers, none zero, are needed (N m/A, one per "
                             f"joint: {', '.join(model.joint_names)}), got {k.tolist()}")
        if not with_current:
            raise InputError(f"{where}: torque constants were given but the log has no motor currents "
                             "(current_<joint>, or an RTDE recording's actual_current_i)")
    if with_tau:
        if with_current and torque_constants is not None:
            notes.append("both measured torques and currents are logged: the torques are compared, the currents not")
        measured = np.full((samples, model.n), np.nan)
        for j in with_tau:
            measured[:, model.joint_names.index(j)] = renamed[f"tau_meas_{j}"]
        return measured, "tau_meas", notes
    if with_current and torque_constants is not None:
        measured = np.full((samples, model.n), np.nan)
        for j in with_current:
            i = model.joint_names.index(j)
            measured[:, i] = k[i] * renamed[f"current_{j}"]
        return measured, "currents times torque constants", notes
    if with_current:
        notes.append("motor currents are logged: give torque constants (--torque-constant k1,...) to compare them "
                     "with the torques")
    return None, "", notes


def _check_plausible(model: Model, plan, renamed: dict, torque_constants, source) -> None:
    """Measured torques no robot could produce are a mistake (units, a corrupt cell), never a residual: checked on the
    logged samples, before any is filled or resampled, naming the file's line and the log's column."""
    k = None if torque_constants is None else np.asarray(torque_constants, dtype=float).reshape(-1)
    checked = [(f"tau_meas_{j}", 1.0) for j in plan.measured("tau_meas")]
    if not checked and k is not None and k.shape == (model.n,):
        checked = [(f"current_{j}", k[model.joint_names.index(j)]) for j in plan.measured("current")]
    for name, scale in checked:
        torque = scale * np.asarray(renamed[name], dtype=float)
        big = np.flatnonzero(np.abs(np.nan_to_num(torque)) > MAX_MEASURED)
        if len(big):
            raise InputError(f"{source.where}: {source.line(int(big[0]))}, column '{plan.read.get(name, name)}': a "
                             f"measured torque of {torque[big[0]]:.3g} is beyond any robot's ({MAX_MEASURED:g} N m); "
                             "check the log's units and torque constants")


def joint_log(model: Model, table, *, dt: float | None = None, columns: Mapping[str, str] | None = None,
              window: int | None = None, constants: Mapping[str, float] | None = None,
              time_unit: str = "s", resample: float | None = None, split_gaps: bool = False,
              repair: bool = False, torque_constants=None, needs: str = "qdd") -> JointLog:
    """Θ, Θ̇, Θ̈ of ``model``'s joints from a log (module docstring).

    Parameters
    ----------
    model : Model
        The robot.
    table : LogSource or table
        A log (a :class:`~course_dynamics.tools.sources.LogSource` or anything
        :func:`~course_dynamics.tools.sources.as_source` takes).
    dt : float, optional
        The sample step of a log without a ``t`` column, s.
    columns : mapping of str to str, optional
        Our column name → the log's.
    window : int, optional
        The Savitzky–Golay window in samples, odd (default: about 20 ms).
    constants : mapping of str to float, optional
        Our column name → a value for every row, for signals the log lacks
        (e.g. ``{"q_panda_finger_joint1": 0.04}``; a constant q has zero rates).
    time_unit : str
        The unit of the log's ``t`` column: s, ms, us or ns.
    resample : float, optional
        Put the log on an even clock at this rate first, Hz.
    split_gaps : bool
        Differentiate the pieces between long gaps apart instead of refusing them.
    repair : bool
        Whatever the clock needs, at once (:func:`~course_dynamics.tools.resampling.even_clock`): resample on the
        median period when the steps are not whole periods, split at long gaps, drop the segments too short to
        differentiate; each said in a note. A log on one clock gives the same result with it or without.
    torque_constants : array_like, shape (n,), optional
        Turn logged motor currents into measured torques, N·m/A.
    needs : str
        What the caller uses: ``"qdd"`` (Θ̈ read or differentiated, on an even clock) or ``"qd"`` (Θ̇ alone: Θ̈ is
        not formed (NaN where not read), and a log with Θ̇ is taken on its own stamps, uneven or not).

    Returns
    -------
    JointLog
        Θ, Θ̇, Θ̈ on the log's samples (or its even clock), the measured torques, and the notes.

    Raises
    ------
    InputError
        A mapped or needed column that is missing or holds text, a column of the wrong length, two of our
        columns mapped to one of the log's, t not increasing, the clock's problems the options leave (all named
        in one message), a bad ``dt``, time unit or window.
    """
    if needs not in ("qd", "qdd"):
        raise ValueError(f"needs is 'qd' or 'qdd', not {needs!r}")
    source = as_source(table)
    where, line = source.where, source.line
    check_time_unit(source, time_unit)
    planned = planned_columns(model, source, columns=columns, constants=constants)
    plan, renamed, samples = planned.plan, planned.values, planned.samples
    plan.require_positions(where)
    check_values(planned)
    _check_plausible(model, plan, renamed, torque_constants, source)
    mimic_notes = _mimic_notes(model, source, renamed, samples)
    t = log_times(planned, dt, time_unit)
    if not plan.has_time and (resample is not None or split_gaps):
        raise InputError("resampling and splitting at gaps need the log's own times (a t column)")

    notes = list(source.notes) + mimic_notes
    segments = ((0, samples),)
    step = float(dt) if dt is not None else (float(np.median(np.diff(t))) if samples > 1 else 0.0)
    derived = tuple(d for d in plan.derived if needs == "qdd" or d.order == 1)   # what must be differentiated
    if repair and not (derived or resample is not None):
        notes.append("repair: nothing is differentiated, so the log's stamps are taken as they are")
    if derived or resample is not None:
        if samples < 2:
            raise InputError(f"{where}: one row cannot be differentiated (give qd_{' and qdd_' * (needs == 'qdd')} "
                             "columns)")
        fewest = (window or POLYORDER + 2) if derived else MIN_SEGMENT_ROWS   # what each segment's filter needs
        clock = even_clock(t, renamed, resample=resample, split_gaps=split_gaps, repair=repair, min_rows=fewest,
                           where=where, line=line)
        t, renamed, segments, step = clock.t, clock.columns, clock.segments, clock.step
        notes += clock.notes
        samples = len(t)
    check_clock(step, samples, where, warn=dt is None)  # every log: one it differentiates, one it takes as it is
    q = stack_joint_columns(renamed, "q", model.joint_names)
    qd, qdd = np.empty_like(q), np.empty_like(q)
    derived_qd, derived_qdd = plan.derived_kind("qd"), plan.derived_kind("qdd")
    for j in model.joint_names:
        i = model.joint_names.index(j)
        if j not in derived_qd:
            qd[:, i] = renamed[f"qd_{j}"]
        qdd[:, i] = np.nan if j in derived_qdd else renamed[f"qdd_{j}"]
    sigma_qdd = np.zeros_like(q)
    if derived or needs == "qd":  # a motion to differentiate or to follow (a full-state log may list unrelated states)
        _check_rate_units(model, plan, q, qd, step, where, segments)
    if derived:
        sigma_qdd, found = _differentiate(model, plan, q, qd, qdd, segments, step, window, where)
        notes += found
    for name, value in plan.constants.items():
        notes.append(f"{name} = {value:g} throughout (not in the log)")
    measured, measured_from, more = _measured(model, plan, renamed, samples, torque_constants, where)
    return JointLog(t=t, q=q, qd=qd, qdd=qdd, notes=tuple(notes + more), measured=measured,
                    measured_from=measured_from, segments=segments, sigma_qdd=sigma_qdd)


#: How far (rad or m) a mimic joint's own logged position may stray from multiplier · q_leader + offset before a
#: note says so: well above encoder noise, well below a coupling that does not hold.
MIMIC_TOLERANCE = 1e-3


def _mimic_notes(model, source, renamed: dict, samples: int) -> list[str]:
    """A mimic joint's position in the log, where it has one, checked against its leader's (it is never read)."""
    notes = []
    for body, (j, a, b) in zip(model.bodies, model.coupling):
        name = f"q_{body.joint}"
        column = source.mimics.get(name, name if source.format == "table" else None)
        leader = renamed.get(f"q_{model.joint_names[j]}")
        if not body.mimic or column not in source.columns or leader is None:
            continue
        logged = np.asarray(source.columns[column], dtype=float)
        if logged.shape != (samples,):
            continue
        gap = np.abs(logged - (a * np.asarray(leader, dtype=float) + b))
        worst = int(np.nanargmax(gap)) if np.isfinite(gap).any() else 0
        coupling = f"{a:g} * q_{model.joint_names[j]} {'-' if b < 0 else '+'} {abs(b):g}"
        if not np.all(gap <= MIMIC_TOLERANCE):
            notes.append(f"{column} (joint '{body.joint}' mimics '{model.joint_names[j]}') is not "
                         f"{coupling}: off by {gap[worst]:.3g} at {source.line(worst)}; it is not read, the joint "
                         "follows the coupling")
        else:
            notes.append(f"{column}: joint '{body.joint}' mimics '{model.joint_names[j]}' ({coupling}, within "
                         f"{MIMIC_TOLERANCE:g} throughout): not read")
    return notes


def _check_rate_units(model, plan, q, qd, step, where, segments=()) -> None:
    """A logged Θ̇ must be the rate of the logged Θ: one in deg/s, or a t in other units, is refused by name.

    A difference across a gap (from one of ``segments`` to the next) is no rate, and is left out."""
    if step <= 0 or len(q) < 20:  # a handful of rows cannot tell units apart (and other checks speak first)
        return
    # differences over several samples (little noise), but within a short time: a stride of a sizeable part of a
    # long log's period would compare the logged rate with an aliased slope
    stride = max(1, min(len(q) // 200, int(RATE_CHECK_SPAN / (2 * step))))
    piece = np.zeros(len(q), dtype=int)
    for number, (start, stop) in enumerate(segments):
        piece[start:stop] = number
    within = piece[2 * stride:] == piece[:-2 * stride]        # the differences that stay within one segment
    if not within.any():
        return
    for i, j in enumerate(model.joint_names):
        if f"qd_{j}" not in plan.read or f"q_{j}" not in plan.read:
            continue
        slope = ((q[2 * stride:, i] - q[:-2 * stride, i]) / (2 * stride * step))[within]
        logged = qd[stride:len(q) - stride, i][within]
        moving, rate = float(np.sqrt(np.mean(slope**2))), float(np.sqrt(np.mean(logged**2)))
        if max(moving, rate) < 1e-3 or min(moving, rate) == 0:
            continue
        ratio = rate / moving
        if not 1 / RATE_UNITS_RATIO < ratio < RATE_UNITS_RATIO:
            raise InputError(f"{where}: the logged qd_{j} is {ratio:.3g} times the rate of q_{j} "
                             f"(RMS {rate:.3g} against "
                             f"{moving:.3g} per s): are they in the same units (rad and rad/s; 57.3 is degrees), "
                             f"and t in seconds (--time-unit)?")


def _differentiate(model, plan, q, qd, qdd, segments, step, window, where) -> tuple[np.ndarray, list[str]]:
    """Fill the derived columns of ``qd`` and ``qdd`` in place, segment by segment
    (:mod:`~course_dynamics.tools.differentiation`): σ_Θ̈ (K, n) that the noise leaves (0 where Θ̈ was read), and the
    notes saying how."""
    names = model.joint_names
    sigma = np.zeros_like(q)
    groups = [(plan.derived_kind("qd"), None), (plan.derived_kind("qdd", "qd"), "qd")]
    notes = []
    for joints, given in groups:
        if not joints:
            continue
        columns = [names.index(j) for j in joints]
        suffix = "" if len(joints) == model.n else f" (joints {', '.join(joints)})"
        for number, (start, stop) in enumerate(segments):
            rows = slice(start, stop)
            found = derivatives(step, q[rows][:, columns], None if given is None else qd[rows][:, columns], window,
                                where=where)
            qdd[rows, columns] = found.qdd
            sigma[rows, columns] = found.sigma_qdd
            if given is None:
                qd[rows, columns] = found.qd
            if number == 0:  # the first segment's choices speak for all (each segment chose its own windows)
                notes += [n + suffix if n.startswith(("qd:", "qdd:")) else n for n in found.notes]
    if len(segments) > 1:
        notes.append(f"windows chosen per segment ({len(segments)} segments); the notes above are the first's")
    return sigma, notes


def _as_list(value) -> list:
    if value is None:
        return []
    return list(value) if isinstance(value, (list, tuple)) else [value]


def torques_from_log(model: Model, table, *, dt: float | None = None, columns: Mapping[str, str] | None = None,
                     window: int | None = None, constants: Mapping[str, float] | None = None, time_unit: str = "s",
                     friction: Friction | None = None, payload=None, wrench=None,
                     compiled: bool | None = None, resample: float | None = None, split_gaps: bool = False,
                     repair: bool = False,
                     torque_constants=None, progress=None, drives: Drives | None = None) -> TorqueLog:
    """The joint torques a logged motion needs, whether they and its rates stay within the URDF's limits,
    and, when the log holds what the robot measured, how far those are from ours.

    τ = M(Θ)Θ̈ + V(Θ,Θ̇) + G(Θ) (Newton–Euler, (6.45)–(6.53)) + F(Θ̇) (friction, (6.114)) + Iₐ Θ̈ + τ₀ (drives)
    + Σ Jᵀ F_ext (wrenches at frames, chapter 5's static forces), on the model (under its gravity:
    ``model.with_gravity(g)`` to change it) with every ``payload`` lumped in. ``payload``: a
    :class:`~course_dynamics.tools.loads.Payload` or a list of them; ``wrench``: a
    :class:`~course_dynamics.tools.loads.Wrench` or a list.
    ``compiled``: None lets the evaluator (:mod:`course_dynamics.core.evaluator`) choose once for the log
    (a compiled model where the cache holds it or from about 20 000 rows); True/False force it.
    ``progress(done, total)``, if given, is called as the work goes: the state read and differentiated counts
    K of the 3 K steps of a K-row log, the torques and their uncertainty K each. Other parameters as
    :func:`joint_log`.

    Returns a :class:`TorqueLog`: ``tau`` (N, n); ``log`` with ``t``, ``q``, ``qd``, ``qdd`` as
    used; ``report`` (:class:`~course_dynamics.tools.limits.LimitsReport`); ``residuals``
    (:class:`~course_dynamics.tools.residuals.ResidualReport`, or None); ``notes``; ``table()``.

    Parameters
    ----------
    model : Model
        The robot.
    table : LogSource or table
        A log, as :func:`joint_log` takes.
    dt : float, optional
        The sample step of a log without a ``t`` column, s.
    columns : mapping of str to str, optional
        Our column name → the log's.
    window : int, optional
        The Savitzky–Golay window in samples, odd (default: about 20 ms).
    constants : mapping of str to float, optional
        Our column name → a value for every row, for signals the log lacks.
    time_unit : str
        The unit of the log's ``t`` column: s, ms, us or ns.
    friction : Friction, optional
        Joint friction F(Θ̇) added to the torques (6.114).
    payload : Payload or list of Payload, optional
        Loads lumped into their links.
    wrench : Wrench or list of Wrench, optional
        External wrenches, whose Jᵀ F_ext is added.
    compiled : bool, optional
        Whether to use the compiled model; None lets the evaluator choose.
    resample : float, optional
        Put the log on an even clock at this rate first, Hz.
    split_gaps : bool
        Differentiate the pieces between long gaps apart instead of refusing them.
    repair : bool
        Resample, split and drop what the clock needs, at once, as :func:`joint_log` does.
    torque_constants : array_like, shape (n,), optional
        Turn logged motor currents into measured torques, N·m/A.
    progress : callable, optional
        Called as ``progress(done, total)`` as the work goes.
    drives : Drives, optional
        Rotor inertias and torque offsets (:class:`~course_dynamics.core.drives.Drives`), added as Iₐ Θ̈ + τ₀.

    Returns
    -------
    TorqueLog
        The torques (K, n), the state they were computed from, the limits report and the residuals.

    Raises
    ------
    InputError
        Whatever :func:`joint_log` refuses, a payload on a link fixed to the base, and torques that overflow.
    ModelError
        A payload's or wrench's link that is not one of the robot's.
    """
    for load in _as_list(payload):
        model = with_payload(model, load)
    log = joint_log(model, table, dt=dt, columns=columns, window=window, constants=constants, time_unit=time_unit,
                    resample=resample, split_gaps=split_gaps, repair=repair, torque_constants=torque_constants)
    if progress is not None:
        progress(len(log.t), 3 * len(log.t))
    run = implementation(model, calls=-(-len(log.t) // ROWS_AT_A_TIME), states=min(len(log.t), ROWS_AT_A_TIME),
                         compiled=compiled)  # chosen once for the whole log, its blocks all alike
    run = run if drives is None else Driven(run, drives)
    pushes = _as_list(wrench)
    tau = np.empty_like(log.q)
    for start in range(0, len(log.t), ROWS_AT_A_TIME):
        rows = slice(start, start + ROWS_AT_A_TIME)
        q, qd = log.q[rows], log.qd[rows]
        block = run.inverse_dynamics(q, qd, log.qdd[rows])
        if friction is not None:
            block = block + friction.torques(qd)                     # (6.114)
        for push in pushes:
            block = block + wrench_torques(model, q, push)          # τ = Jᵀ F (chapter 5)
        tau[rows] = block
        if progress is not None:
            progress(len(log.t) + min(start + ROWS_AT_A_TIME, len(log.t)), 3 * len(log.t))
    if not np.all(np.isfinite(tau)):
        row = int(np.flatnonzero(~np.all(np.isfinite(tau), axis=1))[0])
        source = as_source(table)
        where = f"{source.line(row)} of {source.where}" if source.lines is not None else f"row {row + 1}"
        raise InputError(f"the torques overflow at t = {log.t[row]:.9g} s ({where}): the log's values there are too "
                         f"large to give finite torques")
    residuals = None if log.measured is None else residual_report(model.joint_names, log.t, tau, log.measured,
                                                                  log.measured_from)
    sigma = _torque_sigma(log, run, progress)
    if progress is not None:
        progress(3 * len(log.t), 3 * len(log.t))
    return TorqueLog(log=log, tau=tau, report=limits_report(model, log.t, log.qd, tau, sigma), model=model,
                     residuals=residuals, tau_sigma=sigma)


def _torque_sigma(log: JointLog, run, progress=None) -> np.ndarray | None:
    """σ_τ (K, n): what the noise left in a differentiated Θ̈ leaves in τ = M Θ̈ + …, σ_τᵢ = √Σⱼ (Mᵢⱼ σ_Θ̈ⱼ)².

    The noise a differentiated Θ̇ carries into V is left out: at the rates robots move, M Θ̈ is where it shows.
    None when nothing was differentiated. ``run``: the implementation the evaluator chose for the log.
    """
    if log.sigma_qdd is None or not np.any(log.sigma_qdd):
        return None
    sigma = np.empty_like(log.q)
    for start in range(0, len(log.t), ROWS_AT_A_TIME):
        rows = slice(start, start + ROWS_AT_A_TIME)
        M = run.mass_matrix(log.q[rows])
        sigma[rows] = np.sqrt(np.einsum("kij,kj->ki", M**2, log.sigma_qdd[rows] ** 2))
        if progress is not None:
            progress(2 * len(log.t) + min(start + ROWS_AT_A_TIME, len(log.t)), 3 * len(log.t))
    return sigma


__all__ = ["ROWS_AT_A_TIME", "JointLog", "TorqueLog", "joint_log", "torques_from_log"]

"""What a log says of a motion before anything is differentiated: the columns its plan reads, and its times.

Every reader of motion goes through here, so that every command reads the same logs the same way:
:func:`~course_dynamics.tools.logs.joint_log` (``torques``, ``identify``: Θ, Θ̇, Θ̈ and what the robot
measured) and :func:`read_motion` (``animate``'s Θ(t), ``simulate``'s applied τ(t)). A log is anything
:func:`~course_dynamics.tools.sources.as_source` takes: what :func:`~course_dynamics.tools.sources.open_log`
reads (a delimited table, a UR RTDE recording, a ROS bag or MCAP file) or a table in memory, and so also
what ``torques --out``, ``simulate --out`` and ``excite --out`` write. Columns none of ours are ignored.

==================  =============  ===================================================
code                Craig          meaning (shape, unit)
==================  =============  ===================================================
``t``               t              sample times (K,), s
``q``               Θ              joint positions (K, n), rad or m
``tau``             τ              applied joint torques (K, n), N·m or N: ``tau_<joint>``,
                                   or else what the robot measured, ``tau_meas_<joint>``
==================  =============  ===================================================

>>> import numpy as np
>>> from course_dynamics import load_robot
>>> log = {"t": [0.0, 0.1], "q_theta1": [0.0, 0.1], "q_theta2": [0.2, 0.3], "tau_theta1": [1.0, 2.0],
...        "tau_theta2": [0.5, 0.5], "tau_meas_theta1": [1.1, 2.1], "energy": [3.0, 3.0]}
>>> motion = read_motion(load_robot("two_link"), log)
>>> motion.q.shape, motion.tau[:, 0].tolist(), motion.tau_from
((2, 2), [1.0, 2.0], 'tau')
"""
from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..base.errors import CourseDynamicsWarning, InputError
from ..core.model import Model
from .columns import ColumnPlan, merged_map, plan_columns
from .sources import LogSource, as_source
from .tables import stack_joint_columns

#: The units a log's ``t`` column may be in, each with its length in seconds.
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}
#: The longest sample step (seconds) read without a warning; a longer one suggests t in ms read as seconds.
SLOW_SAMPLES = 0.5
#: The sample steps a log may have, s (the ends included).
STEPS = (1e-9, 1e6)


def check_clock(step: float, samples: int, where: str, warn: bool = True) -> None:
    """The one check of a log's sample step, for every reader: outside :data:`STEPS` is an error (t is not in
    seconds), beyond :data:`SLOW_SAMPLES` a warning (``warn``: the step came from the log's own t).

    Parameters
    ----------
    step : float
        The sample step, s (the median, or the even clock's).
    samples : int
        How many samples the log has (one has no step).
    where : str
        How messages name the log.
    warn : bool
        Whether a slow clock is warned about.

    Raises
    ------
    InputError
        If the step is outside 1e-9 s to 1e6 s.

    Examples
    --------
    >>> check_clock(0.004, 500, "log.csv")
    >>> check_clock(4.0, 500, "log.csv", warn=False)
    >>> check_clock(4e297, 500, "log.csv")
    Traceback (most recent call last):
    course_dynamics.base.errors.InputError: log.csv: the sample step 4e+297 s is outside 1e-9 s to 1e6 s;
    is t in seconds (time_unit, --time-unit)?
    """
    if samples < 2:
        return
    if not STEPS[0] * (1 - 1e-9) <= step <= STEPS[1] * (1 + 1e-9):  # the ends, within a clock's round-off
        raise InputError(f"{where}: the sample step {step:g} s is outside 1e-9 s to 1e6 s; is t in "
                         "seconds (time_unit, --time-unit)?")
    if warn and step > SLOW_SAMPLES:
        warnings.warn(f"{where}: the samples are {step:g} s apart; if t is not in seconds, give --time-unit",
                      CourseDynamicsWarning)


@dataclass(frozen=True)
class Planned:
    """A log's columns as the plan reads them: ``values`` by our names (read, set constant, or held at zero)."""

    source: LogSource
    plan: ColumnPlan
    values: dict
    samples: int


@dataclass(frozen=True)
class Motion:
    """Times, positions (or None) and applied torques (or None) of a logged motion; ``tau_from`` names the columns.

    Parameters
    ----------
    t : numpy.ndarray, shape (K,)
        Sample times, s.
    q : numpy.ndarray, shape (K, n), optional
        Joint positions Θ, rad (m for a prismatic joint); None when not read.
    tau : numpy.ndarray, shape (K, n), optional
        Applied joint torques τ, N·m (N for a prismatic joint); None when the log has none.
    where : str
        How messages name the log (its file).
    tau_from : str
        The columns τ came from: ``tau``, ``tau_meas``, or empty.
    notes : tuple of str
        What the reader should know of the log.
    format : str
        The source's format: ``table``, ``ur-rtde`` or ``bag`` (whose clocks are the recorder's wall clock).
    """

    t: np.ndarray
    q: np.ndarray | None
    tau: np.ndarray | None
    where: str
    tau_from: str = ""
    notes: tuple[str, ...] = ()
    format: str = "table"   # the source's: table, ur-rtde or bag (whose clocks are the recorder's wall clock)


def check_time_unit(source: LogSource, time_unit: str) -> None:
    if time_unit not in TIME_UNITS:
        raise InputError(f"unknown time unit '{time_unit}' (choose from {', '.join(TIME_UNITS)})")
    clocks = {"bag": "a bag log's times are in seconds", "ur-rtde": "a ur-rtde log's times are in seconds",
              "rostopic": "a rostopic CSV's stamps are read as nanoseconds",
              "plotjuggler": "a PlotJuggler CSV's __time is in seconds"}
    if time_unit != "s" and source.format in clocks:
        raise InputError(f"{source.where}: {clocks[source.format]}; --time-unit is for tables")


def planned_columns(model: Model, log, *, columns: Mapping[str, str] | None = None,
                    constants: Mapping[str, float] | None = None, applied: bool = False) -> Planned:
    """The plan for ``log`` and the columns it reads, checked for words and equal lengths (no value checked yet).

    ``applied``: the log's ``tau_<joint>`` columns are read too (applied torques).
    """
    source = as_source(log)
    data, where = source.columns, source.where
    plan = plan_columns(model, list(data) + list(source.text), columns=merged_map(source.implied, columns),
                        constants=constants, where=where, applied=applied)
    for name, theirs in plan.read.items():
        if theirs in source.text:
            raise source.not_numbers(theirs, name)
    values = {name: data[theirs] for name, theirs in plan.read.items()}
    lengths = {len(v) for v in values.values()}
    if len(lengths) > 1:
        raise InputError(f"{where}: columns have different lengths {sorted(lengths)}")
    samples = lengths.pop() if lengths else 0
    for name, value in plan.constants.items():
        values[name] = np.full(samples, float(value))
    for name in plan.held:  # a joint held still: its rates are zero
        values[name] = np.zeros(samples)
    return Planned(source, plan, values, samples)


def check_values(planned: Planned) -> None:
    """At least one row, and every value finite (an error names the first bad cell's line and column)."""
    source, plan = planned.source, planned.plan
    if planned.samples == 0:
        raise InputError(f"{source.where}: no data rows")
    for name, values in planned.values.items():
        bad = np.flatnonzero(~np.isfinite(values))
        if len(bad):
            raise InputError(f"{source.where}: {source.line(bad[0])}, column '{plan.read.get(name, name)}': value is "
                             f"{values[bad[0]]} (must be finite)")


def log_times(planned: Planned, dt: float | None, time_unit: str) -> np.ndarray:
    """The log's times in seconds, increasing: its ``t`` column (removed from ``values``), or ``dt`` apart."""
    source, where, line = planned.source, planned.source.where, planned.source.line
    if planned.plan.has_time:
        if dt is not None:
            raise InputError(f"{where} has a time column; dt (--log-dt) is only for logs without one")
        t = planned.values.pop("t") * TIME_UNITS[time_unit]
        steps = np.diff(t)
        if np.any(steps <= 0):
            row = int(np.flatnonzero(steps <= 0)[0]) + 1
            raise InputError(f"{where}: {line(row)}: t = {t[row]:.9g} s does not come after {t[row - 1]:.9g} s "
                             f"(t must increase)")
        return t
    if dt is None:
        raise InputError(f"{where}: no column 't' (map one, or give the sample step dt (--log-dt) for a log "
                         f"without times)")
    if not (np.isfinite(dt) and dt > 0):
        raise InputError(f"dt must be a positive number of seconds, got {dt}")
    return np.arange(planned.samples) * float(dt)


def read_motion(model: Model, log, *, columns: Mapping[str, str] | None = None,
                constants: Mapping[str, float] | None = None, dt: float | None = None, time_unit: str = "s",
                positions: bool = True, torques: bool = False) -> Motion:
    """Times, and Θ (``positions``) and the applied τ of ``model``'s joints, from a log.

    τ is the log's ``tau_<joint>`` columns when it has them (else None); with ``torques`` it is needed, and a
    log without them gives what the robot measured (``tau_meas_<joint>``, a bag's effort). Nothing is
    differentiated, filled or resampled.
    ``columns``, ``constants``, ``dt``, ``time_unit`` as :func:`~course_dynamics.tools.logs.joint_log`.

    Parameters
    ----------
    model : Model
        The robot.
    log : LogSource or table
        A log, anything :func:`~course_dynamics.tools.sources.as_source` takes.
    columns : mapping of str to str, optional
        Our column name → the log's.
    constants : mapping of str to float, optional
        Our column name → a value for every row, for signals the log lacks.
    dt : float, optional
        The sample step of a log without a ``t`` column, s.
    time_unit : str
        The unit of the log's ``t`` column, one of :data:`TIME_UNITS`.
    positions : bool
        Whether Θ is read (and needed).
    torques : bool
        Whether τ is needed (the measured torques stand in for applied ones).

    Returns
    -------
    Motion
        The times, Θ and τ, and the notes.

    Raises
    ------
    InputError
        A needed column missing or holding words, a value not finite, no rows, t not increasing.
    """
    source = as_source(log)
    check_time_unit(source, time_unit)
    planned = planned_columns(model, source, columns=columns, constants=constants, applied=True)
    plan, values, joints = planned.plan, planned.values, model.joint_names
    if positions:
        plan.require_positions(source.where)
    tau_from = "tau" if all(f"tau_{j}" in values for j in joints) else ""
    if torques and not tau_from:
        tau_from = "tau_meas"
        if not all(f"tau_meas_{j}" in values for j in joints):
            missing = [f"tau_{j}" for j in joints if f"tau_{j}" not in values]
            raise InputError(f"{source.where}: missing columns: {', '.join(missing)} "
                             "(the torques to apply: tau_<joint> "
                             "as 'torques --out', 'simulate --out' and 'excite --out' write them, or the torques a "
                             "robot measured: tau_meas_<joint>, a bag's effort)")
    check_values(planned)
    t = log_times(planned, dt, time_unit)
    check_clock(float(np.median(np.diff(t))) if len(t) > 1 else 0.0, len(t), source.where, warn=dt is None)
    q = stack_joint_columns(values, "q", joints) if positions else None
    tau = stack_joint_columns(values, tau_from, joints) if tau_from else None
    notes = list(source.notes)
    if tau_from == "tau_meas":
        notes.append("the applied torques are the ones the robot measured (tau_meas, a bag's effort)")
    return Motion(t=t, q=q, tau=tau, where=source.where, tau_from=tau_from, notes=tuple(notes), format=source.format)


__all__ = ["SLOW_SAMPLES", "STEPS", "TIME_UNITS", "Motion", "check_clock", "read_motion"]

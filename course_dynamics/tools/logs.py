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

A log is any table of numbers with named columns: a file read by
:func:`course_dynamics.tools.tables.read_table`, a pandas DataFrame, a dict of arrays or
a numpy structured array. Our names are ``t``, ``q_<joint>``, ``qd_<joint>`` and
``qdd_<joint>``; ``columns`` maps ours to the log's (``{"q_shoulder_pan_joint":
"joint1_pos"}``), and every other column of the log is ignored.

Positions only: when a log has no ``qd_`` (or no ``qdd_``) columns, they are
differentiated from Θ(t) by a Savitzky–Golay filter (scipy): a cubic fitted by
least squares to a window of samples around each one, differentiated exactly.
It smooths as it differentiates, which plain finite differences of a measured
signal do not (they amplify its noise by 1/Δt, and Θ̈ by 1/Δt²). The window
(odd, in samples) is ``window``; by default the odd count nearest to 20 ms of
samples, and at least 7. The samples must be evenly spaced (within 10 % of the
median step). What was differentiated is said in :attr:`TorqueLog.notes`, and
the CLI writes it at the top of its output.

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

import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..base.errors import InputError
from ..base.files import read_small
from ..core.evaluator import implementation
from ..core.friction import Friction
from ..core.model import Model
from ..core.newton_euler import inverse_dynamics
from .limits import LimitsReport, limits_report
from .loads import with_payload, wrench_torques
from .columns import KINDS, plan_columns
from .tables import Table, joint_columns, stack_joint_columns

POLYORDER = 3                 # a cubic: Θ̈ is its second derivative, still linear in time within a window
DEFAULT_WINDOW_SECONDS = 0.02
MIN_WINDOW = 7
MAX_MAP_BYTES = 2**20         # a column map of a thousand joints is under 100 kB
EVEN_SPACING = 0.1            # largest deviation of a step from the median step, relative
# τ is computed this many rows at a time: the recursion's temporaries (for the UR5 about 1.6 kB a row
# interpreted, 0.5 kB compiled, measured with tracemalloc) then stay under 60 MB however long the log.
ROWS_AT_A_TIME = 2**15


@dataclass(frozen=True)
class JointLog:
    """Θ, Θ̇, Θ̈ on the samples of a log; ``notes`` says what was computed rather than read."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    notes: tuple[str, ...] = ()


@dataclass(frozen=True)
class TorqueLog:
    """The torques a log needs, the state they were computed from, and the limits report."""

    log: JointLog
    tau: np.ndarray
    report: LimitsReport
    model: Model

    @property
    def t(self) -> np.ndarray:
        return self.log.t

    @property
    def notes(self) -> tuple[str, ...]:
        return self.log.notes

    def table(self, with_state: bool = False) -> tuple[list[str], np.ndarray]:
        """Header and rows: t, tau_<joint> (and q_, qd_, qdd_ with ``with_state``)."""
        kinds = (KINDS if with_state else ()) + ("tau",)
        header = ["t"] + joint_columns(kinds, self.model.joint_names)
        blocks = [getattr(self.log, k) for k in kinds[:-1]] + [self.tau]
        return header, np.column_stack([self.t] + blocks)


def as_columns(table) -> tuple[dict[str, np.ndarray], str]:
    """Named 1-D float columns of a table, and a name for it in messages.

    Takes an :class:`Table`, a pandas DataFrame, a dict of arrays or a numpy structured array.
    """
    if isinstance(table, Table):
        return table.columns(), table.path
    if isinstance(table, np.ndarray) and table.dtype.names:
        return {name: np.asarray(table[name], dtype=float) for name in table.dtype.names}, "the table"
    if hasattr(table, "columns") and hasattr(table, "__getitem__") and not isinstance(table, Mapping):
        return {str(name): np.asarray(table[name], dtype=float) for name in table.columns}, "the table"  # pandas
    if isinstance(table, Mapping):
        try:
            return {str(k): np.asarray(v, dtype=float).reshape(-1) for k, v in table.items()}, "the table"
        except (TypeError, ValueError) as exc:
            raise InputError(f"the table's columns must be numbers: {exc}") from None
    raise InputError(f"a log must be a table with named columns (a DataFrame, a dict of arrays, a structured array), "
                     f"got {type(table).__name__}")


def parse_column_map(text: str) -> dict[str, str]:
    """``ours=theirs,…`` or the path of a TOML file of ``ours = "theirs"`` lines (optionally under ``[columns]``)."""
    if text.endswith(".toml") or (Path(text).is_file() and "=" not in text):
        try:
            document = tomllib.loads(read_small(text, MAX_MAP_BYTES, "column map").decode("utf-8"))
        except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
            raise InputError(f"{text}: not a valid TOML column map: {exc}") from None
        document = document.get("columns", document)
        if not all(isinstance(v, str) for v in document.values()):
            raise InputError(f"{text}: every entry must be ours = \"theirs\" (a column name in quotes)")
        return dict(document)
    mapping = {}
    for item in filter(None, (part.strip() for part in text.split(","))):
        ours, sep, theirs = item.partition("=")
        if not sep or not ours.strip() or not theirs.strip():
            raise InputError(f"column map entry '{item}' must be ours=theirs, e.g. q_joint1=joint1_pos")
        if ours.strip() in mapping:
            raise InputError(f"column map: '{ours.strip()}' is mapped twice")
        mapping[ours.strip()] = theirs.strip()
    return mapping


def _window(samples: int, dt: float, window: int | None, where: str) -> int:
    if window is not None:
        if window < POLYORDER + 2 or window % 2 == 0:
            raise InputError(f"the smoothing window must be an odd number of samples, at least {POLYORDER + 2}; got {window}")
        if window > samples:
            raise InputError(f"{where}: the smoothing window ({window} samples) is longer than the log ({samples} rows)")
        return window
    chosen = max(MIN_WINDOW, 2 * int(round(DEFAULT_WINDOW_SECONDS / dt / 2)) + 1)
    chosen = min(chosen, samples if samples % 2 else samples - 1)
    if chosen < POLYORDER + 2:
        raise InputError(f"{where}: {samples} rows are too few to differentiate (at least {POLYORDER + 2} are needed)")
    return chosen


def _even_step(t: np.ndarray, where: str, line) -> float:
    steps = np.diff(t)
    dt = float(np.median(steps))
    worst = int(np.argmax(np.abs(steps - dt)))
    if abs(steps[worst] - dt) > EVEN_SPACING * dt:
        raise InputError(f"{where}: t is not evenly spaced (the step before {line(worst + 1)} is {steps[worst]:.6g} s, "
                         f"the median step is {dt:.6g} s); differentiating needs even steps: resample the log, "
                         f"or give qd_ and qdd_ columns")
    return dt


TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}


def joint_log(model: Model, table, *, dt: float | None = None, columns: Mapping[str, str] | None = None,
              window: int | None = None, constants: Mapping[str, float] | None = None,
              time_unit: str = "s") -> JointLog:
    """Θ, Θ̇, Θ̈ of ``model``'s joints from a log (module docstring).

    Parameters
    ----------
    table : a log (see :func:`as_columns`)
    dt : float, s — the sample step of a log without a ``t`` column
    columns : our column name → the log's
    window : odd int — Savitzky–Golay window in samples (default: about 20 ms)
    constants : our column name → a value for every row, for signals the log lacks
        (e.g. ``{"q_panda_finger_joint1": 0.04}``; a constant q has zero rates)
    time_unit : the unit of the log's ``t`` column: s, ms, us or ns

    Raises
    ------
    InputError
        A mapped or needed column that is missing, a column of the wrong length, two of our
        columns mapped to one of the log's, t not increasing or unevenly spaced, a bad ``dt``,
        time unit or window.
    """
    data, where = as_columns(table)
    lines = table.lines if isinstance(table, Table) else None

    def line(row: int) -> str:
        return f"line {int(lines[row])}" if lines is not None else f"row {row + 1}"

    if time_unit not in TIME_UNITS:
        raise InputError(f"unknown time unit '{time_unit}' (choose from {', '.join(TIME_UNITS)})")
    plan = plan_columns(model, data, columns=columns, constants=constants, where=where)
    renamed = {name: data[theirs] for name, theirs in plan.read.items()}
    lengths = {len(v) for v in renamed.values()}
    if len(lengths) > 1:
        raise InputError(f"{where}: columns have different lengths {sorted(lengths)}")
    samples = lengths.pop() if lengths else 0
    for name, value in plan.constants.items():
        renamed[name] = np.full(samples, float(value))
    for name in plan.held:  # a joint held still: its rates are zero
        renamed[name] = np.zeros(samples)
    plan.require_positions(where)
    q = stack_joint_columns(renamed, "q", model.joint_names)
    if samples == 0:
        raise InputError(f"{where}: no data rows")
    for name, values in renamed.items():
        bad = np.flatnonzero(~np.isfinite(values))
        if len(bad):
            raise InputError(f"{where}: {line(bad[0])}, column '{plan.read.get(name, name)}': value is {values[bad[0]]} "
                             f"(must be finite)")

    if plan.has_time:
        if dt is not None:
            raise InputError(f"{where} has a time column; dt (--dt) is only for logs without one")
        t = renamed["t"] * TIME_UNITS[time_unit]
        steps = np.diff(t)
        if np.any(steps <= 0):
            row = int(np.flatnonzero(steps <= 0)[0]) + 1
            raise InputError(f"{where}: {line(row)}: t = {t[row]:.9g} s does not come after {t[row - 1]:.9g} s "
                             f"(t must increase)")
    else:
        if dt is None:
            raise InputError(f"{where}: no column 't' (map one, or give the sample step dt (--dt) for a log without "
                             f"times)")
        if not (np.isfinite(dt) and dt > 0):
            raise InputError(f"dt must be a positive number of seconds, got {dt}")
        t = np.arange(samples) * float(dt)

    notes = []
    derived_qd, derived_qdd = plan.derived_kind("qd"), plan.derived_kind("qdd")
    qd = np.empty_like(q)
    qdd = np.empty_like(q)
    if plan.derived:
        from scipy.signal import savgol_filter  # scipy's import takes 0.2 s: only logs that need differentiating pay it

        if samples < 2:
            raise InputError(f"{where}: one row cannot be differentiated (give qd_ and qdd_ columns)")
        step = _even_step(t, where, line) if plan.has_time else float(dt)
        w = _window(samples, step, window, where)
        how = f"Savitzky-Golay derivative ({w}-sample window = {w * step:.4g} s, cubic)"

        if not 1e-9 <= step <= 1e6:
            raise InputError(f"{where}: the sample step {step:g} s is outside 1e-9 s to 1e6 s; is t in seconds "
                             f"(time_unit, --time-unit)?")

        def derivative(y, order):
            with np.errstate(all="ignore"):
                values = savgol_filter(y, w, POLYORDER, deriv=order, delta=step, axis=0, mode="interp")
            if not np.all(np.isfinite(values)):
                raise InputError(f"{where}: differentiating q gives values beyond floating-point range")
            return values

    def which(joints):
        return "" if len(joints) == model.n else f" (joints {', '.join(joints)})"

    for i, j in enumerate(model.joint_names):
        qd[:, i] = derivative(q[:, i], 1) if j in derived_qd else renamed[f"qd_{j}"]
        if j not in derived_qdd:
            qdd[:, i] = renamed[f"qdd_{j}"]
        else:
            qdd[:, i] = derivative(q[:, i], 2) if j in derived_qd else derivative(qd[:, i], 1)
    if derived_qd:
        notes.append(f"qd: first {how} of q{which(derived_qd)}")
    from_q, from_qd = plan.derived_kind("qdd", "q"), plan.derived_kind("qdd", "qd")
    if from_q:
        notes.append(f"qdd: second {how} of q{which(from_q)}")
    if from_qd:
        notes.append(f"qdd: first {how} of qd{which(from_qd)}")
    for name, value in plan.constants.items():
        notes.append(f"{name} = {value:g} throughout (not in the log)")
    return JointLog(t=t, q=q, qd=qd, qdd=qdd, notes=tuple(notes))


def _as_list(value) -> list:
    if value is None:
        return []
    return list(value) if isinstance(value, (list, tuple)) else [value]


def torques_from_log(model: Model, table, *, dt: float | None = None, columns: Mapping[str, str] | None = None,
                     window: int | None = None, constants: Mapping[str, float] | None = None, time_unit: str = "s",
                     friction: Friction | None = None, payload=None, wrench=None,
                     compiled: bool | None = None) -> TorqueLog:
    """The joint torques a logged motion needs, and whether they and its rates stay within the URDF's limits.

    τ = M(Θ)Θ̈ + V(Θ,Θ̇) + G(Θ) (Newton–Euler, (6.45)–(6.53)) + F(Θ̇) (friction, (6.114))
    + Σ Jᵀ F_ext (wrenches at frames, chapter 5's static forces), on the model (under its gravity:
    ``model.with_gravity(g)`` to change it) with every ``payload`` lumped in. ``payload``: a :class:`~course_dynamics.tools.loads.Payload`
    or a list of them; ``wrench``: a :class:`~course_dynamics.tools.loads.Wrench` or a list.
    ``compiled``: None lets the evaluator (:mod:`course_dynamics.core.evaluator`) choose by the log's
    length (a compiled model from about 20 000 rows, or sooner once this process has done that much work
    on the model); True/False force it. Other parameters as :func:`joint_log`.

    Returns a :class:`TorqueLog`: ``tau`` (N, n); ``log`` with ``t``, ``q``, ``qd``, ``qdd`` as
    used; ``report`` (:class:`~course_dynamics.tools.limits.LimitsReport`); ``notes``; ``table()``.
    """
    for load in _as_list(payload):
        model = with_payload(model, load)
    log = joint_log(model, table, dt=dt, columns=columns, window=window, constants=constants, time_unit=time_unit)
    fast = implementation(model, calls=-(-len(log.t) // ROWS_AT_A_TIME), states=min(len(log.t), ROWS_AT_A_TIME),
                          compiled=compiled)

    def dynamics(q, qd, qdd):
        return fast.inverse_dynamics(q, qd, qdd) if fast is not None else inverse_dynamics(model, q, qd, qdd)
    pushes = _as_list(wrench)
    tau = np.empty_like(log.q)
    for start in range(0, len(log.t), ROWS_AT_A_TIME):
        rows = slice(start, start + ROWS_AT_A_TIME)
        q, qd = log.q[rows], log.qd[rows]
        block = dynamics(q, qd, log.qdd[rows])
        if friction is not None:
            block = block + friction.torques(qd)                     # (6.114)
        for push in pushes:
            block = block + wrench_torques(model, q, push)          # τ = Jᵀ F (chapter 5)
        tau[rows] = block
    if not np.all(np.isfinite(tau)):
        row = int(np.flatnonzero(~np.all(np.isfinite(tau), axis=1))[0])
        where = f"line {int(table.lines[row])} of {table.path}" if isinstance(table, Table) else f"row {row + 1}"
        raise InputError(f"the torques overflow at t = {log.t[row]:.9g} s ({where}): the log's values there are too "
                         f"large to give finite torques")
    return TorqueLog(log=log, tau=tau, report=limits_report(model, log.t, log.qd, tau), model=model)

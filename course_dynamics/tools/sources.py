"""Where a log comes from: a table, a UR RTDE recording, a ROS CSV export or a ROS bag, read into one shape.

================  =================================================================================
format            what is read, and how its columns become ours
================  =================================================================================
``table``         a delimited table (:func:`~course_dynamics.tools.tables.read_table`): comma,
                  semicolon, tab or whitespace; our column names, or a map to them
``ur-rtde``       a UR controller's RTDE recording (``record.py`` writes it space separated):
                  ``timestamp`` (s of the controller's uptime) → t from the log's start, ``actual_q_i`` → Θ,
                  ``actual_qd_i`` → Θ̇ and ``actual_current_i`` → the motor currents, i = 0, 1, … the URDF's
                  i-th joint
``rostopic``      ``rostopic echo -p`` of a ``sensor_msgs/JointState`` topic: ``field.header.stamp`` (ns; ``%time``,
                  the receive time, when unstamped) → t from the log's start, ``field.positionK``,
                  ``field.velocityK``, ``field.effortK`` → Θ, Θ̇ and the measured torque of the joint named
                  in ``field.nameK``, matched to the URDF by name; other columns (``field.header.frame_id``,
                  empty) are not read
``plotjuggler``   PlotJuggler's CSV export: ``__time`` (s since the epoch) → t from the log's start,
                  ``<topic>/<joint>/position``, ``…/velocity``, ``…/effort`` → Θ, Θ̇ and the measured
                  torque by joint name; an empty cell is a series without a sample at that time, and a
                  row missing one of the columns read is left out
``bag``           a ROS 1 bag, a ROS 2 bag (sqlite3 or MCAP) or an MCAP file: ``sensor_msgs/JointState``
                  matched by joint name (``effort`` is the measured torque) or Franka's
                  ``franka_msgs/FrankaState`` (``q``, ``dq``, ``tau_J``) (:mod:`~course_dynamics.tools.bags`)
``auto``          a bag by its file; a table whose header has ``timestamp`` and ``actual_q_0`` … is
                  an RTDE recording, ``%time`` and ``field.name0`` a rostopic CSV, ``__time`` first a
                  PlotJuggler CSV; any other table is a table
================  =================================================================================

Every source gives a :class:`LogSource`: the log's own columns, the map from our names to them
that its format implies (an explicit map from the user overrides it entry by entry), and how to
name a row in messages. A recorder's clock (of the epoch, of the controller's uptime) is read from the
log's start, and a note gives the stamp it started at; a table's own ``t`` is taken as it is. What happens
next — which columns are used (:mod:`~course_dynamics.tools.columns`), the clock
(:mod:`~course_dynamics.tools.resampling`), the derivatives — is the same for all.
"""
from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from dataclasses import dataclass, field, replace
import numpy as np

from ..base.errors import InputError
from ..core.model import Model
from .bags import is_bag, read_bag
from .tables import Table, read_table

#: The log formats :func:`open_log` reads (the table above).
FORMATS = ("auto", "table", "ur-rtde", "rostopic", "plotjuggler", "bag")
RTDE_SIGNALS = {"q": "actual_q", "qd": "actual_qd", "current": "actual_current"}
ROS_SIGNALS = {"q": "position", "qd": "velocity", "tau_meas": "effort"}   # ours → sensor_msgs/JointState's fields


@dataclass(frozen=True)
class LogSource:
    """A log's columns by its own names, the map its format implies, and where each row came from.

    Parameters
    ----------
    columns : dict
        {the log's column name: numpy.ndarray of shape (K,)}, in the log's units.
    where : str
        How messages name the log (its file).
    format : str
        ``table``, ``ur-rtde``, ``rostopic``, ``plotjuggler`` or ``bag``.
    implied : dict
        Our column names → the log's, as its format implies them.
    lines : numpy.ndarray, shape (K,), optional
        The file line of each row (tables); None otherwise.
    text : tuple of str
        The columns that hold words, not numbers (ignored unless used).
    notes : tuple of str
        What the reader should know of how the log was read.
    words : dict
        A text column → (line, its first cell), for messages.
    mimics : dict
        ``q_<joint>`` of a joint that mimics another → the log's column: not read (the joint follows its leader),
        only checked against the coupling (:func:`~course_dynamics.tools.logs.joint_log`).
    """

    columns: dict
    where: str
    format: str
    implied: dict = field(default_factory=dict)   # ours → theirs, from the format
    lines: np.ndarray | None = None                # the file line of each row (tables)
    text: tuple[str, ...] = ()                     # columns that hold words, not numbers (ignored unless used)
    notes: tuple[str, ...] = ()
    words: dict = field(default_factory=dict)      # a text column → (line, its first cell), for messages
    mimics: dict = field(default_factory=dict)     # q_<mimic joint> → the log's column: checked, not read

    def not_numbers(self, column: str, ours: str) -> InputError:
        """The error for a text column read as one of ours.

        Parameters
        ----------
        column : str
            The log's column.
        ours : str
            Our name it was read as.

        Returns
        -------
        InputError
            The error to raise, naming the line and the cell.
        """
        line, cell = self.words.get(column, (None, ""))
        at = f"line {line}, " if line is not None else ""
        return InputError(f"{self.where}: {at}column '{column}': '{cell}' is not a number (a column of words, read as "
                          f"{ours})")

    def line(self, row: int) -> str:
        """Row ``row`` (from 0) as a reader finds it: a file's line, a bag's message.

        Parameters
        ----------
        row : int
            The row, from 0.

        Returns
        -------
        str
            ``line 12``, ``message 3`` or ``row 3``.
        """
        if self.lines is not None:
            return f"line {int(self.lines[row])}"
        return f"message {row + 1}" if self.format == "bag" else f"row {row + 1}"


def rtde_map(model: Model, header, where: str) -> dict[str, str]:
    """Our names → an RTDE recording's: ``timestamp``, ``actual_q_i``, ``actual_qd_i``, ``actual_current_i``."""
    header = set(header)
    logged = 0
    while f"actual_q_{logged}" in header:
        logged += 1
    if "timestamp" not in header or logged == 0:
        raise InputError(f"{where}: not an RTDE recording (it needs the columns timestamp and actual_q_0, "
                         f"actual_q_1, …)")
    if logged != model.n:
        raise InputError(f"{where}: the recording has {logged} joints (actual_q_0 … actual_q_{logged - 1}), robot "
                         f"'{model.name}' has {model.n} ({', '.join(model.joint_names)})")
    mapping = {"t": "timestamp"}
    for i, joint in enumerate(model.joint_names):
        for ours, theirs in RTDE_SIGNALS.items():
            if f"{theirs}_{i}" in header:
                mapping[f"{ours}_{joint}"] = f"{theirs}_{i}"
    return mapping


def _looks_like_rtde(header) -> bool:
    return "timestamp" in header and "actual_q_0" in header


def _looks_like_rostopic(header) -> bool:
    return "%time" in header and "field.name0" in header


def _looks_like_plotjuggler(header) -> bool:
    return bool(header) and header[0] == "__time"


def _from_start(columns: dict, name: str, scale: float, where: str, unit: str) -> str:
    """The time column ``name`` in s from its first row (a recorder's clock, in 1/``scale`` s); the note saying so."""
    t = columns[name]
    if np.isnan(t[0]):
        raise InputError(f"{where}: column '{name}' has no time in its first row")
    columns[name] = (t - t[0]) * scale
    return f"t: {name} ({unit}), from the log's start (stamp {t[0] * scale:.6f} s)"


def _matched(model: Model, found: dict, where: str, kind: str) -> tuple[dict, list[str], dict]:
    """Ours → theirs from {joint: {field: column}}; the notes on the joints left out; the mimic joints' positions."""
    joints = [j for j in model.joint_names if j in found]
    if not joints:
        raise InputError(f"{where}: none of the {kind}'s joints ({', '.join(list(found)[:8]) or 'none'}) is one of "
                         f"robot '{model.name}' ({', '.join(model.joint_names)})")
    implied = {f"{ours}_{j}": found[j][field] for j in joints for ours, field in ROS_SIGNALS.items()
               if field in found[j]}
    notes = [f"read as a {kind} (joints matched to the URDF by name)"]
    mimics = {b.joint for b in model.bodies if b.mimic}
    others = [j for j in found if j not in model.joint_names and j not in mimics]
    if others:
        notes.append(f"joints that the robot does not have, ignored: {', '.join(others)}")
    return implied, notes, {f"q_{j}": found[j]["position"] for j in found if j in mimics and "position" in found[j]}


def _rostopic(model: Model, table: Table, where: str):
    """The implied map, columns and notes of a ``rostopic echo -p`` CSV."""
    found, k = {}, 0
    while f"field.name{k}" in table.header:
        if f"field.name{k}" in table.text:
            name = table.first_word(f"field.name{k}")[1]
            found[name] = {field: f"field.{field}{k}" for field in ROS_SIGNALS.values()
                           if f"field.{field}{k}" in table.header and f"field.{field}{k}" not in table.text}
        k += 1
    implied, notes, mimics = _matched(model, found, where, "rostopic CSV")
    columns = as_source(table).columns
    stamped = "field.header.stamp" in columns and np.all(columns["field.header.stamp"] > 0)
    clock = "field.header.stamp" if stamped else "%time"
    notes.append(_from_start(columns, clock, 1e-9, where, "ns"))
    return {"t": clock, **implied}, columns, notes, mimics


def _plotjuggler(model: Model, table: Table, where: str):
    """The implied map, columns (rows missing a read sample left out) and notes of a PlotJuggler CSV."""
    found = {}
    for name in table.header[1:]:
        head, _, field = name.rpartition("/")
        joint = head.rpartition("/")[2]
        if field in ROS_SIGNALS.values() and joint and name not in table.text:
            other = found.setdefault(joint, {}).setdefault(field, name)
            if other != name:
                raise InputError(f"{where}: columns '{other}' and '{name}' are both the {field} of joint '{joint}' "
                                 f"(two topics): export one of them")
    implied, notes, mimics = _matched(model, found, where, "PlotJuggler CSV")
    source = as_source(table)
    read = [table.header.index(c) for c in ["__time", *implied.values()]]
    full = ~np.isnan(table.data[:, read]).any(axis=1)
    if not full.any():
        raise InputError(f"{where}: no row holds a sample of every column read ({', '.join(implied.values())})")
    columns = {name: values[full] for name, values in source.columns.items()}
    if not full.all():
        notes.append(f"rows without a sample of every column read, left out: {int((~full).sum())} of {len(full)} "
                     f"(first: line {int(table.lines[~full][0])})")
    notes.append(_from_start(columns, "__time", 1.0, where, "s"))
    return {"t": "__time", **implied}, columns, notes, table.lines[full], mimics


def open_log(path, model: Model, *, format: str = "auto", topic: str | None = None,
             decimal: str | None = None) -> LogSource:
    """Read the log at ``path`` in ``format`` (module docstring) for ``model``'s joints.

    ``topic``: a bag's topic (default ``/joint_states``, else its one joint-state topic); ``decimal``: a table's
    decimal separator when it cannot tell. Raises
    :class:`~course_dynamics.base.errors.InputError` for an unknown format, a topic given for a
    table, and whatever the readers refuse.

    Parameters
    ----------
    path : str or os.PathLike
        The log's file (or a ROS 2 bag's folder).
    model : Model
        The robot whose joints are read.
    format : str
        One of :data:`FORMATS`.
    topic : str, optional
        A bag's topic.
    decimal : str, optional
        A table's decimal separator, ``.`` or ``,``.

    Returns
    -------
    LogSource
        The log's columns, its format's map to ours, and its rows' lines.

    Raises
    ------
    InputError
        If the format or an option does not fit the file, or the reader refuses it.
    """
    if format not in FORMATS:
        raise InputError(f"unknown log format '{format}' (choose from {', '.join(FORMATS)})")
    bag = is_bag(path)
    if not bag and (Path(path).parent / "metadata.yaml").is_file():
        raise InputError(f"{path}: part of a ROS 2 bag (its folder holds metadata.yaml): give the bag's folder, "
                         f"{Path(path).parent}")
    if format == "bag" or (format == "auto" and bag):
        if decimal is not None:
            raise InputError(f"{path}: a bag has no decimal separator to choose (--decimal is for tables)")
        mimics = tuple(b.joint for b in model.bodies if b.mimic)
        log = read_bag(path, tuple(model.joint_names) + mimics, topic=topic)
        return LogSource(dict(log.columns), log.where, "bag", notes=tuple(log.notes),
                         mimics={f"q_{j}": f"q_{j}" for j in mimics if f"q_{j}" in log.columns})
    if topic is not None:
        raise InputError(f"{path}: --topic is for bags; this log is read as a table")
    if bag:
        raise InputError(f"{path}: a bag cannot be read as a {format} (use --format bag or auto)")
    table = read_table(path, decimal=decimal, blanks=True)
    ours = any(name.startswith("q_") for name in table.header)
    if format == "rostopic" or (format == "auto" and not ours and _looks_like_rostopic(table.header)):
        if not _looks_like_rostopic(table.header):
            raise InputError(f"{path}: not a rostopic CSV (it needs the columns %time, field.name0, "
                             f"field.position0, …)")
        implied, columns, notes, mimics = _rostopic(model, table, str(path))
        return replace(as_source(table), columns=columns, where=str(path), format="rostopic", implied=implied,
                       notes=tuple(notes), mimics=mimics)
    if format == "plotjuggler" or (format == "auto" and not ours and _looks_like_plotjuggler(table.header)):
        if not _looks_like_plotjuggler(table.header):
            raise InputError(f"{path}: not a PlotJuggler CSV (its first column must be __time)")
        implied, columns, notes, lines, mimics = _plotjuggler(model, table, str(path))
        return replace(as_source(table), columns=columns, lines=lines, where=str(path), format="plotjuggler",
                       implied=implied, notes=tuple(notes), mimics=mimics)
    if table.blanks:   # only a recorder's export has cells without a sample: refused as before, where they are
        table = read_table(path, decimal=decimal)
    kind, implied, notes = "table", {}, ()
    source = as_source(table)
    if format == "ur-rtde" or (format == "auto" and _looks_like_rtde(table.header) and not ours):
        implied = rtde_map(model, table.header, str(path))
        kind = "ur-rtde"
        if format == "auto":
            notes = ("read as a UR RTDE recording (timestamp, actual_q_i, actual_qd_i, actual_current_i: joint i is "
                     "the URDF's i-th)",)
        if len(source.columns["timestamp"]):
            notes += (_from_start(source.columns, "timestamp", 1.0, str(path), "s"),)
    return replace(source, where=str(path), format=kind, implied=implied, notes=notes)


def _words(table: Table) -> dict:
    return {name: table.first_word(name) for name in table.text}


def as_source(log) -> LogSource:
    """Any log as a :class:`LogSource`: one already (from :func:`open_log`), a
    :class:`~course_dynamics.tools.tables.Table`, a pandas DataFrame, a dict of arrays or a numpy structured array.

    Parameters
    ----------
    log : LogSource, Table, pandas.DataFrame, dict or numpy.ndarray
        The log.

    Returns
    -------
    LogSource
        The log's columns as float arrays.

    Raises
    ------
    InputError
        If ``log`` is none of these, or a column does not hold numbers.
    """
    if isinstance(log, LogSource):
        return log
    if isinstance(log, Table):
        return LogSource(log.columns(), log.path, "table", lines=log.lines, text=log.text, words=_words(log))
    if isinstance(log, np.ndarray) and log.dtype.names:
        return LogSource({name: np.asarray(log[name], dtype=float) for name in log.dtype.names}, "the table", "table")
    if hasattr(log, "columns") and hasattr(log, "__getitem__") and not isinstance(log, Mapping):  # pandas
        return LogSource({str(name): np.asarray(log[name], dtype=float) for name in log.columns}, "the table", "table")
    if isinstance(log, Mapping):
        try:
            return LogSource({str(k): np.asarray(v, dtype=float).reshape(-1) for k, v in log.items()}, "the table",
                             "table")
        except (TypeError, ValueError) as exc:
            raise InputError(f"the table's columns must be numbers: {exc}") from None
    raise InputError(f"a log must be a table with named columns (a DataFrame, a dict of arrays, a structured array), "
                     f"got {type(log).__name__}")


__all__ = ["FORMATS", "LogSource", "as_source", "open_log"]

"""Where a log comes from: a table, a UR RTDE recording or a ROS bag, read into one shape.

==============  =================================================================================
format          what is read, and how its columns become ours
==============  =================================================================================
``table``       a delimited table (:func:`~course_dynamics.tools.tables.read_table`): comma,
                semicolon, tab or whitespace; our column names, or a map to them
``ur-rtde``     a UR controller's RTDE recording (``record.py`` writes it space separated):
                ``timestamp`` → t, ``actual_q_i`` → Θ, ``actual_qd_i`` → Θ̇ and
                ``actual_current_i`` → the motor currents, i = 0, 1, … the URDF's i-th joint
``bag``         a ROS 1 bag, a ROS 2 bag (sqlite3 or MCAP) or an MCAP file: ``sensor_msgs/JointState``
                matched by joint name (``effort`` is the measured torque) or Franka's
                ``franka_msgs/FrankaState`` (``q``, ``dq``, ``tau_J``) (:mod:`~course_dynamics.tools.bags`)
``auto``        a bag by its file; a table whose header has ``timestamp`` and ``actual_q_0`` … is
                an RTDE recording; any other table is a table
==============  =================================================================================

Every source gives a :class:`LogSource`: the log's own columns, the map from our names to them
that its format implies (an explicit map from the user overrides it entry by entry), and how to
name a row in messages. What happens next — which columns are used (:mod:`~course_dynamics.tools.columns`),
the clock (:mod:`~course_dynamics.tools.resampling`), the derivatives — is the same for all.
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
FORMATS = ("auto", "table", "ur-rtde", "bag")
RTDE_SIGNALS = {"q": "actual_q", "qd": "actual_qd", "current": "actual_current"}


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
        ``table``, ``ur-rtde`` or ``bag``.
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
    """

    columns: dict
    where: str
    format: str
    implied: dict = field(default_factory=dict)   # ours → theirs, from the format
    lines: np.ndarray | None = None                # the file line of each row (tables)
    text: tuple[str, ...] = ()                     # columns that hold words, not numbers (ignored unless used)
    notes: tuple[str, ...] = ()
    words: dict = field(default_factory=dict)      # a text column → (line, its first cell), for messages

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
        log = read_bag(path, tuple(model.joint_names), topic=topic)
        return LogSource(dict(log.columns), log.where, "bag", notes=tuple(log.notes))
    if topic is not None:
        raise InputError(f"{path}: --topic is for bags; this log is read as a table")
    if bag:
        raise InputError(f"{path}: a bag cannot be read as a {format} (use --format bag or auto)")
    table = read_table(path, decimal=decimal)
    kind, implied, notes = "table", {}, ()
    if format == "ur-rtde" or (format == "auto" and _looks_like_rtde(table.header)
                               and not any(name.startswith("q_") for name in table.header)):
        implied = rtde_map(model, table.header, str(path))
        kind = "ur-rtde"
        if format == "auto":
            notes = ("read as a UR RTDE recording (timestamp, actual_q_i, actual_qd_i, actual_current_i: joint i is "
                     "the URDF's i-th)",)
    return replace(as_source(table), where=str(path), format=kind, implied=implied, notes=notes)


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

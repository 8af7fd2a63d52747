"""Which of a log's columns give t, Θ, Θ̇ and Θ̈, worked out once: the column plan.

==================  ==============================================================
code                meaning
==================  ==============================================================
``ours``            our column names: ``t``, ``q_<joint>``, ``qd_<joint>``, ``qdd_<joint>``, and what the
                    robot measured: ``tau_meas_<joint>`` (N·m or N), ``current_<joint>`` (A)
``theirs``          the log's column names, as its header spells them
``read``            ours → theirs, for every one of ours the log holds (mapped or not)
``constants``       ours → a value for every row, for signals the log lacks
``derived``         ``qd_``/``qdd_`` columns to be differentiated, and from what
==================  ==============================================================

:func:`plan_columns` looks only at names, never at data, so the reader
(:func:`course_dynamics.tools.logs.joint_log`) and the CLI's ``torques --columns`` (which
lists the plan without reading a number) act on the same decisions. A source of logs
(a recorder's CSV, a bag) gives a list of column names and, where it knows them, a map;
everything after that goes through this one plan.

>>> from course_dynamics import load_robot
>>> plan = plan_columns(load_robot("two_link"), ["time", "q_theta1", "q_theta2", "temp"], columns={"t": "time"})
>>> plan.read["t"], plan.ignored, plan.missing_positions
('time', ('temp',), ())
>>> [d.name + " from " + d.source for d in plan.derived]
['qd_theta1 from q', 'qd_theta2 from q', 'qdd_theta1 from q', 'qdd_theta2 from q']
"""
from __future__ import annotations

import tomllib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..base.errors import InputError
from ..base.files import read_small
from ..core.model import Model
from .tables import joint_columns

MAX_MAP_BYTES = 2**20         # a column map of a thousand joints is under 100 kB
#: The kinds of our joint columns a log gives or the plan derives (Θ, Θ̇, Θ̈).
KINDS = ("q", "qd", "qdd")
MEASURED = ("tau_meas", "current")   # optional: read when the log has them, never derived
APPLIED = ("tau",)                    # applied torques: read only for a reader that asks (simulate's torques)


@dataclass(frozen=True)
class Derived:
    """One of our rate columns the log lacks: ``name`` (``qd_j`` or ``qdd_j``) from ``source`` (``q`` or ``qd``).

    Parameters
    ----------
    name : str
        Our column, ``qd_<joint>`` or ``qdd_<joint>``.
    joint : str
        The joint's name.
    order : int
        1 for Θ̇, 2 for Θ̈.
    source : str
        ``"q"``: differentiate Θ ``order`` times; ``"qd"``: differentiate the given Θ̇ once.
    """

    name: str
    joint: str
    order: int      # 1 for qd, 2 for qdd
    source: str     # "q": differentiate Θ ``order`` times; "qd": differentiate the given Θ̇ once


@dataclass(frozen=True)
class ColumnPlan:
    """Where each of our columns comes from (module docstring); built by :func:`plan_columns`.

    Parameters
    ----------
    joints : tuple of str
        The robot's joints, in the model's order.
    theirs : tuple of str
        The log's column names, in order.
    read : mapping of str to str
        Ours → theirs, for every one of ours the log holds.
    constants : mapping of str to float
        Ours → a value for every row, for signals the log lacks.
    held : tuple of str
        The ``qd_``/``qdd_`` columns that are zero because their q is a constant.
    derived : tuple of Derived
        The rate columns to be differentiated, and from what.
    """

    joints: tuple[str, ...]
    theirs: tuple[str, ...]
    read: Mapping[str, str]
    constants: Mapping[str, float]
    held: tuple[str, ...]           # qd_/qdd_ columns that are zero because their q is a constant
    derived: tuple[Derived, ...]

    @property
    def ours(self) -> tuple[str, ...]:
        """Every column name of ours the plan knows for these joints (``t``, Θ, Θ̇, Θ̈, what the robot measured)."""
        return ("t",) + tuple(joint_columns(KINDS + MEASURED, self.joints))

    @property
    def has_time(self) -> bool:
        """Whether the log has a ``t`` column."""
        return "t" in self.read

    @property
    def missing_positions(self) -> tuple[str, ...]:
        """``q_<joint>`` columns neither in the log nor given a constant."""
        return tuple(f"q_{j}" for j in self.joints if f"q_{j}" not in self.read and f"q_{j}" not in self.constants)

    @property
    def used_as(self) -> dict[str, str]:
        """The log's column → ours, for the columns the plan reads."""
        return {theirs: ours for ours, theirs in self.read.items()}

    @property
    def ignored(self) -> tuple[str, ...]:
        """The log's columns the plan does not read, in order."""
        used = self.used_as
        return tuple(c for c in self.theirs if c not in used)

    def require_positions(self, where: str) -> None:
        """Raise :class:`~course_dynamics.base.errors.InputError` unless every joint's Θ is read or set.

        Parameters
        ----------
        where : str
            The log's name in messages.

        Raises
        ------
        InputError
            If a ``q_<joint>`` column is neither in the log nor given a constant.
        """
        if self.missing_positions:
            raise InputError(f"{where}: missing columns: {', '.join(self.missing_positions)} (a column map can name "
                             f"the log's own; a joint the log does not record can be given a constant)")

    def measured(self, kind: str) -> list[str]:
        """The joints whose ``kind`` (tau_meas or current) the log holds.

        Parameters
        ----------
        kind : str
            ``"tau_meas"`` or ``"current"``.

        Returns
        -------
        list of str
            The joints' names, in the model's order.
        """
        return [j for j in self.joints if f"{kind}_{j}" in self.read]

    def derived_kind(self, kind: str, source: str | None = None) -> list[str]:
        """The joints whose ``kind`` (qd or qdd) is differentiated (from ``source``, if given).

        Parameters
        ----------
        kind : str
            ``"qd"`` or ``"qdd"``.
        source : str, optional
            ``"q"`` or ``"qd"``; None for either.

        Returns
        -------
        list of str
            The joints' names, in the model's order.
        """
        order = KINDS.index(kind)
        return [d.joint for d in self.derived if d.order == order and (source is None or d.source == source)]


def merged_map(implied: Mapping[str, str], columns: Mapping[str, str] | None) -> dict[str, str]:
    """A format's map overridden by the user's, entry by entry: a column the user maps, theirs or ours, is the user's.

    Parameters
    ----------
    implied : mapping of str to str
        Ours → theirs, as the log's format implies them.
    columns : mapping of str to str, optional
        Ours → theirs, as the user gave them.

    Returns
    -------
    dict of str to str
        The merged map.

    Examples
    --------
    >>> merged_map({"t": "timestamp", "q_a": "actual_q_0"}, {"q_a": "pos_a"})
    {'t': 'timestamp', 'q_a': 'pos_a'}
    """
    columns = dict(columns or {})
    taken = set(columns.values())
    kept = {ours: theirs for ours, theirs in implied.items() if ours not in columns and theirs not in taken}
    return {**kept, **columns}


def plan_columns(model: Model, theirs: Iterable[str], *, columns: Mapping[str, str] | None = None,
                 constants: Mapping[str, float] | None = None, where: str = "the table",
                 applied: bool = False) -> ColumnPlan:
    """The column plan for a log whose header is ``theirs`` (module docstring).

    Parameters
    ----------
    model : Model
        The robot whose joints the log must cover.
    theirs : iterable of str
        The log's column names, in order.
    columns : mapping of str to str, optional
        Our column name → the log's (a map; unmapped ones of ours are looked up by name).
    constants : mapping of str to float, optional
        Our column name → a value for every row.
    where : str
        The log's name in messages.
    applied : bool
        Also read ``tau_<joint>``, applied torques (otherwise such columns are ignored like any other).

    Returns
    -------
    ColumnPlan
        What is read, set, held at zero and derived.

    Raises
    ------
    InputError
        A map or constant for a name that is none of ours, a mapped column the log lacks, two of ours mapped to one
        of the log's, a constant that is not finite or is also read from the log.
    """
    theirs = tuple(theirs)
    available = set(theirs)
    columns, constants = dict(columns or {}), dict(constants or {})
    ours = ["t"] + joint_columns(KINDS + MEASURED + (APPLIED if applied else ()), model.joint_names)
    for name in list(columns) + list(constants):
        for k, body in enumerate(model.bodies):
            prefix = name.removesuffix(f"_{body.joint}")
            if name not in ours and body.mimic and prefix != name and prefix in KINDS + MEASURED + APPLIED:
                leader = model.joint_names[model.coupling[k][0]]
                raise InputError(f"column map: '{name}': joint '{body.joint}' is a mimic of joint '{leader}' and has "
                                 f"no column of its own; set or map {prefix}_{leader} (it moves with that one)")
        if name not in ours:
            raise InputError(f"column map: '{name}' is none of our columns (t, q_<joint>, qd_<joint>, qdd_<joint>, "
                             f"{'tau_<joint>, ' if applied else ''}tau_meas_<joint>, current_<joint> for joints "
                             f"{', '.join(model.joint_names)})")
    for name in constants:
        if name.startswith(MEASURED):
            raise InputError(f"{name} is something the robot measured: it can be read from the log, not set")
        kind, _, joint = name.partition("_")
        if kind in ("qd", "qdd") and f"q_{joint}" not in constants:
            raise InputError(f"{name} can be set only for a joint whose q is set too (a constant rate under a logged "
                             f"position would contradict it); q_{joint} comes from the log")
    for name, other in columns.items():
        if other not in available:
            raise InputError(f"{where}: no column '{other}' (mapped from {name}); columns: {', '.join(theirs)}")
    taken = list(columns.values())
    for other in sorted(set(taken)):
        if taken.count(other) > 1:
            both = [name for name, mapped in columns.items() if mapped == other]
            raise InputError(f"column map: {' and '.join(both)} are both mapped to the log's column '{other}'")
    for name, value in constants.items():
        if not np.isfinite(value):
            raise InputError(f"the constant value of {name} must be finite, got {value}")
        if name in columns or name in available:
            raise InputError(f"{name} is both given a constant value and read from {where}")
    read = {name: columns.get(name, name) for name in ours if columns.get(name, name) in available}
    held = tuple(f"{kind}_{name[2:]}" for name in constants if name.startswith("q_") for kind in ("qd", "qdd")
                 if f"{kind}_{name[2:]}" not in read and f"{kind}_{name[2:]}" not in constants)
    given = set(read) | set(constants) | set(held)
    derived = [Derived(f"qd_{j}", j, 1, "q") for j in model.joint_names if f"qd_{j}" not in given]
    derived += [Derived(f"qdd_{j}", j, 2, "qd" if f"qd_{j}" in given else "q") for j in model.joint_names
                if f"qdd_{j}" not in given]
    return ColumnPlan(joints=tuple(model.joint_names), theirs=theirs, read=read, constants=constants, held=held,
                      derived=tuple(derived))


def parse_column_map(text: str) -> dict[str, str]:
    """``ours=theirs,…`` or the path of a TOML file of ``ours = "theirs"`` lines (optionally under ``[columns]``).

    Parameters
    ----------
    text : str
        The map as written on the command line, or a TOML file's path.

    Returns
    -------
    dict of str to str
        Ours → theirs.

    Raises
    ------
    InputError
        If an entry is not ``ours=theirs`` or maps a name twice, or the TOML file is too large, not valid, or has
        an entry that is not a string.
    """
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


__all__ = ["KINDS", "ColumnPlan", "Derived", "merged_map", "parse_column_map", "plan_columns"]

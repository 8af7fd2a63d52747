"""Joint drives: the rotor inertia a motor adds on its joint and a constant torque offset.

==================  ==============  =============================================================
code                symbol          meaning (shape, unit)
==================  ==============  =============================================================
``armature``        Iₐ              each joint's rotor inertia reflected to the joint (n,), kg·m²
                                    (kg for a prismatic joint): gear ratio² times the rotor's own
``offset``          τ₀              each joint's constant torque offset (n,), N·m (N): what the
                                    drive measures or needs beyond the dynamics, at any motion
``torques``         Iₐ Θ̈ + τ₀       what the drives add to τ (n,) or (N, n), N·m (N)
==================  ==============  =============================================================

With drives the whole model is

    τ = M(Θ) Θ̈ + V(Θ, Θ̇) + G(Θ) + F(Θ̇) + Iₐ Θ̈ + τ₀

(Iₐ as the diagonal matrix diag(Iₐ)), so forward dynamics solves (M + diag(Iₐ)) Θ̈ = τ − V − G − F − τ₀
and the kinetic energy holds the rotors' ½ Θ̇ᵀ diag(Iₐ) Θ̇. Pinocchio's ``model.armature`` is the same
convention (added to the diagonal of CRBA's M and to RNEA's τ). The rotor of each joint is taken to spin
with its own joint alone (the gyroscopic coupling of a rotor carried by the links before it is left out,
as Pinocchio and MuJoCo leave it out). Neither part changes the recursions: :class:`Driven` adds them to
whichever implementation the evaluator chose, at the one place friction is added too.

A URDF has no field for either, so they live in a TOML file of their own (:func:`read_drives`,
:func:`drives_text`), one table per joint; a joint the file does not name has no armature and no offset::

    # drives of ur5: identified by course-dynamics from ur5.csv
    [joint.shoulder_pan_joint]
    armature = 0.12         # kg·m² ± 0.003
    offset = -0.31          # N·m ± 0.01

>>> drives = Drives(armature=[0.5, 0.0], offset=[0.1, -0.2])     # kg·m², N·m
>>> drives.torques([2.0, 1.0])                                    # Iₐ Θ̈ + τ₀
array([ 1.1, -0.2])
"""
from __future__ import annotations

import json
import math
import re
import tomllib
from dataclasses import dataclass

import numpy as np

from ..base.errors import InputError
from ..base.files import read_small
from .forward_dynamics import solve
from .model import Model
from .urdf import MAX_MAGNITUDE

#: The largest drives file read, bytes (a thousand joints take about 100 kB).
MAX_FILE_BYTES = 1_000_000
#: The keys of a joint's table.
KEYS = ("armature", "offset")
COMMENT_COLUMN = 24  # where each value's comment starts
DIGITS = 7           # significant digits written: far below any standard error a log gives
BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")


@dataclass(frozen=True)
class Drives:
    """Per-joint rotor inertias and torque offsets (read-only float arrays of shape (n,)).

    Parameters
    ----------
    armature : array_like, shape (n,)
        Iₐ of each joint, kg·m² (kg for a prismatic joint), finite and ≥ 0.
    offset : array_like, shape (n,)
        τ₀ of each joint, N·m (N for a prismatic joint), finite.

    Raises
    ------
    InputError
        If a value is not finite, an armature is negative, or the two differ in shape.

    Examples
    --------
    >>> Drives(armature=[0.2], offset=[0.0]).mass_matrix(np.array([[1.0]]))
    array([[1.2]])
    """

    armature: np.ndarray
    offset: np.ndarray

    def __post_init__(self):
        for name in KEYS:
            values = np.array(getattr(self, name), dtype=float)
            if values.ndim != 1 or not np.all(np.isfinite(values)):
                raise InputError(f"drive {name}s must be one finite number per joint, got {values.tolist()}")
            values.setflags(write=False)
            object.__setattr__(self, name, values)
        if np.any(self.armature < 0):
            raise InputError(f"drive armatures must be non-negative, got {self.armature.tolist()}")
        if self.armature.shape != self.offset.shape:
            raise InputError(f"drives need as many armatures as offsets, got {len(self.armature)} and "
                             f"{len(self.offset)}")

    @classmethod
    def none(cls, model: Model) -> "Drives":
        """No drive on any joint of ``model``: Iₐ = 0, τ₀ = 0.

        Parameters
        ----------
        model : Model
            The robot (its number of joints n).

        Returns
        -------
        Drives
            Zeros, shape (n,).

        Examples
        --------
        >>> from course_dynamics import load_robot
        >>> Drives.none(load_robot("two_link")).torques([1.0, 2.0])
        array([0., 0.])
        """
        return cls(armature=np.zeros(model.n), offset=np.zeros(model.n))

    def torques(self, qdd) -> np.ndarray:
        """Iₐ Θ̈ + τ₀, shape like ``qdd``: (n,) or (N, n).

        Parameters
        ----------
        qdd : array_like, shape (n,) or (N, n)
            Joint accelerations Θ̈, rad/s² (m/s² for a prismatic joint).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            What the drives add to τ, N·m (N for a prismatic joint).
        """
        return self.armature * np.asarray(qdd, dtype=float) + self.offset

    def mass_matrix(self, M) -> np.ndarray:
        """M + diag(Iₐ), for M of shape (n, n) or (N, n, n).

        Parameters
        ----------
        M : array_like, shape (n, n) or (N, n, n)
            The links' mass matrix M(Θ), kg·m² (kg).

        Returns
        -------
        numpy.ndarray, shape like ``M``
            The mass matrix the joints' accelerations see, rotors included.
        """
        return np.asarray(M, dtype=float) + np.diag(self.armature)

    def kinetic_energy(self, qd) -> np.ndarray:
        """The rotors' kinetic energy ½ Θ̇ᵀ diag(Iₐ) Θ̇, J; shape () or (N,).

        Parameters
        ----------
        qd : array_like, shape (n,) or (N, n)
            Joint velocities Θ̇, rad/s (m/s).

        Returns
        -------
        float or numpy.ndarray, shape (N,)
            The rotors' kinetic energy, J.
        """
        qd = np.asarray(qd, dtype=float)
        return 0.5 * np.sum(self.armature * qd * qd, axis=-1)


class Driven:
    """An implementation of the dynamics (what :func:`~course_dynamics.core.evaluator.implementation` chose)
    with ``drives`` added: the one place the drives enter τ, M, the bias and Θ̈.

    ``bias`` holds τ₀ with V + G, so that anything built on M and the bias (forward dynamics, a joint held at
    its limit, a stop's impulse) takes the drives as they are.

    Parameters
    ----------
    run : object
        The implementation: ``inverse_dynamics(q, qd, qdd)``, ``mass_matrix(q)`` and ``bias(q, qd)``, with the
        model as ``run.model``.
    drives : Drives
        The drives of the model's joints.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.evaluator import implementation
    >>> arm = load_robot("pendulum")
    >>> driven = Driven(implementation(arm), Drives(armature=[0.25], offset=[0.0]))
    >>> driven.mass_matrix(np.zeros(1)) - implementation(arm).mass_matrix(np.zeros(1))
    array([[0.25]])
    """

    def __init__(self, run, drives: Drives):
        self.run, self.drives, self.model = run, drives, run.model

    def inverse_dynamics(self, q, qd, qdd) -> np.ndarray:
        """τ = M Θ̈ + V + G + Iₐ Θ̈ + τ₀, shape (n,) or (N, n), N·m (N).

        Parameters
        ----------
        q, qd, qdd : numpy.ndarray, shape (n,) or (N, n)
            Joint positions (rad, m), velocities (rad/s, m/s) and accelerations (rad/s², m/s²).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            The joint torques, N·m (N).
        """
        return self.run.inverse_dynamics(q, qd, qdd) + self.drives.torques(qdd)

    def mass_matrix(self, q) -> np.ndarray:
        """M(Θ) + diag(Iₐ), shape (n, n) or (N, n, n), kg·m² (kg).

        Parameters
        ----------
        q : numpy.ndarray, shape (n,) or (N, n)
            Joint positions, rad (m).

        Returns
        -------
        numpy.ndarray, shape (n, n) or (N, n, n)
            The mass matrix with the rotors.
        """
        return self.drives.mass_matrix(self.run.mass_matrix(q))

    def bias(self, q, qd) -> np.ndarray:
        """V(Θ, Θ̇) + G(Θ) + τ₀, shape (n,) or (N, n), N·m (N).

        Parameters
        ----------
        q, qd : numpy.ndarray, shape (n,) or (N, n)
            Joint positions (rad, m) and velocities (rad/s, m/s).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            What τ must overcome at Θ̈ = 0, the offsets included.
        """
        return self.run.bias(q, qd) + self.drives.offset

    def accelerations(self, q: np.ndarray, qd: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """Θ̈ = (M + diag(Iₐ))⁻¹ (τ − V − G − τ₀), friction already taken off τ.

        Parameters
        ----------
        q, qd, tau : numpy.ndarray, shape (n,) or (N, n)
            Joint positions (rad, m), velocities (rad/s, m/s) and torques (N·m, N).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            Joint accelerations, rad/s² (m/s²).

        Raises
        ------
        SingularMassMatrixError
            If M + diag(Iₐ) is singular.
        """
        return solve(self.model, self.mass_matrix(q), tau - self.bias(q, qd), q)  # (6.115) with the rotors

    def forward_dynamics(self, q, qd, tau, friction=None) -> np.ndarray:
        """Θ̈ of :meth:`accelerations` after taking ``friction`` off τ.

        Parameters
        ----------
        q, qd, tau : numpy.ndarray, shape (n,) or (N, n)
            Joint positions (rad, m), velocities (rad/s, m/s) and applied torques (N·m, N).
        friction : Friction, optional
            Subtracted from τ as F(Θ̇) (6.114).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            Joint accelerations, rad/s² (m/s²).
        """
        return self.accelerations(q, qd, tau if friction is None else tau - friction.torques(qd))


def _joint_index(model: Model, name: str, where: str) -> int:
    """Θ's index of joint ``name``, or an InputError naming the file and the joint."""
    if name in model.joint_names:
        return model.joint_names.index(name)
    if name in (body.joint for body in model.bodies):
        raise InputError(f"{where}: joint '{name}' is a mimic joint with no coordinate of its own: give its drive on "
                         "the joint it mimics")
    raise InputError(f"{where}: robot '{model.name}' has no moving joint '{name}' (its joints: "
                     f"{', '.join(model.joint_names)})")


def _value(table: dict, key: str, name: str, where: str) -> float:
    value = table.get(key, 0.0)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"{where}: joint '{name}': {key} must be a finite number, got {value!r}")
    if key == "armature" and value < 0:
        raise InputError(f"{where}: joint '{name}': armature must be non-negative, got {value!r}")
    if abs(value) > MAX_MAGNITUDE:  # no drive is this large, and its torques would overflow
        raise InputError(f"{where}: joint '{name}': {key} {value:g} is more than {MAX_MAGNITUDE:g} in size "
                         "(kg·m², kg, N·m or N): no drive has it")
    return float(value)


def _decode_error(text: str, exc: Exception, where: str) -> InputError:
    """tomllib's complaint, with the [joint.<name>] table its line is in (tomllib names only the line)."""
    found = re.search(r"at line (\d+)", str(exc))
    table = None
    if found:
        for line in text.splitlines()[:int(found.group(1))]:
            header = re.match(r"\s*\[\s*joint\s*\.\s*([^\]]+?)\s*\]", line)
            if header:
                table = header.group(1).strip().strip('"\'')
    return InputError(f"{where}: not a TOML file of drives ({exc})" + (f", in the table of joint '{table}'"
                                                                       if table else ""))


def parse_drives(text: str, model: Model, where: str = "the drives file") -> Drives:
    """The drives a TOML text gives ``model`` (module docstring); joints it does not name get zeros.

    Parameters
    ----------
    text : str
        The TOML: ``[joint.<name>]`` tables of ``armature`` (kg·m², kg) and ``offset`` (N·m, N), nothing else.
    model : Model
        The robot whose joints the tables name.
    where : str
        How messages name the text (its file).

    Returns
    -------
    Drives
        Iₐ and τ₀ of every joint of ``model``.

    Raises
    ------
    InputError
        One line naming ``where`` (and the joint): not TOML (or nested too deeply to read), a joint or key named
        twice, no joint, a key or table other than these, a joint the robot does not have, a value that is not a
        finite number or is more than 1e9 in size, a negative
        armature.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> parse_drives("[joint.theta2]\\narmature = 0.3\\n", load_robot("two_link")).armature
    array([0. , 0.3])
    """
    try:
        document = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise _decode_error(text, exc, where) from None
    except RecursionError:  # tomllib recurses once per level of nested arrays and inline tables
        raise InputError(f"{where}: not a TOML file of drives (its values are nested too deeply to read)") from None
    other = [key for key in document if key != "joint"]
    joints = document.get("joint")
    if other or not isinstance(joints, dict):
        raise InputError(f"{where}: a drives file holds [joint.<name>] tables only"
                         + (f", not '{other[0]}'" if other else
                            ", and it has none" if joints is None else
                            f", but its 'joint' is a value ({type(joints).__name__}), not tables"))
    armature, offset = np.zeros(model.n), np.zeros(model.n)
    for name, table in joints.items():
        j = _joint_index(model, name, where)
        if not isinstance(table, dict):
            raise InputError(f"{where}: joint '{name}' must be a table ([joint.{name}]) of armature and offset")
        unknown = [key for key in table if key not in KEYS]
        if unknown:
            raise InputError(f"{where}: joint '{name}': unknown key '{unknown[0]}' (a joint has armature and offset)")
        armature[j], offset[j] = (_value(table, key, name, where) for key in KEYS)
    return Drives(armature=armature, offset=offset)


def read_drives(path, model: Model) -> Drives:
    """The drives file at ``path`` for ``model`` (:func:`parse_drives`), at most :data:`MAX_FILE_BYTES`.

    Parameters
    ----------
    path : str or pathlib.Path
        The TOML file.
    model : Model
        The robot.

    Returns
    -------
    Drives
        Iₐ and τ₀ of every joint.

    Raises
    ------
    InputError
        If the file cannot be read, is too large, is not UTF-8, or :func:`parse_drives` refuses it.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from course_dynamics import load_robot
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "drives.toml"
    >>> _ = path.write_text("[joint.theta1]\\noffset = -0.5   # N·m\\n")
    >>> read_drives(path, load_robot("two_link")).offset
    array([-0.5,  0. ])
    """
    data = read_small(path, MAX_FILE_BYTES, "drives file")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a TOML file of drives (not UTF-8 text)") from None
    return parse_drives(text, model, str(path))


def _key(name: str) -> str:
    """A TOML key for a joint name: bare when it can be, else a quoted string (JSON's escapes are TOML's)."""
    return name if BARE_KEY.fullmatch(name) else json.dumps(name, ensure_ascii=False)


def drives_text(drives: Drives, model: Model, header: str, errors: tuple | None = None) -> str:
    """The TOML of ``drives`` for every joint of ``model``, each value with its unit and standard error.

    Parameters
    ----------
    drives : Drives
        The drives to write.
    model : Model
        The robot (joint names and types).
    header : str
        The first comment line's text (one line).
    errors : (numpy.ndarray, numpy.ndarray), optional
        The standard errors of the armatures and of the offsets, shape (n,) each; NaN where a value was not
        identified (its comment then says so).

    Returns
    -------
    str
        The file's text, which :func:`parse_drives` reads back as ``drives`` to seven significant digits.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> print(drives_text(Drives([0.25], [-0.5]), load_robot("pendulum"), "drives of pendulum"), end="")
    # drives of pendulum
    [joint.theta]
    armature = 0.25         # kg·m²
    offset = -0.5           # N·m
    """
    lines = ["# " + " ".join(header.split())]
    for j, body in enumerate(model.coordinate_bodies):
        units = ("kg", "N") if body.is_prismatic else ("kg·m²", "N·m")
        lines.append(f"[joint.{_key(body.joint)}]")
        for key, unit, values, k in zip(KEYS, units, (drives.armature, drives.offset), range(2)):
            error = "" if errors is None else (f" ± {float(errors[k][j]):.2g}" if np.isfinite(errors[k][j])
                                               else ", not identified")
            text = f"{key} = {float(f'{float(values[j]):.{DIGITS}g}')!r}"
            lines.append(text + " " * max(COMMENT_COLUMN - len(text), 2) + f"# {unit}{error}")
    return "\n".join(lines) + "\n"


__all__ = ["KEYS", "MAX_FILE_BYTES", "Driven", "Drives", "drives_text", "parse_drives", "read_drives"]

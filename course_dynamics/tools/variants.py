"""Each student their own robot: a course robot's variant and the exercises' states, derived from the student's id.

A course gives every student the same exercises on a robot of their own, so that
one student's numbers do not pass another's checks. The variant is derived
reproducibly from the id as given (a login, or an e-mail's local part), through
SHA-256, so the notebooks, the grader and the handout agree without storing
anything:

==================  ==========================================================
what varies         how (per link i, factors drawn from the id and the robot)
==================  ==========================================================
lengths             λᵢ ∈ [0.75, 1.3]: the origins of the joints link i carries
                    (ⁱPᵢ₊₁) and its centre of mass ⁱP_Cᵢ, rounded to 1 mm
masses              μᵢ ∈ [0.6, 1.6]: mᵢ, rounded to 0.01 kg
inertia tensors     ᶜⁱIᵢ × μᵢλᵢ² (the same body, scaled), to 4 significant digits
the check states    :func:`rng_for` (id, exercise): seeded states and given data
==================  ==========================================================

Joint axes, frame orientations, limits and gravity stay the course robot's.
The default student :data:`COURSE_STUDENT` (a notebook without an id) gets a
variant too, so that an exercise never runs on the worked examples' robot.

>>> a, b = robot_variant("two_link", "ada"), robot_variant("two_link", "grace")
>>> a.model.bodies[0].mass != b.model.bodies[0].mass, robot_variant("two_link", "ada") == a
(True, True)
"""
from __future__ import annotations

import csv
import hashlib
import io as text_io
import re
from dataclasses import dataclass, field, replace
from functools import lru_cache

import numpy as np

from ..base.errors import InputError
from ..base.files import read_small
from ..core.model import Model
from ..core.parameters import parameter_values
from ..core.robots import COURSE_ROBOTS, load_robot

STUDENT_ID = re.compile(r"[A-Za-z0-9][A-Za-z0-9._+-]{0,63}")
#: The id of a notebook written without one (it gets a variant too).
COURSE_STUDENT = "course"  # the id of a notebook written without one
LENGTHS, MASSES = (0.75, 1.3), (0.6, 1.6)


def check_student_id(student: str, where: str = "student id") -> str:
    """``student`` if it is an id a course uses and safe as a file name, else an InputError naming it.

    Parameters
    ----------
    student : str
        The id: letters, digits and ``. _ + -``, at most 64, starting with a letter or digit, not ending in a dot.
    where : str
        How the message names it.

    Returns
    -------
    str
        ``student``, unchanged.

    Raises
    ------
    InputError
        If ``student`` is not such an id.

    Examples
    --------
    >>> check_student_id("ada.lovelace")
    'ada.lovelace'
    """
    if not isinstance(student, str) or not STUDENT_ID.fullmatch(student) or student.endswith("."):
        raise InputError(f"{where} {student!r}: use letters, digits and . _ + - (at most 64, starting with a letter "
                         "or digit, not ending in a dot): a login or an e-mail's local part")
    return student


def rng_for(student: str, purpose: str) -> np.random.Generator:
    """The random numbers of ``purpose`` (an exercise's name, a robot's) for this student: the same every time.

    Parameters
    ----------
    student : str
        The student's id.
    purpose : str
        What the numbers are for.

    Returns
    -------
    numpy.random.Generator
        A generator seeded from SHA-256 of ``purpose`` and ``student``.

    Examples
    --------
    >>> float(rng_for("ada", "v_dot_c1").uniform()) == float(rng_for("ada", "v_dot_c1").uniform())
    True
    """
    digest = hashlib.sha256(f"{purpose}\0{student}".encode()).digest()
    return np.random.default_rng(int.from_bytes(digest[:16], "little"))


def _significant(x: np.ndarray, digits: int) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    scale = np.where(x == 0, 1.0, 10.0 ** (digits - 1 - np.floor(np.log10(np.abs(np.where(x == 0, 1.0, x))))))
    return np.round(x * scale) / scale


@dataclass(frozen=True)
class Variant:
    """A student's robot: ``model`` (its numbers changed as the module table says), the factors drawn, and the
    parameters a student reads (:func:`~course_dynamics.core.parameters.parameter_values`).

    Parameters
    ----------
    robot : str
        The course robot's name.
    student : str
        The student's id.
    model : Model
        The student's robot.
    lengths : tuple of float
        The length factors λᵢ drawn, one per link.
    masses : tuple of float
        The mass factors μᵢ drawn, one per link.
    """

    robot: str
    student: str
    model: Model = field(compare=False)
    lengths: tuple[float, ...]
    masses: tuple[float, ...]

    @property
    def parameters(self) -> dict[str, float]:
        """The parameters of the student's robot by name, SI units."""
        return parameter_values(self.model)

    def describe(self) -> str:
        """The variant as a student reads it: gravity, then per link its joint (where frame i sits in its parent's
        frame at θ = 0: origin and rotation, the axis Ẑ), its mass, centre of mass and inertia tensor.

        Returns
        -------
        str
            One line for gravity, two per link, one per extra frame; m, kg, kg·m², m/s².
        """
        model = self.model
        lines = [f"{self.robot} for {self.student}: gravity g = {_vector(model.gravity)} m/s² in the base frame"]
        for i, body in enumerate(model.bodies):
            parent = "the base" if body.parent < 0 else f"link {body.parent + 1}"
            lines += [f"link {i + 1}, joint {body.joint} ({body.joint_type}, about {_vector(body.axis)} of its own "
                      f"frame): frame {i + 1} in the frame of {parent} at {body.joint} = 0 has its origin at "
                      f"{_vector(body.P)} m and rotation rows {'; '.join(_vector(row) for row in body.R0)}",
                      f"    m = {float(body.mass):g} kg, centre of mass P_C = {_vector(body.p_com)} m, "
                      "inertia about it "
                      f"I_C = rows {'; '.join(_vector(row) for row in body.I_com)} kg·m² (frame {i + 1}'s axes)"]
        for frame in model.frames:
            if frame.body >= 0 and frame.name not in {b.name for b in model.bodies} and frame.P.any():
                lines.append(f"frame {frame.name}: fixed to link {frame.body + 1}, origin {_vector(frame.P)} m")
        return "\n".join(lines)


def _vector(values) -> str:
    # 12 digits: a solution typed from these numbers agrees with the grader to far better than its tolerance
    return "(" + ", ".join(f"{float(v) + 0.0:.12g}" if abs(float(v)) > 1e-12 else "0" for v in values) + ")"


@lru_cache(maxsize=64)
def robot_variant(robot: str, student: str) -> Variant:
    """The variant of course robot ``robot`` for ``student`` (module docstring).

    Parameters
    ----------
    robot : str
        A course robot's name.
    student : str
        The student's id.

    Returns
    -------
    Variant
        The student's robot and the factors drawn; the same for the same arguments.

    Raises
    ------
    InputError
        If ``student`` is not a valid id or ``robot`` is not a course robot.
    """
    check_student_id(student)
    if robot not in COURSE_ROBOTS:
        raise InputError(f"robot '{robot}': only the course robots ({', '.join(COURSE_ROBOTS)}) have student variants")
    model = load_robot(robot)
    rng = rng_for(student, f"robot {robot}")
    lengths = rng.uniform(*LENGTHS, model.n_bodies)
    masses = rng.uniform(*MASSES, model.n_bodies)
    bodies = []
    for i, body in enumerate(model.bodies):
        own, parents = lengths[i], (lengths[body.parent] if body.parent >= 0 else 1.0)
        mass = float(np.round(float(body.mass) * masses[i], 2))
        bodies.append(replace(body, P=np.round(body.P * parents, 3), p_com=np.round(body.p_com * own, 3), mass=mass,
                              I_com=_significant(body.I_com * masses[i] * own**2, 4)))
    frames = tuple(replace(f, P=np.round(f.P * lengths[f.body], 3)) if f.body >= 0 else f for f in model.frames)
    return Variant(robot, student, replace(model, bodies=tuple(bodies), frames=frames), tuple(lengths), tuple(masses))


MAX_ROSTER_BYTES = 4 * 2**20


def read_roster(path) -> list[str]:
    """The student ids of a roster: a CSV file with an ``id`` column (other columns are ignored), one student per row.

    Every id is checked (:func:`check_student_id`) and none may repeat; an error names the file and the row.

    Parameters
    ----------
    path : str or os.PathLike
        The roster's CSV file.

    Returns
    -------
    list of str
        The ids, in the file's order.

    Raises
    ------
    InputError
        If the file is too large, not UTF-8, has no single ``id`` column, an id that is not valid or repeats, or
        no students.
    """
    raw = read_small(path, MAX_ROSTER_BYTES, "roster")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise InputError(f"{path}: the roster is not UTF-8 text") from None
    rows = list(csv.reader(text_io.StringIO(text)))
    header = [cell.strip().lower() for cell in rows[0]] if rows else []
    if "id" not in header:
        raise InputError(f"{path}: a roster is a CSV file whose first row names an 'id' column")
    if header.count("id") > 1:
        raise InputError(f"{path}: the first row names {header.count('id')} 'id' columns; name one")
    column = header.index("id")
    ids, seen = [], {}
    for number, row in enumerate(rows[1:], start=2):
        if not any(cell.strip() for cell in row):
            continue
        student = row[column].strip() if column < len(row) else ""
        check_student_id(student, f"{path}, row {number}: student id")
        if student.casefold() in seen:
            other, first = seen[student.casefold()]
            same = "repeats" if other == student else f"differs only in case from {other!r} of"
            raise InputError(f"{path}, row {number}: student id {student!r} {same} row {first} (one folder each, and "
                             "some file systems do not tell case apart)")
        seen[student.casefold()] = (student, number)
        ids.append(student)
    if not ids:
        raise InputError(f"{path}: the roster lists no students")
    return ids


__all__ = ["COURSE_STUDENT", "Variant", "check_student_id", "read_roster", "rng_for", "robot_variant"]

"""The assignment file: what students must compute, on which robot, and how it is scored.

An assignment is a small TOML file (see :data:`EXAMPLE`, printed by
``course-dynamics grade --example-assignment``). Every key is checked when the
file is read; a bad one is an :class:`~course_dynamics.base.errors.InputError`
naming the file and the key.
"""
from __future__ import annotations

import hashlib
import math
import re
import tomllib
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

from ..base.errors import InputError
from ..core.model import STANDARD_GRAVITY, Model
from ..core.robots import COURSE_ROBOTS, load, robot_names
from ..core.urdf import InertiaWarning
from ..tools.variants import check_student_id, read_roster, rng_for, robot_variant

#: The terms an assignment can grade, in the order they are graded and shown (τ, M(Θ), V(Θ, Θ̇), G(Θ),
#: C(Θ, Θ̇)).
TERMS = ("tau", "M", "V", "G", "C")
PARTIAL_CREDIT = ("states", "none")
#: The ways graded functions receive the robot, ``"functions"`` (``tau(q, qd, qdd)``, the robot's numbers the
#: student's own) and ``"robot"`` (``tau(robot, q, qd, qdd)``, called on the practice robot and on hidden robots).
INTERFACES = ("functions", "robot")
DEFAULT_FORBIDDEN = ("pinocchio", "course_dynamics", "course_dynamics_reference")
MAX_SAMPLES = 1000
MIN_MEMORY = 256  # MiB: Python with numpy needs about this much address space

#: The example assignment file, with every key explained in its comments (what
#: ``course-dynamics grade --example-assignment`` prints).
EXAMPLE = '''\
# A course-dynamics assignment: `course-dynamics grade THIS_FILE submissions/*.py --out grades/`

robot = "two_link"          # a shipped robot's name, or a URDF path relative to this file
# gravity = [0.0, 0.0, -9.81]        # m/s^2 in the base frame (the default); tell students if you change it
# allow_nonphysical_inertia = false  # true loads a URDF whose inertias break the triangle inequality
samples = 40                # seeded random states (within joint limits; velocities, accelerations ~ N(0, 1))
seed = 7                    # with each file's own text, chooses the states it is graded on: the same file
                            # always gets the same states, and a table of answers read off earlier feedback
                            # does not fit a file of its own
# states = "per-file"       # "shared": every file on the same states of the seed (a table of answers
                            # computed from the seed would then pass)
tolerance = 1e-6            # relative error allowed per state and term, against course_dynamics
                            # (which agrees with Pinocchio to 1e-9)
time_limit = 20             # CPU seconds per submission; the wall clock allows 2 x time_limit + 5 s
memory_limit = 1024         # MiB per submission
output_limit = 1000000      # bytes a submission may print; more is status "output limit" and no points
forbidden_imports = ["pinocchio", "course_dynamics", "course_dynamics_reference"]
# A submission's Python holds the standard library and numpy, nothing else installed: forbidden packages
# are not there to be imported. allowed_imports adds installed packages by module name (list a package's
# own dependencies too, e.g. ["sympy", "mpmath"]).
allowed_imports = []

# Partial credit per term: "states" gives points x (fraction of states that agree);
# "none" gives the points only when every state agrees.
partial_credit = "states"

# flags_in_feedback = false  # true: a student's own feedback lists its integrity flags too (they are always in
#                           # the gradebook's flags column and the summary; they never change a score)

# gradescope_student = "email"  # in the Gradescope bundle (`grade THIS_FILE --gradescope autograder.zip`), the
#                               # user field of submission_metadata.json that names the student: "email" (its
#                               # local part, the default), or another field such as "sid" or "id"

# interface = "robot"       # every graded function takes the robot as plain data first: tau(robot, q, qd, qdd),
#                           # M(robot, q), ... (`grade THIS_FILE --handout ID` prints its keys); graded on the
#                           # robot above and on hidden robots of its shape (other lengths, masses, inertias,
#                           # axes), new ones for every file, so a closed form worked out for one robot, or code
#                           # generated for it, fails. The default "functions": tau(q, qd, qdd) for this robot.

# roster = "roster.csv"     # a CSV file (next to this one) whose 'id' column lists the students: a submission's id
#                           # (its file name, or on Gradescope the e-mail's local part) is matched to it exactly,
#                           # else ignoring case and a "+tag" when that names one student; one on no roster
#                           # scores 0 with status "not on roster". Without a roster, ids are taken as given.

# variant = "per-student"   # each student (the submission's file name) on their own variant of the course robot
#                           # and states, as `student-notebooks --student ID` gives them; `grade THIS_FILE
#                           # --handout ID` prints a student's numbers. The default "same" grades all alike.

# Points per term; any of tau, M, V, G, C. A submission is one Python file that defines
# any of  tau(q, qd, qdd)  M(q)  V(q, qd)  G(q)  C(q, qd)  taking numpy arrays in the joint
# order `course-dynamics info` prints and returning arrays: tau, V, G of shape (n,), M and C (n, n).
# A term the student does not define is derived from their tau, as the library does:
# G = tau(q, 0, 0), V = tau(q, qd, 0) - G, column j of M = tau(q, 0, e_j) - G, and
# C (the Christoffel form, C qd = V) from M by central differences (accurate to about 1e-8,
# so a derived C is held to a tolerance of at least 1e-7).
[points]
tau = 40
M = 20
V = 20
G = 20
'''


@dataclass(frozen=True)
class Assignment:
    """A checked assignment file; ``robot`` is the loaded model, ``source`` the TOML path.

    Parameters
    ----------
    source : pathlib.Path
        The assignment's TOML file.
    robot_argument : str
        Its ``robot`` key as written: a shipped robot's name or a URDF path.
    robot : Model
        The loaded robot, with the assignment's gravity.
    points : dict of str to float
        Points per graded term (keys among :data:`TERMS`), in the order of :data:`TERMS`.
    samples : int
        How many seeded random states each submission is graded on.
    seed : int
        The seed of those states.
    tolerance : float
        The relative error allowed per state and term.
    time_limit : float
        CPU seconds per submission, s.
    memory_limit : int
        Memory per submission, MiB.
    output_limit : int
        Bytes a submission may print.
    forbidden_imports : tuple of str
        Modules a submission may not import.
    allowed_imports : tuple of str
        Installed packages, by module name, added to a submission's Python.
    partial_credit : str
        ``"states"`` (points times the fraction of states that agree) or ``"none"`` (all or nothing).
    notes : tuple of str
        Notes that go with the assignment (none is read from the file).
    variant : str
        ``"same"``, or ``"per-student"``: each student on their own variant of the course robot and states.
    flags_in_feedback : bool
        Whether a student's own feedback lists its integrity flags.
    gradescope_student : str
        The user field of Gradescope's submission metadata that names the student.
    states : str
        ``"per-file"`` (states seeded by the seed and the file's text) or ``"shared"`` (the seed's states for all).
    interface : str
        ``"functions"`` (``tau(q, qd, qdd)``) or ``"robot"`` (``tau(robot, q, qd, qdd)``, on hidden robots too).
    roster : tuple of str or None
        The roster's student ids; None when the assignment names no roster.
    """

    source: Path
    robot_argument: str
    robot: Model
    points: dict[str, float]
    samples: int = 40
    seed: int = 0
    tolerance: float = 1e-6
    time_limit: float = 20.0
    memory_limit: int = 1024
    output_limit: int = 1_000_000
    forbidden_imports: tuple[str, ...] = DEFAULT_FORBIDDEN
    allowed_imports: tuple[str, ...] = ()
    partial_credit: str = "states"
    notes: tuple[str, ...] = field(default=())
    variant: str = "same"  # "per-student": each student's own robot and states (tools/variants)
    flags_in_feedback: bool = False  # a student's feedback lists its integrity flags
    gradescope_student: str = "email"  # the user field of Gradescope's metadata that names the student
    states: str = "per-file"  # "shared": every submission on the seed's states
    interface: str = "functions"  # "robot": the robot is every graded function's first argument
    roster: tuple[str, ...] | None = None  # the roster's ids, None without one

    def for_student(self, student: str, where: str = "") -> Assignment:
        """The assignment as ``student`` is graded: with ``variant = "per-student"``, on their own variant of the
        course robot and their own states (the notebooks' mechanism); otherwise unchanged. ``where`` names what
        gave the id (a submission file) in an error.

        Parameters
        ----------
        student : str
            The student's id.
        where : str
            What gave the id, for an error; the assignment's file when empty.

        Returns
        -------
        Assignment
            The assignment for that student.

        Raises
        ------
        InputError
            If ``variant = "per-student"`` and ``student`` is not a valid student id.
        """
        if self.variant != "per-student":
            return self
        chosen = robot_variant(self.robot_argument, check_student_id(student, f"{where or self.source}: student id"))
        seed = int(rng_for(student, f"assignment seed {self.seed}").integers(2**31))
        return replace(self, robot=chosen.model.with_gravity(self.robot.gravity), seed=seed)

    def for_submission(self, student: str, source: bytes, where: str = "") -> Assignment:
        """The assignment as this submission is graded: :meth:`for_student`, on states of its own, seeded by the
        assignment's seed and the file's bytes (so a lookup table cannot be made for the states it will meet).

        Parameters
        ----------
        student : str
            The student's id.
        source : bytes
            The submission file's bytes.
        where : str
            What gave the id, for an error; the assignment's file when empty.

        Returns
        -------
        Assignment
            The assignment for that submission: with ``states = "shared"``, that of :meth:`for_student`.

        Raises
        ------
        InputError
            If ``variant = "per-student"`` and ``student`` is not a valid student id.
        """
        graded = self.for_student(student, where)
        if self.states == "shared":
            return graded
        digest = hashlib.sha256(f"{graded.seed}".encode() + b"\0" + source).digest()
        return replace(graded, seed=int.from_bytes(digest[:4], "little") & 0x7FFFFFFF)

    @property
    def total_points(self) -> float:
        """The points of all graded terms together."""
        return float(sum(self.points.values()))

    @property
    def terms(self) -> tuple[str, ...]:
        """The graded terms, in the order tau, M, V, G, C."""
        return tuple(t for t in TERMS if t in self.points)


KEYS = {"robot", "samples", "seed", "tolerance", "time_limit", "memory_limit", "output_limit", "forbidden_imports",
        "allowed_imports", "partial_credit", "points", "gravity", "allow_nonphysical_inertia", "variant",
        "flags_in_feedback", "gradescope_student", "states", "interface", "roster"}
STATES = ("per-file", "shared")
VARIANTS = ("same", "per-student")


def load_assignment(path) -> Assignment:
    """Read and check an assignment TOML file (module docstring).

    Parameters
    ----------
    path : str or os.PathLike
        The assignment's TOML file; a URDF ``robot`` is found relative to it.

    Returns
    -------
    Assignment
        The checked assignment, its robot loaded.

    Raises
    ------
    InputError
        If the file cannot be read, is not TOML, or has an unknown key or a bad value (naming the file and the key),
        or the robot's URDF file cannot be read.
    UnknownRobotError
        If ``robot`` is neither a shipped robot nor a file.
    ModelError
        If the robot's URDF file is no robot the dynamics can use.
    """
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise InputError(f"{path}: is a directory, expected an assignment .toml file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: cannot read: {exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path}: not valid TOML: {exc}") from None
    unknown = sorted(set(data) - KEYS)
    if unknown:
        raise InputError(f"{path}: unknown key '{unknown[0]}' (keys are {', '.join(sorted(KEYS))})")

    def number(key, default, kind=float, positive=True):
        value = data.get(key, default)
        if (isinstance(value, bool) or not isinstance(value, (int, float))
                or (kind is int and not isinstance(value, int))):
            raise InputError(f"{path}: {key} must be a{'n integer' if kind is int else ' number'}, got {value!r}")
        if not math.isfinite(value) or (positive and value <= 0) or value < 0:
            raise InputError(f"{path}: {key} must be {'positive' if positive else 'non-negative'} and finite, "
                             f"got {value!r}")
        return kind(value)

    robot_argument = data.get("robot")
    if not isinstance(robot_argument, str) or not robot_argument:
        raise InputError(f"{path}: robot must name a shipped robot ({', '.join(robot_names())}) or a URDF file")
    target = robot_argument if robot_argument in robot_names() else str(path.parent / robot_argument)
    if robot_argument not in robot_names() and not Path(target).exists() and not Path(target).suffix:
        raise InputError(f"{path}: robot '{robot_argument}' is neither a shipped robot ({', '.join(robot_names())}) "
                         f"nor a URDF file next to the assignment")
    gravity = data.get("gravity", list(STANDARD_GRAVITY))
    if (not isinstance(gravity, list) or len(gravity) != 3
            or not all(isinstance(g, (int, float)) and not isinstance(g, bool) and math.isfinite(g) and abs(g) <= 1e6
                       for g in gravity)):
        raise InputError(f"{path}: gravity must be three finite numbers [gx, gy, gz] of at most 1e6 m/s^2, "
                         f"got {gravity!r}")
    allow, show_flags = data.get("allow_nonphysical_inertia", False), data.get("flags_in_feedback", False)
    for key, value in (("allow_nonphysical_inertia", allow), ("flags_in_feedback", show_flags)):
        if not isinstance(value, bool):
            raise InputError(f"{path}: {key} must be true or false, got {value!r}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InertiaWarning)  # the instructor asked for it
        model = load(target, gravity=[float(g) for g in gravity], allow_nonphysical_inertia=allow)
    points = data.get("points")
    if not isinstance(points, dict) or not points:
        raise InputError(f"{path}: [points] must give points to at least one of {', '.join(TERMS)}")
    for term, value in points.items():
        if term not in TERMS:
            raise InputError(f"{path}: points: unknown term '{term}' (terms are {', '.join(TERMS)})")
        if (isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value < 0
                or value > 1e6):
            raise InputError(f"{path}: points.{term} must be a number from 0 to 1e6, got {value!r}")
    forbidden = data.get("forbidden_imports", list(DEFAULT_FORBIDDEN))
    if not isinstance(forbidden, list) or not all(isinstance(x, str) and x.isidentifier() for x in forbidden):
        raise InputError(f"{path}: forbidden_imports must be a list of module names, got {forbidden!r}")
    allowed = data.get("allowed_imports", [])
    if not isinstance(allowed, list) or not all(isinstance(x, str) and x.isidentifier() for x in allowed):
        raise InputError(f"{path}: allowed_imports must be a list of module names, got {allowed!r}")
    both = sorted(set(allowed) & set(forbidden))
    if both:
        raise InputError(f"{path}: '{both[0]}' is both forbidden and allowed")
    partial = data.get("partial_credit", "states")
    if partial not in PARTIAL_CREDIT:
        raise InputError(f"{path}: partial_credit must be one of {', '.join(PARTIAL_CREDIT)}, got {partial!r}")
    variant = data.get("variant", "same")
    if variant not in VARIANTS:
        raise InputError(f"{path}: variant must be one of {', '.join(VARIANTS)}, got {variant!r}")
    if variant == "per-student" and robot_argument not in COURSE_ROBOTS:
        raise InputError(f"{path}: variant = \"per-student\" needs a course robot ({', '.join(COURSE_ROBOTS)}), "
                         f"not '{robot_argument}'")
    field_name = data.get("gradescope_student", "email")
    if not isinstance(field_name, str) or not re.fullmatch(r"[a-z][a-z_]{0,31}", field_name):
        raise InputError(f"{path}: gradescope_student must name a user field of Gradescope's submission metadata "
                         f"(such as \"email\" or \"sid\"), got {field_name!r}")
    states = data.get("states", "per-file")
    if states not in STATES:
        raise InputError(f"{path}: states must be one of {', '.join(STATES)}, got {states!r}")
    interface = data.get("interface", "functions")
    if interface not in INTERFACES:
        raise InputError(f"{path}: interface must be one of {', '.join(INTERFACES)}, got {interface!r}")
    roster = data.get("roster")
    if roster is not None:
        if not isinstance(roster, str) or not roster:
            raise InputError(f"{path}: roster must name a CSV file next to the assignment, got {roster!r}")
        if not (path.parent / roster).is_file():
            raise InputError(f"{path}: roster '{roster}' is no file next to the assignment")
        roster = tuple(read_roster(path.parent / roster))
    samples, memory = number("samples", 40, int), number("memory_limit", 1024, int)
    if samples > MAX_SAMPLES:
        raise InputError(f"{path}: samples must be at most {MAX_SAMPLES}, got {samples}")
    if memory < MIN_MEMORY:
        raise InputError(f"{path}: memory_limit must be at least {MIN_MEMORY} MiB (Python and numpy need it), "
                         f"got {memory}")
    return Assignment(
        source=path, robot_argument=robot_argument, robot=model,
        points={t: float(points[t]) for t in TERMS if t in points},
        samples=samples, seed=number("seed", 0, int, positive=False),
        tolerance=number("tolerance", 1e-6), time_limit=number("time_limit", 20.0),
        memory_limit=memory, output_limit=number("output_limit", 1_000_000, int),
        forbidden_imports=tuple(forbidden), allowed_imports=tuple(allowed), partial_credit=partial, variant=variant,
        flags_in_feedback=show_flags, gradescope_student=field_name, states=states, interface=interface,
        roster=roster,
    )


__all__ = ["EXAMPLE", "INTERFACES", "TERMS", "Assignment", "load_assignment"]

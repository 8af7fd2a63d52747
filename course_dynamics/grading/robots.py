"""The robots of ``interface = "robot"``: the student's practice robot and hidden ones of its shape, as plain data.

With ``interface = "robot"`` every graded function takes the robot as its first argument
(``tau(robot, q, qd, qdd)``, ``M(robot, q)``, …) and is called on the practice robot (the
assignment's, or the student's own variant) and on :data:`HIDDEN_ROBOTS` more of the same
shape, drawn from the seed of the submission's states (the assignment's seed and the file's
bytes: every resubmission meets other robots). A closed form worked out for the practice
robot, or code the library generated for it, is right on that robot and wrong on the others.

=====================  ===================================================================
what a hidden robot    how (factors drawn per link)
=====================  ===================================================================
tree, joint types      the practice robot's: parents, revolute or prismatic, joint limits
lengths                ᵖPᵢ × λ and ⁱP_Cᵢ × λ', λ, λ' ∈ [0.6, 1.6] (directions kept)
joint axes             a planar robot (in the base frame at Θ = 0, its revolute axes
                       parallel, its prismatic ones perpendicular to them) keeps its
                       axes, each with a random sign; any other gets random unit axes
masses                 mᵢ × μ, μ ∈ [0.5, 2]
inertia tensors        a new body: second moments (x, y, z) ∈ [0.2, 1] × mᵢ ℓᵢ², ℓᵢ the
                       link's length scale, turned by a random rotation; its principal
                       moments y + z, x + z, x + y are positive and obey the triangle
                       inequality
=====================  ===================================================================

The robot crosses into the sandbox as numbers (:func:`robot_record`); the harness gives each call its own copy with
numpy arrays (:func:`~course_dynamics.grading.harness.robot_data`, which documents the keys). No hidden robot's
numbers reach any output: the feedback shows the practice robot's states alone.
"""
from __future__ import annotations

import hashlib
from dataclasses import replace

import numpy as np
from scipy.spatial.transform import Rotation

from ..core.model import Model
from .assignment import Assignment
from .records import Diagnosis

#: How many hidden robots of the practice robot's shape a submission of ``interface = "robot"`` is also graded on.
HIDDEN_ROBOTS = 3
LENGTHS, MASSES, MOMENTS = (0.6, 1.6), (0.5, 2.0), (0.2, 1.0)
PARALLEL = 1e-9  # |a × b| below which two unit axes are parallel
#: What a student of ``interface = "robot"`` is told (``grade ASSIGNMENT --handout ID`` prints it).
INTERFACE = """\
interface = "robot": write tau(robot, q, qd, qdd), M(robot, q), V(robot, q, qd), G(robot, q), C(robot, q, qd).
robot is plain data, numpy arrays and numbers (a copy of its own for every call):
  robot["gravity"]: (3,) gravity g in the base frame, m/s^2
  robot["joints"][i]: "name"; "parent", the index of the link it hangs from (-1: the fixed base);
    "type", "revolute" or "prismatic"; "axis", (3,) its unit axis in its own frame i;
    "xyz", (3,) m, and "rpy", (3,) rad, the origin and rotation of frame i in its parent's frame at q = 0
    (URDF's: R = Rz(yaw) Ry(pitch) Rx(roll)); "origin", (4, 4), the same as one transform
  robot["links"][i], the link joint i moves: "name"; "mass", kg; "com", (3,) its centre of mass in frame i, m;
    "inertia", (3, 3) kg m^2, about the centre of mass, axes of frame i
A revolute joint turns frame i about its axis by q[i] (R = R_origin Rot(axis, q[i])); a prismatic one slides it
along its axis by q[i]. Your functions are graded on your robot and on robots of its shape you do not see (other
lengths, masses, inertias, axes): compute everything from robot, nothing from numbers of your own."""
#: The one sentence of a term right on the practice robot and wrong on a hidden one.
OWN_NUMBERS = "right on your robot, wrong on others: your code assumes your robot's numbers"


def _planar(model: Model) -> bool:
    """Whether the robot moves in a plane: in the base frame at Θ = 0, every revolute axis parallel to the first
    and every prismatic axis perpendicular to it (a robot of prismatic joints alone keeps its axes too)."""
    rotations, revolute, prismatic = [], [], []
    for body in model.bodies:
        R = (rotations[body.parent] if body.parent >= 0 else np.eye(3)) @ np.asarray(body.R0, dtype=float)
        rotations.append(R)
        (prismatic if body.is_prismatic else revolute).append(R @ np.asarray(body.axis, dtype=float))
    if not revolute:
        return True
    normal = revolute[0]
    return all(np.linalg.norm(np.cross(normal, a)) < PARALLEL for a in revolute) and \
        all(abs(normal @ a) < PARALLEL for a in prismatic)


def hidden_robot(model: Model, rng: np.random.Generator) -> Model:
    """A robot of ``model``'s shape with other numbers (module table).

    Parameters
    ----------
    model : Model
        The practice robot.
    rng : numpy.random.Generator
        Where the factors come from.

    Returns
    -------
    Model
        The hidden robot: the same tree, joint types, limits and gravity.
    """
    planar, bodies = _planar(model), []
    for body in model.bodies:
        P = np.asarray(body.P, dtype=float) * rng.uniform(*LENGTHS)
        p_com = np.asarray(body.p_com, dtype=float) * rng.uniform(*LENGTHS)
        if planar:
            axis = np.asarray(body.axis, dtype=float) * rng.choice((-1.0, 1.0))
        else:
            axis = rng.normal(size=3)
            axis /= np.linalg.norm(axis)
        mass = float(body.mass) * rng.uniform(*MASSES)
        length = max(float(np.linalg.norm(P)), float(np.linalg.norm(p_com)), 0.05)
        x, y, z = rng.uniform(*MOMENTS, 3) * mass * length**2
        R = Rotation.random(random_state=rng).as_matrix()
        I_com = R @ np.diag([y + z, x + z, x + y]) @ R.T
        bodies.append(replace(body, P=P, p_com=p_com, axis=axis, mass=mass, I_com=(I_com + I_com.T) / 2))
    return replace(model, name=f"{model.name} (hidden)", bodies=tuple(bodies), frames=())


def hidden_assignments(assignment: Assignment, count: int = HIDDEN_ROBOTS) -> list[Assignment]:
    """The assignment on each hidden robot, with states of its own, all drawn from the submission's seed.

    Parameters
    ----------
    assignment : Assignment
        The assignment as this submission is graded
        (:meth:`~course_dynamics.grading.assignment.Assignment.for_submission`).
    count : int
        How many hidden robots.

    Returns
    -------
    list of Assignment
        One per hidden robot: its robot and the seed of its states.
    """
    found = []
    for k in range(count):
        digest = hashlib.sha256(f"hidden robot {k}\0{assignment.seed}".encode()).digest()
        rng = np.random.default_rng(int.from_bytes(digest[:16], "little"))
        found.append(replace(assignment, robot=hidden_robot(assignment.robot, rng),
                             seed=int(rng.integers(2**31))))
    return found


def _rpy(R: np.ndarray) -> list[float]:
    """URDF roll, pitch, yaw of a rotation: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    if np.allclose(R, np.eye(3), rtol=0, atol=0):
        return [0.0, 0.0, 0.0]
    return Rotation.from_matrix(R).as_euler("xyz").tolist()


def robot_record(model: Model) -> dict:
    """``model`` as the harness receives it: the keys of :func:`~course_dynamics.grading.harness.robot_data`, in
    lists of floats.

    Parameters
    ----------
    model : Model
        The robot (numeric).

    Returns
    -------
    dict
        ``gravity``, ``joints`` (name, parent, type, axis, xyz, rpy, origin) and ``links`` (name, mass, com, inertia).
    """
    joints, links = [], []
    for body in model.bodies:
        R, P = np.asarray(body.R0, dtype=float), np.asarray(body.P, dtype=float)
        origin = np.eye(4)
        origin[:3, :3], origin[:3, 3] = R, P
        joints.append({"name": body.joint, "parent": int(body.parent),
                       "type": "prismatic" if body.joint_type == "prismatic" else "revolute",
                       "axis": np.asarray(body.axis, dtype=float).tolist(), "xyz": P.tolist(), "rpy": _rpy(R),
                       "origin": origin.tolist()})
        links.append({"name": body.name, "mass": float(body.mass), "com": np.asarray(body.p_com, dtype=float).tolist(),
                      "inertia": np.asarray(body.I_com, dtype=float).tolist()})
    return {"gravity": np.asarray(model.gravity, dtype=float).tolist(), "joints": joints, "links": links}


def combined(practice: Diagnosis, hidden: list[Diagnosis], partial_credit: str) -> Diagnosis:
    """One term's diagnosis on the practice robot and the hidden ones: points from the states of all, the practice
    robot's findings and worst state, or :data:`OWN_NUMBERS` when only the hidden robots disagree.

    Parameters
    ----------
    practice : Diagnosis
        The term on the practice robot.
    hidden : list of Diagnosis
        The term on each hidden robot (never shown: only whether and where they agree counts).
    partial_credit : str
        ``"states"`` or ``"none"``, as in :func:`~course_dynamics.grading.score.score`.

    Returns
    -------
    Diagnosis
        The term's diagnosis, its states those of every robot (the practice robot's first).
    """
    agreeing, total = list(practice.agreeing), practice.total
    for other in hidden:
        agreeing += [total + k for k in other.agreeing]
        total += other.total
    if partial_credit == "states":
        points = round(practice.max_points * len(agreeing) / total, 2) if total else 0.0
    else:
        points = practice.max_points if total and len(agreeing) == total else 0.0
    found = {}
    if practice.correct and len(agreeing) < total:
        found = dict(findings=(OWN_NUMBERS,), tags=("own numbers",), worst="")
    return replace(practice, points=points, agreeing=tuple(agreeing), total=total, **found)


__all__ = ["HIDDEN_ROBOTS", "INTERFACE", "OWN_NUMBERS", "combined", "hidden_assignments", "hidden_robot",
           "robot_record"]

"""What the URDF linter reports: its classes of finding, each with a severity and a fix, and the finding record.

A class is a name (the ``ruleId`` of a SARIF result), a severity and a fix. Severities, weakest first:

===========  ==============================================================================================
severity     meaning
===========  ==============================================================================================
``note``     legal and read as written here, but some engine or importer reads it otherwise
``warning``  probably not what the author meant: the dynamics of the file are likely wrong
``error``    the loader or the other URDF readers refuse the file, or its dynamics are degenerate
===========  ==============================================================================================

:data:`CLASSES` is the table the site's lint page prints; :func:`empty_subtrees` is the one test of "a joint
that carries nothing", run by the linter on a URDF's links and by ``validate`` and ``terms`` on a model's bodies.

>>> CLASSES["point-mass"].severity
'note'
>>> empty_subtrees([-1, 0, 1], [True, False, False])   # a root with mass, then two bodies carrying nothing
[False, True, True]
"""
from __future__ import annotations

import re
from dataclasses import dataclass

from ..base.errors import ModelError
from ..core.urdf import load_urdf

#: The severities, weakest first.
SEVERITIES = ("note", "warning", "error")


@dataclass(frozen=True)
class LintClass:
    """One class of finding.

    Parameters
    ----------
    name : str
        Its name, as findings, ``--json`` and SARIF (``ruleId``) give it: ``"negative-mass"``.
    severity : str
        One of :data:`SEVERITIES`.
    summary : str
        What it finds, one line.
    fix : str
        How to fix it, one or two sentences.
    """

    name: str
    severity: str
    summary: str
    fix: str


def _classes(*rows) -> dict:
    return {name: LintClass(name, severity, summary, fix) for name, severity, summary, fix in rows}


NO_FRICTION_ENGINES = "Pinocchio's RNEA and Isaac Sim's importer ignore it, MuJoCo's mj_inverse adds it"

#: Every class of finding, by name, in the order the site's table lists them.
CLASSES: dict[str, LintClass] = _classes(
    # The file as a tree of links and joints
    ("not-a-urdf", "error", "a file that is no URDF at all: missing, too large, not XML, no <robot>",
     "Give lint the URDF (a xacro file must be expanded first: xacro robot.urdf.xacro > robot.urdf)."),
    ("unreadable-number", "error", "a number URDF does not write, non-finite, or beyond 1e9 in size",
     "Write plain decimal numbers (1.5, 2e-3), finite, in SI units."),
    ("padded-number", "warning", "a number written with spaces around it where URDF has one number",
     "Remove the spaces: urdfdom (ROS, Pinocchio) does not read such a number (in <inertial>, it drops it whole)."),
    ("xml-namespace", "error", "an element in a default XML namespace (xmlns=\"...\")",
     "Remove the xmlns attribute: URDF readers disagree on whether the element is a URDF element."),
    ("empty-name", "error", "a link or joint with an empty name",
     "Give every link and joint a name."),
    ("duplicate-name", "error", "two links, or two joints, with one name",
     "Rename one of them, and the joints that refer to it."),
    ("unusable-name", "error", "a name holding a control character, or longer than 1000 characters",
     "Use a name of printable characters, as short as a CSV column header should be."),
    ("undefined-link", "error", "a joint whose parent or child link is not defined",
     "Define the link, or correct the joint's <parent link> or <child link>."),
    ("unsupported-joint", "error", "a joint type other than revolute, continuous, prismatic or fixed",
     "Fixed-base robots only: replace a floating or planar joint by the fixed base or by simple joints."),
    ("not-a-tree", "error", "a kinematic loop, several root links or a link no joint reaches",
     "Make the links one tree: every link but one root is the child of exactly one joint."),
    ("nothing-moves", "error", "no revolute, continuous or prismatic joint",
     "Add the robot's moving joints: with fixed joints only there are no dynamics."),
    ("refused", "error", "anything else the loader refuses (its message says what)",
     "Correct what the message names."),
    # Masses and inertias
    ("no-mass", "error", "no link has a mass: every torque is zero, M(q) is zero",
     "Add <inertial> to the moving links (from the CAD model, or identify them: course-dynamics identify)."),
    ("joint-carries-nothing", "error", "a moving joint with no mass and no inertia beyond it: its column of M is 0",
     "Add <inertial> to the link it moves (and to the links beyond), or make the joint fixed."),
    ("missing-inertial", "warning", "the link a moving joint moves has no <inertial>",
     "Add its <inertial> (mass, centre of mass, inertia), even if a link beyond carries mass."),
    ("incomplete-inertial", "error", "an <inertial> without its <mass> or its <inertia>",
     "Write both: urdfdom (ROS, Pinocchio), MuJoCo and PyBullet refuse the file (read here as 0)."),
    ("negative-mass", "error", "a negative mass",
     "Write the link's mass in kilograms, positive."),
    ("zero-mass", "warning", "an <inertial> of mass 0",
     "Give the link its mass, or remove the <inertial>; with mass 0 the inertia must be 0 too."),
    ("inertia-not-psd", "error", "an inertia tensor with a negative principal moment",
     "Recompute the tensor about the centre of mass; check the sign convention of the products "
     "(URDF's ixy is +I_xy of the matrix, with no minus sign)."),
    ("triangle-inequality", "error", "principal moments with I1 + I2 < I3: no body has them",
     "Recompute the tensor; a tensor giving only izz (planar models) breaks it: give ixx and iyy too."),
    ("base-inertia-not-physical", "warning", "an inertia no body has, on a link fixed to the base",
     "Recompute the tensor: the loader ignores it (the link moves nothing here), an engine that moves the base "
     "uses it."),
    ("inertia-on-boundary", "warning", "principal moments with I1 + I2 = I3 or a zero moment (a flat plate, a rod)",
     "Give the body some thickness: engines that check strictly (or after rounding) refuse the tensor."),
    ("point-mass", "note", "a positive mass with zero rotational inertia (a point mass, as in the textbook robots)",
     "None needed for the textbook's models; engines that need a positive-definite inertia refuse it."),
    ("inertial-rpy", "note", "an <inertial><origin rpy> that is not 0 0 0: some importers drop it",
     "Write the tensor in the link's axes (the message gives it) with rpy=\"0 0 0\"."),
    # Inertias against the link's geometry (collision shapes, else visual shapes: boxes, cylinders, spheres)
    ("implausible-density", "warning", "mass over the shapes' volume outside 10 to 25 000 kg/m^3",
     "Check the mass and the shapes: no solid is lighter than foam or denser than osmium."),
    ("gyration-exceeds-link", "warning", "a radius of gyration larger than the link's shapes reach, or the robot",
     "Check the inertia: sqrt(I/m) about the centre of mass cannot exceed the farthest point of the body."),
    ("com-outside-geometry", "warning", "the centre of mass outside the box around the link's shapes",
     "Check the <inertial><origin xyz>: it is in the link's frame, in metres."),
    ("units-slip", "warning",
     "values off by a power of 10^3 from what the shapes or the joints imply (grams, millimetres)",
     "Convert to SI: kilograms, metres, kg m^2 (1 g = 1e-3 kg, 1 mm = 1e-3 m, 1 kg mm^2 = 1e-6 kg m^2)."),
    ("placeholder-inertia", "note", "a negligible mass (under 1e-3 of the robot's) that does not fit its shapes",
     "None needed: a placeholder (a sensor's or a frame's) weighs nothing in the dynamics; a real mass is better."),
    # Inertias against the joints (no shapes needed)
    ("mass-beyond-effort", "warning", "a joint that could not hold what it carries against gravity, by 100 times",
     "Check the masses (grams?) and the joint's effort limit."),
    # Joints
    ("missing-limit", "error", "a revolute or prismatic joint without <limit>: URDF requires one",
     "Add <limit lower upper effort velocity>; urdfdom (ROS, Pinocchio's parser) refuses the file without it."),
    ("reversed-limits", "error", "a joint limit with lower > upper",
     "Swap lower and upper."),
    ("zero-range", "warning", "a moving joint with lower = upper (both default to 0): it cannot move",
     "Give the joint its range, or make it fixed."),
    ("huge-limits", "warning", "a limit of +-1.79e308 (DBL_MAX) or infinite",
     "Write the joint's real range (a revolute joint without one is a continuous joint)."),
    ("zero-effort-velocity", "warning", "an effort or velocity limit of 0 or missing",
     "Write the actuator's limits: engines that enforce them hold the joint still (read here as no limit)."),
    ("negative-effort-velocity", "error", "a negative effort or velocity limit",
     "Write the limits as positive numbers."),
    ("zero-axis", "error", "a joint axis of zero length",
     "Write the axis as a unit vector in the joint's frame."),
    ("axis-not-unit", "warning", "a joint axis that is not a unit vector",
     "Normalise it: URDF asks for a unit vector; read normalised here, as Pinocchio, MuJoCo and PyBullet read it."),
    ("mimic-joint", "note", "a <mimic> joint, honoured: it has no coordinate of its own",
     "Give states and logs one value per independent joint: the mimic joint follows multiplier * q + offset of "
     "the joint it names, and its torque acts on that joint's; engines that ignore <mimic> (PyBullet) give it a "
     "coordinate of its own."),
    ("mimic-on-fixed", "warning", "a <mimic> on a fixed joint, which moves nothing: ignored",
     "Remove the <mimic>, or make the joint revolute, continuous or prismatic if it is meant to follow another."),
    ("mimic-pinocchio-cannot-build", "note", "a mimic of a form honoured here that Pinocchio 4.1 cannot build: its "
     "leader later in the tree, a mimic of a mimic, or a continuous joint coupled to one that is not",
     "Nothing to change for course-dynamics; for Pinocchio, name the leader's own leader, order the leader "
     "first, or give both joints one type (validate and crosscheck say why Pinocchio is not compared)."),
    ("damping-friction", "note", "a joint <dynamics damping friction> that engines treat differently",
     f"Know where it counts: course-dynamics uses it only with --friction urdf; {NO_FRICTION_ENGINES}."),
)


@dataclass(frozen=True)
class Finding:
    """One finding of the linter.

    Parameters
    ----------
    rule : str
        The name of its class in :data:`CLASSES`.
    element : str
        ``"link"``, ``"joint"`` or ``"robot"``.
    name : str
        The name of that link, joint or robot.
    message : str
        What is wrong, with the values read.
    line : int or None, optional
        The line of the element in the URDF file (1 is the first), when known: the line its start tag ends on,
        as the XML parser counts; ``course-dynamics lint`` gives the line it starts on (found by
        :mod:`course_dynamics.output.xml_spans`), which differs for a start tag written over several lines.
    """

    rule: str
    element: str
    name: str
    message: str
    line: int | None = None

    @property
    def severity(self) -> str:
        """The severity of its class, ``"note"``, ``"warning"`` or ``"error"``."""
        return CLASSES[self.rule].severity

    @property
    def fix(self) -> str:
        """Its class's fix."""
        return CLASSES[self.rule].fix

    def as_dict(self) -> dict:
        """The finding as JSON-ready data.

        Returns
        -------
        dict
            ``rule``, ``severity``, ``element``, ``name``, ``line``, ``message`` and ``fix``.
        """
        return dict(rule=self.rule, severity=self.severity, element=self.element, name=self.name, line=self.line,
                    message=self.message, fix=self.fix)


def empty_subtrees(parents, loaded) -> list[bool]:
    """Which nodes of a tree carry nothing: neither they nor any node below them is loaded.

    The one test of "a moving joint that carries nothing": a joint's column of M is zero, and its torque too,
    when the body it moves and every body beyond have no mass and no inertia.

    Parameters
    ----------
    parents : sequence of int, length n
        Each node's parent, parents before children (−1 for a root).
    loaded : sequence of bool, length n
        Whether a node has mass or inertia of its own.

    Returns
    -------
    list of bool, length n
        True for a node whose subtree, itself included, holds no loaded node.

    Examples
    --------
    >>> empty_subtrees([-1, 0, 0], [False, False, True])   # the root carries its loaded child
    [False, True, False]
    """
    carries = [bool(x) for x in loaded]
    for i in range(len(carries) - 1, -1, -1):
        if carries[i] and parents[i] >= 0:
            carries[parents[i]] = True
    return [not x for x in carries]


def loader_findings(robot) -> list[Finding]:
    """What the loader says of a file the checks found no error in: its refusal (``refused``, on the line of the
    first joint or link it names), or a note per mimic of a form Pinocchio cannot build
    (``mimic-pinocchio-cannot-build``, :attr:`~course_dynamics.core.model.Model.mimic_forms`).

    Parameters
    ----------
    robot : course_dynamics.tools.lint.Robot
        The file as the checks read it (its path, name, line, links and joints with their lines).

    Returns
    -------
    list of Finding
        None for a file the loader reads with no such mimic.
    """
    try:
        model = load_urdf(robot.path, allow_nonphysical_inertia=False)
    except ModelError as refusal:
        message = str(refusal).removeprefix(f"{robot.path}: ")
        element, name, line = _named_in(robot, message)
        return [Finding("refused", element, name, message, line)]
    return [Finding("mimic-pinocchio-cannot-build", "joint", joint, f"joint '{joint}': {why}: honoured here, but "
                    "Pinocchio 4.1's mimic=True cannot build it (validate and crosscheck have no Pinocchio to "
                    "compare with)", _named_in(robot, f"joint '{joint}'")[2]) for joint, why in model.mimic_forms]


def _named_in(robot, message: str) -> tuple:
    """(element, name, line) of the first link or joint ``message`` names that the file has, else the robot's."""
    items = {("joint", j.name): j.line for j in robot.joints} | {("link", k.name): k.line for k in robot.links}
    for kind, name in re.findall(r"\b(joint|link) '([^']*)'", message):
        if (kind, name) in items:
            return kind, name, items[kind, name]
    return "robot", robot.name, robot.line


__all__ = ["CLASSES", "Finding", "LintClass", "SEVERITIES", "empty_subtrees", "loader_findings"]

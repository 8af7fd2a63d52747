"""The URDF physics linter: a URDF file's links and joints read as written, and what is wrong with their physics.

The file is read as the loader reads it (:func:`course_dynamics.core.urdf.read_tree`: the size limit, no DTD,
no entity), but not refused at the first problem: every link and joint is read into a small record, and
each check of :data:`CHECKS` turns what it finds into :class:`~course_dynamics.tools.lint_classes.Finding`
records of the classes in :data:`~course_dynamics.tools.lint_classes.CLASSES`. The library's own checks
decide where they exist: the numbers (:func:`~course_dynamics.core.urdf.check_numbers`), the namespaces, the
inertia tensors (:func:`~course_dynamics.core.inertia.physical_problems`), the loader itself for anything else
it refuses. Only a file that is no URDF at all (missing, too large, not XML, no ``<robot>``) raises.

=========  ===========================================================================================
symbol     meaning
=========  ===========================================================================================
``m``      a link's mass, kg
``I``      its inertia tensor about its centre of mass, in the ``<inertial>`` frame's axes, kg·m²
``R``      the rotation of the ``<inertial>`` frame in the link's frame (from its rpy)
``V``      the volume of the link's shapes (collision shapes, else visual ones), m³
``rho``    m / V, kg/m³
``k``      the radius of gyration sqrt(I₃ / m) about the centre of mass (I₃ its largest principal moment), m
``reach``  the distance from the centre of mass to the farthest corner of the box around the shapes, m
=========  ===========================================================================================

>>> from course_dynamics.core.robots import robot_path
>>> [(f.rule, f.name) for f in lint_urdf(robot_path("two_link")).findings]
[('point-mass', 'link1'), ('point-mass', 'link2')]
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from urllib.parse import quote

import numpy as np

from ..base.errors import CourseDynamicsWarning, ModelError
from ..core.urdf import (
    MAX_NAME,
    SUPPORTED_TYPES,
    URDF_NUMBER,
    check_namespaces,
    check_numbers,
    read_tree,
)
from .lint_classes import CLASSES, SEVERITIES, Finding, empty_subtrees, loader_findings
from .lint_geometry import geometry_findings, shape
from .lint_inertia import inertia_findings
from .lint_scale import scale_findings

MAX_MAGNITUDE = 1e9      # m, kg, kg·m²: the loader's bound on any value
HUGE_LIMIT = 1e300       # rad or m: exporters write 1.79769e308 (DBL_MAX) for "no limit"
UNIT_AXIS = 1e-6         # | |axis| - 1 | allowed
#: The attributes that hold one number, by element: urdfdom reads none of them with spaces around it.
ONE_NUMBER = {"mass": ("value",), "inertia": ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"),
              "limit": ("lower", "upper", "effort", "velocity"), "dynamics": ("damping", "friction"),
              "mimic": ("multiplier", "offset"), "cylinder": ("radius", "length"), "sphere": ("radius",)}


@dataclass
class Inertial:
    """A link's ``<inertial>`` as written; a value it lacks is 0, one not readable is NaN.

    Parameters
    ----------
    line : int
        The line of the ``<inertial>`` element.
    mass : float
        m, kg.
    xyz : numpy.ndarray, shape (3,)
        The centre of mass in the link's frame, m.
    rpy : numpy.ndarray, shape (3,)
        The orientation of the inertial frame in the link's frame, rad.
    inertia : numpy.ndarray, shape (3, 3)
        I about the centre of mass, in the inertial frame's axes (the URDF's ixx ... izz), kg·m².
    """

    line: int
    mass: float
    xyz: np.ndarray
    rpy: np.ndarray
    inertia: np.ndarray


@dataclass
class Link:
    """A ``<link>`` as the checks read it.

    Parameters
    ----------
    name : str
        Its name (empty if it has none).
    line : int
        The line of its element.
    inertial : Inertial or None
        Its ``<inertial>``, or None.
    collision : list of course_dynamics.tools.lint_geometry.Shape, optional
        Its collision shapes.
    visual : list of course_dynamics.tools.lint_geometry.Shape, optional
        Its visual shapes.
    """

    name: str
    line: int
    inertial: Inertial | None
    collision: list = field(default_factory=list)
    visual: list = field(default_factory=list)


@dataclass
class Joint:
    """A ``<joint>`` as the checks read it.

    Parameters
    ----------
    name : str
        Its name (empty if it has none).
    line : int
        The line of its element.
    type : str
        Its type attribute.
    parent : str or None
        Its parent link's name.
    child : str or None
        Its child link's name.
    axis : numpy.ndarray, shape (3,)
        Its axis as written ((1, 0, 0) without ``<axis>``).
    limit : dict or None
        ``lower``, ``upper`` (rad or m), ``effort`` (N·m or N), ``velocity`` (rad/s or m/s): each a number,
        NaN when not readable, or None when absent; None without ``<limit>``.
    damping : float
        Its ``<dynamics damping>`` (0 when absent).
    friction : float
        Its ``<dynamics friction>`` (0 when absent).
    mimic : str or None
        The joint its ``<mimic>`` names, or None.
    origin : numpy.ndarray, shape (6,)
        Its ``<origin>`` xyz (m) and rpy (rad), zeros when absent.
    """

    name: str
    line: int
    type: str
    parent: str | None
    child: str | None
    axis: np.ndarray
    limit: dict | None
    damping: float
    friction: float
    mimic: str | None
    origin: np.ndarray


@dataclass
class Robot:
    """A URDF file as the checks see it.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    name : str
        The robot's name.
    line : int
        The line of its ``<robot>`` element.
    links : list of Link
        In the file's order.
    joints : list of Joint
        In the file's order.
    findings : list of Finding, optional
        What reading it found (the loader's number and namespace checks).
    """

    path: Path
    name: str
    line: int
    links: list
    joints: list
    findings: list = field(default_factory=list)   # what reading it found (numbers, namespaces)


def _floats(element, attribute: str, count: int, default: float = 0.0) -> np.ndarray:
    """The numbers of an attribute; its default when absent, NaN where a value is not a number URDF writes."""
    text = None if element is None else element.get(attribute)
    if text is None:
        return np.full(count, default)
    tokens = text.split()
    if len(tokens) != count or not all(URDF_NUMBER.fullmatch(t) for t in tokens):
        return np.full(count, math.nan)
    return np.array([float(t) for t in tokens])


def _link_of(joint, tag: str) -> str | None:
    """The ``link`` attribute of a joint's ``<parent>`` or ``<child>``."""
    element = joint.find(tag)
    return None if element is None else element.get("link")


def _inertial(element) -> Inertial | None:
    if element is None:
        return None
    origin, tensor = element.find("origin"), element.find("inertia")
    values = {name: _floats(tensor, name, 1)[0] for name in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
    inertia = np.array([[values["ixx"], values["ixy"], values["ixz"]], [values["ixy"], values["iyy"], values["iyz"]],
                        [values["ixz"], values["iyz"], values["izz"]]])
    return Inertial(element.sourceline, float(_floats(element.find("mass"), "value", 1)[0]),
                    _floats(origin, "xyz", 3), _floats(origin, "rpy", 3), inertia)


def _shapes(link, tag: str) -> list:
    shapes = []
    for element in link.findall(tag):
        geometry = element.find("geometry")
        kinds = [g for g in (geometry if geometry is not None else []) if isinstance(g.tag, str)]
        if not kinds:
            continue
        origin = element.find("origin")
        values = {name: _floats(kinds[0], name, count, math.nan) for name, count in
                  (("size", 3), ("radius", 1), ("length", 1))}
        shapes.append(shape(kinds[0].tag, values, _floats(origin, "xyz", 3), _floats(origin, "rpy", 3)))
    return shapes


def read_robot(path) -> Robot:
    """A URDF file's links and joints as written, and the findings of the loader's number and namespace checks.

    Parameters
    ----------
    path : str or pathlib.Path
        The URDF file.

    Returns
    -------
    Robot
        Its name, links and joints, in the file's order, each with its line.

    Raises
    ------
    ModelError
        When the file is no URDF at all: missing, larger than ``MAX_URDF_BYTES``, not well-formed XML, with a DTD,
        or with a root element other than ``<robot>``.
    """
    path = Path(path)
    root = read_tree(path)
    if root.tag != "robot":
        raise ModelError(f"{path}: not a URDF: its root element is <{str(root.tag)[:60]}>, not <robot>")
    robot = Robot(path, root.get("name") or "", root.sourceline, [], [])
    where = str(path)
    for top in root:
        if top.tag not in ("link", "joint"):
            continue
        name = top.get("name") or ""
        for check, rule in ((check_numbers, "unreadable-number"), (check_namespaces, "xml-namespace")):
            try:
                check([top] if check is check_numbers else top, where)
            except ModelError as problem:
                robot.findings.append(Finding(rule, top.tag, name, str(problem).removeprefix(f"{where}: "),
                                              top.sourceline))
        robot.findings.extend(_written(top, name))
        if top.tag == "link":
            robot.links.append(Link(name, top.sourceline, _inertial(top.find("inertial")), _shapes(top, "collision"),
                                    _shapes(top, "visual")))
            continue
        limit, dynamics, mimic = top.find("limit"), top.find("dynamics"), top.find("mimic")
        robot.joints.append(Joint(
            name, top.sourceline, top.get("type") or "", _link_of(top, "parent"), _link_of(top, "child"),
            _floats(top.find("axis"), "xyz", 3) if top.find("axis") is not None else np.array([1.0, 0.0, 0.0]),
            None if limit is None else {k: (None if limit.get(k) is None else float(_floats(limit, k, 1)[0]))
                                        for k in ("lower", "upper", "effort", "velocity")},
            float(_floats(dynamics, "damping", 1)[0]), float(_floats(dynamics, "friction", 1)[0]),
            None if mimic is None else (mimic.get("joint") or ""),
            np.concatenate([_floats(top.find("origin"), "xyz", 3), _floats(top.find("origin"), "rpy", 3)])))
    return robot


MOVING = ("revolute", "continuous", "prismatic")


def _written(top, name: str):
    """What other readers refuse in how a link or joint is written: a padded number, an incomplete <inertial>."""
    owner = f"{top.tag} '{name}'"
    for element in top.iter(*ONE_NUMBER):
        for attribute in ONE_NUMBER[element.tag]:
            text = element.get(attribute)
            if text is not None and text != text.strip() and URDF_NUMBER.fullmatch(text.strip()):
                dropped = " and drops the <inertial>" if element.tag in ("mass", "inertia") else ""
                yield Finding("padded-number", top.tag, name, f"{owner}: <{element.tag} {attribute}=\"{text}\">: read "
                              f"here as {text.strip()}, but urdfdom (ROS, Pinocchio) does not read it{dropped}",
                              top.sourceline)
    if top.tag == "link":
        for inertial in top.findall("inertial"):
            missing = [f"<{tag}>" for tag in ("mass", "inertia") if inertial.find(tag) is None]
            if missing:
                yield Finding("incomplete-inertial", "link", name, f"{owner}: its <inertial> has no "
                              f"{' and no '.join(missing)}, which urdfdom (ROS, Pinocchio), MuJoCo and PyBullet "
                              "refuse (read here as 0)", top.sourceline)


def _names(robot: Robot):
    if not robot.name.isprintable() or len(robot.name) > MAX_NAME:
        yield Finding("unusable-name", "robot", robot.name[:40], f"robot name {robot.name[:40]!r}: a control "
                      f"character or over {MAX_NAME} characters", robot.line)
    for kind, items in (("link", robot.links), ("joint", robot.joints)):
        seen = {}
        for item in items:
            if not item.name.strip():
                yield Finding("empty-name", kind, item.name, f"a {kind} has an empty name", item.line)
            elif not item.name.isprintable() or len(item.name) > MAX_NAME:
                yield Finding("unusable-name", kind, item.name[:40], f"{kind} name {item.name[:40]!r}"
                              f"{'...' if len(item.name) > 40 else ''}: a control character or over {MAX_NAME} "
                              "characters", item.line)
            if item.name in seen:
                yield Finding("duplicate-name", kind, item.name, f"two {kind}s are named '{item.name}' (lines "
                              f"{seen[item.name]} and {item.line})", item.line)
            seen.setdefault(item.name, item.line)


def _numbers(robot: Robot):
    """Values the loader refuses though written as numbers: NaN, inf, beyond 1e9 in size."""
    flagged = {(f.element, f.name, f.line) for f in robot.findings if f.rule == "unreadable-number"}  # once each
    for link in robot.links:
        if link.inertial is not None and ("link", link.name, link.line) not in flagged:
            values = np.concatenate([[link.inertial.mass], link.inertial.xyz, link.inertial.rpy,
                                     link.inertial.inertia.ravel()])
            if _not_finite(values):
                yield Finding("unreadable-number", "link", link.name, f"link '{link.name}': its <inertial> has a "
                              f"value that is not a finite number within {MAX_MAGNITUDE:g} in size", link.line)
    for joint in robot.joints:
        for what, values in (("axis", joint.axis), ("origin", joint.origin)):
            if _not_finite(values) and ("joint", joint.name, joint.line) not in flagged:
                yield Finding("unreadable-number", "joint", joint.name, f"joint '{joint.name}': its {what} "
                              f"{values.tolist()} is not finite numbers within {MAX_MAGNITUDE:g} in size", joint.line)


def _not_finite(values) -> bool:
    values = np.asarray(values, dtype=float)
    return not np.all(np.isfinite(values)) or bool(np.abs(values).max() > MAX_MAGNITUDE)


def _tree(robot: Robot):
    """Joints against links: types, undefined links, loops, roots (the loader's structural refusals)."""
    links = {link.name for link in robot.links}
    parent_of = {}
    for joint in robot.joints:
        if joint.type not in SUPPORTED_TYPES:
            yield Finding("unsupported-joint", "joint", joint.name, f"joint '{joint.name}': type '{joint.type}' is "
                          f"not supported ({', '.join(SUPPORTED_TYPES)})", joint.line)
        for role, link in (("parent", joint.parent), ("child", joint.child)):
            if link not in links:
                yield Finding("undefined-link", "joint", joint.name, f"joint '{joint.name}': " + (
                    f"{role} link '{link}' is not defined" if link else f"no <{role} link=...>"), joint.line)
        if joint.child in parent_of:
            yield Finding("not-a-tree", "joint", joint.name, f"kinematic loop: link '{joint.child}' is the child of "
                          f"both joint '{parent_of[joint.child].name}' and joint '{joint.name}'", joint.line)
        parent_of.setdefault(joint.child, joint)
    roots = [link for link in robot.links if link.name not in parent_of]
    if not robot.links:
        yield Finding("not-a-tree", "robot", robot.name, "no <link> at all (a xacro file not expanded?)", robot.line)
    elif len(roots) != 1:
        yield Finding("not-a-tree", "robot", robot.name, f"{len(roots)} root links ("
                      f"{', '.join(r.name for r in roots[:5]) or 'every link has a parent joint'}); a URDF has one",
                      robot.line)
    if not any(joint.type in MOVING for joint in robot.joints):
        yield Finding("nothing-moves", "robot", robot.name, "no revolute, continuous or prismatic joint", robot.line)


def _tree_order(robot: Robot):
    """(links parents first, parent index of each, the joint above each) when the links form one tree; else None."""
    links = {link.name: link for link in robot.links}
    children = {name: [] for name in links}
    parent_of = {}
    for joint in robot.joints:
        if joint.parent not in links or joint.child not in links or joint.child in parent_of:
            return None
        parent_of[joint.child] = joint
        children[joint.parent].append(joint)
    roots = [name for name in links if name not in parent_of]
    if len(roots) != 1 or len(links) != len(robot.links):
        return None
    order, parents, above, pending = [], [], [], [(roots[0], -1, None)]
    while pending:
        name, parent, joint = pending.pop()
        order.append(links[name])
        parents.append(parent)
        above.append(joint)
        pending.extend((j.child, len(order) - 1, j) for j in reversed(children[name]))
    return (order, parents, above) if len(order) == len(links) else None


def _loaded(link: Link) -> bool:
    inertial = link.inertial
    return inertial is not None and bool(inertial.mass > 0 or np.any(inertial.inertia != 0))


def _masses(robot: Robot):
    """No mass at all; a moving joint that carries nothing; a moved link with no <inertial>."""
    tree = _tree_order(robot)
    if tree is None:
        return
    links, parents, above = tree
    empty = empty_subtrees(parents, [_loaded(link) for link in links])
    moving = [(link, joint) for link, joint in zip(links, above) if joint is not None and joint.type in MOVING]
    yield from _mass_findings(robot.name, robot.line, [(joint.name, link.name, joint.line) for link, joint in moving],
                              [e for e, (link, joint) in zip(empty, zip(links, above))
                               if joint is not None and joint.type in MOVING])
    for link, joint in moving:
        if link.inertial is None:
            yield Finding("missing-inertial", "link", link.name, f"link '{link.name}', moved by joint "
                          f"'{joint.name}', has no <inertial>", link.line)


def _mass_findings(robot: str, line, moving, empty):
    if moving and all(empty):
        yield Finding("no-mass", "robot", robot, f"robot '{robot}': no link it moves has a mass or an inertia, so "
                      "every torque is 0 and M(q) is 0", line)
        return
    for (joint, link, joint_line), nothing in zip(moving, empty):
        if nothing:
            yield Finding("joint-carries-nothing", "joint", joint, f"joint '{joint}' moves link '{link}', and "
                          "neither it nor any link beyond has a mass or an inertia", joint_line)


def _inertias(robot: Robot):
    yield from inertia_findings(robot, _tree_order(robot))


def _joints(robot: Robot):
    for joint in robot.joints:
        owner, line = f"joint '{joint.name}'", joint.line
        if joint.type in ("revolute", "prismatic") and joint.limit is None:
            yield Finding("missing-limit", "joint", joint.name, f"{owner}: a {joint.type} joint without <limit>", line)
        limit = joint.limit or {}
        lower, upper = limit.get("lower"), limit.get("upper")
        if joint.type in ("revolute", "prismatic") and joint.limit is not None:
            low, high = (0.0 if lower is None else lower), (0.0 if upper is None else upper)
            if low > high or math.isnan(low) or math.isnan(high):
                yield Finding("reversed-limits", "joint", joint.name, f"{owner}: lower={low:g} upper={high:g} are "
                              "not an interval", line)
            elif low == high:
                yield Finding("zero-range", "joint", joint.name, f"{owner}: lower = upper = {low:g}"
                              + (" (neither given: both default to 0)" if lower is None and upper is None else ""),
                              line)
            if max(abs(low), abs(high)) >= HUGE_LIMIT:
                yield Finding("huge-limits", "joint", joint.name, f"{owner}: lower={low:g} upper={high:g}", line)
        if joint.type in MOVING and joint.limit is not None:
            for name in ("effort", "velocity"):
                value = limit.get(name)
                if value is not None and not value >= 0:
                    yield Finding("negative-effort-velocity", "joint", joint.name, f"{owner}: {name} limit "
                                  f"{value:g}", line)
                elif not value:
                    yield Finding("zero-effort-velocity", "joint", joint.name, f"{owner}: {name} limit "
                                  + ("missing" if value is None else "0"), line)
        norm = float(np.linalg.norm(joint.axis)) if np.all(np.isfinite(joint.axis)) else math.nan
        if joint.type in MOVING and norm < 1e-12:
            yield Finding("zero-axis", "joint", joint.name, f"{owner}: axis {joint.axis.tolist()}", line)
        elif joint.type in MOVING and abs(norm - 1) > UNIT_AXIS:
            yield Finding("axis-not-unit", "joint", joint.name, f"{owner}: axis {joint.axis.tolist()} has length "
                          f"{norm:.6g}", line)
        if joint.mimic is not None and joint.type == "fixed":
            yield Finding("mimic-on-fixed", "joint", joint.name, f"{owner} is fixed: its <mimic> of joint "
                          f"'{joint.mimic}' moves nothing and is ignored, its multiplier and offset unread", line)
        elif joint.mimic is not None:
            known = any(other.name == joint.mimic for other in robot.joints)
            yield Finding("mimic-joint", "joint", joint.name, f"{owner} mimics joint '{joint.mimic}'"
                          + (": honoured, it moves with that joint's coordinate and has none of its own, as "
                             "Pinocchio's mimic=True reads it" if known else
                             " (which is not defined): course-dynamics refuses to load it"), line)
        if joint.type in MOVING and (joint.damping or joint.friction):
            yield Finding("damping-friction", "joint", joint.name, f"{owner}: damping {joint.damping:g}, friction "
                          f"{joint.friction:g}", line)


def _geometry(robot: Robot):
    total = sum(link.inertial.mass for link in robot.links if link.inertial is not None
                and math.isfinite(link.inertial.mass) and link.inertial.mass > 0)
    for link in robot.links:
        yield from geometry_findings(link, total)


def _scale(robot: Robot):
    yield from scale_findings(robot, _tree_order(robot))


#: The checks, each a function of a :class:`Robot` yielding findings, in the order they run.
CHECKS = (_names, _numbers, _tree, _masses, _inertias, _geometry, _scale, _joints)
#: The classes that diagnose one link's inertial data against its size, of which a link gets the first only.
DIAGNOSES = ("units-slip", "implausible-density", "com-outside-geometry", "gyration-exceeds-link",
             "placeholder-inertia")


@dataclass(frozen=True)
class LintReport:
    """What the linter found in one URDF file.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    robot : str
        The robot's name.
    findings : tuple of Finding
        In the file's order (by line), errors first on a line.
    """

    path: Path
    robot: str
    findings: tuple

    def count(self, severity: str) -> int:
        """How many findings have ``severity``.

        Parameters
        ----------
        severity : str
            ``"error"``, ``"warning"`` or ``"note"``.

        Returns
        -------
        int
            The number of such findings.
        """
        return sum(f.severity == severity for f in self.findings)

    def fails(self, fail_on: str = "error") -> bool:
        """Whether a finding is at least as severe as ``fail_on``.

        Parameters
        ----------
        fail_on : str, optional
            ``"error"`` (default), ``"warning"`` or ``"note"``.

        Returns
        -------
        bool
            True when some finding has that severity or a worse one.
        """
        return any(SEVERITIES.index(f.severity) >= SEVERITIES.index(fail_on) for f in self.findings)

    def as_dict(self) -> dict:
        """The report as JSON-ready data.

        Returns
        -------
        dict
            ``path``, ``robot``, ``errors``, ``warnings``, ``notes`` (counts) and ``findings``.
        """
        return dict(path=str(self.path), robot=self.robot, errors=self.count("error"),
                    warnings=self.count("warning"), notes=self.count("note"),
                    findings=[f.as_dict() for f in self.findings])


def lint_urdf(path) -> LintReport:
    """Lint one URDF file: every finding of every check, and the loader's refusal when no check explains it.

    Parameters
    ----------
    path : str or pathlib.Path
        The URDF file.

    Returns
    -------
    LintReport
        The findings, by line.

    Raises
    ------
    ModelError
        When the file is no URDF at all (see :func:`read_robot`).

    Examples
    --------
    >>> from course_dynamics.core.robots import robot_path
    >>> report = lint_urdf(robot_path("rp_arm"))
    >>> report.robot, report.fails("error")
    ('rp_arm', False)
    """
    robot = read_robot(path)
    findings, diagnosed = list(robot.findings), set()
    for check in CHECKS:
        for finding in check(robot):
            if finding.rule in DIAGNOSES and finding.element == "link":
                if finding.name in diagnosed:
                    continue   # one diagnosis per link
                diagnosed.add(finding.name)
            findings.append(finding)
    if not any(f.severity == "error" for f in findings):
        findings += loader_findings(robot)
    order = sorted(range(len(findings)), key=lambda i: (findings[i].line or 0, -SEVERITIES.index(
        findings[i].severity), i))
    return LintReport(robot.path, robot.name, tuple(findings[i] for i in order))


def not_a_urdf(path, error) -> LintReport:
    """The report of a file that is no URDF at all: one ``not-a-urdf`` finding, so that a run over many files
    goes on.

    Parameters
    ----------
    path : str or pathlib.Path
        The file (or the name given).
    error : Exception
        Why it is no URDF (the :class:`~course_dynamics.base.errors.ModelError` of :func:`lint_urdf`, or the
        error reading it).

    Returns
    -------
    LintReport
        The report, with no robot name and one error finding without a line.

    Examples
    --------
    >>> not_a_urdf("log.csv", ModelError("log.csv: malformed XML")).findings[0].message
    'malformed XML'
    """
    path = Path(path)
    message = str(error).removeprefix(f"{path}: ")
    return LintReport(path, "", (Finding("not-a-urdf", "robot", "", message),))


def mass_findings(model) -> list:
    """The ``no-mass`` and ``joint-carries-nothing`` findings of a loaded model (what ``validate`` and ``terms``
    warn of).

    Parameters
    ----------
    model : course_dynamics.core.model.Model
        The robot.

    Returns
    -------
    list of Finding
        One ``no-mass`` finding when no body has a mass or an inertia, else one ``joint-carries-nothing``
        finding per joint whose body and the bodies beyond have none; empty for a robot with its masses.

    Examples
    --------
    >>> from course_dynamics.core.robots import load_robot
    >>> mass_findings(load_robot("two_link"))
    []
    """
    loaded = [bool(b.mass > 0 or np.any(b.I_com != 0)) for b in model.bodies]
    empty = empty_subtrees([b.parent for b in model.bodies], loaded)
    return list(_mass_findings(model.name, None, [(b.joint, b.name, None) for b in model.bodies], empty))


class MassWarning(CourseDynamicsWarning):
    """A robot with no mass where a joint moves: given by :func:`warn_if_massless`, one per finding."""


def warn_if_massless(model) -> list:
    """One :class:`MassWarning` per :func:`mass_findings` finding of a model; the findings.

    Parameters
    ----------
    model : course_dynamics.core.model.Model
        The robot.

    Returns
    -------
    list of Finding
        The findings warned of (empty for a robot with its masses).

    Examples
    --------
    >>> from course_dynamics.core.robots import load_robot
    >>> warn_if_massless(load_robot("rrr_arm"))
    []
    """
    findings = mass_findings(model)
    for finding in findings:
        where = "" if finding.element == "robot" else f"robot '{model.name}': "
        warnings.warn(MassWarning(f"{where}{finding.message} [{finding.rule}]"), stacklevel=2)
    return findings


def sarif(reports) -> dict:
    """A SARIF 2.1.0 log of lint reports, for code-scanning tools: one run, the classes as rules, one result per
    finding with the file and the line of its element.

    Parameters
    ----------
    reports : sequence of LintReport
        The files linted.

    Returns
    -------
    dict
        The SARIF document (``version``, ``$schema``, ``runs``), JSON-ready.
    """
    rules = [dict(id=c.name, shortDescription=dict(text=c.summary), help=dict(text=c.fix),
                  defaultConfiguration=dict(level=c.severity)) for c in CLASSES.values()]
    index = {c.name: i for i, c in enumerate(CLASSES.values())}
    results = []
    for report in reports:
        for f in report.findings:
            uri = report.path.as_uri() if report.path.is_absolute() else quote(report.path.as_posix())
            location = dict(artifactLocation=dict(uri=uri))
            if f.line is not None:
                location["region"] = dict(startLine=f.line)
            results.append(dict(ruleId=f.rule, ruleIndex=index[f.rule], level=f.severity,
                                message=dict(text=f"{f.message}. Fix: {f.fix}"),
                                locations=[dict(physicalLocation=location)]))
    return {"version": "2.1.0", "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
            "runs": [dict(tool=dict(driver=dict(name="course-dynamics lint", rules=rules)), results=results)]}


__all__ = ["CHECKS", "DIAGNOSES", "Inertial", "Joint", "Link", "LintReport", "MassWarning", "Robot", "lint_urdf",
           "mass_findings", "not_a_urdf", "read_robot", "sarif", "warn_if_massless"]

"""URDF → :class:`~course_dynamics.core.model.Model`, through yourdfpy (never Pinocchio).

What is read, and how (see the site's "Known limits" for what is not):

* revolute, continuous and prismatic joints become moving bodies, in depth-first
  order from the root link (parents before children, URDF child order);
* fixed joints are merged: the child link's mass is lumped into the moving body
  that carries it (parallel-axis theorem, rotated inertia), as Pinocchio does,
  and its children hang from that body; links fixed to the base are ignored;
* any unit axis (it is normalised; a zero axis is an error), joint origins and
  inertial frames with rpy, full inertia tensors, links without ``<inertial>``;
* ``<mimic joint multiplier offset>`` is honoured: the mimic joint's body moves with
  θ = multiplier · θ_leader + offset and has no coordinate of its own (Θ holds the
  independent joints only, as Pinocchio's ``buildModelFromUrdf(..., mimic=True)``);
  its torque maps onto the leader through Sᵀ (:mod:`course_dynamics.core.model`).
  A mimic of a mimic is composed; a mimic naming no joint, a fixed joint, itself
  through a cycle, with a non-finite multiplier or offset, or one (declared or
  composed) outside ``MIMIC_MULTIPLIER_RANGE`` / ``MAX_MIMIC_OFFSET`` of
  :mod:`~course_dynamics.core.model`, and a joint with two ``<mimic>`` elements,
  are refused naming the joint. A ``<mimic>`` on a fixed joint moves nothing and is
  not read (its values neither);
* ``<dynamics damping friction>`` is kept on the body for the friction models.

Every problem raises :class:`~course_dynamics.base.errors.ModelError` with one line naming the file and the
joint or link at fault.
"""
from __future__ import annotations

import logging
import math
import os
import re
import threading
import warnings
from pathlib import Path

import numpy as np

from ..base.errors import CourseDynamicsWarning, InputError, ModelError
from ..base.files import read_small
from .inertia import physical_problems
from .joints import KINDS
from .model import STANDARD_GRAVITY, Body, Frame, Model

SUPPORTED_TYPES = (*KINDS, "fixed")  # the moving kinds of course_dynamics.core.joints, and fixed joints (merged)
# Round-off allowed when checking that an inertia is physical (kg·m²).
INERTIA_TOLERANCE = 1e-12


class InertiaWarning(CourseDynamicsWarning):
    """A link's inertia is not physical, loaded anyway because the caller allowed it.

    Given to ``warnings.warn`` by :func:`load_urdf` with ``allow_nonphysical_inertia=True``, once per link; the
    message names the file, the link and the problem.
    """


def load_urdf(path, gravity=STANDARD_GRAVITY, allow_nonphysical_inertia: bool = False) -> Model:
    """Load a fixed-base URDF as a :class:`~course_dynamics.core.model.Model`.

    Parameters
    ----------
    path : str or pathlib.Path
        The URDF file.
    gravity : array_like, shape (3,), optional
        g in the base frame, m/s²; default (0, 0, −9.81).
    allow_nonphysical_inertia : bool, optional
        Load a link whose inertia breaks the triangle inequality or is not positive
        semi-definite (as classroom URDFs that give only izz do), with an
        :class:`InertiaWarning` per link instead of an error.

    Returns
    -------
    Model
        The robot: one body per moving joint, parents first, fixed links merged; every link a frame; one
        coordinate per moving joint that mimics none.

    Raises
    ------
    ModelError
        For a missing or malformed file, an unsupported joint, a kinematic loop,
        several roots, two joints with one name, a non-physical inertial, a zero
        axis, a non-finite value, or a ``<mimic>`` that cannot be honoured (naming no
        moving joint, a cycle of mimics).

    Examples
    --------
    >>> from course_dynamics.core.robots import robot_path
    >>> arm = load_urdf(robot_path("two_link"))
    >>> arm.name, arm.joint_names, arm.base_link
    ('two_link', ('theta1', 'theta2'), 'world')
    """
    path = Path(path)
    where = str(path)
    gravity = np.asarray(gravity, dtype=float)
    if gravity.shape != (3,) or not np.all(np.isfinite(gravity)):
        raise ModelError(f"gravity must be three finite numbers, got {gravity.tolist()}")
    robot = read_description(path)
    for kind, names in (("robot", [robot.name or ""]), ("link", [link.name for link in robot.links]),
                        ("joint", [joint.name for joint in robot.joints])):
        for name in names:
            if not str(name).isprintable():
                raise ModelError(f"{where}: {kind} name {name!r} holds a control character (a line break, a tab, ...)")
            if kind != "robot" and not str(name).strip():
                raise ModelError(f"{where}: a {kind} has an empty name")
            if len(str(name)) > MAX_NAME:
                raise ModelError(f"{where}: a {kind} name has {len(str(name))} characters, more than {MAX_NAME}: "
                                 f"{str(name)[:40]!r}...")
    links = {link.name: link for link in robot.links}
    if len(links) != len(robot.links):
        raise ModelError(f"{where}: two links share a name")
    parent_joint, seen = {}, set()
    children = {name: [] for name in links}
    for joint in robot.joints:
        if joint.name in seen:
            raise ModelError(f"{where}: two joints are named '{joint.name}'")
        seen.add(joint.name)
        for role, link in (("parent", joint.parent), ("child", joint.child)):
            if link not in links:
                raise ModelError(f"{where}: joint '{joint.name}': {role} link '{link}' is not defined")
        if joint.type not in SUPPORTED_TYPES:
            raise ModelError(
                f"{where}: joint '{joint.name}': type '{joint.type}' is not supported "
                f"(fixed-base robots with {', '.join(SUPPORTED_TYPES)} joints only)"
            )
        if joint.child in parent_joint:
            raise ModelError(
                f"{where}: kinematic loop: link '{joint.child}' is the child of both "
                f"joint '{parent_joint[joint.child].name}' and joint '{joint.name}'"
            )
        parent_joint[joint.child] = joint
        children[joint.parent].append(joint)
    roots = [name for name in links if name not in parent_joint]
    if len(roots) != 1:
        if not roots:
            raise ModelError(f"{where}: kinematic loop: every link has a parent joint, so there is no root link")
        raise ModelError(f"{where}: {len(roots)} root links ({', '.join(roots)}); a URDF must have exactly one")

    unreachable = sorted(set(links) - _descendants(roots[0], children))
    if unreachable:
        raise ModelError(f"{where}: kinematic loop: links {', '.join(unreachable)} "
                         f"are not reachable from root '{roots[0]}'")

    # Depth-first from the root: each link hangs from a body (−1: the fixed base)
    # through a constant 4×4 transform; a moving joint starts a new body.
    specs: list[dict] = []
    lumps: list[list] = []
    frames: list[Frame] = []
    pending = [(roots[0], -1, np.eye(4), None)]
    while pending:
        link_name, body, T_body_link, joint = pending.pop()
        if joint is not None and joint.type != "fixed":
            specs.append(dict(joint=joint, parent=body, T=T_body_link, link=link_name))
            lumps.append([])
            body, T_body_link = len(specs) - 1, np.eye(4)
        frames.append(Frame(name=link_name, body=body, R=T_body_link[:3, :3], P=T_body_link[:3, 3]))
        if body >= 0:
            lumps[body].append(_inertial_in_body(where, links[link_name], T_body_link, allow_nonphysical_inertia))
        for child in reversed(children[link_name]):
            origin = child.origin if child.origin is not None else np.eye(4)  # no <origin>: the identity
            T = T_body_link @ _checked(where, f"joint '{child.name}' origin", origin)
            pending.append((child.child, body, T, child))
    if not specs:
        raise ModelError(f"{where}: no revolute, continuous or prismatic joint: nothing moves")
    _check_mimics(where, robot.joints)
    try:
        bodies = [_body(where, spec, lump) for spec, lump in zip(specs, lumps)]
        return Model(name=robot.name, bodies=tuple(bodies), gravity=gravity, source=where, base_link=roots[0],
                     frames=tuple(frames))
    except ModelError as exc:
        raise ModelError(f"{where}: {exc}") from None


def _check_mimics(where: str, joints) -> None:
    """Each moving joint's ``<mimic>`` names another moving joint, with a finite multiplier and offset."""
    kinds = {joint.name: joint.type for joint in joints}
    for joint in joints:
        if joint.mimic is None or joint.type == "fixed":
            continue
        leader = joint.mimic.joint
        if not leader:
            raise ModelError(f"{where}: joint '{joint.name}': <mimic> names no joint")
        if leader not in kinds:
            raise ModelError(f"{where}: joint '{joint.name}' mimics joint '{leader}', which the URDF does not define")
        if kinds[leader] == "fixed":
            raise ModelError(f"{where}: joint '{joint.name}' mimics joint '{leader}', a fixed joint (it has no "
                             "coordinate to follow)")
        if leader == joint.name:
            raise ModelError(f"{where}: joint '{joint.name}' mimics itself")
        for name in ("multiplier", "offset"):
            value = float(getattr(joint.mimic, name))
            if not math.isfinite(value):
                raise ModelError(f"{where}: joint '{joint.name}': <mimic {name}=\"{value}\"> must be finite")


#: The largest URDF file read, in bytes (64 MiB). A 1 000-joint chain is under 1 MiB; anything far larger is
#: not a robot description.
MAX_URDF_BYTES = 64 * 2**20
MAX_ANGLE = 1e4  # rad in an rpy: exporters write angles within a turn or two; 1e300 rad is no orientation
MAX_NAME = 1000  # characters of a link or joint name: a name becomes a CSV column, a label, part of messages

# Numbers as URDF (XML Schema's double) writes them, in ASCII. Python's float() also takes '1_000', '٣' (any
# Unicode digit), '１' (full width) and spaces: read silently, each would be a number nobody wrote on purpose.
URDF_NUMBER = re.compile(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?|[+-]?(?:inf|infinity|nan)", re.ASCII | re.I)
NUMERIC_ATTRIBUTES = {"xyz", "rpy", "ixx", "ixy", "ixz", "iyy", "iyz", "izz", "lower", "upper", "effort", "velocity",
                      "damping", "friction", "radius", "length", "size", "scale", "rgba", "multiplier", "offset",
                      "soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity", "rising", "falling"}

VALUE_COUNTS = {"xyz": 3, "rpy": 3, "size": 3, "scale": 3, "rgba": 4}


def _owner(element) -> str:
    """'link 'x'' or 'joint 'y'' for the element holding ``element``, as messages name them."""
    while element is not None and element.tag not in ("link", "joint"):
        element = element.getparent()
    return "the robot" if element is None else f"{element.tag} '{element.get('name')}'"


def check_numbers(root, where: str) -> None:
    """Every number of the links and joints written as URDF writes numbers (``URDF_NUMBER``), none lost to 0.

    Parameters
    ----------
    root : lxml.etree._Element or iterable of them
        The ``<robot>`` element (its ``<link>`` and ``<joint>`` children are checked), or the links and joints.
    where : str
        The file, as messages name it.

    Raises
    ------
    ModelError
        At the first number URDF does not write (``1_000``, ``heavy``, an empty attribute, a wrong count of
        values, an angle over ``MAX_ANGLE``, a value too small for a double), naming the link or joint.

    Examples
    --------
    >>> from lxml import etree
    >>> check_numbers(etree.fromstring(b'<robot><link name="a"><mass value="1_0"/></link></robot>'), "a.urdf")
    Traceback (most recent call last):
    ...
    course_dynamics.base.errors.ModelError: a.urdf: link 'a': <mass value="1_0">: '1_0' is not a number as URDF \
writes them (ASCII digits, '.', an exponent)
    """
    for top in root:
        if top.tag not in ("link", "joint"):
            continue  # gazebo, transmission and other extensions are not read
        for element in top.iter():
            for attribute, text in element.attrib.items():
                if not (attribute in NUMERIC_ATTRIBUTES or (element.tag == "mass" and attribute == "value")):
                    continue
                if not text.strip():
                    raise ModelError(f"{where}: {_owner(element)}: <{element.tag} {attribute}=\"{text}\">: empty, "
                                     "a number is expected (or leave the attribute out)")
                count = VALUE_COUNTS.get(attribute)
                if count is not None and len(text.split()) != count:
                    raise ModelError(f"{where}: {_owner(element)}: <{element.tag} {attribute}=\"{text[:60]}\">: "
                                     f"{len(text.split())} values, expected {count}")
                for token in text.split():
                    if not URDF_NUMBER.fullmatch(token):
                        raise ModelError(f"{where}: {_owner(element)}: <{element.tag} {attribute}=\"{text[:60]}\">: "
                                         f"{token[:30]!r} is not a number as URDF writes them (ASCII digits, '.', "
                                         "an exponent)")
                    if attribute == "rpy" and abs(float(token)) > MAX_ANGLE:
                        raise ModelError(f"{where}: {_owner(element)}: <{element.tag} rpy=\"{text[:60]}\">: an angle "
                                         f"of {float(token):g} rad, more than {MAX_ANGLE:g} in size")
                    if float(token) == 0 and re.search(r"[1-9]", token.lower().split("e")[0]):
                        raise ModelError(f"{where}: {_owner(element)}: <{element.tag} {attribute}=\"{text[:60]}\">: "
                                         f"{token!r} is too small for a double and would be read as 0")


def check_namespaces(root, where: str) -> None:
    """No element in a default XML namespace: lxml (and so yourdfpy) would skip it, urdfdom reads it by its
    bare name.

    Parameters
    ----------
    root : lxml.etree._Element
        The element whose descendants (itself included) are checked.
    where : str
        The file, as messages name it.

    Raises
    ------
    ModelError
        At the first element in a default namespace, naming its link or joint.

    Examples
    --------
    >>> from lxml import etree
    >>> check_namespaces(etree.fromstring(b'<robot><joint name="j"><axis xmlns="urn:x"/></joint></robot>'), "a.urdf")
    Traceback (most recent call last):
    ...
    course_dynamics.base.errors.ModelError: a.urdf: joint 'j': <axis> is in the default XML namespace 'urn:x' \
(an xmlns="..." attribute): URDF readers disagree on whether it is a URDF element; remove the xmlns
    """
    for element in root.iter():
        if isinstance(element.tag, str) and element.tag.startswith("{") and element.prefix is None:
            namespace, name = element.tag[1:].split("}", 1)
            raise ModelError(f"{where}: {_owner(element)}: <{name}> is in the default XML namespace {namespace[:80]!r} "
                             "(an xmlns=\"...\" attribute): URDF readers disagree on whether it is a URDF element; "
                             "remove the xmlns")


def xml_parser():
    """lxml configured for files nobody vouches for.

    No DTD is loaded, no entity is substituted, nothing is fetched from the network,
    and lxml's limits on depth (256) and amplification stay on (no ``huge_tree``).
    Documents that declare a DTD at all are refused by :func:`read_description`.

    Returns
    -------
    lxml.etree.XMLParser
        A new parser.

    Examples
    --------

    >>> from lxml import etree
    >>> etree.fromstring(b"<robot name='arm'/>", xml_parser()).get("name")
    'arm'
    """
    from lxml import etree

    return etree.XMLParser(resolve_entities=False, load_dtd=False, no_network=True, dtd_validation=False,
                           huge_tree=False)


def _xml_problem(raw: bytes, exc: Exception) -> str:
    if b"encoding=" not in raw[:200]:
        try:
            raw.decode("utf-8")
        except UnicodeDecodeError as bad:
            return (f"not UTF-8 (byte {bad.start} is 0x{raw[bad.start]:02x}) and no other encoding is declared "
                    f"(<?xml version=\"1.0\" encoding=\"...\"?>)")
    return f"malformed XML: {exc}"


def read_description(path):
    """The yourdfpy description of a URDF file, read defensively.

    The file is read by :func:`read_tree` and its numbers and namespaces checked; yourdfpy then reads
    the checked tree, never the file again. Meshes are not loaded here.

    Parameters
    ----------
    path : str or pathlib.Path
        The URDF file.

    Returns
    -------
    yourdfpy.Robot
        The description, as yourdfpy reads it (``.name``, ``.links``, ``.joints``).

    Raises
    ------
    ModelError
        Naming the file and the problem: missing, not a regular file, too large, empty, with a DTD, not
        well-formed XML, a number or namespace URDF does not write, a joint with two ``<mimic>``, or what
        yourdfpy refuses.

    Examples
    --------
    >>> from course_dynamics.core.robots import robot_path
    >>> description = read_description(robot_path("rp_arm"))
    >>> description.name, [joint.type for joint in description.joints]
    ('rp_arm', ['fixed', 'revolute', 'prismatic'])
    """
    from io import BytesIO

    from lxml import etree

    yourdfpy = _import_yourdfpy()
    path = Path(path)
    root = read_tree(path)
    check_namespaces(root, str(path))
    check_numbers(root, str(path))
    for joint in root.iter("joint"):
        if len(joint.findall("mimic")) > 1:   # yourdfpy would keep the first silently
            raise ModelError(f"{path}: joint '{joint.get('name')}': {len(joint.findall('mimic'))} <mimic> elements; "
                             "a joint follows at most one joint")
    logging.getLogger("yourdfpy").setLevel(logging.CRITICAL)
    try:
        urdf = yourdfpy.URDF.load(
            BytesIO(etree.tostring(root)), mesh_dir=str(path.parent), build_scene_graph=False,
            build_collision_scene_graph=False, load_meshes=False, load_collision_meshes=False,
        )
    except Exception as exc:  # yourdfpy reports bad values with assorted exception types
        raise ModelError(f"{path}: malformed URDF: {exc}") from None
    return urdf.robot


# What yourdfpy's own import reads from trimesh: two names in its functions' annotations, nothing else.
_TRIMESH_ANNOTATIONS = frozenset({"Trimesh", "Scene"})
_trimesh_lock = threading.Lock()


def _import_yourdfpy():
    """yourdfpy, imported without loading trimesh (1.5–2 s of scipy and networkx) until a mesh is wanted.

    yourdfpy imports trimesh at its own import, though reading a URDF without meshes uses nothing of it
    but ``trimesh.transformations`` (plain numpy). So, when trimesh is not loaded yet, its package is
    entered in ``sys.modules`` unexecuted, with its ``__path__``: submodules import as usual, and the
    first attribute anyone asks of the package itself executes the real ``trimesh/__init__.py`` into it
    (once, under a lock), so every caller, the viewer's mesh reader included, gets the whole trimesh.
    While yourdfpy itself is imported, the two names its annotations use 
    are answered with placeholders instead; any other name loads trimesh, so a yourdfpy that needs more
    at import gets it, only slower.

    Returns the ``yourdfpy`` package.
    """
    import importlib.util
    import sys
    import types

    if "yourdfpy" in sys.modules or "trimesh" in sys.modules:
        import yourdfpy

        return yourdfpy
    spec = importlib.util.find_spec("trimesh")
    package = importlib.util.module_from_spec(spec)
    importing = [True]

    class Deferred(types.ModuleType):
        def __getattr__(self, name):
            if name.startswith("__"):
                raise AttributeError(name)
            if importing[0] and name in _TRIMESH_ANNOTATIONS:
                return type(name, (), {"__module__": "trimesh"})
            with _trimesh_lock:
                if type(self) is Deferred:
                    self.__class__ = types.ModuleType
                    spec.loader.exec_module(self)
            return getattr(self, name)

    package.__class__ = Deferred
    sys.modules["trimesh"] = package
    try:
        import yourdfpy
    except BaseException:
        if type(package) is Deferred:
            sys.modules.pop("trimesh", None)
        raise
    finally:
        importing[0] = False
    return yourdfpy


def read_tree(path):
    """The XML tree of a URDF file, read defensively: what :func:`read_description` and the linter parse.

    The file must be a regular file of at most :data:`MAX_URDF_BYTES`, not empty, well-formed XML (parsed by
    :func:`xml_parser`, so every element knows its ``sourceline``) with no DTD and no entity.

    Parameters
    ----------
    path : str or pathlib.Path
        The URDF file.

    Returns
    -------
    lxml.etree._Element
        The root element (not checked to be ``<robot>``).

    Raises
    ------
    ModelError
        Naming the file and the problem: missing, not a regular file, too large, empty, with a DTD or an
        entity, not well-formed XML.

    Examples
    --------
    >>> from course_dynamics.core.robots import robot_path
    >>> read_tree(robot_path("pendulum")).tag
    'robot'
    """
    from lxml import etree

    path = Path(path)
    if not os.path.lexists(path):
        raise ModelError(f"{path}: no such file")
    try:  # a regular file (a pipe would block, a device never end), checked on the opened file too
        raw = read_small(path, MAX_URDF_BYTES, "URDF file")
    except InputError as exc:
        raise ModelError(str(exc)) from None
    if not raw.strip():
        raise ModelError(f"{path}: empty file")
    if b"<!ENTITY" in raw or re.search(rb"<!DOCTYPE[^>]*\[", raw):
        raise ModelError(f"{path}: declares a DTD (<!DOCTYPE ... [...]>); URDF files have none, and XML entities "
                         "are refused")
    try:
        root = etree.fromstring(raw, parser=xml_parser())
    except (etree.LxmlError, ValueError) as exc:
        raise ModelError(f"{path}: {_xml_problem(raw, exc)}") from None
    if root.getroottree().docinfo.internalDTD is not None or b"<!ENTITY" in raw:
        raise ModelError(f"{path}: declares a DTD (<!DOCTYPE ... [...]>); URDF files have none, and XML entities "
                         "are refused")
    return root


def _descendants(root: str, children: dict) -> set[str]:
    seen, pending = set(), [root]
    while pending:
        name = pending.pop()
        if name not in seen:
            seen.add(name)
            pending.extend(joint.child for joint in children[name])
    return seen


MAX_MAGNITUDE = 1e9  # m, kg, kg·m²: larger lengths, masses or inertias describe no robot, and overflow later


def _checked(where: str, what: str, values) -> np.ndarray:
    array = np.asarray(values, dtype=float)
    if not np.all(np.isfinite(array)):
        raise ModelError(f"{where}: {what} has a non-finite value (NaN or inf)")
    if array.size and np.abs(array).max() > MAX_MAGNITUDE:
        raise ModelError(f"{where}: {what} has a value of {np.abs(array).max():g}, more than {MAX_MAGNITUDE:g} in size")
    return array


def _inertial_in_body(where: str, link, T_body_link: np.ndarray, allow_nonphysical: bool = False):
    """(m, c, I) of one link in its body's frame: mass, COM, inertia about the COM."""
    inertial = link.inertial
    if inertial is None:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    what = f"link '{link.name}' inertial"
    mass = float(_checked(where, f"{what} mass", inertial.mass if inertial.mass is not None else 0.0))
    if mass < 0:
        raise ModelError(f"{where}: link '{link.name}': negative mass {mass} kg")
    T_origin = _checked(where, f"{what} origin", inertial.origin if inertial.origin is not None else np.eye(4))
    inertia = _checked(where, f"{what} inertia", inertial.inertia if inertial.inertia is not None else np.zeros((3, 3)))
    _check_inertia(where, link.name, inertia, allow_nonphysical)
    T = T_body_link @ T_origin
    R = T[:3, :3]
    return mass, T[:3, 3].copy(), R @ inertia @ R.T


def inertia_problem(inertia) -> str | None:
    """Why the loader refuses a link's inertia tensor, or None: the first of
    :func:`~course_dynamics.core.inertia.physical_problems` with the loader's round-off, ``INERTIA_TOLERANCE``.

    The one rule for the tensor of a link the loader reads (a link on a moving body; those fixed to the base
    move nothing and are not read). Zero is allowed: Craig's point masses (section 6.7) have no rotational
    inertia.

    Parameters
    ----------
    inertia : array_like, shape (3, 3)
        The tensor about the centre of mass, kg·m².

    Returns
    -------
    str or None
        The problem ("tensor is not symmetric (…)", "tensor is not positive semi-definite (…)", "breaks the
        triangle inequality (…)"), or None for a tensor a body can have.

    Examples
    --------
    >>> inertia_problem(np.diag([1.0, 2.0, 2.5])) is None
    True
    >>> inertia_problem(np.diag([-1.0, 2.0, 2.5]))[:35]
    'tensor is not positive semi-definit'
    """
    problems = physical_problems(inertia, INERTIA_TOLERANCE)
    return problems[0] if problems else None


def _check_inertia(where: str, link: str, inertia: np.ndarray, allow_nonphysical: bool = False) -> None:
    """Symmetric, positive semi-definite, and principal moments obeying the triangle inequality."""
    problem = inertia_problem(inertia)
    if problem is None:
        return
    problems = [problem]
    if problems[0].startswith("tensor is not symmetric") or not allow_nonphysical:
        hint = "" if problems[0].startswith("tensor is not symmetric") else \
            " (allow_nonphysical_inertia / --allow-nonphysical-inertia loads it with a warning)"
        raise ModelError(f"{where}: link '{link}': inertia {problems[0]}{hint}")
    warnings.warn(InertiaWarning(f"{where}: link '{link}': inertia {problems[0]}; loaded anyway"), stacklevel=4)


def _body(where: str, spec: dict, lump: list) -> Body:
    joint = spec["joint"]
    axis = _checked(where, f"joint '{joint.name}' axis", joint.axis if joint.axis is not None else (1.0, 0.0, 0.0))
    norm = float(np.linalg.norm(axis))
    if norm < 1e-12:
        raise ModelError(f"{where}: joint '{joint.name}': zero axis")
    lower, upper, effort, velocity = -math.inf, math.inf, math.inf, math.inf
    if joint.limit is not None:
        if joint.type != "continuous":
            lower = -math.inf if joint.limit.lower is None else float(joint.limit.lower)
            upper = math.inf if joint.limit.upper is None else float(joint.limit.upper)
            if math.isnan(lower) or math.isnan(upper) or lower > upper:
                raise ModelError(f"{where}: joint '{joint.name}': limits lower={lower} upper={upper} "
                                 "are not an interval")
        for name, value in (("effort", joint.limit.effort), ("velocity", joint.limit.velocity)):
            if value is not None and not (float(value) >= 0):
                raise ModelError(f"{where}: joint '{joint.name}': {name} limit {value} must be a non-negative number")
        # 0 or absent: the URDF gives no limit (many exporters write effort="0" velocity="0")
        effort = float(joint.limit.effort) if joint.limit.effort else math.inf
        velocity = float(joint.limit.velocity) if joint.limit.velocity else math.inf
    dynamics = joint.dynamics
    damping = float(dynamics.damping or 0.0) if dynamics is not None else 0.0
    friction = float(dynamics.friction or 0.0) if dynamics is not None else 0.0
    mass, p_com, I_com = _combine(lump)
    T = spec["T"]
    mimic = joint.mimic if joint.mimic is not None else None
    return Body(
        name=spec["link"], joint=joint.name, joint_type=joint.type, parent=spec["parent"],
        R0=T[:3, :3], P=T[:3, 3], axis=axis / norm, mass=mass, p_com=p_com, I_com=I_com,
        lower=lower, upper=upper, effort=effort, velocity=velocity, damping=damping, friction=friction,
        parent_link=joint.parent, mimic=mimic.joint if mimic else "",
        multiplier=float(mimic.multiplier) if mimic else 1.0, offset=float(mimic.offset) if mimic else 0.0,
    )


def _combine(parts: list) -> tuple[float, np.ndarray, np.ndarray]:
    """Lump rigidly joined masses: total mass, joint COM, inertia about it (parallel-axis theorem)."""
    mass = sum(m for m, _, _ in parts)
    if mass == 0:
        return 0.0, np.zeros(3), sum((I for _, _, I in parts), np.zeros((3, 3)))
    com = sum(m * c for m, c, _ in parts) / mass
    inertia = np.zeros((3, 3))
    for m, c, I in parts:
        d = c - com
        inertia += I + m * (d @ d * np.eye(3) - np.outer(d, d))
    return mass, com, inertia


__all__ = ["InertiaWarning", "MAX_URDF_BYTES", "check_namespaces", "check_numbers", "inertia_problem", "load_urdf",
           "read_description", "read_tree", "xml_parser"]

"""An identified robot as a URDF: the input URDF's text, with only the identified numbers changed.

==================  ==========================================================================
what is written     where
==================  ==========================================================================
mᵢ, ⁱP_Cᵢ, ᶜⁱIᵢ     the ``<inertial>`` of moving body i's own link (the child link of joint i,
                    whose frame is frame i): ``<origin xyz="ⁱP_Cᵢ" rpy="0 0 0"/>``, ``<mass>``,
                    ``<inertia>`` with the entries of the matrix ᶜⁱIᵢ (axes of frame i)
links merged        a link fixed to body i by fixed joints (a flange, a tool frame, a hand) was
into body i         lumped into body i when the URDF was loaded
                    (:mod:`~course_dynamics.core.urdf`), and body i's identified parameters are
                    the lump's: its ``<inertial>`` is removed (a comment says so), so that no
                    mass is counted twice. A link without ``<inertial>`` has no mass for our
                    loader, Pinocchio and urdfdom alike
v, c                ``<dynamics damping="v" friction="c"/>`` on each moving joint (6.112), when
                    friction is given; otherwise every ``<dynamics>`` stays as it was
==================  ==========================================================================

Everything else — links fixed to the base, visuals, collisions, meshes, limits, transmissions,
gazebo tags, comments, the layout — is kept byte for byte: the file is not re-serialised. Where
the changed elements and attribute values are comes from the parser's own positions
(:mod:`~course_dynamics.output.xml_spans`): the text of a comment, a CDATA section, a processing
instruction or another attribute's value (``note='damping="0.1"'``) is never taken for a tag or an
attribute. Elements are the ones our loader reads: the root's ``<link>`` and ``<joint>`` children,
and of each its own ``<inertial>`` or ``<dynamics>`` child, in no namespace (a second one, or one
put in a namespace by a default ``xmlns``, on which readers disagree, is refused). A DTD or an
entity is refused, nothing is fetched or run. What is inserted is ASCII, with the file's line
ends, so the text keeps its encoding (UTF-8 with or without a BOM, ASCII, Latin-1 and the other
one-byte encodings expat reads; UTF-16 is refused). Numbers are written with ``repr`` (17
significant digits at most), so they read back exactly; and before anything is written the text
is read back by our loader and every identified value compared (:func:`check_reads_back`): a file
that reads back differently is never left. Relative mesh paths are kept as they are: they resolve
against the folder of the written file.

>>> from dataclasses import replace
>>> from pathlib import Path
>>> from course_dynamics import load_robot
>>> arm = load_robot("two_link")
>>> heavier = replace(arm, bodies=(replace(arm.bodies[0], mass=2.5),) + arm.bodies[1:])
>>> text = identified_urdf(Path(arm.source).read_bytes(), heavier).decode()
>>> '<mass value="2.5"/>' in text
True
"""
from __future__ import annotations

import tempfile
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from ..base.errors import InputError, ModelError
from ..base.files import read_small
from ..core.friction import Friction
from ..core.model import Model
from ..core.regressor import TENSOR, parameters, with_parameters
from ..core.urdf import InertiaWarning, load_urdf
from ..tools.payloads import offset_map
from . import io
from .xml_spans import Element, elements

#: The largest URDF file edited, bytes (the loader's own limit, so a larger file was never loaded).
MAX_URDF_BYTES = 64 * 2**20  # as the loader's limit: a URDF larger than this was never loaded
MERGED_NOTE = b"<!-- inertial removed: lumped into the identified inertial of the moving link it is fixed to -->"
HEADER_NOTE = b"<!-- inertial parameters and joint friction identified by course-dynamics identify -->\n"
INDENT_WINDOW = 4096  # bytes looked back for a line's indentation: a 64 MiB one-line file is not scanned per element
# Reading back, the loader lumps each moving link with the links merged into it (now massless): m·c/m differs from
# c by an ulp or two, and the parallel-axis term of that difference is ~m·(1e-17 m)²; a misread value is far off.
READBACK_RTOL, READBACK_ATOL = 1e-12, 1e-15


@dataclass
class _Layout:
    """The top-level links and joints of the text (:class:`~.xml_spans.Element`), with the child each one has edited."""

    root: Element
    links: dict = field(default_factory=dict)      # name → (link, its <inertial> or None)
    joints: dict = field(default_factory=dict)     # name → (joint, its <dynamics> or None)


def _indent(raw: bytes, position: int) -> bytes:
    """The spaces and tabs between the start of ``position``'s line and ``position`` (none on a very long line)."""
    earliest = max(0, position - INDENT_WINDOW)
    line = raw.rfind(b"\n", earliest, position) + 1
    before = raw[line:position]
    return before if (line or not earliest) and not before.strip() else b""


EDITED = {"link": "inertial", "joint": "dynamics"}   # the root's children, and the child of each that is edited


def _local(element: Element) -> str:
    return element.name.split(" ")[-1]


def _check_namespace(element: Element, where: str, owner: str) -> None:
    if element.default_namespace:
        raise InputError(f"{where}: {owner}: <{element.qualified}> is in the namespace "
                         f"'{element.name.split(' ')[0]}' by a default xmlns: our loader skips it, urdfdom "
                         "(Pinocchio) reads it; remove the xmlns")


def _layout(raw: bytes, where: str) -> _Layout:
    """Links and joints as the loader reads them: the root's children named ``link`` or ``joint`` (in no
    namespace), and the child of each named ``inertial`` or ``dynamics``. Two of those, or one that a default
    ``xmlns`` puts in a namespace (which lxml sees and urdfdom does not), are refused: readers would differ."""
    root = elements(raw, where, depth=2)
    layout = _Layout(root)
    _check_namespace(root, where, "the robot")
    for top in (element for element in root.children if _local(element) in EDITED):
        name, part = top.values.get("name", ""), EDITED[_local(top)]
        owner = f"{top.qualified} '{name}'"
        for element in [top] + [child for child in top.children if _local(child) == part]:
            _check_namespace(element, where, owner)
        table = layout.links if top.name == "link" else layout.joints
        if name in table:
            raise InputError(f"{where}: two {top.name}s are named '{name}'")
        parts = [child for child in top.children if child.name == part]
        if len(parts) > 1:
            raise InputError(f"{where}: {owner}: {len(parts)} <{part}> elements; a URDF has one (readers take the "
                             "first, and the others would stay beside the identified one): remove the others")
        table[name] = (top, parts[0] if parts else None)
    return layout


def _number(x) -> str:
    value = float(x)
    if not np.isfinite(value):
        raise InputError(f"an identified value is not finite ({value}); nothing was written")
    return repr(value + 0.0)  # + 0.0: -0.0 reads back the same, but is written 0.0


def _inertial(body, indent: bytes, unit: bytes, newline: bytes = b"\n") -> bytes:
    c, I = body.p_com, body.I_com
    inner = indent + unit
    lines = [b"<inertial>",
             inner + f'<origin xyz="{_number(c[0])} {_number(c[1])} {_number(c[2])}" rpy="0 0 0"/>'.encode(),
             inner + f'<mass value="{_number(body.mass)}"/>'.encode(),
             inner + (f'<inertia ixx="{_number(I[0, 0])}" ixy="{_number(I[0, 1])}" ixz="{_number(I[0, 2])}" '
                      f'iyy="{_number(I[1, 1])}" iyz="{_number(I[1, 2])}" izz="{_number(I[2, 2])}"/>').encode(),
             indent + b"</inertial>"]
    return newline.join(lines)


def _child_indent(raw: bytes, element: Element) -> bytes:
    return _indent(raw, element.children[0].start) if element.children else b""


def _unit(raw: bytes, element: Element) -> bytes:
    """One level of indentation, as the file uses it (two spaces where it cannot tell)."""
    outer, inner = _indent(raw, element.start), _child_indent(raw, element)
    if element.children and inner.startswith(outer) and inner != outer:
        return inner[len(outer):]
    return b"  "


def _set_attributes(raw: bytes, tag: Element, values: dict) -> list:
    """The edits that give the start tag of ``tag`` the ``values`` (name → text): a value there is replaced between
    its quotes, any other attribute is added after the last one (the space before ``/>`` stays)."""
    close = tag.start_end - (2 if tag.empty else 1)
    while raw[close - 1:close] in (b" ", b"\t", b"\r", b"\n"):
        close -= 1
    return [(*tag.attributes[name], value.encode()) if name in tag.attributes else
            (close, close, f' {name}="{value}"'.encode()) for name, value in values.items()]


def _before_end_tag(raw: bytes, element: Element, text: bytes, newline: bytes) -> tuple[int, int, bytes]:
    """The edit that puts ``text`` as the last child of ``element``: on a line of its own when the end tag has one."""
    outer = _indent(raw, element.end_tag)
    line_start = element.end_tag - len(outer)
    if raw[line_start - 1:line_start] != b"\n":
        return element.end_tag, element.end_tag, text          # all on one line: <joint ...><parent/>...</joint>
    indent = _child_indent(raw, element) if element.children else outer + _unit(raw, element)
    return line_start, line_start, indent + text + newline


def _check_encoding(raw: bytes, where: str) -> None:
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")) or b"\x00" in raw[:200]:
        raise InputError(f"{where}: a UTF-16 or UTF-32 URDF cannot be edited in place; save it as UTF-8")


def _applied(raw: bytes, edits: list) -> bytes:
    """``raw`` with each (start, end, text) of ``edits`` done, in one pass (insertions at one place in their order)."""
    pieces, at = [], 0
    for start, end, text in sorted(edits, key=lambda edit: edit[:2]):
        assert start >= at, "two edits of the URDF overlap"
        pieces += [raw[at:start], text]
        at = end
    return b"".join(pieces + [raw[at:]])


def identified_urdf(raw: bytes, identified: Model, friction: Friction | None = None, where: str = "the URDF") -> bytes:
    """The URDF text ``raw`` with ``identified``'s inertial parameters (and ``friction``) written in (module docstring).

    ``identified`` must come from this URDF (same moving links and joints): the model loaded from it,
    with new masses, centres of mass and inertias. Raises
    :class:`~course_dynamics.base.errors.InputError` when a body's link or joint is not in the text, or
    the text is not XML we edit.

    Parameters
    ----------
    raw : bytes
        The text of the URDF the model was loaded from.
    identified : Model
        The identified robot: mᵢ, ⁱP_Cᵢ and ᶜⁱIᵢ of every moving body, kg, m and kg·m².
    friction : Friction, optional
        The identified viscous v (N·m·s/rad) and Coulomb c (N·m) coefficients of (6.112), one per joint
        (N·s/m and N for a prismatic joint), written as ``damping`` and ``friction``; without it every
        ``<dynamics>`` stays as it was.
    where : str, optional
        The name of the text in messages (its file).

    Returns
    -------
    bytes
        The edited text, in the encoding of ``raw``.

    Raises
    ------
    InputError
        If a body's link or joint is not in the text, the text is not XML we edit (a DTD or entity, UTF-16,
        a second ``<inertial>`` or ``<dynamics>``, a default ``xmlns``, two links or joints of one name),
        or an identified value is not finite.
    """
    _check_encoding(raw, where)
    layout = _layout(raw, where)
    newline = b"\r\n" if b"\r\n" in raw else b"\n"
    moving = {body.name for body in identified.bodies}
    merged = [f.name for f in identified.frames if f.body >= 0 and f.name not in moving]
    edits = []   # (start, end, replacement)
    for body in identified.bodies:
        if body.name not in layout.links or body.joint not in layout.joints:
            missing = f"link '{body.name}'" if body.name not in layout.links else f"joint '{body.joint}'"
            raise InputError(f"{where}: has no {missing}, which the identified model has: write the URDF the model "
                             "was loaded from")
        link, inertial = layout.links[body.name]
        unit = _unit(raw, link)
        indent = _child_indent(raw, link) if link.children else _indent(raw, link.start) + unit
        if inertial is not None:
            edits.append((inertial.start, inertial.end, _inertial(body, _indent(raw, inertial.start), unit, newline)))
        elif link.empty:   # <link name="x"/>: its '/>' becomes '>', the inertial and '</link>'
            edits.append((link.start_end - 2, link.start_end, b">" + newline + indent + _inertial(body, indent, unit,
                          newline) + newline + _indent(raw, link.start) + b"</link>"))
        else:
            edits.append((link.start_end, link.start_end, newline + indent + _inertial(body, indent, unit, newline)))
    for name in merged:
        inertial = layout.links.get(name, (None, None))[1]
        if inertial is not None:
            edits.append((inertial.start, inertial.end, MERGED_NOTE))
    if friction is not None:
        for body, (damping, coulomb) in zip(identified.bodies, _body_friction(identified, friction)):
            joint, dynamics = layout.joints[body.joint]
            values = {"damping": _number(damping), "friction": _number(coulomb)}
            if dynamics is not None:  # its other attributes (a simulator's) stay
                edits += _set_attributes(raw, dynamics, values)
            elif not joint.empty:
                text = "<dynamics " + " ".join(f'{k}="{v}"' for k, v in values.items()) + "/>"
                edits.append(_before_end_tag(raw, joint, text.encode(), newline))
    edits.append((layout.root.start, layout.root.start, HEADER_NOTE.rstrip(b"\n") + newline))
    return _applied(raw, edits)


def _body_friction(model: Model, friction: Friction) -> list[tuple[float, float]]:
    """(damping, friction) to write on each body's joint: a coordinate's on its own joint, none on a joint that
    mimics another (its coefficients act on its leader's coordinate, where they were identified)."""
    own = {k: j for j, k in enumerate(model.coordinates)}
    return [(float(friction.viscous[own[k]]), float(friction.coulomb[own[k]])) if k in own else (0.0, 0.0)
            for k in range(model.n_bodies)]


def _shown(value) -> str:
    return " ".join(f"{float(x):.17g}" for x in np.ravel(value))


def check_reads_back(text: bytes, identified: Model, friction: Friction | None, target: str, source: str) -> None:
    """InputError unless our loader reads ``text`` as ``identified`` (every mass, centre of mass and inertia of a
    moving body) and ``friction`` (every damping and friction written): an edit of the wrong text is never left
    behind. ``target`` (the file to be written) and ``source`` (the URDF edited) name the problem.

    Parameters
    ----------
    text : bytes
        The URDF text to check (from :func:`identified_urdf`).
    identified : Model
        The identified robot the text must read back as.
    friction : Friction or None
        The friction coefficients it must read back as; None checks none.
    target : str
        The file to be written, for messages.
    source : str
        The URDF that was edited, for messages.

    Raises
    ------
    InputError
        If the text does not load, or a joint, mass, centre of mass, inertia, damping or friction reads back
        differently.
    """
    with tempfile.TemporaryDirectory(prefix="course-dynamics-") as folder:
        copy = Path(folder) / "identified.urdf"
        io.write_bytes(copy, text)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", InertiaWarning)   # physics is the identification's; here, numbers
                back = load_urdf(copy, allow_nonphysical_inertia=True)
        except ModelError as exc:
            problem = str(exc).replace(f"{copy}: ", "")
            raise InputError(f"{target}: the URDF edited from {source} would not load ({problem}); nothing was "
                             "written") from None

    def refuse(what, got, expected):
        raise InputError(f"{target}: {what} reads back as {got} from the URDF edited from {source}, not the "
                         f"identified {expected}; nothing was written")

    if back.joint_names != identified.joint_names:
        refuse("the moving joints", ", ".join(back.joint_names), ", ".join(identified.joint_names))
    if back.coupling != identified.coupling:
        refuse("the mimic joints", str(back.coupling), str(identified.coupling))
    written = _body_friction(identified, friction) if friction is not None else None
    for i, (got, body) in enumerate(zip(back.bodies, identified.bodies)):
        for what, value, expected in (("mass", got.mass, body.mass), ("centre of mass", got.p_com, body.p_com),
                                      ("inertia", got.I_com, body.I_com)):
            if got.name != body.name or not np.allclose(value, expected, rtol=READBACK_RTOL, atol=READBACK_ATOL):
                refuse(f"link '{body.name}': {what}", _shown(value), _shown(expected))
        if friction is not None:
            for what, value, expected in (("damping", got.damping, written[i][0]),
                                          ("friction", got.friction, written[i][1])):
                if value != float(expected):
                    refuse(f"joint '{body.joint}': {what}", _shown(value), _shown(expected))


def checked_identified_urdf(identified: Model, friction: Friction | None = None, source=None,
                            target: str = "the URDF") -> bytes:
    """The identified URDF's text, read back by our loader (:func:`check_reads_back`) for ``target``.

    ``source``: the URDF the model was loaded from (default ``identified.source``), read as text
    (a regular file of at most :data:`MAX_URDF_BYTES`).

    Parameters
    ----------
    identified : Model
        The identified robot (loaded from ``source``, with new inertial parameters).
    friction : Friction, optional
        The identified friction coefficients, written into each joint's ``<dynamics>``.
    source : str or pathlib.Path, optional
        The URDF file to edit; ``identified.source`` by default.
    target : str, optional
        The file to be written, for messages.

    Returns
    -------
    bytes
        The identified URDF's text.

    Raises
    ------
    InputError
        If the source is not known or cannot be read, is not a URDF we edit, or the text reads back
        differently (:func:`identified_urdf`, :func:`check_reads_back`).
    """
    source = identified.source if source is None else source
    if not source:
        raise InputError(f"robot '{identified.name}': the URDF it was loaded from is not known; give source")
    raw = read_small(source, MAX_URDF_BYTES, "URDF file")
    text = identified_urdf(raw, identified, friction, where=str(source))
    check_reads_back(text, identified, friction, target, str(source))
    return text


def write_identified_urdf(path, identified: Model, friction: Friction | None = None, source=None) -> None:
    """Write the identified URDF to ``path`` (whole or not at all; ``-`` is standard output).

    The text is :func:`checked_identified_urdf`'s: read back by our loader before anything is written.

    Parameters
    ----------
    path : str or pathlib.Path
        The file to write, or ``-`` for standard output.
    identified : Model
        The identified robot.
    friction : Friction, optional
        The identified friction coefficients.
    source : str or pathlib.Path, optional
        The URDF file to edit; ``identified.source`` by default.

    Raises
    ------
    InputError
        As :func:`checked_identified_urdf`, or if ``path`` cannot be written.
    """
    target = "standard output" if str(path) == io.STDOUT else str(path)
    io.write_bytes(path, checked_identified_urdf(identified, friction, source, target))


def payload_urdf(raw: bytes, model: Model, link: str, pi, name: str = "payload", where: str = "the URDF") -> bytes:
    """The URDF text ``raw`` with a payload added: a link ``name`` with ``<inertial>`` π_P, fixed to ``link`` at its
    origin (joint ``<name>_fixed``), as the last children of ``<robot>``; everything else kept byte for byte.

    Parameters
    ----------
    raw : bytes
        The text of the URDF ``model`` was loaded from.
    model : Model
        The robot without the payload.
    link : str
        F, the link the payload is fixed to.
    pi : array_like, shape (10,)
        π_P in F: m (kg, > 0), m c (kg·m), the inertia about F's origin (kg·m²), as
        :data:`~course_dynamics.core.regressor.PARAMETER_NAMES` orders them.
    name : str, optional
        The new link's name.
    where : str, optional
        The name of the text in messages (its file).

    Returns
    -------
    bytes
        The text with the payload, in the encoding of ``raw``.

    Raises
    ------
    InputError
        If the URDF has a link ``name`` or joint ``<name>_fixed`` already (a payload written before: identify from
        the URDF without it), has no link ``link``, is not XML we edit, or a value is not finite.
    """
    _check_encoding(raw, where)
    layout = _layout(raw, where)
    joint = f"{name}_fixed"
    if name in layout.links or joint in layout.joints:
        taken = f"link '{name}'" if name in layout.links else f"joint '{joint}'"
        raise InputError(f"{where}: has a {taken} already (a payload written before?): identify a payload from the "
                         "URDF without it")
    if link not in layout.links:
        raise InputError(f"{where}: has no link '{link}', the payload's flange")
    pi = np.asarray(pi, dtype=float)
    c = pi[1:4] / pi[0]
    I_com = pi[np.array(TENSOR)] - pi[0] * (c @ c * np.eye(3) - np.outer(c, c))          # (6.25)
    body = SimpleNamespace(mass=pi[0], p_com=c, I_com=I_com)
    newline = b"\r\n" if b"\r\n" in raw else b"\n"
    unit = _unit(raw, layout.root)
    indent = _child_indent(raw, layout.root) if layout.root.children else unit
    lines = [f'<link name="{name}">'.encode(), indent + unit + _inertial(body, indent + unit, unit, newline),
             indent + b"</link>", indent + f'<joint name="{joint}" type="fixed">'.encode(),
             indent + unit + f'<parent link="{link}"/>'.encode(), indent + unit + f'<child link="{name}"/>'.encode(),
             indent + unit + b'<origin xyz="0 0 0" rpy="0 0 0"/>', indent + b"</joint>"]
    comment = b"<!-- the payload identified by course-dynamics identify (scope payload) -->"
    text = comment + newline + indent + newline.join(lines)
    return _applied(raw, [_before_end_tag(raw, layout.root, text, newline)])


def checked_payload_urdf(model: Model, link: str, pi, source=None, target: str = "the URDF",
                         name: str = "payload") -> bytes:
    """:func:`payload_urdf`'s text, read back by our loader (:func:`check_reads_back`): the flange's body must read
    back as the arm's with π_P added in its frame (:func:`~course_dynamics.tools.payloads.offset_map`).

    Parameters
    ----------
    model : Model
        The robot without the payload.
    link : str
        F, the link the payload is fixed to.
    pi : array_like, shape (10,)
        π_P in F.
    source : str or pathlib.Path, optional
        The URDF file to edit; ``model.source`` by default.
    target : str, optional
        The file to be written, for messages.
    name : str, optional
        The new link's name.

    Returns
    -------
    bytes
        The URDF's text with the payload.

    Raises
    ------
    InputError
        As :func:`payload_urdf`, or if the text reads back differently.
    """
    source = model.source if source is None else source
    if not source:
        raise InputError(f"robot '{model.name}': the URDF it was loaded from is not known; give source")
    raw = read_small(source, MAX_URDF_BYTES, "URDF file")
    text = payload_urdf(raw, model, link, pi, name, where=str(source))
    frame = model.frame(link)
    pi_all = parameters(model)
    pi_all[10 * frame.body:10 * frame.body + 10] += offset_map(frame.R, frame.P) @ np.asarray(pi, dtype=float)
    check_reads_back(text, with_parameters(model, pi_all), None, target, str(source))
    return text


def model_urdf(model: Model, comment: str = "") -> bytes:
    """A URDF written from the model alone: one link per body (its ``<inertial>``), one joint per body (origin,
    axis, limits, friction, ``<mimic>``), and each frame fixed to a body as a fixed joint and an empty link.

    For robots made in memory (a student's variant of a course robot): loading the text gives the same model,
    numbers and all (``repr`` digits); visuals, meshes and comments of any original file are not carried over.

    Parameters
    ----------
    model : Model
        The robot.
    comment : str, optional
        A comment written after the XML declaration (``--`` becomes ``-``); none by default.

    Returns
    -------
    bytes
        The URDF, UTF-8.

    Raises
    ------
    InputError
        If a number of the model is not finite.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> text = model_urdf(load_robot("pendulum")).decode()
    >>> '<joint name="theta" type="continuous">' in text and '<mass value="1.0"/>' in text
    True
    """
    from scipy.spatial.transform import Rotation

    def xyz(v):
        return " ".join(_number(x) for x in v)

    def rpy(R):
        return xyz(Rotation.from_matrix(np.asarray(R, dtype=float)).as_euler("xyz")) \
            if not np.allclose(R, np.eye(3), 0, 0) else "0 0 0"

    base = model.base_link or "base"
    lines = ['<?xml version="1.0"?>'] + ([f"<!-- {comment.replace('--', '-')} -->"] if comment else [])
    lines += [f'<robot name="{model.name}">', f'  <link name="{base}"/>']
    for body in model.bodies:
        parent = model.bodies[body.parent].name if body.parent >= 0 else base
        lines += [f'  <link name="{body.name}">', "    " + _inertial(body, b"    ", b"  ").decode(), "  </link>"]
        limits = "" if body.joint_type == "continuous" else \
            f'    <limit lower="{_number(body.lower)}" upper="{_number(body.upper)}" effort="{_number(body.effort)}" ' \
            f'velocity="{_number(body.velocity)}"/>'
        lines += [f'  <joint name="{body.joint}" type="{body.joint_type}">', f'    <parent link="{parent}"/>',
                  f'    <child link="{body.name}"/>', f'    <origin xyz="{xyz(body.P)}" rpy="{rpy(body.R0)}"/>',
                  f'    <axis xyz="{xyz(body.axis)}"/>'] + ([limits] if limits else [])
        if body.damping or body.friction:
            lines.append(f'    <dynamics damping="{_number(body.damping)}" friction="{_number(body.friction)}"/>')
        if body.mimic:
            lines.append(f'    <mimic joint="{body.mimic}" multiplier="{_number(body.multiplier)}" '
                         f'offset="{_number(body.offset)}"/>')
        lines.append("  </joint>")
    names = {body.name for body in model.bodies} | {base}
    for frame in model.frames:
        if frame.name in names:
            continue
        parent = model.bodies[frame.body].name if frame.body >= 0 else base
        lines += [f'  <link name="{frame.name}"/>', f'  <joint name="{frame.name}_fixed" type="fixed">',
                  f'    <parent link="{parent}"/>', f'    <child link="{frame.name}"/>',
                  f'    <origin xyz="{xyz(frame.P)}" rpy="{rpy(frame.R)}"/>', "  </joint>"]
    return ("\n".join(lines + ["</robot>", ""])).encode()


__all__ = ["MAX_URDF_BYTES", "check_reads_back", "checked_identified_urdf", "checked_payload_urdf", "identified_urdf",
           "model_urdf", "payload_urdf", "write_identified_urdf"]

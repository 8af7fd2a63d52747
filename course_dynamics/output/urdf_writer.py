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
gazebo tags, comments, the layout — is kept byte for byte: the file is not re-serialised. It is
parsed by the standard library's expat (the parser under ``xml.etree``) only to find where the
changed elements start and end; a DTD or an entity is refused, nothing is fetched or run. What
is inserted is ASCII, so the text keeps its encoding (UTF-8, ASCII or Latin-1; UTF-16 is refused).
Numbers are written with ``repr`` (17 significant digits at most), so they read back exactly.
Relative mesh paths are kept as they are: they resolve against the folder of the written file.

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

import re
import xml.parsers.expat
from dataclasses import dataclass, field

import numpy as np

from ..base.errors import InputError
from ..base.files import read_small
from ..core.friction import Friction
from ..core.model import Model
from . import io

MAX_URDF_BYTES = 64 * 2**20  # as the loader's limit: a URDF larger than this was never loaded
MERGED_NOTE = b"<!-- inertial removed: lumped into the identified inertial of the moving link it is fixed to -->"
HEADER_NOTE = b"<!-- inertial parameters and joint friction identified by course-dynamics identify -->\n"


@dataclass
class _Element:
    """Where a top-level ``<link>`` or ``<joint>`` of the text starts and ends, and its changed child."""

    name: str
    start: int                  # '<' of the start tag
    start_end: int              # just after the start tag's '>'
    empty: bool                 # <link .../>
    end: int = -1               # '<' of the end tag (start_end for an empty element)
    child_indent: bytes = b""
    part: tuple[int, int] | None = None   # (start, end) of the <inertial> or <dynamics> child
    part_tag: str = ""
    part_tag_end: int = -1      # just after the child's start tag
    first_child: int | None = None


@dataclass
class _Layout:
    links: dict = field(default_factory=dict)
    joints: dict = field(default_factory=dict)
    robot: int = 0


def _tag_end(raw: bytes, start: int) -> int:
    """Just after the '>' that closes the tag starting at ``start`` (quoted attribute values may hold '>')."""
    quote = None
    for i in range(start + 1, len(raw)):
        c = raw[i:i + 1]
        if quote:
            quote = None if c == quote else quote
        elif c in (b'"', b"'"):
            quote = c
        elif c == b">":
            return i + 1
    raise InputError("unterminated tag")


def _indent(raw: bytes, position: int) -> bytes:
    """The spaces and tabs between the start of ``position``'s line and ``position``."""
    line = raw.rfind(b"\n", 0, position) + 1
    before = raw[line:position]
    return before if not before.strip() else b""


def _layout(raw: bytes, where: str) -> _Layout:
    """The top-level links and joints of the URDF text, with their ``<inertial>``/``<dynamics>`` children."""
    parser = xml.parsers.expat.ParserCreate()
    parser.SetParamEntityParsing(xml.parsers.expat.XML_PARAM_ENTITY_PARSING_NEVER)
    layout, stack = _Layout(), []

    def refuse(*_):
        raise InputError(f"{where}: declares a DTD or an entity; URDF files have none")

    def start(name, attributes):
        at = parser.CurrentByteIndex
        end = _tag_end(raw, at)
        empty = raw[end - 2:end] == b"/>"
        if not stack:
            layout.robot = at
        owner = stack[1] if len(stack) == 2 and isinstance(stack[1], _Element) else None
        if owner is not None:
            if owner.first_child is None:
                owner.first_child, owner.child_indent = at, _indent(raw, at)
            if name in ("inertial", "dynamics") and owner.part is None:
                owner.part, owner.part_tag, owner.part_tag_end = (at, end if empty else -1), name, end
        if len(stack) == 1 and name in ("link", "joint"):
            element = _Element(attributes.get("name", ""), at, end, empty, end if empty else -1)
            table = layout.links if name == "link" else layout.joints
            if element.name in table:
                raise InputError(f"{where}: two {name}s are named '{element.name}'")
            table[element.name] = element
            stack.append(element)
        else:
            stack.append(name)

    def finish(name):
        at = parser.CurrentByteIndex
        top = stack.pop()
        if isinstance(top, _Element) and not top.empty:
            top.end = at
        if len(stack) == 2 and isinstance(stack[1], _Element) and name == stack[1].part_tag and stack[1].part[1] < 0:
            stack[1].part = (stack[1].part[0], _tag_end(raw, at))

    parser.StartElementHandler, parser.EndElementHandler = start, finish
    parser.StartDoctypeDeclHandler = parser.EntityDeclHandler = refuse
    try:
        parser.Parse(raw, True)
    except xml.parsers.expat.ExpatError as exc:
        raise InputError(f"{where}: malformed XML: {exc}") from None
    return layout


def _number(x) -> str:
    value = float(x)
    if not np.isfinite(value):
        raise InputError(f"an identified value is not finite ({value}); nothing was written")
    return repr(value + 0.0)  # + 0.0: -0.0 reads back the same, but is written 0.0


def _inertial(body, indent: bytes, unit: bytes) -> bytes:
    c, I = body.p_com, body.I_com
    inner = indent + unit
    lines = [b"<inertial>",
             inner + f'<origin xyz="{_number(c[0])} {_number(c[1])} {_number(c[2])}" rpy="0 0 0"/>'.encode(),
             inner + f'<mass value="{_number(body.mass)}"/>'.encode(),
             inner + (f'<inertia ixx="{_number(I[0, 0])}" ixy="{_number(I[0, 1])}" ixz="{_number(I[0, 2])}" '
                      f'iyy="{_number(I[1, 1])}" iyz="{_number(I[1, 2])}" izz="{_number(I[2, 2])}"/>').encode(),
             indent + b"</inertial>"]
    return b"\n".join(lines)


def _unit(raw: bytes, element: _Element) -> bytes:
    """One level of indentation, as the file uses it (two spaces where it cannot tell)."""
    outer = _indent(raw, element.start)
    if element.first_child is not None and element.child_indent.startswith(outer) and element.child_indent != outer:
        return element.child_indent[len(outer):]
    return b"  "


def _with_attributes(tag: bytes, values: dict) -> bytes:
    """The start tag ``tag`` with ``values`` (name → text) set: replaced where present, else added at its end."""
    for name, value in values.items():
        pattern = re.compile(rb"(\s" + name.encode() + rb"\s*=\s*)(\"[^\"]*\"|'[^']*')")
        if pattern.search(tag):
            tag = pattern.sub(lambda m: m.group(1) + b'"' + value.encode() + b'"', tag, count=1)
        else:
            close = len(tag) - (2 if tag.endswith(b"/>") else 1)
            tag = tag[:close].rstrip() + f' {name}="{value}"'.encode() + (b"/>" if tag.endswith(b"/>") else b">")
    return tag


def _before_end_tag(raw: bytes, element: _Element, text: bytes) -> tuple[int, int, bytes]:
    """The edit that puts ``text`` as the last child of ``element``: on a line of its own when the end tag has one."""
    outer = _indent(raw, element.end)
    line_start = element.end - len(outer)
    if raw[line_start - 1:line_start] != b"\n":
        return element.end, element.end, text          # all on one line: <joint ...><parent/>...</joint>
    indent = element.child_indent if element.first_child is not None else outer + _unit(raw, element)
    return line_start, line_start, indent + text + b"\n"


def _check_encoding(raw: bytes, where: str) -> None:
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")) or b"\x00" in raw[:200]:
        raise InputError(f"{where}: a UTF-16 or UTF-32 URDF cannot be edited in place; save it as UTF-8")


def identified_urdf(raw: bytes, identified: Model, friction: Friction | None = None, where: str = "the URDF") -> bytes:
    """The URDF text ``raw`` with ``identified``'s inertial parameters (and ``friction``) written in (module docstring).

    ``identified`` must come from this URDF (same moving links and joints): the model loaded from it,
    with new masses, centres of mass and inertias. Raises :class:`InputError` when a body's link or
    joint is not in the text, or the text is not XML we edit.
    """
    _check_encoding(raw, where)
    layout = _layout(raw, where)
    moving = {body.name for body in identified.bodies}
    merged = [f.name for f in identified.frames if f.body >= 0 and f.name not in moving]
    edits = []   # (start, end, replacement)
    for body in identified.bodies:
        link = layout.links.get(body.name)
        if link is None or body.joint not in layout.joints:
            missing = f"link '{body.name}'" if link is None else f"joint '{body.joint}'"
            raise InputError(f"{where}: has no {missing}, which the identified model has: write the URDF the model "
                             "was loaded from")
        unit = _unit(raw, link)
        indent = link.child_indent if link.first_child is not None else _indent(raw, link.start) + unit
        if link.part is not None:
            edits.append((link.part[0], link.part[1], _inertial(body, _indent(raw, link.part[0]), unit)))
        elif link.empty:
            outer = _indent(raw, link.start)
            closing = raw[link.start:link.start_end - 2].rstrip() + b">"
            edits.append((link.start, link.start_end, closing + b"\n" + indent + _inertial(body, indent, unit)
                          + b"\n" + outer + b"</link>"))
        else:
            edits.append((link.start_end, link.start_end, b"\n" + indent + _inertial(body, indent, unit)))
    for name in merged:
        link = layout.links.get(name)
        if link is not None and link.part is not None:
            edits.append((link.part[0], link.part[1], MERGED_NOTE))
    if friction is not None:
        for i, body in enumerate(identified.bodies):
            joint = layout.joints[body.joint]
            values = {"damping": _number(friction.viscous[i]), "friction": _number(friction.coulomb[i])}
            if joint.part is not None:  # its other attributes (a simulator's) stay
                tag = raw[joint.part[0]:joint.part_tag_end]
                edits.append((joint.part[0], joint.part_tag_end, _with_attributes(tag, values)))
                continue
            text = "<dynamics " + " ".join(f'{k}="{v}"' for k, v in values.items()) + "/>"
            if not joint.empty:
                edits.append(_before_end_tag(raw, joint, text.encode()))
    edits.append((layout.robot, layout.robot, HEADER_NOTE))
    out = raw
    for start, end, text in sorted(edits, key=lambda e: (e[0], e[1]), reverse=True):
        out = out[:start] + text + out[end:]
    return out


def write_identified_urdf(path, identified: Model, friction: Friction | None = None, source=None) -> None:
    """Write the identified URDF to ``path`` (whole or not at all; ``-`` is standard output).

    ``source``: the URDF the model was loaded from (default ``identified.source``), read as text
    (a regular file of at most :data:`MAX_URDF_BYTES`).
    """
    source = identified.source if source is None else source
    if not source:
        raise InputError(f"robot '{identified.name}': the URDF it was loaded from is not known; give source")
    raw = read_small(source, MAX_URDF_BYTES, "URDF file")
    io.write_bytes(path, identified_urdf(raw, identified, friction, where=str(source)))


def model_urdf(model: Model, comment: str = "") -> bytes:
    """A URDF written from the model alone: one link per body (its ``<inertial>``), one joint per body (origin,
    axis, limits, friction), and each frame fixed to a body as a fixed joint and an empty link.

    For robots made in memory (a student's variant of a course robot): loading the text gives the same model,
    numbers and all (``repr`` digits); visuals, meshes and comments of any original file are not carried over.

    >>> from course_dynamics import load_robot
    >>> text = model_urdf(load_robot("pendulum")).decode()
    >>> '<joint name="theta" type="continuous">' in text and '<mass value="1.0"/>' in text
    True
    """
    from scipy.spatial.transform import Rotation

    def xyz(v):
        return " ".join(_number(x) for x in v)

    def rpy(R):
        return xyz(Rotation.from_matrix(np.asarray(R, dtype=float)).as_euler("xyz")) if not np.allclose(R, np.eye(3), 0, 0) \
            else "0 0 0"

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

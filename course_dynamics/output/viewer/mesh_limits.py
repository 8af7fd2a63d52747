"""How much geometry a mesh file expands to, counted before trimesh reads it.

A mesh file's size says little about what it draws: COLLADA nodes may instance
other nodes, so a 4 KB file whose nodes each instance the previous one ten
times, six levels deep, is a million copies of its triangles, and trimesh
builds every one (for minutes). Each file is therefore counted here first,
from its structure alone, and refused above the limits below.

=========  =====================================================================
format     what is counted
=========  =====================================================================
STL        binary: the header's triangle count, which must match the file size;
           ASCII: ``vertex`` keywords / 3, and its solids
OBJ        ``f`` lines (a face of k corners is k − 2 triangles), and its objects,
           groups and materials
COLLADA    the scene graph expanded: every node visit and geometry instance, and
           the triangles of each instance (indices in ``<p>`` per corner, never
           the ``count`` attribute); a DTD, an ``<instance_node>`` cycle, nodes
           nested too deep, or references that make pycollada re-read its node
           libraries too often are refused
=========  =====================================================================

Every count is an upper bound on what trimesh builds (:func:`check_loaded`
compares the two after loading). Numbers are capped at :data:`CAP` while
counting, so that a scene graph of exponential size stays cheap to count.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from ...base.errors import CourseDynamicsError
from ...base.files import Refusals, read_small
from ...core.urdf import xml_parser

#: The largest mesh file that is read, bytes; a larger one is not drawn (the stick model is).
MAX_MESH_BYTES = 200 * 2**20  # any geometry: a mesh file larger than this is not drawn (stick model instead)
# MAX_TRIANGLES and MAX_INSTANCES hold for all the meshes of one robot together. In
# example-robot-data, Panda's visual meshes have 135 000 triangles and UR5's 96 000; the heaviest
# robot (b1 with its z1 arm) about a million. Two million triangles are ~20 s of trimesh parsing
# COLLADA and ~100 MB of HTML, about as much as an offline page should carry.
#: The most triangles the meshes of one robot may expand to together.
MAX_TRIANGLES = 2_000_000
# Node visits and geometry instances, which trimesh walks one by one in Python (~0.4 ms each):
# the most in example-robot-data is 360 (ANYmal with a Kinova arm); 5 000 take about 2 s.
#: The most node visits and geometry instances the meshes of one robot may expand to together.
MAX_INSTANCES = 5_000
# Per STL or OBJ file: trimesh names each solid, object or material group by searching the
# names so far (quadratic: 4 000 parts take 6 s); the most in example-robot-data is 109.
#: The most solids (STL), or objects, groups and materials (OBJ), in one file.
MAX_PARTS = 1_000
# Per COLLADA file: pycollada parses a node again on every pass while it instances a node defined
# after it (a chain of 1 000 such nodes is half a million parses, 10 s); ~7 µs per element.
#: The most node elements pycollada may parse for one COLLADA file, passes included.
MAX_NODE_LOADS = 200_000
#: The deepest that COLLADA nodes may nest.
MAX_NODE_DEPTH = 200  # trimesh walks nested nodes recursively, and Python stops at 1 000 frames
#: Counts are clipped at this while they are added up, far above every limit.
CAP = 10**15  # counts are clipped here while adding up, far above every limit
#: The mesh file suffixes that are read (and counted first).
MESH_FORMATS = (".stl", ".dae", ".obj")


class MeshLimitError(CourseDynamicsError):
    """A mesh file that cannot be counted, or that expands beyond the limits; the message names it."""


@dataclass(frozen=True)
class MeshCount:
    """What one mesh file expands to: triangles, and node visits plus geometry instances.

    Counts add with ``+``, clipped at :data:`CAP`.

    Parameters
    ----------
    triangles : int
        The triangles trimesh would build, at most.
    instances : int
        The node visits and geometry instances it would walk (solids, objects and groups for STL and OBJ).
    """

    triangles: int
    instances: int

    def __add__(self, other: MeshCount) -> MeshCount:
        return MeshCount(min(self.triangles + other.triangles, CAP), min(self.instances + other.instances, CAP))


MESH_REFUSALS = Refusals(error=MeshLimitError, unreadable="mesh file {path}: cannot open: {reason}",
                         not_a_file="mesh file {path}: not a regular file",
                         not_regular="mesh file {path}: not a regular file",
                         too_large="mesh file {path} is {size}, more than {limit}",
                         grew="mesh file {path}: more than {limit}")


def read_mesh_bytes(path: Path) -> bytes:
    """The bytes of a regular mesh file of at most :data:`MAX_MESH_BYTES` (a FIFO or device is refused, unread).

    Parameters
    ----------
    path : pathlib.Path
        The mesh file.

    Returns
    -------
    bytes
        Its content.

    Raises
    ------
    MeshLimitError
        If it cannot be opened, is not a regular file, or is larger than :data:`MAX_MESH_BYTES`.
    """
    return read_small(path, MAX_MESH_BYTES, "mesh file", refusals=MESH_REFUSALS)


def count_mesh(path: Path, data: bytes) -> MeshCount:
    """What the mesh file ``path``, whose bytes are ``data``, expands to (see the module table).

    Raises MeshLimitError naming the file for formats other than STL, OBJ and COLLADA,
    and for files that cannot be counted.

    Parameters
    ----------
    path : pathlib.Path
        The mesh file, whose suffix gives its format (:data:`MESH_FORMATS`).
    data : bytes
        Its content (:func:`read_mesh_bytes`).

    Returns
    -------
    MeshCount
        What it expands to.

    Raises
    ------
    MeshLimitError
        If the format is not read, or the file cannot be counted or is refused (a DTD, a cycle, nodes nested
        too deep, too many parts or node loads).
    """
    counter = COUNTERS.get(Path(path).suffix.lower())
    if counter is None:
        raise MeshLimitError(f"mesh file {path}: format '{Path(path).suffix}' is not read "
                             f"(only {', '.join(MESH_FORMATS)}, whose geometry is counted before reading)")
    try:
        return counter(data)
    except MeshLimitError as exc:
        raise MeshLimitError(f"mesh file {path}: {exc}") from None


def check_count(path: Path, count: MeshCount, total: MeshCount | None = None) -> None:
    """Raise MeshLimitError if ``count`` (or the robot's ``total`` so far) is above the limits.

    Parameters
    ----------
    path : pathlib.Path
        The mesh file, for the message.
    count : MeshCount
        What it expands to.
    total : MeshCount or None, optional
        What the robot's meshes expand to so far, this one included; default ``count``.

    Raises
    ------
    MeshLimitError
        If the triangles pass :data:`MAX_TRIANGLES` or the nodes and instances :data:`MAX_INSTANCES`.
    """
    total = count if total is None else total
    for what, limit, mine, all_ in (("triangles", MAX_TRIANGLES, count.triangles, total.triangles),
                                    ("nodes and instances", MAX_INSTANCES, count.instances, total.instances)):
        if all_ > limit:
            robot = "" if all_ == mine else f" ({all_:,} for the robot so far)"
            raise MeshLimitError(f"mesh file {path} expands to {mine:,} {what}{robot}, "
                                 f"more than the limit of {limit:,}")


def check_loaded(path: Path, count: MeshCount, triangles: int) -> None:
    """Raise MeshLimitError if trimesh built more triangles than were counted (a gap in the counting, refused).

    Parameters
    ----------
    path : pathlib.Path
        The mesh file, for the message.
    count : MeshCount
        What it was counted to expand to.
    triangles : int
        The triangles trimesh built.

    Raises
    ------
    MeshLimitError
        If ``triangles`` is more than ``count.triangles``.
    """
    if triangles > count.triangles:
        raise MeshLimitError(f"mesh file {path}: trimesh built {triangles:,} triangles, more than the "
                             f"{count.triangles:,} counted before reading it")


# ---------------------------------------------------------------------------------- STL and OBJ

_WORD_MARKS = bytes(0x20 if bytes([b]).isspace() else 0x78 for b in range(256))  # blank -> " ", else "x"


def count_words(text: bytes) -> int:
    """Whitespace-separated words in ``text`` (counted in C: no list of words is built)."""
    return (b" " + text.translate(_WORD_MARKS)).count(b" x")


def count_stl(data: bytes) -> MeshCount:
    """Binary STL when the header's triangle count fits the file size exactly (trimesh's test), else ASCII.

    Parameters
    ----------
    data : bytes
        The file's content.

    Returns
    -------
    MeshCount
        What it expands to.

    Raises
    ------
    MeshLimitError
        If it is neither binary nor ASCII STL, or has more than :data:`MAX_PARTS` solids.
    """
    claimed = int.from_bytes(data[80:84], "little") if len(data) >= 84 else None
    if claimed is not None and len(data) == 84 + 50 * claimed:
        return MeshCount(claimed, 1)
    text = data.lower()
    if not text.lstrip().startswith(b"solid") or b"vertex" not in text:
        header = f"says {claimed:,} triangles" if claimed is not None else "is cut short"
        raise MeshLimitError(f"binary STL header {header} but the file has room for "
                             f"{max(len(data) - 84, 0) / 50:,.1f}, and it is not ASCII STL either")
    return _parts_checked(MeshCount(text.count(b"vertex") // 3, max(text.count(b"endsolid"), 1)), "solids")


def count_obj(data: bytes) -> MeshCount:
    """Triangles of the ``f`` lines (k corners: k − 2), and one instance per object, group or material.

    Parameters
    ----------
    data : bytes
        The file's content.

    Returns
    -------
    MeshCount
        What it expands to.

    Raises
    ------
    MeshLimitError
        If it has more than :data:`MAX_PARTS` objects, groups and materials.
    """
    text = b"\n" + data.replace(b"\\\n", b"")  # trimesh joins continued lines too
    faces = re.findall(rb"\n[ \t]*f[ \t][^\n]*", text)
    corners = count_words(b"\n".join(faces)) - len(faces)  # each line's "f" is no corner
    no_corner = len(re.findall(rb"\n[ \t]*f[ \t][ \t\r]*(?=\n|\Z)", text))
    one_corner = len(re.findall(rb"\n[ \t]*f[ \t][ \t]*[^\s]+[ \t\r]*(?=\n|\Z)", text))
    triangles = corners - 2 * len(faces) + 2 * no_corner + one_corner  # faces of 0 or 1 corner draw nothing
    groups = len(re.findall(rb"\n[ \t]*(?:o|g|usemtl)[ \t]", text))
    return _parts_checked(MeshCount(triangles, 1 + groups), "objects, groups and materials")


def _parts_checked(count: MeshCount, parts: str) -> MeshCount:
    if count.instances > MAX_PARTS:
        raise MeshLimitError(f"has {count.instances:,} {parts}, more than the limit of {MAX_PARTS:,} for one file")
    return count


# ---------------------------------------------------------------------------------- COLLADA

# Corners (index groups in <p>) that each triangle of a primitive takes at least: 3 in <triangles>,
# one more per triangle in a polygon, strip or fan.
PRIMITIVE_CORNERS = {"triangles": 3, "polylist": 1, "polygons": 1, "tristrips": 1, "trifans": 1}


def count_dae(data: bytes) -> MeshCount:
    """The COLLADA scene graph expanded: node visits, geometry instances and their triangles.

    Parameters
    ----------
    data : bytes
        The file's content.

    Returns
    -------
    MeshCount
        What it expands to.

    Raises
    ------
    MeshLimitError
        If it is not COLLADA, declares a DTD, has an ``<instance_node>`` cycle, nests nodes deeper than
        :data:`MAX_NODE_DEPTH`, would make pycollada parse more than :data:`MAX_NODE_LOADS` nodes, or names no
        visual scene to draw.
    """
    root = _collada_root(data)
    nodes = list(root.iter("{*}node"))
    position = {node: i for i, node in enumerate(nodes)}
    by_id = {}
    for i, node in enumerate(nodes):
        by_id.setdefault(node.get("id"), i)
    triangles = {geometry.get("id"): _geometry_triangles(geometry) for geometry in root.iter("{*}geometry")}
    edges = [[position[child] for child in _children(node, "node")]
             + [by_id[url] for url in _targets(node, "instance_node") if url in by_id] for node in nodes]
    expanded, depth = [MeshCount(0, 0)] * len(nodes), [0] * len(nodes)
    for i in post_order(edges,
                        lambda i: f"<instance_node> references form a cycle through node '{nodes[i].get('id')}'"):
        expanded[i] = sum((expanded[j] for j in edges[i]), _own_count(nodes[i], triangles))
        depth[i] = 1 + max((depth[j] for j in edges[i]), default=0)
        if depth[i] > MAX_NODE_DEPTH:
            raise MeshLimitError(f"nodes nest more than {MAX_NODE_DEPTH} deep (node '{nodes[i].get('id')}')")
    loads = _node_loads(root)
    if loads > MAX_NODE_LOADS:
        raise MeshLimitError(f"pycollada would parse {loads:,} nodes, more than the limit of {MAX_NODE_LOADS:,} "
                             "(a node that instances one defined after it is parsed again on every pass)")
    scene = _drawn_scene(root)
    return sum((expanded[position[node]] for node in _children(scene, "node")), MeshCount(0, 0))


def _drawn_scene(root):
    """The <visual_scene> that <scene><instance_visual_scene url="#id"/> names: the only one trimesh draws."""
    names = [url for scene in root.iter("{*}scene") for url in _targets(scene, "instance_visual_scene")]
    scenes = {scene.get("id"): scene for scene in root.iter("{*}visual_scene")}
    if not names or names[0] not in scenes:
        raise MeshLimitError("no <scene><instance_visual_scene url=\"#...\"/> names a visual scene to draw")
    return scenes[names[0]]


def post_order(edges: list[list[int]], cycle) -> list[int]:
    """Vertices of a directed graph, each after all it points to; MeshLimitError(``cycle(i)``) on a cycle.

    Iterative, so that a chain of a million references needs no deep Python recursion.
    """
    order, state = [], [0] * len(edges)  # 0 unseen, 1 on the path, 2 done
    for start in range(len(edges)):
        if state[start]:
            continue
        state[start], path = 1, [(start, iter(edges[start]))]
        while path:
            i, pending = path[-1]
            j = next(pending, None)
            if j is None:
                path.pop()
                state[i] = 2
                order.append(i)
            elif state[j] == 1:
                raise MeshLimitError(cycle(j))
            elif state[j] == 0:
                state[j] = 1
                path.append((j, iter(edges[j])))
    return order


def _collada_root(data: bytes):
    """The document's root element, parsed with entities, DTDs and the network off; refused with a DTD."""
    from lxml import etree


    if b"<!ENTITY" in data or b"<!DOCTYPE" in data:
        raise MeshLimitError("declares a DTD (<!DOCTYPE ...>); COLLADA files have none, and XML entities are refused")
    try:
        root = etree.fromstring(data, parser=xml_parser())
    except (etree.LxmlError, ValueError) as exc:
        raise MeshLimitError(f"not COLLADA: malformed XML: {exc}") from None
    info = root.getroottree().docinfo
    if info.internalDTD is not None or info.externalDTD is not None or info.doctype:
        raise MeshLimitError("declares a DTD (<!DOCTYPE ...>); COLLADA files have none, and XML entities are refused")
    if _name(root) != "COLLADA":
        raise MeshLimitError(f"not COLLADA: the root element is <{_name(root)}>")
    return root


def _name(element) -> str:
    """The tag without its namespace ('' for comments and processing instructions)."""
    return element.tag.rsplit("}", 1)[-1] if isinstance(element.tag, str) else ""


def _children(element, name: str) -> list:
    return [child for child in element if _name(child) == name]


def _targets(element, name: str) -> list[str]:
    """The ids that the ``<name url="#id">`` children of ``element`` point to (other URLs are never loaded)."""
    urls = (child.get("url") or "" for child in _children(element, name))
    return [url[1:] for url in urls if url.startswith("#")]


def _offset(element) -> int:
    try:
        return max(int(element.get("offset", "0")), 0)
    except ValueError:
        raise MeshLimitError(f"<input offset=\"{element.get('offset')}\"> is not an integer") from None


def _geometry_triangles(geometry) -> int:
    """Triangles of one <geometry>: indices in its primitives' <p>, per corner, per triangle (an upper bound)."""
    total = 0
    for primitive in geometry.iter(*(f"{{*}}{name}" for name in PRIMITIVE_CORNERS)):
        stride = 1 + max((_offset(i) for i in _children(primitive, "input")), default=0)
        indices = sum(count_words(p.text.encode()) for p in primitive.iter("{*}p", "{*}h") if p.text)
        bound = indices // (stride * PRIMITIVE_CORNERS[_name(primitive)])
        if _name(primitive) == "polylist":
            bound = min(bound, _polylist_triangles(primitive))
        total = min(total + bound, CAP)
    return total


def _polylist_triangles(polylist) -> int:
    """Triangles of a <polylist> from its <vcount> (a polygon of k corners: k − 2); CAP if unreadable."""
    import numpy as np

    try:
        corners = np.array(" ".join(v.text or "" for v in _children(polylist, "vcount")).split(), dtype=np.int64)
    except (ValueError, OverflowError):
        return CAP
    return int(np.clip(corners - 2, 0, CAP).sum())


def _own_count(node, triangles: dict) -> MeshCount:
    """One node's own share: itself, its geometry instances and their triangles (camera, light... count too)."""
    geometries = _targets(node, "instance_geometry")
    others = sum(len(_children(node, name)) for name in ("instance_controller", "instance_camera", "instance_light"))
    return MeshCount(min(sum(triangles.get(g, 0) for g in geometries), CAP), 1 + len(geometries) + others)


def _node_loads(root) -> int:
    """Elements pycollada parses to load the node libraries and visual scenes, passes included.

    pycollada loads a library's top-level nodes in order, again and again while some refer
    (through <instance_node>) to a node it has not loaded yet: a node that needs one defined
    after it waits one more pass, and one whose reference never resolves is tried on every pass.
    """
    loads, library = 0, set()
    for group in [*root.iter("{*}library_nodes"), *root.iter("{*}visual_scene")]:
        tops = _children(group, "node")
        local = {}
        for k, top in enumerate(tops):
            local.setdefault(top.get("id"), k)
        needs = [[url[1:] for url in _instanced_urls(top) if url.startswith("#")] for top in tops]  # others: skipped
        edges = [[local[i] for i in need if i in local] for need in needs]
        passes = [0] * len(tops)
        for k in post_order(edges, lambda k: f"<instance_node> references form a cycle through '{tops[k].get('id')}'"):
            never = any(i not in local and i not in library for i in needs[k])
            passes[k] = CAP if never else max([1] + [passes[j] + (j > k) for j in edges[k]])
        last = max([p for p in passes if p < CAP], default=0) + 1
        loads = min(loads + sum(min(p, last) * sum(1 for _ in top.iter()) for p, top in zip(passes, tops)), CAP)
        if _name(group) == "library_nodes":
            library.update(top.get("id") for top in tops)
    return loads


def _instanced_urls(top) -> list[str]:
    return [node.get("url") or "" for node in top.iter("{*}instance_node")]


COUNTERS = {".stl": count_stl, ".obj": count_obj, ".dae": count_dae}


__all__ = ["CAP", "MAX_INSTANCES", "MAX_MESH_BYTES", "MAX_NODE_DEPTH", "MAX_NODE_LOADS", "MAX_PARTS", "MAX_TRIANGLES",
           "MESH_FORMATS", "MeshCount", "MeshLimitError", "check_count", "check_loaded", "count_dae", "count_mesh",
           "count_obj", "count_stl", "read_mesh_bytes"]

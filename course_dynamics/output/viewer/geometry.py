"""What to draw: the URDF's visual or collision shapes, or a stick model, per moving body.

* ``geometry="visual"`` or ``"collision"``: the URDF's own shapes (boxes,
  cylinders, spheres, STL/DAE/OBJ meshes with ``package://`` paths resolved),
  in one colour per link;
* ``geometry="stick"``: a stick model for robots without visuals and for the
  course robots: links as cylinders from joint to joint, joint axes as short
  bars, the centre of mass of each body as a sphere whose volume grows with
  its mass;
* ``geometry="auto"`` (default): visual meshes when they exist and are small
  enough for a light HTML file, else collision meshes, else the stick model.
  A mesh file that cannot be found, lies outside the folders it may be read
  from, or expands to more geometry than :mod:`.mesh_limits` allows gives a
  warning naming it and the stick model.

Shapes are placed in their body's frame (frame i of :mod:`course_dynamics.core.model`).
"""
from __future__ import annotations

import io
import os
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...base.errors import CourseDynamicsError, CourseDynamicsWarning
from ...base.resources import format_bytes
from ...core.model import Model
from ...core.robots import example_robot_data_share
from ...core.urdf import read_description
from .mesh_limits import (
    MAX_MESH_BYTES,
    MeshCount,
    MeshLimitError,
    check_count,
    check_loaded,
    count_mesh,
    read_mesh_bytes,
)

#: The choices of ``geometry``, what :func:`robot_geometry` draws (module docstring).
GEOMETRIES = ("auto", "visual", "collision", "stick")
#: With ``geometry="auto"``, visual meshes larger than this together, bytes, give way to the collision meshes.
MESH_BUDGET_BYTES = 1_500_000  # auto: larger visual meshes fall back to collision meshes
PACKAGE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*")  # a ROS package name: never '..', never a path
DEFAULT_COLOUR = (0.65, 0.67, 0.72)
STICK_COLOUR = 0x4a6fa5
AXIS_COLOUR = 0xd08030
COM_COLOUR = 0xc0392b
TORQUE_COLOUR = 0x27ae60
PATH_COLOUR = 0x8e44ad
#: Frames per second of an animation, Hz.
ANIMATION_FPS = 30


class ViewerError(CourseDynamicsError):
    """A trajectory that does not fit the robot, or an output that cannot be written.

    Also an unknown ``geometry``, a mesh file that cannot be read, and a meshcat server that did not start.
    """


class MeshWarning(CourseDynamicsWarning):
    """A mesh file of the URDF is not found, not allowed, or too big; the stick model is used instead.

    Also given when a mesh outside the URDF's folder is read because ``mesh_anywhere`` asked for it.
    """


# ---------------------------------------------------------------------------------- geometry


@dataclass
class Shape:
    """One piece of geometry, placed in its body's frame (4×4 ``T``).

    Parameters
    ----------
    kind : str
        ``box``, ``cylinder`` (along z, as in a URDF), ``cylinder_y`` (along y, as in meshcat), ``sphere`` or
        ``mesh``.
    T : numpy.ndarray, shape (4, 4)
        Its placement in the body's frame, m.
    size : tuple of float, optional
        A box's sides (x, y, z); a cylinder's (radius, length); a sphere's (radius,); m.
    path : pathlib.Path or None, optional
        A mesh's file.
    scale : tuple of float, optional
        A mesh's scale along x, y and z.
    colour : int, optional
        The colour, 0xRRGGBB.
    opacity : float, optional
        From 0 (invisible) to 1 (opaque).
    """

    kind: str  # box, cylinder, sphere, mesh
    T: np.ndarray
    size: tuple = ()
    path: Path | None = None
    scale: tuple = (1.0, 1.0, 1.0)
    colour: int = 0xa6abb8
    opacity: float = 1.0


@dataclass
class RobotGeometry:
    """Shapes per moving body (index) and for the fixed base (−1), and the kind that was chosen.

    Parameters
    ----------
    kind : str
        What is drawn: ``visual``, ``collision`` or ``stick``.
    shapes : dict of int to list of Shape, optional
        The shapes of each body, by its index in the model; −1 for the fixed base.
    warnings : list of str, optional
        The warnings given while choosing (each also given as a :class:`MeshWarning`).
    """

    kind: str
    shapes: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)


def resolve_mesh_path(filename: str, urdf) -> Path:
    """Where a URDF mesh reference is read from, symlinks resolved: ``package://``, ``file://``, absolute
    or relative.

    Parameters
    ----------
    filename : str
        The mesh reference, as the URDF writes it.
    urdf : str or pathlib.Path
        The URDF file that holds it.

    Returns
    -------
    pathlib.Path
        The file the reference names (which need not exist, nor be allowed: :func:`mesh_allowed`).
    """
    return mesh_location(filename, Path(urdf))[0]


def mesh_allowed(filename: str, urdf) -> bool:
    """Whether a mesh reference, resolved, lies in a folder it may be read from (see :func:`mesh_location`).

    Parameters
    ----------
    filename : str
        The mesh reference, as the URDF writes it.
    urdf : str or pathlib.Path
        The URDF file that holds it.

    Returns
    -------
    bool
        True if the file may be read.
    """
    return mesh_location(filename, Path(urdf))[1]


def mesh_location(filename: str, urdf: Path) -> tuple[Path, bool]:
    """The file a mesh reference names, symlinks and ``..`` resolved, and whether it may be read.

    A ``package://NAME/...`` file may be read when it lies in a folder of package NAME
    (:func:`package_folders`); any other reference when it lies in the URDF's folder or
    below. The allowed folder comes from the URDF's place and the package search path,
    never from the reference itself; nothing is percent-decoded, so what is checked is
    what is read.

    Parameters
    ----------
    filename : str
        The mesh reference, as the URDF writes it.
    urdf : pathlib.Path
        The URDF file that holds it.

    Returns
    -------
    tuple of (pathlib.Path, bool)
        The file, and whether it may be read.
    """
    urdf_folder = _resolved(urdf.parent)
    if filename.startswith("package://"):
        package, _, rest = filename[len("package://"):].lstrip("/").partition("/")
        return _package_file(package, rest, urdf, urdf_folder)
    text = filename[len("file://"):] if filename.startswith("file://") else filename
    path = _resolved(urdf.parent / text)  # an absolute path stays itself
    return path, _inside(path, urdf_folder)


def package_folders(package: str, urdf: Path) -> list[Path]:
    """The folders of ROS package ``package`` (resolved), in the order they are searched.

    ``NAME`` in each ``ROS_PACKAGE_PATH`` folder and in example-robot-data's share folder;
    then a folder above the URDF named ``NAME`` if it is a package (it holds a
    ``package.xml``), is the URDF's own folder, or lies inside one of those search folders.
    A folder that is merely named like the package is not one: ``package://home/...`` for
    a URDF under /home would otherwise read anything there.

    Parameters
    ----------
    package : str
        The package's name; one that is not a ROS package name (``..``, a path) has no folders.
    urdf : pathlib.Path
        The URDF file that refers to it.

    Returns
    -------
    list of pathlib.Path
        The package's folders that exist, each once, in the order they are searched.
    """
    if not PACKAGE_NAME.fullmatch(package):
        return []
    places = [_resolved(Path(p)) for p in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if p]
    try:

        places.append(_resolved(example_robot_data_share()))
    except FileNotFoundError:
        pass
    folders = [_resolved(place / package) for place in places]
    own = _resolved(urdf).parent
    for ancestor in [own, *own.parents]:
        if ancestor.name == package and (ancestor == own or (ancestor / "package.xml").is_file()
                                         or any(_inside(ancestor, p) and ancestor != p for p in places)):
            folders.append(ancestor)
    return list(dict.fromkeys(folder for folder in folders if folder.is_dir()))  # each once, in order


def _package_file(package: str, rest: str, urdf: Path, urdf_folder: Path) -> tuple[Path, bool]:
    """(file, may be read) for ``package://package/rest``: the first package folder that holds it.

    Folders merely named like the package are searched too, last, so that
    ``mesh_anywhere`` can read a file there; the file is then not allowed.
    """
    trusted = package_folders(package, urdf)
    named = [a for a in _resolved(urdf).parents if a.name == package and a not in trusted]
    candidates = [(folder, folder) for folder in trusted] + [(folder, None) for folder in named]
    candidates.append((urdf_folder / package, urdf_folder))  # not found: report it beside the URDF
    located = []
    for base, root in candidates:
        path = _resolved(Path(f"{base}/{rest}"))  # joined as text, as ROS does: a leading '/' stays inside
        located.append((path, root is not None and _inside(path, root)))
        if path.is_file():
            return located[-1]
    return located[0]


def _resolved(path: Path) -> Path:
    """``path`` made absolute with symlinks and ``..`` resolved (lexically only where that fails: a loop, a NUL)."""
    try:
        return path.resolve()
    except (OSError, RuntimeError, ValueError):
        return Path(os.path.abspath(path))


def _inside(path: Path, folder: Path) -> bool:
    try:
        return path.resolve().is_relative_to(folder)
    except (OSError, RuntimeError, ValueError):
        return False


def _colour(rgba) -> tuple[int, float]:
    if rgba is None:
        rgba = (*DEFAULT_COLOUR, 1.0)
    r, g, b = (int(round(255 * float(np.clip(c, 0, 1)))) for c in rgba[:3])
    return (r << 16) | (g << 8) | b, float(rgba[3]) if len(rgba) > 3 else 1.0


def _urdf_shapes(model: Model, urdf: Path, which: str):
    """Shapes of every link's <visual> or <collision>, in body frames; also the mesh files they need.

    The mesh files are ``(reference, path, allowed)``, one per mesh shape: the URDF's text, the
    file (:func:`mesh_location`) and whether it may be read.
    """

    robot = read_description(urdf)
    materials = {m.name: m for m in robot.materials}
    frames = {f.name: f for f in model.frames}
    shapes, meshes = {}, []
    for link in robot.links:
        frame = frames.get(link.name)
        if frame is None:
            continue
        T_body_link = np.eye(4)
        T_body_link[:3, :3], T_body_link[:3, 3] = frame.R, frame.P
        for element in (link.visuals if which == "visual" else link.collisions):
            geometry = element.geometry
            T = T_body_link @ (element.origin if element.origin is not None else np.eye(4))
            material = getattr(element, "material", None)
            rgba = None
            if material is not None:
                if material.color is None and material.name in materials and materials[material.name].color is not None:
                    material = materials[material.name]
                rgba = material.color.rgba if material.color is not None else None
            colour, opacity = _colour(rgba)
            if geometry.box is not None:
                shape = Shape("box", T, tuple(geometry.box.size), colour=colour, opacity=opacity)
            elif geometry.cylinder is not None:
                shape = Shape("cylinder", T, (geometry.cylinder.radius, geometry.cylinder.length),
                              colour=colour, opacity=opacity)
            elif geometry.sphere is not None:
                shape = Shape("sphere", T, (geometry.sphere.radius,), colour=colour, opacity=opacity)
            elif geometry.mesh is not None:
                path, allowed = mesh_location(geometry.mesh.filename, urdf)
                scale = tuple(geometry.mesh.scale) if geometry.mesh.scale is not None else (1.0, 1.0, 1.0)
                shape = Shape("mesh", T, path=path, scale=scale, colour=colour, opacity=opacity)
                meshes.append((geometry.mesh.filename, path, allowed))
            else:
                continue
            shapes.setdefault(frame.body, []).append(shape)
    return shapes, meshes


def stick_shapes(model: Model) -> dict:
    """The stick model: links as cylinders, joint axes as bars, COM spheres sized by mass.

    Parameters
    ----------
    model : Model
        The robot.

    Returns
    -------
    dict of int to list of Shape
        The shapes of each body, by its index; −1 for the segments from the base to the first joints.
    """
    masses = np.array([float(b.mass) for b in model.bodies])
    reach = max([float(np.linalg.norm(b.P)) for b in model.bodies]
                + [float(np.linalg.norm(b.p_com)) for b in model.bodies] + [0.1])
    radius = 0.04 * reach
    heaviest = max(masses.max(), 1e-9)
    shapes = {}
    for i, body in enumerate(model.bodies):
        ends = [model.bodies[c].P for c in model.children[i]] or [body.p_com]
        for end in ends:
            shapes.setdefault(i, []).append(_segment(np.zeros(3), np.asarray(end, float), radius, STICK_COLOUR))
        axis = np.asarray(body.axis, float)
        shapes[i].append(_segment(-0.15 * reach * axis, 0.15 * reach * axis, 0.6 * radius, AXIS_COLOUR))
        if body.mass > 0:
            T = np.eye(4)
            T[:3, 3] = body.p_com
            shapes[i].append(Shape("sphere", T, (2.5 * radius * (body.mass / heaviest) ** (1 / 3),), colour=COM_COLOUR))
    for i, body in enumerate(model.bodies):  # from the base to the first joints
        if body.parent < 0 and np.linalg.norm(body.P) > 0:
            shapes.setdefault(-1, []).append(_segment(np.zeros(3), np.asarray(body.P, float), radius, STICK_COLOUR))
    return shapes


def y_along(direction: np.ndarray) -> np.ndarray:
    """A rotation whose y axis points along ``direction`` (meshcat cylinders run along y)."""
    y = direction / np.linalg.norm(direction)
    helper = np.array([1.0, 0, 0]) if abs(y[0]) < 0.9 else np.array([0, 0, 1.0])
    x = np.cross(y, helper)
    x /= np.linalg.norm(x)
    return np.column_stack([x, y, np.cross(x, y)])


def _segment(start: np.ndarray, end: np.ndarray, radius: float, colour: int) -> Shape:
    """A cylinder from ``start`` to ``end``."""
    length = float(np.linalg.norm(end - start))
    T = np.eye(4)
    T[:3, 3] = (start + end) / 2
    if length > 1e-12:
        T[:3, :3] = y_along(end - start)
    return Shape("cylinder_y", T, (radius, max(length, 1e-6)), colour=colour)


def robot_geometry(model: Model, urdf, geometry: str = "auto", mesh_anywhere: bool = False) -> RobotGeometry:
    """Choose and collect the shapes to draw (see the module docstring).

    Mesh files are read only from the URDF's folder (and below) and, for ``package://``
    references, from the package's folder: an exported HTML file carries every mesh it
    draws, and a URDF from elsewhere could otherwise make it carry any file on disk. A
    mesh outside falls back to the stick model with a warning; ``mesh_anywhere=True``
    reads it (with a warning saying so). Mesh files are counted before they are read
    (:mod:`.mesh_limits`): geometry beyond the limits, for the robot as a whole, falls
    back to the stick model with a warning too.

    Parameters
    ----------
    model : Model
        The robot, loaded from ``urdf``.
    urdf : str or pathlib.Path
        Its URDF file.
    geometry : str, optional
        One of :data:`GEOMETRIES`: ``auto``, ``visual``, ``collision`` or ``stick``.
    mesh_anywhere : bool, optional
        Read mesh files outside the URDF's folder and its packages too.

    Returns
    -------
    RobotGeometry
        The shapes to draw and the kind chosen.

    Raises
    ------
    ViewerError
        If ``geometry`` is not one of :data:`GEOMETRIES`.

    Warns
    -----
    MeshWarning
        For a mesh that is not found, not allowed, a URL, too large or not finite (the stick model is drawn),
        and for one read from outside because ``mesh_anywhere`` asked.
    """
    if geometry not in GEOMETRIES:
        raise ViewerError(f"unknown geometry '{geometry}' (choose from {', '.join(GEOMETRIES)})")
    urdf = Path(urdf)
    result = RobotGeometry(kind="stick")
    if geometry == "stick":
        result.shapes = stick_shapes(model)
        return result
    candidates = ["visual", "collision"] if geometry == "auto" else [geometry]
    for which in candidates:
        shapes, meshes = _urdf_shapes(model, urdf, which)
        if not shapes:
            continue
        where = f"{which} geometry of {urdf}"
        problem = _reference_problem(shapes, meshes, where, mesh_anywhere, result)
        files = {path for _, path, _ in meshes}
        if problem is None and geometry == "auto" and which == "visual" \
                and sum(p.stat().st_size for p in files) > MESH_BUDGET_BYTES:
            continue  # too heavy for a light HTML file: try the collision meshes
        problem = problem or _count_problem(meshes, where)
        if problem is not None:
            _warn(result, f"{problem}; drawing the stick model")
            break
        result.kind, result.shapes = which, shapes
        return result
    result.shapes = stick_shapes(model)
    return result


def _warn(result: RobotGeometry, message: str, stacklevel: int = 3) -> None:
    """Keep ``message`` in ``result`` and warn it (``stacklevel`` 3: at the line that called robot_geometry)."""
    result.warnings.append(message)
    warnings.warn(message, MeshWarning, stacklevel=stacklevel)


def _reference_problem(shapes: dict, meshes: list, where: str, mesh_anywhere: bool, result: RobotGeometry):
    """Why the shapes cannot be drawn as the URDF gives them (a URL, a non-finite size, a file outside,
    missing or too large), or None. A file outside that ``mesh_anywhere`` reads gets a warning here."""
    urls = [ref for ref, _, _ in meshes if "://" in ref and not ref.startswith(("package://", "file://"))]
    if urls:
        return f"mesh {urls[0]} is a URL: meshes are never fetched ({where})"
    odd = [shape for body in shapes.values() for shape in body
           if not (np.all(np.isfinite(np.asarray(shape.size, dtype=float)))
                   and np.all(np.isfinite(np.asarray(shape.scale, dtype=float))) and np.all(np.isfinite(shape.T)))]
    if odd:
        return f"a {odd[0].kind} of the {where} has a non-finite size, scale or placement"
    outside = [path for _, path, allowed in meshes if not allowed]
    if outside and not mesh_anywhere:
        return (f"mesh file {outside[0]} lies outside the URDF's folder and its packages ({where}): not read "
                "(--allow-any-mesh-path reads it)")
    if outside:
        _warn(result, f"reading mesh file {outside[0]} from outside the URDF's folder, as asked", stacklevel=4)
    missing = [path for _, path, _ in meshes if not path.is_file()]
    if missing:
        return f"mesh file {missing[0]} not found ({where})"
    huge = [path for _, path, _ in meshes if path.stat().st_size > MAX_MESH_BYTES]
    if huge:
        return (f"mesh file {huge[0]} is {format_bytes(huge[0].stat().st_size)}, more than "
                f"{format_bytes(MAX_MESH_BYTES)} ({where})")
    return None


def _count_problem(meshes: list, where: str):
    """Why the mesh files, counted before trimesh reads them, are too much for one robot, or None.

    Each mesh shape counts, so a file drawn by ten links counts ten times (it is loaded ten times).
    """
    counts, total = {}, MeshCount(0, 0)
    for _, path, _ in meshes:
        try:
            if path not in counts:
                counts[path] = count_mesh(path, read_mesh_bytes(path))
            total += counts[path]
            check_count(path, counts[path], total)
        except MeshLimitError as exc:
            return f"{exc} ({where})"
    return None


def load_mesh(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (V, 3) float32 and triangles (F, 3) uint32 of an STL, DAE or OBJ file (trimesh).

    The file is read once, counted (:mod:`.mesh_limits`) and only then parsed, from those
    bytes: trimesh never opens a file itself, so no texture or material file beside it is
    read. Some mesh files carry zero or missing normals, which three.js then draws black;
    sending bare triangles lets the viewer compute its own.

    Raises ViewerError naming the file when it cannot be read or holds too much geometry.

    Parameters
    ----------
    path : str or pathlib.Path
        The mesh file: ``.stl``, ``.dae`` or ``.obj``.

    Returns
    -------
    vertices : numpy.ndarray, shape (V, 3), float32
        The vertices, in the file's units (m in a URDF's meshes).
    faces : numpy.ndarray, shape (F, 3), uint32
        The triangles, as indices into ``vertices``.

    Raises
    ------
    ViewerError
        If the file cannot be read or parsed, is not STL, COLLADA or OBJ, or holds more geometry than
        :mod:`~course_dynamics.output.viewer.mesh_limits` allows.
    """
    import trimesh

    path = Path(path)
    try:
        data = read_mesh_bytes(path)
        count = count_mesh(path, data)
        check_count(path, count)
    except MeshLimitError as exc:
        raise ViewerError(str(exc)) from None
    try:
        mesh = trimesh.load(io.BytesIO(data), file_type=path.suffix.lower()[1:], force="mesh")
        mesh.remove_unreferenced_vertices()  # vertices no triangle uses would only swell the HTML file
        vertices, faces = np.asarray(mesh.vertices, dtype=np.float32), np.asarray(mesh.faces, dtype=np.uint32)
    except Exception as exc:  # trimesh raises many kinds for unreadable files
        raise ViewerError(f"mesh file {path}: cannot read: {exc}") from None
    try:
        check_loaded(path, count, len(faces))
    except MeshLimitError as exc:
        raise ViewerError(str(exc)) from None
    return vertices, faces


__all__ = ["ANIMATION_FPS", "GEOMETRIES", "MESH_BUDGET_BYTES", "MeshWarning", "RobotGeometry", "Shape", "ViewerError",
           "load_mesh", "mesh_allowed", "mesh_location", "package_folders", "resolve_mesh_path", "robot_geometry",
           "stick_shapes"]

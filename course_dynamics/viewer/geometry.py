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
  A mesh file that cannot be found gives a warning naming it and the stick
  model.

Shapes are placed in their body's frame (frame i of :mod:`course_dynamics.model`).
"""
from __future__ import annotations

import os
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import CourseDynamicsError
from ..model import Model

GEOMETRIES = ("auto", "visual", "collision", "stick")
MESH_BUDGET_BYTES = 1_500_000  # auto: larger visual meshes fall back to collision meshes
MAX_MESH_BYTES = 200 * 2**20   # any geometry: a mesh file larger than this is not drawn (stick model instead)
DEFAULT_COLOUR = (0.65, 0.67, 0.72)
STICK_COLOUR = 0x4a6fa5
AXIS_COLOUR = 0xd08030
COM_COLOUR = 0xc0392b
TORQUE_COLOUR = 0x27ae60
PATH_COLOUR = 0x8e44ad
ANIMATION_FPS = 30


class ViewerError(CourseDynamicsError):
    """A trajectory that does not fit the robot, or an output that cannot be written."""


class MeshWarning(UserWarning):
    """A mesh file of the URDF could not be found or read; the stick model is used instead."""


# ---------------------------------------------------------------------------------- geometry


@dataclass
class Shape:
    """One piece of geometry, placed in its body's frame (4×4 ``T``)."""

    kind: str  # box, cylinder, sphere, mesh
    T: np.ndarray
    size: tuple = ()
    path: Path | None = None
    scale: tuple = (1.0, 1.0, 1.0)
    colour: int = 0xa6abb8
    opacity: float = 1.0


@dataclass
class RobotGeometry:
    """Shapes per moving body (index) and for the fixed base (−1), and the kind that was chosen."""

    kind: str
    shapes: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)


def resolve_mesh_path(filename: str, urdf: Path) -> Path:
    """A URDF mesh reference as a file path: ``package://``, ``file://`` or relative to the URDF."""
    if filename.startswith("package://"):
        relative = filename[len("package://"):]
        package = relative.split("/", 1)[0]
        roots = [Path(p) for p in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if p]
        try:
            from ..robots import example_robot_data_share

            roots.append(example_robot_data_share())
        except FileNotFoundError:
            pass
        for ancestor in urdf.resolve().parents:  # a package folder above the URDF
            if ancestor.name == package:
                roots.append(ancestor.parent)
        for root in roots:
            if (root / relative).is_file():
                return root / relative
        return (roots[0] if roots else urdf.parent) / relative
    if filename.startswith("file://"):
        return Path(filename[len("file://"):])
    path = Path(filename)
    return path if path.is_absolute() else urdf.parent / path


def _colour(rgba) -> tuple[int, float]:
    if rgba is None:
        rgba = (*DEFAULT_COLOUR, 1.0)
    r, g, b = (int(round(255 * float(np.clip(c, 0, 1)))) for c in rgba[:3])
    return (r << 16) | (g << 8) | b, float(rgba[3]) if len(rgba) > 3 else 1.0


def _urdf_shapes(model: Model, urdf: Path, which: str):
    """Shapes of every link's <visual> or <collision>, in body frames; also the mesh files they need."""
    from ..urdf import read_description

    robot = read_description(urdf)
    materials = {m.name: m for m in robot.materials}
    frames = {f.name: f for f in model.frames}
    shapes, meshes, references = {}, [], []
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
                shape = Shape("cylinder", T, (geometry.cylinder.radius, geometry.cylinder.length), colour=colour, opacity=opacity)
            elif geometry.sphere is not None:
                shape = Shape("sphere", T, (geometry.sphere.radius,), colour=colour, opacity=opacity)
            elif geometry.mesh is not None:
                path = resolve_mesh_path(geometry.mesh.filename, urdf)
                scale = tuple(geometry.mesh.scale) if geometry.mesh.scale is not None else (1.0, 1.0, 1.0)
                shape = Shape("mesh", T, path=path, scale=scale, colour=colour, opacity=opacity)
                meshes.append(path)
                references.append(geometry.mesh.filename)
            else:
                continue
            shapes.setdefault(frame.body, []).append(shape)
    return shapes, meshes, references


def stick_shapes(model: Model) -> dict:
    """The stick model: links as cylinders, joint axes as bars, COM spheres sized by mass."""
    masses = np.array([float(b.mass) for b in model.bodies])
    reach = max([float(np.linalg.norm(b.P)) for b in model.bodies] + [float(np.linalg.norm(b.p_com)) for b in model.bodies] + [0.1])
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


def mesh_allowed(filename: str, path: Path, urdf: Path) -> bool:
    """Whether a mesh reference stays inside the folder it may read: its package's for ``package://``, else the URDF's."""
    if filename.startswith("package://"):
        relative = Path(filename[len("package://"):])
        root = path
        for _ in relative.parts:
            root = root.parent
        root = root / relative.parts[0]
    else:
        root = urdf.parent
    try:
        return path.resolve().is_relative_to(root.resolve())
    except OSError:
        return False


def robot_geometry(model: Model, urdf, geometry: str = "auto", mesh_anywhere: bool = False) -> RobotGeometry:
    """Choose and collect the shapes to draw (see the module docstring).

    Mesh files are read only from the URDF's folder (and below) and, for ``package://``
    references, from the package's folder: an exported HTML file carries every mesh it
    draws, and a URDF from elsewhere could otherwise make it carry any file on disk. A
    mesh outside falls back to the stick model with a warning; ``mesh_anywhere=True``
    reads it (with a warning saying so).
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
        shapes, meshes, references = _urdf_shapes(model, urdf, which)
        if not shapes:
            continue
        urls = [ref for ref in references if "://" in ref and not ref.startswith(("package://", "file://"))]
        if urls:
            message = (f"mesh {urls[0]} is a URL: meshes are never fetched ({which} geometry of {urdf}); "
                       "drawing the stick model")
            result.warnings.append(message)
            warnings.warn(message, MeshWarning, stacklevel=2)
            break
        odd = [shape for body in shapes.values() for shape in body
               if not (np.all(np.isfinite(np.asarray(shape.size, dtype=float)))
                       and np.all(np.isfinite(np.asarray(shape.scale, dtype=float))) and np.all(np.isfinite(shape.T)))]
        if odd:
            message = f"a {odd[0].kind} of the {which} geometry of {urdf} has a non-finite size, scale or placement; " \
                      "drawing the stick model"
            result.warnings.append(message)
            warnings.warn(message, MeshWarning, stacklevel=2)
            break
        outside = [p for p, ref in zip(meshes, references) if not mesh_allowed(ref, p, urdf)]
        if outside:
            if not mesh_anywhere:
                message = (f"mesh file {outside[0]} lies outside the URDF's folder and its packages ({which} geometry "
                           f"of {urdf}): not read, drawing the stick model (--allow-any-mesh-path reads it)")
                result.warnings.append(message)
                warnings.warn(message, MeshWarning, stacklevel=2)
                break
            message = f"reading mesh file {outside[0]} from outside the URDF's folder, as asked"
            result.warnings.append(message)
            warnings.warn(message, MeshWarning, stacklevel=2)
        missing = [p for p in meshes if not p.is_file()]
        if missing:
            message = f"mesh file {missing[0]} not found ({which} geometry of {urdf}); drawing the stick model"
            result.warnings.append(message)
            warnings.warn(message, MeshWarning, stacklevel=2)
            break
        huge = [p for p in set(meshes) if p.stat().st_size > MAX_MESH_BYTES]
        if huge:
            message = (f"mesh file {huge[0]} is {huge[0].stat().st_size / 2**20:.0f} MiB, more than "
                       f"{MAX_MESH_BYTES // 2**20} MiB ({which} geometry of {urdf}); drawing the stick model")
            result.warnings.append(message)
            warnings.warn(message, MeshWarning, stacklevel=2)
            break
        size = sum(p.stat().st_size for p in set(meshes))
        if geometry == "auto" and which == "visual" and size > MESH_BUDGET_BYTES:
            continue  # too heavy for a light HTML file: try the collision meshes
        result.kind, result.shapes = which, shapes
        return result
    result.shapes = stick_shapes(model)
    return result


def load_mesh(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (V, 3) float32 and triangles (F, 3) uint32 of an STL, DAE or OBJ file (trimesh).

    Some mesh files carry zero or missing normals, which three.js then draws
    black; sending bare triangles lets the viewer compute its own.
    """
    import trimesh

    try:
        mesh = trimesh.load(str(path), force="mesh")
    except Exception as exc:  # trimesh raises many kinds for unreadable files
        raise ViewerError(f"mesh file {path}: cannot read: {exc}") from None
    return np.asarray(mesh.vertices, dtype=np.float32), np.asarray(mesh.faces, dtype=np.uint32)

"""Seeing the robot move: meshcat scenes, keyframe animations and offline HTML.

A scene is built once from the URDF and the :class:`~course_dynamics.model.Model`:

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

Every moving body is a meshcat node ``robot/<link>`` whose transform is ⁰T_i
from our forward kinematics. A trajectory becomes a meshcat ``Animation``
(keyframes, played by the browser), optionally with the joint torques drawn
as bars along the joint axes (length ∝ τ) and the end-effector path as a line.

:func:`export_html` writes one self-contained HTML file (the meshcat viewer
script and every mesh inlined: it opens offline); :func:`show` starts a live
meshcat server on the loopback interface, tied to this Python process.
"""
from __future__ import annotations

import base64
import os
import signal
import subprocess
import sys
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .kinematics import forward_kinematics
from .model import Model

GEOMETRIES = ("auto", "visual", "collision", "stick")
MESH_BUDGET_BYTES = 1_500_000  # auto: larger visual meshes fall back to collision meshes
DEFAULT_COLOUR = (0.65, 0.67, 0.72)
STICK_COLOUR = 0x4a6fa5
AXIS_COLOUR = 0xd08030
COM_COLOUR = 0xc0392b
TORQUE_COLOUR = 0x27ae60
PATH_COLOUR = 0x8e44ad
ANIMATION_FPS = 30


class ViewerError(ValueError):
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
            from .robots import example_robot_data_share

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
    import yourdfpy

    robot = yourdfpy.URDF.load(str(urdf), build_scene_graph=False, build_collision_scene_graph=False,
                               load_meshes=False, load_collision_meshes=False).robot
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
                shape = Shape("cylinder", T, (geometry.cylinder.radius, geometry.cylinder.length), colour=colour, opacity=opacity)
            elif geometry.sphere is not None:
                shape = Shape("sphere", T, (geometry.sphere.radius,), colour=colour, opacity=opacity)
            elif geometry.mesh is not None:
                path = resolve_mesh_path(geometry.mesh.filename, urdf)
                scale = tuple(geometry.mesh.scale) if geometry.mesh.scale is not None else (1.0, 1.0, 1.0)
                shape = Shape("mesh", T, path=path, scale=scale, colour=colour, opacity=opacity)
                meshes.append(path)
            else:
                continue
            shapes.setdefault(frame.body, []).append(shape)
    return shapes, meshes


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


def _y_along(direction: np.ndarray) -> np.ndarray:
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
        T[:3, :3] = _y_along(end - start)
    return Shape("cylinder_y", T, (radius, max(length, 1e-6)), colour=colour)


def robot_geometry(model: Model, urdf, geometry: str = "auto") -> RobotGeometry:
    """Choose and collect the shapes to draw (see the module docstring)."""
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
        missing = [p for p in meshes if not p.is_file()]
        if missing:
            message = f"mesh file {missing[0]} not found ({which} geometry of {urdf}); drawing the stick model"
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


# ---------------------------------------------------------------------------------- meshcat scene


def _meshcat_object(shape: Shape):
    import meshcat.geometry as g

    material = g.MeshPhongMaterial(color=shape.colour, opacity=shape.opacity, transparent=shape.opacity < 1)
    if shape.kind == "box":
        geometry = g.Box(shape.size)
    elif shape.kind == "sphere":
        geometry = g.Sphere(shape.size[0])
    elif shape.kind in ("cylinder", "cylinder_y"):
        geometry = g.Cylinder(shape.size[1], shape.size[0])
    else:
        vertices, faces = load_mesh(shape.path)
        geometry = g.TriangularMeshGeometry(vertices, faces)  # the browser computes smooth normals
    return g.Mesh(geometry, material)


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


def _shape_transform(shape: Shape) -> np.ndarray:
    T = shape.T.copy()
    if shape.kind == "cylinder":  # URDF cylinders run along z, meshcat's along y
        T = T @ np.array([[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]], dtype=float)
    if shape.kind == "mesh":
        T = T @ np.diag([*shape.scale, 1.0])
    return T


def body_placements(model: Model, q: np.ndarray) -> np.ndarray:
    """⁰T_i of every body for every state: shape (K, n, 4, 4) for q of shape (K, n)."""
    placements = forward_kinematics(model, np.atleast_2d(q))
    K = placements.R.shape[0]
    T = np.zeros((K, model.n, 4, 4))
    T[..., :3, :3], T[..., :3, 3], T[..., 3, 3] = placements.R, placements.P, 1.0
    return T


def draw_robot(vis, model: Model, geometry: RobotGeometry, q) -> None:
    """Put the robot's shapes into meshcat under ``robot/`` and pose it at Θ = ``q``."""
    for body, shapes in geometry.shapes.items():
        node = vis["robot"]["base" if body < 0 else model.bodies[body].name]
        for k, shape in enumerate(shapes):
            node[f"shape{k}"].set_object(_meshcat_object(shape))
            node[f"shape{k}"].set_transform(_shape_transform(shape))
    for i, T in enumerate(body_placements(model, q)[0]):
        vis["robot"][model.bodies[i].name].set_transform(T)


def tip_frame(model: Model) -> str:
    """The last URDF link carried by the last body: the end effector by default."""
    return [f.name for f in model.frames if f.body == model.n - 1][-1]


def animate(vis, model: Model, t: np.ndarray, q: np.ndarray, tau: np.ndarray | None = None,
            path_frame: str | None = None, fps: int = ANIMATION_FPS) -> None:
    """A keyframe animation of Θ(t) (and τ(t) bars, and the path of ``path_frame``)."""
    import meshcat.animation
    import meshcat.geometry as g

    t, q = np.asarray(t, float), np.asarray(q, float)
    frames = np.unique(np.round(t * fps).astype(int))
    samples = [int(np.argmin(np.abs(t * fps - f))) for f in frames]  # the sample nearest each frame
    T = body_placements(model, q[samples])
    animation = meshcat.animation.Animation(default_framerate=fps)
    reach = max(float(np.abs(body_placements(model, q[:1])[0, :, :3, 3]).max()), 0.2)
    if tau is not None:
        tau = np.asarray(tau, float)[samples]
        scale = 0.25 * reach / max(float(np.abs(tau).max()), 1e-9)
        for i, body in enumerate(model.bodies):
            vis["torques"][body.joint].set_object(g.Mesh(g.Cylinder(1.0, 0.012 * reach), g.MeshLambertMaterial(color=TORQUE_COLOUR)))
    for k, frame in enumerate(frames):
        with animation.at_frame(vis, int(frame)) as frame_vis:
            for i, body in enumerate(model.bodies):
                frame_vis["robot"][body.name].set_transform(T[k, i])
                if tau is not None:
                    frame_vis["torques"][body.joint].set_transform(_torque_bar(T[k, i], np.asarray(body.axis, float), tau[k, i] * scale))
    if path_frame is not None:
        frame = model.frame(path_frame)
        points = T[:, frame.body, :3, :3] @ frame.P + T[:, frame.body, :3, 3] if frame.body >= 0 else np.tile(frame.P, (len(T), 1))
        vis["path"].set_object(g.Line(g.PointsGeometry(points.T.astype(np.float32)), g.LineBasicMaterial(color=PATH_COLOUR)))
    vis.set_animation(animation, play=True, repetitions=0)


def _torque_bar(T_body: np.ndarray, axis: np.ndarray, length: float) -> np.ndarray:
    """A unit cylinder (along y) stretched to ``length`` along the joint axis, starting at the joint."""
    stretch = np.diag([1.0, length if abs(length) > 1e-9 else 1e-9, 1.0, 1.0])
    placement = np.eye(4)
    placement[:3, :3], placement[:3, 3] = _y_along(axis), axis * length / 2
    return T_body @ placement @ stretch


# ---------------------------------------------------------------------------------- offline HTML


class RecordingWindow:
    """Stands in for meshcat's server connection and keeps every command, in order."""

    def __init__(self):
        self.commands: list[bytes] = []

    def send(self, command) -> None:
        import umsgpack

        self.commands.append(umsgpack.packb(command.lower()))


def html_document(commands: list[bytes], title: str = "course-dynamics") -> str:
    """One HTML page with the meshcat viewer script and the scene commands inlined (opens offline)."""
    import meshcat

    script = (Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js").read_text()
    payload = ",\n".join(f'"{base64.b64encode(c).decode()}"' for c in commands)
    return f"""<!DOCTYPE html>
<html>
<head><meta charset="utf-8"><title>{title}</title>
<style>body {{ margin: 0; }} #meshcat-pane {{ width: 100vw; height: 100vh; overflow: hidden; }}</style>
</head>
<body>
<div id="meshcat-pane"></div>
<script>{script}</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
var sceneCommands = [
{payload}
];
for (const text of sceneCommands) {{
  const bytes = Uint8Array.from(atob(text), c => c.charCodeAt(0));
  viewer.handle_command_bytearray(bytes);
}}
window.sceneReady = true;
</script>
</body>
</html>
"""


def build_scene(vis, model: Model, urdf, geometry: str = "auto", t=None, q=None, tau=None, path: bool = False):
    """Draw the robot into ``vis`` and, if a trajectory is given, its animation. Returns the RobotGeometry."""
    shapes = robot_geometry(model, urdf, geometry)
    q0 = np.zeros(model.n) if q is None else np.asarray(q, float)[0]
    _place_camera(vis, model, q)
    draw_robot(vis, model, shapes, q0)
    if t is not None:
        animate(vis, model, t, q, tau=tau, path_frame=tip_frame(model) if path else None)
    return shapes


def _place_camera(vis, model: Model, q) -> None:
    """Look at the robot, as it starts, from the front right, a little above."""
    start = np.zeros((1, model.n)) if q is None else np.asarray(q, float)[:1]
    placements = body_placements(model, start)[0]
    points = np.concatenate([placements[:, :3, 3], (placements[:, :3, :3] @ np.array([b.p_com for b in model.bodies])[..., None])[..., 0] + placements[:, :3, 3]])
    reach = max(float(np.linalg.norm(points, axis=1).max()), 0.3)
    x, y, z = 1.6 * reach, -2.0 * reach, 1.2 * reach  # world, z up
    vis["/Cameras/default/rotated/<object>"].set_property("position", [x, z, -y])  # three.js is y up


def scene_document(model: Model, urdf, geometry: str = "auto", t=None, q=None, tau=None,
                   trace_path: bool = False) -> tuple[str, RobotGeometry]:
    """The scene (and animation) recorded into one self-contained HTML page, with the geometry drawn."""
    import meshcat

    window = RecordingWindow()
    shapes = build_scene(meshcat.Visualizer(window=window), model, urdf, geometry, t, q, tau, trace_path)
    return html_document(window.commands, title=f"{model.name} — course-dynamics"), shapes


def export_html(path, model: Model, urdf, geometry: str = "auto", t=None, q=None, tau=None, trace_path: bool = False) -> RobotGeometry:
    """Write a self-contained HTML file of the robot (and its animation); whole or not at all."""
    path = Path(path)
    directory = path.parent if str(path.parent) else Path(".")
    if not directory.is_dir():
        raise ViewerError(f"{path}: directory {directory} does not exist")
    document, shapes = scene_document(model, urdf, geometry, t, q, tau, trace_path)
    temporary = path.with_name(f".{path.name}.partial")
    try:
        temporary.write_text(document)
        os.replace(temporary, path)
    except OSError as exc:
        temporary.unlink(missing_ok=True)
        raise ViewerError(f"{path}: cannot write: {exc.strerror}") from None
    return shapes


# ---------------------------------------------------------------------------------- live viewer


@dataclass
class LiveViewer:
    """A meshcat server of ours (loopback only, dies with this process) and a Visualizer on it."""

    vis: object
    process: subprocess.Popen
    url: str

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.process.kill()

    def _repr_html_(self) -> str:
        return f'<iframe src="{self.url}" style="width: 100%; height: 420px; border: none"></iframe>'


def _die_with_parent() -> None:  # pragma: no cover - runs in the child before exec
    """Linux: the server gets SIGTERM when the Python process that started it dies, even by SIGKILL."""
    try:
        import ctypes

        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
    except OSError:
        pass


def start_server(timeout: float = 20.0) -> LiveViewer:
    """Start meshcat's server on 127.0.0.1 (web and ZeroMQ), tied to this process, and connect a Visualizer.

    The server is a child process that receives SIGTERM when this Python
    process dies, even by SIGKILL (Linux ``PR_SET_PDEATHSIG``), and is
    terminated at normal exit; :meth:`LiveViewer.close` stops it at once.
    """
    import atexit
    import re
    import time

    import meshcat

    process = subprocess.Popen(
        [sys.executable, "-u", "-m", "course_dynamics.meshcat_server"],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, preexec_fn=_die_with_parent,
    )
    atexit.register(lambda: process.poll() is None and process.terminate())
    zmq_url = web_url = None
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and (zmq_url is None or web_url is None):
        line = process.stdout.readline()
        if not line:
            break
        zmq_url = zmq_url or (re.search(r"zmq_url=(\S+)", line) or [None, None])[1]
        web_url = web_url or (re.search(r"web_url=(\S+)", line) or [None, None])[1]
    if zmq_url is None or web_url is None:
        process.kill()
        raise ViewerError("the meshcat server did not start")
    return LiveViewer(vis=meshcat.Visualizer(zmq_url=zmq_url), process=process, url=web_url)


def show(model: Model, urdf, geometry: str = "auto", t=None, q=None, tau=None, path: bool = False,
         static: bool = False):
    """Show the robot in a notebook cell: live meshcat viewer, or with ``static=True`` an embedded offline animation.

    Returns an object that Jupyter displays (the live viewer's page in an
    iframe, or the self-contained HTML in an ``srcdoc`` iframe). The live
    viewer keeps a server process; ``.close()`` stops it, and it also stops
    when Python exits.
    """
    if static:
        import html

        document, _ = scene_document(model, urdf, geometry, t, q, tau, path)
        return _StaticHTML(f'<iframe srcdoc="{html.escape(document)}" style="width: 100%; height: 420px; border: none"></iframe>')
    viewer = start_server()
    build_scene(viewer.vis, model, urdf, geometry, t, q, tau, path)
    return viewer


@dataclass
class _StaticHTML:
    markup: str

    def _repr_html_(self) -> str:
        return self.markup

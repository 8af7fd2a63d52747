"""The meshcat scene: the robot's shapes as nodes, posed by forward kinematics, and keyframe animations.

Every moving body is a meshcat node ``robot/<link>`` whose transform is ⁰T_i
from our forward kinematics. A trajectory becomes a meshcat ``Animation``
(keyframes, played by the browser), optionally with the joint torques drawn
as bars along the joint axes (length ∝ τ) and the path of the tip frame as a
line.
"""
from __future__ import annotations

import numpy as np

from ...core.kinematics import forward_kinematics
from ...core.model import Model
from .geometry import (
    ANIMATION_FPS,
    PATH_COLOUR,
    TORQUE_COLOUR,
    RobotGeometry,
    Shape,
    load_mesh,
    robot_geometry,
    y_along,
)


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


def _shape_transform(shape: Shape) -> np.ndarray:
    T = shape.T.copy()
    if shape.kind == "cylinder":  # URDF cylinders run along z, meshcat's along y
        T = T @ np.array([[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]], dtype=float)
    if shape.kind == "mesh":
        T = T @ np.diag([*shape.scale, 1.0])
    return T


def body_placements(model: Model, q: np.ndarray) -> np.ndarray:
    """⁰T_i of every body for every state: shape (K, n, 4, 4) for q of shape (K, n).

    Parameters
    ----------
    model : Model
        The robot.
    q : numpy.ndarray, shape (n,) or (K, n)
        Joint positions Θ, rad (m for a prismatic joint); one state counts as K = 1.

    Returns
    -------
    numpy.ndarray, shape (K, n, 4, 4)
        The homogeneous transform ⁰T_i of body i in the base frame, m.

    Raises
    ------
    StateError
        If ``q`` is not a finite array of shape (n,) or (K, n).
    """
    placements = forward_kinematics(model, np.atleast_2d(q))
    K = placements.R.shape[0]
    T = np.zeros((K, model.n_bodies, 4, 4))
    T[..., :3, :3], T[..., :3, 3], T[..., 3, 3] = placements.R, placements.P, 1.0
    return T


def draw_robot(vis, model: Model, geometry: RobotGeometry, q) -> None:
    """Put the robot's shapes into meshcat under ``robot/`` and pose it at Θ = ``q``.

    Parameters
    ----------
    vis : meshcat.Visualizer
        The scene to draw into.
    model : Model
        The robot.
    geometry : RobotGeometry
        What to draw (:func:`~course_dynamics.output.viewer.geometry.robot_geometry`).
    q : array_like, shape (n,)
        Joint positions Θ, rad (m for a prismatic joint).

    Raises
    ------
    ViewerError
        If a mesh file cannot be read or holds too much geometry.
    StateError
        If ``q`` is not a finite array of shape (n,).
    """
    for body, shapes in geometry.shapes.items():
        node = vis["robot"]["base" if body < 0 else model.bodies[body].name]
        for k, shape in enumerate(shapes):
            node[f"shape{k}"].set_object(_meshcat_object(shape))
            node[f"shape{k}"].set_transform(_shape_transform(shape))
    for i, T in enumerate(body_placements(model, q)[0]):
        vis["robot"][model.bodies[i].name].set_transform(T)


def tip_frame(model: Model) -> str:
    """The last URDF link carried by the last body: the end effector by default.

    Parameters
    ----------
    model : Model
        The robot.

    Returns
    -------
    str
        The link's name.
    """
    return [f.name for f in model.frames if f.body == model.n_bodies - 1][-1]


def animate(vis, model: Model, t: np.ndarray, q: np.ndarray, tau: np.ndarray | None = None,
            path_frame: str | None = None, fps: int = ANIMATION_FPS) -> None:
    """A keyframe animation of Θ(t) (and τ(t) bars, and the path of ``path_frame``).

    Each frame shows the sample nearest its time; the animation plays in a loop.

    Parameters
    ----------
    vis : meshcat.Visualizer
        The scene, with the robot drawn (:func:`draw_robot`).
    model : Model
        The robot.
    t : numpy.ndarray, shape (T,)
        Sample times, s.
    q : numpy.ndarray, shape (T, n)
        Joint positions Θ at those times, rad (m for a prismatic joint).
    tau : numpy.ndarray, shape (T, n), optional
        Joint torques τ, N·m (N), drawn as bars along the joint axes, their length ∝ τ.
    path_frame : str, optional
        A URDF link whose path is drawn as a line.
    fps : int, optional
        Frames per second, Hz.

    Raises
    ------
    ModelError
        If ``path_frame`` is not a link of the robot.
    StateError
        If ``q`` is not a finite array of shape (T, n).
    """
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
            vis["torques"][body.joint].set_object(g.Mesh(g.Cylinder(1.0, 0.012 * reach),
                                                         g.MeshLambertMaterial(color=TORQUE_COLOUR)))
    for k, frame in enumerate(frames):
        with animation.at_frame(vis, int(frame)) as frame_vis:
            for i, body in enumerate(model.bodies):
                frame_vis["robot"][body.name].set_transform(T[k, i])
                if tau is not None:
                    frame_vis["torques"][body.joint].set_transform(
                        _torque_bar(T[k, i], np.asarray(body.axis, float), tau[k, i] * scale))
    if path_frame is not None:
        frame = model.frame(path_frame)
        points = (T[:, frame.body, :3, :3] @ frame.P + T[:, frame.body, :3, 3] if frame.body >= 0
                  else np.tile(frame.P, (len(T), 1)))
        vis["path"].set_object(g.Line(g.PointsGeometry(points.T.astype(np.float32)),
                                      g.LineBasicMaterial(color=PATH_COLOUR)))
    vis.set_animation(animation, play=True, repetitions=0)


def _torque_bar(T_body: np.ndarray, axis: np.ndarray, length: float) -> np.ndarray:
    """A unit cylinder (along y) stretched to ``length`` along the joint axis, starting at the joint."""
    stretch = np.diag([1.0, length if abs(length) > 1e-9 else 1e-9, 1.0, 1.0])
    placement = np.eye(4)
    placement[:3, :3], placement[:3, 3] = y_along(axis), axis * length / 2
    return T_body @ placement @ stretch


def build_scene(vis, model: Model, urdf, geometry: str = "auto", t=None, q=None, tau=None,
                draw_path: bool = False, mesh_anywhere: bool = False) -> RobotGeometry:
    """Draw the robot into ``vis`` and, if a trajectory is given, its animation (and the tip's path if ``draw_path``).

    ``mesh_anywhere``: read mesh files outside the URDF's folder and package (see
    :func:`~course_dynamics.output.viewer.geometry.robot_geometry`).

    Parameters
    ----------
    vis : meshcat.Visualizer
        The scene to draw into.
    model : Model
        The robot, loaded from ``urdf``.
    urdf : str or pathlib.Path
        Its URDF file.
    geometry : str, optional
        What to draw: one of :data:`~course_dynamics.output.viewer.geometry.GEOMETRIES`.
    t : numpy.ndarray, shape (T,), optional
        Sample times of a trajectory, s; none draws the robot still.
    q : numpy.ndarray, shape (T, n), optional
        Joint positions Θ at those times, rad (m for a prismatic joint); the first is the pose drawn (zero
        without ``q``).
    tau : numpy.ndarray, shape (T, n), optional
        Joint torques τ, N·m (N), drawn as bars along the joint axes.
    draw_path : bool, optional
        Draw the path of the tip frame (:func:`tip_frame`).
    mesh_anywhere : bool, optional
        Read mesh files outside the URDF's folder and its packages too.

    Returns
    -------
    RobotGeometry
        What was drawn, with the warnings given.

    Raises
    ------
    ViewerError
        If ``geometry`` is unknown or a mesh file cannot be read.
    StateError
        If ``q`` is not a finite array of shape (T, n).
    """
    shapes = robot_geometry(model, urdf, geometry, mesh_anywhere=mesh_anywhere)
    q0 = np.zeros(model.n) if q is None else np.asarray(q, float)[0]
    _place_camera(vis, model, q)
    draw_robot(vis, model, shapes, q0)
    if t is not None:
        animate(vis, model, t, q, tau=tau, path_frame=tip_frame(model) if draw_path else None)
    return shapes


def _place_camera(vis, model: Model, q) -> None:
    """Look at the robot, as it starts, from the front right, a little above."""
    start = np.zeros((1, model.n)) if q is None else np.asarray(q, float)[:1]
    placements = body_placements(model, start)[0]
    points = np.concatenate([
        placements[:, :3, 3],
        (placements[:, :3, :3] @ np.array([b.p_com for b in model.bodies])[..., None])[..., 0] + placements[:, :3, 3]])
    reach = max(float(np.linalg.norm(points, axis=1).max()), 0.3)
    x, y, z = 1.6 * reach, -2.0 * reach, 1.2 * reach  # world, z up
    vis["/Cameras/default/rotated/<object>"].set_property("position", [x, z, -y])  # three.js is y up


__all__ = ["animate", "body_placements", "build_scene", "draw_robot", "tip_frame"]

"""Offline HTML: the scene recorded into one self-contained page (viewer script and meshes inlined)."""
from __future__ import annotations

import base64
from pathlib import Path

from ...core.model import Model
from .. import io, page
from .geometry import RobotGeometry
from .scene import build_scene


class RecordingWindow:
    """Stands in for meshcat's server connection and keeps every command, in order.

    Given to ``meshcat.Visualizer(window=...)``; :func:`html_document` then replays ``commands`` in the page.

    Attributes
    ----------
    commands : list of bytes
        Every command sent, msgpack-encoded, in order.
    """

    def __init__(self):
        self.commands: list[bytes] = []

    def send(self, command) -> None:
        """Keep one command (what meshcat's server connection would send to the browser).

        Parameters
        ----------
        command : object
            A meshcat command (``SetObject``, ``SetTransform``, ``SetAnimation``, …).
        """
        import umsgpack

        self.commands.append(umsgpack.packb(command.lower()))


BOOT = """var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
var sceneCommands = [
%s
];
for (const text of sceneCommands) {
  const bytes = Uint8Array.from(atob(text), c => c.charCodeAt(0));
  viewer.handle_command_bytearray(bytes);
}
window.sceneReady = true;
"""


def html_document(commands: list[bytes], title: str = "course-dynamics") -> str:
    """One HTML page with the meshcat viewer script and the scene commands inlined (opens offline).

    Parameters
    ----------
    commands : list of bytes
        The scene's commands, msgpack-encoded (``RecordingWindow.commands``).
    title : str, optional
        The page's title.

    Returns
    -------
    str
        The page: self-contained, with nothing fetched when it opens.
    """
    import meshcat

    script = (Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js").read_text()
    payload = ",\n".join(f'"{base64.b64encode(c).decode()}"' for c in commands)
    return page.page(title, page.element("div", id="meshcat-pane"), scripts=[script, BOOT % payload],
                     body_class="viewer")


def scene_document(model: Model, urdf, geometry: str = "auto", t=None, q=None, tau=None,
                   draw_path: bool = False, mesh_anywhere: bool = False) -> tuple[str, RobotGeometry]:
    """The scene (and animation) recorded into one self-contained HTML page, with the geometry drawn.

    Parameters
    ----------
    model : Model
        The robot, loaded from ``urdf``.
    urdf : str or pathlib.Path
        Its URDF file.
    geometry : str, optional
        What to draw: one of :data:`~course_dynamics.output.viewer.geometry.GEOMETRIES`.
    t : numpy.ndarray, shape (T,), optional
        Sample times of a trajectory, s; none draws the robot still.
    q : numpy.ndarray, shape (T, n), optional
        Joint positions Θ at those times, rad (m for a prismatic joint).
    tau : numpy.ndarray, shape (T, n), optional
        Joint torques τ, N·m (N), drawn as bars along the joint axes.
    draw_path : bool, optional
        Draw the path of the tip frame (:func:`~course_dynamics.output.viewer.scene.tip_frame`).
    mesh_anywhere : bool, optional
        Read mesh files outside the URDF's folder and its packages too.

    Returns
    -------
    document : str
        The HTML page.
    geometry : RobotGeometry
        What was drawn, with the warnings given.

    Raises
    ------
    ViewerError
        If ``geometry`` is unknown or a mesh file cannot be read.
    StateError
        If ``q`` is not a finite array of shape (T, n).
    """
    import meshcat

    window = RecordingWindow()
    shapes = build_scene(meshcat.Visualizer(window=window), model, urdf, geometry, t, q, tau, draw_path, mesh_anywhere)
    return html_document(window.commands, title=f"{model.name} — course-dynamics"), shapes


def export_html(path, model: Model, urdf, geometry: str = "auto", t=None, q=None, tau=None,
                draw_path: bool = False, mesh_anywhere: bool = False) -> RobotGeometry:
    """Write a self-contained HTML file of the robot (and its animation) to ``path``, whole or not at all.

    Parameters
    ----------
    path : str or pathlib.Path
        The HTML file to write, or ``-`` for standard output.
    model : Model
        The robot, loaded from ``urdf``.
    urdf : str or pathlib.Path
        Its URDF file.
    geometry : str, optional
        What to draw: one of :data:`~course_dynamics.output.viewer.geometry.GEOMETRIES`.
    t : numpy.ndarray, shape (T,), optional
        Sample times of a trajectory, s; none draws the robot still.
    q : numpy.ndarray, shape (T, n), optional
        Joint positions Θ at those times, rad (m for a prismatic joint).
    tau : numpy.ndarray, shape (T, n), optional
        Joint torques τ, N·m (N), drawn as bars along the joint axes.
    draw_path : bool, optional
        Draw the path of the tip frame (:func:`~course_dynamics.output.viewer.scene.tip_frame`).
    mesh_anywhere : bool, optional
        Read mesh files outside the URDF's folder and its packages too.

    Returns
    -------
    RobotGeometry
        What was drawn, with the warnings given.

    Raises
    ------
    InputError
        If ``path`` cannot be written (checked before the scene is made).
    ViewerError
        If ``geometry`` is unknown or a mesh file cannot be read.
    StateError
        If ``q`` is not a finite array of shape (T, n).
    """
    io.check_writable(path)
    document, shapes = scene_document(model, urdf, geometry, t, q, tau, draw_path, mesh_anywhere)
    io.write_text(path, document)
    return shapes


__all__ = ["RecordingWindow", "export_html", "html_document", "scene_document"]

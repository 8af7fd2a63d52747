"""Offline HTML: the scene recorded into one self-contained page (viewer script and meshes inlined)."""
from __future__ import annotations

import base64
from pathlib import Path

from ...core.model import Model
from .. import io, page
from .geometry import RobotGeometry
from .scene import build_scene


class RecordingWindow:
    """Stands in for meshcat's server connection and keeps every command, in order."""

    def __init__(self):
        self.commands: list[bytes] = []

    def send(self, command) -> None:
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
    """One HTML page with the meshcat viewer script and the scene commands inlined (opens offline)."""
    import meshcat

    script = (Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js").read_text()
    payload = ",\n".join(f'"{base64.b64encode(c).decode()}"' for c in commands)
    return page.page(title, page.element("div", id="meshcat-pane"), scripts=[script, BOOT % payload],
                     body_class="viewer")


def scene_document(model: Model, urdf, geometry: str = "auto", t=None, q=None, tau=None,
                   draw_path: bool = False, mesh_anywhere: bool = False) -> tuple[str, RobotGeometry]:
    """The scene (and animation) recorded into one self-contained HTML page, with the geometry drawn."""
    import meshcat

    window = RecordingWindow()
    shapes = build_scene(meshcat.Visualizer(window=window), model, urdf, geometry, t, q, tau, draw_path, mesh_anywhere)
    return html_document(window.commands, title=f"{model.name} — course-dynamics"), shapes


def export_html(path, model: Model, urdf, geometry: str = "auto", t=None, q=None, tau=None,
                draw_path: bool = False, mesh_anywhere: bool = False) -> RobotGeometry:
    """Write a self-contained HTML file of the robot (and its animation) to ``path``, whole or not at all."""
    io.check_writable(path)
    document, shapes = scene_document(model, urdf, geometry, t, q, tau, draw_path, mesh_anywhere)
    io.write_text(path, document)
    return shapes

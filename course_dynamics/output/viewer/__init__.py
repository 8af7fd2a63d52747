"""Seeing the robot move: meshcat scenes, keyframe animations and offline HTML.

==================  ===============================================================
module              job
==================  ===============================================================
``geometry``        what to draw: URDF visual/collision shapes or a stick model
``scene``           the meshcat scene: nodes posed by forward kinematics, animations
``export``          one self-contained offline HTML page
                    (:func:`~course_dynamics.output.viewer.export.export_html`)
``live``            a live meshcat server on 127.0.0.1 tied to this process
                    (:func:`~course_dynamics.output.viewer.live.show`)
``meshcat_server``  meshcat's server with its web page pinned to the loopback interface
``mesh_limits``     how much geometry a mesh file expands to, counted before trimesh reads it
==================  ===============================================================
"""
from . import geometry
from .export import RecordingWindow, export_html, html_document, scene_document
from .geometry import (
    MeshWarning,
    RobotGeometry,
    ViewerError,
    resolve_mesh_path,
    robot_geometry,
)
from .live import LiveViewer, show, start_server
from .scene import animate, body_placements, build_scene, draw_robot, tip_frame

#: The choices of ``geometry`` (:data:`~course_dynamics.output.viewer.geometry.GEOMETRIES`).
GEOMETRIES = geometry.GEOMETRIES

__all__ = [
    "GEOMETRIES", "LiveViewer", "MeshWarning", "RecordingWindow", "RobotGeometry", "ViewerError", "animate",
    "body_placements", "build_scene", "draw_robot", "export_html", "html_document", "resolve_mesh_path",
    "robot_geometry", "scene_document", "show", "start_server", "tip_frame",
]

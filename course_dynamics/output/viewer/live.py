"""The live viewer: a meshcat server of ours on the loopback interface, tied to this Python process."""
from __future__ import annotations

import signal
import subprocess
import sys
from dataclasses import dataclass

from ...core.model import Model
from .export import scene_document
from .geometry import ViewerError
from .scene import build_scene


@dataclass
class LiveViewer:
    """A meshcat server of ours (loopback only, dies with this process) and a Visualizer on it.

    Jupyter shows it as the viewer's page in an iframe.

    Parameters
    ----------
    vis : meshcat.Visualizer
        The scene, connected to the server.
    process : subprocess.Popen
        The server's process (:mod:`~course_dynamics.output.viewer.meshcat_server`).
    url : str
        The viewer's web page, on 127.0.0.1.
    """

    vis: object
    process: subprocess.Popen
    url: str

    def close(self) -> None:
        """Stop the server: terminated, and killed if it has not ended within 5 s."""
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

    Parameters
    ----------
    timeout : float, optional
        The most time to wait for the server to say where it listens, s.

    Returns
    -------
    LiveViewer
        The server, its web page's address and a Visualizer connected to it.

    Raises
    ------
    ViewerError
        If the server did not start (or said nothing) within ``timeout``.
    """
    import atexit
    import re
    import time

    import meshcat

    process = subprocess.Popen(
        [sys.executable, "-u", "-m", "course_dynamics.output.viewer.meshcat_server"],
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


def show(model: Model, urdf, geometry: str = "auto", t=None, q=None, tau=None, draw_path: bool = False,
         static: bool = False, mesh_anywhere: bool = False):
    """Show the robot in a notebook cell: live meshcat viewer, or with ``static=True`` an embedded offline animation.

    Returns an object that Jupyter displays (the live viewer's page in an
    iframe, or the self-contained HTML in an ``srcdoc`` iframe). The live
    viewer keeps a server process; ``.close()`` stops it, and it also stops
    when Python exits.

    Parameters
    ----------
    model : Model
        The robot, loaded from ``urdf``.
    urdf : str or pathlib.Path
        Its URDF file.
    geometry : str, optional
        What to draw: one of :data:`~course_dynamics.output.viewer.geometry.GEOMETRIES`.
    t : numpy.ndarray, shape (T,), optional
        Sample times of a trajectory, s; none shows the robot still.
    q : numpy.ndarray, shape (T, n), optional
        Joint positions Θ at those times, rad (m for a prismatic joint).
    tau : numpy.ndarray, shape (T, n), optional
        Joint torques τ, N·m (N), drawn as bars along the joint axes.
    draw_path : bool, optional
        Draw the path of the tip frame (:func:`~course_dynamics.output.viewer.scene.tip_frame`).
    static : bool, optional
        Embed an offline animation instead of starting a live server.
    mesh_anywhere : bool, optional
        Read mesh files outside the URDF's folder and its packages too.

    Returns
    -------
    LiveViewer or object
        The live viewer; with ``static=True`` an object Jupyter displays as the offline page.

    Raises
    ------
    ViewerError
        If ``geometry`` is unknown, a mesh file cannot be read, or the live server did not start.
    StateError
        If ``q`` is not a finite array of shape (T, n).
    """
    if static:
        import html

        document, _ = scene_document(model, urdf, geometry, t, q, tau, draw_path, mesh_anywhere)
        return _StaticHTML(f'<iframe srcdoc="{html.escape(document)}" '
                           'style="width: 100%; height: 420px; border: none"></iframe>')
    viewer = start_server()
    build_scene(viewer.vis, model, urdf, geometry, t, q, tau, draw_path)
    return viewer


@dataclass
class _StaticHTML:
    markup: str

    def _repr_html_(self) -> str:
        return self.markup


__all__ = ["LiveViewer", "show", "start_server"]

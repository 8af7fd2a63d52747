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

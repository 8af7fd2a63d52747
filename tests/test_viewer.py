"""course_dynamics/viewer: scenes, offline HTML, and the animation checked in a real browser.

The browser is Debian's Chromium driven by Playwright (``executable_path=/usr/bin/chromium``;
``playwright install`` is never used). The README's test command installs Chromium when it is
missing; here a missing browser is a failure, not a skip.
"""
from __future__ import annotations

import io
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from course_dynamics import load_robot, load_urdf, robot_path
from course_dynamics.cli import main
from course_dynamics.viewer import MeshWarning, RecordingWindow, export_html, resolve_mesh_path, robot_geometry, show

ROOT = Path(__file__).resolve().parent.parent


def wave(model, seconds=3.0, step=0.02):
    """A smooth joint-space motion: t (K,), q (K, n)."""
    t = np.arange(0, seconds + 1e-9, step)
    return t, 0.3 + 0.8 * np.sin(np.outer(t, np.linspace(1.0, 2.0, model.n)))


# ---------------------------------------------------------------- geometry choices


def test_auto_geometry_picks_light_meshes_or_sticks():
    assert robot_geometry(load_robot("ur5"), robot_path("ur5")).kind == "collision"  # visual DAE: 6 MB
    assert robot_geometry(load_robot("double_pendulum"), robot_path("double_pendulum")).kind == "visual"
    assert robot_geometry(load_robot("two_link"), robot_path("two_link")).kind == "stick"  # no <visual>
    sticks = robot_geometry(load_robot("panda"), robot_path("panda"), "stick")
    assert sticks.kind == "stick" and len(sticks.shapes) >= 9


def test_package_paths_resolve():
    path = resolve_mesh_path("package://example-robot-data/robots/ur_description/meshes/ur5/collision/base.stl", robot_path("ur5"))
    assert path.is_file()
    assert resolve_mesh_path("meshes/a.stl", Path("/x/robot.urdf")) == Path("/x/meshes/a.stl")


@pytest.fixture()
def robot_with_missing_mesh(tmp_path):
    text = robot_path("double_pendulum").read_text().replace("meshes/link2.stl", "meshes/no_such_link.stl", 1)
    path = tmp_path / "broken.urdf"
    path.write_text(text)
    return path


def test_missing_mesh_falls_back_to_sticks_with_a_warning(robot_with_missing_mesh):
    model = load_urdf(robot_with_missing_mesh)
    with pytest.warns(MeshWarning, match="mesh file .*no_such_link.stl not found"):
        geometry = robot_geometry(model, robot_with_missing_mesh, "visual")
    assert geometry.kind == "stick"


def test_export_is_whole_and_offline(tmp_path):
    model = load_robot("ur5")
    t, q = wave(model)
    out = tmp_path / "ur5.html"
    export_html(out, model, robot_path("ur5"), t=t, q=q, tau=np.cos(q), draw_path=True)
    text = out.read_text()
    assert out.stat().st_size < 3_000_000
    assert "<script src=" not in text and "<link " not in text  # nothing to fetch
    assert list(tmp_path.iterdir()) == [out]


def test_recording_window_keeps_commands_in_order():
    import meshcat
    import meshcat.geometry as g

    window = RecordingWindow()
    vis = meshcat.Visualizer(window=window)
    vis["a"].set_object(g.Box([1, 1, 1]))
    vis["a"].set_transform(np.eye(4))
    assert len(window.commands) == 2 and b"set_object" in window.commands[0]


def test_static_notebook_embed():
    embed = show(load_robot("pendulum"), robot_path("pendulum"), static=True)
    assert embed._repr_html_().startswith('<iframe srcdoc="')


# ---------------------------------------------------------------- live server: loopback only, dies with its parent


def listening_addresses(port: int) -> set[str]:
    addresses = set()
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        for line in Path(table).read_text().splitlines()[1:]:
            local, state = line.split()[1], line.split()[3]
            host, hex_port = local.rsplit(":", 1)
            if state == "0A" and int(hex_port, 16) == port:
                addresses.add(host)
    return addresses


def test_live_server_listens_on_loopback_and_closes():
    viewer = show(load_robot("two_link"), robot_path("two_link"))
    try:
        assert viewer.url.startswith("http://127.0.0.1:")
        port = int(viewer.url.split(":")[2].split("/")[0])
        assert listening_addresses(port) == {"0100007F"}  # 127.0.0.1, not 0.0.0.0
    finally:
        viewer.close()
    assert viewer.process.poll() is not None


def test_live_server_dies_with_a_killed_python():
    script = ("from course_dynamics import load_robot, robot_path\n"
              "from course_dynamics.viewer import show\n"
              "v = show(load_robot('pendulum'), robot_path('pendulum'))\n"
              "print('PID', v.process.pid, flush=True)\n"
              "import time; time.sleep(60)\n")
    parent = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    line = parent.stdout.readline()
    while not line.startswith("PID"):  # meshcat prints its URL first
        line = parent.stdout.readline()
    server_pid = int(line.split()[1])
    parent.send_signal(signal.SIGKILL)
    parent.wait()
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and Path(f"/proc/{server_pid}").exists():
        state = Path(f"/proc/{server_pid}/stat").read_text().split()[2] if Path(f"/proc/{server_pid}/stat").exists() else "X"
        if state == "Z":
            break
        time.sleep(0.1)
    alive = Path(f"/proc/{server_pid}/stat").exists() and Path(f"/proc/{server_pid}/stat").read_text().split()[2] != "Z"
    if alive:
        os.kill(server_pid, signal.SIGKILL)
    assert not alive, "the meshcat server outlived its killed parent"


# ---------------------------------------------------------------- a real browser


def screenshot(page) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(page.screenshot())).convert("RGB"), dtype=np.int16)


def open_scene(browser, html: Path, bodies):
    page = browser.new_page(viewport={"width": 800, "height": 600})
    requests = []
    page.on("request", lambda request: requests.append(request.url))
    page.goto(html.as_uri())
    page.wait_for_function("window.sceneReady === true", timeout=60_000)
    names = ",".join(f'"{b}"' for b in bodies)
    page.wait_for_function(
        f"[{names}].every(b => Object.keys(viewer.scene_tree.find(['meshcat', 'robot', b]).children).length > 0)", timeout=60_000)
    return page, requests


def at_time(page, seconds: float) -> np.ndarray:
    page.evaluate(f"viewer.animator.pause(); viewer.animator.seek({seconds}); viewer.render();")
    page.wait_for_timeout(200)
    return screenshot(page)


def changed_pixels(a: np.ndarray, b: np.ndarray) -> int:
    return int((np.abs(a - b).sum(axis=-1) > 40).sum())


@pytest.mark.parametrize("name", ["ur5", "two_link"])
def test_animation_plays_in_chromium(browser, tmp_path, name):
    """The exported file draws the robot, and the pose at 0.5 s differs from the pose at 2.5 s."""
    model = load_robot(name)
    t, q = wave(model)
    html = tmp_path / f"{name}.html"
    export_html(html, model, robot_path(name), t=t, q=q)
    page, requests = open_scene(browser, html, [b.name for b in model.bodies])
    assert page.evaluate("viewer.animator.actions.length") > 0
    early, late = at_time(page, 0.5), at_time(page, 2.5)
    page.evaluate("viewer.scene_tree.find(['meshcat', 'robot']).object.visible = false; viewer.render();")
    empty = screenshot(page)
    assert changed_pixels(early, empty) > 300, "the robot is not drawn at t = 0.5 s"
    assert changed_pixels(late, empty) > 300, "the robot is not drawn at t = 2.5 s"
    assert changed_pixels(early, late) > 300, "the pose did not change between 0.5 s and 2.5 s"
    assert all(url.startswith(("file:", "data:", "blob:")) for url in requests), requests  # offline
    page.close()


def test_cli_animate_and_screenshot_for_the_docs(browser, tmp_path, capsys):
    """`animate` end to end on the README example; the screenshot is what docs/animation.png shows."""
    html = tmp_path / "ur5.html"
    code = main(["animate", "ur5", "--trajectory", str(ROOT / "examples" / "ur5_wave.csv"), "--html", str(html),
                 "--torques", "--path"])
    assert code == 0
    page, _ = open_scene(browser, html, [b.name for b in load_robot("ur5").bodies])
    picture = at_time(page, 1.5)
    assert picture.std() > 10
    page.screenshot(path=str(tmp_path / "animation.png"))
    page.close()


# ---------------------------------------------------------------- CLI bad input


def run_cli(capsys, *argv):
    code = main(list(argv))
    return code, capsys.readouterr().err


def test_trajectory_for_another_robot(capsys, tmp_path):
    html = tmp_path / "out.html"
    code, err = run_cli(capsys, "animate", "ur5", "--trajectory", str(ROOT / "examples" / "two_link_trajectory.csv"), "--html", str(html))
    assert code == 2 and err.startswith("error: ") and "missing columns: q_shoulder_pan_joint" in err
    assert not html.exists()


def test_unwritable_html(capsys, tmp_path):
    code, err = run_cli(capsys, "animate", "two_link", "--trajectory", str(ROOT / "examples" / "two_link_trajectory.csv"),
                        "--html", str(tmp_path / "nowhere" / "out.html"))
    assert code == 2 and "does not exist" in err and err.count("\n") == 1


def test_missing_mesh_through_cli(capsys, tmp_path, robot_with_missing_mesh):
    trajectory = tmp_path / "traj.csv"
    trajectory.write_text("t,q_joint1,q_joint2\n0,0,0\n1,0.5,0.2\n")
    html = tmp_path / "out.html"
    code, err = run_cli(capsys, "animate", str(robot_with_missing_mesh), "--trajectory", str(trajectory), "--html", str(html),
                        "--geometry", "visual")
    assert code == 0 and html.exists()
    assert "warning: mesh file" in err and "no_such_link.stl not found" in err


def test_torques_need_data(capsys, tmp_path):
    trajectory = tmp_path / "traj.csv"
    trajectory.write_text("t,q_theta1,q_theta2\n0,0,0\n1,0.5,0.2\n")
    code, err = run_cli(capsys, "animate", "two_link", "--trajectory", str(trajectory), "--html", str(tmp_path / "o.html"), "--torques")
    assert code == 2 and "--torques needs tau_<joint> columns" in err

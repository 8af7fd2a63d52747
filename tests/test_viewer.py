"""course_dynamics/viewer: scenes, offline HTML, and the animation checked in a real browser.

The browser is Debian's Chromium driven by Playwright (``executable_path=/usr/bin/chromium``;
``playwright install`` is never used). The README's test command installs Chromium when it is
missing; here a missing browser is a failure, not a skip.
"""
from __future__ import annotations

import base64
import html
import io
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from course_dynamics import load_robot, load_urdf, robot_path
from course_dynamics.cli import main
from course_dynamics.output.viewer import (
    MeshWarning,
    RecordingWindow,
    ViewerError,
    export_html,
    mesh_limits,
    resolve_mesh_path,
    robot_geometry,
    show,
)
from course_dynamics.output.viewer import geometry as geometry_module
from course_dynamics.output.viewer.geometry import load_mesh

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


# ---------------------------------------------------------------- which mesh files may be read

SECRET = 1234.5  # a coordinate no real mesh has: finding it in an HTML file means the secret mesh leaked


def stl_bytes(triangles: int = 1, coordinate: float = 1.0, claimed: int | None = None) -> bytes:
    """A binary STL of ``triangles`` triangles (header count ``claimed``, default the truth)."""
    corner = np.array([[0, 0, 1], [coordinate, 0, 0], [0, coordinate, 0], [0, 0, coordinate]], dtype="<f4")
    facet = corner.tobytes() + b"\0\0"
    count = triangles if claimed is None else claimed
    return b"binary STL".ljust(80, b" ") + count.to_bytes(4, "little") + facet * triangles


def robot_with_meshes(urdf: Path, filename: str) -> Path:
    """The double pendulum's URDF written to ``urdf``, every mesh (visual and collision) replaced by ``filename``."""
    text = robot_path("double_pendulum").read_text()
    urdf.parent.mkdir(parents=True, exist_ok=True)
    urdf.write_text(re.sub(r'filename="[^"]*"', lambda _: f'filename="{html.escape(filename)}"', text))
    return urdf


@pytest.fixture()
def workspace(tmp_path, monkeypatch):
    """A ROS-like tree: ws/pkg is a package (package.xml) with urdf/robot.urdf to come and
    meshes/link.stl; ws/secret/secret.stl is a mesh no URDF of pkg may read."""
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    ws = tmp_path / "ws"
    (ws / "pkg" / "meshes").mkdir(parents=True)
    (ws / "pkg" / "package.xml").write_text("<package><name>pkg</name></package>")
    (ws / "pkg" / "meshes" / "link.stl").write_bytes(stl_bytes())
    (ws / "secret").mkdir()
    (ws / "secret" / "secret.stl").write_bytes(stl_bytes(coordinate=SECRET))
    return ws


@pytest.fixture()
def home(tmp_path, monkeypatch):
    """home/u/secret.stl, and home/u/robots/r, where a downloaded URDF will go; no package.xml anywhere."""
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    (tmp_path / "home" / "u" / "robots" / "r").mkdir(parents=True)
    (tmp_path / "home" / "u" / "secret.stl").write_bytes(stl_bytes(coordinate=SECRET))
    return tmp_path / "home"


def leaked(document: str) -> bool:
    """Whether the secret coordinate is among the scene commands of an exported HTML page."""
    needle = np.float32(SECRET).tobytes()
    return any(needle in base64.b64decode(text) for text in re.findall(r'"([A-Za-z0-9+/=]{40,})"', document))


def refused(urdf: Path, geometry: str = "visual", match: str = "outside the URDF's folder") -> None:
    model = load_urdf(urdf)
    with pytest.warns(MeshWarning, match=match):
        result = robot_geometry(model, urdf, geometry)
    assert result.kind == "stick"


@pytest.mark.parametrize("reference", [
    "../../secret/secret.stl",                 # relative, up and out
    "{ws}/secret/secret.stl",                  # absolute
    "file://{ws}/secret/secret.stl",
    "package:///{ws}/secret/secret.stl",       # no package name: the rest was joined as an absolute path
    "package://pkg/../secret/secret.stl",      # out of the package with ..
    "package://pkg/meshes/../../secret/secret.stl",
    "package://ws/secret/secret.stl",          # ws is above the URDF, but no package
    "package://..//secret/secret.stl",
    "package://pkg/meshes/escape.stl",         # a symlink out of the package
])
def test_mesh_outside_the_package_is_not_read(workspace, reference):
    (workspace / "pkg" / "meshes" / "escape.stl").symlink_to(workspace / "secret" / "secret.stl")
    urdf = robot_with_meshes(workspace / "pkg" / "urdf" / "robot.urdf", reference.format(ws=workspace))
    refused(urdf)


@pytest.mark.parametrize("reference", ["package://home/u/secret.stl", "package://u/secret.stl"])
def test_package_named_like_a_folder_above_is_not_a_package(home, reference):
    """URDF at home/u/robots/r/robot.urdf: package://home/… or package://u/… would read all of home/ or u/."""
    refused(robot_with_meshes(home / "u" / "robots" / "r" / "robot.urdf", reference))


def test_folder_above_with_package_xml_is_a_package(workspace):
    urdf = robot_with_meshes(workspace / "pkg" / "urdf" / "robot.urdf", "package://pkg/meshes/link.stl")
    assert robot_geometry(load_urdf(urdf), urdf, "visual").kind == "visual"
    (workspace / "pkg" / "package.xml").unlink()
    refused(urdf)


def test_package_that_is_the_urdfs_own_folder(tmp_path, monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    (tmp_path / "r" / "meshes").mkdir(parents=True)
    (tmp_path / "r" / "meshes" / "a.stl").write_bytes(stl_bytes())
    urdf = robot_with_meshes(tmp_path / "r" / "r.urdf", "package://r/meshes/a.stl")
    assert robot_geometry(load_urdf(urdf), urdf, "visual").kind == "visual"


def test_ros_package_path_and_double_slashes(workspace, monkeypatch):
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(workspace))
    (workspace / "pkg" / "package.xml").unlink()  # found through ROS_PACKAGE_PATH, not as a folder above
    for reference in ("package://pkg/meshes/link.stl", "package://pkg//meshes//link.stl", "package:///pkg/meshes/link.stl"):
        urdf = robot_with_meshes(workspace / "pkg" / "urdf" / "robot.urdf", reference)
        assert robot_geometry(load_urdf(urdf), urdf, "visual").kind == "visual", reference


@pytest.mark.parametrize("reference", ["package://pkg//{ws}/secret/secret.stl", "package://pkg/%2e%2e/secret/secret.stl"])
def test_references_that_stay_in_the_package(workspace, reference):
    """After the package name the rest is joined as text (so '//x' is pkg/x), and %2e%2e is a folder
    named '%2e%2e', never '..': both stay in pkg, where no such file is. What is checked is what is read."""
    urdf = robot_with_meshes(workspace / "pkg" / "urdf" / "robot.urdf", reference.format(ws=workspace))
    assert resolve_mesh_path(reference.format(ws=workspace), urdf).is_relative_to(workspace / "pkg")
    refused(urdf, match="not found")


def test_symlink_loop_warns(workspace):
    loop = workspace / "pkg" / "meshes" / "loop.stl"
    loop.symlink_to(loop)
    urdf = robot_with_meshes(workspace / "pkg" / "urdf" / "robot.urdf", "package://pkg/meshes/loop.stl")
    refused(urdf, match="mesh file .*loop.stl")


def test_example_robot_data_paths_with_three_slashes():
    """Talos's URDFs write package:///example-robot-data/...; ROS joins the rest as text."""
    reference = "package:///example-robot-data/robots/ur_description/meshes/ur5/collision/base.stl"
    assert resolve_mesh_path(reference, robot_path("ur5")).is_file()
    assert geometry_module.mesh_allowed(reference, robot_path("ur5"))


def test_leak_through_cli_is_stopped(capsys, home):
    """`animate` of home/u/robots/r/robot.urdf with package://u/secret.stl: a warning, and not one secret byte."""
    urdf = robot_with_meshes(home / "u" / "robots" / "r" / "robot.urdf", "package://u/secret.stl")
    trajectory = urdf.parent / "traj.csv"
    trajectory.write_text("t,q_joint1,q_joint2\n0,0,0\n1,0.5,0.2\n")
    page = urdf.parent / "out.html"
    animate = ["animate", str(urdf), "--trajectory", str(trajectory), "--html", str(page), "--geometry", "visual"]
    code, err = run_cli(capsys, *animate)
    assert code == 0 and "warning: mesh file" in err and "lies outside" in err
    assert not leaked(page.read_text())
    code, err = run_cli(capsys, *animate, "--allow-any-mesh-path")
    assert code == 0 and "from outside the URDF's folder, as asked" in err
    assert leaked(page.read_text())  # the opt-in reads it: the needle does find a mesh that is there


# ---------------------------------------------------------------- mesh bombs and broken mesh files


def collada(nodes: str = "", scene: str = '<node id="root"><instance_geometry url="#tri"/></node>',
            geometry: str = '<triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles>') -> bytes:
    """A COLLADA document: one triangle geometry "tri", ``nodes`` in a node library, ``scene`` in the visual scene."""
    return f"""<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<library_geometries><geometry id="tri"><mesh>
<source id="pos"><float_array id="pos-a" count="12">0 0 0 1 0 0 0 1 0 1 1 0</float_array>
<technique_common><accessor source="#pos-a" count="4" stride="3"><param name="X" type="float"/><param name="Y" type="float"/>
<param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#pos"/></vertices>
{geometry}
</mesh></geometry></library_geometries>
<library_nodes>{nodes}</library_nodes>
<library_visual_scenes><visual_scene id="s">{scene}</visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene>
</COLLADA>""".encode()


def collada_bomb(levels: int = 6, fanout: int = 10, triangles: int = 1) -> bytes:
    """Node k instances node k − 1 ``fanout`` times: ``fanout ** levels`` copies of a geometry of ``triangles``."""
    nodes = '<node id="n0"><instance_geometry url="#tri"/></node>' + "".join(
        f'<node id="n{k}">' + f'<instance_node url="#n{k - 1}"/>' * fanout + "</node>" for k in range(1, levels + 1))
    geometry = f'<triangles><input semantic="VERTEX" source="#v" offset="0"/><p>{"0 1 2 " * triangles}</p></triangles>'
    return collada(nodes, f'<node id="root"><instance_node url="#n{levels}"/></node>', geometry)


ASCII_FACET = b"facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"


def robot_with_mesh_file(tmp_path: Path, name: str, data: bytes) -> Path:
    (tmp_path / name).write_bytes(data)
    return robot_with_meshes(tmp_path / "robot.urdf", name)


def test_collada_bomb_is_refused_quickly(tmp_path, capsys):
    bomb = collada_bomb()
    assert len(bomb) < 4096
    urdf = robot_with_mesh_file(tmp_path, "bomb.dae", bomb)
    start = time.monotonic()
    refused(urdf, match=r"bomb.dae expands to 2,111,112 nodes and instances, more than the limit of 5,000")
    with pytest.raises(ViewerError, match="bomb.dae expands to"):
        load_mesh(tmp_path / "bomb.dae")
    trajectory = tmp_path / "traj.csv"
    trajectory.write_text("t,q_joint1,q_joint2\n0,0,0\n1,0.5,0.2\n")
    code, err = run_cli(capsys, "animate", str(urdf), "--trajectory", str(trajectory), "--html", str(tmp_path / "o.html"))
    assert code == 0 and "warning: mesh file" in err and "bomb.dae expands to" in err
    assert time.monotonic() - start < 5


def test_triangle_bomb_and_the_robots_total(tmp_path, monkeypatch):
    """Few instances of many triangles are refused too, and the limit is for all of the robot's meshes."""
    wide = collada_bomb(levels=3, fanout=10, triangles=2_100)  # 1 111 nodes, 1 000 instances of 2 100 triangles
    refused(robot_with_mesh_file(tmp_path, "wide.dae", wide),
            match=r"wide.dae expands to 2,100,000 triangles, more than the limit of 2,000,000")
    monkeypatch.setattr(mesh_limits, "MAX_TRIANGLES", 3)
    urdf = robot_with_mesh_file(tmp_path, "two.stl", stl_bytes(triangles=2))  # 3 links draw it: 6 triangles
    refused(urdf, match=r"two.stl expands to 2 triangles \(4 for the robot so far\), more than the limit of 3")


HOSTILE_MESHES = [  # file name, its bytes, what the warning says
    ("cycle.dae", collada('<node id="a"><instance_node url="#b"/></node><node id="b"><instance_node url="#a"/></node>',
                          '<node id="root"><instance_node url="#a"/></node>'), "cycle through node"),
    ("self.dae", collada('<node id="a"><instance_node url="#a"/></node>'), "cycle through node 'a'"),
    ("garbage.dae", bytes(range(256)) * 16, "malformed XML"),
    ("cut.dae", collada()[:300], "malformed XML"),
    ("other.dae", b"<robot/>", r"not COLLADA: the root element is <robot>"),
    ("unseen.dae", collada().replace(b'url="#s"', b'url="#elsewhere"'), "names a visual scene to draw"),
    ("entity.dae", b'<?xml version="1.0"?><!DOCTYPE c [<!ENTITY x SYSTEM "file:///etc/passwd">]><COLLADA>&x;</COLLADA>',
     "declares a DTD"),
    ("deep.dae", collada("".join(f'<node id="d{k}"><instance_node url="#d{k - 1}"/></node>' for k in range(1, 300)),
                         '<node id="root"><instance_node url="#d299"/></node>'), "nest more than 200 deep"),
    ("late.dae", collada("".join(f'<node id="f{k}">' + "<node/>" * 10 + f'<instance_node url="#f{k + 1}"/></node>'
                                 for k in range(190)) + '<node id="f190"/>'), "pycollada would parse"),
    ("liar.stl", stl_bytes(triangles=2, claimed=10**9), r"header says 1,000,000,000 triangles but the file has room for 2.0"),
    ("short.stl", b"\0" * 40, "cut short"),
    ("parts.stl", (b"solid a\n" + ASCII_FACET + b"endsolid a\n") * 1001, "1,001 solids, more than the limit of 1,000"),
    ("model.ply", b"ply\nformat ascii 1.0\nend_header\n", "format '.ply' is not read"),
]


@pytest.mark.parametrize("name, data, match", HOSTILE_MESHES, ids=[case[0] for case in HOSTILE_MESHES])
def test_broken_or_hostile_mesh_files_warn(tmp_path, name, data, match):
    start = time.monotonic()
    refused(robot_with_mesh_file(tmp_path, name, data), match=f"mesh file .*{name}.*{match}")
    assert time.monotonic() - start < 5


def test_counts_match_what_trimesh_builds(tmp_path):
    """The counts before reading are upper bounds, and exact for ordinary files."""
    files = {
        "b.stl": stl_bytes(triangles=5),
        "a.stl": b"solid x\n" + ASCII_FACET * 3 + b"endsolid x\n",
        "q.obj": b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nf 1 2 3 4\nf 1 2 5\n",
        "p.dae": collada(geometry='<polylist count="1"><input semantic="VERTEX" source="#v" offset="0"/>'
                                  "<vcount>4</vcount><p>0 1 3 2</p></polylist>"),
        "t.dae": collada(),
    }
    for name, data in files.items():
        (tmp_path / name).write_bytes(data)
        count = mesh_limits.count_mesh(tmp_path / name, data)
        assert count.triangles == len(load_mesh(tmp_path / name)[1]), name


def test_shipped_meshes_fit_the_limits():
    for name in ("ur5", "panda", "double_pendulum"):
        for geometry in ("visual", "collision"):
            result = robot_geometry(load_robot(name), robot_path(name), geometry)
            assert result.kind == geometry and not result.warnings, (name, geometry, result.warnings)


def test_a_counting_gap_is_caught_after_loading(tmp_path, monkeypatch):
    (tmp_path / "m.stl").write_bytes(stl_bytes(triangles=3))
    monkeypatch.setattr(geometry_module, "count_mesh", lambda path, data: mesh_limits.MeshCount(1, 1))
    with pytest.raises(ViewerError, match="trimesh built 3 triangles, more than the 1 counted"):
        load_mesh(tmp_path / "m.stl")


def test_a_fifo_is_never_opened_for_reading(tmp_path):
    os.mkfifo(tmp_path / "pipe.stl")
    refused(robot_with_meshes(tmp_path / "robot.urdf", "pipe.stl"), match="not found")
    with pytest.raises(ViewerError, match="not a regular file"):
        load_mesh(tmp_path / "pipe.stl")


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
              "from course_dynamics.output.viewer import show\n"
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
    """`animate` end to end on the engineer guide's example; the screenshot is what docs/animation.png shows."""
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
    assert code == 2 and "--torques: " in err and "has no tau_<joint> columns" in err and "too few" in err

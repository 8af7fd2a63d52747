"""What several test modules share: the robots checked, the agreement assertion, URDF builders.

Reference values come from Pinocchio (course_dynamics_reference.pinocchio_oracle)
evaluated on the same URDF, never from numbers copied into a test. The test
files import this module as ``helpers`` (``pythonpath = ["tests"]`` in the
pytest configuration), so each runs on its own.
"""
from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np

from course_dynamics.core.robots import robot_names, robot_path
from course_dynamics.core.sampling import relative_error

ROOT = Path(__file__).resolve().parent.parent
DATA = Path(__file__).parent / "data"
AWKWARD = DATA / "awkward.urdf"
SAMPLES = 200  # seeded random states per robot
RTOL = 1e-9  # agreement with Pinocchio, relative

CHECKED_ROBOTS = list(robot_names()) + ["awkward"]
CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--headless=new", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                 "--ignore-gpu-blocklist", "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--no-first-run", "--disable-quic"]


def venv_seeing_this_environment(venv: Path, pip: bool = False) -> Path:
    """A new virtual environment that also sees every package this test run sees; its python.

    ``--system-site-packages`` would show it the base interpreter's packages only, without those of a
    virtual environment the tests run in, so a .pth file adds this run's own site folders (processing
    their .pth files, which is how pin finds Pinocchio) after the new environment's own.
    """
    import os
    import subprocess
    import sys

    subprocess.run([sys.executable, "-m", "venv", *([] if pip else ["--without-pip"]), str(venv)], check=True)
    python = venv / "bin" / "python"
    purelib = subprocess.run([python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                             capture_output=True, text=True, check=True).stdout.strip()
    outer = [p for p in sys.path if p.endswith(("site-packages", "dist-packages")) and os.path.isdir(p)]
    (Path(purelib) / "outer-environment.pth").write_text(f"import site; list(map(site.addsitedir, {outer!r}))\n")
    return python


def urdf_of(name: str) -> Path:
    return AWKWARD if name == "awkward" else robot_path(name)


def assert_agrees(ours, ref, scale=None, rtol=RTOL, what=""):
    """|ours − ref|∞ ≤ rtol · max(|ref|∞, scale): relative, floored at the term's natural scale."""
    ours, ref = np.asarray(ours), np.asarray(ref)
    assert ours.shape == ref.shape, f"{what}: shape {ours.shape} vs {ref.shape}"
    error = relative_error(ours, ref, scale or 0.0)
    assert error <= rtol, f"{what}: relative error {error:.3e} > {rtol:g}"


def tip_frame(model) -> str:
    """The last URDF link carried by the last moving body: a tool frame where there is one."""
    return [f.name for f in model.frames if f.body == model.n_bodies - 1][-1]


@lru_cache(maxsize=None)
def derivation(name: str, symbols: tuple[str, ...], method: str = "newton-euler"):
    """``symbolic.derive`` of a shipped robot, computed once per test session (3-joint derivations take seconds)."""
    from course_dynamics import load_robot
    from course_dynamics.core.symbolic import derive

    return derive(load_robot(name), symbols, method)


# ---------------------------------------------------------------- URDF text with one thing changed at a time

LINK = '<link name="{name}"><inertial><origin xyz="0.1 0 0" rpy="0 0 0"/><mass value="{mass}"/>' \
       '<inertia ixx="{ixx}" iyy="{iyy}" izz="{izz}" ixy="0" ixz="0" iyz="0"/></inertial></link>'
JOINT = '<joint name="{name}" type="{type}"><parent link="{parent}"/><child link="{child}"/>' \
        '<origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="{axis}"/>' \
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'


def arm_urdf(mass="1.0", ixx="0.01", iyy="0.01", izz="0.01", joint_type="revolute", axis="0 0 1", extra=""):
    """A two-link arm as URDF text, with one thing changed at a time."""
    return (
        '<?xml version="1.0"?><robot name="probe"><link name="base"/>'
        + LINK.format(name="link1", mass="1.0", ixx="0.01", iyy="0.01", izz="0.01")
        + LINK.format(name="link2", mass=mass, ixx=ixx, iyy=iyy, izz=izz)
        + JOINT.format(name="joint1", type="revolute", parent="base", child="link1", axis="0 0 1")
        + JOINT.format(name="joint2", type=joint_type, parent="link1", child="link2", axis=axis)
        + extra + "</robot>"
    )


BAD_URDFS = {
    "floating joint": (arm_urdf(joint_type="floating"), "joint 'joint2': type 'floating' is not supported"),
    "planar joint": (arm_urdf(joint_type="planar"), "joint 'joint2': type 'planar' is not supported"),
    "kinematic loop": (
        arm_urdf(extra=JOINT.format(name="loop", type="revolute", parent="base", child="link2", axis="1 0 0")),
        "kinematic loop: link 'link2' is the child of both joint 'joint2' and joint 'loop'"),
    "two roots": (arm_urdf(extra='<link name="stray"/>'), "2 root links (base, stray)"),
    "negative mass": (arm_urdf(mass="-1"), "link 'link2': negative mass"),
    "inertia not positive": (arm_urdf(ixx="-0.01"), "link 'link2': inertia tensor is not positive semi-definite"),
    "triangle inequality": (arm_urdf(ixx="0.01", iyy="0.01", izz="0.05"), "link 'link2': inertia breaks the triangle inequality"),
    "zero axis": (arm_urdf(axis="0 0 0"), "joint 'joint2': zero axis"),
    "NaN mass": (arm_urdf(mass="nan"), "link 'link2' inertial mass has a non-finite value"),
    "inf axis": (arm_urdf(axis="0 inf 0"), "joint 'joint2' axis has a non-finite value"),
    "non-numeric mass": (arm_urdf(mass="heavy"), "link 'link2': <mass value=\"heavy\">: 'heavy' is not a number as URDF writes them"),
    "malformed XML": ('<robot name="x"><link name="a"></robot>', "malformed XML"),
    "undefined link": (arm_urdf(extra=JOINT.format(name="j3", type="fixed", parent="link2", child="ghost", axis="1 0 0")),
                       "joint 'j3': child link 'ghost' is not defined"),
    "nothing moves": ('<robot name="x"><link name="a"/></robot>', "nothing moves"),
    "default namespace": (arm_urdf().replace('<axis xyz="0 0 1"/>', '<axis xmlns="urn:x" xyz="1 0 0"/>', 1),
                          "joint 'joint1': <axis> is in the default XML namespace 'urn:x'"),
}


def run(capsys, *argv):
    """The CLI in this process: (exit code, stdout, stderr)."""
    from course_dynamics.cli import main

    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def assert_one_line_error(code, err, *fragments):
    """Bad input: exit 2 and exactly one ``error: …`` line on stderr containing every fragment, no traceback."""
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert "Traceback" not in err
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])


def chain_urdf(n: int, joint_type: str = "revolute") -> str:
    """An n-joint serial chain as URDF text: alternating z and y axes, each link 0.1 m long."""
    parts = ['<?xml version="1.0"?><robot name="chain"><link name="base"/>']
    for i in range(1, n + 1):
        parts.append(LINK.format(name=f"link{i}", mass="1.0", ixx="0.01", iyy="0.01", izz="0.01"))
        parts.append(JOINT.format(name=f"joint{i}", type=joint_type, parent="base" if i == 1 else f"link{i - 1}",
                                  child=f"link{i}", axis="0 0 1" if i % 2 else "0 1 0"))
    return "".join(parts) + "</robot>"

"""crosscheck: one URDF through course_dynamics, Pinocchio, MuJoCo and PyBullet (reference/crosscheck.py).

Every shipped robot (and the tests' awkward tree) agrees across the four engines within 1e-9 once the named
conventions are applied; each convention has a small URDF here that shows it, named by the report with its
size, and each size is checked against what the convention says it is (b·Θ̇ for damping, the armature on
M's diagonal, PyBullet's own M for its massless links). An engine that is not installed is a note.
"""
from __future__ import annotations

import builtins
import json
import re

import numpy as np
import pytest
from helpers import AWKWARD, RTOL, run
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_random_robots import link_specs, write_urdf

from course_dynamics import load_robot, load_urdf
from course_dynamics.core.drives import Drives
from course_dynamics.core.robots import robot_names
from course_dynamics.core.sampling import random_states

# The test extra installs both engines (the engines extra): here a missing engine is a failure, never a skip.
import mujoco  # noqa: E402, F401
import pybullet  # noqa: E402, F401

from course_dynamics_reference import crosscheck as cc  # noqa: E402
from course_dynamics_reference import engines  # noqa: E402
from course_dynamics_reference.crosscheck import crosscheck  # noqa: E402

SAMPLES = 2
INERTIA = '<inertia ixx="{i}" ixy="0" ixz="0" iyy="{i}" iyz="0" izz="{i}"/>'


def link(name, mass="1.0", xyz="0.2 0 0", rpy="0 0 0", inertia=None):
    inertia = inertia or INERTIA.format(i="0.01")
    return (f'<link name="{name}"><inertial><origin xyz="{xyz}" rpy="{rpy}"/><mass value="{mass}"/>{inertia}'
            '</inertial></link>')


def joint(name, parent, child, kind="revolute", axis="0 0 1", xyz="0 0 0.1", extra=""):
    limit = '' if kind == "continuous" else '<limit lower="-2" upper="2" effort="10" velocity="5"/>'
    return (f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="{xyz}" rpy="0 0 0"/><axis xyz="{axis}"/>{limit}{extra}</joint>')


def arm(*, second="", kind="revolute", extra="", name="probe", links=()):
    """A two-joint arm (base → upper → fore) as URDF text, with one thing changed at a time."""
    return (f'<?xml version="1.0"?><robot name="{name}"><link name="base"/>' + link("upper")
            + (second or link("fore", mass="0.7", xyz="0.15 0.02 0"))
            + joint("shoulder", "base", "upper", axis="0 1 0")
            + joint("elbow", "upper", "fore", kind=kind, xyz="0.4 0 0", extra=extra) + "".join(links) + "</robot>")


def write(tmp_path, text, name="probe.urdf"):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def by_engine(check):
    return {e.engine: e for e in check.engines}


def conventions(engine_check):
    return {c["name"]: c for c in engine_check.conventions}


def agrees(check):
    """Every engine compared (or refused for a named reason) and within the tolerance once conventions apply."""
    assert check.ok, [(e.engine, e.status, e.reason, e.residual, e.first_link) for e in check.engines]
    for e in check.engines:
        if e.status == "compared":
            assert max(e.residual.values()) <= RTOL, (e.engine, e.residual)


@pytest.mark.parametrize("robot", list(robot_names()) + [str(AWKWARD)])
def test_every_shipped_robot_agrees_across_the_four_engines(robot):
    check = crosscheck(robot, samples=SAMPLES)
    agrees(check)
    assert [e.status for e in check.engines] == ["compared"] * 3


def test_fixed_joints_merged_are_named_with_their_count_and_lumped_per_body(tmp_path):
    tool = link("tool", mass="0.3", xyz="0.05 0 0.02")
    text = arm(links=[tool, joint("tool_mount", "fore", "tool", kind="fixed", xyz="0.3 0 0")])
    check = crosscheck(write(tmp_path, text), samples=SAMPLES)
    agrees(check)
    for name in ("mujoco", "pybullet"):
        assert conventions(by_engine(check)[name])["fixed joints merged"]["size"] == "1 links held by fixed joints"
    assert "fixed joints merged" not in conventions(by_engine(check)["pinocchio"])


def test_joint_order_is_named_with_the_engines_order(tmp_path):
    text = ('<?xml version="1.0"?><robot name="tree"><link name="base"/>' + link("a") + link("b", mass="2")
            + link("c", mass="0.5") + joint("to_c", "a", "c", axis="0 1 0", xyz="0.4 0 0")
            + joint("to_b", "base", "b", axis="1 0 0") + joint("to_a", "base", "a") + "</robot>")
    path = write(tmp_path, text)
    check = crosscheck(path, samples=SAMPLES)
    agrees(check)
    pinocchio = by_engine(check)["pinocchio"]
    assert list(load_urdf(path).joint_names) != ["to_a", "to_c", "to_b"]
    assert conventions(pinocchio)["joint order"]["size"] == "its order: to_a, to_c, to_b"


def test_continuous_joints_as_cos_sin_are_named(tmp_path):
    check = crosscheck(write(tmp_path, arm(kind="continuous")), samples=SAMPLES)
    agrees(check)
    assert conventions(by_engine(check)["pinocchio"])["continuous joints as cos/sin"]["size"] == "elbow"


def test_gravity_is_set_on_every_engine_and_its_default_named_with_what_it_would_miss(tmp_path):
    path = write(tmp_path, arm())
    g = np.array([1.0, -2.0, -5.0])
    check = crosscheck(path, samples=SAMPLES, gravity=g)
    agrees(check)
    model = load_urdf(path, gravity=g)
    from course_dynamics import gravity_torques

    q = random_states(model, SAMPLES, 0)[0]
    for name, default in (("pybullet", np.zeros(3)), ("mujoco", np.array([0, 0, -9.81]))):
        expected = np.abs(gravity_torques(model, q) - gravity_torques(load_urdf(path, gravity=default), q)).max()
        size = conventions(by_engine(check)[name])["gravity"]["size"]["G"]
        assert size == pytest.approx(expected, rel=RTOL)


def test_mj_inverse_adds_damping_as_b_times_qd(tmp_path):
    path = write(tmp_path, arm(extra='<dynamics damping="0.8"/>'))
    check = crosscheck(path, samples=SAMPLES)
    agrees(check)
    mujoco = by_engine(check)["mujoco"]
    qd = random_states(load_urdf(path), SAMPLES, 0)[1]
    assert conventions(mujoco)["damping"]["size"]["tau"] == pytest.approx(0.8 * np.abs(qd[:, 1]).max(), rel=RTOL)
    assert mujoco.raw["tau"] > 1e-3  # as MuJoCo's users get it, before the convention is undone
    assert "damping" not in conventions(by_engine(check)["pybullet"])


def test_friction_loss_is_named(tmp_path):
    check = crosscheck(write(tmp_path, arm(extra='<dynamics friction="0.4"/>')), samples=SAMPLES)
    agrees(check)
    size = conventions(by_engine(check)["mujoco"])["frictionloss"]["size"]
    assert 0 < size["tau"] <= 0.4 + 1e-12


def test_armature_is_named_with_its_size_on_the_mass_matrix(tmp_path):
    check = crosscheck(write(tmp_path, arm()), samples=SAMPLES, armature=[0.05, 0.2])
    agrees(check)
    for name in ("mujoco", "pinocchio"):
        assert conventions(by_engine(check)[name])["armature"]["size"]["M"] == pytest.approx(0.2, rel=RTOL)
    assert "armature" not in conventions(by_engine(check)["pybullet"])


def test_mimic_joints_are_coupled_for_the_engines_that_give_them_a_coordinate(tmp_path):
    """course_dynamics and Pinocchio honour <mimic>; MuJoCo's equality constraint holds the coupling (no force at
    states that keep it), PyBullet ignores it: both are given θ = multiplier · θ_leader + offset and mapped back."""
    path = write(tmp_path, arm(extra='<mimic joint="shoulder" multiplier="-0.5" offset="0.2"/>'))
    check = crosscheck(path, samples=SAMPLES)
    agrees(check)
    assert [e.status for e in check.engines] == ["compared"] * 3
    for name in ("mujoco", "pybullet"):
        assert conventions(by_engine(check)[name])["mimic joints coupled here"]["size"] == \
            "elbow = -0.5·shoulder + 0.2"
    held = conventions(by_engine(check)["mujoco"]).get("mimic joints as equality constraints", {"size": {}})
    assert max(held["size"].values(), default=0.0) <= 1e-12  # round-off at most: the states keep the coupling
    assert "mimic joints coupled here" not in conventions(by_engine(check)["pinocchio"])
    mujoco = engines.load_engine("mujoco", load_urdf(path), path)
    apart = np.array([0.3, 0.9])  # the elbow away from −0.5 · 0.3 + 0.2: the constraint pulls it back
    equality = mujoco._tau(3, apart, np.zeros(2), np.zeros(2)) - mujoco._tau(4, apart, np.zeros(2), np.zeros(2))
    assert np.abs(equality).max() > 0


def test_a_joint_limit_reached_is_a_constraint_force_in_mujoco(tmp_path):
    path = write(tmp_path, arm())
    model = load_urdf(path)
    mujoco = engines.load_engine("mujoco", model, path)
    beyond = np.array([0.0, 2.05])  # past the elbow's upper limit of 2 rad
    parts = mujoco.parts("tau", beyond, np.zeros(2), np.zeros(2))
    assert np.abs(parts["limits"]).max() > 0
    plain = mujoco.tau(beyond, np.zeros(2), np.zeros(2)) - sum(parts.values())
    ours = engines.Engine(model).tau(beyond, np.zeros(2), np.zeros(2))
    assert np.abs(plain - ours).max() <= RTOL * np.abs(ours).max()


def test_pybullet_gives_a_link_without_inertial_a_kilogram(tmp_path):
    text = arm(links=['<link name="tool"/>', joint("tool_mount", "fore", "tool", kind="fixed", xyz="0.3 0 0")])
    path = write(tmp_path, text)
    check = crosscheck(path, samples=SAMPLES)
    agrees(check)
    pybullet = by_engine(check)["pybullet"]
    model = load_urdf(path)
    q = random_states(model, SAMPLES, 0)[0]
    bullet = engines.load_engine("pybullet", model, path)
    ours = engines.Engine(model)
    expected = max(np.abs(bullet.M(x) - ours.M(x)).max() for x in q)  # PyBullet's own M, as its users get it
    assert conventions(pybullet)["massless links"]["size"]["M"] == pytest.approx(expected, rel=1e-6)
    assert expected > 0.05


def test_mujoco_raises_a_point_mass_inertia_to_its_bound_and_says_why():
    check = crosscheck("pendulum", samples=SAMPLES)
    agrees(check)
    refused = conventions(by_engine(check)["mujoco"])["inertia refused"]["size"]
    assert "mjMINVAL" in refused and "boundmass=1e-15 kg and boundinertia=1e-15" in refused
    assert refused.endswith("each such body gains at most 1e-15 kg and 1e-15 kg·m²")


def test_an_inertia_that_breaks_the_triangle_inequality_is_refused_or_altered_by_name(tmp_path):
    bad = link("fore", mass="0.7", inertia='<inertia ixx="0.05" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.02"/>')
    with pytest.warns(Warning):
        check = crosscheck(write(tmp_path, arm(second=bad)), samples=SAMPLES, allow_nonphysical_inertia=True)
    agrees(check)
    mujoco, pybullet = by_engine(check)["mujoco"], by_engine(check)["pybullet"]
    assert mujoco.status == "refused" and "A + B >= C" in mujoco.reason
    altered = conventions(pybullet)["inertia refused"]
    assert altered["detail"] == "the inertia of fore" and altered["size"]["M"] > 1e-3


def _fake(load_as, monkeypatch, as_engine="mujoco", forward=None):
    """Make crosscheck's ``as_engine`` one that computes as course_dynamics does on ``load_as`` (a URDF), its
    forward dynamics changed by ``forward(model, q, Θ̈)`` if given."""
    real = cc.load_engine

    class Fake(engines.Engine):
        def forward(self, q, qd, tau):
            qdd = super().forward(q, qd, tau)
            return qdd if forward is None else forward(self.model, q, qdd)

    def load_engine(name, model, urdf, armature=None):
        if name != as_engine:
            return real(name, model, urdf, armature)
        fake = Fake(load_urdf(load_as))
        fake.name = as_engine
        return fake

    monkeypatch.setattr(cc, "load_engine", load_engine)


ROTATED = link("fore", mass="0.7", rpy="0.4 0.3 0.9",
               inertia='<inertia ixx="0.03" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.015"/>')


def test_an_inertial_frame_dropped_on_import_is_unexplained(tmp_path, monkeypatch):
    path = write(tmp_path, arm(second=ROTATED))
    assert agrees(crosscheck(path, samples=SAMPLES)) is None  # the engines installed keep the rpy
    _fake(write(tmp_path, arm(second=ROTATED.replace('rpy="0.4 0.3 0.9"', 'rpy="0 0 0"')), "dropped.urdf"),
          monkeypatch)  # an importer that drops it: no engine installed does, so nothing names it
    check = crosscheck(path, samples=SAMPLES, engines=["pinocchio", "mujoco"])
    mujoco = by_engine(check)["mujoco"]
    assert not check.ok and not mujoco.explained and (mujoco.first_link, mujoco.first_joint) == ("fore", "elbow")
    assert not {c["name"] for c in mujoco.conventions} & set(cc.INERTIA_CONVENTIONS)


def test_pybullets_principal_axes_are_named_only_as_small_as_pybullet_finds_them(tmp_path, monkeypatch):
    path = write(tmp_path, arm(second=ROTATED))
    for turn, named in ((1e-6, True), (1e-3, False)):  # PyBullet's own are ~1e-9 off; 1e-3 rad is no round-off
        _fake(write(tmp_path, arm(second=ROTATED.replace('rpy="0.4 0.3 0.9"', f'rpy="0.4 0.3 {0.9 + turn!r}"')),
                    "turned.urdf"), monkeypatch, as_engine="pybullet")
        check = crosscheck(path, samples=SAMPLES, engines=["pinocchio", "pybullet"])
        pybullet = by_engine(check)["pybullet"]
        assert check.ok is named and pybullet.explained is named
        assert ("principal axes approximated" in conventions(pybullet)) is named
        assert max(pybullet.raw.values()) > cc.TOLERANCE


def test_a_bug_of_ours_that_every_engine_agrees_on_is_unexplained(tmp_path, monkeypatch):
    """course_dynamics' loader made to drop the inertial rpy: the three engines agree with each other, not with us."""
    from course_dynamics.core import urdf as reader

    path = write(tmp_path, arm(second=ROTATED))
    right = reader._inertial_in_body

    def dropped(where, link, T_body_link, allow_nonphysical=False):
        mass, com, inertia = right(where, link, T_body_link, allow_nonphysical)
        if link.inertial is not None and link.inertial.origin is not None:
            R = (T_body_link @ link.inertial.origin)[:3, :3]
            inertia = T_body_link[:3, :3] @ R.T @ inertia @ R @ T_body_link[:3, :3].T
        return mass, com, inertia

    monkeypatch.setattr(reader, "_inertial_in_body", dropped)
    check = crosscheck(path, samples=SAMPLES)
    assert not check.ok and [e.explained for e in check.engines] == [False] * 3
    assert all(e.first_link == "fore" for e in check.engines)
    for e in check.engines:
        assert not {c["name"] for c in e.conventions} & set(cc.INERTIA_CONVENTIONS)


def test_forward_dynamics_are_compared_as_the_torque_they_stand_for(tmp_path, monkeypatch):
    """An engine's Θ̈ off along M's softest direction by what a round-off of τ gives: M·ΔΘ̈ is the round-off."""
    light = link("fore", mass="1e-7", xyz="0.01 0 0", inertia=INERTIA.format(i="1e-13"))
    path = write(tmp_path, arm(second=light))

    def soft(model, q, qdd):
        from course_dynamics import mass_matrix

        moments, axes = np.linalg.eigh(mass_matrix(model, q))
        return qdd + 1e-13 * np.abs(qdd).max() * moments[-1] / moments[0] * axes[:, 0]

    _fake(path, monkeypatch, forward=soft)
    mujoco = by_engine(crosscheck(path, samples=SAMPLES, engines=["mujoco"]))["mujoco"]
    assert mujoco.explained and mujoco.residual["forward"] <= RTOL
    model = load_urdf(path)
    q, qd, qdd = random_states(model, 1, 0)
    fake = cc.load_engine("mujoco", model, path)
    tau = engines.Engine(model).tau(q[0], qd[0], qdd[0])
    assert np.abs(fake.forward(q[0], qd[0], tau) - qdd[0]).max() > 1e-6 * np.abs(qdd[0]).max()  # Θ̈ itself is off


def test_an_outside_urdf_with_meshes_pybullet_cannot_find_is_compared(tmp_path):
    mesh = '<visual><geometry><mesh filename="package://nowhere/meshes/upper.stl"/></geometry></visual>'
    text = arm().replace('<link name="upper"><inertial>', f'<link name="upper">{mesh}<inertial>')
    check = crosscheck(write(tmp_path, text), samples=SAMPLES)
    agrees(check)
    assert by_engine(check)["pybullet"].status == "compared"


def test_more_links_than_pybullet_holds_is_a_refusal_with_its_reason(tmp_path, capsys):
    chain = "\n".join(link(f"l{i}") + joint(f"j{i}", f"l{i - 1}" if i else "base", f"l{i}") for i in range(129))
    path = write(tmp_path, f'<?xml version="1.0"?>\n<robot name="long"><link name="base"/>\n{chain}\n</robot>')
    check = crosscheck(path, samples=1, engines=["pinocchio", "pybullet"])
    pybullet = by_engine(check)["pybullet"]
    assert check.ok and pybullet.status == "refused" and "at most 128 links; this one has 129" in pybullet.reason
    assert conventions(pybullet)["engine limit"]["size"] == pybullet.reason


def test_a_link_breaking_the_triangle_inequality_inside_a_physical_body_is_named(tmp_path):
    """PyBullet alters the link's own inertia, though the body it is lumped into (with a fixed tool) is physical."""
    bad = link("fore", mass="0.7", inertia='<inertia ixx="0.05" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.02"/>')
    tool = link("tool", mass="0.5", xyz="0 0 0", inertia=INERTIA.format(i="0.05"))
    text = arm(second=bad, links=[tool, joint("tool_mount", "fore", "tool", kind="fixed", xyz="0 0 0")])
    with pytest.warns(Warning):
        check = crosscheck(write(tmp_path, text), samples=SAMPLES, allow_nonphysical_inertia=True)
    agrees(check)
    assert conventions(by_engine(check)["pybullet"])["inertia refused"]["detail"] == "the inertia of fore"


def test_an_engine_call_failing_part_way_is_a_refusal_with_its_reason(monkeypatch, capsys):
    import pybullet

    def failing(*args, **kwargs):
        raise pybullet.error("calculateMassMatrix failed.")

    monkeypatch.setattr(pybullet, "calculateMassMatrix", failing)
    code, out, err = run(capsys, "crosscheck", "two_link")
    assert code == 1 and "Traceback" not in err
    assert "  pybullet   refused: calculateMassMatrix failed." in out.splitlines()


def _importing(monkeypatch, failures):
    """Make ``import name`` raise ``failures[name]``."""
    real_import = builtins.__import__

    def failing(name, *args, **kwargs):
        if name.split(".")[0] in failures:
            raise failures[name.split(".")[0]]
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", failing)


def test_an_engine_that_cannot_be_imported_is_skipped_with_its_reason(monkeypatch, capsys):
    _importing(monkeypatch, {"mujoco": OSError("libGL.so.1: cannot open shared object file"),
                             "pybullet": RuntimeError("no display")})
    code, out, err = run(capsys, "crosscheck", "two_link")
    assert code == 0 and err == ""
    assert "  mujoco     mujoco skipped: mujoco cannot be imported (OSError: libGL.so.1: cannot open shared object " \
           "file)" in out.splitlines()
    assert "  pybullet   pybullet skipped: pybullet cannot be imported (RuntimeError: no display)" in out.splitlines()


def test_no_engine_compared_is_said_and_exits_1(monkeypatch, capsys):
    _importing(monkeypatch, {name: ImportError(f"No module named '{name}'") for name in cc.PACKAGES})
    code, out, _ = run(capsys, "crosscheck", "two_link")
    assert code == 1
    last = "NO ENGINE COMPARED: pinocchio skipped, mujoco skipped, pybullet skipped (see the notes)"
    assert out.splitlines()[-1] == last


def test_an_unexplained_difference_names_the_first_body_where_the_engines_part(tmp_path, monkeypatch, capsys):
    path = write(tmp_path, arm())
    _fake(write(tmp_path, arm(second=link("fore", mass="0.75", xyz="0.15 0.02 0")), "heavier.urdf"), monkeypatch)
    check = crosscheck(path, samples=SAMPLES, engines=["mujoco"])
    mujoco = by_engine(check)["mujoco"]
    assert not check.ok and (mujoco.first_link, mujoco.first_joint) == ("fore", "elbow")
    code, out, _ = run(capsys, "crosscheck", path)
    assert code == 1
    assert out.splitlines()[-1] == "UNEXPLAINED DIFFERENCE: mujoco (first at link fore, joint elbow)"


def test_a_missing_engine_is_skipped_with_a_note(tmp_path, monkeypatch, capsys):
    real_import = builtins.__import__

    def without_mujoco(name, *args, **kwargs):
        if name == "mujoco" or name.startswith("mujoco."):
            raise ImportError("No module named 'mujoco'")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", without_mujoco)
    code, out, err = run(capsys, "crosscheck", "two_link")
    assert code == 0 and err == ""
    assert re.search(r"^mujoco +- .* skipped$", out, re.M), out
    assert "mujoco     mujoco skipped: mujoco is not installed" in out


def test_json_is_one_document(capsys):
    code, out, _ = run(capsys, "crosscheck", "double_pendulum", "--json")
    document = json.loads(out)
    assert code == 0 and document["ok"] is True and document["urdf"] == "double_pendulum.urdf"
    mujoco = {e["engine"]: e for e in document["engines"]}["mujoco"]
    assert mujoco["status"] == "compared" and {c["name"] for c in mujoco["conventions"]} == {"damping"}
    assert set(document["conventions"]) == set(cc.CONVENTIONS)


def test_the_page_is_offline_and_escapes_names(tmp_path, capsys):
    path = write(tmp_path, arm(name="a&lt;script&gt;b"))
    out_file = tmp_path / "page.html"
    code, out, _ = run(capsys, "crosscheck", path, "--out", str(out_file))
    html = out_file.read_text()
    assert code == 0 and out.splitlines()[-1] == f"wrote {out_file}"
    assert "<script" not in html and "a&lt;script&gt;b" in html
    assert not re.search(r"""(src|href)=["']?(https?:)?//""", html)
    for heading in ("Conventions", "Before the conventions", "What was called", "The named conventions"):
        assert f">{heading}</h2>" in html


def test_bad_input_is_one_error_line(tmp_path, capsys):
    from helpers import assert_one_line_error

    code, _, err = run(capsys, "crosscheck", "no_such_robot.urdf")
    assert_one_line_error(code, err, "no_such_robot.urdf")
    code, _, err = run(capsys, "crosscheck", "two_link", "--samples", "0")
    assert_one_line_error(code, err, "--samples")
    code, _, err = run(capsys, "crosscheck", "two_link", "--out", "-", "--json")
    assert_one_line_error(code, err, "--out - and --json")
    code, out, err = run(capsys, "crosscheck", "two_link", "--out", str(tmp_path / "missing" / "page.html"))
    assert_one_line_error(code, err, "missing")
    assert out == ""  # nothing computed, nothing printed


def test_the_page_on_standard_output_is_the_whole_output(capsys):
    code, out, _ = run(capsys, "crosscheck", "pendulum", "--out", "-")
    assert code == 0 and out.startswith("<!DOCTYPE html>") and out.rstrip().endswith("</html>")


@pytest.mark.parametrize("reason", ["XML parse error 14", "mass of link 'a' is read as 0 inertia"])
def test_a_refusal_for_a_reason_no_convention_names_is_unexplained(monkeypatch, capsys, reason):
    real = cc.load_engine

    def load_engine(name, model, urdf, armature=None):
        if name == "mujoco":
            raise engines.EngineRefused(reason)
        return real(name, model, urdf, armature)

    monkeypatch.setattr(cc, "load_engine", load_engine)
    code, out, _ = run(capsys, "crosscheck", "rp_arm")
    assert code == 1
    assert f"  mujoco     refused: {reason}" in out.splitlines()
    assert re.search(r"^mujoco +[0-9.]+ .* REFUSED$", out, re.M), out


@pytest.mark.parametrize("name", ["pinocchio", "mujoco", "pybullet"])
def test_every_engine_places_each_body_as_course_dynamics_does(name):
    """The per-body data the first parting link is found from: m, centre of mass and inertia of each body and what
    fixed joints hold to it (the awkward tree has massive links behind fixed joints, a branch, rotated inertial
    frames); 1e-6 because PyBullet finds principal axes iteratively."""
    model = load_urdf(AWKWARD)
    engine, ours = engines.load_engine(name, model, AWKWARD), engines.Engine(model)
    for q in random_states(model, SAMPLES, 1)[0]:
        assert cc.first_parting(engine, ours, q, 1e-6) is None
    engine.close()


def test_mujoco_is_given_a_subnormal_number_as_zero(tmp_path):
    text = arm().replace('<origin xyz="0.4 0 0"', '<origin xyz="0.4 1e-310 0"', 1)
    check = crosscheck(write(tmp_path, text), samples=SAMPLES)
    agrees(check)
    flushed = conventions(by_engine(check)["mujoco"])["subnormal numbers"]["size"]
    assert "number is too large" in flushed and flushed.endswith("1 number of size at most 1e-310 read as 0")


@settings(max_examples=6, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(specs=st.lists(link_specs(), min_size=1, max_size=5).filter(lambda s: any(x["type"] != "fixed" for x in s)))
def test_random_trees_agree_across_the_four_engines(tmp_path, specs):
    """The property test's trees (random joint types, non-unit axes, rotated inertial frames, branches)."""
    path = tmp_path / "random.urdf"
    write_urdf(path, specs)
    agrees(crosscheck(str(path), samples=SAMPLES))


def test_crosscheck_compares_the_drives_with_the_engines_armature(capsys, tmp_path):
    """crosscheck --drives: Pinocchio's and MuJoCo's armature against our drives, no convention between them."""
    drives = tmp_path / "drives.toml"
    drives.write_text("[joint.shoulder_lift_joint]\narmature = 0.4\noffset = -3.0\n[joint.wrist_3_joint]\n"
                      "armature = 0.1\n")
    code, out, err = run(capsys, "crosscheck", "ur5", "--drives", str(drives), "--json", "--samples", "2")
    assert code == 0, err
    engines = {e["engine"]: e for e in json.loads(out)["engines"]}
    for name in ("pinocchio", "mujoco"):
        assert engines[name]["explained"] and max(engines[name]["residual"].values()) < RTOL
        assert "armature" not in [c["name"] for c in engines[name]["conventions"]]   # ours adds it too
        assert any("compared as they are" in note for note in engines[name]["notes"])
        assert any("offsets are no engine's" in note for note in engines[name]["notes"])
    if "pybullet" in engines and engines["pybullet"]["status"] == "compared":
        assert any("PyBullet has no rotor inertia" in note for note in engines["pybullet"]["notes"])


def test_crosscheck_would_see_a_drive_course_dynamics_got_wrong(monkeypatch):
    """The check is not vacuous: ours with half the armature disagrees with Pinocchio's."""
    real = engines.Engine.__init__

    def halved(self, model, rotors=None):
        real(self, model, None if rotors is None else np.asarray(rotors) / 2)
    monkeypatch.setattr(engines.Engine, "__init__", halved)
    model = load_robot("ur5")
    check = crosscheck("ur5", samples=1, engines=("pinocchio",),
                                    drives=Drives(armature=np.full(model.n, 0.3), offset=np.zeros(model.n)))
    assert not check.ok

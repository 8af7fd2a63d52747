"""course_dynamics/output/urdf_writer.py: an identified model written into its URDF, read back by us and by Pinocchio."""
from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from helpers import AWKWARD, assert_agrees

from course_dynamics import load_robot, load_urdf
from course_dynamics.base.errors import InputError
from course_dynamics.core.friction import Friction
from course_dynamics.core.newton_euler import inverse_dynamics
from course_dynamics.core.regressor import parameters, with_parameters
from course_dynamics.output.urdf_writer import identified_urdf, write_identified_urdf

def without_edits(text: str) -> str:
    """The URDF text without what the writer may change: <inertial> blocks, <dynamics> elements, its comments, and
    the whitespace between tags (which an insertion adds to)."""
    text = re.sub(r"<inertial>.*?</inertial>|<dynamics[^>]*/>|<!-- inertial (removed|parameters)[^>]*-->", "", text,
                  flags=re.S)
    text = re.sub(r">\s+<", "><", text.strip())
    return re.sub(r"<link ([^>]*)></link>", r"<link \1/>", text)


def perturbed(model, seed=0):
    """``model`` with π moved as identification moves it: masses ±20 %, centres of mass by ≤ 2 cm, inertias
    ±30 % (a massless body gets 0.1 kg), then through π and :func:`with_parameters`; and friction."""
    rng = np.random.default_rng(seed)
    bodies = tuple(replace(b, mass=max(b.mass, 0.1) * rng.uniform(0.8, 1.2), p_com=b.p_com + rng.uniform(-0.0115, 0.0115, 3),
                           I_com=b.I_com * rng.uniform(0.7, 1.3) + 1e-4 * np.eye(3)) for b in model.bodies)
    pi = parameters(replace(model, bodies=bodies))
    friction = Friction(viscous=rng.uniform(0, 2, model.n), coulomb=rng.uniform(0, 2, model.n))
    return with_parameters(model, pi), friction


@pytest.fixture(scope="module")
def written(robot, tmp_path_factory):
    """(name, original model, identified model, friction, written path, Pinocchio on it, states) per robot."""
    name, model, _, states = robot
    identified, friction = perturbed(model)
    path = tmp_path_factory.mktemp("identified") / f"{name}.urdf"
    write_identified_urdf(path, identified, friction)
    return name, model, identified, friction, path, PinocchioOracle(path, model.joint_names, model.gravity), states


def test_our_loader_reads_back_the_identified_model(written):
    name, _, identified, friction, path, _, (q, qd, qdd) = written
    back = load_urdf(path)
    expected = inverse_dynamics(identified, q, qd, qdd)
    assert_agrees(inverse_dynamics(back, q, qd, qdd), expected, what=f"{name} tau")
    np.testing.assert_allclose(parameters(back), parameters(identified), rtol=1e-12, atol=1e-15)
    # per coordinate, a mimic joint's (none written) on its leader's
    np.testing.assert_array_equal(Friction.from_urdf(back).viscous, friction.viscous)
    np.testing.assert_array_equal(Friction.from_urdf(back).coulomb, friction.coulomb)


def test_pinocchio_reads_the_identified_model(written):
    name, _, identified, friction, _, oracle, (q, qd, qdd) = written
    expected = inverse_dynamics(identified, q, qd, qdd)
    ours = np.array([oracle.tau(*state) for state in zip(q, qd, qdd)])
    assert_agrees(ours, expected, what=f"{name} tau by Pinocchio")
    np.testing.assert_array_equal(oracle.damping, friction.viscous)
    np.testing.assert_array_equal(oracle.friction, friction.coulomb)


def test_links_and_joints_stay_and_only_inertials_and_dynamics_change(written):
    _, model, _, _, path, _, _ = written
    back = load_urdf(path)
    assert back.joint_names == model.joint_names and back.frame_names == model.frame_names
    for old, new in zip(model.frames, back.frames):
        assert old.body == new.body and np.array_equal(old.R, new.R) and np.array_equal(old.P, new.P), old.name
    before, after = open(model.source, encoding="utf-8").read(), path.read_text(encoding="utf-8")
    assert without_edits(after) == without_edits(before)   # everything else, character for character


def test_merged_links_lose_their_inertial_and_the_moving_link_carries_the_lump(tmp_path):
    panda = load_robot("panda")   # panda_link8 and panda_hand are fixed to link 7
    identified, _ = perturbed(panda)
    text = identified_urdf(open(panda.source, "rb").read(), identified).decode()
    hand = re.search(r'<link name="panda_hand">.*?</link>', text, re.S).group(0)
    assert "<inertial>" not in hand and "lumped into the identified inertial" in hand
    assert "<dynamics D=\"1\" K=\"7000\" damping=\"0.003\"" in text        # no friction given: <dynamics> kept
    path = tmp_path / "panda.urdf"
    path.write_text(text)
    assert load_urdf(path).bodies[6].mass == pytest.approx(identified.bodies[6].mass, rel=1e-15)


def test_links_fixed_to_the_base_keep_their_inertial_verbatim():
    awkward = load_urdf(AWKWARD)   # base_link and pedestal (fixed to it) have masses that never move
    identified, _ = perturbed(awkward)
    raw = AWKWARD.read_text()
    text = identified_urdf(raw.encode(), identified).decode()
    for link in ("base_link", "pedestal"):
        block = re.search(rf'<link name="{link}">.*?</link>', raw, re.S).group(0)
        assert "<inertial>" in block and block in text


def test_a_simulators_dynamics_attributes_stay(tmp_path):
    panda = load_robot("panda")
    identified, friction = perturbed(panda)
    text = identified_urdf(open(panda.source, "rb").read(), identified, friction).decode()
    assert f'<dynamics D="1" K="7000" damping="{float(friction.viscous[0])!r}" friction="{float(friction.coulomb[0])!r}" ' \
           'mu_coulomb="0" mu_viscous="16"/>' in text


def test_a_description_with_a_dtd_or_entity_is_refused():
    arm = load_robot("two_link")
    raw = open(arm.source, "rb").read()
    evil = raw.replace(b"<robot", b'<!DOCTYPE robot [<!ENTITY x "y">]>\n<robot', 1)
    with pytest.raises(InputError, match="DTD or an entity"):
        identified_urdf(evil, arm, where="evil.urdf")


def test_a_model_of_another_urdf_is_refused_and_nothing_is_written(tmp_path):
    arm, pendulum = load_robot("two_link"), load_robot("pendulum")
    target = tmp_path / "out.urdf"
    target.write_text("keep me")
    with pytest.raises(InputError, match="has no link"):
        write_identified_urdf(target, pendulum, source=arm.source)
    broken = replace(arm, bodies=(replace(arm.bodies[0], mass=float("nan")),) + arm.bodies[1:])
    with pytest.raises(InputError, match="not finite"):
        write_identified_urdf(target, broken)
    assert target.read_text() == "keep me" and sorted(p.name for p in tmp_path.iterdir()) == ["out.urdf"]


# ---------------------------------------------------------------- hostile text: only what the loader reads is edited

FRICTION = Friction(viscous=np.array([1.25, 2.5]), coulomb=np.array([0.75, 0.125]))
THETA1 = '<joint name="theta1" type="revolute">'
THETA2 = '<joint name="theta2" type="revolute">'
# Text that looks like a <dynamics> or a damping attribute but is none: another attribute's value, a comment, a
# CDATA section, a joint's <inertial> (not its <dynamics>), look-alike element names.
DECOYS_1 = ("""<joint name="theta1" type="revolute" note='damping="0.1"'>\n"""
            """    <!-- <dynamics damping="9"/> --><![CDATA[ <dynamics damping="9"/> ]]>\n"""
            """    <inertial><mass value="1"/></inertial>\n"""
            """    <dynamics friction="0" note=' damping="7"' damping = '0.5' />""")
DECOYS_2 = ("""<joint name="theta2" type="revolute">\n"""
            """    <dynamicsX damping="3"/><x:dynamics xmlns:x="urn:x" damping="3"/>\n"""
            """    <dynamics note=' damping="7" friction="7"'/>""")


def hostile_copy(folder, replacements, encoding="utf-8", newline="\n", prefix=b"", renamed=None):
    """two_link's URDF with ``replacements`` (old → new text, the first occurrence) made and ``renamed`` (old → new
    name, everywhere), written to ``folder`` as ``encoding``."""
    text = Path(load_robot("two_link").source).read_text()
    for old, new in replacements.items():
        assert old in text, old
        text = text.replace(old, new, 1)
    for old, new in (renamed or {}).items():
        text = text.replace(f'"{old}"', f'"{new}"')
    path = folder / "hostile.urdf"
    path.write_bytes(prefix + text.replace("\n", newline).encode(encoding))
    return path


def test_only_the_loaders_dynamics_is_edited_never_text_that_looks_like_one(tmp_path):
    source = hostile_copy(tmp_path, {THETA1: DECOYS_1, THETA2: DECOYS_2})
    model, out = load_urdf(source), tmp_path / "identified.urdf"
    write_identified_urdf(out, model, FRICTION)
    back = load_urdf(out)
    np.testing.assert_array_equal([b.damping for b in back.bodies], FRICTION.viscous)
    np.testing.assert_array_equal([b.friction for b in back.bodies], FRICTION.coulomb)
    oracle = PinocchioOracle(out, model.joint_names, model.gravity)   # urdfdom reads the same <dynamics>
    np.testing.assert_array_equal(oracle.damping, FRICTION.viscous)
    np.testing.assert_array_equal(oracle.friction, FRICTION.coulomb)
    text = out.read_text()
    for decoy in ("""note='damping="0.1"'""", '<!-- <dynamics damping="9"/> -->', '<![CDATA[ <dynamics damping="9"/> ]]>',
                  '<inertial><mass value="1"/></inertial>', '<dynamicsX damping="3"/>',
                  '<x:dynamics xmlns:x="urn:x" damping="3"/>'):
        assert text.count(decoy) == 1, decoy
    assert """<dynamics friction="0.75" note=' damping="7"' damping = '1.25' />""" in text    # its quotes, its spaces
    assert """<dynamics note=' damping="7" friction="7"' damping="2.5" friction="0.125"/>""" in text


def test_a_default_namespace_that_appeared_after_loading_is_refused_and_nothing_is_written(tmp_path):
    # The loader refuses a default xmlns on any element; the writer keeps its own check for a text changed since.
    source = hostile_copy(tmp_path, {})
    model, out = load_urdf(source), tmp_path / "identified.urdf"
    hostile_copy(tmp_path, {"    <axis": '    <dynamics xmlns="urn:x" damping="3"/>\n    <axis'})
    with pytest.raises(InputError) as error:
        write_identified_urdf(out, model, FRICTION)
    assert str(error.value).startswith(str(source)) and "\n" not in str(error.value)
    assert "joint 'theta1'" in str(error.value) and "default xmlns" in str(error.value)
    assert not out.exists()


@pytest.mark.parametrize("replacements, fragments", [
    ({"    <axis": '    <dynamics damping="3"/><dynamics damping="4"/>\n    <axis'}, ["joint 'theta1'", "2 <dynamics>"]),
    ({"    </inertial>": '    </inertial>\n    <inertial><mass value="5"/></inertial>'}, ["link 'link1'", "2 <inertial>"]),
])
def test_an_element_readers_disagree_on_or_a_second_one_is_refused_and_nothing_is_written(tmp_path, replacements,
                                                                                            fragments):
    source = hostile_copy(tmp_path, replacements)
    model, out = load_urdf(source), tmp_path / "identified.urdf"   # our loader reads it (and skips or takes the first)
    with pytest.raises(InputError) as error:
        write_identified_urdf(out, model, FRICTION)
    assert str(error.value).startswith(str(source)) and "\n" not in str(error.value)
    assert all(fragment in str(error.value) for fragment in fragments), str(error.value)
    assert not out.exists()


def test_a_text_that_reads_back_otherwise_than_identified_is_never_written(tmp_path):
    """A URDF with a link the model does not know (a camera fixed to link 2): its mass would be lumped into the
    identified link 2 by every reader; the read-back names the file and the link, and nothing is left."""
    camera = ('<link name="camera"><inertial><mass value="0.25"/><inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" '
              'izz="1e-3"/></inertial></link>\n  <joint name="camera_fixed" type="fixed"><parent link="link2"/>'
              '<child link="camera"/></joint>\n</robot>')
    source, arm = hostile_copy(tmp_path, {"</robot>": camera}), load_robot("two_link")
    out = tmp_path / "identified.urdf"
    with pytest.raises(InputError, match=rf"^{re.escape(str(out))}: link 'link2': mass reads back as 1.25 .* not the "
                                         r"identified 1; nothing was written$"):
        write_identified_urdf(out, arm, FRICTION, source=source)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["hostile.urdf"]


@pytest.mark.parametrize("encoding, declaration, prefix", [
    ("utf-8", '<?xml version="1.0"?>', b"\xef\xbb\xbf"),                                 # a BOM
    ("latin-1", '<?xml version="1.0" encoding="ISO-8859-1"?>', b""),
    ("cp1252", '<?xml version="1.0" encoding="windows-1252"?>', b""),
])
def test_crlf_lines_a_bom_and_one_byte_encodings_are_kept(tmp_path, encoding, declaration, prefix):
    source = hostile_copy(tmp_path, {'<?xml version="1.0"?>': declaration, "section 6.7": "§ 6.7 (für Übungen)"},
                          encoding, "\r\n", prefix, renamed={"link2": "glied2ä"})
    model, out = load_urdf(source), tmp_path / "identified.urdf"
    identified, _ = perturbed(model)
    write_identified_urdf(out, identified, FRICTION)
    raw = out.read_bytes()
    assert raw.startswith(prefix + declaration.encode()) and raw.count(b"\n") == raw.count(b"\r\n")   # no bare LF
    assert "glied2ä".encode(encoding) in raw and "§ 6.7 (für Übungen)".encode(encoding) in raw
    back = load_urdf(out)
    assert back.bodies[1].name == "glied2ä"
    np.testing.assert_allclose(parameters(back), parameters(identified), rtol=1e-12, atol=1e-15)
    np.testing.assert_array_equal([b.damping for b in back.bodies], FRICTION.viscous)


def test_mimic_joints_are_written_back(tmp_path):
    """model_urdf writes each <mimic>; an identified URDF keeps the file's and puts a coordinate's friction on its
    own joint (none on the mimic, whose coefficients act on the leader's coordinate): both read back the same."""
    from helpers import DATA

    from course_dynamics.output.urdf_writer import checked_identified_urdf, model_urdf

    model = load_urdf(DATA / "mimic.urdf")
    (tmp_path / "written.urdf").write_bytes(model_urdf(model))
    written = load_urdf(tmp_path / "written.urdf")
    assert written.coupling == model.coupling and written.joint_names == model.joint_names
    friction = Friction(viscous=[0.5, 0.6, 0.7], coulomb=[0.1, 0.2, 0.3])
    (tmp_path / "identified.urdf").write_bytes(checked_identified_urdf(model, friction, source=DATA / "mimic.urdf"))
    back = load_urdf(tmp_path / "identified.urdf")
    assert back.coupling == model.coupling
    np.testing.assert_array_equal(Friction.from_urdf(back).viscous, friction.viscous)
    np.testing.assert_array_equal(Friction.from_urdf(back).coulomb, friction.coulomb)

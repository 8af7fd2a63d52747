"""course_dynamics/output/urdf_writer.py: an identified model written into its URDF, read back by us and by Pinocchio."""
from __future__ import annotations

import re
from dataclasses import replace

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
    np.testing.assert_array_equal([b.damping for b in back.bodies], friction.viscous)
    np.testing.assert_array_equal([b.friction for b in back.bodies], friction.coulomb)


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

"""course_dynamics/tools/loads.py: a payload lumped into a link and a wrench through Jᵀ, against Pinocchio."""
from __future__ import annotations

import numpy as np
import pytest
from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from helpers import CHECKED_ROBOTS, assert_agrees, tip_frame, urdf_of

from course_dynamics import InputError, ModelError, inverse_dynamics, load_urdf
from course_dynamics.core.inertia import box
from course_dynamics.core.sampling import random_states
from course_dynamics.tools.loads import (
    Payload,
    Wrench,
    payload_link,
    with_payload,
    wrench_torques,
)

SAMPLES = 40


@pytest.mark.parametrize("name", CHECKED_ROBOTS)
@pytest.mark.parametrize("size", [None, (0.1, 0.2, 0.05)])
def test_payload_matches_pinocchio_with_an_appended_body(name, size):
    model = load_urdf(urdf_of(name))
    link = tip_frame(model)
    payload = Payload(mass=2.5, link=link, com=(0.03, -0.02, 0.08), size=size)
    loaded = with_payload(model, payload)
    oracle = PinocchioOracle(urdf_of(name), model.joint_names, model.gravity)
    oracle.add_payload(link, payload.mass, payload.com, payload.inertia())
    q, qd, qdd = random_states(model, SAMPLES, seed=5)
    ours = inverse_dynamics(loaded, q, qd, qdd)
    for k in range(SAMPLES):
        assert_agrees(ours[k], oracle.tau(q[k], qd[k], qdd[k]), what=f"{name} state {k}")
    assert loaded.bodies[model.frame(link).body].mass == pytest.approx(model.bodies[model.frame(link).body].mass + 2.5)


@pytest.mark.parametrize("name", CHECKED_ROBOTS)
def test_wrench_torques_match_pinocchio_external_forces(name):
    model = load_urdf(urdf_of(name))
    link = tip_frame(model)
    wrench = Wrench(link=link, force=(3.0, -10.0, 4.0), moment=(0.5, 0.2, -1.0))
    oracle = PinocchioOracle(urdf_of(name), model.joint_names, model.gravity)
    q, qd, qdd = random_states(model, SAMPLES, seed=6)
    ours = inverse_dynamics(model, q, qd, qdd) + wrench_torques(model, q, wrench)
    for k in range(SAMPLES):
        expected = oracle.tau_with_wrench(q[k], qd[k], qdd[k], link, wrench.force, wrench.moment)
        assert_agrees(ours[k], expected, what=f"{name} state {k}")


def test_wrench_torques_batch_equals_single_states():
    model = load_urdf(urdf_of("ur5"))
    wrench = Wrench(link="tool0", force=(0.0, 0.0, -10.0))
    q, _, _ = random_states(model, 5, seed=1)
    batch = wrench_torques(model, q, wrench)
    assert batch.shape == (5, 6)
    for k in range(5):
        np.testing.assert_allclose(batch[k], wrench_torques(model, q[k], wrench), rtol=1e-14, atol=1e-14)


def test_payload_defaults_to_the_tip_and_a_point_mass():
    payload = Payload(mass=1.0)
    assert payload_link(load_urdf(urdf_of("ur5")), payload) == "tool0"
    assert payload_link(load_urdf(urdf_of("two_link")), payload) == tip_frame(load_urdf(urdf_of("two_link")))
    np.testing.assert_array_equal(payload.inertia(), np.zeros((3, 3)))
    np.testing.assert_array_equal(Payload(mass=12.0, size=(1, 2, 3)).inertia(), box(12.0, 1, 2, 3))


@pytest.mark.parametrize("make, fragment", [
    (lambda: Payload(mass=-1.0), "payload mass must be a positive number"),
    (lambda: Payload(mass=float("nan")), "payload mass must be a positive number"),
    (lambda: Payload(mass=1.0, com=(0, 0)), "three numbers cx,cy,cz within 1000 m"),
    (lambda: Payload(mass=1.0, size=(1, -1, 1)), "between 0 and 1000 m"),
    (lambda: Wrench(link="tool0", force=(0, float("inf"), 0)), "three finite numbers"),
])
def test_bad_loads_are_refused(make, fragment):
    with pytest.raises(InputError, match=fragment):
        make()


def test_a_payload_on_an_unknown_or_fixed_link_is_refused():
    model = load_urdf(urdf_of("ur5"))
    with pytest.raises(ModelError, match="no link or frame 'flange'"):
        with_payload(model, Payload(mass=1.0, link="flange"))
    with pytest.raises(InputError, match="fixed to the base"):
        with_payload(model, Payload(mass=1.0, link=model.base_link))

"""course_dynamics/core/friction.py: (6.110)–(6.112), URDF defaults, behaviour at zero velocity."""
from __future__ import annotations

import numpy as np
import pytest

from course_dynamics import load_robot
from course_dynamics.core.friction import Friction


def test_viscous_coulomb_and_combined():
    qd = np.array([-2.0, 0.0, 3.0])
    viscous = Friction(viscous=[0.5, 0.5, 0.5], coulomb=[0, 0, 0])
    coulomb = Friction(viscous=[0, 0, 0], coulomb=[1.0, 1.0, 1.0])
    combined = Friction(viscous=[0.5, 0.5, 0.5], coulomb=[1.0, 1.0, 1.0])
    np.testing.assert_array_equal(viscous.torques(qd), [-1.0, 0.0, 1.5])  # (6.110)
    np.testing.assert_array_equal(coulomb.torques(qd), [-1.0, 0.0, 1.0])  # (6.111), sgn(0) = 0
    np.testing.assert_array_equal(combined.torques(qd), [-2.0, 0.0, 2.5])  # (6.112)


def test_friction_opposes_motion_and_batches():
    friction = Friction(viscous=[0.2, 0.1], coulomb=[0.3, 0.4], smoothing=0.01)
    qd = np.random.default_rng(0).standard_normal((50, 2))
    F = friction.torques(qd)
    assert F.shape == (50, 2)
    assert np.all(F * qd >= 0)  # F is subtracted from τ: it always takes energy out


def test_smoothing_is_tanh():
    friction = Friction(viscous=[0.0], coulomb=[2.0], smoothing=0.1)
    assert friction.torques([0.05])[0] == pytest.approx(2.0 * np.tanh(0.5))


def test_defaults_come_from_urdf_dynamics():
    """Viscous and Coulomb coefficients as Pinocchio's own URDF parser reads <dynamics damping friction>."""
    from course_dynamics_reference.pinocchio_oracle import PinocchioOracle

    from course_dynamics import robot_path

    model = load_robot("panda")
    oracle = PinocchioOracle(robot_path("panda"), model.joint_names)
    friction = Friction.from_urdf(model)
    np.testing.assert_array_equal(friction.viscous, oracle.damping)
    np.testing.assert_array_equal(friction.coulomb, oracle.friction)
    # <dynamics damping="0.3"/> on both fingers: panda_finger_joint2 mimics joint1 (multiplier 1), so its damping
    # acts on joint1's coordinate too
    assert friction.viscous[-1] == 0.6 and model.joint_names[-1] == "panda_finger_joint1"
    np.testing.assert_array_equal(Friction.none(model).coulomb, 0)


@pytest.mark.parametrize("bad", [{"viscous": [-1.0]}, {"coulomb": [float("nan")]}, {"smoothing": float("inf")},
                                 {"smoothing": float("nan")}, {"smoothing": -0.1}])
def test_bad_coefficients(bad):
    values = {"viscous": [0.0], "coulomb": [0.0], **bad}
    with pytest.raises(ValueError, match="finite and non-negative"):
        Friction(**values)


@pytest.mark.parametrize("smoothing", [0.0, 0.01, 0.3])
def test_slope_is_the_steepest_derivative_of_the_torques(smoothing):
    """v + c / smoothing: F's derivative at θ̇ = 0, where tanh is steepest (no steeper chord anywhere); v for
    sgn, whose slope beside its jump is the viscous part's."""
    friction = Friction(viscous=[0.2, 0.0, 1.5], coulomb=[0.5, 2.0, 0.0], smoothing=smoothing)
    at, h = np.full(3, 0.0 if smoothing else 0.1), 1e-9
    numeric = (friction.torques(at + h) - friction.torques(at - h)) / (2 * h)
    # 1e-6: beside sgn's jump F is about c, so the quotient's round-off is eps · c / h, 1e-6 of a slope of 0.2
    np.testing.assert_allclose(friction.slope(), numeric, rtol=1e-6)
    speeds = np.linspace(0.001, 1.0, 1000)[:, None] * np.array([-1.0, 1.0])[:, None, None]  # either side of 0
    chords = np.abs(np.diff(friction.torques(speeds), axis=1) / np.diff(speeds, axis=1))
    assert np.all(chords <= friction.slope() * (1 + 1e-9)), chords.max(axis=(0, 1))

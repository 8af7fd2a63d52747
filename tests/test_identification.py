"""course_dynamics/tools/identification.py: from a robot's log to the parameters it really has.

The "true robot" is a UR5 whose URDF is wrong in the ways real ones are: masses off by up to ±20 %,
centres of mass moved by up to 2 cm, inertias scaled by up to ±30 %, and joint friction the URDF
does not have (viscous and Coulomb). Its log is a multi-sine motion (``logmakers.multisine``) with
the recorder's noise: q ± 1e-5 rad, q̇ ± 1e-3 rad/s, τ_meas ± σⱼ = 1 % of each joint's RMS torque;
Θ̈ is differentiated from the noisy q̇ as for any log. The identified model is judged on another
motion (another seed) against the true robot's noiseless torques.

Log length: 60 s at 100 Hz, or 15 s at 100 Hz when the environment says CI=true (the assertions are
the same; on this machine the 60 s log is identified in about 3 s, the 15 s one in about 1 s).
"""
from __future__ import annotations

import os
import sys
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
from logmakers import multisine, noisy

from course_dynamics import load_robot
from course_dynamics.base.errors import InputError
from course_dynamics.core.friction import Friction
from course_dynamics.core.inertia import box, physical_problems
from course_dynamics.core.newton_euler import inverse_dynamics
from course_dynamics.core.regressor import parameters
from course_dynamics.output.render import json_text
from course_dynamics.tools.identification import identify, pseudo_inertia
from course_dynamics.tools.logs import joint_log

DURATION = 15.0 if os.environ.get("CI") == "true" else 60.0   # s of log
RATE = 100.0                                                  # Hz
NOISE_Q, NOISE_QD, NOISE_TAU = 1e-5, 1e-3, 0.01              # rad, rad/s, share of each joint's RMS torque


def true_robot(model, seed: int = 0):
    """``model`` as the robot really is (module docstring): (the true model, its friction)."""
    rng = np.random.default_rng(seed)
    bodies = tuple(replace(b, mass=b.mass * rng.uniform(0.8, 1.2),
                           p_com=b.p_com + rng.uniform(-1, 1, 3) * 0.02 / np.sqrt(3),   # |Δc| ≤ 2 cm
                           I_com=b.I_com * rng.uniform(0.7, 1.3)) for b in model.bodies)
    effort = np.where(np.isfinite(model.effort), model.effort, 10.0)
    friction = Friction(viscous=rng.uniform(0.5, 1.5, model.n) * effort / 50,    # N m s/rad: 1.5–4.5 big, 0.3–0.8 wrists
                        coulomb=rng.uniform(0.5, 1.5, model.n) * effort / 30)    # N m: 2.5–7.5 big joints, 0.5–1.4 wrists
    return replace(model, bodies=bodies), friction


def true_torques(true, friction, motion):
    return inverse_dynamics(true, motion.q, motion.qd, motion.qdd) + friction.torques(motion.qd)


def log_columns(model, true, friction, duration=DURATION, seed=1, exact=False, noise_qd=NOISE_QD):
    """A log of the true robot as our column names: t, q_, qd_ (noisy; with ``exact`` also exact qdd_), tau_meas_.

    Returns (columns, σⱼ of the torque noise)."""
    motion = multisine(model, duration=duration, rate=RATE, seed=seed)
    tau = true_torques(true, friction, motion)
    sigma = NOISE_TAU * np.sqrt(np.mean(tau**2, axis=0))
    measured = noisy(tau, sigma, seed + 1)
    q, qd = (motion.q, motion.qd) if exact else (noisy(motion.q, NOISE_Q, seed + 2), noisy(motion.qd, noise_qd, seed + 3))
    columns = {"t": motion.t}
    for j, joint in enumerate(model.joint_names):
        columns |= {f"q_{joint}": q[:, j], f"qd_{joint}": qd[:, j], f"tau_meas_{joint}": measured[:, j]}
        if exact:
            columns[f"qdd_{joint}"] = motion.qdd[:, j]
    return columns, sigma


@pytest.fixture(scope="module")
def ur5_case():
    """The UR5 case, identified once: (urdf model, true model, true friction, σⱼ, identification)."""
    ur5 = load_robot("ur5")
    true, friction = true_robot(ur5)
    columns, sigma = log_columns(ur5, true, friction)
    return ur5, true, friction, sigma, identify(ur5, joint_log(ur5, columns))


def test_the_identified_model_predicts_another_motion_within_the_noise(ur5_case):
    ur5, true, friction, sigma, found = ur5_case
    other = multisine(ur5, duration=8.0, rate=RATE, seed=7)
    tau = true_torques(true, friction, other)
    identified = inverse_dynamics(found.model, other.q, other.qd, other.qdd) + found.friction.torques(other.qd)
    urdf = inverse_dynamics(ur5, other.q, other.qd, other.qdd) + Friction.from_urdf(ur5).torques(other.qd)
    error = np.mean(np.sqrt(np.mean((identified - tau) ** 2, axis=0)) / sigma)   # RMS / σⱼ, averaged over joints
    error_urdf = np.mean(np.sqrt(np.mean((urdf - tau) ** 2, axis=0)) / sigma)
    assert error <= 1.5, error                  # measured: 0.26 (60 s), 0.37 (15 s)
    assert error_urdf >= 5 * error, (error_urdf, error)   # measured: 232× (60 s), 163× (15 s)


def test_every_identified_body_is_physically_consistent(ur5_case):
    ur5, _, _, _, found = ur5_case
    for i, body in enumerate(found.model.bodies):
        J = pseudo_inertia(found.pi[10 * i:10 * i + 10])
        assert np.linalg.eigvalsh(J).min() >= -1e-12 * np.abs(J).max(), body.name
        assert physical_problems(body.I_com) == [] and body.mass >= 0.01 * ur5.bodies[i].mass, body.name
    assert np.all(found.friction.viscous >= 0) and np.all(found.friction.coulomb >= 0)
    np.testing.assert_allclose(parameters(found.model), found.pi[:60], rtol=1e-12, atol=1e-15)


def test_friction_is_found_and_the_held_out_part_of_the_log_improves(ur5_case):
    _, _, friction, sigma, found = ur5_case
    np.testing.assert_allclose(found.friction.viscous, friction.viscous, rtol=0.25)   # measured: within 14 %
    np.testing.assert_allclose(found.friction.coulomb, friction.coulomb, rtol=0.1)    # measured: within 3 %
    assert np.all(found.rms_after < found.rms_before / 5)
    fitted, held = found.samples
    assert abs(held / (fitted + held) - 0.2) < 0.01 and found.held_out[0].min() >= found.split_t
    assert found.solver == "clarabel" and 1 <= found.condition_number < 100     # measured: 22
    assert found.unexcited == () and "m_1" in found.never_act


def test_standard_errors_describe_the_scatter_of_the_least_squares_estimate():
    """With exact states in the log (only τ_meas noisy) the errors of the weighted fit are σ-sized."""
    ur5 = load_robot("ur5")
    true, friction = true_robot(ur5)
    columns, sigma = log_columns(ur5, true, friction, duration=15.0, exact=True)
    found = identify(ur5, joint_log(ur5, columns))
    np.testing.assert_allclose(found.sigma, sigma, rtol=0.15)     # σⱼ from the first fit's residual
    truth = np.concatenate([found.base.values(parameters(true)),
                            np.ravel(np.column_stack([friction.viscous, friction.coulomb]))])
    z = (found.base_wls - truth) / found.base_error
    assert np.abs(z).max() < 4.5 and 0.6 < np.sqrt(np.mean(z**2)) < 1.5, z      # measured: max 2.0, RMS 0.88


def test_what_the_log_does_not_excite_stays_at_the_urdf_values():
    """A two-link arm logged at rest in many poses: gravity reveals the first moments, nothing the inertias.

    The true arm's first link is 2.4 kg (not 2), its second a 1 kg box of 0.3 m sides (not a point mass)."""
    arm = load_robot("two_link")
    true = replace(arm, bodies=(replace(arm.bodies[0], mass=2.4), replace(arm.bodies[1], I_com=box(1.0, 0.3, 0.3, 0.3))))
    q = multisine(arm, duration=8.0, rate=50.0, seed=3).q
    zero = np.zeros_like(q)
    tau = inverse_dynamics(true, q, zero, zero)
    columns = {"t": np.arange(len(q)) / 50.0}
    for j, joint in enumerate(arm.joint_names):
        columns |= {f"q_{joint}": q[:, j], f"qd_{joint}": zero[:, j], f"qdd_{joint}": zero[:, j],
                    f"tau_meas_{joint}": tau[:, j]}
    found = identify(arm, joint_log(arm, columns), friction="none")
    lines = found.base.describe().splitlines()
    assert lines[0] == "π_b1 = mcx_1 + 0.5 m_2" and lines[5] == "π_b6 = Izz_2"
    assert found.base_consistent[0] == pytest.approx(2.4 * 0.5 + 0.5, rel=1e-4)    # from gravity
    assert found.base_consistent[5] == pytest.approx(found.base_urdf[5], rel=1e-3)  # Izz₂ = 0.16: not excited, kept
    assert found.base_consistent[5] < 0.175 - 0.01                                  # (the truth is 0.175)
    assert any("π_b6" in combination for _, combination in found.unexcited)
    assert found.condition_number > 1e3


def test_friction_models_identify_only_what_they_name():
    ur5 = load_robot("ur5")
    true, friction = true_robot(ur5)
    columns, _ = log_columns(ur5, true, replace(friction, coulomb=np.zeros(6)), duration=10.0)
    log = joint_log(ur5, columns)
    viscous = identify(ur5, log, friction="viscous")
    assert viscous.names[-6:] == tuple(f"Fv_{j}" for j in ur5.joint_names)
    np.testing.assert_array_equal(viscous.friction.coulomb, np.zeros(6))      # the URDF's, kept
    np.testing.assert_allclose(viscous.friction.viscous, friction.viscous, rtol=0.25)
    none = identify(ur5, log, friction="none")
    assert len(none.names) == 60 and not none.friction.viscous.any() and not none.friction.coulomb.any()


def test_progress_and_json(ur5_case):
    ur5 = load_robot("ur5")
    true, friction = true_robot(ur5)
    columns, _ = log_columns(ur5, true, friction, duration=5.0)
    calls = []
    found = identify(ur5, joint_log(ur5, columns), holdout=0.0, progress=lambda done, total: calls.append((done, total)))
    assert calls[-1][0] == calls[-1][1] == len(columns["t"]) and found.samples[1] == 0
    assert np.all(np.isnan(found.rms_after))
    record = ur5_case[-1].record()
    assert '"held_out_rms"' in json_text(record) and len(record["base_parameters"]) == 36 + 12
    assert record["held_out_rms"]["urdf"]["elbow_joint"] > record["held_out_rms"]["identified"]["elbow_joint"]


def test_pseudo_inertia_is_positive_semi_definite_exactly_for_real_bodies():
    arm = load_robot("two_link")
    pi = parameters(replace(arm, bodies=(arm.bodies[0], replace(arm.bodies[1], I_com=box(1.0, 0.1, 0.2, 0.3)))))
    assert np.linalg.eigvalsh(pseudo_inertia(pi[10:20])).min() > 0
    broken = pi.copy()
    broken[19] += 0.2   # Izz about the origin up by 0.2 kg m²: Izz > Ixx + Iyy about the centre of mass
    assert np.linalg.eigvalsh(pseudo_inertia(broken[10:20])).min() < 0


@pytest.mark.parametrize("change, fragments", [
    (dict(friction="dry"), ["unknown friction model 'dry'"]),
    (dict(holdout=1.0), ["held-out share", "less than 1"]),
    (dict(prior_weight=-1.0), ["prior weight"]),
])
def test_bad_options(change, fragments):
    arm = load_robot("two_link")
    columns, _ = log_columns(arm, arm, Friction.none(arm), duration=2.0)
    with pytest.raises(InputError) as caught:
        identify(arm, joint_log(arm, columns), **change)
    assert all(f in str(caught.value) for f in fragments)


def test_a_log_without_measured_torques_says_which_columns_are_needed():
    arm = load_robot("two_link")
    columns, _ = log_columns(arm, arm, Friction.none(arm), duration=2.0)
    positions = {k: v for k, v in columns.items() if not k.startswith("tau_meas_")}
    with pytest.raises(InputError, match="no measured torques.*tau_meas_theta1"):
        identify(arm, joint_log(arm, positions), where="arm.csv")


def test_a_log_too_short_for_the_parameters_is_refused():
    ur5 = load_robot("ur5")
    columns, _ = log_columns(ur5, ur5, Friction.none(ur5), duration=0.1)
    with pytest.raises(InputError, match="too few for 48 base parameters"):
        identify(ur5, joint_log(ur5, columns))


def test_without_cvxpy_the_message_says_what_to_install(monkeypatch):
    arm = load_robot("two_link")
    columns, _ = log_columns(arm, arm, Friction.none(arm), duration=2.0)
    monkeypatch.setitem(sys.modules, "cvxpy", None)   # import cvxpy now raises ImportError
    with pytest.raises(InputError, match=r"course-dynamics\[identify\]"):
        identify(arm, joint_log(arm, columns))


def test_a_joint_without_measured_torque_is_left_out():
    ur5 = load_robot("ur5")
    true, friction = true_robot(ur5)
    columns, _ = log_columns(ur5, true, friction, duration=5.0)
    del columns["tau_meas_wrist_3_joint"]
    found = identify(ur5, joint_log(ur5, columns))
    assert found.notes == ("joint 'wrist_3_joint' has no measured torque: its rows are left out",)
    assert np.isnan(found.sigma[5]) and np.isnan(found.rms_after[5]) and np.all(found.rms_after[:5] < found.rms_before[:5])
    assert "Fv_wrist_3_joint" not in found.names and found.friction.viscous[5] == 0.0     # the URDF's


def test_a_short_log_keeps_factors_of_its_own_length_and_moves_the_bar_per_joint():
    """R_j has as many rows as the samples (at most P + 1), so a short log on many joints costs what its samples do;
    R_jᵀ R_j is still [Yⱼ | τⱼ]ᵀ [Yⱼ | τⱼ]."""
    from course_dynamics.tools.identification import _design, _factors, memory_needed

    model = load_robot("ur5")
    rng = np.random.default_rng(3)
    log = SimpleNamespace(**{name: rng.uniform(-1, 1, (30, 6)) for name in ("q", "qd", "qdd")})
    target, rows, measured, columns = rng.standard_normal((30, 6)), np.arange(30), [0, 2, 5], [("viscous", 0)]
    calls = []
    R = _factors(model, log, rows, columns, target, measured, lambda done, total: calls.append((done, total)))
    assert R.shape == (3, 30, 62)
    assert calls == [(10, 30), (20, 30), (30, 30)]
    A = _design(model, log, rows, columns)
    for k, j in enumerate(measured):
        stacked = np.column_stack([A[:, j], target[:, j]])
        np.testing.assert_allclose(R[k].T @ R[k], stacked.T @ stacked, rtol=1e-12,
                                   atol=1e-12 * np.abs(stacked).max() ** 2)
    assert memory_needed(200, 2400, 3000, 200) > 10 * memory_needed(200, 2400, 30, 200)   # the log's length counts


def with_datasheet_friction(model, viscous, coulomb):
    """``model`` with every joint's <dynamics damping friction> set (a datasheet's values)."""
    return replace(model, bodies=tuple(replace(b, damping=viscous, friction=coulomb) for b in model.bodies))


def null_space_part(found, log):
    """The change θ − θ_URDF of the free parameters, in scale units, projected on the null space of the fitted rows'
    regressor (Y and its friction columns), and the size of θ_URDF in the same units."""
    from course_dynamics.tools.identification import _design, _friction_columns

    rows = np.flatnonzero(log.t < found.split_t)
    measured = [j for j in range(found.model.n) if np.isfinite(found.sigma[j])]
    columns = _friction_columns(found.friction_model, measured)
    A = _design(found.original, log, rows, columns)[:, measured, :].reshape(-1, len(found.names)) * found.scale
    _, s, Vt = np.linalg.svd(A, full_matrices=False)     # more rows than columns: Vt is square
    null = Vt[s < 1e-10 * s[0]]
    change = (found.pi - found.pi_urdf) / found.scale
    return null @ change, np.linalg.norm(found.pi_urdf / found.scale)


def test_what_the_log_cannot_see_is_the_urdfs_and_friction_is_the_logs_whatever_the_datasheet_says():
    """The robot's bodies are its URDF's, its friction is not: with the datasheet's friction in the URDF (2 and 1) or
    none, F_v and F_c come out within 10 %; with no physical constraint active, the estimate's part in the
    regressor's null space is the URDF's to 1e-9. Rates from an encoder, q̇ ± 1e-4 rad/s (at 1e-3 rad/s, Θ̈
    differentiated from q̇ biases least squares itself: the elbow's F_v by 13 %, with or without the prior)."""
    ur5 = load_robot("ur5")
    _, friction = true_robot(ur5)
    columns, _ = log_columns(ur5, ur5, friction, duration=15.0, noise_qd=1e-4)
    for urdf in (ur5, with_datasheet_friction(ur5, 2.0, 1.0)):
        log = joint_log(urdf, columns)
        found = identify(urdf, log)
        np.testing.assert_allclose(found.friction.viscous, friction.viscous, rtol=0.1)
        np.testing.assert_allclose(found.friction.coulomb, friction.coulomb, rtol=0.1)
        assert found.active == () and found.moved == 0.0 and found.far == ()
        part, size = null_space_part(found, log)
        assert len(part) >= 24 and np.abs(part).max() <= 1e-9 * size, np.abs(part).max() / size


def test_identified_bodies_stay_plausible_and_active_constraints_are_named(ur5_case):
    """The perturbed UR5: total mass within ±50 % of the URDF's, every centre of mass within its link; where a body
    is physical only with what the log cannot see moved, the report names it."""
    from course_dynamics.tools.plausibility import link_extents

    ur5, _, _, _, found = ur5_case
    total, total_urdf = (sum(float(b.mass) for b in m.bodies) for m in (found.model, ur5))
    assert 0.5 * total_urdf <= total <= 1.5 * total_urdf
    extents = link_extents(ur5)
    assert all(np.linalg.norm(b.p_com) <= e for b, e in zip(found.model.bodies, extents)) and found.far == ()
    named = [line for line in found.active if "does not see moved" in line]
    assert (found.moved > 0) == bool(named)
    part, size = null_space_part(found, joint_log(ur5, log_columns(ur5, *true_robot(ur5))[0]))
    if not named:
        assert np.abs(part).max() <= 1e-9 * size
    summary = {b["body"]: b for b in found.record()["bodies"]}
    assert "m_1" in summary["shoulder_link"]["kept"] and summary["wrist_3_link"]["warnings"] == []


def test_a_joint_held_still_is_a_fixed_joint_and_its_body_is_left_as_the_urdf_has_it():
    """UR5 with its wrist 3 held at 0.3 rad through the log (as ``--set q_wrist_3_joint=0.3`` holds it): no parameters
    of wrist_3_link, no warnings about them, a sane condition number."""
    ur5 = load_robot("ur5")
    true, friction = true_robot(ur5)
    columns, _ = log_columns(ur5, true, friction, duration=10.0)
    columns["q_wrist_3_joint"] = np.full_like(columns["t"], 0.3)
    columns["qd_wrist_3_joint"] = np.zeros_like(columns["t"])
    found = identify(ur5, joint_log(ur5, columns))
    assert found.held == ("wrist_3_joint",) and any("held at 0.3" in note for note in found.notes)
    np.testing.assert_array_equal(found.pi[50:60], found.pi_urdf[50:60])
    wrist, urdf = found.model.bodies[5], ur5.bodies[5]
    assert wrist.mass == urdf.mass and np.array_equal(wrist.p_com, urdf.p_com) and np.array_equal(wrist.I_com, urdf.I_com)
    assert not any("_6" in combination for _, combination in found.unexcited)
    assert found.condition_number < 1e3 and "Fv_wrist_3_joint" not in found.names


def test_bodies_that_move_far_are_named():
    """With no divergence and every direction free (threshold 0), the directions the log cannot see run off (kg by
    the hundred on a 17 kg arm) and each such body is named; at the defaults every body stays plausible."""
    ur5 = load_robot("ur5")
    true, friction = true_robot(ur5)
    log = joint_log(ur5, log_columns(ur5, true, friction, duration=10.0)[0])
    loose = identify(ur5, log, prior_weight=0.0, threshold=0.0)
    named = {line.split("'")[1] for line in loose.far}
    heavy = {b.name for b, b0 in zip(loose.model.bodies, ur5.bodies) if not 0.5 <= b.mass / b0.mass <= 2}
    assert heavy and heavy <= named
    assert {b["body"] for b in loose.record()["bodies"] if b["warnings"]} == named
    assert identify(ur5, log).far == ()

"""Shared fixtures: every robot the tests check, its Pinocchio oracle, and seeded states.

Reference values come only from here: Pinocchio (reference/pinocchio_oracle.py)
evaluated on the same URDF, never numbers copied into a test.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from course_dynamics import load_urdf
from course_dynamics.robots import robot_names, robot_path
from reference.pinocchio_oracle import PinocchioOracle
from reference.validate import random_states

DATA = Path(__file__).parent / "data"
AWKWARD = DATA / "awkward.urdf"
SAMPLES = 200  # random states per robot, as the issue asks
RTOL = 1e-9  # agreement with Pinocchio, relative

CHECKED_ROBOTS = list(robot_names()) + ["awkward"]


def urdf_of(name: str) -> Path:
    return AWKWARD if name == "awkward" else robot_path(name)


@pytest.fixture(scope="module", params=CHECKED_ROBOTS)
def robot(request):
    """(name, model, oracle, states) for each robot, built once per test module."""
    path = urdf_of(request.param)
    model = load_urdf(path)
    oracle = PinocchioOracle(path, model.joint_names, model.gravity)
    q, qd, qdd = random_states(model, SAMPLES, seed=sum(map(ord, request.param)))
    return request.param, model, oracle, (q, qd, qdd)


def assert_agrees(ours, ref, scale=None, rtol=RTOL, what=""):
    """|ours − ref|∞ ≤ rtol · max(|ref|∞, scale): relative, floored at the term's natural scale."""
    ours, ref = np.asarray(ours), np.asarray(ref)
    assert ours.shape == ref.shape, f"{what}: shape {ours.shape} vs {ref.shape}"
    denominator = max(float(np.abs(ref).max()), scale or 0.0, np.finfo(float).tiny)
    error = float(np.abs(ours - ref).max()) / denominator
    assert error <= rtol, f"{what}: relative error {error:.3e} > {rtol:g}"

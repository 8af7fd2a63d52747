"""Fixtures: every robot the tests check, with its Pinocchio oracle and seeded states.

Shared helpers (the agreement assertion, URDF builders) are in ``helpers.py``.
"""
from __future__ import annotations

import os
import tempfile

import pytest

# Compiled models go to a cache of the test session's own, not the user's.
SESSION_CACHE = tempfile.mkdtemp(prefix="course-dynamics-test-cache-")
os.environ.setdefault("COURSE_DYNAMICS_CACHE", SESSION_CACHE)

from course_dynamics_reference.pinocchio_oracle import PinocchioOracle
from course_dynamics_reference.validate import random_states
from helpers import CHECKED_ROBOTS, SAMPLES, urdf_of

from course_dynamics import load_urdf


@pytest.fixture(scope="module", params=CHECKED_ROBOTS)
def robot(request):
    """(name, model, oracle, states) for each robot, built once per test module."""
    path = urdf_of(request.param)
    model = load_urdf(path)
    oracle = PinocchioOracle(path, model.joint_names, model.gravity)
    q, qd, qdd = random_states(model, SAMPLES, seed=sum(map(ord, request.param)))
    return request.param, model, oracle, (q, qd, qdd)


@pytest.fixture(scope="session")
def browser():
    """Debian's Chromium, headless, driven by Playwright (its own browser download is never used)."""
    from pathlib import Path

    from helpers import CHROMIUM, CHROMIUM_ARGS

    if not Path(CHROMIUM).exists():
        pytest.fail(f"{CHROMIUM} is missing: run the README's test command, which installs Debian's chromium")
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield browser
        browser.close()


def pytest_sessionfinish(session, exitstatus):
    import shutil

    shutil.rmtree(SESSION_CACHE, ignore_errors=True)

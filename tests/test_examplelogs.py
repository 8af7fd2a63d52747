"""The sample logs in examples/ are what the tests' generators write (tests/examplelogs.py), and each reads."""
from __future__ import annotations

import numpy as np
import pytest
from bagmakers import FRANKA_TOPIC
from examplelogs import EXAMPLES, NAMES, write_examples

from course_dynamics import load_robot
from course_dynamics.tools.sources import open_log


@pytest.fixture(scope="module")
def fresh(tmp_path_factory):
    return write_examples(tmp_path_factory.mktemp("examples"))


@pytest.mark.parametrize("name", NAMES)
def test_each_example_is_what_the_generators_write_today(fresh, name):
    robot = load_robot("panda" if name.startswith("panda") else "ur5")
    topic = FRANKA_TOPIC if name.startswith("panda") else None          # a Franka bag holds two joint-state topics
    committed = open_log(EXAMPLES / name, robot, topic=topic)
    regenerated = open_log(fresh[name.replace(".csv", "")], robot, topic=topic)
    assert committed.format == regenerated.format and committed.implied == regenerated.implied
    assert set(committed.columns) == set(regenerated.columns)
    for column, values in committed.columns.items():
        # The same numbers but for the last bits of the column's largest: a torque the generator computes goes
        # through numpy's own arithmetic, whose rounding differs between builds (numpy 2.4 moves 15 of the Franka
        # bag's 808 torques by up to 2 units of the last place of their column's largest); any change of the
        # generators' code moves far more.
        bits = 4 * np.finfo(float).eps * np.abs(values).max() if np.issubdtype(values.dtype, np.floating) else 0
        np.testing.assert_allclose(values, regenerated.columns[column], rtol=0, atol=bits, err_msg=f"{name}: {column}")

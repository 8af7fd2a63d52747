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
        np.testing.assert_array_equal(values, regenerated.columns[column], err_msg=f"{name}: {column}")

"""The memory budget and its override (course_dynamics.base.resources): COURSE_DYNAMICS_MEMORY_BUDGET."""
from __future__ import annotations

import os

import numpy as np
import pytest
from helpers import assert_one_line_error, run

import bagmakers
from course_dynamics import load_robot
from course_dynamics.base.errors import InputError
from course_dynamics.base.resources import BUDGET_VARIABLE, check_memory, memory_budget, parse_budget


def test_without_the_variable_the_budget_is_half_the_physical_memory(monkeypatch):
    monkeypatch.delenv(BUDGET_VARIABLE, raising=False)
    assert memory_budget() == os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE") // 2
    monkeypatch.setenv(BUDGET_VARIABLE, "  ")
    assert memory_budget() == os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE") // 2


@pytest.mark.parametrize("text, budget", [("4096", 4096), ("512M", 512 * 2**20), ("512 MiB", 512 * 2**20),
                                          ("1.5g", 3 * 2**29), ("2T", 2 * 2**40), ("8k", 8192)])
def test_the_variable_sets_the_budget(monkeypatch, text, budget):
    monkeypatch.setenv(BUDGET_VARIABLE, text)
    assert memory_budget() == budget == parse_budget(text)


@pytest.mark.parametrize("text", ["lots", "0", "-1", "1e9", "12Q", "0.5", "512MB", "9" * 400, "1,5G"])
def test_a_value_that_is_no_budget_is_one_error_naming_the_variable(monkeypatch, text):
    monkeypatch.setenv(BUDGET_VARIABLE, text)
    with pytest.raises(InputError, match=f"^{BUDGET_VARIABLE}='.*': not a memory budget; give bytes, or a number "
                                         "with K, M, G or T"):
        memory_budget()


def test_the_refusal_names_the_budget_the_variable_sets(monkeypatch):
    monkeypatch.setenv(BUDGET_VARIABLE, "1M")
    with pytest.raises(InputError, match=f"^grid would need about 2 MiB of memory, more than the 1 MiB that "
                                         f"{BUDGET_VARIABLE} allows$"):
        check_memory(2**21, "grid")
    monkeypatch.delenv(BUDGET_VARIABLE)
    with pytest.raises(InputError, match="more than half of this machine's"):
        check_memory(1e30, "grid")


def test_the_command_line_reports_a_bad_budget_in_one_line(capsys, tmp_path, monkeypatch):
    joints = load_robot("ur5").joint_names
    t, q = 1_700_000_000.0 + 0.002 * np.arange(20), np.zeros((20, 6))
    bag = bagmakers.write_joint_states(tmp_path / "run", "ros1", joints, t, q, q, q)
    out = tmp_path / "tau.csv"
    monkeypatch.setenv(BUDGET_VARIABLE, "half")
    code, _, err = run(capsys, "torques", "ur5", "--log", str(bag), "--out", str(out))
    assert_one_line_error(code, err, f"error: {BUDGET_VARIABLE}='half': not a memory budget")
    assert not out.exists()
    monkeypatch.setenv(BUDGET_VARIABLE, "64M")
    code, _, err = run(capsys, "torques", "ur5", "--log", str(bag), "--out", str(out))
    assert code == 0 and out.exists(), err

"""benchmarks/: the scripts run and print their comparisons (tiny sizes; no timing is asserted)."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parent.parent / "benchmarks"


@pytest.mark.parametrize("script, args, expected", [
    ("bench_performance.py", ["--batch", "20", "--repeat", "1", "--duration", "0.01", "--members", "3", "--chains", "4"],
     "one ensemble, compiled / aba for every member"),
    ("bench_symbolic.py", ["--robots", "rp_arm"], "rp_arm"),
    ("bench_torques.py", ["--rows", "500", "--repeat", "1"], "tau stage, ours / Pinocchio"),
    ("bench_regressor.py", ["--batch", "10", "--repeat", "1", "--robots", "two_link"],
     "Y / pin.computeJointTorqueRegressor"),
])
def test_benchmark_runs(script, args, expected):
    result = subprocess.run([sys.executable, str(BENCHMARKS / script), *args], capture_output=True, text=True,
                            cwd=BENCHMARKS.parent)
    assert result.returncode == 0, result.stderr
    assert expected in result.stdout

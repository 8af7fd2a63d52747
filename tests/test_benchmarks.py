"""benchmarks/: the scripts run and print their comparisons (tiny sizes; no timing is asserted), each row with the
threads both sides ran on, and the machine's threads (cores, our batch threading, numpy's BLAS) up front."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parent.parent / "benchmarks"


@pytest.mark.parametrize("script, args, expected", [
    ("bench_performance.py", ["--batch", "20", "--repeat", "1", "--calls", "200", "--duration", "0.01", "--members", "3",
                              "--chains", "4", "--memory", "100,100", "--loop", "10"],
     ["one ensemble, compiled / a loop of RK4 on pin.aba for every member", "ours 1 thread / pin 1 thread",
      "/ rneaInParallel(2)", "≈ C++", "/ mj_inverse", "mujoco.rollout RK4", "peak memory / the size of its output",
      "target ≤ 4", "a fresh process, empty cache", "10 one-state τ calls", "chain of 4: batch τ / rneaInParallel(1)",
      "limits='stop') into the limits", "integrator='adaptive') / simulate(…, dt=2e-4)"]),
    ("bench_symbolic.py", ["--robots", "rp_arm"], ["rp_arm", "ours on 1 thread"]),
    ("bench_torques.py", ["--rows", "500", "--repeat", "1"],
     ["tau stage, ours / Pinocchio (ours 1 thread / pin 1 thread)", "pin 2 threads"]),
    ("bench_regressor.py", ["--batch", "10", "--repeat", "1", "--robots", "two_link"],
     ["Y / pin.computeJointTorqueRegressor from Python", "Y / our interpreted τ", "ours 1 thread / pin 1 thread",
      "one state: compile_model(…).regressor / pin.computeJointTorqueRegressor", "target ≤ 3", "target ≤ 1"]),
    ("bench_tools.py", ["--repeat", "1"],
     ["course-dynamics identify / plain_identify.py", "held-out RMS residual", "excite ur5 --duration 10",
      "target ≤ 1.5", "target ≤ 10"]),
])
def test_benchmark_runs(script, args, expected):
    result = subprocess.run([sys.executable, str(BENCHMARKS / script), *args], capture_output=True, text=True,
                            cwd=BENCHMARKS.parent)
    assert result.returncode == 0, result.stderr
    for text in expected + ["numpy's BLAS", "cores, load average"]:
        assert text in result.stdout, text

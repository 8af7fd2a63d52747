"""benchmarks/: the scripts run and print their comparisons (tiny sizes; no timing is asserted)."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parent.parent / "benchmarks"


@pytest.mark.parametrize("script, args, expected", [
    ("bench_inverse_dynamics.py", ["--batch", "50", "--repeat", "1"], "rneaInPar(1)"),
    ("bench_simulation.py", ["--duration", "0.02"], "ratio (ours / aba)"),
    ("bench_symbolic.py", ["--robots", "rp_arm"], "rp_arm"),
])
def test_benchmark_runs(script, args, expected):
    result = subprocess.run([sys.executable, str(BENCHMARKS / script), *args], capture_output=True, text=True,
                            cwd=BENCHMARKS.parent)
    assert result.returncode == 0, result.stderr
    assert expected in result.stdout

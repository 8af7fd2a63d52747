"""Whole commands a user runs, timed beside what a Pinocchio user writes for the same job, in one run.

Run:  python benchmarks/bench_tools.py [--repeat 3]

Every figure is the best of --repeat runs of a fresh process (the compiled-model cache warm, as after a first
run), each beside its target:

1. ``course-dynamics identify ur5 --log examples/ur5_joint_states.mcap`` (the README's) against
   ``benchmarks/plain_identify.py``, the script a Pinocchio user writes: rosbags to read the messages, a
   Savitzky–Golay derivative, ``pin.computeJointTorqueRegressor`` stacked with friction columns,
   ``numpy.linalg.lstsq``; and the held-out error of each, the mean over joints of the per-joint RMS ratio;
2. ``course-dynamics excite ur5 --duration 10`` with its defaults, in seconds.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from course_dynamics import robot_path

from measure import best, print_conditions, print_load  # this folder is on the path

ROOT = Path(__file__).resolve().parent.parent
LOG = ROOT / "examples" / "ur5_joint_states.mcap"
TARGETS = {"identify": 1.5, "error": 1.0, "excite": 10.0}


def verdict(value: float, target: str) -> str:
    return f"target ≤ {TARGETS[target]:g}: {'met' if value <= TARGETS[target] else 'NOT met'}"


def command(*words: str) -> list[str]:
    return [sys.executable, "-m", "course_dynamics.cli", *words]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    r = args.repeat
    print_conditions(f"whole commands, best of {r} fresh processes; ratio = ours / the plain script's")
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder)
        ours_identify = command("identify", "ur5", "--log", str(LOG), "--out", str(out / "id.urdf"), "--json")
        plain = [sys.executable, str(ROOT / "benchmarks" / "plain_identify.py"), str(robot_path("ur5")), str(LOG)]
        subprocess.run(ours_identify, capture_output=True, check=True)       # the compiled model into the cache
        ours = best(lambda: subprocess.run(ours_identify, capture_output=True, check=True), r)
        theirs = best(lambda: subprocess.run(plain, capture_output=True, check=True), r)
        print("1. identify on the README's MCAP log (s; one process each, 1 thread of Python)")
        print(f"  {'course-dynamics identify / plain_identify.py':<58} {ours:>8.3g} {theirs:>8.3g} s "
              f"{ours / theirs:>6.2f}  {verdict(ours / theirs, 'identify')}")
        found = json.loads(subprocess.run(ours_identify, capture_output=True, check=True, text=True).stdout)
        script = json.loads(subprocess.run(plain, capture_output=True, check=True, text=True).stdout)
        ours_rms = np.array([found["held_out_rms"]["identified"][j] for j in script["joints"]])
        ratio = float(np.mean(ours_rms / np.array(script["held_out_rms"])))
        print(f"  {'held-out RMS residual, mean over joints of ours / theirs':<58} {ratio:>24.2f}  "
              f"{verdict(ratio, 'error')}")
        excite = command("excite", "ur5", "--duration", "10", "--out", str(out / "motion.csv"), "--quiet")
        seconds = best(lambda: subprocess.run(excite, capture_output=True, check=True), r)
        print("2. excite ur5 --duration 10, defaults (s)")
        print(f"  {'course-dynamics excite ur5 --duration 10':<58} {seconds:>8.3g} s  {verdict(seconds, 'excite')}")
    print_load()


if __name__ == "__main__":
    main()

"""Symbolic derivation time: the two-link arm and the 3-joint rrr_arm, both methods.

Run:  python benchmarks/bench_symbolic.py

Each line times `derive` (raw derivation, B/C extraction and simplification), once, on one thread (sympy);
there is no Pinocchio side.
"""
from __future__ import annotations

import time

from course_dynamics import load_robot
from course_dynamics.core.symbolic import derive

from measure import print_conditions, print_load  # this folder is on the path

CASES = [("two_link", ("m1", "m2", "l1", "l2", "g")), ("rp_arm", ("m1", "m2", "l1", "Izz1", "Izz2", "g")),
         ("rrr_arm", ()), ("rrr_arm", ("m1", "m2", "m3", "l2", "l3", "g"))]


def main() -> None:
    import argparse

    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--robots", help="comma-separated subset of the robots (default all cases)")
    args = parser.parse_args()
    chosen = set(args.robots.split(",")) if args.robots else None
    print_conditions("Symbolic derivation, one run of each, ours on 1 thread (sympy)")
    print(f"{'robot':<10} {'symbols':<32} {'newton-euler':>13} {'lagrange':>10}")
    for name, symbols in CASES:
        if chosen is not None and name not in chosen:
            continue
        model = load_robot(name)
        times = []
        for method in ("newton-euler", "lagrange"):
            start = time.perf_counter()
            derive(model, symbols, method)
            times.append(time.perf_counter() - start)
        print(f"{name:<10} {','.join(symbols) or '(URDF numbers)':<32} {times[0]:>12.2f}s {times[1]:>9.2f}s")
    print_load()


if __name__ == "__main__":
    main()

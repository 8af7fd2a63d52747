"""``course-dynamics terms``: τ, M, C, V and G at one state."""
from __future__ import annotations

import sys

import numpy as np

from ...core.dynamics import dynamics_terms
from ...output import render
from ..options import (
    UsageError,
    add,
    add_all,
    add_robot_argument,
    check_finite,
    load_robot_argument,
    numbers,
    print_json,
    progress_bar,
    warn_if_gravity_free,
)
from . import COMMANDS

HELP = COMMANDS["terms"]
TERMS_BYTES_PER_SQUARED_JOINT = 200  # n x n matrices of floats, about 25 of them alive at once at the peak
DESCRIPTION = ("Evaluate tau = M(q) qdd + V(q, qd) + G(q) and the Coriolis matrix C (C qd = V); --json prints them "
               "with keys joints, tau, M, C, V, G.")


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    add(parser, "--q", required=True)
    add_all(parser, "--qd", "--qdd", "--json", "--quiet")


def run(args) -> int:
    model = load_robot_argument(args)
    from ...base.resources import check_memory

    check_memory(TERMS_BYTES_PER_SQUARED_JOINT * model.n**2,
                 f"robot '{model.name}' has {model.n} joints: its M and C and their intermediates", error=UsageError)
    warn_if_gravity_free(model)
    from ...tools.lint import warn_if_massless

    warn_if_massless(model)  # every term of such a joint is 0: say so rather than print zeros silently
    # The library checks the lengths and values, naming the joint at fault.
    q = numbers(args.q, "--q")
    qd = numbers(args.qd, "--qd") if args.qd is not None else np.zeros(model.n)
    qdd = numbers(args.qdd, "--qdd") if args.qdd is not None else np.zeros(model.n)
    bar = progress_bar(args, total=5, unit="term")
    terms = dynamics_terms(model, q, qd, qdd, progress=lambda name: bar.update(1))
    bar.close()
    check_finite("the result", terms.tau, terms.M, terms.C, terms.V, terms.G)
    if args.json:
        print_json(dict(joints=list(terms.joints), tau=terms.tau.tolist(), M=terms.M.tolist(), C=terms.C.tolist(),
                        V=terms.V.tolist(), G=terms.G.tolist()))
        return 0
    print(f"robot {model.name}: tau = M(q) qdd + V(q, qd) + G(q)   (N·m, or N for prismatic joints)")
    rows = [["joint", "tau", "V", "G"]] + [[name] + [f"{x:.6g}" for x in values]
                                           for name, *values in zip(terms.joints, terms.tau, terms.V, terms.G)]
    print(render.text_table(rows))
    for label, matrix in (("M(q)", terms.M), ("C(q, qd)", terms.C)):
        print(f"\n{label}:")
        print("\n".join(render.matrix_lines(terms.joints, matrix)))
    return 0

"""Symbolic use of the one recursion: exact model numbers and joint symbols.

The Newton–Euler code runs unchanged on sympy expressions (see
:mod:`course_dynamics.algebra`). Two helpers make its output exact and readable:

* :func:`rationalize` turns a model's floating-point numbers into sympy
  rationals (9.81 → 981/100, cos(π/2) round-off → 0), so that results simplify
  exactly instead of carrying 6e-17 residues;
* :func:`joint_symbols` gives Θ, Θ̇, Θ̈ as numpy object arrays of symbols
  named ``q_<joint>``, ``qd_<joint>``, ``qdd_<joint>``.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from .model import Model

ROUND_OFF = 1e-12


def _exact(array: np.ndarray, tolerance: float) -> np.ndarray:
    import sympy

    out = np.empty(np.shape(array), dtype=object)
    for index, value in np.ndenumerate(np.asarray(array)):
        out[index] = sympy.nsimplify(value, rational=True, tolerance=tolerance) if isinstance(value, (float, np.floating)) else value
    return out


def rationalize(model: Model, tolerance: float = ROUND_OFF) -> Model:
    """The same robot with every number an exact sympy rational (within ``tolerance``)."""
    bodies = tuple(
        replace(
            body, R0=_exact(body.R0, tolerance), P=_exact(body.P, tolerance), axis=_exact(body.axis, tolerance),
            mass=_exact(np.array(body.mass), tolerance)[()], p_com=_exact(body.p_com, tolerance),
            I_com=_exact(body.I_com, tolerance),
        )
        for body in model.bodies
    )
    return replace(model, bodies=bodies, gravity=_exact(model.gravity, tolerance))


def joint_symbols(model: Model) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(Θ, Θ̇, Θ̈) as object arrays of real sympy symbols q_<joint>, qd_<joint>, qdd_<joint>."""
    import sympy

    def symbols(prefix):
        return np.array([sympy.Symbol(f"{prefix}_{name}", real=True) for name in model.joint_names], dtype=object)

    return symbols("q"), symbols("qd"), symbols("qdd")

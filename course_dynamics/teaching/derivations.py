"""Checking a derivation by hand: equations of motion written in θ(t), compared term by term with the library's.

A student derives example 6.5 (the RP arm) by Lagrange as one does on paper:
θ₁ and d₂ are functions of time (:func:`time_functions`), k and u are written in
them, and d/dt ∂L/∂θ̇ is taken with the chain rule (sympy's ``diff`` in t).
:func:`in_joint_symbols` turns such an expression into the joint symbols of
:mod:`course_dynamics.core.symbolic` (θ̈, then θ̇, then θ), so that any form
equivalent up to simplification is accepted, and :func:`term_differences` says
which terms differ, by what they multiply:

==================  =============================================  ==============
monomial            part of τᵢ (Craig's names)                     example
==================  =============================================  ==============
θ̈ⱼ                  Mᵢⱼ, the inertia term                          M₁₁ of θ̈₁
θ̇ⱼθ̇ₖ (j ≠ k)        a Coriolis term of Vᵢ (Craig's B)              2m₂d₂ḋ₂θ̇₁
θ̇ⱼ²                 a centrifugal term of Vᵢ (Craig's C)           −m₂d₂θ̇₁²
g                   Gᵢ, the gravity term                           g m₂ sin θ₁
==================  =============================================  ==============

>>> import sympy
>>> t, theta = time_functions("theta")
>>> q, qd, qdd = (sympy.Symbol(n, real=True) for n in ("q_theta", "qd_theta", "qdd_theta"))
>>> in_joint_symbols(sympy.diff(theta**2, t, 2), {"theta": (q, qd, qdd)})
2*q_theta*qdd_theta + 2*qd_theta**2
"""
from __future__ import annotations

import unicodedata

SUBSCRIPTS = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")


def _sympy():
    import sympy  # heavy: only the derivation exercises use it

    return sympy


def time_functions(*names: str):
    """t and one real function of t per name: ``t, theta1, d2 = time_functions("theta1", "d2")``.

    Parameters
    ----------
    *names : str
        The joints' names (``"theta1"``, ``"d2"``).

    Returns
    -------
    tuple
        The real sympy symbol t (s), then θ(t) (rad) or d(t) (m) as an applied sympy function, one per name.
    """
    sympy = _sympy()
    t = sympy.Symbol("t", real=True)
    return (t, *(sympy.Function(name, real=True)(t) for name in names))


def in_joint_symbols(expression, joints: dict):
    """``expression`` with each joint's θ(t), θ̇(t), θ̈(t) replaced by the symbols ``joints[name] = (q, qd, qdd)``.

    Second derivatives go first, so that θ̈ is never read as the derivative of θ̇; an expression already written in
    the symbols is returned as it is.

    Parameters
    ----------
    expression : sympy.Expr or str
        The expression in θ(t) and its derivatives (what sympy can ``sympify``).
    joints : dict
        Joint name → (q, qd, qdd), the sympy symbols of Θ, Θ̇ and Θ̈ for that joint.

    Returns
    -------
    sympy.Expr
        The expression in the joint symbols.
    """
    sympy = _sympy()
    t = sympy.Symbol("t", real=True)
    expression = sympy.sympify(expression)
    for order in (2, 1, 0):
        replacements = {}
        for name, symbols in joints.items():
            function = sympy.Function(name, real=True)(t)
            for candidate in {function, sympy.Function(name)(t)}:
                replacements[candidate.diff(t, order) if order else candidate] = symbols[order]
        expression = expression.xreplace(replacements) if order == 0 else expression.subs(replacements)
    return expression


def _shown(expression, names: dict) -> str:
    """An expression with the joint symbols shown as θ₁, θ̇₁, θ̈₁, d₂, …"""
    sympy = _sympy()
    shown = str(sympy.sympify(expression).xreplace({k: sympy.Symbol(v) for k, v in names.items()}))
    return unicodedata.normalize("NFC", shown.replace("**", "^"))  # d + combining dot: ḋ, as typed


def display_names(joints: dict) -> dict:
    """Symbol → how a student writes it: θ₁, θ̇₁, θ̈₁ for a joint named theta1, d₂, ḋ₂, d̈₂ for d2."""
    names = {}
    for name, (q, qd, qdd) in joints.items():
        base = name.replace("theta", "θ").rstrip("0123456789")
        index = name[len(name.rstrip("0123456789")):].translate(SUBSCRIPTS)
        names.update({q: base + index, qd: base + "\u0307" + index, qdd: base + "\u0308" + index})
    return names


def term_differences(answer, expected, joints: dict, g, row: int) -> list[str]:
    """What differs between τ_row as derived (``answer``) and as it should be, term by term ([] if they agree),
    in Craig's names: "M₁₁ is missing m2*d₂^2", "V₁ lacks the Coriolis term 2*m2*d₂*ḋ₂*θ̇₁", "G₂ has an extra …".

    Parameters
    ----------
    answer : sympy.Expr
        τ_row as derived, in the joint symbols (:func:`in_joint_symbols`).
    expected : sympy.Expr
        τ_row as it should be, in the same symbols.
    joints : dict
        Joint name → (q, qd, qdd), the sympy symbols of Θ, Θ̇ and Θ̈ for that joint.
    g : sympy.Symbol
        The symbol of gravity's acceleration, m/s².
    row : int
        The joint's number, from 1 (for the names τᵢ, Mᵢⱼ, Vᵢ, Gᵢ).

    Returns
    -------
    list of str
        One line per differing term; empty when the two are equal up to simplification.

    Examples
    --------
    >>> import sympy
    >>> q, qd, qdd, m, g = sympy.symbols("q_theta1 qd_theta1 qdd_theta1 m g", real=True)
    >>> term_differences(m * qdd, m * qdd + m * g * sympy.cos(q), {"theta1": (q, qd, qdd)}, g, 1)
    ['G₁ is missing g*m*cos(θ₁)']
    """
    sympy = _sympy()
    if sympy.simplify(sympy.expand(answer - expected)) == 0:
        return []
    qdd = [symbols[2] for symbols in joints.values()]
    qd = [symbols[1] for symbols in joints.values()]
    names, n, i = display_names(joints), len(qd), str(row).translate(SUBSCRIPTS)
    try:
        answer_terms = dict(sympy.Poly(sympy.expand(answer), *qdd, *qd, g).terms())
        expected_terms = dict(sympy.Poly(sympy.expand(expected), *qdd, *qd, g).terms())
    except sympy.PolynomialError:
        return [f"τ{i} is not a polynomial in the joint rates, accelerations and g: a derivative of θ(t) is left "
                "over, or a rate sits inside a function"]
    found = []
    for monomial in sorted(set(answer_terms) | set(expected_terms), reverse=True):
        theirs, ours = answer_terms.get(monomial, 0), expected_terms.get(monomial, 0)
        gap = sympy.simplify(theirs - ours)
        if gap == 0:
            continue
        rates = sympy.Mul(*[v**p for v, p in zip([*qdd, *qd, g], monomial, strict=True)])
        acc, vel = monomial[:n], monomial[n:2 * n]
        if monomial[-1]:  # a term in g belongs to G, whatever rates multiply it
            part, kind = f"G{i}", ""
        elif any(acc):
            part, kind = f"M{i}{str(list(acc).index(1) + 1).translate(SUBSCRIPTS)}", ""
        elif sum(vel) == 2:
            part, kind = f"V{i}", "Coriolis term" if max(vel) == 1 else "centrifugal term"
        else:
            part, kind = f"τ{i}", ""
        missing = gap.could_extract_minus_sign()
        amount = -gap if missing else gap
        verb = "is missing" if missing else "has an extra"
        if not kind:  # an entry of M (its coefficient of θ̈ⱼ), or G, or what multiplies no rate
            found.append(f"{part} {verb} {_shown(amount if part.startswith('M') else amount * rates, names)}")
        elif theirs == 0:
            found.append(f"{part} lacks the {kind} {_shown(ours * rates, names)}")
        elif ours == 0:
            found.append(f"{part} has an extra {kind} {_shown(theirs * rates, names)}")
        else:
            found.append(f"{part}'s {kind} {verb} {_shown(amount * rates, names)}")
    return found or [f"τ{i} differs from the right one"]


REVEALED = 2  # at most this many differing terms are written out; more, and only the parts are named


def _by_name(expression, allowed):
    """``expression`` with symbols named like an allowed one replaced by it (a student's own ``Symbol("m")``)."""
    named = {str(s): s for s in allowed}
    return expression.xreplace({s: named[str(s)] for s in expression.free_symbols if str(s) in named})


def _slipped(expected, joints, g) -> dict[str, tuple[list, str]]:
    """The equations made with the slips students make: code → (rows, words)."""
    sympy = _sympy()
    qd = [symbols[1] for symbols in joints.values()]

    def coriolis_halved(e):
        poly = sympy.Poly(sympy.expand(e), *qd)
        return sum(c * sympy.Mul(*[v**p for v, p in zip(qd, m, strict=True)]) * (sympy.Rational(1, 2) if
               sum(m) == 2 and max(m) == 1 else 1) for m, c in poly.terms())

    def swapped(e):
        trig = e.atoms(sympy.sin, sympy.cos)
        return e.xreplace({f: (sympy.cos if f.func is sympy.sin else sympy.sin)(f.args[0]) for f in trig})

    return {"joints-swapped": (expected[::-1], "the equations of the joints in the wrong order"),
            "gravity-sign": ([e.xreplace({g: -g}) for e in expected], "gravity with the wrong sign"),
            "coriolis-half": ([coriolis_halved(e) for e in expected], "half the Coriolis term: d/dt of a square "
                              "(d₂² here) brings a 2"),
            "sin-cos-swapped": ([swapped(e) for e in expected], "sin and cos exchanged")}


def equation_problems(rows, expected, joints: dict, parameters, g) -> list[str]:
    """What is wrong with equations of motion derived by hand (``rows``, one per joint) against ``expected``, in
    Craig's names; [] when every row equals its own up to simplification. A slip students make is named by its
    code; a few differing terms are written out; many are only located, so that the feedback never is the answer."""
    sympy = _sympy()
    t = sympy.Symbol("t", real=True)
    allowed = {s for q in joints.values() for s in q} | set(parameters) | {t}
    made, lines = [], []
    for row, theirs in enumerate(rows, start=1):
        i = str(row).translate(SUBSCRIPTS)
        theirs = _by_name(in_joint_symbols(theirs, joints), allowed)
        stray = sorted(str(s) for s in theirs.free_symbols - allowed)
        leftover = sorted(map(str, theirs.atoms(sympy.Derivative, sympy.core.function.AppliedUndef)))
        if stray or leftover:
            lines.append(f"τ{i} uses {', '.join(stray + leftover)}: write it with time_functions(…) of the joints "
                         f"and the parameter symbols {', '.join(map(str, parameters))} only")
        elif theirs.atoms(sympy.Float):
            lines.append(f"τ{i} holds decimal numbers "
                         f"({', '.join(sorted({str(x) for x in theirs.atoms(sympy.Float)})[:3])}): "
                         "write every parameter as its symbol (g, not 9.81)")
        made.append(theirs)
    if lines:
        return lines
    if all(sympy.simplify(a - b) == 0 for a, b in zip(made, expected, strict=True)):
        return []
    for code, (slipped, words) in _slipped(expected, joints, g).items():
        if all(sympy.simplify(a - b) == 0 for a, b in zip(made, slipped, strict=True)):
            return [f"[{code}] matches the right equations computed with this slip: {words}"]
    found = [term_differences(a, b, joints, g, row) for row, (a, b) in enumerate(zip(made, expected), start=1)]
    if sum(map(len, found)) <= REVEALED:
        return [line for lines_ in found for line in lines_]
    parts = [line.split(" ")[0].rstrip("'s") for lines_ in found for line in lines_]
    return [f"these parts differ from the right ones: {', '.join(dict.fromkeys(parts))} — start again from k and u, "
            "and take d/dt with the chain rule"]


__all__ = ["in_joint_symbols", "term_differences", "time_functions"]

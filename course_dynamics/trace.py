"""The Newton–Euler iterations shown step by step, as the notes' worked example lays them out.

:func:`trace` evaluates the outward iteration (6.45)–(6.50) and the inward
iteration (6.51)–(6.53) once and keeps, for every link, ⁱωᵢ, ⁱω̇ᵢ, ⁱv̇ᵢ, ⁱv̇_Cᵢ,
ⁱFᵢ, ⁱNᵢ, ⁱfᵢ, ⁱnᵢ and τᵢ (each vector in its own link's frame). Numeric or
symbolic; rendered as a text table, LaTeX or JSON.
"""
from __future__ import annotations

from dataclasses import dataclass


from .model import Model
from .newton_euler import newton_euler_links

OUTWARD = (("omega", "ω", r"\omega", "(6.45)"), ("omega_dot", "ω̇", r"\dot\omega", "(6.46)"),
           ("v_dot", "v̇", r"\dot v", "(6.47)"), ("v_dot_c", "v̇_C", r"\dot v_{C}", "(6.48)"),
           ("F", "F", "F", "(6.49)"), ("N", "N", "N", "(6.50)"))
INWARD = (("f", "f", "f", "(6.51)"), ("n", "n", "n", "(6.52)"))


@dataclass(frozen=True)
class Trace:
    """Per-link quantities of one Newton–Euler evaluation; ``values[key][i]`` is link i's vector."""

    model_name: str
    joints: tuple[str, ...]
    links: tuple[str, ...]
    prismatic: tuple[bool, ...]
    values: dict
    tau: list
    symbolic: bool


def trace(model: Model, q, qd, qdd, symbols=None) -> Trace:
    """Run both iterations and keep every intermediate quantity.

    ``symbols`` = None gives numbers at the state (q, qd, qdd). Otherwise the
    trace is symbolic: joint variables are the symbols q_<joint>, qd_<joint>,
    qdd_<joint> (q, qd, qdd are ignored), ``symbols`` names the parameters kept
    symbolic (see :mod:`course_dynamics.symbolic`), and entries are simplified.
    """
    if symbols is None:
        links = newton_euler_links(model, q, qd, qdd)
        values = {key: getattr(links, key).tolist() for key, *_ in OUTWARD + INWARD}
        tau = links.tau.tolist()
    else:
        from .symbolic import check_symbolic_size, joint_symbols, symbolic_model, tidy

        check_symbolic_size(model)
        exact, _ = symbolic_model(model, symbols)
        q_s, qd_s, qdd_s = joint_symbols(model)
        links = newton_euler_links(exact, q_s, qd_s, qdd_s)
        values = {key: [[tidy(x, q_s) for x in row] for row in getattr(links, key)] for key, *_ in OUTWARD + INWARD}
        tau = [tidy(x, q_s) for x in links.tau]
    return Trace(model_name=model.name, joints=model.joint_names, links=tuple(b.name for b in model.bodies),
                 prismatic=tuple(b.is_prismatic for b in model.bodies), values=values, tau=tau, symbolic=symbols is not None)


def _text(x) -> str:
    return f"{x:.6g}" if isinstance(x, float) else str(x)


def as_table(t: Trace) -> str:
    """Plain text: outward iteration link by link, then inward iteration from the tip."""
    lines = [f"robot {t.model_name}: Newton-Euler iterations (every vector in its own link's frame i)", "",
             "Outward iteration, i = 1 .. n: velocities, accelerations, inertial loads (6.45)-(6.50)"]
    for i, (link, joint) in enumerate(zip(t.links, t.joints)):
        lines.append(f"  link {i + 1} ({link}, joint {joint}{', prismatic' if t.prismatic[i] else ''}):")
        for key, label, _, number in OUTWARD:
            number = "(6.35)" if t.prismatic[i] and key in ("omega", "omega_dot", "v_dot") else number
            lines.append(f"    {label:<4} = [{', '.join(_text(x) for x in t.values[key][i])}]   {number}")
    lines += ["", "Inward iteration, i = n .. 1: joint forces, moments and torques (6.51)-(6.53)"]
    for i in reversed(range(len(t.links))):
        lines.append(f"  link {i + 1} ({t.links[i]}):")
        for key, label, _, number in INWARD:
            lines.append(f"    {label:<4} = [{', '.join(_text(x) for x in t.values[key][i])}]   {number}")
        unit = "tau (force along the axis)   (6.44)" if t.prismatic[i] else "tau  (moment about the axis)   (6.53)"
        lines.append(f"    tau_{i + 1} = {_text(t.tau[i])}   {unit}")
    return "\n".join(lines)


def latex_names(joints, prismatic) -> dict:
    """Craig's letters for the joint symbols: q_<joint> → θᵢ (dᵢ if prismatic), qd → θ̇ᵢ, qdd → θ̈ᵢ."""
    import sympy

    names = {}
    for i, (joint, is_prismatic) in enumerate(zip(joints, prismatic), start=1):
        letter = "d" if is_prismatic else r"\theta"
        for prefix, accent in (("q", ""), ("qd", r"\dot"), ("qdd", r"\ddot")):
            names[sympy.Symbol(f"{prefix}_{joint}", real=True)] = f"{accent}{{{letter}}}_{{{i}}}" if accent else f"{letter}_{{{i}}}"
    return names


def _latex_entry(x, names=None) -> str:
    if isinstance(x, float):
        return f"{x:.6g}"
    import sympy

    return sympy.latex(x, symbol_names=names or {})


def as_latex(t: Trace) -> str:
    """LaTeX: one ``align*`` block per iteration, one line per quantity, Craig's leading superscripts."""
    names = latex_names(t.joints, t.prismatic)

    def vector(values):
        return r"\begin{bmatrix}" + r" \\ ".join(_latex_entry(x, names) for x in values) + r"\end{bmatrix}"

    out = [r"% Newton-Euler iterations of " + t.model_name, r"\begin{align*}"]
    for i in range(len(t.links)):
        for key, _, symbol, number in OUTWARD:
            out.append(f"{{}}^{{{i + 1}}}{symbol}_{{{i + 1}}} &= {vector(t.values[key][i])} && \\text{{{number}}} \\\\")
    out += [r"\end{align*}", r"\begin{align*}"]
    for i in reversed(range(len(t.links))):
        for key, _, symbol, number in INWARD:
            out.append(f"{{}}^{{{i + 1}}}{symbol}_{{{i + 1}}} &= {vector(t.values[key][i])} && \\text{{{number}}} \\\\")
        out.append(f"\\tau_{{{i + 1}}} &= {_latex_entry(t.tau[i], names)} \\\\")
    out.append(r"\end{align*}")
    return "\n".join(out)


def as_dict(t: Trace) -> dict:
    """JSON-ready: numbers stay numbers; symbolic entries become strings sympy.sympify parses."""
    def entry(x):
        return x if isinstance(x, float) else str(x)

    links = []
    for i, (link, joint) in enumerate(zip(t.links, t.joints)):
        record = {"link": link, "joint": joint}
        for key, *_ in OUTWARD + INWARD:
            record[key] = [entry(x) for x in t.values[key][i]]
        record["tau"] = entry(t.tau[i])
        links.append(record)
    return {"robot": t.model_name, "joints": list(t.joints), "symbolic": t.symbolic, "links": links}


def derivation_dict(d) -> dict:
    """A :class:`~course_dynamics.symbolic.Derivation` as JSON-ready strings (keys joints, tau, M, V, G, B, C)."""
    def s(x):
        return str(x)

    return {
        "joints": list(d.joints), "tau": [s(x) for x in d.tau], "M": [[s(x) for x in row] for row in d.M],
        "V": [s(x) for x in d.V], "G": [s(x) for x in d.G], "B": [[s(x) for x in row] for row in d.B],
        "C": [[s(x) for x in row] for row in d.C],
    }


def derivation_text(d, fmt: str) -> str:
    """A derivation typeset as LaTeX or Markdown (with LaTeX math)."""
    import sympy

    n = len(d.joints)
    names = latex_names(d.joints, d.prismatic)
    pairs = ", ".join(f"{names[d.qd[j]]}{names[d.qd[k]]}" for j, k in d.pairs) or "none"
    blocks = [
        (r"\tau", sympy.Matrix(d.tau)), (r"M(\Theta)", sympy.Matrix(d.M)), (r"V(\Theta,\dot\Theta)", sympy.Matrix(d.V)),
        (r"G(\Theta)", sympy.Matrix(d.G)),
        (r"B(\Theta)", sympy.Matrix(d.B) if d.pairs else sympy.zeros(n, 0)), (r"C(\Theta)", sympy.Matrix(d.C)),
    ]
    symbols = ", ".join(sorted(d.parameters)) or "none (numbers from the URDF)"
    header = (f"Closed-form dynamics by {d.method}: joints {', '.join(d.joints)}; parameter symbols: {symbols}. "
              f"tau = M qdd + B [{pairs}] + C [qd^2] + G (6.63).")
    if fmt == "latex":
        body = "\n".join(f"{name} &= {sympy.latex(value, symbol_names=names)} \\\\" for name, value in blocks)
        return f"% {header}\n\\begin{{align*}}\n{body}\n\\end{{align*}}"
    lines = [f"**{header}**", ""]
    for name, value in blocks:
        lines += [f"$$ {name} = {sympy.latex(value, symbol_names=names)} $$", ""]
    return "\n".join(lines)


__all__ = ["Trace", "as_dict", "as_latex", "as_table", "derivation_dict", "derivation_text", "trace"]

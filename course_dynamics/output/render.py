"""Text, Markdown, LaTeX and JSON renderings of the library's results.

The command line, the notebooks and the reports print through these functions;
none of them computes anything.

======================  ========================================================
function                renders
======================  ========================================================
``text_table``          rows of cells as aligned plain-text columns
``matrix_lines``        a labelled matrix, one row per line
``trace_table``         a :class:`~course_dynamics.tools.trace.Trace` as plain text
``trace_latex``         the same as LaTeX ``align*`` blocks, Craig's superscripts
``trace_record``        the same as a JSON-ready dict
``derivation_text``     a :class:`~course_dynamics.core.symbolic.Derivation` as
                        Markdown (LaTeX inside ``$$``) or LaTeX
``derivation_record``   the same as a JSON-ready dict of strings
``json_text``           a JSON document (strict: NaN and inf are refused)
``markdown_escape``     any text (a robot, joint or student name, a message)
                        made safe to place in Markdown
``code_block``          text as a fenced Markdown code block it cannot leave
======================  ========================================================

Everything that came from a user (names from a URDF, student files and their
output) goes through :func:`markdown_escape`, :func:`code_block` or
``html.escape`` before it reaches Markdown or HTML.
"""
from __future__ import annotations

import json
import re

from ..base.errors import InputError
from ..tools.trace import INWARD_QUANTITIES, OUTWARD_QUANTITIES, Trace

#: The formats of a Newton–Euler trace, by :func:`trace_table`, :func:`trace_latex` and :func:`trace_record`.
TRACE_FORMATS = ("table", "latex", "json")
#: The formats of a closed-form derivation, by :func:`derivation_text` (Markdown, LaTeX) and :func:`derivation_record`.
DERIVATION_FORMATS = ("markdown", "latex", "json")

# key: (plain-text label, LaTeX symbol, equation number)
TRACE_SYMBOLS = {
    "omega": ("ω", r"\omega", "(6.45)"), "omega_dot": ("ω̇", r"\dot\omega", "(6.46)"),
    "v_dot": ("v̇", r"\dot v", "(6.47)"), "v_dot_c": ("v̇_C", r"\dot v_{C}", "(6.48)"),
    "F": ("F", "F", "(6.49)"), "N": ("N", "N", "(6.50)"), "f": ("f", "f", "(6.51)"), "n": ("n", "n", "(6.52)"),
}
PRISMATIC_OUTWARD = ("omega", "omega_dot", "v_dot")  # replaced by (6.35) for a prismatic joint


def format_value(x) -> str:
    """A float to 6 significant digits; anything else (a sympy expression) as its string."""
    return f"{x:.6g}" if isinstance(x, float) else str(x)


def text_table(rows: list[list[str]], align: str | None = None, gap: int = 2) -> str:
    """Rows of strings as aligned columns; ``align`` has one ``<`` (left) or ``>`` (right) per column.

    By default the first column is left-aligned and the others right-aligned (labels, then numbers).

    Parameters
    ----------
    rows : list of list of str
        The cells, row by row; every row has the same number of cells, and there is at least one row.
    align : str, optional
        One ``<`` or ``>`` per column; ``None`` (the default) for ``"<>>…"``.
    gap : int, optional
        Spaces between columns.

    Returns
    -------
    str
        The table, one line per row (no trailing spaces, no final newline).

    Examples
    --------
    >>> print(text_table([["joint", "tau"], ["theta1", "1.5"], ["theta2", "-0.25"]]))
    joint     tau
    theta1    1.5
    theta2  -0.25
    """
    widths = [max(len(row[c]) for row in rows) for c in range(len(rows[0]))]
    align = align or "<" + ">" * (len(widths) - 1)
    lines = []
    for row in rows:
        cells = [cell.ljust(w) if a == "<" else cell.rjust(w) for cell, w, a in zip(row, widths, align)]
        lines.append((" " * gap).join(cells).rstrip())
    return "\n".join(lines)


def matrix_lines(labels, matrix, width: int = 12) -> list[str]:
    """One line per row: its label, then the entries to 6 significant digits in columns of ``width``.

    Parameters
    ----------
    labels : sequence of str
        One label per row.
    matrix : array_like, shape (n, m)
        The numbers (M(Θ), a Jacobian, …).
    width : int, optional
        The width of each number's column, characters.

    Returns
    -------
    list of str
        One line per row.
    """
    label_width = max(len(label) for label in labels)
    return [f"{label:<{label_width}}  " + " ".join(f"{x:>{width}.6g}" for x in row)
            for label, row in zip(labels, matrix)]


URL_LIKE = re.compile(r"(?:[A-Za-z][A-Za-z0-9+.-]*://|www\.)\S+|[\w.+-]+@[\w-]+(?:\.[\w-]+)+")


def markdown_escape(text) -> str:
    """``text`` on one line, with the characters that make Markdown or HTML markup escaped.

    Escaped: backslash, backtick, ``*``, ``_``, ``[``, ``]``, ``|``, ``~`` and HTML's ``<``, ``>``, ``&``
    (as entities); without brackets no link or image can form, so parentheses may stay. What a renderer
    would turn into a link by itself (a bare URL, ``www.``…, an e-mail address) becomes inline code.

    Parameters
    ----------
    text : object
        The text (anything else is made a string first); its line breaks become spaces.

    Returns
    -------
    str
        The escaped text, on one line.

    Examples
    --------
    >>> markdown_escape("see http://evil.example/x_y or me@evil.example <b>")
    'see `http://evil.example/x_y` or `me@evil.example` &lt;b&gt;'
    """
    text = " ".join(str(text).splitlines())
    pieces, last = [], 0
    for found in URL_LIKE.finditer(text):
        pieces += [_escaped(text[last:found.start()]), _code_span(found.group().replace("|", "%7C"))]
        last = found.end()
    return "".join(pieces + [_escaped(text[last:])])


def _escaped(text: str) -> str:
    text = text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    return re.sub(r"([\\`*_\[\]|~])", r"\\\1", text)


def _code_span(text: str) -> str:
    """Inline code holding ``text`` literally: a fence longer than any run of backticks in it."""
    fence = "`" * (max((len(run) for run in re.findall(r"`+", text)), default=0) + 1)
    pad = " " if text.startswith("`") or text.endswith("`") else ""
    return f"{fence}{pad}{text}{pad}{fence}"


def code_block(text, language: str = "text") -> str:
    """A fenced code block whose fence is longer than any run of backticks in ``text``.

    Parameters
    ----------
    text : object
        The block's contents (made a string).
    language : str, optional
        The fence's language tag.

    Returns
    -------
    str
        The block, fences included (no final newline).
    """
    longest = max((len(run) for run in re.findall(r"`+", str(text))), default=0)
    fence = "`" * max(3, longest + 1)
    return f"{fence}{language}\n{text}\n{fence}"


def json_text(document) -> str:
    """Indented JSON; a NaN or inf is an InputError (its values were out of range), never invalid JSON.

    Parameters
    ----------
    document : object
        What :func:`json.dumps` takes: dicts, lists, strings, numbers, booleans, ``None``.

    Returns
    -------
    str
        The document, indented by 2 (no final newline).

    Raises
    ------
    InputError
        If a number in ``document`` is NaN or infinite.
    """

    try:
        return json.dumps(document, indent=2, allow_nan=False)
    except ValueError:
        raise InputError("a result is not finite (inf or nan): the given values are too large for floating-point "
                         "arithmetic") from None


# ---------------------------------------------------------------------------- the Newton–Euler trace


def trace_table(t: Trace) -> str:
    """Plain text: outward iteration link by link, then inward iteration from the tip.

    Parameters
    ----------
    t : Trace
        The trace (:class:`~course_dynamics.tools.trace.Trace`), numeric or symbolic.

    Returns
    -------
    str
        Each link's ⁱωᵢ, ⁱω̇ᵢ, ⁱv̇ᵢ, ⁱv̇_Cᵢ, ⁱFᵢ, ⁱNᵢ, then ⁱfᵢ, ⁱnᵢ and τᵢ, labelled with Craig's equation numbers.
    """
    lines = [f"robot {t.model_name}: Newton-Euler iterations (every vector in its own link's frame i)", "",
             "Outward iteration, i = 1 .. n: velocities, accelerations, inertial loads (6.45)-(6.50)"]
    for i, (link, joint) in enumerate(zip(t.links, t.joints)):
        lines.append(f"  link {i + 1} ({link}, joint {joint}{', prismatic' if t.prismatic[i] else ''}):")
        for key in OUTWARD_QUANTITIES:
            label, _, number = TRACE_SYMBOLS[key]
            number = "(6.35)" if t.prismatic[i] and key in PRISMATIC_OUTWARD else number
            lines.append(f"    {label:<4} = [{', '.join(format_value(x) for x in t.values[key][i])}]   {number}")
    lines += ["", "Inward iteration, i = n .. 1: joint forces, moments and torques (6.51)-(6.53)"]
    for i in reversed(range(len(t.links))):
        lines.append(f"  link {i + 1} ({t.links[i]}):")
        for key in INWARD_QUANTITIES:
            label, _, number = TRACE_SYMBOLS[key]
            lines.append(f"    {label:<4} = [{', '.join(format_value(x) for x in t.values[key][i])}]   {number}")
        unit = "tau (force along the axis)   (6.44)" if t.prismatic[i] else "tau  (moment about the axis)   (6.53)"
        lines.append(f"    tau_{i + 1} = {format_value(t.tau[i])}   {unit}")
    return "\n".join(lines)


def latex_names(joints, prismatic, parameters=None) -> dict:
    """Craig's letters for the joint symbols: q_<joint> → θᵢ (dᵢ if prismatic), qd → θ̇ᵢ, qdd → θ̈ᵢ;
    and for the parameter symbols that need it: lc<i> → l_{c_i}."""
    import sympy

    names = {}
    for name, symbol in (parameters or {}).items():
        match = re.fullmatch(r"lc(\d*)", name)
        if match:
            names[symbol] = rf"l_{{c_{{{match.group(1)}}}}}" if match.group(1) else "l_{c}"
    for i, (joint, is_prismatic) in enumerate(zip(joints, prismatic), start=1):
        letter = "d" if is_prismatic else r"\theta"
        for prefix, accent in (("q", ""), ("qd", r"\dot"), ("qdd", r"\ddot")):
            names[sympy.Symbol(f"{prefix}_{joint}", real=True)] = (
                f"{accent}{{{letter}}}_{{{i}}}" if accent else f"{letter}_{{{i}}}")
    return names


def latex_entry(x, names=None) -> str:
    """One entry as LaTeX: a float to 6 significant digits, a sympy expression with Craig's joint letters."""
    if isinstance(x, float):
        return f"{x:.6g}"
    import sympy

    return sympy.latex(x, symbol_names=names or {})


def trace_latex(t: Trace) -> str:
    """LaTeX: one ``align*`` block per iteration, one line per quantity, Craig's leading superscripts.

    Parameters
    ----------
    t : Trace
        The trace (:class:`~course_dynamics.tools.trace.Trace`), numeric or symbolic.

    Returns
    -------
    str
        Two ``align*`` blocks (outward, then inward), the joint symbols as θᵢ, θ̇ᵢ, θ̈ᵢ (dᵢ for a prismatic joint).
    """
    names = latex_names(t.joints, t.prismatic)

    def vector(values):
        return r"\begin{bmatrix}" + r" \\ ".join(latex_entry(x, names) for x in values) + r"\end{bmatrix}"

    def line(i, key):
        _, symbol, number = TRACE_SYMBOLS[key]
        # the link's index joins a subscript the symbol has (v̇_C of link 2 is \dot v_{C_{2}}, not a double subscript)
        indexed = f"{symbol[:-1]}_{{{i + 1}}}}}" if symbol.endswith("}") else f"{symbol}_{{{i + 1}}}"
        return f"{{}}^{{{i + 1}}}{indexed} &= {vector(t.values[key][i])} && \\text{{{number}}} \\\\"

    out = [r"% Newton-Euler iterations of " + t.model_name, r"\begin{align*}"]
    for i in range(len(t.links)):
        out += [line(i, key) for key in OUTWARD_QUANTITIES]
    out += [r"\end{align*}", r"\begin{align*}"]
    for i in reversed(range(len(t.links))):
        out += [line(i, key) for key in INWARD_QUANTITIES]
        out.append(f"\\tau_{{{i + 1}}} &= {latex_entry(t.tau[i], names)} \\\\")
    out.append(r"\end{align*}")
    return "\n".join(out)


def trace_record(t: Trace) -> dict:
    """JSON-ready: numbers stay numbers; symbolic entries become strings.

    Parameters
    ----------
    t : Trace
        The trace (:class:`~course_dynamics.tools.trace.Trace`), numeric or symbolic.

    Returns
    -------
    dict
        ``{"robot", "joints", "symbolic", "links"}``; each link a dict of its ``link``, ``joint``, vectors
        (``omega``, ``omega_dot``, ``v_dot``, ``v_dot_c``, ``F``, ``N``, ``f``, ``n``) and ``tau``.
    """
    def entry(x):
        return x if isinstance(x, float) else str(x)

    links = []
    for i, (link, joint) in enumerate(zip(t.links, t.joints)):
        record = {"link": link, "joint": joint}
        for key in OUTWARD_QUANTITIES + INWARD_QUANTITIES:
            record[key] = [entry(x) for x in t.values[key][i]]
        record["tau"] = entry(t.tau[i])
        links.append(record)
    return {"robot": t.model_name, "joints": list(t.joints), "symbolic": t.symbolic, "links": links}


# ---------------------------------------------------------------------------- closed-form derivations


def derivation_record(d) -> dict:
    """A :class:`~course_dynamics.core.symbolic.Derivation` as JSON-ready strings (keys joints, tau, M, V, G, B, C).

    Parameters
    ----------
    d : Derivation
        The closed forms (:class:`~course_dynamics.core.symbolic.Derivation`).

    Returns
    -------
    dict
        ``joints`` (list of str), ``tau``, ``V``, ``G`` (lists of str, n), ``M``, ``C`` (n × n) and ``B``
        (n × n(n−1)/2) as nested lists of str.
    """
    def s(x):
        return str(x)

    return {
        "joints": list(d.joints), "tau": [s(x) for x in d.tau], "M": [[s(x) for x in row] for row in d.M],
        "V": [s(x) for x in d.V], "G": [s(x) for x in d.G], "B": [[s(x) for x in row] for row in d.B],
        "C": [[s(x) for x in row] for row in d.C],
    }


def derivation_text(d, fmt: str) -> str:
    """A derivation typeset as LaTeX (``fmt="latex"``) or Markdown with LaTeX math (``"markdown"``).

    Parameters
    ----------
    d : Derivation
        The closed forms (:class:`~course_dynamics.core.symbolic.Derivation`).
    fmt : str
        ``"latex"``; anything else gives Markdown.

    Returns
    -------
    str
        τ, M(Θ), V(Θ, Θ̇), G(Θ), B(Θ) and C(Θ) of (6.63), in Craig's letters.
    """
    import sympy

    n = len(d.joints)
    names = latex_names(d.joints, d.prismatic, d.parameters)
    pairs = ", ".join(f"{names[d.qd[j]]}{names[d.qd[k]]}" for j, k in d.pairs)
    blocks = [
        (r"\tau", sympy.Matrix(d.tau)), (r"M(\Theta)", sympy.Matrix(d.M)), (r"V(\Theta,\dot\Theta)", sympy.Matrix(d.V)),
        (r"G(\Theta)", sympy.Matrix(d.G)),
        (r"B(\Theta)", sympy.Matrix(d.B) if d.pairs else sympy.zeros(n, 0)), (r"C(\Theta)", sympy.Matrix(d.C)),
    ]
    symbols = ", ".join(sorted(d.parameters)) or "none (numbers from the URDF)"
    split = (r"\tau = M(\Theta)\ddot\Theta + B(\Theta)[\dot\Theta\dot\Theta] + C(\Theta)[\dot\Theta^2] + G(\Theta)"
             + (rf", \quad [\dot\Theta\dot\Theta] = ({pairs})" if pairs else ""))
    header = f"Closed-form dynamics by {d.method}: joints {', '.join(d.joints)}; parameter symbols: {symbols}"
    if fmt == "latex":
        body = "\n".join(f"{name} &= {sympy.latex(value, symbol_names=names)} \\\\" for name, value in blocks)
        return f"% {header}.\n% {split} (6.63)\n\\begin{{align*}}\n{body}\n\\end{{align*}}"
    lines = [f"**{header}.** The split of (6.63): ${split}$.", ""]
    for name, value in blocks:
        lines += [f"$$ {name} = {sympy.latex(value, symbol_names=names)} $$", ""]
    return "\n".join(lines)


__all__ = ["DERIVATION_FORMATS", "TRACE_FORMATS", "code_block", "derivation_record", "derivation_text", "json_text",
           "markdown_escape", "matrix_lines", "text_table", "trace_latex", "trace_record", "trace_table"]

"""Submissions made of the code course-dynamics itself writes for a robot, as a student would paste it in.

``derive`` prints the closed forms as JSON (Python expressions), Markdown and LaTeX (the same
expressions typeset); :func:`derived_submission` turns each format into a Python file the way
a student does by hand (LaTeX: ``\\frac{a}{b}`` to ``(a)/(b)``, ``\\dot{\\theta}_{1}`` to
``qd_theta1``, a space between factors to ``*``). :func:`compiled_submission` wraps the compiled
model's generated module. With ``robot=True`` the functions take the robot first and ignore it.
Also: one general Newton–Euler for ``interface = "robot"``, written from the robot's data alone.
"""
from __future__ import annotations

import contextlib
import io
import json
import re

FORMATS = ("json", "markdown", "latex")

ROBOT_NEWTON_EULER = '''
import numpy as np


def rotation(axis, angle):
    """Rodrigues: the rotation by angle about the unit axis."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * (k @ k)


def tau(robot, q, qd, qdd):
    """Craig's outward and inward iterations over the robot's tree, from its data alone."""
    joints, links, n = robot["joints"], robot["links"], len(robot["joints"])
    zero = np.zeros(3)
    R, P, w, wd, vd, F, N = [], [], [], [], [], [], []
    for i, joint in enumerate(joints):
        z, origin = joint["axis"], joint["origin"]
        revolute = joint["type"] == "revolute"
        R.append(origin[:3, :3] @ rotation(z, q[i]) if revolute else origin[:3, :3])
        P.append(origin[:3, 3] if revolute else origin[:3, 3] + origin[:3, :3] @ z * q[i])
        p = joint["parent"]
        wp, wdp, vdp = (zero, zero, -robot["gravity"]) if p < 0 else (w[p], wd[p], vd[p])
        Rt = R[i].T
        v = Rt @ (np.cross(wdp, P[i]) + np.cross(wp, np.cross(wp, P[i])) + vdp)
        if revolute:
            w.append(Rt @ wp + qd[i] * z)
            wd.append(Rt @ wdp + np.cross(Rt @ wp, qd[i] * z) + qdd[i] * z)
            vd.append(v)
        else:
            w.append(Rt @ wp)
            wd.append(Rt @ wdp)
            vd.append(v + 2 * np.cross(w[i], qd[i] * z) + qdd[i] * z)
        c, m, I = links[i]["com"], links[i]["mass"], links[i]["inertia"]
        F.append(m * (np.cross(wd[i], c) + np.cross(w[i], np.cross(w[i], c)) + vd[i]))
        N.append(I @ wd[i] + np.cross(w[i], I @ w[i]))
    f, nn, out = [zero] * n, [zero] * n, np.zeros(n)
    for i in reversed(range(n)):
        fi = F[i] + f[i]
        ni = N[i] + nn[i] + np.cross(links[i]["com"], F[i])
        out[i] = (ni if joints[i]["type"] == "revolute" else fi) @ joints[i]["axis"]
        p = joints[i]["parent"]
        if p >= 0:
            f[p] = f[p] + R[i] @ fi
            nn[p] = nn[p] + R[i] @ ni + np.cross(P[i], R[i] @ fi)
    return out
'''


def derive_output(urdf: str, fmt: str) -> str:
    """What ``course-dynamics derive URDF`` prints in ``fmt`` (json, markdown or latex)."""
    from course_dynamics.cli import main

    flag = {"json": ["--json"], "markdown": [], "latex": ["--latex"]}[fmt]
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        assert main(["derive", urdf, *flag]) == 0
    return printed.getvalue()


def _group(text: str, start: int) -> tuple[str, int]:
    """The balanced {…} group at ``start``: its inside and the index after it."""
    assert text[start] == "{", text[start:start + 20]
    depth = 0
    for i in range(start, len(text)):
        depth += {"{": 1, "}": -1}.get(text[i], 0)
        if depth == 0:
            return text[start + 1:i], i + 1
    raise ValueError("unbalanced braces")


def latex_python(latex: str) -> str:
    """One entry of derive's LaTeX as the Python a student types for it."""
    text = re.sub(r"\\(d?dot)\{\\(\w+)\}_\{(\w+)\}", lambda m: ("qdd_" if m.group(1) == "ddot" else "qd_")
                  + m.group(2) + m.group(3), latex)
    text = re.sub(r"\\(theta|phi|psi|alpha|beta)_\{(\w+)\}", r"q_\1\2", text)
    text = text.replace(r"\left(", "(").replace(r"\right)", ")")
    text = re.sub(r"\\(sin|cos)\{", r"\1{", text)
    while r"\frac" in text:
        i = text.index(r"\frac")
        a, j = _group(text, i + 5)
        b, k = _group(text, j)
        text = text[:i] + f"(({a})/({b}))" + text[k:]
    text = text.replace("{", "(").replace("}", ")").replace("^", "**")
    return re.sub(r"(?<=[\w)])\s+(?=[\w(])", "*", text).strip()


def _tau_entries(output: str, fmt: str) -> tuple[list[str], list[str]]:
    """τ's entries as Python expressions, and the joints, from derive's output in ``fmt``."""
    if fmt == "json":
        record = json.loads(output)
        return record["tau"], record["joints"]
    joints = re.search(r"joints ([\w, ]+);", output).group(1).split(", ")
    matrix = re.search(r"\\begin\{matrix\}(.*?)\\end\{matrix\}", output, re.S).group(1)  # τ comes first
    return [latex_python(row) for row in matrix.split(r"\\")], joints


def derived_submission(urdf: str, fmt: str, robot: bool = False) -> str:
    """derive's τ for the robot in ``urdf``, pasted into a ``tau`` (taking the robot first when ``robot``)."""
    entries, joints = _tau_entries(derive_output(urdf, fmt), fmt)
    lines = ["import numpy as np", "from numpy import cos, sin", "", "",
             f"def tau({'robot, ' if robot else ''}q, qd, qdd):"]
    for kind in ("q", "qd", "qdd"):
        lines.append(f"    {', '.join(f'{kind}_{j}' for j in joints)}{',' if len(joints) == 1 else ''} = {kind}")
    lines.append(f"    return np.array([{', '.join(entries)}], dtype=float)")
    return "\n".join(lines) + "\n"


def compiled_submission(model, robot: bool = False) -> str:
    """The compiled model's generated module for ``model`` as it is (it defines ``tau(q, qd, qdd)``); with ``robot``,
    its ``tau`` wrapped to take the robot first."""
    from course_dynamics.core.compiled import model_key
    from course_dynamics.core.compiled.codegen import module_source
    from course_dynamics.core.compiled.tracing import trace_programs

    source = module_source(model, trace_programs(model), model_key(model))
    if robot:
        source += "\n\n_generated = tau\n\n\ndef tau(robot, q, qd, qdd):\n    return _generated(q, qd, qdd)\n"
    return source

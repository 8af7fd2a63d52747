"""The identification report: a folder with ``report.html``, ``report.md``, ``report.json`` and ``held_out.svg``.

================  ===============================================================================
file              holds
================  ===============================================================================
``report.html``   one page (:mod:`~course_dynamics.output.page`): the held-out residuals, the
                  base parameters before and after with their standard errors, every body's
                  parameters, what the log determined of each and what stayed at the URDF's
                  (with the bodies that moved far), friction, what the log does not excite,
                  and the figure inline
``report.md``     the same tables in Markdown (names escaped), the figure as a link
``report.json``   :meth:`~course_dynamics.tools.identification.Identification.record`, with the
                  URDF and log named
``held_out.svg``  measured torques against the URDF's and the identified model's, joint by joint,
                  on the held-out part of the log (matplotlib)
================  ===============================================================================

The folder is written by :func:`~course_dynamics.output.folders.write_folder` for the command
``identify``: files the user put there are never replaced.

>>> from course_dynamics.output.identification_report import REPORT_FILES
>>> REPORT_FILES
('report.html', 'report.md', 'report.json', 'held_out.svg')
"""
from __future__ import annotations

import numpy as np

from ..tools.identification import Identification
from . import folders, page, plotting, render

#: The files of the report folder, in the order they are listed.
REPORT_FILES = ("report.html", "report.md", "report.json", "held_out.svg")
OWNER = "identify"


def _number(x, digits: int = 4) -> str:
    return "–" if x is None or not np.isfinite(x) else f"{x:.{digits}g}"


def residual_rows(result: Identification) -> list[list[str]]:
    """Per measured joint: σ (the noise the fit found), RMS residual on the held-out part with the URDF and
    identified, and their ratio.

    Parameters
    ----------
    result : Identification
        The identification (:class:`~course_dynamics.tools.identification.Identification`).

    Returns
    -------
    list of list of str
        One row per measured joint, in the columns of :data:`RESIDUAL_HEADER`: the joint, σ, the two RMS
        residuals (N·m, N for a prismatic joint) and the URDF's over the identified one, 4 (3 for the ratio)
        significant digits, ``–`` for a value that is not finite.
    """
    rows = []
    for j, joint in enumerate(result.model.joint_names):
        if not np.isfinite(result.sigma[j]):
            continue
        before, after = result.rms_before[j], result.rms_after[j]
        ratio = before / after if np.isfinite(before) and after > 0 else np.nan
        rows.append([joint, _number(result.sigma[j]), _number(before), _number(after), _number(ratio, 3)])
    return rows


#: The columns of :func:`residual_rows`.
RESIDUAL_HEADER = ("joint", "σ (fit)", "RMS held out, URDF", "RMS held out, identified", "URDF / identified")


def base_rows(result: Identification) -> list[list[str]]:
    """Per base parameter (then friction): its definition, the URDF's value, weighted least squares ± one
    standard error, the physically consistent value."""
    definitions = result.base.describe().splitlines() + list(result.base_names[result.base.rank:])
    return [[definition, _number(a), f"{_number(b)} ± {_number(e, 2)}", _number(c)]
            for definition, a, b, e, c in zip(definitions, result.base_urdf, result.base_wls, result.base_error,
                                              result.base_consistent)]


BASE_HEADER = ("base parameter", "URDF", "least squares ± σ", "identified (consistent)")


def body_rows(result: Identification) -> list[list[str]]:
    """Per moving body: mass, centre of mass (frame i) and principal moments about it, before → after."""
    rows = []
    for old, new in zip(result.original.bodies, result.model.bodies):
        def moments(body):
            return ", ".join(_number(x, 3) for x in np.linalg.eigvalsh(np.asarray(body.I_com, dtype=float)))
        com = [", ".join(_number(x, 3) for x in np.asarray(b.p_com, dtype=float)) for b in (old, new)]
        rows.append([old.name, f"{_number(float(old.mass))} → {_number(float(new.mass))}", f"({com[0]}) → ({com[1]})",
                     f"{moments(old)} → {moments(new)}"])
    return rows


BODY_HEADER = ("body (link)", "mass (kg)", "centre of mass in frame i (m)", "principal moments about it (kg m²)")


def seen_rows(result: Identification) -> list[list[str]]:
    """Per body: the parameters the log determined, saw only in combination, and left at the URDF's, the body's
    divergence from the URDF's, and what moved far."""
    return [[b["body"], ", ".join(b["determined"]) or "–", ", ".join(b["in_combination"]) or "–",
             ", ".join(b["kept"]) or "–", _number(b["divergence"], 3), "; ".join(b["warnings"]) or "–"]
            for b in result.bodies]


SEEN_HEADER = ("body (link)", "determined by the log", "seen only in combination", "kept at the URDF's",
               "divergence d(J‖J₀)", "moved far")


def friction_rows(result: Identification) -> list[list[str]]:
    old, new = result.original_friction, result.friction
    return [[joint, f"{_number(old.viscous[j])} → {_number(new.viscous[j])}",
             f"{_number(old.coulomb[j])} → {_number(new.coulomb[j])}"]
            for j, joint in enumerate(result.model.joint_names)]


FRICTION_HEADER = ("joint", "viscous F_v (N m s/rad)", "Coulomb F_c (N m)")


def held_out_figure(result: Identification):
    """Measured τ (grey) against the URDF's (dashed) and the identified model's, one panel per measured joint."""
    plt = plotting.pyplot()  # the one matplotlib set-up: off-screen, no TeX from names, labels as paths
    t, measured, before, after = result.held_out
    joints = [j for j in range(result.model.n) if np.isfinite(result.sigma[j])]
    figure, axes = plt.subplots(len(joints), 1, sharex=True, figsize=(8, 1.2 + 1.6 * len(joints)),
                                constrained_layout=True, squeeze=False)
    for axis, j in zip(axes[:, 0], joints):
        axis.plot(t, measured[:, j], color="0.6", linewidth=0.8, label="measured")
        axis.plot(t, before[:, j], color="tab:red", linewidth=0.9, linestyle="--", label="URDF")
        axis.plot(t, after[:, j], color="tab:blue", linewidth=1.0, label="identified")
        name = result.model.joint_names[j]
        axis.set_title(f"{name}: RMS residual {_number(result.rms_before[j], 3)} (URDF), "
                       f"{_number(result.rms_after[j], 3)} (identified)", fontsize="small", loc="left")
        axis.set_ylabel(f"τ {name}", fontsize="small")
        axis.grid(alpha=0.3)
    axes[0, 0].legend(loc="upper right", fontsize="x-small", ncol=3)
    axes[-1, 0].set_xlabel("t (s)")
    figure.suptitle(f"{result.model.name}: torques on the held-out part of the log (N m, or N for prismatic joints)")
    return figure


def _markdown_table(header, rows) -> str:
    cells = [[render.markdown_escape(c) for c in row] for row in [list(header)] + rows]
    lines = ["| " + " | ".join(cells[0]) + " |", "|" + "---|" * len(header)]
    return "\n".join(lines + ["| " + " | ".join(row) + " |" for row in cells[1:]])


def _facts(result: Identification, urdf: str, log: str) -> list[str]:
    fitted, held = result.samples
    condition = _number(result.condition_number, 3)
    return [f"URDF {urdf}, log {log}",
            f"{fitted} samples fitted, {held} held out (from t = {result.split_t:.6g} s)",
            f"friction identified: {result.friction_model}; solver {result.solver}",
            f"condition number of the weighted base regressor (unit-norm columns): {condition}"]


def _sections(result: Identification):
    """(title, header, rows) of every table, in the order of the report."""
    return [("Held-out residuals (measured − predicted)", RESIDUAL_HEADER, residual_rows(result)),
            ("Base parameters", BASE_HEADER, base_rows(result)),
            ("Bodies", BODY_HEADER, body_rows(result)),
            ("What the log determined, body by body", SEEN_HEADER, seen_rows(result)),
            ("Friction", FRICTION_HEADER, friction_rows(result))]


def _excitation(result: Identification) -> list[str]:
    lines = [f"hardly excited (singular value {share:.2g} of the largest): {combination}"
             for share, combination in result.unexcited] or ["every base parameter is excited by the log"]
    if result.never_act:
        lines.append("no motion can reveal (they stay at the URDF's values unless a body's consistency needs "
                     f"them to move): {', '.join(result.never_act)}")
    lines += [f"a physical constraint is active: {line}" for line in result.active]
    lines += [f"warning: moved far from the URDF: {line}" for line in result.far]
    return lines + list(result.notes)


def report_markdown(result: Identification, urdf: str, log: str) -> str:
    parts = [f"# Identification of {render.markdown_escape(result.model.name)}", ""]
    parts += [f"* {render.markdown_escape(line)}" for line in _facts(result, urdf, log)] + [""]
    for title, header, rows in _sections(result):
        parts += [f"## {title}", "", _markdown_table(header, rows), ""]
    parts += ["## What the log excites", ""] + [f"* {render.markdown_escape(x)}" for x in _excitation(result)]
    parts += ["", "![torques on the held-out part](held_out.svg)", ""]
    return "\n".join(parts)


def report_html(result: Identification, urdf: str, log: str, svg: str) -> str:
    title = f"Identification of {result.model.name}"
    body = [page.heading(title), page.bullet_list(_facts(result, urdf, log))]
    for section_title, header, rows in _sections(result):
        body.append(page.section(section_title, page.table(rows, header=header, css="numbers")))
    body.append(page.section("What the log excites", page.bullet_list(_excitation(result))))
    body.append(page.figure(page.svg(svg), "Measured torques against the URDF's and the identified model's"))
    return page.page(title, body)


def report_files(result: Identification, urdf: str, log: str) -> dict[str, str | bytes]:
    """Every file of the report folder (:data:`REPORT_FILES`), by name.

    Parameters
    ----------
    result : Identification
        The identification (:class:`~course_dynamics.tools.identification.Identification`).
    urdf : str
        The URDF identified, as the report names it.
    log : str
        The log it was identified from, as the report names it.

    Returns
    -------
    dict of str to str
        File name → its text (the HTML page, the Markdown, the JSON record, the SVG figure).

    Raises
    ------
    InputError
        If a value of the record is not finite (:func:`~course_dynamics.output.render.json_text`).
    """
    svg = plotting.figure_bytes(held_out_figure(result), "svg").decode("utf-8")
    document = {"urdf": urdf, "log": log, **result.record()}
    return {"report.html": report_html(result, urdf, log, svg), "report.md": report_markdown(result, urdf, log),
            "report.json": render.json_text(document) + "\n", "held_out.svg": svg}


def check_report_folder(folder, also=()) -> None:
    """Fail before long work unless the report (and the files named ``also``) can be written into ``folder``.

    Parameters
    ----------
    folder : str or pathlib.Path
        The report folder (it need not exist yet).
    also : iterable of str, optional
        Other files to be written with the report (the identified URDF).

    Raises
    ------
    InputError
        If a file in the way was not written there by ``identify``, or the folder cannot be written
        (:func:`~course_dynamics.output.folders.check_folder`).
    """
    folders.check_folder(folder, REPORT_FILES + tuple(also), OWNER)


def write_report(folder, result: Identification, urdf: str, log: str, also=None):
    """Write the report folder (module docstring) and the files ``also`` (name → bytes, e.g. the identified
    URDF); returns the paths written.

    Parameters
    ----------
    folder : str or pathlib.Path
        The report folder, made if missing.
    result : Identification
        The identification (:class:`~course_dynamics.tools.identification.Identification`).
    urdf : str
        The URDF identified, as the report names it.
    log : str
        The log it was identified from, as the report names it.
    also : Mapping of str to bytes, optional
        Other files to write into the folder, by name.

    Returns
    -------
    list of pathlib.Path
        The paths written.

    Raises
    ------
    InputError
        If a file in the way was not written there by ``identify``, the folder cannot be written
        (:func:`~course_dynamics.output.folders.write_folder`), or a value of the record is not finite.
    """
    return folders.write_folder(folder, {**dict(also or {}), **report_files(result, urdf, log)}, OWNER)


__all__ = ["REPORT_FILES", "RESIDUAL_HEADER", "check_report_folder", "report_files", "residual_rows", "write_report"]

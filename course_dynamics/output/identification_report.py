"""The identification report: a folder with ``report.html``, ``report.md``, ``report.json`` and ``held_out.svg``.

================  ===============================================================================
file              holds
================  ===============================================================================
``report.html``   one page (:mod:`~course_dynamics.output.page`): the held-out residuals, the
                  base parameters before and after with their standard errors, every body's
                  parameters, what the log determined of each and what stayed at the URDF's
                  (with the bodies that moved far), friction, the drives (rotor inertia and
                  torque offset, ± one standard error) when given or identified, what the log
                  does not excite, and the figure inline
``report.md``     the same tables in Markdown (names escaped), the figure as a link
``report.json``   :meth:`~course_dynamics.tools.identification.Identification.record`, with the
                  URDF and log named and what reading the log did (``log_notes``)
``held_out.svg``  measured torques against the URDF's and the identified model's, joint by joint,
                  on the held-out part of the log (matplotlib)
================  ===============================================================================

The folder is written by :func:`~course_dynamics.output.folders.write_folder` for the command
``identify``: files the user put there are never replaced. A payload's folder (``identify --scope payload``,
:func:`payload_report_files`) holds ``report.html``, ``report.md`` and ``report.json``: the payload's mass, centre
of mass and inertia with standard errors (:func:`payload_rows`), UR's and Franka's forms (:func:`payload_forms`),
and :meth:`~course_dynamics.tools.payloads.PayloadIdentification.record`.

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


def drive_rows(result: Identification) -> list[list[str]]:
    """Per joint: armature and offset, given → identified ± one standard error (``given`` where not fitted).

    Parameters
    ----------
    result : Identification
        The identification (:class:`~course_dynamics.tools.identification.Identification`) with drives.

    Returns
    -------
    list of list of str
        One row per joint in the columns of :data:`DRIVES_HEADER`; none without drives.
    """
    if result.drives is None:
        return []
    old, new, error = result.original_drives, result.drives, result.drive_error

    def cell(before, after, e):
        if not np.isfinite(e):
            return f"{_number(before)} (not fitted)"
        return f"{_number(before)} → {_number(after)} ± {_number(e, 2)}"
    return [[joint, cell(old.armature[j], new.armature[j], error[0, j]),
             cell(old.offset[j], new.offset[j], error[1, j])] for j, joint in enumerate(result.model.joint_names)]


#: The columns of :func:`drive_rows`.
DRIVES_HEADER = ("joint", "armature I_a (kg m², kg)", "offset τ₀ (N m, N)")


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


def _facts(result: Identification, urdf: str, log: str, log_notes=()) -> list[str]:
    fitted, held = result.samples
    condition = _number(result.condition_number, 3)
    return [f"URDF {urdf}, log {log}",
            f"{fitted} samples fitted, {held} held out (from t = {result.split_t:.6g} s)",
            f"friction identified: {result.friction_model}; solver {result.solver}",
            f"condition number of the weighted base regressor (unit-norm columns): {condition}"] + [
        f"the log: {note}" for note in log_notes]


def _sections(result: Identification):
    """(title, header, rows) of every table, in the order of the report."""
    return [("Held-out residuals (measured − predicted)", RESIDUAL_HEADER, residual_rows(result)),
            ("Base parameters", BASE_HEADER, base_rows(result)),
            ("Bodies", BODY_HEADER, body_rows(result)),
            ("What the log determined, body by body", SEEN_HEADER, seen_rows(result)),
            ("Friction", FRICTION_HEADER, friction_rows(result))] + (
        [("Drives (rotor inertia, torque offset)", DRIVES_HEADER, drive_rows(result))] if result.drives else [])


def _excitation(result: Identification) -> list[str]:
    lines = [f"hardly excited (singular value {share:.2g} of the largest): {combination}"
             for share, combination in result.unexcited] or ["every base parameter is excited by the log"]
    if result.never_act:
        lines.append("no motion can reveal (they stay at the URDF's values unless a body's consistency needs "
                     f"them to move): {', '.join(result.never_act)}")
    lines += [f"a physical constraint is active: {line}" for line in result.active]
    lines += [f"warning: moved far from the URDF: {line}" for line in result.far]
    return lines + list(result.notes)


def report_markdown(result: Identification, urdf: str, log: str, log_notes=()) -> str:
    parts = [f"# Identification of {render.markdown_escape(result.model.name)}", ""]
    parts += [f"* {render.markdown_escape(line)}" for line in _facts(result, urdf, log, log_notes)] + [""]
    for title, header, rows in _sections(result):
        parts += [f"## {title}", "", _markdown_table(header, rows), ""]
    parts += ["## What the log excites", ""] + [f"* {render.markdown_escape(x)}" for x in _excitation(result)]
    parts += ["", "![torques on the held-out part](held_out.svg)", ""]
    return "\n".join(parts)


def report_html(result: Identification, urdf: str, log: str, svg: str, log_notes=()) -> str:
    title = f"Identification of {result.model.name}"
    body = [page.heading(title), page.bullet_list(_facts(result, urdf, log, log_notes))]
    for section_title, header, rows in _sections(result):
        body.append(page.section(section_title, page.table(rows, header=header, css="numbers")))
    body.append(page.section("What the log excites", page.bullet_list(_excitation(result))))
    body.append(page.figure(page.svg(svg), "Measured torques against the URDF's and the identified model's"))
    return page.page(title, body)


def report_files(result: Identification, urdf: str, log: str, log_notes=()) -> dict[str, str | bytes]:
    """Every file of the report folder (:data:`REPORT_FILES`), by name.

    Parameters
    ----------
    result : Identification
        The identification (:class:`~course_dynamics.tools.identification.Identification`).
    urdf : str
        The URDF identified, as the report names it.
    log : str
        The log it was identified from, as the report names it.
    log_notes : sequence of str
        What reading the log did (the notes of its :class:`~course_dynamics.tools.logs.JointLog`: differentiated,
        filled, resampled, split, dropped), listed with the facts and as ``log_notes`` in the JSON.

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
    document = {"urdf": urdf, "log": log, "log_notes": list(log_notes), **result.record()}
    return {"report.html": report_html(result, urdf, log, svg, log_notes),
            "report.md": report_markdown(result, urdf, log, log_notes),
            "report.json": render.json_text(document) + "\n", "held_out.svg": svg}


#: The files of a payload's report folder (``identify --scope payload --out DIR``).
PAYLOAD_REPORT_FILES = ("report.html", "report.md", "report.json")
#: The columns of the payload's table.
PAYLOAD_HEADER = ("quantity", "identified ± σ", "unit", "frame")


def _estimate(value, error, determined: bool) -> str:
    if not determined or not np.isfinite(value):
        return "not determined"
    return f"{value:.5g} ± {error:.2g}"


def payload_rows(result, model) -> list[list[str]]:
    """The payload's table (:data:`PAYLOAD_HEADER`): mass, centre of mass and inertia about it with standard errors,
    then UR's and Franka's forms.

    Parameters
    ----------
    result : PayloadIdentification
        The payload (:class:`~course_dynamics.tools.payloads.PayloadIdentification`).
    model : Model
        The robot it was identified on.

    Returns
    -------
    list of list of str
        One row per quantity.
    """
    known = result.determined
    rows = [["mass m", _estimate(result.mass, result.mass_sigma, known["mass"]), "kg", ""]]
    rows += [[f"centre of mass c_{axis}", _estimate(result.com[k], result.com_sigma[k], True), "m",
              result.link] for k, axis in enumerate("xyz")]
    upper = ((0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2))
    rows += [[f"inertia about c, I_{'xyz'[a]}{'xyz'[b]}", _estimate(result.inertia[a, b], result.inertia_sigma[k],
                                                                     known["inertia"]), "kg m²", result.link]
             for k, (a, b) in enumerate(upper)]
    return rows


def payload_forms(result, model) -> list[str]:
    """The payload as the robots' controllers take it, one line each (none unless it is detected with its centre of
    mass): UR's ``set_payload`` and Franka's load, each in its flange frame.

    Parameters
    ----------
    result : PayloadIdentification
        The payload (:class:`~course_dynamics.tools.payloads.PayloadIdentification`).
    model : Model
        The robot it was identified on.

    Returns
    -------
    list of str
        ``UR (frame tool0): set_payload(…)``, ``Franka (frame panda_link8): mass = …``.
    """
    if not (result.detected and result.determined["com"]):
        return []
    names = {"ur": "UR", "franka": "Franka"}
    return [f"{names[key]} (frame {form['frame']}): {form['call']}" for key, form in result.robot_forms(model).items()]


def payload_report_files(result, model, urdf: str, log: str) -> dict[str, str]:
    """The payload's report folder (:data:`PAYLOAD_REPORT_FILES`): its table, notes and record, by file name.

    Parameters
    ----------
    result : PayloadIdentification
        The payload (:class:`~course_dynamics.tools.payloads.PayloadIdentification`).
    model : Model
        The robot it was identified on.
    urdf : str
        The URDF, as the report names it.
    log : str
        The log, as the report names it.

    Returns
    -------
    dict of str to str
        File name → its text.

    Raises
    ------
    InputError
        If a value of the record is not finite (:func:`~course_dynamics.output.render.json_text`).
    """
    title = f"Payload on {model.name} ({result.link})"
    fitted, held = result.samples
    facts = [f"URDF {urdf}, log {log}", f"{fitted} samples fitted, {held} held out; friction identified: "
             f"{result.friction_model}; {result.solver}",
             "payload detected" if result.detected else "no payload detected"] + payload_forms(result, model) \
        + list(result.notes)
    rows = payload_rows(result, model)
    markdown = "\n".join([f"# {render.markdown_escape(title)}", ""] + [f"* {render.markdown_escape(x)}" for x in facts]
                         + ["", _markdown_table(PAYLOAD_HEADER, rows), ""])
    html = page.page(title, [page.heading(title), page.bullet_list(facts),
                             page.section("Payload", page.table(rows, header=PAYLOAD_HEADER, css="numbers"))])
    document = {"urdf": urdf, "log": log, **result.record(model)}
    return {"report.html": html, "report.md": markdown, "report.json": render.json_text(document) + "\n"}


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


def write_report(folder, result: Identification, urdf: str, log: str, also=None, log_notes=()):
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
    log_notes : sequence of str
        What reading the log did, as :func:`report_files` lists it.

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
    return folders.write_folder(folder, {**dict(also or {}), **report_files(result, urdf, log, log_notes)}, OWNER)


__all__ = ["DRIVES_HEADER", "PAYLOAD_HEADER", "PAYLOAD_REPORT_FILES", "REPORT_FILES", "RESIDUAL_HEADER",
           "check_report_folder", "drive_rows", "payload_forms", "payload_report_files", "payload_rows", "report_files",
           "residual_rows", "write_report"]

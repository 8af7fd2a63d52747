"""Pictures of a motion (matplotlib, drawn off-screen; PNG or SVG by the file's suffix).

:func:`plot_trajectory` draws one run (Θ(t), Θ̇(t), E(t)); :func:`plot_ensemble`
draws how far the members of an ensemble drift from the first one;
:func:`plot_torques` draws τ(t) per joint against its effort limit (also as a
self-contained HTML page with the limits table); :func:`plot_residuals` draws a
momentum observer's r(t) with its thresholds and contact events. Files are written whole or not
at all (:mod:`course_dynamics.output.io`).
"""
from __future__ import annotations

from io import BytesIO
from pathlib import Path

from ..base.errors import InputError
from ..tools.simulation import Trajectory
from . import io, page

#: The picture formats of a plot file, by its suffix.
PLOT_FORMATS = ("png", "svg")
#: What every ``--plot`` takes, the picture formats and ``html`` (a page with the figure inline).
FIGURE_FORMATS = PLOT_FORMATS + ("html",)   # what every --plot takes: html is a page with the figure inline
#: The most joints a torque figure draws (one panel each).
MAX_PANELS = 24   # a torque figure draws one panel per joint: 24 already make a picture 37 inches tall


def check_panels(model) -> None:
    """InputError (naming ``--plot`` and the joints) when the torque figure would need more than
    :data:`MAX_PANELS` panels.

    Refused rather than cut to the first 24: a figure of the limits that silently leaves out joints could hide the one
    beyond its limit, and every joint is in the table and the JSON anyway.

    Parameters
    ----------
    model : Model
        The robot.

    Raises
    ------
    InputError
        If the robot has more than :data:`MAX_PANELS` joints.
    """
    if model.n > MAX_PANELS:
        raise InputError(f"--plot draws one panel per joint, at most {MAX_PANELS}: robot '{model.name}' has {model.n} "
                         "joints; leave out --plot (the table, the CSV and --json hold every joint)")


def plot_format(path, formats=PLOT_FORMATS) -> str:
    """The picture format of ``path`` from its suffix; InputError for another one.

    Parameters
    ----------
    path : str or pathlib.Path
        The file to be written.
    formats : tuple of str, optional
        The formats taken (:data:`PLOT_FORMATS` by default, :data:`FIGURE_FORMATS` with ``html``).

    Returns
    -------
    str
        The suffix, lower case, without its dot (``"png"``).

    Raises
    ------
    InputError
        If the suffix is not one of ``formats``.

    Examples
    --------
    >>> plot_format("run.SVG")
    'svg'
    """
    fmt = Path(str(path)).suffix.lower().lstrip(".")
    if fmt not in formats:
        raise InputError(f"{path}: a plot is written as {', '.join('.' + f for f in formats)} (by the file's suffix)")
    return fmt


def figure_bytes(figure, fmt: str) -> bytes:
    """The figure drawn as ``fmt`` (png or svg); the figure is closed.

    The same figure gives the same bytes on every run: an SVG carries no date, and its element ids come from a
    fixed salt rather than a random one.

    Parameters
    ----------
    figure : matplotlib.figure.Figure
        The figure.
    fmt : str
        ``"png"`` or ``"svg"``.

    Returns
    -------
    bytes
        The file's bytes.
    """
    import matplotlib
    import matplotlib.pyplot as plt

    buffer = BytesIO()
    with matplotlib.rc_context({"svg.hashsalt": "course-dynamics"}):
        figure.savefig(buffer, format=fmt, dpi=110, metadata={"Date": None} if fmt == "svg" else None)
    plt.close(figure)
    return buffer.getvalue()


def figure_file(figure, fmt: str, title: str = "") -> bytes:
    """The figure as the bytes of a ``fmt`` file (:data:`FIGURE_FORMATS`): png, svg, or a page holding the SVG.

    Parameters
    ----------
    figure : matplotlib.figure.Figure
        The figure (closed afterwards).
    fmt : str
        ``"png"``, ``"svg"`` or ``"html"``.
    title : str, optional
        The page's title and heading (``html`` only); ``"figure"`` when empty.

    Returns
    -------
    bytes
        The file's bytes (a page in UTF-8 for ``html``).
    """
    if fmt != "html":
        return figure_bytes(figure, fmt)
    drawing = figure_bytes(figure, "svg").decode("utf-8")
    name = title or "figure"
    return page.page(name, [page.heading(name), page.figure(page.svg(drawing))]).encode("utf-8")


def _save(figure, path) -> None:
    import matplotlib.pyplot as plt

    data = figure_bytes(figure, plot_format(path))
    plt.close(figure)
    io.write_bytes(path, data)


def pyplot():
    """``matplotlib.pyplot``, set up to draw off-screen (Agg), with no TeX from names and SVG labels as paths.

    Every figure of the project is drawn through it: a ``$`` in a joint name is a dollar sign, and no text
    from a URDF reaches an SVG as text.

    Returns
    -------
    module
        ``matplotlib.pyplot``.
    """
    import matplotlib

    matplotlib.use("Agg")  # no screen needed
    matplotlib.rcParams["text.parse_math"] = False  # a '$' in a joint name is a dollar sign, not TeX
    matplotlib.rcParams["svg.fonttype"] = "path"    # labels as paths: no text from a URDF reaches the SVG
    import matplotlib.pyplot as plt

    return plt


def plot_trajectory(trajectory: Trajectory, path, title: str = "") -> None:
    """Joint positions Θ(t), velocities Θ̇(t) and total energy E(t), stacked, saved as ``path`` (PNG or SVG).

    Parameters
    ----------
    trajectory : Trajectory
        One simulated run (:class:`~course_dynamics.tools.simulation.Trajectory`): Θ, Θ̇ of shape (T, n),
        rad or m and rad/s or m/s; E in J.
    path : str or pathlib.Path
        The file to write, ``.png`` or ``.svg``.
    title : str, optional
        The figure's title.

    Raises
    ------
    InputError
        If the suffix is neither, or ``path`` cannot be written.
    """
    _save(trajectory_figure(trajectory, title), path)


def trajectory_figure(trajectory: Trajectory, title: str = ""):
    """The figure of :func:`plot_trajectory`.

    Parameters
    ----------
    trajectory : Trajectory
        One simulated run (:class:`~course_dynamics.tools.simulation.Trajectory`).
    title : str, optional
        The figure's title.

    Returns
    -------
    matplotlib.figure.Figure
        Three panels sharing t, s: Θ(t), Θ̇(t) and E(t).
    """
    plt = pyplot()

    figure, axes = plt.subplots(3, 1, sharex=True, figsize=(8, 7.5), constrained_layout=True)
    for j, name in enumerate(trajectory.joints):
        axes[0].plot(trajectory.t, trajectory.q[:, j], label=name)
        axes[1].plot(trajectory.t, trajectory.qd[:, j], label=name)
    axes[2].plot(trajectory.t, trajectory.energy, color="black")
    axes[0].set_ylabel("Θ (rad or m)")
    axes[1].set_ylabel("dΘ/dt (rad/s or m/s)")  # the combining dot of Θ̇ is lost in most fonts
    axes[2].set_ylabel("E = k + u (J)")
    axes[2].set_xlabel("t (s)")
    axes[0].legend(loc="upper right", fontsize="small", ncol=min(len(trajectory.joints), 4))
    if title:
        axes[0].set_title(title)
    for axis in axes:
        axis.grid(alpha=0.3)
    return figure


def plot_ensemble(trajectory: Trajectory, path, title: str = "") -> None:
    """Divergence of an ensemble from member 0: max over joints of ``|Θₖ(t) − Θ₀(t)|``, log scale, and Θ of every
    member.

    Parameters
    ----------
    trajectory : Trajectory
        An ensemble run (:class:`~course_dynamics.tools.simulation.Trajectory`): Θ of shape (T, K, n), K ≥ 2.
    path : str or pathlib.Path
        The file to write, ``.png`` or ``.svg``.
    title : str, optional
        The figure's title.

    Raises
    ------
    InputError
        If the suffix is neither, or ``path`` cannot be written.
    """
    _save(ensemble_figure(trajectory, title), path)


def ensemble_figure(trajectory: Trajectory, title: str = ""):
    """The figure of :func:`plot_ensemble`.

    Parameters
    ----------
    trajectory : Trajectory
        An ensemble run (:class:`~course_dynamics.tools.simulation.Trajectory`), Θ of shape (T, K, n), K ≥ 2.
    title : str, optional
        The figure's title; by default the number of members.

    Returns
    -------
    matplotlib.figure.Figure
        Two panels sharing t, s: the divergence (rad or m, log scale) and Θ of every member.
    """
    import numpy as np

    plt = pyplot()

    q, t = trajectory.q, trajectory.t
    distance = np.abs(q[:, 1:, :] - q[:, :1, :]).max(axis=-1)  # (T, K − 1)
    figure, axes = plt.subplots(2, 1, sharex=True, figsize=(8, 7), constrained_layout=True)
    alpha = max(0.05, min(0.5, 20 / distance.shape[1]))   # many members: each fainter
    axes[0].semilogy(t, np.maximum(distance, 1e-17), color="tab:blue", alpha=alpha, linewidth=0.8)
    axes[0].semilogy(t, np.maximum(np.median(distance, axis=1), 1e-17), color="black", linewidth=2, label="median")
    # Plain "1e-05" labels: the default ones are TeX, which a figure here never parses (text.parse_math is off).
    from matplotlib.ticker import LogFormatter

    axes[0].yaxis.set_major_formatter(LogFormatter(labelOnlyBase=True))
    axes[0].set_ylabel("max_j |θ_j(t) − θ_j of member 0| (rad or m)")
    axes[0].legend(loc="lower right")
    for j, name in enumerate(trajectory.joints):
        axes[1].plot(t, q[:, :, j], linewidth=0.6, alpha=max(0.05, min(0.6, 20 / q.shape[1])), color=f"C{j}")
        axes[1].plot([], [], color=f"C{j}", label=name)
    axes[1].set_ylabel("Θ (rad or m), every member")
    axes[1].set_xlabel("t (s)")
    axes[1].legend(loc="upper right", fontsize="small")
    axes[0].set_title(title or f"{q.shape[1]} members: divergence from member 0")
    for axis in axes:
        axis.grid(alpha=0.3)
    return figure


def torque_figure(result, title: str = ""):
    """τ(t) of a :class:`~course_dynamics.tools.logs.TorqueLog`, one panel per joint, effort limits as bands;
    where the robot measured its torques, those in grey beneath ours, with the residual in the panel's title.

    Parameters
    ----------
    result : TorqueLog
        The torques of a log (:class:`~course_dynamics.tools.logs.TorqueLog`), τ of shape (N, n), N·m (N for
        a prismatic joint).
    title : str, optional
        The figure's title; by default the robot's name and a key to the bands.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per joint.

    Raises
    ------
    InputError
        If the robot has more than :data:`MAX_PANELS` joints.
    """
    import numpy as np

    model, report = result.model, result.report
    check_panels(model)
    plt = pyplot()
    n = model.n
    figure, axes = plt.subplots(n, 1, sharex=True, figsize=(8, 1.2 + 1.5 * n), constrained_layout=True, squeeze=False)
    residuals = {r.joint: r for r in result.residuals.joints} if result.residuals is not None else {}
    for j, (axis, name) in enumerate(zip(axes[:, 0], model.joint_names)):
        tau = result.tau[:, j]
        shown = [tau]
        if name in residuals:
            measured = result.log.measured[:, j]
            axis.plot(result.t, measured, color="0.55", linewidth=0.8, label="measured")
            shown.append(measured)
        axis.plot(result.t, tau, color=f"C{j}", linewidth=1.0, label="ours")
        if name in residuals:
            axis.legend(loc="upper right", fontsize="x-small")
        limit = report.effort[j]
        if np.isfinite(limit):
            top = max(limit, max(np.abs(s).max() for s in shown)) * 1.15
            axis.axhspan(limit, top, color="tab:red", alpha=0.15, linewidth=0)
            axis.axhspan(-top, -limit, color="tab:red", alpha=0.15, linewidth=0)
            axis.set_ylim(-top, top)
            used = f"{100 * report.effort_used[j]:.0f}% of {limit:g}"
        else:
            used = "no effort limit in the URDF"
        for v in report.violations:
            if v.joint == name:
                axis.axvspan(v.start, v.end, color="tab:red" if v.kind == "effort" else "tab:orange", alpha=0.3,
                             linewidth=0)
        axis.set_ylabel(f"τ {name}", fontsize="small")
        fit = ""
        if name in residuals:
            r = residuals[name]
            fit = f"; residual rms {r.rms:.3g}" + ("" if r.r2 is None else f", R² {r.r2:.3f}")
        axis.set_title(f"{name}: peak {report.peak_tau[j]:.4g}, rms {report.rms_tau[j]:.4g} ({used}){fit}",
                       fontsize="small", loc="left")
        axis.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("t (s)")
    figure.suptitle(title or f"{model.name}: joint torques (N m, or N for prismatic joints)\n"
                             "red bands: the effort limit; shaded in time: red beyond it, "
                             "orange beyond the velocity limit")
    return figure


def torques_page(result, title: str = "") -> str:
    """A self-contained HTML page: the torque figure (SVG) and the limits table; every name escaped.

    Parameters
    ----------
    result : TorqueLog
        The torques of a log (:class:`~course_dynamics.tools.logs.TorqueLog`).
    title : str, optional
        The page's title and heading; by default the robot's name.

    Returns
    -------
    str
        The HTML page: the verdict, the limits table, the violations, the residuals against measured torques,
        the derived signals and the figure.

    Raises
    ------
    InputError
        If the robot has more than :data:`MAX_PANELS` joints.
    """
    plt = pyplot()
    figure = torque_figure(result, title)
    svg = figure_bytes(figure, "svg").decode("utf-8")
    plt.close(figure)

    def cell(x, share=False):
        if x is None:
            return "–"
        if share:
            return f"{100 * x:.0f}%"
        return f"{x:.4g}" if isinstance(x, float) else str(x)

    header = ("joint", "peak |τ|", "RMS τ", "effort limit", "used", "peak |q̇|", "velocity limit", "used")
    keys = ("joint", "peak_tau", "rms_tau", "effort_limit", "effort_used", "peak_qd", "velocity_limit", "velocity_used")
    rows = [[cell(r[k], k.endswith("_used")) for k in keys] for r in result.report.rows()]
    heading = title or f"{result.model.name}: joint torques and limits"
    verdict = "A limit is exceeded." if result.report.exceeded else "Every joint stays within its limits."
    body = [page.heading(heading), page.paragraph(verdict), page.table(rows, header=header, css="numbers")]
    if result.report.violations:
        body.append(page.section("Violations", page.bullet_list(v.describe() for v in result.report.violations)))
    if result.residuals is not None:
        fit = [[r.joint, cell(r.rms_measured), cell(r.rms), cell(r.peak), cell(r.peak_t), cell(r.r2)]
               for r in result.residuals.joints]
        body.append(page.section(f"The model against the robot (measured: {result.residuals.source})",
                                 page.table(fit, header=("joint", "RMS τ measured", "RMS residual", "peak residual",
                                                         "at t (s)", "R²"), css="numbers")))
    if result.notes:
        body.append(page.section("Derived signals", page.bullet_list(result.notes)))
    body.append(page.figure(page.svg(svg)))
    return page.page(heading, body)


def plot_torques(result, path, title: str = "") -> None:
    """Draw τ(t) against the effort limits to ``path``: PNG, SVG, or HTML (figure and limits table).

    Parameters
    ----------
    result : TorqueLog
        The torques of a log (:class:`~course_dynamics.tools.logs.TorqueLog`).
    path : str or pathlib.Path
        The file to write: ``.png``, ``.svg`` or ``.html``.
    title : str, optional
        The figure's (and page's) title.

    Raises
    ------
    InputError
        If the suffix is none of these, the robot has more than :data:`MAX_PANELS` joints, or ``path`` cannot
        be written.
    """
    fmt = plot_format(path, FIGURE_FORMATS)
    if fmt == "html":
        io.write_text(path, torques_page(result, title))
        return
    _save(torque_figure(result, title), path)


def residual_figure(found, title: str = ""):
    """r(t) of a :class:`~course_dynamics.tools.collisions.Detection`, one panel per measured joint, its threshold
    as dashed lines and the contact events shaded.

    Parameters
    ----------
    found : Detection
        What :func:`~course_dynamics.tools.collisions.detect` found: r of shape (K, n), N·m (N for a prismatic
        joint).
    title : str, optional
        The figure's title; by default the robot's joints and a key.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per measured joint.

    Raises
    ------
    InputError
        If more than :data:`MAX_PANELS` joints were measured.
    """
    if len(found.measured) > MAX_PANELS:
        raise InputError(f"--plot draws one panel per joint, at most {MAX_PANELS}: {len(found.measured)} joints were "
                         "measured; leave out --plot (the CSV and --json hold every joint)")
    plt = pyplot()
    n = len(found.measured)
    figure, axes = plt.subplots(n, 1, sharex=True, figsize=(8, 1.2 + 1.3 * n), constrained_layout=True, squeeze=False)
    for axis, name in zip(axes[:, 0], found.measured):
        j = found.joints.index(name)
        theta = found.threshold[j]
        for e in found.events:
            axis.axvspan(e.start, e.end, color="tab:red", alpha=0.2, linewidth=0)
        if found.band is None:
            axis.axhline(theta, color="0.4", linestyle="--", linewidth=0.8)
            axis.axhline(-theta, color="0.4", linestyle="--", linewidth=0.8)
        else:   # the threshold with the friction model's band at each sample
            axis.plot(found.t, theta + found.band[:, j], color="0.4", linestyle="--", linewidth=0.8)
            axis.plot(found.t, -theta - found.band[:, j], color="0.4", linestyle="--", linewidth=0.8)
        axis.plot(found.t, found.r[:, j], color=f"C{j}", linewidth=0.9)
        peaks = [p for e in found.events for joint, p in zip(e.joints, e.peak) if joint == name]
        peak = f"; peak in a contact {max(peaks, key=abs):+.3g}" if peaks else ""
        axis.set_title(f"{name}: K {found.gain[j]:.3g} 1/s, threshold {theta:.3g}{peak}", fontsize="small", loc="left")
        axis.set_ylabel(f"r {name}", fontsize="small")
        axis.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("t (s)")
    figure.suptitle((title or "momentum observer") + "\nr(t) -> the external joint torques (N m, or N); dashed: the "
                    "thresholds; shaded: the contact events")
    return figure


def plot_residuals(found, path, title: str = "") -> None:
    """Draw the observer's r(t) with thresholds and events (:func:`residual_figure`) to ``path``: PNG, SVG or HTML.

    Parameters
    ----------
    found : Detection
        What :func:`~course_dynamics.tools.collisions.detect` found.
    path : str or pathlib.Path
        The file to write: ``.png``, ``.svg`` or ``.html``.
    title : str, optional
        The figure's (and page's) title.

    Raises
    ------
    InputError
        If the suffix is none of these, too many joints were measured, or ``path`` cannot be written.
    """
    fmt = plot_format(path, FIGURE_FORMATS)
    data = figure_file(residual_figure(found, title), fmt, title)
    (io.write_text(path, data.decode("utf-8")) if fmt == "html" else io.write_bytes(path, data))


__all__ = ["FIGURE_FORMATS", "MAX_PANELS", "PLOT_FORMATS", "check_panels", "ensemble_figure", "figure_bytes",
           "figure_file", "plot_ensemble", "plot_format", "plot_residuals", "plot_torques", "plot_trajectory", "pyplot",
           "residual_figure", "torque_figure", "torques_page", "trajectory_figure"]

"""A comparison report worth handing out: course_dynamics against Pinocchio (and the textbook) for every term.

:func:`build_report` computes, per robot, the error of τ, M, C, V, G on seeded
random states (:func:`course_dynamics_reference.validate.term_errors`), τ along
a smooth trajectory by both libraries, and for the course robots the textbook's
closed forms against ours; :func:`write_report` writes

==================  ==============================================================
file                content
==================  ==============================================================
``index.html``      one self-contained page (:mod:`course_dynamics.output.page`):
                    figures inline as SVG, formulas as MathML, no script, no
                    request; opens from disk
``report.md``       the same for GitHub, with the figures as ``figures/*.svg``
``report.json``     ``{"robots": [{"name", "terms": {"tau": {"max", "median", …}}, …}],
                    "environment": {…}}``
==================  ==============================================================

Robot, joint and link names come from URDFs: they are escaped for HTML and
Markdown, and matplotlib draws every label as paths, never as SVG text.
"""
from __future__ import annotations

import datetime
import platform
from dataclasses import dataclass, field
from importlib import metadata, resources
from pathlib import Path

import numpy as np

from course_dynamics.core.dynamics import gravity_torques, mass_matrix, velocity_torques
from course_dynamics.core.newton_euler import inverse_dynamics
from course_dynamics.core.robots import load, resolve
from course_dynamics.core.sampling import (
    random_states,
    relative_error,
    smooth_trajectory,
    term_scales,
)
from course_dynamics.output import page, plotting, render
from course_dynamics.output.folders import write_folder

from . import TERMS, TOLERANCE, textbook
from .pinocchio_oracle import PinocchioOracle
from .validate import display_name, term_errors

TERM_TITLES = {"tau": "τ (inverse dynamics)", "M": "M (mass matrix)", "C": "C (Coriolis matrix)",
               "V": "V (velocity terms)", "G": "G (gravity)"}
CLOSED_FORMS = {"two_link": "Craig (6.60)–(6.62)", "rp_arm": "Craig example 6.5", "pendulum": "the pendulum equation"}


@dataclass
class RobotSection:
    """Everything the report says about one robot."""

    name: str
    urdf: str
    joints: list[dict]
    bodies: list[dict]
    terms: dict[str, dict[str, float]]
    trajectory: dict[str, float]
    textbook: dict[str, float] | None
    figures: dict[str, str] = field(default_factory=dict)  # name → SVG text


def _figure_svg(draw) -> str:
    """The figure ``draw(plt)`` makes, as SVG text drawn as the library draws every figure (labels as paths)."""
    return plotting.figure_bytes(draw(plotting.pyplot()), "svg").decode("utf-8")


def _error_histograms(relative: dict[str, np.ndarray], tolerance: float):
    def draw(plt):
        figure, axis = plt.subplots(figsize=(7.0, 3.4), constrained_layout=True)
        floor = 1e-18
        bins = np.linspace(-18, max(-8, np.log10(tolerance) + 1), 41)
        for term in TERMS:
            axis.hist(np.log10(np.maximum(relative[term], floor)), bins=bins, histtype="step", linewidth=1.6,
                      label=term)
        axis.axvline(np.log10(tolerance), color="black", linestyle="--", linewidth=1, label="tolerance")
        axis.set_xlabel("log10 relative error (ours vs Pinocchio; 0 exactly counted at -18)")
        axis.set_ylabel("states")
        axis.set_title("Distribution of the relative error per term")
        axis.legend(ncol=3, fontsize="small")
        return figure

    return draw


def _trajectory_plot(t, ours, theirs, joints):
    def draw(plt):
        figure, axis = plt.subplots(figsize=(7.0, 3.6), constrained_layout=True)
        for j, name in enumerate(joints):
            line, = axis.plot(t, ours[:, j], linewidth=2.2, alpha=0.6, label=f"{name} (ours)")
            axis.plot(t, theirs[:, j], linestyle="--", color=line.get_color(), linewidth=1.0,
                      label=f"{name} (Pinocchio)")
        axis.set_xlabel("t (s)")
        axis.set_ylabel("τ (N·m, or N for prismatic joints)")
        axis.set_title("τ along a smooth trajectory: ours (solid) and Pinocchio (dashed)")
        axis.legend(fontsize="x-small", ncol=2)
        return figure

    return draw


def robot_section(name_or_path: str, samples: int, seed: int, tolerance: float = TOLERANCE, progress=None,
                  gravity=None, allow_nonphysical_inertia: bool = False) -> RobotSection:
    """Compute one robot's section: errors per term, a trajectory, the textbook comparison, figures.

    Under a ``gravity`` of the caller's the textbook comparison is left out: the printed
    closed forms hold for the course's own gravity only.
    """
    urdf = resolve(name_or_path)
    given_gravity = {} if gravity is None else {"gravity": gravity}
    model = load(urdf, allow_nonphysical_inertia=allow_nonphysical_inertia, **given_gravity)
    oracle = PinocchioOracle(urdf, model.joint_names, model.gravity)
    q, qd, qdd = random_states(model, samples, seed)
    errors = term_errors(model, oracle, q, qd, qdd, progress=progress)
    terms = {t: {"max": float(a.max()), "median": float(np.median(a)), "max_relative": float(r.max()),
                 "median_relative": float(np.median(r)), "agrees": bool(r.max() <= tolerance)}
             for t, (a, r) in errors.items()}
    t, q_t, qd_t, qdd_t = smooth_trajectory(model, seed=seed)
    ours = inverse_dynamics(model, q_t, qd_t, qdd_t)
    theirs = np.array([oracle.tau(*state) for state in zip(q_t, qd_t, qdd_t)])
    trajectory = {"samples": len(t), "duration": float(t[-1]), "max_abs_difference": float(np.abs(ours - theirs).max()),
                  "max_abs_tau": float(np.abs(theirs).max())}
    section = RobotSection(
        name=display_name(name_or_path), urdf=str(urdf),
        joints=[{"name": b.joint, "type": b.joint_type, "lower": _finite(b.lower), "upper": _finite(b.upper)}
                for b in model.bodies],
        bodies=[{"link": b.name, "mass": float(b.mass)} for b in model.bodies], terms=terms, trajectory=trajectory,
        textbook=_textbook(name_or_path, model, q, qd) if gravity is None else None,
    )
    section.figures["errors"] = _figure_svg(_error_histograms({k: r for k, (_, r) in errors.items()}, tolerance))
    section.figures["trajectory"] = _figure_svg(_trajectory_plot(t, ours, theirs, model.joint_names))
    return section


def _finite(x: float):
    return float(x) if np.isfinite(x) else None


def _textbook(name: str, model, q, qd) -> dict[str, float] | None:
    """Largest relative error of our M, V, G against the course robot's printed closed forms."""
    forms = {"two_link": textbook.two_link, "rp_arm": textbook.rp_arm, "pendulum": textbook.pendulum}
    if name not in forms:
        return None
    M, V, G = mass_matrix(model, q), velocity_torques(model, q, qd), gravity_torques(model, q)
    worst = {"M": 0.0, "V": 0.0, "G": 0.0}
    for k in range(len(q)):
        printed = dict(zip(("M", "V", "G"), forms[name](q[k], qd[k], **textbook.COURSE_PARAMETERS[name])))
        scales = term_scales(printed["M"], printed["G"], qd[k], np.zeros(model.n), model.gravity)
        for key, ours in (("M", M[k]), ("V", V[k]), ("G", G[k])):
            worst[key] = max(worst[key], relative_error(ours, printed[key], scales[key]))
    return worst


def errata_count() -> int:
    """The number of misprints listed in the errata (rows of its "Misprints" table)."""
    text = resources.files("course_dynamics_reference").joinpath("errata.md").read_text(encoding="utf-8")
    table = text.split("## Misprints", 1)[1].split("\n\n", 2)[1]
    return sum(1 for line in table.splitlines() if line.startswith("| ") and not line.startswith("| where"))


def environment(seed: int, samples: int) -> dict:
    import pinocchio

    def version(package):
        try:
            return metadata.version(package)
        except metadata.PackageNotFoundError:
            return "unknown"

    return {"python": platform.python_version(), "numpy": np.__version__, "pinocchio": pinocchio.__version__,
            "course-dynamics": version("course-dynamics"), "seed": seed, "samples": samples,
            "date": datetime.date.today().isoformat(), "platform": platform.platform()}


@dataclass
class Report:
    robots: list[RobotSection]
    environment: dict
    tolerance: float
    misprints: int

    def as_dict(self) -> dict:
        # the URDF by its file name: a report is published, and the folders of this machine are nobody's business
        return {"robots": [{"name": r.name, "urdf": Path(r.urdf).name, "joints": r.joints, "bodies": r.bodies,
                            "terms": r.terms, "trajectory": r.trajectory, "textbook": r.textbook}
                           for r in self.robots],
                "tolerance": self.tolerance, "misprints_in_the_notes": self.misprints, "environment": self.environment}


def build_report(targets, samples: int = 200, seed: int = 0, tolerance: float = TOLERANCE, progress=None,
                 gravity=None, allow_nonphysical_inertia: bool = False) -> Report:
    """Compute the report for every robot in ``targets`` (paths or shipped names); options as :func:`robot_section`."""
    sections = [robot_section(t, samples, seed, tolerance, progress, gravity, allow_nonphysical_inertia)
                for t in targets]
    return Report(sections, environment(seed, samples), tolerance, errata_count())


def _number(x: float) -> str:
    return f"{x:.1e}"


def report_html(report: Report) -> str:
    env = report.environment
    parts = [page.heading("course-dynamics against Pinocchio"),
             page.paragraph("Every term of ",
                            page.math(r"\tau = M(\Theta)\ddot\Theta + V(\Theta, \dot\Theta) + G(\Theta)"),
                            " and the Coriolis matrix ", page.math("C"), ", computed by course-dynamics' hand-written "
                            f"Newton–Euler recursion and by Pinocchio on {env['samples']} seeded random states per "
                            f"robot (seed {env['seed']}). Relative error: ",
                            page.math(r"\lVert \text{ours} - \text{Pinocchio} \rVert_\infty / "
                                      r"\max(\lVert \text{Pinocchio} \rVert_\infty, s)"),
                            f", with s the term's scale; the project holds itself to {report.tolerance:g}.")]
    for r in report.robots:
        parts.append(page.heading(r.name, 2))
        joints = ", ".join(f"{j['name']} ({j['type']})" for j in r.joints)
        bodies = ", ".join(f"{b['link']} {b['mass']:.4g} kg" for b in r.bodies)
        parts.append(page.paragraph(f"{len(r.joints)} joints: {joints}; moving bodies: {bodies}."))
        rows = [(TERM_TITLES[t], _number(v["max"]), _number(v["median"]), _number(v["max_relative"]),
                 _number(v["median_relative"]), "yes" if v["agrees"] else "NO") for t, v in r.terms.items()]
        parts.append(page.table(rows, header=("term", "max abs", "median abs", "max rel", "median rel", "agrees"),
                                css="numbers"))
        parts.append(page.figure(page.svg(r.figures["errors"]), "Relative error per state and term."))
        parts.append(page.figure(page.svg(r.figures["trajectory"]),
                                 f"τ along a smooth {r.trajectory['duration']:g} s trajectory; the largest "
                                 f"difference is {_number(r.trajectory['max_abs_difference'])} "
                                 f"(τ up to {r.trajectory['max_abs_tau']:.3g})."))
        if r.textbook is not None:
            parts.append(page.paragraph(f"Against the textbook ({CLOSED_FORMS[r.name]}): largest relative error of M "
                                        f"{_number(r.textbook['M'])}, V {_number(r.textbook['V'])}, "
                                        f"G {_number(r.textbook['G'])}."))
    parts.append(page.section("The notes", page.paragraph(
        f"The errata list {report.misprints} misprints found in the lecture notes, each shown numerically by a test (",
        page.code("reference/errata.md"), " in the project).")))
    parts.append(page.section("Environment", page.table([(k, str(v)) for k, v in env.items()], css="numbers")))
    return page.page("course-dynamics against Pinocchio", parts)


def report_markdown(report: Report) -> str:
    e = render.markdown_escape
    env = report.environment
    lines = ["# course-dynamics against Pinocchio", "",
             f"Every term computed by course-dynamics and by Pinocchio on {env['samples']} seeded random states "
             f"per robot (seed {env['seed']}); relative error ‖ours − Pinocchio‖∞ / max(‖Pinocchio‖∞, "
             f"the term's scale), tolerance {report.tolerance:g}.", ""]
    for index, r in enumerate(report.robots):
        lines += [f"## {e(r.name)}", "",
                  f"{len(r.joints)} joints: " + ", ".join(f"{e(j['name'])} ({e(j['type'])})" for j in r.joints) + ".",
                  "",
                  "| term | max abs | median abs | max rel | median rel | agrees |", "|---|---|---|---|---|---|"]
        lines += [f"| {e(TERM_TITLES[t])} | {_number(v['max'])} | {_number(v['median'])} | "
                  f"{_number(v['max_relative'])} | {_number(v['median_relative'])} | "
                  f"{'yes' if v['agrees'] else 'NO'} |" for t, v in r.terms.items()]
        lines += ["", f"![relative errors](figures/robot{index}_errors.svg)", "",
                  f"![tau along a trajectory](figures/robot{index}_trajectory.svg)", "",
                  f"Along a smooth {r.trajectory['duration']:g} s trajectory the largest difference in τ is "
                  f"{_number(r.trajectory['max_abs_difference'])}.", ""]
        if r.textbook is not None:
            lines += [f"Against the textbook ({CLOSED_FORMS[r.name]}): largest relative error of M "
                      f"{_number(r.textbook['M'])}, V {_number(r.textbook['V'])}, G {_number(r.textbook['G'])}.", ""]
    lines += ["## The notes", "", f"The errata list {report.misprints} misprints found in the lecture notes.", "",
              "## Environment", "", "| | |", "|---|---|"]
    lines += [f"| {e(k)} | {e(str(v))} |" for k, v in env.items()]
    return "\n".join(lines) + "\n"


OWNER = "report"  # the command named in the output folder's manifest
FIGURES = ("errors", "trajectory")


def report_files(robots: int) -> list[str]:
    """The names :func:`write_report` writes for ``robots`` robots, relative to its folder."""
    return (["index.html", "report.md", "report.json"]
            + [f"figures/robot{index}_{key}.svg" for index in range(robots) for key in FIGURES])


def write_report(out: Path, report: Report) -> list[Path]:
    """index.html, report.md, report.json and figures/ in ``out`` (made if missing), each file whole or not at all.

    ``out`` may hold other files: :func:`course_dynamics.output.folders.write_folder` replaces only the files an
    earlier report wrote there and nobody changed since, refuses anything else in the way (a file it
    did not write, a ``figures`` that is a link) before writing any, and deletes nothing.
    """
    documents = {"index.html": report_html(report), "report.md": report_markdown(report),
                 "report.json": render.json_text(report.as_dict()) + "\n"}
    for index, r in enumerate(report.robots):
        for key in FIGURES:
            documents[f"figures/robot{index}_{key}.svg"] = r.figures[key]
    return write_folder(out, documents, OWNER)

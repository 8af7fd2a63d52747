"""The command line's grammar: every flag of every command, defined once.

A flag name has one meaning wherever it appears — one destination, type, choices, action and help
text (``tests/test_cli_grammar.py`` reads every parser and holds this). A command adds a flag with
:func:`add`, which may set only whether the flag is required and its default; what the flag does in
that command is the command's description. Outputs: ``--out`` is where the command's output goes,
``--plot`` a figure of it, ``--html`` an animation; ``--json`` prints the result as one JSON document and
``--quiet`` hides the progress bar. A log is read by ``--log`` and described by the ``--log-…`` flags.

An old spelling (:data:`RENAMES`) is still read for one release: :func:`add_renamed` adds it hidden,
and using it prints one ``warning: --old is now --new; …`` line through the warnings path.
"""
from __future__ import annotations

import argparse
import importlib
import warnings
from typing import NamedTuple

from ..core.cartesian import EXPRESSED_IN, MAX_CONDITION, ROW_NAMES
from ..core.symbolic import METHODS

FRICTION_SOURCES = ("none", "urdf")
SCOPES = ("robot", "payload")  # what identify identifies and excite excites for
LOG = ("the motion's log: a table (comma, semicolon, tab or whitespace separated; t, q_<joint>, and what else it "
       "has), a UR RTDE recording, a ROS 1/ROS 2 bag or an MCAP file - and so also what torques, simulate and "
       "excite write with --out")


class Later(NamedTuple):
    """A flag's choices kept by the module that owns them, read when a command adds the flag (a command then
    imports the tools it uses, and no other: ``info`` loads no log reader, viewer or simulation)."""

    module: str                 # under course_dynamics
    name: str
    convert: type = tuple

    def value(self):
        return self.convert(getattr(importlib.import_module(f"course_dynamics.{self.module}"), self.name))


def _flag(help, **kwargs) -> dict:
    return dict(help=help, **kwargs)


def definition(name: str) -> dict:
    """Flag ``name``'s keywords as :data:`FLAGS` holds them, its :class:`Later` choices read."""
    return {key: value.value() if isinstance(value, Later) else value for key, value in FLAGS[name].items()}


FLAGS: dict[str, dict] = {
    # The robot and its world
    "--gravity": _flag("gravitational acceleration in the base frame, m/s^2 (default 0,0,-9.81)", metavar="GX,GY,GZ"),
    "--allow-nonphysical-inertia": _flag(
        "load links whose inertia breaks the triangle inequality or is not positive semi-definite (e.g. only izz "
        "given), with one warning per link, instead of refusing", action="store_true"),
    # What every command prints or writes
    "--json": _flag("print the result as one JSON document on standard output (its keys: see the description)",
                    action="store_true"),
    "--quiet": _flag("no progress bar (one is drawn on standard error, on a terminal only, for a step that lasts "
                     "over a second)", action="store_true"),
    "--out": _flag("where to write the output: a file (- for standard output, where the output is one file) or, "
                   "for output of several files, a folder (made if missing; it may hold other files: only files "
                   "the same command wrote there are replaced); written whole or not at all", metavar="PATH"),
    "--plot": _flag("also draw the result to FILE: .png, .svg or .html (a page with the figure), by its suffix",
                    metavar="FILE"),
    "--html": _flag("write a self-contained HTML animation (opens offline)", metavar="FILE"),
    "--sarif": _flag("also write the findings to FILE as a SARIF 2.1.0 log (for code-scanning tools)", metavar="FILE"),
    "--fail-on": _flag("the least severe finding that makes the exit status 1 (default error)",
                       choices=("error", "warning", "note"), default="error"),
    "--geometry": _flag("what to draw: URDF visual or collision meshes, or a stick model; auto picks the lightest "
                        "faithful one (default)", choices=Later("output.viewer", "GEOMETRIES"), default="auto"),
    "--torques": _flag("draw joint torques as bars along the joint axes (a log's tau_<joint>, or computed from its "
                       "motion)", action="store_true"),
    "--path": _flag("draw the end-effector path", action="store_true", dest="draw_path"),
    "--allow-any-mesh-path": _flag(
        "read mesh files outside the URDF's folder and its packages (by default they are not read, and the stick "
        "model is drawn: the HTML file would carry them to whoever opens it)", action="store_true"),
    # States
    "--q": _flag("joint positions q1,q2,... (rad or m)"),
    "--qd": _flag("joint velocities (default 0)"),
    "--qdd": _flag("joint accelerations (default 0)"),
    "--q0": _flag("initial joint positions"),
    "--qd0": _flag("initial joint velocities (default 0)"),
    "--duration": _flag("the length of the motion, s", type=float),
    "--dt": _flag("time between the samples of the motion written, s (simulate: also the integration step; excite: "
                  "default 0.01)", type=float),
    "--seed": _flag("random seed (default 0)", type=int, default=0),
    "--samples": _flag("random states per robot (default %(default)s)", type=int, default=200),
    "--tolerance": _flag("relative tolerance (default %(default)g)", type=float),
    "--no-compile": _flag("use the interpreted recursions, never a compiled model (see the site: Compiled models)",
                          action="store_true"),
    # Friction (6.110)-(6.112)
    "--friction": _flag("joint friction to apply: none, or viscous = URDF damping and Coulomb = URDF friction "
                        "(default none)", choices=FRICTION_SOURCES, default="none"),
    "--viscous": _flag("viscous coefficients v1,v2,... (N m s/rad), overriding --friction"),
    "--coulomb": _flag("Coulomb coefficients c1,c2,... (N m), overriding --friction"),
    "--friction-width": _flag("Coulomb sgn(qd) -> tanh(qd/WIDTH) if > 0, rad/s (default 0)", type=float,
                              default=0.0, metavar="WIDTH"),
    # Drives: rotor inertia and torque offset per joint
    "--drives": _flag("a TOML file of the joints' drives, as identify --drives-out writes it: [joint.<name>] tables "
                      "of armature (rotor inertia I_a, kg m^2, kg for a prismatic joint; tau gains I_a qdd) and offset "
                      "(tau_0, N m or N; tau gains it); a joint the file does not name has neither, and no file is "
                      "read unless named here", metavar="FILE"),
    # Reading a log
    "--log": _flag(LOG, metavar="LOG"),
    "--log-format": _flag("how to read the log: a table, a UR RTDE recording (timestamp, actual_q_i, actual_qd_i, "
                          "actual_current_i; joint i is the URDF's i-th), a rostopic echo -p or PlotJuggler CSV of a "
                          "JointState topic, a ROS bag/MCAP; default auto: a bag by its file, the others by their "
                          "header, else a table", choices=Later("tools.sources", "FORMATS"), default="auto"),
    "--topic": _flag("a bag's topic (default /joint_states, else its one joint-state topic)"),
    "--map": _flag("our column names for the log's, e.g. q_shoulder_pan_joint=joint1_pos, or a TOML file of such "
                   "lines (may be repeated)", metavar="OURS=THEIRS,...|FILE.toml", action="append"),
    "--set": _flag("a constant for a signal the log lacks, e.g. q_panda_finger_joint1=0.04 (a constant q has zero "
                   "rates; may be repeated)", metavar="OURS=VALUE,...", action="append"),
    "--decimal": _flag("the log's decimal separator, when it cannot tell (default: read from the log; a log that "
                       "could be read two ways is refused)", choices=Later("tools.tables", "DECIMALS")),
    "--log-dt": _flag("the sample step of a log without a t column, s", type=float, metavar="STEP"),
    "--time-unit": _flag("the unit of the log's t column (default s)", choices=Later("tools.motion", "TIME_UNITS"),
                         default="s"),
    "--resample": _flag("put the log on an even clock at HZ (cubic splines) before differentiating", type=float,
                        metavar="HZ"),
    "--split-gaps": _flag("treat the pieces between gaps longer than 5 sample periods as separate segments (each "
                          "differentiated on its own) instead of refusing the log", action="store_true"),
    "--repair": _flag("mend the clock of a real log at once, with a note for each step: resample it (cubic splines) on "
                      "its median sample period when its steps are not whole periods (--resample HZ sets the rate "
                      "instead), split it at gaps longer than 5 periods (as --split-gaps), and drop the pieces "
                      "between gaps too short to differentiate (a lone sample); a log already on one clock is left "
                      "as it is, and t is never sorted", action="store_true"),
    "--smooth": _flag("one Savitzky-Golay window in samples (odd, >= 5) for differentiated rates (default: chosen per "
                      "joint from the log's own noise)", type=int, metavar="W"),
    "--torque-constant": _flag("motor torque constants, N m/A, one per joint: logged currents times these are the "
                               "measured torques", metavar="K1,K2,..."),
    # torques
    "--columns": _flag("list the log's columns and which of them would be used, then stop", action="store_true"),
    "--with-state": _flag("also write q_, qd_, qdd_ columns (as used)", action="store_true"),
    "--retime": _flag("find the smallest k such that the motion played k times slower (qd/k, qdd/k^2) is within "
                      "every limit less --margin; --out then writes the retimed log (t, q_, qd_, qdd_, tau_)",
                      action="store_true"),
    "--payload": _flag("a payload of MASS kg fixed to LINK (default: the tip, the last link on the last moving body, "
                       "e.g. ur5's tool0), its centre of mass at CX,CY,CZ m in the link's frame (may be repeated)",
                       metavar="MASS[@LINK][,CX,CY,CZ]", action="append"),
    "--payload-size": _flag("make the (single) payload a uniform box with these edges (m) along the link's axes "
                            "(default: a point mass)", metavar="A,B,C"),
    "--wrench": _flag("force (N) and moment (N m, about the link's origin) the robot exerts on its surroundings at "
                      "LINK, in base coordinates; adds J^T F, the static-force relation of chapter 5 (may be "
                      "repeated)", metavar="LINK:FX,FY,FZ[,NX,NY,NZ]", action="append"),
    # excite
    "--harmonics": _flag("harmonics per joint, from 2 to 50 (default 5; 4 with --scope payload)", type=int),
    "--instants": _flag("instants of the period the condition number is optimised on (default 40; 20 with --scope "
                        "payload)", type=int),
    "--max-iterations": _flag("of the optimisation (default 100; 40 with --scope payload; 0 keeps the random "
                              "start)", type=int),
    "--margin": _flag("share of every limit kept clear of (default 0.05): by excite's optimisation, by torques "
                      "--retime", type=float, default=0.05),
    # identify
    "--friction-fit": _flag("which joint friction to identify: viscous F_v qd, Coulomb F_c sgn(qd), both (default; "
                            "none with --scope payload) or none; what is not identified stays as the URDF's "
                            "<dynamics>", choices=Later("tools.identification", "FRICTION_MODELS")),
    "--scope": _flag("what the identification is for: the whole robot (default), or only a payload fixed to the "
                     "flange (--flange), the arm's own parameters as the URDF gives them", choices=SCOPES,
                     default="robot"),
    "--flange": _flag("the URDF link a payload is fixed to, with --scope payload (default: the last link of the last "
                      "moving body every tip is carried by, e.g. ur5's tool0, panda's panda_hand_tcp)",
                      metavar="LINK"),
    "--armature": _flag("also identify each moving measured joint's rotor inertia I_a (tau gains I_a qdd); one that "
                        "acts exactly as a link's inertia does (the first joint's, with its body's about the axis) "
                        "is left in that base parameter, with a note", action="store_true"),
    "--offset": _flag("also identify each moving measured joint's constant torque offset tau_0", action="store_true"),
    "--drives-out": _flag("write the drives (armature, offset, each with its standard error) to this TOML file, "
                          "which torques, simulate, identify and crosscheck read with --drives", metavar="FILE"),
    "--holdout": _flag("the share of the log's time, at its end, kept out of the fit to judge it (default 0.2; 0 "
                       "fits everything)", type=float, default=0.2, metavar="FRACTION"),
    "--prior-weight": _flag("the weight of each body's log-determinant divergence from the URDF's pseudo-inertia "
                            "against the mean squared residual in units of the noise (default 1e-5): larger keeps "
                            "weakly excited bodies nearer the URDF; what the log does not see stays at the URDF "
                            "whatever it is", type=float, metavar="LAMBDA"),
    # cartesian
    "--frame": _flag("URDF link name of the task frame"),
    "--rows": _flag(f"task rows among {','.join(ROW_NAMES)} (default all six)"),
    "--expressed-in": _flag("coordinates of J and the task: the base frame, or the task frame itself as Craig's 3J "
                            "(default base)", choices=EXPRESSED_IN, default="base"),
    "--max-condition": _flag(f"cond(J) above which J counts as singular (default {MAX_CONDITION:g})", type=float,
                             default=MAX_CONDITION),
    # simulate
    "--integrator": _flag("euler is the notes' (6.116)-(6.117); default rk4",
                          choices=Later("tools.simulation", "INTEGRATORS"), default="rk4"),
    "--torque": _flag("constant applied torques tau1,tau2,... (default 0)"),
    "--torque-log": _flag("a log of the torques to apply, interpolated linearly in time: t and tau_<joint> (or the "
                          "measured tau_meas_<joint>, a bag's effort), in any form --log takes", metavar="LOG"),
    "--limits": _flag("at a joint limit: report it and go on, or stop the joint there by an impulse through M and "
                      "hold it while the motion pushes into the limit, never adding energy (default report)",
                      choices=Later("tools.simulation", "LIMIT_MODES"), default="report"),
    "--ensemble": _flag("integrate K copies at once: member 0 starts at --q0, the others at --q0 plus a seeded "
                        "normal perturbation (the CSV gets a member column; --plot draws their divergence)", type=int,
                        metavar="K"),
    "--perturbation": _flag("standard deviation of the ensemble's perturbation of q0, rad or m (default 1e-6)",
                            type=float, default=1e-6),
    # detect
    "--gain": _flag("the momentum observer's gain K, 1/s, one value or one per joint (default 100): the residual "
                    "follows an external torque with time constant 1/K; a larger K detects sooner and lets more "
                    "of the rates' and torques' noise through", metavar="K|K1,K2,..."),
    "--threshold": _flag("the residual above which a joint is in contact, N m, one value or one per joint (default: "
                         "6 sigma of the residual's own noise above its median)", metavar="T|T1,T2,..."),
    "--noise-window": _flag("measure the residual's noise on this many seconds at the start of the log, after the "
                            "observer has settled (default: over the whole log, robustly)", type=float,
                            metavar="SECONDS"),
    "--min-duration": _flag("the shortest contact event, s (default 0.005): shorter crossings are noise",
                            type=float, default=0.005, metavar="SECONDS"),
    "--link": _flag("a URDF link: each contact's wrench there, from the external torques through the Jacobian "
                    "transpose (the whole wrench where the measured joints' J^T has rank 6, else the force at its "
                    "origin in the directions they see, the others named)", metavar="LINK"),
    # trace, derive
    "--symbolic": _flag("symbolic trace in q_<joint>, qd_<joint>, qdd_<joint>", action="store_true"),
    "--symbols": _flag("parameters kept symbolic: m<i>, l<i> (link length), lc<i> (distance to the link's centre of "
                       "mass), I<xx|yy|zz|xy|xz|yz><i>, g (a one-joint robot also takes m, l, lc)"),
    "--method": _flag("newton-euler (default) or lagrange", choices=METHODS, default="newton-euler"),
    "--digits": _flag("symbolic output: the URDF's numbers as N-digit decimals instead of exact fractions (real "
                      "robots)", type=int, metavar="N"),
    "--latex": _flag("print LaTeX instead of text", action="store_true"),
    # grade
    "--example-assignment": _flag("print a commented assignment file and exit", action="store_true"),
    "--gradescope": _flag("write a Gradescope autograder bundle for the assignment (setup.sh, run_autograder, the "
                          "assignment, this course-dynamics as a wheel) to ZIP and exit; upload it as the "
                          "assignment's autograder (Ubuntu 24.04 base image)", metavar="ZIP"),
    "--handout": _flag("print the numbers of student ID's robot (an assignment with variant = \"per-student\") and, "
                       "with --out DIR, write its URDF there; with interface = \"robot\", first the keys of the "
                       "robot every graded function takes; grades nothing", metavar="ID"),
    "--similarity": _flag("add the near-identical pairs of submissions to the summary, each with a side-by-side page: "
                          "compared on the syntax tree (names, comments, formatting set aside), and with the code "
                          "course-dynamics generates for each student's robot (flag generated-code). A lead, not a "
                          "verdict", action="store_true"),
    "--similarity-threshold": _flag("list pairs from SCORE, the share of the smaller submission the other holds "
                                    "(default 0.8; implies --similarity)", type=float, metavar="SCORE"),
    "--starter": _flag("the starter code every student was given: removed before --similarity compares (implies "
                       "--similarity)", metavar="FILE"),
    "--no-sandbox": _flag("grade without bubblewrap (separate processes and limits only); the gradebook says so",
                          action="store_true"),
    "--jobs": _flag("submissions graded at once (default: the number of CPUs)", type=int),
    # the notebooks
    "--solutions": _flag("with the worked solutions (the instructor's version)", action="store_true"),
    "--student": _flag("a student's id (a login or an e-mail's local part): the exercises use their own robot and "
                       "numbers", metavar="ID"),
    "--roster": _flag("a CSV file with an 'id' column: one subfolder per student", metavar="FILE"),
    "--only": _flag("only the notebook numbered NN (repeatable, or comma-separated: 01,03; default all)",
                    metavar="NN", action="append"),
    "--force": _flag("replace notebooks already in OUTDIR, keeping each as NN_topic.ipynb.bak-YYYYmmdd-HHMMSS",
                     action="store_true"),
}
ALIASES = {"--log": ("--trajectory",)}   # spellings of one flag, equally current
OVERRIDABLE = {"required", "default"}


def add(parser, name: str, **overrides):
    """Add flag ``name`` as :data:`FLAGS` defines it; ``overrides`` may set only ``required`` and ``default``."""
    wrong = set(overrides) - OVERRIDABLE
    if wrong:
        raise TypeError(f"{name}: a command may set only {', '.join(sorted(OVERRIDABLE))}, not {', '.join(wrong)}")
    return parser.add_argument(name, *ALIASES.get(name, ()), **{**definition(name), **overrides})


def add_all(parser, *names: str) -> None:
    for name in names:
        add(parser, name)


class RenamedOption(FutureWarning):
    """An option used by its old spelling (still read for one release)."""


class Renamed(argparse.Action):
    """A hidden old spelling: stores into the new flag's destination (or lets ``apply`` do it) and warns once."""

    def __init__(self, option_strings, dest, new: str = "", apply=None, **kwargs):
        self.new, self.apply = new, apply
        super().__init__(option_strings, dest, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None):
        new = self.new
        if self.apply is not None:
            new = self.apply(namespace, values)
        else:
            setattr(namespace, self.dest, values)
        warnings.warn(f"{option_string} is now {new}; the old spelling goes in the next release", RenamedOption,
                      stacklevel=2)


def add_renamed(parser, old: str, new: str, *, dest: str | None = None, apply=None, **kwargs) -> None:
    """Read ``old`` as flag ``new`` (hidden from --help), with one warning line when it is used.

    By default the old spelling parses as the new flag does; ``apply(namespace, value)`` returns the text that
    names the new spelling after doing what it says (for an old flag that became several).
    """
    known = definition(new) if new in FLAGS else {}
    parsing = {k: known[k] for k in ("type", "choices", "metavar", "nargs") if k in known}
    target = dest or known.get("dest") or new.lstrip("-").replace("-", "_")
    parser.add_argument(old, action=Renamed, dest=target, new=new, apply=apply, default=argparse.SUPPRESS,
                        help=argparse.SUPPRESS, **{**parsing, **kwargs})


def output_format(formats):
    """The old ``--format X`` of trace and derive: json is now --json, latex --latex, the text the default."""
    def apply(namespace, value):
        if value in ("json", "latex"):
            setattr(namespace, value, True)
            return f"--{value}"
        return "the default (no option)"
    return dict(apply=apply, choices=formats, dest=argparse.SUPPRESS)


# (command, old spelling, new spelling): what the site's table of renamed flags lists (topics/command-line).
RENAMES = (
    ("torques, identify", "--format", "--log-format"),
    ("torques, identify", "--dt", "--log-dt"),
    ("torques, simulate", "--smoothing", "--friction-width"),
    ("simulate", "--torque-csv", "--torque-log"),
    ("trace, derive", "--decimal N", "--digits N"),
    ("trace, derive", "--format json | latex", "--json | --latex"),
    ("identify", "--friction", "--friction-fit"),
    ("identify", "--report DIR", "--out DIR"),
    ("excite", "--samples", "--instants"),
)

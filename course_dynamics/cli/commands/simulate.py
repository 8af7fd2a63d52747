"""``course-dynamics simulate``: forward dynamics in time (6.115)–(6.117), written as CSV."""
from __future__ import annotations

import sys
import warnings

import numpy as np

from ...base.errors import CourseDynamicsWarning
from ...base.text import one_line
from ...core.robots import resolve
from ...output import io
from ...tools.simulation import (
    INTEGRATORS,
    LIMIT_MODES,
    SimulationError,
    TorqueTable,
    simulate,
    time_grid,
)
from ..animation import add_animation_options, animation_document
from ..options import (
    UsageError,
    add,
    add_all,
    add_friction_arguments,
    add_log_arguments,
    add_renamed,
    add_robot_argument,
    drives_argument,
    friction,
    joint_values,
    load_robot_argument,
    map_files,
    print_json,
    progress_bar,
    read_motion_argument,
)
from . import COMMANDS

HELP = COMMANDS["simulate"]
DESCRIPTION = ("Integrate qdd = M^-1 (tau - V - G - F) from q0, qd0, under constant torques (--torque) or the "
               "torques of a log (--torque-log: any log torques --log reads that holds tau_<joint> or measured "
               "torques, such as what torques --out, simulate --out and excite --out write; the --log-... options "
               "say how to read it). The output CSV has t, q_<joint>, qd_<joint>, qdd_<joint>, tau_<joint> and "
               "energy (kinetic + potential, J), and can be fed back to 'torques' and 'animate'. --plot draws q(t), "
               "qd(t) and energy(t); --json prints a summary (samples, energy_start, energy_end, events, ...). "
               "--limits stop makes each joint limit a stop: an impulse through the mass matrix stops the joint "
               "(the others keep their momentum), its reaction holds it while the motion pushes into the limit, and it "
               "is let go when the reaction would pull; no stop adds energy, and each is printed with its time, "
               "joints and the kinetic energy it took (--json: stops). --drives puts each joint's rotor inertia on "
               "M's diagonal (the energy then holds the rotors' 1/2 I_a qd^2) and takes its torque offset off the "
               "applied torque (an offset does work as an applied torque does).")


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    add(parser, "--q0", required=True)
    add(parser, "--qd0")
    add(parser, "--duration", required=True)
    add(parser, "--dt", required=True)
    add(parser, "--integrator")
    torque = parser.add_mutually_exclusive_group()
    add(torque, "--torque")
    add(torque, "--torque-log")
    add_renamed(torque, "--torque-csv", "--torque-log")
    add_log_arguments(parser, log=None)
    add_friction_arguments(parser)
    add(parser, "--drives")
    add(parser, "--limits")
    add(parser, "--out", required=True)
    add(parser, "--plot")
    add_animation_options(parser, html_required=False)
    add_all(parser, "--ensemble", "--perturbation", "--seed", "--no-compile", "--json", "--quiet")


def _torque(args, model):
    if args.torque is not None:
        return joint_values(args.torque, "--torque", model)
    if args.torque_log is not None:
        motion = read_motion_argument(args, model, args.torque_log, positions=False, torques=True)
        notes, t = list(motion.notes), motion.t
        if motion.format != "table" and t[0] != 0:  # a recorder's wall clock: the log's motion starts with the run's
            notes.append(f"the torque log's times start at {t[0]:.9g} s (the recorder's clock): they are counted from "
                         "its first sample")
            t = t - t[0]
        for note in notes:
            print(f"note: {one_line(note)}", file=sys.stderr)
        return TorqueTable(t, motion.tau)
    return None


def run(args) -> int:
    model = load_robot_argument(args)
    q0 = joint_values(args.q0, "--q0", model)
    qd0 = joint_values(args.qd0, "--qd0", model)
    if args.ensemble is not None:
        if args.ensemble < 1:
            raise UsageError("--ensemble must be at least 1")
        if args.seed < 0:
            raise UsageError(f"--seed must be a non-negative integer, got {args.seed}")
        if not (np.isfinite(args.perturbation) and args.perturbation >= 0):
            raise UsageError(f"--perturbation must be a non-negative number, got {args.perturbation}")
        if args.html:
            raise UsageError("--html animates one run; it cannot be combined with --ensemble")
    # The run's size is checked before anything of that size is made (the ensemble's perturbations included).
    members = args.ensemble or 1
    advice = (f": take fewer --ensemble members ({members} asked), a larger dt or a shorter duration" if args.ensemble
              else ": take a larger dt or a shorter duration")
    steps = len(time_grid(args.duration, args.dt, values_per_sample=members * (4 * model.n + 1) + 1, advice=advice)) - 1
    if args.ensemble is not None:
        noise = np.random.default_rng(args.seed).standard_normal((args.ensemble, model.n)) * args.perturbation
        noise[0] = 0.0
        q0 = q0 + noise
    torque, joint_friction, joint_drives = _torque(args, model), friction(args, model), drives_argument(args, model)
    if args.plot:
        from ...output.plotting import FIGURE_FORMATS, plot_format

        plot_format(args.plot, FIGURE_FORMATS)
    io.check_distinct([args.torque_log, args.drives, *map_files(args)], [args.out, args.plot, args.html])
    for target in (args.out, args.plot, args.html):
        if target:
            io.check_writable(target)
    progress = progress_bar(args, total=steps, unit="step")
    trajectory = simulate(model, q0, qd0, args.duration, args.dt, integrator=args.integrator, torque=torque,
                          friction=joint_friction, limits=args.limits, progress=progress.update,
                          compiled=False if args.no_compile else None, drives=joint_drives)
    progress.close()
    if not (np.all(np.isfinite(trajectory.q)) and np.all(np.isfinite(trajectory.qd))):
        raise SimulationError("the motion left the range of floating-point numbers (inf or nan): the torques or "
                              "initial rates are too large for this step; nothing written")
    # Every output is made in memory first and written only when all of them are ready.
    header, data = trajectory.table()
    picture = document = None
    if args.plot:
        from ...output.plotting import (
            FIGURE_FORMATS,
            ensemble_figure,
            figure_file,
            plot_format,
            trajectory_figure,
        )

        draw = trajectory_figure if trajectory.members is None else ensemble_figure
        ensemble = f", {trajectory.members} members, perturbation {args.perturbation:g}" if trajectory.members else ""
        title = f"{model.name}: {args.integrator}, dt = {args.dt:g} s{ensemble}"
        picture = figure_file(draw(trajectory, title=title), plot_format(args.plot, FIGURE_FORMATS), title)
    if args.html:
        document = animation_document(model, resolve(args.urdf), trajectory.t, trajectory.q, trajectory.tau, args)
    io.write_csv(args.out, header, data)
    if picture is not None:
        io.write_bytes(args.plot, picture)
    if document is not None:
        io.write_text(args.html, document)
    if args.limits != "stop":  # passing a limit is a warning; a stop is part of the motion, printed below
        for event in trajectory.events:
            warnings.warn(event, CourseDynamicsWarning)
    summary = dict(robot=model.name, joints=list(model.joint_names), integrator=args.integrator, dt=args.dt,
                   duration=args.duration, samples=len(trajectory.t), energy_start=float(np.mean(trajectory.energy[0])),
                   energy_end=float(np.mean(trajectory.energy[-1])), events=list(trajectory.events), out=str(args.out),
                   plot=args.plot)
    if args.limits == "stop":
        summary.update(energy_max=float(np.max(trajectory.energy)), stops=[stop.record() for stop in trajectory.stops],
                       stops_energy=float(sum(stop.energy for stop in trajectory.stops)))
    if trajectory.members is not None:
        summary.update(members=trajectory.members, perturbation=args.perturbation,
                       final_spread=float(np.abs(trajectory.q[-1] - trajectory.q[-1, 0]).max()))
    if args.json:
        print_json(summary)
    else:
        members = f"{trajectory.members} members, " if trajectory.members else ""
        energy = "mean energy" if trajectory.members else "energy"
        print(f"simulated {model.name} for {args.duration:g} s ({members}{len(trajectory.t)} samples, "
              f"{args.integrator}, dt = {args.dt:g} s); {energy} {summary['energy_start']:.6g} J -> "
              f"{summary['energy_end']:.6g} J; "
              f"wrote {args.out}")
        if trajectory.members:
            print(f"largest distance from member 0 at the end: {summary['final_spread']:.3g} (rad or m)")
        if args.limits == "stop":
            _print_stops(trajectory.stops, summary)
    return 0


#: How many stops the text output lists (--json lists every one).
STOPS_SHOWN = 10


def _print_stops(stops, summary) -> None:
    """The stops, one a line (the first :data:`STOPS_SHOWN`), after what they took in all."""
    if not stops:
        print(f"no joint reached a limit (energy at most {summary['energy_max']:.6g} J)")
        return
    count = f"{len(stops)} joint stop{'s' if len(stops) != 1 else ''}"
    print(f"{count} took {-summary['stops_energy']:.6g} J of kinetic energy (energy at most "
          f"{summary['energy_max']:.6g} J):")
    for stop in stops[:STOPS_SHOWN]:
        print(f"  {stop.sentence()}")
    if len(stops) > STOPS_SHOWN:
        print(f"  … and {len(stops) - STOPS_SHOWN} more (--json lists every stop)")

"""``course-dynamics simulate``: forward dynamics in time (6.115)–(6.117), written as CSV."""
from __future__ import annotations

import sys

import numpy as np

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
from ...tools.tables import joint_columns, read_columns, stack_joint_columns
from ..animation import add_animation_options, animation_document
from ..options import (
    UsageError,
    add_friction_arguments,
    add_robot_argument,
    friction,
    joint_values,
    load_robot_argument,
    print_json,
    progress_bar,
)

HELP = "forward dynamics in time (6.115)-(6.117), written as CSV"
DESCRIPTION = ("Integrate qdd = M^-1 (tau - V - G - F) from q0, qd0. The output CSV has t, q_<joint>, qd_<joint>, "
               "qdd_<joint>, tau_<joint> and energy (kinetic + potential, J), and can be fed back to 'torques'.")


def add_arguments(parser) -> None:
    add_robot_argument(parser)
    parser.add_argument("--q0", required=True, help="initial joint positions")
    parser.add_argument("--qd0", help="initial joint velocities (default 0)")
    parser.add_argument("--duration", type=float, required=True, help="simulated time, s")
    parser.add_argument("--dt", type=float, required=True, help="time step, s")
    parser.add_argument("--integrator", choices=INTEGRATORS, default="rk4",
                        help="euler is the notes' (6.116)-(6.117); default rk4")
    torque = parser.add_mutually_exclusive_group()
    torque.add_argument("--torque", help="constant applied torques tau1,tau2,... (default 0)")
    torque.add_argument("--torque-csv", help="CSV with t and tau_<joint> columns, interpolated linearly in time")
    add_friction_arguments(parser)
    parser.add_argument("--limits", choices=LIMIT_MODES, default="report",
                        help="at a joint limit: report it and go on, or stop the joint there (default report)")
    parser.add_argument("--out", required=True, help="output CSV (written whole or not at all)")
    parser.add_argument("--plot", help="also draw q(t), qd(t) and energy(t) to this PNG file")
    add_animation_options(parser, html_required=False)
    parser.add_argument("--ensemble", type=int, metavar="K",
                        help="integrate K copies at once: member 0 starts at --q0, the others at --q0 plus a seeded "
                             "normal perturbation (the CSV gets a member column; --plot draws their divergence)")
    parser.add_argument("--perturbation", type=float, default=1e-6,
                        help="standard deviation of the ensemble's perturbation of q0, rad or m (default 1e-6)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the ensemble's perturbation (default 0)")
    parser.add_argument("--no-compile", action="store_true",
                        help="use the interpreted recursions, not a compiled model (see README: compiled models)")
    parser.add_argument("--json", action="store_true", help="print a JSON summary")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def _torque(args, model):
    if args.torque is not None:
        return joint_values(args.torque, "--torque", model)
    if args.torque_csv is not None:
        joints = model.joint_names
        columns = read_columns(args.torque_csv, ["t"] + joint_columns(("tau",), joints),
                                  joint_columns(("q", "qd", "qdd"), joints) + ["energy"])
        return TorqueTable(columns["t"], stack_joint_columns(columns, "tau", joints))
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
        noise = np.random.default_rng(args.seed).standard_normal((args.ensemble, model.n)) * args.perturbation
        noise[0] = 0.0
        q0 = q0 + noise
    torque, joint_friction = _torque(args, model), friction(args, model)
    if args.plot:
        from ...output.plotting import plot_format

        plot_format(args.plot)
    io.check_distinct([args.torque_csv], [args.out, args.plot, args.html])
    for target in (args.out, args.plot, args.html):
        if target:
            io.check_writable(target)
    members = args.ensemble or 1
    steps = len(time_grid(args.duration, args.dt, values_per_sample=members * (4 * model.n + 1) + 1)) - 1
    progress = progress_bar(total=steps, enabled=not args.quiet, delay=1.0)
    trajectory = simulate(model, q0, qd0, args.duration, args.dt, integrator=args.integrator, torque=torque,
                          friction=joint_friction, limits=args.limits, progress=progress.update,
                          compiled=False if args.no_compile else None)
    progress.close()
    if not (np.all(np.isfinite(trajectory.q)) and np.all(np.isfinite(trajectory.qd))):
        raise SimulationError("the motion left the range of floating-point numbers (inf or nan): the torques or "
                              "initial rates are too large for this step; nothing written")
    # Every output is made in memory first and written only when all of them are ready.
    header, data = trajectory.table()
    picture = document = None
    if args.plot:
        from ...output.plotting import (
            ensemble_figure,
            figure_bytes,
            plot_format,
            trajectory_figure,
        )

        draw = trajectory_figure if trajectory.members is None else ensemble_figure
        picture = figure_bytes(draw(trajectory, title=f"{model.name}: {args.integrator}, dt = {args.dt:g} s"
                                    + (f", {trajectory.members} members, perturbation {args.perturbation:g}"
                                       if trajectory.members else "")), plot_format(args.plot))
    if args.html:
        document = animation_document(model, resolve(args.urdf), trajectory.t, trajectory.q, trajectory.tau, args)
    io.write_csv(args.out, header, data)
    if picture is not None:
        io.write_bytes(args.plot, picture)
    if document is not None:
        io.write_text(args.html, document)
    for event in trajectory.events:
        print(f"warning: {event}", file=sys.stderr)
    summary = dict(robot=model.name, joints=list(model.joint_names), integrator=args.integrator, dt=args.dt,
                   duration=args.duration, samples=len(trajectory.t), energy_start=float(np.mean(trajectory.energy[0])),
                   energy_end=float(np.mean(trajectory.energy[-1])), events=list(trajectory.events), out=str(args.out),
                   plot=args.plot)
    if trajectory.members is not None:
        summary.update(members=trajectory.members, perturbation=args.perturbation,
                       final_spread=float(np.abs(trajectory.q[-1] - trajectory.q[-1, 0]).max()))
    if args.json:
        print_json(summary)
    else:
        members = f"{trajectory.members} members, " if trajectory.members else ""
        energy = "mean energy" if trajectory.members else "energy"
        print(f"simulated {model.name} for {args.duration:g} s ({members}{len(trajectory.t)} samples, {args.integrator}, "
              f"dt = {args.dt:g} s); {energy} {summary['energy_start']:.6g} J -> {summary['energy_end']:.6g} J; "
              f"wrote {args.out}")
        if trajectory.members:
            print(f"largest distance from member 0 at the end: {summary['final_spread']:.3g} (rad or m)")
    return 0

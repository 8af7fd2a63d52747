"""``course-dynamics animate``: a logged or simulated motion as a self-contained HTML animation (meshcat)."""
from __future__ import annotations

import sys
from pathlib import Path

from ...base.text import one_line
from ...core.robots import resolve
from ...output import io
from ..animation import add_animation_options, export_animation
from ..options import (
    UsageError,
    add_all,
    add_log_arguments,
    add_robot_argument,
    column_map,
    constants,
    load_robot_argument,
    map_files,
    open_log_argument,
    print_json,
)
from . import COMMANDS

HELP = COMMANDS["animate"]
DESCRIPTION = ("Draw the robot (URDF meshes or a stick model) and animate the motion of a log (--log: what torques "
               "--log reads - a table with t and q_<joint>, a UR RTDE recording, a ROS bag or MCAP file - and what "
               "torques, simulate and excite write with --out) as meshcat keyframes, in one HTML file that opens "
               "offline in any browser. --torques draws the log's tau_<joint>, or, when it has none, the torques its "
               "motion needs (as torques computes them). --json prints what was written (html, bytes, samples).")


def add_arguments(parser) -> None:
    add_robot_argument(parser, gravity=False)
    add_log_arguments(parser)
    add_animation_options(parser, html_required=True)
    add_all(parser, "--json")


def run(args) -> int:
    from ...tools.motion import read_motion

    model = load_robot_argument(args)
    io.check_distinct([args.log, *map_files(args)], [args.html])
    io.check_writable(args.html)
    source = open_log_argument(args, model, args.log)
    reading = dict(columns=column_map(args), constants=constants(args), dt=args.log_dt, time_unit=args.time_unit)
    motion = read_motion(model, source, **reading)
    t, q, tau, notes = motion.t, motion.q, motion.tau, motion.notes
    if args.torques and tau is None:  # the torques the motion needs, read and differentiated as 'torques' does
        from ...base.errors import InputError
        from ...tools.logs import torques_from_log

        try:
            needed = torques_from_log(model, source, **reading)
        except InputError as exc:
            raise UsageError(f"--torques: {args.log} has no tau_<joint> columns, and the torques its motion needs "
                             f"cannot be computed: {exc}") from None
        t, q, tau, notes = needed.t, needed.log.q, needed.tau, needed.notes
    for note in notes:
        print(f"note: {one_line(note)}", file=sys.stderr)
    export_animation(args.html, model, resolve(args.urdf), t, q, tau, args)
    size = Path(args.html).stat().st_size
    if args.json:
        print_json(dict(robot=model.name, log=str(args.log), html=str(args.html), bytes=size, samples=len(q)))
    else:
        print(f"wrote {args.html} ({size / 1e6:.2f} MB, {len(q)} samples); open it in any browser, offline",
              file=sys.stderr)
    return 0

"""What every command shares: option parsing, robot loading, reading a log, JSON and progress output.

Every flag is defined once, in :mod:`course_dynamics.cli.flags` (the command line's grammar); commands add
them with :func:`add` and the groups here, and call the library; nothing here computes dynamics.
"""
from __future__ import annotations

import argparse
import sys
import warnings

import numpy as np

from ..base.errors import CourseDynamicsWarning, InputError
from ..core.robots import load
from ..output import render
from .flags import FRICTION_SOURCES, add, add_all, add_renamed
from .parsing import UsageError, check_output_names, join_value_options, robots_epilog

# the grammar and the parsing, as commands use them
__all__ = ["FRICTION_SOURCES", "UsageError", "add", "add_all", "add_renamed", "check_output_names",
           "join_value_options", "robots_epilog"]

MAX_SAMPLES = 100_000  # random states per robot in a comparison: more adds nothing but memory
MAX_GRAVITY = 1e6      # m/s^2 per component (1e5 g): beyond it no result is meaningful


def add_robot_argument(parser, nargs=None, help: str = "URDF file or shipped robot name", gravity: bool = True) -> None:
    """The URDF argument, ``--allow-nonphysical-inertia`` and (for commands that compute dynamics) ``--gravity``."""
    parser.add_argument("urdf", nargs=nargs, help=help)
    if gravity:
        add(parser, "--gravity")
    add(parser, "--allow-nonphysical-inertia")


def numbers(text: str, option: str) -> np.ndarray:
    """Comma-separated numbers; UsageError naming the option otherwise."""
    if any(v.strip() == "" for v in text.split(",")):
        raise UsageError(f"{option} has an empty value in '{text}' (comma-separated numbers, none left out)")
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise UsageError(f"{option} must be comma-separated numbers, got '{text}'") from None
    return np.array(values)


def joint_values(text, option: str, model, default=None) -> np.ndarray:
    """One finite number per joint from ``text`` (zeros, or ``default``, when the option is absent)."""
    if text is None:
        return np.zeros(model.n) if default is None else default
    values = numbers(text, option)
    if values.shape != (model.n,):
        raise UsageError(f"{option} has {len(values)} values but robot '{model.name}' has {model.n} joints "
                         f"({', '.join(model.joint_names)})")
    if not np.all(np.isfinite(values)):
        raise UsageError(f"{option} must be finite, got '{text}'")
    return values


def gravity(args):
    """``--gravity gx,gy,gz`` as an array, or None when not given."""
    if getattr(args, "gravity", None) is None:
        return None
    g = numbers(args.gravity, "--gravity")
    if g.shape != (3,) or not np.all(np.isfinite(g)):
        raise UsageError(f"--gravity needs three finite numbers gx,gy,gz, got '{args.gravity}'")
    if np.abs(g).max() > MAX_GRAVITY:
        raise UsageError(f"--gravity components must be at most {MAX_GRAVITY:g} m/s^2 in size, got '{args.gravity}'")
    return g


def load_robot_argument(args, target: str | None = None):
    """The model of ``target`` (default ``args.urdf``) under the command's ``--gravity`` and inertia options.

    A link loaded despite a non-physical inertia is an :class:`~course_dynamics.core.urdf.InertiaWarning`: one
    ``warning:`` line on stderr.
    """
    target = args.urdf if target is None else target
    g = gravity(args)
    return load(target, allow_nonphysical_inertia=getattr(args, "allow_nonphysical_inertia", False),
                **({} if g is None else {"gravity": g}))


def add_friction_arguments(parser) -> None:
    """Joint friction F(qd) of (6.110)-(6.112): from the URDF, per joint, or none."""
    add_all(parser, "--friction", "--viscous", "--coulomb", "--friction-width")
    add_renamed(parser, "--smoothing", "--friction-width")


def friction(args, model):
    """The :class:`~course_dynamics.core.friction.Friction` the options ask for, or None for none."""
    from ..core.friction import Friction

    if args.friction != "urdf" and args.viscous is None and args.coulomb is None:
        return None
    base = Friction.from_urdf(model) if args.friction == "urdf" else Friction.none(model)
    return Friction(viscous=joint_values(args.viscous, "--viscous", model, base.viscous),
                    coulomb=joint_values(args.coulomb, "--coulomb", model, base.coulomb),
                    smoothing=args.friction_width)


def drives_argument(args, model):
    """The :class:`~course_dynamics.core.drives.Drives` of ``--drives FILE``, or None without it."""
    from ..core.drives import read_drives

    if getattr(args, "drives", None) is None:
        return None
    return read_drives(args.drives, model)


def warn_if_gravity_free(model) -> None:
    """One warning line when G(q) vanishes everywhere (the gravity path is then untested)."""
    from ..core.sampling import gravity_free

    if gravity_free(model):
        warnings.warn(f"robot '{model.name}': G(q) = 0 at every sampled state (gravity {model.gravity.tolist()} m/s^2 "
                      "cannot act on its joints), so gravity is not tested here", CourseDynamicsWarning)


def check_finite(what: str, *arrays) -> None:
    """InputError when a result holds inf or nan: inputs beyond floating-point range must not print as numbers."""
    for array in arrays:
        if not np.all(np.isfinite(np.asarray(array, dtype=float))):
            raise InputError(f"{what} is not finite (inf or nan): the given values are too large for floating-point "
                             "arithmetic")


def add_sampling_arguments(parser, tolerance: float) -> None:
    """--samples, --seed, --tolerance: the seeded random states of a comparison with Pinocchio."""
    add_all(parser, "--samples", "--seed")
    add(parser, "--tolerance", default=tolerance)


def check_sampling(args) -> None:
    """At least one sample, and a tolerance that is a positive finite number."""
    if not 1 <= args.samples <= MAX_SAMPLES:
        raise UsageError(f"--samples must be between 1 and {MAX_SAMPLES}, got {args.samples}")
    if args.seed < 0:
        raise UsageError(f"--seed must be a non-negative integer, got {args.seed}")
    if not (np.isfinite(args.tolerance) and args.tolerance > 0):
        raise UsageError(f"--tolerance must be a positive finite number, got {args.tolerance}")


def print_json(document) -> None:
    sys.stdout.write(render.json_text(document) + "\n")


def progress_bar(args, total: int | None, unit: str = "step", delay: float = 1.0):
    """A tqdm bar on stderr, only on a terminal and without ``--quiet``; it appears after ``delay`` seconds."""
    from tqdm import tqdm

    enabled = not getattr(args, "quiet", False) and sys.stderr.isatty()
    return tqdm(total=total, unit=unit, disable=not enabled, file=sys.stderr, leave=False, delay=delay, mininterval=0.5)


def progress_callback(bar):
    """``progress(done, total)`` for the library, moving ``bar`` to ``done``."""
    def progress(done, total):
        bar.update(done - bar.n)
    return progress


def symbol_names(text) -> tuple[str, ...]:
    """``m1,m2,g`` → ('m1', 'm2', 'g')."""
    return tuple(name.strip() for name in text.split(",") if name.strip()) if text else ()


def add_log_arguments(parser, log: str | None = "--log", required: bool = True) -> None:
    """How to read a log: shared by every command that reads motion (torques, identify, animate, simulate).

    ``log``: the flag that names the log (``--log``, or simulate's ``--torque-log``), or None when the command
    adds it itself.
    """
    if log is not None:
        add(parser, log, required=required)
    add_all(parser, "--log-format", "--topic", "--map", "--set", "--decimal", "--log-dt", "--time-unit")


def add_differentiation_arguments(parser) -> None:
    """How a log's rates are found and what its currents mean: commands that differentiate (torques, identify)."""
    add_all(parser, "--resample", "--split-gaps", "--repair", "--smooth", "--torque-constant")
    add_renamed(parser, "--format", "--log-format")
    add_renamed(parser, "--dt", "--log-dt")


def column_map(args) -> dict[str, str]:
    """``--map`` (repeatable): our column names → the log's."""
    from ..tools.columns import parse_column_map

    mapping = {}
    for text in args.map or ():
        for ours, theirs in parse_column_map(text).items():
            if ours in mapping:
                raise UsageError(f"--map: '{ours}' is mapped twice")
            mapping[ours] = theirs
    return mapping


def constants(args) -> dict[str, float]:
    """``--set`` (repeatable): a constant value for each named signal the log lacks."""
    values = {}
    for text in args.set or ():
        for item in filter(None, (part.strip() for part in text.split(","))):
            name, sep, value = item.partition("=")
            try:
                number = float(value)
            except ValueError:
                number = None
            if not sep or number is None:
                raise UsageError(f"--set entries must be OURS=VALUE, e.g. q_panda_finger_joint1=0.04; got '{item}'")
            if name.strip() in values:
                raise UsageError(f"--set: '{name.strip()}' is set twice")
            values[name.strip()] = number
    return values


def map_files(args) -> list[str]:
    """The ``--map`` values that are files: inputs, which no output may replace."""
    return [text for text in args.map or () if "=" not in text]


def check_log_outputs(args, model) -> None:
    """Before a long log is read: ``--out -`` and ``--json`` not both on standard output, ``--plot``'s format and
    panels, no output replacing an input (the log, the URDF, a ``--map`` file), every output writable."""
    from ..output import io

    if args.out == io.STDOUT and args.json:
        raise UsageError("--out - and --json both want standard output; write the CSV to a file")
    if args.plot:
        from ..output.plotting import FIGURE_FORMATS, check_panels, plot_format

        plot_format(args.plot, FIGURE_FORMATS)
        check_panels(model)
    io.check_distinct([args.log, model.source or None, *map_files(args)], [args.out, args.plot])
    for target in (args.out, args.plot):
        if target:
            io.check_writable(target)


def open_log_argument(args, model, path):
    """The log at ``path`` as ``--log-format``, ``--topic`` and ``--decimal`` say (a LogSource)."""
    from ..tools.sources import open_log

    return open_log(path, model, format=args.log_format, topic=args.topic, decimal=args.decimal)


def read_motion_argument(args, model, path, positions: bool = True, torques: bool = False):
    """Times, Θ and/or the applied τ of the log at ``path``, read as every command reads a log."""
    from ..tools.motion import read_motion

    return read_motion(model, open_log_argument(args, model, path), columns=column_map(args), constants=constants(args),
                       dt=args.log_dt, time_unit=args.time_unit, positions=positions, torques=torques)


def notebook_numbers(args) -> tuple[str, ...] | None:
    """``--only`` (repeatable, each value possibly comma-separated) as notebook numbers; None for all."""
    numbers = tuple(part.strip() for text in args.only or () for part in text.split(",") if part.strip())
    return numbers or None

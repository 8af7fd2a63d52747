"""What every command shares: option parsing, robot loading, JSON and progress output.

Commands declare their own arguments with the helpers here and call the
library; nothing here computes dynamics.
"""
from __future__ import annotations

import argparse
import sys

import numpy as np

from ..base.errors import InputError
from ..core.robots import load, robot_names
from ..output import render

# Options whose values are comma-separated numbers that may start with a minus sign.
VALUE_OPTIONS = ("--q", "--qd", "--qdd", "--gravity", "--q0", "--qd0", "--torque", "--viscous", "--coulomb",
                 "--payload-size")
FRICTION_SOURCES = ("none", "urdf")
MAX_SAMPLES = 100_000  # random states per robot in a comparison: more adds nothing but memory
MAX_GRAVITY = 1e6      # m/s^2 per component (1e5 g): beyond it no result is meaningful


class UsageError(InputError):
    """Bad command-line input (reported as ``error: …``, exit 2)."""


class Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2, as for every other bad input
        raise UsageError(message)


def join_value_options(argv: list[str]) -> list[str]:
    """``--q -0.1,0.2`` → ``--q=-0.1,0.2``, so negative first values are not taken for options."""
    out, i = [], 0
    while i < len(argv):
        if argv[i] in VALUE_OPTIONS and i + 1 < len(argv):
            out.append(f"{argv[i]}={argv[i + 1]}")
            i += 2
        else:
            out.append(argv[i])
            i += 1
    return out


def add_robot_argument(parser, nargs=None, help: str = "URDF file or shipped robot name", gravity: bool = True) -> None:
    """The URDF argument, ``--allow-nonphysical-inertia`` and (for commands that compute dynamics) ``--gravity``."""
    parser.add_argument("urdf", nargs=nargs, help=help)
    if gravity:
        parser.add_argument("--gravity", metavar="GX,GY,GZ",
                            help="gravitational acceleration in the base frame, m/s^2 (default 0,0,-9.81)")
    parser.add_argument("--allow-nonphysical-inertia", action="store_true",
                        help="load links whose inertia breaks the triangle inequality or is not positive "
                             "semi-definite (e.g. only izz given), with one warning per link, instead of refusing")


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

    A link loaded despite a non-physical inertia prints one ``warning:`` line on stderr.
    """
    import warnings

    from ..core.urdf import InertiaWarning

    target = args.urdf if target is None else target
    g = gravity(args)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", InertiaWarning)
        model = load(target, allow_nonphysical_inertia=getattr(args, "allow_nonphysical_inertia", False),
                     **({} if g is None else {"gravity": g}))
    for warning in caught:
        if issubclass(warning.category, InertiaWarning):
            print(f"warning: {render.one_line(warning.message)}", file=sys.stderr)
        else:
            warnings.warn_explicit(warning.message, warning.category, warning.filename, warning.lineno)
    return model


def add_friction_arguments(parser) -> None:
    """Joint friction F(qd) of (6.110)-(6.112): from the URDF, per joint, or none."""
    parser.add_argument("--friction", choices=FRICTION_SOURCES, default="none",
                        help="joint friction: none, or viscous = URDF damping and Coulomb = URDF friction (default none)")
    parser.add_argument("--viscous", help="viscous coefficients v1,v2,... (N m s/rad), overriding --friction")
    parser.add_argument("--coulomb", help="Coulomb coefficients c1,c2,... (N m), overriding --friction")
    parser.add_argument("--smoothing", type=float, default=0.0, help="Coulomb sgn(qd) -> tanh(qd/smoothing) if > 0")


def friction(args, model):
    """The :class:`~course_dynamics.core.friction.Friction` the options ask for, or None for none."""
    from ..core.friction import Friction

    if args.friction != "urdf" and args.viscous is None and args.coulomb is None:
        return None
    base = Friction.from_urdf(model) if args.friction == "urdf" else Friction.none(model)
    return Friction(viscous=joint_values(args.viscous, "--viscous", model, base.viscous),
                    coulomb=joint_values(args.coulomb, "--coulomb", model, base.coulomb), smoothing=args.smoothing)


def warn_if_gravity_free(model) -> None:
    """One warning line when G(q) vanishes everywhere (the gravity path is then untested)."""
    from ..core.sampling import gravity_free

    if gravity_free(model):
        print(f"warning: robot '{render.one_line(model.name)}': G(q) = 0 at every sampled state (gravity {model.gravity.tolist()} m/s^2 "
              "cannot act on its joints), so gravity is not tested here", file=sys.stderr)


def check_finite(what: str, *arrays) -> None:
    """InputError when a result holds inf or nan: inputs beyond floating-point range must not print as numbers."""
    for array in arrays:
        if not np.all(np.isfinite(np.asarray(array, dtype=float))):
            raise InputError(f"{what} is not finite (inf or nan): the given values are too large for floating-point "
                             "arithmetic")


def check_oracle_memory(model) -> None:
    """Refuse, before any work, a robot whose comparison with Pinocchio would not fit in memory."""
    from course_dynamics_reference.validate import memory_estimate

    from ..base.resources import check_memory

    check_memory(memory_estimate(model.n), f"robot '{model.name}' has {model.n} joints: comparing it with Pinocchio",
                 " ('terms' computes one state of it with our library alone)")


def check_output_names(args) -> None:
    """An empty output name ('') would mean the current folder: refuse it for every output option."""
    for option in ("out", "plot", "html"):
        value = getattr(args, option, None)
        if value is not None and not str(value).strip():
            raise UsageError("an output name is empty ('' would mean the current folder); name a file or folder")


def add_sampling_arguments(parser, tolerance: float) -> None:
    """--samples, --seed, --tolerance: the seeded random states of a comparison with Pinocchio."""
    parser.add_argument("--samples", type=int, default=200, help="random states per robot (default 200)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("--tolerance", type=float, default=tolerance, help=f"relative tolerance (default {tolerance:g})")


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


def progress_bar(total: int, enabled: bool, delay: float = 0.0, unit: str = "step"):
    """A tqdm bar on stderr; with ``delay`` it appears only for work that lasts longer."""
    from tqdm import tqdm

    return tqdm(total=total, unit=unit, disable=not enabled, file=sys.stderr, leave=False, delay=delay, mininterval=0.5)


def symbol_names(text) -> tuple[str, ...]:
    """``m1,m2,g`` → ('m1', 'm2', 'g')."""
    return tuple(name.strip() for name in text.split(",") if name.strip()) if text else ()


def robots_epilog() -> str:
    return (f"URDF arguments take a file path or the name of a shipped robot: {', '.join(robot_names())}. "
            "Joint values are comma-separated, in the joint order 'info' prints "
            "(rad, rad/s, rad/s^2 for revolute joints; m, m/s, m/s^2 for prismatic).")

"""What every command shares: option parsing, robot loading, JSON and progress output.

Commands declare their own arguments with the helpers here and call the
library; nothing here computes dynamics.
"""
from __future__ import annotations

import argparse
import sys

import numpy as np

from .. import render
from ..errors import InputError
from ..robots import load, robot_names

# Options whose values are comma-separated numbers that may start with a minus sign.
VALUE_OPTIONS = ("--q", "--qd", "--qdd", "--gravity", "--q0", "--qd0", "--torque", "--viscous", "--coulomb")


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


def add_robot_argument(parser, nargs=None, help: str = "URDF file or shipped robot name") -> None:
    parser.add_argument("urdf", nargs=nargs, help=help)


def numbers(text: str, option: str) -> np.ndarray:
    """Comma-separated numbers; UsageError naming the option otherwise."""
    try:
        values = [float(v) for v in text.split(",") if v.strip() != ""]
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
    return g


def load_robot_argument(target: str, gravity=None):
    """The model of a URDF path or shipped robot name, under ``gravity`` if given."""
    return load(target) if gravity is None else load(target, gravity=gravity)


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

"""The command line's parser and the checks made before any command runs, without the library.

``course-dynamics --help`` builds its parser from this module and the commands' one-line helps alone
(:data:`~course_dynamics.cli.commands.COMMANDS`), so it loads neither numpy nor the dynamics.
"""
from __future__ import annotations

import argparse

from ..base.errors import InputError
from ..base.robot_files import robot_names

# Options whose values are comma-separated numbers that may start with a minus sign.
VALUE_OPTIONS = ("--q", "--qd", "--qdd", "--gravity", "--q0", "--qd0", "--torque", "--viscous", "--coulomb",
                 "--payload-size")


class UsageError(InputError):
    """Bad command-line input (reported as ``error: …``, exit 2)."""


class Parser(argparse.ArgumentParser):
    """An argument parser whose every complaint is a :class:`UsageError` (one ``error:`` line, exit 2)."""

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


def check_output_names(args) -> None:
    """An empty output name ('') would mean the current folder: refuse it for every output option."""
    for option in ("out", "plot", "html"):
        value = getattr(args, option, None)
        if value is not None and not str(value).strip():
            raise UsageError("an output name is empty ('' would mean the current folder); name a file or folder")


def robots_epilog() -> str:
    """The help's last paragraph: what a URDF argument takes (the shipped robots by name) and the joint units."""
    return (f"URDF arguments take a file path or the name of a shipped robot: {', '.join(robot_names())}. "
            "Joint values are comma-separated, in the joint order 'info' prints "
            "(rad, rad/s, rad/s^2 for revolute joints; m, m/s, m/s^2 for prismatic).")


__all__ = ["VALUE_OPTIONS", "Parser", "UsageError", "check_output_names", "join_value_options", "robots_epilog"]

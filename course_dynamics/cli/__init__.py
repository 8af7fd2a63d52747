"""Layer 6, ``course-dynamics``: the command line, a thin layer over the library (it may import every layer).

Every command reads a URDF (or the name of a shipped robot), calls
course_dynamics, and prints a table or, with ``--json``, one JSON document.
Each lives in its own module in ``course_dynamics.cli.commands``; every flag
is defined once in ``course_dynamics.cli.flags`` (one meaning per name; old
spellings read for one release with a warning line), and shared option handling
is in ``course_dynamics.cli.options``.

Bad input of any kind (a :class:`~course_dynamics.base.errors.CourseDynamicsError`)
ends with one line ``error: …`` on stderr and exit code 2; Ctrl-C ends with
exit code 130, even where a library we call catches the interrupt
(``course_dynamics.cli.interrupts``). No output file is left behind
half-written. Running out of memory (which the size checks should have refused
first) ends with one ``error: ran out of memory …`` line and exit code 2.

==============  ================================================================
module          job
==============  ================================================================
``commands``    one module per command (``course-dynamics --help`` lists them)
``flags``       the grammar: every flag of every command, defined once
``parsing``     the parser and the checks before a command runs, without the library
``options``     what commands share: loading a robot, reading a log, JSON and progress output
``animation``   the animation options of ``animate`` and ``simulate``, and the HTML export
``interrupts``  Ctrl-C that ends a command, even inside a library that catches it
==============  ================================================================
"""
from __future__ import annotations

import importlib
import logging
import os
import sys
import warnings

# One BLAS thread unless the environment asks for more, set before numpy loads: numpy's and scipy's wheels each
# bring their own OpenBLAS, whose idle threads spin for about 0.1 s after every call, so on a machine of few cores
# the first call into one copy after the other waits for them (identify measured 0.1 s of it); a command's BLAS
# work is small matrices, and its large batches run on the native code's own threads.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from ..base.errors import CourseDynamicsError, CourseDynamicsWarning
from ..base.text import one_line
from .commands import COMMANDS
from .interrupts import Interrupts, interruptible
from .parsing import Parser, check_output_names, join_value_options, robots_epilog


def _version() -> str:
    from importlib import metadata

    try:
        return metadata.version("course-dynamics")
    except metadata.PackageNotFoundError:  # a checkout on the path, not installed
        return "(not installed)"


def build_parser(argv: list[str] | None = None) -> Parser:
    """The ``course-dynamics`` argument parser: one sub-command per module of ``course_dynamics.cli.commands``.

    Each sub-command's parser carries its help, description and flags, and the function that runs it as
    ``run`` in the parsed namespace.

    Parameters
    ----------
    argv : list of str, optional
        The command line to be parsed. When given, only the command it names gets its module imported and its
        flags (every other command is listed by its one-line help alone), so ``course-dynamics --help`` loads no
        command and ``course-dynamics info ur5`` loads one; None builds every command's parser.

    Returns
    -------
    argparse.ArgumentParser
        The parser of the whole command line. A bad command line makes its ``parse_args`` raise
        :class:`~course_dynamics.base.errors.InputError` (which :func:`main` reports as one ``error: …`` line
        and exit code 2) instead of exiting.
    """
    parser = Parser(
        prog="course-dynamics",
        description="Manipulator dynamics in Craig's notation (Introduction to Robotics, ch. 6), "
                    "computed by hand-written Newton-Euler and checked against Pinocchio.",
        epilog=robots_epilog(),
    )
    parser.add_argument("--version", action="version", version=f"course-dynamics {_version()}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=Parser)
    named = None if argv is None else next((a for a in argv if not a.startswith("-")), "")
    for name, help in COMMANDS.items():
        if named is not None and name.replace("_", "-") != named:
            sub.add_parser(name.replace("_", "-"), help=help)
            continue
        command = importlib.import_module(f"{__name__}.commands.{name}")
        p = sub.add_parser(name.replace("_", "-"), help=command.HELP,
                           description=getattr(command, "DESCRIPTION", command.HELP), epilog=robots_epilog())
        command.add_arguments(p)
        p.set_defaults(run=command.run)
    return parser


def main(argv=None) -> int:
    """Run one ``course-dynamics`` command, as the console script does.

    Bad input ends with one ``error: …`` line on stderr rather than a traceback; warnings of
    course_dynamics are printed as one ``warning: …`` line each (module docstring).

    Parameters
    ----------
    argv : list of str, optional
        The command line without the program name, e.g. ``["torques", "puma560", "--q", "0,0,0,0,0,0"]``;
        ``None`` (the default) reads ``sys.argv[1:]``.

    Returns
    -------
    int
        The exit code: 0 on success, 2 for bad input (a
        :class:`~course_dynamics.base.errors.CourseDynamicsError`, an unwritable path, running out of memory),
        130 when interrupted with Ctrl-C; ``torques`` returns 1 when a torque exceeds one of the robot's limits.
    """
    argv = sys.argv[1:] if argv is None else list(argv)
    with warnings.catch_warnings():
        shown = warnings.showwarning

        def warning_line(message, category, filename, lineno, file=None, line=None):
            """Our warnings as one ``warning: …`` line (without the source line Python prints); others as before."""
            if category.__module__.startswith("course_dynamics"):
                print(f"warning: {one_line(message)}", file=sys.stderr)
            else:
                shown(message, category, filename, lineno, file, line)

        warnings.showwarning = warning_line
        # Every warning of ours is a line, however often it comes (a user's own -W filter still decides first).
        warnings.filterwarnings("always", category=CourseDynamicsWarning, append=True)
        with interruptible() as interrupts:
            return _main(argv, interrupts)


def _main(argv: list, interrupts: Interrupts | None) -> int:
    try:
        argv = join_value_options(argv)
        args = build_parser(argv).parse_args(argv)
        check_output_names(args)
        import numpy as np

        # Overflow shows as inf/nan in the results, which every command checks and reports as one error line.
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            code = args.run(args)
        sys.stdout.flush()  # a full or broken standard output is reported here, not at exit
        return code
    except CourseDynamicsError as exc:
        print(f"error: {one_line(exc)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return _interrupted(interrupts)
    except MemoryError as exc:
        # A safety net only: every size a small input sets is checked against the budget before the work starts;
        # this is for what no estimate foresaw. Outputs are written whole at the end, so none is left half-written.
        print(f"error: ran out of memory ({one_line(exc) or 'MemoryError'}): lower what was asked (--samples, "
              "--ensemble, --duration, the log's length, the robot's joints), or set COURSE_DYNAMICS_MEMORY_BUDGET "
              "so that the size checks refuse it before it starts", file=sys.stderr)
        return 2
    except BrokenPipeError:
        return 0
    except OSError as exc:  # a path the system refuses (too long, not a folder, a full device)
        if exc.filename is None:  # standard output itself: drop what it could not take, so exit stays quiet
            sys.stdout = open(os.devnull, "w")
        where = exc.filename if exc.filename is not None else "standard output"
        print(f"error: {one_line(where)}: cannot write: {exc.strerror or exc}" if exc.filename is None
              else f"error: {one_line(where)}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    except Exception:
        # A library that caught the Ctrl-C may fail on after it in its own way (trimesh, interrupted in its optional
        # imports, keeps a wrapper for the module and then raises TypeError): an exception after a Ctrl-C is the
        # Ctrl-C's. Any other is ours to see, with its traceback.
        if interrupts is not None and interrupts.pending:
            return _interrupted(interrupts)
        raise


def _interrupted(interrupts: Interrupts | None) -> int:
    """The one line and exit status 130 of a command that Ctrl-C ended."""
    if interrupts is not None:
        interrupts.received()
    # What an interrupted notebook kernel leaves behind (asyncio's "Task exception was never retrieved",
    # logged when the task is collected) is not the user's business: one line, as for any error.
    logging.getLogger("asyncio").disabled = True
    print("error: interrupted", file=sys.stderr)
    return 130


__all__ = ["build_parser", "main"]

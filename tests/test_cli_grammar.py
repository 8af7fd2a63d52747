"""course_dynamics/cli/flags.py: one grammar for the command line.

Every command's parser is built (``course_dynamics.cli.build_parser``) and read: a flag name has one meaning
wherever it appears (destination, type, choices, nargs, action, help text and metavar), an old spelling is
hidden, says what replaced it and still works, and no command imports another command.
"""
from __future__ import annotations

import argparse
import ast
import io
import json
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers import ROOT, run

from course_dynamics.cli import build_parser
from course_dynamics.cli.commands import COMMANDS
from course_dynamics.cli.flags import FLAGS, RENAMES, Renamed

COMMANDS_FOLDER = ROOT / "course_dynamics" / "cli" / "commands"
LONG_STEPS = ("torques", "excite", "identify", "simulate", "validate", "report", "grade", "terms", "student-notebooks",
              "publish-notebooks")


def subparsers() -> dict[str, argparse.ArgumentParser]:
    action = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def meaning(action: argparse.Action) -> tuple:
    return (action.dest, action.type, tuple(action.choices) if action.choices else None, action.nargs,
            type(action).__name__, action.help, action.metavar)


def current_flags(parser) -> list[tuple[str, argparse.Action]]:
    return [(name, a) for a in parser._actions if not isinstance(a, Renamed) and a.help != argparse.SUPPRESS
            for name in a.option_strings if name.startswith("--") and name != "--help"]


def meanings_by_name() -> dict[str, dict[tuple, list[str]]]:
    found: dict[str, dict[tuple, list[str]]] = {}
    for command, parser in subparsers().items():
        for name, action in current_flags(parser):
            found.setdefault(name, {}).setdefault(meaning(action), []).append(command)
    return found


def test_every_flag_name_has_one_meaning_across_the_commands():
    found = meanings_by_name()
    assert len(found) > 60 and len(subparsers()) == len(COMMANDS)
    twice = {name: {str(m): commands for m, commands in kinds.items()} for name, kinds in found.items() if len(kinds) > 1}
    assert not twice, json.dumps(twice, indent=1)


def test_the_check_sees_a_flag_with_two_meanings():
    """The same reading of the parsers finds a flag whose help (or type) differs in two commands."""
    parsers = subparsers()
    parsers["info"].add_argument("--seed", type=float, help="another seed")
    kinds = {meaning(a) for command in ("info", "validate") for name, a in current_flags(parsers[command])
             if name == "--seed"}
    assert len(kinds) == 2


def test_every_flag_comes_from_the_one_table():
    for command, parser in subparsers().items():
        for name, action in current_flags(parser):
            spelled = name if name in FLAGS else next(n for n in FLAGS if n in action.option_strings)
            assert action.help == FLAGS[spelled]["help"], (command, name)


def test_hidden_options_are_old_spellings_that_name_their_replacement():
    renamed = {old.split()[0] for _, old, _ in RENAMES}
    for command, parser in subparsers().items():
        for action in parser._actions:
            if action.help == argparse.SUPPRESS:
                assert isinstance(action, Renamed), (command, action.option_strings)
            if isinstance(action, Renamed):
                (old,) = action.option_strings
                assert old in renamed, (command, old)
                assert action.help == argparse.SUPPRESS and action.new.split()[0] in FLAGS, (command, old, action.new)


@pytest.mark.parametrize("command", [c.replace("_", "-") for c in COMMANDS])
def test_every_command_prints_json_on_request(command):
    assert "--json" in dict(current_flags(subparsers()[command]))


@pytest.mark.parametrize("command", LONG_STEPS)
def test_long_steps_have_quiet(command):
    assert "--quiet" in dict(current_flags(subparsers()[command]))


def test_no_command_imports_another_command():
    for path in COMMANDS_FOLDER.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                names = [node.module or ""] + [a.name for a in node.names]
                if node.level == 1:   # from . import x / from .x import y: inside commands/
                    assert not any(n in COMMANDS for n in names), (path.name, names)
                assert not any(".commands." in f".{n}." for n in names if node.level == 0), (path.name, names)


def test_an_old_spelling_works_with_one_warning_line(capsys):
    code, out, err = run(capsys, "trace", "two_link", "--q", "0.3,0.4", "--format", "json")
    assert code == 0 and json.loads(out)["robot"] == "two_link"
    assert err.splitlines() == ["warning: --format is now --json; the old spelling goes in the next release"]
    code, out, err = run(capsys, "derive", "pendulum", "--decimal", "3", "--json")
    assert code == 0 and "9.81" in out
    assert err.splitlines() == ["warning: --decimal is now --digits; the old spelling goes in the next release"]
    code, out_new, _ = run(capsys, "derive", "pendulum", "--digits", "3", "--json")
    assert out_new == out


def test_renamed_options_give_what_the_new_ones_give(capsys, tmp_path):
    log = ROOT / "examples" / "ur5_log.csv"
    mapping = ROOT / "examples" / "ur5_log_columns.toml"
    common = ["torques", "ur5", "--log", str(log), "--map", str(mapping), "--coulomb", "1,1,1,1,1,1", "--json"]
    code, new, err_new = run(capsys, *common, "--friction-width", "0.1", "--log-format", "table")
    assert code == 0 and "warning" not in err_new
    code, old, err_old = run(capsys, *common, "--smoothing", "0.1", "--format", "table")
    assert code == 0 and json.loads(old) == json.loads(new)
    assert err_old.splitlines() == ["warning: --smoothing is now --friction-width; the old spelling goes in the next "
                                    "release", "warning: --format is now --log-format; the old spelling goes in the "
                                    "next release"]
    code, _, err = run(capsys, "excite", "two_link", "--duration", "2", "--out", str(tmp_path / "x.csv"), "--harmonics",
                       "3", "--samples", "12", "--max-iterations", "3", "--quiet", "--json")
    assert code == 0 and "warning: --samples is now --instants" in err


def test_only_takes_repeats_and_commas_alike():
    parsers = subparsers()
    from course_dynamics.cli.options import notebook_numbers

    for command in ("student-notebooks", "publish-notebooks"):
        a = parsers[command].parse_args(["out", "--only", "01,03", "--only", "05"])
        assert notebook_numbers(a) == ("01", "03", "05")
        assert notebook_numbers(parsers[command].parse_args(["out"])) is None


def test_simulate_plot_takes_every_figure_format(capsys, tmp_path):
    for suffix in ("png", "svg", "html"):
        plot = tmp_path / f"sim.{suffix}"
        code, _, err = run(capsys, "simulate", "pendulum", "--q0", "0.5", "--duration", "0.2", "--dt", "0.01",
                           "--out", str(tmp_path / "sim.csv"), "--plot", str(plot), "--quiet")
        assert code == 0, err
        data = plot.read_bytes()
        assert data.startswith({"png": b"\x89PNG", "svg": b"<?xml", "html": b"<!DOCTYPE html>"}[suffix]), data[:20]
    assert b"<svg" in (tmp_path / "sim.html").read_bytes()
    written = np.genfromtxt(tmp_path / "sim.csv", delimiter=",", names=True)
    assert written.dtype.names[:2] == ("t", "q_theta") and len(written) == 21


class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_the_progress_bar_is_drawn_on_a_terminal_only_and_quiet_hides_it(monkeypatch):
    from course_dynamics.cli import options

    for stream, quiet, drawn in ((Terminal(), False, True), (Terminal(), True, False), (io.StringIO(), False, False)):
        monkeypatch.setattr(sys, "stderr", stream)
        assert (not options.progress_bar(argparse.Namespace(quiet=quiet), total=3).disable) == drawn


@pytest.mark.parametrize("quiet", [False, True])
def test_torques_shows_its_progress_on_a_long_log(monkeypatch, quiet):
    from course_dynamics.cli import main, options
    from course_dynamics.cli.commands import torques

    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    monkeypatch.setattr(torques, "progress_bar", lambda args, total, unit: options.progress_bar(args, total, unit, 0.0))
    argv = ["torques", "ur5", "--log", str(ROOT / "examples" / "ur5_log.csv"), "--map",
            str(ROOT / "examples" / "ur5_log_columns.toml"), "--json"] + (["--quiet"] if quiet else [])
    assert main(argv) == 0
    drawn = terminal.getvalue()
    assert ("joint torques" in drawn and "6003/6003" in drawn) != quiet, drawn[-300:]

"""Ctrl-C ends a command with one line and exit status 130, even when a library swallows it and fails after."""
from __future__ import annotations

import os
import signal

import pytest

from course_dynamics.cli import main
from course_dynamics.cli.commands import info


def test_a_library_that_swallows_ctrl_c_and_then_fails_ends_as_interrupted(monkeypatch, capsys):
    """As trimesh does when interrupted in its optional imports: it keeps a wrapper and raises TypeError later."""
    def run(args):
        try:
            os.kill(os.getpid(), signal.SIGINT)
        except KeyboardInterrupt:
            pass                                                  # the library's `except BaseException`
        raise TypeError("unsupported operand type(s) for |: 'ExceptionWrapper' and 'NoneType'")

    monkeypatch.setattr(info, "run", run)
    assert main(["info", "two_link"]) == 130
    assert capsys.readouterr().err == "error: interrupted\n"


def test_without_ctrl_c_our_own_bug_keeps_its_traceback(monkeypatch):
    def run(args):
        raise TypeError("a bug of ours")

    monkeypatch.setattr(info, "run", run)
    with pytest.raises(TypeError, match="a bug of ours"):
        main(["info", "two_link"])

"""The README stays true: its Python quick start runs, and every `course-dynamics` example command succeeds."""
from __future__ import annotations

import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text()
PLACEHOLDERS = ("my_robot.urdf", "torques.csv")  # files a reader brings; shown for the syntax


def test_python_quick_start_runs():
    block = re.search(r"## Quick start \(Python\)\n\n```python\n(.*?)```", README, re.S).group(1)
    namespace: dict = {}
    exec(compile(block, "README quick start", "exec"), namespace)
    assert namespace["tau"].shape == (2,)


def example_commands() -> list[str]:
    commands = []
    for block in re.findall(r"```sh\n(.*?)```", README, re.S):
        text = block.replace("\\\n", " ")
        for line in text.splitlines():
            line = line.split("  #")[0].strip()
            if line.startswith("course-dynamics ") and not any(p in line for p in PLACEHOLDERS):
                commands.append(line)
    return commands


@pytest.mark.parametrize("command", example_commands())
def test_cli_example_runs(command, tmp_path):
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    argv = shlex.split(command)
    result = subprocess.run([sys.executable, "-m", "course_dynamics.cli", *argv[1:]], cwd=tmp_path,
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


def test_error_examples_show_real_messages():
    """The `$ command` / `error: …` pairs in the README are what the program prints.

    The condition number of an exactly singular matrix is round-off (it differs between BLAS builds),
    so it is left out of the comparison.
    """
    def normal(text):
        return re.sub(r"condition number [0-9.e+-]+", "condition number …", text.strip())

    pairs = re.findall(r"\$ (course-dynamics [^\n]*)\n(error: [^\n]*)", README)
    assert len(pairs) >= 3
    for command, message in pairs:
        result = subprocess.run([sys.executable, "-m", "course_dynamics.cli", *shlex.split(command)[1:]],
                                cwd=ROOT, capture_output=True, text=True)
        assert result.returncode == 2 and normal(result.stderr) == normal(message), (command, result.stderr)

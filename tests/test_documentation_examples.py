"""The README and every page of the documentation site stay true: every Python block runs, every
`course-dynamics` example command succeeds (or exits as its ``# exit N`` says), every output shown is what the
command prints, and every ``error:`` line shown is the one the program prints.

The commands run in this process (``course_dynamics.cli.main``), from a folder
holding a copy of ``examples/``; the installed entry point itself is tested in
test_cli.py. A page's blocks are its fenced code: ```` ```sh ```` for commands,
```` ```python ```` for Python, a plain ```` ``` ```` right after a ``sh`` block for its output.
"""
from __future__ import annotations

import re
import shlex
import shutil
import sys
from pathlib import Path

import pytest

from course_dynamics.cli import main

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text()
# Every page: the README, then the site's Markdown pages (docs/, without the build folder).
PAGES = {"README.md": README} | {str(p.relative_to(ROOT)): p.read_text() for p in sorted((ROOT / "docs").rglob("*.md"))
                                 if "_build" not in p.parts}
ALL = "\n\n".join(PAGES.values())


def fences(text: str) -> list[tuple[int, int, str, str]]:
    """Every fenced block of a page as (start, end, language, body), read line by line as Markdown reads it: a
    fence opens with ```` ``` ```` and an info string (``sh``, ``python``, a MyST ``{toctree}``, nothing) and
    closes at the next bare ```` ``` ````."""
    found, opened, offset = [], None, 0
    for line in text.splitlines(keepends=True):
        stripped = line.strip()
        if opened is None and stripped.startswith("```"):
            opened = (offset, stripped[3:].split(" ")[0], offset + len(line))
        elif opened is not None and stripped == "```":
            found.append((opened[0], offset + len(line), opened[1], text[opened[2]:offset]))
            opened = None
        offset += len(line)
    return found


def blocks_of(language: str, text: str = ALL) -> list[str]:
    return [body for _, _, lang, body in fences(text) if lang == language]
sys.path.insert(0, str(ROOT / "docs" / "_ext"))
from course_dynamics_docs import PLACEHOLDERS  # noqa: E402  files a reader brings; shown for the syntax, not run

sys.path.remove(str(ROOT / "docs" / "_ext"))


def test_python_quick_start_runs():
    block = re.search(r"## Quick start \(Python\)\n\n```python\n(.*?)```", README, re.S).group(1)
    namespace: dict = {}
    exec(compile(block, "README quick start", "exec"), namespace)
    assert namespace["tau"].shape == (2,)


def example_blocks() -> list[list[tuple[str, int]]]:
    """Each ``sh`` block's commands as (command, expected exit status): 0, or the N of a trailing ``# exit N``."""
    blocks = []
    for block in blocks_of("sh"):
        text = block.replace("\\\n", " ")
        commands = []
        for line in text.splitlines():
            line, _, comment = line.partition("  #")
            line = line.strip()
            status = re.match(r"\s*exit (\d+)", comment)
            if line.startswith("course-dynamics ") and not any(p in line for p in PLACEHOLDERS):
                commands.append((line, int(status.group(1)) if status else 0))
        if commands:
            blocks.append(commands)
    return blocks


@pytest.mark.parametrize("commands", example_blocks(), ids=lambda block: block[0][0][:60])
def test_cli_examples_run(commands, tmp_path, monkeypatch, capsys):
    """A block's commands run in order in one folder (a later one may use what an earlier one wrote)."""
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    for command, status in commands:
        argv = shlex.split(command)[1:]
        if ">" in argv:  # a redirection of standard output: the shell's job, not the command's
            argv = argv[:argv.index(">")]
        code = main(argv)
        err = capsys.readouterr().err
        assert code == status, (command, err)
        assert " is now --" not in err, (command, err)  # a page shows the spelling of today, not an old one


def test_python_log_example_runs(tmp_path, monkeypatch):
    block = next(b for b in blocks_of("python") if "torques_from_log(" in b)
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    exec(compile(block, "README log example", "exec"), namespace)
    assert namespace["result"].report.exceeded and namespace["result"].tau.shape == (2001, 6)


def test_error_examples_show_real_messages(capsys):
    """The `$ command` / `error: …` pairs in the README are what the program prints.

    The condition number of an exactly singular matrix is round-off (it differs between BLAS builds),
    so it is left out of the comparison.
    """
    def normal(text):
        return re.sub(r"condition number [0-9.e+-]+", "condition number …", text.strip())

    pairs = re.findall(r"\$ (course-dynamics [^\n]*)\n(error: [^\n]*)", ALL)
    assert len(pairs) >= 3
    for command, message in pairs:
        code = main(shlex.split(command)[1:])
        err = capsys.readouterr().err
        assert code == 2 and normal(err) == normal(message), (command, err)


def command_output_pairs() -> list[tuple[str, str]]:
    """(command, shown output) where a ```sh block is followed directly by a plain ``` block.

    The command is the first line of the sh block; outputs with elisions (… or ...) are left out.
    """
    pairs = []
    for text in PAGES.values():
        blocks = fences(text)
        for (_, end, lang, code), (start, _, next_lang, shown) in zip(blocks, blocks[1:]):
            if lang == "sh" and next_lang == "" and not text[end:start].strip() and "..." not in shown \
                    and "…" not in shown:
                command = code.replace("\\\n", " ").splitlines()[0].split("  #")[0].strip()
                if command.startswith("course-dynamics "):
                    pairs.append((command, shown))
    return pairs


@pytest.mark.parametrize("command, shown", command_output_pairs(), ids=lambda x: x if x.startswith("course") else "")
def test_shown_output_is_what_the_command_prints(command, shown, tmp_path, monkeypatch, capsys):
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    assert main(shlex.split(command)[1:]) == 0
    printed = capsys.readouterr().out.replace(str(ROOT) + "/", "")
    assert same_text(printed, shown), printed


def same_text(printed: str, shown: str) -> bool:
    """Equal word for word and line for line; numbers equal to 1e-9 (relative) or 1e-12, so that round-off
    at the 16th digit (1e-16 where an entry is 0 in exact arithmetic) does not make the README wrong."""
    number = re.compile(r"-?\d+(?:\.\d+)?(?:e[-+]?\d+)?")
    if number.sub("#", printed) != number.sub("#", shown):
        return False
    pairs = zip(map(float, number.findall(printed)), map(float, number.findall(shown)))
    return all(abs(a - b) <= max(1e-9 * abs(b), 1e-12) for a, b in pairs)


def test_outputs_are_shown_for_several_commands():
    assert {command.split()[1] for command, _ in command_output_pairs()} >= {"info", "terms", "cartesian"}


def python_blocks() -> list[str]:
    return blocks_of("python")


@pytest.mark.parametrize("number", range(len(python_blocks())))
def test_every_python_block_runs_as_written_in_a_fresh_process(number, tmp_path):
    """Each block defines what it uses: a reader can paste any one of them alone into a new Python."""
    import os
    import subprocess
    import sys

    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    block = python_blocks()[number]
    if "show(" in block:  # the live viewer: served on loopback, then stopped by the block itself
        block = "import webbrowser\nwebbrowser.open = lambda *a, **k: True\n" + block
    env = dict(os.environ, MPLBACKEND="Agg")
    result = subprocess.run([sys.executable, "-c", block], cwd=tmp_path, capture_output=True, text=True, env=env,
                            timeout=300)
    assert result.returncode == 0, result.stderr[-3000:]

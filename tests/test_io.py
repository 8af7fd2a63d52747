"""course_dynamics/output/io.py: whole-or-nothing writes, modes, links, special files, new files and backups."""
from __future__ import annotations

import os
import stat

import numpy as np
import pytest

from course_dynamics import InputError
from course_dynamics.output import io
from course_dynamics.tools.tables import (
    read_columns,
)


def test_csv_round_trip_is_exact(tmp_path):
    data = np.random.default_rng(0).standard_normal((5, 3))
    io.write_csv(tmp_path / "x.csv", ["t", "q_a", "q_b"], data)
    columns = read_columns(tmp_path / "x.csv", ["t", "q_a", "q_b"])
    np.testing.assert_array_equal(np.column_stack([columns["t"], columns["q_a"], columns["q_b"]]), data)


def test_a_failed_write_leaves_nothing(tmp_path):
    target = tmp_path / "out.txt"
    with pytest.raises(RuntimeError):
        with io.output(target) as handle:
            handle.write("half")
            raise RuntimeError("interrupted")
    assert list(tmp_path.iterdir()) == []


def test_a_failed_write_keeps_the_old_file(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("old")
    with pytest.raises(KeyboardInterrupt):
        with io.output(target) as handle:
            handle.write("new")
            raise KeyboardInterrupt
    assert target.read_text() == "old" and list(tmp_path.iterdir()) == [target]


def test_new_files_follow_the_umask_and_replaced_files_keep_their_mode(tmp_path):
    old = os.umask(0o022)
    try:
        io.write_text(tmp_path / "new.txt", "x")
        assert stat.S_IMODE((tmp_path / "new.txt").stat().st_mode) == 0o644
        kept = tmp_path / "kept.txt"
        kept.write_text("x")
        kept.chmod(0o640)
        io.write_text(kept, "y")
        assert stat.S_IMODE(kept.stat().st_mode) == 0o640 and kept.read_text() == "y"
    finally:
        os.umask(old)


def test_a_link_at_the_target_is_replaced_not_followed(tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    link = tmp_path / "out.html"
    link.symlink_to(victim)
    io.write_text(link, "<html/>")
    assert victim.read_text() == "precious"
    assert not link.is_symlink() and link.read_text() == "<html/>"


def test_a_planted_temp_name_is_not_followed(tmp_path):
    """The temporary file's name is random (mkstemp, O_EXCL): a link planted at a predictable name is left alone."""
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    (tmp_path / ".out.html.partial").symlink_to(victim)
    io.write_text(tmp_path / "out.html", "<html/>")
    assert victim.read_text() == "precious" and (tmp_path / "out.html").read_text() == "<html/>"


def test_special_files_are_streamed_into_never_replaced(tmp_path):
    io.write_text("/dev/null", "discarded")
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    reader = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
    try:
        io.write_text(fifo, "through the pipe")
        assert os.read(reader, 100) == b"through the pipe"
    finally:
        os.close(reader)
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)


def test_an_output_named_as_the_folder_of_another_is_refused(tmp_path):
    """A drives file named as the report folder would be found a folder only after the work: refused before."""
    folder = tmp_path / "rep"
    with pytest.raises(InputError, match="named for two outputs .it is the folder .*rep/identified.urdf"):
        io.check_distinct([], [folder / "identified.urdf", folder / "report.md", folder])
    io.check_distinct([], [folder / "identified.urdf", tmp_path / "rep.toml"])   # a sibling is fine
    assert not folder.exists()


def test_dash_is_standard_output(capsys):
    io.write_csv("-", ["t"], np.array([[1.5]]))
    assert capsys.readouterr().out == "t\n1.5\n"


@pytest.mark.parametrize("target, message", [
    ("missing_dir/out.csv", "does not exist"),
    (".", "is a directory"),
])
def test_unwritable_targets_are_named(tmp_path, monkeypatch, target, message):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(InputError, match=message):
        io.write_text(target, "x")


def test_a_killed_writers_temporary_file_is_cleaned_by_the_next_write(tmp_path):
    import subprocess
    import sys

    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    stale = tmp_path / f".out.csv.{dead.stdout.strip()}.abc123.partial"
    stale.write_text("half")
    alive = tmp_path / f".out.csv.{os.getppid()}.def456.partial"  # a running process's: left alone
    alive.write_text("in progress")
    io.write_text(tmp_path / "out.csv", "whole")
    assert not stale.exists() and alive.exists() and (tmp_path / "out.csv").read_text() == "whole"


def test_write_new_never_replaces_anything(tmp_path):
    assert io.write_new(tmp_path / "a.txt", "first") and (tmp_path / "a.txt").read_text() == "first"
    assert not io.write_new(tmp_path / "a.txt", "second") and (tmp_path / "a.txt").read_text() == "first"
    (tmp_path / "victim").write_text("precious")
    (tmp_path / "link.txt").symlink_to(tmp_path / "victim")
    assert not io.write_new(tmp_path / "link.txt", "through") and (tmp_path / "victim").read_text() == "precious"
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".partial")]


def test_backups_take_a_free_name_and_are_copies(tmp_path, monkeypatch):
    monkeypatch.setattr(io.time, "strftime", lambda _: "20240101-120000")
    work = tmp_path / "01_x.ipynb"
    work.write_text("the student's answers")
    (tmp_path / "01_x.ipynb.bak-20240101-120000").write_text("an older backup")
    backup = io.keep_backup(work)
    assert backup.name == "01_x.ipynb.bak-20240101-120000-2" and backup.read_text() == "the student's answers"
    assert (tmp_path / "01_x.ipynb.bak-20240101-120000").read_text() == "an older backup"
    io.write_text(work, "new")
    assert backup.read_text() == "the student's answers" and os.stat(backup).st_ino != os.stat(work).st_ino


def test_an_interrupt_just_after_the_temporary_is_made_leaves_nothing(tmp_path, monkeypatch):
    # Python acts on a signal as a C call returns: here, as the temporary file has just been made.
    made = os.open

    def made_then_interrupted(*args, **kwargs):
        made(*args, **kwargs)
        raise KeyboardInterrupt

    monkeypatch.setattr(io.os, "open", made_then_interrupted)
    with pytest.raises(KeyboardInterrupt):
        io.write_text(tmp_path / "out.txt", "whole or nothing")
    monkeypatch.undo()
    assert list(tmp_path.iterdir()) == []

"""course_dynamics/io.py: whole-or-nothing writes, modes, links and special files; CSV reading."""
from __future__ import annotations

import codecs
import os
import stat

import numpy as np
import pytest

from course_dynamics import InputError
from course_dynamics import io


def test_csv_round_trip_is_exact(tmp_path):
    data = np.random.default_rng(0).standard_normal((5, 3))
    io.write_csv(tmp_path / "x.csv", ["t", "q_a", "q_b"], data)
    columns = io.read_columns(tmp_path / "x.csv", ["t", "q_a", "q_b"])
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


def test_joint_columns_and_stacking():
    names = io.joint_columns(("q", "qd"), ("a", "b"))
    assert names == ["q_a", "q_b", "qd_a", "qd_b"]
    stacked = io.stack_joint_columns({"q_a": np.array([1.0, 2.0]), "q_b": np.array([3.0, 4.0])}, "q", ("a", "b"))
    np.testing.assert_array_equal(stacked, [[1.0, 3.0], [2.0, 4.0]])


TABLE = [[0.0, 1.5, -2.25], [0.01, 1.75, -2.5]]


@pytest.mark.parametrize("name, raw", [
    ("comma", b"t,q_a,q_b\n0,1.5,-2.25\n0.01,1.75,-2.5\n"),
    ("semicolon, CRLF", b"t;q_a;q_b\r\n0;1.5;-2.25\r\n0.01;1.75;-2.5\r\n"),
    ("semicolon, decimal comma", b"t;q_a;q_b\n0;1,5;-2,25\n0,01;1,75;-2,5\n"),
    ("tab, comments, blank lines", b"# logged by a robot\nt\tq_a\tq_b\n\n0\t1.5\t-2.25\n# pause\n0.01\t1.75\t-2.5\n"),
    ("UTF-8 BOM", codecs.BOM_UTF8 + b"t,q_a,q_b\n0,1.5,-2.25\n0.01,1.75,-2.5\n"),
    ("UTF-16 with BOM", "t,q_a,q_b\r\n0,1.5,-2.25\r\n0.01,1.75,-2.5\r\n".encode("utf-16")),
    ("quoted cells", b'"t","q_a","q_b"\n"0","1.5","-2.25"\n"0.01","1.75","-2.5"\n'),
])
def test_read_table_takes_logs_as_they_come(tmp_path, name, raw):
    (tmp_path / "log.csv").write_bytes(raw)
    table = io.read_table(tmp_path / "log.csv")
    assert table.header == ("t", "q_a", "q_b"), name
    np.testing.assert_array_equal(table.data, TABLE)


def test_read_table_falls_back_to_latin1_headers(tmp_path):
    (tmp_path / "log.csv").write_bytes("t,température\n0,1\n".encode("latin-1"))
    assert io.read_table(tmp_path / "log.csv").header == ("t", "température")


@pytest.mark.parametrize("content, fragment", [
    ("", "empty file, expected a header row"),
    ("# only a comment\n", "empty file"),
    ("t,q\n", "no data rows"),
    ("t,q,t\n0,1,2\n", "line 1: column 't' appears twice"),
    ("t,,q\n0,1,2\n", "line 1: column 2 has no name"),
    ("t,q\n0,1\n0.1,\n", "line 3, column 'q': empty cell"),
    ("t,q\n# note\n0,1\n0.1,abc\n", "line 4, column 'q': 'abc' is not a number"),
    ("t,q\n0,1\n0.1,nan\n", "line 3, column 'q': value is nan (must be finite)"),
    ("t,q\n0,1\n0.1,1e999\n", "line 3, column 'q': value is inf"),
    ("t,q\n0,1,2\n", "line 2 has 3 values, the header has 2"),
])
def test_read_table_names_the_line_and_column(tmp_path, content, fragment):
    (tmp_path / "log.csv").write_text(content)
    with pytest.raises(InputError) as caught:
        io.read_table(tmp_path / "log.csv")
    assert str(tmp_path / "log.csv") in str(caught.value) and fragment in str(caught.value)


def test_read_table_of_a_directory_or_missing_file(tmp_path):
    with pytest.raises(InputError, match="is a directory"):
        io.read_table(tmp_path)
    with pytest.raises(InputError, match="cannot read: No such file"):
        io.read_table(tmp_path / "missing.csv")


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


def test_csv_comments_come_before_the_header_and_are_skipped_on_reading(tmp_path):
    io.write_csv(tmp_path / "x.csv", ["t", "q"], [[0.0, 1.0]], comments=["qd: differentiated\nfrom q"])
    assert (tmp_path / "x.csv").read_text().splitlines()[0] == "# qd: differentiated from q"
    assert io.read_table(tmp_path / "x.csv").header == ("t", "q")


def test_names_holding_the_delimiter_or_quotes_read_back(tmp_path):
    header = ["t", "q_a,b", 'q_say "hi"']
    io.write_csv(tmp_path / "x.csv", header, [[0.0, 1.0, 2.0]])
    assert io.read_table(tmp_path / "x.csv").header == tuple(header)

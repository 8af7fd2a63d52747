"""course_dynamics/output/io.py: whole-or-nothing writes, modes, links and special files; CSV reading."""
from __future__ import annotations

import codecs
import os
import stat

import numpy as np
import pytest

from course_dynamics import InputError
from course_dynamics.output import io
from course_dynamics.output.folders import (
    MANIFEST,
    MANIFEST_MAX_BYTES,
    check_folder,
    write_folder,
)
from course_dynamics.tools.tables import (
    BYTES_PER_VALUE,
    MAX_LINE_CHARS,
    SAMPLE_ROWS,
    joint_columns,
    read_columns,
    read_table,
    stack_joint_columns,
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
    names = joint_columns(("q", "qd"), ("a", "b"))
    assert names == ["q_a", "q_b", "qd_a", "qd_b"]
    stacked = stack_joint_columns({"q_a": np.array([1.0, 2.0]), "q_b": np.array([3.0, 4.0])}, "q", ("a", "b"))
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
    table = read_table(tmp_path / "log.csv")
    assert table.header == ("t", "q_a", "q_b"), name
    np.testing.assert_array_equal(table.data, TABLE)


def test_read_table_falls_back_to_latin1_headers(tmp_path):
    (tmp_path / "log.csv").write_bytes("t,température\n0,1\n".encode("latin-1"))
    assert read_table(tmp_path / "log.csv").header == ("t", "température")


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
        read_table(tmp_path / "log.csv")
    assert str(tmp_path / "log.csv") in str(caught.value) and fragment in str(caught.value)


def test_read_table_of_a_directory_or_missing_file(tmp_path):
    with pytest.raises(InputError, match="is a directory"):
        read_table(tmp_path)
    with pytest.raises(InputError, match="cannot read: No such file"):
        read_table(tmp_path / "missing.csv")


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
    assert read_table(tmp_path / "x.csv").header == ("t", "q")


def test_names_holding_the_delimiter_or_quotes_read_back(tmp_path):
    header = ["t", "q_a,b", 'q_say "hi"']
    io.write_csv(tmp_path / "x.csv", header, [[0.0, 1.0, 2.0]])
    assert read_table(tmp_path / "x.csv").header == tuple(header)


# ---------------------------------------------------------------------------- numbers that could be read two ways

@pytest.mark.parametrize("content, fragment", [
    # float() takes each of these; a log does not
    ("t,q\n0,1_000\n", "line 2, column 'q': '1_000' is not a number ('_' between digits"),
    ("t,q\n0,١٢٣\n", "line 2, column 'q': '١٢٣' is not a number (only the digits 0-9"),
    ("t;q\n0;1,5\n1;１２３\n", "line 3, column 'q': '１２３' is not a number (only the digits 0-9"),
    ("t,q\n0,0x10\n", "line 2, column 'q': '0x10' is not a number (hexadecimal"),
    ("t,q\n0,infinity\n", "line 2, column 'q': value is inf (must be finite)"),
    ("t;q\n0;1,5\n1;-Infinity\n", "line 3, column 'q': value is -inf (must be finite)"),
    # a thousands separator, or a decimal one?
    ("t;q\n0;1,234\n1;2,500\n", "line 2, column 'q': '1,234' could be 1.234 with a decimal comma or 1234 with a "
                                "thousands separator"),
    ("t;q\n0;1,5\n1;2.5\n", "line 3, column 'q': '2.5' has a decimal point, but line 2, column 'q' has '1,5'"),
    ("t\tq\n0\t1.5\n1\t1,234\n", "line 3, column 'q': '1,234' has a decimal comma, but line 2, column 'q' has '1.5'"),
    ("t;q\n0;1.234,5\n", "line 2, column 'q': '1.234,5' is not a number (it has both a point and a comma"),
    ("t;q\n0;1,234.5\n", "line 2, column 'q': '1,234.5' is not a number (it has both a point and a comma"),
    ("t;q\n0;1.234.567\n", "'1.234.567' is not a number (thousands separators are not read)"),
    ("t;q\n0;1 234,5\n", "'1 234,5' is not a number (a space inside a number"),
    ('t,q\n0,"1,5"\n', "line 2, column 'q': '1,5' holds a comma in a comma-separated file"),
    ("t q_a q_b\n0 1.5 2.5\n1 1.5 2.5\n", "line 1: the columns look separated by spaces"),
])
def test_numbers_that_could_be_read_two_ways_are_refused(tmp_path, content, fragment):
    (tmp_path / "log.csv").write_text(content, encoding="utf-8")
    with pytest.raises(InputError) as caught:
        read_table(tmp_path / "log.csv")
    assert str(caught.value).startswith(f"{tmp_path / 'log.csv'}: ") and fragment in str(caught.value), caught.value


def test_float_takes_what_the_table_reader_refuses():
    """Why read_table does not hand cells to float(): each of these would be read as a number."""
    assert [float(text) for text in ("1_000", "١٢٣", "１２３", " 7\u2003")] == [1000.0, 123.0, 123.0, 7.0]


@pytest.mark.parametrize("content, decimal, expected", [
    ("t;q\n0;1,234\n1;0,5\n", None, [[0, 1.234], [1, 0.5]]),     # 0,5 cannot hold a thousands separator
    ("t;q\n0;1,234\n1;2,500\n", "comma", [[0, 1.234], [1, 2.5]]),
    ("t;q\n0;1.234\n1;2\n", None, [[0, 1.234], [1, 2]]),          # no comma anywhere: the point is decimal
    ("t;q\n" + "".join(f"{k};{k}\n" for k in range(12)) + "12;0,5\n", None, [[k, k] for k in range(12)] + [[12, 0.5]]),
    ("t,q\n0,+1.5\n1,-.5e1\n", None, [[0, 1.5], [1, -5]]),
    ("t;pos,x\n0;1,5\n", None, [[0, 1.5]]),                       # as many commas as semicolons: the rows say which
    ("t,q\n0,1 # paused\n1,2\n", None, [[0, 1], [1, 2]]),
    ("t,q\r0,1\r1,2\r", None, [[0, 1], [1, 2]]),
])
def test_numbers_read_one_way_only(tmp_path, content, decimal, expected):
    (tmp_path / "log.csv").write_text(content, encoding="utf-8", newline="")
    np.testing.assert_array_equal(read_table(tmp_path / "log.csv", decimal=decimal).data, expected)


def test_a_given_decimal_separator_refuses_the_other(tmp_path):
    (tmp_path / "log.csv").write_text("t;q\n0;1,5\n")
    with pytest.raises(InputError, match="line 2, column 'q': '1,5' has a comma, but the decimal separator was given"):
        read_table(tmp_path / "log.csv", decimal="point")
    (tmp_path / "log.csv").write_text("t;q\n0;1.5\n")
    with pytest.raises(InputError, match="'1.5' has a decimal point, but the decimal separator was given as a comma"):
        read_table(tmp_path / "log.csv", decimal="comma")
    (tmp_path / "log.csv").write_text("t,q\n0,1\n")
    with pytest.raises(InputError, match="line 1: the columns are separated by commas, so no comma can be a decimal"):
        read_table(tmp_path / "log.csv", decimal="comma")


# ---------------------------------------------------------------------------- inputs that are no regular files

def test_special_files_are_refused_without_reading_or_waiting(tmp_path):
    import signal

    fifo = tmp_path / "log.csv"
    os.mkfifo(fifo)
    signal.signal(signal.SIGALRM, lambda *_: pytest.fail("read_table waited on a pipe"))
    signal.alarm(10)
    try:
        with pytest.raises(InputError, match=r"log.csv: not a regular file \(a named pipe\), not a table"):
            read_table(fifo)
    finally:
        signal.alarm(0)
    with pytest.raises(InputError, match=r"/dev/zero: not a regular file \(a character device\)"):
        read_table("/dev/zero")
    with pytest.raises(InputError, match="a table is read from a file, not from standard input"):
        read_table("-")


def test_a_line_longer_than_any_table_is_refused(tmp_path):
    with open(tmp_path / "log.csv", "wb") as handle:  # sparse: no disk used, nothing but zero bytes
        handle.truncate(MAX_LINE_CHARS + 10)
    with pytest.raises(InputError, match="line 1 is longer than 16 MiB"):
        read_table(tmp_path / "log.csv")


def test_a_log_too_large_for_memory_is_refused_before_it_is_read(tmp_path, monkeypatch):
    monkeypatch.setattr("course_dynamics.base.resources.memory_budget", lambda: 10**6)
    rows = "".join(f"{k * 0.001!r},{k * 1e-4!r},0.5\n" for k in range(50_000))
    (tmp_path / "log.csv").write_text("t,q_a,q_b\n" + rows)
    with pytest.raises(InputError, match=r"log.csv: 1.\d+ MiB, about 5.\d+e\+04 rows of 3 values: reading and using "
                                         r"them would need about 1\d.\d MiB of memory, more than half of this machine's"):
        read_table(tmp_path / "log.csv")


def test_a_log_whose_first_rows_mislead_the_estimate_is_still_bounded(tmp_path, monkeypatch):
    monkeypatch.setattr("course_dynamics.base.resources.memory_budget", lambda: 3 * BYTES_PER_VALUE * 1000)
    long_rows = "".join(" " * 5000 + f"{k},0,0\n" for k in range(SAMPLE_ROWS))
    (tmp_path / "log.csv").write_text("t,q_a,q_b\n" + long_rows + "1,0,0\n" * 5000)
    with pytest.raises(InputError, match="more than 1000 rows of 3 values: reading and using them would need more"):
        read_table(tmp_path / "log.csv")


def test_reading_a_log_does_not_hold_its_text(tmp_path):
    """The rows are streamed into the array: the peak is the array and the line numbers, not copies of the text."""
    import tracemalloc

    rows = 40_000
    t = np.arange(rows) * 1e-3
    data = np.column_stack([t] + [np.sin(t * k) for k in range(1, 7)])
    io.write_csv(tmp_path / "log.csv", ["t"] + [f"q_{k}" for k in range(6)], data)
    size = (tmp_path / "log.csv").stat().st_size
    tracemalloc.start()
    try:
        table = read_table(tmp_path / "log.csv")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    np.testing.assert_array_equal(table.data, data)
    assert peak < 0.8 * size, (peak, size)  # 4 bytes per byte of log before, when the text was split into lines


# ---------------------------------------------------------------------------- writing only where nothing is

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


# ---------------------------------------------------------------------------- output folders and their manifest

def manifest_of(folder):
    import json

    return json.loads((folder / MANIFEST).read_text())["files"]


def test_an_output_folder_replaces_only_its_own_files(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    written = write_folder(out, {"index.html": "<p>1</p>", "figures/a.svg": b"<svg/>"}, "report")
    assert written == [out / "index.html", out / "figures" / "a.svg"]
    assert {name: entry["command"] for name, entry in manifest_of(out).items()} == {"index.html": "report",
                                                                                     "figures/a.svg": "report"}
    write_folder(out, {"index.html": "<p>2</p>", "figures/a.svg": "<svg>2</svg>"}, "report")  # ours, unchanged
    assert (out / "index.html").read_text() == "<p>2</p>" and (out / "notes.txt").read_text() == "mine"
    assert sorted(p.name for p in out.iterdir()) == [MANIFEST, "figures", "index.html", "notes.txt"]


def test_files_an_earlier_run_wrote_are_kept_and_stay_ours(tmp_path):
    write_folder(tmp_path, {"a.md": "a", "b.md": "b"}, "grade")
    write_folder(tmp_path, {"a.md": "a2"}, "grade")
    assert (tmp_path / "b.md").read_text() == "b" and set(manifest_of(tmp_path)) == {"a.md", "b.md"}
    write_folder(tmp_path, {"b.md": "b2"}, "grade")
    assert (tmp_path / "b.md").read_text() == "b2"
    (tmp_path / "a.md").unlink()
    write_folder(tmp_path, {"b.md": "b3"}, "grade")
    assert set(manifest_of(tmp_path)) == {"b.md"}  # a file gone is no longer listed


@pytest.mark.parametrize("prepare, fragment", [
    (lambda out: (out / "index.html").write_text("a page of my own"), "index.html: exists and was not written by "
                                                                         "course-dynamics"),
    (lambda out: (write_folder(out, {"index.html": "x"}, "report"), (out / "index.html").write_text("edited")),
     "index.html: was changed since course-dynamics report wrote it"),
    (lambda out: write_folder(out, {"index.html": "x"}, "publish-notebooks"),
     "index.html: was written by course-dynamics publish-notebooks, not report"),
    (lambda out: (out / "index.html").mkdir(), "index.html: is a directory, not a file course-dynamics wrote"),
    (lambda out: (write_folder(out, {"index.html": "x"}, "report"), (out / "index.html").unlink(),
                  (out / "index.html").symlink_to(out.parent / "victim")),
     "index.html: is a symbolic link, not a file course-dynamics wrote"),
    (lambda out: (out / "figures").symlink_to(out.parent / "elsewhere"), "figures: is not a plain folder"),
    (lambda out: (out / "figures").write_text("a file"), "figures: is not a plain folder"),
])
def test_an_output_folder_refuses_what_it_did_not_write_before_writing_anything(tmp_path, prepare, fragment):
    out, elsewhere = tmp_path / "out", tmp_path / "elsewhere"
    out.mkdir()
    elsewhere.mkdir()
    (tmp_path / "victim").write_text("precious")
    prepare(out)
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file() and not p.is_symlink()}
    with pytest.raises(InputError) as caught:
        write_folder(out, {"new.md": "n", "index.html": "<p>new</p>", "figures/a.svg": "<svg/>"}, "report")
    assert fragment in str(caught.value) and "nothing was written" in str(caught.value), caught.value
    assert {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file() and not p.is_symlink()} == before
    assert not (out / "new.md").exists() and list(elsewhere.iterdir()) == []


HOSTILE_MANIFESTS = {
    "not JSON": b"{\"files\": ",
    "not UTF-8": b"\xff\xfe\x00",
    "a list": b"[]",
    "no version": b'{"files": {"index.html": {"command": "report", "versions": []}}}',
    "another format": b'{"course-dynamics": 2, "files": {}}',
    "files as a list": b'{"course-dynamics": 1, "files": ["index.html"]}',
    "a bad hash": b'{"course-dynamics": 1, "files": {"index.html": {"command": "report", "versions": '
                  b'[{"bytes": 1, "sha256": "zz"}]}}}',
    "deeply nested": b"[" * 100_000 + b"]" * 100_000,
}


def hostile_entry(name: str, content: bytes) -> bytes:
    import hashlib
    import json

    version = {"bytes": len(content), "sha256": hashlib.sha256(content).hexdigest()}
    return json.dumps({"course-dynamics": 1, "files": {name: {"command": "report", "versions": [version]}}}).encode()


@pytest.mark.parametrize("kind", list(HOSTILE_MANIFESTS) + ["names ../victim", "names an absolute path", "a link",
                                                            "too large"])
def test_a_hostile_manifest_is_refused_and_authorises_nothing(tmp_path, kind):
    out = tmp_path / "out"
    out.mkdir()
    victim = tmp_path / "victim"
    victim.write_bytes(b"precious")
    manifest = out / MANIFEST
    if kind == "names ../victim":
        manifest.write_bytes(hostile_entry("../victim", b"precious"))
    elif kind == "names an absolute path":
        manifest.write_bytes(hostile_entry(str(victim), b"precious"))
    elif kind == "a link":
        real = tmp_path / "real.json"
        real.write_bytes(hostile_entry("index.html", b"mine"))
        manifest.symlink_to(real)
    elif kind == "too large":
        with open(manifest, "wb") as handle:
            handle.truncate(MANIFEST_MAX_BYTES + 1)
    else:
        manifest.write_bytes(HOSTILE_MANIFESTS[kind])
    (out / "index.html").write_bytes(b"mine")
    with pytest.raises(InputError) as caught:
        write_folder(out, {"index.html": "x"}, "report")
    assert "nothing was written" in str(caught.value), caught.value
    assert victim.read_bytes() == b"precious" and (out / "index.html").read_bytes() == b"mine"


def test_a_run_interrupted_half_way_leaves_files_the_next_run_may_replace(tmp_path, monkeypatch):
    write_folder(tmp_path, {"a.md": "a1", "b.md": "b1"}, "grade")
    from course_dynamics.output import folders

    real = folders.whole_file

    def interrupted(path, *args, **kwargs):
        if path.name == "b.md":
            raise KeyboardInterrupt
        return real(path, *args, **kwargs)

    monkeypatch.setattr(folders, "whole_file", interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_folder(tmp_path, {"a.md": "a2", "b.md": "b2"}, "grade")
    monkeypatch.setattr(folders, "whole_file", real)
    assert (tmp_path / "a.md").read_text() == "a2" and (tmp_path / "b.md").read_text() == "b1"
    write_folder(tmp_path, {"a.md": "a3", "b.md": "b3"}, "grade")  # both recognised: the old b, the new a
    assert (tmp_path / "a.md").read_text() == "a3" and (tmp_path / "b.md").read_text() == "b3"


@pytest.mark.parametrize("name", ["../x", "/etc/x", "a/../../x", "", "a//b", "./a", MANIFEST])
def test_output_folder_names_stay_inside(tmp_path, name):
    with pytest.raises(InputError):
        write_folder(tmp_path / "out", {name: "x"}, "report")
    assert not (tmp_path / "out").exists() and not (tmp_path / "x").exists()


def test_check_folder_fails_early_and_writes_nothing(tmp_path):
    check_folder(tmp_path / "new" / "site", ["index.html"], "report")  # a folder to be made: fine
    assert not (tmp_path / "new").exists()
    (tmp_path / "index.html").write_text("mine")
    with pytest.raises(InputError, match="index.html: exists and was not written by course-dynamics"):
        check_folder(tmp_path, ["index.html", "report.md"], "report")
    (tmp_path / "file").write_text("x")
    with pytest.raises(InputError, match="Not a directory"):
        check_folder(tmp_path / "file" / "site", ["index.html"], "report")

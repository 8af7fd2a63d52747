"""course_dynamics/tools/tables.py: logs as they come, numbers read one way only, special and oversized files."""
from __future__ import annotations

import codecs
import os

import numpy as np
import pytest
from logmakers import write_ur_rtde

from course_dynamics import InputError
from course_dynamics.output import io
from course_dynamics.tools.cells import BLOCK_ROWS
from course_dynamics.tools.tables import (
    BYTES_PER_VALUE,
    MAX_LINE_CHARS,
    SAMPLE_ROWS,
    joint_columns,
    read_columns,
    read_table,
    stack_joint_columns,
)


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


def test_csv_comments_come_before_the_header_and_are_skipped_on_reading(tmp_path):
    io.write_csv(tmp_path / "x.csv", ["t", "q"], [[0.0, 1.0]], comments=["qd: differentiated\nfrom q"])
    assert (tmp_path / "x.csv").read_text().splitlines()[0] == "# qd: differentiated from q"
    assert read_table(tmp_path / "x.csv").header == ("t", "q")


def test_names_holding_the_delimiter_or_quotes_read_back(tmp_path):
    header = ["t", "q_a,b", 'q_say "hi"']
    io.write_csv(tmp_path / "x.csv", header, [[0.0, 1.0, 2.0]])
    assert read_table(tmp_path / "x.csv").header == tuple(header)


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
    ("t q_a q_b\n0 1.5 2.5\n1 1.5\n", "line 3 has 2 values, the header has 3 (columns separated by whitespace)"),
    ("t q_a q_b\n0 1.5 2.5\n1 1.5 2.5 3.5 4.5\n", "line 3 has 5 values, the header has 3"),
    ("t q\n0 1,234\n1 2,500\n", "line 2, column 'q': '1,234' could be 1.234 with a decimal comma or 1234"),
    ("t q\n0 1,5\n1 2.5\n", "line 3, column 'q': '2.5' has a decimal point, but line 2, column 'q' has '1,5'"),
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
    ("t q\n0 1,5\n1 -2,25\n", None, [[0, 1.5], [1, -2.25]]),   # between runs of whitespace a comma is decimal
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


# Whitespace-separated tables: UR's RTDE recorder, aligned output.

def rtde_motion(rows=50, seed=0):
    rng = np.random.default_rng(seed)
    t = 1234.5678 + np.arange(rows) * 0.002
    return t, rng.uniform(-3, 3, (rows, 6)), rng.uniform(-1, 1, (rows, 6)), rng.uniform(-2, 2, (rows, 6))


def test_a_space_separated_rtde_log_reads_as_written(tmp_path):
    t, q, qd, current = rtde_motion()
    write_ur_rtde(tmp_path / "robot_data.csv", t, q, qd, current)
    table = read_table(tmp_path / "robot_data.csv")
    assert table.header[:3] == ("timestamp", "actual_q_0", "actual_q_1") and table.header[-1] == "actual_current_5"
    assert table.text == ()
    np.testing.assert_allclose(table.data, np.column_stack([t, q, qd, current]), rtol=1e-11)  # written with 12 digits
    np.testing.assert_array_equal(table.lines, np.arange(2, 2 + len(t)))


@pytest.mark.parametrize("name, content", [
    ("runs of spaces", "t   q_a  q_b\n0  1.5   -2.25\n0.01 1.75 -2.5\n"),
    ("tabs and spaces", "t \t q_a\t\tq_b\n0\t 1.5  \t-2.25\n0.01 \t1.75\t-2.5\t\n"),
    ("leading and trailing spaces", "   t q_a q_b   \n  0 1.5 -2.25\n    0.01   1.75  -2.5  \n"),
    ("runs of tabs, as aligned output", "t\t\tq_a\tq_b\n0\t\t1.5\t-2.25\n0.01\t\t1.75\t-2.5\n"),
    ("tab after one name, spaces after another", "t\tq_a  q_b\n0\t1.5  -2.25\n0.01\t1.75  -2.5\n"),
    ("quoted cells", '"t" "q_a" "q_b"\n"0" 1.5 "-2.25"\n0.01 1.75 -2.5\n'),
])
def test_runs_of_whitespace_separate_columns(tmp_path, name, content):
    (tmp_path / "log.txt").write_text(content)
    table = read_table(tmp_path / "log.txt")
    assert table.header == ("t", "q_a", "q_b"), name
    np.testing.assert_array_equal(table.data, TABLE)


@pytest.mark.parametrize("content, header", [
    ("t,joint 1 pos,q\n0,1.5,-2.25\n0.01,1.75,-2.5\n", ("t", "joint 1 pos", "q")),   # commas: a name holds spaces
    ("t;joint 1 pos;q\n0;1.5;-2.25\n0.01;1.75;-2.5\n", ("t", "joint 1 pos", "q")),
    ("t\tjoint 1 pos\tq\n0\t1.5\t-2.25\n0.01\t1.75\t-2.5\n", ("t", "joint 1 pos", "q")),  # every row splits at tabs
])
def test_names_holding_spaces_keep_their_delimiter(tmp_path, content, header):
    (tmp_path / "log.csv").write_text(content)
    table = read_table(tmp_path / "log.csv")
    assert table.header == header
    np.testing.assert_array_equal(table.data, TABLE)


def test_a_single_column_whose_name_holds_a_space(tmp_path):
    (tmp_path / "log.csv").write_text("joint position\n1.5\n2\n")
    table = read_table(tmp_path / "log.csv")
    assert table.header == ("joint position",) and table.data.tolist() == [[1.5], [2.0]]


# Text columns: words a controller logs beside the numbers.

def test_text_columns_are_listed_and_left_out_of_the_columns(tmp_path):
    t, q, qd, _ = rtde_motion()
    write_ur_rtde(tmp_path / "robot_data.csv", t, q, qd, mode_words=True)
    table = read_table(tmp_path / "robot_data.csv")
    assert table.header[-1] == "robot_mode_word" and table.text == ("robot_mode_word",)
    assert list(table.columns()) == list(table.header[:-1])
    assert table.first_word("robot_mode_word") == (2, "running")
    assert np.isnan(table.column("robot_mode_word")).all()
    np.testing.assert_allclose(table.data[:, :-1], np.column_stack([t, q, qd]), rtol=1e-11)
    with pytest.raises(KeyError, match="'timestamp' is not a text column"):
        table.first_word("timestamp")


@pytest.mark.parametrize("content, text, first_words", [
    ('t,mode,q,state\n0,mode = auto,1.5,"RUNNING"\n0.01,manual,1.75,"IDLE"\n', ("mode", "state"), ("mode = auto", "RUNNING")),
    ('t,mode,q\n0,"auto, safe",1.5\n0.01,"a ""b""",1.75\n', ("mode",), ("auto, safe",)),  # quoted: commas, quotes
    ("t;mode;q\n0;v1.2;1,5\n0,01;a,b;1,75\n", ("mode",), ("v1.2",)),   # a text cell's point or comma says nothing
    ("t\tmode\tq\n0\tmode = auto\t1.5\n0.01\tx\t1.75\n", ("mode",), ("mode = auto",)),  # spaces in a tab file's word
    ("t,mode,q\n0,auto,1.5\n0.01,2,1.75\n", ("mode",), ("auto",)),            # a later number stays text
    ("t,mode,q\n0,auto,1.5\n0.01,,1.75\n", ("mode",), ("auto",)),             # so does a later empty cell
])
def test_a_column_is_text_when_its_first_cell_is_a_word(tmp_path, content, text, first_words):
    (tmp_path / "log.csv").write_text(content)
    table = read_table(tmp_path / "log.csv")
    assert table.text == text and table.first_words == first_words
    assert list(table.columns()) == ["t", "q"]
    np.testing.assert_array_equal(np.column_stack(list(table.columns().values())), [[0, 1.5], [0.01, 1.75]])


@pytest.mark.parametrize("content, fragment", [
    ("t,mode,q\n0,auto,1.5\n0.01,auto,RUNNING\n", "line 3, column 'q': 'RUNNING' is not a number"),
    ("t,mode,q\n0,auto,1.5\n0.01,auto,1.7S\n", "line 3, column 'q': '1.7S' is not a number"),
    ("t,mode,q\n0,auto,1.5\n0.01,auto,\n", "line 3, column 'q': empty cell"),
    ("t,mode,q\n0,auto,1.5\n0.01,auto,nan\n", "line 3, column 'q': value is nan (must be finite)"),
    ('t,mode,q\n0,auto,1.5\n0.01,auto,"1,5"\n', "line 3, column 'q': '1,5' holds a comma in a comma-separated file"),
    ("t,mode,q\n0,auto,1.5\n0.01,auto\n", "line 3 has 2 values, the header has 3"),
    ("t q mode\n0 1.5 auto\n0.01 1.75 auto manual\n", "line 3 has 4 values, the header has 3 (columns separated by"),
    ("t,q\n0,1\n0.1,RUNNING\n", "line 3, column 'q': 'RUNNING' is not a number"),
    ("t,mode\nidle,auto\n", "line 2: every cell is a word ('idle', …): no column holds numbers"),
])
def test_a_word_in_a_numeric_column_is_an_error(tmp_path, content, fragment):
    """The first data row decides which columns are text: a typo later on never turns a signal into text."""
    (tmp_path / "log.csv").write_text(content)
    with pytest.raises(InputError) as caught:
        read_table(tmp_path / "log.csv")
    assert str(caught.value).startswith(f"{tmp_path / 'log.csv'}: ") and fragment in str(caught.value), caught.value


def test_read_columns_refuses_a_named_column_of_words(tmp_path):
    (tmp_path / "log.csv").write_text("t,q,mode\n0,1,auto\n")
    with pytest.raises(InputError, match="line 2, column 'mode': 'auto' is not a number"):
        read_columns(tmp_path / "log.csv", ["t", "q"], ["mode"])
    with pytest.raises(InputError, match="unexpected columns: mode"):
        read_columns(tmp_path / "log.csv", ["t", "q"])


@pytest.fixture
def numpy_reads(monkeypatch):
    """What numpy's reader is handed: ("stream", rows it took) for a whole file, ("block", rows) for a block."""
    calls, loadtxt = [], np.loadtxt

    def spy(rows, *args, **kwargs):
        if isinstance(rows, list):
            calls.append(("block", len(rows)))
            return loadtxt(rows, *args, **kwargs)
        taken = []
        try:
            return loadtxt((taken.append(row) or row for row in rows), *args, **kwargs)
        finally:
            calls.append(("stream", len(taken)))

    monkeypatch.setattr(np, "loadtxt", spy)
    return calls


@pytest.mark.parametrize("mode_words", [False, True])
def test_every_row_of_a_long_log_goes_to_numpy_in_one_pass(tmp_path, monkeypatch, numpy_reads, mode_words):
    """All-numeric files (and the numeric cells of files with text columns) are read by numpy's reader, never
    cell by cell in Python: robust where a timing would not be."""
    monkeypatch.setattr("course_dynamics.tools.tables.parse_rows", lambda *_: pytest.fail("read row by row"))
    t, q, qd, _ = rtde_motion(rows=3 * BLOCK_ROWS + 5)
    write_ur_rtde(tmp_path / "robot_data.csv", t, q, qd, mode_words=mode_words)
    table = read_table(tmp_path / "robot_data.csv")
    assert numpy_reads == [("stream", len(t))] and table.data.shape == (len(t), 13 + mode_words)


@pytest.mark.parametrize("mode", ["", "auto;"])
def test_decimal_commas_are_read_by_numpy_in_blocks(tmp_path, numpy_reads, mode):
    rows = 3 * BLOCK_ROWS + 5
    lines = [f"{k};{mode}{k},25;-{k},5" for k in range(rows)]
    (tmp_path / "log.csv").write_text(f"t;{'mode;' if mode else ''}q_a;q_b\n" + "\n".join(lines) + "\n")
    table = read_table(tmp_path / "log.csv")
    blocks = [rows for kind, rows in numpy_reads if kind == "block"]
    assert sum(blocks) == rows and max(blocks) == BLOCK_ROWS  # every row, BLOCK_ROWS at a time
    np.testing.assert_array_equal(table.columns()["q_b"], -np.arange(rows) - 0.5)


@pytest.mark.parametrize("delimiter", [",", " "])
def test_reading_a_log_with_text_columns_does_not_hold_its_text(tmp_path, delimiter):
    """The slower path of files with words streams too: the text is never held whole (that took 4 bytes per byte)."""
    import tracemalloc

    rows = 40_000
    t = np.arange(rows) * 1e-3
    columns = [t] + [np.sin(t * k) for k in range(1, 7)] + [["RUNNING"] * rows]
    header = ["t"] + [f"q_{k}" for k in range(6)] + ["mode"]
    (tmp_path / "log.csv").write_text(delimiter.join(header) + "\n" + "".join(
        delimiter.join([*(repr(float(c[i])) for c in columns[:-1]), "RUNNING"]) + "\n" for i in range(rows)))
    size = (tmp_path / "log.csv").stat().st_size
    tracemalloc.start()
    try:
        table = read_table(tmp_path / "log.csv")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert table.text == ("mode",)
    np.testing.assert_array_equal(np.column_stack(list(table.columns().values())), np.column_stack(columns[:-1]))
    assert peak < 1.3 * size, (peak, size)  # the numbers, once read and once beside the NaN of the text column


def test_blanks_are_nan_only_when_asked_and_counted(tmp_path):
    """A recorder's export leaves a cell empty where a series has no sample; a plain table's empty cell is refused."""
    path = tmp_path / "export.csv"
    path.write_text("__time,/a/x,/b/y,mode\n0.5,1.5,,run\n0.75,,2.25,run\n1.0,3.0,4.0,stop\n")
    table = read_table(path, blanks=True)
    assert table.blanks == 2 and table.text == ("mode",)
    np.testing.assert_array_equal(table.data[:, :3], [[0.5, 1.5, np.nan], [0.75, np.nan, 2.25], [1.0, 3.0, 4.0]])
    with pytest.raises(InputError, match="line 2, column '/b/y': empty cell"):
        read_table(path)

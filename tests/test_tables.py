"""course_dynamics/tools/tables.py: logs as they come, numbers read one way only, special and oversized files."""
from __future__ import annotations

import codecs
import os

import numpy as np
import pytest

from course_dynamics import InputError
from course_dynamics.output import io
from course_dynamics.tools.tables import (
    BYTES_PER_VALUE,
    MAX_LINE_CHARS,
    SAMPLE_ROWS,
    joint_columns,
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

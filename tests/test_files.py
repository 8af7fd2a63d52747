"""base/files.py: the one way a file we are given is opened, whatever words its caller refuses it in."""
from __future__ import annotations

import os

import pytest

from course_dynamics.base.errors import InputError
from course_dynamics.base.files import Refusals, open_regular, read_small


def test_a_pipe_a_device_and_a_folder_are_refused_with_what_they_are(tmp_path):
    os.mkfifo(tmp_path / "pipe")
    with pytest.raises(InputError, match=r"pipe: not a regular file \(a named pipe\), not a table$"):
        read_small(tmp_path / "pipe", 10, "table")  # refused without waiting for a writer
    with pytest.raises(InputError, match=r"^/dev/zero: not a regular file \(a character device\), not a table$"):
        open_regular("/dev/zero", "table")
    with pytest.raises(InputError, match=r": is a directory, not a table$"):
        read_small(tmp_path, 10, "table")
    (tmp_path / "link").symlink_to(tmp_path / "pipe")
    with pytest.raises(InputError, match=r"link: is a symbolic link, not a table$"):
        read_small(tmp_path / "link", 10, "table", follow=False)


def test_sizes_are_refused_before_reading(tmp_path):
    path = tmp_path / "big"
    with open(path, "wb") as handle:
        handle.truncate(3 * 2**30)  # sparse: nothing may read it whole
    with pytest.raises(InputError, match=r"big: 3 GiB is more than a table may be \(1 MiB\)$"):
        read_small(path, 2**20, "table")
    (tmp_path / "small").write_bytes(b"abc")
    assert read_small(tmp_path / "small", 3) == b"abc"
    with pytest.raises(InputError, match=r"^.*missing: cannot read: No such file or directory$"):
        read_small(tmp_path / "missing", 3)
    with pytest.raises(InputError, match="cannot read: embedded null byte"):
        read_small("a\0b", 3)


class Refused(InputError):
    pass


def test_a_caller_words_the_refusals_and_chooses_the_error(tmp_path):
    mine = Refusals(error=Refused, unreadable="cannot open {what} {path} ({reason})", not_a_file="{what}: a folder",
                    not_regular="{what}: {kind}", too_large="{size_bytes} > {limit_bytes} bytes",
                    grew="more than {limit}")
    os.mkfifo(tmp_path / "pipe")
    with pytest.raises(Refused, match="^mesh: a named pipe$"):
        read_small(tmp_path / "pipe", 10, "mesh", refusals=mine)
    with pytest.raises(Refused, match="^mesh: a folder$"):
        read_small(tmp_path, 10, "mesh", refusals=mine)
    (tmp_path / "four").write_bytes(b"abcd")
    with pytest.raises(Refused, match="^4 > 3 bytes$"):
        read_small(tmp_path / "four", 3, "mesh", refusals=mine)
    with pytest.raises(Refused, match=r"^cannot open mesh .*none \(No such file or directory\)$"):
        read_small(tmp_path / "none", 3, "mesh", refusals=mine)

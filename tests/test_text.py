"""base/text.py: a name or a message printed on one line cannot start another line of our output."""
from __future__ import annotations

import pytest

from course_dynamics.base.text import one_line


@pytest.mark.parametrize("text, shown", [
    ("theta1", "theta1"),
    ("ω̇ of link 2 (Θ̈)", "ω̇ of link 2 (Θ̈)"),                      # printable Unicode stays as it is
    ("a\nerror: forged", "a\\nerror: forged"),                     # a line break cannot forge a line
    ("a\r\x1b[2Kb", "a\\r\\x1b[2Kb"),                              # nor a carriage return or a terminal's escape
    ("\u200eright\u2028left\t", "\\u200eright\\u2028left\\t"),     # direction marks, Unicode's line separator, tabs
])
def test_every_control_character_is_written_as_its_escape(text, shown):
    assert one_line(text) == shown
    assert len(one_line(text).splitlines()) == 1


def test_anything_is_shown_as_its_string():
    assert one_line(ValueError("bad\nvalue")) == "bad\\nvalue"

"""Text that must stay on one line: a name or a message cannot forge a line of our output.

Whatever came from a file or a user (a joint name, a bag's topic, an exception's message) can hold a line
break, an escape sequence or a direction mark; printed as it is, it could end our ``error:`` line and start
another that looks like ours. :func:`one_line` writes every such character as its escape.
"""
from __future__ import annotations


def one_line(text) -> str:
    """``text`` with every control character (line breaks, escape sequences) written as an escape: one safe line.

    Parameters
    ----------
    text : object
        What to write; anything but a string is first made one with ``str``.

    Returns
    -------
    str
        ``text`` on one line, each character that is not printable written as its Python escape.

    Examples
    --------
    >>> print(one_line("joint\\nerror: forged \\x1b[2J\\u200e"))
    joint\\nerror: forged \\x1b[2J\\u200e
    """
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(text))


__all__ = ["one_line"]

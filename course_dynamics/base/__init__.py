"""Layer 0, what every layer shares: the errors we raise, opening files we are given, the memory budget, one-line text.

It imports nothing of course_dynamics but itself.

==============  ================================================================
module          job
==============  ================================================================
``errors``      the one error hierarchy: one-line messages naming the file, joint or row
``files``       opening a given file: regular files only, of a size we can take
``resources``   the machine's memory budget, and byte counts for people
``text``        one safe line: a name or message with its control characters escaped
==============  ================================================================
"""

__all__: list[str] = []  # a package of modules: it re-exports nothing

"""Layer 0, what every layer shares: errors, opening given files, the memory budget, one-line text, robot files.

It imports nothing of course_dynamics but itself.

================  ================================================================
module            job
================  ================================================================
``errors``        the one error hierarchy: one-line messages naming the file, joint or row
``files``         opening a given file: regular files only, of a size we can take
``resources``     the machine's memory budget, and byte counts for people
``robot_files``   the shipped robots by name, and where their URDF files are
``text``          one safe line: a name or message with its control characters escaped
================  ================================================================
"""

__all__: list[str] = []  # a package of modules: it re-exports nothing

"""One module per command. Each declares ``HELP`` (and optionally ``DESCRIPTION``),
``add_arguments(parser)`` and ``run(args) -> exit code``, and calls the library.

A command imports the library inside ``run``: ``course-dynamics --help`` and every other command then load
only what they use (numpy, not sympy, matplotlib, yourdfpy or nbconvert), which keeps start-up short."""

# In the order ``course-dynamics --help`` lists them.
COMMANDS = ("info", "terms", "torques", "excite", "identify", "cartesian", "simulate", "trace", "derive", "animate", "validate", "report", "grade", "student_notebooks", "publish_notebooks")

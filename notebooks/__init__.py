"""The notebook course (installed as ``course_dynamics_notebooks``): jupytext percent-format sources.

Open them through ``course-dynamics student-notebooks DIR`` (student versions) or with ``--solutions``;
see :mod:`course_dynamics.teaching.course`.
"""

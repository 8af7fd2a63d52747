"""Layer 5, teaching: the notebook course and its exercise checks.

It may import every layer below, grading's scorer included (a notebook check scores an answer as
the grader does); only the command line sits above it.

==============  ================================================================
module          job
==============  ================================================================
``course``      the notebooks: student versions, running and publishing them
``exercises``   the exercise checks a notebook calls: ``check("name")``
==============  ================================================================
"""

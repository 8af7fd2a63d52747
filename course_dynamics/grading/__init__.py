"""Layer 4, grading students' dynamics code: safely, and with feedback that teaches.

It may import base, core, tools and output; teaching uses its scorer, and only the command
line and teaching sit above it. ``harness``, ``integrity`` and ``launcher`` import nothing of ours at all:
they run beside student code.

===============  ================================================================
module           job
===============  ================================================================
``assignment``   the assignment TOML file: robot, states, tolerance, limits, points
``plan``         the calls a submission is asked, our answers, and its answers as terms
``robots``       interface = "robot": the practice robot and hidden ones of its shape, as plain data
``uploads``      what a student hands in (a .py, a notebook's code cells) and their id on the roster
``harness``      the only code of ours next to student code: imports it, calls it, watches it
``integrity``    the audit hook in the submission's interpreter and its signed channel: what it tries
``launcher``     starts the sandbox with limits, as a fresh standard-library process
``environment``  the Python a submission runs in: the standard library and the allowed packages
``view``         what of the disk a submission sees in the sandbox, from the Python build's layout
``libraries``    the shared libraries that Python and its packages load, found as the loader finds them
``sandbox``      a separate process with limits, in bubblewrap, killed cleanly
``containment``  cgroups, a seccomp filter and the subreaper beside the sandbox
``results``      the results document a submission's process sends back, read as hostile
``records``      the records of scoring: an answer, a finding, a diagnosis
``slips``        the recursion's operations with one slip a student makes, in the equations it names
``mistakes``     the mistakes students make, each made on purpose by our own code
``diagnosis``    the named mistakes: small checks over one answer, each with its advice
``numbers``      whose numbers: right dynamics of another robot, and the parameters that differ
``score``        the one scorer of a term, used by the grader and the notebooks
``similarity``   near-identical submissions, compared without running them
``grade``        a whole class: inspect, run, score
``feedback``     gradebook.csv, per-student Markdown/HTML/Gradescope JSON, summary.html
``autograder``   Gradescope's bundle and what runs in it
===============  ================================================================

>>> from course_dynamics.grading import EXAMPLE
>>> "[points]" in EXAMPLE
True
"""
from .assignment import EXAMPLE, TERMS, Assignment, load_assignment
from .diagnosis import Diagnosis, diagnose
from .score import score
from .feedback import write_outputs
from .grade import SubmissionGrade, grade_class, grade_submission
from .sandbox import SandboxError, check_sandbox

__all__ = ["EXAMPLE", "TERMS", "Assignment", "Diagnosis", "SandboxError", "SubmissionGrade", "check_sandbox",
           "diagnose", "grade_class", "grade_submission", "load_assignment", "score", "write_outputs"]

"""Layer 5, teaching: the notebook course and its exercise checks.

It may import every layer below, grading's scorer included (a notebook check scores an answer as
the grader does); only the command line sits above it.

=================  ============================================================================
module             job
=================  ============================================================================
``course``         the notebooks: student versions, running and publishing them
``exercises``      the exercise checks a notebook calls: ``check("name")``
``catalogue``      each exercise: what it gives the student, how its answer is known, its hints
``derivations``    a derivation by hand (equations in θ(t)) compared term by term with ours
``propagation``    the notes' homework as functions: the propagation rules, with their slips
``limits``         a time limit for a check in a student's kernel, even inside its ``except:``
=================  ============================================================================
"""

__all__ = []

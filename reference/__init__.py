"""The oracle: Pinocchio and the textbook's closed forms (installed as ``course_dynamics_reference``).

Nothing here is used by :mod:`course_dynamics` to compute; it is what
course_dynamics is checked against. Pinocchio, MuJoCo and PyBullet are imported
only in this package, and only by the modules that need them (``pinocchio_oracle``,
``validate``; ``engines`` for ``crosscheck``, which puts one URDF through all four
and names the convention behind each difference), so importing this package itself
stays light.
"""

TERMS = ("tau", "M", "C", "V", "G")
TOLERANCE = 1e-9  # relative: the agreement with Pinocchio the project holds itself to

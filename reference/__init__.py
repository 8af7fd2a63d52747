"""The oracle: Pinocchio and the textbook's closed forms.

Nothing here is used by :mod:`course_dynamics` to compute; it is what
course_dynamics is checked against. Pinocchio is imported only in this package.
"""

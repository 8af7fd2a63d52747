"""Layer 1, the chapter's core: Craig's chapter 6 on any fixed-base URDF.

The model (frozen dataclasses), the URDF reader, the algebra every number type runs through,
kinematics, the Newton–Euler iterations (6.45)–(6.53), the Lagrangian formulation (6.69)–(6.77),
M by composite bodies, C, Craig's B/C split (6.63), Cartesian dynamics (6.99), friction
(6.110)–(6.112), forward dynamics (6.115), the symbolic path and compiled models (the same
recursions traced into straight-line code). It may import :mod:`course_dynamics.base` and
itself only: nothing here knows about logs, pages, plots, courses, grading or the command line.
"""

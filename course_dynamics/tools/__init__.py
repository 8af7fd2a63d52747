"""Layer 2, tools built on the core: simulation, robot logs, loads, limits, the link-by-link trace.

They may import :mod:`course_dynamics.base`, :mod:`course_dynamics.core` and each other; never
output, grading, teaching or the command line.

==============  ================================================================
module          job
==============  ================================================================
``simulation``  forward dynamics in time (6.115)–(6.117): integrators, ensembles
``tables``      reading logs as robots and people write them
``logs``        from a log to torques: columns, differentiation, payloads, limits
``loads``       payloads and external wrenches
``limits``      effort and velocity limits: peaks, shares, violations
``trace``       the Newton–Euler iterations link by link, for teaching
==============  ================================================================
"""

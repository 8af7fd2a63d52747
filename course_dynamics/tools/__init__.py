"""Layer 2, tools built on the core: simulation, robot logs, loads, limits, the link-by-link trace.

They may import :mod:`course_dynamics.base`, :mod:`course_dynamics.core` and each other; never
output, grading, teaching or the command line.

===================  ================================================================================================
module               job
===================  ================================================================================================
``simulation``       forward dynamics in time (6.115)–(6.117): integrators, ensembles
``joint_stops``      joint limits as unilateral constraints: a stop's impulse through M, a held joint's reaction
``tables``           reading delimited tables as robots and people write them
``cells``            a table's cells read as numbers one way only, and split at a delimiter
``bags``             ROS 1/ROS 2 bags and MCAP: joint states and Franka's state, without ROS
``bagtypes``         the message definitions bags are read with (Franka's state, the typestores)
``decompression``    every decompression a bag needs, streamed and stopped at a bound
``sources``          any log (table, UR RTDE recording, bag) read into one shape, with its format's map
``motion``           one reader of motion (t, Θ, applied τ) for every command that reads one
``columns``          which of a log's columns give t, Θ, Θ̇, Θ̈ and the measured torques: one plan
``resampling``       an even clock: dropped samples filled, resampling, long gaps split
``differentiation``  Θ̇ and Θ̈ from noisy samples, the window chosen from the noise
``logs``             from a log to torques: the steps above, then payloads, limits and residuals
``residuals``        the model against the robot: measured torques next to ours
``collisions``       collisions and external torques from a log: the generalized-momentum observer
``identification``   inertial and friction parameters from a log: least squares, then physically consistent
``consistency``      the physically consistent step of an identification (cvxpy), its solvers' warnings as ours
``plausibility``     is an identified body plausible: its mass against the URDF's, its centre of mass within its link
``excitation``       a trajectory within the limits that makes the parameters identifiable
``excitationcost``   an excitation's memory and time estimated before it starts; its evaluations in batches
``loads``            payloads and external wrenches
``payloads``         a payload's mass, centre of mass and inertia from a short log, on a known arm
``limits``           effort and velocity limits: peaks, shares, violations
``retiming``         a motion played uniformly slower until it is within its limits: the smallest time scaling
``trace``            the Newton–Euler iterations link by link, for teaching
``variants``         each student's own variant of a course robot, and their states
``lint``             a URDF's physics checked as written: findings by class, link or joint, severity and fix
``lint_classes``     the linter's classes of finding (severity, fix) and its finding record
``lint_geometry``    the linter's checks of an inertia against the link's shapes (density, reach, units)
``lint_inertia``     the linter's checks of each link's mass and inertia tensor, by the loader's rule
``lint_scale``       the linter's checks that need no shapes: masses and inertias against joints and effort limits
===================  ================================================================================================
"""

__all__: list[str] = []  # a package of modules: it re-exports nothing

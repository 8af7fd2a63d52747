"""One module per command. Each declares ``HELP`` (and optionally ``DESCRIPTION``),
``add_arguments(parser)`` and ``run(args) -> exit code``, and calls the library.

A command imports the library inside ``run``: ``course-dynamics --help`` and every other command then load
only what they use (numpy, not sympy, matplotlib, yourdfpy or nbconvert), which keeps start-up short.

=====================  ==========================================================
module                 ``course-dynamics …``
=====================  ==========================================================
``info``               the joints and moving bodies of a robot
``lint``               a URDF's physics checked, each finding with its class, severity and fix
``terms``              τ, M, C, V and G at one state
``torques``            the joint torques a logged trajectory needs, and a limits report
``detect``             collisions and external torques in a log, by the momentum observer
``excite``             an excitation trajectory for identification
``identify``           the inertial and friction parameters a log shows, as a URDF
``cartesian``          operational-space dynamics Mx, Vx, Gx (6.99) of a frame
``simulate``           forward dynamics in time (6.115)–(6.117)
``trace``              the Newton–Euler iterations link by link
``derive``             closed-form τ, M, V, G and Craig's B, C
``animate``            a motion as a self-contained HTML animation
``validate``           every term against Pinocchio on seeded random states
``crosscheck``         one URDF in course_dynamics, Pinocchio, MuJoCo and PyBullet, each difference explained
``report``             a comparison report against Pinocchio
``grade``              students' dynamics code graded in a sandbox, with feedback
``student_notebooks``  the course's notebooks without solutions
``publish_notebooks``  the course run and rendered as static HTML pages
=====================  ==========================================================
"""

# Each command's one-line help, in the order ``course-dynamics --help`` lists them: read without importing the
# commands (their modules import the library), so the top-level help starts at once.
COMMANDS = {
    "info": 'joints (order, type, axis, limits, parent) and moving bodies (mass, COM)',
    "lint": "check a URDF's masses, inertias, limits and axes; each finding with its class, severity and fix",
    "terms": 'tau, M, C, V, G at one state',
    "torques": 'joint torques along a trajectory log, and a limits report',
    "detect": 'collisions and external torques in a log with measured torques (momentum observer)',
    "excite": 'an excitation trajectory for identification (periodic Fourier motion, well-conditioned regressor)',
    "identify": 'identify the inertial and friction parameters from a log with measured torques; write them as a URDF',
    "cartesian": 'Cartesian-space dynamics Mx, Vx, Gx (6.99) of a frame',
    "simulate": 'forward dynamics in time (6.115)-(6.117), written as CSV',
    "trace": 'the Newton-Euler iterations link by link (numeric or symbolic)',
    "derive": "closed-form tau, M, V, G and Craig's B, C (symbolic)",
    "animate": 'animate a logged or simulated motion as a self-contained HTML file (meshcat)',
    "validate": 'compare every term with Pinocchio on random states',
    "crosscheck": 'compare one URDF across course_dynamics, Pinocchio, MuJoCo and PyBullet, explaining each difference',
    "report": 'write a comparison report against Pinocchio (HTML, Markdown, JSON) for the course page',
    "grade": "grade students' dynamics code (sandboxed) against the library, with feedback",
    "student_notebooks":
        'write the notebook course as .ipynb for students (solutions removed) or instructors (--solutions)',
    "publish_notebooks":
        'run every notebook and render the course to static HTML pages (with an index) for a course site',
}

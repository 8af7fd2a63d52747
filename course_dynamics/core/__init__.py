"""Layer 1, the chapter's core: Craig's chapter 6 on any fixed-base URDF.

The model (frozen dataclasses), the URDF reader, the algebra every number type runs through,
kinematics, the Newton–Euler iterations (6.45)–(6.53), the Lagrangian formulation (6.69)–(6.77),
M by composite bodies, C, Craig's B/C split (6.63), Cartesian dynamics (6.99), friction
(6.110)–(6.112), forward dynamics (6.115), the symbolic path and compiled models (the same
recursions traced into straight-line code). It may import :mod:`course_dynamics.base` and
itself only: nothing here knows about logs, pages, plots, courses, grading or the command line.

====================  ================================================================
module                job
====================  ================================================================
``model``             the immutable robot model, one record per moving body
``urdf``              a URDF read as a model (through yourdfpy, never Pinocchio)
``robots``            the robots we ship: the course models and example-robot-data arms
``joints``            what each kind of joint does to its body, in one place
``state``             joint-space states: checked, and between arrays and scalars
``algebra``           three-vector algebra on floats, numpy batches and sympy symbols
``inertia``           inertia tensors of simple bodies: moved, turned and checked
``kinematics``        joint transforms, placements, point Jacobians, potential energy
``newton_euler``      the outward and inward iterations (6.45)–(6.53)
``operations``        the operations those iterations are written against
``dynamics``          the terms of τ = M(Θ)Θ̈ + V(Θ, Θ̇) + G(Θ) (6.59)
``crba``              M(Θ) by composite bodies, in one pass
``spatial``           six-dimensional velocities, forces and inertias, for the O(n²) algorithms
``coriolis``          C(Θ, Θ̇) in O(n²), with Ṁ − 2C skew-symmetric
``lagrange``          the Lagrangian formulation (6.69)–(6.77): a second, independent path
``cartesian``         Jacobians and the operational-space terms (6.91)–(6.105)
``friction``          joint friction F(Θ̇) (6.110)–(6.112)
``drives``            the joints' rotor inertias Iₐ and torque offsets τ₀, and their TOML file
``forward_dynamics``  Θ̈ = M⁻¹(τ − V − G − F) (6.115)
``regressor``         τ = Y(Θ, Θ̇, Θ̈) π and the base parameters, from the one recursion
``parameters``        the symbolic path's parameters: exact numbers, or the notes' symbols
``symbolic``          closed forms: the same recursions run on sympy expressions
``sampling``          seeded random states and the relative error every comparison uses
``evaluator``         the one evaluator: the fastest implementation giving the same numbers
``compiled``          compiled models: the recursions traced into straight-line Python or C
====================  ================================================================

The subpackage :mod:`course_dynamics.core.compiled` holds these modules:

=======================  =============================================================
module                   job
=======================  =============================================================
``compiled.tracing``     the recursions run once on traced scalars, as straight-line programs
``compiled.codegen``     a traced program written out as Python, for one state and a batch
``compiled.native``      the same programs as C, built into an extension where a compiler exists
``compiled.steps``       the native loop's C: each body's step traced once, looped over any robot
``compiled.looped``      the native loop at run time: the extension built with the package, checked
``compiled.rollout``     the whole simulation in one native call: the fixed-step integrators' C
``compiled.impulses``    joint stops in that call, one stop's C: the impulse through M, the held joints
``compiled.stopping``    joint stops in that call, the steps' C: crossings located, contacts, releases
``compiled.entry``       the one-state entry: a call checked and computed in C
``compiled.building``    building the native library: bounded, limited, remembered if it fails
``compiled.cache``       the on-disk cache: a private folder, entries behind a keyed hash
=======================  =============================================================
"""

__all__: list[str] = []  # a package of modules: it re-exports nothing

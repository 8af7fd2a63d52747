"""The notebooks' exercises: what each gives the student, how its answer is known, and its hints in tiers.

Every exercise runs on the student's own robot and numbers
(:mod:`course_dynamics.tools.variants`): :func:`use_student` names the student
(a student's notebook does it in its first cell), :func:`my_robot` is their
variant of a course robot, and :func:`given` their data for an exercise. A
notebook without a student id works for :data:`~course_dynamics.tools.variants.COURSE_STUDENT`,
whose robots differ from the worked examples' too.

Hints come in tiers (the ``hints`` of an :class:`Exercise`): which term or idea, then which
equation, then, last, the method step by step: never the answer the exercise asks for (its closed
form or its value).

>>> use_student("ada")
>>> bool((given("v_dot_c1")["q"] == given("v_dot_c1")["q"]).all()), my_robot("two_link").student
(True, 'ada')
>>> use_student("course")
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..core import inertia
from ..core.algebra import Vec3, point_acceleration
from ..core.cartesian import cartesian_dynamics
from ..core.forward_dynamics import forward_dynamics
from ..core.friction import Friction
from ..core.newton_euler import inverse_dynamics, newton_euler_links
from ..core.operations import EXACT, Operations
from ..core.regressor import base_parameters, parameter_names, regressor
from ..core.robots import load_robot
from ..core.symbolic import derive
from .propagation import Z, chain_quantities, inward_moment, moving_point, omega_dot_next, prismatic, v_dot_next
from ..tools.variants import COURSE_STUDENT, Variant, check_student_id, rng_for, robot_variant

_STUDENT = {"id": COURSE_STUDENT}


def use_student(student: str) -> None:
    """Check the exercises of this kernel against ``student``'s robot and numbers (an id as the course uses it).

    Parameters
    ----------
    student : str
        The student's id (letters, digits and ``. _ + -``; ``"course"`` for the course's own numbers).

    Raises
    ------
    InputError
        If ``student`` is not an id a course uses.
    """
    _STUDENT["id"] = check_student_id(student)


def student() -> str:
    """The student whose exercises this kernel checks.

    Returns
    -------
    str
        The id :func:`use_student` set, or :data:`~course_dynamics.tools.variants.COURSE_STUDENT`.
    """
    return _STUDENT["id"]


def my_robot(name: str = "two_link") -> Variant:
    """The student's own variant of course robot ``name``: ``.describe()`` lists its numbers, ``.parameters``
    gives m1, l1, … by name, ``.model`` is the model (its bodies' masses, centres of mass, tensors and joint
    placements, which the spatial arm's exercises read).

    Parameters
    ----------
    name : str, optional
        A course robot (``"two_link"``, ``"rp_arm"``, ``"spatial_arm"``, …).

    Returns
    -------
    Variant
        The student's robot (:class:`~course_dynamics.tools.variants.Variant`), the same on every call.

    Raises
    ------
    InputError
        If ``name`` is not a course robot.
    """
    return robot_variant(name, student())


def _robot(name: str):
    return my_robot(name).model


def _state(rng, n: int = 2, low: float = -np.pi, high: float = np.pi) -> dict:
    """A state with two decimals, easy to type into a calculator: Θ (rad), Θ̇ (rad/s), Θ̈ (rad/s²)."""
    return {"q": rng.uniform(low, high, n).round(2), "qd": rng.uniform(-2, 2, n).round(2),
            "qdd": rng.uniform(-2, 2, n).round(2)}


# ---------------------------------------------------------------------------------------- what the exercises give

def _given_6_15(rng) -> dict:
    from scipy.spatial.transform import Rotation

    return {"Omega_B": rng.uniform(-1, 1, 3).round(2), "Omega_B_dot": rng.uniform(-1, 1, 3).round(2),
            "R_AB": Rotation.from_rotvec(rng.uniform(-0.6, 0.6, 3).round(2)).as_matrix(),
            "Omega_C_in_B": np.array([0.0, 0.0, rng.uniform(0.5, 2)]).round(2),
            "Omega_C_dot_in_B": np.array([0.0, 0.0, rng.uniform(-1, 1)]).round(2)}


def _principal(rng) -> dict:
    moments = rng.uniform(0.2, 0.4, 3).round(2)
    I = np.diag(moments) + np.array([[0, 1, 0], [1, 0, 0], [0, 0, 0]]) * round(float(rng.uniform(-0.06, 0.06)), 3)
    return {"I": I + np.array([[0, 0, 1], [0, 0, 0], [1, 0, 0]]) * round(float(rng.uniform(-0.03, 0.03)), 3)}


def _physical(rng) -> dict:
    tensors = [np.diag([0.1, 0.2, 0.25]), np.diag([0.1, 0.1, 0.3]), np.array([[0.2, 0.1, 0.0], [0.1, 0.2, 0.0],
                                                                              [0.0, 0.0, 0.3]]),
               np.diag([0.3, -0.05, 0.3]), np.array([[0.2, 0.25, 0.0], [0.25, 0.2, 0.0], [0.0, 0.0, 0.3]])]
    return {"tensors": [tensors[k] for k in rng.permutation(len(tensors))[:3]]}


#: Exercise name → how its data is drawn from the student's random numbers (what :func:`given` returns).
GIVEN = {
    "omega_dot_C": _given_6_15,
    "principal_moments": _principal,
    "physical": _physical,
    "v_dot_c1": _state,
    "Mx_value": lambda rng: {"q": np.array([rng.uniform(-np.pi, np.pi), rng.uniform(0.5, 2.6)]).round(2)},
    "tau_with_friction": lambda rng: {**_state(rng), "viscous": rng.uniform(0.05, 0.5, 2).round(2),
                                      "coulomb": rng.uniform(0.1, 0.8, 2).round(2)},
    "I_xy_corner": lambda rng: {"m": round(float(rng.uniform(1, 4)), 1), "w": round(float(rng.uniform(0.1, 0.5)), 2),
                                "l": round(float(rng.uniform(0.2, 0.8)), 2),
                                "h": round(float(rng.uniform(0.05, 0.2)), 2)},
    "Y_mcx2": _state,
    "predict_G": lambda rng: {"theta1": round(float(rng.uniform(1.0, 1.5)), 2)},  # rad: link 1 raised, link 2 back
    "links_spatial_arm": lambda rng: _state(rng, 3, -2.0, 2.0),
}


def given(name: str) -> dict:
    """The data exercise ``name`` gives this student (numbers they work with, the same every time).

    Parameters
    ----------
    name : str
        An exercise that gives data (a key of :data:`GIVEN`).

    Returns
    -------
    dict
        Name → value: arrays such as Θ (``"q"``, rad), Θ̇ (``"qd"``, rad/s) and Θ̈ (``"qdd"``, rad/s²) of shape
        (n,), or the numbers of a body (``"m"``, kg; ``"w"``, ``"l"``, ``"h"``, m), as the exercise says.

    Raises
    ------
    KeyError
        If no exercise of that name gives data.
    """
    if name not in GIVEN:
        raise KeyError(f"no exercise named {name!r} gives data (those that do: {', '.join(GIVEN)})")
    return GIVEN[name](rng_for(student(), name))


def symbols(*names: str):
    """Positive real sympy symbols for parameters (m, l, g, …) and real ones for angles and rates.

    The angles and rates are ``theta``, ``theta_dot``, ``theta_ddot``, ``theta1``, ``theta2``, ``d2`` and ``t``;
    every other name is positive. A formula a student writes in these symbols is what the checks compare.

    Parameters
    ----------
    *names : str
        The symbols' names.

    Returns
    -------
    sympy.Symbol or list of sympy.Symbol
        One symbol for one name, else a list in the order of ``names``.

    Examples
    --------
    >>> m, theta = symbols("m", "theta")
    >>> m.is_positive, theta.is_positive
    (True, None)
    """
    import sympy

    real = ("theta", "theta_dot", "theta_ddot", "theta1", "theta2", "d2", "t")
    made = [sympy.Symbol(n, real=True) if n in real else sympy.Symbol(n, positive=True) for n in names]
    return made[0] if len(made) == 1 else made


# ---------------------------------------------------------------------------------------- the answers

def _omega_dot_C():
    d = given("omega_dot_C")
    R = d["R_AB"]
    return d["Omega_B_dot"] + R @ d["Omega_C_dot_in_B"] + np.cross(d["Omega_B"], R @ d["Omega_C_in_B"])  # (6.15)


def _I_corner():
    m, w, l, h = symbols("m", "w", "l", "h")
    return inertia.parallel_axis(inertia.box(m, w, l, h), m, (w / 2, l / 2, h / 2))


def _v_dot_c1(ops: Operations = EXACT):
    d = given("v_dot_c1")
    return newton_euler_links(_robot("two_link"), d["q"], d["qd"], d["qdd"], ops).v_dot_c[0]


def _pendulum(kind: str):
    m, l, g, theta, theta_dot, theta_ddot = symbols("m", "l", "g", "theta", "theta_dot", "theta_ddot")
    import sympy

    return {"k": m * l**2 * theta_dot**2 / 2, "u": -m * g * l * sympy.cos(theta),
            "tau": m * l**2 * theta_ddot + m * g * l * sympy.sin(theta), "gravity": m * g * l * sympy.sin(theta)}[kind]


def _J_tool():
    import sympy

    l1, l2, theta2 = symbols("l1", "l2", "theta2")
    return sympy.Matrix([[l1 * sympy.sin(theta2), 0], [l1 * sympy.cos(theta2) + l2, l2]])


def _Mx_value():
    q = given("Mx_value")["q"]
    return cartesian_dynamics(_robot("two_link"), q, np.zeros(2), "tool", expressed_in="frame", rows=["x", "y"]).Mx


def _tau_with_friction():
    d = given("tau_with_friction")
    friction = Friction(viscous=d["viscous"], coulomb=d["coulomb"])
    return inverse_dynamics(_robot("two_link"), d["q"], d["qd"], d["qdd"]) + friction.torques(d["qd"])  # (6.114)


def _I_xy_corner():
    d = given("I_xy_corner")
    return d["m"] * d["w"] * d["l"] / 4  # the parallel-axis theorem with +: example 6.1's ᴬI_xy


def _Y_mcx2():
    d = given("Y_mcx2")
    arm = _robot("two_link")
    return regressor(arm, d["q"], d["qd"], d["qdd"])[:, parameter_names(arm).index("mcx_2")]


RP_PARAMETERS = ("m1", "m2", "l1", "Izz1", "Izz2", "g")


@lru_cache(maxsize=1)
def rp_arm_equations():
    """Example 6.5 by the library: τ₁, τ₂ of the RP arm in the parameters m1, m2, l1, Izz1, Izz2, g (the same
    symbols as :func:`symbols`), with the joint symbols (name → (q, qd, qdd)) they are written in, and Craig's B
    and C; derived once per process (every check of the three RP-arm exercises reads it), as tuples."""
    derived = derive(load_robot("rp_arm"), RP_PARAMETERS)
    ours = dict(zip(RP_PARAMETERS, symbols(*RP_PARAMETERS), strict=True))
    to_ours = {derived.parameters[name]: ours[name] for name in RP_PARAMETERS}
    joints = {name: (derived.q[j], derived.qd[j], derived.qdd[j]) for j, name in enumerate(("theta1", "d2"))}
    plain = {**to_ours, **{q: symbols(name) for name, (q, _, _) in joints.items()}}  # B and C in θ₁, d₂ as written

    def written(rows):
        return tuple(tuple(e.xreplace(plain) for e in row) for row in rows)

    return tuple(e.xreplace(to_ours) for e in derived.tau), joints, written(derived.B), written(derived.C)


def _euler(q, qd, qdd, dt):
    return q + qd * dt + 0.5 * qdd * dt**2, qd + qdd * dt  # (6.117), (6.116)


def _semi_implicit(q, qd, qdd, dt):
    qd_next = qd + qdd * dt
    return q + qd_next * dt, qd_next


def _forward_accelerations(q, qd, tau):
    return forward_dynamics(_robot("two_link"), q, qd, tau)  # (6.115), the student's own arm


@dataclass(frozen=True)
class Exercise:
    """How to check one exercise: ``kind`` is "term" (a robot function graded like the grader does),
    "links" (every quantity of both iterations, link by link, at the exercise's given state), "equations"
    (equations of motion derived by hand in θ(t), term by term: :mod:`~course_dynamics.teaching.derivations`),
    "function" (compared on random inputs with ``reference``), "value" or "formula"; ``hints`` in tiers, the
    method last (never the answer).

    Parameters
    ----------
    kind : str
        ``"term"``, ``"links"``, ``"equations"``, ``"function"``, ``"value"`` or ``"formula"``.
    answer : callable, optional
        The right answer, made when called (a value, a sympy expression or matrix, or the equations).
    robot : str, optional
        The course robot the exercise is on (the student's variant of it).
    term : str, optional
        For ``"term"``: the robot function graded, ``"tau"``, ``"M"``, ``"V"`` or ``"G"``.
    reference : callable, optional
        For ``"function"``: the right function, compared with the student's on random inputs.
    inputs : callable, optional
        For ``"function"``: a random generator (``numpy.random.Generator``) → one list of arguments.
    tolerance : float, optional
        The relative tolerance of a numeric comparison.
    variables : tuple of str, optional
        For ``"formula"``: the symbols (:func:`symbols`) a formula is compared in.
    constant_in : tuple of str, optional
        A formula may differ from the answer by anything that does not depend on these (a potential energy's
        constant).
    hints : tuple of str, optional
        The hints in tiers: which term or idea, then which equation, then the method step by step (for a function
        exercise, the equation it implements); never the answer a formula, value or term exercise asks for.
    mistakes : tuple of tuple, optional
        The slips students make, each (code, the reference with that slip, its words): an answer that matches
        one is told which.
    time_functions : tuple of str, optional
        A formula may be written in these as functions of t (θ(t) for ``theta``).
    slipped : callable, optional
        A value's answer made by the recursion with other operations (a slip, named if it fits).
    """

    kind: str
    answer: Callable | None = None
    robot: str = "two_link"
    term: str = ""
    reference: Callable | None = None
    inputs: Callable | None = None
    tolerance: float = 1e-6
    variables: tuple[str, ...] = ()
    constant_in: tuple[str, ...] = ()  # a formula may differ by anything that does not depend on these
    hints: tuple[str, ...] = ()
    mistakes: tuple[tuple[str, Callable, str], ...] = ()  # (code, the reference with that mistake, its words)
    time_functions: tuple[str, ...] = ()  # a formula may be written in these as functions of t (θ(t) for theta)
    # a value's answer made by the recursion with other operations (a slip, named if it fits)
    slipped: Callable | None = None


def _own(draw):
    """Inputs ``draw(links, i, rng)``: the student's spatial arm at a state of theirs (its
    :func:`~course_dynamics.teaching.propagation.chain_quantities`) and a link i that has a child."""
    def inputs(rng):
        model = _robot("spatial_arm")
        state = _state(rng, model.n, -2.0, 2.0)
        return draw(chain_quantities(model, state["q"], state["qd"], state["qdd"]), int(rng.integers(model.n - 1)), rng)

    return inputs


NEWTON_EULER_HINTS = (
    "τ collects gravity, the inertial forces and the moments of every link outboard of each joint",
    "the outward iteration (6.45)–(6.50) from the base (⁰v̇₀ = −g), then the inward iteration (6.51)–(6.53)",
    "ⁱ⁺¹ωᵢ₊₁ = ⁱ⁺¹ᵢR ⁱωᵢ + θ̇ᵢ₊₁Ẑ; ⁱ⁺¹ω̇ᵢ₊₁ = ⁱ⁺¹ᵢR ⁱω̇ᵢ + ⁱ⁺¹ᵢR ⁱωᵢ × θ̇ᵢ₊₁Ẑ + θ̈ᵢ₊₁Ẑ; "
    "ⁱ⁺¹v̇ᵢ₊₁ = ⁱ⁺¹ᵢR (ⁱω̇ᵢ × ⁱPᵢ₊₁ + ⁱωᵢ × (ⁱωᵢ × ⁱPᵢ₊₁) + ⁱv̇ᵢ); v̇_C likewise with P_C; F = m v̇_C; "
    "N = ᶜI ω̇ + ω × ᶜI ω; ⁱfᵢ = ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁ + ⁱFᵢ; ⁱnᵢ = ⁱNᵢ + ⁱᵢ₊₁R ⁱ⁺¹nᵢ₊₁ + ⁱP_Cᵢ × ⁱFᵢ + "
    "ⁱPᵢ₊₁ × ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁; τᵢ = ⁱnᵢᵀ Ẑ",
)

#: Every exercise, by the name a notebook's ``check("name")`` gives.
EXERCISES: dict[str, Exercise] = {
    "point_acceleration": Exercise(
        "function",
        reference=lambda v, wd, w, p: np.array(tuple(point_acceleration(*(Vec3.of(x) for x in (v, wd, w, p))))),
        inputs=_own(lambda L, i, rng: [L.v_dot[i], L.omega_dot[i], L.omega[i], L.p_com[i]]), hints=(
            "three parts: the frame's own acceleration, one from ω̇ and one from ω",
            "(6.12): a point fixed in a moving frame",
            "v̇ + ω̇ × P + ω × (ω × P)")),
    "omega_dot_C": Exercise("value", _omega_dot_C, hints=(
        "the angular acceleration of {B}, plus {C}'s own in {A}'s axes, plus a term from {B} turning {C}'s ω",
        "(6.15), differentiated from (6.14)",
        "ᴬΩ̇_C = ᴬΩ̇_B + ᴬ_BR ᴮΩ̇_C + ᴬΩ_B × ᴬ_BR ᴮΩ_C")),
    "I_corner": Exercise("formula", _I_corner, variables=("m", "w", "l", "h"), hints=(
        "start from the box about its centre of mass",
        "the box's tensor about its centre, then the parallel-axis theorem to the corner",
        "ᴬI = ᶜI + m (PᵀP 1 − P Pᵀ) with P = (w/2, l/2, h/2)")),
    "principal_moments": Exercise("value", lambda: np.linalg.eigvalsh(given("principal_moments")["I"]), hints=(
        "the principal moments are the moments about the principal axes, where every product of inertia vanishes",
        "they are the eigenvalues of the tensor (np.linalg.eigvalsh)", "return them smallest first")),
    "physical": Exercise("value", lambda: np.array([not inertia.physical_problems(t)
                                                    for t in given("physical")["tensors"]]), hints=(
        "a real body's tensor has three properties to check",
        "symmetry, its principal moments, and the triangle inequality",
        "symmetric, no negative principal moment, and I₁ + I₂ ≥ I₃ for its principal moments")),
    "tau_two_link": Exercise("term", term="tau", hints=NEWTON_EULER_HINTS),
    "tau_spatial_arm": Exercise("term", robot="spatial_arm", term="tau", hints=NEWTON_EULER_HINTS),
    "links_spatial_arm": Exercise("links", robot="spatial_arm", hints=NEWTON_EULER_HINTS),
    "v_dot_c1": Exercise("value", _v_dot_c1, slipped=_v_dot_c1, hints=(
        "the centre of mass accelerates with the origin of frame 1, plus its motion about that origin",
        "(6.47) gives ¹v̇₁ = ¹₀R ⁰v̇₀ with ⁰v̇₀ = −g; then (6.48)",
        "¹v̇_C₁ = ¹ω̇₁ × ¹P_C₁ + ¹ω₁ × (¹ω₁ × ¹P_C₁) + ¹v̇₁")),
    "M_two_link": Exercise("term", term="M", hints=(
        "column j of M is the torque of unit Θ̈ⱼ without gravity or velocity",
        "(6.60): M₁₁, M₁₂ = M₂₁, M₂₂ of the two-link arm",
        "τ with Θ̇ = 0, g = 0 and Θ̈ = e₁, then e₂, gives M's columns: masses times lengths squared, some with c₂")),
    "V_two_link": Exercise("term", term="V", hints=(
        "V has a Coriolis term in θ̇₁θ̇₂ and centrifugal terms in θ̇ⱼ²",
        "(6.61), and the factor 2 of the Coriolis term (6.63)",
        "τ(Θ, Θ̇, 0) − G: each term is m₂, l₁, l₂ and s₂ times two joint rates, θ̇₁θ̇₂ with Craig's factor 2")),
    "G_two_link": Exercise("term", term="G", hints=(
        "G holds each link up: the weight of every link outboard of the joint times its horizontal moment arm",
        "(6.62), with c₁ for link 1's direction and c₁₂ for link 2's",
        "∂u/∂Θ (6.73), each mass's height written with θ₁ and θ₁ + θ₂; joint 2 holds up link 2 only")),
    "k_pendulum": Exercise("formula", lambda: _pendulum("k"), variables=("m", "l", "g", "theta", "theta_dot"), hints=(
        "the kinetic energy of a point mass moving on a circle", "(6.69) for a point mass", "½ m v², v its speed")),
    "u_pendulum": Exercise("formula", lambda: _pendulum("u"), variables=("m", "l", "g", "theta", "theta_dot"),
                           constant_in=("theta",), hints=(
        "the height of the mass as a function of θ; θ = 0 hangs straight down",
        "(6.73): the potential energy −m gᵀ P_C, plus any constant",
        "P_C(θ) with θ = 0 straight down, g pointing down")),
    "tau_pendulum": Exercise("formula", lambda: _pendulum("tau"), time_functions=("theta",), mistakes=(
        ("gravity-sign", lambda: _pendulum("tau") - 2 * _pendulum("gravity"),
         "gravity with the wrong sign: with it, the pendulum would fall away from hanging (the notes print it so)"),
        ("time-derivative-missing", lambda: _pendulum("gravity"),
         "only −∂L/∂θ: d/dt ∂L/∂θ̇ is not zero, since θ̇ changes in time (write θ as a function of t)")),
                             variables=("m", "l", "g", "theta", "theta_dot", "theta_ddot"), hints=(
        "the Lagrangian L = k − u (6.75), differentiated", "(6.77): d/dt ∂L/∂θ̇ − ∂L/∂θ = τ",
        "d/dt of ∂L/∂θ̇ with θ(t); then check gravity's sign: hanging at rest needs no torque (the notes' is wrong)")),
    "lagrange_rp_arm": Exercise("equations", lambda: rp_arm_equations()[0], robot="rp_arm", hints=(
        "write k and u with θ₁ and d₂ as functions of t, then differentiate L = k − u with the chain rule",
        "(6.77) for each joint: d/dt ∂L/∂θ̇ᵢ − ∂L/∂θᵢ = τᵢ, as example 6.5 does",
        "k = ½(m₁l₁² + I_zz1 + I_zz2 + m₂d₂²)θ̇₁² + ½m₂ḋ₂², u = g(m₁l₁ + m₂d₂) sin θ₁; d/dt (m₂d₂²θ̇₁) = "
        "m₂d₂²θ̈₁ + 2m₂d₂ḋ₂θ̇₁")),
    "B_rp_arm": Exercise("formula", lambda: __import__("sympy").Matrix(rp_arm_equations()[2]),
                         variables=("m2", "d2"), mistakes=(
        ("coriolis-half", lambda: __import__("sympy").Matrix(rp_arm_equations()[2]) / 2,
         "half the Coriolis coefficient: d/dt (m₂d₂²θ̇₁) brings 2m₂d₂ḋ₂θ̇₁, and B holds all of it"),), hints=(
        "B multiplies the products θ̇ⱼθ̇ₖ (j < k): the RP arm has one, θ̇₁ḋ₂", "(6.63)–(6.64)",
        "collect example 6.5's τ terms in θ̇₁ḋ₂: one column, a row per joint, the whole coefficient (6.63)")),
    "C_rp_arm": Exercise("formula", lambda: __import__("sympy").Matrix(rp_arm_equations()[3]),
                         variables=("m2", "d2"), hints=(
        "C multiplies the squares θ̇ⱼ²", "(6.63) and (6.65)", "Cᵢⱼ: the coefficient of θ̇ⱼ² in example 6.5's τᵢ")),
    "J_tool": Exercise("formula", _J_tool, variables=("l1", "l2", "theta2"), hints=(
        "column j is the tip's velocity when only θ̇ⱼ = 1, written in frame {3}",
        "the velocity propagation of Craig (5.66), ending in frame {3}",
        "ω and v propagated to frame {3} ((5.45), (5.47)); read off θ̇₁'s and θ̇₂'s coefficients in ³v")),
    "Mx_value": Exercise("value", _Mx_value, hints=(
        "the mass the tip feels, in Cartesian directions", "(6.99): M_x from M and the Jacobian of frame {3}",
        "M_x = J⁻ᵀ M J⁻¹")),
    "friction_torque": Exercise(
        "function", reference=lambda qd, v, c: c * np.sign(qd) + v * qd,
        inputs=lambda rng: [rng.uniform(-2, 2, 2).round(2) * (rng.uniform(size=2) > 0.2),  # some at rest: sgn(0) = 0
                            given("tau_with_friction")["viscous"], given("tau_with_friction")["coulomb"]], hints=(
            "one part grows with speed, one opposes motion with a fixed size",
            "viscous and Coulomb friction together (Craig's (6.112))",
            "c sgn(θ̇) + v θ̇")),
    "tau_with_friction": Exercise("value", _tau_with_friction, hints=(
        "the rigid-body torque plus what the joints' friction needs",
        "friction added to (6.59), as the notes' section on friction says (Craig's (6.114))",
        "τ = M Θ̈ + V + G + F(Θ̇)")),
    "forward_accelerations": Exercise(
        "function", reference=_forward_accelerations,
        inputs=lambda rng: [rng.uniform(-np.pi, np.pi, 2), rng.uniform(-2, 2, 2), rng.uniform(-30, 30, 2)], hints=(
            "the equations of motion solved for the accelerations, on your own two-link arm",
            "(6.115) without friction: M(Θ) Θ̈ = τ − V(Θ, Θ̇) − G(Θ)",
            "M, V and G of my_robot(\"two_link\").model at (Θ, Θ̇), then solve the linear system for Θ̈")),
    "euler_step": Exercise("function", reference=_euler,
                           inputs=lambda rng: [*rng.standard_normal((3, 2)), float(rng.uniform(0.001, 0.05))],
                           hints=("one step of Taylor series in Δt", "(6.116) for Θ̇, (6.117) for Θ",
                                  "Θ̇ + Θ̈Δt and Θ + Θ̇Δt + ½Θ̈Δt², both with the old Θ̇ and Θ̈")),
    "semi_implicit_step": Exercise("function", reference=_semi_implicit,
                                   inputs=lambda rng: [*rng.standard_normal((3, 2)), float(rng.uniform(0.001, 0.05))],
                                   hints=(
        "the same two updates in the other order", "the new Θ̇ first, then Θ with the new Θ̇",
        "Θ̇' = Θ̇ + Θ̈Δt, Θ' = Θ + Θ̇'Δt")),
    "omega_dot_propagation": Exercise(
        "function", reference=omega_dot_next, inputs=_own(lambda L, i, rng: [
            L.R_up[i + 1].T, L.omega[i], L.omega_dot[i], float(L.qd[i + 1]), float(L.qdd[i + 1])]), hints=(
            "differentiate (6.45) in time: the rotation turns with link i, the joint axis with link i+1",
            "(6.15) for two frames, with the rotation of (5.45) carrying ⁱω̇ᵢ into frame i+1",
            "ⁱ⁺¹ω̇ᵢ₊₁ = ⁱ⁺¹ᵢR ⁱω̇ᵢ + ⁱ⁺¹ᵢR ⁱωᵢ × θ̇ᵢ₊₁ ⁱ⁺¹Ẑᵢ₊₁ + θ̈ᵢ₊₁ ⁱ⁺¹Ẑᵢ₊₁ (6.32)"),
        mistakes=(("angular-acceleration-in-cross",
                   lambda R, w, wd, qd, qdd: R @ wd + np.cross(R @ wd, qd * Z) + qdd * Z,
                   "ω̇ in the cross product where ω belongs: the notes' line 'from (5.45)' prints it that way"),
                  ("rotation-transposed", lambda R, w, wd, qd, qdd: omega_dot_next(R.T, w, wd, qd, qdd),
                   "the rotation used the wrong way: R is ⁱ⁺¹ᵢR, from frame i into frame i+1"),
                  ("cross-reversed", lambda R, w, wd, qd, qdd: omega_dot_next(R, w, wd, qd, qdd,
                                                                              lambda a, b: np.cross(b, a)),
                   "the cross product in the wrong order: ⁱ⁺¹ᵢR ⁱωᵢ × θ̇ᵢ₊₁Ẑ"))),
    "v_dot_propagation": Exercise(
        "function", reference=v_dot_next, inputs=_own(lambda L, i, rng: [
            L.R_up[i + 1].T, L.omega[i], L.omega_dot[i], L.v_dot[i], L.P_up[i + 1]]), hints=(
            "the origin of frame i+1 is a point fixed in link i",
            "(6.12) for that point, then rotated into frame i+1: (6.34)",
            "ⁱ⁺¹v̇ᵢ₊₁ = ⁱ⁺¹ᵢR (ⁱω̇ᵢ × ⁱPᵢ₊₁ + ⁱωᵢ × (ⁱωᵢ × ⁱPᵢ₊₁) + ⁱv̇ᵢ)"),
        mistakes=(("centripetal-missing", lambda R, w, wd, vd, P: v_dot_next(R, w, wd, vd, P, 0.0),
                   "the centripetal term ω × (ω × P) left out"),
                  ("rotation-transposed", lambda R, w, wd, vd, P: v_dot_next(R.T, w, wd, vd, P),
                   "the rotation used the wrong way: R is ⁱ⁺¹ᵢR"))),
    "v_dot_com": Exercise(
        "function", reference=lambda w, wd, vd, P_c: v_dot_next(np.eye(3), w, wd, vd, P_c),
        inputs=_own(lambda L, i, rng: [L.omega[i + 1], L.omega_dot[i + 1], L.v_dot[i + 1], L.p_com[i + 1]]), hints=(
            "the centre of mass is a point fixed in link i, and everything is written in frame i",
            "(6.12) with {A} = {B} = frame i: (6.36)", "ⁱv̇_Cᵢ = ⁱω̇ᵢ × ⁱP_Cᵢ + ⁱωᵢ × (ⁱωᵢ × ⁱP_Cᵢ) + ⁱv̇ᵢ"),
        mistakes=(("centripetal-missing", lambda w, wd, vd, P_c: v_dot_next(np.eye(3), w, wd, vd, P_c, 0.0),
                   "the centripetal term ω × (ω × P_C) left out"),
                  ("cross-reversed", lambda w, wd, vd, P_c: vd + np.cross(P_c, wd) + np.cross(w, np.cross(w, P_c)),
                   "P_C × ω̇ where ω̇ × P_C belongs (a × b = −b × a)"),
                  ("cross-reversed", lambda w, wd, vd, P_c: vd - np.cross(wd, P_c) - np.cross(w, np.cross(w, P_c)),
                   "both cross products in the wrong order (a × b = −b × a)"))),
    "inward_moment": Exercise(
        "function", reference=inward_moment, inputs=_own(lambda L, i, rng: [
            L.R_up[i + 1], L.N[i], L.n[i + 1], L.p_com[i], L.F[i], L.P_up[i + 1], L.f[i + 1]]), hints=(
            "the moments on link i about the origin of frame i: its own, its child's, and those of the forces",
            "(6.38)–(6.39) balanced for link i, written in frame i: (6.42)",
            "ⁱnᵢ = ⁱNᵢ + ⁱᵢ₊₁R ⁱ⁺¹nᵢ₊₁ + ⁱP_Cᵢ × ⁱFᵢ + ⁱPᵢ₊₁ × ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁"),
        mistakes=(("moment-arm-missing", lambda *a: inward_moment(*a, arm=0.0),
                   "the moment arm ⁱPᵢ₊₁ × ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁ of the child's force left out"),
                  ("rotation-transposed", lambda R, *a: inward_moment(R.T, *a),
                   "the rotation used the wrong way: R is ⁱᵢ₊₁R, from frame i+1 into frame i"),
                  ("rotation-missing", lambda R, N, n, P_c, F, P, f: N + R @ n + np.cross(P_c, F) + np.cross(P, f),
                   "the child's force taken in its own frame: ⁱ⁺¹fᵢ₊₁ must be rotated into frame i, ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁, "
                   "before its moment arm acts on it"),
                  ("cross-reversed", lambda R, N, n, P_c, F, P, f: N + R @ n + np.cross(F, P_c) + np.cross(R @ f, P),
                   "the moments of the forces in the wrong order: r × F, the arm first (a × b = −b × a)"))),
    "prismatic_joint": Exercise(
        "function", reference=prismatic, inputs=_own(lambda L, i, rng: [  # a slider in place of joint i + 1
            L.R_up[i + 1].T, L.omega[i], L.omega_dot[i], L.v_dot[i], L.P_up[i + 1], *rng.uniform(-2, 2, 2).round(2),
            L.f[i + 1]]), hints=(
            "a sliding joint adds a velocity ḋ along Ẑ in a turning frame: a Coriolis term, and no rotation",
            "(6.35) for ⁱ⁺¹v̇ᵢ₊₁ ((6.34) plus two terms from (6.10)), and (6.44) for the joint's force",
            "ⁱ⁺¹v̇ᵢ₊₁ = ⁱ⁺¹ᵢR(ⁱω̇ᵢ × ⁱPᵢ₊₁ + ⁱωᵢ × (ⁱωᵢ × ⁱPᵢ₊₁) + ⁱv̇ᵢ) + 2 ⁱ⁺¹ωᵢ₊₁ × ḋᵢ₊₁Ẑ + d̈ᵢ₊₁Ẑ with "
            "ⁱ⁺¹ωᵢ₊₁ = ⁱ⁺¹ᵢR ⁱωᵢ; τ = ⁱ⁺¹fᵢ₊₁ᵀ Ẑ"),
        mistakes=(("coriolis-half", lambda *a: prismatic(*a, coriolis=1.0),
                   "the Coriolis term 2ω × ḋẐ without its 2"),)),
    "moving_point": Exercise(
        "function", reference=moving_point, inputs=_own(lambda L, i, rng: [  # {A} the base, {B} link i
            L.R_base[i] @ L.v_dot[i], L.R_base[i], L.R_base[i] @ L.omega[i], L.R_base[i] @ L.omega_dot[i],
            *rng.uniform(-0.3, 0.3, (3, 3)).round(2)]), hints=(
            "a point that moves in a moving frame: five parts, one of them from both motions at once",
            "(6.10), differentiated from (6.7)–(6.8); the notes print one term too many",
            "ᴬV̇_Q = ᴬV̇_BORG + ᴬ_BR ᴮV̇_Q + 2 ᴬΩ_B × ᴬ_BR ᴮV_Q + ᴬΩ̇_B × ᴬ_BR ᴮQ + ᴬΩ_B × (ᴬΩ_B × ᴬ_BR ᴮQ)"),
        mistakes=(("coriolis-doubled", lambda *a: moving_point(*a, coriolis=3.0),
                   "(6.10) as the notes print it: the Coriolis term Ω × R V_Q counted once more beside 2 Ω × R V_Q"),
                  ("coriolis-half", lambda *a: moving_point(*a, coriolis=1.0),
                   "the Coriolis term without its 2: Ω × R V_Q comes once from differentiating R V_Q and once "
                   "from differentiating Ω × R Q"))),
    "I_xy_corner": Exercise("value", _I_xy_corner, hints=(
        "the box's own product of inertia about its centre is zero", "the parallel-axis theorem for products",
        "ᴬI_xy = ᶜI_xy + m x_c y_c (the notes print −)")),
    "inward_force": Exercise(
        "function", reference=lambda R, f_next, F: R @ f_next + F,
        inputs=_own(lambda L, i, rng: [L.R_up[i + 1], L.f[i + 1], L.F[i]]),
        hints=("link i carries its own inertial force and what link i+1 pushes back with",
               "(6.51), in frame i", "ⁱfᵢ = ⁱᵢ₊₁R ⁱ⁺¹fᵢ₊₁ + ⁱFᵢ")),
    "Y_mcx2": Exercise("value", _Y_mcx2, hints=(
        "τ is linear in m₂l₂: its column of the regressor is the torque per unit m₂l₂",
        "the terms of (6.60)–(6.62) that contain m₂l₂ once",
        "∂τ/∂(m₂l₂), reading (6.60)–(6.62) with m₂l₂ factored out")),
    "base_two_link": Exercise(
        "function", reference=lambda pi: base_parameters(_robot("two_link")).values(pi),
        inputs=lambda rng: [rng.standard_normal(20)], hints=(
            "some parameters never change τ, and some change it only together",
            "for τ, link 2's mass is a point mass of link 1 at joint 2, (l₁, 0, 0)",
            "what does that point mass add to link 1's first moment h₁ and to I_zz,₁?")),
}


__all__ = ["EXERCISES", "GIVEN", "Exercise", "given", "my_robot", "student", "symbols", "use_student"]

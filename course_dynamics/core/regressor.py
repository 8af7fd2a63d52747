"""The inertial-parameter regressor τ = Y(Θ, Θ̇, Θ̈) π, and the base parameters, from the one recursion.

Ten parameters per moving body i (frames as in :mod:`course_dynamics.core.model`), in
Pinocchio's order (``Inertia.toDynamicParameters``), so that our Y and π equal Pinocchio's
column for column once its joints are put in our order:

=====================================  ==========  ====================================================
name                                   Craig       meaning (unit)
=====================================  ==========  ====================================================
``m_i``                                mᵢ          mass of body i (kg)
``mcx_i``, ``mcy_i``, ``mcz_i``        mᵢ ⁱP_Cᵢ    first moment h = m c, c the centre of mass in frame i
                                                   (kg·m)
``Ixx_i``, ``Ixy_i``, ``Iyy_i``,       ⁱIᵢ         inertia tensor about the ORIGIN of frame i, axes of
``Ixz_i``, ``Iyz_i``, ``Izz_i``                    frame i (kg·m²)
=====================================  ==========  ====================================================

ⁱIᵢ = ᶜⁱIᵢ + m (cᵀc 1 − c cᵀ), the parallel-axis theorem (6.25). Its entries are the tensor's: ``Ixy_i`` is
entry (x, y), the URDF's ``ixy``, so Craig's product of inertia I_xy is the negative of ``Ixy_i``.

``Y`` has shape (n, 10 n) (N·m or N per unit of each parameter): row j is joint j, columns
are the bodies' blocks of ten in ``model.bodies`` order (body numbers from 1, as in Craig).

Why τ is linear in π: written about the origin of frame i rather than the centre of mass,
Newton's and Euler's equations for body i are f = m v̇ + ω̇ × h + ω × (ω × h) and
n = I_o ω̇ + ω × I_o ω + h × v̇ (ω, ω̇, v̇ as in :mod:`course_dynamics.core.newton_euler`).
The kinematics (ω, ω̇, v̇ of every frame) do not depend on any mass, and these loads are
linear in (m, h, I_o); the inward iteration (6.51)–(6.53) only rotates, shifts and adds
them, so every τⱼ is a linear combination of the parameters, with coefficients that
depend on the state alone.

How Y is computed: column k is ∂τ/∂π_k, the dual part of τ when the recursion
(``newton_euler.torque_entries``) runs on a model whose parameters
are Dual numbers π₀ + ε e_k, converted into the model's m, ⁱP_Cᵢ = h/m and
ᶜⁱIᵢ = I_o − m (cᵀc 1 − c cᵀ) by :func:`with_parameters`. One pass gives every column: the
dual parts are vectors of 10 n entries (with a trailing batch axis for N states). Exact to
rounding, no finite differences. Because τ is linear in π, Y does not depend on π₀; it is
seeded at a unit point mass at each frame origin (m = 1, h = 0, I_o = 0), a point every
body has, massless or not, where h/m needs no care.

Base parameters: the columns of Y are linearly dependent (a body's mass can only act
through the joints before it, so it is seen only in combinations with the proximal bodies'
parameters). :func:`base_parameters` stacks Y over seeded random states, scales every
column to unit length, drops columns below ``ZERO_COLUMN`` of the largest (parameters that
never act), takes the rank r from ``scipy.linalg.qr(pivoting=True)`` (diagonal entries of R
above ``RANK_TOLERANCE`` times the first), and keeps the first r independent columns in the
model's order (Gautier's unpivoted QR, same tolerance): so distal bodies are grouped into
proximal ones, π_b = Izz_1 + l₁² m_2 as in the textbooks, where the pivoted QR's choice by
column norm gives rational ones (two_link: m_2 + mcx_1/l₁). Then Y π = Y_b β π for
Y_b = Y[:, independent] and the r × 10 n matrix β.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from itertools import combinations_with_replacement

import numpy as np

from ..base.errors import ModelError
from .algebra import Dual
from .kinematics import joint_transforms
from .model import Model
from .newton_euler import torque_entries
from .parameters import parameter_values, symbolic_model
from .sampling import random_states
from .state import as_state, entries, layout_of

#: The names of a body's ten parameters, in Pinocchio's order (the module table).
PARAMETER_NAMES = ("m", "mcx", "mcy", "mcz", "Ixx", "Ixy", "Iyy", "Ixz", "Iyz", "Izz")
PARAMETER_SYMBOLS = ("m{i}", "m{i}c{i},x", "m{i}c{i},y", "m{i}c{i},z", "I{i},xx", "I{i},xy", "I{i},yy",
                     "I{i},xz", "I{i},yz", "I{i},zz")  # for display: I{i} is ⁱIᵢ, about the origin
#: Where entry (a, b) of I_o sits among a body's ten parameters (``TENSOR[a][b]``).
TENSOR = ((4, 5, 7), (5, 6, 8), (7, 8, 9))
SEED = (1.0,) + (0.0,) * 9  # π₀ of every body: a unit point mass at its frame origin
#: The number of random states stacked for the base parameters by default.
SAMPLES = 64
ZERO_COLUMN = 1e-12  # a column this small (relative to the largest) is a parameter that never acts
RANK_TOLERANCE = 1e-9  # on unit-length columns: |R_kk| is the sine of the angle to the columns before
FIT_TOLERANCE = 1e-8  # describe(): how exactly β must be a quadratic polynomial in the named lengths

SUBSCRIPTS = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")


def parameter_names(model: Model) -> list[str]:
    """The names of π's entries, ``m_1 … Izz_n`` (body numbers from 1).

    Parameters
    ----------
    model : Model
        The robot.

    Returns
    -------
    list of str
        10 n names, body by body in :data:`PARAMETER_NAMES` order.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> parameter_names(load_robot("pendulum"))
    ['m_1', 'mcx_1', 'mcy_1', 'mcz_1', 'Ixx_1', 'Ixy_1', 'Iyy_1', 'Ixz_1', 'Iyz_1', 'Izz_1']
    """
    return [f"{name}_{i}" for i in range(1, model.n_bodies + 1) for name in PARAMETER_NAMES]


def parameter_symbols(model: Model) -> list[str]:
    """Craig-like display symbols of π's entries: m₂, m₂c₂,x (a first moment), I₂,xx (²I₂ about the origin).

    Parameters
    ----------
    model : Model
        The robot.

    Returns
    -------
    list of str
        10 n symbols, in the order of :func:`parameter_names`.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> parameter_symbols(load_robot("two_link"))[10:14]
    ['m₂', 'm₂c₂,x', 'm₂c₂,y', 'm₂c₂,z']
    """
    numbers = [str(i).translate(SUBSCRIPTS) for i in range(1, model.n_bodies + 1)]
    return [symbol.format(i=number) for number in numbers for symbol in PARAMETER_SYMBOLS]


def _parallel_axis(mass, c) -> list:
    """m (cᵀc 1 − c cᵀ), entry by entry, for scalars of any kind (floats, sympy, Duals) (6.25)."""
    squared = c[0] * c[0] + c[1] * c[1] + c[2] * c[2]
    return [[mass * ((squared if a == b else 0) - c[a] * c[b]) for b in range(3)] for a in range(3)]


def _is_number(x) -> bool:
    return isinstance(x, (int, float, np.integer, np.floating))


def _body_parameters(body) -> list:
    m, c, I = body.mass_s, list(body.p_com_v), body.I_com_m.rows
    shift = _parallel_axis(m, c)
    I_o = [[I[a][b] + shift[a][b] for b in range(3)] for a in range(3)]
    return [m, m * c[0], m * c[1], m * c[2], I_o[0][0], I_o[0][1], I_o[1][1], I_o[0][2], I_o[1][2], I_o[2][2]]


def parameters(model: Model) -> np.ndarray:
    """π of the model, shape (10 n,): per body m, m c, I_o (module table); object dtype for symbolic models.

    Parameters
    ----------
    model : Model
        The robot.

    Returns
    -------
    numpy.ndarray, shape (10 n,)
        π: kg, kg·m and kg·m², in :func:`parameter_names` order.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> parameters(load_robot("two_link"))[10:20].tolist()   # m₂ = 1 kg at 0.4 m: h = 0.4, Izz = m l² = 0.16
    [1.0, 0.4, 0.0, 0.0, 0.0, 0.0, 0.16000000000000003, 0.0, 0.0, 0.16000000000000003]
    """
    values = [x for body in model.bodies for x in _body_parameters(body)]
    return np.array(values, dtype=float if all(_is_number(x) for x in values) else object)


def _reciprocal(m):
    return Dual(1.0 / m.a, -m.b / (m.a * m.a)) if isinstance(m, Dual) else 1 / m


def _body_from(body, number: int, p: list):
    m, h = p[0], p[1:4]
    I_o = [[p[k] for k in row] for row in TENSOR]
    if _is_number(m) and (m < 0 or (m == 0 and any(x != 0 for x in h))):
        raise ModelError(f"body {number} '{body.name}' (joint '{body.joint}'): mass {m:g} kg with first moment "
                         f"m c = ({', '.join(f'{x:g}' for x in h)}) kg m has no centre of mass; a mass must be > 0 "
                         "(or 0 with m c = 0, a massless body)")
    if _is_number(m) and m == 0:
        return replace(body, mass=0.0, I_com=I_o)  # massless: the centre of mass is never used, keep it
    c = [x * _reciprocal(m) for x in h]
    shift = _parallel_axis(m, c)
    return replace(body, mass=m, p_com=c, I_com=[[I_o[a][b] - shift[a][b] for b in range(3)] for a in range(3)])


def with_parameters(model: Model, pi) -> Model:
    """The same robot with inertial parameters π (shape (10 n,), module table): m, ⁱP_Cᵢ = h/m, ᶜⁱIᵢ by (6.25).

    Floats, sympy expressions or Dual numbers. A ModelError names the body whose mass is
    negative, or zero with a non-zero first moment (no centre of mass); a zero mass with
    h = 0 is a massless body and keeps its centre of mass. Nothing else is checked: an
    identified π need not be physical (I_com positive definite).

    Parameters
    ----------
    model : Model
        The robot.
    pi : array_like, shape (10 n,)
        π in :func:`parameter_names` order: kg, kg·m, kg·m².

    Returns
    -------
    Model
        The robot with those masses, centres of mass and inertias.

    Raises
    ------
    ModelError
        If ``pi`` is not of shape (10 n,), or a body's mass is negative, or zero with a non-zero first moment.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> pi = parameters(arm)
    >>> pi[10:12] = [2.0, 0.6]                       # m₂ = 2 kg, h = 0.6 kg m: the centre of mass at 0.3 m
    >>> heavier = with_parameters(arm, pi).bodies[1]
    >>> heavier.mass, heavier.p_com.tolist()
    (2.0, [0.3, 0.0, 0.0])
    >>> pi[10] = 0.0
    >>> with_parameters(arm, pi)
    Traceback (most recent call last):
    course_dynamics.base.errors.ModelError: body 2 'link2' (joint 'theta2'): mass 0 kg with first moment
    m c = (0.6, 0, 0) kg m has no centre of mass; a mass must be > 0 (or 0 with m c = 0, a massless body)
    """
    pi = np.asarray(pi)
    if pi.shape != (10 * model.n_bodies,):
        raise ModelError(f"robot '{model.name}' has {model.n_bodies} bodies, so π has {10 * model.n_bodies} entries, "
                         f"got shape {pi.shape}")
    values = pi.astype(float).tolist() if pi.dtype != object else list(pi)
    bodies = tuple(_body_from(body, i + 1, values[10 * i:10 * i + 10]) for i, body in enumerate(model.bodies))
    return replace(model, bodies=bodies)


def regressor(model: Model, q, qd, qdd) -> np.ndarray:
    """Y(Θ, Θ̇, Θ̈), shape (n, 10 n) or (N, n, 10 n): τ = Y π under ``model.gravity`` (module docstring).

    Parameters
    ----------
    model : Model
        The robot; Y does not depend on its inertial parameters, only on its geometry and gravity.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint), in ``model.joint_names`` order, as for
        :func:`~course_dynamics.core.newton_euler.inverse_dynamics` (numpy object arrays of sympy symbols give
        a symbolic Y).
    qd : array_like, shape (n,) or (N, n)
        Joint velocities Θ̇, rad/s (m/s).
    qdd : array_like, shape (n,) or (N, n)
        Joint accelerations Θ̈, rad/s² (m/s²).

    Returns
    -------
    numpy.ndarray, shape (n, 10 n) or (N, n, 10 n)
        Y; column k is ∂τ/∂π_k (N·m or N per unit of parameter k, named by :func:`parameter_names`).

    Raises
    ------
    StateError
        If a state is not numeric or not finite, its last axis is not the model's n joints, or the batches
        differ in length.

    Examples
    --------
    >>> from course_dynamics import load_robot, inverse_dynamics
    >>> arm = load_robot("pendulum")                 # θ = 0 hangs down: τ = m g l sin θ + m l² θ̈
    >>> Y = regressor(arm, [0.5], [0.0], [1.0])
    >>> dict(zip(parameter_names(arm), Y[0].round(4)))["mcz_1"]      # −g sin θ per unit of m c_z (c_z = −l)
    np.float64(-4.7032)
    >>> bool(np.allclose(Y @ parameters(arm), inverse_dynamics(arm, [0.5], [0.0], [1.0])))
    True
    """
    q, qd, qdd = as_state(model, q, "q"), as_state(model, qd, "qd"), as_state(model, qdd, "qdd")
    batch = layout_of(q, qd, qdd).batch
    count = 10 * model.n_bodies
    seeds = np.eye(count).reshape((count, count) + (1,) * len(batch))  # e_k, broadcasting over the batch
    rows = regressor_rows(model, joint_transforms(model, entries(q)), entries(qd), entries(qdd), seeds)
    Y = np.stack([np.broadcast_to(row, (count,) + batch) for row in rows])
    return np.moveaxis(Y, (0, 1), (-2, -1)).copy()


def regressor_rows(model: Model, X, theta_dot: list, theta_ddot: list, seeds) -> list:
    """Y's rows as the dual parts of τ: the recursion (``newton_euler.torque_entries``) on the model with
    parameters π₀ + ε e_k (module docstring), given transforms; the building block of :func:`regressor` and of
    the compiled regressor.

    Parameters
    ----------
    model : Model
        The robot.
    X : JointTransforms
        The joint transforms at Θ (:func:`~course_dynamics.core.kinematics.joint_transforms`).
    theta_dot, theta_ddot : list
        Θ̇ and Θ̈, one scalar per coordinate (float, (N,) array or traced value), rad/s, rad/s² (m/s, m/s²).
    seeds : sequence
        e_k for k < 10 n_bodies: anything that adds, negates and scales by the scalars (numpy rows; the tracer's
        sparse columns).

    Returns
    -------
    list
        Row j of Y, one per coordinate: the dual part of τⱼ (of the kind of ``seeds``), or 0.0 where τⱼ depends
        on no parameter.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.kinematics import joint_transforms
    >>> arm = load_robot("pendulum")
    >>> regressor_rows(arm, joint_transforms(arm, [0.5]), [0.0], [1.0], np.eye(10))[0].round(4)[:4]
    array([ 0.    , -8.6091,  0.    , -4.7032])
    """
    seeded = with_parameters(model, np.array([Dual(a, seeds[k]) for k, a in enumerate(SEED * model.n_bodies)],
                                             dtype=object))
    tau = torque_entries(seeded, X, theta_dot, theta_ddot, model.gravity_v)
    return [t.b if isinstance(t, Dual) else 0.0 for t in tau]


def _stacked(model: Model, samples: int, seed: int, held=None) -> np.ndarray:
    """Y over random states, (samples n, 10 n); coordinates ``held`` (index → value) stay at their values at rest
    and their rows are left out (their joints are fixed joints)."""
    q, qd, qdd = random_states(model, samples, seed)
    held = dict(held or {})
    for j, value in held.items():
        q[:, j], qd[:, j], qdd[:, j] = value, 0.0, 0.0
    rows = [j for j in range(model.n) if j not in held]
    return regressor(model, q, qd, qdd)[:, rows, :].reshape(-1, 10 * model.n_bodies)


def _grouping(W: np.ndarray, independent, acting) -> np.ndarray:
    """β (r, columns) with W π = W[:, independent] β π, solved on unit-length columns; |K| < RANK_TOLERANCE is 0."""
    scale = np.linalg.norm(W, axis=0)
    dependent = [k for k in acting if k not in independent]
    beta = np.zeros((len(independent), W.shape[1]))
    beta[np.arange(len(independent)), independent] = 1.0
    if dependent:
        unit = W[:, independent] / scale[independent]
        import scipy.linalg  # scipy's, as the QR before it: numpy's BLAS right after scipy's waits for its threads

        K = scipy.linalg.lstsq(unit, W[:, dependent] / scale[dependent])[0]
        K[np.abs(K) < RANK_TOLERANCE] = 0.0
        beta[:, dependent] = K * scale[dependent] / scale[independent][:, None]
    return beta


@dataclass(frozen=True)
class BaseParameters:
    """The identifiable combinations π_b = β π of a robot's parameters (:func:`base_parameters`).

    ``independent`` are the r columns of Y kept (Y_b = Y[..., independent]), ``beta`` is
    (r, 10 n), so that Y π = Y_b β π for every π.

    Parameters
    ----------
    names : tuple of str
        The names of π's entries (:func:`parameter_names`).
    independent : tuple of int
        The r columns of Y kept, in the model's order.
    beta : numpy.ndarray, shape (r, 10 n)
        β, with π_b = β π.
    model : Model
        The robot they were found for.
    samples : int, optional
        The number of random states stacked.
    seed : int, optional
        Their seed.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> base = base_parameters(load_robot("two_link"))
    >>> base.rank, [base.names[k] for k in base.independent]
    (6, ['mcx_1', 'mcy_1', 'Izz_1', 'mcx_2', 'mcy_2', 'Izz_2'])
    >>> print(base.describe())
    π_b1 = mcx_1 + 0.5 m_2
    π_b2 = mcy_1
    π_b3 = Izz_1 + 0.25 m_2
    π_b4 = mcx_2
    π_b5 = mcy_2
    π_b6 = Izz_2

    In the notes' symbols (Craig 6.7: point masses, so Izz about the centre of mass is 0):
    l₁ is found in the geometry, the rest in π.

    >>> print(base.describe(["m1", "m2", "l1", "lc1", "lc2"]))
    π_b1 = mcx_1 + l1·m_2 = l1·m2 + lc1·m1
    π_b2 = mcy_1 = 0
    π_b3 = Izz_1 + l1²·m_2 = l1²·m2 + lc1²·m1
    π_b4 = mcx_2 = lc2·m2
    π_b5 = mcy_2 = 0
    π_b6 = Izz_2 = lc2²·m2
    """

    names: tuple[str, ...]
    independent: tuple[int, ...]
    beta: np.ndarray
    model: Model = field(repr=False, compare=False)
    samples: int = SAMPLES
    seed: int = 0

    @property
    def rank(self) -> int:
        """r, the number of base parameters (the rank of the stacked Y)."""
        return len(self.independent)

    def values(self, pi) -> np.ndarray:
        """π_b = β π, shape (r,).

        Parameters
        ----------
        pi : array_like, shape (10 n,)
            π (:func:`parameters`).

        Returns
        -------
        numpy.ndarray, shape (r,)
            The base parameters' values, in the units of their independent columns' parameters.
        """
        return self.beta @ np.asarray(pi)

    def regressor(self, Y) -> np.ndarray:
        """Y_b: the independent columns of a regressor Y (..., n, 10 n).

        Parameters
        ----------
        Y : array_like, shape (n, 10 n) or (N, n, 10 n)
            A regressor (:func:`~course_dynamics.core.regressor.regressor`).

        Returns
        -------
        numpy.ndarray, shape (n, r) or (N, n, r)
            Y_b = Y[..., independent].
        """
        return np.asarray(Y)[..., list(self.independent)]

    def describe(self, symbols=(), digits: int = 4) -> str:
        """One line per base parameter, ``π_b1 = …``, coefficients to ``digits`` significant figures.

        With ``symbols`` (names of :mod:`course_dynamics.core.parameters`: m1, l1, lc2, Izz1, …),
        each line also gives the combination in those symbols: masses, centres of mass and
        inertias through π, and a named link length l<i> through β, found by fitting β (a
        polynomial of degree ≤ 2 in the lengths) over seeded lengths within ±50 %; if β is not
        such a polynomial to ``FIT_TOLERANCE``, its numbers are kept.

        Parameters
        ----------
        symbols : sequence of str, optional
            Parameter symbols of :func:`~course_dynamics.core.parameters.symbolic_model`; none by default.
        digits : int, optional
            Significant figures of the numeric coefficients.

        Returns
        -------
        str
            r lines, ``π_b1 = …`` to ``π_br = …``.

        Raises
        ------
        SymbolError
            If a symbol is no parameter of the robot.
        """
        if not symbols:
            lines = (f"π_b{j + 1} = {_combination(row, self.names, digits)}" for j, row in enumerate(self.beta))
            return "\n".join(lines)
        import sympy

        exact, _ = symbolic_model(self.model, symbols)
        pi = parameters(exact)
        beta = _symbolic_beta(self, exact, digits)
        lines = []
        for j in range(self.rank):
            theirs = sympy.expand(sum(beta[j][k] * pi[k] for k in range(len(pi))))
            lines.append(f"π_b{j + 1} = {_combination(beta[j], self.names, digits)} = {_pretty(theirs)}")
        return "\n".join(lines)


def _combination(row, names, digits: int) -> str:
    """Σ β_k name_k in the columns' order (the independent one first), numbers or sympy coefficients."""
    text = ""
    for coefficient, name in ((c, n) for c, n in zip(row, names) if c != 0):
        negative, factor = _term(coefficient, digits)
        sign = ("- " if negative else "") if not text else (" - " if negative else " + ")
        text += f"{sign}{factor}{name}"
    return text


def _term(coefficient, digits: int) -> tuple[bool, str]:
    """(negative, the factor's text) of a coefficient, a float or a sympy expression."""
    if _is_number(coefficient):
        size = abs(coefficient)
        return coefficient < 0, "" if np.isclose(size, 1.0, rtol=1e-12) else f"{size:.{digits}g} "
    negative = coefficient.could_extract_minus_sign()
    size = -coefficient if negative else coefficient
    return negative, "" if size == 1 else f"({_pretty(size)})·" if size.is_Add else f"{_pretty(size)}·"


def _pretty(expression) -> str:
    return str(expression).replace("**2", "²").replace("**3", "³").replace("*", "·")


def _number(value: float, digits: int):
    import sympy

    return sympy.Integer(round(value)) if abs(value - round(value)) < FIT_TOLERANCE else sympy.Float(value, digits)


def _symbolic_beta(base: BaseParameters, exact: Model, digits: int) -> list:
    """β with the named lengths of the geometry as symbols: a degree-2 polynomial fit over seeded lengths."""
    import sympy

    model = base.model
    lengths = sorted({s for body in exact.bodies for x in body.P for s in getattr(x, "free_symbols", ())}, key=str)
    monomials = [()] + [m for d in (1, 2) for m in combinations_with_replacement(range(len(lengths)), d)]
    nominal = np.array([parameter_values(model)[str(s)] for s in lengths])
    rng = np.random.default_rng(base.seed)
    points = nominal * rng.uniform(0.5, 1.5, (2 * len(monomials), len(lengths))) if lengths else np.zeros((1, 0))
    acting = [k for k in range(len(base.names)) if k in base.independent or base.beta[:, k].any()]
    betas = []
    for point in points:
        values = dict(zip(lengths, point))
        bodies = [replace(body, P=[float(sympy.sympify(x).subs(values)) for x in shaped.P]) if lengths else body
                  for body, shaped in zip(model.bodies, exact.bodies)]
        W = _stacked(replace(model, bodies=tuple(bodies)), base.samples, base.seed)
        betas.append(_grouping(W, list(base.independent), acting).ravel())
    A = np.array([[np.prod(point[list(m)]) for m in monomials] for point in points]).reshape(len(points), -1)
    B = np.array(betas)
    C = np.linalg.lstsq(A, B, rcond=None)[0]
    if lengths and np.abs(A @ C - B).max() > FIT_TOLERANCE * max(np.abs(B).max(), 1.0):
        lengths, monomials, C = [], [()], base.beta.reshape(1, -1)  # not a polynomial: keep the numbers
    terms = [sympy.Mul(*(lengths[i] for i in m)) for m in monomials]
    flat = [sum((_number(c, digits) * t for c, t in zip(column, terms) if abs(c) > FIT_TOLERANCE), sympy.Integer(0))
            for column in C.T]
    width = len(base.names)
    return [flat[j * width:(j + 1) * width] for j in range(base.rank)]


def base_parameters(model: Model, samples: int = SAMPLES, seed: int = 0, held=None) -> BaseParameters:
    """The base parameters: rank r, independent columns and β, from Y stacked over ``samples`` random states.

    States from :func:`~course_dynamics.core.sampling.random_states` (``seed``); method and
    tolerances in the module docstring. A ModelError if the pivoted and the ordered QR
    disagree about the rank (more samples may settle it).

    Parameters
    ----------
    model : Model
        The robot.
    samples : int, optional
        The number of random states stacked (:data:`SAMPLES`).
    seed : int, optional
        Their seed.
    held : mapping of int to float, optional
        Coordinates held at a value (rad or m) as by a fixed joint: they stay there, at rest, and their torques
        are not rows (a body moved by no other coordinate is then lumped into its parent's combinations).

    Returns
    -------
    BaseParameters
        The rank, the independent columns and β.

    Raises
    ------
    ModelError
        If the pivoted and the ordered QR disagree about the rank.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> base = base_parameters(load_robot("rp_arm"))
    >>> base.rank                                    # the slider's mass and first moment act on their own
    6
    >>> print(base.describe(["m1", "m2", "Izz1", "Izz2", "lc1"]))
    π_b1 = mcx_1 = lc1·m1
    π_b2 = mcy_1 = 0
    π_b3 = Izz_1 + Izz_2 = Izz1 + Izz2 + lc1²·m1
    π_b4 = m_2 = m2
    π_b5 = mcx_2 = 0
    π_b6 = mcy_2 = 0
    """
    W = _stacked(model, samples, seed, held)
    scale = np.linalg.norm(W, axis=0)
    acting = np.flatnonzero(scale > ZERO_COLUMN * scale.max())
    unit = W[:, acting] / scale[acting]
    import scipy.linalg  # here: scipy takes 0.17 s to import, and the evaluator imports this module for Y

    R = scipy.linalg.qr(unit, mode="r", pivoting=True)[0]
    rank = int(np.sum(np.abs(np.diag(R)) > RANK_TOLERANCE * abs(R[0, 0])))
    ordered = np.abs(np.diag(scipy.linalg.qr(unit, mode="r")[0]))
    independent = [int(k) for k, d in zip(acting, ordered) if d > RANK_TOLERANCE]
    if len(independent) != rank:
        raise ModelError(f"robot '{model.name}': the regressor's rank is {rank} by pivoted QR but {len(independent)} "
                         f"in the model's order at tolerance {RANK_TOLERANCE:g}; try more samples than {samples}")
    beta = _grouping(W, independent, list(acting))
    return BaseParameters(tuple(parameter_names(model)), tuple(independent), beta, model, samples, seed)


__all__ = ["BaseParameters", "PARAMETER_NAMES", "SAMPLES", "TENSOR", "base_parameters", "parameter_names",
           "parameter_symbols", "parameters", "regressor", "regressor_rows", "with_parameters"]

"""The immutable robot model, in Craig's quantities, one record per moving body.

Frames and notation (Craig ch. 6; frame i is the frame of moving body i, which
is the URDF child link of joint i, with any fixed-joint descendants merged in;
p is the parent body of i, which in a serial chain is Craig's i−1):

==================  =============================================================
name                meaning (shape, unit)
==================  =============================================================
``R0``              ᵖᵢR at Θ = 0: orientation of frame i in its parent (3, 3)
``P``               ᵖPᵢ at Θ = 0: origin of frame i in its parent (3,), m
``axis``            ⁱẐᵢ: unit joint axis in frame i (3,) (any direction, not only z)
``mass``            mᵢ, kg
``p_com``           ⁱP_Cᵢ: centre of mass in frame i (3,), m
``I_com``           ᶜⁱIᵢ: inertia tensor about the COM, axes parallel to frame i
                    (3, 3), kg·m², as a matrix (off-diagonal entries are the
                    URDF ``ixy``… values, i.e. Craig's −I_xy)
``parent``          index of the parent body, −1 for the fixed base
``parent_link``     the URDF parent link of joint i (may be merged into body ``parent``)
``lower, upper``    joint position limits (rad or m; ±inf where the URDF gives none)
``effort``          the joint's torque (N·m) or force (N) limit, inf where none is given
``velocity``        the joint's speed limit (rad/s or m/s), inf where none is given
``damping``         viscous friction coefficient from ``<dynamics damping>``
``friction``        Coulomb friction from ``<dynamics friction>`` (N·m or N)
``mimic``           the joint whose coordinate drives joint i (URDF ``<mimic joint>``), "" for none
``multiplier``      θᵢ = multiplier · θ_mimic + offset (URDF ``<mimic>``)
``offset``          the offset of that coupling (rad or m)
``S, b``            the coupling θ_bodies = S Θ + b, shape (n_bodies, n) and (n_bodies,)
``gravity``         g: gravitational acceleration in the base frame (3,), m/s²
==================  =============================================================

Joint motion: a revolute or continuous joint rotates frame i about ``axis`` by
θᵢ, so ᵖᵢR(θᵢ) = R0 · Rot(axis, θᵢ) and ᵖPᵢ = P; a prismatic joint slides
it along ``axis`` by dᵢ, so ᵖᵢR = R0 and ᵖPᵢ(dᵢ) = P + R0 · axis · dᵢ.

One gravity convention, stated once: the base accelerates upward, ⁰v̇₀ = −g
(Craig's trick), so that gravity loads every link through the recursion.

Mimic joints: Θ has one coordinate per independent joint (n of them); a body whose
joint mimics another moves with it. The coupling is linear, θ_bodies = S Θ + b, S
holding a 1 in each independent body's own column and the multiplier in a mimic
body's leader's column (chains of mimics composed), b the offsets. The recursions
run per body and this module is the one place that maps between the two, by the
chain rule with S constant:

    θ_bodies = S Θ + b,  θ̇_bodies = S Θ̇,  θ̈_bodies = S Θ̈     (:meth:`Model.body_entries`)
    τ = Sᵀ τ_bodies,  G = Sᵀ G_bodies,  V = Sᵀ V_bodies         (:meth:`Model.coordinate_entries`)
    M = Sᵀ M_bodies S,  C = Sᵀ C_bodies S                       (:meth:`Model.coordinate_matrix`)
    J = J_bodies S                                              (:meth:`Model.coordinate_entries` on columns)

Without mimic joints S is the identity and each map returns its argument.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from ..base.errors import ModelError
from .algebra import Mat3, Vec3
from .joints import KINDS

#: g at the Earth's surface in m/s², pointing down the base frame's z axis (the default of every model).
STANDARD_GRAVITY = (0.0, 0.0, -9.81)
JOINT_TYPES = tuple(KINDS)  # what each does: course_dynamics.core.joints
#: The least and the largest size of a mimic coupling's multiplier a in θ = a θ_leader + b, declared or composed
#: along a chain of mimics (a = 0, the joint held at b, is allowed too). No gear or linkage ratio is near 1e6, and
#: beyond it the mimic's share of M (a² times its inertia) and its limits mapped onto the leader, (limit − b)/a,
#: stop meaning anything (a = 1e308 gives limits of ±2e-308 and an M of inf).
MIMIC_MULTIPLIER_RANGE = (1e-6, 1e6)
#: The largest size of a mimic coupling's offset b, declared or composed, in rad or m (a double resolves an angle
#: of 1e6 rad to about 1e-10 rad, and no joint is offset by more than a few turns or metres).
MAX_MIMIC_OFFSET = 1e6


def _frozen_array(values, shape, what: str) -> np.ndarray:
    array = np.array(values, dtype=float if _is_numeric(values) else object)
    if array.shape != shape:
        raise ModelError(f"{what}: expected shape {shape}, got {array.shape}")
    array.setflags(write=False)
    return array


def _is_numeric(values) -> bool:
    if isinstance(values, np.ndarray) and values.dtype == object:
        return False  # symbolic entries stay symbolic, even numbers like sympy.Rational(1, 2)
    try:
        np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        return False
    return True


def _check_coupling(joint: str, what: str, a: float, b: float) -> None:
    """Refuse a coupling θ = a θ_leader + b outside ``MIMIC_MULTIPLIER_RANGE`` and ``MAX_MIMIC_OFFSET``."""
    smallest, largest = MIMIC_MULTIPLIER_RANGE
    if not (a == 0 or smallest <= abs(a) <= largest):
        raise ModelError(f"joint '{joint}': {what} gives a multiplier of {a:g}; a coupling needs 0 or "
                         f"{smallest:g} <= |multiplier| <= {largest:g}")
    if not abs(b) <= MAX_MIMIC_OFFSET:
        raise ModelError(f"joint '{joint}': {what} gives an offset of {b:g}; a coupling needs |offset| <= "
                         f"{MAX_MIMIC_OFFSET:g}")


@dataclass(frozen=True)
class Body:
    """One moving body: the link carried by joint i and everything fixed to it.

    Vectors and matrices are kept as read-only arrays (float, or object for sympy entries).

    Parameters
    ----------
    name : str
        The URDF child link of joint i.
    joint : str
        The joint's name: Θ's entry for this body.
    joint_type : str
        ``"revolute"``, ``"continuous"`` or ``"prismatic"``.
    parent : int
        The index of the parent body p, −1 for the fixed base.
    R0 : array_like, shape (3, 3)
        ᵖᵢR at Θ = 0: the orientation of frame i in its parent.
    P : array_like, shape (3,)
        ᵖPᵢ at Θ = 0: the origin of frame i in its parent, m.
    axis : array_like, shape (3,)
        ⁱẐᵢ, the unit joint axis in frame i.
    mass : float or sympy.Expr
        mᵢ, kg.
    p_com : array_like, shape (3,)
        ⁱP_Cᵢ, the centre of mass in frame i, m.
    I_com : array_like, shape (3, 3)
        ᶜⁱIᵢ, the inertia tensor about the centre of mass, axes parallel to frame i, kg·m².
    lower : float, optional
        The lower position limit, rad (m for a prismatic joint); −inf for none.
    upper : float, optional
        The upper position limit, rad (m); inf for none.
    effort : float, optional
        The torque limit, N·m (force, N); inf for none.
    velocity : float, optional
        The speed limit, rad/s (m/s); inf for none.
    damping : float, optional
        The viscous friction coefficient of ``<dynamics damping>``, N·m·s/rad (N·s/m).
    friction : float, optional
        The Coulomb friction of ``<dynamics friction>``, N·m (N).
    parent_link : str, optional
        The URDF parent link of the joint (which may be merged into body ``parent``).
    mimic : str, optional
        The joint this one mimics (URDF ``<mimic joint>``); "" (the default) for a joint with its own coordinate.
    multiplier : float, optional
        θᵢ = multiplier · θ_mimic + offset; 1 by default.
    offset : float, optional
        As ``multiplier``, rad (m for a prismatic joint); 0 by default.

    Raises
    ------
    ModelError
        If a vector or matrix has the wrong shape, ``joint_type`` is not one the dynamics takes, or a mimic's
        multiplier or offset is not finite or outside ``MIMIC_MULTIPLIER_RANGE`` or ``MAX_MIMIC_OFFSET``.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> body = load_robot("two_link").bodies[1]
    >>> body.name, body.joint, body.mass, body.p_com.tolist()
    ('link2', 'theta2', 1.0, [0.4, 0.0, 0.0])
    """

    name: str
    joint: str
    joint_type: str
    parent: int
    R0: np.ndarray
    P: np.ndarray
    axis: np.ndarray
    mass: object
    p_com: np.ndarray
    I_com: np.ndarray
    lower: float = -np.inf
    upper: float = np.inf
    effort: float = np.inf
    velocity: float = np.inf
    damping: float = 0.0
    friction: float = 0.0
    parent_link: str = ""
    mimic: str = ""
    multiplier: float = 1.0
    offset: float = 0.0

    def __post_init__(self):
        if not (np.isfinite(self.multiplier) and np.isfinite(self.offset)):
            raise ModelError(f"joint '{self.joint}': mimic multiplier {self.multiplier} and offset {self.offset} "
                             "must be finite")
        if self.mimic:
            _check_coupling(self.joint, "its <mimic>", self.multiplier, self.offset)
        for name, shape in (("R0", (3, 3)), ("P", (3,)), ("axis", (3,)), ("p_com", (3,)), ("I_com", (3, 3))):
            object.__setattr__(self, name, _frozen_array(getattr(self, name), shape, f"body '{self.name}' {name}"))
        if self.joint_type not in JOINT_TYPES:
            raise ModelError(f"joint '{self.joint}': type '{self.joint_type}' is not one of {', '.join(JOINT_TYPES)}")

    @property
    def is_prismatic(self) -> bool:
        """True for a prismatic joint (its coordinate is a length dᵢ, m), False for a revolute or continuous one."""
        return self.joint_type == "prismatic"

    # The recursion works on Vec3/Mat3 of plain scalars; build them once per body.
    @cached_property
    def R0_m(self) -> Mat3:
        return Mat3.of(self.R0)

    @cached_property
    def P_v(self) -> Vec3:
        return Vec3.of(self.P)

    @cached_property
    def axis_v(self) -> Vec3:
        return Vec3.of(self.axis)

    @cached_property
    def R0_axis_v(self) -> Vec3:
        return self.R0_m @ self.axis_v

    @cached_property
    def rotation_parts(self) -> tuple:
        """The constant parts (K₀, K_c, K_s) of ᵖᵢR(θ) = K₀ + cos θ K_c + sin θ K_s, as nested tuples.

        They are (R0 a aᵀ, R0 (1 − a aᵀ), R0 ``[a]ₓ``), a being the unit axis.
        """
        a = self.axis
        A = np.outer(a, a)
        K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]], dtype=a.dtype)
        eye = np.eye(3, dtype=int).astype(a.dtype)
        parts = (self.R0 @ A, self.R0 @ (eye - A), self.R0 @ K)
        return tuple(Mat3.of(part).rows for part in parts)

    @cached_property
    def p_com_v(self) -> Vec3:
        return Vec3.of(self.p_com)

    @cached_property
    def I_com_m(self) -> Mat3:
        return Mat3.of(self.I_com)

    @cached_property
    def mass_s(self):
        return float(self.mass) if isinstance(self.mass, (int, float, np.floating)) else self.mass


@dataclass(frozen=True)
class Frame:
    """A URDF link as a frame rigidly attached to a body: ᵇR_F and ᵇP_F in body ``body``'s frame.

    ``body`` is −1 for links fixed to the base. Every URDF link is a frame,
    whether it moves on its own joint or was merged into a body by a fixed joint.

    Parameters
    ----------
    name : str
        The URDF link.
    body : int
        The index of the body it is fixed to, −1 for the base.
    R : array_like, shape (3, 3)
        ᵇR_F, its orientation in the body's frame.
    P : array_like, shape (3,)
        ᵇP_F, its origin in the body's frame, m.

    Raises
    ------
    ModelError
        If ``R`` or ``P`` has the wrong shape.

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> tool = load_robot("two_link").frame("tool")   # Craig's {3}, fixed to body 1 (link 2)
    >>> tool.body, tool.P.tolist()
    (1, [0.4, 0.0, 0.0])
    """

    name: str
    body: int
    R: np.ndarray
    P: np.ndarray

    def __post_init__(self):
        object.__setattr__(self, "R", _frozen_array(self.R, (3, 3), f"frame '{self.name}' R"))
        object.__setattr__(self, "P", _frozen_array(self.P, (3,), f"frame '{self.name}' P"))


@dataclass(frozen=True)
class Model:
    """A fixed-base robot: moving bodies in topological order (parents first).

    ``joint_names[j]`` is the joint whose coordinate is Θ[j]; Θ has one entry
    per independent moving joint (rad for revolute and continuous, m for prismatic).
    A mimic joint's body moves with its leader's coordinate (module docstring):
    ``n`` counts coordinates, ``n_bodies`` bodies.

    Parameters
    ----------
    name : str
        The robot's name (the URDF's ``<robot name>``).
    bodies : sequence of Body
        The moving bodies, each after its parent.
    gravity : array_like, shape (3,), optional
        g in the base frame, m/s²; :data:`STANDARD_GRAVITY` by default.
    source : str, optional
        Where the model was read from (the URDF's path).
    base_link : str, optional
        The URDF's root link, the fixed base.
    frames : sequence of Frame, optional
        Every URDF link as a frame.

    Raises
    ------
    ModelError
        If a body's parent does not come before it, ``gravity`` is not of shape (3,), or a mimic joint names no
        moving joint of the robot, its mimics form a cycle or compose to a coupling outside
        ``MIMIC_MULTIPLIER_RANGE`` or ``MAX_MIMIC_OFFSET`` (naming the joint).

    Examples
    --------

    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> arm.n, arm.joint_names, arm.children, arm.gravity.tolist()
    (2, ('theta1', 'theta2'), ((1,), ()), [0.0, 0.0, -9.81])
    """

    name: str
    bodies: tuple[Body, ...]
    gravity: np.ndarray = field(default_factory=lambda: np.array(STANDARD_GRAVITY))
    source: str = ""
    base_link: str = ""
    frames: tuple[Frame, ...] = ()

    def __post_init__(self):
        object.__setattr__(self, "bodies", tuple(self.bodies))
        object.__setattr__(self, "frames", tuple(self.frames))
        object.__setattr__(self, "gravity", _frozen_array(self.gravity, (3,), f"robot '{self.name}' gravity"))
        for i, body in enumerate(self.bodies):
            if not -1 <= body.parent < i:
                raise ModelError(f"body '{body.name}': parent index {body.parent} does not come before it")
        if self.has_mimic:
            self.coupling  # noqa: B018 (resolved now: a missing leader or a cycle is refused when built)
            for j in np.flatnonzero(self.lower > self.upper):
                mimics = [f"'{body.joint}'" for body, (column, _, _) in zip(self.bodies, self.coupling)
                          if column == j and body.mimic and (np.isfinite(body.lower) or np.isfinite(body.upper))]
                raise ModelError(f"joint '{self.joint_names[j]}': its limits and those of joint "
                                 f"{', '.join(mimics)} that mimic{'s' if len(mimics) == 1 else ''} it leave no "
                                 f"position (lower {self.lower[j]:g} > upper {self.upper[j]:g})")

    @property
    def n(self) -> int:
        """Number of joint coordinates n, one per independent joint (a mimic joint has none of its own)."""
        return len(self.coordinates)

    @property
    def n_bodies(self) -> int:
        """Number of moving bodies, mimic joints' included."""
        return len(self.bodies)

    @property
    def joint_names(self) -> tuple[str, ...]:
        """The independent joints, in the order of Θ's entries."""
        return tuple(self.bodies[k].joint for k in self.coordinates)

    @property
    def coordinate_bodies(self) -> tuple[Body, ...]:
        """The body of each coordinate Θ[j] (its joint's type, limits and axis)."""
        return tuple(self.bodies[k] for k in self.coordinates)

    @cached_property
    def coordinates(self) -> tuple[int, ...]:
        """The index of the body of each coordinate Θ[j], every body whose joint mimics none."""
        return tuple(k for k, body in enumerate(self.bodies) if not body.mimic)

    @cached_property
    def coupling(self) -> tuple[tuple[int, float, float], ...]:
        """(j, a, b) for each body k, so that θₖ = a Θ[j] + b, chains of mimics composed (k's coordinate, 1 and
        0 for an independent body)."""
        by_joint = {body.joint: k for k, body in enumerate(self.bodies)}
        column = {k: j for j, k in enumerate(self.coordinates)}
        coupling = []
        for k, body in enumerate(self.bodies):
            a, b, seen = 1.0, 0.0, [body.joint]
            while self.bodies[k].mimic:
                leader = self.bodies[k].mimic
                if leader not in by_joint:
                    raise ModelError(f"joint '{self.bodies[k].joint}' mimics joint '{leader}', which is not a "
                                     f"moving joint of robot '{self.name}'")
                if leader in seen:
                    raise ModelError(f"joint '{body.joint}': its mimics form a cycle ({' -> '.join(seen + [leader])})")
                a, b = a * self.bodies[k].multiplier, a * self.bodies[k].offset + b  # θ = a (m θ_l + o) + b
                seen.append(leader)
                k = by_joint[leader]
                _check_coupling(body.joint, f"its chain of mimics ({' -> '.join(seen)})", a, b)
            coupling.append((column[k], a, b))
        return tuple(coupling)

    @cached_property
    def mimic_forms(self) -> tuple[tuple[str, str], ...]:
        """(joint, why) for each mimic joint of a form honoured here that Pinocchio 4.1's ``mimic=True`` cannot
        build: its leader later in the tree, a mimic of a mimic, or a continuous joint coupled to one that is
        not (configurations of different sizes, (cos θ, sin θ) against θ)."""
        by_joint = {body.joint: k for k, body in enumerate(self.bodies)}
        forms = []
        for k, body in enumerate(self.bodies):
            if not body.mimic:
                continue
            leader = self.bodies[by_joint[body.mimic]]
            if by_joint[body.mimic] > k:
                forms.append((body.joint, f"its leader '{leader.joint}' comes later in the tree"))
            elif leader.mimic:
                forms.append((body.joint, f"its leader '{leader.joint}' is itself a mimic"))
            elif (body.joint_type == "continuous") != (leader.joint_type == "continuous"):
                forms.append((body.joint, f"it is {body.joint_type} and its leader '{leader.joint}' "
                              f"{leader.joint_type}: configurations of different sizes"))
        return tuple(forms)

    @property
    def has_mimic(self) -> bool:
        """True when some body moves with another joint's coordinate."""
        return len(self.coordinates) != len(self.bodies)

    @cached_property
    def S(self) -> np.ndarray:
        """S, shape (n_bodies, n), with θ̇_bodies = S Θ̇ (module docstring)."""
        S = np.zeros((self.n_bodies, self.n))
        for k, (j, a, _) in enumerate(self.coupling):
            S[k, j] = a
        S.setflags(write=False)
        return S

    @cached_property
    def b(self) -> np.ndarray:
        """b, shape (n_bodies,), rad or m, with θ_bodies = S Θ + b (module docstring)."""
        b = np.array([offset for _, _, offset in self.coupling], dtype=float)
        b.setflags(write=False)
        return b

    def body_entries(self, theta: list, offset: bool = True) -> list:
        """θ_bodies = S Θ + b (``offset``) or S Θ̇ for rates: one scalar per body from one per coordinate.

        Parameters
        ----------
        theta : list
            One scalar per coordinate (float, (N,) array, sympy expression, dual or traced number).
        offset : bool, optional
            Add b (positions); False for velocities and accelerations.

        Returns
        -------
        list
            One scalar per body; ``theta`` itself for a robot without mimic joints.

        Examples
        --------
        >>> from course_dynamics import load_robot
        >>> load_robot("two_link").body_entries([0.1, 0.2])
        [0.1, 0.2]
        """
        if not self.has_mimic:
            return theta
        out = []
        for j, a, b in self.coupling:
            value = theta[j] if a == 1 else a * theta[j]
            out.append(value + b if offset and b != 0 else value)
        return out

    def coordinate_entries(self, values: list) -> list:
        """Sᵀ v: one scalar per coordinate from one per body (torques, Jacobian columns; anything a float scales).

        Parameters
        ----------
        values : list
            One value per body.

        Returns
        -------
        list
            One per coordinate, Σₖ Sₖⱼ vₖ; ``values`` itself for a robot without mimic joints.

        Examples
        --------
        >>> from course_dynamics import load_robot
        >>> load_robot("two_link").coordinate_entries([1.5, 2.5])
        [1.5, 2.5]
        """
        if not self.has_mimic:
            return values
        out = [None] * self.n
        for (j, a, _), value in zip(self.coupling, values):
            term = value if a == 1 else a * value
            out[j] = term if out[j] is None else out[j] + term
        return out

    def coordinate_matrix(self, matrix: list) -> list:
        """Sᵀ A S, nested (n, n), from a nested (n_bodies, n_bodies) A such as M or C of the bodies.

        Parameters
        ----------
        matrix : list of list
            A[k][l] over bodies.

        Returns
        -------
        list of list
            (Sᵀ A S)[i][j]; ``matrix`` itself for a robot without mimic joints.

        Examples
        --------
        >>> from course_dynamics import load_robot
        >>> load_robot("two_link").coordinate_matrix([[1.0, 2.0], [3.0, 4.0]])
        [[1.0, 2.0], [3.0, 4.0]]
        """
        if not self.has_mimic:
            return matrix
        columns = [self.coordinate_entries([row[c] for row in matrix]) for c in range(self.n_bodies)]  # (SᵀA)ᵀ
        rows = [self.coordinate_entries([columns[c][i] for c in range(self.n_bodies)]) for i in range(self.n)]
        return rows

    @cached_property
    def children(self) -> tuple[tuple[int, ...], ...]:
        """The indices of the bodies whose parent is body i, for each body i (``children[i]``)."""
        return tuple(tuple(j for j, b in enumerate(self.bodies) if b.parent == i) for i in range(self.n_bodies))

    def _mimic_ranges(self, name: str) -> list:
        """For each coordinate, the ranges of its leader's ``name`` limit and each mimic's mapped back (Θ units)."""
        ranges = [[] for _ in range(self.n)]
        for body, (j, a, b) in zip(self.bodies, self.coupling):
            if name == "position":
                lo, hi = body.lower, body.upper
                if a != 0 and (np.isfinite(lo) or np.isfinite(hi)):
                    ends = sorted(((lo - b) / a, (hi - b) / a))
                    ranges[j].append(ends)
            elif a != 0:
                ranges[j].append(body.velocity / abs(a))
        return ranges

    @cached_property
    def lower(self) -> np.ndarray:
        """Lower position limits, shape (n,), rad or m; −inf where the URDF gives none.

        A coordinate with mimics gets the interval where every joint it drives is within its limits.
        """
        return np.array([max([lo for lo, _ in r], default=-np.inf) for r in self._mimic_ranges("position")])

    @cached_property
    def upper(self) -> np.ndarray:
        """Upper position limits, shape (n,), rad or m; inf where the URDF gives none (as :attr:`lower`)."""
        return np.array([min([hi for _, hi in r], default=np.inf) for r in self._mimic_ranges("position")])

    @cached_property
    def effort(self) -> np.ndarray:
        """Torque (N·m) or force (N) limits, inf where the URDF gives none; the independent joint's own (its
        actuator drives the mimics too)."""
        return np.array([b.effort for b in self.coordinate_bodies], dtype=float)

    @cached_property
    def velocity(self) -> np.ndarray:
        """Speed limits (rad/s or m/s), inf where the URDF gives none; a coordinate with mimics gets the
        smallest of its own and each mimic's divided by the multiplier's size."""
        return np.array([min(r, default=np.inf) for r in self._mimic_ranges("velocity")], dtype=float)

    @property
    def frame_names(self) -> tuple[str, ...]:
        """The names of ``frames``, every URDF link."""
        return tuple(f.name for f in self.frames)

    def frame(self, name: str) -> Frame:
        """The frame of URDF link ``name``; ModelError naming the known frames if absent.

        Parameters
        ----------
        name : str
            A URDF link.

        Returns
        -------
        Frame
            The link's frame.

        Raises
        ------
        ModelError
            If the robot has no such link (the message lists those it has).

        Examples
        --------
        >>> from course_dynamics import load_robot
        >>> load_robot("two_link").frame("link2").body
        1
        """
        for frame in self.frames:
            if frame.name == name:
                return frame
        raise ModelError(f"robot '{self.name}' has no link or frame '{name}' (frames: {', '.join(self.frame_names)})")

    @cached_property
    def gravity_v(self) -> Vec3:
        """g in m/s², base frame, as a Vec3; the one place the algorithms read gravity from.

        It enters the recursion once, as the base acceleration ⁰v̇₀ = −g; :meth:`with_gravity` is the one
        way to change it.
        """
        return Vec3.of(self.gravity)

    def with_gravity(self, gravity) -> "Model":
        """The same robot under another gravity vector g (base frame, m/s²).

        Parameters
        ----------
        gravity : array_like, shape (3,)
            g in the base frame, m/s².

        Returns
        -------
        Model
            A copy of the model with that gravity.

        Raises
        ------
        ModelError
            If ``gravity`` is not of shape (3,).

        Examples
        --------
        >>> from course_dynamics import load_robot
        >>> load_robot("pendulum").with_gravity([0.0, 0.0, -1.62]).gravity.tolist()
        [0.0, 0.0, -1.62]
        """
        return replace(self, gravity=np.asarray(gravity, dtype=float))


__all__ = ["Body", "Frame", "MAX_MIMIC_OFFSET", "MIMIC_MULTIPLIER_RANGE", "Model", "STANDARD_GRAVITY"]

"""Tracing: the library's own recursions run once on traced scalars, recorded as straight-line programs.

Every +, −, ×, ÷, cos and sin the recursions do on a :class:`Traced` scalar is
recorded as one node of a :class:`Tape`; identical operations are recorded once
(common-subexpression elimination by hash-consing) and operations on constants
are done on the spot (0·x, 1·x, the model's numbers). No second copy of any
algorithm exists here: :func:`trace_programs` calls the recursions themselves.
"""
from __future__ import annotations

from dataclasses import dataclass

from ...base.errors import CourseDynamicsError
from .. import coriolis, crba
from ..kinematics import joint_transforms
from ..model import Model
from ..newton_euler import torque_entries
from ..regressor import regressor_rows

# Operations of all five programs together. Panda takes 19 000, a 20-joint chain 74 000 (2 s to compile, 5 MB of
# source); a 30-joint chain would take 163 000 (7 s) and a 60-joint one several GB of memory.
#: The most operations the five programs of one robot may take together (a chain of about 20 joints).
MAX_OPERATIONS = 80_000
#: The most operations of the regressor's program, which is traced on its own (UR5 takes 1 800, Panda 5 400); a
#: robot whose regressor is larger keeps its other programs, and its regressor runs interpreted.
MAX_REGRESSOR_OPERATIONS = 40_000


class ProgramTooLargeError(CourseDynamicsError):
    """A robot whose compiled programs would take more than :data:`MAX_OPERATIONS` operations.

    The evaluator answers it by running the interpreted recursions.

    Parameters
    ----------
    what : str, optional
        The robot, as the message names it (``robot 'chain' (60 joints)``).
    remedy : str, optional
        The rest of the message after the limit: what to do instead.

    Examples
    --------
    >>> print(ProgramTooLargeError("robot 'chain' (60 joints)"))
    robot 'chain' (60 joints) is too large to compile: its programs would take more than 80000 operations; use the
    interpreted recursions (--no-compile, compiled=False)
    """

    def __init__(self, what: str = "", remedy: str = "; use the interpreted recursions (--no-compile, compiled=False)"):
        self.what = what
        super().__init__(f"{what} is too large to compile: its programs would take more than {MAX_OPERATIONS} "
                         f"operations{remedy}")



class Tape:
    """The program being recorded: nodes (op, argument, argument), each recorded once.

    An argument is ``("t", index)`` for a recorded node or ``("c", value)`` for a constant.

    Parameters
    ----------
    limit : int, optional
        The most nodes the tape may hold.

    Raises
    ------
    ProgramTooLargeError
        From :meth:`~course_dynamics.core.compiled.tracing.Tape.record`, once the tape would hold more than
        ``limit`` nodes.

    Examples
    --------
    >>> tape = Tape()
    >>> x = tape.input("q0")
    >>> y = 2.0 * x + x * 2.0   # x · 2 is recorded once
    >>> tape.nodes
    [('input', 'q0'), ('mul', ('c', 2.0), ('t', 0)), ('add', ('t', 1), ('t', 1))]
    """

    def __init__(self, limit: int = MAX_OPERATIONS):
        self.nodes: list[tuple] = []
        self.index: dict[tuple, int] = {}
        self.limit = limit

    def record(self, op: str, *arguments) -> "Traced":
        """The traced value of one operation, recorded unless the same one was recorded before.

        Parameters
        ----------
        op : str
            The operation: ``input``, ``add``, ``sub``, ``mul``, ``div``, ``neg``, ``cos`` or ``sin``.
        *arguments : tuple
            Its arguments, ``("t", index)`` or ``("c", value)`` (an input's name for ``input``).

        Returns
        -------
        Traced
            The value the operation computes.

        Raises
        ------
        ProgramTooLargeError
            If the tape already holds ``limit`` nodes.
        """
        key = (op, *arguments)
        i = self.index.get(key)
        if i is None:
            i = len(self.nodes)
            if i >= self.limit:
                raise ProgramTooLargeError()
            self.nodes.append(key)
            self.index[key] = i
        return Traced(self, i)

    def input(self, name: str) -> "Traced":
        """A named input of the program (``q0``, ``qd1``, …).

        Parameters
        ----------
        name : str
            The input's name in the generated code.

        Returns
        -------
        Traced
            The input as a traced value.

        Raises
        ------
        ProgramTooLargeError
            If the tape is full.
        """
        return self.record("input", name)


def _ref(x):
    """A node argument: ("t", index) for a traced value, ("c", float) for a constant."""
    return ("t", x.i) if isinstance(x, Traced) else ("c", float(x))


class Traced:
    """A scalar that records the arithmetic done on it (see the module docstring).

    It takes part in ``+``, ``-``, ``*``, ``/`` and unary ``-`` with other traced values and with numbers; a
    result known without arithmetic (``x * 1``, ``x - x``, ``0 * x``) is given at once and nothing is recorded.

    Parameters
    ----------
    tape : Tape
        The tape it is recorded on.
    i : int
        Its node's index on the tape.

    Examples
    --------
    >>> x = Tape().input("q0")
    >>> x * 1 is x, x - x, 0 * x   # done on the spot: nothing recorded
    (True, 0.0, 0.0)
    """

    __slots__ = ("tape", "i")
    __array_ufunc__ = None

    def __init__(self, tape: Tape, i: int):
        self.tape, self.i = tape, i

    def _binary(self, op, other, commutative):
        a, b = _ref(self), _ref(other)
        if commutative and b < a:
            a, b = b, a
        return self.tape.record(op, a, b)

    def __add__(self, other):
        if isinstance(other, Traced):
            return self._binary("add", other, True)
        if not isinstance(other, (int, float)):
            return NotImplemented
        return self if other == 0 else self._binary("add", other, True)

    __radd__ = __add__

    def __sub__(self, other):
        if isinstance(other, Traced):
            return 0.0 if other.i == self.i else self._binary("sub", other, False)
        if not isinstance(other, (int, float)):
            return NotImplemented
        return self if other == 0 else self._binary("sub", other, False)

    def __rsub__(self, other):
        if not isinstance(other, (int, float)):
            return NotImplemented
        return -self if other == 0 else self.tape.record("sub", ("c", float(other)), _ref(self))

    def __neg__(self):
        op, *arguments = self.tape.nodes[self.i]
        if op == "neg":
            return Traced(self.tape, arguments[0][1])
        return self.tape.record("neg", _ref(self))

    def __mul__(self, other):
        if isinstance(other, Traced):
            return self._binary("mul", other, True)
        if not isinstance(other, (int, float)):
            return NotImplemented
        if other == 0:
            return 0.0
        if other == 1:
            return self
        return -self if other == -1 else self._binary("mul", other, True)

    __rmul__ = __mul__

    def __truediv__(self, other):
        if isinstance(other, Traced):
            return self._binary("div", other, False)
        if not isinstance(other, (int, float)):
            return NotImplemented
        return self if other == 1 else self._binary("div", other, False)

    def __rtruediv__(self, other):
        if not isinstance(other, (int, float)):
            return NotImplemented
        return 0.0 if other == 0 else self.tape.record("div", ("c", float(other)), _ref(self))

    def __eq__(self, other):  # a traced value is never a known number
        return isinstance(other, Traced) and other.i == self.i

    __hash__ = None

    def cos_sin(self):
        """cos and sin of this value, each recorded once.

        Returns
        -------
        tuple of Traced
            (cos x, sin x).
        """
        return self.tape.record("cos", _ref(self)), self.tape.record("sin", _ref(self))


class Columns:
    """A sparse vector of scalars by column, ``{k: value}``: the dual part of a
    :class:`~course_dynamics.core.algebra.Dual` that carries one derivative per inertial parameter, where most are
    zero (the regressor's seeds e_k).

    It adds and subtracts with another, negates, and scales by a scalar (a number or a :class:`Traced`); a
    column that is not there is zero and costs nothing.

    Parameters
    ----------
    entries : dict of int to scalar
        The columns that are not zero.

    Examples
    --------
    >>> x = Tape().input("q0")
    >>> (Columns({0: 1.0}) * x + Columns({2: 1.0})).entries[2]
    1.0
    """

    __slots__ = ("entries",)
    __array_ufunc__ = None

    def __init__(self, entries: dict):
        self.entries = entries

    def __add__(self, other):
        if isinstance(other, (int, float)) and other == 0:
            return self
        if not isinstance(other, Columns):
            return NotImplemented
        entries = dict(self.entries)
        for k, v in other.entries.items():
            entries[k] = entries[k] + v if k in entries else v
        return Columns(entries)

    __radd__ = __add__

    def __neg__(self):
        return Columns({k: -v for k, v in self.entries.items()})

    def __sub__(self, other):
        return self + (-other)

    def __rsub__(self, other):
        return (-self) + other

    def __mul__(self, scale):
        if isinstance(scale, Columns):
            return NotImplemented
        if isinstance(scale, (int, float)) and scale == 0:
            return Columns({})
        return Columns({k: v * scale for k, v in self.entries.items()})

    __rmul__ = __mul__

    def __truediv__(self, scale):
        return Columns({k: v / scale for k, v in self.entries.items()})


@dataclass
class Program:
    """A straight-line program: named inputs, nodes, and the outputs (node references or constants).

    Parameters
    ----------
    name : str
        The program: ``tau``, ``mass_matrix``, ``bias``, ``coriolis``, ``forward_dynamics`` or ``regressor``.
    inputs : list of str
        Its arguments, each a vector of n values: ``q``, ``qd``, ``qdd`` or ``tau``.
    nodes : list of list
        Its operations in order, ``[op, argument, …]``, each argument ``["t", index]`` or ``["c", value]``
        (``["input", "q0"]`` for an input).
    outputs : list of list
        What it returns, in order, each ``["t", index]`` or ``["c", value]``.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> program = trace_programs(load_robot("pendulum"))["mass_matrix"]
    >>> program.inputs, len(program.nodes), program.outputs   # M = m l² (cos² θ + sin² θ): node 7
    (['q'], 8, [['t', 7]])
    """

    name: str
    inputs: list[str]
    nodes: list[list]
    outputs: list

    def as_data(self) -> dict:
        """The program as plain data (JSON can hold it).

        Returns
        -------
        dict
            ``name``, ``inputs``, ``nodes`` and ``outputs``, as the fields.
        """
        return {"name": self.name, "inputs": self.inputs, "nodes": self.nodes, "outputs": self.outputs}


def recorded_program(name: str, tape: Tape, input_names: list[str], outputs: list) -> Program:
    """The program that computes ``outputs`` from a tape: only the nodes they need, renumbered in order.

    Parameters
    ----------
    name : str
        The program's name.
    tape : Tape
        What was recorded.
    input_names : list of str
        Its inputs' vectors, in the order its function takes them.
    outputs : list
        What it returns: traced values or numbers.

    Returns
    -------
    Program
        The program.

    Examples
    --------
    >>> t = Tape()
    >>> x, y = t.input("q0"), t.input("q1")
    >>> _ = x * y
    >>> recorded_program("twice", t, ["q"], [x + x]).nodes         # x · y is not needed
    [['input', 'q0'], ['add', ['t', 0], ['t', 0]]]
    """
    needed, stack = set(), [o.i for o in outputs if isinstance(o, Traced)]
    while stack:
        i = stack.pop()
        if i not in needed:
            needed.add(i)
            stack += [a[1] for a in tape.nodes[i][1:] if isinstance(a, tuple) and a[0] == "t"]
    order = sorted(needed)
    number = {old: new for new, old in enumerate(order)}
    nodes = []
    for i in order:
        op, *arguments = tape.nodes[i]
        nodes.append([op] + [a if op == "input" else ([a[0], number[a[1]]] if a[0] == "t" else list(a))
                             for a in arguments])
    return Program(name, input_names, nodes,
                   [["t", number[o.i]] if isinstance(o, Traced) else ["c", float(o)] for o in outputs])


def _inputs(tape: Tape, prefix: str, n: int) -> list:
    return [tape.input(f"{prefix}{j}") for j in range(n)]


def trace_programs(model: Model) -> dict[str, Program]:
    """Run the library's recursions on traced scalars and keep what they computed (module docstring).

    Raises :class:`ProgramTooLargeError` as soon as the programs together pass :data:`MAX_OPERATIONS`.

    Parameters
    ----------
    model : Model
        The robot; its gravity is built into the programs.

    Returns
    -------
    dict of str to Program
        The programs by name: ``tau`` τ(Θ, Θ̇, Θ̈), ``mass_matrix`` (the upper triangle of M(Θ), row by row),
        ``bias`` V(Θ, Θ̇) + G(Θ), ``coriolis`` C(Θ, Θ̇) row by row, ``forward_dynamics`` (Θ̈ and the n pivots
        of the LDLᵀ factorization of M), and ``regressor`` Y(Θ, Θ̇, Θ̈) row by row (n × 10 n_bodies entries;
        left out where it would pass :data:`MAX_REGRESSOR_OPERATIONS`).

    Raises
    ------
    ProgramTooLargeError
        If the programs together would take more than :data:`MAX_OPERATIONS` operations.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> sorted(trace_programs(load_robot("two_link")))
    ['bias', 'coriolis', 'forward_dynamics', 'mass_matrix', 'regressor', 'tau']
    """
    n, g = model.n, model.gravity_v
    programs, tapes = {}, []

    def tape() -> Tape:
        tapes.append(Tape(MAX_OPERATIONS - sum(len(t.nodes) for t in tapes)))
        return tapes[-1]

    try:
        t = tape()
        q, qd, qdd = _inputs(t, "q", n), _inputs(t, "qd", n), _inputs(t, "qdd", n)
        tau = torque_entries(model, joint_transforms(model, q), qd, qdd, g)
        programs["tau"] = recorded_program("tau", t, ["q", "qd", "qdd"], tau)

        t = tape()
        q = _inputs(t, "q", n)
        M = crba.mass_matrix_entries(model, q)
        upper = [M[i][j] for i in range(n) for j in range(i, n)]
        programs["mass_matrix"] = recorded_program("mass_matrix", t, ["q"], upper)

        t = tape()
        q, qd = _inputs(t, "q", n), _inputs(t, "qd", n)
        bias = torque_entries(model, joint_transforms(model, q), qd, [0] * n, g)
        programs["bias"] = recorded_program("bias", t, ["q", "qd"], bias)

        t = tape()
        q, qd = _inputs(t, "q", n), _inputs(t, "qd", n)
        C = coriolis.coriolis_matrix_entries(model, q, qd)
        programs["coriolis"] = recorded_program("coriolis", t, ["q", "qd"],
                                                [C[i][j] for i in range(n) for j in range(n)])

        t = tape()
        q, qd, tau = _inputs(t, "q", n), _inputs(t, "qd", n), _inputs(t, "tau", n)
        M = crba.mass_matrix_entries(model, q)
        bias = torque_entries(model, joint_transforms(model, q), qd, [0] * n, g)
        qdd, pivots = _ldl_solve(M, [t_ - b for t_, b in zip(tau, bias)])  # (6.115)
        programs["forward_dynamics"] = recorded_program("forward_dynamics", t, ["q", "qd", "tau"], qdd + pivots)
    except ProgramTooLargeError:
        raise ProgramTooLargeError(f"robot {model.name!r} ({n} joints)") from None
    try:  # on a tape of its own: a regressor too large to compile leaves the other programs compiled
        t = Tape(MAX_REGRESSOR_OPERATIONS)
        q, qd, qdd = _inputs(t, "q", n), _inputs(t, "qd", n), _inputs(t, "qdd", n)
        count = 10 * model.n_bodies
        rows = regressor_rows(model, joint_transforms(model, q), qd, qdd, [Columns({k: 1.0}) for k in range(count)])
        entries = [row.entries if isinstance(row, Columns) else {} for row in rows]
        programs["regressor"] = recorded_program("regressor", t, ["q", "qd", "qdd"],
                                         [row.get(k, 0.0) for row in entries for k in range(count)])
    except ProgramTooLargeError:
        pass
    return programs


def _ldl_solve(M: list, rhs: list) -> tuple[list, list]:
    """x = M⁻¹ rhs by M = L D Lᵀ (L unit lower triangular), unrolled; returns x and the pivots D."""
    n = len(rhs)
    L = [[0] * n for _ in range(n)]
    D = [0] * n
    for j in range(n):
        D[j] = M[j][j] - sum((L[j][k] * L[j][k] * D[k] for k in range(j)), 0)
        for i in range(j + 1, n):
            L[i][j] = (M[i][j] - sum((L[i][k] * L[j][k] * D[k] for k in range(j)), 0)) / D[j]
    y = list(rhs)
    for i in range(n):
        y[i] = rhs[i] - sum((L[i][k] * y[k] for k in range(i)), 0)
    x = [0] * n
    for i in reversed(range(n)):
        x[i] = y[i] / D[i] - sum((L[k][i] * x[k] for k in range(i + 1, n)), 0)
    return x, D


__all__ = ["MAX_OPERATIONS", "MAX_REGRESSOR_OPERATIONS", "Columns", "Program", "ProgramTooLargeError", "Tape", "Traced",
           "recorded_program", "trace_programs"]

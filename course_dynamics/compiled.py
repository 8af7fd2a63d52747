"""Compiled models: our own recursions traced once into straight-line Python, for speed.

Python spends most of a single evaluation on its own bookkeeping, not on the
arithmetic. :func:`compile_model` therefore runs the library's recursions once
on *traced* scalars (:class:`Traced`): every +, −, ×, ÷, cos and sin they do is
recorded as one line of a program, identical operations are recorded once
(common-subexpression elimination by hash-consing), and operations on
constants are done on the spot (0·x, 1·x, the model's numbers). The program is
then written out as plain Python (:attr:`CompiledModel.source`: a student can
read it) and compiled twice: with ``math`` for one state (Python floats, the
fastest scalar arithmetic) and with ``numpy`` for a batch (one array per line).

=====================  ==========================================================
program                traced from
=====================  ==========================================================
``tau``                :func:`~course_dynamics.newton_euler.torque_entries` (6.45)–(6.53)
``mass_matrix``        :func:`~course_dynamics.crba.mass_matrix_entries` (upper triangle)
``bias``               V + G = τ(Θ, Θ̇, 0), the same Newton–Euler recursion
``coriolis``           :func:`~course_dynamics.coriolis.coriolis_matrix_entries`
``forward_dynamics``   M and the bias as above, then Θ̈ = M⁻¹(τ − V − G) (6.115)
                       by an unrolled LDLᵀ factorization, with its pivots
=====================  ==========================================================

No second copy of any algorithm exists: the programs are what the library's
code does, so they agree with the interpreted path to the last bit in most
entries (the tests hold them to 1e-12 and to Pinocchio to 1e-9). The model's
gravity is built in; a different gravity means a different model.

Tracing takes milliseconds; compiling the Python takes most of the time (UR5
about 0.2 s, Panda 0.5 s). So the compiled module is cached on disk, one file
``<key>.entry`` (its source and its bytecode), in ``$COURSE_DYNAMICS_CACHE``,
else ``$XDG_CACHE_HOME/course-dynamics``, else ``~/.cache/course-dynamics``
(made private to the user); ``COURSE_DYNAMICS_CACHE=off`` turns the cache off.
The key is a hash of the model's numbers, the Python and library versions and
the source of every traced module, so any change makes a new entry.

A cached entry is code we are about to run, so nothing in it is trusted until
checked, and checked *before* anything is executed:

* the folder must be owned by the current user and writable by no one else,
  and no folder above it writable by another user (unless sticky, as /tmp);
* the entry must be a regular file (never followed through a link) owned by
  the current user and writable by no one else;
* its content must carry a keyed hash (HMAC-SHA256) made with a secret of 32
  random bytes that lives in the folder, readable by the user alone: anyone
  else can compute the key of an entry, but not its hash;
* only then are its bytes (the very bytes that were checked) executed, and
  every compiled function is compared with the interpreted recursions at a
  random state.

A folder that fails these checks is warned about once (:class:`CacheWarning`)
and the model is compiled in memory; a bad entry is generated again and
replaced. A folder that cannot be written means no cache, not an error.

A robot whose programs would exceed :data:`MAX_OPERATIONS` operations (a chain
of about 20 joints; the Coriolis program grows as n³) is not compiled:
:class:`ProgramTooLargeError`, which the callers that compile on their own
(``simulate``, long logs) answer by running the interpreted recursions.
"""
from __future__ import annotations

import hashlib
import hmac
import json
import marshal
import os
import stat
import sys
import time
import warnings
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path

import numpy as np

from . import coriolis, crba
from .errors import CourseDynamicsError
from .kinematics import joint_transforms
from .model import Model
from .newton_euler import gravity_vector, torque_entries
from .state import as_state

OPERATIONS = {"add": "{} + {}", "sub": "{} - {}", "mul": "{} * {}", "div": "{} / {}", "neg": "-{}", "cos": "cos({})",
              "sin": "sin({})"}
TRACED_MODULES = ("algebra", "kinematics", "newton_euler", "spatial", "crba", "coriolis", "compiled")
SINGULAR_PIVOT_RATIO = 1e-14  # as forward_dynamics: smallest allowed ratio of LDLᵀ pivots
# Operations of all five programs together. Panda takes 19 000, a 20-joint chain 74 000 (2 s to compile, 5 MB of
# source); a 30-joint chain would take 163 000 (7 s) and a 60-joint one several GB of memory.
MAX_OPERATIONS = 80_000
CACHE_OFF = "off"            # COURSE_DYNAMICS_CACHE=off: no cache
MAX_ENTRY_BYTES = 64 * 2**20  # a cached entry larger than this is not read (it is far above MAX_OPERATIONS' size)


class ProgramTooLargeError(CourseDynamicsError):
    """A robot whose compiled programs would take more than :data:`MAX_OPERATIONS` operations."""

    def __init__(self, what: str = "", remedy: str = "; use the interpreted recursions (--no-compile, compiled=False)"):
        self.what = what
        super().__init__(f"{what} is too large to compile: its programs would take more than {MAX_OPERATIONS} "
                         f"operations{remedy}")


class CompileWarning(UserWarning):
    """A model that was run interpreted because it is too large to compile (the message says so)."""


def too_large_to_compile(error: ProgramTooLargeError) -> None:
    """What a caller that compiles on its own does with a robot too large for it: warn, then run interpreted."""
    warnings.warn(str(ProgramTooLargeError(error.what, "; running the interpreted recursions")), CompileWarning,
                  stacklevel=3)


class CacheWarning(UserWarning):
    """The cache folder cannot be trusted with code (the message says why): compiled in memory instead."""


# ---------------------------------------------------------------------------------------- tracing


class Tape:
    """The program being recorded: nodes (op, argument, argument), each recorded once."""

    def __init__(self, limit: int = MAX_OPERATIONS):
        self.nodes: list[tuple] = []
        self.index: dict[tuple, int] = {}
        self.limit = limit

    def record(self, op: str, *arguments) -> "Traced":
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
        return self.record("input", name)


def _ref(x):
    """A node argument: ("t", index) for a traced value, ("c", float) for a constant."""
    return ("t", x.i) if isinstance(x, Traced) else ("c", float(x))


class Traced:
    """A scalar that records the arithmetic done on it (see the module docstring)."""

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
        return self.tape.record("cos", _ref(self)), self.tape.record("sin", _ref(self))


@dataclass
class Program:
    """A straight-line program: named inputs, nodes, and the outputs (node references or constants)."""

    name: str
    inputs: list[str]
    nodes: list[list]
    outputs: list

    def as_data(self) -> dict:
        return {"name": self.name, "inputs": self.inputs, "nodes": self.nodes, "outputs": self.outputs}


def _program(name: str, tape: Tape, input_names: list[str], outputs: list) -> Program:
    """Keep only the nodes the outputs need, renumbered in order."""
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
    """
    n, g = model.n, gravity_vector(model)
    programs, tapes = {}, []

    def tape() -> Tape:
        tapes.append(Tape(MAX_OPERATIONS - sum(len(t.nodes) for t in tapes)))
        return tapes[-1]

    try:
        t = tape()
        q, qd, qdd = _inputs(t, "q", n), _inputs(t, "qd", n), _inputs(t, "qdd", n)
        tau = torque_entries(model, joint_transforms(model, q), qd, qdd, g)
        programs["tau"] = _program("tau", t, ["q", "qd", "qdd"], tau)

        t = tape()
        q = _inputs(t, "q", n)
        M = crba.mass_matrix_entries(model, q)
        programs["mass_matrix"] = _program("mass_matrix", t, ["q"], [M[i][j] for i in range(n) for j in range(i, n)])

        t = tape()
        q, qd = _inputs(t, "q", n), _inputs(t, "qd", n)
        bias = torque_entries(model, joint_transforms(model, q), qd, [0] * n, g)
        programs["bias"] = _program("bias", t, ["q", "qd"], bias)

        t = tape()
        q, qd = _inputs(t, "q", n), _inputs(t, "qd", n)
        C = coriolis.coriolis_matrix_entries(model, q, qd)
        programs["coriolis"] = _program("coriolis", t, ["q", "qd"], [C[i][j] for i in range(n) for j in range(n)])

        t = tape()
        q, qd, tau = _inputs(t, "q", n), _inputs(t, "qd", n), _inputs(t, "tau", n)
        M = crba.mass_matrix_entries(model, q)
        bias = torque_entries(model, joint_transforms(model, q), qd, [0] * n, g)
        qdd, pivots = _ldl_solve(M, [t_ - b for t_, b in zip(tau, bias)])  # (6.115)
        programs["forward_dynamics"] = _program("forward_dynamics", t, ["q", "qd", "tau"], qdd + pivots)
    except ProgramTooLargeError:
        raise ProgramTooLargeError(f"robot {model.name!r} ({n} joints)") from None
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


# ---------------------------------------------------------------------------------------- source


def _argument(a, nodes) -> str:
    kind, value = a
    if kind == "t":
        op, *arguments = nodes[value]
        return arguments[0] if op == "input" else f"t{value}"  # inputs by their own names: q0, qd1, …
    return repr(float(value)) if value >= 0 else f"({float(value)!r})"


def program_source(program: Program, n: int, free: bool = False) -> str:
    """The program as one Python function: unpack the inputs, one line per operation, return the outputs.

    With ``free`` every value is deleted after its last use, so that a batch keeps only the arrays it still
    needs (the one-state version keeps its floats: the readable form).
    """
    lines = [f"def {program.name}({', '.join(program.inputs)}):"]
    for name in program.inputs:
        lines.append(f"    {', '.join(f'{name}{j}' for j in range(n))}{',' if n == 1 else ''} = {name}")
    last_use = {}
    if free:
        kept = {value for kind, value in program.outputs if kind == "t"}
        kept |= {i for i, (op, *_) in enumerate(program.nodes) if op == "input"}
        for i, (op, *arguments) in enumerate(program.nodes):
            for a in arguments:
                if op != "input" and a[0] == "t" and a[1] not in kept:
                    last_use[a[1]] = i
    dead: dict[int, list[int]] = {}
    for value, i in last_use.items():
        dead.setdefault(i, []).append(value)
    nodes = program.nodes
    for i, (op, *arguments) in enumerate(nodes):
        if op != "input":
            lines.append(f"    t{i} = {OPERATIONS[op].format(*(_argument(a, nodes) for a in arguments))}")
        if i in dead:
            lines.append(f"    del {', '.join(f't{v}' for v in sorted(dead[i]))}")
    lines.append(f"    return ({', '.join(_argument(o, nodes) for o in program.outputs)},)")
    return "\n".join(lines)


def module_source(model: Model, programs: dict[str, Program], key: str) -> str:
    """One module with every program twice: ``<name>`` on floats (math) and ``<name>_batch`` on arrays (numpy)."""
    n = model.n
    # Names from the URDF appear only inside comments, as Python reprs: a repr has no line break in it, so no
    # name can end the comment and become code (a docstring could be closed by a name holding three quotes).
    header = (f"# course-dynamics compiled model {key}\n"
              f"# robot {model.name!r}, {n} joints in the order {list(model.joint_names)!r}\n"
              '"""Generated by course_dynamics.compiled (the robot and its joint order are in the comment above).\n\n'
              "Each function is one of the library's recursions for this robot, traced: every line is one operation\n"
              "the recursion does, done once; the numbers are the robot's parameters. The functions ending in _batch\n"
              'are the same lines on numpy arrays, each value deleted after its last use."""\n'
              "from math import cos, sin\n\nimport numpy\n")
    scalar = [program_source(p, n) for p in programs.values()]
    batch = [program_source(p, n, free=True).replace(f"def {p.name}(", f"def {p.name}_batch(", 1)
             .replace("cos(", "numpy.cos(").replace("sin(", "numpy.sin(") for p in programs.values()]
    return header + "\n\n" + "\n\n\n".join(scalar + batch) + "\n"


# ---------------------------------------------------------------------------------------- the compiled model


def cache_folder() -> Path | None:
    """The cache folder (module docstring); None when ``COURSE_DYNAMICS_CACHE=off``."""
    chosen = os.environ.get("COURSE_DYNAMICS_CACHE")
    if chosen == CACHE_OFF:
        return None
    if chosen:
        return Path(chosen)
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "course-dynamics"


def model_key(model: Model) -> str:
    """A hash of everything the programs depend on: the model's numbers, the library and Python versions, the code."""
    here = Path(__file__).resolve().parent
    digest = hashlib.sha256()
    try:
        digest.update(metadata.version("course-dynamics").encode())
    except metadata.PackageNotFoundError:
        pass
    digest.update(f"{sys.version} {sys.implementation.cache_tag} marshal {marshal.version}".encode())
    for module in TRACED_MODULES:
        digest.update((here / f"{module}.py").read_bytes())
    description = [model.name, model.gravity.tolist(), [
        [b.joint, b.joint_type, b.parent, b.R0.tolist(), b.P.tolist(), b.axis.tolist(), float(b.mass), b.p_com.tolist(),
         b.I_com.tolist()] for b in model.bodies]]
    digest.update(json.dumps(description).encode())
    return digest.hexdigest()


@dataclass
class CompiledModel:
    """The compiled programs of one model (module docstring); methods mirror the library's functions."""

    model: Model
    source: str
    generation_seconds: float
    from_cache: bool
    path: Path | None = None
    functions: dict = field(repr=False, default_factory=dict)

    def _run(self, name: str, *arrays) -> np.ndarray:
        if all(a.ndim == 1 for a in arrays):
            return np.array(self.functions[name](*(a.tolist() for a in arrays)))
        batch = np.broadcast_shapes(*(a.shape[:-1] for a in arrays))
        columns = [(a if a.shape[:-1] == batch else np.broadcast_to(a, batch + a.shape[-1:])) for a in arrays]
        out = self.functions[f"{name}_batch"](*(c.T if c.ndim == 2 else np.moveaxis(c, -1, 0) for c in columns))
        return np.stack([o if np.shape(o) == batch else np.broadcast_to(o, batch) for o in out], axis=-1)

    def inverse_dynamics(self, q, qd, qdd) -> np.ndarray:
        """τ, shape (n,) or (N, n), as :func:`~course_dynamics.newton_euler.inverse_dynamics`."""
        m = self.model
        return self._run("tau", as_state(m, q, "q"), as_state(m, qd, "qd"), as_state(m, qdd, "qdd"))

    def mass_matrix(self, q) -> np.ndarray:
        """M(Θ), shape (n, n) or (N, n, n)."""
        upper = self._run("mass_matrix", as_state(self.model, q, "q"))
        n = self.model.n
        M = np.empty(upper.shape[:-1] + (n, n))
        rows, cols = np.triu_indices(n)
        M[..., rows, cols] = upper
        M[..., cols, rows] = upper
        return M

    def bias(self, q, qd) -> np.ndarray:
        """V(Θ, Θ̇) + G(Θ), shape (n,) or (N, n)."""
        return self._run("bias", as_state(self.model, q, "q"), as_state(self.model, qd, "qd"))

    def coriolis_matrix(self, q, qd) -> np.ndarray:
        """C(Θ, Θ̇), shape (n, n) or (N, n, n)."""
        C = self._run("coriolis", as_state(self.model, q, "q"), as_state(self.model, qd, "qd"))
        return C.reshape(C.shape[:-1] + (self.model.n, self.model.n))

    def forward_dynamics(self, q, qd, tau, friction=None) -> np.ndarray:
        """Θ̈ (6.115), shape (n,) or (N, n), as :func:`~course_dynamics.forward_dynamics.forward_dynamics`."""
        m = self.model
        q, qd, tau = as_state(m, q, "q"), as_state(m, qd, "qd"), as_state(m, tau, "tau")
        if friction is not None:
            tau = tau - friction.torques(qd)  # (6.114)
        return self.accelerations(q, qd, tau)

    def accelerations(self, q: np.ndarray, qd: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """Θ̈ for checked float arrays (n,) or (K, n): an AccelerationFunction for ``simulate``."""
        n = self.model.n
        try:
            with np.errstate(divide="ignore", invalid="ignore"):
                out = self._run("forward_dynamics", q, qd, tau)
        except ZeroDivisionError:  # a zero pivot: M is singular
            out = np.zeros(np.broadcast_shapes(q.shape, qd.shape, tau.shape)[:-1] + (2 * n,))
        pivots = out[..., n:]
        if not np.all(pivots.min(axis=-1) > SINGULAR_PIVOT_RATIO * np.abs(pivots).max(axis=-1)):
            from .forward_dynamics import accelerations

            return accelerations(self.model, q, qd, tau)  # raises SingularMassMatrixError, naming the joint
        return out[..., :n]


PROGRAMS = ("tau", "mass_matrix", "bias", "coriolis", "forward_dynamics")


def _functions_of(source: str, code, name: str) -> dict:
    namespace: dict = {"__name__": f"course_dynamics_compiled_{name}"}
    exec(code, namespace)  # our own program: just generated, or read back after its keyed hash was checked
    return {n: namespace[n] for p in PROGRAMS for n in (p, f"{p}_batch")}


def _agrees_with_the_recursion(model: Model, functions: dict) -> bool:
    """Every compiled function at one random state against the interpreted recursions, to 1e-12."""
    from .dynamics import coriolis_matrix, mass_matrix_and_bias
    from .newton_euler import inverse_dynamics

    n = model.n
    q, qd, qdd = np.random.default_rng().uniform(-1, 1, (3, n))
    rows, cols = np.triu_indices(n)
    try:
        M, bias = mass_matrix_and_bias(model, q, qd)
        expected = {"tau": inverse_dynamics(model, q, qd, qdd), "mass_matrix": M[rows, cols], "bias": bias,
                    "coriolis": coriolis_matrix(model, q, qd).ravel(),
                    "forward_dynamics": np.linalg.solve(M, qdd - bias)}
        arguments = {"tau": (q, qd, qdd), "mass_matrix": (q,), "bias": (q, qd), "coriolis": (q, qd),
                     "forward_dynamics": (q, qd, qdd)}
        for name, ours in expected.items():
            got = np.array(functions[name](*(a.tolist() for a in arguments[name])))[:len(ours)]
            out = functions[f"{name}_batch"](*(a[:, None] for a in arguments[name]))
            batch = np.array([np.broadcast_to(np.asarray(o, dtype=float), (1,))[0] for o in out])[:len(ours)]
            scale = 1 + np.abs(ours).max()
            if not (np.all(np.abs(got - ours) <= 1e-9 * scale) and np.all(np.abs(batch - ours) <= 1e-9 * scale)):
                return False
    except Exception:  # a garbled program: generate it again
        return False
    return True


# ---------------------------------------------------------------------------------------- the cache

_warned_folders: set[str] = set()


def _only_ours(st, what: str, sticky_ok: bool) -> str | None:
    """Why a folder with stat ``st`` could be changed by another user, or None."""
    if st.st_uid not in (os.getuid(), 0):
        return f"{what} belongs to another user (uid {st.st_uid})"
    if st.st_mode & 0o022 and not (sticky_ok and st.st_mode & stat.S_ISVTX):
        return f"other users can write to {what} (mode {stat.S_IMODE(st.st_mode):o})"
    return None


def _distrust(folder: Path) -> str | None:
    """Why the way to ``folder`` could be changed by another user, or None (module docstring).

    Every folder on the path as written and as resolved is checked, and every symbolic link on it
    must be ours or root's: a link is only as safe as the folder it sits in and its owner.
    """
    folder = Path(os.path.abspath(folder))
    try:
        for path in [*reversed(folder.parents), folder]:
            st = os.lstat(path)
            if stat.S_ISLNK(st.st_mode):
                if st.st_uid not in (os.getuid(), 0):
                    return f"the link {path} on its way belongs to another user (uid {st.st_uid})"
                continue
            if path != folder:
                reason = _only_ours(st, f"the folder {path} above it", sticky_ok=True)
                if reason:
                    return reason
        for path in folder.resolve().parents:
            reason = _only_ours(os.stat(path), f"the folder {path} above it", sticky_ok=True)
            if reason:
                return reason
    except OSError as exc:
        return f"it cannot be inspected ({exc.strerror})"
    return None


def _open_folder(folder: Path) -> tuple[int | None, str | None]:
    """A descriptor of ``folder`` once it is known to be only this user's, or (None, why not).

    Everything in the cache is then opened relative to this descriptor, so swapping a folder or a
    link on the way after the checks changes nothing.
    """
    reason = _distrust(folder)
    if reason:
        return None, reason
    try:
        fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        return None, f"it cannot be opened ({exc.strerror})"
    st = os.fstat(fd)
    reason = "it belongs to another user" if st.st_uid != os.getuid() else \
        _only_ours(st, "it", sticky_ok=False)
    if reason:
        os.close(fd)
        return None, reason
    return fd, None


def _read_private(folder_fd: int, name: str, private_mode: int, limit: int) -> bytes | None:
    """The bytes of ``name`` in the folder if it is a regular file of ours, no link, no bits of ``private_mode``."""
    try:
        fd = os.open(name, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0), dir_fd=folder_fd)
    except OSError:
        return None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode) or st.st_uid != os.getuid() or st.st_mode & private_mode \
                or st.st_size > limit:
            return None
        with os.fdopen(fd, "rb", closefd=False) as handle:
            data = handle.read(limit + 1)
        return data if len(data) <= limit else None
    except OSError:
        return None
    finally:
        os.close(fd)


def _write_private(folder_fd: int, name: str, data: bytes) -> bool:
    """Write ``name`` in the folder whole, mode 0600: a new file (O_EXCL, no link followed) renamed over it.

    The same rule as :func:`course_dynamics.io.output`, but relative to the checked folder's descriptor,
    which a writer of paths cannot be: a folder or link swapped on the way after the check changes nothing.
    """
    temporary = f".{name}.{os.getpid()}.{os.urandom(6).hex()}.partial"
    try:
        fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | getattr(os, "O_CLOEXEC", 0),
                     0o600, dir_fd=folder_fd)
    except OSError:
        return False
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
        os.replace(temporary, name, src_dir_fd=folder_fd, dst_dir_fd=folder_fd)  # a rename never follows a link
        return True
    except OSError:
        try:
            os.unlink(temporary, dir_fd=folder_fd)
        except OSError:
            pass
        return False


SECRET_BYTES = 32


def _secret(folder_fd: int) -> bytes | None:
    """The folder's 32 secret bytes, made on first use (readable by this user alone)."""
    secret = _read_private(folder_fd, "secret", 0o077, SECRET_BYTES)
    if secret is not None and len(secret) == SECRET_BYTES:
        return secret
    try:
        os.lstat("secret", dir_fd=folder_fd)
        return None  # not ours, not private, or damaged: never replaced behind the user's back
    except FileNotFoundError:
        pass
    except OSError:
        return None
    try:
        fd = os.open("secret", os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600, dir_fd=folder_fd)
    except OSError:
        return None
    with os.fdopen(fd, "wb") as handle:
        handle.write(os.urandom(SECRET_BYTES))
    secret = _read_private(folder_fd, "secret", 0o077, SECRET_BYTES)
    return secret if secret is not None and len(secret) == SECRET_BYTES else None


class _Cache:
    """Entries ``<key>.entry`` in a trusted folder: HMAC (32 bytes), source length (8), source, marshalled code.

    Used as a context manager: the folder's descriptor is closed at the end.
    """

    def __init__(self, folder: Path | None):
        self.folder, self.fd, self.secret = folder, None, None
        if folder is None:
            return
        try:
            folder.mkdir(mode=0o700, parents=True, exist_ok=True)
        except OSError:
            self.folder = None  # cannot be made: no cache, as documented
            return
        self.fd, reason = _open_folder(folder)
        if reason is None:
            self.secret = _secret(self.fd)
            if self.secret is None:
                reason = f"its secret file {folder / 'secret'} is not a private file of this user"
        if reason is not None:
            self.close()
            self.folder = None
            if str(folder) not in _warned_folders:
                _warned_folders.add(str(folder))
                warnings.warn(f"the compiled-model cache {folder} is not used: {reason}; compiling in memory "
                              f"(make it a private folder of yours, or set COURSE_DYNAMICS_CACHE={CACHE_OFF})",
                              CacheWarning, stacklevel=3)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self) -> None:
        if self.fd is not None:
            os.close(self.fd)
            self.fd = None

    def path(self, key: str) -> Path | None:
        return None if self.folder is None else self.folder / f"{key}.entry"

    def _mac(self, key: str, body: bytes) -> bytes:
        return hmac.new(self.secret, key.encode() + b"\0" + body, hashlib.sha256).digest()

    def load(self, key: str) -> tuple[str, object] | None:
        """(source, code) of a checked entry, or None."""
        if self.folder is None:
            return None
        data = _read_private(self.fd, f"{key}.entry", 0o022, MAX_ENTRY_BYTES)
        if data is None or len(data) < 40 or not hmac.compare_digest(data[:32], self._mac(key, data[32:])):
            return None
        length = int.from_bytes(data[32:40], "little")
        try:
            return data[40:40 + length].decode("utf-8"), marshal.loads(data[40 + length:])
        except (ValueError, EOFError, TypeError, UnicodeDecodeError):
            return None

    def store(self, key: str, source: str, code) -> Path | None:
        if self.folder is None:
            return None
        text = source.encode("utf-8")
        body = len(text).to_bytes(8, "little") + text + marshal.dumps(code)
        return self.path(key) if _write_private(self.fd, f"{key}.entry", self._mac(key, body) + body) else None


def compile_model(model: Model, cache: bool = True) -> CompiledModel:
    """Trace (or load from the cache) and compile the programs of ``model`` (module docstring).

    Raises :class:`ProgramTooLargeError` for a robot too large to compile.
    """
    start = time.perf_counter()
    key = model_key(model)
    with _Cache(cache_folder() if cache else None) as store:
        entry = store.load(key)
        if entry is not None:
            source, code = entry
            try:
                functions = _functions_of(source, code, key[:16])
            except Exception:  # a program that does not run: generate it again
                functions = None
            if functions is not None and _agrees_with_the_recursion(model, functions):
                return CompiledModel(model, source, time.perf_counter() - start, True, store.path(key), functions)
        source = module_source(model, trace_programs(model), key)
        code = compile(source, f"<compiled {key[:16]}>", "exec")
        functions = _functions_of(source, code, key[:16])
        stored = store.store(key, source, code)
    return CompiledModel(model, source, time.perf_counter() - start, False, stored, functions)

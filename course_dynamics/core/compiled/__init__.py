"""Compiled models: our own recursions traced once into straight-line Python, for speed.

Python spends most of a single evaluation on its own bookkeeping, not on the
arithmetic. :func:`compile_model` therefore runs the library's recursions once
on *traced* scalars (:class:`~course_dynamics.core.compiled.tracing.Traced`):
every +, −, ×, ÷, cos and sin they do is recorded as one line of a program,
identical operations are recorded once
(common-subexpression elimination by hash-consing), and operations on
constants are done on the spot (0·x, 1·x, the model's numbers). The program is
then written out as plain Python (``CompiledModel.source``: a student can
read it) and compiled twice: with ``math`` for one state (Python floats, the
fastest scalar arithmetic) and with ``numpy`` for a batch (one array per line).

=====================  ==========================================================
program                traced from
=====================  ==========================================================
``tau``                ``course_dynamics.core.newton_euler.torque_entries`` (6.45)–(6.53)
``mass_matrix``        ``course_dynamics.core.crba.mass_matrix_entries`` (upper triangle)
``bias``               V + G = τ(Θ, Θ̇, 0), the same Newton–Euler recursion
``coriolis``           ``course_dynamics.core.coriolis.coriolis_matrix_entries``
``forward_dynamics``   M and the bias as above, then Θ̈ = M⁻¹(τ − V − G) (6.115)
                       by an unrolled LDLᵀ factorization, with its pivots
``regressor``          ``course_dynamics.core.regressor.regressor_rows``: τ on dual
                       numbers, one sparse derivative per inertial parameter
=====================  ==========================================================

No second copy of any algorithm exists: the programs are what the library's
code does, so they agree with the interpreted path to the last bit in most
entries (the tests hold them to 1e-12 and to Pinocchio to 1e-9). The model's
gravity is built in; a different gravity means a different model.

Tracing takes milliseconds; compiling the Python takes most of the time (UR5
about 0.2 s, Panda 0.5 s). So the compiled module is cached on disk, one file
``<key>.entry`` (its source and its bytecode), in ``$COURSE_DYNAMICS_CACHE``,
else ``$XDG_CACHE_HOME/course-dynamics``, else ``~/.cache/course-dynamics``
(made private to the user: mode 0700, with any folder above it that is missing, and
its files 0600, whatever the umask); ``COURSE_DYNAMICS_CACHE=off`` turns the cache off.
The key is a hash of the model's numbers, the Python and library versions and
the source of every traced module, so any change makes a new entry.

A cached entry is code we are about to run, so nothing in it is trusted until
checked, and checked *before* anything is executed:

* the folder must be owned by the current user and writable by no one else,
  and no folder above it writable by everyone (unless sticky, as /tmp); one its
  group can write (``~/.cache`` under ``umask 002``) is fine, as the folder itself
  is checked through the descriptor everything in it is then opened by;
* the entry must be a regular file (never followed through a link) owned by
  the current user and writable by no one else;
* its content must carry a keyed hash (HMAC-SHA256) made with a secret of 32
  random bytes that lives in the folder, readable by the user alone: anyone
  else can compute the key of an entry, but not its hash;
* only then are its bytes (the very bytes that were checked) executed, and
  every compiled function is compared with the interpreted recursions at a
  random state.

A folder that fails these checks is warned about once
(:class:`~course_dynamics.core.compiled.cache.CacheWarning`) and the model is
compiled in memory; a bad entry is generated again and replaced. A folder that
cannot be written means no cache, not an error.

A robot whose programs would exceed :data:`MAX_OPERATIONS` operations (a chain
of about 20 joints; the Coriolis program grows as n²) is not compiled:
:class:`~course_dynamics.core.compiled.tracing.ProgramTooLargeError`, which the
evaluator (:mod:`~course_dynamics.core.evaluator`, the one place that chooses
whether to compile) answers by running the interpreted recursions.

The native library (:mod:`~course_dynamics.core.compiled.native`, ``<key>.native``) is
built under a bound and limits, in the background for the evaluator, and a build that
failed or timed out is remembered (``<key>.native-failed``) and not tried again:
:mod:`~course_dynamics.core.compiled.building`.
"""
from __future__ import annotations

import functools
import hashlib
import json
import marshal
import os
import re
import sys
import time
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path

import numpy as np

from ...base.errors import CourseDynamicsWarning
from ..dynamics import coriolis_matrix, mass_matrix_and_bias
from ..forward_dynamics import SINGULAR_PIVOT_RATIO, accelerations
from ..model import Model
from ..newton_euler import inverse_dynamics
from ..regressor import regressor
from ..state import as_state, batch_shape
from . import building, cache, codegen, native, tracing
from .cache import Cache, CacheWarning, cache_folder
from .codegen import module_source, program_source
from .tracing import (
    Program,
    ProgramTooLargeError,
    Tape,
    Traced,
    trace_programs,
)

#: The value of ``COURSE_DYNAMICS_CACHE`` that turns the cache off
#: (:data:`~course_dynamics.core.compiled.cache.CACHE_OFF`).
CACHE_OFF = cache.CACHE_OFF
#: The most operations the programs of one robot may take together
#: (:data:`~course_dynamics.core.compiled.tracing.MAX_OPERATIONS`).
MAX_OPERATIONS = tracing.MAX_OPERATIONS


class CompileWarning(CourseDynamicsWarning):
    """A model that was run interpreted because it is too large to compile (the message says so).

    The evaluator gives it when :func:`compile_model` raises
    :class:`~course_dynamics.core.compiled.tracing.ProgramTooLargeError`.

    Examples
    --------
    >>> issubclass(CompileWarning, UserWarning)          # warnings.simplefilter("error", CompileWarning) makes it fatal
    True
    """


PACKAGE = Path(__file__).resolve().parent.parent.parent  # course_dynamics/


# A relative import, at any indentation (lazy ones too), its names on one line or in parentheses.
RELATIVE_IMPORT = re.compile(r"^[ \t]*from[ \t]+(\.+)([\w.]*)[ \t]+import[ \t]+(\([^)]*\)|[^\n]*)", re.MULTILINE)


@functools.cache
def traced_sources() -> tuple[Path, ...]:
    """The source files a compiled program can depend on: the tracer, the code writer, this module, and every
    module of ours they import, directly or through others, lazy imports included. Read with
    :data:`RELATIVE_IMPORT`, not ``ast``: the evaluator asks for a model's key on its first call in a process,
    and parsing the modules took 0.2 s, the scan 20 ms (the tests hold the two to the same files)."""
    pending = [Path(__file__).resolve(), Path(tracing.__file__).resolve(), Path(codegen.__file__).resolve()]
    found: set[Path] = set()
    while pending:
        path = pending.pop()
        if path in found:
            continue
        found.add(path)
        for dots, module, names in RELATIVE_IMPORT.findall(path.read_text(encoding="utf-8")):
            base = path.parent
            for _ in range(len(dots) - 1):
                base = base.parent
            target = base.joinpath(*(module.split(".") if module else []))
            candidates = [target.with_suffix(".py"), target / "__init__.py"]
            names = re.sub(r"#[^\n]*", "", names.strip("()")).split(",")
            candidates += [target / f"{name.split()[0]}.py" for name in names if name.strip()]  # ``from . import crba``
            pending += [c.resolve() for c in candidates if c.is_file() and c.resolve().is_relative_to(PACKAGE)]
    return tuple(sorted(found))


@functools.cache
def code_fingerprint() -> bytes:
    """A hash of the library and Python versions and of :func:`traced_sources`: the same for every model, so
    computed once per process."""
    digest = hashlib.sha256()
    try:
        digest.update(metadata.version("course-dynamics").encode())
    except metadata.PackageNotFoundError:
        pass
    digest.update(f"{sys.version} {sys.implementation.cache_tag} marshal {marshal.version}".encode())
    for path in traced_sources():
        digest.update(path.relative_to(PACKAGE).as_posix().encode() + b"\0" + path.read_bytes())
    return digest.digest()


def model_key(model: Model) -> str:
    """A hash of everything the programs depend on: the model's numbers, the library and Python versions, and
    the source of every module the trace can run (``traced_sources``).

    Parameters
    ----------
    model : Model
        The robot.

    Returns
    -------
    str
        64 hexadecimal digits (SHA-256): the name of the model's cache entries.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> key = model_key(arm)
    >>> len(key), key == model_key(load_robot("two_link")), key == model_key(arm.with_gravity([0, 0, -1.62]))
    (64, True, False)
    """
    digest = hashlib.sha256(code_fingerprint())
    description = [model.name, model.gravity.tolist(), [
        [b.joint, b.joint_type, b.parent, b.R0.tolist(), b.P.tolist(), b.axis.tolist(), float(b.mass), b.p_com.tolist(),
         b.I_com.tolist(), b.mimic, b.multiplier, b.offset] for b in model.bodies]]
    digest.update(json.dumps(description).encode())
    return digest.hexdigest()


@dataclass
class CompiledModel:
    """The compiled programs of one model (module docstring); methods mirror the library's functions.

    Made by :func:`compile_model`. Each method checks its arguments as the library's function does and takes
    one state (n,) or a batch (N, n) (any batch shape that broadcasts).

    Parameters
    ----------
    model : Model
        The robot, its gravity built into the programs.
    source : str
        The generated Python module, for reading: each program for one state and, as ``<name>_batch``, for a
        batch.
    generation_seconds : float
        The time tracing and compiling (or loading from the cache) took, s.
    from_cache : bool
        Whether the programs were read from the cache.
    path : pathlib.Path or None
        The cache entry, ``<key>.entry``; None where no cache was used.
    functions : dict of str to callable
        The compiled Python functions by name (``tau``, ``tau_batch``, ``mass_matrix``, …).
    native : dict of str to callable
        The native functions by program name; empty where there is no native code.
    native_source : str
        The C source of the native library when it was built in this process; ``""`` otherwise.
    native_seconds : float
        The time building (or loading) the native library took, s.
    native_reason : str
        Why there is no native code (yet): turned off, no compiler, over the bound, failed before, being built;
        ``""`` when there is.
    native_build : object or None
        The build running in the background (``native_code="background"``), until :meth:`collected` takes it up.
    loop : Looped or None
        The native loop (:mod:`~course_dynamics.core.compiled.looped`), standing in for τ, M and V + G while
        there is no native code (the evaluator gives it); None by default.
    _calls : dict
        Each native program a one-state call has used, with its output's width and shape (filled on first use).

    Examples
    --------
    >>> import numpy as np
    >>> from course_dynamics import load_robot, mass_matrix
    >>> arm = load_robot("two_link")
    >>> fast = compile_model(arm)
    >>> Q = np.random.default_rng(0).uniform(-1, 1, (100, 2))
    >>> fast.mass_matrix(Q).shape, np.allclose(fast.mass_matrix(Q), mass_matrix(arm, Q), rtol=1e-12)
    ((100, 2, 2), True)
    >>> "def tau(" in fast.source                        # the generated code, for reading
    True
    """

    model: Model
    source: str
    generation_seconds: float
    from_cache: bool
    path: Path | None = None
    functions: dict = field(repr=False, default_factory=dict)
    native: dict = field(repr=False, default_factory=dict)  # the same programs as C (native.py), where built
    native_source: str = ""
    native_seconds: float = 0.0  # building (or loading) the native library
    native_reason: str = ""      # why there is no native code (yet): over the bound, failed before, building, …
    native_build: building.Build | None = field(repr=False, default=None)  # a build running in the background
    loop: object = field(repr=False, default=None)  # the native loop, for τ, M and V + G while there is no C
    _calls: dict = field(repr=False, compare=False, default_factory=dict)  # name -> (C function, width, shape)

    def collected(self, wait: float = 0.0) -> CompiledModel:
        """This model with its background build's library once the build has ended (a new CompiledModel; the
        same one while it runs), waiting at most ``wait`` s for it.

        Parameters
        ----------
        wait : float, optional
            The most time to wait for the build to end, s; 0 looks without waiting.

        Returns
        -------
        CompiledModel
            A new model with the native functions (or with ``native_reason`` saying why there are none) once
            the build has ended; this one while it runs, or when there is no build.
        """
        return building.collect(self, _agrees_with_the_recursion, wait)

    def _run(self, name: str, *arrays) -> np.ndarray:
        function = self.native.get(name)
        if function is not None and all(a.dtype == np.float64 for a in arrays):
            return self._run_native(function, name, arrays)
        out = None if function is not None or self.loop is None else self.loop.batch(name, *arrays)
        if out is not None:
            return out
        if all(a.ndim == 1 for a in arrays):
            return np.array(self.functions[name](*(a.tolist() for a in arrays)))
        batch = batch_shape(*arrays)
        columns = [(a if a.shape[:-1] == batch else np.broadcast_to(a, batch + a.shape[-1:])) for a in arrays]
        out = self.functions[f"{name}_batch"](*(c.T if c.ndim == 2 else np.moveaxis(c, -1, 0) for c in columns))
        return np.stack([o if np.shape(o) == batch else np.broadcast_to(o, batch) for o in out], axis=-1)

    def native_call(self, name: str, *arrays) -> np.ndarray | None:
        """What the method ``name`` returns (τ; M as an n × n matrix; Θ̈ once its pivots show M is not singular),
        from the native program, if the arguments are one state of finite float64 values (n,) each; None otherwise
        (no native code, or anything the checked path should see first).

        Parameters
        ----------
        name : str
            The program: ``tau``, ``mass_matrix`` or ``forward_dynamics`` (or ``bias``, ``coriolis``).
        *arrays : numpy.ndarray, shape (n,)
            Its inputs, in order (Θ, Θ̇, Θ̈ for ``tau``; Θ for ``mass_matrix``; Θ, Θ̇, τ for ``forward_dynamics``).

        Returns
        -------
        numpy.ndarray or None
            τ, shape (n,), N·m; M(Θ), shape (n, n); Θ̈, shape (n,), rad/s²: or None where the native program
            does not take the arguments.

        Raises
        ------
        SingularMassMatrixError
            For ``forward_dynamics``, if M(Θ) is singular (the error names the joint).
        """
        call = self._calls.get(name)
        if call is None:  # once a program: its function, its output's width and the shape it is returned in
            function, n, bodies = self.native.get(name), self.model.n, self.model.n_bodies
            shape = {"mass_matrix": (n, n), "regressor": (n, 10 * bodies)}.get(name)
            call = self._calls[name] = (function, native.width(name, n, bodies), shape) if function else ()
        if not call:
            return None if self.loop is None else self.loop.native_call(name, *arrays)
        for a in arrays:  # one state each: a batch of one keeps its batch shape on the other path
            if type(a) is not np.ndarray or a.ndim != 1:
                return None
        function, width, shape = call
        out = np.empty(width)
        try:
            function(*arrays, out)
        except (TypeError, ValueError, BufferError):
            return None
        if shape is not None:
            return out.reshape(shape)
        if name == "forward_dynamics":
            n = self.model.n
            pivots = out[n:].tolist()
            if not min(pivots) > SINGULAR_PIVOT_RATIO * max(map(abs, pivots)):
                return accelerations(self.model, *arrays)  # raises SingularMassMatrixError, naming the joint
            return out[:n]
        return out

    def _run_native(self, function, name: str, arrays) -> np.ndarray:
        """The native program on checked float64 states: any batch shape, shared over threads when large."""
        return native.run_batch(function, arrays, native.width(name, self.model.n, self.model.n_bodies))

    def inverse_dynamics(self, q, qd, qdd) -> np.ndarray:
        """τ, shape (n,) or (N, n), as :func:`~course_dynamics.core.newton_euler.inverse_dynamics`.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint positions Θ, rad (m for a prismatic joint).
        qd : array_like, shape (n,) or (N, n)
            Joint velocities Θ̇, rad/s (m/s).
        qdd : array_like, shape (n,) or (N, n)
            Joint accelerations Θ̈, rad/s² (m/s²).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            Joint torques τ, N·m (N for a prismatic joint).

        Raises
        ------
        StateError
            If an argument is not a finite array of shape (n,) or (N, n).
        """
        fast = self.native_call("tau", q, qd, qdd)
        if fast is not None:
            return fast
        m = self.model
        return self._run("tau", as_state(m, q, "q"), as_state(m, qd, "qd"), as_state(m, qdd, "qdd"))

    def regressor(self, q, qd, qdd) -> np.ndarray:
        """Y(Θ, Θ̇, Θ̈), shape (n, 10 n_bodies) or (N, n, 10 n_bodies), as
        :func:`~course_dynamics.core.regressor.regressor` (which runs where the regressor was over its bound,
        :data:`~course_dynamics.core.compiled.tracing.MAX_REGRESSOR_OPERATIONS`).

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint positions Θ, rad (m for a prismatic joint).
        qd : array_like, shape (n,) or (N, n)
            Joint velocities Θ̇, rad/s (m/s).
        qdd : array_like, shape (n,) or (N, n)
            Joint accelerations Θ̈, rad/s² (m/s²).

        Returns
        -------
        numpy.ndarray, shape (n, 10 n_bodies) or (N, n, 10 n_bodies)
            Y; τ = Y π (N·m or N per unit of each parameter).

        Raises
        ------
        StateError
            If an argument is not a finite array of shape (n,) or (N, n).
        """
        m = self.model
        fast = self.native_call("regressor", q, qd, qdd)
        if fast is not None:
            return fast
        q, qd, qdd = as_state(m, q, "q"), as_state(m, qd, "qd"), as_state(m, qdd, "qdd")
        if "regressor" not in self.functions:
            return regressor(m, q, qd, qdd)
        out = self._run("regressor", q, qd, qdd)
        return out.reshape(out.shape[:-1] + (m.n, 10 * m.n_bodies))

    def mass_matrix(self, q) -> np.ndarray:
        """M(Θ), shape (n, n) or (N, n, n).

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint positions Θ, rad (m for a prismatic joint).

        Returns
        -------
        numpy.ndarray, shape (n, n) or (N, n, n)
            The mass matrix M(Θ), kg·m² (kg for prismatic joints).

        Raises
        ------
        StateError
            If an argument is not a finite array of shape (n,) or (N, n).
        """
        fast = self.native_call("mass_matrix", q)
        if fast is not None:
            return fast
        n = self.model.n
        out = self._run("mass_matrix", as_state(self.model, q, "q"))
        if out.shape[-1] != n * n:  # the Python programs give the upper triangle, the native ones M whole
            out = out[..., _symmetric_index(n)]
        return out.reshape(out.shape[:-1] + (n, n))

    def bias(self, q, qd) -> np.ndarray:
        """V(Θ, Θ̇) + G(Θ), shape (n,) or (N, n).

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint positions Θ, rad (m for a prismatic joint).
        qd : array_like, shape (n,) or (N, n)
            Joint velocities Θ̇, rad/s (m/s).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            The velocity and gravity torques V(Θ, Θ̇) + G(Θ), N·m (N for a prismatic joint).

        Raises
        ------
        StateError
            If an argument is not a finite array of shape (n,) or (N, n).
        """
        return self._run("bias", as_state(self.model, q, "q"), as_state(self.model, qd, "qd"))

    def gravity_torques(self, q) -> np.ndarray:
        """G(Θ) = V + G at Θ̇ = 0, shape (n,) or (N, n).

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint positions Θ, rad (m for a prismatic joint).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            The gravity torques G(Θ), N·m (N for a prismatic joint).

        Raises
        ------
        StateError
            If an argument is not a finite array of shape (n,) or (N, n).
        """
        q = as_state(self.model, q, "q")
        return self._run("bias", q, np.zeros_like(q))

    def coriolis_matrix(self, q, qd) -> np.ndarray:
        """C(Θ, Θ̇), shape (n, n) or (N, n, n).

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint positions Θ, rad (m for a prismatic joint).
        qd : array_like, shape (n,) or (N, n)
            Joint velocities Θ̇, rad/s (m/s).

        Returns
        -------
        numpy.ndarray, shape (n, n) or (N, n, n)
            The Coriolis matrix C(Θ, Θ̇), with V(Θ, Θ̇) = C(Θ, Θ̇) Θ̇, kg·m²/s.

        Raises
        ------
        StateError
            If an argument is not a finite array of shape (n,) or (N, n).
        """
        C = self._run("coriolis", as_state(self.model, q, "q"), as_state(self.model, qd, "qd"))
        return C.reshape(C.shape[:-1] + (self.model.n, self.model.n))

    def forward_dynamics(self, q, qd, tau, friction=None) -> np.ndarray:
        """Θ̈ (6.115), shape (n,) or (N, n), as :func:`~course_dynamics.core.forward_dynamics.forward_dynamics`.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint positions Θ, rad (m for a prismatic joint).
        qd : array_like, shape (n,) or (N, n)
            Joint velocities Θ̇, rad/s (m/s).
        tau : array_like, shape (n,) or (N, n)
            Applied joint torques τ, N·m (N for a prismatic joint).
        friction : Friction, optional
            Subtracted from τ as F(Θ̇) (6.114); default none.

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            Joint accelerations Θ̈, rad/s² (m/s²).

        Raises
        ------
        StateError
            If an argument is not a finite array of shape (n,) or (N, n).
        SingularMassMatrixError
            If M(Θ) is singular (the error names the joint).
        """
        fast = self.native_call("forward_dynamics", q, qd, tau) if friction is None else None
        if fast is not None:
            return fast
        m = self.model
        q, qd, tau = as_state(m, q, "q"), as_state(m, qd, "qd"), as_state(m, tau, "tau")
        if friction is not None:
            tau = tau - friction.torques(qd)  # (6.114)
        return self.accelerations(q, qd, tau)

    def accelerations(self, q: np.ndarray, qd: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """Θ̈ for checked float arrays (n,) or (K, n): an AccelerationFunction for ``simulate``.

        Parameters
        ----------
        q : numpy.ndarray, shape (n,) or (K, n)
            Joint positions Θ, rad (m for a prismatic joint), float, already checked.
        qd : numpy.ndarray, shape (n,) or (K, n)
            Joint velocities Θ̇, rad/s (m/s).
        tau : numpy.ndarray, shape (n,) or (K, n)
            Applied joint torques τ, friction already subtracted, N·m (N for a prismatic joint).

        Returns
        -------
        numpy.ndarray, shape (n,) or (K, n)
            Joint accelerations Θ̈, rad/s² (m/s²).

        Raises
        ------
        SingularMassMatrixError
            If M(Θ) is singular (the error names the joint).
        """
        n = self.model.n
        fast = self.native_call("forward_dynamics", q, qd, tau)
        if fast is not None:  # one state, natively: the path of a simulation's every step
            return fast
        if self.loop is not None and "forward_dynamics" not in self.native:
            return self.loop.accelerations(q, qd, tau)
        try:
            with np.errstate(divide="ignore", invalid="ignore"):
                out = self._run("forward_dynamics", q, qd, tau)
        except ZeroDivisionError:  # a zero pivot: M is singular
            out = np.zeros(np.broadcast_shapes(q.shape, qd.shape, tau.shape)[:-1] + (2 * n,))
        pivots = out[..., n:]
        if not np.all(pivots.min(axis=-1) > SINGULAR_PIVOT_RATIO * np.abs(pivots).max(axis=-1)):

            return accelerations(self.model, q, qd, tau)  # raises SingularMassMatrixError, naming the joint
        return out[..., :n]


PROGRAMS = ("tau", "mass_matrix", "bias", "coriolis", "forward_dynamics", "regressor")
THREADS, THREAD_STATES = native.THREADS, native.THREAD_STATES  # how a native batch is shared (set them there)


@functools.cache
def _symmetric_index(n: int) -> np.ndarray:
    """For each entry of an n×n symmetric matrix, row by row, its place in the packed upper triangle."""
    packed = np.empty((n, n), dtype=np.intp)
    rows, cols = np.triu_indices(n)
    packed[rows, cols] = packed[cols, rows] = np.arange(len(rows))
    return packed.ravel()


def _functions_of(code, name: str) -> dict:
    namespace: dict = {"__name__": f"course_dynamics_compiled_{name}"}
    exec(code, namespace)  # our own program: just generated, or read back after its keyed hash was checked
    # every program the module holds (a regressor over its bound is not there)
    return {n: namespace[n] for p in PROGRAMS for n in (p, f"{p}_batch") if n in namespace}


def _agrees_with_the_recursion(model: Model, functions: dict, native_out: bool = False) -> bool:
    """Every compiled function at one random state against the interpreted recursions, to 1e-12 (``native_out``:
    the native functions, which fill an output array, for one state and for a batch of two)."""

    n = model.n
    q, qd, qdd = np.random.default_rng().uniform(-1, 1, (3, n))
    rows, cols = np.triu_indices(n)
    try:
        M, bias = mass_matrix_and_bias(model, q, qd)
        expected = {"tau": inverse_dynamics(model, q, qd, qdd), "mass_matrix": M[rows, cols], "bias": bias,
                    "coriolis": coriolis_matrix(model, q, qd).ravel(),
                    "forward_dynamics": np.linalg.solve(M, qdd - bias)}
        if "regressor" in functions:
            expected["regressor"] = regressor(model, q, qd, qdd).ravel()
        arguments = {"tau": (q, qd, qdd), "mass_matrix": (q,), "bias": (q, qd), "coriolis": (q, qd),
                     "forward_dynamics": (q, qd, qdd), "regressor": (q, qd, qdd)}
        for name, ours in expected.items():
            if native_out:
                ours = M.ravel() if name == "mass_matrix" else ours  # natively M comes whole
                size = native.width(name, n, model.n_bodies)
                got, pair = np.empty(size), np.empty((2, size))
                functions[name](*arguments[name], got)
                functions[name](*(np.stack([a, a]) for a in arguments[name]), pair)
                got, batch = got[:len(ours)], pair[1, :len(ours)]
            else:
                got = np.array(functions[name](*(a.tolist() for a in arguments[name])))[:len(ours)]
                out = functions[f"{name}_batch"](*(a[:, None] for a in arguments[name]))
                batch = np.array([np.broadcast_to(np.asarray(o, dtype=float), (1,))[0] for o in out])[:len(ours)]
            scale = 1 + np.abs(ours).max()
            if not (np.all(np.abs(got - ours) <= 1e-9 * scale) and np.all(np.abs(batch - ours) <= 1e-9 * scale)):
                return False
    except Exception:  # a garbled program: generate it again
        return False
    return True


def compile_model(model: Model, cache: bool = True, native_code: bool | None = True) -> CompiledModel:
    """Trace (or load from the cache) and compile the programs of ``model`` (module docstring).

    ``native_code``: True also builds the C version (native.py) where a compiler exists, waiting for it (a
    build is bounded and a failed one remembered: building.py), "background" builds it in a child process
    (``CompiledModel.native_build``; the evaluator takes it up), None uses one only if the cache holds it,
    False never; ``CompiledModel.native_reason`` says why there is none. Raises
    :class:`~course_dynamics.core.compiled.tracing.ProgramTooLargeError` for a robot too large to compile.

    Parameters
    ----------
    model : Model
        The robot; its gravity is built into the programs.
    cache : bool, optional
        Read the programs from the cache folder (:func:`~course_dynamics.core.compiled.cache.cache_folder`) and
        keep them there; False compiles in memory.
    native_code : bool or str or None, optional
        True: build the native library and wait for it; ``"background"``: build it in a child process; None:
        use one only if the cache holds it; False: never.

    Returns
    -------
    CompiledModel
        The compiled programs, checked against the interpreted recursions at a random state.

    Raises
    ------
    ProgramTooLargeError
        If the programs would take more than :data:`MAX_OPERATIONS` operations.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> ur5 = compile_model(load_robot("ur5"))
    >>> ur5.model.n, ur5.generation_seconds < 60
    (6, True)
    """
    start = time.perf_counter()
    key = model_key(model)
    with Cache(cache_folder() if cache else None) as store:
        entry = store.load(key)
        compiled = None
        if entry is not None:
            source, code = entry
            try:
                functions = _functions_of(code, key[:16])
            except Exception:  # a program that does not run: generate it again
                functions = None
            if functions is not None and _agrees_with_the_recursion(model, functions):
                compiled = CompiledModel(model, source, time.perf_counter() - start, True, store.path(key), functions)
        programs = None
        if compiled is None:
            programs = trace_programs(model)
            source = module_source(model, programs, key)
            code = compile(source, f"<compiled {key[:16]}>", "exec")
            functions = _functions_of(code, key[:16])
            stored = store.store(key, source, code)
            compiled = CompiledModel(model, source, time.perf_counter() - start, False, stored, functions)
        if native_code is not False:
            building.attach(compiled, programs, key, store, native_code, _agrees_with_the_recursion)
    return compiled


__all__ = ["CACHE_OFF", "MAX_OPERATIONS", "CacheWarning", "CompileWarning", "CompiledModel", "Program",
           "ProgramTooLargeError", "Tape", "Traced", "cache_folder", "compile_model", "model_key", "module_source",
           "program_source", "trace_programs"]

"""The native loop at run time: the extension built with the package, checked, behind a compiled model's methods.

The loop's C is the recursions' own steps (:mod:`~course_dynamics.core.compiled.steps`) looped over the bodies
of any robot. :func:`library` imports the extension built at installation (none where no compiler was there,
or with ``COURSE_DYNAMICS_NATIVE=off``, or one built from any other C than the shipped ``looped.c``);
:func:`looped` gives a model's :class:`Looped`, compared first with the recursions as written at a state drawn
from the model's own numbers; the evaluator (:mod:`~course_dynamics.core.evaluator`) chooses it.

=================  ==============================================================================
name               what
=================  ==============================================================================
:func:`library`    the installed extension, or None
:func:`why_not`    why the loop does not run here ("" where it does)
:class:`Looped`    τ, M and V + G natively (G and forward dynamics from them), the rest interpreted
:func:`looped`     a model's checked :class:`Looped`, or None
:func:`rollout`    a whole fixed-step simulation in native calls (:mod:`~course_dynamics.core.compiled.rollout`)
:func:`remember`   the one-state entry for a model (:mod:`~course_dynamics.core.compiled.entry`);
                   :func:`forget`, :func:`remembered`
=================  ==============================================================================
"""
from __future__ import annotations

import hashlib
import importlib
from dataclasses import dataclass, field

import numpy as np

from ..crba import mass_matrix as interpreted_mass_matrix
from ..drives import Drives
from ..dynamics import coriolis_matrix
from ..forward_dynamics import forward_dynamics as interpreted_forward_dynamics
from ..forward_dynamics import solve
from ..friction import Friction
from ..model import Model
from ..newton_euler import inverse_dynamics
from ..regressor import regressor
from ..state import as_state
from . import native
from .rollout import SCHEMES, STATUS
from .steps import SOURCE, model_array, source_digest


_LIBRARY: list = []  # the extension once imported (or None where it is not installed)


def library():
    """The installed native loop (its functions ``tau``, ``mass_matrix``, ``bias``), or None where it was not
    built (no compiler at installation) or native code is turned off (``COURSE_DYNAMICS_NATIVE=off``).

    Returns
    -------
    module or None
        ``course_dynamics.core.compiled._looped``.

    Examples
    --------
    >>> lib = library()
    >>> lib is None or sorted(name for name in ("tau", "mass_matrix", "bias") if hasattr(lib, name))
    ['bias', 'mass_matrix', 'tau']
    """
    if not native.enabled():
        return None
    if not _LIBRARY:
        try:
            module = importlib.import_module(f"{__package__}._looped")
            shipped = SOURCE.read_text(encoding="utf-8")
            _LIBRARY.append(module if module.SOURCE_SHA256 == source_digest(shipped) else None)  # or another C
        except (ImportError, AttributeError, OSError, ValueError):
            _LIBRARY.append(None)
    return _LIBRARY[0]


def why_not() -> str:
    """Why the native loop does not run here ("" where it does).

    Returns
    -------
    str
        "" where :func:`library` gives the extension; otherwise why not, in words.

    Examples
    --------
    >>> why_not() == "" or "COURSE_DYNAMICS_NATIVE" in why_not() or "not built" in why_not()
    True
    """
    if not native.enabled():
        return "native code is turned off (COURSE_DYNAMICS_NATIVE=off)"
    if library() is None:
        return ("the native loop was not built when the package was installed (no C compiler then), or was built "
                "from another version of the recursions (reinstall the package)")
    return ""


def remember(model: Model, run, environ: dict, names: tuple, writes: list):
    """Make the native entry (:mod:`~course_dynamics.core.compiled.entry`) run the model's one-state calls with
    ``run``'s C, for as long as the environment's values of ``names`` and the cache's writes are what they are now.

    Parameters
    ----------
    model : Model
        The robot (the entry is for this very object).
    run : object
        The compiled model or the :class:`Looped` the evaluator chose (:func:`terms` says what the C runs).
    environ : dict
        ``os.environ``'s own dict of encoded names and values.
    names : tuple of bytes
        The encoded names the choice depends on.
    writes : list
        The cache's one-item list of its count of writes.

    Returns
    -------
    callable or None
        The entry, ``one(model, code, *arrays)`` (a code of
        :data:`~course_dynamics.core.compiled.entry.PROGRAMS`), or None where there is no native entry or run
        has no C.

    Examples
    --------
    >>> import os
    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> one = remember(arm, looped(arm), os.environ._data, (b"HOME",), [0])
    >>> one is None or one(arm, 0, np.zeros(2), np.zeros(2), np.zeros(2)).round(6)
    array([18.639,  3.924])
    """
    lib, source = library(), terms(run)
    if lib is None or source is None:
        return None
    lib.remember(model, run, source, environ, names, writes, np.empty)
    return lib.one


def forget(model_id: int) -> None:
    """The native entry of the model of this id, forgotten (whether native code is on or not).

    Parameters
    ----------
    model_id : int
        ``id(model)``.

    Examples
    --------
    >>> forget(0)
    """
    function = getattr(_LIBRARY[0], "forget", None) if _LIBRARY else None
    if callable(function):  # not while the interpreter shuts down, emptying the modules
        function(model_id)


def remembered(model: Model):
    """What the native entry runs this model's one-state calls with, or None (the checked path runs them).

    Parameters
    ----------
    model : Model
        The robot.

    Returns
    -------
    object or None
        The compiled model or :class:`Looped` the evaluator remembered.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> remembered(load_robot("two_link")) is None
    True
    """
    lib = _LIBRARY[0] if _LIBRARY else None
    return None if lib is None else lib.remembered(model)


@dataclass(frozen=True)
class Looped:
    """The native loop behind the methods a compiled model has: τ, M and V + G natively for float64 states,
    the rest (and anything else) by the recursions as written.

    Made by :func:`looped` (which checks it against the recursions first).

    Parameters
    ----------
    model : Model
        The robot.
    array : numpy.ndarray
        Its :func:`~course_dynamics.core.compiled.steps.model_array`.
    native : dict
        The native loop's functions by program name (``tau``, ``mass_matrix``, ``bias``).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> run = looped(arm)
    >>> run is None or np.allclose(run.mass_matrix([0.0, 0.5]), interpreted_mass_matrix(arm, [0.0, 0.5]), rtol=1e-12)
    True
    """

    model: Model
    array: np.ndarray = field(repr=False)
    native: dict = field(repr=False, default_factory=dict)

    def native_call(self, name: str, *arrays) -> np.ndarray | None:
        """What the method ``name`` returns for one state of finite float64 values (n,) each, from the native
        loop; None for anything else (the checked path then sees it).

        Parameters
        ----------
        name : str
            ``tau``, ``mass_matrix`` or ``bias`` (None for any other).
        *arrays : numpy.ndarray, shape (n,)
            Its inputs, in order.

        Returns
        -------
        numpy.ndarray or None
            τ or V + G, shape (n,); M, shape (n, n); or None.
        """
        function = self.native.get(name)
        if function is None:
            return None
        for a in arrays:
            if type(a) is not np.ndarray or a.ndim != 1:
                return None
        n = self.model.n
        out = np.empty(native.width(name, n))
        try:
            function(self.array, *arrays, out)
        except (TypeError, ValueError, BufferError):
            return None
        return out.reshape(n, n) if name == "mass_matrix" else out

    def batch(self, name: str, *arrays: np.ndarray) -> np.ndarray | None:
        """The loop's program ``name`` on checked states of any batch shape, its entries a state flat (M whole,
        n × n); None where the loop has no such program or a state is not float64.

        Parameters
        ----------
        name : str
            ``tau``, ``mass_matrix`` or ``bias``.
        *arrays : numpy.ndarray, shape (..., n)
            Its inputs, in order, already checked.

        Returns
        -------
        numpy.ndarray, shape (..., width) or None
            τ or V + G (width n); M (width n²).
        """
        function = self.native.get(name)
        if function is None or not all(a.dtype == np.float64 for a in arrays):
            return None
        return native.run_batch(function, arrays, native.width(name, self.model.n), (self.array,))

    def _run(self, name: str, *arrays: np.ndarray) -> np.ndarray | None:
        out = self.batch(name, *arrays)
        if out is None or name != "mass_matrix":
            return out
        return out.reshape(out.shape[:-1] + (self.model.n, self.model.n))

    def inverse_dynamics(self, q, qd, qdd) -> np.ndarray:
        """τ, as :func:`~course_dynamics.core.newton_euler.inverse_dynamics`.

        Parameters
        ----------
        q, qd, qdd : array_like, shape (n,) or (N, n)
            Θ, Θ̇ and Θ̈, rad, rad/s, rad/s² (m, m/s, m/s²).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            τ, N·m (N).
        """
        m = self.model
        q, qd, qdd = as_state(m, q, "q"), as_state(m, qd, "qd"), as_state(m, qdd, "qdd")
        out = self._run("tau", q, qd, qdd)
        return inverse_dynamics(m, q, qd, qdd) if out is None else out

    def mass_matrix(self, q) -> np.ndarray:
        """M(Θ), as :func:`~course_dynamics.core.crba.mass_matrix`.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Θ, rad (m).

        Returns
        -------
        numpy.ndarray, shape (n, n) or (N, n, n)
            M, kg·m² (kg).
        """
        q = as_state(self.model, q, "q")
        out = self._run("mass_matrix", q)
        return interpreted_mass_matrix(self.model, q) if out is None else out

    def bias(self, q, qd) -> np.ndarray:
        """V(Θ, Θ̇) + G(Θ) = τ(Θ, Θ̇, 0).

        Parameters
        ----------
        q, qd : array_like, shape (n,) or (N, n)
            Θ and Θ̇, rad and rad/s (m, m/s).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            V + G, N·m (N).
        """
        m = self.model
        q, qd = as_state(m, q, "q"), as_state(m, qd, "qd")
        out = self._run("bias", q, qd)
        return inverse_dynamics(m, q, qd, np.zeros_like(qd)) if out is None else out

    def gravity_torques(self, q) -> np.ndarray:
        """G(Θ) = V + G at Θ̇ = 0.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Θ, rad (m).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            G, N·m (N).
        """
        q = as_state(self.model, q, "q")
        return self.bias(q, np.zeros_like(q))

    def coriolis_matrix(self, q, qd) -> np.ndarray:
        """C(Θ, Θ̇) by the recursions as written (the loop has no program for it).

        Parameters
        ----------
        q, qd : array_like, shape (n,) or (N, n)
            Θ and Θ̇.

        Returns
        -------
        numpy.ndarray, shape (n, n) or (N, n, n)
            C, kg·m²/s.
        """
        return coriolis_matrix(self.model, q, qd)

    def regressor(self, q, qd, qdd) -> np.ndarray:
        """Y(Θ, Θ̇, Θ̈) by the recursions as written (the loop has no program for it).

        Parameters
        ----------
        q, qd, qdd : array_like, shape (n,) or (N, n)
            Θ, Θ̇ and Θ̈.

        Returns
        -------
        numpy.ndarray, shape (n, 10 n_bodies) or (N, n, 10 n_bodies)
            Y, with τ = Y π.
        """
        return regressor(self.model, q, qd, qdd)

    def forward_dynamics(self, q, qd, tau, friction: Friction | None = None) -> np.ndarray:
        """Θ̈ (6.115), as :func:`~course_dynamics.core.forward_dynamics.forward_dynamics`: M and V + G from the
        loop, then the same checked solve.

        Parameters
        ----------
        q, qd, tau : array_like, shape (n,) or (N, n)
            Θ, Θ̇ and the applied τ.
        friction : Friction, optional
            Subtracted from τ as F(Θ̇).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            Θ̈, rad/s² (m/s²).

        Raises
        ------
        SingularMassMatrixError
            If M(Θ) is singular (the error names the joint).
        """
        m = self.model
        q, qd, tau = as_state(m, q, "q"), as_state(m, qd, "qd"), as_state(m, tau, "tau")
        if friction is not None:
            tau = tau - friction.torques(qd)  # (6.114)
        if not all(a.dtype == np.float64 for a in (q, qd, tau)):
            return interpreted_forward_dynamics(m, q, qd, tau)
        return self.accelerations(q, qd, tau)

    def accelerations(self, q: np.ndarray, qd: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """Θ̈ without friction for checked float arrays: an AccelerationFunction for ``simulate``.

        Parameters
        ----------
        q, qd, tau : numpy.ndarray, shape (n,) or (K, n)
            Θ, Θ̇ and τ, float64, already checked.

        Returns
        -------
        numpy.ndarray, shape (n,) or (K, n)
            Θ̈, rad/s² (m/s²).

        Raises
        ------
        SingularMassMatrixError
            If M(Θ) is singular.
        """
        M, bias = self._run("mass_matrix", q), self._run("bias", q, qd)
        return solve(self.model, M, tau - bias, q)  # (6.115)


def looped(model: Model) -> Looped | None:
    """The native loop for ``model``, checked first against the recursions as written: τ, M and V + G at a state
    drawn from the model's own numbers (so the same in every process), one state and a batch of two, each to
    1e-9 of its size, or 1e-12 of the three's largest (V + G is zero on a robot that gravity does not load); None
    where the loop does not run here (:func:`why_not`), for a model with symbols, or where it disagrees.

    Parameters
    ----------
    model : Model
        The robot.

    Returns
    -------
    Looped or None
        What runs the loop for this model (its model array read-only).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> run = looped(load_robot("ur5"))
    >>> run is None or run.native_call("tau", np.zeros(6), np.zeros(6), np.zeros(6)).shape
    (6,)
    """
    lib = library()
    if lib is None:
        return None
    try:
        array = model_array(model)
    except (TypeError, ValueError):  # symbols: no float numbers to loop over
        return None
    array.setflags(write=False)
    run = Looped(model, array, {"tau": lib.tau, "mass_matrix": lib.mass_matrix, "bias": lib.bias})
    seed = int.from_bytes(hashlib.sha256(array.tobytes()).digest()[:8], "little")
    q, qd, qdd = np.random.default_rng(seed).uniform(-1, 1, (3, model.n))
    expected = {"tau": (inverse_dynamics(model, q, qd, qdd), (q, qd, qdd)),
                "mass_matrix": (interpreted_mass_matrix(model, q), (q,)),
                "bias": (inverse_dynamics(model, q, qd, 0 * qd), (q, qd))}
    largest = max(np.abs(ours).max() for ours, _ in expected.values())
    try:
        for name, (ours, arguments) in expected.items():
            one = run.native_call(name, *arguments)
            two = run._run(name, *(np.stack([a, a]) for a in arguments))
            tolerance = max(1e-9 * np.abs(ours).max(), 1e-12 * largest, np.finfo(float).tiny)
            if one is None or not (np.abs(one - ours).max() <= tolerance and np.abs(two - ours).max() <= tolerance):
                return None
    except (TypeError, ValueError, BufferError):
        return None
    return run


#: Forward-dynamics evaluations in one native call of a run (between calls, progress is told and Ctrl-C heard).
CHUNK_EVALUATIONS = 100_000
#: Forward-dynamics evaluations a step of each native integrator takes.
EVALUATIONS = {"euler": 1, "semi-implicit": 1, "rk4": 4}


@dataclass(frozen=True)
class Rolled:
    """A run from :func:`rollout`: the samples, and where it stopped if it failed.

    Parameters
    ----------
    q, qd, qdd, tau : numpy.ndarray, shape (T, n) or (T, K, n)
        Θ (rad, m), Θ̇ (rad/s, m/s), Θ̈ (rad/s², m/s²) and the applied τ (N·m, N) at every sample.
    failure : str
        "" for a whole run; else "not finite", "singular" or "torque not finite"
        (:data:`~course_dynamics.core.compiled.rollout.STATUS`), the earliest in time of the members'.
    t : float
        Where it failed: the time of the failing evaluation, s.
    state : numpy.ndarray, shape (3, n)
        There: Θ, Θ̇ and τ − F(Θ̇) (the applied τ where the torque was not finite).
    member : int
        There: the ensemble's member (0 for one run; the first of those failing at that time).
    reaction : numpy.ndarray, shape (T, n) or (T, K, n), optional
        With joint stops: the held joints' reaction λ as each step began, N·m (N).
    stops : numpy.ndarray, shape (S, 4 + 2n), optional
        With joint stops: the stops found, one row each
        (:data:`~course_dynamics.core.compiled.impulses.STOP_RECORD`), by time and member.

    Examples
    --------
    >>> done = Rolled(*np.zeros((4, 2, 1)))
    >>> done.failure == "" and done.q.shape
    (2, 1)
    """

    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    tau: np.ndarray
    failure: str = ""
    t: float = 0.0
    state: np.ndarray | None = None
    member: int = 0
    reaction: np.ndarray | None = None
    stops: np.ndarray | None = None


def terms(run):
    """What a native run computes M and V + G with, for an implementation the evaluator gave: a compiled
    model's own C (the capsule of its library), else the native loop's model array; None for neither.

    Parameters
    ----------
    run : object
        A :class:`Looped`, a :class:`~course_dynamics.core.compiled.CompiledModel`, or the recursions as written.

    Returns
    -------
    object or None
        The capsule or the model array.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> source = terms(looped(load_robot("two_link")))
    >>> source is None or source.shape
    (192,)
    """
    own = getattr(run, "native", None) or {}
    if "terms" in own:
        return own["terms"]
    loop = run if isinstance(run, Looped) else getattr(run, "loop", None)
    return None if loop is None else loop.array


def rollout(run, times: np.ndarray, q0: np.ndarray, qd0: np.ndarray, integrator: str, torque_times: np.ndarray,
            torques: np.ndarray, friction: Friction | None = None, drives: Drives | None = None,
            progress=None, stops: tuple[np.ndarray, np.ndarray, float] | None = None) -> Rolled | None:
    """A fixed-step simulation natively, from its first sample to its last
    (:mod:`~course_dynamics.core.compiled.rollout`).

    Parameters
    ----------
    run : object
        What the evaluator gave for the run (:func:`terms` says what the C computes with).
    times : numpy.ndarray, shape (T,)
        The samples, s, increasing (T ≥ 2).
    q0, qd0 : numpy.ndarray, shape (n,) or (K, n)
        Θ and Θ̇ at the first sample (an ensemble of K members).
    integrator : str
        ``euler``, ``semi-implicit`` or ``rk4``.
    torque_times : numpy.ndarray, shape (R,)
        The applied torques' times, s, increasing (one row: held all along).
    torques : numpy.ndarray, shape (R, n)
        The applied torques there, N·m (N): linear in time between rows, held outside them.
    friction : Friction, optional
        Taken off τ (6.114).
    drives : Drives, optional
        Rotor inertias on M's diagonal, offsets added to the bias.
    progress : callable, optional
        Called with the steps each native call took.
    stops : tuple, optional
        Joint stops (:mod:`~course_dynamics.core.compiled.stopping`,
        :mod:`~course_dynamics.core.compiled.impulses`): the lower and upper limits a stop holds, shape (n,)
        each, rad (m; ∓inf for a joint without), and the run's step dt, s.

    Returns
    -------
    Rolled or None
        The run; None where it cannot be native (no native library, no terms, another integrator).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.evaluator import implementation
    >>> arm = load_robot("pendulum")
    >>> times = np.arange(3) * 1e-3
    >>> run = rollout(implementation(arm, calls=12), times, np.array([0.5]), np.zeros(1), "rk4", np.zeros(1),
    ...               np.zeros((1, 1)))
    >>> run is None or (run.q.shape, run.failure)
    ((3, 1), '')
    """
    lib, source = library(), terms(run)
    if lib is None or source is None or integrator not in SCHEMES:
        return None
    n, members = q0.shape[-1], 1 if q0.ndim == 1 else len(q0)
    zero = np.zeros(n)
    parameters = np.concatenate([[0.0 if friction is None else friction.smoothing],
                                 zero if friction is None else friction.viscous,
                                 zero if friction is None else friction.coulomb,
                                 zero if drives is None else drives.armature,
                                 zero if drives is None else drives.offset])
    table = np.ascontiguousarray(np.column_stack([torque_times, torques]), dtype=np.float64)
    times = np.ascontiguousarray(times, dtype=np.float64)
    q, qd, qdd, tau = (np.empty((len(times),) + q0.shape) for _ in range(4))
    q[0], qd[0] = q0, qd0
    extra, found = (), []
    if stops is not None:  # the joints held (the C's state between chunks) and their reaction, the bounds, the stops
        held, reaction = np.zeros((len(times),) + q0.shape), np.zeros((len(times),) + q0.shape)
        extra = (held, reaction, np.concatenate([[stops[2]], stops[0], stops[1]]).astype(np.float64), found)
    chunk = max(1, CHUNK_EVALUATIONS // (members * EVALUATIONS[integrator]))
    parts = max(1, min(native.THREADS, members, members * chunk // native.THREAD_STATES))
    bounds = np.linspace(0, members, parts + 1).astype(int)
    status = np.zeros((parts, 3 + 3 * n))

    def call(k0: int, k1: int, part: int) -> int:
        return lib.rollout(source, times, q, qd, qdd, tau, table, parameters, status[part], SCHEMES[integrator],
                           k0, k1, int(bounds[part]), int(bounds[part + 1]), *extra)

    for k0 in range(0, len(times) - 1, chunk):
        k1 = min(len(times) - 1, k0 + chunk)
        codes = [call(k0, k1, 0)] if parts == 1 else list(native.pool().map(lambda p: call(k0, k1, p), range(parts)))
        if any(codes):
            first = min((p for p in range(parts) if codes[p]), key=lambda p: (status[p, 2], status[p, 1]))
            row = status[first]
            return Rolled(q, qd, qdd, tau, STATUS[codes[first]], float(row[2]), row[3:].reshape(3, n).copy(),
                          int(row[1]))
        if progress is not None:
            progress(k1 - k0)
    if stops is None:
        return Rolled(q, qd, qdd, tau)
    rows = np.frombuffer(b"".join(found), dtype=np.float64).reshape(-1, 4 + 2 * n)
    rows = rows[np.lexsort((rows[:, 1], rows[:, 0]))]
    return Rolled(q, qd, qdd, tau, reaction=reaction, stops=rows)


__all__ = ["CHUNK_EVALUATIONS", "EVALUATIONS", "Looped", "Rolled", "forget", "library", "looped", "remember",
           "remembered", "rollout", "terms", "why_not"]

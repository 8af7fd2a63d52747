"""The one evaluator: for a model and a call, the implementation that runs it, chosen by one rule.

Three implementations compute every term: the recursions as written (:mod:`~course_dynamics.core.newton_euler`,
:mod:`~course_dynamics.core.crba`, …, the text a student reads; they take one state, a batch, sympy symbols,
dual or complex numbers); the native loop (:mod:`~course_dynamics.core.compiled.looped`: each body's step of
those recursions traced once into C, built with the package where a compiler was, looped over the bodies of
any robot: τ, M and V + G of float64 states, the rest as written); and the compiled programs traced from them
for one robot (:mod:`~course_dynamics.core.compiled`; float states only, agreeing to 1e-12). Which one runs
is chosen here and nowhere else, by :func:`choice`: for the package's own functions
(``course_dynamics.inverse_dynamics``, ``mass_matrix``, ``coriolis_matrix``, ``gravity_torques``,
``forward_dynamics``, :func:`regressor`), ``simulate``, a log's torques, an excitation, an identification, a payload.

The rule depends on the call (its numbers, the work it asks), the model and what the compiled-model cache
holds; never on how many calls came before ("else": no loop installed, or ``COURSE_DYNAMICS_NATIVE=off``):

====================================================  =========================================================
the call                                              runs
====================================================  =========================================================
``compiled=False`` (``--no-compile``)                 the recursions as written
symbols, duals, complex numbers                       the recursions as written (the programs take floats only)
a robot too large to compile                          the native loop, else the recursions (one ``CompileWarning``)
``compiled=True``                                     the compiled model, waiting for its native build
floats, and the cache holds the compiled model        the compiled model, loaded from the cache
floats, work of :data:`COMPILE_SECONDS` or more       the compiled model, compiled now (and kept in the cache)
floats, less work, the cache does not hold it         the native loop, else the recursions vectorised over a batch
====================================================  =========================================================

"Work" is an estimate of what the interpreted recursions would take for this call alone — :data:`CALL_SECONDS`
a call plus :data:`STATE_SECONDS` a state of a batch (:func:`interpreted_seconds`); a tool whose calls are known
in advance (a simulation's steps, a log's blocks) asks once for all of them. :data:`COMPILE_SECONDS` is about
what loading a compiled model from a warm cache costs: a batch of about 20 000 states, 100 Euler steps.
"The cache holds it": ``<key>.entry`` is in the cache folder
(:func:`~course_dynamics.core.compiled.cache.cache_folder`; with ``COURSE_DYNAMICS_CACHE=off`` it never does), or
this process loaded it from there or stored it there. So the same call on the same model runs the same code
whatever ran before, as long as the cache holds the same; a loop of one-state calls runs C from its first call
(the loop, or the compiled model once compiled, in this process or an earlier one). Built objects are kept in
this process by the model's content (:func:`~course_dynamics.core.compiled.model_key`) and cache folder.

The compiled model runs as C where a compiler exists (:mod:`~course_dynamics.core.compiled.native`) and the
cache holds its library; a call of work :data:`NATIVE_SECONDS` or more (a long simulation) starts its build in
the background (:mod:`~course_dynamics.core.compiled.building`: bounded, never tried again once it failed). Until a
choice finds the library (never in the middle of a call; looked for after this process built or loaded one, else
once a second) the loop stands in for its τ, M and V + G (``CompiledModel.loop``). A one-state call of finite
float64 values whose choice runs C goes straight to it, checks and all (:mod:`~course_dynamics.core.compiled.entry`:
the choice remembered for the model object, the environment and the cache's content as this process knows it).

>>> import numpy as np
>>> from course_dynamics import load_robot
>>> g = -9.81 - np.random.default_rng().uniform(0, 1e-3)             # numbers no cache holds yet
>>> arm = load_robot("two_link").with_gravity([0, 0, g])
>>> choice(arm, calls=1, states=10).path in ("loop", "interpreted"), choice(arm, calls=1000).path   # a little; more
(True, 'compiled')
>>> choice(arm, calls=1, states=10).reason                           # and from now on: the cache holds it
'the cache holds its compiled model'
>>> q = np.array([0.1, 0.2])
>>> np.allclose(implementation(arm).inverse_dynamics(q, q, q), newton_euler.inverse_dynamics(arm, q, q, q), rtol=1e-12)
True
"""
from __future__ import annotations

import dataclasses
import os
import time
import warnings
import weakref
from dataclasses import dataclass, field

import numpy as np

from . import dynamics
from . import forward_dynamics as interpreted_forward
from . import newton_euler
from . import regressor as interpreted_regressor
from .compiled import CompiledModel, CompileWarning, ProgramTooLargeError, cache_folder, compile_model, model_key
from .compiled.building import BUSY_SECONDS, may_be_built
from .compiled.cache import WRITES
from .compiled.entry import PROGRAMS
from .compiled.looped import Looped, forget, looped, remember
from .compiled.native import enabled as native_enabled
from .drives import Driven, Drives
from .friction import Friction
from .model import Model
from .state import as_state, batch_shape

#: The interpreted recursions' cost of one call, s (UR5 0.26 ms for τ at one state).
CALL_SECONDS = 3e-4
#: The interpreted recursions' cost of one more state in a vectorised batch, s (UR5 13 ms for τ at 10 000 states).
STATE_SECONDS = 1.5e-6
#: What loading a compiled model from a warm cache costs, s (two-link 10 ms, UR5 25 ms, Panda 50 ms).
COMPILE_SECONDS = 0.03
#: The work, s, that pays for building the C version once (UR5 about 3 s, then cached).
NATIVE_SECONDS = 1.0
#: The most states the interpreted recursions take at once; a larger batch is computed in blocks of this many.
BLOCK_STATES = 8192
#: The work of one regressor call in τ calls, interpreted (UR5 takes 1.9 ms a call and 0.12 ms a state of a batch).
REGRESSOR_WORK = 80

ASKED = "asked for"
NOT_FLOATS = "symbols, duals or complex numbers: the compiled programs take float64 only"
CACHED = "the cache holds its compiled model"
PAYS = "this call's work pays for compiling it"
LITTLE = "little work, and the cache does not hold its compiled model"


@dataclass(frozen=True)
class Interpreted:
    """The recursions as written, behind a compiled model's methods: what a choice of "interpreted" runs.

    Each method takes what the function of the same name takes, without the model.

    Parameters
    ----------
    model : Model
        The robot.
    native : dict, optional
        Empty: the recursions have no native code (as a compiled model without C).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> np.round(Interpreted(load_robot("two_link")).gravity_torques([0.0, 0.0]), 6)
    array([18.639,  3.924])
    """

    model: Model
    native: dict = field(default_factory=dict, repr=False)  # none: as a compiled model without C

    def inverse_dynamics(self, q, qd, qdd) -> np.ndarray:
        """τ by :func:`~course_dynamics.core.newton_euler.inverse_dynamics`.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint positions Θ, rad (m).
        qd : array_like, shape (n,) or (N, n)
            Joint velocities Θ̇, rad/s (m/s).
        qdd : array_like, shape (n,) or (N, n)
            Joint accelerations Θ̈, rad/s² (m/s²).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            Joint torques τ, N·m (N).
        """
        return newton_euler.inverse_dynamics(self.model, q, qd, qdd)

    def regressor(self, q, qd, qdd) -> np.ndarray:
        """Y by :func:`~course_dynamics.core.regressor.regressor`.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint positions Θ, rad (m).
        qd : array_like, shape (n,) or (N, n)
            Joint velocities Θ̇, rad/s (m/s).
        qdd : array_like, shape (n,) or (N, n)
            Joint accelerations Θ̈, rad/s² (m/s²).

        Returns
        -------
        numpy.ndarray, shape (n, 10 n_bodies) or (N, n, 10 n_bodies)
            Y, with τ = Y π.
        """
        return interpreted_regressor.regressor(self.model, q, qd, qdd)

    def mass_matrix(self, q) -> np.ndarray:
        """M(Θ) by :func:`~course_dynamics.core.dynamics.mass_matrix`.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint positions Θ, rad (m).

        Returns
        -------
        numpy.ndarray, shape (n, n) or (N, n, n)
            M(Θ), kg·m² (kg).
        """
        return dynamics.mass_matrix(self.model, q)

    def coriolis_matrix(self, q, qd) -> np.ndarray:
        """C(Θ, Θ̇) by :func:`~course_dynamics.core.dynamics.coriolis_matrix`.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint positions Θ, rad (m).
        qd : array_like, shape (n,) or (N, n)
            Joint velocities Θ̇, rad/s (m/s).

        Returns
        -------
        numpy.ndarray, shape (n, n) or (N, n, n)
            C(Θ, Θ̇), kg·m²/s.
        """
        return dynamics.coriolis_matrix(self.model, q, qd)

    def gravity_torques(self, q) -> np.ndarray:
        """G(Θ) by :func:`~course_dynamics.core.dynamics.gravity_torques`.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint positions Θ, rad (m).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            G(Θ), N·m (N).
        """
        return dynamics.gravity_torques(self.model, q)

    def bias(self, q, qd) -> np.ndarray:
        """V(Θ, Θ̇) + G(Θ) = τ(Θ, Θ̇, 0), by Newton–Euler.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint positions Θ, rad (m).
        qd : array_like, shape (n,) or (N, n)
            Joint velocities Θ̇, rad/s (m/s).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            V + G, N·m (N).
        """
        qd = as_state(self.model, qd, "qd")
        return newton_euler.inverse_dynamics(self.model, q, qd, np.zeros_like(qd))

    def forward_dynamics(self, q, qd, tau, friction: Friction | None = None) -> np.ndarray:
        """Θ̈ by :func:`~course_dynamics.core.forward_dynamics.forward_dynamics`.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint positions Θ, rad (m).
        qd : array_like, shape (n,) or (N, n)
            Joint velocities Θ̇, rad/s (m/s).
        tau : array_like, shape (n,) or (N, n)
            Joint torques τ, N·m (N).
        friction : Friction, optional
            Subtracted from τ as F(Θ̇); default none.

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            Θ̈, rad/s² (m/s²).
        """
        return interpreted_forward.forward_dynamics(self.model, q, qd, tau, friction)

    def accelerations(self, q: np.ndarray, qd: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """Θ̈ without friction for checked float arrays, by
        :func:`~course_dynamics.core.forward_dynamics.accelerations`.

        Parameters
        ----------
        q : numpy.ndarray, shape (n,) or (N, n)
            Joint positions Θ, rad (m).
        qd : numpy.ndarray, shape (n,) or (N, n)
            Joint velocities Θ̇, rad/s (m/s).
        tau : numpy.ndarray, shape (n,) or (N, n)
            Joint torques τ, N·m (N).

        Returns
        -------
        numpy.ndarray, shape (n,) or (N, n)
            Θ̈, rad/s² (m/s²).
        """
        return interpreted_forward.accelerations(self.model, q, qd, tau)


@dataclass(frozen=True)
class Choice:
    """What :func:`choice` chose: ``path`` "interpreted" or "compiled", ``reason`` (the row of the module
    docstring's table), and ``run``, the :class:`Interpreted` recursions or the
    :class:`~course_dynamics.core.compiled.CompiledModel` that runs the call.

    Parameters
    ----------
    path : str
        ``"interpreted"`` or ``"compiled"``.
    reason : str
        Why, in words (a row of the module docstring's table).
    run : Interpreted or CompiledModel
        What runs the call.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> chosen = choice(load_robot("two_link"), floats=False)
    >>> chosen.path, type(chosen.run).__name__, chosen.native
    ('interpreted', 'Interpreted', False)
    """

    path: str
    reason: str
    run: Interpreted | CompiledModel = field(repr=False, compare=False)

    @property
    def native(self) -> bool:
        """Whether C runs the call (the native loop, or a compiled model with its C or the loop standing in)."""
        return bool(self.run.native) or getattr(self.run, "loop", None) is not None


@dataclass
class _Compiled:
    """One model content's compiled model in this process, or why there is none."""

    compiled: CompiledModel | None = None
    too_large: str = ""
    warned: bool = False  # the recursions ran it, too large to compile, after a warning
    native_tried: bool = False  # a native build was asked for (the cache holds no library, or it is building)
    look_again: float = 0.0  # when to look in the cache again for C it did not hold (time.monotonic())
    seen: int = -1  # the cache's WRITES when it last looked


_KEYS: dict[int, tuple[weakref.ref, str]] = {}                  # id(model) -> its model_key
_COMPILED: dict[tuple[str, str], _Compiled] = {}                # (cache folder, model_key) -> what was built
_FOLDERS: dict[tuple, object] = {}                              # the environment -> its cache folder
_LOOPS: dict[str, Looped | None] = {}                           # model_key -> its checked native loop, or None


_NAMES = ("COURSE_DYNAMICS_CACHE", "XDG_CACHE_HOME", "HOME", "COURSE_DYNAMICS_NATIVE")  # cache_folder(); native
try:  # CPython's dict behind os.environ, read without decoding: the one-state shortcut asks on every call
    _RAW, _RAW_NAMES = os.environ._data, tuple(map(os.environ.encodekey, _NAMES))
except AttributeError:
    _RAW = None


def _environment() -> tuple:
    """What the cache folder is chosen from, as it is now."""
    if _RAW is None:
        return tuple(map(os.environ.get, _NAMES))
    raw = _RAW.get
    return raw(_RAW_NAMES[0]), raw(_RAW_NAMES[1]), raw(_RAW_NAMES[2]), raw(_RAW_NAMES[3])


def _key(model: Model) -> str:
    known = _KEYS.get(id(model))
    if known is None or known[0]() is not model:
        known = (weakref.ref(model, lambda _, i=id(model): (_KEYS.pop(i, None), forget(i))), model_key(model))
        _KEYS[id(model)] = known
    return known[1]


def interpreted_seconds(calls: int, states: int) -> float:
    """The estimated time of ``calls`` interpreted calls on ``states`` states each, s.

    Parameters
    ----------
    calls : int
        The number of calls.
    states : int
        The number of states of each call (1 for one state, N for a batch).

    Returns
    -------
    float
        ``calls`` × (:data:`CALL_SECONDS` + ``states`` × :data:`STATE_SECONDS`), s.

    Examples
    --------
    >>> round(interpreted_seconds(calls=1000, states=1), 4)   # a simulation's worth of one-state calls, s
    0.3015
    """
    return calls * (CALL_SECONDS + states * STATE_SECONDS)


def choice(model: Model, calls: int = 1, states: int = 1, floats: bool = True, compiled: bool | None = None) -> Choice:
    """The implementation of ``calls`` calls on ``states`` states each (float64 unless ``floats`` is False), by
    the rule of the module docstring; ``compiled`` True or False overrides it (True raises
    :class:`~course_dynamics.core.compiled.tracing.ProgramTooLargeError` for a robot too large to compile).

    Parameters
    ----------
    model : Model
        The robot.
    calls : int, optional
        The number of calls the choice is for (a simulation's steps, a log's blocks).
    states : int, optional
        The number of states of each call.
    floats : bool, optional
        Whether the states are float64 (False for symbols, duals, complex numbers).
    compiled : bool, optional
        True for the compiled model, False for the recursions as written; None (the default) lets the rule of
        the module docstring choose.

    Returns
    -------
    Choice
        The path, the reason and what runs.

    Raises
    ------
    ProgramTooLargeError
        With ``compiled=True``, for a robot too large to compile.

    Warns
    -----
    CompileWarning
        Once, when the rule would compile a robot too large to compile (the recursions as written run).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> arm = load_robot("two_link")
    >>> choice(arm, compiled=False)
    Choice(path='interpreted', reason='asked for')
    >>> choice(arm, floats=False).reason
    'symbols, duals or complex numbers: the compiled programs take float64 only'
    """
    if compiled is False or not floats:
        return Choice("interpreted", ASKED if compiled is False else NOT_FLOATS, Interpreted(model))
    environment = _environment()
    folder = _FOLDERS.get(environment[:3])
    if folder is None:
        folder = _FOLDERS[environment[:3]] = str(cache_folder() or "")
    work = interpreted_seconds(calls, states)
    if not (folder or compiled or work >= COMPILE_SECONDS):
        return _uncompiled(model, LITTLE, environment)  # no cache to hold it
    key = _key(model)
    known = _COMPILED.setdefault((folder, key), _Compiled())
    if known.too_large and not compiled:
        return _uncompiled(model, known.too_large, environment, known)
    if compiled:
        reason = ASKED
    elif folder and ((known.compiled is not None and known.compiled.path is not None)
                     or os.path.exists(os.path.join(folder, f"{key}.entry"))):
        reason = CACHED
    elif work >= COMPILE_SECONDS:
        reason = PAYS
    else:
        return _uncompiled(model, LITTLE, environment)
    native = True if compiled else ("background" if work >= NATIVE_SECONDS else None)
    if known.compiled is not None and known.compiled.native_build is not None:
        known.compiled = known.compiled.collected()  # a new CompiledModel once its library is built
    elif known.compiled is not None and (known.seen != WRITES[0] or time.monotonic() >= known.look_again):
        known.look_again, known.seen = time.monotonic() + BUSY_SECONDS, WRITES[0]  # after a write, or 1 s on
        if may_be_built(known.compiled.native_reason, folder, key):  # its C, in the cache since the last look
            known.compiled = compile_model(model, native_code=native)
    if known.compiled is None or (native and not known.native_tried and not known.compiled.native):
        try:
            known.compiled, known.seen = compile_model(model, native_code=native), WRITES[0]
        except ProgramTooLargeError as error:
            if compiled:
                raise
            known.too_large = str(ProgramTooLargeError(error.what, ""))
            return _uncompiled(model, known.too_large, environment, known)
        known.native_tried = known.native_tried or bool(native)
    run = known.compiled
    if (run.native or run.loop is not None) and not native_enabled():  # turned off since: its Python programs
        run = dataclasses.replace(run, native={}, loop=None, _calls={})
    elif not run.native and run.loop is None and (loop := _loop(model)) is not None:
        run = known.compiled = dataclasses.replace(run, loop=loop)  # the loop stands in for its C
    return _remembered(model, Choice("compiled", reason, run), environment)


def _loop(model: Model) -> Looped | None:
    """The native loop for this model's content (checked once, by ``looped``), or None where it does not run."""
    if not native_enabled():
        return None
    key = _key(model)
    return _LOOPS[key] if key in _LOOPS else _LOOPS.setdefault(key, looped(model))


def _uncompiled(model: Model, reason: str, environment: tuple, known: _Compiled | None = None) -> Choice:
    """A float call no compiled model runs: the loop, else the recursions (warned once if too large: ``known``)."""
    if (loop := _loop(model)) is not None:
        return _remembered(model, Choice("loop", reason, loop), environment)
    if known is not None and not known.warned:
        known.warned = True
        warnings.warn(f"{known.too_large}; running the interpreted recursions", CompileWarning, stacklevel=4)
    return Choice("interpreted", reason, Interpreted(model))


def _remembered(model: Model, chosen: Choice, environment: tuple) -> Choice:
    """The choice, remembered for the model's one-state calls where it runs native code for them (the loop, or a
    compiled model with C that the cache holds), in the native entry; ``environment`` is what it was made under."""
    global _ONE
    if _RAW is not None and environment == _environment() and (chosen.path == "loop" or (
            chosen.native and chosen.reason == CACHED and chosen.run.native_build is None)):
        if (one := remember(model, chosen.run, _RAW, _RAW_NAMES, WRITES)) is not None:
            _ONE = one
            return chosen
    forget(id(model))
    return chosen


def _unremembered(model, code: int, *arrays) -> None:
    """The native entry where no model has one yet: it takes no call (None)."""


_ONE = _unremembered  # the native entry's ``one`` once a model is remembered in it, and its codes:
_TAU, _MASS_MATRIX, _FORWARD_DYNAMICS, _REGRESSOR = map(PROGRAMS.get, ("tau", "mass_matrix", "forward_dynamics",
                                                                       "regressor"))


def implementation(model: Model, calls: int = 1, states: int = 1, compiled: bool | None = None):
    """What runs ``calls`` calls of ``states`` float states each: ``choice(...).run``, a
    :class:`~course_dynamics.core.compiled.CompiledModel` or the :class:`Interpreted` recursions, with the same
    methods (``inverse_dynamics``, ``mass_matrix``, ``bias``, ``forward_dynamics``, ``accelerations``, …).

    Parameters
    ----------
    model : Model
        The robot.
    calls : int, optional
        The number of calls.
    states : int, optional
        The number of float states of each call.
    compiled : bool, optional
        True for the compiled model, False for the recursions as written; None (the default) lets the rule of
        the module docstring choose.

    Returns
    -------
    Interpreted or CompiledModel
        What runs the calls.

    Raises
    ------
    ProgramTooLargeError
        With ``compiled=True``, for a robot too large to compile.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> type(implementation(load_robot("two_link"), compiled=False)).__name__
    'Interpreted'
    """
    return choice(model, calls, states, compiled=compiled).run


def _blocked(run, name: str, *arrays: np.ndarray, **options) -> np.ndarray:
    """``run.<name>(*arrays)``; the interpreted recursions on a float batch of more than :data:`BLOCK_STATES` states
    take it that many states at a time, into one output (their temporaries, dozens of arrays of the batch's length
    for each body, would otherwise need 30 times the output's memory)."""
    method = getattr(run, name)
    batch = batch_shape(*arrays)
    states = int(np.prod(batch, dtype=np.int64))
    if not isinstance(run, (Interpreted, Looped)) or states <= BLOCK_STATES or \
            any(a.dtype != np.float64 for a in arrays):
        return method(*arrays, **options)
    flat = [np.broadcast_to(a, batch + a.shape[-1:]).reshape(states, a.shape[-1]) for a in arrays]
    first = method(*(f[:BLOCK_STATES] for f in flat), **options)
    out = np.empty((states,) + first.shape[1:])
    out[:BLOCK_STATES] = first
    for start in range(BLOCK_STATES, states, BLOCK_STATES):
        out[start:start + BLOCK_STATES] = method(*(f[start:start + BLOCK_STATES] for f in flat), **options)
    return out.reshape(batch + first.shape[1:])


def _run(model: Model, *arrays: np.ndarray, work: int = 1):
    """What runs one call on these checked states (:func:`choice`), a call ``work`` τ calls' worth."""
    floats = all(a.dtype == np.float64 for a in arrays)
    states = int(np.prod(batch_shape(*arrays), dtype=np.int64)) if floats else 1
    return choice(model, work, states, floats).run


def inverse_dynamics(model: Model, q, qd, qdd) -> np.ndarray:
    """τ (6.45)–(6.53), shape (n,) or (N, n), N·m or N, by the chosen implementation (module docstring).

    As :func:`course_dynamics.core.newton_euler.inverse_dynamics`, which it calls for symbols and little work.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.
    qd : array_like, shape (n,) or (N, n)
        Joint velocities Θ̇, rad/s (m/s for a prismatic joint).
    qdd : array_like, shape (n,) or (N, n)
        Joint accelerations Θ̈, rad/s² (m/s² for a prismatic joint).

    Returns
    -------
    numpy.ndarray, shape (n,) or (N, n)
        Joint torques τ, N·m (N for a prismatic joint).

    Raises
    ------
    StateError
        If a state is not numeric or not finite, its last axis is not the model's n joints, or the batches
        differ in length.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> np.round(inverse_dynamics(load_robot("two_link"), [0.1, 0.2], [1, 0], [0, 1]), 6)
    array([18.74624 ,  3.948474])
    """
    out = _ONE(model, _TAU, q, qd, qdd)
    if out is not None:
        return out
    q, qd, qdd = as_state(model, q, "q"), as_state(model, qd, "qd"), as_state(model, qdd, "qdd")
    return _blocked(_run(model, q, qd, qdd), "inverse_dynamics", q, qd, qdd)


def regressor(model: Model, q, qd, qdd) -> np.ndarray:
    """Y(Θ, Θ̇, Θ̈), shape (n, 10 n_bodies) or (N, n, 10 n_bodies), by the chosen implementation (its work
    :data:`REGRESSOR_WORK` τ calls'); as :func:`course_dynamics.core.regressor.regressor`.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.
    qd : array_like, shape (n,) or (N, n)
        Joint velocities Θ̇, rad/s (m/s for a prismatic joint).
    qdd : array_like, shape (n,) or (N, n)
        Joint accelerations Θ̈, rad/s² (m/s² for a prismatic joint).

    Returns
    -------
    numpy.ndarray, shape (n, 10 n_bodies) or (N, n, 10 n_bodies)
        Y, column k ∂τ/∂π_k (N·m or N per unit of parameter k), so that τ = Y π.

    Raises
    ------
    StateError
        If a state is not numeric or not finite, its last axis is not the model's n joints, or the batches
        differ in length.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> from course_dynamics.core.regressor import parameters
    >>> arm = load_robot("two_link")
    >>> Y = regressor(arm, [0.1, 0.2], [1, 0], [0, 1])
    >>> Y.shape, np.round(Y @ parameters(arm), 6)          # τ = Y π
    ((2, 20), array([18.74624 ,  3.948474]))
    """
    out = _ONE(model, _REGRESSOR, q, qd, qdd)
    if out is not None:
        return out
    q, qd, qdd = as_state(model, q, "q"), as_state(model, qd, "qd"), as_state(model, qdd, "qdd")
    return _blocked(_run(model, q, qd, qdd, work=REGRESSOR_WORK), "regressor", q, qd, qdd)


def mass_matrix(model: Model, q) -> np.ndarray:
    """M(Θ), shape (n, n) or (..., n, n), by the chosen implementation; as
    :func:`course_dynamics.core.dynamics.mass_matrix`.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.

    Returns
    -------
    numpy.ndarray, shape (n, n) or (N, n, n)
        The mass matrix M(Θ), kg·m² (kg between prismatic joints).

    Raises
    ------
    StateError
        If ``q`` is not numeric or not finite, or its last axis is not the model's n joints.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> np.round(mass_matrix(load_robot("two_link"), [0.0, 0.5]), 6)
    array([[1.261033, 0.335517],
           [0.335517, 0.16    ]])
    """
    out = _ONE(model, _MASS_MATRIX, q)
    if out is not None:
        return out
    q = as_state(model, q, "q")
    return _blocked(_run(model, q), "mass_matrix", q)


def coriolis_matrix(model: Model, q, qd) -> np.ndarray:
    """C(Θ, Θ̇), shape (n, n) or (..., n, n), by the chosen implementation; as
    :func:`course_dynamics.core.dynamics.coriolis_matrix`.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.
    qd : array_like, shape (n,) or (N, n)
        Joint velocities Θ̇, rad/s (m/s for a prismatic joint).

    Returns
    -------
    numpy.ndarray, shape (n, n) or (N, n, n)
        The Coriolis matrix C(Θ, Θ̇), with C Θ̇ = V, kg·m²/s between revolute joints.

    Raises
    ------
    StateError
        If a state is not numeric or not finite, its last axis is not the model's n joints, or the batches
        differ in length.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> np.round(coriolis_matrix(load_robot("two_link"), [0.0, 0.5], [1.0, 0.0]), 6)
    array([[ 0.      , -0.095885],
           [ 0.095885,  0.      ]])
    """
    q, qd = as_state(model, q, "q"), as_state(model, qd, "qd")
    return _blocked(_run(model, q, qd), "coriolis_matrix", q, qd)


def gravity_torques(model: Model, q) -> np.ndarray:
    """G(Θ), shape (n,) or (N, n), by the chosen implementation; as
    :func:`course_dynamics.core.dynamics.gravity_torques`.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint); a numpy object array of sympy expressions for a
        closed form.

    Returns
    -------
    numpy.ndarray, shape (n,) or (N, n)
        Gravity torques G(Θ), N·m (N for a prismatic joint).

    Raises
    ------
    StateError
        If ``q`` is not numeric or not finite, or its last axis is not the model's n joints.

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> np.round(gravity_torques(load_robot("two_link"), [0.0, 0.0]), 6)
    array([18.639,  3.924])
    """
    q = as_state(model, q, "q")
    return _blocked(_run(model, q), "gravity_torques", q)


def forward_dynamics(model: Model, q, qd, tau, friction: Friction | None = None,
                     drives: Drives | None = None) -> np.ndarray:
    """Θ̈ (6.115), shape (n,) or (N, n), by the chosen implementation; as
    :func:`course_dynamics.core.forward_dynamics.forward_dynamics`, with ``drives`` as
    :class:`~course_dynamics.core.drives.Driven` adds them.

    Parameters
    ----------
    model : Model
        The robot.
    q : array_like, shape (n,) or (N, n)
        Joint positions Θ, rad (m for a prismatic joint).
    qd : array_like, shape (n,) or (N, n)
        Joint velocities Θ̇, rad/s (m/s for a prismatic joint).
    tau : array_like, shape (n,) or (N, n)
        Applied joint torques τ, N·m (N for a prismatic joint).
    friction : Friction, optional
        Subtracted from τ as F(Θ̇) (6.114); default none.
    drives : Drives, optional
        Rotor inertias added to M's diagonal and torque offsets taken off τ; default none.

    Returns
    -------
    numpy.ndarray, shape (n,) or (N, n)
        Joint accelerations Θ̈, rad/s² (m/s² for a prismatic joint).

    Raises
    ------
    StateError
        If a state is not numeric or not finite, its last axis is not the model's n joints, or the batches
        differ in length.
    SingularMassMatrixError
        If M(Θ) is singular (a joint that moves no mass).

    Examples
    --------
    >>> from course_dynamics import load_robot
    >>> np.round(forward_dynamics(load_robot("two_link"), [0.0, 0.5], [0, 0], [24.0, 5.0]), 6)
    array([4.623991, 0.030879])
    """
    out = _ONE(model, _FORWARD_DYNAMICS, q, qd, tau) if friction is None and drives is None else None
    if out is not None:
        return out
    q, qd, tau = as_state(model, q, "q"), as_state(model, qd, "qd"), as_state(model, tau, "tau")
    run = _run(model, q, qd, tau)
    run = run if drives is None else Driven(run, drives)
    return _blocked(run, "forward_dynamics", q, qd, tau, friction=friction)


__all__ = ["BLOCK_STATES", "CALL_SECONDS", "COMPILE_SECONDS", "Choice", "Interpreted", "NATIVE_SECONDS",
           "REGRESSOR_WORK", "STATE_SECONDS", "choice", "coriolis_matrix", "forward_dynamics", "gravity_torques",
           "implementation", "interpreted_seconds", "inverse_dynamics", "mass_matrix", "regressor"]
